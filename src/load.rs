//! Reading a mesh as the tools read it: any format the kernel reads
//! ([`halfedge::io::read`]: OBJ, PLY, OFF, STL, gzip-compressed), then welding vertices at
//! the same place by a [`Weld`] policy, so that a triangle soup or a mesh cut along seams
//! (faces on their own copies of vertices at one place, as many exporters write UV or
//! normal seams) is edited as the surface it is.

use std::path::Path;

use halfedge::{BuildReport, Mesh};

use crate::error::{Error, Result};
use crate::progress::{self, Progress};

/// How vertices at the same place are welded after reading.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Weld {
    /// Vertices at exactly the same position are merged when that closes boundaries
    /// ([`Mesh::welded_seams`]); the default.
    #[default]
    Auto,
    /// None: the file's vertices.
    Off,
    /// Vertices within this fraction of the bounding-box diagonal ([`Mesh::welded`]).
    Within(f64),
}

/// The help text of a `--weld` option (the command line and the examples use it).
pub const WELD_HELP: &str = "Welding of vertices at the same place before the job: `auto` \
    merges vertices at exactly the same position when that closes boundaries (a triangle \
    soup, seams of an export), `off` keeps the file's vertices, a number F merges vertices \
    within F times the bounding-box diagonal";

impl std::str::FromStr for Weld {
    type Err = String;

    /// Parses `auto`, `off` or a finite, non-negative fraction of the diagonal.
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s.trim() {
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
}

/// What a welding merged.
#[derive(Clone, Debug)]
pub struct Welding {
    /// Says what was merged (the output numbers vertices as the welded mesh).
    pub note: String,
    /// For every vertex of the file, its index in the welded mesh.
    pub vertex_map: Vec<u32>,
    /// Vertices merged onto others.
    pub merged_vertices: usize,
}

/// A mesh read and welded, with what the reader and the welding did.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The mesh (welded, when [`welding`](Self::welding) says so).
    pub mesh: Mesh,
    /// What the builder did (duplicated vertices, dropped faces, corners merged by an STL
    /// reader), for the welded mesh when it was welded.
    pub build: BuildReport,
    /// What the welding merged, when it merged anything.
    pub welding: Option<Welding>,
}

/// Reads `path` and welds it as `weld` asks; the reading and the welding are steps of
/// `progress`.
///
/// # Errors
/// The reader's errors ([`Error::Mesh`], naming the file and the place); a welding
/// tolerance on a mesh without vertices.
pub fn load(path: &Path, weld: Weld, progress: &mut dyn Progress) -> Result<Loaded> {
    let (mesh, build) = progress::step(progress, &format!("loading {}", path.display()), || {
        halfedge::io::read(path)
    })?;
    apply_weld(mesh, build, weld, progress)
}

/// Welds `mesh` (read with report `build`) as `weld` asks.
///
/// # Errors
/// [`Error::Mesh`] from the welding (a non-finite tolerance cannot happen: [`Weld`]
/// parses finite fractions only); [`Error::NoVertices`] for a tolerance on an empty mesh.
pub fn apply_weld(
    mesh: Mesh,
    build: BuildReport,
    weld: Weld,
    progress: &mut dyn Progress,
) -> Result<Loaded> {
    let unwelded = |mesh, build| Loaded {
        mesh,
        build,
        welding: None,
    };
    let (tolerance, welded) = match weld {
        Weld::Off => return Ok(unwelded(mesh, build)),
        Weld::Auto => (
            0.0,
            progress::step(progress, "welding", || mesh.welded_seams())?,
        ),
        Weld::Within(fraction) => {
            let (lo, hi) = mesh.bounding_box().ok_or(Error::NoVertices)?;
            let tolerance = fraction * lo.distance(hi);
            let welded = progress::step(progress, "welding", || mesh.welded(tolerance))?;
            (
                tolerance,
                Some(welded).filter(|(_, w)| w.merged_vertices > 0),
            )
        }
    };
    let Some((welded, welding)) = welded else {
        return Ok(unwelded(mesh, build));
    };
    let loops = |mesh: &Mesh| mesh.boundary_loops().len();
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
        loops(&mesh),
        loops(&welded),
    );
    Ok(Loaded {
        mesh: welded,
        build: welding.build,
        welding: Some(Welding {
            note,
            vertex_map: welding.vertex_map,
            merged_vertices: welding.merged_vertices,
        }),
    })
}

/// True when a file of this size deserves a spinner while it loads.
#[must_use]
pub fn is_large_file(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| m.len() > progress::LARGE_FILE_BYTES)
}
