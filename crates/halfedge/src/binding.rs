use std::fmt;

/// How many ancestors a source remembers: values made on an older ancestor than that are
/// refused, which is safe, and a long chain of clones (an undo stack) does not make every
/// clone longer.
const MAX_LINEAGE: usize = 16;

/// Source of instance numbers.
static NEXT_INSTANCE: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

fn next_instance() -> u64 {
    NEXT_INSTANCE.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// Who a mesh (or another source of derived values) is, and how often it changed (see
/// the [docs above](Self)). A clone is a new instance that remembers the one it was
/// cloned from.
#[derive(Debug)]
pub struct Provenance {
    instance: u64,
    connectivity: u64,
    positions: u64,
    /// The hierarchy and the number of records it had collapsed, set by a hierarchy after
    /// its own steps while it trusts its mesh, cleared by any change of connectivity.
    level: Option<(u64, usize)>,
    /// The instances this one was cloned from, oldest first, each with its connectivity
    /// count when the clone was made (the last [`MAX_LINEAGE`]).
    lineage: Vec<(u64, u64)>,
}

impl Default for Provenance {
    fn default() -> Self {
        Self::new()
    }
}

impl Clone for Provenance {
    fn clone(&self) -> Self {
        let skip = (self.lineage.len() + 1).saturating_sub(MAX_LINEAGE);
        let mut lineage = Vec::with_capacity(self.lineage.len() + 1 - skip);
        lineage.extend_from_slice(&self.lineage[skip..]);
        lineage.push((self.instance, self.connectivity));
        Self {
            instance: next_instance(),
            connectivity: self.connectivity,
            positions: self.positions,
            level: None,
            lineage,
        }
    }
}

impl Provenance {
    /// A new instance that never changed.
    #[must_use]
    pub fn new() -> Self {
        Self {
            instance: next_instance(),
            connectivity: 0,
            positions: 0,
            level: None,
            lineage: Vec::new(),
        }
    }

    /// The binding of a value derived from the source now.
    #[inline]
    #[must_use]
    pub fn binding(&self) -> Binding {
        Binding {
            instance: self.instance,
            connectivity: self.connectivity,
            positions: self.positions,
            level: self.level,
        }
    }

    /// Records a change of connectivity (elements added, removed, relinked, or a change of
    /// the number of points of a polyline): every binding made before stops fitting.
    #[inline]
    pub fn connectivity_changed(&mut self) {
        self.connectivity += 1;
        self.level = None;
    }

    /// Records that positions were (or may have been) written: bindings made before still
    /// fit, but no longer [exactly](Binding::fits_exactly).
    #[inline]
    pub fn positions_changed(&mut self) {
        self.positions = self.positions.wrapping_add(1);
    }

    /// The instance number (in messages).
    #[inline]
    #[must_use]
    pub fn instance(&self) -> u64 {
        self.instance
    }

    /// The number of connectivity changes so far.
    #[inline]
    pub(crate) fn connectivity_count(&self) -> u64 {
        self.connectivity
    }

    /// Tags the source with a hierarchy and its position (the hierarchy calls this after
    /// its own steps, while it trusts its mesh).
    #[inline]
    pub(crate) fn tag_level(&mut self, hierarchy: u64, applied: usize) {
        self.level = Some((hierarchy, applied));
    }

    /// Takes over `previous`'s instance with one more connectivity change than it had
    /// (keeping this one's position count and lineage): for a mesh put back in the place
    /// of `previous` after a rollback, so that nobody who saw the states in between
    /// trusts it.
    pub(crate) fn succeed(&mut self, previous: &Provenance) {
        self.instance = previous.instance;
        self.connectivity = previous.connectivity + 1;
        self.level = None;
    }

    /// True when the connectivity change number `count` of instance `instance` is part of
    /// this source's history: `instance` is this one, or one it was cloned from (directly
    /// or through clones) when that one had made at most `count` changes.
    pub(crate) fn is_own_history(&self, instance: u64, count: u64) -> bool {
        instance == self.instance
            || self
                .lineage
                .iter()
                .any(|&(id, forked_at)| id == instance && count <= forked_at)
    }

    /// The instances this one was cloned from, oldest first, with their connectivity
    /// counts then.
    #[cfg(test)]
    pub(crate) fn lineage(&self) -> &[(u64, u64)] {
        &self.lineage
    }
}

/// What a derived value was made for: a source instance, its connectivity and positions
/// then, and the hierarchy level it was at (see the [docs above](Self)).
///
/// Knowing whether data still fits its mesh: the one way to ask.
///
/// Every mesh (and every other source of derived values, such as a polyline of the `edit`
/// crate) keeps a [`Provenance`]: its instance number, how often its connectivity and its
/// positions changed, the instances it was cloned from, and the level its hierarchy put
/// it at. A value derived from it — an editing area, a session, regions, a sub-mesh,
/// per-vertex data, an attribute handle, a BVH — keeps the [`Binding`] of the moment it
/// was made, and checks it on every use with [`Binding::check`] (connectivity) or
/// [`Binding::check_exactly`] (connectivity and positions). Both refuse with one error,
/// [`Stale`], which says what was made for which state and what it met; every error enum
/// of the workspace carries it as its `Stale` variant.
///
/// A binding **fits** a source ([`Binding::fits`]) while the source's connectivity is
/// unchanged (positions and attributes may change), and, in a hierarchy, whenever the
/// hierarchy is back at the same position by its own steps (walking to another level and
/// back). It also fits a clone of the source made since, until the clone's connectivity
/// changes. Any other change of connectivity, every level change, and any other source
/// make it stale. It fits **exactly** ([`Binding::fits_exactly`]) when, besides, it is the
/// same instance and no position was written since: what a BVH or a cached field needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Binding {
    instance: u64,
    connectivity: u64,
    positions: u64,
    level: Option<(u64, usize)>,
}

