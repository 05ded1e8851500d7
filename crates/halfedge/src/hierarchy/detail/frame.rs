//! Local frames of a collapsed edge's neighbourhood: ring tangents (first Fourier mode),
//! centroids, and exact translations.

use glam::DVec3;

/// Cosines and sines of `2π j / n` for `j < n`, for ring lengths up to
/// [`TABLED_RING`] (computed once, so every frame of a ring uses the same bits).
pub(super) const TABLED_RING: usize = 96;

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
pub(super) fn ring_tangents_with(
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
    pub(super) axes: glam::DMat3,
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
pub(super) const NO_RING: Ring = 0;
/// The frame is built from the edge's link (both lists, one loop).
pub(super) const LINK: Ring = 3;

impl Lists<'_> {
    /// The list of ring `ring` (1: `l0`, 2: `l1`, otherwise the link).
    #[inline]
    pub(super) fn ring(&self, ring: Ring) -> &[u32] {
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
    pub(super) fn of_ring_with_centroid(
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
    pub(super) fn overflows(positions: &[DVec3], lists: Lists<'_>, ring: Ring) -> bool {
        let list = match ring {
            1 => lists.l0,
            2 => lists.l1,
            _ => lists.link,
        };
        ring_tangents(positions, list).is_some_and(|(x, y)| !(x.is_finite() && y.is_finite()))
    }

    #[inline]
    pub(super) fn from_tangents(x: DVec3, y: DVec3) -> Option<Self> {
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
    pub(super) fn local(&self, v: DVec3) -> Option<DVec3> {
        let d = self.axes.inverse() * v;
        d.is_finite().then_some(d)
    }

    /// The world offset of local coordinates `d`.
    #[inline]
    pub(super) fn world(&self, d: DVec3) -> DVec3 {
        self.axes * d
    }
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
