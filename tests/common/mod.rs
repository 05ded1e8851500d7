//! Helpers shared by the workspace's integration tests (OpenMesh, the examples' binaries).
#![allow(dead_code, missing_docs)]

use std::path::{Path, PathBuf};

/// The report keys OpenMesh and this kernel both compute.
pub const KEYS: [&str; 9] = [
    "vertices",
    "edges",
    "faces",
    "halfedges",
    "boundary_vertices",
    "boundary_loops",
    "components",
    "euler",
    "valence_histogram",
];

/// An example's binary, built by `cargo test` next to the test binaries (a filtered
/// `cargo test --test NAME` does not build examples: run the whole suite, or
/// `cargo build --release --examples` first).
pub fn example_binary(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let path = exe
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(
        path.exists(),
        "{} not built (cargo test builds examples)",
        path.display()
    );
    path
}

/// The workspace root.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `../shared/meshes` (the first ancestor of the workspace that has `shared/meshes`), or
/// `$MULTIRES_MESHES`. Only the real-mesh and OpenMesh tiers (`#[ignore]`d tests) read it;
/// it panics, saying how to get the meshes, when there are none.
pub fn shared_meshes() -> PathBuf {
    if let Some(dir) = std::env::var_os("MULTIRES_MESHES") {
        return PathBuf::from(dir);
    }
    root()
        .ancestors()
        .map(|a| a.join("shared/meshes"))
        .find(|d| d.is_dir())
        .expect(
            "the real-mesh tier needs the shared test meshes: a `shared/meshes` folder above \
             the workspace, or MULTIRES_MESHES=DIR",
        )
}

/// Panics with what to install unless python3 can import `openmesh` and `numpy` (the
/// OpenMesh tier).
pub fn require_openmesh() {
    let probe = std::process::Command::new("python3")
        .args(["-c", "import openmesh, numpy"])
        .output();
    match probe {
        Ok(out) if out.status.success() => {}
        Ok(out) => panic!(
            "the OpenMesh tier needs the python module openmesh ({}): \
             `python3 -m pip install openmesh==1.2.1 numpy` (it builds from source with cmake \
             and a C++ compiler; .ci/run installs everything)",
            String::from_utf8_lossy(&out.stderr).trim()
        ),
        Err(e) => {
            panic!("the OpenMesh tier needs python3 ({e}) with `pip install openmesh==1.2.1 numpy`")
        }
    }
}
