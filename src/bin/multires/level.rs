//! `multires level`: one level of a saved hierarchy as a mesh.

use std::time::Instant;

use halfedge::hierarchy::Hierarchy;
use multires::progress;
use serde_json::json;

use crate::args::LevelArgs;
use crate::output::Output;

pub fn run(a: LevelArgs, out: &Output) -> multires::Result<()> {
    let clock = Instant::now();
    let mut bars = out.bars(multires::load::is_large_file(&a.hierarchy));
    let mut h = progress::step(&mut bars, "loading the hierarchy", || {
        Hierarchy::load(&a.hierarchy)
    })?;
    let load_seconds = clock.elapsed().as_secs_f64();
    let level = a.level.min(h.coarsest_level());
    let clock = Instant::now();
    progress::step(&mut bars, &format!("walking to level {level}"), || {
        h.go_to_level(level)
    })?;
    let walk_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    progress::step(
        &mut bars,
        &format!("writing {}", a.output.display()),
        || halfedge::io::write(&a.output, h.mesh()),
    )?;
    let write_seconds = clock.elapsed().as_secs_f64();
    out.json(json!({
        "hierarchy": a.hierarchy.display().to_string(),
        "output": a.output.display().to_string(),
        "level": level,
        "vertices": h.mesh().n_vertices(),
        "faces": h.mesh().n_faces(),
        "load_seconds": load_seconds,
        "walk_seconds": walk_seconds,
        "write_seconds": write_seconds,
    }));
    out.text(format!(
        "level {level} of {} -> {}: {} vertices, {} faces{}",
        a.hierarchy.display(),
        a.output.display(),
        h.mesh().n_vertices(),
        h.mesh().n_faces(),
        if level < a.level {
            format!(" (level {} asked; the coarsest is {level})", a.level)
        } else {
            String::new()
        }
    ));
    Ok(())
}
