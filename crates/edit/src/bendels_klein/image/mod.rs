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
//!   d_handle))` with a [`ShapeFunction`](crate::bendels_klein::shape::ShapeFunction).
//! - **Blend**: each grid vertex moves by `exp(α log A)` (3×3 homogeneous `A`, through
//!   [`crate::bendels_klein::affine_power::AffinePower::transform_point2`]); handle vertices by `A`, fixed
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

use std::path::PathBuf;

use crate::bendels_klein::regions::RegionKind;
use crate::EditError;

/// The largest picture, in pixels (`width × height`), that rasters, masks and image
/// sessions accept: 2²⁶, e.g. 8192 × 8192 (an RGBA raster of 256 MiB). Larger sizes are
/// refused with [`ImageEditError::TooLarge`] before anything is allocated.
pub const MAX_PIXELS: usize = 1 << 26;

/// What can go wrong with an image edit (module [`crate::image_edit`]).
#[derive(Debug, thiserror::Error)]
pub enum ImageEditError {
    /// The image is narrower or lower than 2 pixels: it carries no grid cell.
    #[error("the image is {width}×{height}: at least 2×2 pixels are needed")]
    TooSmall {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// The image has more than [`MAX_PIXELS`] pixels.
    #[error("an image of {width}×{height} pixels × {channels} channels is too large (at most {MAX_PIXELS} pixels)")]
    TooLarge {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// Channels.
        channels: u8,
    },
    /// A channel count other than 1 (grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA).
    #[error("{0} channels: 1 (grey), 2 (grey + alpha), 3 (RGB) or 4 (RGBA) expected")]
    Channels(u8),
    /// Pixel data of the wrong length.
    #[error("the pixel data has {got} bytes, {expected} expected")]
    DataLength {
        /// Bytes given.
        got: usize,
        /// Width × height × channels.
        expected: usize,
    },
    /// A mask of another size than the image (or than another mask).
    #[error("a mask of {got:?} pixels for an image of {expected:?}")]
    MaskSize {
        /// The mask's (width, height).
        got: (u32, u32),
        /// The image's (width, height).
        expected: (u32, u32),
    },
    /// A polygon with fewer than three points.
    #[error("a polygon needs at least 3 points, got {0}")]
    PolygonTooShort(usize),
    /// A polygon point (or a transform parameter) is NaN or infinite.
    #[error("polygon point {index} is not finite")]
    NonFinitePolygon {
        /// Its index.
        index: usize,
    },
    /// The handle or the fixed region covers no pixel.
    #[error("the {0} region covers no pixel")]
    EmptyRegion(RegionKind),
    /// A pixel is in both the handle and the fixed region.
    #[error("pixel ({x}, {y}) is in both the handle and the fixed region")]
    Overlap {
        /// Column.
        x: u32,
        /// Row.
        y: u32,
    },
    /// A handle pixel is next to a fixed pixel (8-neighbourhood): no room for the
    /// deformable region between them (Sec. 2, footnote 1).
    #[error("handle pixel {handle:?} touches fixed pixel {fixed:?}")]
    HandleTouchesFixed {
        /// The handle pixel (x, y).
        handle: (u32, u32),
        /// The fixed pixel (x, y).
        fixed: (u32, u32),
    },
    /// A grid step of 0.
    #[error("the grid step must be at least 1 pixel")]
    GridStep,
    /// An output raster of another size or channel count than the session's image.
    #[error("the output is {got:?} (width, height, channels), the session's image {expected:?}")]
    OutputMismatch {
        /// The output's (width, height, channels).
        got: (u32, u32, u8),
        /// The image's.
        expected: (u32, u32, u8),
    },
    /// Reading or writing a PNG failed.
    #[error("{path}: {source}")]
    Png {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: image::ImageError,
    },
    /// An error of the shared machinery: the transform (no real logarithm, not
    /// affine, not finite).
    #[error(transparent)]
    Edit(#[from] EditError),
}

/// `Result` with an [`ImageEditError`].
pub type ImageResult<T> = std::result::Result<T, ImageEditError>;

#[cfg(test)]
mod tests;
