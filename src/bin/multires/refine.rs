//! `multires refine`: the full-resolution mesh of a saved hierarchy, after its edits.

use std::time::Instant;

use halfedge::hierarchy::Hierarchy;
use multires::progress;
use serde_json::json;

use crate::args::RefineArgs;
use crate::output::Output;

pub fn run(a: RefineArgs, out: &Output) -> multires::Result<()> {
    let clock = Instant::now();
    let mut bars = out.bars(multires::load::is_large_file(&a.hierarchy));
    let mut h = progress::step(&mut bars, "loading the hierarchy", || {
        Hierarchy::load(&a.hierarchy)
    })?;
    let load_seconds = clock.elapsed().as_secs_f64();
    let from = h.level_at_or_finer();
    let clock = Instant::now();
    progress::step(&mut bars, "refining to the input", || h.go_to_level(0))?;
    let refine_seconds = clock.elapsed().as_secs_f64();
    let mesh = h.into_mesh();
    let clock = Instant::now();
    progress::step(
        &mut bars,
        &format!("writing {}", a.output.display()),
        || halfedge::io::write(&a.output, &mesh),
    )?;
    let write_seconds = clock.elapsed().as_secs_f64();
    out.json(json!({
        "hierarchy": a.hierarchy.display().to_string(),
        "output": a.output.display().to_string(),
        "from_level": from,
        "vertices": mesh.n_vertices(),
        "faces": mesh.n_faces(),
        "load_seconds": load_seconds,
        "refine_seconds": refine_seconds,
        "write_seconds": write_seconds,
    }));
    out.text(format!(
        "{} -> {}: refined from level {from} to {} vertices, {} faces (load {:.3} s, refine \
         {:.3} s, write {:.3} s)",
        a.hierarchy.display(),
        a.output.display(),
        mesh.n_vertices(),
        mesh.n_faces(),
        load_seconds,
        refine_seconds,
        write_seconds
    ));
    Ok(())
}
