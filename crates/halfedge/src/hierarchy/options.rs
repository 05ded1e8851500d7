//! What a hierarchy build is asked for ([`HierarchyOptions`], [`Method`]) and what it
//! reports while it runs ([`BuildProgress`]).

use std::ops::ControlFlow;

use super::detail::DetailMode;
use crate::error::{Error, Result};

/// The simplification method of a [`Hierarchy`](crate::hierarchy::Hierarchy).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The seed paper's rounds (section 3): planarity criterion, midpoint placement,
    /// locks; one round per level.
    Rounds,
    /// Garland–Heckbert quadric error priority decimation, levels cut every
    /// [`HierarchyOptions::level_ratio`] of the faces.
    Qem,
}

/// Where a rounds collapse puts its survivor ([`HierarchyOptions::placement`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SurvivorPlacement {
    /// The edge's midpoint, as the seed paper does (an interior edge touching the
    /// boundary collapses onto its boundary vertex with either placement).
    #[default]
    Midpoint,
    /// Where QEM puts it (Garland & Heckbert 1997): the minimiser of the summed vertex
    /// quadrics or, when that is ill-conditioned, far from the edge or flips a face, the
    /// cheapest legal one of the midpoint and the endpoints. The rounds' order and tests
    /// stay as they are; the survivors land nearer the input surface, for the cost of
    /// the quadrics (about 100 bytes per vertex while building) and a 3×3 solve per
    /// tested edge.
    Quadric,
}

/// How to build a [`Hierarchy`](crate::hierarchy::Hierarchy): the method, its parameters and the stop criteria.
///
/// Stop criteria (whichever comes first): the face count reaches
/// [`target_faces`](Self::target_faces) (the last level may then be a partial round), the
/// hierarchy has [`max_levels`](Self::max_levels) levels below the input, no collapse
/// within [`max_error`](Self::max_error) remains, or a level removes less than
/// [`min_level_reduction`](Self::min_level_reduction) of its faces.
///
/// **Reaching the face target with rounds.** The paper's planarity criterion (60°) runs
/// out on coarse levels: stars stop being nearly planar, and rounds stall thousands of
/// faces above a small target (a 1.6 M-face scan stalls near 8,000). With a face target
/// and [`relax_when_stalled`](Self::relax_when_stalled) (the default), a round that stalls
/// short of the target does not end the build: the planarity bound is widened by 15° and
/// the rounds go on (the stalled round's collapses and the next round's make one level),
/// again at every stall up to 180° (no planarity test), then the flip bound likewise up
/// to 90°. Every level above the first stall keeps the paper's criterion, the widened
/// bounds are kept from the level they were first needed, and
/// [`Hierarchy::build_outcome`](crate::hierarchy::Hierarchy::build_outcome) lists every widening. A build that still cannot reach
/// the target (every remaining collapse is topologically illegal, for instance separate
/// small components, or `max_error` forbids it) says why there, with the count of edges
/// each test refused in the last round. Without a face target the rounds stop at the
/// first stall, as in the paper. QEM reaches any target its legality rules allow.
#[derive(Clone, Debug)]
pub struct HierarchyOptions {
    /// The simplification method.
    pub method: Method,
    /// Rounds: the planarity bound, in radians. The star of edge `v0v1` (the faces
    /// around `v0` and `v1`) is planar enough when every face normal is within this angle
    /// of the normalised average of the star's face normals. Default 60°; 90° lets rounds
    /// go down to about a thousand faces on most meshes.
    pub max_normal_deviation: f64,
    /// Both methods: a collapse is refused when it turns a surviving face's normal by more
    /// than this angle, in radians (a flip is more than 90°). Default 45°: a tighter bound
    /// than OpenMesh's 90° keeps coarse levels smooth enough for later rounds to go on.
    pub max_flip_angle: f64,
    /// QEM: each level ends when the face count drops to this fraction of the previous
    /// level's (default 0.55, i.e. about 45 % of the faces removed per level, like rounds).
    pub level_ratio: f64,
    /// QEM: weight of the boundary constraint planes (planes through each boundary edge,
    /// perpendicular to its face), relative to the face planes. Default 10.
    pub boundary_weight: f64,
    /// Stop when the mesh has at most this many faces. Default 0 (no face target).
    pub target_faces: usize,
    /// Stop after this many levels below the input. Default: no limit.
    pub max_levels: usize,
    /// Error bound, a distance. Rounds: a collapse is skipped when the survivor's new
    /// position lies farther than this from the plane of a face of the star. QEM: the
    /// decimation stops when the cheapest collapse's error (the root mean square distance
    /// to the planes of its quadric, area-weighted) exceeds it. Default: no bound.
    pub max_error: f64,
    /// Stop after a level that removed less than this fraction of its faces (default 1 %).
    pub min_level_reduction: f64,
    /// How splits place their vertices after an edit at a coarser level (module
    /// [`DetailMode`](crate::hierarchy::DetailMode)): local frames with exact regions (the default) or the seed paper's
    /// centroid translations.
    pub detail_mode: DetailMode,
    /// Both methods: when the mesh has sub-mesh labels (the vertex attribute
    /// [`labels::LABEL_ATTRIBUTE`](crate::labels::LABEL_ATTRIBUTE)), only edges whose two ends carry the same label
    /// collapse, so no edge ever joins two different sub-meshes at any level and every
    /// fine vertex is collapsed into a vertex of its own sub-mesh (or of the frontier, for
    /// frontier vertices). Default true.
    pub respect_labels: bool,
    /// Rounds with a face target: when a round stalls (removes less than
    /// [`min_level_reduction`](Self::min_level_reduction)) short of the target, widen the
    /// planarity bound, then the flip bound, and go on (see the type's docs). Default
    /// `true`; `false` stops at the first stall, as the paper does.
    pub relax_when_stalled: bool,
    /// Rounds: where a collapse puts its survivor (default
    /// [`SurvivorPlacement::Midpoint`], the paper's). QEM always places by its quadric
    /// and ignores this. Collapses made again after an edit
    /// ([`Hierarchy::replan`](crate::hierarchy::Hierarchy)) use the midpoint.
    pub placement: SurvivorPlacement,
}

