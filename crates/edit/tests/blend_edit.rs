//! The Bendels & Klein editing session on generated meshes: invariants of every edit,
//! the paper's Fig. 3 point (geodesic α is monotone, Euclidean α need not be), crease-free
//! joins with a C¹ shape function, and adaptive refinement.

use edit::bendels_klein::{BlendOptions, BlendSession, DistanceKind, RefineOptions};
use edit::bendels_klein::{CurveOptions, ShapeCurve, ShapeFunction};
use edit::bendels_klein::{FastMarching, MarchSource};
use edit::bendels_klein::{Regions, Role};
use glam::{DMat4, DQuat, DVec3};
use halfedge::{generators, Mesh, VertexId};

/// A planar grid over [−1, 1]² with a round handle (r < r_handle) and a fixed outside
/// (r > r_fixed) around the centre.
fn disc_edit(n: usize, r_handle: f64, r_fixed: f64) -> (Mesh, Regions) {
    let mut mesh = generators::grid(n, n, 2.0, 2.0);
    for p in mesh.positions_mut() {
        *p -= DVec3::new(1.0, 1.0, 0.0);
    }
    let handle: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).length() < r_handle)
        .collect();
    let fixed: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).length() > r_fixed)
        .collect();
    let regions = Regions::from_sets(&mesh, &handle, &fixed).unwrap();
    (mesh, regions)
}

fn assert_invariants(mesh: &Mesh, session: &BlendSession, a: DMat4) {
    let original = session.original_positions();
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        match session.regions().role(mesh, v) {
            Role::Fixed => assert_eq!(
                mesh.position(v).to_array().map(f64::to_bits),
                original[i].to_array().map(f64::to_bits),
                "fixed vertex {v} moved"
            ),
            Role::Handle => assert_eq!(mesh.position(v), a.transform_point3(original[i])),
            Role::Deformable => {
                let alpha = session.alpha()[i];
                assert!((0.0..=1.0).contains(&alpha));
                assert!(mesh.position(v).is_finite());
            }
        }
    }
}

#[test]
fn fixed_area_is_bit_identical_and_handle_moves_rigidly_after_any_edit() {
    for kind in [DistanceKind::Geodesic, DistanceKind::Euclidean] {
        let (mut mesh, regions) = disc_edit(40, 0.25, 0.75);
        let before: Vec<DVec3> = mesh.positions().to_vec();
        let mut session = BlendSession::new(
            &mesh,
            regions,
            BlendOptions::default()
                .with_distance(kind)
                .with_shape(ShapeFunction::Smoothstep),
        )
        .unwrap();
        assert_eq!(mesh.positions(), &before[..], "setting up moved the mesh");
        let mut shear = DMat4::IDENTITY;
        shear.z_axis.x = 0.4;
        let edits = [
            DMat4::from_translation(DVec3::new(0.1, -0.2, 0.5)),
            DMat4::from_rotation_translation(
                DQuat::from_axis_angle(DVec3::new(1.0, 1.0, 0.0).normalize(), 1.2),
                DVec3::new(0.0, 0.0, 0.3),
            ),
            DMat4::from_scale(DVec3::new(1.5, 0.8, 2.0)) * shear,
            DMat4::from_axis_angle(DVec3::Z, 3.0),
        ];
        for a in edits {
            session.apply(&mut mesh, a).unwrap();
            assert_invariants(&mesh, &session, a);
        }
        // Shape changes, then the current transform again.
        let curve = ShapeCurve::new(&[(0.2, 0.6), (0.5, 0.8)], CurveOptions::default()).unwrap();
        for shape in [
            ShapeFunction::Linear,
            ShapeFunction::Smootherstep,
            ShapeFunction::Curve(curve),
        ] {
            session.set_shape(shape);
            session.reapply(&mut mesh).unwrap();
            assert_invariants(&mesh, &session, edits[3]);
        }
        // A transform without real log is refused and changes nothing.
        let snapshot = mesh.positions().to_vec();
        assert!(session
            .apply(&mut mesh, DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0)))
            .is_err());
        assert_eq!(mesh.positions(), &snapshot[..]);
        // Reset brings everything back.
        session.reset(&mut mesh).unwrap();
        assert_eq!(mesh.positions(), &before[..]);
        // Another mesh is refused.
        let mut other = generators::grid(3, 3, 1.0, 1.0);
        assert!(session.apply(&mut other, DMat4::IDENTITY).is_err());
    }
}

