//! `multires check`: every connectivity invariant, and with `--openmesh` the topology
//! OpenMesh reads from the same file.

use std::path::Path;
use std::process::Command;

use halfedge::Mesh;
use multires::load::{self, Weld};
use multires::Error;
use serde_json::json;

use crate::args::CheckArgs;
use crate::output::Output;

/// What OpenMesh reads from `path` (run in python3 with the `openmesh` package): vertex,
/// face and edge counts and the boundary halfedges.
const OPENMESH_SCRIPT: &str = r#"
import json, sys
import openmesh as om
m = om.read_trimesh(sys.argv[1])
b = sum(1 for h in m.halfedges() if m.is_boundary(h))
print(json.dumps({"vertices": m.n_vertices(), "faces": m.n_faces(),
                  "edges": m.n_edges(), "boundary_halfedges": b}))
"#;

fn counts(mesh: &Mesh) -> serde_json::Value {
    let boundary = mesh
        .halfedges()
        .filter(|&h| mesh.is_boundary_halfedge(h))
        .count();
    json!({
        "vertices": mesh.n_vertices(),
        "faces": mesh.n_faces(),
        "edges": mesh.n_edges(),
        "boundary_halfedges": boundary,
    })
}

/// OpenMesh's counts for `path` (decompressed into a temporary file first for `.gz`).
fn openmesh_counts(path: &Path) -> Result<serde_json::Value, String> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    let mut temporary = None;
    let readable = if let Some(inner) = name
        .strip_suffix(".gz")
        .filter(|_| name.to_ascii_lowercase().ends_with(".gz"))
    {
        let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
        let limit = halfedge::io::gz::decompressed_limit(bytes.len() as u64);
        let data = halfedge::io::gz::decompress(&bytes, path, limit).map_err(|e| e.to_string())?;
        let file =
            std::env::temp_dir().join(format!("multires-check-{}-{inner}", std::process::id()));
        std::fs::write(&file, data).map_err(|e| e.to_string())?;
        temporary = Some(file.clone());
        file
    } else {
        path.to_owned()
    };
    let output = Command::new("python3")
        .arg("-c")
        .arg(OPENMESH_SCRIPT)
        .arg(&readable)
        .output();
    if let Some(file) = temporary {
        let _ = std::fs::remove_file(file);
    }
    let output = output.map_err(|e| {
        format!("cannot run python3 ({e}): --openmesh needs python3 with the openmesh package")
    })?;
    if !output.status.success() {
        let err = String::from_utf8_lossy(&output.stderr);
        let last = err.lines().last().unwrap_or("").trim().to_owned();
        return Err(if last.contains("No module named") {
            "--openmesh needs the openmesh package for python3 (pip install openmesh)".to_owned()
        } else {
            format!("OpenMesh could not read the file: {last}")
        });
    }
    serde_json::from_slice(&output.stdout).map_err(|e| format!("unexpected OpenMesh output: {e}"))
}

pub fn run(a: CheckArgs, out: &Output) -> multires::Result<()> {
    let mut bars = out.bars(load::is_large_file(&a.mesh));
    // The file's own vertices (no welding), as OpenMesh reads them.
    let loaded = load::load(&a.mesh, Weld::Off, &mut bars)?;
    let mesh = &loaded.mesh;
    let verdict = multires::progress::step(&mut bars, "checking every invariant", || mesh.check());
    let ours = counts(mesh);
    let mut report = json!({
        "file": a.mesh.display().to_string(),
        "valid": verdict.is_ok(),
        "counts": ours,
    });
    if let Err(e) = &verdict {
        report["error"] = json!(e.to_string());
    }
    let mut mismatch = None;
    if a.openmesh {
        let theirs = openmesh_counts(&a.mesh).map_err(|reason| Error::InvalidOption {
            option: "--openmesh",
            reason,
        })?;
        let agree = theirs == report["counts"];
        report["openmesh"] = theirs.clone();
        report["openmesh_agrees"] = json!(agree);
        if !agree {
            mismatch = Some(theirs);
        }
    }
    out.json(report.clone());
    out.text(format!(
        "{}: {}; {} vertices, {} faces, {} edges, {} boundary halfedges{}",
        a.mesh.display(),
        match &verdict {
            Ok(()) => "every invariant holds".to_owned(),
            Err(e) => format!("INVALID: {e}"),
        },
        report["counts"]["vertices"],
        report["counts"]["faces"],
        report["counts"]["edges"],
        report["counts"]["boundary_halfedges"],
        match (&mismatch, a.openmesh) {
            (Some(theirs), _) => format!("\nOpenMesh reads something else: {theirs}"),
            (None, true) => "\nOpenMesh reads the same topology".to_owned(),
            _ => String::new(),
        }
    ));
    verdict?;
    if let Some(theirs) = mismatch {
        return Err(Error::OpenMeshDisagrees {
            path: a.mesh.clone(),
            ours: report["counts"].to_string(),
            theirs: theirs.to_string(),
        });
    }
    Ok(())
}
