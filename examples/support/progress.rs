//! Progress display shared by the examples (included with `#[path]`): spinners and bars
//! from `indicatif` on the long steps, shown only for large meshes (the libraries never
//! print; they offer callbacks such as `Hierarchy::build_with_progress`). indicatif draws
//! on stderr and stays silent when it is not a terminal.

#![allow(dead_code)] // each example uses part of it

use std::path::Path;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// Meshes with more faces than this get progress displays.
pub const LARGE_FACES: usize = 200_000;

/// Mesh files bigger than this (bytes) get a spinner while loading: about 200k faces in
/// OBJ, 400k in binary PLY.
pub const LARGE_FILE_BYTES: u64 = 8 << 20;

/// True when `faces` is large enough for progress displays.
pub fn is_large(faces: usize) -> bool {
    faces > LARGE_FACES
}

/// A spinner with `message`, ticking on its own; hidden unless `show`.
pub fn spinner(show: bool, message: impl Into<String>) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new_spinner().with_style(
        ProgressStyle::with_template("{spinner} {msg} {elapsed}").expect("valid template"),
    );
    bar.set_message(message.into());
    bar.enable_steady_tick(Duration::from_millis(120));
    bar
}

/// A bar of `len` steps with `template` (indicatif syntax); hidden unless `show`.
pub fn bar(show: bool, len: u64, template: &str) -> ProgressBar {
    if !show {
        return ProgressBar::hidden();
    }
    ProgressBar::new(len).with_style(
        ProgressStyle::with_template(template)
            .expect("valid template")
            .progress_chars("=> "),
    )
}

/// Runs `f` under a spinner with `message` when `show`, and clears it afterwards.
pub fn step<T>(show: bool, message: impl Into<String>, f: impl FnOnce() -> T) -> T {
    let bar = spinner(show, message);
    let result = f();
    bar.finish_and_clear();
    result
}

/// Reads a mesh file, with a spinner when the file is large.
pub fn read(path: &Path) -> halfedge::Result<(halfedge::Mesh, halfedge::BuildReport)> {
    let large = std::fs::metadata(path).is_ok_and(|m| m.len() > LARGE_FILE_BYTES);
    step(large, format!("loading {}", path.display()), || {
        halfedge::io::read(path)
    })
}
