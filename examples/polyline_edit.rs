//! Bendels & Klein editing of a polyline or polygon from the command line
//! (`edit::bendels_klein::polyline`).
//!
//! ```text
//! cargo run --release --example polyline_edit -- IN.txt OUT.txt \
//!     --handle 4..8 --fixed 0..2,10..13 [--translate dx,dy[,dz]] [--rotate DEG] \
//!     [--axis x,y,z] [--scale S] [--pivot x,y[,z]] [--distance arc|euclidean] \
//!     [--shape smoothstep|linear|c2|curve:x,y;…] [--refine LEN] [--svg OUT.svg]
//! ```
//!
//! **File format** (input and output): one point per line, 2 or 3 numbers separated by
//! spaces or commas (the same count on every line); blank lines and lines starting with
//! `#` are ignored; a line `closed` makes the curve a closed polygon. `IN` may be
//! `sample:N`, a generated wavy open polyline of `N` 2-D points (the curve of the paper's
//! Fig. 2 for `N = 14`).
//!
//! Regions are index spans `FIRST..LAST` (inclusive; on a closed polygon `LAST < FIRST`
//! wraps around), comma-separated, or picks: `--pick-handle "x,y x,y"` takes the span
//! between the points nearest to the two positions (likewise `--pick-fixed`, repeatable).
//! The handle moves by `T(pivot + translate) · R(rotate about axis) · S(scale) ·
//! T(−pivot)`, the pivot being the handle's centroid unless given; in 2-D the rotation is
//! about the pivot in the plane. `--refine LEN` inserts points where the edit stretched
//! deformable segments beyond `LEN`. `--svg` (2-D) draws the original (grey), the edited
//! curve (black), handle points (orange) and fixed points (blue). Prints one JSON line
//! with timings and counts; errors go to stderr.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use edit::bendels_klein::polyline::{
    CurveDistance, CurveRegions, Polyline, PolylineOptions, PolylineSession, Span,
};
use edit::bendels_klein::{
    BlendPoint, CurveOptions, RefineOptions, Role, ShapeCurve, ShapeFunction,
};
use glam::{DMat3, DMat4, DVec2, DVec3};

#[derive(Parser, Debug)]
#[command(about = "Bendels & Klein polyline editing: move a part, keep another, blend between")]
struct Args {
    /// Input polyline (text format, see the docs), or `sample:N`.
    input: String,
    /// Output polyline (same format).
    output: PathBuf,
    /// Handle spans "FIRST..LAST,…".
    #[arg(long)]
    handle: Option<String>,
    /// Fixed spans "FIRST..LAST,…".
    #[arg(long)]
    fixed: Option<String>,
    /// Handle by two picked positions "x,y x,y" (nearest points).
    #[arg(long)]
    pick_handle: Option<String>,
    /// Fixed part by two picked positions "x,y x,y" (repeatable).
    #[arg(long)]
    pick_fixed: Vec<String>,
    /// Translation "dx,dy" (2-D) or "dx,dy,dz" (3-D).
    #[arg(long, default_value = "0,0,0", allow_hyphen_values = true)]
    translate: String,
    /// Rotation in degrees about the pivot.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    rotate: f64,
    /// Rotation axis "x,y,z" (3-D only).
    #[arg(long, default_value = "0,0,1", allow_hyphen_values = true)]
    axis: String,
    /// Uniform scale about the pivot.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    scale: f64,
    /// Pivot "x,y[,z]". Default: the handle's centroid.
    #[arg(long, allow_hyphen_values = true)]
    pivot: Option<String>,
    /// Distances: arc (along the curve) or euclidean.
    #[arg(long, default_value = "arc")]
    distance: String,
    /// Shape function: smoothstep (c1), linear, c2 (smootherstep) or curve:x,y;x,y….
    #[arg(long, default_value = "smoothstep")]
    shape: String,
    /// Refine: split deformable segments longer than this after the edit (0: never).
    #[arg(long, default_value_t = 0.0)]
    refine: f64,
    /// Also write an SVG picture of the edit (2-D).
    #[arg(long)]
    svg: Option<PathBuf>,
}

