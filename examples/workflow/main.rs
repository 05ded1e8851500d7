//! The whole multiresolution job from the command line: load → simplify to a level →
//! label a sub-mesh by a cutting plane → one edit of each family (a Lee 1999 area drag, a
//! Bendels & Klein handle rotation, a sub-mesh taper) → refine back with the detail
//! coefficients → write the mesh and before/after pictures, with a summary table.
//!
//! ```text
//! cargo run --release --example workflow -- [FILE] [--level N] [--method rounds|qem]
//!     [--axis y] [--plane 0.72] [--skip lee,blend,taper] [--weld auto|off|F] [--out DIR]
//! ```
//!
//! It runs on any mesh — closed or open, one component or several, any genus — because
//! each step chooses its region by rules that adapt to the mesh, and says which rule it
//! used:
//!
//! - **Welding**: a mesh written as a triangle soup or with seams (faces on their own
//!   copies of vertices at the same place) is welded first (`Mesh::welded`), when that
//!   closes boundaries; `--weld off` keeps the file's vertices, `--weld F` merges
//!   vertices within `F` times the bounding-box diagonal.
//! - **Level**: `--level` (default 3), but never coarser than the coarsest level with at
//!   least 500 faces (or the input's faces, when it has fewer): edits on a handful of
//!   faces would mean nothing.
//! - **Sub-mesh** (for the taper): the part cut off by a plane perpendicular to `--axis`
//!   (default `y`, up) at `--plane` of the mesh's extent along it (default 0.72), near
//!   the vertex furthest along the axis; the part on the axis' side is the sub-mesh, and
//!   separate components go with the side their centroid lies on. Where that section
//!   runs into the mesh boundary (an open mesh), does not separate the mesh (it goes
//!   around a handle) or cuts off fewer than 4 vertices, the plane moves towards the tip
//!   in steps of 4 % of the extent, then away from it; where no height works, the other
//!   axes are tried (`y`, `z`, `x`, `-y`, `-z`, `-x`). Where no section is a closed
//!   loop at all (an open mesh: a terrain, a flat or partial scan), the sub-mesh is the
//!   part beyond the same planes reached from the tip without crossing them, given as a
//!   vertex mask (the hierarchy then carries no labels for it).
//! - **Lee area** (dragged along the normal): a disk of about a twelfth of the coarse
//!   vertices (30 to 5,000) around the vertex of the largest component furthest to the
//!   front (+z). Where the disk reaches the mesh boundary or wraps around a handle it is
//!   halved (down to a vertex and its ring); then the largest component's extreme
//!   vertices along `x`, `-x`, `y`, `-y`, `-z` are tried, and last the vertex farthest
//!   from the boundary.
//! - **Bendels & Klein** (handle rotated 25° and pulled): the handle is the vertices
//!   within an edge-path distance of 8 % of the bounding-box diagonal from the vertex
//!   furthest along −x, the fixed region everything beyond 30 %; where the handle would
//!   touch the fixed region or either is empty, both radii are halved (three times at
//!   most); where no radius works (the vertex is on a small loose part), the same around
//!   the vertex furthest along −x of the largest component.
//!
//! A step none of whose rules applies is left out with a note saying why and which flag
//! changes it; the job goes on. The pictures are framed on the union of the before and
//! after meshes, so a part an edit pulled out stays in the frame.

#[path = "../support/picks.rs"]
mod picks;
#[path = "../support/progress.rs"]
mod progress;
#[path = "../support/weld.rs"]
mod weld;

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Parser;
use edit::bendels_klein::{BlendOptions, BlendSession, DistanceKind, Regions, ShapeFunction};
use edit::deform::{Propagation, SubMesh, SubmeshEdit, Variation};
use edit::lee::{AreaSession, EditingArea, SessionOptions};
use edit::HierarchyEdit;
use glam::{DMat4, DVec3};
use halfedge::hierarchy::{BuildProgress, Hierarchy, HierarchyOptions};
use halfedge::{Mesh, VertexId};
use multires::render::{self, Camera, Panel};

