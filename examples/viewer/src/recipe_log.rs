//! The edits made in the viewer, as the steps of an edit recipe (`multires::recipe`).
//!
//! Every edit that has a recipe step (a Lee drag → `lee_drag`, a Bendels–Klein handle
//! transform → `blend`, a sub-mesh pull / scale / rotate / taper / twist, Taubin
//! smoothing → `smooth`) is recorded by its tool, in order, in the exact, non-portable
//! forms of the schema (vertex indices, the handle's 4 × 4 matrix, the drag vector, the
//! sub-mesh's axis as the tool computed it), with the hierarchy level it was made at, so
//! that `multires edit` (on the hierarchy as built) or `multires::recipe::apply_to_mesh`
//! (on the loaded mesh) replays it bit for bit. The log is part of the document's state:
//! every undo step stores the log as it was, so undo removes a step and redo restores it.
//!
//! An edit that has no recipe step (an FFD deformation, a Bendels–Klein refinement, any
//! change a tool did not record) is logged as *unsupported*, and the recipe then refuses
//! to be saved, naming the edits (undo them to save). So do edits made on the plain mesh
//! before the hierarchy was built: a recipe replays on the hierarchy as built.

use multires::recipe::{HierarchySpec, Recipe, Step, RECIPE_VERSION};

/// Names one logged entry, so that a tool can replace the step it recorded (a handle
/// transform changed again, a drag re-shaped) instead of adding one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordId(u64);

/// One entry of the log.
#[derive(Clone, Debug, PartialEq)]
enum Logged {
    /// An edit with its recipe step.
    Step { id: RecordId, step: Box<Step> },
    /// An edit without one: what it was.
    Unsupported { id: RecordId, what: String },
    /// The hierarchy was built here (from the mesh as it then was), with these options
    /// when the recipe schema can express them.
    Built { spec: Option<HierarchySpec> },
}

/// The log of recipe steps (see the module docs): a value the document stores with every
/// undo step.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RecipeLog {
    entries: Vec<Logged>,
    /// The label of the last change, while no tool has recorded its step.
    pending: Option<String>,
}

impl RecipeLog {
    /// A change labelled `label` begins (a new undo step that changes the mesh): the
    /// previous change left unrecorded becomes an unsupported entry.
    pub(crate) fn begin_change(&mut self, label: &str, next_id: &mut u64) {
        self.flush(next_id);
        self.pending = Some(label.to_owned());
    }

    /// Turns the pending change, if any, into an unsupported entry.
    pub(crate) fn flush(&mut self, next_id: &mut u64) {
        if let Some(what) = self.pending.take() {
            *next_id += 1;
            self.entries.push(Logged::Unsupported {
                id: RecordId(*next_id),
                what,
            });
        }
    }

    /// The hierarchy was built: the steps from here on replay on it.
    pub(crate) fn built(&mut self, next_id: &mut u64) {
        self.flush(next_id);
        self.entries.push(Logged::Built { spec: None });
    }

    /// Sets the options of the last hierarchy build (`None`: not expressible).
    pub(crate) fn set_built_spec(&mut self, spec: Option<HierarchySpec>) {
        if let Some(Logged::Built { spec: s }) = self
            .entries
            .iter_mut()
            .rev()
            .find(|e| matches!(e, Logged::Built { .. }))
        {
            *s = spec;
        }
    }

    /// Records the current change: its step, or (`Err`) what it was when it has none.
    /// When `replacing` names the last entry, that entry is replaced (the same edit
    /// changed again); otherwise a new one is added. Returns the entry's id.
    pub(crate) fn record(
        &mut self,
        replacing: Option<RecordId>,
        step: Result<Step, String>,
        next_id: &mut u64,
    ) -> RecordId {
        self.pending = None;
        let id = match (replacing, self.entries.last()) {
            (Some(r), Some(Logged::Step { id, .. } | Logged::Unsupported { id, .. }))
                if *id == r =>
            {
                self.entries.pop();
                r
            }
            _ => {
                *next_id += 1;
                RecordId(*next_id)
            }
        };
        self.entries.push(match step {
            Ok(step) => Logged::Step {
                id,
                step: Box::new(step),
            },
            Err(what) => Logged::Unsupported { id, what },
        });
        id
    }

