//! Detail coefficients: how a split places the two vertices of its record after the mesh
//! was edited at a coarser level.
//!
//! Two schemes ([`DetailMode`]), chosen when the hierarchy is built:
//!
//! - [`DetailMode::LocalFrame`] (the default), after the local-frame details of Kobbelt,
//!   Campagna, Vorsatz & Seidel (1998) and Guskov, Sweldens & Schröder (1999): at collapse
//!   time each endpoint's position is stored as an offset from the survivor's placed
//!   position, in a frame of the collapsed edge's link (the ring of vertices around the
//!   edge): its first Fourier mode `Σ cos(2πj/n) q_j`, `Σ sin(2πj/n) q_j` gives two
//!   tangents that follow every affine map of the ring, the third axis is their normal
//!   scaled by the square root of their area. The centroid of that ring is stored in the
//!   same frame. At split time the frame is built again from the neighbours' current
//!   positions. Where the survivor moved *with* its ring (it is where the ring's motion,
//!   read through the frame, puts it), both endpoints go to the survivor's position plus
//!   their offsets in the new frame: a neighbourhood translated, rotated, scaled or
//!   sheared at a coarse level takes its detail along, turned and scaled with it. Where
//!   it moved *apart* from its ring (a vertex dragged on its own, the edge of a moved
//!   region, a fast-varying edit), each endpoint is also written in the affine frame of
//!   the coarse triangle it lies over (survivor and two link vertices, where they were
//!   before the edit), and the two placements are blended by the survivor's hat function:
//!   the frame's near the survivor, the triangle's towards the link, where it meets the
//!   neighbours' own motion. So the fine vertices' motion interpolates the coarse
//!   vertices' (to second order for smooth edits) instead of stepping between them.
//! - [`DetailMode::Translation`], the seed paper's centroid translations ("Interactive
//!   Editing of Multiresolution Meshes", section 3, Fig. 1): each endpoint takes its
//!   recorded position plus the translation `C_f − C_i` of the centroid of its own
//!   neighbours. Rotations are not carried (a rotated part comes back with unrotated
//!   detail) and every split averages moved and unmoved neighbours, so an edit diffuses
//!   about one ring further at every level. Kept for fidelity with the paper.
//!
//! **Regions** (local frames only): a split whose survivor is exactly where the hierarchy
//! left it (bit for bit) puts both endpoints back at their recorded positions, unless the
//! survivor is in an edit's region ([`crate::Hierarchy::mark_region`]). So outside the
//! regions a fine vertex moves only when its *ancestor* at the edited level (the vertex
//! it was collapsed into) moved: everything an edit left in place stays exact at every
//! finer level. Inside a region, an unmoved vertex next to moved ones takes its share of
//! their motion, so the transition between moved and still parts is the edit's own. A
//! survivor marked with an affine map ([`crate::Hierarchy::mark_affine`]) whose position
//! is that map's image of where the hierarchy left it places both endpoints at the map's
//! image of their recorded positions, exactly: rigidly moved handles land where the user
//! put them.
//!
//! Exactness: the frame (and the centroids) are computed by one function over the same
//! neighbour list in the same order at collapse and at split time, so with no edit they
//! agree bit for bit; and the hierarchy skips all of this while no position was edited.
//!
//! Storage is flat: one `Vec<u32>` of neighbour vertex indices for all records, with two
//! lists per record (`v0`'s, then `v1`'s) delimited by one offset array, two vectors per
//! record (the local offsets, or the recorded centroids), and with local frames the
//! ring's centroid and which ring the frame is built from. The positions before an edit,
//! which the triangle placement reads, are kept by the hierarchy (one copy of the edited
//! level's vertices, taken by `Hierarchy::mesh_mut`).

use glam::DVec3;

use super::motion::Motion;

/// How a split places its vertices after an edit at a coarser level (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DetailMode {
    /// Offsets in a local frame of the neighbourhood, anchored at the survivor; regions
    /// that did not move stay exact; affine marks land exactly. The default.
    #[default]
    LocalFrame,
    /// The seed paper's centroid translations `C_f − C_i` (section 3, Fig. 1).
    Translation,
}

/// Cosines and sines of `2π j / n` for `j < n`, for ring lengths up to
/// [`TABLED_RING`] (computed once, so every frame of a ring uses the same bits).
const TABLED_RING: usize = 96;

/// Cosines and sines of `2π j / n`, `j < n`, for every ring length `n ≤ TABLED_RING`,
/// one table after the other (ring `n` starts at `n (n − 1) / 2`).
fn ring_tables() -> &'static [(f64, f64)] {
    static TABLE: std::sync::OnceLock<Vec<(f64, f64)>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        (0..=TABLED_RING)
            .flat_map(|n| {
                (0..n).map(move |j| {
                    let (s, c) = (std::f64::consts::TAU * j as f64 / n as f64).sin_cos();
                    (c, s)
                })
            })
            .collect()
    })
}

