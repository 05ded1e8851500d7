//! `multires edit`: applies a recipe to a saved hierarchy, each step at its level, and
//! saves the hierarchy with the edits.

use std::time::Instant;

use halfedge::hierarchy::Hierarchy;
use multires::progress;
use multires::recipe::{self, Recipe};
use serde_json::json;

use crate::args::EditArgs;
use crate::output::Output;

pub fn run(a: EditArgs, out: &Output) -> multires::Result<()> {
    let recipe = Recipe::read(&a.recipe)?;
    let clock = Instant::now();
    let mut bars = out.bars(multires::load::is_large_file(&a.hierarchy));
    let mut h = progress::step(&mut bars, "loading the hierarchy", || {
        Hierarchy::load(&a.hierarchy)
    })?;
    let load_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let outcomes = recipe::apply(&mut h, &recipe, &mut bars)?;
    let edit_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    progress::step(&mut bars, &format!("saving {}", a.output.display()), || {
        h.save(&a.output)
    })?;
    let write_seconds = clock.elapsed().as_secs_f64();
    let mut mesh_file = None;
    let clock = Instant::now();
    if let Some(path) = &a.mesh {
        let mut refined = h.clone();
        progress::step(&mut bars, "refining to the input", || {
            refined.go_to_level(0)
        })?;
        halfedge::io::write(path, refined.mesh())?;
        mesh_file = Some(path.display().to_string());
    }
    let mesh_seconds = clock.elapsed().as_secs_f64();
    let steps: Vec<_> = outcomes
        .iter()
        .map(|o| {
            json!({"step": o.step, "method": o.method, "level": o.level, "moved": o.moved,
                   "detail": o.detail, "seconds": o.seconds})
        })
        .collect();
    out.json(json!({
        "hierarchy": a.hierarchy.display().to_string(),
        "recipe": a.recipe.display().to_string(),
        "output": a.output.display().to_string(),
        "mesh": mesh_file,
        "steps": steps,
        "load_seconds": load_seconds,
        "edit_seconds": edit_seconds,
        "write_seconds": write_seconds,
        "mesh_seconds": mesh_seconds,
    }));
    let mut text = format!(
        "{} + {} -> {}",
        a.hierarchy.display(),
        a.recipe.display(),
        a.output.display()
    );
    for o in &outcomes {
        text += &format!(
            "\n  step {} {} at level {}: {} ({} vertices moved, {:.3} s)",
            o.step, o.method, o.level, o.detail, o.moved, o.seconds
        );
    }
    if let Some(m) = &mesh_file {
        text += &format!("\n  full resolution written to {m}");
    }
    out.text(text);
    Ok(())
}
