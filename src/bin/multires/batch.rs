//! `multires batch`: a recipe (or the workflow) over a corpus (see `multires::batch`).

use halfedge::hierarchy::Method;
use multires::batch::{self, BatchOptions};
use multires::recipe::Recipe;
use multires::workflow::WorkflowOptions;
use serde_json::json;

use crate::args::BatchArgs;
use crate::output::Output;

pub fn run(a: BatchArgs, out: &Output) -> multires::Result<()> {
    let recipe = a.recipe.as_deref().map(Recipe::read).transpose()?;
    let shard = a.shard.as_deref().map(batch::parse_shard).transpose()?;
    let all = batch::collect_inputs(&a.inputs)?;
    let total = all.len();
    let inputs = match shard {
        Some((i, n)) => batch::shard(all, i, n),
        None => all,
    };
    let mut options = BatchOptions::new(&a.out).with_format(&a.format);
    if let Some(recipe) = recipe {
        options = options.with_recipe(recipe);
    }
    if let Some(jobs) = a.jobs {
        options = options.with_jobs(jobs);
    }
    options.workflow = WorkflowOptions::default().with_method(Method::Rounds);
    options.picture = a.picture;
    options.weld = a.weld.weld;
    options.shard = shard;
    let mut bars = out.bars(inputs.len() > 1);
    let (rows, summary) = batch::run(&inputs, &options, &mut bars)?;
    out.json(json!({
        "out": a.out.display().to_string(),
        "corpus": total,
        "summary": summary,
        "report": a.out.join("report.jsonl").display().to_string(),
    }));
    let mut text = format!(
        "{} meshes{}: {} ok, {} skipped (up to date), {} errors in {:.3} s; report in {}",
        summary.meshes,
        summary.shard.as_ref().map_or(String::new(), |s| format!(
            " (shard {s} of a corpus of {total})"
        )),
        summary.ok,
        summary.skipped,
        summary.errors,
        summary.seconds,
        a.out.join("report.jsonl").display()
    );
    let failures: Vec<String> = rows
        .iter()
        .filter(|r| r.status == "error")
        .map(|row| {
            let error = row.error.as_deref().unwrap_or("?");
            if error.starts_with(&row.input) {
                error.to_owned()
            } else {
                format!("{}: {error}", row.input)
            }
        })
        .collect();
    for failure in &failures {
        text += &format!("\n  error: {failure}");
    }
    out.text(text);
    if let Some(first) = failures.into_iter().next() {
        return Err(multires::Error::BatchFailures {
            first,
            failed: summary.errors,
            meshes: summary.meshes,
            report: a.out.join("report.jsonl"),
        });
    }
    Ok(())
}