type Error = Box<dyn std::error::Error>;

fn parse_numbers(s: &str) -> Result<Vec<f64>, String> {
    s.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<f64>()
                .map_err(|e| format!("{t:?}: {e}"))
                .and_then(|x| {
                    x.is_finite()
                        .then_some(x)
                        .ok_or_else(|| format!("{t:?} is not finite"))
                })
        })
        .collect()
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
                .map(|p| match parse_numbers(p)?[..] {
                    [x, y] => Ok((x, y)),
                    _ => Err(format!("expected x,y in the curve, got {p:?}")),
                })
                .collect::<Result<_, String>>()?;
            ShapeFunction::Curve(
                ShapeCurve::new(&points, CurveOptions::default()).map_err(|e| e.to_string())?,
            )
        }
    })
}

fn parse_spans(s: &str) -> Result<Vec<Span>, String> {
    s.split(',')
        .filter(|t| !t.trim().is_empty())
        .map(|t| {
            let t = t.trim();
            let parse = |x: &str| {
                x.trim()
                    .parse::<usize>()
                    .map_err(|e| format!("span {t:?}: {e}"))
            };
            match t.split_once("..") {
                Some((a, b)) => Ok(Span::new(parse(a)?, parse(b)?)),
                None => parse(t).map(Span::single),
            }
        })
        .collect()
}

/// The points (each 2 or 3 numbers) and whether the curve is closed.
fn read_input(input: &str) -> Result<(Vec<Vec<f64>>, bool), Error> {
    if let Some(n) = input.strip_prefix("sample:") {
        let n: usize = n.trim().parse()?;
        let points = (0..n)
            .map(|i| {
                let x = i as f64 * 13.0 / (n.max(2) - 1) as f64;
                vec![x, 0.3 * (0.9 * x).sin()]
            })
            .collect();
        return Ok((points, false));
    }
    let text = std::fs::read_to_string(input).map_err(|e| format!("{input}: {e}"))?;
    let mut closed = false;
    let mut points = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        if line == "closed" {
            closed = true;
            continue;
        }
        let p = parse_numbers(line).map_err(|e| format!("{input}:{}: {e}", number + 1))?;
        if p.len() != 2 && p.len() != 3 {
            return Err(format!("{input}:{}: expected 2 or 3 numbers", number + 1).into());
        }
        if points
            .first()
            .is_some_and(|q: &Vec<f64>| q.len() != p.len())
        {
            return Err(format!("{input}:{}: mixed 2-D and 3-D points", number + 1).into());
        }
        points.push(p);
    }
    Ok((points, closed))
}

/// What the generic edit needs from the dimension.
trait Dim: BlendPoint {
    fn from_numbers(v: &[f64]) -> Result<Self, String>;
    fn numbers(self) -> Vec<f64>;
    fn transform(args: &Args, pivot: Self) -> Result<Self::Affine, String>;
    fn centroid(points: &[Self]) -> Self;
}

impl Dim for DVec2 {
    fn from_numbers(v: &[f64]) -> Result<Self, String> {
        match v {
            [x, y] | [x, y, _] => Ok(DVec2::new(*x, *y)),
            _ => Err(format!("expected x,y, got {v:?}")),
        }
    }
    fn numbers(self) -> Vec<f64> {
        vec![self.x, self.y]
    }
    fn transform(args: &Args, pivot: Self) -> Result<DMat3, String> {
        let t = Self::from_numbers(&parse_numbers(&args.translate)?)?;
        Ok(DMat3::from_translation(pivot + t)
            * DMat3::from_angle(args.rotate.to_radians())
            * DMat3::from_scale(DVec2::splat(args.scale))
            * DMat3::from_translation(-pivot))
    }
    fn centroid(points: &[Self]) -> Self {
        points.iter().sum::<DVec2>() / points.len().max(1) as f64
    }
}

