//! The hierarchy build of the *Multiresolution* tool: on its own thread, with progress,
//! cancel, and the result taken in as one undo step.

use super::*;

/// What the build thread sends back: the hierarchy (or the error) and the build time.
pub(super) type BuildResult = (Result<Hierarchy, halfedge::Error>, Duration);

/// A hierarchy build running on its own thread.
pub(super) struct PendingBuild {
    /// The latest progress report of the build.
    pub(super) progress: Arc<Mutex<Option<BuildProgress>>>,
    /// Where the result arrives.
    pub(super) result: Receiver<BuildResult>,
    pub(super) thread: JoinHandle<()>,
    pub(super) started: Instant,
    pub(super) method: Method,
    pub(super) target_faces: usize,
    pub(super) input_faces: usize,
    /// The document's revision when the build started: it must not change meanwhile.
    pub(super) revision: Revision,
    /// Set to ask the build to stop at its next progress report.
    pub(super) cancel: Arc<AtomicBool>,
    /// The options as a recipe's `[hierarchy]` table, when it can express them.
    pub(super) spec: Option<HierarchySpec>,
}

impl PendingBuild {
    /// The progress so far: `(levels done, faces left)`.
    pub(super) fn progress(&self) -> (usize, usize) {
        let last = self.progress.lock().ok().and_then(|p| *p);
        last.map_or((0, self.input_faces), |p| (p.levels, p.faces))
    }
}

/// Fraction of the faces to remove (input down to the target) removed so far, in `[0, 1]`.
pub(super) fn build_fraction(input_faces: usize, target_faces: usize, faces_left: usize) -> f32 {
    let target = target_faces.min(input_faces);
    let span = input_faces - target;
    if span == 0 {
        return 1.0;
    }
    let removed = input_faces.saturating_sub(faces_left.max(target));
    removed as f32 / span as f32
}

/// The message of a panic payload.
pub(super) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

impl Multires {
    /// The build options as a recipe's `[hierarchy]` table (what `multires simplify` and
    /// `multires batch` build; `max_normal_deviation` only when it is not the method's
    /// default).
    pub(super) fn recipe_spec(&self) -> Option<HierarchySpec> {
        // The viewer's bound applies to rounds builds (QEM keeps the library's).
        let default_bound = HierarchyOptions::rounds().max_normal_deviation;
        let bound = self.max_normal_deviation.to_radians();
        let max_normal_deviation = (self.method == Method::Rounds
            && bound.to_bits() != default_bound.to_bits())
        .then_some(self.max_normal_deviation);
        Some(HierarchySpec {
            max_normal_deviation,
            method: Some(choice_name(&METHODS, self.method).to_owned()),
            target_faces: Some(self.target_faces),
            detail: Some(
                match self.detail {
                    DetailMode::Translation => "translation",
                    _ => "local",
                }
                .to_owned(),
            ),
        })
    }

    pub(super) fn options(&self) -> HierarchyOptions {
        let base = match self.method {
            Method::Rounds => HierarchyOptions::rounds()
                .with_max_normal_deviation(self.max_normal_deviation.to_radians()),
            Method::Qem => HierarchyOptions::qem(),
        };
        base.with_target_faces(self.target_faces)
            .with_detail_mode(self.detail)
    }

    /// True while a hierarchy build runs on its thread.
    pub fn is_building(&self) -> bool {
        self.pending.is_some()
    }

    /// Asks a running build to stop at its next progress report (the end of a level or
    /// 65,536 collapses); [`Tool::poll`] then reports the tool idle, the mesh unchanged.
    pub fn cancel_build(&self) {
        if let Some(p) = &self.pending {
            p.cancel.store(true, Ordering::Relaxed);
        }
    }

    /// The error for actions that need the tool idle.
    pub(super) fn check_idle(&self) -> Result<(), ToolError> {
        match self.pending {
            Some(_) => Err(ToolError::new(
                "a hierarchy build is running: wait for it to finish",
            )),
            None => Ok(()),
        }
    }

