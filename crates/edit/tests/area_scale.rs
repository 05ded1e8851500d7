//! The editing session of Lee 1999 on generated meshes: boundary fixing (§5.3) seen from
//! the mesh, no crease at the border at large scales, primitives of several vertices
//! interpolated, and a scale that reaches as far on a coarse as on a fine mesh (§3.6),
//! with the reach table of `docs/guide/area-editing.md`.

use edit::lee::LeeError;
use edit::lee::{AreaSession, AreaSide, EditingArea, FrameKind, SessionOptions};
use glam::DVec3;
use halfedge::{generators, Mesh, VertexId};

/// A planar `n × n` grid over the unit square and the square area `[1/8, 7/8]²` made from
/// its four corner picks (they become the rectangle's corners, so the harmonic map is
/// the identity up to a shift), with the vertex at the centre.
fn grid_area(n: usize) -> (Mesh, EditingArea, VertexId) {
    assert_eq!(n % 8, 0);
    let mesh = generators::grid(n, n, 1.0, 1.0);
    let id = |i: usize, j: usize| mesh.vertex_at(i + j * (n + 1)).unwrap();
    let (a, b) = (n / 8, n - n / 8);
    let centre = id(n / 2, n / 2);
    let picks = [id(a, a), id(b, a), id(b, b), id(a, b)];
    let area = EditingArea::from_picks(&mesh, &picks, AreaSide::Vertex(centre)).unwrap();
    (mesh, area, centre)
}

/// The unit icosphere subdivided `level` times and the cap of faces whose centroid lies
/// within 50° of a vertex (the same part of the sphere at every level), with that vertex.
fn cap_area(level: usize) -> (Mesh, EditingArea, VertexId) {
    let mesh = generators::icosphere(level);
    let pole = mesh.vertex_at(0).unwrap();
    let axis = mesh.position(pole);
    let cos = 50f64.to_radians().cos();
    let faces: Vec<_> = mesh
        .faces()
        .filter(|&f| {
            let c = mesh.triangle(f).map(|v| mesh.position(v));
            ((c[0] + c[1] + c[2]) / 3.0).normalize().dot(axis) >= cos
        })
        .collect();
    let area = EditingArea::from_faces(&mesh, &faces).unwrap();
    (mesh, area, pole)
}

/// Great-circle distance on the unit sphere; plain distance on the plane.
fn surface_distance(a: DVec3, b: DVec3, sphere: bool) -> f64 {
    if sphere {
        a.normalize().dot(b.normalize()).clamp(-1.0, 1.0).acos()
    } else {
        a.distance(b)
    }
}

fn motion(mesh: &Mesh, rest: &[DVec3], v: VertexId) -> f64 {
    (mesh.position(v) - rest[mesh.vertex_index(v)]).length()
}

/// Embedded distance of local vertex `i` to the rectangle's border.
fn to_border(session: &AreaSession, i: usize) -> f64 {
    let p = session.embedding().uv()[i];
    let size = session.embedding().size();
    p.x.min(p.y).min(size.x - p.x).min(size.y - p.y)
}

fn local(session: &AreaSession, mesh: &Mesh, v: VertexId) -> usize {
    session.area().local_index(mesh, v).unwrap()
}

/// Faces whose normal turned over against `rest`.
fn flipped(mesh: &Mesh, rest: &[DVec3], faces: &[halfedge::FaceId]) -> usize {
    faces
        .iter()
        .filter(|&&f| {
            let now = mesh.triangle(f).map(|v| mesh.position(v));
            let was = mesh.triangle(f).map(|v| rest[mesh.vertex_index(v)]);
            let n0 = (was[1] - was[0]).cross(was[2] - was[0]);
            let n1 = (now[1] - now[0]).cross(now[2] - now[0]);
            n0.dot(n1) <= 0.0
        })
        .count()
}

/// The interior vertices next to the area's boundary.
fn first_ring(mesh: &Mesh, area: &EditingArea) -> Vec<VertexId> {
    area.interior()
        .iter()
        .copied()
        .filter(|&v| mesh.adjacent_vertices(v).any(|w| area.is_boundary(mesh, w)))
        .collect()
}

