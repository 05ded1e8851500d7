//! *Multiresolution* — the progressive hierarchy and the sub-mesh labels of *Interactive
//! Editing of Multiresolution Meshes* (the seed paper, sections 3 and 4.1).
//!
//! - **Build** a [`Hierarchy`] of the current mesh with the paper's rounds or a QEM
//!   decimation, down to a target face count; the document stays at the finest level.
//!   The build runs on its own thread (a copy of the mesh moves in, the hierarchy comes
//!   back through a channel) while the panel shows its progress (levels done, faces left);
//!   the viewer stays responsive and keeps the mesh unchanged until it returns
//!   ([`Tool::poll`]).
//! - **Level slider**: coarsens or refines with the hierarchy's detail coefficients. The
//!   document holds the hierarchy ([`crate::document::Document::go_to_level`]): its mesh is
//!   the document's mesh, so edits made by other tools at a coarse level are edits of the
//!   hierarchy's mesh and ride along to the finer levels; a level change is one undo step
//!   (the level and the positions left, not a copy of the mesh).
//! - **Sub-mesh frontier** (section 4.1, Fig. 2): (a) picked vertices joined into a closed
//!   loop by shortest edge paths, (b) a collar of faces (the faces around the loop through
//!   the picked vertices; the frontier is its border on the side of the smaller part),
//!   (c) a cutting plane through a picked point, normal along an axis or the view. The
//!   labels (host, sub-mesh, frontier) colour the mesh, the frontier is drawn over it, and
//!   the labels ride along through level changes (Fig. 4 rule, [`halfedge::labels`]).
//!   They live in one place, the mesh's label attribute
//!   ([`halfedge::labels::LABEL_ATTRIBUTE`]), where the *Sub-mesh edits* and *FFD* tools
//!   read them ([`SubMeshLabels::of`]).

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::DVec3;
use halfedge::hierarchy::{BuildProgress, DetailMode, Hierarchy, HierarchyOptions, Method};
use halfedge::labels::LABEL_ATTRIBUTE;
use halfedge::labels::{Label, FRONTIER};
use halfedge::{FaceId, Mesh, VertexId};
use three_d::egui;

use super::params::{self, Param, Widget};
use super::{
    bool_param, choice_name, choice_param, number_param, Background, Overlay, Pick, Tool,
    ToolContext, ToolError, ViewInfo,
};
use crate::colors::{ColorLayer, LabelField, LabelTarget, Rgba, NO_LABEL};
use crate::document::Revision;
use crate::format::group;

/// Label of the host (the part outside the sub-mesh).
pub const HOST: u32 = 0;
/// Label of the sub-mesh.
pub const SUBMESH: u32 = 1;

/// Colour of the frontier segments.
const FRONTIER_COLOR: Rgba = [255, 220, 40, 255];

/// Sub-mesh labels of a mesh, read from its label attribute
/// ([`halfedge::labels::LABEL_ATTRIBUTE`], the one place they are stored): one label per
/// vertex slot ([`HOST`], [`SUBMESH`] or [`FRONTIER`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SubMeshLabels {
    /// Label per vertex slot (dead slots: [`NO_LABEL`], which is also [`FRONTIER`]'s
    /// value: ask [`is_live`](Self::is_live)).
    pub labels: Vec<u32>,
    /// Live slots.
    live: Vec<bool>,
}

impl SubMeshLabels {
    /// The labels of `mesh`, if it has a label attribute.
    pub fn of(mesh: &Mesh) -> Option<Self> {
        let attribute = mesh.find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE)?;
        let mut live = vec![false; mesh.vertex_slots()];
        for v in mesh.vertices() {
            live[mesh.vertex_index(v)] = true;
        }
        Some(Self {
            labels: read_labels(mesh, attribute),
            live,
        })
    }

    /// True when vertex slot `i` is live.
    pub fn is_live(&self, i: usize) -> bool {
        self.live.get(i).copied().unwrap_or(false)
    }

    /// A summary: vertices per part.
    pub fn description(&self) -> String {
        let (host, sub, front) = self.counts();
        format!(
            "sub-mesh {} · host {} · frontier {} vertices",
            group(sub),
            group(host),
            group(front)
        )
    }

    /// The sub-mesh as a mask per vertex slot: the sub-mesh and its frontier (the frontier
    /// vertices are shared by the sub-mesh and the host, section 4.1).
    pub fn inside_mask(&self) -> Vec<bool> {
        self.labels
            .iter()
            .zip(&self.live)
            .map(|(&l, &live)| live && (l == SUBMESH || l == FRONTIER))
            .collect()
    }

    /// Number of vertices per label `(host, sub-mesh, frontier)`.
    pub fn counts(&self) -> (usize, usize, usize) {
        let mut c = (0, 0, 0);
        for (&l, _) in self.labels.iter().zip(&self.live).filter(|(_, &live)| live) {
            match l {
                HOST => c.0 += 1,
                SUBMESH => c.1 += 1,
                FRONTIER => c.2 += 1,
                _ => {}
            }
        }
        c
    }

    /// Labels for display: host 0, sub-mesh 1, frontier 2.
    pub fn display_labels(&self) -> Vec<u32> {
        self.labels
            .iter()
            .zip(&self.live)
            .map(|(&l, &live)| match l {
                _ if !live => NO_LABEL,
                HOST => 0,
                SUBMESH => 1,
                FRONTIER => 2,
                _ => NO_LABEL,
            })
            .collect()
    }

    /// The colour layer of these labels (named [`LABEL_LAYER`]).
    pub fn layer(&self) -> ColorLayer {
        ColorLayer::Labels(LabelField {
            name: LABEL_LAYER.into(),
            target: LabelTarget::Vertices,
            labels: self.display_labels(),
            legend: vec![
                (0, "host".into()),
                (1, "sub-mesh".into()),
                (2, "frontier".into()),
            ],
        })
    }

    /// Colours the mesh by these labels.
    pub fn show(&self, ctx: &mut ToolContext<'_>) {
        ctx.display.set(self.layer());
    }
}

