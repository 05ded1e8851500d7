//! End-to-end tests of the viewer binary in scripted mode.
//!
//! The viewer needs an X display with OpenGL. The tests run it under `xvfb-run` (Mesa's
//! llvmpipe renders in software) when `xvfb-run` is installed, else on `$DISPLAY` when
//! one is set. With neither, they fail when the `CI` environment variable is set (CI
//! must run them: install the packages named in the message) and are skipped with a
//! note otherwise, so that a developer without Xvfb can still run `cargo test`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use glam::DVec3;
use halfedge::{generators, Mesh};

const PACKAGES: &str = "xvfb xauth libgl1-mesa-dri libegl1 libxkbcommon-x11-0";

/// Serialises the tests that start a display: `xvfb-run -a` races when started in
/// parallel, and llvmpipe gains nothing from sharing two cores.
static DISPLAY_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// A command prefix that gives the viewer a display, or `None` (after failing in CI).
fn display_command() -> Option<Command> {
    let has_xvfb_run = Command::new("sh")
        .args(["-c", "command -v xvfb-run"])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if has_xvfb_run {
        let mut cmd = Command::new("xvfb-run");
        cmd.args(["-a", "-s", "-screen 0 1280x1024x24"]);
        return Some(cmd);
    }
    if std::env::var_os("DISPLAY").is_some() {
        // `env` runs the viewer directly on the current display.
        return Some(Command::new("env"));
    }
    if std::env::var_os("CI").is_some() {
        panic!(
            "the viewer tests need an X display: install Xvfb and software OpenGL \
             (apt-get install {PACKAGES}) so that `xvfb-run` exists"
        );
    }
    eprintln!(
        "skipping the viewer test: neither xvfb-run nor DISPLAY (apt-get install {PACKAGES})"
    );
    None
}

fn scratch_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("viewer-test-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs the viewer with `args` on a display, killing it after `limit`.
fn run_viewer(prefix: Command, args: &[&std::ffi::OsStr], limit: Duration) -> Output {
    let _guard = DISPLAY_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut cmd = prefix;
    cmd.arg(env!("CARGO_BIN_EXE_viewer"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("the viewer starts");
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if start.elapsed() > limit {
            child.kill().ok();
            let out = child.wait_with_output().unwrap();
            panic!(
                "the viewer did not finish within {limit:?}\nstdout:\n{}\nstderr:\n{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    child.wait_with_output().unwrap()
}

fn read(path: &Path) -> Mesh {
    halfedge::io::read(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .0
}

/// Standard deviation of the luminance and number of distinct colours of a PNG.
fn image_stats(path: &Path) -> (f64, usize, (u32, u32)) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8();
    let lum: Vec<f64> = img
        .pixels()
        .map(|p| 0.2126 * p.0[0] as f64 + 0.7152 * p.0[1] as f64 + 0.0722 * p.0[2] as f64)
        .collect();
    let mean = lum.iter().sum::<f64>() / lum.len() as f64;
    let var = lum.iter().map(|l| (l - mean) * (l - mean)).sum::<f64>() / lum.len() as f64;
    let mut colors: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    colors.sort_unstable();
    colors.dedup();
    (var.sqrt(), colors.len(), img.dimensions())
}

fn display(out: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

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
    std::fs::write(&script, text.to_string()).unwrap();
    let out = run_viewer(
        prefix,
        &[
            input.as_os_str(),
            "--script".as_ref(),
            script.as_os_str(),
            "--size".as_ref(),
            "800x600".as_ref(),
            "--msaa".as_ref(),
            "0".as_ref(),
        ],
        Duration::from_secs(240),
    );
    assert!(out.status.success(), "{}", display(&out));

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