/// Command-line options.
#[derive(Parser, Debug)]
#[command(
    about = "simplify → edit → refine a mesh with multires (OBJ or PLY; any mesh: the \
             edit regions adapt, see the example's docs)"
)]
struct Args {
    /// Mesh to edit (OBJ or PLY); default: data/blob.obj.
    mesh: Option<PathBuf>,
    /// Hierarchy level to edit at (0 = input; clamped to the coarsest).
    #[arg(long, default_value_t = 3)]
    level: usize,
    /// Simplification: the paper's rounds or QEM.
    #[arg(long, default_value = "rounds")]
    method: String,
    /// Output folder for the mesh and the pictures.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Output mesh format: obj or ply.
    #[arg(long, default_value = "ply")]
    format: String,
    /// Axis of the cutting plane that labels the sub-mesh: the sub-mesh is the part
    /// furthest along it (x, y, z, -x, -y or -z).
    #[arg(long, default_value = "y", value_parser = parse_axis)]
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
    /// Welding of vertices at the same place before the job: `auto` merges vertices at
    /// exactly the same position when that closes boundaries (a triangle soup, seams
    /// of an export), `off` keeps the file's vertices, a number `F` merges vertices
    /// within `F` times the bounding-box diagonal.
    #[arg(long, default_value = "auto", value_parser = weld::parse)]
    weld: weld::Weld,
}

fn parse_axis(s: &str) -> Result<DVec3, String> {
    match s.trim() {
        "x" | "+x" => Ok(DVec3::X),
        "y" | "+y" => Ok(DVec3::Y),
        "z" | "+z" => Ok(DVec3::Z),
        "-x" => Ok(DVec3::NEG_X),
        "-y" => Ok(DVec3::NEG_Y),
        "-z" => Ok(DVec3::NEG_Z),
        other => Err(format!("unknown axis {other:?} (x, y, z, -x, -y or -z)")),
    }
}

fn axis_name(d: DVec3) -> &'static str {
    [
        (DVec3::X, "x"),
        (DVec3::Y, "y"),
        (DVec3::Z, "z"),
        (DVec3::NEG_X, "-x"),
        (DVec3::NEG_Y, "-y"),
        (DVec3::NEG_Z, "-z"),
    ]
    .iter()
    .find(|(a, _)| *a == d)
    .map_or("?", |(_, n)| n)
}

struct Row {
    step: &'static str,
    detail: String,
    seconds: f64,
}

type BoxError = Box<dyn std::error::Error>;

