//! Measures how an edit made at a coarse level of the hierarchy comes back at full
//! resolution (issue 12): the same edit is made (a) at level `N`, then refined back to
//! the input, and (b) directly on the input, on the corresponding region; one JSON object
//! compares them.
//!
//! ```text
//! cargo run --release --example coarse_edit -- FILE --edit EDIT --level N
//!     [--method rounds|qem] [--detail local|translation]
//!     [--seed-vertex I] [--region-fraction F] [--amount A] [--out DIR]
//!     [--weld auto|off|F]
//! ```
//!
//! `EDIT` is one of `rotate, twist, taper, scale, pull` (sub-mesh edits, no propagation),
//! `lee` (Lee 1999 area drag), `bk` (Bendels & Klein handle) or `ffd` (shape/height-surface
//! FFD bend). A triangle soup or a mesh with seams is welded first, as in the workflow
//! (`--weld`; a note on stderr says so, and `--seed-vertex` still names the file's vertex).
//!
//! # The region rule
//!
//! Deterministic, on the mesh at level `N` (so it works on closed, open, multi-component
//! and higher-genus meshes alike):
//!
//! 1. **Component**: the connected component with the most vertices (ties: the first in
//!    vertex order). With `--seed-vertex I`, the component of input vertex `I`'s
//!    ancestor at level `N`.
//! 2. **Tip**: the vertex of the component farthest from the component's centroid among
//!    those at least three edge rings away from the mesh boundary (fewer rings only when
//!    no vertex is that far in); with `--seed-vertex I`, `I`'s ancestor.
//! 3. **Region**: the nearest `F` (`--region-fraction`, default 0.2) of the component's
//!    vertices by edge-path (Dijkstra) distance from the tip, ties by index; `R` is the
//!    distance of its farthest vertex. Its **frontier** is its vertices with a neighbour
//!    outside; its **axis** runs from the frontier's centroid `c` to the tip (`d`).
//!
//! The edits, with `--amount A` (default 1) scaling every magnitude:
//!
//! - `pull`: the region (a sub-mesh, `n = 0`) moves by `0.3 A R` along `d` (a
//!   translation).
//! - `rotate`: by `30° A` about the line through `c` across the axis (perpendicular to `d`
//!   and, where possible, to the region's mean normal), `n = 0`: a rigid motion.
//! - `scale`: by `0.8^A` about `c`, `n = 0`, re-seated on the frontier's plane by the
//!   library: affine. At level 0 the scaled region gets the level-`N` edit's re-seating
//!   translation (the plane fitted to the frontier differs a little between
//!   resolutions), so both sides make the same map. (Growing it instead folds the faces
//!   at the frontier over the host at every resolution.)
//! - `twist` / `taper`: by `60° A` / to `0.6^A` about the axis along which the region
//!   reaches farthest beyond its frontier (towards the tip, or the normal of the plane
//!   fitted to the frontier), with [`Variation::Along`](edit::deform::Variation::Along)
//!   from the frontier's highest axial coordinate to 70 % of the way to the region's top:
//!   the strength is geometric, so the same at both resolutions, and the frontier does
//!   not move. The part beyond 70 % is moved by one rigid (twist) or affine (taper) map.
//!   A flat region (reaching less than `0.05 R` beyond its frontier along both axes, as
//!   inside a flat or open mesh, where the frontier encloses the region) has nothing to
//!   twist: without `--seed-vertex` the tip is then chosen again with no distance from
//!   the boundary asked (the farthest vertex from the centroid, where a flat mesh
//!   protrudes), and a region still flat is refused with an error.
//! - `lee`: an editing area made of the faces around the first `K` vertices of the
//!   region order whose neighbours are all among them (and that are two rings from the
//!   mesh boundary), with the pockets they enclose, `K` = the region's vertex count
//!   shrunk by a quarter until the area is a disk that does not touch the mesh boundary
//!   and its B-spline lattice moves the tip onto its target; embedded with mean-value
//!   weights (the harmonic map of a coarse area with obtuse triangles can fold). The tip
//!   is dragged along its normal by `0.3 A` times the area's Euclidean reach, at the
//!   default scale s = 0.5.
//! - `bk`: handle = the nearest `0.15 F` of the component (3 % by default), fixed =
//!   everything beyond the nearest `1.25 F` (25 %) and every other component, except the
//!   handle's neighbours (which a long edge can put beyond the ball); the handle
//!   turns by `30° A` about a tangent axis through its centroid and lifts by `0.2 A R`
//!   along its mean normal (geodesic distances, smoothstep).
//! - `ffd`: a bicubic 8 × 8 shape and height lattice over the region's footprint (a frame
//!   at `c` with `x` along `d` and `y` along the region's mean normal made perpendicular
//!   to it, 5 % margin), attached to the nearest `2 F` of the component; the shape lattice
//!   is bent by `45° A` and its two outer layers of control points on every side are put
//!   back, so that the deformation fades to nothing at the lattice's border (whichever
//!   borders the attached vertices cross).
//!
//! A smooth edit (`twist`, `taper`, `lee`, `bk`, `ffd`) that turns a face of the level-`N`
//! mesh over is too strong for the mesh the user edits: its magnitudes are halved (at most
//! four times) until it does not; `amount` in the output is the factor used. Rigid
//! sub-mesh edits without propagation fold the faces at the frontier at every resolution
//! and keep their magnitudes.
//!
//! At level `N`, the sub-mesh edits are marked in the hierarchy by the library
//! (`SubMesh::apply_with_marks`, given through `HierarchyEdit`: the sub-mesh as region, a pull, rotation or scale as an
//! affine map, a twist or taper along its axis as a field, `Hierarchy::mark_field`); for
//! the other edits the example declares every rigid part (the B&K handle, the Lee
//! primitive) with `Hierarchy::mark_affine` and the coarse vertices the edit may move (its
//! region) with `Hierarchy::mark_region`, before refining back. Every rigid or affine
//! part's map is also found from the edit's parameters and checked against the moved
//! positions to 1e-12 of the diagonal; `handle_error` measures it at full resolution (for
//! a twist or taper: on the coarse vertices beyond the ramp whose whole cluster is beyond
//! it in the input). At level
//! 0, the same edit acts on the *corresponding* region: the input vertices whose ancestor
//! at level `N` (`Hierarchy::ancestors`) is in the coarse region (sub-mesh, Lee primitive,
//! B&K handle and fixed area, FFD attachment ball; the Lee area is the input faces the
//! hierarchy collapses into the coarse area), with the same axes, maps, Lee lattice size
//! and FFD frame and lattice.
//!
//! # Output
//!
//! One JSON object: `mesh`, `edit`, `level`, `method`, `detail`, `faces` (input),
//! `level_faces` (level `N`), `tip`, `region_vertices_coarse` / `_fine` (what the method
//! may move), `flips_coarse_path` / `flips_full_res` (faces whose normal turned over
//! against the input, `n_after · n_input < 0`), `outside_moved` (input vertices whose
//! ancestor is not among the coarse vertices the method may move — the sub-mesh, the Lee
//! area's interior, the B&K handle and deformable area, the FFD's attached vertices — and
//! whose position changed at all), `handle_error` (largest distance of a fine vertex of a
//! rigid or affine part from that map's image of its input position, over the diagonal;
//! `null` for `ffd`, which has none), `handle_vertices`, `rms_vs_full_res` and
//! `max_vs_full_res` (distance between (a) and (b) over all vertices, over the diagonal),
//! `refine_seconds`, `build_seconds`, `marks` (affine marks given), `amount`,
//! `coarse_flips` (faces of the level-`N` mesh the coarse edit turned over) and
//! `meets_targets`
//! (`outside_moved` = 0, `handle_error` ≤ 1e-9, `flips_coarse_path` ≤ `flips_full_res`,
//! `rms_vs_full_res` ≤ 0.01). With `--detail translation` (the paper's centroid
//! translations) no marks can be given and the targets are not expected to hold.
//!
//! `--edit bk-refine` is the Bendels & Klein edit with adaptive refinement inside the
//! hierarchy (`BlendSession::refine_in_hierarchy`), then a walk to every level and back; its
//! JSON has `new_vertices`, `levels`, `levels_reachable`, `handle_error` and
//! `refine_seconds` (no full-resolution comparison: the refined mesh has other vertices).
//!
//! Errors are printed with a hint of which flag to change; the exit code is then 2.
//!
//! The measurement itself is `testkit::coarse_edit` (`crates/testkit/src/coarse_edit/`),
//! shared with `tests/coarse_edit.rs`; this file is its command line.

