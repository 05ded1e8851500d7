//! The paper's examples on a real mesh (Bendels & Klein, Fig. 7 and 8): pull the Stanford
//! bunny's nose with a translation and with a rotation, rotate its ear; refine the
//! stretched area. The default tier runs them on a stand-in of the bunny's size, density
//! and pose: `data/creature.obj` subdivided twice, turned to look along −x and scaled
//! to the bunny's bounding box; the bunny itself is the real-mesh tier.

use edit::bendels_klein::FastMarching;
use edit::bendels_klein::ShapeFunction;
use edit::bendels_klein::{BlendOptions, BlendSession, DistanceKind, RefineOptions};
use edit::bendels_klein::{Regions, Role};
use glam::{DMat4, DQuat, DVec3};
use halfedge::{Mesh, VertexId};

/// The bunny's stand-in (the default tier): see [`testkit::stand_in::bunny_at_origin`].
fn creature() -> Mesh {
    testkit::stand_in::bunny_at_origin()
}

/// The Stanford bunny (the real-mesh tier).
fn bunny() -> Mesh {
    testkit::load_shared("stanford-bunny.obj")
}

/// The bunny faces −x: the nose tip is its leftmost vertex, an ear tip its highest.
fn extreme(mesh: &Mesh, key: impl Fn(DVec3) -> f64) -> VertexId {
    mesh.vertices()
        .filter(|&v| !mesh.is_isolated(v))
        .max_by(|&a, &b| key(mesh.position(a)).total_cmp(&key(mesh.position(b))))
        .unwrap()
}

/// Vertices at Euclidean distance ≈ `radius` from `centre`, picked around `axis` at `n`
/// even angles: the clicks that draw a border loop with the paper's 3D cursor.
fn picks_around(mesh: &Mesh, centre: DVec3, axis: DVec3, radius: f64, n: usize) -> Vec<VertexId> {
    let u = axis.any_orthonormal_vector();
    let w = axis.cross(u);
    let candidates: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| !mesh.is_isolated(v))
        .filter(|&v| (mesh.position(v).distance(centre) - radius).abs() < 0.15 * radius)
        .collect();
    (0..n)
        .map(|k| {
            let t = k as f64 / n as f64 * std::f64::consts::TAU;
            let target = u * t.cos() + w * t.sin();
            *candidates
                .iter()
                .max_by(|&&a, &&b| {
                    let da = (mesh.position(a) - centre).normalize().dot(target);
                    let db = (mesh.position(b) - centre).normalize().dot(target);
                    da.total_cmp(&db)
                })
                .unwrap()
        })
        .collect()
}

fn assert_edit(mesh: &Mesh, session: &BlendSession, a: DMat4) {
    let original = session.original_positions();
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        match session.regions().role(mesh, v) {
            Role::Fixed => assert_eq!(
                mesh.position(v).to_array().map(f64::to_bits),
                original[i].to_array().map(f64::to_bits)
            ),
            Role::Handle => assert_eq!(mesh.position(v), a.transform_point3(original[i])),
            Role::Deformable => assert!(mesh.position(v).is_finite()),
        }
    }
}

fn nose_regions(mesh: &Mesh) -> (Regions, DVec3) {
    let tip = extreme(mesh, |p| -p.x);
    let centre = mesh.position(tip);
    let handle = picks_around(mesh, centre, DVec3::X, 0.008, 6);
    let fixed = picks_around(mesh, centre, DVec3::X, 0.03, 12);
    let regions = Regions::from_picks(mesh, &handle, &fixed).expect("nose regions");
    (regions, centre)
}

