//! A long refinement after an edit places the split vertices on one thread and splits on
//! another (`Hierarchy::refine_to`, `go_to_level`); one split at a time
//! (`Hierarchy::split_next`) must give the same mesh, positions, labels and position in
//! the hierarchy, bit for bit, with every kind of mark, with baselines from edits at two
//! levels, and when a field overflows part way.

use glam::{DAffine3, DQuat, DVec3};
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{Mesh, VertexId};

/// An icosphere with bumps: 40,962 vertices, enough records for the threaded walk.
fn bumpy_sphere() -> Mesh {
    testkit::meshes::bumpy_sphere(6, 0.05)
}

/// What a walk leaves (see [`state`]).
type State = (
    Vec<[u64; 3]>,
    Vec<[usize; 3]>,
    Vec<halfedge::labels::Label>,
    usize,
);

/// Everything a walk leaves: positions and faces by slot, the label of every vertex
/// slot, the number of collapsed records.
fn state(
    h: &Hierarchy,
    labels: Option<halfedge::Attribute<VertexId, halfedge::labels::Label>>,
) -> State {
    let mesh = h.mesh();
    mesh.check().unwrap();
    let positions = mesh
        .vertices()
        .map(|v| mesh.position(v).to_array().map(f64::to_bits))
        .collect();
    let faces = mesh
        .faces()
        .map(|f| mesh.triangle(f).map(|v| mesh.vertex_index(v)))
        .collect();
    let labels = labels
        .map(|a| mesh.attribute_values(a).unwrap().to_vec())
        .unwrap_or_default();
    (positions, faces, labels, h.applied())
}

/// Splits one record at a time down to `applied`, stopping at the first error, then
/// unfolds what the refinement turned over, as a walk does at its end.
fn one_by_one(h: &mut Hierarchy, applied: usize) -> halfedge::Result<()> {
    let finer = h.applied() > applied;
    while h.applied() > applied {
        h.split_next()?;
    }
    if finer {
        h.unfold_refinement();
    }
    Ok(())
}

/// An edit at level 3 (a non-rigid wave, a rotated cap marked affine, a twisted band
/// marked as a field, a region) and, after walking to level 5, a second wave: the walk
/// back to the input has marks of every kind and two baselines to serve.
fn edited() -> (
    Hierarchy,
    halfedge::Attribute<VertexId, halfedge::labels::Label>,
) {
    let options = HierarchyOptions::rounds().with_target_faces(500);
    let mut h = Hierarchy::build(bumpy_sphere(), &options).unwrap();
    assert!(h.n_levels() > 6);
    h.go_to_level(3).unwrap();
    let m = h.mesh_mut();
    let frontier = m
        .frontier_from_plane(DVec3::new(0.0, 0.0, 0.2), DVec3::Z)
        .unwrap();
    let (labels, _) = m.label_sides(&frontier, 1, 2).unwrap();
    h.attach_labels(labels).unwrap();
    let coarse = h.mesh();
    let pick = |f: &dyn Fn(DVec3) -> bool| -> Vec<VertexId> {
        coarse
            .vertices()
            .filter(|&v| f(coarse.position(v)))
            .collect()
    };
    let cap = pick(&|p| p.z > 0.6);
    let band = pick(&|p| p.x > 0.5 && p.z <= 0.6);
    let region = pick(&|p| p.y > 0.3 && p.x <= 0.5 && p.z <= 0.6);
    let turn = DAffine3::from_translation(DVec3::new(0.0, 0.0, 0.6))
        * DAffine3::from_quat(DQuat::from_rotation_x(0.4))
        * DAffine3::from_translation(DVec3::new(0.0, 0.0, -0.6));
    let twist = |p: DVec3| DQuat::from_rotation_x(0.5 * (p.x - 0.5)) * p;
    let slots: Vec<(usize, DVec3)> = coarse
        .vertices()
        .map(|v| (coarse.vertex_index(v), coarse.position(v)))
        .collect();
    let positions = h.mesh_mut().positions_mut();
    for &(i, p) in &slots {
        positions[i] = p + DVec3::new(0.0, 0.03 * (7.0 * p.z).sin(), 0.0);
    }
    for &v in &cap {
        let i = h.mesh().vertex_index(v);
        let p = slots.iter().find(|s| s.0 == i).unwrap().1;
        h.mesh_mut().positions_mut()[i] = turn.transform_point3(p);
    }
    for &v in &band {
        let i = h.mesh().vertex_index(v);
        let p = slots.iter().find(|s| s.0 == i).unwrap().1;
        h.mesh_mut().positions_mut()[i] = twist(p);
    }
    h.mark_affine(&cap, turn).unwrap();
    h.mark_field(&band, twist).unwrap();
    h.mark_region(&region).unwrap();
    h.go_to_level(5).unwrap();
    for p in h.mesh_mut().positions_mut() {
        p.x += 0.02 * (5.0 * p.y).cos();
    }
    (h, labels)
}