use std::path::PathBuf;

use clap::{Parser, ValueEnum};
use halfedge::hierarchy::{DetailMode, Method};

use multires::load::{self, Weld, WELD_HELP};
use multires::progress::{Bars, LARGE_FACES};
use testkit::coarse_edit::{self, EditKind, Failure, Options};

#[derive(Clone, Copy, Debug, ValueEnum)]
enum EditArg {
    Rotate,
    Twist,
    Taper,
    Scale,
    Pull,
    Lee,
    Bk,
    /// Bendels & Klein with adaptive refinement inside the hierarchy, then a walk to
    /// every level and back (`levels_reachable`).
    BkRefine,
    Ffd,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum MethodArg {
    Rounds,
    Qem,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum DetailArg {
    /// Local-frame detail with exact regions and affine marks (the default).
    Local,
    /// The seed paper's centroid translations.
    Translation,
}

/// Command-line options.
#[derive(Parser, Debug)]
#[command(
    about = "Edit a mesh at a coarse level of its hierarchy, refine back, and compare with \
             the same edit made at full resolution (one JSON object on stdout)",
    after_help = "Region: the largest component at the level; tip = its vertex farthest from \
                  the component's centroid (at least 3 rings from the mesh boundary); region = \
                  the nearest --region-fraction of the component by edge-path distance from \
                  the tip. Smooth edits (twist, taper, lee, bk, ffd) are halved (at most 4 \
                  times) while they turn a face of the coarse mesh over. Targets: \
                  outside_moved = 0, handle_error <= 1e-9, flips_coarse_path <= \
                  flips_full_res, rms_vs_full_res <= 0.01 (meets_targets). Errors go to \
                  stderr with a hint; the exit code is then 2."
)]
struct Args {
    /// Mesh file (.obj, .ply).
    file: PathBuf,
    /// The edit: sub-mesh rotate, twist, taper, scale or pull; lee (area drag); bk
    /// (Bendels & Klein handle); ffd (shape/height-surface bend).
    #[arg(long, value_enum)]
    edit: EditArg,
    /// The hierarchy level to edit at (1 = one level coarser than the input).
    #[arg(long)]
    level: usize,
    /// Simplification: the paper's rounds or QEM decimation.
    #[arg(long, value_enum, default_value = "rounds")]
    method: MethodArg,
    /// Detail coefficients: local frames (default) or the paper's translations.
    #[arg(long, value_enum, default_value = "local")]
    detail: DetailArg,
    /// Input vertex (file index) whose ancestor at the level is the tip of the region
    /// (default: the tip rule below).
    #[arg(long)]
    seed_vertex: Option<usize>,
    /// Fraction of the component's vertices (at the level) in the region.
    #[arg(long, default_value_t = 0.2)]
    region_fraction: f64,
    /// Multiplies the edit's magnitudes (angles, offsets, log factors; see the example's
    /// docs for the defaults).
    #[arg(long, default_value_t = 1.0)]
    amount: f64,
    /// Write the input and both results here as PLY (input.ply, coarse-path.ply,
    /// full-res.ply; same vertex order in all three).
    #[arg(long)]
    out: Option<PathBuf>,
    #[arg(long, default_value = "auto", value_parser = |s: &str| s.parse::<Weld>(), help = WELD_HELP)]
    weld: Weld,
}