/// Anything a [`Binding`] can be checked against: a mesh, a polyline.
pub trait Bound {
    /// The source's provenance.
    fn provenance(&self) -> &Provenance;
}

impl Bound for Provenance {
    fn provenance(&self) -> &Provenance {
        self
    }
}

impl Binding {
    /// True when this binding fits `source`: same connectivity (see the
    /// [docs above](Self)); positions may have changed.
    #[inline]
    pub fn fits<S: Bound + ?Sized>(&self, source: &S) -> bool {
        let p = source.provenance();
        let same_connectivity = self.connectivity == p.connectivity
            && (self.instance == p.instance
                || p.lineage
                    .iter()
                    .any(|&(id, count)| id == self.instance && count == self.connectivity));
        same_connectivity
            || (self.instance == p.instance && self.level.is_some() && self.level == p.level)
    }

    /// True when this binding fits `source` exactly: the same instance, with the same
    /// connectivity and no position written since.
    #[inline]
    pub fn fits_exactly<S: Bound + ?Sized>(&self, source: &S) -> bool {
        let p = source.provenance();
        self.instance == p.instance
            && self.connectivity == p.connectivity
            && self.positions == p.positions
    }

    /// True when this binding names the same instance with the same connectivity as
    /// `source` now (no clone, no level tag: what a hierarchy asks of its own mesh).
    #[inline]
    pub fn same_connectivity<S: Bound + ?Sized>(&self, source: &S) -> bool {
        let p = source.provenance();
        self.instance == p.instance && self.connectivity == p.connectivity
    }

    /// True when no position of the same instance was written since (connectivity aside).
    #[inline]
    pub fn same_positions<S: Bound + ?Sized>(&self, source: &S) -> bool {
        let p = source.provenance();
        self.instance == p.instance && self.positions == p.positions
    }

    /// `Ok` when this binding [fits](Self::fits) `source`, else [`Stale`] naming `what`.
    ///
    /// # Errors
    /// [`Stale`] when the binding does not fit.
    pub fn check<S: Bound + ?Sized>(&self, source: &S, what: &'static str) -> Result<(), Stale> {
        if self.fits(source) {
            return Ok(());
        }
        Err(Stale::new(what, *self, source.provenance().binding()))
    }