/// The edit level keeps at least this many faces (or all of a smaller input's).
const MIN_EDIT_FACES: usize = 500;

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> Result<(), BoxError> {
    if !(args.plane >= 0.0 && args.plane < 1.0) {
        return Err(format!("--plane must be in [0, 1), got {}", args.plane).into());
    }
    let path = args
        .mesh
        .clone()
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("data/blob.obj"));
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let mut rows = Vec::new();
    let mut notes: Vec<String> = Vec::new();

    let clock = Instant::now();
    let (input, report) = progress::read(&path)?;
    let large = progress::is_large(input.n_faces());
    let (input, report, welding) = weld::apply(input, report, args.weld, large)?;
    notes.extend(welding.map(|w| w.note));
    progress::step(large, "checking the mesh", || input.check())?;
    if input.n_faces() == 0 {
        return Err(format!("{}: the mesh has no faces to edit", path.display()).into());
    }
    let topology = input.topology_report();
    rows.push(Row {
        step: "load",
        detail: format!(
            "{}: {} vertices, {} faces, {} component(s), {} boundary loop(s), Euler {} \
             ({} duplicated vertices, {} dropped faces)",
            path.display(),
            input.n_vertices(),
            input.n_faces(),
            topology.components,
            topology.boundary_loops,
            topology.euler,
            report.duplicated_vertices,
            report.dropped_faces
        ),
        seconds: clock.elapsed().as_secs_f64(),
    });
    let original = input.clone();
    let (lo, hi) = input.bounding_box().ok_or("the mesh has no vertices")?;
    let diagonal = lo.distance(hi);

    // --- simplify ---------------------------------------------------------------
    let options = match args.method.as_str() {
        "rounds" => HierarchyOptions::rounds(),
        "qem" => HierarchyOptions::qem(),
        other => return Err(format!("unknown --method {other:?} (rounds or qem)").into()),
    };
    let bar = progress::bar(
        large,
        input.n_faces() as u64,
        "simplifying [{bar:40}] {pos}/{len} faces removed {msg}",
    );
    let clock = Instant::now();
    let input_faces = input.n_faces();
    let mut hierarchy =
        Hierarchy::build_with_progress(input, &options, &mut |p: BuildProgress| {
            bar.set_position((p.input_faces - p.faces) as u64);
            bar.set_message(format!("(level {})", p.levels));
        })?;
    bar.finish_and_clear();
    let build_seconds = clock.elapsed().as_secs_f64();
    let min_faces = MIN_EDIT_FACES.min(input_faces);
    let finest_enough = hierarchy
        .level_face_counts()
        .iter()
        .rposition(|&f| f >= min_faces)
        .unwrap_or(0);
    let level = args.level.min(finest_enough);
    if level < args.level {
        notes.push(format!(
            "editing at level {level} ({} faces) instead of {}: the levels above it have \
             fewer than {min_faces} faces (--level chooses; {:?})",
            hierarchy.level_face_counts()[level],
            args.level,
            hierarchy.level_face_counts()
        ));
    }
    let clock = Instant::now();
    hierarchy.go_to_level(level)?;
    rows.push(Row {
        step: "simplify",
        detail: format!(
            "{} levels {:?} faces; editing at level {level} ({} faces of {input_faces})",
            hierarchy.n_levels(),
            hierarchy.level_face_counts(),
            hierarchy.mesh().n_faces()
        ),
        seconds: build_seconds + clock.elapsed().as_secs_f64(),
    });

    // --- label a sub-mesh by a cutting plane ------------------------------------
    let clock = Instant::now();
    let sub = if args.skip.iter().any(|s| s == "taper") {
        rows.push(skipped("label", "left out (--skip taper)"));
        None
    } else {
        match label_submesh(hierarchy.mesh_mut(), args.axis, args.plane) {
            Ok(labelled) => {
                hierarchy.attach_labels(labelled.attribute).unwrap();
                hierarchy.labels_defined_here();
                notes.extend(labelled.note.clone());
                rows.push(Row {
                    step: "label",
                    detail: labelled.detail.clone(),
                    seconds: clock.elapsed().as_secs_f64(),
                });
                Some(labelled.sub)
            }
            Err(why) => match mask_submesh(hierarchy.mesh(), args.axis, args.plane) {
                // An open mesh (a terrain, a flat or partial scan): no section is a
                // closed loop, but the part beyond the plane is still a sub-mesh.
                Ok((sub, detail)) => {
                    notes.push(format!(
                        "no plane section is a closed frontier ({why}); the sub-mesh is the \
                         part beyond the plane reached from its tip, given to the taper as \
                         a vertex mask (no labels: the hierarchy's levels were not kept \
                         from crossing it)"
                    ));
                    rows.push(Row {
                        step: "label",
                        detail,
                        seconds: clock.elapsed().as_secs_f64(),
                    });
                    Some(sub)
                }
                Err(_) => {
                    notes.push(format!("sub-mesh taper left out: {why}"));
                    rows.push(skipped("label", "no cutting plane applies (see notes)"));
                    None
                }
            },
        }
    };
    let coarse_before = hierarchy.mesh().clone();

    // --- Lee 1999: drag an editing area on the front ----------------------------
    if args.skip.iter().any(|s| s == "lee") {
        rows.push(skipped("Lee drag", "left out (--skip lee)"));
    } else {
        let clock = Instant::now();
        match lee_drag(&mut hierarchy, diagonal, large) {
            Ok((detail, note)) => {
                notes.extend(note);
                rows.push(Row {
                    step: "Lee drag",
                    detail,
                    seconds: clock.elapsed().as_secs_f64(),
                });
            }
            Err(why) => {
                notes.push(format!(
                    "Lee area drag left out: {why} (--skip lee leaves it out without trying)"
                ));
                rows.push(skipped("Lee drag", "no editing area applies (see notes)"));
            }
        }
    }

    // --- Bendels & Klein: rotate a handle on the side ----------------------------
    let mut landing: Option<Landing> = None;
    if args.skip.iter().any(|s| s == "blend") {
        rows.push(skipped("B&K rotate", "left out (--skip blend)"));
    } else {
        let clock = Instant::now();
        match blend_rotate(&mut hierarchy, diagonal, large) {
            Ok((detail, note, to_land)) => {
                notes.extend(note);
                landing = Some(to_land);
                rows.push(Row {
                    step: "B&K rotate",
                    detail,
                    seconds: clock.elapsed().as_secs_f64(),
                });
            }
            Err(why) => {
                notes.push(format!(
                    "Bendels & Klein rotation left out: {why} (--skip blend leaves it out \
                     without trying)"
                ));
                rows.push(skipped("B&K rotate", "no regions apply (see notes)"));
            }
        }
    }

    // --- sub-mesh taper above the plane -----------------------------------------
    let before_taper = hierarchy.mesh().positions().to_vec();
    if let Some(sub) = &sub {
        let clock = Instant::now();
        let taper = SubmeshEdit::Taper {
            axis: None,
            factor: 0.6,
            variation: Variation::Levels(None),
        };
        // Marked in the hierarchy: its region (the sub-mesh) and the part at full
        // strength, which lands exactly when refined.
        let tapered = sub
            .apply_with_marks(hierarchy.mesh_mut(), &taper, Propagation::linear(2))
            .map_err(edit::Error::from)
            .and_then(|applied| applied.mark(&mut hierarchy));
        match tapered {
            Ok(_) => rows.push(Row {
                step: "taper",
                detail: "sub-mesh tapered to 0.6, 2 propagation levels".to_string(),
                seconds: clock.elapsed().as_secs_f64(),
            }),
            Err(e) => {
                notes.push(format!(
                    "sub-mesh taper left out: {e} (--axis and --plane choose another \
                     sub-mesh, --skip taper leaves it out)"
                ));
                rows.push(skipped("taper", "the taper failed (see notes)"));
            }
        }
    }
    hierarchy.mesh().check()?;
    let coarse_after = hierarchy.mesh().clone();
    // Handle vertices the taper moved too: their fine vertices are the taper's image of
    // the handle's, not the handle's alone.
    let handle_tapered = landing.as_ref().map_or(0, |landing| {
        landing
            .handle
            .iter()
            .filter(|&&i| before_taper[i as usize] != coarse_after.positions()[i as usize])
            .count()
    });

    // --- refine back with detail coefficients -----------------------------------
    let clock = Instant::now();
    let bar = progress::bar(
        large,
        level as u64,
        "refining [{bar:40}] level {pos}/{len} back to the input {msg}",
    );
    for l in (0..level).rev() {
        hierarchy.go_to_level(l)?;
        bar.inc(1);
        bar.set_message(format!("({} faces)", hierarchy.mesh().n_faces()));
    }
    bar.finish_and_clear();
    let ancestors = hierarchy.ancestors(level)?;
    let result = hierarchy.into_mesh();
    progress::step(large, "checking the result", || result.check())?;
    // How exactly the handle landed: its fine vertices against the rigid image of their
    // input positions (later edits that moved the handle too make this larger).
    let landed = landing.map(|landing| {
        let mut in_handle = vec![false; result.vertex_slots()];
        for &i in &landing.handle {
            if let Some(x) = in_handle.get_mut(i as usize) {
                *x = true;
            }
        }
        let (mut count, mut worst) = (0usize, 0.0f64);
        for v in original.vertices() {
            let i = original.vertex_index(v);
            if ancestors.get(i).is_some_and(|&a| in_handle[a as usize]) {
                let target = landing.map.transform_point3(original.position(v));
                worst = worst.max(result.positions()[i].distance(target) / diagonal);
                count += 1;
            }
        }
        (count, worst)
    });
    let moved = result
        .vertices()
        .filter(|&v| result.position(v) != original.position(v))
        .count();
    rows.push(Row {
        step: "refine",
        detail: format!(
            "back to {} vertices, {} faces; {moved} vertices moved, {} kept bit for bit{}",
            result.n_vertices(),
            result.n_faces(),
            result.n_vertices() - moved,
            landed.map_or(String::new(), |(count, worst)| format!(
                "; the B&K handle's {count} vertices are its rigid image within {worst:.1e} \
                 of the diagonal{}",
                if handle_tapered > 0 {
                    format!(
                        " ({handle_tapered} of its coarse vertices were tapered afterwards: \
                         --skip taper leaves them as the rotation put them)"
                    )
                } else {
                    String::new()
                }
            ))
        ),
        seconds: clock.elapsed().as_secs_f64(),
    });

    // --- write -------------------------------------------------------------------
    let clock = Instant::now();
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("mesh");
    let out_mesh = args.out.join(format!("{stem}-edited.{}", args.format));
    progress::step(large, format!("writing {}", out_mesh.display()), || {
        halfedge::io::write(&out_mesh, &result)
    })?;
    let (w, h) = (args.picture, args.picture * 3 / 4);
    // One frame for every picture: the union of the before and after meshes.
    let frame = render::union_bounds([&original, &result, &coarse_before, &coarse_after]);
    let camera = Camera::default();
    let colors = render::displacement_colors(&original, &result, 0.05 * diagonal);
    let before = render::render(Panel::new(&original), &camera, frame, w, h)?;
    let after = render::render(Panel::with_colors(&result, &colors), &camera, frame, w, h)?;
    let coarse = render::render_side_by_side(
        &[Panel::new(&coarse_before), Panel::new(&coarse_after)],
        &camera,
        frame,
        (w / 2).max(1),
        (h / 2).max(1),
    )?;
    before.save_png(args.out.join("before.png"))?;
    after.save_png(args.out.join("after.png"))?;
    render::Image::side_by_side(&[&before, &after])?.save_png(args.out.join("before-after.png"))?;
    coarse.save_png(args.out.join("coarse-edit.png"))?;
    rows.push(Row {
        step: "write",
        detail: format!(
            "{} and before/after pictures in {}",
            out_mesh.display(),
            args.out.display()
        ),
        seconds: clock.elapsed().as_secs_f64(),
    });

    println!("{:<11} {:>9}  details", "step", "seconds");
    for row in &rows {
        println!("{:<11} {:>9.3}  {}", row.step, row.seconds, row.detail);
    }
    println!(
        "{:<11} {:>9.3}",
        "total",
        rows.iter().map(|r| r.seconds).sum::<f64>()
    );
    for note in &notes {
        println!("note: {note}");
    }
    Ok(())
}

