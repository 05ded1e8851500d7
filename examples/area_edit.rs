//! Area editing after Lee 1999 (*Interactive multiresolution editing of arbitrary
//! meshes*): load a mesh, take a disk-shaped editing area around a vertex, drag the vertex
//! along its normal in a few steps as a user would, and write the result (OBJ or PLY, by
//! the output's extension).
//!
//! ```text
//! cargo run --release --example area_edit -- data/creature.obj --scale 0.25
//! ```
//!
//! Without a path, `data/blob.obj` is used. The dragged vertex is by default the one of
//! the largest component furthest along +z (the front of a mesh that looks along +z: the
//! creature's snout). Where the disk around it is not an editing area (it reaches the
//! boundary of an open mesh, wraps around a handle), the disk is halved down to 16
//! vertices, then the other extreme vertices and the vertex farthest from the boundary
//! are tried, and a note says what was used. A triangle soup or a mesh with seams is
//! welded first (`--weld`, as in the workflow; `--vertex` still names the file's vertex).

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Parser;

use edit::lee::{AreaSession, EditingArea, FrameKind, SessionOptions};
use halfedge::VertexId;
use multires::load::{self, Weld, WELD_HELP};
use multires::progress::Bars;
use multires::workflow::picks;

#[derive(Parser, Debug)]
#[command(about = "Drag a vertex with Lee 1999 area editing and write the result (OBJ or PLY)")]
struct Args {
    /// Mesh to edit (OBJ or PLY); default: data/blob.obj.
    mesh: Option<PathBuf>,
    /// Vertex to drag (file index); default: the vertex furthest along +z.
    #[arg(long)]
    vertex: Option<usize>,
    /// Approximate number of vertices of the editing area (grown in rings around the vertex).
    #[arg(long, default_value_t = 400)]
    area_vertices: usize,
    /// Scale parameter s in [0, 1]: 0 moves only the vertex, 1 the whole area.
    #[arg(long, default_value_t = 0.5)]
    scale: f64,
    /// Drag distance as a fraction of the bounding-box diagonal.
    #[arg(long, default_value_t = 0.05)]
    pull: f64,
    /// Local frames: "global" or "normal".
    #[arg(long, default_value = "global")]
    frames: String,
    /// Output mesh, OBJ or PLY by extension; default: area_edit.obj in the system's
    /// temporary folder.
    #[arg(long)]
    output: Option<PathBuf>,
    #[arg(long, default_value = "auto", value_parser = |s: &str| s.parse::<Weld>(), help = WELD_HELP)]
    weld: Weld,
}