    /// `Ok` when this binding [fits exactly](Self::fits_exactly) `source`, else
    /// [`Stale`] naming `what`.
    ///
    /// # Errors
    /// [`Stale`] when the binding does not fit exactly.
    pub fn check_exactly<S: Bound + ?Sized>(
        &self,
        source: &S,
        what: &'static str,
    ) -> Result<(), Stale> {
        if self.fits_exactly(source) {
            return Ok(());
        }
        Err(Stale::new(what, *self, source.provenance().binding()))
    }

    /// `Ok` when `other` names the same source in the same state (two values derived from
    /// one source, checked against each other where the source is not at hand), else
    /// [`Stale`] naming `what`.
    ///
    /// # Errors
    /// [`Stale`] when the two bindings differ.
    pub fn check_same(&self, other: &Binding, what: &'static str) -> Result<(), Stale> {
        if self == other {
            return Ok(());
        }
        Err(Stale::new(what, *other, *self))
    }

    /// The instance number (in messages).
    #[must_use]
    pub fn instance(&self) -> u64 {
        self.instance
    }

    /// The instance and its connectivity count: the point in a history a collapse record
    /// names (see `Provenance::is_own_history`).
    #[inline]
    pub(crate) fn history_point(&self) -> (u64, u64) {
        (self.instance, self.connectivity)
    }
}

impl fmt::Display for Binding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.level {
            Some((hierarchy, applied)) => write!(
                f,
                "mesh #{} in hierarchy #{hierarchy} with {applied} records collapsed",
                self.instance
            ),
            None => write!(
                f,
                "#{} after {} connectivity changes and {} position writes",
                self.instance, self.connectivity, self.positions
            ),
        }
    }
}

/// A value derived from a mesh (or another source) met another source, or the same one at
/// another hierarchy level or after its connectivity (or, where that matters, its
/// positions) changed: the one error for "made for another mesh or state".
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what} was made for {made} and met {met}: make it again from what it is used on")]
pub struct Stale {
    /// What was used (for example "the sub-mesh").
    pub what: &'static str,
    /// The state it was made for.
    pub made: Binding,
    /// The state it met.
    pub met: Binding,
}

impl Stale {
    /// The error for `what`, made for `made`, meeting `met`.
    #[must_use]
    pub fn new(what: &'static str, made: Binding, met: Binding) -> Self {
        Self { what, made, met }
    }
}

#[cfg(test)]
mod tests {
    use crate::generators;

    #[test]
    fn a_binding_fits_until_the_connectivity_changes() {
        let mut mesh = generators::icosphere(1);
        let b = mesh.binding();
        assert!(b.check(&mesh, "x").is_ok());
        let v = mesh.vertices().next().unwrap();
        let p = mesh.position(v);
        mesh.set_position(v, p * 2.0);
        assert!(b.fits(&mesh), "positions do not count");
        assert!(!b.fits_exactly(&mesh), "except for an exact fit");
        let mut clone = mesh.clone();
        assert!(
            b.fits(&clone),
            "a clone made since has the same connectivity"
        );
        assert!(
            !mesh.binding().fits_exactly(&clone),
            "but is another instance"
        );
        let h = mesh.halfedges().next().unwrap();
        clone.collapse(h).unwrap();
        assert!(!b.fits(&clone), "until its own connectivity changes");
        assert!(
            !generators::icosphere(1).binding().fits(&mesh),
            "another mesh"
        );
        mesh.collapse(h).unwrap();
        assert!(!b.fits(&mesh.clone()), "a clone made after a change");
        let e = b.check(&mesh, "the thing").unwrap_err();
        assert!(e.to_string().contains("the thing was made for #"), "{e}");
        assert!(b.check_exactly(&mesh, "it").is_err());
    }
}
