//! The editing session of Lee 1999 on real meshes: fixed boundary, the scale parameter's
//! effect on the moved region, the primitive reaching its targets, the paper's nose edit
//! (Fig. 7), and bad input.

use edit::lee::LeeError;
use edit::lee::{AreaSession, EditingArea, FrameKind, SessionOptions};
use glam::DVec3;
use halfedge::{Mesh, VertexId};
use testkit::regions::nose;

const PULL: DVec3 = DVec3::new(0.03, -0.02, 0.12);

/// Spot (or its stand-in, whichever `load` gives) with an area of about 500 vertices
/// around the snout.
fn spot_session(load: &dyn Fn(&str) -> Mesh, options: &SessionOptions) -> (Mesh, AreaSession) {
    let mesh = load("spot.obj");
    let area = EditingArea::disk_around(&mesh, nose(&mesh), 500).unwrap();
    let session = AreaSession::new(&mesh, area, options).unwrap();
    (mesh, session)
}

/// Vertices whose position differs from `before` (bitwise).
fn moved(mesh: &Mesh, before: &[DVec3]) -> Vec<VertexId> {
    mesh.vertices()
        .filter(|&v| mesh.position(v) != before[mesh.vertex_index(v)])
        .collect()
}

/// Area (at rest) of the faces with a vertex displaced by more than `threshold`.
fn moved_face_area(mesh: &Mesh, before: &[DVec3], threshold: f64) -> f64 {
    let moved =
        |v: VertexId| (mesh.position(v) - before[mesh.vertex_index(v)]).length() > threshold;
    mesh.faces()
        .filter(|&f| mesh.triangle(f).into_iter().any(moved))
        .map(|f| {
            let [a, b, c] = mesh.triangle(f).map(|v| before[mesh.vertex_index(v)]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

fn nose_and_ring(mesh: &Mesh) -> Vec<VertexId> {
    let nose = nose(mesh);
    std::iter::once(nose)
        .chain(mesh.adjacent_vertices(nose))
        .collect()
}

#[test]
fn boundary_and_outside_never_move_for_any_scale() {
    boundary_and_outside_never_move_for_any_scale_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn boundary_and_outside_never_move_for_any_scale_on_real_meshes() {
    boundary_and_outside_never_move_for_any_scale_with(&testkit::load_shared);
}

fn boundary_and_outside_never_move_for_any_scale_with(load: &dyn Fn(&str) -> Mesh) {
    for frames in [
        FrameKind::Global,
        FrameKind::Normal {
            seed: None,
            x_axis: None,
        },
    ] {
        let options = SessionOptions::default().with_frames(frames);
        let (mut mesh, mut session) = spot_session(load, &options);
        let rest = mesh.positions().to_vec();
        session.set_primitive(&mesh, &nose_and_ring(&mesh)).unwrap();
        for k in 0..=20 {
            session.set_scale(k as f64 / 20.0).unwrap();
            session.drag(&mut mesh, PULL).unwrap();
            for v in mesh.vertices() {
                let inside =
                    session.area().contains(&mesh, v) && !session.area().is_boundary(&mesh, v);
                if !inside {
                    assert_eq!(
                        mesh.position(v),
                        rest[mesh.vertex_index(v)],
                        "s = {}",
                        k as f64 / 20.0
                    );
                }
            }
        }
        mesh.check().unwrap();
    }
}

#[test]
fn scale_zero_moves_only_the_primitive_and_scale_one_the_whole_area() {
    scale_zero_moves_only_the_primitive_and_scale_one_the_whole_area_with(
        &testkit::stand_in::by_shape,
    );
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn scale_zero_moves_only_the_primitive_and_scale_one_the_whole_area_on_real_meshes() {
    scale_zero_moves_only_the_primitive_and_scale_one_the_whole_area_with(&testkit::load_shared);
}

fn scale_zero_moves_only_the_primitive_and_scale_one_the_whole_area_with(
    load: &dyn Fn(&str) -> Mesh,
) {
    let (mut mesh, mut session) = spot_session(load, &SessionOptions::default());
    let rest = mesh.positions().to_vec();
    let primitive = nose_and_ring(&mesh);
    session.set_primitive(&mesh, &primitive).unwrap();

    session.set_scale(0.0).unwrap();
    session.drag(&mut mesh, PULL).unwrap();
    let mut moved_at_zero = moved(&mesh, &rest);
    moved_at_zero.sort();
    let mut expected = primitive.clone();
    expected.sort();
    assert_eq!(moved_at_zero, expected);
    for &v in &primitive {
        assert!((mesh.position(v) - (rest[mesh.vertex_index(v)] + PULL)).length() < 1e-15);
    }

    session.set_scale(1.0).unwrap();
    session.apply(&mut mesh).unwrap();
    let moved_at_one = moved(&mesh, &rest);
    assert_eq!(moved_at_one.len(), session.area().n_interior());
    for &v in session.area().interior() {
        assert_ne!(mesh.position(v), rest[mesh.vertex_index(v)]);
    }
}

#[test]
fn moved_region_grows_monotonically_with_scale() {
    moved_region_grows_monotonically_with_scale_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn moved_region_grows_monotonically_with_scale_on_real_meshes() {
    moved_region_grows_monotonically_with_scale_with(&testkit::load_shared);
}

fn moved_region_grows_monotonically_with_scale_with(load: &dyn Fn(&str) -> Mesh) {
    let (mut mesh, mut session) = spot_session(load, &SessionOptions::default());
    let rest = mesh.positions().to_vec();
    session.set_primitive(&mesh, &[nose(&mesh)]).unwrap();
    let mut previous: Vec<bool> = vec![false; mesh.vertex_slots()];
    let mut counts = Vec::new();
    for k in 0..=40 {
        session.set_scale(k as f64 / 40.0).unwrap();
        session.drag(&mut mesh, PULL).unwrap();
        let now: Vec<bool> = (0..mesh.vertex_slots())
            .map(|i| mesh.positions()[i] != rest[i])
            .collect();
        for i in 0..now.len() {
            assert!(
                !previous[i] || now[i],
                "vertex {i} stops moving at s = {}",
                k as f64 / 40.0
            );
        }
        counts.push(now.iter().filter(|&&m| m).count());
        previous = now;
    }
    assert_eq!(counts[0], 1);
    assert_eq!(*counts.last().unwrap(), session.area().n_interior());
    assert!(counts[10] < counts[30], "{counts:?}");
}

#[test]
fn primitive_reaches_its_targets_away_from_the_boundary() {
    primitive_reaches_its_targets_away_from_the_boundary_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn primitive_reaches_its_targets_away_from_the_boundary_on_real_meshes() {
    primitive_reaches_its_targets_away_from_the_boundary_with(&testkit::load_shared);
}

fn primitive_reaches_its_targets_away_from_the_boundary_with(load: &dyn Fn(&str) -> Mesh) {
    let (mut mesh, mut session) = spot_session(load, &SessionOptions::default());
    let rest = mesh.positions().to_vec();
    let nose = nose(&mesh);
    // a single vertex is interpolated exactly at every scale
    session.set_primitive(&mesh, &[nose]).unwrap();
    for k in 0..=10 {
        session.set_scale(k as f64 / 10.0).unwrap();
        session.drag(&mut mesh, PULL).unwrap();
        let error = (mesh.position(nose) - (rest[mesh.vertex_index(nose)] + PULL)).length();
        assert!(
            error < 1e-12 * PULL.length(),
            "s = {}: {error}",
            k as f64 / 10.0
        );
    }
    // a closed chain (the nose's ring) and its centre
    session.cancel(&mut mesh).unwrap();
    let primitive = nose_and_ring(&mesh);
    session.set_primitive(&mesh, &primitive).unwrap();
    for s in [0.25, 0.5, 0.75, 1.0] {
        session.set_scale(s).unwrap();
        session.drag(&mut mesh, PULL).unwrap();
        for &v in &primitive {
            let error = (mesh.position(v) - (rest[mesh.vertex_index(v)] + PULL)).length();
            assert!(
                error < 1e-3 * PULL.length(),
                "s = {s}: {v} misses by {error}"
            );
        }
    }
    // second mode: vertices moved one by one, the others held, then applied
    session.cancel(&mut mesh).unwrap();
    // the held vertex is a third of the rectangle away from the nose in the embedding,
    // farther than the support of the finest B-splines (two cells of 1/16 each way)
    let far = {
        let a = session.area();
        let uv = session.embedding().uv();
        let at_nose = uv[a.local_index(&mesh, nose).unwrap()];
        let size = session.embedding().size().x;
        let i = (0..a.n_interior())
            .find(|&i| (0.3 * size..0.4 * size).contains(&uv[i].distance(at_nose)))
            .unwrap();
        a.vertices()[i]
    };
    session.set_primitive(&mesh, &[nose, far]).unwrap();
    session.set_scale(0.5).unwrap();
    let lift = DVec3::new(0.0, 0.05, 0.05);
    let target = rest[mesh.vertex_index(nose)] + lift;
    session.move_vertex(&mesh, nose, target).unwrap();
    session.apply(&mut mesh).unwrap();
    assert!((mesh.position(nose) - target).length() < 1e-3 * lift.length());
    assert!((mesh.position(far) - rest[mesh.vertex_index(far)]).length() < 1e-3 * lift.length());
    mesh.check().unwrap();
}

#[test]
fn holding_adjacent_vertices_reaches_every_target_at_any_level_count() {
    holding_adjacent_vertices_reaches_every_target_at_any_level_count_with(
        &testkit::stand_in::by_shape,
    );
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn holding_adjacent_vertices_reaches_every_target_at_any_level_count_on_real_meshes() {
    holding_adjacent_vertices_reaches_every_target_at_any_level_count_with(&testkit::load_shared);
}

fn holding_adjacent_vertices_reaches_every_target_at_any_level_count_with(
    load: &dyn Fn(&str) -> Mesh,
) {
    // Moving the nose while holding its one-ring (second mode): the ring is 0.3 % of the
    // rectangle away in the embedding, closer than the dense lattice separates at 6
    // levels; the sparse detail levels at the primitive separate the targets.
    let (mut mesh, mut session) = spot_session(load, &SessionOptions::default());
    let rest = mesh.positions().to_vec();
    let nose = nose(&mesh);
    let ring = nose_and_ring(&mesh);
    let lift = DVec3::new(0.0, 0.05, 0.05);
    let mut errors = Vec::new();
    for levels in [6, 10] {
        session.cancel(&mut mesh).unwrap();
        session.set_levels(levels).unwrap();
        session.set_primitive(&mesh, &ring).unwrap();
        session.set_scale(0.5).unwrap();
        session
            .move_vertex(&mesh, nose, rest[mesh.vertex_index(nose)] + lift)
            .unwrap();
        session.apply(&mut mesh).unwrap();
        let error = ring
            .iter()
            .map(|&v| {
                let target =
                    rest[mesh.vertex_index(v)] + if v == nose { lift } else { DVec3::ZERO };
                (mesh.position(v) - target).length()
            })
            .fold(0.0, f64::max);
        errors.push(error / lift.length());
    }
    assert!(errors.iter().all(|&e| e < 1e-6), "{errors:?}");
}

#[test]
fn pulling_the_nose_makes_a_narrower_bump_at_a_smaller_scale() {
    pulling_the_nose_makes_a_narrower_bump_at_a_smaller_scale_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn pulling_the_nose_makes_a_narrower_bump_at_a_smaller_scale_on_real_meshes() {
    pulling_the_nose_makes_a_narrower_bump_at_a_smaller_scale_with(&testkit::load_shared);
}

fn pulling_the_nose_makes_a_narrower_bump_at_a_smaller_scale_with(load: &dyn Fn(&str) -> Mesh) {
    // Lee 1999 Fig. 7 (b), (c): the nose pulled with s = 0.75 and s = 0.25, global frame.
    let (mut mesh, mut session) = spot_session(load, &SessionOptions::default());
    let rest = mesh.positions().to_vec();
    let nose = nose(&mesh);
    session.set_primitive(&mesh, &[nose]).unwrap();
    let pull = DVec3::new(0.0, 0.0, 0.15);
    let (mut visible, mut any) = (Vec::new(), Vec::new());
    for s in [0.75, 0.25] {
        session.set_scale(s).unwrap();
        session.drag(&mut mesh, pull).unwrap();
        assert!((mesh.position(nose) - (rest[mesh.vertex_index(nose)] + pull)).length() < 1e-12);
        // the bump: faces displaced by more than 1 % of the pull
        visible.push(moved_face_area(&mesh, &rest, 0.01 * pull.length()));
        any.push(moved_face_area(&mesh, &rest, 0.0));
    }
    let area_of_area: f64 = session
        .area()
        .faces()
        .iter()
        .map(|&f| mesh.face_area(f))
        .sum();
    assert!(visible[1] < 0.5 * visible[0], "bump areas {visible:?}");
    assert!(visible[1] > 0.0);
    assert!(any[1] < any[0], "moved areas {any:?}");
    assert!(any[0] <= area_of_area * (1.0 + 1e-9));
}

#[test]
fn normal_frames_move_vertices_along_their_normals() {
    normal_frames_move_vertices_along_their_normals_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn normal_frames_move_vertices_along_their_normals_on_real_meshes() {
    normal_frames_move_vertices_along_their_normals_with(&testkit::load_shared);
}

fn normal_frames_move_vertices_along_their_normals_with(load: &dyn Fn(&str) -> Mesh) {
    let options = SessionOptions::default()
        .with_frames(FrameKind::Normal {
            seed: None,
            x_axis: Some(DVec3::X),
        })
        .with_scale(0.75);
    let (mut mesh, mut session) = spot_session(load, &options);
    let rest = mesh.positions().to_vec();
    let nose = nose(&mesh);
    session.set_primitive(&mesh, &[nose]).unwrap();
    let normal = mesh.vertex_normal(nose);
    session.drag(&mut mesh, 0.1 * normal).unwrap();
    let uv_before = session.embedding().uv().to_vec();
    let mut reference = mesh.clone();
    reference.positions_mut().copy_from_slice(&rest);
    for &v in session.area().interior() {
        let p = rest[mesh.vertex_index(v)];
        let d = mesh.position(v) - p;
        let n = reference.vertex_normal(v);
        // the displacement is read back from f64 positions: near the border, where it
        // falls to 1e-9 of the pull, rounding of `p + d` is the rest
        assert!(
            d.cross(n).length() <= 1e-9 * d.length() + 4.0 * f64::EPSILON * p.length(),
            "{v}: {d} not along {n}"
        );
    }
    // switching back to the global frame re-shapes the edit without re-embedding
    session.set_frames(&mesh, FrameKind::Global).unwrap();
    session.apply(&mut mesh).unwrap();
    assert_eq!(session.embedding().uv(), uv_before.as_slice());
    let far = session
        .area()
        .interior()
        .iter()
        .copied()
        .find(|&v| mesh.position(v) != rest[mesh.vertex_index(v)] && v != nose)
        .unwrap();
    let d = (mesh.position(far) - rest[mesh.vertex_index(far)]).normalize();
    assert!(
        d.dot(normal) > 1.0 - 1e-9,
        "global frame: every vertex moves along the nose normal"
    );
}

#[test]
fn bad_input_is_refused_and_leaves_the_mesh_unchanged() {
    bad_input_is_refused_and_leaves_the_mesh_unchanged_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn bad_input_is_refused_and_leaves_the_mesh_unchanged_on_real_meshes() {
    bad_input_is_refused_and_leaves_the_mesh_unchanged_with(&testkit::load_shared);
}

fn bad_input_is_refused_and_leaves_the_mesh_unchanged_with(load: &dyn Fn(&str) -> Mesh) {
    let (mut mesh, mut session) = spot_session(load, &SessionOptions::default());
    let rest = mesh.positions().to_vec();
    let nose = nose(&mesh);
    assert!(matches!(
        session.drag(&mut mesh, PULL),
        Err(LeeError::EmptyPrimitive)
    ));
    assert!(matches!(
        session.set_primitive(&mesh, &[]),
        Err(LeeError::EmptyPrimitive)
    ));
    // Spot's tail end is far from the snout
    let outside = mesh
        .vertices()
        .find(|&v| !session.area().contains(&mesh, v))
        .unwrap();
    assert!(matches!(
        session.set_primitive(&mesh, &[nose, outside]),
        Err(LeeError::PrimitiveOutsideArea { vertex }) if vertex == outside
    ));
    let on_boundary = session.area().boundary()[0];
    assert!(matches!(
        session.set_primitive(&mesh, &[on_boundary]),
        Err(LeeError::PrimitiveOnAreaBoundary { .. })
    ));
    assert!(session.primitive().is_empty());
    session.set_primitive(&mesh, &[nose, nose]).unwrap();
    assert_eq!(session.primitive(), vec![nose]);
    for bad in [
        DVec3::new(f64::NAN, 0.0, 0.0),
        DVec3::new(0.0, f64::INFINITY, 0.0),
    ] {
        assert!(matches!(
            session.drag(&mut mesh, bad),
            Err(LeeError::NonFiniteDisplacement { .. })
        ));
        assert!(matches!(
            session.move_vertex(&mesh, nose, bad),
            Err(LeeError::NonFiniteTarget { .. })
        ));
    }
    let not_in_primitive = session
        .area()
        .interior()
        .iter()
        .copied()
        .find(|&v| v != nose)
        .unwrap();
    assert!(matches!(
        session.move_vertex(&mesh, not_in_primitive, DVec3::ZERO),
        Err(LeeError::NotInPrimitive { .. })
    ));
    assert!(matches!(
        session.set_scale(f64::NAN),
        Err(LeeError::InvalidParameter { .. })
    ));
    assert!(matches!(
        session.set_scale(1.5),
        Err(LeeError::InvalidParameter { .. })
    ));
    assert!(matches!(
        session.set_levels(2),
        Err(LeeError::InvalidParameter { .. })
    ));
    let mut other = load("cow.obj");
    assert!(matches!(
        session.drag(&mut other, PULL),
        Err(LeeError::Stale(_))
    ));
    assert_eq!(mesh.positions(), rest.as_slice());
    // and the session still works afterwards
    session.drag(&mut mesh, PULL).unwrap();
    assert_ne!(mesh.positions(), rest.as_slice());
}

#[test]
fn parallel_evaluation_matches_the_sequential_one() {
    parallel_evaluation_matches_the_sequential_one_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn parallel_evaluation_matches_the_sequential_one_on_real_meshes() {
    parallel_evaluation_matches_the_sequential_one_with(&testkit::load_shared);
}

fn parallel_evaluation_matches_the_sequential_one_with(load: &dyn Fn(&str) -> Mesh) {
    let (mut sequential, mut a) = spot_session(load, &SessionOptions::default());
    let parallel_options = SessionOptions::default().with_parallel_threshold(1);
    let (mut parallel, mut b) = spot_session(load, &parallel_options);
    let nose = nose(&sequential);
    a.set_primitive(&sequential, &nose_and_ring(&sequential))
        .unwrap();
    b.set_primitive(&parallel, &nose_and_ring(&parallel))
        .unwrap();
    for s in [0.0, 0.3, 1.0] {
        a.set_scale(s).unwrap();
        b.set_scale(s).unwrap();
        a.drag(&mut sequential, PULL).unwrap();
        b.drag(&mut parallel, PULL).unwrap();
        assert_eq!(sequential.positions(), parallel.positions());
    }
    assert_ne!(sequential.position(nose), load("spot.obj").position(nose));
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn spots_snout_areas_fall_off_smoothly_to_the_border() {
    // The areas where the finest-lattice-only fixing creased the surface (the first ring
    // moved 70-86 % of the pull at s = 1): the first ring moves at most d/D of the pull
    // (d its embedded distance to the border, D the nose's), no face next to the border
    // turns over under a pull with a sideways part, and the nose with its ring lands.
    let spot = testkit::load_shared("spot.obj");
    let nose = nose(&spot);
    for n in [150, 500] {
        let mut mesh = spot.clone();
        let rest = mesh.positions().to_vec();
        let area = EditingArea::disk_around(&mesh, nose, n).unwrap();
        let mut session = AreaSession::new(&mesh, area, &SessionOptions::default()).unwrap();
        let a = session.area().clone();
        let uv = session.embedding().uv().to_vec();
        let size = session.embedding().size();
        let to_border = |i: usize| {
            let p = uv[i];
            p.x.min(p.y).min(size.x - p.x).min(size.y - p.y)
        };
        let big = to_border(a.local_index(&mesh, nose).unwrap());
        let ring: Vec<VertexId> = a
            .interior()
            .iter()
            .copied()
            .filter(|&v| mesh.adjacent_vertices(v).any(|w| a.is_boundary(&mesh, w)))
            .collect();
        let near_border: Vec<_> = a
            .faces()
            .iter()
            .copied()
            .filter(|&f| {
                mesh.triangle(f)
                    .iter()
                    .any(|v| a.is_boundary(&mesh, *v) || ring.contains(v))
            })
            .collect();
        let primitive = nose_and_ring(&mesh);
        session.set_primitive(&mesh, &primitive).unwrap();
        let c = rest[mesh.vertex_index(nose)];
        let gap = a
            .boundary()
            .iter()
            .map(|&v| c.distance(rest[mesh.vertex_index(v)]))
            .fold(f64::INFINITY, f64::min);
        let normal = mesh.vertex_normal(nose);
        let pull = 0.5 * gap * (normal + normal.any_orthonormal_vector());
        for s in [0.2, 0.5, 1.0] {
            session.set_scale(s).unwrap();
            session.drag(&mut mesh, pull).unwrap();
            for &v in &ring {
                let d = to_border(a.local_index(&mesh, v).unwrap()) / big;
                let m = (mesh.position(v) - rest[mesh.vertex_index(v)]).length() / pull.length();
                assert!(
                    m <= d,
                    "{n} vertices, s = {s}: {v} at d/D = {d:.3} moves {m:.3}"
                );
            }
            let flipped = near_border
                .iter()
                .filter(|&&f| {
                    let now = mesh.triangle(f).map(|v| mesh.position(v));
                    let was = mesh.triangle(f).map(|v| rest[mesh.vertex_index(v)]);
                    (was[1] - was[0])
                        .cross(was[2] - was[0])
                        .dot((now[1] - now[0]).cross(now[2] - now[0]))
                        <= 0.0
                })
                .count();
            assert_eq!(flipped, 0, "{n} vertices, s = {s}");
            for &v in &primitive {
                let error = (mesh.position(v) - rest[mesh.vertex_index(v)] - pull).length();
                assert!(
                    error <= 1e-3 * pull.length(),
                    "{n} vertices, s = {s}: {v} misses by {error:e}"
                );
            }
        }
    }
}
