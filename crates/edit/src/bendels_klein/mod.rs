//! Bendels & Klein, *Image and 3D-object editing with precisely specified editing
//! regions*.

pub mod affine_power;
mod blend;
mod distance;
pub(crate) mod error;
pub mod image;
mod mesh;
pub mod polyline;
mod regions;
mod shape;

pub use blend::{blend_ratio, BlendPoint, RefineOptions, RefineReport, MAX_NEW_VERTICES};
pub use distance::ball::geodesic_ball;
pub use distance::euclidean::{point_segment_distance, BorderGrid, QueryPoints, MAX_TRACED_PIECES};
pub use distance::geodesic::{sphere_distance, FastMarching, FastMarchingUpdate, MarchSource};
pub use error::{
    BendelsKleinError, ControlPointProblem, NoLogReason, RegionKind, Site, TransformOverflow,
};
pub use mesh::{virtual_origin_distance, BlendOptions, BlendSession, DistanceKind};
pub use regions::{Border, Regions, Role};
pub use shape::{CurveOptions, ShapeCurve, ShapeFunction};