fn skipped(step: &'static str, why: &str) -> Row {
    Row {
        step,
        detail: format!("skipped: {why}"),
        seconds: 0.0,
    }
}

/// The sub-mesh cut off by a plane, with what the table and the notes say about it.
struct Labelled {
    attribute: halfedge::Attribute<VertexId, halfedge::labels::Label>,
    sub: SubMesh,
    detail: String,
    note: Option<String>,
}

/// The smallest Lee area tried: a vertex and its ring.
const MIN_AREA: usize = 7;

/// The smallest sub-mesh the taper is worth making on.
const MIN_SUBMESH: usize = 4;

/// One plane the sub-mesh rule tries: perpendicular to `axis` at `height` along it
/// (`fraction` of the mesh's extent), near `tip`, the vertex furthest along the axis at
/// `top`; `first_axis` when the axis is the one asked for.
struct CuttingPlane {
    axis: DVec3,
    tip: VertexId,
    fraction: f64,
    height: f64,
    top: f64,
    first_axis: bool,
}

/// The planes of the sub-mesh rule, in the order it tries them: perpendicular to `axis`
/// from `fraction` of the extent towards the tip in steps of 4 %, then away from it; then
/// the same for the other axes from 72 %.
fn cutting_planes(mesh: &Mesh, axis: DVec3, fraction: f64) -> Result<Vec<CuttingPlane>, String> {
    let mut axes = vec![axis];
    for a in [
        DVec3::Y,
        DVec3::Z,
        DVec3::X,
        DVec3::NEG_Y,
        DVec3::NEG_Z,
        DVec3::NEG_X,
    ] {
        if a != axis {
            axes.push(a);
        }
    }
    let mut planes = Vec::new();
    for (k, &a) in axes.iter().enumerate() {
        let tip = mesh
            .extreme_vertex(a)
            .map_err(|e| e.to_string())?
            .ok_or("the mesh has no vertex with a face")?;
        let top = mesh.position(tip).dot(a);
        let bottom = mesh
            .vertices()
            .filter(|&v| !mesh.is_isolated(v))
            .map(|v| mesh.position(v).dot(a))
            .fold(f64::INFINITY, f64::min);
        let start = if k == 0 { fraction } else { 0.72 };
        let up = (0..)
            .map(|i| start + 0.04 * i as f64)
            .take_while(|&f| f < 0.99);
        let down = (1..)
            .map(|i| start - 0.04 * i as f64)
            .take_while(|&f| f > 0.01);
        planes.extend(up.chain(down).map(|f| CuttingPlane {
            axis: a,
            tip,
            fraction: f,
            height: bottom + f * (top - bottom),
            top,
            first_axis: k == 0,
        }));
    }
    Ok(planes)
}

