//! *Multiresolution* — the progressive hierarchy and the sub-mesh labels of *Interactive
//! Editing of Multiresolution Meshes* (the seed paper, sections 3 and 4.1).
//!
//! - **Build** a [`Hierarchy`] of the current mesh with the paper's rounds or a QEM
//!   decimation, down to a target face count; the document stays at the finest level.
//!   The build runs on its own thread (a copy of the mesh moves in, the hierarchy comes
//!   back through a channel) while the panel shows its progress (levels done, faces left);
//!   the viewer stays responsive and keeps the mesh unchanged until it returns
//!   ([`Tool::poll`]).
//! - **Level slider**: coarsens or refines with the hierarchy's detail coefficients. Edits
//!   made by other tools at a coarse level ride along to the finer levels: before moving,
//!   the document's positions are copied into the hierarchy's mesh (when the document's
//!   connectivity is the hierarchy's current level, or a level already visited, e.g. after
//!   undo), then the hierarchy moves, and its mesh goes back into the document as one undo
//!   step.
//! - **Sub-mesh frontier** (section 4.1, Fig. 2): (a) picked vertices joined into a closed
//!   loop by shortest edge paths, (b) a collar of faces (the faces around the loop through
//!   the picked vertices; the frontier is its border on the side of the smaller part),
//!   (c) a cutting plane through a picked point, normal along an axis or the view. The
//!   labels (host, sub-mesh, frontier) colour the mesh, the frontier is drawn over it, and
//!   the labels ride along through level changes (Fig. 4 rule, [`halfedge::labels`]).
//!   They are shared with the *Sub-mesh edits* and *FFD* tools through [`SharedLabels`].

use std::cell::RefCell;
use std::collections::HashMap;
use std::ops::ControlFlow;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::DVec3;
use halfedge::{
    BuildProgress, DetailMode, FaceId, Hierarchy, HierarchyOptions, Mesh, Method, VertexId,
    FRONTIER,
};
use three_d::egui;

use super::params::{self, Param, Widget};
use super::{
    bool_param, choice_name, choice_param, number_param, Background, Overlay, Pick, Tool,
    ToolContext, ToolError, ViewInfo,
};
use crate::colors::{Rgba, NO_LABEL};
use crate::document::Revision;
use crate::format::group;

/// Label of the host (the part outside the sub-mesh).
pub const HOST: u32 = 0;
/// Label of the sub-mesh.
pub const SUBMESH: u32 = 1;

/// Colour of the frontier segments.
const FRONTIER_COLOR: Rgba = [255, 220, 40, 255];

/// A hash of a mesh's connectivity: slot counts and, for every live face, its index, its
/// corners and its halfedges (rotated to start at the smallest corner). Equal
/// fingerprints mean the same handles and the same triangles, so that per-slot data (labels,
/// positions) carry over.
pub fn connectivity_fingerprint(mesh: &Mesh) -> u64 {
    const K: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut h: u64 = 0xCBF2_9CE4_8422_2325;
    let mut mix = |x: u64| {
        h = (h ^ x).wrapping_mul(K).rotate_left(29);
    };
    for x in [
        mesh.vertex_slots(),
        mesh.halfedge_slots(),
        mesh.face_slots(),
        mesh.n_vertices(),
        mesh.n_faces(),
    ] {
        mix(x as u64);
    }
    for f in mesh.faces() {
        mix(mesh.face_index(f) as u64);
        let hs: Vec<_> = mesh.face_halfedges(f).collect();
        let vs: Vec<usize> = hs
            .iter()
            .map(|&e| mesh.vertex_index(mesh.to_vertex(e)))
            .collect();
        let start = (0..vs.len()).min_by_key(|&i| vs[i]).unwrap_or(0);
        for k in 0..vs.len() {
            let i = (start + k) % vs.len();
            mix(vs[i] as u64);
            mix(mesh.halfedge_index(hs[i]) as u64);
        }
    }
    h
}