/// The two tangent vectors of a ring of neighbours (listed in ring order): its first
/// Fourier mode `Σ cos(2π j/n) q_j`, `Σ sin(2π j/n) q_j`. Both are linear in the
/// positions and blind to translations, so an affine map of the ring maps them by its
/// linear part. `None` for rings of fewer than three vertices or longer than the table.
#[inline]
fn ring_tangents(positions: &[DVec3], list: &[u32]) -> Option<(DVec3, DVec3)> {
    ring_tangents_with(list, |i| positions.get(i as usize).copied())
}

/// [`ring_tangents`] and the centroid of the ring, in one pass over its positions (the
/// same operations in the same order as [`ring_tangents`] and [`centroid`]).
#[inline]
fn ring_tangents_and_centroid(positions: &[DVec3], list: &[u32]) -> Option<(DVec3, DVec3, DVec3)> {
    let n = list.len();
    if !(3..=TABLED_RING).contains(&n) {
        return None;
    }
    let start = n * (n - 1) / 2;
    let table = ring_tables().get(start..start + n)?;
    let (mut x, mut y, mut sum) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for (&i, &(c, s)) in list.iter().zip(table) {
        let q = positions[i as usize];
        x += c * q;
        y += s * q;
        sum += q;
    }
    Some((x, y, sum / n as f64))
}

/// [`ring_tangents`] of the positions `position` gives (the same operations in the same
/// order, so the same bits for the same positions).
#[inline]
fn ring_tangents_with(
    list: &[u32],
    position: impl Fn(u32) -> Option<DVec3>,
) -> Option<(DVec3, DVec3)> {
    let n = list.len();
    if !(3..=TABLED_RING).contains(&n) {
        return None;
    }
    let start = n * (n - 1) / 2;
    let table = ring_tables().get(start..start + n)?;
    let (mut x, mut y) = (DVec3::ZERO, DVec3::ZERO);
    for (&i, &(c, s)) in list.iter().zip(table) {
        let q = position(i)?;
        x += c * q;
        y += s * q;
    }
    Some((x, y))
}

/// A local frame of a record's neighbourhood: the columns `x`, `y` (the first Fourier
/// mode of one neighbour ring, see [`ring_tangents`]) and `z` along `x × y`, of length
/// `sqrt |x × y|`. The frame follows every similarity of the neighbourhood exactly, and
/// stretches and shears within the tangent plane with it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Frame {
    axes: glam::DMat3,
}

/// The neighbour lists of a record: `v0`'s, `v1`'s, and both one after the other (the
/// link of the collapsed edge, as they are stored).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lists<'a> {
    pub l0: &'a [u32],
    pub l1: &'a [u32],
    pub link: &'a [u32],
}

/// Which ring a record's frame is built from: none, `v0`'s or `v1`'s.
pub(crate) type Ring = u8;
const NO_RING: Ring = 0;
/// The frame is built from the edge's link (both lists, one loop).
const LINK: Ring = 3;

impl Lists<'_> {
    /// The list of ring `ring` (1: `l0`, 2: `l1`, otherwise the link).
    #[inline]
    fn ring(&self, ring: Ring) -> &[u32] {
        match ring {
            1 => self.l0,
            2 => self.l1,
            _ => self.link,
        }
    }
}

impl Frame {
    /// The frame of ring `ring` (1: `l0`, 2: `l1`), or `None` when that ring spans no
    /// plane (its tangents are nearly parallel, vanish or are not finite).
    #[inline]
    pub(crate) fn of_ring(positions: &[DVec3], lists: Lists<'_>, ring: Ring) -> Option<Self> {
        let list = match ring {
            1 => lists.l0,
            2 => lists.l1,
            LINK => lists.link,
            _ => return None,
        };
        let (x, y) = ring_tangents(positions, list)?;
        Self::from_tangents(x, y)
    }

    /// [`of_ring`](Self::of_ring) and the centroid of that ring.
    #[inline]
    fn of_ring_with_centroid(
        positions: &[DVec3],
        lists: Lists<'_>,
        ring: Ring,
    ) -> Option<(Self, DVec3)> {
        if !matches!(ring, 1 | 2 | LINK) {
            return None;
        }
        let (x, y, centre) = ring_tangents_and_centroid(positions, lists.ring(ring))?;
        Some((Self::from_tangents(x, y)?, centre))
    }

    /// True when ring `ring`'s tangents are not finite (its coordinates overflow).
    fn overflows(positions: &[DVec3], lists: Lists<'_>, ring: Ring) -> bool {
        let list = match ring {
            1 => lists.l0,
            2 => lists.l1,
            _ => lists.link,
        };
        ring_tangents(positions, list).is_some_and(|(x, y)| !(x.is_finite() && y.is_finite()))
    }

    #[inline]
    fn from_tangents(x: DVec3, y: DVec3) -> Option<Self> {
        let normal = x.cross(y);
        let area2 = normal.length_squared();
        // Tangents at least ~0.1° apart (and nothing infinite or NaN).
        let enough = area2 > 4e-6 * x.length_squared() * y.length_squared();
        if !enough || !area2.is_finite() {
            return None;
        }
        // One division for the three components (a split's placement waits on it).
        let z = normal * (1.0 / area2.sqrt().sqrt());
        Some(Self {
            axes: glam::DMat3::from_cols(x, y, z),
        })
    }