/// How far from `centre` the motion stays at or above 10 % of `pull`: the farthest point
/// where it crosses 10 %, interpolated linearly along the area's edges, measured on the
/// surface at rest.
fn reach(mesh: &Mesh, rest: &[DVec3], area: &EditingArea, centre: VertexId, pull: f64) -> f64 {
    let sphere = rest.iter().all(|p| (p.length() - 1.0).abs() < 1e-9);
    let c = rest[mesh.vertex_index(centre)];
    let mut far: f64 = 0.0;
    for &f in area.faces() {
        let t = mesh.triangle(f);
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (ma, mb) = (motion(mesh, rest, a) / pull, motion(mesh, rest, b) / pull);
            let (pa, pb) = (rest[mesh.vertex_index(a)], rest[mesh.vertex_index(b)]);
            if ma >= 0.1 {
                far = far.max(surface_distance(c, pa, sphere));
            }
            if (ma - 0.1) * (mb - 0.1) < 0.0 {
                let x = (ma - 0.1) / (ma - mb);
                far = far.max(surface_distance(c, pa.lerp(pb, x), sphere));
            }
        }
    }
    far
}

#[test]
fn boundary_fixing_makes_the_motion_vanish_on_the_border_with_its_slope() {
    // Lee 1999 §5.3: the offsets and their first and second derivatives vanish on the
    // border of the rectangle, so near it the motion falls like the cube of the embedded
    // distance d: at most 4 (d / D)³ of the pull for d ≤ D/2, D the primitive's distance.
    // (Without fixing, the motion no longer vanishes at the border at large scales.)
    for (name, (mesh, area, centre)) in [("grid", grid_area(48)), ("cap", cap_area(4))] {
        for frames in [
            FrameKind::Global,
            FrameKind::Normal {
                seed: None,
                x_axis: None,
            },
        ] {
            let mut mesh = mesh.clone();
            let rest = mesh.positions().to_vec();
            let options = SessionOptions::default().with_frames(frames.clone());
            let mut session = AreaSession::new(&mesh, area.clone(), &options).unwrap();
            session.set_primitive(&mesh, &[centre]).unwrap();
            let big = to_border(&session, local(&session, &mesh, centre));
            let pull = 0.2 * mesh.vertex_normal(centre) + DVec3::new(0.05, -0.03, 0.0);
            for s in [0.25, 0.5, 0.75, 1.0] {
                session.set_scale(s).unwrap();
                session.drag(&mut mesh, pull).unwrap();
                let mut checked = 0;
                for (i, &v) in session.area().interior().iter().enumerate() {
                    let d = to_border(&session, i) / big;
                    if d <= 0.5 {
                        let m = motion(&mesh, &rest, v) / pull.length();
                        assert!(
                            m <= 4.0 * d.powi(3),
                            "{name} {frames:?} s = {s}: {v} at d/D = {d:.3} moves {m:.4}"
                        );
                        checked += 1;
                    }
                }
                assert!(checked > session.area().boundary().len());
                for &v in session.area().boundary() {
                    assert_eq!(mesh.position(v), rest[mesh.vertex_index(v)]);
                }
            }
        }
    }
}

