//! The `coarse_edit` example's measurement (issue 12, `testkit::coarse_edit`): an edit made at a coarse level and
//! refined back against the same edit made at full resolution, for every edit, both
//! simplification methods and levels 2 to 4. The four targets: nothing outside
//! the edit's region moves, rigid and affine parts land within 1e-9 of the diagonal, no
//! more flipped faces than at full resolution, and an RMS distance to the full-resolution
//! edit of at most 1 % of the diagonal.
//!
//! The default tier runs on generated meshes (closed, open, genus one, two components,
//! flat) and asserts all four targets there. The real-mesh tier (`--include-ignored`)
//! asserts them on the shared meshes at level 3 with both methods.

use glam::DVec3;
use halfedge::hierarchy::{DetailMode, Method};
use halfedge::{generators, Mesh};
use testkit::coarse_edit::{self, EditKind, Options, Report};

/// A smooth bump field on top of a surface point (a few waves).
fn bumps(p: DVec3) -> f64 {
    0.04 * (5.0 * p.x + 1.0).sin() * (4.0 * p.y + 2.0).sin() * (3.0 * p.z).sin()
        + 0.015 * (11.0 * p.x).sin() * (9.0 * p.y + 1.0).sin() * (13.0 * p.z + 2.0).sin()
}

/// A closed genus-0 surface: an icosphere stretched along x, with bumps.
fn bumpy_capsule() -> Mesh {
    let mut mesh = generators::icosphere(4);
    for p in mesh.positions_mut() {
        let n = *p;
        *p = DVec3::new(2.0 * n.x, n.y, n.z) * (1.0 + bumps(n));
    }
    mesh
}

/// An open surface with one boundary loop: the bumpy capsule without its faces below
/// z = −0.4 (unreferenced vertices dropped).
fn open_cap() -> Mesh {
    let capsule = bumpy_capsule();
    let mut index = vec![u32::MAX; capsule.vertex_slots()];
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for f in capsule.faces() {
        let tri = capsule.triangle(f);
        if tri.iter().all(|&v| capsule.position(v).z >= -0.4) {
            triangles.push(tri.map(|v| {
                let i = capsule.vertex_index(v);
                if index[i] == u32::MAX {
                    index[i] = positions.len() as u32;
                    positions.push(capsule.position(v));
                }
                index[i]
            }));
        }
    }
    Mesh::from_triangles(&positions, &triangles).unwrap().0
}

/// A flat open patch with a gentle bump: a 40 × 30 grid.
fn flat_patch() -> Mesh {
    let mut mesh = generators::grid(40, 30, 4.0, 3.0);
    for p in mesh.positions_mut() {
        let d2 = (p.x - 2.0).powi(2) + (p.y - 1.5).powi(2);
        p.z = 0.3 * (-d2 / 0.3).exp();
    }
    mesh
}

/// A genus-one surface: a torus of `nu × nv` quads split in triangles, with bumps.
fn bumpy_torus(nu: usize, nv: usize) -> Mesh {
    let (major, minor) = (1.0, 0.35);
    let mut positions = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let a = std::f64::consts::TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let b = std::f64::consts::TAU * j as f64 / nv as f64;
            let r = minor * (1.0 + 2.0 * bumps(DVec3::new(a.cos(), a.sin(), b.cos())));
            // slightly elliptic, so that the farthest vertex is unique
            positions.push(DVec3::new(
                1.3 * (major + r * b.cos()) * a.cos(),
                (major + r * b.cos()) * a.sin(),
                r * b.sin(),
            ));
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
    let mut triangles = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Mesh::from_triangles(&positions, &triangles).unwrap().0
}

/// Two components: the bumpy capsule and a smaller bumpy sphere beside it.
fn two_components() -> Mesh {
    let a = bumpy_capsule();
    let mut b = generators::icosphere(3);
    for p in b.positions_mut() {
        let n = *p;
        *p = DVec3::new(0.0, 2.5, 0.0) + 0.6 * n * (1.0 + bumps(n + DVec3::X));
    }
    let mut positions: Vec<DVec3> = a.positions().to_vec();
    let offset = positions.len() as u32;
    positions.extend_from_slice(b.positions());
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    for (mesh, base) in [(&a, 0), (&b, offset)] {
        for f in mesh.faces() {
            triangles.push(mesh.triangle(f).map(|v| base + mesh.vertex_index(v) as u32));
        }
    }
    Mesh::from_triangles(&positions, &triangles).unwrap().0
}

