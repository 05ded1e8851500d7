//! Euclidean distances to border polylines in a uniform grid (Bendels & Klein, Sec. 4.1).

use std::collections::HashMap;

use glam::DVec3;
use rayon::prelude::*;

use crate::bendels_klein::error::{BendelsKleinError, Result};

/// Euclidean distance from `p` to the segment `[a, b]` (a point when `a == b`): the
/// arithmetic every query of this module uses, so brute force and grid agree exactly.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 4.1, eq. (1)–(2).
#[inline]
#[must_use]
pub fn point_segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    Segment::new(a, b).distance_squared(p).sqrt()
}

#[derive(Clone, Copy, Debug)]
struct Segment {
    a: DVec3,
    d: DVec3,
    inv_len2: f64,
}

impl Segment {
    #[inline]
    fn new(a: DVec3, b: DVec3) -> Self {
        let d = b - a;
        let l2 = d.length_squared();
        Self {
            a,
            d,
            inv_len2: if l2 > 0.0 { 1.0 / l2 } else { 0.0 },
        }
    }
    #[inline]
    fn closest(&self, p: DVec3) -> DVec3 {
        let t = ((p - self.a).dot(self.d) * self.inv_len2).clamp(0.0, 1.0);
        self.a + self.d * t
    }
    #[inline]
    fn distance_squared(&self, p: DVec3) -> f64 {
        let w = p - self.a;
        let t = (w.dot(self.d) * self.inv_len2).clamp(0.0, 1.0);
        (w - self.d * t).length_squared()
    }
}

type Cell = [i32; 3];

/// Most half-cell pieces a [`BorderGrid`] traces its segments in (a segment much longer
/// than the cell size is traced in many): about a few hundred MB of cell lists at most.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 4.1.
pub const MAX_TRACED_PIECES: usize = 1 << 22;

/// Euclidean distance to border polylines (Bendels & Klein, Sec. 4.1, eq. 1–2):
/// `d_E(v, border) = min_i d(v, (v_i v_{i+1}))` over the border's segments.
///
/// [`BorderGrid`] is the paper's spatial search structure: a uniform grid (cell size
/// twice the mean edge length, so that an edge lies in one or two cells) whose cells list
/// the border segments that pass through them; segments are inserted by tracing the
/// cells along them, so rebuilding for new borders costs O(border edges).
/// [`BorderGrid::distance`] answers one query by searching rings of cells around the
/// query cell until no unseen cell can hold a nearer segment.
///
/// For a whole field the ring search alone is slow far from the border (the rings to
/// search grow as (d / cell)³). [`BorderGrid::distances`] therefore buckets the query
/// points into the same uniform grid ([`QueryPoints`], cells in Morton order, built
/// once per point set and shared by the handle and fixed fields) and walks the implicit
/// octree of those cells top-down, handing each block of cells the list of segments
/// that can still be nearest to some point in it. A segment `s` is dropped for a block
/// (centre `c`, radius `r`) when a lower bound of `d(q, s) − d(q, s*)` over the block is
/// positive, `s*` being the segment nearest to `c`: with `g_s = d(c, s)`, `u_s` the unit
/// vector from `s` to `c`, `D* = d(c, s*)`,
///
/// ```text
/// d(q, s) − d(q, s*) ≥ (g_s − D*) − min(2r, |u_s − u*| r + r² / (2 D*))
/// ```
///
/// (convexity of `d(·, s)` and a second-order bound of `|q − x*|`). Far from the border
/// the segments seen from a block under nearly the same direction are cut quickly, so a
/// leaf keeps a handful of candidates and each point costs a few segment tests. Every
/// point is finally evaluated against a superset of its nearest segments with the same
/// arithmetic as [`point_segment_distance`], so the field equals the brute-force minimum
/// bit for bit.
///
/// Border segments in a uniform grid (Bendels & Klein, Sec. 4.1): insertion by tracing
/// the cells along each segment, single queries by ring search, whole fields by
/// [`BorderGrid::distances`].
#[derive(Clone, Debug)]
pub struct BorderGrid {
    cell: f64,
    segments: Vec<Segment>,
    cells: HashMap<Cell, Vec<u32>>,
}