    /// The better conditioned of the two rings' frames at collapse time, and which ring.
    pub(crate) fn choose(positions: &[DVec3], lists: Lists<'_>) -> Option<(Ring, Self)> {
        let quality = |ring: Ring| {
            let f = Self::of_ring(positions, lists, ring)?;
            let [x, y, _] = f.axes.to_cols_array_2d().map(DVec3::from_array);
            Some((x.cross(y).length() / (x.length() * y.length()), ring, f))
        };
        if let Some((q, ring, f)) = quality(LINK) {
            if q > 0.5 {
                return Some((ring, f));
            }
        }
        match (quality(1), quality(2)) {
            (Some(a), Some(b)) => Some(if b.0 > a.0 { (b.1, b.2) } else { (a.1, a.2) }),
            (Some(a), None) | (None, Some(a)) => Some((a.1, a.2)),
            (None, None) => None,
        }
    }

    /// `v` (a world offset) in this frame's coordinates.
    #[inline]
    fn local(&self, v: DVec3) -> Option<DVec3> {
        let d = self.axes.inverse() * v;
        d.is_finite().then_some(d)
    }

    /// The world offset of local coordinates `d`.
    #[inline]
    fn world(&self, d: DVec3) -> DVec3 {
        self.axes * d
    }
}

/// The detail coefficients of every record of a hierarchy, indexed by record number.
#[derive(Clone, Debug, Default)]
pub(crate) struct Details {
    mode: DetailMode,
    /// Neighbour vertex indices of all records, `v0`'s list then `v1`'s list per record.
    neighbours: Vec<u32>,
    /// `offsets[2 r]..offsets[2 r + 1]` is `v0`'s list of record `r`,
    /// `offsets[2 r + 1]..offsets[2 r + 2]` is `v1`'s; starts with 0.
    offsets: Vec<u32>,
    /// Local frames: `[d0, d1]`, the offsets of `p0` and `p1` from the placed survivor in
    /// the record's frame (or in world axes when `framed` is false).
    /// Translation: `[C_i(v0), C_i(v1)]`.
    coefficients: Vec<[DVec3; 2]>,
    /// Local frames: the ring the record's frame is built from ([`NO_RING`]: the
    /// neighbourhood had no frame at collapse time, the offsets are in world axes).
    framed: Vec<Ring>,
    /// Local frames: the centroid of the frame's ring, as an offset from the placed
    /// survivor in the record's frame (what lets a split tell how far the survivor moved
    /// apart from its ring, see [`Details::placement`]).
    centres: Vec<DVec3>,
}

/// Sizes of [`DetailBuffers`] (capacity, and how much of it to map): neighbours, offsets,
/// coefficients, frames, centres.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DetailSizes([(usize, usize); 5]);

impl DetailSizes {
    /// The buffers, their memory written once (see [`super::build::Prefaulted`]).
    pub(crate) fn make(self) -> DetailBuffers {
        let [n, o, c, f, e] = self.0;
        DetailBuffers {
            neighbours: super::build::prefaulted(n),
            offsets: super::build::prefaulted(o),
            coefficients: super::build::prefaulted(c),
            framed: super::build::prefaulted(f),
            centres: super::build::prefaulted(e),
        }
    }
}

/// Empty buffers for [`Details`], their memory already written once (see
/// [`DetailSizes::make`]).
#[derive(Debug)]
pub(crate) struct DetailBuffers {
    neighbours: Vec<u32>,
    offsets: Vec<u32>,
    coefficients: Vec<[DVec3; 2]>,
    framed: Vec<Ring>,
    centres: Vec<DVec3>,
}

/// Centroid of the positions of the listed vertices, summed in list order (the order is
/// what makes `C_f == C_i` bit for bit when nothing moved). Zero for an empty list.
#[inline]
pub(crate) fn centroid(positions: &[DVec3], list: &[u32]) -> DVec3 {
    if list.is_empty() {
        return DVec3::ZERO;
    }
    let mut sum = DVec3::ZERO;
    for &i in list {
        sum += positions[i as usize];
    }
    sum / list.len() as f64
}

/// `p + d`, except that components where `d` is zero are left untouched (bit for bit,
/// signed zeros included).
#[inline]
pub(crate) fn translate_exact(p: DVec3, d: DVec3) -> DVec3 {
    DVec3::new(
        if d.x != 0.0 { p.x + d.x } else { p.x },
        if d.y != 0.0 { p.y + d.y } else { p.y },
        if d.z != 0.0 { p.z + d.z } else { p.z },
    )
}

