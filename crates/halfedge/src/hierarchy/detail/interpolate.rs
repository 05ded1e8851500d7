//! Placing a split's vertices where the survivor moved apart from its ring: the coarse
//! triangle's affine frame, blending, and drawing back faces that would fold.

use glam::DVec3;

use super::frame::{ring_tangents_with, Frame, Lists, TABLED_RING};
use super::Collapsed;

/// True when the survivor moved with its ring (within rounding): `delta`, the part of its
/// motion the ring does not explain, is below `1e-10` of the ring's size (or not finite:
/// the caller refuses non-finite placements).
#[inline]
pub(super) fn moved_together(f: &Frame, ring_len: usize, delta: DVec3) -> bool {
    let [x, y, _] = f.axes.to_cols_array_2d().map(DVec3::from_array);
    // |delta|² > 1e-20 (|x|² + |y|²) / n², without the division.
    let n2 = (ring_len.max(1) as f64).powi(2);
    let apart = delta.length_squared() * n2 > 1e-20 * (x.length_squared() + y.length_squared());
    !apart
}

/// What refinement knows of the positions before an edit: the positions themselves (by
/// vertex slot) and, for a vertex, the motion of its whole cluster at a point when that
/// motion is exact (`Some(0)` for a vertex that stayed and is in no region).
pub(crate) type Before<'a> = (&'a [[f64; 3]], &'a dyn Fn(u32, DVec3) -> Option<DVec3>);

