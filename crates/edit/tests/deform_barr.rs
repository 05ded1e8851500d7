//! Barr's taper, twist and bend (Barr 1984) as standalone deformers on meshes.

use edit::deform::DeformError;
use edit::deform::{apply_deformer, Bend, Deformer, Profile, Taper, Twist};
use edit::Vertices;
use glam::DVec3;
use halfedge::generators;
use testkit::check::{bit_identical, max_distance};
use testkit::meshes::closed_box;

fn deformers() -> (Taper, Twist, Bend) {
    let axis = DVec3::new(0.2, 1.0, -0.1);
    let c = DVec3::new(0.1, -0.3, 0.05);
    (
        Taper::new(c, axis, Profile::local(-0.5, 0.8, 0.6, 1.7).unwrap()).unwrap(),
        Twist::new(c, axis, Profile::local(-0.7, 0.9, -0.4, 1.3).unwrap()).unwrap(),
        Bend::new(c, axis, DVec3::X, 0.9, Some((-0.4, 0.6))).unwrap(),
    )
}

#[test]
fn identity_parameters_leave_positions_bit_identical() {
    let mut mesh = generators::icosphere(3);
    // include signed zeros and odd values
    mesh.positions_mut()[0] = DVec3::new(-0.0, 0.0, -1.0);
    let before = mesh.positions().to_vec();
    let axis = DVec3::new(0.3, 0.4, 1.0);
    let c = DVec3::new(0.01, 0.02, 0.03);
    let identities: Vec<Box<dyn Deformer>> = vec![
        Box::new(Taper::new(c, axis, Profile::local(-1.0, 1.0, 1.0, 1.0).unwrap()).unwrap()),
        Box::new(Taper::new(c, axis, Profile::global(-1.0, 1.0, 1.0, 1.0).unwrap()).unwrap()),
        Box::new(Twist::linear(c, axis, -1.0, 1.0, 0.0).unwrap()),
        Box::new(Bend::new(c, axis, DVec3::X, 0.0, None).unwrap()),
        Box::new(Bend::new(c, axis, DVec3::X, 0.0, Some((-0.5, 0.5))).unwrap()),
    ];
    for d in &identities {
        apply_deformer(&mut mesh, d.as_ref(), Vertices::All).unwrap();
        assert!(bit_identical(&before, mesh.positions()));
        for p in &before {
            assert_eq!(
                d.deform_point(*p).to_array().map(f64::to_bits),
                p.to_array().map(f64::to_bits)
            );
        }
    }
    // a local twist leaves everything below its range bit-identical
    let twist = Twist::linear(DVec3::ZERO, DVec3::Z, 0.2, 0.9, 1.0).unwrap();
    apply_deformer(&mut mesh, &twist, Vertices::All).unwrap();
    for (a, b) in before.iter().zip(mesh.positions()) {
        if a.z < 0.2 {
            assert_eq!(
                a.to_array().map(f64::to_bits),
                b.to_array().map(f64::to_bits)
            );
        }
    }
}

