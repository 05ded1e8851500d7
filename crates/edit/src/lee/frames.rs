//! Local frames of an editing area (Lee 1999, §3.4–3.5).

use glam::{DMat3, DVec3};
use halfedge::{Mesh, VertexId};
use rayon::prelude::*;

use crate::lee::area::EditingArea;
use crate::lee::error::{LeeError, Result};

/// The kind of local frames.
///
/// Paper: Lee 1999, *Interactive multiresolution editing of arbitrary meshes* §3.4–3.5.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum FrameKind {
    /// The mesh's global frame at every vertex (Lee 1999's first option).
    #[default]
    Global,
    /// Normal-based frames (Lee 1999's second option): the seed's frame rotated minimally
    /// onto each vertex normal.
    Normal {
        /// The seed vertex (in the area); `None`: the interior vertex embedded nearest to
        /// the rectangle's centre.
        seed: Option<VertexId>,
        /// Direction of the seed's `x` axis, projected onto the seed's tangent plane;
        /// `None` (or a direction along the normal): any orthonormal pair.
        x_axis: Option<DVec3>,
    },
}

/// Local frames of the editing area's vertices (Lee 1999, §3.4–3.5).
///
/// A frame `(x, y, n)` turns a displacement `Δp` into the offset
/// `Δd = (x·Δp, y·Δp, n·Δp)` (eq. 1) and an interpolated offset back into the update
/// `p_new = p_old + Δd_x x + Δd_y y + Δd_n n`. Either every vertex uses the global frame,
/// or frames follow the normals: a frame `(x₀, y₀, n₀)` at a seed vertex is carried to
/// every other vertex by the single minimal rotation that takes `n₀` onto the vertex's
/// normal (the normalised sum of the unit normals of its faces).
///
/// The frames of an area's local vertices: `None` for the global frame, else one
/// `DMat3` per local vertex with columns `x`, `y`, `n`.
#[derive(Clone, Debug, Default)]
pub struct LocalFrames {
    frames: Option<Vec<DMat3>>,
}

impl LocalFrames {
    /// The global frame.
    #[must_use]
    pub fn global() -> Self {
        Self { frames: None }
    }

    /// Computes the frames of `kind` for the local vertices of `area`, the vertex positions
    /// given per local vertex by `positions`. `default_seed` is the local vertex used
    /// when the kind names no seed.
    ///
    /// # Errors
    /// [`LeeError::PrimitiveOutsideArea`] when the seed is not in the area (the seed is
    /// a picked vertex like a primitive's); [`LeeError::Stale`] for an area of
    /// another mesh; [`LeeError::AreaPositionCount`] when
    /// `positions` does not have one entry per local vertex, and
    /// [`LeeError::InvalidParameter`] for a `default_seed` out of range (normal frames).
    pub fn new(
        mesh: &Mesh,
        area: &EditingArea,
        positions: &[DVec3],
        kind: &FrameKind,
        default_seed: usize,
    ) -> Result<Self> {
        let FrameKind::Normal { seed, x_axis } = kind else {
            return Ok(Self::global());
        };
        area.check_mesh(mesh)?;
        if positions.len() != area.vertices().len() {
            return Err(LeeError::AreaPositionCount {
                expected: area.vertices().len(),
                found: positions.len(),
            });
        }
        if default_seed >= positions.len() {
            return Err(LeeError::InvalidParameter {
                name: "default_seed",
                reason: format!(
                    "local vertex {default_seed} of an area of {} vertices",
                    positions.len()
                ),
            });
        }
        let seed = match seed {
            Some(v) => area
                .local_index(mesh, *v)
                .ok_or(LeeError::PrimitiveOutsideArea { vertex: *v })?,
            None => default_seed,
        };
        if let Some(x) = x_axis {
            if !x.is_finite() {
                return Err(LeeError::InvalidParameter {
                    name: "x_axis",
                    reason: format!("{x} is not finite"),
                });
            }
        }
        let normals = local_normals(mesh, area, positions);
        let n0 = if normals[seed] == DVec3::ZERO {
            DVec3::Z
        } else {
            normals[seed]
        };
        let x0 = x_axis
            .map(|x| x.reject_from_normalized(n0))
            .filter(|x| x.length_squared() > 1e-24)
            .map(DVec3::normalize)
            .unwrap_or_else(|| n0.any_orthonormal_vector());
        let y0 = n0.cross(x0);
        let frames = normals
            .par_iter()
            .map(|&n| {
                let n = if n == DVec3::ZERO { n0 } else { n };
                let r = minimal_rotation(n0, n, x0);
                DMat3::from_cols(r * x0, r * y0, n)
            })
            .collect();
        Ok(Self {
            frames: Some(frames),
        })
    }

