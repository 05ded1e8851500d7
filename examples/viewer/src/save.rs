//! Saving the edited mesh.
//!
//! TODO(io): replace [`write_obj`] by `halfedge::io::write_obj` / `halfedge::io::write`
//! (OBJ and PLY) when the IO branch is merged; this local writer exists only because the
//! kernel cannot write files on this branch yet.

use std::io::Write;
use std::path::Path;

use halfedge::Mesh;

/// Why a mesh could not be saved.
#[derive(Debug, thiserror::Error)]
pub enum SaveError {
    /// The file extension names no format the viewer can write.
    #[error("{0}: cannot write this format (the viewer writes .obj)")]
    UnsupportedFormat(String),
    /// Writing failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The underlying error.
        source: std::io::Error,
    },
}

/// Writes `mesh` to `path`, choosing the format by extension (`.obj`).
pub fn save(mesh: &Mesh, path: &Path) -> Result<(), SaveError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("obj") => write_obj(mesh, path),
        _ => Err(SaveError::UnsupportedFormat(path.display().to_string())),
    }
}

/// Writes a Wavefront OBJ: the live vertices in `vertex_index` order (so a mesh read from
/// a file and edited keeps its vertex numbering when it has no removed vertices), then
/// the faces as triangles with 1-based indices. Positions use Rust's shortest
/// round-trip formatting, so reading the file back gives the same `f64`s.
///
/// Local stand-in for `halfedge::io::write_obj` (see the module docs).
pub fn write_obj(mesh: &Mesh, path: &Path) -> Result<(), SaveError> {
    let io_err = |source| SaveError::Io {
        path: path.display().to_string(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io_err)?;
    let mut out = std::io::BufWriter::new(file);
    write_obj_to(mesh, &mut out).map_err(io_err)?;
    out.flush().map_err(io_err)
}

/// Writes the OBJ text of `mesh` to any writer (see [`write_obj`]).
pub fn write_obj_to(mesh: &Mesh, out: &mut impl Write) -> std::io::Result<()> {
    writeln!(
        out,
        "# multires viewer: {} vertices, {} faces",
        mesh.n_vertices(),
        mesh.n_faces()
    )?;
    let mut number = vec![0u32; mesh.vertex_slots()];
    for (k, v) in (1u32..).zip(mesh.vertices()) {
        let p = mesh.position(v);
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
        number[mesh.vertex_index(v)] = k;
    }
    for f in mesh.faces() {
        let [a, b, c] = mesh.triangle(f).map(|v| number[mesh.vertex_index(v)]);
        writeln!(out, "f {a} {b} {c}")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use halfedge::generators;

    #[test]
    fn obj_round_trip_keeps_positions_bit_for_bit() {
        let mut mesh = generators::icosphere(2);
        mesh.positions_mut()[5] *= 1.0 + 1e-13;
        let dir = std::env::temp_dir().join(format!("viewer-save-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("sphere.obj");
        save(&mesh, &path).unwrap();
        let (back, report) = halfedge::io::read(&path).unwrap();
        assert_eq!(report.duplicated_vertices, 0);
        assert_eq!(back.n_vertices(), mesh.n_vertices());
        assert_eq!(back.n_faces(), mesh.n_faces());
        assert_eq!(back.positions(), mesh.positions());
        back.check().unwrap();
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn unknown_extension_is_an_error() {
        let mesh = generators::icosphere(0);
        let err = save(&mesh, Path::new("/tmp/x.stl")).unwrap_err();
        assert!(matches!(err, SaveError::UnsupportedFormat(_)));
    }
}
