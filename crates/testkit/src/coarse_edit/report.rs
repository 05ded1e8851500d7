//! [`Report`]: what one measurement found, the four targets and the example's JSON.

use halfedge::hierarchy::{DetailMode, Method};

use super::EditKind;

/// What one measurement found (see the example's module docs for each field).
#[derive(Clone, Debug)]
pub struct Report {
    /// The edit.
    pub edit: EditKind,
    /// The edited level.
    pub level: usize,
    /// Simplification method.
    pub method: Method,
    /// Detail mode.
    pub detail: DetailMode,
    /// Input face count.
    pub faces: usize,
    /// Face count at the edited level.
    pub level_faces: usize,
    /// The tip (a vertex index, live at the edited level and at level 0).
    pub tip: usize,
    /// Vertices of the region at the edited level and at level 0 (the edit's own
    /// region: sub-mesh, Lee area interior, B&K handle ∪ deformable, FFD attached).
    pub region_vertices: [usize; 2],
    /// Faces flipped against the input by the coarse edit refined back.
    pub flips_coarse_path: usize,
    /// Faces flipped against the input by the same edit made at full resolution.
    pub flips_full_res: usize,
    /// Fine vertices outside the edit's coarse region that moved at all.
    pub outside_moved: usize,
    /// Largest distance of a rigidly or affinely moved fine vertex from its target,
    /// divided by the diagonal; `None` without a rigid part.
    pub handle_error: Option<f64>,
    /// Fine vertices measured by `handle_error`.
    pub handle_vertices: usize,
    /// RMS distance between the two results over all vertices, divided by the diagonal.
    pub rms_vs_full_res: f64,
    /// Largest distance between the two results, divided by the diagonal.
    pub max_vs_full_res: f64,
    /// Seconds to refine the edited hierarchy back to level 0.
    pub refine_seconds: f64,
    /// Seconds to build the hierarchy (from [`Prepared`](super::Prepared)).
    pub build_seconds: f64,
    /// Affine marks given to the hierarchy (0 in translation mode).
    pub marks: usize,
    /// The factor the edit's magnitudes were multiplied by (the `--amount`, halved while
    /// a smooth edit turned a face of the coarse mesh over).
    pub amount: f64,
    /// Faces of the coarse mesh the coarse edit turned over.
    pub coarse_flips: usize,
    /// Input vertices that moved at all: refined back from the coarse edit, and edited at
    /// full resolution.
    pub moved: [usize; 2],
}

impl Report {
    /// True when the four targets of the example hold: nothing outside moved, the rigid
    /// parts landed within 1e-9 of the diagonal, no more flips than at full resolution,
    /// and the RMS distance to the full-resolution edit is at most 1 % of the diagonal.
    pub fn meets_targets(&self) -> bool {
        self.region_is_exact() && self.handles_land() && self.no_extra_flips() && self.is_close()
    }

    /// `outside_moved` = 0.
    pub fn region_is_exact(&self) -> bool {
        self.outside_moved == 0
    }

    /// `handle_error` ≤ 1e-9 (or no rigid part).
    pub fn handles_land(&self) -> bool {
        self.handle_error.is_none_or(|e| e <= 1e-9)
    }

    /// `flips_coarse_path` ≤ `flips_full_res`.
    pub fn no_extra_flips(&self) -> bool {
        self.flips_coarse_path <= self.flips_full_res
    }

    /// `rms_vs_full_res` ≤ 0.01.
    pub fn is_close(&self) -> bool {
        self.rms_vs_full_res <= 0.01
    }

    /// The JSON object the example prints.
    pub fn to_json(&self, mesh: &str) -> serde_json::Value {
        serde_json::json!({
            "mesh": mesh,
            "edit": self.edit.name(),
            "level": self.level,
            "method": match self.method { Method::Rounds => "rounds", Method::Qem => "qem" },
            "detail": match self.detail {
                DetailMode::LocalFrame => "local",
                DetailMode::Translation => "translation",
            },
            "faces": self.faces,
            "level_faces": self.level_faces,
            "tip": self.tip,
            "region_vertices_coarse": self.region_vertices[0],
            "region_vertices_fine": self.region_vertices[1],
            "flips_coarse_path": self.flips_coarse_path,
            "flips_full_res": self.flips_full_res,
            "outside_moved": self.outside_moved,
            "handle_error": self.handle_error,
            "handle_vertices": self.handle_vertices,
            "rms_vs_full_res": self.rms_vs_full_res,
            "max_vs_full_res": self.max_vs_full_res,
            "refine_seconds": self.refine_seconds,
            "build_seconds": self.build_seconds,
            "marks": self.marks,
            "amount": self.amount,
            "coarse_flips": self.coarse_flips,
            "moved_coarse_path": self.moved[0],
            "moved_full_res": self.moved[1],
            "meets_targets": self.meets_targets(),
        })
    }
}
