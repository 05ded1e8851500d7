//! The whole multiresolution job, as `multires workflow` runs it (this example is the
//! same program, kept so that `cargo run --example workflow` still works): load →
//! simplify to a level → label a sub-mesh by a cutting plane → one edit of each family →
//! refine back → write the mesh and before/after pictures, with a summary table. The job
//! itself is the library's [`multires::workflow`], whose docs give the rules each step
//! follows.
//!
//! ```text
//! cargo run --release --example workflow -- [FILE] [--level N] [--method rounds|qem]
//!     [--axis y] [--plane 0.72] [--skip lee,blend,taper] [--weld auto|off|F] [--out DIR]
//! ```

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Parser;
use glam::DVec3;
use halfedge::hierarchy::Method;
use multires::load::{self, Weld, WELD_HELP};
use multires::progress::{Bars, LARGE_FACES};
use multires::workflow::{self, WorkflowOptions};

/// Command-line options.
#[derive(Parser, Debug)]
#[command(
    about = "simplify → edit → refine a mesh with multires (OBJ, PLY, OFF, STL; any mesh: \
             the edit regions adapt, see multires::workflow)"
)]
struct Args {
    /// Mesh to edit; default: data/blob.obj.
    mesh: Option<PathBuf>,
    /// Hierarchy level to edit at (0 = input; clamped to the coarsest).
    #[arg(long, default_value_t = 3)]
    level: usize,
    /// Simplification: the paper's rounds or QEM.
    #[arg(long, default_value = "rounds", value_parser = ["rounds", "qem"])]
    method: String,
    /// Output folder for the mesh and the pictures.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Output mesh format: obj, ply, off or stl.
    #[arg(long, default_value = "ply")]
    format: String,
    /// Axis of the cutting plane that labels the sub-mesh: the sub-mesh is the part
    /// furthest along it (x, y, z, -x, -y or -z).
    #[arg(long, default_value = "y", value_parser = multires::recipe::parse_axis)]
    axis: DVec3,
    /// Height of the cutting plane, as a fraction of the mesh's extent along the axis
    /// (it moves towards the tip when the section there cannot cut the mesh).
    #[arg(long, default_value_t = 0.72)]
    plane: f64,
    /// Steps to leave out, comma-separated: lee, blend, taper.
    #[arg(long, value_delimiter = ',', value_parser = ["lee", "blend", "taper"])]
    skip: Vec<String>,
    /// Picture size in pixels (width of one panel; height is 3/4 of it).
    #[arg(long, default_value_t = 640)]
    picture: usize,
    #[arg(long, default_value = "auto", value_parser = |s: &str| s.parse::<Weld>(), help = WELD_HELP)]
    weld: Weld,
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> multires::Result<()> {
    let path = args
        .mesh
        .clone()
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("data/blob.obj"));
    let options = WorkflowOptions::default()
        .with_level(args.level)
        .with_method(if args.method == "qem" {
            Method::Qem
        } else {
            Method::Rounds
        })
        .with_plane(args.axis, args.plane)
        .with_skipped(&args.skip)?;
    let clock = Instant::now();
    let mut bars = Bars::new(load::is_large_file(&path));
    let loaded = load::load(&path, args.weld, &mut bars)?;
    bars.set_shown(loaded.mesh.n_faces() > LARGE_FACES);
    let load_seconds = clock.elapsed().as_secs_f64();
    let mut done = workflow::run_timed(loaded, &path, &options, &mut bars, load_seconds)?;
    done.write(&args.out, &args.format, args.picture, &mut bars)?;
    print!("{}", done.table());
    Ok(())
}