    /// Number of steps recorded since the last hierarchy build (or the load), and the
    /// edits without a step among them.
    pub fn counts(&self) -> (usize, usize) {
        let start = self.start();
        let tail = &self.entries[start..];
        let steps = tail
            .iter()
            .filter(|e| matches!(e, Logged::Step { .. }))
            .count();
        let unsupported = tail
            .iter()
            .filter(|e| matches!(e, Logged::Unsupported { .. }))
            .count()
            + usize::from(self.pending.is_some());
        (steps, unsupported)
    }

    /// Index of the first entry after the last build (0 without one).
    fn start(&self) -> usize {
        self.entries
            .iter()
            .rposition(|e| matches!(e, Logged::Built { .. }))
            .map_or(0, |i| i + 1)
    }

    /// The recipe of the edits, or why it cannot be saved: edits without a recipe step
    /// (named), edits made on the plain mesh before the hierarchy was built.
    ///
    /// # Errors
    /// A message naming what keeps the recipe from replaying the viewer's edits.
    pub fn recipe(&self) -> Result<Recipe, String> {
        let start = self.start();
        let before = self.entries[..start.saturating_sub(1)]
            .iter()
            .filter(|e| !matches!(e, Logged::Built { .. }))
            .count();
        if before > 0 {
            return Err(format!(
                "{before} edit(s) were made on the plain mesh before the hierarchy was built: \
                 a recipe replays on the hierarchy as built (undo them and the build, build \
                 first, then edit)"
            ));
        }
        let mut refused: Vec<&str> = self.entries[start..]
            .iter()
            .filter_map(|e| match e {
                Logged::Unsupported { what, .. } => Some(what.as_str()),
                _ => None,
            })
            .collect();
        if let Some(p) = &self.pending {
            refused.push(p);
        }
        if !refused.is_empty() {
            return Err(format!(
                "no recipe step for {} edit(s): {} (undo them to save the recipe)",
                refused.len(),
                refused.join("; ")
            ));
        }
        let hierarchy = match start.checked_sub(1).map(|i| &self.entries[i]) {
            Some(Logged::Built { spec }) => spec.clone(),
            _ => None,
        };
        let steps = self.entries[start..]
            .iter()
            .filter_map(|e| match e {
                Logged::Step { step, .. } => Some((**step).clone()),
                _ => None,
            })
            .collect();
        Ok(Recipe {
            version: RECIPE_VERSION,
            hierarchy,
            steps,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use multires::recipe::{Pull, Region};

    fn pull(x: f64) -> Step {
        Step::Pull(Pull {
            level: None,
            region: Region::All,
            propagation: 0,
            falloff: Default::default(),
            offset: [x, 0.0, 0.0],
        })
    }

    #[test]
    fn steps_replace_flush_and_refuse() {
        let mut next = 0;
        let mut log = RecipeLog::default();
        log.begin_change("pull", &mut next);
        let id = log.record(None, Ok(pull(1.0)), &mut next);
        log.begin_change("pull again", &mut next);
        log.record(Some(id), Ok(pull(2.0)), &mut next);
        assert_eq!(log.recipe().unwrap().steps, vec![pull(2.0)]);
        log.begin_change("FFD bend", &mut next);
        assert_eq!(log.counts(), (1, 1));
        let e = log.recipe().unwrap_err();
        assert!(e.contains("FFD bend"), "{e}");
        log.begin_change("pull", &mut next);
        log.record(Some(id), Ok(pull(3.0)), &mut next);
        assert_eq!(log.counts(), (2, 1));
        // A build after edits: the edits before it cannot replay on the hierarchy.
        log.built(&mut next);
        assert!(log.recipe().unwrap_err().contains("before the hierarchy"));
        let mut fresh = RecipeLog::default();
        fresh.built(&mut next);
        fresh.set_built_spec(Some(HierarchySpec::default()));
        fresh.begin_change("pull", &mut next);
        fresh.record(None, Ok(pull(1.0)), &mut next);
        let r = fresh.recipe().unwrap();
        assert_eq!((r.version, r.steps.len()), (RECIPE_VERSION, 1));
        assert!(r.hierarchy.is_some());
    }
}