#[test]
fn translation_moves_each_vertex_by_alpha_times_the_offset() {
    let (mut mesh, regions) = disc_edit(30, 0.3, 0.8);
    let mut session = BlendSession::new(&mesh, regions, BlendOptions::default()).unwrap();
    let t = DVec3::new(0.2, 0.1, 0.6);
    session
        .apply(&mut mesh, DMat4::from_translation(t))
        .unwrap();
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        let moved = mesh.position(v) - session.original_positions()[i];
        let expected = session.alpha()[i] * t;
        assert!((moved - expected).length() < 1e-14, "{moved} vs {expected}");
    }
}

/// A strip folded into a U in the xz-plane: arm 1 along +x at z = 0, a half turn of
/// radius `radius`, arm 2 back along −x at z = 2 radius. Returns the mesh and the
/// arc-length coordinate of every vertex along the strip.
fn u_strip(arm: f64, radius: f64, width: f64, nu: usize, nv: usize) -> (Mesh, Vec<f64>) {
    let length = 2.0 * arm + std::f64::consts::PI * radius;
    let mut mesh = generators::grid(nu, nv, length, width);
    let mut arc = vec![0.0; mesh.vertex_slots()];
    let vertices: Vec<VertexId> = mesh.vertices().collect();
    for v in vertices {
        let p = mesh.position(v);
        let s = p.x;
        arc[mesh.vertex_index(v)] = s;
        let (x, z) = if s <= arm {
            (s, 0.0)
        } else if s <= arm + std::f64::consts::PI * radius {
            let phi = (s - arm) / radius;
            (arm + radius * phi.sin(), radius - radius * phi.cos())
        } else {
            (
                arm - (s - arm - std::f64::consts::PI * radius),
                2.0 * radius,
            )
        };
        mesh.set_position(v, DVec3::new(x, p.y, z));
    }
    (mesh, arc)
}

#[test]
fn geodesic_alpha_is_monotone_from_fixed_to_handle_euclidean_is_not() {
    // Fig. 3 of the paper: the fixed area is the start of arm 1, the handle the second
    // half of arm 2, whose border hangs right above the middle of arm 1.
    let (arm, radius) = (2.0, 0.15);
    let (mesh, arc) = u_strip(arm, radius, 0.2, 240, 4);
    let s_fixed = 0.1;
    let s_handle = arm + std::f64::consts::PI * radius + 0.5 * arm;
    let roles: Vec<Role> = (0..mesh.vertex_slots())
        .map(|i| {
            if arc[i] <= s_fixed {
                Role::Fixed
            } else if arc[i] >= s_handle {
                Role::Handle
            } else {
                Role::Deformable
            }
        })
        .collect();
    let regions =
        Regions::from_roles(&mesh, halfedge::VertexData::new(&mesh, roles).unwrap()).unwrap();
    let alpha_of = |kind| {
        let session = BlendSession::new(
            &mesh,
            regions.clone(),
            BlendOptions::default()
                .with_distance(kind)
                .with_shape(ShapeFunction::Linear),
        )
        .unwrap();
        session.alpha().to_vec()
    };
    let geodesic = alpha_of(DistanceKind::Geodesic);
    let euclidean = alpha_of(DistanceKind::Euclidean);
    // Along one long side of the strip (y = 0), in order of arc length.
    let mut side: Vec<(f64, usize)> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).y == 0.0)
        .map(|v| (arc[mesh.vertex_index(v)], mesh.vertex_index(v)))
        .collect();
    side.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Largest fall of α below its running maximum, walking from fixed to handle.
    let worst_drop = |alpha: &[f64]| {
        let mut peak = f64::NEG_INFINITY;
        let mut drop = 0.0f64;
        for &(_, i) in &side {
            peak = peak.max(alpha[i]);
            drop = drop.max(peak - alpha[i]);
        }
        drop
    };
    let geodesic_drop = worst_drop(&geodesic);
    let euclidean_drop = worst_drop(&euclidean);
    println!("largest decrease of α along the strip: geodesic {geodesic_drop:.2e}, euclidean {euclidean_drop:.3}");
    assert!(
        geodesic_drop <= 1e-12,
        "geodesic α decreases by {geodesic_drop}"
    );
    assert!(
        euclidean_drop > 0.1,
        "euclidean α should fold back (Fig. 3a)"
    );
    // Geodesic α is close to the arc-length parameter, as in Fig. 3b.
    for &(s, i) in &side {
        if s > s_fixed && s < s_handle {
            let expected = (s - s_fixed) / (s_handle - s_fixed);
            assert!((geodesic[i] - expected).abs() < 0.01, "at s = {s}");
        }
    }
    // Discrete monotonicity everywhere: every deformable vertex has a neighbour with
    // a larger α (or a handle neighbour) and one with a smaller α (or a fixed one).
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        if regions.role(&mesh, v) != Role::Deformable {
            continue;
        }
        let up = mesh.adjacent_vertices(v).any(|w| {
            let j = mesh.vertex_index(w);
            geodesic[j] > geodesic[i] || regions.role(&mesh, w) == Role::Handle
        });
        let down = mesh.adjacent_vertices(v).any(|w| {
            let j = mesh.vertex_index(w);
            geodesic[j] < geodesic[i] || regions.role(&mesh, w) == Role::Fixed
        });
        assert!(up && down, "α has a local extremum at {v}");
    }
}