    /// True for the global frame.
    #[must_use]
    pub fn is_global(&self) -> bool {
        self.frames.is_none()
    }

    /// The frame of local vertex `i` (columns `x`, `y`, `n`); the global frame for an
    /// index out of range.
    #[must_use]
    pub fn frame(&self, i: usize) -> DMat3 {
        self.frames
            .as_ref()
            .and_then(|f| f.get(i).copied())
            .unwrap_or(DMat3::IDENTITY)
    }

    /// Offset `Δd = (x·Δp, y·Δp, n·Δp)` of displacement `Δp` at local vertex `i` (eq. 1);
    /// in the global frame for an index out of range.
    #[inline]
    #[must_use]
    pub fn to_offset(&self, i: usize, displacement: DVec3) -> DVec3 {
        match self.frames.as_ref().and_then(|f| f.get(i)) {
            None => displacement,
            Some(f) => f.transpose() * displacement,
        }
    }

    /// Displacement `Δd_x x + Δd_y y + Δd_n n` of offset `Δd` at local vertex `i`; in the
    /// global frame for an index out of range.
    #[inline]
    #[must_use]
    pub fn to_displacement(&self, i: usize, offset: DVec3) -> DVec3 {
        match self.frames.as_ref().and_then(|f| f.get(i)) {
            None => offset,
            Some(f) => *f * offset,
        }
    }
}

/// The rotation taking unit `a` onto unit `b` about `a × b` (Rodrigues); for opposite
/// vectors the half turn about `fallback_axis` (a unit vector perpendicular to `a`).
fn minimal_rotation(a: DVec3, b: DVec3, fallback_axis: DVec3) -> DMat3 {
    let c = a.dot(b);
    if c < -1.0 + 1e-12 {
        return DMat3::from_axis_angle(fallback_axis, std::f64::consts::PI);
    }
    let v = a.cross(b);
    let k = 1.0 / (1.0 + c);
    DMat3::from_cols(
        DVec3::new(v.x * v.x * k + c, v.x * v.y * k + v.z, v.x * v.z * k - v.y),
        DVec3::new(v.y * v.x * k - v.z, v.y * v.y * k + c, v.y * v.z * k + v.x),
        DVec3::new(v.z * v.x * k + v.y, v.z * v.y * k - v.x, v.z * v.z * k + c),
    )
}

/// Unit normals of the local vertices from the given positions: the normalised sum of the
/// unit normals of the faces around each vertex (faces outside the area use the mesh's
/// positions; zero when degenerate).
fn local_normals(mesh: &Mesh, area: &EditingArea, positions: &[DVec3]) -> Vec<DVec3> {
    let local = area.local_of_slot();
    let position = |v: VertexId| match local[mesh.vertex_index(v)] {
        u32::MAX => mesh.position(v),
        i => positions[i as usize],
    };
    area.vertices()
        .par_iter()
        .map(|&v| {
            mesh.adjacent_faces(v)
                .map(|f| {
                    let [a, b, c] = mesh.triangle(f).map(position);
                    (b - a).cross(c - a).normalize_or_zero()
                })
                .sum::<DVec3>()
                .normalize_or_zero()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minimal_rotation_takes_a_onto_b() {
        let a = DVec3::Z;
        for b in [
            DVec3::X,
            DVec3::new(0.3, -0.4, 0.5).normalize(),
            -DVec3::Z,
            DVec3::Z,
        ] {
            let r = minimal_rotation(a, b, DVec3::X);
            assert!((r * a - b).length() < 1e-12, "{b}");
            assert!((r.determinant() - 1.0).abs() < 1e-12);
            assert!((r * r.transpose() - DMat3::IDENTITY).abs_diff_eq(DMat3::ZERO, 1e-12));
        }
    }
}
