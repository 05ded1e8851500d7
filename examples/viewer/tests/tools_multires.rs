//! Scripted runs of the Multiresolution, Sub-mesh edits and FFD tools under Xvfb (see
//! `tests/scripted.rs` for how the display is found): each selects its tool, sets
//! parameters, picks, drags or applies, saves the mesh and takes a screenshot; the tests
//! check the PNG is not blank, the saved meshes pass `check()`, the edit moved what it
//! should and nothing else, and undo restores the input bit for bit.

mod common;

use common::{display_command, image_stats, read};

use std::path::Path;
use std::process::Command;

use glam::DVec3;
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{generators, Mesh};
use testkit::temp_dir as scratch_dir;
use viewer::camera::{OrbitCamera, UpAxis, Viewport};
use viewer::pick::Bvh;

/// Runs a script on `input` and asserts success.
fn run_script(prefix: Command, name: &str, dir: &Path, input: &Path, actions: serde_json::Value) {
    let script = serde_json::json!({ "actions": actions });
    common::run_script(
        prefix,
        input,
        &dir.join(format!("{name}.json")),
        &script,
        "900x640",
    );
}

/// The FFD script's common start: attach a `grid` × `grid` net globally, apply an
/// identity bend and save the mesh to `identity`; then `actions`.
fn ffd_identity_then(grid: u32, identity: &Path, actions: serde_json::Value) -> serde_json::Value {
    let mut all = serde_json::json!([
        {"action": "select_tool", "tool": "ffd"},
        {"action": "set", "param": "grid_u", "value": grid},
        {"action": "set", "param": "grid_v", "value": grid},
        {"action": "set", "param": "mode", "value": "global"},
        {"action": "set", "param": "attach", "value": true},
        {"action": "set", "param": "operation", "value": "bend"},
        {"action": "set", "param": "bend", "value": 0},
        {"action": "apply"},
        {"action": "save", "path": identity}
    ]);
    if let (Some(all), serde_json::Value::Array(rest)) = (all.as_array_mut(), actions) {
        all.extend(rest);
    }
    all
}

fn assert_screenshot(path: &Path) {
    let (sigma, colors, size) = image_stats(path);
    assert_eq!(size, (900, 640));
    assert!(
        sigma > 10.0,
        "luminance deviation {sigma}: blank screenshot?"
    );
    assert!(colors > 200, "only {colors} colours: blank screenshot?");
}

/// The rings of `rings` around vertex `centre` of `mesh` (a mask per slot).
fn rings_around(mesh: &Mesh, centre: usize, rings: usize) -> Vec<bool> {
    let mut mask = vec![false; mesh.vertex_slots()];
    mask[centre] = true;
    let mut front = vec![centre];
    for _ in 0..rings {
        let mut next = Vec::new();
        for &i in &front {
            for w in mesh.adjacent_vertices(mesh.vertex_at(i).unwrap()) {
                let j = mesh.vertex_index(w);
                if !mask[j] {
                    mask[j] = true;
                    next.push(j);
                }
            }
        }
        front = next;
    }
    mask
}

