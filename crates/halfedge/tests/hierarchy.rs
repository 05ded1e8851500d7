//! The progressive hierarchy (seed paper, section 3): exact round trips, level sizes,
//! stop criteria, walking the levels, and the centroid detail coefficients carrying
//! coarse edits to the fine mesh.

use glam::DVec3;
use halfedge::hierarchy::{DetailMode, Hierarchy, HierarchyOptions, Method, SurvivorPlacement};
use halfedge::surface_distance::{surface_distance, Sampling};
use halfedge::{generators, Error, Mesh};
use testkit::check::{snapshot, Snapshot};

const REAL: [&str; 4] = ["spot.obj", "stanford-bunny.obj", "cow.obj", "teapot.obj"];

fn options(method: Method) -> HierarchyOptions {
    match method {
        Method::Rounds => HierarchyOptions::rounds(),
        Method::Qem => HierarchyOptions::qem(),
    }
}

/// Coarsest-level diagonal of the bounding box, for relative tolerances.
fn diagonal(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounding_box().unwrap();
    (hi - lo).length()
}

#[test]
fn coarsen_all_refine_all_is_bit_identical() {
    coarsen_all_refine_all_is_bit_identical_on_real_meshes_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn coarsen_all_refine_all_is_bit_identical_on_the_real_meshes() {
    coarsen_all_refine_all_is_bit_identical_on_real_meshes_with(&testkit::load_shared);
}

fn coarsen_all_refine_all_is_bit_identical_on_real_meshes_with(load: &dyn Fn(&str) -> Mesh) {
    for name in REAL {
        for method in [Method::Rounds, Method::Qem] {
            let mesh = load(name);
            let before = snapshot(&mesh);
            let mut h = Hierarchy::build(mesh, &options(method).with_target_faces(300)).unwrap();
            h.mesh().check().unwrap();
            assert!(
                h.n_levels() > 2,
                "{name} {method:?}: {:?}",
                h.level_face_counts()
            );
            assert_eq!(h.current_level(), Some(h.coarsest_level()));
            h.refine_to(0).unwrap();
            h.mesh().check().unwrap();
            assert!(
                snapshot(h.mesh()) == before,
                "{name} {method:?}: refining back did not restore the input exactly"
            );
        }
    }
}

/// Rounds placed by the quadric (issue 32): the same exact round trip, the same bytes on
/// any number of threads, and coarse levels nearer the input than the paper's midpoints
/// (two-sided mean distance over the sampled surfaces).
#[test]
fn rounds_placed_by_the_quadric_stay_nearer_the_input() {
    rounds_placed_by_the_quadric_stay_nearer_the_input_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn rounds_placed_by_the_quadric_stay_nearer_the_input_on_real_meshes() {
    rounds_placed_by_the_quadric_stay_nearer_the_input_with(&testkit::load_shared);
}

fn rounds_placed_by_the_quadric_stay_nearer_the_input_with(load: &dyn Fn(&str) -> Mesh) {
    let midpoint = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(300);
    let quadric = midpoint.clone().with_placement(SurvivorPlacement::Quadric);
    for name in REAL {
        let mesh = load(name);
        let before = snapshot(&mesh);
        let by_midpoint = Hierarchy::build(mesh.clone(), &midpoint).unwrap();
        let build = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| Hierarchy::build(mesh.clone(), &quadric).unwrap())
        };
        let mut by_quadric = build(1);
        let bytes = |h: &Hierarchy| {
            let mut out = Vec::new();
            h.write_to(&mut out).unwrap();
            out
        };
        assert!(
            bytes(&by_quadric) == bytes(&build(3)),
            "{name}: the hierarchy depends on the thread count"
        );
        by_quadric.mesh().check().unwrap();
        let sampling = Sampling::default();
        let far = |h: &Hierarchy| surface_distance(&mesh, h.mesh(), &sampling).unwrap().mean();
        let (d_mid, d_quad) = (far(&by_midpoint), far(&by_quadric));
        assert!(
            d_quad < d_mid,
            "{name}: mean distance {d_quad} by the quadric against {d_mid} by midpoints \
             (faces {} and {})",
            by_quadric.mesh().n_faces(),
            by_midpoint.mesh().n_faces()
        );
        by_quadric.refine_to(0).unwrap();
        by_quadric.mesh().check().unwrap();
        assert!(
            snapshot(by_quadric.mesh()) == before,
            "{name}: refining back did not restore the input exactly"
        );
    }
}