#[test]
fn no_fold_at_the_border_at_any_scale() {
    // Lee 1999 §5.3 fixes the border; the band over which the motion dies must be as wide
    // as the edit, or a large scale creases the surface just inside the border. The
    // first interior ring moves at most (d / D) of the pull (a ramp no steeper than a
    // straight line from the border to the primitive), and a pull with a sideways part
    // of half the primitive's distance to the border turns over no face near it.
    let areas = [
        ("grid", grid_area(32)),
        ("cap", cap_area(3)),
        ("small cap", {
            let mesh = generators::icosphere(3);
            let pole = mesh.vertex_at(0).unwrap();
            let area = EditingArea::disk_around(&mesh, pole, 150).unwrap();
            (mesh, area, pole)
        }),
    ];
    for (name, (mut mesh, area, centre)) in areas {
        let rest = mesh.positions().to_vec();
        let mut session = AreaSession::new(&mesh, area, &SessionOptions::default()).unwrap();
        let ring = first_ring(&mesh, session.area());
        let near_border: Vec<_> = session
            .area()
            .faces()
            .iter()
            .copied()
            .filter(|&f| {
                mesh.triangle(f)
                    .iter()
                    .any(|v| session.area().is_boundary(&mesh, *v) || ring.contains(v))
            })
            .collect();
        session.set_primitive(&mesh, &[centre]).unwrap();
        let c = rest[mesh.vertex_index(centre)];
        let gap = session
            .area()
            .boundary()
            .iter()
            .map(|&v| c.distance(rest[mesh.vertex_index(v)]))
            .fold(f64::INFINITY, f64::min);
        let normal = mesh.vertex_normal(centre);
        let side = normal.any_orthonormal_vector();
        let pull = 0.5 * gap * (normal + side);
        let big = to_border(&session, local(&session, &mesh, centre));
        for s in [0.2, 0.5, 1.0] {
            session.set_scale(s).unwrap();
            session.drag(&mut mesh, pull).unwrap();
            for &v in &ring {
                let d = to_border(&session, local(&session, &mesh, v)) / big;
                let m = motion(&mesh, &rest, v) / pull.length();
                assert!(m <= d, "{name} s = {s}: {v} at d/D = {d:.3} moves {m:.3}");
            }
            assert_eq!(
                flipped(&mesh, &rest, &near_border),
                0,
                "{name} s = {s}: faces turned over at the border"
            );
        }
    }
}

#[test]
fn primitives_of_several_vertices_reach_their_targets() {
    // Lee 1999 §3.3, §5.1: the multilevel B-splines pass through the primitive's offsets.
    // Chains and patches of adjacent vertices (closer than the finest dense cell) and
    // scattered sets, dragged or moved one by one, at every scale.
    for (name, (mesh, area, centre)) in [("grid", grid_area(32)), ("cap", cap_area(3))] {
        let mut mesh = mesh.clone();
        let rest = mesh.positions().to_vec();
        let mut session = AreaSession::new(&mesh, area, &SessionOptions::default()).unwrap();
        // a chain of 3 through the centre and a patch of 10 around it
        let ring: Vec<VertexId> = mesh.adjacent_vertices(centre).collect();
        let chain = vec![ring[0], centre, ring[ring.len() / 2]];
        let mut patch = vec![centre];
        patch.extend(&ring);
        for &v in &ring {
            for w in mesh.adjacent_vertices(v) {
                if patch.len() < 10 && !patch.contains(&w) {
                    patch.push(w);
                }
            }
        }
        assert_eq!(patch.len(), 10);
        for primitive in [vec![centre], chain, patch] {
            session.cancel(&mut mesh).unwrap();
            session.set_primitive(&mesh, &primitive).unwrap();
            let drag = DVec3::new(0.03, -0.05, 0.2);
            for s in [0.0, 0.03, 0.1, 0.2, 0.5, 0.75, 1.0] {
                session.set_scale(s).unwrap();
                session.drag(&mut mesh, drag).unwrap();
                for &v in &primitive {
                    let error = (mesh.position(v) - rest[mesh.vertex_index(v)] - drag).length();
                    assert!(
                        error <= 1e-3 * drag.length(),
                        "{name}, {} vertices, s = {s}: {v} misses by {error:e}",
                        primitive.len()
                    );
                }
            }
            // second mode: every vertex its own target (a twist of the primitive)
            session.cancel(&mut mesh).unwrap();
            session.set_primitive(&mesh, &primitive).unwrap();
            let targets: Vec<DVec3> = primitive
                .iter()
                .enumerate()
                .map(|(k, &v)| {
                    let a = k as f64;
                    rest[mesh.vertex_index(v)] + 0.1 * DVec3::new(a.cos(), a.sin(), 1.0)
                })
                .collect();
            for (&v, &target) in primitive.iter().zip(&targets) {
                session.move_vertex(&mesh, v, target).unwrap();
            }
            for s in [0.05, 0.5, 1.0] {
                session.set_scale(s).unwrap();
                session.apply(&mut mesh).unwrap();
                for (&v, &target) in primitive.iter().zip(&targets) {
                    let error = (mesh.position(v) - target).length();
                    assert!(
                        error <= 1e-3 * 0.1 * 2f64.sqrt(),
                        "{name}, {} vertices moved one by one, s = {s}: {v} misses by {error:e}",
                        primitive.len()
                    );
                }
            }
        }
    }
}