/// Marks the coarse vertices above z = 0.5 with `field(p, own)`, where `own` says that
/// `p` is one of their own positions (where a field must give their current positions).
fn mark_cap_field(h: &mut Hierarchy, field: impl Fn(DVec3, bool) -> DVec3 + Send + Sync + 'static) {
    let coarse = h.mesh();
    let cap: Vec<VertexId> = coarse
        .vertices()
        .filter(|&v| coarse.position(v).z > 0.5)
        .collect();
    let at: Vec<DVec3> = cap.iter().map(|&v| coarse.position(v)).collect();
    h.mark_field(&cap, move |p| field(p, at.contains(&p)))
        .unwrap();
}

#[test]
fn a_threaded_refinement_is_the_split_by_split_one_bit_for_bit() {
    let (h, labels) = edited();
    let mut threaded = h.clone();
    let mut single = h;
    threaded.refine_to(0).unwrap();
    one_by_one(&mut single, 0).unwrap();
    assert_eq!(threaded.current_level(), Some(0));
    assert!(
        state(&threaded, Some(labels)) == state(&single, Some(labels)),
        "the threaded refinement differs from one split at a time"
    );
    // Part way: to level 2, then on to the input.
    let (h, labels) = edited();
    let (mut threaded, mut single) = (h.clone(), h);
    threaded.go_to_level(2).unwrap();
    let applied = threaded.applied();
    one_by_one(&mut single, applied).unwrap();
    assert!(state(&threaded, Some(labels)) == state(&single, Some(labels)));
}

#[test]
fn a_field_that_overflows_stops_both_walks_at_the_same_record() {
    let (mut h, labels) = edited();
    // A field that overflows far from its coarse vertices' own positions: the first
    // finer vertex of the cap placed beyond x = 0.05 makes its split fail.
    mark_cap_field(&mut h, |p, own| {
        if own || p.x < 0.05 {
            p
        } else {
            DVec3::splat(f64::INFINITY)
        }
    });
    let (mut threaded, mut single) = (h.clone(), h);
    let a = threaded.refine_to(0);
    let b = one_by_one(&mut single, 0);
    assert!(
        matches!(a, Err(halfedge::Error::Overflow(_))),
        "the threaded walk did not fail: {a:?}"
    );
    assert!(matches!(b, Err(halfedge::Error::Overflow(_))));
    assert!(threaded.applied() > 0);
    assert!(state(&threaded, Some(labels)) == state(&single, Some(labels)));
    // Both can walk back coarser from there, alike.
    threaded.go_to_level(6).unwrap();
    single.go_to_level(6).unwrap();
    assert!(state(&threaded, Some(labels)) == state(&single, Some(labels)));
}

