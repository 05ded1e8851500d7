//! Deforms a mesh with the methods of issue 6 and writes the result as OBJ:
//! a Barr twist and taper along the mesh's longest axis, then Taubin smoothing, then a
//! shape/height-surface FFD bend; prints what each step cost. A triangle soup or a mesh
//! with seams is welded first (`--weld`, as in the workflow: smoothing would otherwise
//! pull the copies of a seam's vertices apart).
//!
//! ```text
//! cargo run --release --example deform -- data/creature.obj --out creature-deformed.obj
//! ```

use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;

use edit::deform::{
    apply_deformer, taubin, AttachOptions, Ffd, LatticeFrame, Profile, SmoothingWeights, Taper,
    TaubinOptions, Twist,
};
use edit::Vertices;
use glam::DVec3;
use multires::load::{self, Weld, WELD_HELP};
use multires::progress::{Bars, Progress, LARGE_FACES};

/// Twist, taper, smooth and bend a mesh.
#[derive(Parser)]
struct Args {
    /// The mesh to deform (OBJ or PLY).
    mesh: PathBuf,
    /// Where to write the result (OBJ or PLY, by extension).
    #[arg(long, default_value = "deformed.obj")]
    out: PathBuf,
    /// Twist angle over the mesh's length, in degrees.
    #[arg(long, default_value_t = 90.0)]
    twist: f64,
    /// Taper factor at the far end of the mesh.
    #[arg(long, default_value_t = 0.5)]
    taper: f64,
    /// Taubin λ|μ iterations.
    #[arg(long, default_value_t = 10)]
    smooth: usize,
    /// FFD bend angle in degrees.
    #[arg(long, default_value_t = 45.0)]
    bend: f64,
    #[arg(long, default_value = "auto", value_parser = |s: &str| s.parse::<Weld>(), help = WELD_HELP)]
    weld: Weld,
}

/// Runs a step, under a spinner when `bars` are shown (large meshes), and prints its time.
fn timed<T>(bars: &mut Bars, what: &str, f: impl FnOnce() -> T) -> T {
    bars.start(what, None);
    let start = Instant::now();
    let result = f();
    bars.finish();
    println!(
        "{what:<40} {:>10.2} ms",
        start.elapsed().as_secs_f64() * 1e3
    );
    result
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> Result<(), Box<dyn std::error::Error>> {
    let mut bars = Bars::new(load::is_large_file(&args.mesh));
    let (mesh, report) = timed(&mut bars, "read", || halfedge::io::read(&args.mesh))?;
    bars.set_shown(mesh.n_faces() > LARGE_FACES);
    let load::Loaded {
        mut mesh, welding, ..
    } = load::apply_weld(mesh, report, args.weld, &mut bars)?;
    println!(
        "{}: {} vertices, {} faces",
        args.mesh.display(),
        mesh.n_vertices(),
        mesh.n_faces()
    );
    if let Some(welding) = welding {
        println!("note: {}", welding.note);
    }
    let (lo, hi) = mesh.bounding_box().ok_or("the mesh is empty")?;
    let extent = hi - lo;
    let longest = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let axis = DVec3::AXES[longest];
    let centre = 0.5 * (lo + hi);
    let half = 0.5 * extent[longest];

    let twist = Twist::linear(centre, axis, -half, half, args.twist.to_radians())?;
    timed(&mut bars, "Barr twist", || {
        apply_deformer(&mut mesh, &twist, Vertices::All)
    })?;
    let taper = Taper::new(centre, axis, Profile::local(-half, half, 1.0, args.taper)?)?;
    timed(&mut bars, "Barr taper", || {
        apply_deformer(&mut mesh, &taper, Vertices::All)
    })?;
    let options = TaubinOptions::default().with_weights(SmoothingWeights::Cotangent);
    timed(
        &mut bars,
        &format!("Taubin, {} iterations", args.smooth),
        || taubin(&mut mesh, Vertices::All, &options, args.smooth),
    )?;

    // the FFD's shape surface lies under the mesh, its u direction along the longest axis
    let up = DVec3::AXES[(longest + 1) % 3];
    let frame = LatticeFrame::new(lo.dot(up) * up, axis, up)?;
    let mut ffd = timed(&mut bars, "FFD attach", || {
        Ffd::covering(
            &mesh,
            Vertices::All,
            frame,
            ([3, 3], [8, 4]),
            ([3, 3], [8, 4]),
            0.05,
            AttachOptions::default(),
        )
    })?;
    ffd.bend(args.bend.to_radians())?;
    timed(&mut bars, "FFD deform (bend)", || ffd.deform(&mut mesh))?;

    mesh.check()?;
    timed(&mut bars, "write", || halfedge::io::write(&args.out, &mesh))?;
    println!("wrote {}", args.out.display());
    Ok(())
}