fn default_mesh() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/blob.obj")
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> Result<(), Box<dyn std::error::Error>> {
    let path = args.mesh.unwrap_or_else(default_mesh);
    let t = Instant::now();
    let mut bars = Bars::new(load::is_large_file(&path));
    let load::Loaded {
        mut mesh, welding, ..
    } = load::load(&path, args.weld, &mut bars)?;
    println!(
        "loaded {} ({} vertices, {} faces) in {:.1?}",
        path.display(),
        mesh.n_vertices(),
        mesh.n_faces(),
        t.elapsed()
    );
    if let Some(welding) = &welding {
        println!("note: {}", welding.note);
    }
    // Where to drag: the given vertex, or the largest component's vertex furthest along
    // +z, then its other extreme vertices, then the vertex farthest from the boundary
    // (on an open mesh the extreme vertices are often on the boundary).
    let candidates: Vec<(VertexId, String)> = match args.vertex {
        Some(i) => {
            // The file's vertex `i`, where welding put it.
            let welded = match &welding {
                Some(w) => w.vertex_map.get(i).map(|&j| j as usize),
                None => Some(i),
            };
            let vertex = welded.and_then(|j| mesh.vertex_at(j)).ok_or_else(|| {
                format!(
                    "vertex {i} does not exist (the file has {} vertices)",
                    welding
                        .as_ref()
                        .map_or(mesh.vertex_slots(), |w| w.vertex_map.len())
                )
            })?;
            vec![(vertex, format!("vertex {i}"))]
        }
        None => {
            let mut list = picks::drag_candidates(&mesh);
            list.extend(picks::farthest_candidate(&mesh));
            if list.is_empty() {
                return Err("the mesh has no vertex with a face to drag".into());
            }
            list
        }
    };
    let frames_of = |vertex: VertexId| match args.frames.as_str() {
        "global" => Ok(FrameKind::Global),
        "normal" => Ok(FrameKind::Normal {
            seed: Some(vertex),
            x_axis: None,
        }),
        other => Err(format!("unknown frames {other:?} (global or normal)")),
    };
    frames_of(candidates[0].0)?;

    // The first disk around a candidate that is an editing area (a disk inside the mesh
    // whose embedding works), halving the area down to 16 vertices before moving on.
    let t = Instant::now();
    let mut first_failure: Option<String> = None;
    let mut chosen = None;
    'candidates: for (vertex, what) in &candidates {
        let mut size = args.area_vertices;
        while size >= 16.min(args.area_vertices) {
            let options = SessionOptions::default()
                .with_frames(frames_of(*vertex)?)
                .with_scale(args.scale);
            match EditingArea::disk_around(&mesh, *vertex, size)
                .and_then(|area| AreaSession::new(&mesh, area, &options))
            {
                Ok(session) => {
                    chosen = Some((*vertex, what.clone(), size, session));
                    break 'candidates;
                }
                Err(e) => {
                    first_failure.get_or_insert_with(|| e.to_string());
                }
            }
            if size == 0 {
                break;
            }
            size /= 2;
        }
    }
    let Some((vertex, what, size, mut session)) = chosen else {
        return Err(format!(
            "{}: the editing area must be a disk inside the mesh; pick another --vertex or \
             a smaller --area-vertices",
            first_failure.unwrap_or_default()
        )
        .into());
    };
    if let Some(why) = first_failure {
        println!(
            "note: the area of {} vertices around {} could not be used ({why}); used {size} \
             vertices around {what} (--vertex, --area-vertices)",
            args.area_vertices, candidates[0].1
        );
    }
    println!(
        "editing area: {} vertices ({} interior), {} faces; selected and embedded in \
         {:.1?} ({:?}, {} flipped triangles), {} B-spline levels",
        session.area().vertices().len(),
        session.area().n_interior(),
        session.area().faces().len(),
        t.elapsed(),
        session.embedding().solver(),
        session.embedding().flipped_faces().len(),
        session.levels()
    );

    session.set_primitive(&mesh, &[vertex])?;
    let (lo, hi) = mesh.bounding_box().ok_or("empty mesh")?;
    let direction = mesh.vertex_normal(vertex);
    let distance = args.pull * (hi - lo).length();
    let steps = 30;
    let mut times = Vec::with_capacity(steps);
    for k in 1..=steps {
        let t = Instant::now();
        session.drag(&mut mesh, direction * (distance * k as f64 / steps as f64))?;
        times.push(t.elapsed());
    }
    session.commit(&mesh)?;
    let mean = times.iter().sum::<std::time::Duration>() / steps as u32;
    let max = times.iter().max().copied().unwrap_or_default();
    let moved = session.area().n_interior();
    println!(
        "dragged vertex {} by {distance:.4} along its normal in {steps} steps at s = {}: \
         {mean:.1?} per drag (max {max:.1?}) over {moved} interior vertices",
        mesh.vertex_index(vertex),
        args.scale
    );

    let output = args
        .output
        .unwrap_or_else(|| std::env::temp_dir().join("area_edit.obj"));
    let t = Instant::now();
    halfedge::io::write(&output, &mesh)?;
    println!("wrote {} in {:.1?}", output.display(), t.elapsed());
    Ok(())
}