/// The sub-mesh rule of the module docs: planes perpendicular to `axis` (then to the
/// other axes), from `fraction` of the extent towards the tip.
fn label_submesh(mesh: &mut Mesh, axis: DVec3, fraction: f64) -> Result<Labelled, String> {
    let mut first_failure: Option<String> = None;
    for cut in cutting_planes(mesh, axis, fraction)? {
        let CuttingPlane {
            axis: a,
            tip,
            fraction: f,
            height,
            top,
            first_axis,
        } = cut;
        let point = mesh.position(tip) - a * (top - height);
        let attempt = mesh.frontier_from_plane(point, a).and_then(|frontier| {
            let (attribute, counts) = mesh.label_sides(&frontier, 1, 2)?;
            Ok((frontier, attribute, counts))
        });
        match attempt {
            Ok((frontier, attribute, counts)) => {
                let values = mesh.attribute_values(attribute).unwrap();
                if values[mesh.vertex_index(tip)] == 1 && counts.left_vertices >= MIN_SUBMESH {
                    let sub = SubMesh::from_labels(mesh, attribute, |&l| l == 1)
                        .map_err(|e| e.to_string())?;
                    let moved = !first_axis || f != fraction;
                    let detail = format!(
                        "plane {} = {height:.3} ({:.0} % of the extent): frontier of {} \
                             edges, sub-mesh on the {} side {} vertices, the rest {}",
                        axis_name(a),
                        100.0 * f,
                        frontier.halfedges().len(),
                        axis_name(a),
                        counts.left_vertices,
                        counts.right_vertices
                    );
                    let note = moved.then(|| {
                        format!(
                            "the cutting plane {} at {:.0} % could not cut off a part ({}); \
                                 used {} at {:.0} % instead (--axis, --plane)",
                            axis_name(axis),
                            100.0 * fraction,
                            first_failure.as_deref().unwrap_or("no part on its side"),
                            axis_name(a),
                            100.0 * f
                        )
                    });
                    return Ok(Labelled {
                        attribute,
                        sub,
                        detail,
                        note,
                    });
                }
                first_failure.get_or_insert_with(|| {
                    format!(
                        "the section nearest to the tip cuts off {} vertices without the tip",
                        counts.left_vertices
                    )
                });
            }
            Err(e) => {
                first_failure.get_or_insert_with(|| e.to_string());
            }
        }
    }
    Err(format!(
        "no plane perpendicular to ±x, ±y or ±z cuts off a part of the mesh (along {} at \
         {:.0} %: {}); --axis and --plane choose the plane, --skip taper leaves the step out",
        axis_name(axis),
        100.0 * fraction,
        first_failure.unwrap_or_default()
    ))
}

