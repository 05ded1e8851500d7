//! Bendels & Klein on pictures and polylines (issue 16): one drag of a 1-megapixel RGB
//! image (blend of the grid + resampling), preparing its distance fields, and one drag
//! of a 100,000-point polyline, each beside a reference in the same group:
//!
//! - `image_drag`: `drag_1MP_rgb` (`ImageSession::apply` + `render_into`, grid step 4)
//!   against `global_affine_warp_1MP_rgb`, a plain inverse affine warp of the whole
//!   picture with bilinear sampling (no grid, no regions): the least any resampling of
//!   every pixel costs.
//! - `image_prepare`: `session_new_1MP` (region checks and both exact distance fields
//!   at the grid vertices) against `full_edt_1MP`, one exact distance transform of one
//!   mask over every pixel.
//! - `polyline_drag`: `drag_100k_points` (`PolylineSession::apply`) against
//!   `affine_100k_points`, the handle's transform applied to every point (the cost of
//!   moving the whole curve rigidly).
//!
//! `cargo bench --bench image_blend`. Each group also prints the CPU time per run on
//! stderr (`[cpu]`), which on a loaded machine is nearer to what an idle one shows.

use std::hint::black_box;
use std::sync::Mutex;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, Criterion};
use edit::bendels_klein::image::{edt, test_pattern, ImageOptions, ImageSession, Mask, Raster};
use edit::bendels_klein::polyline::{
    CurveRegions, Polyline, PolylineOptions, PolylineSession, Span,
};
use glam::{DMat3, DVec2};
use rayon::prelude::*;

/// CPU time of all threads of this process in ns (Linux `schedstat`; 0 elsewhere).
fn process_cpu_ns() -> u64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0;
    };
    tasks
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum()
}

/// Runs `f` `iterations` times once per label and prints wall and CPU time per run.
fn cpu_report<T>(label: &str, iterations: u32, mut f: impl FnMut() -> T) {
    static DONE: Mutex<Vec<String>> = Mutex::new(Vec::new());
    {
        let mut done = DONE.lock().unwrap();
        if done.iter().any(|l| l == label) {
            return;
        }
        done.push(label.to_owned());
    }
    let (c0, w0) = (process_cpu_ns(), Instant::now());
    for _ in 0..iterations {
        black_box(f());
    }
    let wall = w0.elapsed().as_secs_f64() * 1e3 / f64::from(iterations);
    let cpu = (process_cpu_ns() - c0) as f64 / 1e6 / f64::from(iterations);
    eprintln!("[cpu] {label}: wall {wall:.2} ms, cpu {cpu:.2} ms per run");
}

const SIDE: u32 = 1000;

fn circle(centre: DVec2, radius: f64, n: usize) -> Vec<DVec2> {
    (0..n)
        .map(|k| {
            let t = k as f64 / n as f64 * std::f64::consts::TAU;
            centre + radius * DVec2::new(t.cos(), t.sin())
        })
        .collect()
}

/// The 1000² test picture, a round handle of radius 180 in the middle, the border fixed:
/// every pixel but the border is resampled by a drag.
fn masks() -> (Raster, Mask, Mask) {
    let image = test_pattern(SIDE, SIDE).expect("picture");
    let centre = DVec2::splat(499.5);
    let handle = Mask::polygon(SIDE, SIDE, &circle(centre, 180.0, 64)).expect("handle");
    let fixed = Mask::border(SIDE, SIDE, 1).expect("fixed");
    (image, handle, fixed)
}

fn drag() -> DMat3 {
    let centre = DVec2::splat(499.5);
    DMat3::from_translation(centre + DVec2::new(40.0, -25.0))
        * DMat3::from_angle(0.3)
        * DMat3::from_translation(-centre)
}