/// Largest angle between the normals of the two faces of any edge in `edges`.
fn max_dihedral(mesh: &Mesh, edges: impl Iterator<Item = halfedge::HalfedgeId>) -> f64 {
    edges
        .filter_map(|h| {
            let (f, g) = (mesh.face(h)?, mesh.face(mesh.opposite(h))?);
            Some(mesh.face_normal(f).angle_between(mesh.face_normal(g)))
        })
        .fold(0.0, f64::max)
}

/// A disc of radius 1 meshed in rings (`rings` rings of `m` vertices around a centre
/// vertex), so that circles r = k / rings run along edges; handle r ≤ r_handle, fixed
/// r ≥ r_fixed.
fn polar_disc_edit(rings: usize, m: usize, r_handle: f64, r_fixed: f64) -> (Mesh, Regions) {
    let mut positions = vec![DVec3::ZERO];
    for k in 1..=rings {
        let r = k as f64 / rings as f64;
        for j in 0..m {
            let t = j as f64 / m as f64 * std::f64::consts::TAU;
            positions.push(DVec3::new(r * t.cos(), r * t.sin(), 0.0));
        }
    }
    let id = |k: usize, j: usize| (1 + (k - 1) * m + j % m) as u32;
    let mut triangles = Vec::new();
    for j in 0..m {
        triangles.push([0, id(1, j), id(1, j + 1)]);
    }
    for k in 1..rings {
        for j in 0..m {
            triangles.push([id(k, j), id(k + 1, j), id(k + 1, j + 1)]);
            triangles.push([id(k, j), id(k + 1, j + 1), id(k, j + 1)]);
        }
    }
    let mesh = Mesh::from_triangles(&positions, &triangles).unwrap().0;
    let eps = 1e-9;
    let handle: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).length() <= r_handle + eps)
        .collect();
    let fixed: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).length() >= r_fixed - eps)
        .collect();
    let regions = Regions::from_sets(&mesh, &handle, &fixed).unwrap();
    (mesh, regions)
}

