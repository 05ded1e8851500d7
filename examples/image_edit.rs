//! Bendels & Klein editing of a picture from the command line (`edit::bendels_klein::image`).
//!
//! ```text
//! cargo run --release --example image_edit -- IN.png OUT.png \
//!     --handle "120,90 200,90 200,170 120,170" [--fixed "x,y x,y …"] \
//!     [--translate dx,dy] [--rotate DEG] [--scale S] [--pivot x,y] \
//!     [--shape smoothstep|linear|c2|curve:x,y;x,y…] [--grid-step 4] [--overlay BEFORE.png]
//! ```
//!
//! Pixel coordinates, origin at the top-left corner, `y` down. `--handle` is the polygon
//! around the part that moves rigidly; everything outside the `--fixed` polygon stays
//! (without it, the image border stays). The handle moves by
//! `T(pivot + translate) · R(rotate) · S(scale) · T(−pivot)` (pivot: the handle polygon's
//! centroid unless given; a positive angle turns clockwise on screen, since `y` points
//! down). `IN.png` may be `pattern:WxH`, the procedurally drawn test picture
//! (`edit::bendels_klein::image::test_pattern`). `--overlay` writes the input with the handle
//! (orange) and fixed (blue) polygons drawn on it. A 16-bit PNG is edited and written at
//! 16 bits (`edit::bendels_klein::image::Picture::read_png`). Prints one JSON line with timings and
//! counts (`bits`: 8 or 16); errors go to stderr.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use edit::bendels_klein::image::{
    test_pattern, ImageOptions, ImageSessionOf, Mask, Picture, Raster, RasterOf, Sample,
};
use edit::bendels_klein::{CurveOptions, ShapeCurve, ShapeFunction};
use glam::{DMat3, DVec2};

#[derive(Parser, Debug)]
#[command(about = "Bendels & Klein image editing: move a region, keep another, blend between")]
struct Args {
    /// Input PNG, or `pattern:WxH` for the generated test picture.
    input: String,
    /// Output PNG.
    output: PathBuf,
    /// Handle polygon, "x,y x,y …" (at least 3 points).
    #[arg(long)]
    handle: String,
    /// Fixed border polygon: everything outside it stays. Default: the image border.
    #[arg(long)]
    fixed: Option<String>,
    /// Handle mask PNG (non-zero first channel = handle), instead of `--handle`'s polygon.
    #[arg(long)]
    handle_mask: Option<PathBuf>,
    /// Fixed mask PNG (non-zero first channel = fixed), added to the fixed region.
    #[arg(long)]
    fixed_mask: Option<PathBuf>,
    /// Translation "dx,dy" in pixels.
    #[arg(long, default_value = "0,0", allow_hyphen_values = true)]
    translate: String,
    /// Rotation in degrees (clockwise on screen).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    rotate: f64,
    /// Uniform scale.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    scale: f64,
    /// Centre of rotation and scale "x,y". Default: the handle polygon's centroid.
    #[arg(long)]
    pivot: Option<String>,
    /// Shape function: smoothstep (c1), linear, c2 (smootherstep) or curve:x,y;x,y….
    #[arg(long, default_value = "smoothstep")]
    shape: String,
    /// Pixels between grid vertices.
    #[arg(long, default_value_t = 4)]
    grid_step: u32,
    /// Also write the input with the region polygons drawn on it.
    #[arg(long)]
    overlay: Option<PathBuf>,
}

fn parse_pair(s: &str) -> Result<DVec2, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>().map_err(|e| format!("{x:?}: {e}")))
        .collect::<Result<_, _>>()?;
    match v[..] {
        [x, y] if x.is_finite() && y.is_finite() => Ok(DVec2::new(x, y)),
        _ => Err(format!("expected two finite numbers \"x,y\", got {s:?}")),
    }
}

fn parse_polygon(s: &str) -> Result<Vec<DVec2>, String> {
    s.split_whitespace().map(parse_pair).collect()
}

fn parse_shape(s: &str) -> Result<ShapeFunction, String> {
    Ok(match s {
        "smoothstep" | "c1" => ShapeFunction::Smoothstep,
        "linear" => ShapeFunction::Linear,
        "c2" | "smootherstep" => ShapeFunction::Smootherstep,
        _ => {
            let points = s.strip_prefix("curve:").ok_or_else(|| {
                format!("unknown shape {s:?}: smoothstep, linear, c2 or curve:x,y;…")
            })?;
            let points: Vec<(f64, f64)> = points
                .split(';')
                .filter(|p| !p.trim().is_empty())
                .map(|p| parse_pair(p).map(|v| (v.x, v.y)))
                .collect::<Result<_, _>>()?;
            ShapeFunction::Curve(
                ShapeCurve::new(&points, CurveOptions::default()).map_err(|e| e.to_string())?,
            )
        }
    })
}

/// The input picture at its own depth (8 or 16 bits per channel).
fn read_input(input: &str) -> Result<Picture, Box<dyn std::error::Error>> {
    if let Some(size) = input.strip_prefix("pattern:") {
        let (w, h) = size
            .split_once('x')
            .ok_or_else(|| format!("expected pattern:WxH, got {input:?}"))?;
        return Ok(Picture::Eight(test_pattern(
            w.trim().parse()?,
            h.trim().parse()?,
        )?));
    }
    Ok(Picture::read_png(input)?)
}

