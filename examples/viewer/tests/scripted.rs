//! End-to-end tests of the viewer binary in scripted mode.
//!
//! The viewer needs an X display with OpenGL. The tests run it under `xvfb-run` (Mesa's
//! llvmpipe renders in software) when `xvfb-run` is installed, else on `$DISPLAY` when
//! one is set. With neither, they fail when the `CI` environment variable is set (CI
//! must run them: install the packages named in the message) and are skipped with a
//! note otherwise, so that a developer without Xvfb can still run `cargo test`.

mod common;

use common::{display, display_command, image_stats, read, run_script, run_viewer};

use std::process::Command;
use std::time::Duration;

use glam::DVec3;
use halfedge::generators;
use testkit::temp_dir as scratch_dir;

#[test]
fn scripted_drag_undo_redo_save_and_screenshot() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("drag");
    let input = dir.join("sphere.obj");
    let original = generators::icosphere(3);
    halfedge::io::write_obj(&input, &original).unwrap();
    let (a, b, c, shot) = (
        dir.join("a.obj"),
        dir.join("b.obj"),
        dir.join("c.obj"),
        dir.join("shot.png"),
    );
    let script = dir.join("script.json");
    let text = serde_json::json!({"actions": [
        {"action": "select_tool", "tool": "sub-mesh edits"},
        {"action": "set", "param": "source", "value": "ring"},
        {"action": "set", "param": "rings", "value": 2},
        {"action": "set", "param": "levels", "value": 0},
        {"action": "set", "param": "operation", "value": "pull"},
        {"action": "pick_vertex", "index": 0},
        {"action": "drag", "vector": [0.3, 0.0, 0.0], "steps": 4},
        {"action": "save", "path": a},
        {"action": "undo"},
        {"action": "save", "path": b},
        {"action": "redo"},
        {"action": "orbit", "yaw": 20, "pitch": 10},
        {"action": "drag_screen", "dx": 40, "dy": -30, "steps": 3},
        {"action": "save", "path": c},
        {"action": "view", "wireframe": true},
        {"action": "screenshot", "path": shot}
    ]});
    run_script(prefix, &input, &script, &text, "800x600");

    // The drag pulled the two rings around vertex 0 by the vector (no propagation) and
    // nothing else.
    let moved = read(&a);
    moved.check().unwrap();
    assert_eq!(moved.n_vertices(), original.n_vertices());
    let v0 = original.vertex_at(0).unwrap();
    let mut ring = vec![false; original.vertex_slots()];
    ring[0] = true;
    for w in original.adjacent_vertices(v0) {
        ring[original.vertex_index(w)] = true;
        for x in original.adjacent_vertices(w) {
            ring[original.vertex_index(x)] = true;
        }
    }
    let t = DVec3::new(0.3, 0.0, 0.0);
    let mut changed = 0;
    for (i, (p, q)) in original
        .positions()
        .iter()
        .zip(moved.positions())
        .enumerate()
    {
        if ring[i] {
            assert!(
                (*q - *p - t).length() < 1e-12,
                "vertex {i} moved by {}",
                *q - *p
            );
            changed += 1;
        } else {
            assert_eq!(p, q, "vertex {i} outside the sub-mesh moved");
        }
    }
    assert!(changed > 1, "the rings follow the picked vertex");

    // Undo restored the input exactly; redo and a screen drag moved further.
    assert_eq!(read(&b).positions(), original.positions());
    let further = read(&c);
    assert_ne!(further.positions()[0], moved.positions()[0]);
    assert_eq!(further.positions()[1..].len(), moved.positions()[1..].len());

    // The screenshot shows the window: not blank, many colours.
    let (sigma, colors, size) = image_stats(&shot);
    assert_eq!(size, (800, 600));
    assert!(
        sigma > 10.0,
        "luminance deviation {sigma}: blank screenshot?"
    );
    assert!(colors > 200, "only {colors} colours: blank screenshot?");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn screenshot_without_a_script() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("shot");
    let input = dir.join("grid.obj");
    halfedge::io::write_obj(&input, &generators::grid(20, 20, 1.0, 1.0)).unwrap();
    let shot = dir.join("grid.png");
    let out = run_viewer(
        prefix,
        &[
            input.as_os_str(),
            "--screenshot".as_ref(),
            shot.as_os_str(),
            "--size".as_ref(),
            "640x480".as_ref(),
        ],
        Duration::from_secs(240),
    );
    assert!(out.status.success(), "{}", display(&out));
    let (sigma, _, size) = image_stats(&shot);
    assert_eq!(size, (640, 480));
    assert!(
        sigma > 10.0,
        "luminance deviation {sigma}: blank screenshot?"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_failing_action_exits_with_status_1_and_names_it() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("fail");
    let script = dir.join("script.json");
    std::fs::write(
        &script,
        r#"[{"action": "frame"}, {"action": "pick_vertex", "index": 123456789}]"#,
    )
    .unwrap();
    let out = run_viewer(
        prefix,
        &[
            "--script".as_ref(),
            script.as_os_str(),
            "--msaa".as_ref(),
            "0".as_ref(),
        ],
        Duration::from_secs(240),
    );
    assert_eq!(out.status.code(), Some(1), "{}", display(&out));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("action 1 (pick_vertex)") && err.contains("no vertex 123456789"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_malformed_script_is_refused_before_opening_a_window() {
    // No display needed: the script is parsed first.
    let dir = scratch_dir("bad");
    let script = dir.join("script.json");
    std::fs::write(&script, r#"[{"action": "zoom", "factr": 2}]"#).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_viewer"))
        .args(["--script".as_ref(), script.as_os_str()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", display(&out));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("action 0") && err.contains("factr"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