impl BorderGrid {
    /// An empty grid with the given cell size (the paper: twice the mean edge length).
    ///
    /// # Errors
    /// [`BendelsKleinError::InvalidParameter`] unless `cell_size` is finite and positive.
    pub fn new(cell_size: f64) -> Result<Self> {
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(BendelsKleinError::InvalidParameter {
                name: "cell_size",
                reason: format!("must be finite and positive, got {cell_size}"),
            });
        }
        Ok(Self {
            cell: cell_size,
            segments: Vec::new(),
            cells: HashMap::new(),
        })
    }

    /// A grid holding `segments`, with cell size `cell_size`.
    ///
    /// # Errors
    /// As [`BorderGrid::new`], and [`BendelsKleinError::InvalidParameter`] for non-finite
    /// endpoints.
    pub fn from_segments(
        cell_size: f64,
        segments: impl IntoIterator<Item = (DVec3, DVec3)>,
    ) -> Result<Self> {
        let mut grid = Self::new(cell_size)?;
        grid.set_segments(segments)?;
        Ok(grid)
    }

    /// The cell size.
    #[must_use]
    pub fn cell_size(&self) -> f64 {
        self.cell
    }
    /// Number of segments.
    #[must_use]
    pub fn len(&self) -> usize {
        self.segments.len()
    }
    /// True when the grid holds no segment.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// Removes every segment (keeps the allocations).
    pub fn clear(&mut self) {
        self.segments.clear();
        for list in self.cells.values_mut() {
            list.clear();
        }
    }

    /// Replaces the segments (the borders changed): a rebuild in O(segments). On error
    /// the grid is unchanged.
    ///
    /// # Errors
    /// [`BendelsKleinError::InvalidParameter`] for a non-finite endpoint, or when the segments
    /// are so long for the cell size that tracing them would take more than
    /// [`MAX_TRACED_PIECES`] pieces.
    pub fn set_segments(
        &mut self,
        segments: impl IntoIterator<Item = (DVec3, DVec3)>,
    ) -> Result<()> {
        let segments: Vec<(DVec3, DVec3)> = segments.into_iter().collect();
        if let Some(i) = segments
            .iter()
            .position(|(a, b)| !(a.is_finite() && b.is_finite()))
        {
            return Err(BendelsKleinError::InvalidParameter {
                name: "segments",
                reason: format!("segment {i} has a non-finite endpoint"),
            });
        }
        let pieces: f64 = segments.iter().map(|&(a, b)| self.pieces(a, b)).sum();
        self.check_pieces(pieces)?;
        self.clear();
        self.cells.retain(|_, list| !list.is_empty());
        for (a, b) in segments {
            self.push(a, b);
        }
        Ok(())
    }

    /// Number of half-cell pieces [`push`](Self::push) traces `a b` in (as f64: it may be
    /// huge or infinite for a tiny cell).
    fn pieces(&self, a: DVec3, b: DVec3) -> f64 {
        (a.distance(b) / (0.5 * self.cell)).ceil().max(1.0)
    }

    /// Refuses to trace more than [`MAX_TRACED_PIECES`] pieces (each lists the segment in
    /// up to 8 cells): a cell size far below the segments' lengths would fill memory.
    fn check_pieces(&self, pieces: f64) -> Result<()> {
        if pieces.is_finite() && pieces + (self.len() as f64) <= MAX_TRACED_PIECES as f64 {
            return Ok(());
        }
        Err(BendelsKleinError::InvalidParameter {
            name: "cell_size",
            reason: format!(
                "cells of {} would be traced {pieces} times by the segments (at most \
                 {MAX_TRACED_PIECES}): the cell size is too small for them",
                self.cell
            ),
        })
    }

    /// Adds one segment, tracing the cells it passes through (the paper's incremental
    /// insertion). Returns its index.
    ///
    /// # Errors
    /// As [`set_segments`](Self::set_segments).
    pub fn insert_segment(&mut self, a: DVec3, b: DVec3) -> Result<usize> {
        if !(a.is_finite() && b.is_finite()) {
            return Err(BendelsKleinError::InvalidParameter {
                name: "segment",
                reason: "non-finite endpoint".into(),
            });
        }
        self.check_pieces(self.pieces(a, b))?;
        Ok(self.push(a, b))
    }

    fn push(&mut self, a: DVec3, b: DVec3) -> usize {
        let id = self.segments.len() as u32;
        self.segments.push(Segment::new(a, b));
        // Trace: pieces no longer than half a cell, each piece's box of cells. A
        // superset of the cells the segment meets, each listed once.
        let pieces = self.pieces(a, b) as usize;
        for k in 0..pieces {
            let p = a.lerp(b, k as f64 / pieces as f64);
            let q = a.lerp(b, (k + 1) as f64 / pieces as f64);
            let lo = self.cell_of(p.min(q));
            let hi = self.cell_of(p.max(q));
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        let list = self.cells.entry([x, y, z]).or_default();
                        if !list.contains(&id) {
                            list.push(id);
                        }
                    }
                }
            }
        }
        id as usize
    }

    #[inline]
    fn cell_of(&self, p: DVec3) -> Cell {
        let c = (p / self.cell).floor();
        [
            c.x.clamp(-1e9, 1e9) as i32,
            c.y.clamp(-1e9, 1e9) as i32,
            c.z.clamp(-1e9, 1e9) as i32,
        ]
    }

    /// Brute-force distance from `p` to the nearest segment (`+∞` without segments).
    #[must_use]
    pub fn distance_brute_force(&self, p: DVec3) -> f64 {
        self.segments
            .iter()
            .map(|s| s.distance_squared(p))
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    /// Distance from `p` to the nearest segment by ring search in the grid (`+∞`
    /// without segments). Exact: equal to [`BorderGrid::distance_brute_force`].
    #[must_use]
    pub fn distance(&self, p: DVec3) -> f64 {
        if self.segments.is_empty() {
            return f64::INFINITY;
        }
        let c = self.cell_of(p);
        let mut best = f64::INFINITY;
        let mut visited = 0usize;
        for k in 0i32.. {
            // Cells at Chebyshev distance exactly k from c.
            for x in -k..=k {
                for y in -k..=k {
                    let on_shell = x.abs() == k || y.abs() == k;
                    let zs: &mut dyn Iterator<Item = i32> = if on_shell {
                        &mut (-k..=k)
                    } else {
                        &mut [-k, k].into_iter()
                    };
                    for z in zs {
                        if k == 0 && z != 0 {
                            continue;
                        }
                        visited += 1;
                        if let Some(list) = self.cells.get(&[c[0] + x, c[1] + y, c[2] + z]) {
                            for &s in list {
                                best = best.min(self.segments[s as usize].distance_squared(p));
                            }
                        }
                    }
                }
            }
            // Unseen segments lie in cells at ring ≥ k + 1: at least k cells away.
            if best.sqrt() <= k as f64 * self.cell {
                break;
            }
            if visited > 8 * self.segments.len() + 64 {
                return self.distance_brute_force(p);
            }
        }
        best.sqrt()
    }

    /// Distances from every point to the nearest segment, in parallel (see the module
    /// docs). Equal to [`BorderGrid::distance_brute_force`] point by point.
    #[must_use]
    pub fn distances(&self, points: &[DVec3]) -> Vec<f64> {
        self.distances_to(&QueryPoints::new(points, self.cell))
    }

    /// Distances to the nearest segment for prepared query points (in the order the
    /// points were given to [`QueryPoints::new`]).
    #[must_use]
    pub fn distances_to(&self, queries: &QueryPoints) -> Vec<f64> {
        let n = queries.order.len();
        if self.segments.is_empty() || n == 0 {
            return vec![f64::INFINITY; n];
        }
        let mut sorted = vec![0.0; n];
        let all: Vec<u32> = (0..self.segments.len() as u32).collect();
        let node = Node {
            level: 0,
            prefix: 0,
            start: 0,
        };
        self.descend(queries, node, &all, &mut sorted);
        let mut out = vec![0.0; n];
        for (&i, &d) in queries.order.iter().zip(&sorted) {
            out[i as usize] = d;
        }
        out
    }

    /// The fields of two borders over the same prepared points, in one walk of the
    /// query octree: `(distances to self, distances to other)`, each equal bit for bit to
    /// [`distances_to`](Self::distances_to). Bendels & Klein need both the handle and
    /// the fixed border's field; sharing the walk shares the node bounds and the memory
    /// traffic over the points.
    #[must_use]
    pub fn distances_to_pair(
        &self,
        other: &BorderGrid,
        queries: &QueryPoints,
    ) -> (Vec<f64>, Vec<f64>) {
        let n = queries.order.len();
        if self.segments.is_empty() || other.segments.is_empty() || n == 0 {
            return (self.distances_to(queries), other.distances_to(queries));
        }
        let mut sorted = vec![[0.0; 2]; n];
        let all = |g: &BorderGrid| (0..g.segments.len() as u32).collect::<Vec<u32>>();
        let node = Node {
            level: 0,
            prefix: 0,
            start: 0,
        };
        descend_pair(
            [self, other],
            queries,
            node,
            [&all(self), &all(other)],
            &mut sorted,
        );
        let mut first = vec![0.0; n];
        let mut second = vec![0.0; n];
        for (&i, &[a, b]) in queries.order.iter().zip(&sorted) {
            first[i as usize] = a;
            second[i as usize] = b;
        }
        (first, second)
    }

    fn descend(&self, q: &QueryPoints, node: Node, candidates: &[u32], out: &mut [f64]) {
        let points = &q.sorted_points[node.start..node.start + out.len()];
        let (centre, radius) = node_bounds(q, node, points);
        let kept = self.filter(candidates, centre, radius);
        let leaf = points.len() <= 32 || kept.len() <= 2 || node.level == q.depth;
        if leaf {
            for (p, d) in points.iter().zip(out.iter_mut()) {
                *d = self.nearest(&kept, *p);
            }
            return;
        }
        let children = split_children(q, node, out);
        if out_len(&children) > 8192 {
            children
                .into_par_iter()
                .for_each(|(child, slice)| self.descend(q, child, &kept, slice));
        } else {
            for (child, slice) in children {
                self.descend(q, child, &kept, slice);
            }
        }
    }

    /// Distance from `p` to the nearest of the `kept` segments (a leaf of the walk).
    #[inline]
    fn nearest(&self, kept: &[u32], p: DVec3) -> f64 {
        kept.iter()
            .map(|&s| self.segments[s as usize].distance_squared(p))
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    /// The candidates that can be nearest to some point of the ball (centre, radius).
    /// Two passes: the nearest candidate to the centre first (squared distances only),
    /// then the bound of the module docs, tested without square roots where possible.
    fn filter(&self, candidates: &[u32], centre: DVec3, radius: f64) -> Vec<u32> {
        let mut best = (f64::INFINITY, 0u32);
        for &s in candidates {
            let d2 = self.segments[s as usize].distance_squared(centre);
            if d2 < best.0 {
                best = (d2, s);
            }
        }
        let d_star = best.0.sqrt();
        let x_star = self.segments[best.1 as usize].closest(centre);
        let u_star = if d_star > 0.0 {
            (centre - x_star) / d_star
        } else {
            DVec3::ZERO
        };
        let slack = 1e-9 * (d_star + radius) + 1e-300;
        let coarse = 2.0 * radius + slack;
        let curvature = if d_star > 0.0 {
            radius * radius / (2.0 * d_star)
        } else {
            f64::INFINITY
        };
        let mut kept = Vec::with_capacity(candidates.len().min(64));
        for &s in candidates {
            let x = self.segments[s as usize].closest(centre);
            let g = centre.distance(x);
            let excess = g - d_star;
            if excess > coarse {
                continue;
            }
            // Keep when excess ≤ |u − u*| r + r²/(2D*) + slack.
            let rest = excess - curvature - slack;
            if rest > 0.0 && g > 0.0 {
                let u = (centre - x) / g;
                if rest * rest > (u - u_star).length_squared() * radius * radius {
                    continue;
                }
            }
            kept.push(s);
        }
        kept
    }
}

fn out_len<T>(children: &[(Node, &mut [T])]) -> usize {
    children.iter().map(|(_, s)| s.len()).sum()
}

/// Centre and radius of a node's points: the exact ball for small nodes (and the root),
/// the octree cell's ball for large ones (no pass over the points).
fn node_bounds(q: &QueryPoints, node: Node, points: &[DVec3]) -> (DVec3, f64) {
    if points.len() <= 512 || node.level == 0 {
        let (lo, hi) = points.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let c = 0.5 * (lo + hi);
        let r = points.iter().map(|p| p.distance(c)).fold(0.0, f64::max);
        (c, r)
    } else {
        q.node_ball(node)
    }
}

/// The children of `node` (the 8 octants, contiguous in Morton order) with their parts
/// of `out`.
fn split_children<'a, T>(
    q: &QueryPoints,
    node: Node,
    out: &'a mut [T],
) -> Vec<(Node, &'a mut [T])> {
    let shift = 3 * (q.depth - node.level - 1);
    let codes = &q.codes[node.start..node.start + out.len()];
    let mut children = Vec::with_capacity(8);
    let mut rest = out;
    let mut offset = 0;
    for octant in 0..8u64 {
        let prefix = (node.prefix << 3) | octant;
        let end = codes.partition_point(|&c| (c >> shift) <= prefix);
        let (mine, tail) = rest.split_at_mut(end - offset);
        if !mine.is_empty() {
            children.push((
                Node {
                    level: node.level + 1,
                    prefix,
                    start: node.start + offset,
                },
                mine,
            ));
        }
        rest = tail;
        offset = end;
    }
    children
}