#[test]
fn twist_then_inverse_restores_to_1e12() {
    twist_then_inverse_restores_to_1e12_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn twist_then_inverse_restores_to_1e12_on_real_meshes() {
    twist_then_inverse_restores_to_1e12_with(&testkit::load_shared);
}

fn twist_then_inverse_restores_to_1e12_with(load: &dyn Fn(&str) -> halfedge::Mesh) {
    let mut mesh = load("spot.obj");
    let before = mesh.positions().to_vec();
    let (_, twist, _) = deformers();
    apply_deformer(&mut mesh, &twist, Vertices::All).unwrap();
    assert!(max_distance(&before, mesh.positions()) > 0.1);
    apply_deformer(&mut mesh, &twist.inverse(), Vertices::All).unwrap();
    assert!(max_distance(&before, mesh.positions()) < 1e-12);
    // the inverse is the twist by −θ
    let minus = Twist::new(
        twist.centre(),
        twist.axis(),
        Profile::local(-0.7, 0.9, 0.4, -1.3).unwrap(),
    )
    .unwrap();
    apply_deformer(&mut mesh, &twist, Vertices::All).unwrap();
    apply_deformer(&mut mesh, &minus, Vertices::All).unwrap();
    assert!(max_distance(&before, mesh.positions()) < 1e-12);
}

#[test]
fn taper_and_bend_inverses_restore_to_1e12() {
    taper_and_bend_inverses_restore_to_1e12_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn taper_and_bend_inverses_restore_to_1e12_on_real_meshes() {
    taper_and_bend_inverses_restore_to_1e12_with(&testkit::load_shared);
}

fn taper_and_bend_inverses_restore_to_1e12_with(load: &dyn Fn(&str) -> halfedge::Mesh) {
    let mut mesh = load("spot.obj");
    let before = mesh.positions().to_vec();
    let (taper, _, bend) = deformers();
    apply_deformer(&mut mesh, &taper, Vertices::All).unwrap();
    assert!(max_distance(&before, mesh.positions()) > 0.05);
    apply_deformer(&mut mesh, &taper.inverse(), Vertices::All).unwrap();
    assert!(max_distance(&before, mesh.positions()) < 1e-12);

    apply_deformer(&mut mesh, &bend, Vertices::All).unwrap();
    assert!(max_distance(&before, mesh.positions()) > 0.05);
    apply_deformer(&mut mesh, &bend.inverse(), Vertices::All).unwrap();
    assert!(max_distance(&before, mesh.positions()) < 1e-12);
    mesh.check().unwrap();
}

#[test]
fn bend_keeps_arc_length_of_the_axis_and_cross_sections_rigid() {
    // a slender box along y, bent by a quarter turn over its length
    let mut mesh = closed_box(
        DVec3::new(-0.05, 0.0, -0.05),
        DVec3::new(0.05, 2.0, 0.05),
        [2, 40, 2],
    );
    let before = mesh.positions().to_vec();
    let k = std::f64::consts::FRAC_PI_2 / 2.0;
    let bend = Bend::new(DVec3::ZERO, DVec3::Y, DVec3::Z, k, Some((0.0, 2.0))).unwrap();
    apply_deformer(&mut mesh, &bend, Vertices::All).unwrap();
    for (p, q) in before.iter().zip(mesh.positions()) {
        // the neutral line z = 0 maps onto the circle of radius 1/k about (·, 0, 1/k)
        let r = 1.0 / k - p.z;
        let centre = DVec3::new(q.x, 0.0, 1.0 / k);
        assert!((q.distance(centre) - r).abs() < 1e-12);
        assert!((q.x - p.x).abs() < 1e-15);
        // the angle on the circle is k·y
        let angle = q.y.atan2(1.0 / k - q.z);
        assert!((angle - k * p.y).abs() < 1e-12);
    }
}

#[test]
fn selections_move_only_their_vertices_and_errors_change_nothing() {
    let mut mesh = generators::icosphere(3);
    let before = mesh.positions().to_vec();
    let (_, twist, _) = deformers();
    let mask =
        halfedge::VertexData::new(&mesh, before.iter().map(|p| p.x > 0.3).collect()).unwrap();
    apply_deformer(&mut mesh, &twist, Vertices::Mask(&mask)).unwrap();
    for (i, (a, b)) in before.iter().zip(mesh.positions()).enumerate() {
        if mask[i] {
            assert!(b.distance(twist.deform_point(*a)) == 0.0);
        } else {
            assert_eq!(a, b);
        }
    }
    let mut mesh = generators::icosphere(3);
    let list: Vec<_> = mesh.vertices().step_by(7).collect();
    apply_deformer(&mut mesh, &twist, Vertices::List(&list)).unwrap();
    let moved = before
        .iter()
        .zip(mesh.positions())
        .filter(|(a, b)| a != b)
        .count();
    assert!(moved > 0 && moved <= list.len());

    let mut mesh = generators::icosphere(3);
    // A mask made for another mesh, even one of the same size, is stale.
    let other = generators::icosphere(3);
    assert!(matches!(
        apply_deformer(
            &mut mesh,
            &twist,
            Vertices::Mask(&halfedge::VertexData::filled(&other, true))
        ),
        Err(DeformError::Stale(_))
    ));
    // a global taper reaching zero on the object is refused before anything moves
    let taper = Taper::new(
        DVec3::ZERO,
        DVec3::Z,
        Profile::global(-1.0, 0.0, 0.0, 1.0).unwrap(),
    )
    .unwrap();
    assert!(matches!(
        apply_deformer(&mut mesh, &taper, Vertices::All),
        Err(DeformError::NonPositiveTaper { .. })
    ));
    assert!(bit_identical(&before, mesh.positions()));
}
