//! Attaching a point to the shape surface (Feng, Ma & Peng §3): the foot of the point
//! along the surface normal, found as the closest point by Newton's method from the best
//! sample of a coarse grid.

use glam::DVec3;

use super::bspline::Patches;

/// The foot of a point on the shape surface.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Foot {
    pub(crate) u: f64,
    pub(crate) v: f64,
    /// Directed distance along the unit normal.
    pub(crate) h: f64,
    /// Length of the part of `P − S(u, v)` not along the normal (zero at a true foot).
    pub(crate) residual: f64,
}

/// A coarse grid of samples of the surface (structure of arrays), for initial guesses.
pub(crate) struct Samples {
    n: [usize; 2],
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
}

impl Samples {
    /// `n[0] × n[1]` samples at evenly spaced parameters.
    pub(crate) fn new(surface: &Patches<DVec3>, n: [usize; 2]) -> Self {
        let mut s = Self {
            n,
            x: Vec::with_capacity(n[0] * n[1]),
            y: Vec::with_capacity(n[0] * n[1]),
            z: Vec::with_capacity(n[0] * n[1]),
        };
        for i in 0..n[0] {
            for j in 0..n[1] {
                let p = surface.value(i as f64 / (n[0] - 1) as f64, j as f64 / (n[1] - 1) as f64);
                s.x.push(p.x);
                s.y.push(p.y);
                s.z.push(p.z);
            }
        }
        s
    }

    /// The parameters of the sample nearest to `p`.
    #[inline]
    fn nearest(&self, p: DVec3) -> (f64, f64) {
        let mut best = f64::INFINITY;
        let mut best_k = 0;
        for k in 0..self.x.len() {
            let d =
                (self.x[k] - p.x).powi(2) + (self.y[k] - p.y).powi(2) + (self.z[k] - p.z).powi(2);
            if d < best {
                best = d;
                best_k = k;
            }
        }
        let (i, j) = (best_k / self.n[1], best_k % self.n[1]);
        (
            i as f64 / (self.n[0] - 1) as f64,
            j as f64 / (self.n[1] - 1) as f64,
        )
    }
}

/// The closest point of the surface to `p`: Newton's method on
/// `f(u, v) = ½ |S(u, v) − p|²` (the Hessian shifted to positive definite where it is
/// not), with the parameters kept in `[0, 1]²` (a parameter on its
/// bound whose step points outward is frozen) and step halving when `f` does not
/// decrease. At an interior minimum `p − S` is along the normal: the paper's projection.
pub(crate) fn foot(
    surface: &Patches<DVec3>,
    samples: &Samples,
    p: DVec3,
    max_iterations: usize,
) -> Foot {
    let (mut u, mut v) = samples.nearest(p);
    let (mut s, mut s_u, mut s_v, mut s_uu, mut s_uv, mut s_vv) = surface.second(u, v);
    let mut f = 0.5 * (s - p).length_squared();
    for _ in 0..max_iterations {
        let d = s - p;
        let g = [d.dot(s_u), d.dot(s_v)];
        let full = [
            s_u.length_squared() + d.dot(s_uu),
            s_u.dot(s_v) + d.dot(s_uv),
            s_v.length_squared() + d.dot(s_vv),
        ];
        // shift the Hessian to positive definite where it is not (far from the foot, or
        // beyond a focal point), so that every step goes downhill; near the foot it is
        // the plain Newton step and converges quadratically
        let half_trace = 0.5 * (full[0] + full[2]);
        let gap = (0.25 * (full[0] - full[2]).powi(2) + full[1] * full[1]).sqrt();
        let lowest = half_trace - gap;
        let floor = 1e-3 * (s_u.length_squared() + s_v.length_squared());
        let h = if lowest > floor {
            full
        } else {
            let shift = floor - lowest;
            [full[0] + shift, full[1], full[2] + shift]
        };
        let det = h[0] * h[2] - h[1] * h[1];
        let mut step = if det > 0.0 {
            [
                -(h[2] * g[0] - h[1] * g[1]) / det,
                -(h[0] * g[1] - h[1] * g[0]) / det,
            ]
        } else {
            [0.0, 0.0]
        };
        // freeze a parameter on its bound whose step points outward
        let out_u = (u <= 0.0 && step[0] < 0.0) || (u >= 1.0 && step[0] > 0.0);
        let out_v = (v <= 0.0 && step[1] < 0.0) || (v >= 1.0 && step[1] > 0.0);
        if out_u && out_v {
            break;
        }
        if out_u {
            step = [0.0, if h[2] > 0.0 { -g[1] / h[2] } else { 0.0 }];
        } else if out_v {
            step = [if h[0] > 0.0 { -g[0] / h[0] } else { 0.0 }, 0.0];
        }
        if !(step[0].is_finite() && step[1].is_finite()) || (step[0] == 0.0 && step[1] == 0.0) {
            break;
        }
        // step halving until f decreases; near the foot f no longer resolves the
        // progress (a tangential offset δ changes f by δ²/2), so a step that does not
        // raise f beyond rounding and shrinks the gradient is taken too
        let gradient = g[0].hypot(g[1]);
        let mut accepted = false;
        let mut converged = false;
        let mut scale = 1.0;
        for _ in 0..30 {
            let nu = (u + scale * step[0]).clamp(0.0, 1.0);
            let nv = (v + scale * step[1]).clamp(0.0, 1.0);
            let e = surface.second(nu, nv);
            let nd = e.0 - p;
            let nf = 0.5 * nd.length_squared();
            let n_gradient = nd.dot(e.1).hypot(nd.dot(e.2));
            if nf < f || (nf <= f * (1.0 + 1e-12) && n_gradient < gradient) {
                let moved = (nu - u).abs() + (nv - v).abs();
                u = nu;
                v = nv;
                (s, s_u, s_v, s_uu, s_uv, s_vv) = e;
                f = nf;
                accepted = moved > 0.0;
                // a full Newton step this small leaves an error of its square: done
                converged = scale == 1.0 && !(out_u || out_v) && moved < 1e-9;
                break;
            }
            scale *= 0.5;
        }
        if converged || !accepted || (scale * (step[0].abs() + step[1].abs())) < 1e-15 {
            break;
        }
    }
    let n = s_v.cross(s_u).normalize_or_zero();
    let d = p - s;
    let h = d.dot(n);
    let residual = if n == DVec3::ZERO {
        d.length()
    } else {
        (d - h * n).length()
    };
    Foot { u, v, h, residual }
}
