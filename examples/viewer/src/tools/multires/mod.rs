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
use multires::recipe::HierarchySpec;
use three_d::egui;

use super::params::{self, Param, Widget};
use super::{
    bool_param, choice_name, choice_param, number_param, Background, Overlay, Pick, Tool,
    ToolContext, ToolError, ViewInfo,
};
use crate::colors::{ColorLayer, LabelField, LabelTarget, Rgba, NO_LABEL};
use crate::document::Revision;
use crate::format::group;

mod build;
mod labels;
#[cfg(test)]
mod tests;

use build::*;
use labels::*;
pub use labels::{
    frontier_overlay, refreshed_label_layer, FrontierMode, PlaneNormal, SubMeshLabels, HOST,
    LABEL_LAYER, SUBMESH,
};

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
}

impl Multires {
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
