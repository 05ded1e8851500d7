//! The placement frame of an FFD's surfaces (Feng, Ma & Peng §2, generalised).

use glam::DVec3;

use crate::deform::checks::{finite_point, unit_direction};
use crate::deform::error::Result;

/// A right-handed orthonormal placement frame: the shape surface starts on its XZ plane
/// with `u` along `x` and `v` along `z`, so that the surface normal `∂S/∂v × ∂S/∂u` is
/// `+y`, and heights are measured along `y` (Feng, Ma & Peng place both surfaces in the
/// world frame; this generalises it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatticeFrame {
    pub(super) origin: DVec3,
    pub(super) x: DVec3,
    pub(super) y: DVec3,
    pub(super) z: DVec3,
}

impl Default for LatticeFrame {
    fn default() -> Self {
        Self::WORLD
    }
}

impl LatticeFrame {
    /// The world frame: the paper's XZ plane, heights along `y`.
    pub const WORLD: LatticeFrame = LatticeFrame {
        origin: DVec3::ZERO,
        x: DVec3::X,
        y: DVec3::Y,
        z: DVec3::Z,
    };

    /// The frame at `origin` with `y` along `up` and `x` along `x_direction` made
    /// perpendicular to it; `z = x × y`.
    pub fn new(origin: DVec3, x_direction: DVec3, up: DVec3) -> Result<Self> {
        let origin = finite_point("frame origin", origin)?;
        let y = unit_direction("frame up", up)?;
        let x = unit_direction(
            "frame x (perpendicular to up)",
            x_direction - x_direction.dot(y) * y,
        )?;
        Ok(Self {
            origin,
            x,
            y,
            z: x.cross(y),
        })
    }

    /// The origin.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }
    /// The unit axes `(x, y, z)`.
    pub fn axes(&self) -> (DVec3, DVec3, DVec3) {
        (self.x, self.y, self.z)
    }
    /// The coordinates of a world point in this frame.
    pub fn to_local(&self, p: DVec3) -> DVec3 {
        let d = p - self.origin;
        DVec3::new(d.dot(self.x), d.dot(self.y), d.dot(self.z))
    }
    /// World position of frame coordinates.
    pub fn to_world(&self, l: DVec3) -> DVec3 {
        self.origin + l.x * self.x + l.y * self.y + l.z * self.z
    }
}
