//! `multires convert`: between every format the kernel reads and writes.

use std::time::Instant;

use halfedge::io::{self, PlyFormat, StlFormat};
use multires::load;
use serde_json::json;

use crate::args::ConvertArgs;
use crate::output::Output;

/// Writes `mesh` to `path` by its extension; `ascii` picks the text forms of PLY and STL.
pub fn write_mesh(
    path: &std::path::Path,
    mesh: &halfedge::Mesh,
    ascii: bool,
) -> halfedge::Result<()> {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if ascii && name.ends_with(".ply") {
        io::write_ply(path, mesh, PlyFormat::Ascii)
    } else if ascii && name.ends_with(".stl") {
        io::write_stl(path, mesh, StlFormat::Ascii)
    } else {
        io::write(path, mesh)
    }
}

pub fn run(a: ConvertArgs, out: &Output) -> multires::Result<()> {
    let clock = Instant::now();
    let mut bars = out.bars(load::is_large_file(&a.input));
    let loaded = load::load(&a.input, a.weld.weld, &mut bars)?;
    let load_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    multires::progress::step(
        &mut bars,
        &format!("writing {}", a.output.display()),
        || write_mesh(&a.output, &loaded.mesh, a.ascii),
    )?;
    let write_seconds = clock.elapsed().as_secs_f64();
    out.json(json!({
        "input": a.input.display().to_string(),
        "output": a.output.display().to_string(),
        "vertices": loaded.mesh.n_vertices(),
        "faces": loaded.mesh.n_faces(),
        "load_seconds": load_seconds,
        "write_seconds": write_seconds,
    }));
    out.text(format!(
        "{} -> {}: {} vertices, {} faces (read {:.3} s, written {:.3} s){}",
        a.input.display(),
        a.output.display(),
        loaded.mesh.n_vertices(),
        loaded.mesh.n_faces(),
        load_seconds,
        write_seconds,
        loaded
            .welding
            .map_or(String::new(), |w| format!("\nnote: {}", w.note))
    ));
    Ok(())
}