/// Every edit at `level` with both methods; the reports.
fn measure_all(
    name: &str,
    mesh: &Mesh,
    levels: &[usize],
    edits: &[EditKind],
) -> Vec<(String, Report)> {
    let mut reports = Vec::new();
    for method in [Method::Rounds, Method::Qem] {
        for &level in levels {
            let prepared =
                coarse_edit::prepare(mesh.clone(), method, DetailMode::LocalFrame, level)
                    .unwrap_or_else(|e| panic!("{name} {method:?} level {level}: {e}"));
            for &edit in edits {
                let report = coarse_edit::measure(&prepared, &Options::new(edit))
                    .unwrap_or_else(|e| {
                        panic!("{name} {method:?} level {level} {}: {e}", edit.name())
                    })
                    .report;
                reports.push((name.to_string(), report));
            }
        }
    }
    reports
}

/// Panics with every report that misses `target`.
fn assert_all(reports: &[(String, Report)], what: &str, target: impl Fn(&Report) -> bool) {
    let failed: Vec<String> = reports
        .iter()
        .filter(|(_, r)| !target(r))
        .map(|(name, r)| r.to_json(name).to_string())
        .collect();
    assert!(
        failed.is_empty(),
        "{} of {} measurements miss {what}:\n{}",
        failed.len(),
        reports.len(),
        failed.join("\n")
    );
}

/// Every edit on the generated meshes, at levels 2 to 4 with both methods.
fn generated_reports() -> Vec<(String, Report)> {
    let mut reports = Vec::new();
    for (name, mesh) in [
        ("capsule", bumpy_capsule()),
        ("open cap", open_cap()),
        ("torus", bumpy_torus(72, 24)),
        ("two components", two_components()),
    ] {
        reports.extend(measure_all(name, &mesh, &[2, 3, 4], &EditKind::ALL));
    }
    reports
}

#[test]
fn coarse_edits_keep_their_regions_land_their_handles_and_stay_close_on_generated_meshes() {
    let reports = generated_reports();
    assert_all(&reports, "outside_moved = 0", Report::region_is_exact);
    assert_all(&reports, "handle_error <= 1e-9", Report::handles_land);
    assert_all(&reports, "rms_vs_full_res <= 0.01", Report::is_close);
    // the measurements measure something: rigid parts were marked and compared, regions
    // were not empty, and both edits moved the surface
    for (name, r) in &reports {
        let what = r.to_json(name);
        assert!(r.marks > 0 || r.edit == EditKind::Ffd, "{what}");
        assert!(
            r.region_vertices[0] > 0 && r.region_vertices[1] > r.region_vertices[0],
            "{what}"
        );
        assert_eq!(r.handle_error.is_some(), r.edit != EditKind::Ffd, "{what}");
        assert!(r.handle_vertices > 0 || r.edit == EditKind::Ffd, "{what}");
        assert!(r.moved[0] > 0 && r.moved[1] > 0, "{what}");
    }
}

#[test]
fn coarse_edits_end_like_full_resolution_edits_on_generated_meshes() {
    // No coarse edit flips a fine face more than the same edit at full resolution (17 of
    // the 192 runs did, with 56 extra faces, before a twist or taper along its axis was
    // marked as the map of space it is and a scale was compared with the same
    // re-seating at both resolutions).
    let reports = generated_reports();
    assert_all(
        &reports,
        "flips_coarse_path <= flips_full_res",
        Report::no_extra_flips,
    );
}