fn main() {
    let args = Args::parse();
    match run(&args) {
        Ok(json) => println!("{json}"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    }
}

fn run(args: &Args) -> Result<serde_json::Value, Failure> {
    let (input, report) = halfedge::io::read(&args.file).map_err(|e| Failure {
        message: format!("cannot read {}: {e}", args.file.display()),
        hint: "pass an .obj or .ply mesh file".into(),
    })?;
    // A triangle soup or seams welded (the file's vertex numbers of --seed-vertex follow).
    let mut bars = Bars::new(input.n_faces() > LARGE_FACES);
    let load::Loaded {
        mesh: input,
        welding,
        ..
    } = load::apply_weld(input, report, args.weld, &mut bars).map_err(|e| Failure {
        message: format!("cannot weld {}: {e}", args.file.display()),
        hint: "pass --weld off".into(),
    })?;
    let seed_vertex =
        match (&welding, args.seed_vertex) {
            (Some(w), Some(i)) => Some(w.vertex_map.get(i).map(|&j| j as usize).ok_or_else(
                || Failure {
                    message: format!(
                        "--seed-vertex {i} is not a vertex of the file ({} vertices)",
                        w.vertex_map.len()
                    ),
                    hint: "pass a vertex index below the file's vertex count".into(),
                },
            )?),
            (_, seed) => seed,
        };
    if let Some(w) = &welding {
        eprintln!("note: {}", w.note);
    }
    let method = match args.method {
        MethodArg::Rounds => Method::Rounds,
        MethodArg::Qem => Method::Qem,
    };
    let detail = match args.detail {
        DetailArg::Local => DetailMode::LocalFrame,
        DetailArg::Translation => DetailMode::Translation,
    };
    let name = args
        .file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if let EditArg::BkRefine = args.edit {
        let prepared = coarse_edit::prepare(input, method, detail, args.level)?;
        let options = Options {
            seed_vertex,
            region_fraction: args.region_fraction,
            amount: args.amount,
            ..Options::new(EditKind::Bk)
        };
        return coarse_edit::measure_bk_refine(&prepared, &options, &name);
    }
    let edit = match args.edit {
        EditArg::Rotate => EditKind::Rotate,
        EditArg::Twist => EditKind::Twist,
        EditArg::Taper => EditKind::Taper,
        EditArg::Scale => EditKind::Scale,
        EditArg::Pull => EditKind::Pull,
        EditArg::Lee => EditKind::Lee,
        EditArg::Bk | EditArg::BkRefine => EditKind::Bk,
        EditArg::Ffd => EditKind::Ffd,
    };
    let prepared = coarse_edit::prepare(input, method, detail, args.level)?;
    let options = Options {
        seed_vertex,
        region_fraction: args.region_fraction,
        amount: args.amount,
        ..Options::new(edit)
    };
    let measured = coarse_edit::measure(&prepared, &options)?;
    if let Some(dir) = &args.out {
        let write = |name: &str, mesh: &halfedge::Mesh| {
            std::fs::create_dir_all(dir)
                .map_err(|e| e.to_string())
                .and_then(|_| halfedge::io::write(dir.join(name), mesh).map_err(|e| e.to_string()))
                .map_err(|e| Failure {
                    message: format!("cannot write into {}: {e}", dir.display()),
                    hint: "pass a writable --out folder".into(),
                })
        };
        write("input.ply", &prepared.input)?;
        write("coarse-path.ply", &measured.coarse_path)?;
        write("full-res.ply", &measured.full_res)?;
    }
    Ok(measured.report.to_json(&name))
}