#[test]
fn c1_shape_function_leaves_no_crease_at_either_border() {
    let mut results = Vec::new();
    for shape in [
        ShapeFunction::Linear,
        ShapeFunction::Smoothstep,
        ShapeFunction::Curve(
            ShapeCurve::new(&[(0.3, 0.2), (0.6, 0.7)], CurveOptions::default()).unwrap(),
        ),
    ] {
        let (mut mesh, regions) = polar_disc_edit(40, 96, 0.25, 0.85);
        let mut session = BlendSession::new(
            &mesh,
            regions.clone(),
            BlendOptions::default()
                .with_distance(DistanceKind::Geodesic)
                .with_shape(shape.clone()),
        )
        .unwrap();
        session
            .apply(
                &mut mesh,
                DMat4::from_translation(DVec3::new(0.0, 0.0, 0.3)),
            )
            .unwrap();
        let role = |v| regions.role(&mesh, v);
        let border_edges = |kind: Role| {
            let mesh = &mesh;
            mesh.edges().filter(move |&h| {
                role(mesh.from_vertex(h)) == kind && role(mesh.to_vertex(h)) == kind && {
                    [h, mesh.opposite(h)].iter().any(|&g| {
                        mesh.face(g).is_some()
                            && role(mesh.to_vertex(mesh.next(g))) == Role::Deformable
                    })
                }
            })
        };
        let inside = max_dihedral(
            &mesh,
            mesh.edges().filter(|&h| {
                role(mesh.from_vertex(h)) == Role::Deformable
                    && role(mesh.to_vertex(h)) == Role::Deformable
            }),
        );
        let at_fixed = max_dihedral(&mesh, border_edges(Role::Fixed));
        let at_handle = max_dihedral(&mesh, border_edges(Role::Handle));
        println!(
            "{shape:?}: max dihedral inside {:.2}°, at the fixed border {:.2}°, at the handle border {:.2}°",
            inside.to_degrees(),
            at_fixed.to_degrees(),
            at_handle.to_degrees()
        );
        results.push((inside, at_fixed, at_handle));
    }
    let (lin_inside, lin_fixed, lin_handle) = results[0];
    // Linear: a crease at both borders, much sharper than anything inside.
    assert!(lin_fixed > 3.0 * lin_inside && lin_handle > 3.0 * lin_inside);
    for &(inside, at_fixed, at_handle) in &results[1..] {
        // C¹ (f'(0) = f'(1) = 0): the borders bend no more than the inside does.
        assert!(at_fixed <= inside && at_handle <= inside);
        assert!(at_fixed < 0.25 * lin_fixed && at_handle < 0.25 * lin_handle);
    }
}

#[test]
fn refinement_splits_stretched_triangles_and_keeps_the_mesh_valid() {
    for kind in [DistanceKind::Geodesic, DistanceKind::Euclidean] {
        let (mut mesh, regions) = disc_edit(16, 0.2, 0.9);
        let mean = mesh.mean_edge_length();
        let mut session = BlendSession::new(
            &mesh,
            regions,
            BlendOptions::default()
                .with_distance(kind)
                .with_shape(ShapeFunction::Smoothstep),
        )
        .unwrap();
        let a = DMat4::from_translation(DVec3::new(0.0, 0.0, 1.5));
        session.apply(&mut mesh, a).unwrap();
        let (v0, f0) = (mesh.n_vertices(), mesh.n_faces());
        let report = session
            .refine(&mut mesh, RefineOptions::new(1.5 * mean))
            .unwrap();
        mesh.check().unwrap();
        println!("{kind:?}: {report:?}, {} → {} faces", f0, mesh.n_faces());
        assert!(report.new_vertices > 0);
        assert_eq!(mesh.n_vertices(), v0 + report.new_vertices);
        assert_eq!(mesh.n_faces(), f0 + 2 * report.new_vertices);
        assert!(report.longest_edge <= 1.5 * mean);
        assert_invariants(&mesh, &session, a);
        // New vertices: inside the deformable area, on the blended surface.
        for v in mesh.vertices().skip(v0) {
            assert_eq!(session.regions().role(&mesh, v), Role::Deformable);
        }
        // Further edits move the refined mesh consistently.
        let b = DMat4::from_rotation_translation(
            DQuat::from_rotation_x(0.5),
            DVec3::new(0.0, 0.2, 1.0),
        );
        session.apply(&mut mesh, b).unwrap();
        assert_invariants(&mesh, &session, b);
        mesh.check().unwrap();
    }
}

