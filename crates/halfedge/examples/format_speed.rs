//! Read speed of every format on one generated mesh: writes a subdivided icosphere
//! (1.3 M faces, or `--level N`: 20·4^N faces) as binary PLY, binary and ASCII STL, OFF,
//! OBJ and gzip-compressed binary STL into a temporary folder, then reads each file three
//! times with `io::read` and prints the best time, the file size and what was read.
//!
//! ```text
//! cargo run -p multires-halfedge --release --example format_speed [-- --level 8] [--keep DIR]
//! ```
//!
//! `--keep DIR` writes the files into DIR and leaves them there (for timing other
//! readers, such as OpenMesh's, on the same files).

use std::time::Instant;

use halfedge::generators;
use halfedge::io::{self, PlyFormat, StlFormat};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let level: usize = value("--level").map_or(Ok(8), |l| l.parse())?;
    let keep = value("--keep");
    let dir = match &keep {
        Some(d) => std::path::PathBuf::from(d),
        None => std::env::temp_dir().join(format!("format-speed-{}", std::process::id())),
    };
    std::fs::create_dir_all(&dir)?;
    let mesh = generators::icosphere(level);
    println!(
        "icosphere({level}): {} vertices, {} faces",
        mesh.n_vertices(),
        mesh.n_faces()
    );
    let files = [
        ("binary PLY", dir.join("mesh.ply")),
        ("binary STL", dir.join("mesh.stl")),
        ("ASCII STL", dir.join("mesh-ascii.stl")),
        ("OFF", dir.join("mesh.off")),
        ("OBJ", dir.join("mesh.obj")),
        ("binary STL, gzip", dir.join("mesh.stl.gz")),
    ];
    for (what, path) in &files {
        let started = Instant::now();
        match *what {
            "binary PLY" => io::write_ply(path, &mesh, PlyFormat::BinaryLittleEndian)?,
            "ASCII STL" => io::write_stl(path, &mesh, StlFormat::Ascii)?,
            _ => io::write(path, &mesh)?,
        }
        let written = started.elapsed();
        let size = std::fs::metadata(path)?.len();
        let mut best = f64::INFINITY;
        let mut read = None;
        for _ in 0..3 {
            let started = Instant::now();
            let (back, report) = io::read(path)?;
            best = best.min(started.elapsed().as_secs_f64());
            read = Some((back.n_vertices(), back.n_faces(), report.merged_vertices));
        }
        let (v, f, merged) = read.unwrap();
        println!(
            "{what:>18}: {:>7.1} MB, written in {:>6.3} s, read in {best:>6.3} s \
             ({v} vertices, {f} faces, {merged} corners merged)",
            size as f64 / 1e6,
            written.as_secs_f64(),
        );
    }
    if keep.is_none() {
        std::fs::remove_dir_all(&dir)?;
    }
    Ok(())
}