/// Name of the colour layer of the sub-mesh labels.
pub const LABEL_LAYER: &str = "sub-mesh labels";

/// The colour layer `layer` should become after the mesh's labels changed (a level
/// change, undo, redo): the labels read again from `mesh` when `layer` shows the sub-mesh
/// labels (none left: the base colour); `None` for any other layer, which stays.
pub fn refreshed_label_layer(layer: &ColorLayer, mesh: &Mesh) -> Option<ColorLayer> {
    if layer.name() != Some(LABEL_LAYER) {
        return None;
    }
    Some(SubMeshLabels::of(mesh).map_or(ColorLayer::None, |l| l.layer()))
}

/// The frontier edges of `mesh`'s labels (both ends on the frontier) as segments.
pub fn frontier_overlay(mesh: &Mesh, overlay: &mut Overlay) {
    let Some(attribute) = mesh.find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE) else {
        return;
    };
    let labels = mesh.attribute_values(attribute).unwrap();
    for e in mesh.edges() {
        let (a, b) = (mesh.from_vertex(e), mesh.to_vertex(e));
        if labels[mesh.vertex_index(a)] == FRONTIER && labels[mesh.vertex_index(b)] == FRONTIER {
            overlay.segment(mesh.position(a), mesh.position(b), FRONTIER_COLOR);
        }
    }
}

/// How the sub-mesh frontier is made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrontierMode {
    /// (a) Picked vertices joined into a closed loop.
    Loop,
    /// (b) The collar of faces around the loop through the picked vertices.
    Collar,
    /// (c) A cutting plane through the picked point.
    Plane,
}

impl FrontierMode {
    const ALL: [(FrontierMode, &'static str); 3] = [
        (FrontierMode::Loop, "loop"),
        (FrontierMode::Collar, "collar"),
        (FrontierMode::Plane, "plane"),
    ];
    fn name(self) -> &'static str {
        choice_name(&Self::ALL, self)
    }
}

/// The normal of the cutting plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlaneNormal {
    /// World x.
    X,
    /// World y.
    Y,
    /// World z.
    Z,
    /// The viewing direction at the time of the pick.
    View,
}

impl PlaneNormal {
    const ALL: [(PlaneNormal, &'static str); 4] = [
        (PlaneNormal::X, "x"),
        (PlaneNormal::Y, "y"),
        (PlaneNormal::Z, "z"),
        (PlaneNormal::View, "view"),
    ];
    fn name(self) -> &'static str {
        choice_name(&Self::ALL, self)
    }
    fn vector(self, view: &ViewInfo) -> DVec3 {
        match self {
            PlaneNormal::X => DVec3::X,
            PlaneNormal::Y => DVec3::Y,
            PlaneNormal::Z => DVec3::Z,
            PlaneNormal::View => view.forward,
        }
    }
}

/// What the build thread sends back: the hierarchy (or the error) and the build time.
type BuildResult = (Result<Hierarchy, halfedge::Error>, Duration);

/// A hierarchy build running on its own thread.
struct PendingBuild {
    /// The latest progress report of the build.
    progress: Arc<Mutex<Option<BuildProgress>>>,
    /// Where the result arrives.
    result: Receiver<BuildResult>,
    thread: JoinHandle<()>,
    started: Instant,
    method: Method,
    target_faces: usize,
    input_faces: usize,
    /// The document's revision when the build started: it must not change meanwhile.
    revision: Revision,
    /// Set to ask the build to stop at its next progress report.
    cancel: Arc<AtomicBool>,
}

impl PendingBuild {
    /// The progress so far: `(levels done, faces left)`.
    fn progress(&self) -> (usize, usize) {
        let last = self.progress.lock().ok().and_then(|p| *p);
        last.map_or((0, self.input_faces), |p| (p.levels, p.faces))
    }
}

/// Fraction of the faces to remove (input down to the target) removed so far, in `[0, 1]`.
fn build_fraction(input_faces: usize, target_faces: usize, faces_left: usize) -> f32 {
    let target = target_faces.min(input_faces);
    let span = input_faces - target;
    if span == 0 {
        return 1.0;
    }
    let removed = input_faces.saturating_sub(faces_left.max(target));
    removed as f32 / span as f32
}

