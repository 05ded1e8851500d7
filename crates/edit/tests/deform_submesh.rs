//! Sub-mesh edits with propagation levels (*Interactive editing of multiresolution
//! meshes* §4), on generated meshes and on the paper's bunny examples.

use edit::deform::{Axis, Propagation, SubMesh, SubmeshEdit, Variation};
use glam::DVec3;
use halfedge::{generators, Mesh};
use testkit::check::{bit_identical, max_distance};
use testkit::regions::{bunny_ear, bunny_head};

/// A 30×30 grid (bumped so it is not planar) with a disk of radius 4 around the centre
/// inside.
fn grid_disk() -> (Mesh, SubMesh) {
    let mut mesh = generators::grid(30, 30, 30.0, 30.0);
    for p in mesh.positions_mut() {
        p.z = 0.3 * (0.3 * p.x).sin() * (0.2 * p.y).cos();
    }
    let inside: Vec<bool> = mesh
        .positions()
        .iter()
        .map(|p| (p.x - 15.0).hypot(p.y - 15.0) <= 4.0)
        .collect();
    let sub = SubMesh::from_mask(
        &mesh,
        &halfedge::VertexData::new(&mesh, (inside).to_vec()).unwrap(),
    )
    .unwrap();
    (mesh, sub)
}

fn all_edits(mesh: &Mesh, sub: &SubMesh) -> Vec<SubmeshEdit> {
    let axis = sub.axis(mesh).unwrap();
    let (lo, hi) = sub.axial_extent(mesh, &axis).unwrap();
    vec![
        SubmeshEdit::Pull {
            offset: DVec3::new(0.5, -0.2, 1.0),
        },
        SubmeshEdit::Scale {
            centre: DVec3::new(15.0, 15.0, 0.0),
            factor: 1.4,
        },
        SubmeshEdit::Rotate {
            axis: Axis::new(DVec3::new(15.0, 15.0, 0.0), DVec3::new(0.2, 1.0, 0.3)).unwrap(),
            angle: 0.3,
            bounded: false,
        },
        SubmeshEdit::Taper {
            axis: Some(axis),
            factor: 1.5,
            variation: Variation::Uniform,
        },
        SubmeshEdit::Twist {
            axis: Some(Axis::new(axis.point(), DVec3::new(1.0, 0.0, 0.2)).unwrap()),
            angle: 0.4,
            variation: Variation::Along {
                start: lo - 5.0,
                end: hi,
            },
        },
    ]
}

