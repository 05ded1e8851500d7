//! Bendels & Klein, *Image and 3D-object editing with precisely specified editing
//! regions*.

pub mod affine_power;
mod distance;
pub mod image;
mod mesh;
pub mod polyline;
mod regions;
mod shape;

pub use distance::ball::geodesic_ball;
pub use distance::euclidean::{point_segment_distance, BorderGrid, QueryPoints, MAX_TRACED_PIECES};
pub use distance::geodesic::{sphere_distance, FastMarching, FastMarchingUpdate, MarchSource};
pub use mesh::{
    blend_ratio, virtual_origin_distance, BlendOptions, BlendSession, DistanceKind, RefineOptions,
    RefineReport, MAX_NEW_VERTICES,
};
pub use regions::{Border, RegionKind, Regions, Role};
pub use shape::{CurveOptions, ShapeCurve, ShapeFunction};
