//! `multires workflow`: the whole job (see `multires::workflow`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use halfedge::hierarchy::Method;
use multires::load;
use multires::workflow::{self, WorkflowOptions};
use serde_json::json;

use crate::args::WorkflowArgs;
use crate::output::Output;

pub fn run(a: WorkflowArgs, out: &Output) -> multires::Result<()> {
    let path = a
        .mesh
        .clone()
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("data/blob.obj"));
    let options = WorkflowOptions::default()
        .with_level(a.level)
        .with_method(if a.method == "qem" {
            Method::Qem
        } else {
            Method::Rounds
        })
        .with_plane(a.axis, a.plane)
        .with_skipped(&a.skip)?;
    let clock = Instant::now();
    let mut bars = out.bars(load::is_large_file(&path));
    let loaded = load::load(&path, a.weld.weld, &mut bars)?;
    bars.set_shown(
        multires::progress::LARGE_FACES < loaded.mesh.n_faces() && !out.quiet && !out.json,
    );
    let load_seconds = clock.elapsed().as_secs_f64();
    let mut done = workflow::run_timed(loaded, &path, &options, &mut bars, load_seconds)?;
    let written: PathBuf = done.write(&a.out, &a.format, a.picture, &mut bars)?;
    let rows: Vec<_> = done
        .rows
        .iter()
        .map(|r| {
            json!({"step": r.step, "detail": r.detail, "seconds": r.seconds,
                   "peak_bytes": r.peak_bytes})
        })
        .collect();
    let seconds = |step: &str| {
        done.rows
            .iter()
            .find(|r| r.step == step)
            .map_or(0.0, |r| r.seconds)
    };
    out.json(json!({
        "input": path.display().to_string(),
        "output": written.display().to_string(),
        "level": done.level,
        "vertices": done.result.n_vertices(),
        "faces": done.result.n_faces(),
        "steps": rows,
        "notes": done.notes,
        "load_seconds": seconds("load"),
        "build_seconds": done.build_seconds,
        "refine_seconds": seconds("refine"),
        "write_seconds": seconds("write"),
        "total_seconds": done.rows.iter().map(|r| r.seconds).sum::<f64>(),
        "peak_bytes": done.peak_bytes(),
    }));
    if !out.json {
        print!("{}", done.table());
    }
    Ok(())
}
