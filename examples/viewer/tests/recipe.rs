//! The viewer writes its edits as an edit recipe (`multires::recipe`), and the recipe
//! replays them bit for bit: on a hierarchy, `multires edit` on a hierarchy built by
//! `multires simplify` with the viewer's options gives the viewer's full-resolution mesh;
//! on a plain mesh, `multires::recipe::apply_to_mesh` gives the viewer's mesh. An edit
//! without a recipe step (FFD) makes `save_recipe` fail, naming it. Scripted runs under
//! Xvfb (see `tests/scripted.rs` for how the display is found).

mod common;

use common::{display, display_command, read, run_viewer};
use testkit::temp_dir as scratch_dir;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use glam::DVec3;
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{generators, Mesh};
use multires::progress::Silent;
use multires::recipe::{self, Recipe, Step};

/// Runs a script on `input` and asserts success.
fn run_script(prefix: Command, dir: &Path, input: &Path, actions: serde_json::Value) {
    let script = serde_json::json!({ "actions": actions });
    common::run_script(prefix, input, &dir.join("script.json"), &script, "900x640");
}

/// The index of the live vertex of `mesh` nearest to `p`.
fn nearest(mesh: &Mesh, p: DVec3) -> usize {
    let v = mesh
        .vertices()
        .min_by(|&a, &b| {
            mesh.position(a)
                .distance(p)
                .total_cmp(&mesh.position(b).distance(p))
        })
        .unwrap();
    mesh.vertex_index(v)
}

/// Positions as bits.
fn bits(mesh: &Mesh) -> Vec<[u64; 3]> {
    mesh.positions()
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect()
}

/// Asserts that two meshes have the same faces and the same positions, bit for bit.
fn assert_bit_identical(viewer: &Mesh, replay: &Mesh, what: &str) {
    assert_eq!(viewer.to_arrays().1, replay.to_arrays().1, "{what}: faces");
    let (a, b) = (bits(viewer), bits(replay));
    assert_eq!(a.len(), b.len(), "{what}: vertex count");
    let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert_eq!(
        differ,
        0,
        "{what}: {differ} of {} positions differ",
        a.len()
    );
}

/// The `multires` binary: `$MULTIRES_BIN`, else next to this test's binary, brought up
/// to date by `cargo build -p multires --bin multires` into the same target folder (a no-op when it
/// is, so that a stale binary never replays a recipe of a newer schema).
fn multires_binary() -> PathBuf {
    if let Some(path) = std::env::var_os("MULTIRES_BIN") {
        return PathBuf::from(path);
    }
    static BUILT: std::sync::Once = std::sync::Once::new();
    let exe = std::env::current_exe().unwrap();
    let dir = exe.parent().unwrap().parent().unwrap();
    let path = dir.join(format!("multires{}", std::env::consts::EXE_SUFFIX));
    BUILT.call_once(|| {
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let profile = dir.file_name().unwrap().to_string_lossy().into_owned();
        let mut cmd = Command::new(cargo);
        cmd.args(["build", "-p", "multires", "--bin", "multires"])
            .current_dir(env!("CARGO_MANIFEST_DIR"));
        if profile == "release" {
            cmd.arg("--release");
        }
        let status = cmd.status().expect("cargo runs");
        assert!(
            status.success(),
            "cargo build -p multires --bin multires failed"
        );
    });
    assert!(path.exists(), "{} not built", path.display());
    path
}

fn run_multires(args: &[&std::ffi::OsStr]) {
    let out = Command::new(multires_binary())
        .args(args)
        .output()
        .expect("multires runs");
    assert!(out.status.success(), "multires {args:?}: {}", display(&out));
}

fn methods(recipe: &Recipe) -> Vec<&'static str> {
    recipe.steps.iter().map(Step::method).collect()
}

