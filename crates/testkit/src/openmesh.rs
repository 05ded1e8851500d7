//! The OpenMesh comparison tier (`#[ignore]`d tests that run python scripts with
//! `openmesh==1.2.1`): the report keys both sides compute, and the check that the python
//! module is there.

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