/// Where the split of a survivor that moved apart from its ring puts its endpoints, from
/// where the neighbourhood was before the edit (`rest`, the positions the record was
/// collapsed from) and the frame's placement `carried`.
///
/// Each endpoint is written in the affine frame of the triangle of the coarse mesh it
/// lies nearest to (the survivor and two consecutive vertices of the edge's link, at
/// rest): `p − s = β e₁ + γ e₂ + h n`, with the triangle's edges `e₁`, `e₂` from the
/// survivor `s` and its normal `n` scaled to the square root of its area, and read back
/// at the same coordinates in the triangle now: its motion is then the linear
/// interpolation of the triangle's corners' motion (it meets the neighbours' own motion
/// at the link, so there is no step between the descendants of a moved and of a still
/// coarse vertex), a similarity of the triangle carries it exactly, and creases are
/// kept (each endpoint follows the face it lies on, not an averaged plane). The result
/// blends from `carried` at the survivor to the triangle's placement at the link by the
/// survivor's hat function `λ = β + γ`. `None` when some data is missing (the caller
/// falls back to [`settle`]).
#[allow(clippy::too_many_arguments)]
pub(super) fn interpolate(
    positions: &[DVec3],
    rest: &[[f64; 3]],
    link: &[u32],
    anchor: DVec3,
    at: Collapsed,
    (now, ring): (&Frame, &[u32]),
    carried: [DVec3; 2],
    exact: &dyn Fn(u32, DVec3) -> Option<DVec3>,
) -> Option<[DVec3; 2]> {
    let n = link.len();
    if !(2..=2 * TABLED_RING).contains(&n) {
        return None;
    }
    let rest_of = |i: u32| rest.get(i as usize).map(|&p| DVec3::from_array(p));
    // Each triangle's rest frame, inverted once for both endpoints.
    let mut frames = [(glam::DMat3::ZERO, 0usize); 2 * TABLED_RING];
    let mut count = 0;
    for j in 0..n {
        let k = (j + 1) % n;
        if link[j] == link[k] {
            continue;
        }
        let (e1, e2) = (rest_of(link[j])? - at.placed, rest_of(link[k])? - at.placed);
        let normal = e1.cross(e2);
        let area2 = normal.length();
        let spans = area2 > 1e-12 * e1.length() * e2.length();
        if !spans {
            continue;
        }
        let m = glam::DMat3::from_cols(e1, e2, normal / area2.sqrt());
        frames[count] = (m.inverse(), j);
        count += 1;
    }
    let frames = &frames[..count];
    let place = |p: DVec3| -> Option<(DVec3, f64)> {
        let d = p - at.placed;
        // The triangle the point lies over (weights in [0, 1]) nearest to it, else the
        // one it is least outside of.
        let (mut best, mut best_score) = (None, f64::INFINITY);
        for &(inverse, j) in frames {
            let c = inverse * d;
            let outside = (-c.x).max(-c.y).max(c.x + c.y - 1.0).max(0.0);
            let score = outside * 1e6 + c.z.abs();
            if score < best_score {
                (best, best_score) = (Some((c, j)), score);
            }
        }
        let (c, j) = best?;
        let k = (j + 1) % n;
        let (rj, rk) = (rest_of(link[j])?, rest_of(link[k])?);
        let (qj, qk) = (positions[link[j] as usize], positions[link[k] as usize]);
        let normal = |s: DVec3, a: DVec3, b: DVec3| {
            let n = (a - s).cross(b - s);
            let scale = n.length().sqrt();
            if scale > 0.0 {
                n / scale
            } else {
                DVec3::ZERO
            }
        };
        // Barycentric weights. A corner whose whole cluster moves exactly (`exact` gives
        // that motion at a point: none for a vertex that stayed and is in no region)
        // gives every point of that cluster its exact motion, so the survivor's share
        // falls to zero half-way towards it (where that cluster begins) instead of at
        // it, and the corner's weight there brings the cluster's motion at this point.
        let (beta, gamma) = (c.x, c.y);
        let alpha = 1.0 - beta - gamma;
        let (ej, ek) = (exact(link[j], p), exact(link[k], p));
        let to_exact =
            if ej.is_some() { beta } else { 0.0 } + if ek.is_some() { gamma } else { 0.0 };
        let survivor = if to_exact > 0.0 {
            (alpha - to_exact).max(0.0)
        } else {
            alpha
        };
        let grow = if to_exact > 0.0 {
            1.0 + (alpha - survivor) / to_exact
        } else {
            1.0
        };
        let corner = |w: f64, e: Option<DVec3>, q: DVec3, r: DVec3| match e {
            Some(m) => w * grow * m,
            None => w * (q - r),
        };
        let motion = survivor * (anchor - at.placed)
            + corner(beta, ej, qj, rj)
            + corner(gamma, ek, qk, rk)
            + c.z * (normal(anchor, qj, qk) - normal(at.placed, rj, rk));
        Some((p + motion, (1.0 - survivor).clamp(0.0, 1.0)))
    };
    // Near the survivor the frame's placement (exact for any affine map of the
    // neighbourhood, second order for smooth ones); towards the link the triangle's
    // (which meets the neighbours' own motion): weight λ = β + γ, the hat function of
    // the survivor, so a quadratic motion is followed to second order too. Next to a
    // still neighbour the ring's motion is a step, which the frame reads as a stretch:
    // the triangles' placement alone then.
    // How far the link's motion is from the one map the frame reads from it, relative
    // to the motion: small for smooth edits, large at a step (a still neighbour, a
    // fast-varying edit), where the frame's placement is no guide and overshoots.
    let (x, y) = ring_tangents_with(ring, rest_of)?;
    let then = Frame::from_tangents(x, y)?;
    let map = now.axes * then.axes.inverse();
    let (mut residual, mut motion) = (0.0f64, (anchor - at.placed).length());
    for &i in link {
        let (q, r) = (positions[i as usize], rest_of(i)?);
        residual = residual.max((q - anchor - map * (r - at.placed)).length());
        motion = motion.max((q - r).length());
    }
    // A still neighbour (its cluster's motion is exactly zero) is a step; a rigidly or
    // affinely moved one (a marked part) is not: its motion is smooth.
    let step = link.iter().any(|&i| exact(i, at.p0) == Some(DVec3::ZERO));
    let moved = motion > 0.0;
    let trust = if step || !moved {
        0.0
    } else {
        (1.0 - (residual / motion - 0.05) / 0.2).clamp(0.0, 1.0)
    };
    let blend = |(q, lambda): (DVec3, f64), carried: DVec3| {
        carried + (1.0 - trust * (1.0 - lambda)) * (q - carried)
    };
    Some([
        blend(place(at.p0)?, carried[0]),
        blend(place(at.p1)?, carried[1]),
    ])
}

/// How many faces around a split's two vertices placed at `q` are turned over (by more
/// than 90°) against where they were before the edit: the triangles of each vertex and
/// two consecutive neighbours of its list, and the triangles across the split edge at
/// either end of each list.
pub(super) fn turned_over(
    positions: &[DVec3],
    rest: &[[f64; 3]],
    lists: Lists<'_>,
    at: Collapsed,
    q: [DVec3; 2],
) -> usize {
    let rest_of = |i: u32| rest.get(i as usize).map(|&p| DVec3::from_array(p));
    let now_of = |i: u32| positions.get(i as usize).copied();
    let normal = |a: DVec3, b: DVec3, c: DVec3| (b - a).cross(c - a);
    let mut count = 0;
    for (k, list) in [lists.l0, lists.l1].into_iter().enumerate() {
        let then = if k == 0 { at.p0 } else { at.p1 };
        for w in list.windows(2) {
            if let (Some(ra), Some(rb), Some(a), Some(b)) =
                (rest_of(w[0]), rest_of(w[1]), now_of(w[0]), now_of(w[1]))
            {
                count += usize::from(normal(q[k], a, b).dot(normal(then, ra, rb)) < 0.0);
            }
        }
        for &l in [list.first(), list.last()].into_iter().flatten() {
            if let (Some(rl), Some(a)) = (rest_of(l), now_of(l)) {
                count += usize::from(normal(q[0], q[1], a).dot(normal(at.p0, at.p1, rl)) < 0.0);
            }
        }
    }
    count
}