/// The sub-mesh of an open mesh no plane section closes around: the vertices beyond a
/// plane perpendicular to an axis, reached from the vertex furthest along it without
/// crossing the plane, tried in the order of [`label_submesh`] (axes, then heights).
fn mask_submesh(mesh: &Mesh, axis: DVec3, fraction: f64) -> Result<(SubMesh, String), String> {
    let live = mesh.vertices().filter(|&v| !mesh.is_isolated(v)).count();
    for cut in cutting_planes(mesh, axis, fraction)? {
        let (a, tip, f, height) = (cut.axis, cut.tip, cut.fraction, cut.height);
        // Flood from the tip over the vertices beyond the plane.
        let mut inside = vec![false; mesh.vertex_slots()];
        let mut stack = vec![tip];
        inside[mesh.vertex_index(tip)] = true;
        let mut count = 1;
        while let Some(v) = stack.pop() {
            for w in mesh.adjacent_vertices(v) {
                let i = mesh.vertex_index(w);
                if !inside[i] && mesh.position(w).dot(a) >= height {
                    inside[i] = true;
                    count += 1;
                    stack.push(w);
                }
            }
        }
        if count < MIN_SUBMESH || live - count < MIN_SUBMESH {
            continue;
        }
        let mask = halfedge::VertexData::new(mesh, inside).map_err(|e| e.to_string())?;
        let sub = SubMesh::from_mask(mesh, &mask).map_err(|e| e.to_string())?;
        let detail = format!(
            "plane {} = {height:.3} ({:.0} % of the extent): the {count} vertices beyond \
                 it reached from the vertex furthest along {} (an open cut: vertex mask), \
                 the rest {}",
            axis_name(a),
            100.0 * f,
            axis_name(a),
            live - count
        );
        return Ok((sub, detail));
    }
    Err("no plane perpendicular to ±x, ±y or ±z has vertices beyond it".into())
}

