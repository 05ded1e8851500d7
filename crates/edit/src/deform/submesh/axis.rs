//! The axis of a sub-mesh edit (*Interactive editing of multiresolution meshes* §4.3:
//! rotation about a picked vertex's normal, Barr's taper and twist along an axis).

use glam::DVec3;
use halfedge::{Mesh, VertexId};

use crate::deform::checks::{finite_point, unit_direction};
use crate::deform::error::{DeformError, Result};

/// An oriented line: a point and a unit direction (rotation, taper and twist axes).
///
/// Paper: *Interactive editing of multiresolution meshes* §4.3; Barr 1984.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    pub(super) point: DVec3,
    pub(super) direction: DVec3,
}

impl Axis {
    /// The line through `point` along `direction` (normalised here).
    pub fn new(point: DVec3, direction: DVec3) -> Result<Self> {
        Ok(Self {
            point: finite_point("axis point", point)?,
            direction: unit_direction("axis direction", direction)?,
        })
    }

    /// The paper's default rotation axis: through vertex `v` along its normal.
    pub fn vertex_normal(mesh: &Mesh, v: VertexId) -> Result<Self> {
        mesh.ensure_vertex(v)?;
        let n = mesh.vertex_normal(v);
        if n == DVec3::ZERO {
            return Err(DeformError::NoVertexNormal(v));
        }
        Self::new(mesh.position(v), n)
    }

    /// A point of the axis.
    pub fn point(&self) -> DVec3 {
        self.point
    }

    /// The unit direction.
    pub fn direction(&self) -> DVec3 {
        self.direction
    }

    /// The axial coordinate `(p − point)·direction`.
    #[inline]
    pub fn coordinate(&self, p: DVec3) -> f64 {
        (p - self.point).dot(self.direction)
    }
}
