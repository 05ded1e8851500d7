//! The command line's arguments (clap).

use std::path::PathBuf;
use std::sync::LazyLock;

use clap::{Args, Parser, Subcommand};
use multires::load::{Weld, WELD_HELP};

/// `--version`: the program's version and the formats it reads and writes.
static VERSION: LazyLock<String> = LazyLock::new(|| {
    format!(
        "{} (hierarchy file format {}, recipe format {})",
        env!("CARGO_PKG_VERSION"),
        halfedge::hierarchy::file::FORMAT_VERSION,
        multires::recipe::RECIPE_VERSION
    )
});

/// Multiresolution editing of triangle meshes: simplify, edit at a coarse level, refine
/// back; read and write OBJ, PLY, OFF, STL (and their .gz); hierarchies saved as .mrh.
#[derive(Parser, Debug)]
#[command(name = "multires", version = VERSION.as_str(), propagate_version = true)]
pub struct Cli {
    /// No progress bars, no text beyond the result.
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// Report as one JSON object on stdout.
    #[arg(long, global = true)]
    pub json: bool,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Counts, bounding box, components, boundary loops, genus and the reader's fixes of
    /// a mesh (or the levels of a .mrh hierarchy).
    Info(InfoArgs),
    /// Every connectivity invariant of a mesh; `--openmesh` compares its topology with
    /// OpenMesh's.
    Check(CheckArgs),
    /// Converts between OBJ, PLY, OFF and STL (and their .gz), by extension.
    Convert(ConvertArgs),
    /// Builds the progressive hierarchy of a mesh and saves it (.mrh).
    Simplify(SimplifyArgs),
    /// Writes one level of a saved hierarchy as a mesh.
    Level(LevelArgs),
    /// Applies an edit recipe (TOML) to a saved hierarchy, each step at its level.
    Edit(EditArgs),
    /// Writes the full-resolution mesh of a saved hierarchy (after its edits).
    Refine(RefineArgs),
    /// The whole job: simplify, one edit of each family at a coarse level, refine, write
    /// the mesh and before/after pictures.
    Workflow(WorkflowArgs),
    /// Runs a recipe (or the workflow) over a folder, a glob or a manifest of meshes.
    Batch(BatchArgs),
    /// How far apart two meshes' surfaces are: mean, root mean square and Hausdorff
    /// distances over sample points (Metro's measure of a simplification's error).
    Distance(DistanceArgs),
}

fn parse_degrees(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(d) if d.is_finite() && d > 0.0 && d <= 180.0 => Ok(d),
        _ => Err(format!("expected an angle in (0, 180] degrees, got {s:?}")),
    }
}

fn parse_weld(s: &str) -> Result<Weld, String> {
    s.parse()
}

/// The welding option shared by the subcommands that read meshes.
#[derive(Args, Debug, Clone)]
pub struct WeldArg {
    #[arg(long, default_value = "auto", value_parser = parse_weld, help = WELD_HELP)]
    pub weld: Weld,
}

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// The mesh (OBJ, PLY, OFF, STL, .gz) or hierarchy (.mrh).
    pub mesh: PathBuf,
    #[command(flatten)]
    pub weld: WeldArg,
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// The mesh.
    pub mesh: PathBuf,
    /// Also compare the topology with OpenMesh's reading of the same file (needs python3
    /// with the `openmesh` package).
    #[arg(long)]
    pub openmesh: bool,
}

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The input mesh.
    pub input: PathBuf,
    /// The output mesh (format by extension).
    pub output: PathBuf,
    /// PLY and STL: write text instead of binary.
    #[arg(long)]
    pub ascii: bool,
    #[command(flatten)]
    pub weld: WeldArg,
}

#[derive(Args, Debug)]
pub struct SimplifyArgs {
    /// The mesh.
    pub mesh: PathBuf,
    /// The hierarchy file to write (.mrh).
    #[arg(short, long)]
    pub output: PathBuf,
    /// rounds (the paper's) or qem.
    #[arg(long, default_value = "rounds", value_parser = ["rounds", "qem"])]
    pub method: String,
    /// Stop at this many faces.
    #[arg(long, default_value_t = 2000)]
    pub target_faces: usize,
    /// Stop after this many levels below the input.
    #[arg(long)]
    pub max_levels: Option<usize>,
    /// The bound on a face normal's turn in one collapse, in degrees (default: the
    /// method's; the viewer's default is 90).
    #[arg(long, value_parser = parse_degrees)]
    pub max_normal_deviation: Option<f64>,
    /// Detail coefficients: local (local frames) or translation (the seed paper's).
    #[arg(long, default_value = "local", value_parser = ["local", "translation"])]
    pub detail: String,
    /// Rounds: where a collapse puts its survivor, midpoint (the paper's) or quadric
    /// (where QEM would; nearer the input surface, about 20 % slower). QEM always places
    /// by its quadric.
    #[arg(long, default_value = "midpoint", value_parser = ["midpoint", "quadric"])]
    pub placement: String,
    /// Also write every level as a mesh into this folder.
    #[arg(long)]
    pub levels: Option<PathBuf>,
    /// Format of the level meshes.
    #[arg(long, default_value = "ply")]
    pub format: String,
    #[command(flatten)]
    pub weld: WeldArg,
}