/// The Lee rule of the module docs: an editing area around a front vertex, dragged along
/// its normal. Returns the table's detail and a note when the rule had to adapt.
fn lee_drag(
    hierarchy: &mut Hierarchy,
    diagonal: f64,
    large: bool,
) -> Result<(String, Option<String>), String> {
    let mesh = hierarchy.mesh();
    // The extreme vertices, then (`None`: found only if they all fail) the vertex
    // farthest from the boundary.
    let centres = picks::drag_candidates(mesh)
        .into_iter()
        .map(Some)
        .chain([None]);
    let n = mesh.n_vertices();
    let first_size = (n / 12).clamp(30, 5_000).min(n / 3).max(MIN_AREA);
    let mut first_failure: Option<String> = None;
    for (attempt, candidate) in centres.enumerate() {
        let Some((centre, what)) =
            candidate.or_else(|| picks::farthest_candidate(hierarchy.mesh()))
        else {
            continue;
        };
        let mut size = first_size;
        while size >= MIN_AREA {
            let mesh = hierarchy.mesh();
            let tried = EditingArea::disk_around(mesh, centre, size).and_then(|area| {
                let options = SessionOptions::default().with_scale(0.6);
                progress::step(large, "Lee: embedding the editing area", || {
                    AreaSession::new(mesh, area, &options)
                })
            });
            match tried {
                Ok(mut session) => {
                    let pull = mesh.vertex_normal(centre) * 0.15 * diagonal;
                    // The drag tells the hierarchy its area and the primitive's
                    // translation: refined back, the primitive lands on its target and
                    // nothing outside the area moves.
                    session
                        .set_primitive(hierarchy.mesh(), &[centre])
                        .and_then(|()| session.drag(hierarchy.mesh_mut(), pull))
                        .map_err(edit::Error::from)
                        .and_then(|()| session.mark(hierarchy))
                        .and_then(|()| Ok(session.commit(hierarchy.mesh())?))
                        .map_err(|e| e.to_string())?;
                    let mesh = hierarchy.mesh();
                    let detail = format!(
                        "area of {} vertices around v{} ({what}), pulled by {:.3} along its \
                         normal at s = 0.6",
                        session.area().vertices().len(),
                        mesh.vertex_index(centre),
                        pull.length()
                    );
                    let note = (attempt > 0 || size != first_size).then(|| {
                        format!(
                            "the Lee area of {first_size} vertices around the front vertex \
                             could not be used ({}); used {size} vertices around {what}",
                            first_failure.as_deref().unwrap_or("?")
                        )
                    });
                    return Ok((detail, note));
                }
                Err(e) => {
                    first_failure.get_or_insert_with(|| e.to_string());
                }
            }
            size /= 2;
        }
    }
    Err(format!(
        "no disk of {MIN_AREA} or more vertices around an extreme vertex or the vertex \
         farthest from the boundary is a valid editing area (first: {})",
        first_failure.unwrap_or_default()
    ))
}

/// Where the Bendels & Klein handle should land: its coarse vertex slots and the rigid
/// map the user gave it.
struct Landing {
    handle: Vec<u32>,
    map: glam::DAffine3,
}

