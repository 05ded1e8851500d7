//! Test support for the multires workspace: a dev-dependency of every crate, used by the
//! integration tests (`tests/*.rs`) and the benches. It gathers what the tests used to copy
//! into each crate's `tests/common` modules:
//!
//! - where the meshes are: [`shared_meshes`] / [`shared_mesh`] / [`load_shared`] (the real
//!   meshes of the `#[ignore]`d real-mesh tier), [`data_dir`] / [`data`] (the small
//!   generated meshes of the workspace's `data/`), [`temp_dir`], [`workspace_root`],
//!   [`example_binary`];
//! - [`stand_in`]: the generated meshes that replace the shared meshes in the default
//!   tier, one meaning per name;
//! - [`meshes`]: generated meshes the tests need and `halfedge::generators` lacks;
//! - [`check`]: snapshots and comparisons of meshes (bit-for-bit positions and
//!   connectivity, Euler characteristic, volume, …);
//! - [`regions`]: the vertex regions the editing tests pick (Spot's snout, the bunny's ear
//!   and head);
//! - [`ply`]: PLY files written byte by byte, to test the readers;
//! - [`openmesh`]: the OpenMesh comparison tier's requirements;
//! - [`bench`](mod@bench): the benches' inputs: the shared meshes and the large meshes made from them
//!   (subdivided, cached as PLY in `bench-cache/`), for `benches/*.rs` and `bench_cache`;
//! - [`coarse_edit`]: the measurement of the `coarse_edit` example and
//!   `tests/coarse_edit.rs` (an edit made at a coarse level and refined back, against the
//!   same edit at full resolution).
//!
//! `testkit` depends on `halfedge` and `edit`, and both dev-depend on `testkit`: the types
//! agree in their integration tests, not in their `#[cfg(test)]` unit tests (those see a
//! second copy of the crate), so only integration tests, benches and the root package's
//! examples use it.

#![forbid(unsafe_code)]

pub mod bench;
pub mod check;
pub mod coarse_edit;
pub mod meshes;
pub mod openmesh;
pub mod ply;
pub mod regions;
pub mod stand_in;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

use halfedge::Mesh;

/// The workspace root (the folder of the root `Cargo.toml`).
pub fn workspace_root() -> &'static Path {
    static ROOT: OnceLock<PathBuf> = OnceLock::new();
    ROOT.get_or_init(|| {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        root.canonicalize().unwrap_or(root)
    })
}

/// The shared real meshes: `$MULTIRES_MESHES`, else the `shared/meshes` folder of the
/// first ancestor of the workspace that has one (`../shared/meshes` beside the checkout).
/// Only the real-mesh and OpenMesh tiers (`#[ignore]`d tests) and the benches read them.
///
/// # Panics
/// When there is no such folder, saying how to get the meshes.
pub fn shared_meshes() -> PathBuf {
    if let Some(dir) = std::env::var_os("MULTIRES_MESHES") {
        return PathBuf::from(dir);
    }
    workspace_root()
        .ancestors()
        .map(|a| a.join("shared/meshes"))
        .find(|d| d.is_dir())
        .expect(
            "the real-mesh tier needs the shared test meshes: a `shared/meshes` folder above \
             the workspace, or MULTIRES_MESHES=DIR",
        )
}

/// The path of a shared mesh by file name (`"spot.obj"`); see [`shared_meshes`].
///
/// # Panics
/// When there is no shared meshes folder (not when the file is missing).
pub fn shared_mesh(name: &str) -> PathBuf {
    shared_meshes().join(name)
}

/// A shared mesh by file name (`"spot.obj"`), read with `halfedge::io::read`.
///
/// # Panics
/// When the shared meshes are missing or the file does not read.
pub fn load_shared(name: &str) -> Mesh {
    let path = shared_mesh(name);
    halfedge::io::read(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .0
}

/// The workspace's `data/` folder: small generated meshes checked in (see
/// `examples/make_data.rs`), read by the default tier.
pub fn data_dir() -> PathBuf {
    workspace_root().join("data")
}

/// A mesh of `data/` by file name (`"creature.obj"`).
///
/// # Panics
/// When the file does not read.
pub fn data(name: &str) -> Mesh {
    let path = data_dir().join(name);
    halfedge::io::read(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .0
}

/// A fresh, empty-at-first folder of its own under the system's temporary folder, named
/// after `test`: every call gets another folder (the process id and a counter), since the
/// tests of one binary run in parallel in one process.
///
/// # Panics
/// When the folder cannot be created.
pub fn temp_dir(test: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("multires-{test}-{}-{n}", std::process::id()));
    std::fs::create_dir_all(&dir)
        .unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    dir
}

/// An example's binary of the root package, built by `cargo test` next to the test
/// binaries (a filtered `cargo test --test NAME` does not build examples: run the whole
/// suite, or `cargo build --release --examples` first).
///
/// # Panics
/// When the binary is not built.
pub fn example_binary(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let path = exe
        .parent()
        .and_then(Path::parent)
        .expect("the test binary sits in target/<profile>/deps")
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(
        path.exists(),
        "{} not built (cargo test builds examples)",
        path.display()
    );
    path
}
