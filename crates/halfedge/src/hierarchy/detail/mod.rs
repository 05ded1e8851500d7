mod frame;
mod interpolate;
#[cfg(test)]
mod tests;

use glam::DVec3;

use crate::hierarchy::motion::Motion;

use frame::NO_RING;
pub(crate) use frame::{centroid, translate_exact, Frame, Lists, Ring};
use interpolate::{interpolate, moved_together, settle, unfold, Before};

/// How a split places its vertices after an edit at a coarser level (see the
/// [docs above](Self)).
///
/// Detail coefficients: how a split places the two vertices of its record after the mesh
/// was edited at a coarser level.
///
/// Two schemes ([`DetailMode`]), chosen when the hierarchy is built:
///
/// - [`DetailMode::LocalFrame`] (the default), after the local-frame details of Kobbelt,
///   Campagna, Vorsatz & Seidel (1998) and Guskov, Sweldens & Schröder (1999): at collapse
///   time each endpoint's position is stored as an offset from the survivor's placed
///   position, in a frame of the collapsed edge's link (the ring of vertices around the
///   edge): its first Fourier mode `Σ cos(2πj/n) q_j`, `Σ sin(2πj/n) q_j` gives two
///   tangents that follow every affine map of the ring, the third axis is their normal
///   scaled by the square root of their area. The centroid of that ring is stored in the
///   same frame. At split time the frame is built again from the neighbours' current
///   positions. Where the survivor moved *with* its ring (it is where the ring's motion,
///   read through the frame, puts it), both endpoints go to the survivor's position plus
///   their offsets in the new frame: a neighbourhood translated, rotated, scaled or
///   sheared at a coarse level takes its detail along, turned and scaled with it. Where
///   it moved *apart* from its ring (a vertex dragged on its own, the edge of a moved
///   region, a fast-varying edit), each endpoint is also written in the affine frame of
///   the coarse triangle it lies over (survivor and two link vertices, where they were
///   before the edit), and the two placements are blended by the survivor's hat function:
///   the frame's near the survivor, the triangle's towards the link, where it meets the
///   neighbours' own motion. So the fine vertices' motion interpolates the coarse
///   vertices' (to second order for smooth edits) instead of stepping between them.
/// - [`DetailMode::Translation`], the seed paper's centroid translations ("Interactive
///   Editing of Multiresolution Meshes", section 3, Fig. 1): each endpoint takes its
///   recorded position plus the translation `C_f − C_i` of the centroid of its own
///   neighbours. Rotations are not carried (a rotated part comes back with unrotated
///   detail) and every split averages moved and unmoved neighbours, so an edit diffuses
///   about one ring further at every level. Kept for fidelity with the paper.
///
/// **Regions** (local frames only): a split whose survivor is exactly where the hierarchy
/// left it (bit for bit) puts both endpoints back at their recorded positions, unless the
/// survivor is in an edit's region ([`crate::hierarchy::Hierarchy::mark_region`]). So outside the
/// regions a fine vertex moves only when its *ancestor* at the edited level (the vertex
/// it was collapsed into) moved: everything an edit left in place stays exact at every
/// finer level. Inside a region, an unmoved vertex next to moved ones takes its share of
/// their motion, so the transition between moved and still parts is the edit's own. A
/// survivor marked with an affine map ([`crate::hierarchy::Hierarchy::mark_affine`]) whose position
/// is that map's image of where the hierarchy left it places both endpoints at the map's
/// image of their recorded positions, exactly: rigidly moved handles land where the user
/// put them.
///
/// Exactness: the frame (and the centroids) are computed by one function over the same
/// neighbour list in the same order at collapse and at split time, so with no edit they
/// agree bit for bit; and the hierarchy skips all of this while no position was edited.
///
/// Storage is flat: one `Vec<u32>` of neighbour vertex indices for all records, with two
/// lists per record (`v0`'s, then `v1`'s) delimited by one offset array, two vectors per
/// record (the local offsets, or the recorded centroids), and with local frames the
/// ring's centroid and which ring the frame is built from. The positions before an edit,
/// which the triangle placement reads, are kept by the hierarchy (one copy of the edited
/// level's vertices, taken by `Hierarchy::mesh_mut`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DetailMode {
    /// Offsets in a local frame of the neighbourhood, anchored at the survivor; regions
    /// that did not move stay exact; affine marks land exactly. The default.
    #[default]
    LocalFrame,
    /// The seed paper's centroid translations `C_f − C_i` (section 3, Fig. 1).
    Translation,
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
            neighbours: super::buffers::prefaulted(n),
            offsets: super::buffers::prefaulted(o),
            coefficients: super::buffers::prefaulted(c),
            framed: super::buffers::prefaulted(f),
            centres: super::buffers::prefaulted(e),
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

