//! `multires distance`: how far apart two meshes' surfaces are
//! (`halfedge::surface_distance`).

use std::time::Instant;

use halfedge::surface_distance::{surface_distance, OneSided, Sampling};
use multires::load;
use serde_json::json;

use crate::args::DistanceArgs;
use crate::output::Output;

/// One side's figures, absolute and over the diagonal.
fn side_json(side: &OneSided, diagonal: f64) -> serde_json::Value {
    let relative = |x: f64| if diagonal > 0.0 { x / diagonal } else { 0.0 };
    json!({
        "samples": side.samples,
        "mean": side.mean,
        "rms": side.rms,
        "max": side.max,
        "mean_over_diagonal": relative(side.mean),
        "rms_over_diagonal": relative(side.rms),
        "max_over_diagonal": relative(side.max),
    })
}

pub fn run(a: DistanceArgs, out: &Output) -> multires::Result<()> {
    let clock = Instant::now();
    let large = load::is_large_file(&a.first) || load::is_large_file(&a.second);
    let mut bars = out.bars(large);
    let first = load::load(&a.first, a.weld.weld, &mut bars)?.mesh;
    let second = load::load(&a.second, a.weld.weld, &mut bars)?.mesh;
    let load_seconds = clock.elapsed().as_secs_f64();
    let sampling = Sampling {
        vertices: !a.no_vertices,
        face_samples: a.samples,
    };
    let clock = Instant::now();
    let d = multires::progress::step(&mut bars, "measuring", || {
        surface_distance(&first, &second, &sampling)
    })?;
    let seconds = clock.elapsed().as_secs_f64();
    let relative = |x: f64| {
        if d.diagonal > 0.0 {
            x / d.diagonal
        } else {
            0.0
        }
    };
    out.json(json!({
        "first": a.first.display().to_string(),
        "second": a.second.display().to_string(),
        "diagonal": d.diagonal,
        "first_to_second": side_json(&d.forward, d.diagonal),
        "second_to_first": side_json(&d.backward, d.diagonal),
        "mean": d.mean(),
        "hausdorff": d.hausdorff(),
        "mean_over_diagonal": relative(d.mean()),
        "hausdorff_over_diagonal": relative(d.hausdorff()),
        "load_seconds": load_seconds,
        "seconds": seconds,
    }));
    out.text(format!(
        "{} <-> {}: Hausdorff {:.6e} ({:.4e} of the diagonal {:.6e}), mean {:.6e} ({:.4e})\n  \
         first -> second: mean {:.6e}, rms {:.6e}, max {:.6e} over {} samples\n  \
         second -> first: mean {:.6e}, rms {:.6e}, max {:.6e} over {} samples",
        a.first.display(),
        a.second.display(),
        d.hausdorff(),
        relative(d.hausdorff()),
        d.diagonal,
        d.mean(),
        relative(d.mean()),
        d.forward.mean,
        d.forward.rms,
        d.forward.max,
        d.forward.samples,
        d.backward.mean,
        d.backward.rms,
        d.backward.max,
        d.backward.samples,
    ));
    Ok(())
}
