//! Bendels & Klein on images (*Image and 3D-object editing with precisely specified
//! editing regions*, Secs. 2, 4.1 and 7, Fig. 6): a region of a picture is moved by an
//! affine map, a second region stays exactly as it is, and the picture between them
//! follows smoothly.
//!
//! As in the paper, the image is carried by a regular **grid mesh** (one vertex every
//! [`ImageOptions::grid_step`] pixels, each cell two triangles), and the edit is the
//! polyline / mesh edit on that grid:
//!
//! - **Regions** are pixel [`Mask`]s, made from polygons drawn over the image
//!   ([`Mask::polygon`], [`Mask::outside_polygon`]), the image border
//!   ([`Mask::border`]) or a mask picture ([`Mask::from_raster`]). The handle and the
//!   fixed region may not share nor touch a pixel (Sec. 2, footnote 1).
//! - **Distances** (Sec. 4.1: "the Euclidean distance field, which in this case
//!   coincides with the geodesic one"): an exact Euclidean distance transform of each
//!   mask ([`edt`], Felzenszwalb & Huttenlocher 2012, *Distance transforms of sampled
//!   functions*), evaluated at the grid vertices; `α = f(d_fixed / (d_fixed +
//!   d_handle))` with a [`ShapeFunction`](super::ShapeFunction).
//! - **Blend**: each grid vertex moves by `exp(α log A)` (3×3 homogeneous `A`, through
//!   [`AffinePower::transform_point2`](super::affine_power::AffinePower::transform_point2));
//!   handle vertices by `A`, fixed
//!   vertices not at all.
//! - **Resampling** ([`ImageSession::render`]): by inverse mapping. Every output pixel
//!   centre is located in the deformed triangle that covers it; its barycentric
//!   coordinates give the source position on the undeformed grid, where the input is
//!   sampled bilinearly (colour channels premultiplied by alpha, so RGBA stays clean at
//!   transparent edges). Pixels of the fixed region are never written (bit for bit the
//!   input), nor are pixels under triangles that did not move. Where triangles overlap
//!   (a fold-over, only for extreme edits) the one nearer the handle (larger α) wins;
//!   [`ImageSession::folded_triangles`] counts them.
//!
//! Pixel `(x, y)` is the point `(x, y)` (its centre), origin at the top-left corner, `y`
//! down; polygons and transforms use the same coordinates.

pub mod edt;
mod mask;
mod pattern;
mod raster;
mod session;

pub use mask::Mask;
pub use pattern::test_pattern;
pub use raster::{Picture, Raster, Raster16, RasterOf, Sample};
pub use session::{ImageOptions, ImageSession, ImageSession16, ImageSessionOf, RenderStats};

pub use crate::bendels_klein::error::MAX_PIXELS;

#[cfg(test)]
mod tests;