/// Sub-mesh labels of the current mesh: one label per vertex slot ([`HOST`], [`SUBMESH`]
/// or [`FRONTIER`]), valid for the connectivity they were made on.
#[derive(Clone, Debug, PartialEq)]
pub struct SubMeshLabels {
    /// Label per vertex slot (dead slots: [`NO_LABEL`]).
    pub labels: Vec<u32>,
    /// [`connectivity_fingerprint`] of the mesh they belong to.
    pub fingerprint: u64,
    /// How they were made (for the status line and panels).
    pub description: String,
}

impl SubMeshLabels {
    /// True when the labels belong to `mesh`'s connectivity.
    pub fn matches(&self, mesh: &Mesh) -> bool {
        self.labels.len() == mesh.vertex_slots()
            && self.fingerprint == connectivity_fingerprint(mesh)
    }

    /// The sub-mesh as a mask per vertex slot: the sub-mesh and its frontier (the frontier
    /// vertices are shared by the sub-mesh and the host, section 4.1).
    pub fn inside_mask(&self) -> Vec<bool> {
        self.labels
            .iter()
            .map(|&l| l == SUBMESH || l == FRONTIER)
            .collect()
    }

    /// Number of vertices per label `(host, sub-mesh, frontier)`.
    pub fn counts(&self) -> (usize, usize, usize) {
        let mut c = (0, 0, 0);
        for &l in &self.labels {
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
            .map(|&l| match l {
                HOST => 0,
                SUBMESH => 1,
                FRONTIER => 2,
                _ => NO_LABEL,
            })
            .collect()
    }

    /// Colours the mesh by these labels.
    pub fn show(&self, ctx: &mut ToolContext<'_>) {
        ctx.show_vertex_labels(
            "sub-mesh labels",
            self.display_labels(),
            vec![
                (0, "host".into()),
                (1, "sub-mesh".into()),
                (2, "frontier".into()),
            ],
        );
    }

    /// The frontier edges (both ends on the frontier) as segments over `mesh`.
    pub fn frontier_overlay(&self, mesh: &Mesh, overlay: &mut Overlay) {
        if self.labels.len() != mesh.vertex_slots() {
            return;
        }
        for e in mesh.edges() {
            let (a, b) = (mesh.from_vertex(e), mesh.to_vertex(e));
            if self.labels[mesh.vertex_index(a)] == FRONTIER
                && self.labels[mesh.vertex_index(b)] == FRONTIER
            {
                overlay.segment(mesh.position(a), mesh.position(b), FRONTIER_COLOR);
            }
        }
    }
}

/// The sub-mesh labels shared by the tools (set by *Multiresolution*, used by *Sub-mesh
/// edits* and *FFD*).
#[derive(Clone, Debug, Default)]
pub struct SharedLabels(Rc<RefCell<Option<SubMeshLabels>>>);

impl SharedLabels {
    /// The labels, if any and if they belong to `mesh`.
    pub fn get(&self, mesh: &Mesh) -> Option<SubMeshLabels> {
        self.0
            .borrow()
            .as_ref()
            .filter(|l| l.matches(mesh))
            .cloned()
    }
    /// Replaces the labels.
    pub fn set(&self, labels: Option<SubMeshLabels>) {
        *self.0.borrow_mut() = labels;
    }
    /// True when labels are set (whatever mesh they belong to).
    pub fn is_set(&self) -> bool {
        self.0.borrow().is_some()
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
    /// Connectivity of the input, to tell whether level 0 comes back with other slots.
    input_fingerprint: u64,
    /// The document's revision when the build started: it must not change meanwhile.
    revision: Revision,
    /// Sub-mesh labels of the input, attached to the hierarchy at level 0.
    labels: Option<SubMeshLabels>,
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
    shared: SharedLabels,
    /// Rounds (the paper) or QEM.
    pub method: Method,
    /// Stop building at this many faces.
    pub target_faces: usize,
    /// Planarity bound of the rounds, degrees.
    pub max_normal_deviation: f64,
    /// How refinement carries coarse edits: local frames with exact regions (default) or
    /// the paper's centroid translations.
    pub detail: DetailMode,
    hierarchy: Option<Hierarchy>,
    /// The build running on another thread, if any.
    pending: Option<PendingBuild>,
    /// Level shown by the slider.
    level: usize,
    /// Connectivity fingerprint → level, for the levels visited.
    visited: HashMap<u64, usize>,
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

impl Multires {
    /// The tool, sharing its labels through `shared`.
    pub fn new(shared: SharedLabels) -> Self {
        Self {
            shared,
            method: Method::Rounds,
            target_faces: 500,
            max_normal_deviation: 90.0,
            detail: DetailMode::LocalFrame,
            hierarchy: None,
            pending: None,
            level: 0,
            visited: HashMap::new(),
            frontier: FrontierMode::Loop,
            normal: PlaneNormal::Y,
            flip: false,
            picks: Vec::new(),
            plane: None,
            collar: Vec::new(),
            view: None,
        }
    }

    /// The hierarchy, once built.
    pub fn hierarchy(&self) -> Option<&Hierarchy> {
        self.hierarchy.as_ref()
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
        let input_fingerprint = connectivity_fingerprint(&input);
        let input_faces = input.n_faces();
        let labels = self.shared.get(&input);
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
            input_fingerprint,
            revision: ctx.doc.revision(),
            labels,
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
        let input_fp = pending.input_fingerprint;
        let input_faces = pending.input_faces;
        let coarse_faces = h.mesh().n_faces();
        // Back to the input (bit for bit), where the document is.
        h.go_to_level(0)?;
        if let Some(labels) = pending.labels {
            // Labels made on the input: attach them at level 0.
            let attribute = h.mesh_mut().label_attribute()?;
            let n = labels.labels.len();
            h.mesh_mut().attribute_values_mut(attribute)[..n].copy_from_slice(&labels.labels);
            h.attach_labels(attribute);
        }
        let fp = connectivity_fingerprint(h.mesh());
        if fp != input_fp {
            ctx.begin_topology_edit("Build hierarchy");
            *ctx.mesh_mut() = h.mesh().clone();
            ctx.doc.end_edit();
        }
        self.visited.clear();
        self.visited.insert(fp, 0);
        self.level = 0;
        // Counted as the panel counts them: the input is level 0.
        let levels = h.coarsest_level() + 1;
        // Say plainly when the target was missed, or reached only by widening the bounds.
        let outcome = h.build_outcome();
        let how = if !outcome.target_reached() || !outcome.relaxations.is_empty() {
            format!(" ({outcome})")
        } else {
            String::new()
        };
        self.hierarchy = Some(h);
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

    /// Copies the document's positions into the hierarchy's mesh, first moving the
    /// hierarchy to the document's level when the document shows another visited level.
    fn sync_from_document(&mut self, ctx: &ToolContext<'_>) -> Result<(), ToolError> {
        self.check_idle()?;
        let h = self
            .hierarchy
            .as_mut()
            .ok_or_else(|| ToolError::new("no hierarchy: build one first"))?;
        let doc = ctx.mesh();
        let fp = connectivity_fingerprint(doc);
        if fp != connectivity_fingerprint(h.mesh()) {
            let Some(&level) = self.visited.get(&fp) else {
                return Err(ToolError::new(
                    "the mesh's connectivity is none of the hierarchy's levels (another \
                     mesh was loaded or its connectivity changed): build the hierarchy again",
                ));
            };
            h.go_to_level(level)?;
            if connectivity_fingerprint(h.mesh()) != fp {
                return Err(ToolError::new(
                    "the hierarchy could not return to the document's level: build it again",
                ));
            }
            self.level = level;
        }
        let target = h.mesh_mut();
        let src = doc.positions();
        let live: Vec<usize> = doc.vertices().map(|v| doc.vertex_index(v)).collect();
        let dst = target.positions_mut();
        for i in live {
            dst[i] = src[i];
        }
        Ok(())
    }

    /// Moves to `level` (coarsening or refining with detail coefficients), one undo step.
    pub fn go_to_level(
        &mut self,
        level: usize,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        self.sync_from_document(ctx)?;
        let h = self.hierarchy.as_mut().expect("synced");
        if level > h.coarsest_level() {
            return Err(ToolError::new(format!(
                "level {level} does not exist (levels 0..={})",
                h.coarsest_level()
            )));
        }
        let from = h.current_level().unwrap_or(self.level);
        if from == level
            && connectivity_fingerprint(ctx.mesh()) == connectivity_fingerprint(h.mesh())
        {
            self.level = level;
            return Ok(());
        }
        let start = Instant::now();
        h.go_to_level(level)?;
        let took = start.elapsed();
        let fp = connectivity_fingerprint(h.mesh());
        self.visited.insert(fp, level);
        self.level = level;
        ctx.begin_topology_edit(&format!("Level {level}"));
        *ctx.mesh_mut() = h.mesh().clone();
        self.picks.clear();
        self.collar.clear();
        // The labels rode along (Fig. 4 rule): publish them for this level.
        if let Some(attribute) = h.label_attribute() {
            let labels = read_labels(h.mesh(), attribute);
            let labels = SubMeshLabels {
                labels,
                fingerprint: fp,
                description: "multiresolution labels".into(),
            };
            labels.show(ctx);
            self.shared.set(Some(labels));
        }
        let verb = if level > from { "coarsened" } else { "refined" };
        ctx.info(format!(
            "Level {level}: {} faces, {} vertices ({verb} from level {from} in {:.1} ms)",
            group(ctx.mesh().n_faces()),
            group(ctx.mesh().n_vertices()),
            took.as_secs_f64() * 1e3
        ));
        Ok(())
    }

    /// Makes the frontier from the picks and labels the two sides (on the hierarchy's
    /// mesh when there is one, so that the labels ride along through levels).
    pub fn define_labels(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.check_idle()?;
        let use_hierarchy = self.hierarchy.is_some() && self.sync_from_document(ctx).is_ok();
        let mut scratch;
        let mesh: &mut Mesh = if use_hierarchy {
            self.hierarchy.as_mut().expect("checked").mesh_mut()
        } else {
            scratch = ctx.mesh().clone();
            &mut scratch
        };
        let frontier = match self.frontier {
            FrontierMode::Loop => {
                if self.picks.len() < 3 {
                    return Err(ToolError::new(format!(
                        "a loop needs at least 3 picked vertices ({} so far)",
                        self.picks.len()
                    )));
                }
                mesh.frontier_through(&self.picks)?
            }
            FrontierMode::Collar => {
                if self.picks.len() < 3 {
                    return Err(ToolError::new(format!(
                        "a collar needs at least 3 picked vertices ({} so far)",
                        self.picks.len()
                    )));
                }
                let path = mesh.closed_loop_through(&self.picks)?;
                let mut seen = vec![false; mesh.face_slots()];
                let mut collar = Vec::new();
                for &e in &path {
                    for f in mesh.adjacent_faces(mesh.from_vertex(e)) {
                        if !std::mem::replace(&mut seen[mesh.face_index(f)], true) {
                            collar.push(f);
                        }
                    }
                }
                let frontier = mesh.frontier_from_collar(&collar)?;
                self.collar = collar;
                frontier
            }
            FrontierMode::Plane => {
                let (point, normal) = self
                    .plane
                    .ok_or_else(|| ToolError::new("pick a point of the cutting plane"))?;
                mesh.frontier_from_plane(point, normal)?
            }
        };
        let (mut attribute, mut counts) = mesh.label_sides(&frontier, SUBMESH, HOST)?;
        let mut swap = match self.frontier {
            FrontierMode::Plane => {
                // The sub-mesh is on the normal's side of the plane.
                let (point, normal) = self.plane.expect("checked");
                let values = mesh.attribute_values(attribute);
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
            (attribute, counts) = mesh.label_sides(&frontier, HOST, SUBMESH)?;
        }
        let labels = read_labels(mesh, attribute);
        let fp = connectivity_fingerprint(mesh);
        if use_hierarchy {
            self.hierarchy
                .as_mut()
                .expect("checked")
                .attach_labels(attribute);
        }
        let sub = if swap {
            counts.right_vertices
        } else {
            counts.left_vertices
        };
        let host = if swap {
            counts.left_vertices
        } else {
            counts.right_vertices
        };
        let description = format!(
            "{} frontier of {} edges: sub-mesh {} vertices, host {}, frontier {}",
            self.frontier.name(),
            frontier.halfedges().len(),
            group(sub),
            group(host),
            group(counts.frontier_vertices)
        );
        let labels = SubMeshLabels {
            labels,
            fingerprint: fp,
            description: description.clone(),
        };
        labels.show(ctx);
        self.shared.set(Some(labels));
        ctx.info(format!("Labelled: {description}"));
        Ok(())
    }

    fn clear_picks(&mut self, ctx: &mut ToolContext<'_>) {
        self.picks.clear();
        self.collar.clear();
        self.plane = None;
        self.shared.set(None);
        if let Some(h) = &mut self.hierarchy {
            h.detach_labels();
        }
        ctx.clear_colors();
        ctx.info("Multiresolution: picks and labels cleared");
    }

    fn show_labels(&self, ctx: &mut ToolContext<'_>) {
        if let Some(l) = self.shared.get(ctx.mesh()) {
            l.show(ctx);
        }
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
    let values = mesh.attribute_values(attribute);
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
    // The slider of the levels is drawn by the panel (its range is the hierarchy's).
    Param::new(
        "level",
        "level",
        Widget::None,
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
        if let Some(labels) = self.shared.0.borrow().as_ref() {
            if labels.labels.len() == mesh.vertex_slots() {
                labels.frontier_overlay(mesh, overlay);
            }
        }
    }

    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        self.picks.retain(|&v| mesh.is_valid_vertex(v));
        self.collar.retain(|&f| mesh.is_valid_face(f));
        if let Some(&level) = self.visited.get(&connectivity_fingerprint(mesh)) {
            self.level = level;
        }
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
        if let Some(h) = &self.hierarchy {
            let coarsest = h.coarsest_level();
            let counts = h.level_face_counts().to_vec();
            // The slider's range is the hierarchy's levels.
            let mut level = self.level;
            let r = ui.add(egui::Slider::new(&mut level, 0..=coarsest).text("level"));
            if level != self.level {
                let value = serde_json::Value::from(level);
                if let Err(e) = params::set("Multiresolution", PARAMS, self, "level", &value, ctx) {
                    ctx.error(format!("Level change failed: {e}"));
                }
            }
            ui.weak(format!(
                "level {}: {} faces · {} levels · {} faces at the coarsest",
                self.level,
                group(counts[self.level.min(coarsest)]),
                coarsest + 1,
                group(counts[coarsest])
            ));
            if r.drag_stopped() || (r.changed() && !r.dragged()) {
                ctx.doc.end_edit();
            }
        } else {
            ui.weak("No hierarchy yet.");
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
        if let Some(l) = self.shared.get(ctx.mesh()) {
            let (host, sub, front) = l.counts();
            ui.weak(format!(
                "sub-mesh {} · host {} · frontier {} vertices",
                group(sub),
                group(host),
                group(front)
            ));
        } else if self.shared.is_set() {
            ui.weak("The labels belong to another level or mesh.");
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
    use crate::colors::Display;
    use crate::document::Document;
    use crate::tools::Status;
    use halfedge::generators;

    fn view() -> ViewInfo {
        ViewInfo {
            eye: DVec3::new(0.0, 0.0, 5.0),
            forward: DVec3::NEG_Z,
            right: DVec3::X,
            up: DVec3::Y,
            scene_radius: 1.0,
        }
    }

    /// A document and the rest of what a tool context borrows, for tests without a window.
    struct Fixture {
        doc: Document,
        display: Display,
        status: Status,
    }

    impl Fixture {
        fn new(mesh: Mesh) -> Self {
            Self {
                doc: Document::new(mesh, None, None),
                display: Display::default(),
                status: Status::default(),
            }
        }

        fn ctx(&mut self) -> ToolContext<'_> {
            ToolContext {
                doc: &mut self.doc,
                display: &mut self.display,
                status: &mut self.status,
                view: view(),
                pick: None,
            }
        }
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
        let mut fixture = Fixture::new(input.clone());
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new(SharedLabels::default());
        tool.target_faces = 200;
        tool.apply(&mut ctx).unwrap();
        tool.cancel_build();
        assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
        assert!(
            ctx.status.message.starts_with("Build cancelled"),
            "{}",
            ctx.status.message
        );
        assert!(tool.hierarchy.is_none());
        assert!(ctx.mesh().positions() == input.positions());
        assert_eq!(ctx.mesh().n_faces(), input.n_faces());
        // The tool builds again afterwards.
        tool.target_faces = 20_000;
        tool.apply(&mut ctx).unwrap();
        assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
        assert!(tool.hierarchy.is_some());
    }

    #[test]
    fn the_detail_switch_reaches_the_hierarchy() {
        let mut fixture = Fixture::new(generators::icosphere(3));
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new(SharedLabels::default());
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
            assert_eq!(tool.hierarchy().unwrap().detail_mode(), mode);
        }
    }

    #[test]
    fn background_build_gives_the_levels_of_a_direct_build_and_undo_works() {
        let input = generators::icosphere(4);
        let mut fixture = Fixture::new(input.clone());
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new(SharedLabels::default());
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
        let h = tool.hierarchy().expect("built");
        assert_eq!(h.level_face_counts(), direct.level_face_counts());
        assert!(h.coarsest_level() >= 2);
        // The document stays the input, bit for bit.
        assert_eq!(ctx.mesh().positions(), input.positions());
        // Level changes and undo work on the hierarchy from the thread.
        let coarsest = h.coarsest_level();
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
        let mut fixture = Fixture::new(generators::icosphere(2));
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new(SharedLabels::default());
        // Out of range (the panel and scripts refuse it; the field is public).
        tool.max_normal_deviation = 200.0;
        tool.start_build(&mut ctx).unwrap();
        match poll_until_idle(&mut tool, &mut ctx) {
            Background::Failed(e) => assert!(e.0.contains("max_normal_deviation"), "{e}"),
            other => panic!("expected a failure, got {other:?}"),
        }
        assert!(ctx.status.is_error);
        assert!(ctx.status.message.starts_with("Build failed"));
        assert!(tool.hierarchy().is_none() && !tool.is_building());
        assert_eq!(ctx.doc.undo_len(), 0);
    }

    #[test]
    fn a_mesh_changed_during_the_build_refuses_the_result() {
        let mut fixture = Fixture::new(generators::icosphere(2));
        let mut ctx = fixture.ctx();
        let mut tool = Multires::new(SharedLabels::default());
        tool.target_faces = 40;
        tool.start_build(&mut ctx).unwrap();
        ctx.positions_mut()[0] += DVec3::X;
        ctx.doc.end_edit();
        assert!(matches!(
            poll_until_idle(&mut tool, &mut ctx),
            Background::Failed(_)
        ));
        assert!(tool.hierarchy().is_none());
    }

    #[test]
    fn progress_fraction_counts_the_faces_removed_towards_the_target() {
        assert_eq!(build_fraction(1000, 100, 1000), 0.0);
        assert_eq!(build_fraction(1000, 100, 550), 0.5);
        assert_eq!(build_fraction(1000, 100, 100), 1.0);
        assert_eq!(build_fraction(1000, 100, 50), 1.0);
        assert_eq!(build_fraction(50, 100, 50), 1.0);
    }

    #[test]
    fn fingerprints_tell_connectivity_apart() {
        let a = generators::icosphere(2);
        let mut b = a.clone();
        b.positions_mut()[0] += DVec3::X;
        assert_eq!(connectivity_fingerprint(&a), connectivity_fingerprint(&b));
        let c = generators::icosphere(1);
        assert_ne!(connectivity_fingerprint(&a), connectivity_fingerprint(&c));
        let mut h =
            Hierarchy::build(a.clone(), &HierarchyOptions::rounds().with_target_faces(80)).unwrap();
        assert_ne!(
            connectivity_fingerprint(h.mesh()),
            connectivity_fingerprint(&a)
        );
        h.go_to_level(0).unwrap();
        assert_eq!(
            connectivity_fingerprint(h.mesh()),
            connectivity_fingerprint(&a)
        );
    }
}