#[test]
fn the_paper_translations_refine_alike_on_both_walks() {
    let options = HierarchyOptions::rounds()
        .with_target_faces(500)
        .with_detail_mode(halfedge::hierarchy::DetailMode::Translation);
    let mut h = Hierarchy::build(bumpy_sphere(), &options).unwrap();
    h.go_to_level(4).unwrap();
    for p in h.mesh_mut().positions_mut() {
        p.y += 0.03 * (6.0 * p.z).sin();
    }
    let (mut threaded, mut single) = (h.clone(), h);
    threaded.refine_to(0).unwrap();
    one_by_one(&mut single, 0).unwrap();
    assert!(state(&threaded, None) == state(&single, None));
}

#[test]
fn without_an_edit_both_walks_give_the_input_back_bit_for_bit() {
    let input = bumpy_sphere();
    let options = HierarchyOptions::rounds().with_target_faces(500);
    let h = Hierarchy::build(input.clone(), &options).unwrap();
    let (mut threaded, mut single) = (h.clone(), h);
    threaded.refine_to(0).unwrap();
    one_by_one(&mut single, 0).unwrap();
    assert!(state(&threaded, None) == state(&single, None));
    let same = input.vertices().all(|v| {
        threaded.mesh().position(v).to_array().map(f64::to_bits)
            == input.position(v).to_array().map(f64::to_bits)
    });
    assert!(
        same,
        "the threaded walk did not give the input back bit for bit"
    );
    // Down and up again: still the hierarchy's own positions, so still exact.
    threaded.go_to_level(threaded.coarsest_level()).unwrap();
    threaded.go_to_level(0).unwrap();
    assert!(state(&threaded, None) == state(&single, None));
}

#[test]
fn a_field_that_panics_leaves_both_walks_at_the_same_consistent_record() {
    let (mut h, labels) = edited();
    // A user's field that panics on the first finer vertex beyond x = 0.05.
    mark_cap_field(&mut h, |p, own| {
        assert!(own || p.x < 0.05, "the user's field gave up");
        p
    });
    let (mut threaded, mut single) = (h.clone(), h);
    let quiet = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let a = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| threaded.refine_to(0)));
    let b = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| one_by_one(&mut single, 0)));
    std::panic::set_hook(quiet);
    assert!(a.is_err() && b.is_err(), "the field did not panic");
    assert!(threaded.applied() > 0);
    assert_eq!(
        threaded.mesh().positions().len(),
        single.mesh().positions().len()
    );
    assert!(state(&threaded, Some(labels)) == state(&single, Some(labels)));
    // Both walk on alike once the field is gone (a walk coarser drops the marks).
    threaded.go_to_level(6).unwrap();
    single.go_to_level(6).unwrap();
    threaded.refine_to(0).unwrap();
    one_by_one(&mut single, 0).unwrap();
    assert!(state(&threaded, Some(labels)) == state(&single, Some(labels)));
}

mod random_sessions {
    //! Random editing sessions, played on two copies of one hierarchy: one walks as the
    //! library does (threaded refinements), the other refines one split at a time. Their
    //! meshes must stay the same bit for bit after every step.

    use super::*;
    use proptest::prelude::*;
    use std::sync::OnceLock;