/// [`BorderGrid::descend`] for two borders at once (see
/// [`BorderGrid::distances_to_pair`]): the same bounds, filters and leaf rule per border,
/// so each field equals its single walk bit for bit.
fn descend_pair(
    grids: [&BorderGrid; 2],
    q: &QueryPoints,
    node: Node,
    candidates: [&[u32]; 2],
    out: &mut [[f64; 2]],
) {
    let points = &q.sorted_points[node.start..node.start + out.len()];
    let (centre, radius) = node_bounds(q, node, points);
    let kept = [0, 1].map(|k| grids[k].filter(candidates[k], centre, radius));
    let end = points.len() <= 32 || node.level == q.depth;
    let leaf = [0, 1].map(|k| end || kept[k].len() <= 2);
    if leaf[0] || leaf[1] {
        for k in (0..2).filter(|&k| leaf[k]) {
            for (p, d) in points.iter().zip(out.iter_mut()) {
                d[k] = grids[k].nearest(&kept[k], *p);
            }
        }
        if leaf[0] && leaf[1] {
            return;
        }
        // One border is done here; the other goes on down alone (filtering its kept
        // segments again with the same bounds keeps them all: the filter is idempotent).
        let k = usize::from(leaf[0]);
        let mut single = vec![0.0; out.len()];
        grids[k].descend(q, node, &kept[k], &mut single);
        for (d, v) in out.iter_mut().zip(single) {
            d[k] = v;
        }
        return;
    }
    let children = split_children(q, node, out);
    if out_len(&children) > 8192 {
        children
            .into_par_iter()
            .for_each(|(child, slice)| descend_pair(grids, q, child, [&kept[0], &kept[1]], slice));
    } else {
        for (child, slice) in children {
            descend_pair(grids, q, child, [&kept[0], &kept[1]], slice);
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Node {
    level: u32,
    prefix: u64,
    start: usize,
}

/// Query points bucketed in a uniform grid, cells in Morton order: the implicit octree
/// [`BorderGrid::distances_to`] walks. Build once per point set, reuse for every border.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 4.1.
#[derive(Clone, Debug)]
pub struct QueryPoints {
    origin: DVec3,
    cell: f64,
    depth: u32,
    codes: Vec<u64>,
    order: Vec<u32>,
    sorted_points: Vec<DVec3>,
}

impl QueryPoints {
    /// Buckets `points` into cells of size `cell_size` (the border grid's cell size;
    /// enlarged if the points span more than 2²⁰ cells). Non-finite points are put at
    /// the origin of the grid.
    #[must_use]
    pub fn new(points: &[DVec3], cell_size: f64) -> Self {
        let finite = |p: &DVec3| p.is_finite();
        let (lo, hi) = points.iter().filter(|p| finite(p)).fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let (lo, hi) = if lo.x.is_finite() {
            (lo, hi)
        } else {
            (DVec3::ZERO, DVec3::ZERO)
        };
        let extent = (hi - lo).max_element();
        let mut cell = if cell_size.is_finite() && cell_size > 0.0 {
            cell_size
        } else {
            1.0
        };
        if extent / cell > (1u64 << 20) as f64 {
            cell = extent / (1u64 << 20) as f64;
        }
        let cells = ((extent / cell).floor() as u64 + 1).max(1);
        let depth = 64 - (cells - 1).leading_zeros();
        let mut keyed: Vec<(u64, u32)> = points
            .par_iter()
            .enumerate()
            .map(|(i, p)| {
                let p = if p.is_finite() { *p } else { lo };
                let c = ((p - lo) / cell).floor();
                let max = (cells - 1) as f64;
                let code = morton(
                    c.x.clamp(0.0, max) as u64,
                    c.y.clamp(0.0, max) as u64,
                    c.z.clamp(0.0, max) as u64,
                );
                (code, i as u32)
            })
            .collect();
        keyed.par_sort_unstable();
        let codes = keyed.iter().map(|k| k.0).collect();
        let order: Vec<u32> = keyed.iter().map(|k| k.1).collect();
        let sorted_points = order
            .iter()
            .map(|&i| {
                let p = points[i as usize];
                if p.is_finite() {
                    p
                } else {
                    lo
                }
            })
            .collect();
        Self {
            origin: lo,
            cell,
            depth,
            codes,
            order,
            sorted_points,
        }
    }

    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.order.len()
    }
    /// True when there is no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// Ball around the octree cell of a node.
    fn node_ball(&self, node: Node) -> (DVec3, f64) {
        let (x, y, z) = unmorton(node.prefix);
        let size = self.cell * (1u64 << (self.depth - node.level)) as f64;
        let lo = self.origin + DVec3::new(x as f64, y as f64, z as f64) * size;
        (lo + DVec3::splat(0.5 * size), 0.5 * size * 3f64.sqrt())
    }
}

#[inline]
fn spread(mut x: u64) -> u64 {
    x &= 0x1f_ffff;
    x = (x | (x << 32)) & 0x1f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x1f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

#[inline]
fn compact(mut x: u64) -> u64 {
    x &= 0x1249_2492_4924_9249;
    x = (x ^ (x >> 2)) & 0x10c3_0c30_c30c_30c3;
    x = (x ^ (x >> 4)) & 0x100f_00f0_0f00_f00f;
    x = (x ^ (x >> 8)) & 0x1f_0000_ff00_00ff;
    x = (x ^ (x >> 16)) & 0x1f_0000_0000_ffff;
    x = (x ^ (x >> 32)) & 0x1f_ffff;
    x
}

#[inline]
fn morton(x: u64, y: u64, z: u64) -> u64 {
    (spread(x) << 2) | (spread(y) << 1) | spread(z)
}

fn unmorton(code: u64) -> (u64, u64, u64) {
    (compact(code >> 2), compact(code >> 1), compact(code))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_point(rng: &mut ChaCha8Rng, s: f64) -> DVec3 {
        DVec3::new(
            rng.random_range(-s..s),
            rng.random_range(-s..s),
            rng.random_range(-s..s),
        )
    }

    #[test]
    fn morton_round_trips() {
        for (x, y, z) in [(0, 0, 0), (1, 2, 3), (0x1f_ffff, 5, 0x10_0000), (7, 7, 7)] {
            assert_eq!(unmorton(morton(x, y, z)), (x, y, z));
        }
    }

    #[test]
    fn segment_distance_is_exact_on_simple_cases() {
        let (a, b) = (DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0));
        assert_eq!(point_segment_distance(DVec3::new(1.0, 3.0, 4.0), a, b), 5.0);
        assert_eq!(
            point_segment_distance(DVec3::new(-3.0, 4.0, 0.0), a, b),
            5.0
        );
        assert_eq!(point_segment_distance(DVec3::new(5.0, 0.0, 4.0), a, b), 5.0);
        assert_eq!(point_segment_distance(DVec3::new(0.0, 3.0, 4.0), a, a), 5.0);
    }

    #[test]
    fn fields_equal_brute_force_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(42);
        // A wiggly closed polyline and a few loose segments.
        let mut segments = Vec::new();
        let n = 400;
        let ring = |k: usize| {
            let t = k as f64 / n as f64 * std::f64::consts::TAU;
            DVec3::new(
                t.cos() * (1.0 + 0.2 * (7.0 * t).sin()),
                t.sin(),
                0.3 * (3.0 * t).cos(),
            )
        };
        for k in 0..n {
            segments.push((ring(k), ring(k + 1)));
        }
        for _ in 0..20 {
            let a = random_point(&mut rng, 2.0);
            segments.push((a, a + random_point(&mut rng, 0.1)));
        }
        segments.push((DVec3::splat(0.5), DVec3::splat(0.5)));
        let grid = BorderGrid::from_segments(0.03, segments.iter().copied()).unwrap();
        // Near, far and coincident points.
        let mut points: Vec<DVec3> = (0..20_000).map(|_| random_point(&mut rng, 1.5)).collect();
        points.extend((0..2000).map(|_| random_point(&mut rng, 30.0)));
        points.extend((0..n).map(ring));
        let field = grid.distances(&points);
        // The pair walk gives both fields bit for bit, with borders of different reach
        // (one small loop, so that one border bottoms out before the other).
        let small: Vec<(DVec3, DVec3)> = segments[..40].to_vec();
        let other = BorderGrid::from_segments(0.03, small.iter().copied()).unwrap();
        let queries = QueryPoints::new(&points, 0.03);
        let (first, second) = grid.distances_to_pair(&other, &queries);
        assert!(first
            .iter()
            .zip(&field)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        let alone = other.distances_to(&queries);
        assert!(second
            .iter()
            .zip(&alone)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        let (second_first, first_second) = other.distances_to_pair(&grid, &queries);
        assert_eq!((second_first, first_second), (alone, field.clone()));
        for (p, d) in points.iter().zip(&field) {
            let brute = segments
                .iter()
                .map(|&(a, b)| point_segment_distance(*p, a, b))
                .fold(f64::INFINITY, f64::min);
            assert_eq!(*d, brute, "at {p}");
            assert_eq!(*d, grid.distance_brute_force(*p));
        }
        for p in points.iter().step_by(37) {
            assert_eq!(
                grid.distance(*p),
                grid.distance_brute_force(*p),
                "ring at {p}"
            );
        }
    }

    #[test]
    fn rebuild_and_empty_grids() {
        let mut grid = BorderGrid::new(0.5).unwrap();
        assert!(grid.distances(&[DVec3::ONE])[0].is_infinite());
        assert!(grid.distance(DVec3::ONE).is_infinite());
        grid.set_segments([(DVec3::ZERO, DVec3::X)]).unwrap();
        assert_eq!(grid.distance(DVec3::new(0.5, 2.0, 0.0)), 2.0);
        grid.set_segments([(DVec3::Y * 10.0, DVec3::Y * 11.0)])
            .unwrap();
        assert_eq!(grid.len(), 1);
        assert_eq!(grid.distance(DVec3::new(0.0, 13.0, 0.0)), 2.0);
        assert!(grid
            .set_segments([(DVec3::ZERO, DVec3::splat(f64::NAN))])
            .is_err());
        assert_eq!(grid.len(), 1);
        assert!(BorderGrid::new(0.0).is_err());
        assert!(BorderGrid::new(f64::NAN).is_err());
    }
}