/// The message of a panic payload.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// The multiresolution tool (see the module docs).
pub struct Multires {
    /// Rounds (the paper) or QEM.
    pub method: Method,
    /// Stop building at this many faces.
    pub target_faces: usize,
    /// Planarity bound of the rounds, degrees.
    pub max_normal_deviation: f64,
    /// How refinement carries coarse edits: local frames with exact regions (default) or
    /// the paper's centroid translations.
    pub detail: DetailMode,
    /// The build running on another thread, if any.
    pending: Option<PendingBuild>,
    /// The document's level, as of the last callback (for the listing).
    level: usize,
    /// Frontier construction.
    pub frontier: FrontierMode,
    /// Cutting-plane normal.
    pub normal: PlaneNormal,
    /// Swap the sub-mesh and the host.
    pub flip: bool,
    picks: Vec<VertexId>,
    plane: Option<(DVec3, DVec3)>,
    collar: Vec<FaceId>,
    view: Option<ViewInfo>,
}

impl Default for Multires {
    fn default() -> Self {
        Self::new()
    }
}

impl Multires {
    /// The tool.
    pub fn new() -> Self {
        Self {
            method: Method::Rounds,
            target_faces: 500,
            max_normal_deviation: 90.0,
            detail: DetailMode::LocalFrame,
            pending: None,
            level: 0,
            frontier: FrontierMode::Loop,
            normal: PlaneNormal::Y,
            flip: false,
            picks: Vec::new(),
            plane: None,
            collar: Vec::new(),
            view: None,
        }
    }

    fn options(&self) -> HierarchyOptions {
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
    fn check_idle(&self) -> Result<(), ToolError> {
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
    fn finish_build(
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

    /// Moves the document's hierarchy to `level` (coarsening or refining with detail
    /// coefficients), one undo step.
    pub fn go_to_level(
        &mut self,
        level: usize,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        self.check_idle()?;
        let from = ctx
            .doc
            .hierarchy()
            .ok_or_else(|| ToolError::new("no hierarchy: build one first"))?
            .level_at_or_finer();
        if ctx.doc.hierarchy().and_then(Hierarchy::current_level) == Some(level) {
            self.level = level;
            return Ok(());
        }
        let start = Instant::now();
        ctx.doc.go_to_level(level, &format!("Level {level}"))?;
        let took = start.elapsed();
        self.level = level;
        self.picks.clear();
        self.collar.clear();
        // The labels rode along in the mesh (Fig. 4 rule): show them at this level.
        self.show_labels(ctx);
        let verb = if level > from { "coarsened" } else { "refined" };
        ctx.info(format!(
            "Level {level}: {} faces, {} vertices ({verb} from level {from} in {:.1} ms)",
            group(ctx.mesh().n_faces()),
            group(ctx.mesh().n_vertices()),
            took.as_secs_f64() * 1e3
        ));
        Ok(())
    }

    /// Makes the frontier from the picks and labels the two sides, in the label attribute
    /// of the document's mesh (the hierarchy's mesh when there is one, so that the labels
    /// ride along through levels).
    pub fn define_labels(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.check_idle()?;
        let cut = Cut {
            frontier: self.frontier,
            picks: &self.picks,
            plane: self.plane,
            flip: self.flip,
        };
        let (collar, description) = ctx.doc.edit_labels(|mesh| cut.label(mesh))?;
        self.collar = collar;
        self.show_labels(ctx);
        ctx.info(format!("Labelled: {description}"));
        Ok(())
    }

    fn clear_picks(&mut self, ctx: &mut ToolContext<'_>) {
        self.picks.clear();
        self.collar.clear();
        self.plane = None;
        ctx.doc.edit_labels(|mesh| {
            if let Some(a) = mesh.find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE) {
                mesh.remove_attribute(a).unwrap();
            }
        });
        ctx.clear_colors();
        ctx.info("Multiresolution: picks and labels cleared");
    }

    fn show_labels(&self, ctx: &mut ToolContext<'_>) {
        if let Some(l) = SubMeshLabels::of(ctx.mesh()) {
            l.show(ctx);
        }
    }
}

/// What a cut of the mesh into sub-mesh and host is made from.
struct Cut<'a> {
    frontier: FrontierMode,
    picks: &'a [VertexId],
    plane: Option<(DVec3, DVec3)>,
    flip: bool,
}

impl Cut<'_> {
    /// Makes the frontier and labels the two sides in `mesh`'s label attribute; returns
    /// the collar (collar mode) and a description.
    fn label(&self, mesh: &mut Mesh) -> Result<(Vec<FaceId>, String), ToolError> {
        let mut collar = Vec::new();
        let frontier = match self.frontier {
            FrontierMode::Loop => {
                if self.picks.len() < 3 {
                    return Err(ToolError::new(format!(
                        "a loop needs at least 3 picked vertices ({} so far)",
                        self.picks.len()
                    )));
                }
                mesh.frontier_through(self.picks)?
            }
            FrontierMode::Collar => {
                if self.picks.len() < 3 {
                    return Err(ToolError::new(format!(
                        "a collar needs at least 3 picked vertices ({} so far)",
                        self.picks.len()
                    )));
                }
                let path = mesh.closed_loop_through(self.picks)?;
                let mut seen = vec![false; mesh.face_slots()];
                for &e in &path {
                    for f in mesh.adjacent_faces(mesh.from_vertex(e)) {
                        if !std::mem::replace(&mut seen[mesh.face_index(f)], true) {
                            collar.push(f);
                        }
                    }
                }
                mesh.frontier_from_collar(&collar)?
            }
            FrontierMode::Plane => {
                let (point, normal) = self
                    .plane
                    .ok_or_else(|| ToolError::new("pick a point of the cutting plane"))?;
                mesh.frontier_from_plane(point, normal)?
            }
        };
        let (attribute, mut counts) = mesh.label_sides(&frontier, SUBMESH, HOST)?;
        let mut swap = match (self.frontier, self.plane) {
            (FrontierMode::Plane, Some((point, normal))) => {
                // The sub-mesh is on the normal's side of the plane.
                let values = mesh.attribute_values(attribute).unwrap();
                let side: f64 = mesh
                    .vertices()
                    .filter(|&v| values[mesh.vertex_index(v)] == SUBMESH)
                    .map(|v| (mesh.position(v) - point).dot(normal))
                    .sum();
                side < 0.0
            }
            _ => counts.left_vertices > counts.right_vertices,
        };
        swap ^= self.flip;
        if swap {
            (_, counts) = mesh.label_sides(&frontier, HOST, SUBMESH)?;
        }
        let (sub, host) = if swap {
            (counts.right_vertices, counts.left_vertices)
        } else {
            (counts.left_vertices, counts.right_vertices)
        };
        let description = format!(
            "{} frontier of {} edges: sub-mesh {} vertices, host {}, frontier {}",
            self.frontier.name(),
            frontier.halfedges().len(),
            group(sub),
            group(host),
            group(counts.frontier_vertices)
        );
        Ok((collar, description))
    }
}