#[test]
fn virtual_origin_distances_of_new_vertices() {
    // Handle: the single centre vertex, a point source; fixed: the rings from r = 0.85
    // on (a circle along edges, so that both fields are smooth).
    let (mut mesh, _) = polar_disc_edit(12, 32, 0.2, 0.85);
    let centre = mesh
        .vertices()
        .find(|&v| mesh.position(v).length() < 1e-12)
        .unwrap();
    let fixed: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).length() > 0.84)
        .collect();
    let regions = Regions::from_sets(&mesh, &[centre], &fixed).unwrap();
    let longest = mesh
        .edges()
        .map(|h| mesh.edge_length(h))
        .fold(0.0, f64::max);
    let mean = mesh.mean_edge_length();
    let mut session = BlendSession::new(&mesh, regions, BlendOptions::default()).unwrap();
    session
        .apply(
            &mut mesh,
            DMat4::from_translation(DVec3::new(0.0, 0.0, 0.8)),
        )
        .unwrap();
    let v0 = mesh.n_vertices();
    session
        .refine(&mut mesh, RefineOptions::new(1.2 * mean))
        .unwrap();
    mesh.check().unwrap();
    // A fresh march from the fixed border on the refined *original* geometry.
    let mut flat = mesh.clone();
    flat.positions_mut()
        .copy_from_slice(&session.original_positions()[..mesh.vertex_slots()]);
    let marching = FastMarching::new(&flat);
    let sources: Vec<MarchSource> = session
        .regions()
        .fixed_border()
        .vertices
        .iter()
        .map(|&v| MarchSource::on_curve(flat.vertex_index(v)))
        .collect();
    let fresh = marching.distances(&sources, None).unwrap();
    let (mut n, mut sum, mut worst, mut worst_exact) = (0, 0.0, 0.0f64, 0.0f64);
    for v in mesh.vertices().skip(v0) {
        let i = mesh.vertex_index(v);
        let p = session.original_positions()[i];
        // Point source: the virtual origin is exact (and so is the march on the grid).
        let exact = p.distance(flat.position(centre));
        assert!(
            (session.handle_distances()[i] - exact).abs() < 1e-12,
            "{} vs {exact}",
            session.handle_distances()[i]
        );
        // Fronts from the fixed border are curves (R = ∞): the virtual origin recedes to
        // infinity, the midpoint takes the mean of its ends. Compared with a fresh march
        // and with the exact distance to the border polyline (the mesh is planar).
        let (approx, reference) = (session.fixed_distances()[i], fresh[i]);
        let exact_line = session
            .regions()
            .fixed_border()
            .edges
            .iter()
            .map(|&(a, b)| {
                edit::bendels_klein::point_segment_distance(p, flat.position(a), flat.position(b))
            })
            .fold(f64::INFINITY, f64::min);
        worst = worst.max((approx - reference).abs());
        worst_exact = worst_exact.max((approx - exact_line).abs());
        sum += (approx - reference).abs() / reference;
        n += 1;
    }
    println!(
        "{n} new vertices; fixed-border distance: mean relative deviation {:.2e}, max {:.2e} ({:.2e} edge lengths) from a fresh march, max {:.2e} from the exact distance",
        sum / n as f64,
        worst,
        worst / longest,
        worst_exact
    );
    assert!(n > 100);
    assert!(worst < 0.05 * longest && worst_exact < 0.05 * longest);
}

#[test]
fn regions_drawn_by_picks_drive_a_session() {
    let mesh = generators::icosphere(4);
    let near = |p: DVec3| {
        mesh.vertices()
            .min_by(|&a, &b| {
                mesh.position(a)
                    .distance(p)
                    .total_cmp(&mesh.position(b).distance(p))
            })
            .unwrap()
    };
    let ring = |z: f64, n: usize| -> Vec<VertexId> {
        let r = (1.0 - z * z).sqrt();
        (0..n)
            .map(|k| {
                let t = k as f64 / n as f64 * std::f64::consts::TAU;
                near(DVec3::new(r * t.cos(), r * t.sin(), z))
            })
            .collect()
    };
    let regions = Regions::from_picks(&mesh, &ring(0.9, 6), &ring(0.0, 12)).unwrap();

    // The handle is the cap above the upper loop, the fixed area the southern half (the
    // loops zigzag by up to two edges around their circles).
    for v in mesh.vertices() {
        let z = mesh.position(v).z;
        let role = regions.role(&mesh, v);
        if z > 0.97 {
            assert_eq!(role, Role::Handle);
        } else if z > 0.25 && z < 0.8 {
            assert_eq!(role, Role::Deformable);
        } else if z < -0.25 {
            assert_eq!(role, Role::Fixed);
        }
    }
    let mut mesh = mesh;
    let mut session = BlendSession::new(&mesh, regions, BlendOptions::default()).unwrap();
    let a = DMat4::from_translation(DVec3::new(0.0, 0.0, 0.5));
    session.apply(&mut mesh, a).unwrap();
    assert_invariants(&mesh, &session, a);
}