#[derive(Args, Debug)]
pub struct DistanceArgs {
    /// The first mesh (the reference: distances are also given over the diagonal of its
    /// bounding box).
    pub first: PathBuf,
    /// The second mesh.
    pub second: PathBuf,
    /// Points spread over each surface by area, besides its vertices.
    #[arg(long, default_value_t = 100_000)]
    pub samples: usize,
    /// Sample the faces only, not the vertices.
    #[arg(long)]
    pub no_vertices: bool,
    #[command(flatten)]
    pub weld: WeldArg,
}

#[derive(Args, Debug)]
pub struct LevelArgs {
    /// The hierarchy (.mrh).
    pub hierarchy: PathBuf,
    /// The level (0: the input; clamped to the coarsest).
    #[arg(long)]
    pub level: usize,
    /// The mesh to write (format by extension).
    #[arg(short, long)]
    pub output: PathBuf,
}

#[derive(Args, Debug)]
pub struct EditArgs {
    /// The hierarchy (.mrh).
    pub hierarchy: PathBuf,
    /// The recipe (TOML).
    #[arg(long)]
    pub recipe: PathBuf,
    /// The hierarchy to write (.mrh), with the edits.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write the full-resolution result as a mesh.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct RefineArgs {
    /// The hierarchy (.mrh).
    pub hierarchy: PathBuf,
    /// The mesh to write (format by extension).
    #[arg(short, long)]
    pub output: PathBuf,
}

#[derive(Args, Debug)]
pub struct WorkflowArgs {
    /// The mesh; default: data/blob.obj of the repository.
    pub mesh: Option<PathBuf>,
    /// Hierarchy level to edit at (0 = input; clamped to the coarsest).
    #[arg(long, default_value_t = 3)]
    pub level: usize,
    /// Simplification: rounds (the paper's) or qem.
    #[arg(long, default_value = "rounds", value_parser = ["rounds", "qem"])]
    pub method: String,
    /// Output folder for the mesh and the pictures.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Output mesh format: obj, ply, off or stl.
    #[arg(long, default_value = "ply")]
    pub format: String,
    /// Axis of the cutting plane that labels the sub-mesh: the sub-mesh is the part
    /// furthest along it (x, y, z, -x, -y or -z).
    #[arg(long, default_value = "y", value_parser = multires::recipe::parse_axis)]
    pub axis: glam::DVec3,
    /// Height of the cutting plane, as a fraction of the mesh's extent along the axis.
    #[arg(long, default_value_t = 0.72)]
    pub plane: f64,
    /// Steps to leave out, comma-separated: lee, blend, taper.
    #[arg(long, value_delimiter = ',', value_parser = ["lee", "blend", "taper"])]
    pub skip: Vec<String>,
    /// Picture size in pixels (width of one panel; height is 3/4 of it).
    #[arg(long, default_value_t = 640)]
    pub picture: usize,
    #[command(flatten)]
    pub weld: WeldArg,
}

#[derive(Args, Debug)]
pub struct BatchArgs {
    /// Meshes: folders (searched recursively), glob patterns (quoted: "scans/*.ply"),
    /// mesh files, or manifest files (a .txt or .list file naming one mesh per line).
    #[arg(required = true)]
    pub inputs: Vec<String>,
    /// The recipe (TOML) to run on every mesh; without it, the workflow.
    #[arg(long)]
    pub recipe: Option<PathBuf>,
    /// Output folder: the edited meshes, `report.jsonl` and `summary.json`.
    #[arg(long)]
    pub out: PathBuf,
    /// Meshes processed at once (default: one per core).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// This machine's share of the corpus, `I/N` (1 ≤ I ≤ N): a deterministic split with
    /// no coordinator.
    #[arg(long)]
    pub shard: Option<String>,
    /// Output mesh format.
    #[arg(long, default_value = "ply")]
    pub format: String,
    /// Workflow only: also write the pictures (panels this many pixels wide; 0: none).
    #[arg(long, default_value_t = 0)]
    pub picture: usize,
    #[command(flatten)]
    pub weld: WeldArg,
}