/// The arrays of [`Details`], borrowed (see [`Details::raw_parts`]).
pub(crate) struct DetailParts<'a> {
    pub(crate) neighbours: &'a [u32],
    pub(crate) offsets: &'a [u32],
    pub(crate) coefficients: &'a [[DVec3; 2]],
    pub(crate) framed: &'a [Ring],
    pub(crate) centres: &'a [DVec3],
}

/// The arrays of [`Details`], owned (see [`Details::from_raw_parts`]).
pub(crate) struct DetailVecs {
    pub(crate) neighbours: Vec<u32>,
    pub(crate) offsets: Vec<u32>,
    pub(crate) coefficients: Vec<[DVec3; 2]>,
    pub(crate) framed: Vec<Ring>,
    pub(crate) centres: Vec<DVec3>,
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
        super::buffers::adopt(&mut self.neighbours, neighbours);
        super::buffers::adopt(&mut self.offsets, offsets);
        super::buffers::adopt(&mut self.coefficients, coefficients);
        super::buffers::adopt(&mut self.framed, framed);
        super::buffers::adopt(&mut self.centres, centres);
    }

    /// The arrays as they are kept (for the hierarchy file).
    pub(crate) fn raw_parts(&self) -> DetailParts<'_> {
        DetailParts {
            neighbours: &self.neighbours,
            offsets: &self.offsets,
            coefficients: &self.coefficients,
            framed: &self.framed,
            centres: &self.centres,
        }
    }

    /// Details from [`raw_parts`](Self::raw_parts) read back from a file for `records`
    /// records of a mesh with `vertex_slots` vertex slots, checked: two lists per record
    /// delimited by non-decreasing offsets from 0 to the end of the neighbours, every
    /// neighbour a vertex slot, one pair of coefficients per record, and with local
    /// frames one known ring and one centre per record (none with translations). Says
    /// what is wrong otherwise.
    pub(crate) fn from_raw_parts(
        mode: DetailMode,
        parts: DetailVecs,
        records: usize,
        vertex_slots: usize,
    ) -> Result<Self, String> {
        let DetailVecs {
            neighbours,
            offsets,
            coefficients,
            framed,
            centres,
        } = parts;
        if offsets.len() != 2 * records + 1 {
            return Err(format!(
                "{} list offsets for {records} records (expected {})",
                offsets.len(),
                2 * records + 1
            ));
        }
        if offsets[0] != 0 || offsets[offsets.len() - 1] as usize != neighbours.len() {
            return Err(format!(
                "the neighbour lists do not span the {} neighbours",
                neighbours.len()
            ));
        }
        if let Some(k) = offsets.windows(2).position(|w| w[0] > w[1]) {
            return Err(format!("list offset {k} is past the next one"));
        }
        if let Some(k) = neighbours.iter().position(|&i| i as usize >= vertex_slots) {
            return Err(format!(
                "neighbour {k} is vertex slot {}, of {vertex_slots}",
                neighbours[k]
            ));
        }
        if coefficients.len() != records {
            return Err(format!(
                "{} coefficient pairs for {records} records",
                coefficients.len()
            ));
        }
        let framed_len = if mode == DetailMode::LocalFrame {
            records
        } else {
            0
        };
        if framed.len() != framed_len || centres.len() != framed_len {
            return Err(format!(
                "{} frame rings and {} centres for {records} records in {mode:?}",
                framed.len(),
                centres.len()
            ));
        }
        if let Some(r) = framed.iter().position(|&ring| ring > frame::LINK) {
            return Err(format!("record {r} names the unknown ring {}", framed[r]));
        }
        Ok(Self {
            mode,
            neighbours,
            offsets,
            coefficients,
            framed,
            centres,
        })
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
    /// the survivor is in an edit's region ([`crate::hierarchy::Hierarchy::mark_region`]), so it is
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