#[test]
fn coarse_edits_meet_the_targets_far_from_the_origin_and_at_any_scale() {
    // The capsule placed 10⁷ units away (as georeferenced scans are: positions round to
    // about 10⁻⁹ there), and shrunk to a micrometre: every edit at level 3 with rounds
    // still makes its measurements and meets the four targets. (The example's check of
    // the rigid parts asked for 1e-12 of the diagonal whatever the coordinates, and its
    // FFD lattice had a thickness floor of 1e-9 units: the first refused every rigid
    // edit far away, the second made the micrometre FFD a different edit.)
    let capsule = bumpy_capsule();
    let moved = |f: &dyn Fn(DVec3) -> DVec3| {
        let mut mesh = capsule.clone();
        for p in mesh.positions_mut() {
            *p = f(*p);
        }
        mesh
    };
    let far = moved(&|p| p + DVec3::new(1.0e7, -3.0e6, 2.0e6));
    let tiny = moved(&|p| p * 1e-6);
    let mut reports = Vec::new();
    for (name, mesh) in [("far", &far), ("tiny", &tiny)] {
        let prepared =
            coarse_edit::prepare(mesh.clone(), Method::Rounds, DetailMode::LocalFrame, 3)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        for edit in EditKind::ALL {
            let report = coarse_edit::measure(&prepared, &Options::new(edit))
                .unwrap_or_else(|e| panic!("{name} {}: {e}", edit.name()))
                .report;
            reports.push((name.to_string(), report));
        }
    }
    assert_all(&reports, "all four targets", Report::meets_targets);
    // The same edits as on the capsule where it is: the same regions.
    let prepared =
        coarse_edit::prepare(capsule, Method::Rounds, DetailMode::LocalFrame, 3).unwrap();
    for (name, r) in &reports {
        let here = coarse_edit::measure(&prepared, &Options::new(r.edit))
            .unwrap()
            .report;
        assert_eq!(
            r.region_vertices,
            here.region_vertices,
            "{name} {}",
            r.edit.name()
        );
    }
}

#[test]
fn a_flat_region_twists_from_the_boundary_and_refuses_a_seed_inside() {
    // On a flat open patch the rule's region (three rings in from the rim) is enclosed by
    // its frontier: nothing reaches beyond it along any axis a twist or taper could use.
    // The rule then takes the tip on the boundary (a corner, where the patch protrudes),
    // and the edits meet the targets like the others. A tip given inside the patch is
    // refused with an error naming the flag to change.
    let mesh = flat_patch();
    let prepared =
        coarse_edit::prepare(mesh.clone(), Method::Rounds, DetailMode::LocalFrame, 3).unwrap();
    let mut reports = Vec::new();
    for edit in EditKind::ALL {
        let report = coarse_edit::measure(&prepared, &Options::new(edit))
            .unwrap()
            .report;
        if matches!(edit, EditKind::Twist | EditKind::Taper) {
            let coarse = prepared.hierarchy.mesh();
            let tip = coarse.vertex_at(report.tip).unwrap();
            assert!(
                coarse.is_boundary_vertex(tip),
                "{}",
                report.to_json("flat patch")
            );
            assert!(report.moved[0] > 0 && report.moved[1] > 0);
        }
        reports.push(("flat patch".to_string(), report));
    }
    assert_all(&reports, "the targets", Report::meets_targets);
    // the input vertex nearest the patch's centre, away from the bump
    let inside = mesh
        .vertices()
        .min_by(|&a, &b| {
            let d = |v| mesh.position(v).distance(DVec3::new(1.0, 0.75, 0.0));
            d(a).total_cmp(&d(b))
        })
        .map(|v| mesh.vertex_index(v))
        .unwrap();
    for edit in [EditKind::Twist, EditKind::Taper] {
        let options = Options {
            seed_vertex: Some(inside),
            ..Options::new(edit)
        };
        let e = coarse_edit::measure(&prepared, &options).err().unwrap();
        assert!(
            e.message.contains("flat") && e.hint.contains("--seed-vertex"),
            "{e}"
        );
    }
}

#[test]
fn the_paper_translations_move_vertices_outside_the_region() {
    // The same measurement with the seed paper's centroid translations: the edit
    // diffuses beyond its region and the rigid part does not land (what local frames fix).
    let prepared =
        coarse_edit::prepare(bumpy_capsule(), Method::Rounds, DetailMode::Translation, 3).unwrap();
    let report = coarse_edit::measure(&prepared, &Options::new(EditKind::Rotate))
        .unwrap()
        .report;
    assert_eq!(report.marks, 0);
    assert!(report.outside_moved > 0, "{report:?}");
    assert!(report.handle_error.unwrap() > 1e-4, "{report:?}");
    assert!(!report.meets_targets());
}

