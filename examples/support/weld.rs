//! `--weld` of the examples (included with `#[path]`, beside `progress.rs`): a mesh
//! written as a triangle soup or with seams (faces on their own copies of vertices at
//! the same place, as many exporters write UV or normal seams) falls apart into pieces
//! that no editing region can span, so it is welded before the job.

#![allow(dead_code)] // each example uses part of it

use halfedge::{BuildReport, Mesh};

use crate::progress;

/// What `--weld` asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Weld {
    /// Vertices at exactly the same position, when merging them closes boundaries
    /// ([`Mesh::welded_seams`]).
    Auto,
    /// None: the file's vertices.
    Off,
    /// Vertices within this fraction of the bounding-box diagonal ([`Mesh::welded`]).
    Within(f64),
}

/// The `--weld` help text.
pub const HELP: &str = "Welding of vertices at the same place before the job: `auto` merges \
    vertices at exactly the same position when that closes boundaries (a triangle soup, \
    seams of an export), `off` keeps the file's vertices, a number F merges vertices within \
    F times the bounding-box diagonal";

/// Parses `auto`, `off` or a finite, non-negative fraction of the diagonal.
pub fn parse(s: &str) -> Result<Weld, String> {
    match s {
        "auto" => Ok(Weld::Auto),
        "off" => Ok(Weld::Off),
        other => match other.parse::<f64>() {
            Ok(f) if f.is_finite() && f >= 0.0 => Ok(Weld::Within(f)),
            _ => Err(format!(
                "expected auto, off or a fraction of the diagonal (finite, not negative), got {other:?}"
            )),
        },
    }
}

/// What a welding merged.
pub struct Welding {
    /// Says what was merged (the output numbers vertices as the welded mesh).
    pub note: String,
    /// For every vertex of the file, its index in the welded mesh.
    pub vertex_map: Vec<u32>,
}

/// `input` welded as `weld` asks, with its build report and, when anything was merged,
/// what. `large` shows a spinner.
pub fn apply(
    input: Mesh,
    report: BuildReport,
    weld: Weld,
    large: bool,
) -> Result<(Mesh, BuildReport, Option<Welding>), Box<dyn std::error::Error>> {
    let loops = |mesh: &Mesh| mesh.boundary_loops().len();
    let (tolerance, welded) = match weld {
        Weld::Off => return Ok((input, report, None)),
        Weld::Auto => (
            0.0,
            progress::step(large, "welding", || input.welded_seams())?,
        ),
        Weld::Within(fraction) => {
            let (lo, hi) = input.bounding_box().ok_or("the mesh has no vertices")?;
            let tolerance = fraction * lo.distance(hi);
            let welded = progress::step(large, "welding", || input.welded(tolerance))?;
            (
                tolerance,
                Some(welded).filter(|(_, w)| w.merged_vertices > 0),
            )
        }
    };
    let Some((welded, welding)) = welded else {
        return Ok((input, report, None));
    };
    let note = format!(
        "welded {} vertices onto others at {} ({} faces dropped as thinner than that; \
         boundary loops {} -> {}): the output numbers vertices as the welded mesh \
         (--weld off keeps the file's vertices)",
        welding.merged_vertices,
        if tolerance == 0.0 {
            "exactly the same position".to_string()
        } else {
            format!("a distance of at most {tolerance:.3e}")
        },
        welding.collapsed_faces,
        loops(&input),
        loops(&welded),
    );
    Ok((
        welded,
        welding.build,
        Some(Welding {
            note,
            vertex_map: welding.vertex_map,
        }),
    ))
}