#[test]
fn scattered_primitives_reach_their_targets() {
    // three vertices far apart: each its own bump, each reached
    let (mut mesh, area, _) = grid_area(32);
    let rest = mesh.positions().to_vec();
    let id = |i: usize, j: usize| mesh.vertex_at(i + j * 33).unwrap();
    let primitive = [id(9, 9), id(20, 13), id(14, 23)];
    let mut session = AreaSession::new(&mesh, area, &SessionOptions::default()).unwrap();
    session.set_primitive(&mesh, &primitive).unwrap();
    let drag = DVec3::new(0.0, 0.02, 0.1);
    for s in [0.1, 0.5, 1.0] {
        session.set_scale(s).unwrap();
        session.drag(&mut mesh, drag).unwrap();
        for &v in &primitive {
            let error = (mesh.position(v) - rest[mesh.vertex_index(v)] - drag).length();
            assert!(
                error <= 1e-3 * drag.length(),
                "s = {s}: {v} misses by {error:e}"
            );
        }
    }
}

#[test]
fn a_scale_reaches_as_far_on_a_coarse_and_on_a_fine_mesh() {
    // Lee 1999 §3.6: the scale controls the influence area. The same part of a surface
    // at two resolutions (four times as many vertices, one more B-spline level) moves as
    // far for the same s.
    let pairs = [
        ("grid", grid_area(32), grid_area(64)),
        ("cap", cap_area(4), cap_area(5)),
    ];
    for (name, coarse, fine) in pairs {
        let mut reaches = Vec::new();
        let mut levels = Vec::new();
        let mut edge = Vec::new();
        for (mut mesh, area, centre) in [coarse, fine] {
            let rest = mesh.positions().to_vec();
            let mut session = AreaSession::new(&mesh, area, &SessionOptions::default()).unwrap();
            levels.push(session.levels());
            edge.push(
                mesh.adjacent_vertices(centre)
                    .map(|v| mesh.position(v).distance(mesh.position(centre)))
                    .sum::<f64>()
                    / mesh.adjacent_vertices(centre).count() as f64,
            );
            session.set_primitive(&mesh, &[centre]).unwrap();
            let pull = 0.1 * mesh.vertex_normal(centre);
            let mut row = Vec::new();
            for s in [0.25, 0.5, 0.75, 1.0] {
                session.set_scale(s).unwrap();
                session.drag(&mut mesh, pull).unwrap();
                row.push(reach(&mesh, &rest, session.area(), centre, 0.1));
            }
            reaches.push(row);
        }
        assert!(levels[1] > levels[0], "{name}: levels {levels:?}");
        for (k, s) in [0.25, 0.5, 0.75, 1.0].into_iter().enumerate() {
            let (a, b) = (reaches[0][k], reaches[1][k]);
            // within a quarter of the coarse mesh's edge: the same function, sampled
            // more sparsely on the coarse mesh
            assert!(
                (a - b).abs() <= 0.25 * edge[0],
                "{name} s = {s}: reach {a:.4} coarse, {b:.4} fine (edge {:.4})",
                edge[0]
            );
        }
        // and it grows with s
        assert!(reaches[1].windows(2).all(|w| w[0] < w[1]), "{reaches:?}");
    }
}

/// The table of `docs/guide/area-editing.md`: reach (motion ≥ 10 % of the drag) over the
/// rectangle's side, for the grid's square area (96 × 96 edges, 7 levels) and the 50°
/// sphere cap on icosphere level 6 (7 levels; the side is a quarter of the boundary loop,
/// about 1.20). Both go down to the finest scale `2^{3−7} = 1/16`.
const REACH_TABLE: [(f64, f64, f64); 6] = [
    (0.1, 0.049, 0.051),
    (0.2, 0.098, 0.102),
    (0.25, 0.112, 0.116),
    (0.5, 0.223, 0.234),
    (0.75, 0.272, 0.282),
    (1.0, 0.311, 0.320),
];