/// True when the survivor moved with its ring (within rounding): `delta`, the part of its
/// motion the ring does not explain, is below `1e-10` of the ring's size (or not finite:
/// the caller refuses non-finite placements).
#[inline]
fn moved_together(f: &Frame, ring_len: usize, delta: DVec3) -> bool {
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
fn interpolate(
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
fn turned_over(
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
fn unfold(
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
fn settle(
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

/// The coefficients of a range of records ([`Details::save`]).
pub(crate) struct SavedRange {
    coefficients: Vec<[DVec3; 2]>,
    framed: Vec<Ring>,
    centres: Vec<DVec3>,
}

/// Where a split puts its two vertices, given the survivor's position before the split.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Placement {
    /// Both at their recorded positions (the split already put them there).
    Recorded,
    /// At these positions.
    At([DVec3; 2]),
    /// The survivor moved apart from its ring: ask again with the positions before the
    /// edit (only when the caller said it can provide them).
    NeedsBefore,
}

/// Positions `[p0, p1]` recorded before a collapse and the survivor's position after it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Collapsed {
    pub p0: DVec3,
    pub p1: DVec3,
    pub placed: DVec3,
}

impl Details {
    /// Room for about `records` records, in `mode`.
    pub(crate) fn with_capacity(mode: DetailMode, records: usize) -> Self {
        let mut offsets = Vec::with_capacity(2 * records + 1);
        offsets.push(0);
        Self {
            mode,
            neighbours: Vec::with_capacity(12 * records),
            offsets,
            coefficients: Vec::with_capacity(records),
            framed: Vec::with_capacity(if mode == DetailMode::LocalFrame {
                records
            } else {
                0
            }),
            centres: Vec::with_capacity(if mode == DetailMode::LocalFrame {
                records
            } else {
                0
            }),
        }
    }

    /// These buffers emptied, for `records` records of `mode` (see
    /// [`with_capacity`](Self::with_capacity)), keeping the memory they hold.
    pub(crate) fn recycled(mut self, mode: DetailMode, records: usize) -> Self {
        self.mode = mode;
        self.neighbours.clear();
        self.neighbours.reserve(12 * records);
        self.offsets.clear();
        self.offsets.reserve(2 * records + 1);
        self.offsets.push(0);
        self.coefficients.clear();
        self.coefficients.reserve(records);
        let framed = if mode == DetailMode::LocalFrame {
            records
        } else {
            0
        };
        self.framed.clear();
        self.framed.reserve(framed);
        self.centres.clear();
        self.centres.reserve(framed);
        self
    }

    /// The sizes of buffers like these details' (their reserved capacities, and how
    /// much of them `records` records fill), to be made off the building thread (see
    /// [`super::build::Prefaulted`]).
    pub(crate) fn prefaulted_sizes(&self, records: usize) -> DetailSizes {
        let share =
            |capacity: usize, per_record: usize| (capacity, capacity.min(per_record * records));
        DetailSizes([
            share(self.neighbours.capacity(), 12),
            share(self.offsets.capacity(), 2),
            share(self.coefficients.capacity(), 1),
            share(self.framed.capacity(), 1),
            share(self.centres.capacity(), 1),
        ])
    }

    /// Moves these details into `buffers` (made from
    /// [`prefaulted_sizes`](Self::prefaulted_sizes)), which then hold them.
    pub(crate) fn adopt(&mut self, buffers: DetailBuffers) {
        let DetailBuffers {
            neighbours,
            offsets,
            coefficients,
            framed,
            centres,
        } = buffers;
        super::build::adopt(&mut self.neighbours, neighbours);
        super::build::adopt(&mut self.offsets, offsets);
        super::build::adopt(&mut self.coefficients, coefficients);
        super::build::adopt(&mut self.framed, framed);
        super::build::adopt(&mut self.centres, centres);
    }

    /// The scheme.
    pub(crate) fn mode(&self) -> DetailMode {
        self.mode
    }

    /// Appends the record of the next collapse: the neighbours of `v0` (without `v1`) and
    /// of `v1` (without `v0`) given as vertex indices by the two iterators, and computes
    /// its coefficients from `positions` (of the neighbours) and `at`.
    pub(crate) fn push(
        &mut self,
        positions: &[DVec3],
        v0_ring: impl Iterator<Item = u32>,
        v1_ring: impl Iterator<Item = u32>,
        [i0, i1]: [u32; 2],
        at: Collapsed,
    ) {
        let start0 = self.neighbours.len();
        self.push_ring(v0_ring, i1);
        let start1 = self.neighbours.len();
        self.push_ring(v1_ring, i0);
        let end = self.neighbours.len();
        debug_assert!(start0 <= start1);
        self.offsets.push(start1 as u32);
        self.offsets.push(end as u32);
        self.coefficients.push([DVec3::ZERO; 2]);
        if self.mode == DetailMode::LocalFrame {
            self.framed.push(NO_RING);
            self.centres.push(DVec3::ZERO);
        }
        self.refresh(self.coefficients.len() - 1, positions, at);
    }

    /// Appends a copy of record `r` of `from` (same scheme): for a collapse made again
    /// on a neighbourhood exactly as it was when `from`'s record was taken.
    pub(crate) fn push_copy(&mut self, from: &Details, r: usize) {
        debug_assert_eq!(self.mode, from.mode);
        let (l0, l1) = from.lists(r);
        self.neighbours.extend_from_slice(l0);
        self.offsets.push(self.neighbours.len() as u32);
        self.neighbours.extend_from_slice(l1);
        self.offsets.push(self.neighbours.len() as u32);
        self.coefficients.push(from.coefficients[r]);
        if self.mode == DetailMode::LocalFrame {
            self.framed.push(from.framed[r]);
            self.centres.push(from.centres[r]);
        }
    }

    /// Appends the one-ring `ring` (in rotation order) of one endpoint without the other
    /// endpoint `other`, starting right after `other`: so `v0`'s list then `v1`'s list
    /// walk once around the collapsed edge (its link).
    fn push_ring(&mut self, ring: impl Iterator<Item = u32>, other: u32) {
        let start = self.neighbours.len();
        self.neighbours.extend(ring);
        let list = &mut self.neighbours[start..];
        if let Some(k) = list.iter().position(|&i| i == other) {
            list.rotate_left(k + 1);
            self.neighbours.pop();
        }
    }

    /// The neighbour lists of record `r`: `(v0's, v1's)`.
    #[inline]
    pub(crate) fn lists(&self, r: usize) -> (&[u32], &[u32]) {
        let a = self.offsets[2 * r] as usize;
        let b = self.offsets[2 * r + 1] as usize;
        let c = self.offsets[2 * r + 2] as usize;
        (&self.neighbours[a..b], &self.neighbours[b..c])
    }

    /// True when every neighbour of record `r` is an index into `positions` of length
    /// `len`: always so on the hierarchy's own mesh, checked before using a mesh the
    /// hierarchy cannot vouch for.
    pub(crate) fn in_bounds(&self, r: usize, len: usize) -> bool {
        self.all_neighbours(r).iter().all(|&i| (i as usize) < len)
    }

    /// The [`Lists`] of record `r`.
    #[inline]
    fn record_lists(&self, r: usize) -> Lists<'_> {
        let (l0, l1) = self.lists(r);
        Lists {
            l0,
            l1,
            link: self.all_neighbours(r),
        }
    }

    /// Both neighbour lists of record `r`, one after the other.
    #[inline]
    fn all_neighbours(&self, r: usize) -> &[u32] {
        &self.neighbours[self.offsets[2 * r] as usize..self.offsets[2 * r + 2] as usize]
    }

    /// Recomputes the coefficients of record `r` from the neighbours' current positions
    /// and the collapse `at` (when the record is collapsed again after an edit at a finer
    /// level).
    pub(crate) fn refresh(&mut self, r: usize, positions: &[DVec3], at: Collapsed) {
        let (l0, l1) = self.lists(r);
        match self.mode {
            DetailMode::Translation => {
                let c = [centroid(positions, l0), centroid(positions, l1)];
                self.coefficients[r] = c;
            }
            DetailMode::LocalFrame => {
                let offsets = [at.p0 - at.placed, at.p1 - at.placed];
                let lists = self.record_lists(r);
                let framed = Frame::choose(positions, lists).and_then(|(ring, f)| {
                    let centre = centroid(positions, lists.ring(ring)) - at.placed;
                    Some((
                        ring,
                        [f.local(offsets[0])?, f.local(offsets[1])?],
                        f.local(centre)?,
                    ))
                });
                let (framed, coefficients, centre) =
                    framed.unwrap_or((NO_RING, offsets, DVec3::ZERO));
                self.framed[r] = framed;
                self.coefficients[r] = coefficients;
                self.centres[r] = centre;
            }
        }
    }

    /// Where splitting record `r` puts `v0` and `v1`, with the survivor now at `anchor`,
    /// the neighbours at `positions`, and the collapse as recorded in `at`. `in_region`:
    /// the survivor is in an edit's region ([`crate::Hierarchy::mark_region`]), so it is
    /// placed by its neighbourhood's motion even when it did not move itself.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn placement(
        &self,
        r: usize,
        positions: &[DVec3],
        rest: Option<Before<'_>>,
        anchor: DVec3,
        at: Collapsed,
        in_region: bool,
        before_on_request: bool,
    ) -> Placement {
        let (l0, l1) = self.lists(r);
        let [a, b] = self.coefficients[r];
        match self.mode {
            DetailMode::Translation => {
                let d0 = centroid(positions, l0) - a;
                let d1 = centroid(positions, l1) - b;
                Placement::At([translate_exact(at.p0, d0), translate_exact(at.p1, d1)])
            }
            DetailMode::LocalFrame => {
                if anchor == at.placed && !in_region {
                    return Placement::Recorded;
                }
                let ring = self.framed[r];
                if ring == NO_RING {
                    return Placement::At([anchor + a, anchor + b]);
                }
                let lists = self.record_lists(r);
                match Frame::of_ring_with_centroid(positions, lists, ring) {
                    Some((f, centre)) => {
                        let carried = [anchor + f.world(a), anchor + f.world(b)];
                        let predicted = centre - f.world(self.centres[r]);
                        if moved_together(&f, lists.link.len(), anchor - predicted) {
                            return Placement::At(carried);
                        }
                        if rest.is_none() && before_on_request {
                            return Placement::NeedsBefore;
                        }
                        let interpolated = rest.and_then(|(rest, exact)| {
                            interpolate(
                                positions,
                                rest,
                                lists.link,
                                anchor,
                                at,
                                (&f, lists.ring(ring)),
                                carried,
                                exact,
                            )
                        });
                        let interpolated = interpolated
                            .zip(rest)
                            .map(|(q, (rest, _))| unfold(positions, rest, lists, anchor, at, q));
                        Placement::At(interpolated.unwrap_or_else(|| {
                            settle(
                                &f,
                                positions,
                                lists.link,
                                anchor,
                                predicted,
                                [a, b],
                                carried,
                            )
                        }))
                    }
                    // Coordinates so large that the frame overflows: the caller refuses
                    // the non-finite placement.
                    None if Frame::overflows(positions, self.record_lists(r), ring) => {
                        Placement::At([DVec3::INFINITY; 2])
                    }
                    // The edit flattened the neighbourhood to a line or a point: its
                    // detail has no frame to live in and shrinks to the survivor.
                    None => Placement::At([anchor; 2]),
                }
            }
        }
    }

    /// Where splitting record `r` puts `v0` and `v1` when the survivor was moved by
    /// `motion` (an affine map or a field) from where the hierarchy left it: the motion of
    /// their recorded positions, or `None` when the survivor is not (within rounding) the
    /// motion of its placed position.
    #[inline]
    pub(crate) fn motion_placement(
        motion: &Motion,
        anchor: DVec3,
        at: Collapsed,
    ) -> Option<[DVec3; 2]> {
        let expected = motion.apply(at.placed);
        let scale = motion.scale_at(at.placed, expected);
        ((anchor - expected).abs().max_element() <= 1e-10 * scale.max(f64::MIN_POSITIVE))
            .then(|| [motion.apply(at.p0), motion.apply(at.p1)])
    }

    /// Prefetches the current positions of record `r`'s neighbours, which
    /// [`placement`](Self::placement) will read (see [`crate::prefetch`]).
    #[inline]
    pub(crate) fn prefetch(&self, r: usize, positions: &[DVec3]) {
        for &i in self.all_neighbours(r) {
            crate::prefetch::prefetch(positions, i as usize);
        }
    }

    /// The coefficients of the records in `range`, to [`restore`](Self::restore) them.
    pub(crate) fn save(&self, range: std::ops::Range<usize>) -> SavedRange {
        SavedRange {
            coefficients: self.coefficients[range.clone()].to_vec(),
            framed: self
                .framed
                .get(range.clone())
                .map(<[Ring]>::to_vec)
                .unwrap_or_default(),
            centres: self
                .centres
                .get(range)
                .map(<[DVec3]>::to_vec)
                .unwrap_or_default(),
        }
    }

    /// Puts back the coefficients [`save`](Self::save)d for `range`.
    pub(crate) fn restore(&mut self, range: std::ops::Range<usize>, saved: SavedRange) {
        self.coefficients[range.clone()].copy_from_slice(&saved.coefficients);
        if let Some(framed) = self.framed.get_mut(range.clone()) {
            framed.copy_from_slice(&saved.framed);
        }
        if let Some(centres) = self.centres.get_mut(range) {
            centres.copy_from_slice(&saved.centres);
        }
    }

    /// Prefetches record `r`'s own memory: its neighbour list (the indices that
    /// [`prefetch`](Self::prefetch) will follow a few records later) and coefficients.
    #[inline]
    pub(crate) fn prefetch_record(&self, r: usize) {
        if let Some(&start) = self.offsets.get(2 * r) {
            let start = start as usize;
            crate::prefetch::prefetch(&self.neighbours, start);
            // A list of ~12 indices may straddle two cache lines.
            crate::prefetch::prefetch(&self.neighbours, start + 15);
        }
        crate::prefetch::prefetch(&self.coefficients, r);
        crate::prefetch::prefetch(&self.centres, r);
    }

    /// Gives back the room reserved for records that were not made (the neighbour
    /// lists are reserved for about twelve indices per record).
    pub(crate) fn shrink_to_fit(&mut self) {
        self.neighbours.shrink_to_fit();
        self.offsets.shrink_to_fit();
        self.coefficients.shrink_to_fit();
        self.framed.shrink_to_fit();
        self.centres.shrink_to_fit();
    }

    /// Bytes used (for reports).
    pub(crate) fn heap_bytes(&self) -> usize {
        self.neighbours.capacity() * 4
            + self.offsets.capacity() * 4
            + self.coefficients.capacity() * std::mem::size_of::<[DVec3; 2]>()
            + self.framed.capacity()
            + self.centres.capacity() * std::mem::size_of::<DVec3>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DAffine3;

    #[test]
    fn zero_translation_keeps_signed_zero() {
        let p = DVec3::new(-0.0, 1.0, -2.5);
        let q = translate_exact(p, DVec3::ZERO);
        assert_eq!(
            q.to_array().map(f64::to_bits),
            p.to_array().map(f64::to_bits)
        );
        let q = translate_exact(p, DVec3::new(0.0, 1.0, 0.0));
        assert_eq!(q.y, 2.0);
        assert_eq!(q.x.to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn centroid_is_order_deterministic() {
        let positions = vec![
            DVec3::new(0.1, 0.2, 0.3),
            DVec3::new(1e16, -3.0, 0.7),
            DVec3::new(-1e16, 5.0, 0.1),
        ];
        let at = Collapsed {
            p0: DVec3::X,
            p1: DVec3::Y,
            placed: DVec3::Z,
        };
        let mut d = Details::with_capacity(DetailMode::Translation, 1);
        d.push(
            &positions,
            [0u32, 1, 2].into_iter(),
            [2u32].into_iter(),
            [7, 8],
            at,
        );
        assert_eq!(
            d.placement(0, &positions, None, DVec3::Z, at, false, false),
            Placement::At([at.p0, at.p1])
        );
        let (a, b) = d.lists(0);
        assert_eq!((a, b), (&[0u32, 1, 2][..], &[2u32][..]));
    }

    /// A hexagon ring around the origin, in the plane z = 0.
    fn ring() -> Vec<DVec3> {
        (0..6)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 6.0;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect()
    }

    #[test]
    fn local_frames_follow_a_similarity_of_the_neighbourhood() {
        let positions = ring();
        let at = Collapsed {
            p0: DVec3::new(0.3, 0.1, 0.2),
            p1: DVec3::new(-0.2, 0.05, -0.1),
            placed: DVec3::new(0.05, 0.07, 0.04),
        };
        let mut d = Details::with_capacity(DetailMode::LocalFrame, 1);
        d.push(
            &positions,
            [0u32, 1, 2, 3].into_iter(),
            [3u32, 4, 5, 0].into_iter(),
            [7, 8],
            at,
        );
        // Unmoved survivor: the recorded positions, exactly.
        assert_eq!(
            d.placement(0, &positions, None, at.placed, at, false, false),
            Placement::Recorded
        );
        // Rotate, scale and translate everything: the endpoints follow exactly.
        let t = DAffine3::from_scale_rotation_translation(
            DVec3::splat(1.7),
            glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 1.1),
            DVec3::new(4.0, -2.0, 3.0),
        );
        let moved: Vec<DVec3> = positions.iter().map(|&p| t.transform_point3(p)).collect();
        let Placement::At([q0, q1]) = d.placement(
            0,
            &moved,
            None,
            t.transform_point3(at.placed),
            at,
            false,
            false,
        ) else {
            panic!("a moved survivor is placed")
        };
        assert!((q0 - t.transform_point3(at.p0)).length() < 1e-12);
        assert!((q1 - t.transform_point3(at.p1)).length() < 1e-12);
        // The translation scheme keeps the detail unrotated.
        let mut paper = Details::with_capacity(DetailMode::Translation, 1);
        paper.push(
            &positions,
            [0u32, 1, 2, 3].into_iter(),
            [3u32, 4, 5, 0].into_iter(),
            [7, 8],
            at,
        );
        let Placement::At([r0, _]) = paper.placement(
            0,
            &moved,
            None,
            t.transform_point3(at.placed),
            at,
            false,
            false,
        ) else {
            panic!()
        };
        assert!((r0 - t.transform_point3(at.p0)).length() > 1e-3);
    }

    /// The lists of a record, stored one after the other.
    fn lists<'a>(l0: &'a [u32], l1: &'a [u32]) -> Lists<'a> {
        let link: Vec<u32> = l0.iter().chain(l1).copied().collect();
        Lists {
            l0,
            l1,
            link: Box::leak(link.into_boxed_slice()),
        }
    }

    #[test]
    fn degenerate_neighbourhoods_have_no_frame() {
        let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        assert_eq!(Frame::choose(&line, lists(&[0, 1, 2], &[])), None);
        let point = [DVec3::ONE; 3];
        assert_eq!(Frame::choose(&point, lists(&[0, 1, 2], &[2])), None);
        let nan = [DVec3::ZERO, DVec3::X, DVec3::new(0.0, f64::NAN, 0.0)];
        assert_eq!(Frame::choose(&nan, lists(&[0, 1, 2], &[])), None);
        assert_eq!(
            Frame::choose(&ring(), lists(&[0, 1, 2, 3, 4, 5], &[]))
                .unwrap()
                .0,
            LINK
        );
        assert_eq!(
            Frame::choose(&ring(), lists(&[0, 2, 4], &[0, 2, 4]))
                .unwrap()
                .0,
            1
        );
    }

    #[test]
    fn local_frames_follow_an_affine_map_of_the_tangent_plane() {
        // A shear and stretch within the ring's plane: tangential offsets follow exactly.
        let positions = ring();
        let at = Collapsed {
            p0: DVec3::new(0.3, 0.1, 0.0),
            p1: DVec3::new(-0.2, 0.05, 0.0),
            placed: DVec3::new(0.05, 0.07, 0.0),
        };
        let mut d = Details::with_capacity(DetailMode::LocalFrame, 1);
        d.push(
            &positions,
            [0u32, 1, 2, 3, 4, 5].into_iter(),
            [0u32, 2].into_iter(),
            [7, 8],
            at,
        );
        let t = glam::DAffine3::from_mat3(glam::DMat3::from_cols(
            DVec3::new(2.0, 0.3, 0.0),
            DVec3::new(0.5, 0.7, 0.0),
            DVec3::Z,
        ));
        let moved: Vec<DVec3> = positions.iter().map(|&p| t.transform_point3(p)).collect();
        let Placement::At([q0, q1]) = d.placement(
            0,
            &moved,
            None,
            t.transform_point3(at.placed),
            at,
            false,
            false,
        ) else {
            panic!()
        };
        assert!((q0 - t.transform_point3(at.p0)).length() < 1e-12);
        assert!((q1 - t.transform_point3(at.p1)).length() < 1e-12);
    }

    #[test]
    fn affine_marks_need_the_survivor_to_match() {
        let at = Collapsed {
            p0: DVec3::new(1.0, 2.0, 3.0),
            p1: DVec3::new(2.0, 2.0, 3.0),
            placed: DVec3::new(1.5, 2.0, 3.0),
        };
        let t = DAffine3::from_rotation_z(0.7) * DAffine3::from_translation(DVec3::X);
        let anchor = t.transform_point3(at.placed);
        let [q0, q1] = Details::motion_placement(&Motion::Affine(t), anchor, at).unwrap();
        assert_eq!(q0, t.transform_point3(at.p0));
        assert_eq!(q1, t.transform_point3(at.p1));
        assert!(
            Details::motion_placement(&Motion::Affine(t), anchor + DVec3::Y * 1e-6, at).is_none()
        );
    }

    #[test]
    fn an_interpolated_split_that_folds_its_faces_is_drawn_back_towards_the_survivor() {
        // The hexagon at rest and now, the survivor at its centre: endpoints that stay
        // inside the ring turn nothing over and are kept as they are; an endpoint thrown
        // beyond the ring (as an interpolation between very different motions can)
        // turns its fan over and is drawn back until nothing is turned over.
        let positions = ring();
        let rest: Vec<[f64; 3]> = positions.iter().map(|p| p.to_array()).collect();
        let at = Collapsed {
            p0: DVec3::new(-0.25, 0.0, 0.0),
            p1: DVec3::new(0.35, 0.0, 0.0),
            placed: DVec3::ZERO,
        };
        let lists = lists(&[0, 1, 2, 3], &[3, 4, 5, 0]);
        let lifted = DVec3::new(0.0, 0.0, 0.2);
        let inside = [at.p0 + lifted, at.p1 + DVec3::new(0.1, 0.05, 0.1)];
        assert_eq!(turned_over(&positions, &rest, lists, at, inside), 0);
        assert_eq!(unfold(&positions, &rest, lists, lifted, at, inside), inside);
        let folded = [at.p0, DVec3::new(-2.5, 0.0, 0.0)];
        assert!(turned_over(&positions, &rest, lists, at, folded) > 0);
        let drawn = unfold(&positions, &rest, lists, lifted, at, folded);
        assert_eq!(turned_over(&positions, &rest, lists, at, drawn), 0);
        // drawn back along the way to the survivor's translation of the record
        let direction = (folded[1] - (at.p1 + lifted)).normalize();
        let back = drawn[1] - (at.p1 + lifted);
        assert!(back.cross(direction).length() < 1e-12 && back.dot(direction) >= 0.0);
    }

    #[test]
    fn a_survivor_moved_apart_from_its_ring_spreads_its_motion_over_its_endpoints() {
        // The hexagon at rest, the survivor at the centre lifted by 1 along z: each
        // endpoint takes `max(1 − 2λ, 0)` of the lift, `λ` its hat coordinate (its
        // fraction of the way to the ring): the motion falls to zero half-way to the
        // still ring, where the ring's own (exact) descendants begin.
        let positions = ring();
        let rest: Vec<[f64; 3]> = positions.iter().map(|p| p.to_array()).collect();
        let at = Collapsed {
            p0: DVec3::new(-0.25, 0.0, 0.0),
            p1: DVec3::new(0.75, 0.0, 0.0),
            placed: DVec3::ZERO,
        };
        let mut d = Details::with_capacity(DetailMode::LocalFrame, 1);
        d.push(
            &positions,
            [0u32, 1, 2, 3].into_iter(),
            [3u32, 4, 5, 0].into_iter(),
            [7, 8],
            at,
        );
        // The ring's vertices stay where they were (their clusters do not move).
        let still = |i: u32, _: DVec3| (i < 6).then_some(DVec3::ZERO);
        let lifted = DVec3::Z;
        let Placement::At([q0, q1]) = d.placement(
            0,
            &positions,
            Some((&rest, &still)),
            lifted,
            at,
            false,
            false,
        ) else {
            panic!("a moved survivor is placed")
        };
        for (q, p, lambda) in [(q0, at.p0, 0.25), (q1, at.p1, 0.75)] {
            let motion = q - p;
            assert!(
                (motion - f64::max(1.0 - 2.0 * lambda, 0.0) * DVec3::Z).length() < 1e-12,
                "{motion} at λ = {lambda}"
            );
        }
        // Unmoved and outside any region: exactly where it was; in a region with its
        // ring moved, it takes its share of the ring's motion.
        assert_eq!(
            d.placement(
                0,
                &positions,
                Some((&rest, &still)),
                at.placed,
                at,
                false,
                false
            ),
            Placement::Recorded
        );
        let mut moved = positions.clone();
        moved[0] += DVec3::Z;
        let others_still = |i: u32, _: DVec3| (i > 0 && i < 6).then_some(DVec3::ZERO);
        let Placement::At([_, q1]) = d.placement(
            0,
            &moved,
            Some((&rest, &others_still)),
            at.placed,
            at,
            true,
            false,
        ) else {
            panic!("a survivor in a region is placed")
        };
        assert!(q1.z > 0.1 && q1.z < 1.0, "{q1}");
    }
}