impl Dim for DVec3 {
    fn from_numbers(v: &[f64]) -> Result<Self, String> {
        match v {
            [x, y] => Ok(DVec3::new(*x, *y, 0.0)),
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => Err(format!("expected x,y,z, got {v:?}")),
        }
    }
    fn numbers(self) -> Vec<f64> {
        vec![self.x, self.y, self.z]
    }
    fn transform(args: &Args, pivot: Self) -> Result<DMat4, String> {
        let t = Self::from_numbers(&parse_numbers(&args.translate)?)?;
        let axis = Self::from_numbers(&parse_numbers(&args.axis)?)?;
        let axis = axis
            .try_normalize()
            .ok_or_else(|| format!("the rotation axis {axis} has no direction"))?;
        Ok(DMat4::from_translation(pivot + t)
            * DMat4::from_axis_angle(axis, args.rotate.to_radians())
            * DMat4::from_scale(DVec3::splat(args.scale))
            * DMat4::from_translation(-pivot))
    }
    fn centroid(points: &[Self]) -> Self {
        points.iter().sum::<DVec3>() / points.len().max(1) as f64
    }
}

fn write_curve<P: Dim>(path: &PathBuf, points: &[P], closed: bool) -> Result<(), Error> {
    let mut text = String::from("# written by polyline_edit\n");
    if closed {
        text.push_str("closed\n");
    }
    for p in points {
        let v: Vec<String> = p.numbers().iter().map(|x| x.to_string()).collect();
        text.push_str(&v.join(" "));
        text.push('\n');
    }
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}

fn write_svg(
    path: &PathBuf,
    before: &[DVec2],
    after: &[DVec2],
    roles: &[Role],
    closed: bool,
) -> Result<(), Error> {
    let all = before.iter().chain(after);
    let lo = all
        .clone()
        .fold(DVec2::splat(f64::INFINITY), |a, &b| a.min(b));
    let hi = all.fold(DVec2::splat(f64::NEG_INFINITY), |a, &b| a.max(b));
    let size = (hi - lo).max(DVec2::splat(1e-9));
    let scale = 560.0 / size.x.max(size.y);
    let margin = 20.0;
    // y up in the data, down in SVG.
    let map = |p: DVec2| DVec2::new(margin + (p.x - lo.x) * scale, margin + (hi.y - p.y) * scale);
    let (w, h) = (size.x * scale + 2.0 * margin, size.y * scale + 2.0 * margin);
    let path_of = |points: &[DVec2]| {
        let mut d: Vec<String> = points
            .iter()
            .map(|&p| {
                let q = map(p);
                format!("{:.2},{:.2}", q.x, q.y)
            })
            .collect();
        if closed {
            d.push(d[0].clone());
        }
        d.join(" ")
    };
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <polyline points=\"{}\" fill=\"none\" stroke=\"#aaa\" stroke-width=\"1.5\" stroke-dasharray=\"4 3\"/>\n\
         <polyline points=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"1.5\"/>\n",
        path_of(before),
        path_of(after)
    );
    for (&p, role) in after.iter().zip(roles) {
        let colour = match role {
            Role::Handle => "#ff8c00",
            Role::Fixed => "#285aff",
            Role::Deformable => "#2a2",
        };
        let q = map(p);
        svg.push_str(&format!(
            "<circle cx=\"{:.2}\" cy=\"{:.2}\" r=\"2.5\" fill=\"{colour}\"/>\n",
            q.x, q.y
        ));
    }
    svg.push_str("</svg>\n");
    std::fs::write(path, svg).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}