#[test]
fn reach_against_scale_is_the_guides_table() {
    for (column, (mut mesh, area, centre)) in [(1, grid_area(128)), (2, cap_area(6))] {
        let rest = mesh.positions().to_vec();
        let mut session = AreaSession::new(&mesh, area, &SessionOptions::default()).unwrap();
        println!(
            "column {column}: {} levels, finest scale {}",
            session.levels(),
            session.finest_scale()
        );
        session.set_primitive(&mesh, &[centre]).unwrap();
        let side = session.embedding().size().max_element();
        let pull = 0.1 * mesh.vertex_normal(centre);
        let mut measured = Vec::new();
        for &(s, grid, cap) in &REACH_TABLE {
            session.set_scale(s).unwrap();
            session.drag(&mut mesh, pull).unwrap();
            let r = reach(&mesh, &rest, session.area(), centre, 0.1) / side;
            let expected = if column == 1 { grid } else { cap };
            measured.push((s, r, expected));
        }
        println!("column {column} (s, measured, table): {measured:.3?}");
        for (s, r, expected) in measured {
            assert!(
                (r - expected).abs() <= 0.005,
                "column {column}, s = {s}: measured {r:.3}, the guide says {expected}"
            );
        }
    }
}

#[test]
fn the_edit_changes_continuously_with_the_scale() {
    // across the nodes s = 1/2^k and the finest level's node, and where the detail
    // levels start or stop
    let (mut mesh, area, centre) = grid_area(32);
    let mut session = AreaSession::new(&mesh, area, &SessionOptions::default()).unwrap();
    let mut primitive = vec![centre];
    primitive.extend(mesh.adjacent_vertices(centre));
    session.set_primitive(&mesh, &primitive).unwrap();
    let pull = DVec3::new(0.0, 0.05, 0.1);
    let finest = session.finest_scale();
    for node in [1.0, 0.5, 0.25, finest, 0.5 * finest] {
        let mut shapes = Vec::new();
        for s in [node - 1e-9, node, (node + 1e-9).min(1.0)] {
            session.set_scale(s).unwrap();
            session.drag(&mut mesh, pull).unwrap();
            shapes.push(mesh.positions().to_vec());
        }
        for pair in shapes.windows(2) {
            let jump = pair[0]
                .iter()
                .zip(&pair[1])
                .map(|(a, b)| a.distance(*b))
                .fold(0.0, f64::max);
            assert!(jump <= 1e-6 * pull.length(), "s = {node}: jump {jump:e}");
        }
    }
}

#[test]
fn level_counts_are_bounded_and_keep_the_reach() {
    let (mut mesh, area, centre) = grid_area(32);
    let rest = mesh.positions().to_vec();
    for levels in [0, 2, 13, 14, usize::MAX] {
        let options = SessionOptions::default().with_levels(levels);
        assert!(matches!(
            AreaSession::new(&mesh, area.clone(), &options),
            Err(LeeError::InvalidParameter { name: "levels", .. })
        ));
    }
    let mut session = AreaSession::new(&mesh, area.clone(), &SessionOptions::default()).unwrap();
    let auto = session.levels();
    assert!(matches!(
        session.set_levels(13),
        Err(LeeError::InvalidParameter { name: "levels", .. })
    ));
    assert_eq!(session.levels(), auto);
    // the documented maximum works (its lattice is about 100 MB) and reaches as far
    session.set_primitive(&mesh, &[centre]).unwrap();
    session.set_scale(0.5).unwrap();
    let pull = DVec3::new(0.0, 0.0, 0.1);
    session.drag(&mut mesh, pull).unwrap();
    let at_auto = reach(&mesh, &rest, session.area(), centre, 0.1);
    let options = SessionOptions::default()
        .with_levels(edit::lee::MAX_SESSION_LEVELS)
        .with_scale(0.5);
    session.cancel(&mut mesh).unwrap();
    let mut deep = AreaSession::new(&mesh, area, &options).unwrap();
    deep.set_primitive(&mesh, &[centre]).unwrap();
    deep.drag(&mut mesh, pull).unwrap();
    let at_max = reach(&mesh, &rest, deep.area(), centre, 0.1);
    assert!((at_auto - at_max).abs() < 1e-3, "{at_auto} vs {at_max}");
    assert!((mesh.position(centre) - rest[mesh.vertex_index(centre)] - pull).length() < 1e-12);
}
