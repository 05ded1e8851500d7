//! Edge weights shared by the methods: cotangent weights (Pinkall & Polthier; Eck et al.'s
//! harmonic spring constants are 4× these) and uniform weights.

use halfedge::{HalfedgeId, Mesh};

/// Cotangent of the angle at the corner opposite `h` in its face, or 0 for a boundary
/// halfedge or one that is not live in `mesh`. Degenerate corners (and corners at
/// non-finite positions) give 0 rather than NaN or infinity.
///
/// Paper: Pinkall & Polthier 1993, *Computing discrete minimal surfaces and their
/// conjugates*.
pub fn opposite_cotangent(mesh: &Mesh, h: HalfedgeId) -> f64 {
    if !mesh.is_valid_halfedge(h) || mesh.is_boundary_halfedge(h) {
        return 0.0;
    }
    let a = mesh.position(mesh.from_vertex(h));
    let b = mesh.position(mesh.to_vertex(h));
    let c = mesh.position(mesh.to_vertex(mesh.next(h)));
    let (u, v) = (a - c, b - c);
    let cross = u.cross(v).length();
    // (NaN compares false: non-finite corners end here too.)
    let degenerate =
        cross.is_nan() || cross <= f64::EPSILON * u.length_squared().max(v.length_squared());
    if degenerate {
        return 0.0;
    }
    let cot = u.dot(v) / cross;
    if cot.is_finite() {
        cot
    } else {
        0.0
    }
}

/// The cotangent weight of the edge of `h`: `(cot α + cot β) / 2`, with α, β the angles
/// opposite the edge (one term on a boundary edge). Can be negative for obtuse angles;
/// 0 for a halfedge that is not live in `mesh`.
///
/// Paper: Pinkall & Polthier 1993; Eck et al. 1995, *Multiresolution analysis of arbitrary
/// meshes* (whose harmonic spring constants are 4× these).
pub fn cotan_weight(mesh: &Mesh, h: HalfedgeId) -> f64 {
    if !mesh.is_valid_halfedge(h) {
        return 0.0;
    }
    0.5 * (opposite_cotangent(mesh, h) + opposite_cotangent(mesh, mesh.opposite(h)))
}
