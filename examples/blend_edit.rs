//! Bendels & Klein editing with precisely specified regions, from the command line.
//!
//! ```text
//! cargo run --release --example blend_edit -- data/blob.obj --out blob-edited.obj --angle 35
//! ```
//!
//! Picks the extreme vertex of the mesh's largest component along `--direction`
//! (default −x: the nose of a mesh that looks along −x, as the Stanford bunny does),
//! draws the handle border and the fixed border as closed loops through vertices
//! picked around it (radii `--handle-radius` and `--fixed-radius`, as fractions of the
//! bounding-box diagonal; halved twice at most where the loops do not close and nest,
//! then edge-path balls around the vertex instead, then rings of edges around it, with a
//! note), rotates the handle by `--angle` degrees about an axis through
//! the fixed border's centre (then moves it by `--pull`), refines stretched triangles,
//! writes the mesh (OBJ or PLY, by extension) and prints the timings of each step. A
//! triangle soup or a mesh with seams is welded first (`--weld`, as in the workflow).

use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;

use edit::bendels_klein::Regions;
use edit::bendels_klein::ShapeFunction;
use edit::bendels_klein::{BlendOptions, BlendSession, DistanceKind, RefineOptions};
use glam::{DMat4, DVec3};
use halfedge::selection::Selection;
use halfedge::{Mesh, VertexId};
use multires::load::{self, Weld, WELD_HELP};
use multires::progress::{self, Bars, LARGE_FACES};

#[derive(Parser, Debug)]
#[command(
    about = "Bendels & Klein editing: pick regions around an extreme vertex, rotate the handle, \
             write the mesh (OBJ or PLY)"
)]
struct Args {
    /// Input mesh (OBJ or PLY).
    mesh: PathBuf,
    /// Output mesh, OBJ or PLY by extension.
    #[arg(long, default_value = "blend_edit.obj")]
    out: PathBuf,
    /// Direction whose extreme vertex is the centre of the edit, "x,y,z" (default −x).
    #[arg(long, default_value = "-1,0,0", value_parser = parse_vec)]
    direction: DVec3,
    /// Handle border radius, as a fraction of the bounding-box diagonal.
    #[arg(long, default_value_t = 0.04)]
    handle_radius: f64,
    /// Fixed border radius, as a fraction of the bounding-box diagonal.
    #[arg(long, default_value_t = 0.14)]
    fixed_radius: f64,
    /// Rotation of the handle in degrees.
    #[arg(long, default_value_t = 30.0)]
    angle: f64,
    /// Translation applied after the rotation, "x,y,z".
    #[arg(long, default_value = "0,0,0", value_parser = parse_vec)]
    pull: DVec3,
    /// Euclidean instead of geodesic distances.
    #[arg(long)]
    euclidean: bool,
    /// Refine edges longer than this multiple of the mean edge length (0: no refinement).
    #[arg(long, default_value_t = 2.0)]
    refine: f64,
    #[arg(long, default_value = "auto", value_parser = |s: &str| s.parse::<Weld>(), help = WELD_HELP)]
    weld: Weld,
}

fn parse_vec(s: &str) -> Result<DVec3, String> {
    let parts: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>().map_err(|e| e.to_string()))
        .collect::<Result<_, _>>()?;
    match parts[..] {
        [x, y, z] => Ok(DVec3::new(x, y, z)),
        _ => Err(format!("expected x,y,z, got {s:?}")),
    }
}