impl Default for HierarchyOptions {
    fn default() -> Self {
        Self {
            method: Method::Rounds,
            max_normal_deviation: 60f64.to_radians(),
            max_flip_angle: 45f64.to_radians(),
            level_ratio: 0.55,
            boundary_weight: 10.0,
            target_faces: 0,
            max_levels: usize::MAX,
            max_error: f64::INFINITY,
            min_level_reduction: 0.01,
            detail_mode: DetailMode::LocalFrame,
            respect_labels: true,
            relax_when_stalled: true,
            placement: SurvivorPlacement::Midpoint,
        }
    }
}

impl HierarchyOptions {
    /// The paper's rounds with default parameters.
    pub fn rounds() -> Self {
        Self::default()
    }
    /// QEM decimation with default parameters.
    pub fn qem() -> Self {
        Self {
            method: Method::Qem,
            ..Self::default()
        }
    }
    /// Sets [`target_faces`](Self::target_faces).
    pub fn with_target_faces(mut self, faces: usize) -> Self {
        self.target_faces = faces;
        self
    }
    /// Sets [`max_levels`](Self::max_levels).
    pub fn with_max_levels(mut self, levels: usize) -> Self {
        self.max_levels = levels;
        self
    }
    /// Sets [`max_error`](Self::max_error).
    pub fn with_max_error(mut self, error: f64) -> Self {
        self.max_error = error;
        self
    }
    /// Sets [`max_normal_deviation`](Self::max_normal_deviation) (radians).
    pub fn with_max_normal_deviation(mut self, radians: f64) -> Self {
        self.max_normal_deviation = radians;
        self
    }

    /// Sets [`respect_labels`](Self::respect_labels).
    pub fn with_respect_labels(mut self, respect: bool) -> Self {
        self.respect_labels = respect;
        self
    }

    /// Sets [`detail_mode`](Self::detail_mode).
    pub fn with_detail_mode(mut self, mode: DetailMode) -> Self {
        self.detail_mode = mode;
        self
    }

    /// Sets [`max_flip_angle`](Self::max_flip_angle) (radians).
    pub fn with_max_flip_angle(mut self, radians: f64) -> Self {
        self.max_flip_angle = radians;
        self
    }

    /// Sets [`placement`](Self::placement).
    pub fn with_placement(mut self, placement: SurvivorPlacement) -> Self {
        self.placement = placement;
        self
    }

    /// Sets [`relax_when_stalled`](Self::relax_when_stalled).
    pub fn with_relax_when_stalled(mut self, relax: bool) -> Self {
        self.relax_when_stalled = relax;
        self
    }

    pub(super) fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(Error::InvalidArgument(what));
        if !(self.max_normal_deviation > 0.0 && self.max_normal_deviation <= std::f64::consts::PI) {
            return bad(format!(
                "max_normal_deviation must be in (0, π], got {}",
                self.max_normal_deviation
            ));
        }
        if !(self.max_flip_angle > 0.0 && self.max_flip_angle <= std::f64::consts::PI) {
            return bad(format!(
                "max_flip_angle must be in (0, π], got {}",
                self.max_flip_angle
            ));
        }
        if !(self.level_ratio > 0.0 && self.level_ratio < 1.0) {
            return bad(format!(
                "level_ratio must be in (0, 1), got {}",
                self.level_ratio
            ));
        }
        if !(self.boundary_weight >= 0.0 && self.boundary_weight.is_finite()) {
            return bad(format!(
                "boundary_weight must be finite and non-negative, got {}",
                self.boundary_weight
            ));
        }
        if self.max_error.is_nan() || self.max_error < 0.0 {
            return bad(format!(
                "max_error must be non-negative, got {}",
                self.max_error
            ));
        }
        if !(0.0..1.0).contains(&self.min_level_reduction) {
            return bad(format!(
                "min_level_reduction must be in [0, 1), got {}",
                self.min_level_reduction
            ));
        }
        Ok(())
    }
}

/// Progress of a [`Hierarchy::build_with_progress`](crate::hierarchy::Hierarchy::build_with_progress) or
/// [`Hierarchy::build_cancellable`](crate::hierarchy::Hierarchy::build_cancellable), reported at the end of every level
/// and every 65,536 collapses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuildProgress {
    /// Levels completed so far (below the input).
    pub levels: usize,
    /// Faces left.
    pub faces: usize,
    /// Faces of the input.
    pub input_faces: usize,
}

/// Hands the build's progress (`levels` completed and `faces` left, of `input_faces`) to
/// its callback; [`Error::Cancelled`] when the callback says stop.
#[inline]
pub(crate) fn report(
    levels: usize,
    faces: usize,
    input_faces: usize,
    progress: &mut dyn FnMut(BuildProgress) -> ControlFlow<()>,
) -> Result<()> {
    let p = BuildProgress {
        levels,
        faces,
        input_faces,
    };
    match progress(p) {
        ControlFlow::Continue(()) => Ok(()),
        ControlFlow::Break(()) => Err(Error::Cancelled(format!(
            "hierarchy build stopped at {} levels, {} of {} faces left",
            p.levels, p.faces, p.input_faces
        ))),
    }
}
