//! The whole multiresolution job from the command line: load → simplify to a level →
//! label a sub-mesh by a cutting plane → one edit of each family (a Lee 1999 area drag, a
//! Bendels & Klein handle rotation, a sub-mesh taper) → refine back with the centroid
//! detail coefficients → write the mesh and before/after pictures, with a summary table.
//!
//! ```text
//! cargo run --release --example workflow -- [FILE] [--level N] [--method rounds|qem] [--out DIR]
//! ```

#[path = "../support/progress.rs"]
mod progress;
mod render;

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Parser;
use edit::area::{EditingArea, EditingSession, SessionOptions};
use edit::blend::{BlendOptions, BlendSession, DistanceKind};
use edit::regions::Regions;
use edit::shape::ShapeFunction;
use edit::submesh::{Edit, Propagation, SubMesh, Variation};
use glam::{DMat4, DVec3};
use halfedge::{BuildProgress, Hierarchy, HierarchyOptions, Mesh, VertexId};

/// Command-line options.
#[derive(Parser, Debug)]
#[command(about = "simplify → edit → refine a mesh with multires")]
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
    /// Height of the cutting plane that labels the sub-mesh, as a fraction of the
    /// bounding box along y.
    #[arg(long, default_value_t = 0.72)]
    plane: f64,
    /// Picture size in pixels (width; height is 3/4 of it).
    #[arg(long, default_value_t = 640)]
    picture: usize,
}

struct Row {
    step: &'static str,
    detail: String,
    seconds: f64,
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> Result<(), Box<dyn std::error::Error>> {
    let path = args
        .mesh
        .clone()
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("data/blob.obj"));
    std::fs::create_dir_all(&args.out)?;
    let mut rows = Vec::new();

    let clock = Instant::now();
    let (input, report) = progress::read(&path)?;
    let large = progress::is_large(input.n_faces());
    progress::step(large, "checking the mesh", || input.check())?;
    rows.push(Row {
        step: "load",
        detail: format!(
            "{}: {} vertices, {} faces ({} duplicated vertices)",
            path.display(),
            input.n_vertices(),
            input.n_faces(),
            report.duplicated_vertices
        ),
        seconds: clock.elapsed().as_secs_f64(),
    });
    let original = input.clone();
    let frame = input.bounding_box().ok_or("the mesh has no vertices")?;