/// Draws the closed polygon in `colour` (8-bit values of its first channels, scaled to
/// the picture's depth) one pixel wide.
fn draw_polygon<S: Sample>(image: &mut RasterOf<S>, polygon: &[DVec2], colour: [u8; 3]) {
    let c = image.channels() as usize;
    let colour = colour.map(|v| S::from_f32(f32::from(v) / 255.0 * S::MAX));
    let opaque = S::from_f32(S::MAX);
    let value: Vec<S> = match c {
        1 => vec![colour[1]],
        2 => vec![colour[1], opaque],
        3 => colour.to_vec(),
        _ => vec![colour[0], colour[1], colour[2], opaque],
    };
    for k in 0..polygon.len() {
        let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
        let steps = (a.distance(b).ceil() as usize).clamp(1, 100_000);
        for s in 0..=steps {
            let p = a.lerp(b, s as f64 / steps as f64).round();
            if p.x >= 0.0 && p.y >= 0.0 {
                image.set_pixel(p.x as u32, p.y as u32, &value);
            }
        }
    }
}

fn run() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let shape = parse_shape(&args.shape)?;
    let translate = parse_pair(&args.translate)?;
    if !(args.scale.is_finite() && args.scale > 0.0 && args.rotate.is_finite()) {
        return Err(format!(
            "--scale must be positive and --rotate finite, got {} and {}",
            args.scale, args.rotate
        )
        .into());
    }
    let handle_polygon = parse_polygon(&args.handle)?;
    let fixed_polygon = args.fixed.as_deref().map(parse_polygon).transpose()?;

    let clock = Instant::now();
    let picture = read_input(&args.input)?;
    let read_ms = clock.elapsed().as_secs_f64() * 1e3;
    let inputs = Inputs {
        args: &args,
        shape,
        translate,
        handle_polygon,
        fixed_polygon,
        read_ms,
    };
    // A 16-bit picture is edited and written at 16 bits.
    match picture {
        Picture::Eight(image) => edit(image, inputs),
        Picture::Sixteen(image) => edit(image, inputs),
    }
}

/// What [`edit`] needs besides the picture.
struct Inputs<'a> {
    args: &'a Args,
    shape: ShapeFunction,
    translate: DVec2,
    handle_polygon: Vec<DVec2>,
    fixed_polygon: Option<Vec<DVec2>>,
    read_ms: f64,
}

/// The edit of a picture of any depth, written at that depth, and its JSON report.
fn edit<S: Sample>(
    image: RasterOf<S>,
    inputs: Inputs<'_>,
) -> Result<(), Box<dyn std::error::Error>> {
    let Inputs {
        args,
        shape,
        translate,
        handle_polygon,
        fixed_polygon,
        read_ms,
    } = inputs;
    let (w, h) = (image.width(), image.height());

    let clock = Instant::now();
    let handle = match &args.handle_mask {
        Some(path) => Mask::from_raster(&Raster::read_png(path)?, 0),
        None => Mask::polygon(w, h, &handle_polygon)?,
    };
    let mut fixed = match &fixed_polygon {
        Some(polygon) => Mask::outside_polygon(w, h, polygon)?,
        None => Mask::border(w, h, 1)?,
    };
    if let Some(path) = &args.fixed_mask {
        fixed.union_with(&Mask::from_raster(&Raster::read_png(path)?, 0))?;
    }
    let (handle_pixels, fixed_pixels) = (handle.count(), fixed.count());
    let masks_ms = clock.elapsed().as_secs_f64() * 1e3;

    if let Some(path) = &args.overlay {
        let mut before = image.clone();
        if let Some(polygon) = &fixed_polygon {
            draw_polygon(&mut before, polygon, [40, 90, 255]);
        }
        draw_polygon(&mut before, &handle_polygon, [255, 140, 0]);
        before.write_png(path)?;
    }

    let clock = Instant::now();
    let options = ImageOptions::default()
        .with_grid_step(args.grid_step)
        .with_shape(shape);
    let mut session = ImageSessionOf::new(image, handle, fixed, options)?;
    let prepare_ms = clock.elapsed().as_secs_f64() * 1e3;

    let pivot = match &args.pivot {
        Some(p) => parse_pair(p)?,
        None => handle_polygon.iter().sum::<DVec2>() / handle_polygon.len().max(1) as f64,
    };
    let a = DMat3::from_translation(pivot + translate)
        * DMat3::from_angle(args.rotate.to_radians())
        * DMat3::from_scale(DVec2::splat(args.scale))
        * DMat3::from_translation(-pivot);
    let clock = Instant::now();
    session.apply(a)?;
    let blend_ms = clock.elapsed().as_secs_f64() * 1e3;
    let clock = Instant::now();
    let mut out = session.source().clone();
    let stats = session.render_into(&mut out)?;
    let render_ms = clock.elapsed().as_secs_f64() * 1e3;
    let clock = Instant::now();
    out.write_png(&args.output)?;
    let write_ms = clock.elapsed().as_secs_f64() * 1e3;

    let (nx, ny) = session.grid_size();
    let report = serde_json::json!({
        "input": args.input,
        "output": args.output,
        "width": w,
        "height": h,
        "channels": out.channels(),
        "bits": 8 * std::mem::size_of::<S>(),
        "grid": [nx, ny],
        "handle_pixels": handle_pixels,
        "fixed_pixels": fixed_pixels,
        "triangles_drawn": stats.triangles,
        "pixels_resampled": stats.pixels,
        "folded_triangles": session.folded_triangles(),
        "min_area_ratio": session.min_area_ratio(),
        "read_ms": read_ms,
        "masks_ms": masks_ms,
        "prepare_ms": prepare_ms,
        "blend_ms": blend_ms,
        "render_ms": render_ms,
        "write_ms": write_ms,
    });
    println!("{report}");
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
