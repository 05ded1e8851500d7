//! Builds the progressive hierarchy of a mesh file (issue 3) and prints one JSON object:
//! `levels` (face count per level, finest first), `coarsen_seconds`, `refine_seconds` and
//! `roundtrip_identical` (refining all the way back restored every position bit for bit
//! and the same connectivity), `target_reached` and `outcome` (how the build ended, in a
//! sentence: when the rounds had to widen their bounds to reach the target, and why a
//! target was not reached). The outcome also goes to stderr when the target was missed.
//!
//! ```text
//! cargo run --release --example hierarchy -- FILE [--method rounds|qem] [--target-faces N]
//!     [--max-normal-deviation DEG] [--max-flip-angle DEG] [--max-levels N]
//!     [--max-error D] [--no-relax] [--quadric-placement] [--subdivide K] [--progress]
//! ```

use std::path::PathBuf;
use std::time::Instant;

use clap::{Parser, ValueEnum};

use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{generators, Mesh};
use multires::load;
use multires::progress::{self, Bars, Progress, LARGE_FACES};

#[derive(Clone, Copy, Debug, ValueEnum)]
enum MethodArg {
    Rounds,
    Qem,
}

/// Build a mesh's progressive hierarchy and report its levels and timings as JSON.
#[derive(Parser, Debug)]
#[command(version = version(), about)]
struct Args {
    /// Mesh file (.obj, .ply).
    file: PathBuf,
    /// Simplification method: the paper's rounds or QEM decimation.
    #[arg(long, value_enum, default_value = "rounds")]
    method: MethodArg,
    /// Stop at this many faces.
    #[arg(long, default_value_t = 2000)]
    target_faces: usize,
    /// Rounds: planarity bound in degrees (default: the library's, 60°).
    #[arg(long)]
    max_normal_deviation: Option<f64>,
    /// Largest turn of a face normal a collapse may cause, in degrees (default 45°).
    #[arg(long)]
    max_flip_angle: Option<f64>,
    /// Stop after this many levels below the input.
    #[arg(long)]
    max_levels: Option<usize>,
    /// Error bound (a distance; see `HierarchyOptions::max_error`).
    #[arg(long)]
    max_error: Option<f64>,
    /// Rounds: stop at the first stalled round, as the paper does, instead of widening
    /// the planarity and flip bounds until the target is reached.
    #[arg(long)]
    no_relax: bool,
    /// Rounds: put survivors where the quadric says (`SurvivorPlacement::Quadric`)
    /// instead of at the midpoint.
    #[arg(long)]
    quadric_placement: bool,
    /// Subdivide the input 1-to-4 this many times first (to make large meshes).
    #[arg(long, default_value_t = 0)]
    subdivide: usize,
    /// Show progress bars on stderr (on by default for meshes over 200k faces).
    #[arg(long)]
    progress: bool,
}

/// The program's version and the hierarchy file format it reads and writes.
fn version() -> &'static str {
    Box::leak(
        format!(
            "{} (hierarchy files: .mrh format {})",
            env!("CARGO_PKG_VERSION"),
            halfedge::hierarchy::file::FORMAT_VERSION
        )
        .into_boxed_str(),
    )
}

/// Connectivity and position bits of every live element, handle for handle (by index).
#[derive(PartialEq)]
struct Snapshot {
    counts: [usize; 3],
    vertices: Vec<(usize, Option<usize>, [u64; 3])>,
    halfedges: Vec<[usize; 5]>,
    faces: Vec<(Option<usize>, usize)>,
}

fn snapshot(mesh: &Mesh) -> Snapshot {
    Snapshot {
        counts: [mesh.n_vertices(), mesh.n_halfedges(), mesh.n_faces()],
        vertices: mesh
            .vertices()
            .map(|v| {
                (
                    mesh.vertex_index(v),
                    mesh.vertex_halfedge(v).map(|h| mesh.halfedge_index(h)),
                    mesh.position(v).to_array().map(f64::to_bits),
                )
            })
            .collect(),
        halfedges: mesh
            .halfedges()
            .map(|h| {
                [
                    mesh.halfedge_index(h),
                    mesh.vertex_index(mesh.to_vertex(h)),
                    mesh.halfedge_index(mesh.next(h)),
                    mesh.halfedge_index(mesh.prev(h)),
                    mesh.face(h).map_or(usize::MAX, |f| mesh.face_index(f)),
                ]
            })
            .collect(),
        faces: mesh
            .faces()
            .map(|f| {
                (
                    Some(mesh.face_index(f)),
                    mesh.halfedge_index(mesh.face_halfedge(f)),
                )
            })
            .collect(),
    }
}

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(args: &Args) -> Result<(), halfedge::Error> {
    let mut bars = Bars::new(args.progress || load::is_large_file(&args.file));
    let (mut mesh, _) = progress::step(
        &mut bars,
        &format!("loading {}", args.file.display()),
        || halfedge::io::read(&args.file),
    )?;
    for k in 1..=args.subdivide {
        bars.set_shown(args.progress || 4 * mesh.n_faces() > LARGE_FACES);
        mesh = progress::step(
            &mut bars,
            &format!("subdividing {k}/{}", args.subdivide),
            || generators::subdivide(&mesh),
        );
    }
    bars.set_shown(args.progress || mesh.n_faces() > LARGE_FACES);
    let mut options = match args.method {
        MethodArg::Rounds => HierarchyOptions::rounds(),
        MethodArg::Qem => HierarchyOptions::qem(),
    }
    .with_target_faces(args.target_faces);
    if let Some(d) = args.max_normal_deviation {
        options.max_normal_deviation = d.to_radians();
    }
    if let Some(d) = args.max_flip_angle {
        options.max_flip_angle = d.to_radians();
    }
    if let Some(n) = args.max_levels {
        options.max_levels = n;
    }
    if let Some(e) = args.max_error {
        options.max_error = e;
    }
    options.relax_when_stalled = !args.no_relax;
    if args.quadric_placement {
        options.placement = halfedge::hierarchy::SurvivorPlacement::Quadric;
    }
    let before = snapshot(&mesh);
    let input_faces = mesh.n_faces() as u64;
    bars.start("simplifying (faces removed)", Some(input_faces));
    let start = Instant::now();
    let mut hierarchy = Hierarchy::build_with_progress(mesh, &options, &mut |p| {
        bars.advance(
            (p.input_faces - p.faces) as u64,
            &format!("simplifying: {} levels", p.levels),
        );
    })?;
    let coarsen_seconds = start.elapsed().as_secs_f64();
    bars.finish();
    let outcome = hierarchy.build_outcome().clone();
    let start = Instant::now();
    progress::step(&mut bars, "refining back to the input", || {
        hierarchy.refine_to(0)
    })?;
    let refine_seconds = start.elapsed().as_secs_f64();
    let roundtrip_identical = snapshot(hierarchy.mesh()) == before;
    let report = serde_json::json!({
        "file": args.file.display().to_string(),
        "method": format!("{:?}", args.method).to_lowercase(),
        "levels": hierarchy.level_face_counts(),
        "coarsen_seconds": coarsen_seconds,
        "refine_seconds": refine_seconds,
        "roundtrip_identical": roundtrip_identical,
        "target_reached": outcome.target_reached(),
        "outcome": outcome.to_string(),
    });
    if !outcome.target_reached() {
        eprintln!("note: {outcome}");
    }
    println!("{report}");
    Ok(())
}
