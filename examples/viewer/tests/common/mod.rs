//! Scaffolding shared by the viewer's scripted tests: a display for the viewer (Xvfb or
//! `$DISPLAY`), running it with a time limit, reading what it saved, and measuring its
//! screenshots.
#![allow(dead_code)] // each test binary uses its own part

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use halfedge::Mesh;

pub const PACKAGES: &str = "xvfb xauth libgl1-mesa-dri libegl1 libxkbcommon-x11-0";

/// Serialises the tests that start a display: `xvfb-run -a` races when started in
/// parallel, and llvmpipe gains nothing from sharing two cores.
pub static DISPLAY_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// A command prefix that gives the viewer a display, or `None` (after failing in CI).
pub fn display_command() -> Option<Command> {
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

/// Runs the viewer with `args` on a display, killing it after `limit`.
pub fn run_viewer(prefix: Command, args: &[&std::ffi::OsStr], limit: Duration) -> Output {
    let _guard = DISPLAY_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    // xvfb-run replaces the viewer's exit status with its own (5) when it fails to remove
    // its temporary folder after the run, which happens now and then on a loaded host:
    // that run says nothing about the viewer, so it is made once more.
    let rebuild = |prefix: &Command| {
        let mut cmd = Command::new(prefix.get_program());
        cmd.args(prefix.get_args());
        cmd
    };
    let again = rebuild(&prefix);
    let out = run_once(prefix, args, limit);
    if String::from_utf8_lossy(&out.stderr).contains("xvfb-run: error: problem while cleaning up") {
        return run_once(again, args, limit);
    }
    out
}

fn run_once(prefix: Command, args: &[&std::ffi::OsStr], limit: Duration) -> Output {
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

pub fn read(path: &Path) -> Mesh {
    halfedge::io::read(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .0
}

/// Standard deviation of the luminance and number of distinct colours of a PNG.
pub fn image_stats(path: &Path) -> (f64, usize, (u32, u32)) {
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

pub fn display(out: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// Writes `script` (the JSON of a viewer script) to `path`, runs the viewer on `input`
/// with it (window `size`, no multisampling) and asserts that it succeeded.
pub fn run_script(
    prefix: Command,
    input: &Path,
    path: &Path,
    script: &serde_json::Value,
    size: &str,
) {
    std::fs::write(path, script.to_string()).unwrap();
    let out = run_viewer(
        prefix,
        &[
            input.as_os_str(),
            "--script".as_ref(),
            path.as_os_str(),
            "--size".as_ref(),
            size.as_ref(),
            "--msaa".as_ref(),
            "0".as_ref(),
        ],
        Duration::from_secs(300),
    );
    assert!(out.status.success(), "{}", display(&out));
}