/// `q`, the interpolated placement of a split, unless it turns faces around the split
/// over ([`turned_over`]; an interpolation between coarse vertices whose motions differ
/// much, such as the fine vertices between a twist's rigid end and its ramp, can fold
/// them): then the endpoints' motion is drawn towards the survivor's (`t = 1` is `q`,
/// `t = 0` the recorded endpoints translated with the survivor), by the largest of
/// `t = 3/4, 1/2, 1/4, 0` that turns the fewest faces over. A placement that turns
/// nothing over is returned as it is.
pub(super) fn unfold(
    positions: &[DVec3],
    rest: &[[f64; 3]],
    lists: Lists<'_>,
    anchor: DVec3,
    at: Collapsed,
    q: [DVec3; 2],
) -> [DVec3; 2] {
    let count = |q: [DVec3; 2]| turned_over(positions, rest, lists, at, q);
    let first = count(q);
    if first == 0 {
        return q;
    }
    let shift = anchor - at.placed;
    let mut best = (first, q);
    for t in [0.75, 0.5, 0.25, 0.0] {
        let candidate = [
            at.p0 + shift + t * (q[0] - at.p0 - shift),
            at.p1 + shift + t * (q[1] - at.p1 - shift),
        ];
        let c = count(candidate);
        if c < best.0 {
            best = (c, candidate);
        }
    }
    best.1
}

/// Where the split of a survivor that moved apart from its ring puts its endpoints when
/// the positions before the edit are not known for its record (no copy kept by the
/// hierarchy serves it: see `Hierarchy::mesh_mut`).
///
/// `carried` is the survivor's current position `anchor` plus the endpoints' offsets in
/// the current frame `f`: right where the whole neighbourhood moved together. Where the
/// survivor moved apart from its ring (`predicted` is where the ring's motion, read
/// through the frame, puts the survivor; `anchor − predicted` is the part of the
/// survivor's motion the ring did not share), each endpoint gives back that part in
/// proportion to the coarse mesh's hat function of the survivor at the endpoint: `λ = 0`
/// at the survivor, `1` on its ring (the barycentric weight of the ring in the fan of
/// triangles around the survivor, in the frame's tangent plane). So the fine vertices'
/// displacement falls from the survivor's to its ring's, and the step between a moved
/// vertex and a still neighbour is spread over the moved vertex's descendants instead of
/// landing on one fine edge (the part given back grows as `λ²`, which a quadratic motion
/// needs).
pub(super) fn settle(
    f: &Frame,
    positions: &[DVec3],
    link: &[u32],
    anchor: DVec3,
    predicted: DVec3,
    local: [DVec3; 2],
    carried: [DVec3; 2],
) -> [DVec3; 2] {
    let delta = anchor - predicted;
    let inverse = f.axes.inverse();
    let ring: Vec<DVec3> = link
        .iter()
        .map(|&i| inverse * (positions[i as usize] - predicted))
        .collect();
    let hat = |d: DVec3| -> f64 {
        let mut best = f64::INFINITY;
        for (j, u) in ring.iter().enumerate() {
            let w = ring[(j + 1) % ring.len()];
            let det = u.x * w.y - u.y * w.x;
            if det.abs() <= 1e-12 * (u.x.abs() + u.y.abs()) * (w.x.abs() + w.y.abs()) {
                continue;
            }
            let beta = (d.x * w.y - d.y * w.x) / det;
            let gamma = (u.x * d.y - u.y * d.x) / det;
            if beta >= -1e-12 && gamma >= -1e-12 {
                best = best.min(beta + gamma);
            }
        }
        // Beyond the fan (an open ring): the ring's motion.
        let l = if best.is_finite() {
            best.clamp(0.0, 1.0)
        } else {
            1.0
        };
        l * l
    };
    [
        carried[0] - hat(local[0]) * delta,
        carried[1] - hat(local[1]) * delta,
    ]
}