#[test]
fn pull_the_nose_with_a_translation() {
    pull_the_nose_with_a_translation_with(&creature);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn pull_the_nose_with_a_translation_of_the_bunny() {
    pull_the_nose_with_a_translation_with(&bunny);
}

fn pull_the_nose_with_a_translation_with(bunny: &dyn Fn() -> Mesh) {
    let mut mesh = bunny();
    let (regions, tip) = nose_regions(&mesh);
    println!(
        "nose: handle {} vertices, deformable {}, fixed {}",
        regions.handle().len(),
        regions.deformable().len(),
        regions.n_fixed()
    );
    assert!(regions.handle().len() >= 5 && regions.deformable().len() > 200);
    // The handle is around the tip, the fixed area far from it.
    for &v in regions.handle() {
        assert!(mesh.position(v).distance(tip) < 0.015);
    }
    let mut session = BlendSession::new(&mesh, regions, BlendOptions::default()).unwrap();
    let t = DVec3::new(-0.02, 0.005, 0.0);
    let a = DMat4::from_translation(t);
    session.apply(&mut mesh, a).unwrap();
    assert_edit(&mesh, &session, a);
    let mut monotone_violations = 0;
    for &v in session.regions().deformable() {
        let i = mesh.vertex_index(v);
        let moved = mesh.position(v) - session.original_positions()[i];
        assert!((moved - session.alpha()[i] * t).length() < 1e-15);
        // Geodesic α: no local extremum inside the deformable area.
        let alpha = session.alpha();
        let role = |w| session.regions().role(&mesh, w);
        let up = mesh
            .adjacent_vertices(v)
            .any(|w| alpha[mesh.vertex_index(w)] > alpha[i] || role(w) == Role::Handle);
        let down = mesh
            .adjacent_vertices(v)
            .any(|w| alpha[mesh.vertex_index(w)] < alpha[i] || role(w) == Role::Fixed);
        monotone_violations += usize::from(!(up && down));
    }
    assert_eq!(monotone_violations, 0);
    // Stretched triangles get refined; the mesh stays valid and the edit exact.
    let mean = mesh.mean_edge_length();
    let report = session
        .refine(&mut mesh, RefineOptions::new(2.0 * mean))
        .unwrap();
    println!("nose refinement: {report:?}");
    mesh.check().unwrap();
    assert!(report.longest_edge <= 2.0 * mean);
    assert_edit(&mesh, &session, a);
}

#[test]
fn pull_the_nose_with_a_rotation() {
    pull_the_nose_with_a_rotation_with(&creature);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn pull_the_nose_with_a_rotation_of_the_bunny() {
    pull_the_nose_with_a_rotation_with(&bunny);
}

fn pull_the_nose_with_a_rotation_with(bunny: &dyn Fn() -> Mesh) {
    let mut mesh = bunny();
    let (regions, _) = nose_regions(&mesh);
    // Rotate about a vertical axis through the back of the fixed border loop.
    let border = &regions.fixed_border().vertices;
    let pivot = border.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / border.len() as f64
        + DVec3::new(0.02, 0.0, 0.0);
    let axis = DVec3::Y;
    let theta = 0.6;
    let a = DMat4::from_translation(pivot)
        * DMat4::from_quat(DQuat::from_axis_angle(axis, theta))
        * DMat4::from_translation(-pivot);
    let mut session = BlendSession::new(
        &mesh,
        regions,
        BlendOptions::default()
            .with_distance(DistanceKind::Geodesic)
            .with_shape(ShapeFunction::Smootherstep),
    )
    .unwrap();
    session.apply(&mut mesh, a).unwrap();
    assert_edit(&mesh, &session, a);
    // α ⊙ A is the rotation by αθ about the same axis: the distance to the axis and the
    // height along it are kept, the angle turned is αθ.
    for &v in session.regions().deformable() {
        let i = mesh.vertex_index(v);
        let (p, q) = (
            session.original_positions()[i] - pivot,
            mesh.position(v) - pivot,
        );
        assert!((p.y - q.y).abs() < 1e-12);
        let (rp, rq) = (DVec3::new(p.x, 0.0, p.z), DVec3::new(q.x, 0.0, q.z));
        assert!((rp.length() - rq.length()).abs() < 1e-12);
        let turned = rp.cross(rq).y.atan2(rp.dot(rq));
        assert!((turned - session.alpha()[i] * theta).abs() < 1e-9);
    }
}

#[test]
fn rotate_the_ear() {
    rotate_the_ear_with(&creature);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn rotate_the_ear_of_the_bunny() {
    rotate_the_ear_with(&bunny);
}

fn rotate_the_ear_with(bunny: &dyn Fn() -> Mesh) {
    let mesh = bunny();
    let tip = extreme(&mesh, |p| p.y);
    let marching = FastMarching::new(&mesh);
    let d = marching.distances_from_points(&mesh, &[tip], None).unwrap();
    let handle: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| d[mesh.vertex_index(v)] < 0.02)
        .collect();
    let fixed: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| d[mesh.vertex_index(v)] > 0.06)
        .collect();
    let regions = Regions::from_sets(&mesh, &handle, &fixed).unwrap();
    println!(
        "ear: handle {} vertices, deformable {}, fixed {}",
        regions.handle().len(),
        regions.deformable().len(),
        regions.n_fixed()
    );
    let base = regions
        .fixed_border()
        .vertices
        .iter()
        .map(|&v| mesh.position(v))
        .sum::<DVec3>()
        / regions.fixed_border().vertices.len() as f64;
    let axis = DVec3::new(1.0, 0.0, 1.0).normalize();
    let theta = -0.8;
    let a = DMat4::from_translation(base)
        * DMat4::from_axis_angle(axis, theta)
        * DMat4::from_translation(-base);
    let before = testkit::check::snapshot(&mesh);
    for kind in [DistanceKind::Euclidean, DistanceKind::Geodesic] {
        let mut mesh = mesh.clone();
        let mut session = BlendSession::new(
            &mesh,
            regions.clone(),
            BlendOptions::default()
                .with_distance(kind)
                .with_shape(ShapeFunction::Smoothstep),
        )
        .unwrap();
        session.apply(&mut mesh, a).unwrap();
        assert_edit(&mesh, &session, a);
        // The ear tip turned by θ about the axis through the base.
        let (p, q) = (
            session.original_positions()[mesh.vertex_index(tip)] - base,
            mesh.position(tip) - base,
        );
        assert!((p.dot(axis) - q.dot(axis)).abs() < 1e-12);
        assert!((p.length() - q.length()).abs() < 1e-12);
        let mean = mesh.mean_edge_length();
        let report = session
            .refine(&mut mesh, RefineOptions::new(2.0 * mean))
            .unwrap();
        println!("ear, {kind:?}: {report:?}");
        mesh.check().unwrap();
        assert_edit(&mesh, &session, a);
    }
    // The original mesh is untouched by the clones' edits: the same positions bit for bit
    // and the same connectivity, handle for handle.
    mesh.check().unwrap();
    assert_eq!(testkit::check::snapshot(&mesh), before);
}