#[test]
fn multires_edit_at_a_coarse_level_reaches_the_fine_mesh() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("multires");
    let input = dir.join("sphere.obj");
    let original = generators::icosphere(4);
    halfedge::io::write_obj(&input, &original).unwrap();
    let p = |name: &str| dir.join(name);
    let t = [0.25, -0.125, 0.0625];
    run_script(
        prefix,
        "multires",
        &dir,
        &input,
        serde_json::json!([
            {"action": "select_tool", "tool": "multiresolution"},
            {"action": "set", "param": "method", "value": "rounds"},
            {"action": "set", "param": "target_faces", "value": 200},
            {"action": "apply"},
            {"action": "set", "param": "level", "value": 3},
            {"action": "save", "path": p("coarse.obj")},
            {"action": "select_tool", "tool": "sub-mesh edits"},
            {"action": "set", "param": "source", "value": "all"},
            {"action": "set", "param": "operation", "value": "pull"},
            {"action": "pick_screen", "x": 0.5, "y": 0.5},
            {"action": "drag", "vector": t, "steps": 3},
            {"action": "save", "path": p("coarse-moved.obj")},
            {"action": "select_tool", "tool": "multiresolution"},
            {"action": "set", "param": "level", "value": 0},
            {"action": "save", "path": p("fine.obj")},
            {"action": "screenshot", "path": p("shot.png")},
            {"action": "undo"},
            {"action": "undo"},
            {"action": "undo"},
            {"action": "save", "path": p("undone.obj")}
        ]),
    );
    let coarse = read(&p("coarse.obj"));
    coarse.check().unwrap();
    assert!(
        coarse.n_faces() < original.n_faces() / 4,
        "level 3 is coarse"
    );
    let moved = read(&p("coarse-moved.obj"));
    moved.check().unwrap();
    let t = DVec3::from_array(t);
    for v in coarse.vertices() {
        let i = coarse.vertex_index(v);
        assert!((moved.positions()[i] - coarse.positions()[i] - t).length() < 1e-12);
    }
    // Refined back with detail coefficients: the input translated.
    let fine = read(&p("fine.obj"));
    fine.check().unwrap();
    assert_eq!(fine.n_faces(), original.n_faces());
    assert_eq!(fine.n_vertices(), original.n_vertices());
    for (i, (a, b)) in original
        .positions()
        .iter()
        .zip(fine.positions())
        .enumerate()
    {
        let d = (*b - *a - t).length();
        assert!(d < 1e-9, "vertex {i}: off the translated input by {d}");
    }
    // Undo (level 0, pull, level 3) restores the input bit for bit.
    let undone = read(&p("undone.obj"));
    assert_eq!(undone.positions(), original.positions());
    assert_eq!(undone.n_faces(), original.n_faces());
    assert_screenshot(&p("shot.png"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn submesh_edits_without_propagation_leave_the_host_bit_identical() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("submesh");
    let input = dir.join("sphere.obj");
    let original = generators::icosphere(4);
    halfedge::io::write_obj(&input, &original).unwrap();
    let p = |name: &str| dir.join(name);
    run_script(
        prefix,
        "submesh",
        &dir,
        &input,
        serde_json::json!([
            {"action": "select_tool", "tool": "sub-mesh edits"},
            {"action": "set", "param": "source", "value": "ring"},
            {"action": "set", "param": "rings", "value": 4},
            {"action": "set", "param": "levels", "value": 0},
            {"action": "set", "param": "operation", "value": "scale"},
            {"action": "set", "param": "scale", "value": 1.5},
            {"action": "pick_vertex", "index": 7},
            {"action": "apply"},
            {"action": "save", "path": p("scaled.obj")},
            {"action": "undo"},
            {"action": "save", "path": p("undone.obj")},
            {"action": "select_tool", "tool": "multiresolution"},
            {"action": "set", "param": "frontier", "value": "plane"},
            {"action": "set", "param": "normal", "value": "x"},
            {"action": "pick_vertex", "index": 0},
            {"action": "select_tool", "tool": "sub-mesh edits"},
            {"action": "set", "param": "source", "value": "labels"},
            {"action": "set", "param": "operation", "value": "twist"},
            {"action": "set", "param": "twist", "value": 90},
            {"action": "apply"},
            {"action": "set", "param": "operation", "value": "smooth"},
            {"action": "set", "param": "iterations", "value": 5},
            {"action": "apply"},
            {"action": "save", "path": p("twisted.obj")},
            {"action": "orbit", "yaw": 40, "pitch": 15},
            {"action": "screenshot", "path": p("shot.png")}
        ]),
    );
    // Scale of the 4 rings around vertex 7, n = 0: outside bit-identical.
    let scaled = read(&p("scaled.obj"));
    scaled.check().unwrap();
    let ring = rings_around(&original, 7, 4);
    let mut moved = 0;
    for (i, (a, b)) in original
        .positions()
        .iter()
        .zip(scaled.positions())
        .enumerate()
    {
        if ring[i] {
            moved += usize::from(a != b);
        } else {
            assert_eq!(a, b, "vertex {i} outside the sub-mesh moved");
        }
    }
    assert!(moved > 10, "only {moved} vertices of the sub-mesh moved");
    assert_eq!(read(&p("undone.obj")).positions(), original.positions());
    // Twist (n = 0) and smoothing of the sub-mesh cut by the plane x = x(v0) with its
    // collar ring: the far side of the plane does not move.
    let twisted = read(&p("twisted.obj"));
    twisted.check().unwrap();
    let x0 = original.positions()[0].x;
    let edge = 0.2; // more than two edge lengths of icosphere(4)
    let mut moved = 0;
    for (i, (a, b)) in original
        .positions()
        .iter()
        .zip(twisted.positions())
        .enumerate()
    {
        if a.x < x0 - edge {
            assert_eq!(a, b, "vertex {i} beyond the frontier moved");
        } else if a != b {
            moved += 1;
        }
    }
    assert!(moved > 10, "only {moved} vertices of the sub-mesh moved");
    assert_screenshot(&p("shot.png"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn ffd_identity_drag_footprint_and_undo() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("ffd");
    let input = dir.join("terrain.obj");
    // A bumpy 3 × 2 sheet: x longest, z shortest (the FFD's heights).
    let mut original = generators::grid(30, 20, 3.0, 2.0);
    for p in original.positions_mut() {
        p.z = 0.1 * (2.0 * p.x).sin() * (3.0 * p.y).cos();
    }
    halfedge::io::write_obj(&input, &original).unwrap();
    let p = |name: &str| dir.join(name);
    run_script(
        prefix,
        "ffd",
        &dir,
        &input,
        ffd_identity_then(
            10,
            &p("identity.obj"),
            serde_json::json!([
                {"action": "set", "param": "control", "value": ["shape", 4, 4]},
                {"action": "pick_vertex", "index": 0},
                {"action": "drag", "vector": [0.0, 0.0, 0.4], "steps": 4},
                {"action": "save", "path": p("dragged.obj")},
                {"action": "orbit", "yaw": 20, "pitch": 25},
                {"action": "screenshot", "path": p("shot.png")},
                {"action": "undo"},
                {"action": "undo"},
                {"action": "save", "path": p("undone.obj")},
                {"action": "redo"},
                {"action": "redo"},
                {"action": "set", "param": "operation", "value": "twist"},
                {"action": "set", "param": "twist", "value": 30},
                {"action": "apply"},
                {"action": "save", "path": p("twisted.obj")}
            ]),
        ),
    );
    // Identity surfaces give the mesh back.
    let identity = read(&p("identity.obj"));
    identity.check().unwrap();
    for (a, b) in original.positions().iter().zip(identity.positions()) {
        assert!(
            (*a - *b).length() < 1e-9,
            "identity FFD moved a vertex by {}",
            *a - *b
        );
    }
    // Dragging S(4, 4) moves only vertices over its support, u and v in [1/7, 5/7]
    // (bicubic, 10 control points: knots 0,0,0,0,1/7,…,6/7,1,1,1,1).
    let dragged = read(&p("dragged.obj"));
    dragged.check().unwrap();
    let (lo, hi) = original.bounding_box().unwrap();
    let unit = edit::deform::BSplineSurface::planar(
        &edit::deform::LatticeFrame::WORLD,
        [3, 3],
        [10, 10],
        [0.0, 0.0],
        [1.0, 1.0],
        0.0,
    )
    .unwrap();
    let (a, b) = (
        unit.evaluate(1.0 / 7.0, 0.5).x,
        unit.evaluate(5.0 / 7.0, 0.5).x,
    );
    // Frame: x along world x, heights along world z, so frame z = x × z = −y.
    let margin = 0.05;
    let span = |l: f64, h: f64| (l - margin * (h - l), h + margin * (h - l));
    let (x0, x1) = span(lo.x, hi.x);
    let (z0, z1) = span(-hi.y, -lo.y);
    let inside = |q: DVec3| {
        let (x, z) = (q.x, -q.y);
        let eps = 1e-9;
        x > x0 + a * (x1 - x0) - eps
            && x < x0 + b * (x1 - x0) + eps
            && z > z0 + a * (z1 - z0) - eps
            && z < z0 + b * (z1 - z0) + eps
    };
    let mut moved = 0;
    for (i, (q, r)) in identity
        .positions()
        .iter()
        .zip(dragged.positions())
        .enumerate()
    {
        if q != r {
            assert!(
                inside(original.positions()[i]),
                "vertex {i} outside the footprint moved"
            );
            moved += 1;
        }
    }
    assert!(moved > 20, "only {moved} vertices moved");
    assert!(moved < original.n_vertices() / 2);
    // Undo (drag, identity) restores the input bit for bit; redo and a twist work on.
    assert_eq!(read(&p("undone.obj")).positions(), original.positions());
    let twisted = read(&p("twisted.obj"));
    twisted.check().unwrap();
    assert_ne!(twisted.positions(), dragged.positions());
    assert_screenshot(&p("shot.png"));
    std::fs::remove_dir_all(&dir).ok();
}

/// The live positions of `mesh`, sorted (a saved level is compacted: compare as sets).
fn sorted_positions(mesh: &Mesh) -> Vec<[u64; 3]> {
    let mut p: Vec<[u64; 3]> = mesh
        .vertices()
        .map(|v| mesh.position(v).to_array().map(f64::to_bits))
        .collect();
    p.sort_unstable();
    p
}

#[test]
fn multires_builds_in_the_background_and_scripts_wait_for_the_levels() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("multires-build");
    let input = dir.join("sphere.obj");
    let original = generators::icosphere(4);
    halfedge::io::write_obj(&input, &original).unwrap();
    let p = |name: &str| dir.join(name);
    // What the builds give when run directly, as before they moved to a thread.
    let rounds = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(200);
    let mut direct = Hierarchy::build(original.clone(), &rounds).unwrap();
    let coarsest = direct.coarsest_level();
    assert!(coarsest >= 2);
    let qem = HierarchyOptions::qem().with_target_faces(300);
    let direct_qem = Hierarchy::build(original.clone(), &qem).unwrap();
    assert!(direct_qem.coarsest_level() >= 2);

    let mut actions = vec![
        serde_json::json!({"action": "select_tool", "tool": "multiresolution"}),
        serde_json::json!({"action": "set", "param": "method", "value": "rounds"}),
        serde_json::json!({"action": "set", "param": "target_faces", "value": 200}),
        // The build runs on a thread; the next action waits for it.
        serde_json::json!({"action": "apply"}),
    ];
    for level in 1..=coarsest {
        actions.push(serde_json::json!({"action": "set", "param": "level", "value": level}));
        actions
            .push(serde_json::json!({"action": "save", "path": p(&format!("rounds-{level}.obj"))}));
    }
    actions.push(serde_json::json!({"action": "screenshot", "path": p("shot.png")}));
    for _ in 1..=coarsest {
        actions.push(serde_json::json!({"action": "undo"}));
    }
    actions.extend([
        serde_json::json!({"action": "save", "path": p("undone.obj")}),
        serde_json::json!({"action": "set", "param": "method", "value": "qem"}),
        serde_json::json!({"action": "set", "param": "target_faces", "value": 300}),
        serde_json::json!({"action": "apply"}),
        serde_json::json!({"action": "set", "param": "level", "value": 2}),
        serde_json::json!({"action": "save", "path": p("qem-2.obj")}),
    ]);
    run_script(
        prefix,
        "multires-build",
        &dir,
        &input,
        serde_json::Value::Array(actions),
    );
    for level in 1..=coarsest {
        let saved = read(&p(&format!("rounds-{level}.obj")));
        saved.check().unwrap();
        direct.go_to_level(level).unwrap();
        assert_eq!(
            saved.n_faces(),
            direct.level_face_counts()[level],
            "level {level}"
        );
        assert_eq!(saved.n_vertices(), direct.mesh().n_vertices());
        assert_eq!(
            sorted_positions(&saved),
            sorted_positions(direct.mesh()),
            "level {level}: other positions than the direct build's"
        );
    }
    let undone = read(&p("undone.obj"));
    assert_eq!(undone.positions(), original.positions());
    assert_eq!(undone.n_faces(), original.n_faces());
    let qem2 = read(&p("qem-2.obj"));
    qem2.check().unwrap();
    assert_eq!(qem2.n_faces(), direct_qem.level_face_counts()[2]);
    assert_screenshot(&p("shot.png"));
    std::fs::remove_dir_all(&dir).ok();
}

/// The size in pixels of the 3D view of a `size` window, as the viewer's `measure` prints it.
fn view_size(prefix: Command, dir: &Path, input: &Path, size: &str) -> (f64, f64) {
    let script = dir.join("measure.json");
    std::fs::write(
        &script,
        serde_json::json!([{"action": "measure", "frames": 1}]).to_string(),
    )
    .unwrap();
    let out = common::run_viewer(
        prefix,
        &[
            input.as_os_str(),
            "--script".as_ref(),
            script.as_os_str(),
            "--size".as_ref(),
            size.as_ref(),
            "--msaa".as_ref(),
            "0".as_ref(),
        ],
        std::time::Duration::from_secs(120),
    );
    assert!(out.status.success(), "{}", common::display(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let view = stdout
        .split("view ")
        .nth(1)
        .and_then(|s| s.split(':').next())
        .unwrap_or_else(|| panic!("no view size in {stdout}"));
    let (w, h) = view.split_once('x').expect("WxH");
    (w.trim().parse().unwrap(), h.trim().parse().unwrap())
}

#[test]
fn ffd_press_beyond_the_silhouette_grabs_a_control_point() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("ffd-ray");
    let input = dir.join("terrain.obj");
    let mut original = generators::grid(30, 20, 3.0, 2.0);
    for p in original.positions_mut() {
        p.z = 0.1 * (2.0 * p.x).sin() * (3.0 * p.y).cos();
    }
    halfedge::io::write_obj(&input, &original).unwrap();
    let size = "900x640";
    let (width, height) = view_size(display_command().unwrap(), &dir, &input, size);
    // The FFD as the tool attaches it (global, 6 × 6 bicubic): its corner control point
    // S(0, 0) lies 5 % beyond the corner of the sheet.
    let (lo, hi) = original.bounding_box().unwrap();
    let frame = edit::deform::LatticeFrame::new(lo, DVec3::X, DVec3::Z).unwrap();
    let ffd = edit::deform::Ffd::covering(
        &original,
        edit::Vertices::All,
        frame,
        ([3, 3], [6, 6]),
        ([3, 3], [6, 6]),
        0.05,
        edit::deform::AttachOptions::default(),
    )
    .unwrap();
    let corner = ffd.shape().control_point(0, 0).unwrap();
    // Where the viewer's freshly framed camera shows it.
    let camera = OrbitCamera::framing(lo, hi, UpAxis::Y);
    let viewport = Viewport {
        x: 0.0,
        y: 0.0,
        width,
        height,
    };
    let (px, py, _) = camera.project(corner, &viewport).expect("in front");
    let (x, y) = (px / width, 1.0 - py / height);
    assert!(
        (0.05..0.95).contains(&x) && (0.05..0.95).contains(&y),
        "({x}, {y})"
    );
    let ray = camera.ray(px, py, &viewport);
    assert!(
        Bvh::build(&original)
            .intersect(&original, &ray)
            .unwrap()
            .is_none(),
        "the press at ({x}, {y}) should miss the sheet"
    );
    let p = |name: &str| dir.join(name);
    run_script(
        prefix,
        "ffd-ray",
        &dir,
        &input,
        ffd_identity_then(
            6,
            &p("identity.obj"),
            serde_json::json!([
                {"action": "drag", "x": x, "y": y, "vector": [0.0, 0.0, 0.5], "steps": 3},
                {"action": "save", "path": p("dragged.obj")},
                {"action": "screenshot", "path": p("shot.png")},
                {"action": "undo"},
                {"action": "undo"},
                {"action": "save", "path": p("undone.obj")}
            ]),
        ),
    );
    let identity = read(&p("identity.obj"));
    let dragged = read(&p("dragged.obj"));
    dragged.check().unwrap();
    // S(0, 0) (or H(0, 0) drawn over it) only reaches u, v < 1/3 (knots 0,0,0,0,1/3,…):
    // the corner at low x and high y (the frame's v runs along −y).
    let limit = ffd.shape().evaluate(1.0 / 3.0, 1.0 / 3.0);
    assert!(limit.x < 0.5 * (lo.x + hi.x) && limit.y > 0.5 * (lo.y + hi.y));
    let eps = 1e-9;
    let mut moved = 0;
    for (i, (a, b)) in identity
        .positions()
        .iter()
        .zip(dragged.positions())
        .enumerate()
    {
        if a != b {
            let q = original.positions()[i];
            assert!(
                q.x < limit.x + eps && q.y > limit.y - eps,
                "vertex {i} at {q} moved, away from the grabbed corner"
            );
            moved += 1;
        }
    }
    assert!(moved > 10, "only {moved} vertices moved: nothing grabbed?");
    assert_eq!(read(&p("undone.obj")).positions(), original.positions());
    assert_screenshot(&p("shot.png"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bendels_klein_refinement_at_a_coarse_level_keeps_the_hierarchy() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("multires-bk");
    let input = dir.join("sphere.obj");
    let original = generators::icosphere(4);
    halfedge::io::write_obj(&input, &original).unwrap();
    let p = |name: &str| dir.join(name);
    // The viewer's build is the direct one (see the background-build test): its level 2
    // gives the vertex indices to paint at.
    let level = 2;
    let mut direct = Hierarchy::build(
        original.clone(),
        &HierarchyOptions::rounds().with_target_faces(200),
    )
    .unwrap();
    direct.go_to_level(level).unwrap();
    let coarse = direct.mesh();
    let extreme = |sign: f64| {
        coarse
            .vertices()
            .max_by(|&a, &b| {
                (sign * coarse.position(a).z).total_cmp(&(sign * coarse.position(b).z))
            })
            .map(|v| coarse.vertex_index(v))
            .unwrap()
    };
    let (top, bottom) = (extreme(1.0), extreme(-1.0));
    let coarsest = direct.coarsest_level();
    assert!(coarsest > level);
    run_script(
        prefix,
        "multires-bk",
        &dir,
        &input,
        serde_json::json!([
            {"action": "select_tool", "tool": "multiresolution"},
            {"action": "set", "param": "method", "value": "rounds"},
            {"action": "set", "param": "target_faces", "value": 200},
            {"action": "apply"},
            {"action": "set", "param": "level", "value": level},
            {"action": "select_tool", "tool": "bendels"},
            {"action": "set", "param": "brush", "value": 0.15},
            {"action": "set", "param": "paint_handle", "value": top},
            {"action": "set", "param": "brush", "value": 0.3},
            {"action": "set", "param": "paint_fixed", "value": bottom},
            {"action": "set", "param": "translate", "value": [0.0, 0.0, 1.0]},
            {"action": "save", "path": p("edited.obj")},
            {"action": "set", "param": "refine_threshold", "value": 1.5},
            {"action": "apply"},
            {"action": "save", "path": p("refined.obj")},
            {"action": "select_tool", "tool": "multiresolution"},
            {"action": "set", "param": "level", "value": 0},
            {"action": "save", "path": p("fine.obj")},
            {"action": "set", "param": "level", "value": coarsest},
            {"action": "set", "param": "level", "value": level},
            {"action": "save", "path": p("back.obj")},
            {"action": "undo"}, {"action": "undo"}, {"action": "undo"},
            {"action": "undo"},
            {"action": "save", "path": p("undone.obj")},
            {"action": "set", "param": "level", "value": 0},
            {"action": "save", "path": p("undone-fine.obj")}
        ]),
    );
    let (edited, refined) = (read(&p("edited.obj")), read(&p("refined.obj")));
    refined.check().unwrap();
    // The refinement is at the input: the level shown is still a coarse level.
    let fine = read(&p("fine.obj"));
    fine.check().unwrap();
    assert!(
        fine.n_vertices() > original.n_vertices(),
        "no vertex added at the input ({} → {})",
        original.n_vertices(),
        fine.n_vertices()
    );
    assert!(
        refined.n_faces() < fine.n_faces() * 3 / 4,
        "level {level} is coarse ({} faces, {} at level 0)",
        refined.n_faces(),
        fine.n_faces()
    );
    let back = read(&p("back.obj"));
    back.check().unwrap();
    assert_eq!(back.n_vertices(), refined.n_vertices());
    // Undo (level 2, level 0 … the walk is one step per change, the refinement) gives the
    // edited coarse mesh bit for bit, and the input vertex count at level 0.
    let undone = read(&p("undone.obj"));
    assert_eq!(undone.n_vertices(), edited.n_vertices());
    assert_eq!(undone.positions(), edited.positions());
    let undone_fine = read(&p("undone-fine.obj"));
    assert_eq!(undone_fine.n_vertices(), original.n_vertices());
    std::fs::remove_dir_all(&dir).ok();
}