#[test]
fn identity_edits_leave_positions_bit_identical() {
    identity_edits_leave_positions_bit_identical_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn identity_edits_leave_positions_bit_identical_on_real_meshes() {
    identity_edits_leave_positions_bit_identical_with(&testkit::load_shared);
}

fn identity_edits_leave_positions_bit_identical_with(load: &dyn Fn(&str) -> Mesh) {
    let mut mesh = load("stanford-bunny.obj");
    let sub = SubMesh::from_mask(
        &mesh,
        &halfedge::VertexData::new(&mesh, (bunny_ear(&mesh)).to_vec()).unwrap(),
    )
    .unwrap();
    let before = mesh.positions().to_vec();
    let axis = sub.axis(&mesh).unwrap();
    let identities = [
        SubmeshEdit::Pull {
            offset: DVec3::ZERO,
        },
        SubmeshEdit::Scale {
            centre: DVec3::new(0.1, 0.2, 0.3),
            factor: 1.0,
        },
        SubmeshEdit::Rotate {
            axis,
            angle: 0.0,
            bounded: true,
        },
        SubmeshEdit::Rotate {
            axis,
            angle: 0.0,
            bounded: false,
        },
        SubmeshEdit::Taper {
            axis: None,
            factor: 1.0,
            variation: Variation::Levels(None),
        },
        SubmeshEdit::Taper {
            axis: None,
            factor: 1.0,
            variation: Variation::Uniform,
        },
        SubmeshEdit::Twist {
            axis: None,
            angle: 0.0,
            variation: Variation::Along {
                start: 0.0,
                end: 0.01,
            },
        },
    ];
    for edit in &identities {
        for n in [0, 3] {
            sub.apply(&mut mesh, edit, Propagation::linear(n)).unwrap();
            assert!(bit_identical(&before, mesh.positions()), "{edit:?} n = {n}");
        }
    }
}

#[test]
fn without_propagation_nothing_outside_moves() {
    let (mesh0, sub) = grid_disk();
    for edit in all_edits(&mesh0, &sub) {
        let mut mesh = mesh0.clone();
        sub.apply(&mut mesh, &edit, Propagation::NONE).unwrap();
        let mut moved_inside = 0;
        for (i, (a, b)) in mesh0.positions().iter().zip(mesh.positions()).enumerate() {
            if sub.contains_index(i) {
                moved_inside += (a != b) as usize;
            } else {
                assert_eq!(a, b, "{edit:?}: outside vertex {i} moved");
            }
        }
        assert!(moved_inside > 0, "{edit:?} moved nothing");
        mesh.check().unwrap();
    }
}

#[test]
fn propagation_stops_after_n_collars_with_monotone_strength() {
    let (mesh0, sub) = grid_disk();
    let n = 4;
    let collars = sub.collars(&mesh0, n + 3).unwrap();
    for edit in all_edits(&mesh0, &sub) {
        for propagation in [Propagation::linear(n), Propagation::smooth(n)] {
            let mut mesh = mesh0.clone();
            sub.apply(&mut mesh, &edit, propagation).unwrap();
            let moved = |i: u32| mesh0.positions()[i as usize] != mesh.positions()[i as usize];
            for (k, collar) in collars.iter().enumerate() {
                if k >= n {
                    assert!(
                        collar.iter().all(|&i| !moved(i)),
                        "{edit:?}: collar {} moved",
                        k + 1
                    );
                } else {
                    assert!(
                        collar.iter().any(|&i| moved(i)),
                        "{edit:?}: collar {} still",
                        k + 1
                    );
                }
            }
            // everything that moved is inside or within n collars
            let near: Vec<bool> = {
                let mut m = sub.mask().to_vec();
                for c in &collars[..n] {
                    for &i in c {
                        m[i as usize] = true;
                    }
                }
                m
            };
            for (i, flag) in near.iter().enumerate() {
                if !flag {
                    assert!(!moved(i as u32));
                }
            }
        }
    }
    // the strength is monotone across collars: measured on a pull (displacement per
    // collar is constant within it and decreases with k)
    let offset = DVec3::new(0.0, 0.0, 2.0);
    let mut mesh = mesh0.clone();
    sub.apply(
        &mut mesh,
        &SubmeshEdit::Pull { offset },
        Propagation::linear(n),
    )
    .unwrap();
    let mut previous = offset.length();
    for collar in &collars[..n] {
        let d: Vec<f64> = collar
            .iter()
            .map(|&i| mesh.positions()[i as usize].distance(mesh0.positions()[i as usize]))
            .collect();
        let first = d[0];
        assert!(d.iter().all(|x| (x - first).abs() < 1e-12));
        assert!(first < previous && first > 0.0);
        previous = first;
    }
    // and on a scale: the factor per collar decreases from s towards 1
    let centre = DVec3::new(15.0, 15.0, -3.0);
    let mut mesh = mesh0.clone();
    sub.apply(
        &mut mesh,
        &SubmeshEdit::Scale {
            centre,
            factor: 2.0,
        },
        Propagation::smooth(n),
    )
    .unwrap();
    let mut previous = 2.0;
    for collar in &collars[..n] {
        let i = collar[0] as usize;
        let f = (mesh.positions()[i] - centre).length() / (mesh0.positions()[i] - centre).length();
        assert!(f < previous && f > 1.0);
        previous = f;
    }
}

#[test]
fn inverse_edits_restore_and_snapshots_undo_exactly() {
    let (mesh0, sub) = grid_disk();
    for edit in all_edits(&mesh0, &sub) {
        for n in [0, 3] {
            let mut mesh = mesh0.clone();
            sub.apply(&mut mesh, &edit, Propagation::linear(n)).unwrap();
            assert!(max_distance(mesh0.positions(), mesh.positions()) > 0.01);
            sub.apply(&mut mesh, &edit.inverse().unwrap(), Propagation::linear(n))
                .unwrap();
            assert!(
                max_distance(mesh0.positions(), mesh.positions()) < 1e-12,
                "{edit:?} n = {n}: {}",
                max_distance(mesh0.positions(), mesh.positions())
            );
            let snapshot = sub.apply(&mut mesh, &edit, Propagation::linear(n)).unwrap();
            snapshot.restore(&mut mesh).unwrap();
            let mut undone = mesh0.clone();
            sub.apply(&mut undone, &edit, Propagation::linear(n))
                .unwrap();
            sub.apply(
                &mut undone,
                &edit.inverse().unwrap(),
                Propagation::linear(n),
            )
            .unwrap();
            assert!(bit_identical(undone.positions(), mesh.positions()));
        }
    }
}

#[test]
fn bunny_ear_scaled_with_and_without_propagation() {
    bunny_ear_scaled_with_and_without_propagation_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn bunny_ear_scaled_with_and_without_propagation_on_real_meshes() {
    bunny_ear_scaled_with_and_without_propagation_with(&testkit::load_shared);
}

fn bunny_ear_scaled_with_and_without_propagation_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh0 = load("stanford-bunny.obj");
    let ear = bunny_ear(&mesh0);
    let sub = SubMesh::from_mask(
        &mesh0,
        &halfedge::VertexData::new(&mesh0, (ear).to_vec()).unwrap(),
    )
    .unwrap();
    let plane = sub.frontier_plane(&mesh0).unwrap();
    assert!(
        plane.normal.y > 0.9,
        "the ear rises above its frontier: {}",
        plane.normal
    );
    let centre = sub
        .vertex_indices()
        .iter()
        .map(|&i| mesh0.positions()[i as usize])
        .sum::<DVec3>()
        / sub.len() as f64;
    let factor = 1.5;

    // without propagation (Fig. 9 b): the ear is scaled and re-seated on its frontier plane
    let mut mesh = mesh0.clone();
    sub.apply(
        &mut mesh,
        &SubmeshEdit::Scale { centre, factor },
        Propagation::NONE,
    )
    .unwrap();
    let after = sub.frontier_plane(&mesh).unwrap();
    assert!(plane.signed_distance(after.point).abs() < 1e-12);
    assert!(after.normal.dot(plane.normal) > 1.0 - 1e-9);
    let idx = sub.vertex_indices();
    for w in idx.windows(2).step_by(37) {
        let (a, b) = (w[0] as usize, w[1] as usize);
        let d0 = mesh0.positions()[a].distance(mesh0.positions()[b]);
        let d1 = mesh.positions()[a].distance(mesh.positions()[b]);
        assert!((d1 - factor * d0).abs() < 1e-12);
    }
    for (i, (a, b)) in mesh0.positions().iter().zip(mesh.positions()).enumerate() {
        if !ear[i] {
            assert_eq!(a, b);
        }
    }

    // with propagation (Fig. 9 a): no re-seat, the collars follow partly
    let mut mesh = mesh0.clone();
    sub.apply(
        &mut mesh,
        &SubmeshEdit::Scale { centre, factor },
        Propagation::linear(4),
    )
    .unwrap();
    for &i in idx {
        let i = i as usize;
        let expected = centre + factor * (mesh0.positions()[i] - centre);
        assert!(mesh.positions()[i].distance(expected) < 1e-12);
    }
    let collars = sub.collars(&mesh0, 5).unwrap();
    for &i in &collars[4] {
        assert_eq!(mesh.positions()[i as usize], mesh0.positions()[i as usize]);
    }
    mesh.check().unwrap();
}

#[test]
fn bunny_ear_rotated_about_a_vertex_normal_and_bounded_by_the_frontier_plane() {
    bunny_ear_rotated_about_a_vertex_normal_and_bounded_by_the_frontier_plane_with(
        &testkit::stand_in::by_shape,
    );
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn bunny_ear_rotated_about_a_vertex_normal_and_bounded_by_the_frontier_plane_on_real_meshes() {
    bunny_ear_rotated_about_a_vertex_normal_and_bounded_by_the_frontier_plane_with(
        &testkit::load_shared,
    );
}

fn bunny_ear_rotated_about_a_vertex_normal_and_bounded_by_the_frontier_plane_with(
    load: &dyn Fn(&str) -> Mesh,
) {
    let mesh0 = load("stanford-bunny.obj");
    let ear = bunny_ear(&mesh0);
    let sub = SubMesh::from_mask(
        &mesh0,
        &halfedge::VertexData::new(&mesh0, (ear).to_vec()).unwrap(),
    )
    .unwrap();
    let plane = sub.frontier_plane(&mesh0).unwrap();

    // the paper's default axis: the normal at a picked vertex; the ear turns rigidly
    let pick = mesh0.vertex_at(sub.frontier_indices()[0] as usize).unwrap();
    let axis = Axis::vertex_normal(&mesh0, pick).unwrap();
    let mut mesh = mesh0.clone();
    sub.apply(
        &mut mesh,
        &SubmeshEdit::Rotate {
            axis,
            angle: 0.5,
            bounded: false,
        },
        Propagation::NONE,
    )
    .unwrap();
    let idx = sub.vertex_indices();
    for w in idx.windows(2).step_by(23) {
        let (a, b) = (w[0] as usize, w[1] as usize);
        let d0 = mesh0.positions()[a].distance(mesh0.positions()[b]);
        let d1 = mesh.positions()[a].distance(mesh.positions()[b]);
        assert!((d1 - d0).abs() < 1e-12);
    }

    // Fig. 11: a sideways rotation about an axis in the frontier plane pushes part of
    // the ear through that plane; bounded, no vertex crosses it.
    let sideways = Axis::new(plane.point, plane.normal.cross(DVec3::Z)).unwrap();
    let rotate = |bounded| SubmeshEdit::Rotate {
        axis: sideways,
        angle: 1.2,
        bounded,
    };
    let crossings = |m: &Mesh| {
        idx.iter()
            .filter(|&&i| {
                let a = plane.signed_distance(mesh0.positions()[i as usize]);
                let b = plane.signed_distance(m.positions()[i as usize]);
                (a >= 0.0 && b < 0.0) || (a < 0.0 && b > 0.0)
            })
            .count()
    };
    let mut free = mesh0.clone();
    sub.apply(&mut free, &rotate(false), Propagation::linear(3))
        .unwrap();
    assert!(
        crossings(&free) > 50,
        "the unbounded rotation crosses the plane"
    );
    let mut bounded = mesh0.clone();
    let snapshot = sub
        .apply(&mut bounded, &rotate(true), Propagation::linear(3))
        .unwrap();
    assert_eq!(crossings(&bounded), 0);
    assert!(rotate(true).inverse().is_none());
    snapshot.restore(&mut bounded).unwrap();
    assert!(bit_identical(mesh0.positions(), bounded.positions()));
}

/// Angle of rotation about `axis` taking `a` to `b` (both relative to the axis point).
fn angle_about(axis: &Axis, a: DVec3, b: DVec3) -> f64 {
    let d = axis.direction();
    let pa = (a - axis.point()) - (a - axis.point()).dot(d) * d;
    let pb = (b - axis.point()) - (b - axis.point()).dot(d) * d;
    pa.cross(pb).dot(d).atan2(pa.dot(pb))
}

fn perpendicular_distance(axis: &Axis, p: DVec3) -> f64 {
    let q = p - axis.point();
    (q - q.dot(axis.direction()) * axis.direction()).length()
}

#[test]
fn bunny_head_tapered_over_20_levels() {
    // Three subdivisions: the sub-mesh is as many rings deep as the bunny's.
    bunny_head_tapered_over_20_levels_with(&|_: &str| testkit::stand_in::bunny_in_box(3));
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn bunny_head_tapered_over_20_levels_on_real_meshes() {
    bunny_head_tapered_over_20_levels_with(&testkit::load_shared);
}

fn bunny_head_tapered_over_20_levels_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh0 = load("stanford-bunny.obj");
    let head = bunny_head(&mesh0);
    let sub = SubMesh::from_mask(
        &mesh0,
        &halfedge::VertexData::new(&mesh0, (head).to_vec()).unwrap(),
    )
    .unwrap();
    assert!(sub.max_level() > 40, "max level {}", sub.max_level());
    let axis = sub.axis(&mesh0).unwrap();
    let factor = 0.6;
    let levels = 20;
    let mut mesh = mesh0.clone();
    sub.apply(
        &mut mesh,
        &SubmeshEdit::Taper {
            axis: None,
            factor,
            variation: Variation::Levels(Some(levels)),
        },
        Propagation::linear(5),
    )
    .unwrap();
    let mut counts = [0usize; 2];
    for (i, &in_head) in head.iter().enumerate() {
        let (p, q) = (mesh0.positions()[i], mesh.positions()[i]);
        match sub.level(i) {
            None if !in_head => assert_eq!(p, q, "outside vertex {i} moved"),
            Some(0) => assert_eq!(p, q, "frontier vertex {i} moved"),
            Some(l) => {
                let expected = factor.powf((l as f64 / levels as f64).min(1.0));
                let (r0, r1) = (
                    perpendicular_distance(&axis, p),
                    perpendicular_distance(&axis, q),
                );
                assert!((r1 - expected * r0).abs() < 1e-12);
                assert!((axis.coordinate(p) - axis.coordinate(q)).abs() < 1e-12);
                counts[(l as usize >= levels) as usize] += 1;
            }
            None => {}
        }
    }
    assert!(counts[0] > 100 && counts[1] > 100, "{counts:?}");
    // tapering back with 1/factor restores
    sub.apply(
        &mut mesh,
        &SubmeshEdit::Taper {
            axis: None,
            factor: 1.0 / factor,
            variation: Variation::Levels(Some(levels)),
        },
        Propagation::linear(5),
    )
    .unwrap();
    assert!(max_distance(mesh0.positions(), mesh.positions()) < 1e-12);
}

#[test]
fn bunny_ear_twisted_over_10_levels_and_back() {
    // Three subdivisions: the sub-mesh is as many rings deep as the bunny's.
    bunny_ear_twisted_over_10_levels_and_back_with(&|_: &str| testkit::stand_in::bunny_in_box(3));
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn bunny_ear_twisted_over_10_levels_and_back_on_real_meshes() {
    bunny_ear_twisted_over_10_levels_and_back_with(&testkit::load_shared);
}

fn bunny_ear_twisted_over_10_levels_and_back_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh0 = load("stanford-bunny.obj");
    let ear = bunny_ear(&mesh0);
    let sub = SubMesh::from_mask(
        &mesh0,
        &halfedge::VertexData::new(&mesh0, (ear).to_vec()).unwrap(),
    )
    .unwrap();
    assert!(sub.max_level() > 10);
    let axis = sub.axis(&mesh0).unwrap();
    let angle = 1.0;
    let twist = SubmeshEdit::Twist {
        axis: None,
        angle,
        variation: Variation::Levels(Some(10)),
    };
    let mut mesh = mesh0.clone();
    sub.apply(&mut mesh, &twist, Propagation::NONE).unwrap();
    for i in 0..mesh0.vertex_slots() {
        let (p, q) = (mesh0.positions()[i], mesh.positions()[i]);
        match sub.level(i) {
            Some(l) if perpendicular_distance(&axis, p) > 1e-4 => {
                let expected = angle * (l as f64 / 10.0).min(1.0);
                assert!((angle_about(&axis, p, q) - expected).abs() < 1e-9);
            }
            Some(_) => {}
            None => assert_eq!(p, q),
        }
    }
    // the top of the ear (levels ≥ 10) turned rigidly
    let top: Vec<usize> = (0..mesh0.vertex_slots())
        .filter(|&i| sub.level(i).is_some_and(|l| l >= 10))
        .collect();
    for w in top.windows(2).step_by(11) {
        let d0 = mesh0.positions()[w[0]].distance(mesh0.positions()[w[1]]);
        let d1 = mesh.positions()[w[0]].distance(mesh.positions()[w[1]]);
        assert!((d0 - d1).abs() < 1e-12);
    }
    // the usual twist (all levels) differs, and θ then −θ restores to 1e-12
    let mut usual = mesh0.clone();
    let full = SubmeshEdit::Twist {
        axis: None,
        angle,
        variation: Variation::Levels(None),
    };
    sub.apply(&mut usual, &full, Propagation::NONE).unwrap();
    assert!(max_distance(usual.positions(), mesh.positions()) > 1e-3);
    sub.apply(&mut mesh, &twist.inverse().unwrap(), Propagation::NONE)
        .unwrap();
    assert!(max_distance(mesh0.positions(), mesh.positions()) < 1e-12);
    mesh.check().unwrap();
}