fn method_name(m: Method) -> &'static str {
    match m {
        Method::Rounds => "rounds",
        Method::Qem => "QEM",
    }
}

/// The labels of the live vertices ([`NO_LABEL`] for dead slots).
fn read_labels(mesh: &Mesh, attribute: halfedge::Attribute<VertexId, u32>) -> Vec<u32> {
    let values = mesh.attribute_values(attribute).unwrap();
    let mut labels = vec![NO_LABEL; mesh.vertex_slots()];
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        labels[i] = values[i];
    }
    labels
}

/// The method choices.
const METHODS: [(Method, &str); 2] = [(Method::Rounds, "rounds"), (Method::Qem, "qem")];
/// The detail-mode choices.
const DETAILS: [(DetailMode, &str); 2] = [
    (DetailMode::LocalFrame, "local"),
    (DetailMode::Translation, "translation"),
];

/// Redefines the labels after a change of the frontier's settings, when there are
/// enough picks.
fn relabel(t: &mut Multires, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
    if t.has_enough_picks() {
        t.define_labels(ctx)?;
    }
    Ok(())
}

/// The parameters of [`Multires`] (see [`params`]); the hierarchy's build checks the
/// target and the planarity bound.
const PARAMS: &[Param<Multires>] = &[
    Param::new(
        "method",
        "Method",
        Widget::Choice(|| params::names(&METHODS)),
        |t| choice_name(&METHODS, t.method).into(),
        |t, v, _| {
            t.method = choice_param(&METHODS, "method", v)?;
            Ok(())
        },
    ),
    Param::new(
        "detail",
        "Detail",
        Widget::Choice(|| params::names(&DETAILS)),
        |t| choice_name(&DETAILS, t.detail).into(),
        |t, v, _| {
            t.detail = choice_param(&DETAILS, "detail", v)?;
            Ok(())
        },
    ),
    Param::new(
        "target_faces",
        "Target faces",
        Widget::Drag {
            min: 4.0,
            max: 1e7,
            integer: true,
            speed: 10.0,
        },
        |t| t.target_faces.into(),
        |t, v, _| {
            t.target_faces = params::whole("target_faces", v)?;
            Ok(())
        },
    ),
    Param::new(
        "max_normal_deviation",
        "planarity (°)",
        params::slider(10.0, 180.0),
        |t| t.max_normal_deviation.into(),
        |t, v, _| {
            t.max_normal_deviation = number_param("max_normal_deviation", v)?;
            Ok(())
        },
    ),
    Param::new(
        "level",
        "level",
        Widget::Levels(|ctx| {
            ctx.doc
                .hierarchy()
                .map(|h| (0.0, h.coarsest_level() as f64))
        }),
        |t| t.level.into(),
        |t, v, ctx| t.go_to_level(params::whole("level", v)?, ctx),
    ),
    Param::new(
        "frontier",
        "Frontier",
        Widget::Choice(|| params::names(&FrontierMode::ALL)),
        |t| t.frontier.name().into(),
        |t, v, ctx| {
            let frontier = choice_param(&FrontierMode::ALL, "frontier", v)?;
            if frontier != t.frontier {
                t.frontier = frontier;
                t.picks.clear();
                t.plane = None;
            }
            relabel(t, ctx)
        },
    ),
    Param::new(
        "normal",
        "Normal",
        Widget::Choice(|| params::names(&PlaneNormal::ALL)),
        |t| t.normal.name().into(),
        |t, v, ctx| {
            t.normal = choice_param(&PlaneNormal::ALL, "normal", v)?;
            if let Some((p, _)) = t.plane {
                t.plane = Some((p, t.normal.vector(&ctx.view)));
            }
            relabel(t, ctx)
        },
    ),
    Param::new(
        "flip",
        "flip sides",
        Widget::Check,
        |t| t.flip.into(),
        |t, v, ctx| {
            t.flip = bool_param("flip", v)?;
            relabel(t, ctx)
        },
    ),
    Param::action("define", "Label", |t, v, ctx| {
        if bool_param("define", v)? {
            t.define_labels(ctx)?;
        }
        Ok(())
    }),
    Param::action("clear_picks", "Clear", |t, v, ctx| {
        if bool_param("clear_picks", v)? {
            t.clear_picks(ctx);
        }
        Ok(())
    }),
];

