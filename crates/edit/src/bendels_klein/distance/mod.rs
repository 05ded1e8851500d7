//! Distance fields over the deformable area (Bendels & Klein, Sec. 4): the distance of
//! every deformable vertex to the border of the handle and to the border of the fixed
//! area. Their ratio `d_fixed / (d_fixed + d_handle)` parameterises the deformable
//! area from 0 (fixed border) to 1 (handle border).
//!
//! - [`euclidean`]: distance in space to the border polylines (Sec. 4.1), exact, with
//!   border segments kept in a uniform grid of cell size twice the mean edge length
//!   (cheap to rebuild when the borders change) and the query points bucketed in the
//!   same grid. The edit then behaves like a space deformation.
//! - [`geodesic`]: distance on the surface by fast marching (Sec. 4.2; Kimmel & Sethian
//!   1998, obtuse triangles unfolded), multi-source from all border vertices. The edit
//!   then behaves like spline editing, and α grows monotonically along the surface from
//!   the fixed area to the handle (the paper's Fig. 3).
//! - [`ball`]: the vertices within a geodesic distance of seed vertices (a selection,
//!   by fast marching).

pub(super) mod ball;
pub(super) mod euclidean;
pub(super) mod geodesic;
