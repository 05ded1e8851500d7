//! Saving the edited mesh through the kernel's writers (`halfedge::io::write`: `.obj`,
//! `.ply` as binary little endian with double positions, so positions are kept bit for bit).

use std::path::Path;

use halfedge::Mesh;

/// Why a mesh could not be saved.
#[derive(Debug, thiserror::Error)]
pub enum SaveError {
    /// The file extension names no format the viewer can write.
    #[error("{0}: cannot write this format (the viewer writes .obj and .ply)")]
    UnsupportedFormat(String),
    /// Writing failed (the kernel's error names the file).
    #[error(transparent)]
    Mesh(#[from] halfedge::Error),
}

/// Writes `mesh` to `path`, choosing the format by extension (`.obj`, `.ply`).
pub fn save(mesh: &Mesh, path: &Path) -> Result<(), SaveError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("obj" | "ply") => Ok(halfedge::io::write(path, mesh)?),
        _ => Err(SaveError::UnsupportedFormat(path.display().to_string())),
    }
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
