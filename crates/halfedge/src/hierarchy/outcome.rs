use std::fmt;

use super::{Hierarchy, HierarchyOptions};

/// Why the edges of a round were not collapsed, counted over the last round of a build
/// that stalled (rounds only).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Refusals {
    /// Edges left alone because an endpoint was locked by a collapse earlier in the round.
    pub locked: usize,
    /// Edges whose star failed the planarity criterion.
    pub planarity: usize,
    /// Edges whose collapse is topologically illegal (OpenMesh's rules, boundaries).
    pub topology: usize,
    /// Edges whose collapse would move the survivor farther than `max_error` from a
    /// face plane of the star.
    pub error_bound: usize,
    /// Edges whose collapse would turn a face normal beyond the flip bound or make a
    /// face degenerate.
    pub geometry: usize,
}

/// Why a build stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum StopReason {
    /// The face count reached [`HierarchyOptions::target_faces`](super::HierarchyOptions::target_faces).
    TargetReached,
    /// The hierarchy has [`HierarchyOptions::max_levels`](super::HierarchyOptions::max_levels) levels.
    MaxLevels,
    /// No face target was set, and the method ran until it could not go on: rounds until
    /// a round removed less than `min_level_reduction` of the faces, QEM until no legal
    /// collapse (within `max_error`) remained.
    Exhausted {
        /// Rounds: what refused the last round's edges.
        refusals: Option<Refusals>,
    },
    /// The face target was not reached: nothing more could be collapsed under the final
    /// bounds (after any widening), or `max_error` forbade it.
    Stalled {
        /// Rounds: what refused the last round's edges.
        refusals: Option<Refusals>,
    },
}

/// A widening of the rounds' bounds after the rounds stalled short of the face target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxation {
    /// The level whose rounds use the widened bounds first (levels below it used the
    /// earlier bounds).
    pub level: usize,
    /// Faces when the rounds stalled.
    pub faces: usize,
    /// The planarity bound from then on, in radians.
    pub max_normal_deviation: f64,
    /// The flip bound from then on, in radians.
    pub max_flip_angle: f64,
}

/// How a build ended ([`Hierarchy::build_outcome`]); its `Display` says it in a sentence.
///
/// How a hierarchy build ended: whether it reached its face target, and if not, plainly
/// why — which limit stopped it, and for rounds which tests refused the edges of the last
/// round — plus the bounds the rounds widened on the way ([`HierarchyOptions::relax_when_stalled`]).
///
/// [`HierarchyOptions::relax_when_stalled`]: super::HierarchyOptions::relax_when_stalled
#[derive(Clone, Debug, PartialEq)]
pub struct BuildOutcome {
    /// The face target asked for (0: none).
    pub target_faces: usize,
    /// Faces at the coarsest level.
    pub faces: usize,
    /// Why the build stopped.
    pub stop: StopReason,
    /// The bounds the rounds widened, in order (empty when the paper's bounds sufficed).
    pub relaxations: Vec<Relaxation>,
}

impl Default for BuildOutcome {
    fn default() -> Self {
        Self {
            target_faces: 0,
            faces: 0,
            stop: StopReason::Exhausted { refusals: None },
            relaxations: Vec::new(),
        }
    }
}

impl BuildOutcome {
    /// True when the build reached its face target (or had none).
    pub fn target_reached(&self) -> bool {
        self.target_faces == 0 || self.faces <= self.target_faces
    }
}

fn degrees(radians: f64) -> String {
    format!("{:.0} degrees", radians.to_degrees())
}

impl fmt::Display for Refusals {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} edges failed the planarity bound, {} were topologically illegal, {} would \
             flip or flatten a face, {} exceeded max_error, {} were locked",
            self.planarity, self.topology, self.geometry, self.error_bound, self.locked
        )
    }
}

impl fmt::Display for BuildOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.stop {
            StopReason::TargetReached => write!(
                f,
                "reached the target of {} faces ({} faces)",
                self.target_faces, self.faces
            )?,
            StopReason::MaxLevels => write!(
                f,
                "stopped at {} faces after max_levels levels{}",
                self.faces,
                if self.target_reached() {
                    String::new()
                } else {
                    format!(" (target {} faces: raise max_levels)", self.target_faces)
                }
            )?,
            StopReason::Exhausted { refusals } => {
                write!(f, "simplified to {} faces (no face target)", self.faces)?;
                if let Some(r) = refusals {
                    write!(f, "; in the last round {r}")?;
                }
            }
            StopReason::Stalled { refusals } => {
                write!(
                    f,
                    "stopped at {} faces, short of the target of {}: nothing more could be collapsed",
                    self.faces, self.target_faces
                )?;
                match refusals {
                    Some(r) => write!(f, " (in the last round {r})")?,
                    None => write!(f, " (no legal collapse within max_error was left)")?,
                }
            }
        }
        if let Some(last) = self.relaxations.last() {
            let first = &self.relaxations[0];
            write!(
                f,
                "; the rounds stalled {} at {} faces (level {}) and went on with the planarity \
                 bound widened to {} and the flip bound at {}",
                match self.relaxations.len() {
                    1 => "once".to_string(),
                    n => format!("{n} times, first"),
                },
                first.faces,
                first.level,
                degrees(last.max_normal_deviation),
                degrees(last.max_flip_angle),
            )?;
        }
        Ok(())
    }
}

/// Sets the stop reason of a finished build from its state and the method's refusals.
pub(crate) fn finish(h: &mut Hierarchy, options: &HierarchyOptions, refusals: Option<Refusals>) {
    let faces = h.mesh.n_faces();
    let target = options.target_faces;
    h.outcome.target_faces = target;
    h.outcome.faces = faces;
    h.outcome.stop = if target > 0 && faces <= target {
        StopReason::TargetReached
    } else if h.built_levels() >= options.max_levels {
        StopReason::MaxLevels
    } else if target == 0 {
        StopReason::Exhausted { refusals }
    } else {
        StopReason::Stalled { refusals }
    };
}

/// # Build outcome
impl Hierarchy {
    /// How the build ended: whether it reached its face target and, if not, why (see
    /// [`BuildOutcome`]; its `Display` says it in a sentence).
    pub fn build_outcome(&self) -> &BuildOutcome {
        &self.outcome
    }
}