    // --- simplify ---------------------------------------------------------------
    let options = match args.method.as_str() {
        "rounds" => HierarchyOptions::rounds(),
        "qem" => HierarchyOptions::qem(),
        other => return Err(format!("unknown method {other:?} (rounds or qem)").into()),
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
    let level = args.level.min(hierarchy.coarsest_level());
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
    let (lo, hi) = frame;
    let point = DVec3::new(
        0.5 * (lo.x + hi.x),
        lo.y + args.plane * (hi.y - lo.y),
        0.5 * (lo.z + hi.z),
    );
    let mesh = hierarchy.mesh_mut();
    let frontier = mesh.frontier_from_plane(point, DVec3::Y)?;
    let (labels, counts) = mesh.label_sides(&frontier, 1, 2)?;
    hierarchy.attach_labels(labels);
    hierarchy.labels_defined_here();
    let mesh = hierarchy.mesh();
    let label_values = mesh.attribute_values(labels);
    let above = pick_side(mesh, label_values, point)?;
    let sub = SubMesh::from_labels(mesh, label_values, |&l| l == above)?;
    rows.push(Row {
        step: "label",
        detail: format!(
            "plane y = {:.3}: frontier of {} edges, sub-mesh above it {} vertices ({counts:?})",
            point.y,
            frontier.halfedges().len(),
            sub.vertex_indices().len()
        ),
        seconds: clock.elapsed().as_secs_f64(),
    });
    let coarse_before = hierarchy.mesh().clone();

    // --- Lee 1999: drag an editing area on the front ----------------------------
    let clock = Instant::now();
    let mesh = hierarchy.mesh_mut();
    let diagonal = lo.distance(hi);
    let front = extreme_vertex(mesh, DVec3::Z);
    let area_size = (mesh.n_vertices() / 12).clamp(30, 5_000);
    let area = EditingArea::disk_around(mesh, front, area_size)?;
    let options = SessionOptions {
        scale: 0.6,
        ..SessionOptions::default()
    };
    let mut session = progress::step(large, "Lee: embedding the editing area", || {
        EditingSession::new(mesh, area, &options)
    })?;
    session.set_primitive(mesh, &[front])?;
    let pull = mesh.vertex_normal(front) * 0.15 * diagonal;
    session.drag(mesh, pull)?;
    session.commit(mesh)?;
    rows.push(Row {
        step: "Lee drag",
        detail: format!(
            "area of {} vertices around v{}, pulled by {:.3} at s = 0.6",
            session.area().vertices().len(),
            mesh.vertex_index(front),
            pull.length()
        ),
        seconds: clock.elapsed().as_secs_f64(),
    });

    // --- Bendels & Klein: rotate a handle on the side ----------------------------
    let clock = Instant::now();
    let side = extreme_vertex(mesh, -DVec3::X);
    let centre = mesh.position(side);
    let handle = ring_picks(mesh, centre, 0.08 * diagonal, 6);
    let fixed = ring_picks(mesh, centre, 0.3 * diagonal, 10);
    let regions = Regions::from_picks(mesh, &handle, &fixed)?;
    let n_deformable = regions.deformable().len();
    let options = BlendOptions {
        distance: DistanceKind::Geodesic,
        shape: ShapeFunction::Smoothstep,
    };
    let mut blend = progress::step(large, "B&K: geodesic distances (fast marching)", || {
        BlendSession::new(mesh, regions, options)
    })?;
    let rotation = DMat4::from_translation(centre)
        * DMat4::from_axis_angle(DVec3::Z, 25f64.to_radians())
        * DMat4::from_translation(-centre)
        * DMat4::from_translation(-DVec3::X * 0.05 * diagonal);
    blend.apply(mesh, rotation)?;
    rows.push(Row {
        step: "B&K rotate",
        detail: format!(
            "handle around v{} rotated 25° and pulled, {n_deformable} deformable vertices",
            mesh.vertex_index(side)
        ),
        seconds: clock.elapsed().as_secs_f64(),
    });

    // --- sub-mesh taper above the plane -----------------------------------------
    let clock = Instant::now();
    let taper = Edit::Taper {
        axis: None,
        factor: 0.6,
        variation: Variation::Levels(None),
    };
    sub.apply(mesh, &taper, Propagation::linear(2))?;
    rows.push(Row {
        step: "taper",
        detail: "sub-mesh above the plane tapered to 0.6, 2 propagation levels".to_string(),
        seconds: clock.elapsed().as_secs_f64(),
    });
    mesh.check()?;
    let coarse_after = hierarchy.mesh().clone();

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
    let result = hierarchy.into_mesh();
    progress::step(large, "checking the result", || result.check())?;
    let moved = result
        .vertices()
        .filter(|&v| result.position(v) != original.position(v))
        .count();
    rows.push(Row {
        step: "refine",
        detail: format!(
            "back to {} vertices, {} faces; {moved} vertices moved, {} kept bit for bit",
            result.n_vertices(),
            result.n_faces(),
            result.n_vertices() - moved
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
    let view = render::View::default();
    let before = render::render(&original, view, frame, None, w, h);
    let colors = displacement_colors(&original, &result, diagonal);
    let after = render::render(&result, view, frame, Some(&colors), w, h);
    let coarse = render::render(&coarse_before, view, frame, None, w / 2, h / 2);
    let coarse_edit = render::render(&coarse_after, view, frame, None, w / 2, h / 2);
    before.save(&args.out.join("before.png"))?;
    after.save(&args.out.join("after.png"))?;
    render::Image::side_by_side(&[&before, &after]).save(&args.out.join("before-after.png"))?;
    render::Image::side_by_side(&[&coarse, &coarse_edit])
        .save(&args.out.join("coarse-edit.png"))?;
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
    Ok(())
}

/// The label of the side of the frontier that lies above the plane point.
fn pick_side(mesh: &Mesh, labels: &[u32], point: DVec3) -> Result<u32, Box<dyn std::error::Error>> {
    let top = mesh
        .vertices()
        .filter(|&v| labels[mesh.vertex_index(v)] != halfedge::FRONTIER && !mesh.is_isolated(v))
        .max_by(|&a, &b| mesh.position(a).y.total_cmp(&mesh.position(b).y))
        .ok_or("no labelled vertex")?;
    if mesh.position(top).y < point.y {
        return Err("the cutting plane is above the mesh".into());
    }
    Ok(labels[mesh.vertex_index(top)])
}

/// The non-isolated vertex furthest along `direction`.
fn extreme_vertex(mesh: &Mesh, direction: DVec3) -> VertexId {
    mesh.vertices()
        .filter(|&v| !mesh.is_isolated(v))
        .max_by(|&a, &b| {
            mesh.position(a)
                .dot(direction)
                .total_cmp(&mesh.position(b).dot(direction))
        })
        .expect("a mesh with faces")
}

/// `n` vertices at geodesic-ish distance `radius` around `centre`, spread in angle: the
/// picks of a closed border drawn around a point.
fn ring_picks(mesh: &Mesh, centre: DVec3, radius: f64, n: usize) -> Vec<VertexId> {
    let normal = mesh.vertex_normal(extreme_vertex(mesh, centre.normalize_or(DVec3::X)));
    let u = normal.any_orthonormal_vector();
    let w = normal.cross(u);
    let near: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| !mesh.is_isolated(v))
        .filter(|&v| (mesh.position(v).distance(centre) - radius).abs() < 0.2 * radius)
        .collect();
    let mut picks: Vec<VertexId> = (0..n)
        .filter_map(|k| {
            let t = k as f64 / n as f64 * std::f64::consts::TAU;
            let target = u * t.cos() + w * t.sin();
            near.iter().copied().max_by(|&a, &b| {
                let da = (mesh.position(a) - centre).normalize_or_zero().dot(target);
                let db = (mesh.position(b) - centre).normalize_or_zero().dot(target);
                da.total_cmp(&db)
            })
        })
        .collect();
    picks.dedup();
    picks
}

/// Clay for unmoved vertices, shading to orange with the displacement.
fn displacement_colors(before: &Mesh, after: &Mesh, diagonal: f64) -> Vec<DVec3> {
    let clay = DVec3::new(0.78, 0.74, 0.68);
    let hot = DVec3::new(0.95, 0.45, 0.15);
    (0..after.vertex_slots())
        .map(|i| match (before.positions().get(i), after.vertex_at(i)) {
            (Some(&p), Some(v)) => {
                let t = (after.position(v).distance(p) / (0.05 * diagonal)).min(1.0);
                clay.lerp(hot, t)
            }
            _ => clay,
        })
        .collect()
}