/// Splits skip their checks (and the centroids) while the hierarchy's mesh has only been
/// changed by the hierarchy; a mesh swapped in (or changed) behind its back makes every
/// later split checked. Every way, and in clones, refinement restores the input exactly.
#[test]
fn trusted_and_checked_refinement_agree() {
    trusted_and_checked_refinement_agree_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn trusted_and_checked_refinement_agree_on_real_meshes() {
    trusted_and_checked_refinement_agree_with(&testkit::load_shared);
}

fn trusted_and_checked_refinement_agree_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh = load("spot.obj");
    let before = snapshot(&mesh);
    let built = Hierarchy::build(mesh, &HierarchyOptions::rounds().with_target_faces(300)).unwrap();
    let mut trusted = built.clone();
    let mut checked = built.clone();
    let copy = checked.mesh().clone();
    *checked.mesh_mut() = copy;
    // Write access to positions (without a change) makes the hierarchy compute every
    // translation instead of knowing it is zero.
    let mut touched = built.clone();
    touched.mesh_mut().positions_mut();
    for h in [&mut trusted, &mut checked, &mut touched] {
        h.refine_to(0).unwrap();
        h.mesh().check().unwrap();
        assert!(snapshot(h.mesh()) == before);
    }
    // A mesh swapped in with different connectivity is caught by the checks.
    let mut swapped = built.clone();
    *swapped.mesh_mut() = load("spot.obj");
    assert!(matches!(swapped.split_next(), Err(Error::SplitRefused(_))));
    // So is a mesh too small for the records' indices (the splits prefetch and read
    // centroids ahead of their checks; none of that may index out of bounds).
    let mut tiny = built.clone();
    *tiny.mesh_mut() = halfedge::generators::icosphere(0);
    assert!(matches!(tiny.split_next(), Err(Error::SplitRefused(_))));
    assert!(matches!(tiny.refine_to(0), Err(Error::SplitRefused(_))));
    tiny.mesh().check().unwrap();
    let mut tiny = built.clone();
    tiny.refine_to(tiny.coarsest_level() - 1).unwrap();
    *tiny.mesh_mut() = halfedge::generators::icosphere(0);
    assert!(matches!(
        tiny.collapse_next(),
        Err(Error::CollapseRefused { .. })
    ));
    tiny.mesh().check().unwrap();
}