impl Tool for Multires {
    fn name(&self) -> &str {
        "Multiresolution"
    }

    fn description(&self) -> &str {
        "Seed paper §3–4.1: build a hierarchy (rounds or QEM), move between levels with \
         detail coefficients (edits at coarse levels reach the fine ones), cut a sub-mesh \
         by a picked loop, a collar or a cutting plane."
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>) {
        self.view = Some(ctx.view);
        if let Some(p) = &self.pending {
            let (levels, faces) = p.progress();
            ui.strong(format!(
                "Building the {} hierarchy… {:.1} s",
                method_name(p.method),
                p.started.elapsed().as_secs_f64()
            ));
            ui.add(
                egui::ProgressBar::new(build_fraction(p.input_faces, p.target_faces, faces)).text(
                    format!(
                        "{levels} level{} · {} of {} faces left",
                        if levels == 1 { "" } else { "s" },
                        group(faces),
                        group(p.input_faces)
                    ),
                ),
            );
            ui.weak(format!(
                "down to {} faces; the tool is back when the build is done",
                group(p.target_faces.min(p.input_faces))
            ));
            if p.cancel.load(Ordering::Relaxed) {
                ui.weak("Cancelling at the end of this level…");
            } else if ui.button("Cancel").clicked() {
                self.cancel_build();
            }
            ui.separator();
        }
        let idle = self.pending.is_none();
        ui.add_enabled_ui(idle, |ui| self.controls_ui(ui, ctx));
    }

    fn poll(&mut self, ctx: &mut ToolContext<'_>) -> Background {
        // The document's level (undo and redo walk it too).
        self.level = ctx.doc.hierarchy().map_or(0, Hierarchy::level_at_or_finer);
        let Some(pending) = &self.pending else {
            return Background::Idle;
        };
        let received = match pending.result.try_recv() {
            Err(TryRecvError::Empty) => return Background::Running,
            Ok(r) => Some(r),
            Err(TryRecvError::Disconnected) => None,
        };
        let pending = self.pending.take().expect("checked");
        match self.finish_build(pending, received, ctx) {
            Ok(()) => Background::Idle,
            Err(e) => {
                ctx.error(format!("Build failed: {e}"));
                Background::Failed(e)
            }
        }
    }

    fn on_pick(&mut self, pick: Option<&Pick>, ctx: &mut ToolContext<'_>) {
        let Some(pick) = pick else {
            return;
        };
        match self.frontier {
            FrontierMode::Loop | FrontierMode::Collar => {
                if self.picks.last() != Some(&pick.vertex) {
                    self.picks.push(pick.vertex);
                }
            }
            FrontierMode::Plane => {
                self.plane = Some((pick.point, self.normal.vector(&ctx.view)));
            }
        }
        if self.has_enough_picks() {
            if let Err(e) = self.define_labels(ctx) {
                ctx.info(format!("{} picks: {e}", self.picks.len()));
            }
        } else {
            ctx.info(format!(
                "Picked v{} ({} picks)",
                ctx.mesh().vertex_index(pick.vertex),
                self.picks.len()
            ));
        }
    }

    fn apply(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.start_build(ctx)
    }

    fn set_parameter(
        &mut self,
        name: &str,
        value: &serde_json::Value,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        // (The name is copied: the setter borrows the tool mutably.)
        let tool = self.name().to_owned();
        params::set(&tool, PARAMS, self, name, value, ctx)
    }

    fn parameters(&self) -> Vec<(&'static str, serde_json::Value)> {
        params::list(PARAMS, self)
    }

    fn overlay(&self, mesh: &Mesh, overlay: &mut Overlay) {
        for &v in &self.picks {
            if mesh.is_valid_vertex(v) {
                overlay.marker(mesh.position(v), Overlay::PICK, 1.2);
            }
        }
        if let Some((p, _)) = self.plane {
            overlay.marker(p, Overlay::PICK, 1.5);
        }
        frontier_overlay(mesh, overlay);
    }

    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        self.picks.retain(|&v| mesh.is_valid_vertex(v));
        self.collar.retain(|&f| mesh.is_valid_face(f));
    }

    fn activate(&mut self, ctx: &mut ToolContext<'_>) {
        self.show_labels(ctx);
    }
}