/// The Bendels & Klein rule of the module docs: a handle around the vertex furthest
/// along −x of the hierarchy's current mesh, rotated and pulled, in the hierarchy
/// (`BlendSession::apply` and `HierarchyEdit::mark`: the handle lands exactly at full resolution, the
/// fixed part stays where it was). Returns the table's detail and a note when the radii
/// had to shrink.
fn blend_rotate(
    hierarchy: &mut Hierarchy,
    diagonal: f64,
    large: bool,
) -> Result<(String, Option<String>, Landing), String> {
    let mesh = hierarchy.mesh();
    let side = mesh
        .extreme_vertex(DVec3::NEG_X)
        .map_err(|e| e.to_string())?
        .ok_or("the mesh has no vertex with a face")?;
    // The same rule on the largest component, for a mesh whose extreme vertex is on a
    // small part (an eye, a loose piece) that the handle would cover whole.
    let mut sides = vec![(side, "the mesh")];
    let largest = mesh.select_largest_component();
    if let Some(v) = largest
        .extreme_vertex(mesh, DVec3::NEG_X)
        .map_err(|e| e.to_string())?
        .filter(|&v| v != side)
    {
        sides.push((v, "its largest component"));
    }
    let mut first_failure: Option<String> = None;
    for (k, &(side, whose)) in sides.iter().enumerate() {
        let centre = hierarchy.mesh().position(side);
        let side_index = hierarchy.mesh().vertex_index(side);
        for halvings in 0..4 {
            let scale = 0.5f64.powi(halvings);
            let (r_handle, r_fixed) = (0.08 * diagonal * scale, 0.3 * diagonal * scale);
            let attempt = (|| -> Result<(usize, usize, Landing), String> {
                let mesh = hierarchy.mesh();
                let handle = mesh
                    .select_edge_ball(&[side], r_handle)
                    .map_err(|e| e.to_string())?;
                let near = mesh
                    .select_edge_ball(&[side], r_fixed)
                    .map_err(|e| e.to_string())?;
                let fixed: Vec<VertexId> = mesh
                    .vertices()
                    .filter(|&v| !near.contains(mesh, v))
                    .collect();
                let regions = Regions::from_sets(mesh, &handle.vertices(mesh), &fixed)
                    .map_err(|e| e.to_string())?;
                let n_deformable = regions.deformable().len();
                let n_handle = regions.handle().len();
                let handle_slots: Vec<u32> = regions
                    .handle()
                    .iter()
                    .map(|&v| mesh.vertex_index(v) as u32)
                    .collect();
                let options = BlendOptions::default()
                    .with_distance(DistanceKind::Geodesic)
                    .with_shape(ShapeFunction::Smoothstep);
                let mut blend =
                    progress::step(large, "B&K: geodesic distances (fast marching)", || {
                        BlendSession::new(mesh, regions, options)
                    })
                    .map_err(|e| e.to_string())?;
                let rotation = DMat4::from_translation(centre)
                    * DMat4::from_axis_angle(DVec3::Z, 25f64.to_radians())
                    * DMat4::from_translation(-centre)
                    * DMat4::from_translation(-DVec3::X * 0.05 * diagonal * scale);
                blend
                    .apply(hierarchy.mesh_mut(), rotation)
                    .map_err(edit::Error::from)
                    .and_then(|()| blend.mark(hierarchy))
                    .map_err(|e| e.to_string())?;
                let landing = Landing {
                    handle: handle_slots,
                    map: glam::DAffine3::from_mat4(rotation),
                };
                Ok((n_handle, n_deformable, landing))
            })();
            match attempt {
                Ok((n_handle, n_deformable, landing)) => {
                    let detail = format!(
                        "handle of {n_handle} vertices within {r_handle:.3} of v{} (furthest \
                     along -x of {whose}) rotated 25° and pulled; {n_deformable} deformable \
                     vertices, fixed beyond {r_fixed:.3}",
                        side_index
                    );
                    let note = (k > 0 || halvings > 0).then(|| {
                        format!(
                            "the Bendels & Klein regions at 8 % / 30 % of the diagonal around the \
                         vertex furthest along -x could not be used ({}); used {:.1} % / \
                         {:.1} % around the one of {whose}",
                            first_failure.as_deref().unwrap_or("?"),
                            8.0 * scale,
                            30.0 * scale
                        )
                    });
                    return Ok((detail, note, landing));
                }
                Err(e) => {
                    first_failure.get_or_insert(e);
                }
            }
        }
    }
    Err(format!(
        "no handle and fixed region around the vertex furthest along -x of the mesh or of its \
         largest component work, down to 1 % / 3.75 % of the diagonal (first: {})",
        first_failure.unwrap_or_default()
    ))
}