/// Inverse affine warp of an RGB picture with bilinear sampling, rows in parallel.
fn global_warp(source: &Raster, inverse: DMat3, out: &mut Raster) {
    let (w, h) = (source.width() as usize, source.height() as usize);
    let src = source.data();
    out.data_mut()
        .par_chunks_mut(w * 3)
        .enumerate()
        .for_each(|(y, row)| {
            for x in 0..w {
                let q = inverse.transform_point2(DVec2::new(x as f64, y as f64));
                let qx = q.x.clamp(0.0, (w - 1) as f64);
                let qy = q.y.clamp(0.0, (h - 1) as f64);
                let (x0, y0) = ((qx as usize).min(w - 2), (qy as usize).min(h - 2));
                let (fx, fy) = ((qx - x0 as f64) as f32, (qy - y0 as f64) as f32);
                let i = (y0 * w + x0) * 3;
                for k in 0..3 {
                    let p = |j: usize| f32::from(src[j + k]);
                    let top = p(i) + fx * (p(i + 3) - p(i));
                    let bottom = p(i + w * 3) + fx * (p(i + w * 3 + 3) - p(i + w * 3));
                    row[x * 3 + k] = (top + fy * (bottom - top) + 0.5) as u8;
                }
            }
        });
}

fn image_drag(c: &mut Criterion) {
    let mut group = c.benchmark_group("image_drag");
    group.sample_size(20);
    let (image, handle, fixed) = masks();
    let mut session =
        ImageSession::new(image.clone(), handle, fixed, ImageOptions::default()).expect("session");
    let mut out = image.clone();
    let a = drag();
    group.bench_function("drag_1MP_rgb", |b| {
        cpu_report("image drag (blend + resample), 1 MP RGB", 10, || {
            session.apply(a).unwrap();
            session.render_into(&mut out).unwrap()
        });
        b.iter(|| {
            session.apply(black_box(a)).unwrap();
            black_box(session.render_into(&mut out).unwrap())
        })
    });
    let inverse = a.inverse();
    group.bench_function("global_affine_warp_1MP_rgb", |b| {
        cpu_report("global affine warp, 1 MP RGB", 10, || {
            global_warp(&image, inverse, &mut out)
        });
        b.iter(|| global_warp(black_box(&image), inverse, &mut out))
    });
    group.finish();
}

fn image_prepare(c: &mut Criterion) {
    let mut group = c.benchmark_group("image_prepare");
    group.sample_size(20);
    let (image, handle, fixed) = masks();
    group.bench_function("session_new_1MP", |b| {
        cpu_report(
            "image session (regions + distance fields), 1 MP",
            10,
            || {
                ImageSession::new(
                    image.clone(),
                    handle.clone(),
                    fixed.clone(),
                    ImageOptions::default(),
                )
                .unwrap()
            },
        );
        b.iter(|| {
            ImageSession::new(
                black_box(image.clone()),
                handle.clone(),
                fixed.clone(),
                ImageOptions::default(),
            )
            .unwrap()
        })
    });
    group.bench_function("full_edt_1MP", |b| {
        cpu_report("full exact EDT of one mask, 1 MP", 10, || {
            edt::squared_distance_transform(&handle)
        });
        b.iter(|| edt::squared_distance_transform(black_box(&handle)))
    });
    group.finish();
}

fn polyline_drag(c: &mut Criterion) {
    let mut group = c.benchmark_group("polyline_drag");
    group.sample_size(50);
    let n = 100_000;
    let points: Vec<DVec2> = (0..n)
        .map(|i| {
            let x = i as f64 * 0.01;
            DVec2::new(x, (0.37 * x).sin() * 3.0)
        })
        .collect();
    let curve = Polyline::open(points.clone()).expect("curve");
    // Fixed ends, a handle in the middle, 80,000 deformable points.
    let regions = CurveRegions::from_spans(
        &curve,
        &[Span::new(45_000, 54_999)],
        &[Span::new(0, 4_999), Span::new(95_000, n - 1)],
    )
    .expect("regions");
    let mut session =
        PolylineSession::new(&curve, &regions, PolylineOptions::default()).expect("session");
    let a = DMat3::from_translation(DVec2::new(12.0, 30.0)) * DMat3::from_angle(0.4);
    group.bench_function("drag_100k_points", |b| {
        cpu_report("polyline drag, 100 k points", 50, || {
            session.apply(a).unwrap()
        });
        b.iter(|| session.apply(black_box(a)).unwrap())
    });
    let mut moved = points.clone();
    group.bench_function("affine_100k_points", |b| {
        b.iter(|| {
            for (m, &p) in moved.iter_mut().zip(&points) {
                *m = black_box(a).transform_point2(p);
            }
        })
    });
    group.finish();
}

criterion_group!(benches, image_drag, image_prepare, polyline_drag);
criterion_main!(benches);
