//! Least-squares plane through a point set: the plane "that approximates the frontier"
//! of a sub-mesh (*Interactive editing of multiresolution meshes* §4.3, scaling and
//! rotation).

use glam::{DMat3, DVec3};

/// A plane through `point` with unit `normal`.
///
/// Paper: *Interactive editing of multiresolution meshes* §4.3 (the plane fitted to the
/// frontier).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane (for a fitted plane, the centroid of the points).
    pub point: DVec3,
    /// The unit normal.
    pub normal: DVec3,
}

impl Plane {
    /// Signed distance of `p` to the plane (positive on the normal's side).
    #[inline]
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        (p - self.point).dot(self.normal)
    }

    /// The least-squares plane through `points`: through their centroid, normal along
    /// the eigenvector of the smallest eigenvalue of their covariance. `None` for fewer
    /// than three points or points (nearly) on a line.
    pub fn fit(points: &[DVec3]) -> Option<Plane> {
        if points.len() < 3 {
            return None;
        }
        let centroid = points.iter().sum::<DVec3>() / points.len() as f64;
        let mut c = [[0.0f64; 3]; 3];
        for p in points {
            let d = (*p - centroid).to_array();
            for (i, row) in c.iter_mut().enumerate() {
                for (j, x) in row.iter_mut().enumerate() {
                    *x += d[i] * d[j];
                }
            }
        }
        let (values, vectors) = symmetric_eigen(c);
        // values ascending
        if values[2].is_nan() || values[2] <= 0.0 || values[1] <= 1e-12 * values[2] {
            return None;
        }
        let normal = vectors.col(0).normalize();
        normal.is_finite().then_some(Plane {
            point: centroid,
            normal,
        })
    }
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: eigenvalues
/// ascending, eigenvectors as the matching columns.
#[allow(clippy::needless_range_loop)] // index notation mirrors the rotation formulas
pub(crate) fn symmetric_eigen(m: [[f64; 3]; 3]) -> ([f64; 3], DMat3) {
    let mut a = m;
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..50 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if off <= 1e-30 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with J the rotation in the (p, q) plane.
            for k in 0..3 {
                let akp = a[k][p];
                let akq = a[k][q];
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let apk = a[p][k];
                let aqk = a[q][k];
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let vp = row[p];
                let vq = row[q];
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let values = order.map(|i| a[i][i]);
    let cols = order.map(|i| DVec3::new(v[0][i], v[1][i], v[2][i]));
    (values, DMat3::from_cols(cols[0], cols[1], cols[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_of_a_rotated_diagonal_matrix() {
        let r = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let d = DMat3::from_diagonal(DVec3::new(5.0, 0.5, 2.0));
        let m = r * d * r.transpose();
        let arr = [
            m.row(0).to_array(),
            m.row(1).to_array(),
            m.row(2).to_array(),
        ];
        let (values, vectors) = symmetric_eigen(arr);
        assert!((values[0] - 0.5).abs() < 1e-12);
        assert!((values[1] - 2.0).abs() < 1e-12);
        assert!((values[2] - 5.0).abs() < 1e-12);
        for (i, &val) in values.iter().enumerate() {
            let x = vectors.col(i);
            assert!((m * x - val * x).length() < 1e-12);
        }
    }

    #[test]
    fn fits_a_tilted_circle() {
        let n = DVec3::new(1.0, 1.0, 0.5).normalize();
        let (a, b) = n.any_orthonormal_pair();
        let points: Vec<DVec3> = (0..12)
            .map(|i| {
                let t = i as f64 * std::f64::consts::TAU / 12.0;
                DVec3::new(1.0, 2.0, 3.0) + t.cos() * a + t.sin() * b
            })
            .collect();
        let plane = Plane::fit(&points).unwrap();
        assert!(plane.normal.dot(n).abs() > 1.0 - 1e-12);
        assert!((plane.point - DVec3::new(1.0, 2.0, 3.0)).length() < 1e-12);
        let line = [DVec3::ZERO, DVec3::X, 2.0 * DVec3::X];
        assert!(Plane::fit(&line).is_none());
    }
}