#[test]
fn a_round_removes_about_45_percent_of_the_faces() {
    a_round_removes_about_45_percent_of_the_faces_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn a_round_removes_about_45_percent_of_the_faces_on_real_meshes() {
    a_round_removes_about_45_percent_of_the_faces_with(&testkit::load_shared);
}

fn a_round_removes_about_45_percent_of_the_faces_with(load: &dyn Fn(&str) -> Mesh) {
    // The paper: "Each simplification step removes about 45 % of faces". (Meshes with much
    // boundary, like the teapot, have more vertices per face and lose up to 52 %.)
    for name in [
        "spot.obj",
        "stanford-bunny.obj",
        "nefertiti.obj",
        "fandisk.obj",
        "cow.obj",
    ] {
        let h =
            Hierarchy::build(load(name), &HierarchyOptions::rounds().with_max_levels(2)).unwrap();
        let f = h.level_face_counts();
        assert_eq!(f.len(), 3);
        for w in f.windows(2) {
            let removed = 1.0 - w[1] as f64 / w[0] as f64;
            assert!(
                (0.38..=0.5).contains(&removed),
                "{name}: a round removed {:.1} % of the faces ({f:?})",
                100.0 * removed
            );
        }
    }
}

#[test]
fn qem_levels_are_cut_at_the_level_ratio() {
    qem_levels_are_cut_at_the_level_ratio_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn qem_levels_are_cut_at_the_level_ratio_on_real_meshes() {
    qem_levels_are_cut_at_the_level_ratio_with(&testkit::load_shared);
}

fn qem_levels_are_cut_at_the_level_ratio_with(load: &dyn Fn(&str) -> Mesh) {
    let mesh = load("spot.obj");
    let opts = HierarchyOptions::qem().with_target_faces(200);
    let h = Hierarchy::build(mesh, &opts).unwrap();
    let f = h.level_face_counts();
    assert_eq!(*f.last().unwrap(), 200.min(f[f.len() - 2]));
    for w in f[..f.len() - 1].windows(2) {
        let target = (w[0] as f64 * opts.level_ratio).floor() as usize;
        // A collapse removes at most two faces.
        assert!(w[1] <= target && w[1] + 2 > target, "{f:?}");
    }
}

#[test]
fn stop_criteria() {
    stop_criteria_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn stop_criteria_on_real_meshes() {
    stop_criteria_with(&testkit::load_shared);
}

fn stop_criteria_with(load: &dyn Fn(&str) -> Mesh) {
    for method in [Method::Rounds, Method::Qem] {
        // Target face count.
        let h =
            Hierarchy::build(load("spot.obj"), &options(method).with_target_faces(1000)).unwrap();
        let f = h.level_face_counts();
        assert!(
            *f.last().unwrap() <= 1000 && f[f.len() - 2] > 1000,
            "{method:?} {f:?}"
        );
        // Level count.
        let h = Hierarchy::build(load("spot.obj"), &options(method).with_max_levels(3)).unwrap();
        assert_eq!(h.n_levels(), 4, "{method:?}");
        // Error bound: a tighter bound leaves more faces; on a plane nothing is an error.
        let loose = Hierarchy::build(load("spot.obj"), &options(method).with_max_error(1e-2))
            .unwrap()
            .into_mesh()
            .n_faces();
        let tight = Hierarchy::build(load("spot.obj"), &options(method).with_max_error(1e-4))
            .unwrap()
            .into_mesh()
            .n_faces();
        assert!(tight > loose, "{method:?}: tight {tight}, loose {loose}");
        let grid = generators::grid(16, 16, 1.0, 1.0);
        let faces = grid.n_faces();
        let flat = Hierarchy::build(grid, &options(method).with_max_error(1e-12)).unwrap();
        assert!(
            flat.mesh().n_faces() < faces / 4,
            "{method:?}: {:?}",
            flat.level_face_counts()
        );
    }
}

#[test]
fn error_bound_holds_for_every_qem_collapse() {
    error_bound_holds_for_every_qem_collapse_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn error_bound_holds_for_every_qem_collapse_on_real_meshes() {
    error_bound_holds_for_every_qem_collapse_with(&testkit::load_shared);
}

fn error_bound_holds_for_every_qem_collapse_with(load: &dyn Fn(&str) -> Mesh) {
    // Every survivor's error, measured with the quadrics of the input vertices merged
    // into it (replayed from the records), is within the bound at its final position.
    let bound = 2e-3;
    let input = load("spot.obj");
    let h = Hierarchy::build(
        input.clone(),
        &HierarchyOptions::qem().with_max_error(bound),
    )
    .unwrap();
    let planes = halfedge::hierarchy::qem::face_planes(&input);
    let mut q = halfedge::hierarchy::qem::vertex_quadrics(&input, &planes, 10.0);
    for r in h.records() {
        let (i0, i1) = (input.vertex_index(r.v0), input.vertex_index(r.v1));
        q[i1] = q[i0] + q[i1];
    }
    for v in h.mesh().vertices() {
        let e = q[input.vertex_index(v)].error(h.mesh().position(v));
        assert!(e <= bound * (1.0 + 1e-9), "vertex {v}: error {e} > {bound}");
    }
}

#[test]
fn walking_the_levels_in_any_order_gives_the_same_meshes() {
    walking_the_levels_in_any_order_gives_the_same_meshes_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn walking_the_levels_in_any_order_gives_the_same_meshes_on_real_meshes() {
    walking_the_levels_in_any_order_gives_the_same_meshes_with(&testkit::load_shared);
}

fn walking_the_levels_in_any_order_gives_the_same_meshes_with(load: &dyn Fn(&str) -> Mesh) {
    for method in [Method::Rounds, Method::Qem] {
        let mut h =
            Hierarchy::build(load("cow.obj"), &options(method).with_target_faces(200)).unwrap();
        let levels = h.n_levels();
        let mut seen: Vec<Option<Snapshot>> = (0..levels).map(|_| None).collect();
        let order = [0, levels - 1, 2, 1, levels - 1, 3, 0, 2, levels - 2, 1];
        for &level in &order {
            h.go_to_level(level).unwrap();
            h.mesh().check().unwrap();
            assert_eq!(h.current_level(), Some(level));
            assert_eq!(h.mesh().n_faces(), h.level_face_counts()[level]);
            let s = snapshot(h.mesh());
            match &seen[level] {
                Some(first) => assert!(*first == s, "{method:?}: level {level} differs"),
                None => seen[level] = Some(s),
            }
        }
        // Split by split across a level boundary.
        h.go_to_level(2).unwrap();
        let end1 = h.level_ends()[1];
        while h.applied() > end1 {
            assert!(h.split_next().unwrap());
            assert_eq!(h.level_at_or_finer(), 1);
        }
        assert_eq!(h.current_level(), Some(1));
        assert!(h.collapse_next().unwrap());
        assert_eq!(h.current_level(), None);
        h.mesh().check().unwrap();
        h.go_to_level(1).unwrap();
        assert!(snapshot(h.mesh()) == *seen[1].as_ref().unwrap());
        // The ends.
        h.go_to_level(0).unwrap();
        assert!(!h.split_next().unwrap());
        h.go_to_level(levels - 1).unwrap();
        assert!(!h.collapse_next().unwrap());
    }
}

#[test]
fn bad_arguments_are_errors() {
    bad_arguments_are_errors_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn bad_arguments_are_errors_on_real_meshes() {
    bad_arguments_are_errors_with(&testkit::load_shared);
}

fn bad_arguments_are_errors_with(load: &dyn Fn(&str) -> Mesh) {
    let mut bad = HierarchyOptions::rounds();
    bad.max_normal_deviation = 0.0;
    assert!(matches!(
        Hierarchy::build(load("spot.obj"), &bad),
        Err(Error::InvalidArgument(_))
    ));
    let mut bad = HierarchyOptions::qem();
    bad.level_ratio = 1.0;
    assert!(matches!(
        Hierarchy::build(load("spot.obj"), &bad),
        Err(Error::InvalidArgument(_))
    ));
    let mut h = Hierarchy::build(
        load("spot.obj"),
        &HierarchyOptions::rounds().with_max_levels(2),
    )
    .unwrap();
    assert!(matches!(h.go_to_level(7), Err(Error::InvalidArgument(_))));
    h.go_to_level(1).unwrap();
    assert!(matches!(h.refine_to(2), Err(Error::InvalidArgument(_))));
    assert!(matches!(h.coarsen_to(0), Err(Error::InvalidArgument(_))));
    assert!(matches!(h.seek(usize::MAX), Err(Error::InvalidArgument(_))));
    assert_eq!(h.current_level(), Some(1));
}

#[test]
fn topology_changed_behind_the_hierarchy_is_refused() {
    topology_changed_behind_the_hierarchy_is_refused_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn topology_changed_behind_the_hierarchy_is_refused_on_real_meshes() {
    topology_changed_behind_the_hierarchy_is_refused_with(&testkit::load_shared);
}

fn topology_changed_behind_the_hierarchy_is_refused_with(load: &dyn Fn(&str) -> Mesh) {
    let mut h = Hierarchy::build(
        load("spot.obj"),
        &HierarchyOptions::rounds().with_max_levels(2),
    )
    .unwrap();
    // Collapse an edge directly on the mesh: the hierarchy's next split must refuse.
    let mesh = h.mesh_mut();
    let e = mesh
        .halfedges()
        .find(|&e| mesh.is_collapse_ok(e).is_ok())
        .unwrap();
    mesh.collapse(e).unwrap();
    let mut refused = false;
    for _ in 0..h.applied() {
        match h.split_next() {
            Ok(_) => {}
            Err(Error::SplitRefused(_)) => {
                refused = true;
                break;
            }
            Err(e) => panic!("unexpected {e}"),
        }
    }
    assert!(refused, "a split went through a foreign collapse");
    h.mesh().check().unwrap();
}

#[test]
fn progress_is_reported_per_level() {
    progress_is_reported_per_level_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn progress_is_reported_per_level_on_real_meshes() {
    progress_is_reported_per_level_with(&testkit::load_shared);
}

fn progress_is_reported_per_level_with(load: &dyn Fn(&str) -> Mesh) {
    let mut reports = Vec::new();
    let h = Hierarchy::build_with_progress(
        load("spot.obj"),
        &HierarchyOptions::rounds().with_target_faces(1000),
        &mut |p| reports.push(p),
    )
    .unwrap();
    assert!(reports.len() >= h.n_levels() - 1);
    assert_eq!(reports.last().unwrap().faces, h.mesh().n_faces());
    assert!(reports.windows(2).all(|w| w[0].faces >= w[1].faces));
}

#[test]
fn translating_the_coarse_mesh_translates_the_refined_mesh() {
    translating_the_coarse_mesh_translates_the_refined_mesh_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn translating_the_coarse_mesh_translates_the_refined_mesh_on_real_meshes() {
    translating_the_coarse_mesh_translates_the_refined_mesh_with(&testkit::load_shared);
}

fn translating_the_coarse_mesh_translates_the_refined_mesh_with(load: &dyn Fn(&str) -> Mesh) {
    for (name, method) in [
        ("spot.obj", Method::Rounds),
        ("stanford-bunny.obj", Method::Qem),
        ("teapot.obj", Method::Rounds),
    ] {
        let original = load(name);
        let scale = diagonal(&original);
        let t = DVec3::new(0.3, -1.7, 0.55) * scale;
        let mut h =
            Hierarchy::build(original.clone(), &options(method).with_target_faces(500)).unwrap();
        for p in h.mesh_mut().positions_mut() {
            *p += t;
        }
        h.refine_to(0).unwrap();
        let mesh = h.mesh();
        let mut worst = 0.0f64;
        for v in original.vertices() {
            let expected = original.position(v) + t;
            worst = worst.max((mesh.position(v) - expected).length() / scale);
        }
        assert!(worst < 1e-12, "{name} {method:?}: relative error {worst}");
    }
}

#[test]
fn editing_the_fine_mesh_survives_coarsening_and_refining_again() {
    editing_the_fine_mesh_survives_coarsening_and_refining_again_with(
        &testkit::stand_in::by_topology,
    );
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn editing_the_fine_mesh_survives_coarsening_and_refining_again_on_real_meshes() {
    editing_the_fine_mesh_survives_coarsening_and_refining_again_with(&testkit::load_shared);
}

fn editing_the_fine_mesh_survives_coarsening_and_refining_again_with(load: &dyn Fn(&str) -> Mesh) {
    let original = load("spot.obj");
    let scale = diagonal(&original);
    let t = DVec3::new(-0.2, 0.4, 0.1) * scale;
    let mut h = Hierarchy::build(
        original.clone(),
        &HierarchyOptions::qem().with_target_faces(300),
    )
    .unwrap();
    h.refine_to(0).unwrap();
    for p in h.mesh_mut().positions_mut() {
        *p += t;
    }
    h.coarsen_to(h.coarsest_level()).unwrap();
    h.refine_to(0).unwrap();
    for v in original.vertices() {
        let d = (h.mesh().position(v) - (original.position(v) + t)).length() / scale;
        assert!(d < 1e-12, "vertex {v}: relative error {d}");
    }
}

/// The part of the bunny above the plane `y = cut`, at half its height (or of the stand-in
/// `load` gives).
fn bunny_and_cut(load: &dyn Fn(&str) -> Mesh) -> (Mesh, f64) {
    let mesh = load("stanford-bunny.obj");
    let (lo, hi) = mesh.bounding_box().unwrap();
    (mesh, lo.y + 0.5 * (hi.y - lo.y))
}

// The paper's scheme (DetailMode::Translation).
// An edit at a coarse level reaches the fine mesh through the centroid translations of
// the splits that follow. Near the edited part's border a re-inserted vertex has moved and
// unmoved neighbours and takes a blend of their motion; since a split's neighbours can be
// vertices re-inserted just before in the same round, the blend spreads over a few coarse
// edge lengths, decaying by about a factor 10 per coarse edge (measured on the bunny:
// 1e-3 of the motion 4 edges into the part, 1e-13 at 9; 2e-6 9 edges out of it, 1e-12
// at 17). Well inside, the part moves rigidly; well outside, nothing moves.
const INSIDE_EDGES: f64 = 10.0;
const OUTSIDE_EDGES: f64 = 12.0;

#[test]
fn translating_a_coarse_submesh_carries_its_fine_detail_exactly() {
    translating_a_coarse_submesh_carries_its_fine_detail_exactly_with(&|_: &str| detailed_sphere());
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn translating_a_coarse_submesh_carries_its_fine_detail_exactly_on_real_meshes() {
    translating_a_coarse_submesh_carries_its_fine_detail_exactly_with(&testkit::load_shared);
}

fn translating_a_coarse_submesh_carries_its_fine_detail_exactly_with(load: &dyn Fn(&str) -> Mesh) {
    // Translate the upper half of the bunny at a coarse level: after refinement the fine
    // vertices well inside it are the original ones translated (their detail rode along
    // unchanged), and vertices well outside did not move at all.
    let (original, cut) = bunny_and_cut(load);
    let scale = diagonal(&original);
    let mut h = Hierarchy::build(
        original.clone(),
        &HierarchyOptions::rounds()
            .with_max_levels(3)
            .with_detail_mode(DetailMode::Translation),
    )
    .unwrap();
    let edge = h.mesh().mean_edge_length();
    let t = DVec3::new(0.05, 0.1, 0.2) * scale;
    for p in h.mesh_mut().positions_mut() {
        if p.y > cut {
            *p += t;
        }
    }
    h.refine_to(0).unwrap();
    let fine = h.mesh();
    let (mut inside, mut outside) = (0, 0);
    for v in original.vertices() {
        let p = original.position(v);
        if p.y > cut + INSIDE_EDGES * edge {
            inside += 1;
            let d = (fine.position(v) - (p + t)).length() / scale;
            assert!(d < 1e-12, "vertex {v} inside: relative error {d}");
        } else if p.y < cut - OUTSIDE_EDGES * edge {
            outside += 1;
            let d = (fine.position(v) - p).length() / t.length();
            assert!(
                d < 1e-6,
                "vertex {v} outside moved by {d} of the translation"
            );
        }
    }
    assert!(inside > 1000 && outside > 1000, "{inside} {outside}");
}

#[test]
fn scaling_a_coarse_submesh_carries_the_fine_detail_along() {
    scaling_a_coarse_submesh_carries_the_fine_detail_along_with(&|_: &str| detailed_sphere());
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn scaling_a_coarse_submesh_carries_the_fine_detail_along_on_real_meshes() {
    scaling_a_coarse_submesh_carries_the_fine_detail_along_with(&testkit::load_shared);
}

fn scaling_a_coarse_submesh_carries_the_fine_detail_along_with(load: &dyn Fn(&str) -> Mesh) {
    // Scale the upper half of the bunny at a coarse level. The detail coefficients
    // translate, so a re-inserted vertex lands at `p + (s − 1)(C_i − c)` instead of the
    // exactly scaled `p + (s − 1)(p − c)`: the refined part follows the scaling to within
    // (s − 1) × a coarse edge length, and its fine detail (the offset of each vertex from
    // the centroid of its neighbours) is the input's, neither smoothed away nor scaled.
    let (original, cut) = bunny_and_cut(load);
    let mut h = Hierarchy::build(
        original.clone(),
        &HierarchyOptions::rounds()
            .with_max_levels(3)
            .with_detail_mode(DetailMode::Translation),
    )
    .unwrap();
    let edge = h.mesh().mean_edge_length();
    let centre = {
        let m = h.mesh();
        let part: Vec<DVec3> = m
            .vertices()
            .map(|v| m.position(v))
            .filter(|p| p.y > cut)
            .collect();
        part.iter().sum::<DVec3>() / part.len() as f64
    };
    let s = 1.3;
    for p in h.mesh_mut().positions_mut() {
        if p.y > cut {
            *p = centre + s * (*p - centre);
        }
    }
    h.refine_to(0).unwrap();
    let fine = h.mesh();
    let laplacian = |m: &Mesh, v| {
        let n = m.adjacent_vertices(v).count() as f64;
        m.position(v) - m.adjacent_vertices(v).map(|w| m.position(w)).sum::<DVec3>() / n
    };
    let deep: Vec<_> = original
        .vertices()
        .filter(|&v| original.valence(v) > 0 && original.position(v).y > cut + INSIDE_EDGES * edge)
        .collect();
    assert!(deep.len() > 1000);
    let n = deep.len() as f64;
    let mut shape_error = 0.0;
    let (mut detail_fine, mut detail_input) = (0.0, 0.0);
    for &v in &deep {
        let p = original.position(v);
        shape_error += (fine.position(v) - (centre + s * (p - centre))).length() / n;
        detail_fine += laplacian(fine, v).length() / n;
        detail_input += laplacian(&original, v).length() / n;
    }
    assert!(
        shape_error < (s - 1.0) * edge,
        "mean distance to the scaled input {shape_error}, (s − 1) × coarse edge {}",
        (s - 1.0) * edge
    );
    let ratio = detail_fine / detail_input;
    assert!(
        (0.8..1.25).contains(&ratio),
        "fine detail magnitude changed by a factor {ratio}"
    );
    let motion = (s - 1.0) * diagonal(&original);
    for v in original.vertices() {
        if original.position(v).y < cut - OUTSIDE_EDGES * edge {
            let d = (fine.position(v) - original.position(v)).length() / motion;
            assert!(
                d < 1e-6,
                "vertex {v} outside moved by {d} of the edit's motion"
            );
        }
    }
}

#[test]
fn tiny_and_empty_meshes_build_trivial_hierarchies() {
    for method in [Method::Rounds, Method::Qem] {
        let h = Hierarchy::build(Mesh::new(), &options(method)).unwrap();
        assert_eq!(h.n_levels(), 1);
        assert_eq!(h.level_face_counts(), &[0]);
        let p = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let triangle = Mesh::from_triangles(&p, &[[0, 1, 2]]).unwrap().0;
        let mut h = Hierarchy::build(triangle, &options(method)).unwrap();
        assert_eq!(h.mesh().n_faces(), 1);
        h.refine_to(0).unwrap();
        let mut tetra = generators::icosphere(0);
        let before = snapshot(&tetra);
        tetra.check().unwrap();
        let mut h = Hierarchy::build(tetra, &options(method)).unwrap();
        h.mesh().check().unwrap();
        h.refine_to(0).unwrap();
        assert!(snapshot(h.mesh()) == before);
        tetra = h.into_mesh();
        assert_eq!(tetra.n_faces(), 20);
    }
}

/// A progress callback can stop a build (both methods): the build ends with
/// `Error::Cancelled` at the report that said stop, and a callback that never says stop
/// gives the same hierarchy as `build`.
#[test]
fn a_build_can_be_cancelled_from_its_progress_callback() {
    a_build_can_be_cancelled_from_its_progress_callback_with(&testkit::stand_in::by_topology);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn a_build_can_be_cancelled_from_its_progress_callback_on_real_meshes() {
    a_build_can_be_cancelled_from_its_progress_callback_with(&testkit::load_shared);
}

fn a_build_can_be_cancelled_from_its_progress_callback_with(load: &dyn Fn(&str) -> Mesh) {
    use std::ops::ControlFlow;
    let mesh = load("spot.obj");
    for options in [
        HierarchyOptions::rounds().with_target_faces(300),
        HierarchyOptions::qem().with_target_faces(300),
    ] {
        let mut reports = 0;
        let stopped = Hierarchy::build_cancellable(mesh.clone(), &options, &mut |p| {
            reports += 1;
            if p.levels >= 2 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        let Err(Error::Cancelled(message)) = stopped else {
            panic!("expected a cancelled build, got {stopped:?}");
        };
        assert!(message.contains("2 levels"), "{message}");
        assert_eq!(reports, 2);
        let direct = Hierarchy::build(mesh.clone(), &options).unwrap();
        let full =
            Hierarchy::build_cancellable(
                mesh.clone(),
                &options,
                &mut |_| ControlFlow::Continue(()),
            )
            .unwrap();
        assert_eq!(full.level_face_counts(), direct.level_face_counts());
        assert!(snapshot(full.mesh()) == snapshot(direct.mesh()));
    }
}

/// The default tier's stand-in for the bunny in the detail tests: a sphere of 81,920
/// faces with scan-like detail at the scale of its edges (every vertex moved off the
/// sphere by a pseudo-random fraction of an edge).
fn detailed_sphere() -> Mesh {
    let mut mesh = generators::icosphere(6);
    for (i, p) in mesh.positions_mut().iter_mut().enumerate() {
        let hash = (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40;
        let noise = hash as f64 / (1u64 << 24) as f64 * 2.0 - 1.0;
        *p *= 1.0 + 0.006 * noise;
    }
    mesh
}

/// A grid of `n × n` cells over the unit square lifted to the height `z(x, y)`.
fn height_field(n: usize, z: impl Fn(f64, f64) -> f64) -> Mesh {
    let mut mesh = generators::grid(n, n, 1.0, 1.0);
    for v in mesh.vertices().collect::<Vec<_>>() {
        let p = mesh.position(v);
        mesh.set_position(v, DVec3::new(p.x, p.y, z(p.x, p.y)));
    }
    mesh
}

/// QEM keeps a surface made of planes exactly, creases, corners and borders included
/// (what a CAD part is made of): a tilted roof (one ridge) and a tilted staircase (three
/// steps, each riser one cell wide: a convex and a concave crease per step), simplified
/// to a few dozen faces, are as far from the input as rounding. This needs the edge
/// queue to rank an edge by its cheapest *legal* place: before, when the quadric's
/// minimiser would have flipped a face, the collapse went to a costlier candidate at the
/// cheaper one's turn, cutting the border's corners and concave creases (Hausdorff
/// distances up to a quarter of the diagonal).
#[test]
fn qem_keeps_surfaces_made_of_planes_exactly() {
    let roof = |n| height_field(n, |x, y| 0.5 - (x - 0.5).abs() + 0.3 * y);
    let stairs = height_field(120, |x, y| {
        let riser = |at: f64| ((x - at) * 120.0 + 0.5).clamp(0.0, 1.0) * 0.1;
        riser(0.25) + riser(0.5) + riser(0.75) + 0.02 * y
    });
    for (name, mesh, target) in [
        ("roof 40", roof(40), 100),
        ("roof 90", roof(90), 50),
        ("stairs", stairs, 60),
    ] {
        let h = Hierarchy::build(
            mesh.clone(),
            &HierarchyOptions::qem().with_target_faces(target),
        )
        .unwrap();
        h.mesh().check().unwrap();
        assert!(
            h.mesh().n_faces() <= target,
            "{name}: {} faces",
            h.mesh().n_faces()
        );
        let d = surface_distance(&mesh, h.mesh(), &Sampling::default()).unwrap();
        assert!(
            d.hausdorff() <= 1e-9 * d.diagonal,
            "{name}: Hausdorff distance {:e} of the diagonal at {} faces",
            d.hausdorff() / d.diagonal,
            h.mesh().n_faces()
        );
    }
}