impl Multires {
    /// The panel's controls (disabled while a build runs).
    fn controls_ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>) {
        ui.strong("Hierarchy");
        params::widget(ui, PARAMS, "method", self, ctx);
        if let Some(r) = params::widget(ui, PARAMS, "detail", self, ctx) {
            r.on_hover_text(
                "how refinement carries coarse edits (applies to the next build): local \
                 frames carry rotations, translation is the paper's centroid translations",
            );
        }
        params::widget(ui, PARAMS, "target_faces", self, ctx);
        if self.method == Method::Rounds {
            params::widget(ui, PARAMS, "max_normal_deviation", self, ctx);
        }
        if ui.button("Build hierarchy").clicked() {
            if let Err(e) = self.start_build(ctx) {
                ctx.error(format!("Build failed: {e}"));
            }
        }
        self.level = ctx.doc.hierarchy().map_or(0, Hierarchy::level_at_or_finer);
        // The level slider's range is the hierarchy's levels (no hierarchy: no slider).
        if let Some(r) = params::widget(ui, PARAMS, "level", self, ctx) {
            if r.drag_stopped() || (r.changed() && !r.dragged()) {
                ctx.doc.end_edit();
            }
        }
        match ctx.doc.hierarchy() {
            Some(h) => {
                let coarsest = h.coarsest_level();
                let counts = h.level_face_counts();
                ui.weak(format!(
                    "level {}: {} faces · {} levels · {} faces at the coarsest",
                    self.level,
                    group(counts[self.level.min(coarsest)]),
                    coarsest + 1,
                    group(counts[coarsest])
                ));
            }
            None => {
                ui.weak("No hierarchy yet.");
            }
        }
        ui.separator();
        ui.strong("Sub-mesh");
        params::widget(ui, PARAMS, "frontier", self, ctx);
        if self.frontier == FrontierMode::Plane {
            params::widget(ui, PARAMS, "normal", self, ctx);
        }
        params::widget(ui, PARAMS, "flip", self, ctx);
        ui.weak(match self.frontier {
            FrontierMode::Loop => "Click vertices around the part to cut (3 or more).",
            FrontierMode::Collar => {
                "Click vertices around the part: the band of faces along them is the collar."
            }
            FrontierMode::Plane => {
                "Click a point of the cutting plane; the sub-mesh is on the normal's side."
            }
        });
        ui.horizontal(|ui| {
            ui.label(format!("{} picks", self.picks.len()));
            params::widget(ui, PARAMS, "define", self, ctx);
            params::widget(ui, PARAMS, "clear_picks", self, ctx);
        });
        if let Some(l) = SubMeshLabels::of(ctx.mesh()) {
            ui.weak(l.description());
        }
    }

    fn has_enough_picks(&self) -> bool {
        match self.frontier {
            FrontierMode::Loop | FrontierMode::Collar => self.picks.len() >= 3,
            FrontierMode::Plane => self.plane.is_some(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::document::Document;
    use crate::tools::Headless;
    use halfedge::generators;

    /// A document on `mesh` and the rest of what a tool context borrows, for tests
    /// without a window.
    fn fixture(mesh: Mesh) -> Headless {
        Headless::new(Document::new(mesh, None, None))
    }

    /// Polls `tool` like the viewer does every frame until its build is done.
    fn poll_until_idle(tool: &mut Multires, ctx: &mut ToolContext<'_>) -> Background {
        let start = Instant::now();
        loop {
            match tool.poll(ctx) {
                Background::Running => {
                    assert!(
                        start.elapsed() < Duration::from_secs(120),
                        "the build does not end"
                    );
                    std::thread::sleep(Duration::from_millis(5));
                }
                done => return done,
            }
        }
    }

    #[test]
    fn a_cancelled_build_leaves_the_tool_idle_and_the_mesh_unchanged() {
        // Large enough that the first level takes far longer than asking to cancel.
        let input = generators::icosphere(7);
        let mut fixture = fixture(input.clone());
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new();
        tool.target_faces = 200;
        tool.apply(&mut ctx).unwrap();
        tool.cancel_build();
        assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
        assert!(
            ctx.status.message.starts_with("Build cancelled"),
            "{}",
            ctx.status.message
        );
        assert!(ctx.doc.hierarchy().is_none());
        assert!(ctx.mesh().positions() == input.positions());
        assert_eq!(ctx.mesh().n_faces(), input.n_faces());
        // The tool builds again afterwards.
        tool.target_faces = 20_000;
        tool.apply(&mut ctx).unwrap();
        assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
        assert!(ctx.doc.hierarchy().is_some());
    }

    #[test]
    fn the_detail_switch_reaches_the_hierarchy() {
        let mut fixture = fixture(generators::icosphere(3));
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new();
        tool.target_faces = 100;
        assert!(tool
            .set_parameter("detail", &"sideways".into(), &mut ctx)
            .is_err());
        for (name, mode) in [
            ("translation", DetailMode::Translation),
            ("local", DetailMode::LocalFrame),
        ] {
            tool.set_parameter("detail", &name.into(), &mut ctx)
                .unwrap();
            assert!(tool.parameters().contains(&("detail", name.into())));
            tool.apply(&mut ctx).unwrap();
            assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
            assert_eq!(ctx.doc.hierarchy().unwrap().detail_mode(), mode);
        }
    }

    #[test]
    fn background_build_gives_the_levels_of_a_direct_build_and_undo_works() {
        let input = generators::icosphere(4);
        let mut fixture = fixture(input.clone());
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new();
        tool.target_faces = 200;
        tool.apply(&mut ctx).unwrap();
        assert!(tool.is_building());
        assert!(ctx.status.message.starts_with("Building rounds hierarchy"));
        // The rest of the tool waits for the build.
        assert!(tool.set_parameter("level", &1.into(), &mut ctx).is_err());
        assert!(tool.apply(&mut ctx).is_err());
        assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
        assert!(!tool.is_building());
        assert!(
            ctx.status.message.starts_with("Built rounds hierarchy"),
            "{}",
            ctx.status.message
        );
        let direct = Hierarchy::build(
            input.clone(),
            &HierarchyOptions::rounds()
                .with_max_normal_deviation(90f64.to_radians())
                .with_target_faces(200),
        )
        .unwrap();
        let h = ctx.doc.hierarchy().expect("built");
        assert_eq!(h.level_face_counts(), direct.level_face_counts());
        assert!(h.coarsest_level() >= 2);
        let coarsest = h.coarsest_level();
        // The document stays the input, bit for bit.
        assert_eq!(ctx.mesh().positions(), input.positions());
        // Level changes and undo work on the hierarchy from the thread.
        tool.set_parameter("level", &coarsest.into(), &mut ctx)
            .unwrap();
        ctx.doc.end_edit();
        assert_eq!(ctx.mesh().n_faces(), direct.level_face_counts()[coarsest]);
        ctx.mesh().check().unwrap();
        assert!(ctx.doc.undo().is_some());
        assert_eq!(ctx.mesh().positions(), input.positions());
        assert_eq!(ctx.mesh().n_faces(), input.n_faces());
        assert!(ctx.doc.redo().is_some());
        assert_eq!(ctx.mesh().n_faces(), direct.level_face_counts()[coarsest]);
    }

    #[test]
    fn build_errors_reach_the_status_line() {
        let mut fixture = fixture(generators::icosphere(2));
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new();
        // Out of range: the library refuses it.
        tool.max_normal_deviation = 200.0;
        tool.start_build(&mut ctx).unwrap();
        match poll_until_idle(&mut tool, &mut ctx) {
            Background::Failed(e) => assert!(e.0.contains("max_normal_deviation"), "{e}"),
            other => panic!("expected a failure, got {other:?}"),
        }
        assert!(ctx.status.is_error);
        assert!(ctx.status.message.starts_with("Build failed"));
        assert!(ctx.doc.hierarchy().is_none() && !tool.is_building());
        assert_eq!(ctx.doc.undo_len(), 0);
    }

    #[test]
    fn a_mesh_changed_during_the_build_refuses_the_result() {
        let mut fixture = fixture(generators::icosphere(2));
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new();
        tool.target_faces = 40;
        tool.start_build(&mut ctx).unwrap();
        ctx.positions_mut()[0] += DVec3::X;
        ctx.doc.end_edit();
        assert!(matches!(
            poll_until_idle(&mut tool, &mut ctx),
            Background::Failed(_)
        ));
        assert!(ctx.doc.hierarchy().is_none());
    }

    #[test]
    fn progress_fraction_counts_the_faces_removed_towards_the_target() {
        assert_eq!(build_fraction(1000, 100, 1000), 0.0);
        assert_eq!(build_fraction(1000, 100, 550), 0.5);
        assert_eq!(build_fraction(1000, 100, 100), 1.0);
        assert_eq!(build_fraction(1000, 100, 50), 1.0);
        assert_eq!(build_fraction(50, 100, 50), 1.0);
    }

    /// Builds a hierarchy of `mesh` in the document through the tool, down to `target`.
    fn built(fixture: &mut Headless, target: usize) -> Multires {
        let mut tool = Multires::new();
        tool.target_faces = target;
        let mut ctx = fixture.ctx();
        tool.apply(&mut ctx).unwrap();
        assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
        tool
    }

    #[test]
    fn the_document_shows_the_hierarchys_own_mesh_at_every_level() {
        let mut fixture = fixture(generators::icosphere(3));
        let mut tool = built(&mut fixture, 100);
        let mut ctx = fixture.ctx();
        let coarsest = ctx.doc.hierarchy().unwrap().coarsest_level();
        for level in [coarsest, 1, 0, coarsest] {
            tool.go_to_level(level, &mut ctx).unwrap();
            let h = ctx.doc.hierarchy().unwrap();
            // One mesh: the document's mesh is the hierarchy's, not a copy of it.
            assert!(std::ptr::eq(ctx.mesh(), h.mesh()));
            assert_eq!(h.current_level(), Some(level));
            assert_eq!(ctx.mesh().n_faces(), h.level_face_counts()[level]);
            assert_eq!(tool.parameters()[4], ("level", level.into()));
        }
    }

    #[test]
    fn an_edit_at_a_coarse_level_is_carried_to_the_fine_level() {
        let input = generators::icosphere(3);
        let mut fixture = fixture(input.clone());
        let mut tool = built(&mut fixture, 100);
        let mut ctx = fixture.ctx();
        let coarsest = ctx.doc.hierarchy().unwrap().coarsest_level();
        tool.go_to_level(coarsest, &mut ctx).unwrap();
        ctx.doc.end_edit();
        let t = DVec3::new(0.25, -0.5, 0.125);
        ctx.begin_edit("move");
        for p in ctx.positions_mut() {
            *p += t;
        }
        ctx.doc.end_edit();
        tool.go_to_level(0, &mut ctx).unwrap();
        ctx.doc.end_edit();
        assert_eq!(ctx.mesh().n_faces(), input.n_faces());
        for v in input.vertices() {
            let d = ctx.mesh().position(v) - input.position(v) - t;
            assert!(d.length() < 1e-9, "{v}: off by {d}");
        }
        // Undo: level 0, the move, the coarsening, the build; each exact.
        let labels: Vec<String> = ctx.doc.undo_labels().map(str::to_owned).collect();
        assert_eq!(
            labels,
            [
                "Build hierarchy",
                &format!("Level {coarsest}"),
                "move",
                "Level 0"
            ]
        );
        for _ in 0..3 {
            ctx.doc.undo().unwrap();
        }
        assert_eq!(ctx.mesh().positions(), input.positions());
        assert_eq!(ctx.mesh().n_faces(), input.n_faces());
        assert!(ctx.doc.hierarchy().is_some());
        ctx.doc.undo().unwrap();
        assert!(
            ctx.doc.hierarchy().is_none(),
            "undoing the build gives the plain mesh"
        );
        assert_eq!(ctx.mesh().positions(), input.positions());
        ctx.doc.redo().unwrap();
        assert!(ctx.doc.hierarchy().is_some());
    }

    #[test]
    fn labels_live_in_the_mesh_and_ride_along_through_the_levels() {
        let mut fixture = fixture(generators::icosphere(3));
        let mut tool = built(&mut fixture, 100);
        let mut ctx = fixture.ctx();
        tool.set_parameter("frontier", &"plane".into(), &mut ctx)
            .unwrap();
        tool.set_parameter("normal", &"x".into(), &mut ctx).unwrap();
        let v = ctx.mesh().vertices().next().unwrap();
        let pick = Pick {
            vertex: v,
            face: None,
            point: DVec3::ZERO,
        };
        tool.on_pick(Some(&pick), &mut ctx);
        let fine = SubMeshLabels::of(ctx.mesh()).expect("labelled");
        let (host, sub, front) = fine.counts();
        assert!(host > 0 && sub > 0 && front > 0, "{:?}", fine.counts());
        assert_eq!(host + sub + front, ctx.mesh().n_vertices());
        let coarsest = ctx.doc.hierarchy().unwrap().coarsest_level();
        tool.go_to_level(coarsest, &mut ctx).unwrap();
        // The same attribute, at the coarse level: every live vertex labelled.
        let coarse = SubMeshLabels::of(ctx.mesh()).expect("labels ride along");
        let (h, s, f) = coarse.counts();
        assert_eq!(h + s + f, ctx.mesh().n_vertices());
        assert!(s > 0 && h > 0);
        // The other tools read them there.
        let mut sub_tool = super::super::SubMeshEdit::new();
        sub_tool
            .set_parameter("source", &"labels".into(), &mut ctx)
            .unwrap();
        assert!(sub_tool.submesh(ctx.mesh()).is_ok());
        // Back at level 0 the labels are the ones made there.
        tool.go_to_level(0, &mut ctx).unwrap();
        assert_eq!(SubMeshLabels::of(ctx.mesh()), Some(fine));
        // Clearing removes them from the mesh.
        tool.set_parameter("clear_picks", &true.into(), &mut ctx)
            .unwrap();
        assert!(SubMeshLabels::of(ctx.mesh()).is_none());
    }

    #[test]
    fn the_label_layer_follows_the_mesh_through_undo() {
        let mut fixture = fixture(generators::icosphere(3));
        let mut tool = built(&mut fixture, 100);
        let mut ctx = fixture.ctx();
        tool.set_parameter("frontier", &"plane".into(), &mut ctx)
            .unwrap();
        let v = ctx.mesh().vertices().next().unwrap();
        let pick = Pick {
            vertex: v,
            face: None,
            point: DVec3::ZERO,
        };
        tool.on_pick(Some(&pick), &mut ctx);
        let fine_layer = ctx.display.layer().clone();
        assert_eq!(fine_layer.name(), Some(LABEL_LAYER));
        tool.go_to_level(2, &mut ctx).unwrap();
        ctx.doc.end_edit();
        let coarse_layer = ctx.display.layer().clone();
        assert_ne!(coarse_layer, fine_layer);
        // Undo walks back to level 0: the layer shown is stale until refreshed.
        ctx.doc.undo().unwrap();
        let refreshed = refreshed_label_layer(ctx.display.layer(), ctx.mesh()).unwrap();
        assert_eq!(refreshed, fine_layer);
        // Other layers stay as they are.
        assert!(refreshed_label_layer(&ColorLayer::None, ctx.mesh()).is_none());
    }
}