/// Vertices of `part` at distance ≈ `radius` from `centre`, one per direction around
/// `axis`.
fn picks_around(
    mesh: &Mesh,
    part: &Selection,
    centre: DVec3,
    axis: DVec3,
    radius: f64,
    n: usize,
) -> Vec<VertexId> {
    let u = axis.any_orthonormal_vector();
    let w = axis.cross(u);
    let candidates: Vec<VertexId> = part
        .vertices(mesh)
        .into_iter()
        .filter(|&v| !mesh.is_isolated(v))
        .filter(|&v| (mesh.position(v).distance(centre) - radius).abs() < 0.15 * radius)
        .collect();
    (0..n)
        .filter_map(|k| {
            let t = k as f64 / n as f64 * std::f64::consts::TAU;
            let target = u * t.cos() + w * t.sin();
            candidates.iter().copied().max_by(|&a, &b| {
                let da = (mesh.position(a) - centre).normalize().dot(target);
                let db = (mesh.position(b) - centre).normalize().dot(target);
                da.total_cmp(&db)
            })
        })
        .collect()
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> Result<(), Box<dyn std::error::Error>> {
    let clock = Instant::now();
    let mut bars = Bars::new(load::is_large_file(&args.mesh));
    let load::Loaded {
        mut mesh, welding, ..
    } = load::load(&args.mesh, args.weld, &mut bars)?;
    bars.set_shown(mesh.n_faces() > LARGE_FACES);
    println!(
        "loaded {} vertices, {} faces in {:.3} s",
        mesh.n_vertices(),
        mesh.n_faces(),
        clock.elapsed().as_secs_f64()
    );
    if let Some(welding) = welding {
        println!("note: {}", welding.note);
    }
    let (lo, hi) = mesh.bounding_box().ok_or("empty mesh")?;
    let diagonal = lo.distance(hi);
    let direction = args
        .direction
        .try_normalize()
        .ok_or("--direction must be a non-zero vector")?;
    // The edit goes on the largest component (not on a loose part further out).
    let largest = mesh.select_largest_component();
    let tip = largest
        .extreme_vertex(&mesh, direction)?
        .ok_or("the mesh has no vertex with a face")?;
    let centre = mesh.position(tip);

    // The paper's regions: two loops drawn around the tip through picked vertices. Where
    // they do not close and nest at the given radii (a thin or open part), both radii are
    // halved (twice at most); where that fails too, the regions are edge-path balls
    // around the tip (handle within the handle radius, fixed beyond the fixed radius).
    let clock = Instant::now();
    let mut first_failure: Option<String> = None;
    let mut regions = None;
    for halvings in 0..3 {
        let scale = 0.5f64.powi(halvings);
        let (rh, rf) = (args.handle_radius * scale, args.fixed_radius * scale);
        let handle = picks_around(&mesh, &largest, centre, direction, rh * diagonal, 6);
        let fixed = picks_around(&mesh, &largest, centre, direction, rf * diagonal, 12);
        match Regions::from_picks(&mesh, &handle, &fixed) {
            Ok(r) => {
                regions = Some((
                    r,
                    format!("loops through {} + {} picks", handle.len(), fixed.len()),
                    halvings > 0,
                    rh,
                    rf,
                ));
                break;
            }
            Err(e) => {
                first_failure.get_or_insert_with(|| e.to_string());
            }
        }
    }
    // The regions of a handle and of everything beyond `near`, when they leave a
    // deformable band between them.
    let banded = |handle: &Selection, near: &Selection| -> Option<Regions> {
        let fixed: Vec<VertexId> = mesh
            .vertices()
            .filter(|&v| !near.contains(&mesh, v))
            .collect();
        Regions::from_sets(&mesh, &handle.vertices(&mesh), &fixed)
            .ok()
            .filter(|r| !r.deformable().is_empty())
    };
    if regions.is_none() {
        for halvings in 0..4 {
            let scale = 0.5f64.powi(halvings);
            let (rh, rf) = (args.handle_radius * scale, args.fixed_radius * scale);
            let handle = mesh.select_edge_ball(&[tip], rh * diagonal)?;
            let near = mesh.select_edge_ball(&[tip], rf * diagonal)?;
            if let Some(r) = banded(&handle, &near) {
                regions = Some((r, "edge-path balls".to_string(), true, rh, rf));
                break;
            }
        }
    }
    if regions.is_none() {
        // Edges longer than the radii (a long cylinder's, a CAD part's) put a handle
        // vertex beside a fixed one in every ball: rings of edges around the tip instead.
        for (handle_rings, fixed_rings) in [(1, 4), (0, 3), (0, 2)] {
            let mut handle = Selection::from_vertices(&mesh, &[tip])?;
            handle.grow(&mesh, handle_rings)?;
            let mut near = Selection::from_vertices(&mesh, &[tip])?;
            near.grow(&mesh, fixed_rings)?;
            if let Some(r) = banded(&handle, &near) {
                let how = format!(
                    "the tip and {handle_rings} ring(s) around it, fixed beyond {fixed_rings} \
                     rings"
                );
                regions = Some((r, how, true, 0.0, 0.0));
                break;
            }
        }
    }
    let Some((regions, how, adapted, rh, rf)) = regions else {
        return Err(format!(
            "{}: the loops drawn at --handle-radius and --fixed-radius around the extreme \
             vertex must be closed and nested; try other radii or another --direction",
            first_failure.unwrap_or_default()
        )
        .into());
    };
    if adapted {
        println!(
            "note: the loops at {} / {} of the diagonal could not be used ({}); used {how}{} \
             (--handle-radius, --fixed-radius, --direction)",
            args.handle_radius,
            args.fixed_radius,
            first_failure.as_deref().unwrap_or("?"),
            if rh > 0.0 {
                format!(" at {rh:.4} / {rf:.4}")
            } else {
                String::new()
            }
        );
    }
    println!(
        "regions ({how}) in {:.3} s: handle {}, deformable {}, fixed {}",
        clock.elapsed().as_secs_f64(),
        regions.handle().len(),
        regions.deformable().len(),
        regions.n_fixed()
    );

    let border = &regions.fixed_border().vertices;
    let pivot = border.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / border.len() as f64;
    let axis = direction.any_orthonormal_vector();
    let a = DMat4::from_translation(pivot + args.pull)
        * DMat4::from_axis_angle(axis, args.angle.to_radians())
        * DMat4::from_translation(-pivot);

    let clock = Instant::now();
    let options = BlendOptions::default()
        .with_distance(if args.euclidean {
            DistanceKind::Euclidean
        } else {
            DistanceKind::Geodesic
        })
        .with_shape(ShapeFunction::Smoothstep);
    let distances = if args.euclidean {
        "Euclidean distances (grid)"
    } else {
        "geodesic distances (fast marching)"
    };
    let mut session = progress::step(&mut bars, distances, || {
        BlendSession::new(&mesh, regions, options)
    })?;
    println!(
        "distance fields ({:?}) in {:.3} s",
        session.distance_kind(),
        clock.elapsed().as_secs_f64()
    );

    let clock = Instant::now();
    session.apply(&mut mesh, a)?;
    let elapsed = clock.elapsed().as_secs_f64();
    println!(
        "edit (log once, exp per vertex) in {:.3} ms, {:.3} µs per deformable vertex",
        elapsed * 1e3,
        elapsed * 1e6 / session.regions().deformable().len().max(1) as f64
    );

    if args.refine > 0.0 {
        let clock = Instant::now();
        let max = args.refine * mesh.mean_edge_length();
        let report = progress::step(&mut bars, "adaptive refinement", || {
            session.refine(&mut mesh, RefineOptions::new(max))
        })?;
        println!(
            "refinement in {:.3} s: {} new vertices in {} passes, longest edge now {:.3e}",
            clock.elapsed().as_secs_f64(),
            report.new_vertices,
            report.passes,
            report.longest_edge
        );
        mesh.check()?;
    }

    let clock = Instant::now();
    progress::step(
        &mut bars,
        &format!("writing {}", args.out.display()),
        || halfedge::io::write(&args.out, &mesh),
    )?;
    println!(
        "wrote {} in {:.3} s",
        args.out.display(),
        clock.elapsed().as_secs_f64()
    );
    Ok(())
}