#[test]
fn region_options_are_checked() {
    let prepared =
        coarse_edit::prepare(bumpy_capsule(), Method::Qem, DetailMode::LocalFrame, 2).unwrap();
    for (options, what) in [
        (
            Options {
                region_fraction: 0.0,
                ..Options::new(EditKind::Pull)
            },
            "--region-fraction",
        ),
        (
            Options {
                amount: f64::NAN,
                ..Options::new(EditKind::Pull)
            },
            "--amount",
        ),
        (
            Options {
                seed_vertex: Some(1 << 30),
                ..Options::new(EditKind::Lee)
            },
            "--seed-vertex",
        ),
    ] {
        let e = coarse_edit::measure(&prepared, &options).err().unwrap();
        assert!(e.to_string().contains(what), "{e}");
        assert!(!e.hint.is_empty());
    }
    assert!(
        coarse_edit::prepare(bumpy_capsule(), Method::Rounds, DetailMode::LocalFrame, 0).is_err()
    );
    let e = coarse_edit::prepare(
        generators::icosphere(1),
        Method::Rounds,
        DetailMode::LocalFrame,
        40,
    )
    .err()
    .unwrap();
    assert!(e.hint.contains("--level"), "{e}");
}

/// Every edit at level 3 with both methods on every shared mesh.
fn shared_reports() -> Vec<(String, Report)> {
    let dir = testkit::shared_meshes();
    let mut reports = Vec::new();
    for file in [
        "beast.obj",
        "cow.obj",
        "fandisk.obj",
        "horse.ply",
        "nefertiti.obj",
        "spot.obj",
        "stanford-bunny.obj",
        "suzanne.obj",
        "teapot.obj",
    ] {
        let (mesh, _) = halfedge::io::read(dir.join(file)).unwrap();
        reports.extend(measure_all(file, &mesh, &[3], &EditKind::ALL));
    }
    reports
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes; cargo test --release -- --include-ignored"]
fn coarse_edits_meet_the_four_targets_on_the_shared_meshes() {
    let reports = shared_reports();
    assert_all(&reports, "outside_moved = 0", Report::region_is_exact);
    assert_all(&reports, "handle_error <= 1e-9", Report::handles_land);
    assert_all(
        &reports,
        "flips_coarse_path <= flips_full_res",
        Report::no_extra_flips,
    );
    assert_all(&reports, "rms_vs_full_res <= 0.01", Report::is_close);
}

/// `--edit bk-refine` on `mesh` at `levels` with both methods: the JSON objects.
fn bk_refine_reports(name: &str, mesh: &Mesh, levels: &[usize]) -> Vec<serde_json::Value> {
    let mut reports = Vec::new();
    for method in [Method::Rounds, Method::Qem] {
        for &level in levels {
            let prepared =
                coarse_edit::prepare(mesh.clone(), method, DetailMode::LocalFrame, level)
                    .unwrap_or_else(|e| panic!("{name} {method:?} level {level}: {e}"));
            let report =
                coarse_edit::measure_bk_refine(&prepared, &Options::new(EditKind::Bk), name)
                    .unwrap_or_else(|e| panic!("{name} {method:?} level {level} bk-refine: {e}"));
            reports.push(report);
        }
    }
    reports
}

/// A B&K edit with adaptive refinement made at a coarse level composes with the
/// hierarchy: vertices were added, every level is reachable and back with a valid mesh,
/// and the handle is the exact rigid image of its input vertices.
fn assert_bk_refine(reports: &[serde_json::Value]) {
    for r in reports {
        assert_eq!(r["levels_reachable"], true, "{r}");
        assert!(r["new_vertices"].as_u64().unwrap() > 0, "{r}");
        assert!(r["handle_vertices"].as_u64().unwrap() > 0, "{r}");
        assert!(r["handle_error"].as_f64().unwrap() <= 1e-9, "{r}");
        assert!(r["faces"].as_u64() > r["input_faces"].as_u64(), "{r}");
    }
}

#[test]
fn bk_refine_at_a_coarse_level_keeps_every_level_reachable_on_generated_meshes() {
    let mut reports = bk_refine_reports("capsule", &bumpy_capsule(), &[2, 3]);
    reports.extend(bk_refine_reports("torus", &bumpy_torus(72, 24), &[3]));
    assert_bk_refine(&reports);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes; cargo test --release -- --include-ignored"]
fn bk_refine_at_a_coarse_level_keeps_every_level_reachable_on_the_shared_meshes() {
    let dir = testkit::shared_meshes();
    let mut reports = Vec::new();
    for file in [
        "beast.obj",
        "cow.obj",
        "fandisk.obj",
        "horse.ply",
        "nefertiti.obj",
        "spot.obj",
        "stanford-bunny.obj",
        "suzanne.obj",
        "teapot.obj",
    ] {
        let (mesh, _) = halfedge::io::read(dir.join(file)).unwrap();
        reports.extend(bk_refine_reports(file, &mesh, &[3]));
    }
    assert_bk_refine(&reports);
}