#[test]
fn a_recipe_saved_at_a_coarse_level_replays_bit_for_bit_with_multires_edit() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("recipe-hierarchy");
    let p = |name: &str| dir.join(name);
    let input = p("sphere.ply");
    let original = generators::icosphere(4);
    halfedge::io::write(&input, &original).unwrap();
    // The viewer's build, with the options `multires simplify` uses by default (rounds,
    // the library's normal-deviation bound of 60°, local-frame detail), to find vertices
    // of level 2 for the script.
    let (target, level) = (300, 2);
    let mut h = Hierarchy::build(
        original.clone(),
        &HierarchyOptions::rounds().with_target_faces(target),
    )
    .unwrap();
    assert!(h.coarsest_level() >= level);
    h.go_to_level(level).unwrap();
    let coarse = h.mesh();
    let top = nearest(coarse, DVec3::Z);
    let side = nearest(coarse, DVec3::X);
    let back = nearest(coarse, -DVec3::X);
    let front = nearest(coarse, DVec3::Y);
    run_script(
        prefix,
        &dir,
        &input,
        serde_json::json!([
            {"action": "select_tool", "tool": "multiresolution"},
            {"action": "set", "param": "method", "value": "rounds"},
            {"action": "set", "param": "target_faces", "value": target},
            {"action": "set", "param": "max_normal_deviation", "value": 60},
            {"action": "apply"},
            {"action": "set", "param": "level", "value": level},
            // Lee: a disk at the top, its centre dragged, then re-shaped at s = 0.3.
            {"action": "select_tool", "tool": "lee"},
            {"action": "set", "param": "radius", "value": 0.35},
            {"action": "set", "param": "disk", "value": top},
            {"action": "set", "param": "mode", "value": "drag"},
            {"action": "pick_vertex", "index": top},
            {"action": "drag", "vector": [0.05, 0.0, 0.2], "steps": 3},
            {"action": "set", "param": "scale", "value": 0.3},
            // Bendels–Klein: a painted handle at +x, the fixed region at −x; rotated and
            // moved (the second change replaces the first's step).
            {"action": "select_tool", "tool": "bendels"},
            {"action": "set", "param": "brush", "value": 0.12},
            {"action": "set", "param": "paint_handle", "value": side},
            {"action": "set", "param": "brush", "value": 0.45},
            {"action": "set", "param": "paint_fixed", "value": back},
            {"action": "set", "param": "axis", "value": [0.0, 0.0, 1.0]},
            {"action": "set", "param": "angle", "value": 20},
            {"action": "set", "param": "translate", "value": [0.1, 0.0, 0.05]},
            // Sub-mesh edits: a ring at +y pulled, then tapered; a smoothing undone.
            {"action": "select_tool", "tool": "sub-mesh edits"},
            {"action": "set", "param": "source", "value": "ring"},
            {"action": "set", "param": "rings", "value": 2},
            {"action": "set", "param": "levels", "value": 1},
            {"action": "set", "param": "operation", "value": "pull"},
            {"action": "pick_vertex", "index": front},
            {"action": "drag", "vector": [0.0, 0.15, 0.0], "steps": 2},
            {"action": "set", "param": "operation", "value": "taper"},
            {"action": "set", "param": "taper", "value": 0.7},
            {"action": "apply"},
            {"action": "set", "param": "operation", "value": "smooth"},
            {"action": "apply"},
            {"action": "undo"},
            {"action": "save_recipe", "path": p("edits.toml")},
            {"action": "select_tool", "tool": "multiresolution"},
            {"action": "set", "param": "level", "value": 0},
            {"action": "save", "path": p("viewer.ply")}
        ]),
    );
    let recipe = Recipe::read(&p("edits.toml")).unwrap();
    assert_eq!(
        methods(&recipe),
        ["lee_drag", "blend", "pull", "taper"],
        "{}",
        recipe.to_toml()
    );
    assert!(recipe.steps.iter().all(|s| s.level() == Some(level)));
    let Step::LeeDrag(lee) = &recipe.steps[0] else {
        unreachable!()
    };
    assert_eq!(lee.scale, Some(0.3), "the re-shaped drag");
    let spec = recipe.hierarchy.as_ref().expect("the build's options");
    assert_eq!(spec.target_faces, Some(target));
    // The hierarchy as `multires simplify` builds it, the recipe replayed on it.
    let target = target.to_string();
    run_multires(&[
        "simplify".as_ref(),
        input.as_os_str(),
        "-o".as_ref(),
        p("built.mrh").as_os_str(),
        "--target-faces".as_ref(),
        target.as_ref(),
    ]);
    run_multires(&[
        "edit".as_ref(),
        p("built.mrh").as_os_str(),
        "--recipe".as_ref(),
        p("edits.toml").as_os_str(),
        "-o".as_ref(),
        p("edited.mrh").as_os_str(),
        "--mesh".as_ref(),
        p("replayed.ply").as_os_str(),
    ]);
    let viewer = read(&p("viewer.ply"));
    let replayed = read(&p("replayed.ply"));
    assert_ne!(bits(&viewer), bits(&original), "the edits moved the mesh");
    assert_bit_identical(&viewer, &replayed, "multires edit");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_recipe_saved_on_a_plain_mesh_replays_bit_for_bit_with_apply_to_mesh() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("recipe-plain");
    let p = |name: &str| dir.join(name);
    let input = p("sphere.ply");
    let original = generators::icosphere(3);
    halfedge::io::write(&input, &original).unwrap();
    let at = |x: f64, y: f64, z: f64| nearest(&original, DVec3::new(x, y, z).normalize());
    // A loop of 4 picks around the top (Lee), loops around +x and −x (Bendels–Klein).
    let lee_loop: Vec<usize> = (0..4)
        .map(|k| {
            let a = k as f64 * std::f64::consts::FRAC_PI_2;
            at(0.6 * a.cos(), 0.6 * a.sin(), 0.8)
        })
        .collect();
    let handle_loop: Vec<usize> = (0..4)
        .map(|k| {
            let a = k as f64 * std::f64::consts::FRAC_PI_2;
            at(0.9, 0.4 * a.cos(), 0.4 * a.sin())
        })
        .collect();
    let fixed_loop: Vec<usize> = (0..4)
        .map(|k| {
            let a = k as f64 * std::f64::consts::FRAC_PI_2;
            at(-0.2, 0.95 * a.cos(), 0.95 * a.sin())
        })
        .collect();
    let top = at(0.0, 0.0, 1.0);
    let front = at(0.0, -1.0, 0.0);
    run_script(
        prefix,
        &dir,
        &input,
        serde_json::json!([
            {"action": "select_tool", "tool": "lee"},
            {"action": "set", "param": "boundary", "value": lee_loop},
            {"action": "set", "param": "frames", "value": "normal"},
            {"action": "set", "param": "mode", "value": "drag"},
            {"action": "pick_vertex", "index": top},
            {"action": "drag", "vector": [0.0, 0.1, 0.15], "steps": 4},
            {"action": "select_tool", "tool": "bendels"},
            {"action": "set", "param": "handle_loop", "value": handle_loop},
            {"action": "set", "param": "fixed_loop", "value": fixed_loop},
            {"action": "set", "param": "shape", "value": "linear"},
            {"action": "set", "param": "scale", "value": 1.2},
            {"action": "set", "param": "translate", "value": [0.1, 0.05, 0.0]},
            {"action": "select_tool", "tool": "sub-mesh edits"},
            {"action": "set", "param": "source", "value": "ring"},
            {"action": "set", "param": "rings", "value": 3},
            {"action": "pick_vertex", "index": front},
            {"action": "set", "param": "operation", "value": "twist"},
            {"action": "set", "param": "twist", "value": 40},
            {"action": "apply"},
            {"action": "set", "param": "operation", "value": "smooth"},
            {"action": "set", "param": "weights", "value": "cotangent"},
            {"action": "apply"},
            {"action": "set", "param": "operation", "value": "rotate"},
            {"action": "set", "param": "angle", "value": 25},
            {"action": "apply"},
            {"action": "undo"},
            {"action": "undo"},
            {"action": "redo"},
            {"action": "save_recipe", "path": p("edits.toml")},
            {"action": "save", "path": p("viewer.ply")}
        ]),
    );
    let recipe = Recipe::read(&p("edits.toml")).unwrap();
    assert_eq!(
        methods(&recipe),
        ["lee_drag", "blend", "twist", "smooth"],
        "{}",
        recipe.to_toml()
    );
    assert!(recipe.steps.iter().all(|s| s.level().is_none()));
    assert!(recipe.hierarchy.is_none());
    let mut replayed = read(&input);
    recipe::apply_to_mesh(&mut replayed, &recipe, &mut Silent).unwrap();
    let viewer = read(&p("viewer.ply"));
    assert_ne!(bits(&viewer), bits(&original), "the edits moved the mesh");
    assert_bit_identical(&viewer, &replayed, "apply_to_mesh");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_edit_without_a_recipe_step_keeps_the_recipe_from_being_saved() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("recipe-refused");
    let p = |name: &str| dir.join(name);
    let input = p("sphere.ply");
    halfedge::io::write(&input, &generators::icosphere(2)).unwrap();
    let script = serde_json::json!({"actions": [
        {"action": "select_tool", "tool": "ffd"},
        {"action": "set", "param": "mode", "value": "global"},
        {"action": "set", "param": "attach", "value": true},
        {"action": "set", "param": "operation", "value": "bend"},
        {"action": "set", "param": "bend", "value": 30},
        {"action": "apply"},
        {"action": "save_recipe", "path": p("edits.toml")}
    ]});
    std::fs::write(p("script.json"), script.to_string()).unwrap();
    let out = run_viewer(
        prefix,
        &[
            input.as_os_str(),
            "--script".as_ref(),
            p("script.json").as_os_str(),
            "--msaa".as_ref(),
            "0".as_ref(),
        ],
        Duration::from_secs(300),
    );
    assert_eq!(out.status.code(), Some(1), "{}", display(&out));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("save_recipe") && stderr.contains("FFD"),
        "{}",
        display(&out)
    );
    assert!(!p("edits.toml").exists());
    std::fs::remove_dir_all(&dir).ok();
}