    /// Starts building the hierarchy of the document's mesh on another thread (a copy of
    /// the mesh moves in); [`Tool::poll`] takes the result in and leaves the document at
    /// level 0.
    pub fn start_build(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.check_idle()?;
        let input = ctx.mesh().clone();
        let input_faces = input.n_faces();
        let options = self.options();
        let progress = Arc::new(Mutex::new(None));
        let (sender, result) = mpsc::channel();
        let reports = Arc::clone(&progress);
        let cancel = Arc::new(AtomicBool::new(false));
        let cancelled = Arc::clone(&cancel);
        let thread = std::thread::Builder::new()
            .name("hierarchy build".into())
            .spawn(move || {
                let start = Instant::now();
                let h = Hierarchy::build_cancellable(input, &options, &mut |p| {
                    if let Ok(mut last) = reports.lock() {
                        *last = Some(p);
                    }
                    if cancelled.load(Ordering::Relaxed) {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                });
                // The receiver is gone only when the tool was dropped: nothing to tell.
                let _ = sender.send((h, start.elapsed()));
            })
            .map_err(|e| ToolError::new(format!("cannot start the build thread: {e}")))?;
        self.pending = Some(PendingBuild {
            progress,
            result,
            thread,
            started: Instant::now(),
            method: self.method,
            target_faces: self.target_faces,
            input_faces,
            revision: ctx.doc.revision(),
            cancel,
            spec: self.recipe_spec(),
        });
        ctx.info(format!(
            "Building {} hierarchy of {} faces…",
            method_name(self.method),
            group(input_faces)
        ));
        Ok(())
    }

    /// Builds the hierarchy and waits for it (blocking the caller).
    pub fn build(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.start_build(ctx)?;
        let pending = self.pending.take().expect("just started");
        let received = pending.result.recv();
        self.finish_build(pending, received.ok(), ctx)
    }

    /// Takes in the result of a build (`None`: the thread ended without one).
    pub(super) fn finish_build(
        &mut self,
        pending: PendingBuild,
        received: Option<BuildResult>,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        let joined = pending.thread.join();
        let Some((result, built)) = received else {
            let why = match joined {
                Err(payload) => panic_message(payload.as_ref()),
                Ok(()) => "it ended without a result".into(),
            };
            return Err(ToolError::new(format!("the build thread failed: {why}")));
        };
        let mut h = match result {
            Err(halfedge::Error::Cancelled(why)) => {
                ctx.info(format!("Build cancelled ({why}); the mesh is unchanged"));
                return Ok(());
            }
            other => other?,
        };
        if ctx.doc.revision() != pending.revision {
            return Err(ToolError::new(
                "the mesh changed while the hierarchy was being built: build it again",
            ));
        }
        let input_faces = pending.input_faces;
        let coarse_faces = h.mesh().n_faces();
        // Back to the input (bit for bit), where the document is.
        h.go_to_level(0)?;
        // Sub-mesh labels of the input came along in its label attribute: from now on the
        // hierarchy carries them through its levels.
        if let Some(attribute) = h.mesh().find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE) {
            h.attach_labels(attribute).unwrap();
        }
        // Counted as the panel counts them: the input is level 0.
        let levels = h.coarsest_level() + 1;
        // Say plainly when the target was missed, or reached only by widening the bounds.
        let outcome = h.build_outcome();
        let how = if !outcome.target_reached() || !outcome.relaxations.is_empty() {
            format!(" ({outcome})")
        } else {
            String::new()
        };
        // The document holds the hierarchy from now on (one undo step: undo gives the
        // plain mesh back).
        ctx.doc.set_hierarchy(h, "Build hierarchy");
        ctx.doc.set_recipe_hierarchy(pending.spec.clone());
        self.level = 0;
        // ASCII only: the status line's font has no arrows.
        ctx.info(format!(
            "Built {} hierarchy: {levels} levels, {} down to {} faces in {:.0} ms{how}",
            method_name(pending.method),
            group(input_faces),
            group(coarse_faces),
            built.as_secs_f64() * 1e3
        ));
        Ok(())
    }
}