fn edit<P: Dim>(args: &Args, raw: &[Vec<f64>], closed: bool) -> Result<serde_json::Value, Error> {
    let clock = Instant::now();
    let points: Vec<P> = raw
        .iter()
        .map(|v| P::from_numbers(v))
        .collect::<Result<_, _>>()?;
    let curve = Polyline::new(points, closed)?;
    let pick = |s: &str| -> Result<Span, Error> {
        let v = parse_numbers(s)?;
        let half = v.len() / 2;
        if v.len() % 2 != 0 || half < 2 {
            return Err(format!("a pick is two positions, got {s:?}").into());
        }
        let (a, b) = (P::from_numbers(&v[..half])?, P::from_numbers(&v[half..])?);
        Ok(Span::between(&curve, a, b)?)
    };
    let mut handle = args
        .handle
        .as_deref()
        .map(parse_spans)
        .transpose()?
        .unwrap_or_default();
    if let Some(s) = &args.pick_handle {
        handle.push(pick(s)?);
    }
    let mut fixed = args
        .fixed
        .as_deref()
        .map(parse_spans)
        .transpose()?
        .unwrap_or_default();
    for s in &args.pick_fixed {
        fixed.push(pick(s)?);
    }
    let regions = CurveRegions::from_spans(&curve, &handle, &fixed)?;
    let distance = match args.distance.as_str() {
        "arc" => CurveDistance::ArcLength,
        "euclidean" => CurveDistance::Euclidean,
        other => return Err(format!("unknown distance {other:?}: arc or euclidean").into()),
    };
    let options = PolylineOptions::default()
        .with_distance(distance)
        .with_shape(parse_shape(&args.shape)?);
    let mut session = PolylineSession::new(&curve, &regions, options)?;
    let prepare_ms = clock.elapsed().as_secs_f64() * 1e3;

    let handle_points: Vec<P> = (0..curve.len())
        .filter(|&i| regions.roles()[i] == Role::Handle)
        .map(|i| curve.points()[i])
        .collect();
    let pivot = match &args.pivot {
        Some(s) => P::from_numbers(&parse_numbers(s)?)?,
        None => P::centroid(&handle_points),
    };
    let a = P::transform(args, pivot)?;
    let clock = Instant::now();
    session.apply(a)?;
    let blend_ms = clock.elapsed().as_secs_f64() * 1e3;
    let clock = Instant::now();
    let refined = if args.refine > 0.0 {
        Some(session.refine(RefineOptions::new(args.refine))?)
    } else {
        None
    };
    let refine_ms = clock.elapsed().as_secs_f64() * 1e3;
    write_curve(&args.output, session.points(), closed)?;
    if let Some(svg) = &args.svg {
        let flat = |ps: &[P]| -> Vec<DVec2> {
            ps.iter()
                .map(|p| {
                    let v = p.to_space();
                    DVec2::new(v.x, v.y)
                })
                .collect()
        };
        write_svg(
            svg,
            &flat(session.original_points()),
            &flat(session.points()),
            session.roles(),
            closed,
        )?;
    }
    let count = |role| session.roles().iter().filter(|&&r| r == role).count();
    Ok(serde_json::json!({
        "input": args.input,
        "output": args.output,
        "dimension": raw.first().map_or(2, Vec::len),
        "closed": closed,
        "points_in": curve.len(),
        "points_out": session.points().len(),
        "handle": count(Role::Handle),
        "fixed": count(Role::Fixed),
        "deformable": count(Role::Deformable),
        "inserted": refined.map_or(0, |r| r.new_vertices),
        "prepare_ms": prepare_ms,
        "blend_ms": blend_ms,
        "refine_ms": refine_ms,
    }))
}

fn run() -> Result<(), Error> {
    let args = Args::parse();
    if !(args.scale.is_finite() && args.scale > 0.0 && args.rotate.is_finite()) {
        return Err(format!(
            "--scale must be positive and --rotate finite, got {} and {}",
            args.scale, args.rotate
        )
        .into());
    }
    let (raw, closed) = read_input(&args.input)?;
    let report = if raw.first().is_some_and(|p| p.len() == 3) {
        edit::<DVec3>(&args, &raw, closed)?
    } else {
        edit::<DVec2>(&args, &raw, closed)?
    };
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
