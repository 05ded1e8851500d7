//! Topology report of a mesh file, as one JSON object on stdout.
//!
//! ```text
//! cargo run --release --example topology -- data/blob.obj
//! ```
//!
//! Keys: `vertices`, `edges`, `faces`, `halfedges`, `boundary_vertices`,
//! `boundary_loops`, `components`, `euler`, `valence_histogram` (valence as a string →
//! number of vertices; isolated vertices have valence 0 and count as boundary
//! vertices, as in OpenMesh and pmp), `duplicated_vertices` and `dropped_faces` (from
//! the build report: what the OpenMesh-policy builder had to do), then
//! `non_manifold_vertices`; with `--collapse-ok`, `collapse_ok_halfedges`. The same counts come from OpenMesh with
//! `python3 tests/openmesh/report.py FILE`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

/// Command-line arguments.
#[derive(Parser, Debug)]
#[command(about = "Print the topology report of a mesh file (.obj, .ply) as JSON")]
struct Args {
    /// The mesh file (.obj or .ply).
    file: PathBuf,
    /// Also report `collapse_ok_halfedges`: how many halfedges `is_collapse_ok` accepts
    /// (OpenMesh's semantics).
    #[arg(long)]
    collapse_ok: bool,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let (mesh, build) = match halfedge::io::read(&args.file) {
        Ok(loaded) => loaded,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let report = mesh.topology_report();
    let mut json = report.to_json(Some(&build));
    if args.collapse_ok {
        let accepted = mesh
            .halfedges()
            .filter(|&h| mesh.is_collapse_ok(h).is_ok())
            .count();
        json.pop(); // the closing brace
        json.push_str(&format!(", \"collapse_ok_halfedges\": {accepted}}}"));
    }
    println!("{json}");
    ExitCode::SUCCESS
}