    fn built() -> &'static Hierarchy {
        static BUILT: OnceLock<Hierarchy> = OnceLock::new();
        BUILT.get_or_init(|| {
            let options = HierarchyOptions::rounds().with_target_faces(500);
            Hierarchy::build(bumpy_sphere(), &options).unwrap()
        })
    }

    #[derive(Clone, Debug)]
    enum Step {
        /// Walk to a level (index into the levels).
        Level(usize),
        /// Walk to a position between levels (per mille of the records).
        Seek(u32),
        /// Move every vertex by a wave.
        Wave(f64),
        /// Rotate a part and mark it affine.
        Affine(u8, f64),
        /// Twist a part and mark it with the twist field.
        Field(u8, f64),
        /// Mark a part as a region.
        Region(u8),
    }

    fn step() -> impl Strategy<Value = Step> {
        prop_oneof![
            (0usize..8).prop_map(Step::Level),
            (0u32..1000).prop_map(Step::Seek),
            (-0.05f64..0.05).prop_map(Step::Wave),
            (0u8..4, -0.6f64..0.6).prop_map(|(p, a)| Step::Affine(p, a)),
            (0u8..4, -0.6f64..0.6).prop_map(|(p, a)| Step::Field(p, a)),
            (0u8..4).prop_map(Step::Region),
        ]
    }

    fn part(h: &Hierarchy, k: u8) -> Vec<VertexId> {
        let mesh = h.mesh();
        mesh.vertices()
            .filter(|&v| {
                let p = mesh.position(v);
                match k {
                    0 => p.z > 0.5,
                    1 => p.x > 0.3,
                    2 => p.y < -0.2,
                    _ => true,
                }
            })
            .collect()
    }

    /// Walks to `applied`: as the library does, or one split at a time when refining.
    fn walk(h: &mut Hierarchy, applied: usize, threaded: bool) {
        if threaded || applied >= h.applied() {
            h.seek(applied).unwrap();
        } else {
            one_by_one(h, applied).unwrap();
        }
    }

    fn play(h: &mut Hierarchy, step: &Step, threaded: bool) {
        match *step {
            Step::Level(l) => {
                let ends = h.level_ends().to_vec();
                walk(h, ends[l.min(ends.len() - 1)], threaded);
            }
            Step::Seek(m) => {
                let applied = h.n_records() * m as usize / 1000;
                walk(h, applied, threaded);
            }
            Step::Wave(a) => {
                for p in h.mesh_mut().positions_mut() {
                    p.y += a * (6.0 * p.z).sin();
                }
            }
            Step::Affine(k, angle) => {
                let vertices = part(h, k);
                let map = DAffine3::from_quat(DQuat::from_rotation_x(angle));
                for &v in &vertices {
                    let p = h.mesh().position(v);
                    h.mesh_mut().set_position(v, map.transform_point3(p));
                }
                h.mark_affine(&vertices, map).unwrap();
            }
            Step::Field(k, angle) => {
                let vertices = part(h, k);
                let twist = move |p: DVec3| DQuat::from_rotation_z(angle * p.z) * p;
                for &v in &vertices {
                    let p = h.mesh().position(v);
                    h.mesh_mut().set_position(v, twist(p));
                }
                h.mark_field(&vertices, twist).unwrap();
            }
            Step::Region(k) => {
                let vertices = part(h, k);
                h.mark_region(&vertices).unwrap();
            }
        }
    }

    /// Plays `steps` on two copies of the built hierarchy, one walking as the library
    /// does, the other refining one split at a time; asserts their meshes stay the same
    /// after every step.
    fn play_both(steps: &[Step]) -> std::result::Result<(), TestCaseError> {
        let mut threaded = built().clone();
        let mut single = built().clone();
        for step in steps {
            play(&mut threaded, step, true);
            play(&mut single, step, false);
            prop_assert!(
                state(&threaded, None) == state(&single, None),
                "the walks differ after {step:?}"
            );
        }
        Ok(())
    }

    /// Found by the property below: an edit at level 2, another at level 3, then one walk
    /// to the input. One split at a time notes the faces the level-2 edit turned over
    /// when it reaches level 2 (so the unfolding leaves them be); the walk noted only
    /// those of level 3's edit, where it started, and unfolded the others. A walk now
    /// stops at every edited level it passes to note them.
    #[test]
    fn a_walk_across_two_edited_levels_notes_each_levels_turned_faces() {
        play_both(&[
            Step::Level(2),
            Step::Wave(-0.0010676556601194893),
            Step::Level(3),
            Step::Affine(0, 0.4328255321158302),
            Step::Level(0),
        ])
        .unwrap();
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(16))]
        #[test]
        fn threaded_and_one_split_at_a_time_sessions_stay_the_same(
            steps in prop::collection::vec(step(), 1..10)
        ) {
            play_both(&steps)?;
        }
    }
}
