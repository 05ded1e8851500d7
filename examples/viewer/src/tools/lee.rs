//! *Lee area editing* — Lee 1999, *Interactive multiresolution editing of arbitrary
//! meshes* (`edit::lee`): the user specifies an **editing area** (§3.2) by clicking
//! vertices that shortest edge paths join into a closed loop, or as a disk of radius `r`
//! around a clicked vertex; the area is embedded once onto a rectangle by a harmonic map
//! (§4). Then an **editing primitive** (one vertex or several, §3.3) is dragged in the
//! view plane: its displacements become offsets in the chosen **frames** (global or
//! normal-based, §3.4–3.5) and are spread over the area by multilevel B-spline
//! approximation with the continuous **scale** parameter `s` (§3.6, §5), live during
//! the drag. Vertices outside the area (and on its boundary) never move.
//!
//! A drag is one undo step; each drag starts a new edit from the current positions
//! (the session is committed), and the scale and frame controls re-shape the last drag
//! until the next one or an explicit *Commit* (the tool's `apply`).

use std::time::Instant;

use edit::lee::{AreaSession, AreaSide, EditingArea, FrameKind, SessionOptions};
use edit::HierarchyEdit;
use glam::DVec3;
use halfedge::{FaceId, Mesh, VertexId};
use multires::recipe::Step;
use three_d::egui;

use super::recipe_steps;
use crate::recipe_log::RecordId;

use super::edit_support::{
    ball_vertices, copy_positions, diagonal, ms, vertex_list_param, vertex_param, Scratch,
};
use super::params::{self, Param, Widget};
use super::{
    bool_param, choice_name, choice_param, number_param, string_param, Drag, DragPhase, Overlay,
    Pick, Tool, ToolContext, ToolError,
};
use crate::colors::NO_LABEL;

/// What a click on the mesh does in the Lee tool.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LeeMode {
    /// Adds a vertex to the boundary loop of the editing area (built from 3 picks on).
    #[default]
    Boundary,
    /// Makes the editing area a disk of the chosen radius around the clicked vertex.
    Disk,
    /// Adds the clicked vertex to the editing primitive.
    Primitive,
    /// A press on an interior vertex drags it (it becomes the primitive unless it is
    /// in it already).
    Drag,
}

impl LeeMode {
    const ALL: [(LeeMode, &'static str, &'static str); 4] = [
        (LeeMode::Boundary, "boundary", "boundary loop"),
        (LeeMode::Disk, "disk", "disk"),
        (LeeMode::Primitive, "primitive", "primitive"),
        (LeeMode::Drag, "drag", "drag"),
    ];

    fn key(self) -> &'static str {
        Self::ALL.iter().find(|m| m.0 == self).expect("listed").1
    }

    fn parse(s: &str) -> Option<Self> {
        Self::ALL.iter().find(|m| m.1 == s).map(|m| m.0)
    }
}

/// Where the current editing area came from.
#[derive(Clone, Copy, Debug, PartialEq)]
enum AreaSource {
    Loop,
    Disk(VertexId),
}

/// Colour of the editing area's boundary loop.
const BOUNDARY_COLOR: crate::colors::Rgba = [250, 210, 40, 255];

/// Lee 1999 area editing (see the module docs).
#[derive(Clone, Default)]
pub struct LeeAreaEdit {
    /// What a click does.
    pub mode: LeeMode,
    /// Disk radius as a fraction of the bounding-box diagonal.
    pub radius: f64,
    /// Scale parameter `s ∈ [0, 1]` (Lee 1999 §3.6).
    pub scale: f64,
    /// Normal-based local frames (Lee 1999 §3.5) instead of the global frame.
    pub normal_frames: bool,
    boundary_picks: Vec<VertexId>,
    source: Option<AreaSource>,
    primitive: Vec<VertexId>,
    session: Option<AreaSession>,
    scratch: Scratch,
    /// The last drag can still be re-shaped by the scale / frames.
    edit_active: bool,
    /// Updates during the current drag and their total time (for the status line).
    drag_updates: (usize, f64),
    /// The boundary picks the current area was made from (a loop), for its recipe step.
    area_picks: Option<Vec<VertexId>>,
    /// The last drag's vector and the recipe entry that records it (re-shaping the drag
    /// replaces that entry).
    recorded: Option<(DVec3, RecordId)>,
}

impl LeeAreaEdit {
    /// A tool with the default parameters (`s = 0.5`, disk radius 8 % of the diagonal).
    pub fn new() -> Self {
        Self {
            radius: 0.08,
            scale: 0.5,
            ..Self::default()
        }
    }

    fn options(&self) -> SessionOptions {
        SessionOptions::default()
            .with_scale(self.scale)
            .with_frames(self.frame_kind())
    }

    fn frame_kind(&self) -> FrameKind {
        if self.normal_frames {
            FrameKind::Normal {
                seed: None,
                x_axis: None,
            }
        } else {
            FrameKind::Global
        }
    }

    /// The editing area, if one is set.
    pub fn area(&self) -> Option<&EditingArea> {
        self.session.as_ref().map(AreaSession::area)
    }

    /// Builds the editing area from the current source and starts a session.
    fn build_area(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.session = None;
        self.edit_active = false;
        let start = Instant::now();
        let mesh = ctx.mesh();
        let area = match self.source {
            None => return Ok(()),
            Some(AreaSource::Loop) => {
                self.area_picks = Some(self.boundary_picks.clone());
                EditingArea::from_picks(mesh, &self.boundary_picks, AreaSide::Smaller)?
            }
            Some(AreaSource::Disk(seed)) => {
                self.area_picks = None;
                disk_area(mesh, seed, self.radius * diagonal(mesh))?
            }
        };
        let t_area = start.elapsed();
        let session = AreaSession::new(mesh, area, &self.options())?;
        let t_embed = start.elapsed() - t_area;
        let area = session.area();
        let message = format!(
            "Lee: editing area of {} vertices ({} interior, {} on the boundary) in {}, \
             harmonic map in {}, {} B-spline levels",
            area.vertices().len(),
            area.n_interior(),
            area.boundary().len(),
            ms(t_area),
            ms(t_embed),
            session.levels()
        );
        self.session = Some(session);
        self.primitive.retain(|&v| {
            self.session.as_ref().is_some_and(|s| {
                s.area()
                    .local_index(mesh, v)
                    .is_some_and(|i| i < s.area().n_interior())
            })
        });
        if !self.primitive.is_empty() {
            let primitive = self.primitive.clone();
            self.session
                .as_mut()
                .expect("set above")
                .set_primitive(ctx.mesh(), &primitive)?;
        }
        ctx.info(message);
        self.show(ctx);
        Ok(())
    }

    /// Colours the area (labels) — interior, boundary, primitive.
    fn show(&self, ctx: &mut ToolContext<'_>) {
        let Some(session) = &self.session else {
            ctx.clear_colors();
            return;
        };
        let mesh = ctx.mesh();
        let mut labels = vec![NO_LABEL; mesh.vertex_slots()];
        let area = session.area();
        for &v in area.interior() {
            labels[mesh.vertex_index(v)] = 0;
        }
        for &v in area.boundary() {
            labels[mesh.vertex_index(v)] = 1;
        }
        for &v in &self.primitive {
            labels[mesh.vertex_index(v)] = 2;
        }
        let legend = vec![
            (0, format!("editing area ({} interior)", area.n_interior())),
            (1, format!("area boundary ({})", area.boundary().len())),
            (2, format!("primitive ({})", self.primitive.len())),
        ];
        ctx.show_vertex_labels("Lee editing area", labels, legend);
    }

    fn is_interior(&self, mesh: &Mesh, v: VertexId) -> bool {
        self.session.as_ref().is_some_and(|s| {
            s.area()
                .local_index(mesh, v)
                .is_some_and(|i| i < s.area().n_interior())
        })
    }

    /// Sets the primitive (interior vertices of the area) and starts a new edit.
    fn set_primitive(
        &mut self,
        vertices: Vec<VertexId>,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        let session = self
            .session
            .as_mut()
            .ok_or_else(|| ToolError::new("Lee: make an editing area first"))?;
        if !vertices.is_empty() {
            session.set_primitive(ctx.doc.mesh(), &vertices)?;
        }
        self.primitive = vertices;
        self.edit_active = false;
        self.show(ctx);
        Ok(())
    }

    /// Re-shapes the current edit after a change of scale or frames (live, one undo
    /// step per slider gesture).
    fn reshape(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        let kind = self.frame_kind();
        let Some(session) = &mut self.session else {
            return Ok(());
        };
        session.set_scale(self.scale)?;
        let scratch = self.scratch.sync(ctx.doc);
        session.set_frames(scratch, kind)?;
        if !self.edit_active {
            return Ok(());
        }
        let start = Instant::now();
        session.apply(scratch)?;
        let t = start.elapsed();
        let slots: Vec<usize> = session
            .area()
            .interior()
            .iter()
            .map(|&v| scratch.vertex_index(v))
            .collect();
        copy_positions(
            ctx,
            "Lee scale / frames",
            self.scratch.mesh(),
            slots.into_iter(),
        );
        if let Some((delta, id)) = self.recorded {
            let step = self.recipe_step(ctx, delta);
            let id = ctx.doc.record_step(Some(id), step);
            self.recorded = Some((delta, id));
        }
        ctx.info(format!(
            "Lee: re-shaped the last drag at s = {:.3}, {} frames, in {}",
            self.scale,
            if self.normal_frames {
                "normal"
            } else {
                "global"
            },
            ms(t)
        ));
        Ok(())
    }

    /// Ends the current edit: the positions become the rest positions.
    fn commit(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        let session = self
            .session
            .as_mut()
            .ok_or_else(|| ToolError::new("Lee: no editing area to commit"))?;
        session.commit(ctx.doc.mesh())?;
        self.edit_active = false;
        ctx.info("Lee: committed; the next drag starts from the current surface");
        Ok(())
    }

    /// The recipe step of the current drag by `delta` (`Err`: what the edit was and why it
    /// has no exact step).
    fn recipe_step(&self, ctx: &ToolContext<'_>, delta: DVec3) -> Result<Step, String> {
        let refuse = |why: String| format!("Lee drag ({why})");
        let session = self
            .session
            .as_ref()
            .ok_or_else(|| refuse("no session".into()))?;
        let mesh = ctx.mesh();
        let area = recipe_steps::lee_area(mesh, session.area(), self.area_picks.as_deref())
            .map_err(|e| refuse(format!("an editing area the recipe cannot name: {e}")))?;
        let level = recipe_steps::level(ctx).map_err(refuse)?;
        let primitive = session
            .primitive()
            .into_iter()
            .map(|v| recipe_steps::place(mesh, v))
            .collect();
        Ok(recipe_steps::lee_drag(
            level,
            area,
            primitive,
            delta,
            self.scale,
            self.normal_frames,
        ))
    }

    fn clear(&mut self, ctx: &mut ToolContext<'_>) {
        self.boundary_picks.clear();
        self.source = None;
        self.primitive.clear();
        self.session = None;
        self.edit_active = false;
        ctx.clear_colors();
    }

    fn report(&self, ctx: &mut ToolContext<'_>, result: Result<(), ToolError>) {
        if let Err(e) = result {
            ctx.error(format!("Lee: {e}"));
        }
    }
}

/// The disk of radius `radius` around `seed`: the faces whose corners are all reachable
/// from the seed inside the Euclidean ball; when that is not a disk (a pocket, a handle),
/// the breadth-first rings around the seed with as many vertices.
fn disk_area(mesh: &Mesh, seed: VertexId, radius: f64) -> Result<EditingArea, ToolError> {
    let ball = ball_vertices(mesh, seed, radius);
    let mut inside = vec![false; mesh.vertex_slots()];
    for &v in &ball {
        inside[mesh.vertex_index(v)] = true;
    }
    let faces: Vec<FaceId> = mesh
        .faces()
        .filter(|&f| {
            mesh.triangle(f)
                .iter()
                .all(|&v| inside[mesh.vertex_index(v)])
        })
        .collect();
    match EditingArea::from_faces(mesh, &faces) {
        Ok(area) if area.n_interior() > 0 => Ok(area),
        _ => Ok(EditingArea::disk_around(mesh, seed, ball.len().max(7))?),
    }
}

/// The frame choices of the Lee tool: `(normal frames, script name)`.
const FRAMES: [(bool, &str); 2] = [(false, "global"), (true, "normal")];

/// The parameters of [`LeeAreaEdit`] (see [`params`]); the editing method checks the
/// values (the scale, the area).
const PARAMS: &[Param<LeeAreaEdit>] = &[
    Param::new(
        "mode",
        "Click:",
        Widget::Choice(|| LeeMode::ALL.iter().map(|m| m.1).collect()),
        |t| t.mode.key().into(),
        |t, v, _| {
            let s = string_param("mode", v)?;
            t.mode = LeeMode::parse(s).ok_or_else(|| {
                ToolError::bad_value("mode", "boundary, disk, primitive or drag", v)
            })?;
            Ok(())
        },
    ),
    Param::new(
        "radius",
        "disk radius (of the diagonal)",
        params::log_slider(0.01, 0.5),
        |t| t.radius.into(),
        |t, v, ctx| {
            t.radius = number_param("radius", v)?;
            if matches!(t.source, Some(AreaSource::Disk(_))) {
                t.build_area(ctx)?;
            }
            Ok(())
        },
    ),
    Param::new(
        "scale",
        "scale s",
        params::slider(0.0, 1.0),
        |t| t.scale.into(),
        |t, v, ctx| {
            t.scale = number_param("scale", v)?;
            t.reshape(ctx)
        },
    ),
    Param::new(
        "frames",
        "Frames:",
        Widget::Choice(|| params::names(&FRAMES)),
        |t| choice_name(&FRAMES, t.normal_frames).into(),
        |t, v, ctx| {
            // "local" is an old name of the normal frames.
            let local = v.as_str() == Some("local");
            t.normal_frames = local || choice_param(&FRAMES, "frames", v)?;
            t.reshape(ctx)
        },
    ),
    Param::script("boundary", None, |t, v, ctx| {
        let picks = vertex_list_param(ctx.mesh(), "boundary", v)?;
        if picks.len() < 3 {
            return Err(ToolError::new("boundary: at least 3 vertices"));
        }
        t.boundary_picks = picks;
        t.source = Some(AreaSource::Loop);
        t.build_area(ctx)
    }),
    Param::script("disk", None, |t, v, ctx| {
        let v = vertex_param(ctx.mesh(), "disk", v)?;
        t.source = Some(AreaSource::Disk(v));
        t.build_area(ctx)
    }),
    Param::script("primitive", None, |t, v, ctx| {
        let p = vertex_list_param(ctx.mesh(), "primitive", v)?;
        if let Some(&v) = p.iter().find(|&&v| !t.is_interior(ctx.mesh(), v)) {
            return Err(ToolError::new(format!(
                "primitive: vertex {} is not inside the editing area",
                ctx.mesh().vertex_index(v)
            )));
        }
        t.set_primitive(p, ctx)
    }),
    Param::action("clear", "Clear all", |t, v, ctx| {
        if bool_param("clear", v)? {
            t.clear(ctx);
        }
        Ok(())
    }),
    Param::info("boundary_picks", |t| t.boundary_picks.len().into()),
    Param::info("primitive_size", |t| t.primitive.len().into()),
    Param::info("area_vertices", |t| {
        t.area().map_or(0, |a| a.vertices().len()).into()
    }),
];

impl Tool for LeeAreaEdit {
    fn name(&self) -> &str {
        "Lee area editing"
    }

    fn description(&self) -> &str {
        "Lee 1999, Interactive multiresolution editing of arbitrary meshes: pick an editing \
         area (a loop of clicked vertices or a disk), pick a primitive, drag it; the edit \
         spreads over the area by multilevel B-splines at scale s."
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>) {
        params::widget(ui, PARAMS, "mode", self, ctx);
        match self.mode {
            LeeMode::Boundary => {
                ui.weak("Click vertices around the area; shortest paths join them into a loop (closed from 3 picks on).");
            }
            LeeMode::Disk => {
                ui.weak("Click the centre of a disk-shaped area.");
            }
            LeeMode::Primitive => {
                ui.weak("Click interior vertices to add them to the primitive; press on one and drag to move it.");
            }
            LeeMode::Drag => {
                ui.weak("Press on an interior vertex and drag it in the view plane.");
            }
        }
        params::widget(ui, PARAMS, "radius", self, ctx);
        ui.horizontal(|ui| {
            ui.label(format!("{} boundary picks", self.boundary_picks.len()));
            if ui.button("Undo pick").clicked() && self.boundary_picks.pop().is_some() {
                let result = if self.boundary_picks.len() >= 3 {
                    self.build_area(ctx)
                } else {
                    self.session = None;
                    self.show(ctx);
                    Ok(())
                };
                self.report(ctx, result);
            }
        });
        match &self.session {
            Some(s) => {
                ui.label(format!(
                    "Area: {} vertices ({} interior), {} B-spline levels",
                    s.area().vertices().len(),
                    s.area().n_interior(),
                    s.levels()
                ));
            }
            None => {
                ui.weak("No editing area yet.");
            }
        }
        ui.horizontal(|ui| {
            ui.label(format!("Primitive: {} vertices", self.primitive.len()));
            if ui.button("Clear primitive").clicked() {
                let result = self.set_primitive(Vec::new(), ctx);
                self.report(ctx, result);
            }
        });
        ui.separator();
        params::widget(ui, PARAMS, "scale", self, ctx);
        params::widget(ui, PARAMS, "frames", self, ctx);
        ui.horizontal(|ui| {
            if ui
                .add_enabled(self.session.is_some(), egui::Button::new("Commit"))
                .on_hover_text("End the edit: the current surface becomes the rest state")
                .clicked()
            {
                let result = self.commit(ctx);
                self.report(ctx, result);
            }
            params::widget(ui, PARAMS, "clear", self, ctx);
        });
    }

    fn on_pick(&mut self, pick: Option<&Pick>, ctx: &mut ToolContext<'_>) {
        let Some(pick) = pick else {
            return;
        };
        let v = pick.vertex;
        let result = match self.mode {
            LeeMode::Boundary => {
                if self.boundary_picks.last() == Some(&v) {
                    return;
                }
                self.boundary_picks.push(v);
                if self.boundary_picks.len() >= 3 {
                    self.source = Some(AreaSource::Loop);
                    self.build_area(ctx)
                } else {
                    ctx.info(format!(
                        "Lee: {} boundary pick(s); the loop closes from 3 on",
                        self.boundary_picks.len()
                    ));
                    Ok(())
                }
            }
            LeeMode::Disk => {
                self.source = Some(AreaSource::Disk(v));
                self.build_area(ctx)
            }
            LeeMode::Primitive => {
                if self.primitive.contains(&v) {
                    return;
                }
                if !self.is_interior(ctx.mesh(), v) {
                    Err(ToolError::new(
                        "the primitive must be inside the editing area (not on its boundary)",
                    ))
                } else {
                    let mut p = self.primitive.clone();
                    p.push(v);
                    self.set_primitive(p, ctx)
                }
            }
            LeeMode::Drag => Ok(()),
        };
        self.report(ctx, result);
    }

    fn wants_drag(&self, pick: &Pick) -> bool {
        // Only presses on the area's interior drag; elsewhere the press orbits.
        self.session.as_ref().is_some_and(|s| {
            self.primitive.contains(&pick.vertex)
                || (self.mode == LeeMode::Drag && s.area().interior().contains(&pick.vertex))
        })
    }

    fn on_drag(&mut self, drag: &Drag, ctx: &mut ToolContext<'_>) {
        let result = (|| -> Result<(), ToolError> {
            match drag.phase {
                DragPhase::Start => {
                    let v = drag.pick.map(|p| p.vertex);
                    let Some(v) = v.filter(|&v| self.is_interior(ctx.mesh(), v)) else {
                        return Err(ToolError::new(
                            "press on an interior vertex of the editing area to drag",
                        ));
                    };
                    // A session made afresh on the current surface (its embedding and
                    // levels computed there), as the recipe's replay of the drag makes it.
                    let area = self
                        .session
                        .as_ref()
                        .expect("checked by is_interior")
                        .area()
                        .clone();
                    self.session = Some(AreaSession::new(ctx.mesh(), area, &self.options())?);
                    self.recorded = None;
                    let scratch = self.scratch.sync(ctx.doc);
                    let session = self.session.as_mut().expect("set above");
                    if !self.primitive.contains(&v) {
                        self.primitive = vec![v];
                    }
                    // A new edit from the current surface.
                    session.set_primitive(scratch, &self.primitive)?;
                    self.edit_active = false;
                    self.drag_updates = (0, 0.0);
                    self.show(ctx);
                }
                DragPhase::Move | DragPhase::End => {
                    let Some(session) = &mut self.session else {
                        return Ok(());
                    };
                    if session.primitive().is_empty()
                        || !drag
                            .pick
                            .is_some_and(|p| self.primitive.contains(&p.vertex))
                    {
                        return Ok(());
                    }
                    let delta = drag.delta();
                    if delta != glam::DVec3::ZERO || self.edit_active {
                        let start = Instant::now();
                        let scratch = self.scratch.sync(ctx.doc);
                        session.drag(scratch, delta)?;
                        let t = start.elapsed();
                        self.drag_updates.0 += 1;
                        self.drag_updates.1 += t.as_secs_f64();
                        let slots: Vec<usize> = session
                            .area()
                            .interior()
                            .iter()
                            .map(|&v| scratch.vertex_index(v))
                            .collect();
                        copy_positions(ctx, "Lee drag", self.scratch.mesh(), slots.into_iter());
                        self.edit_active = true;
                    }
                    if drag.phase == DragPhase::End && self.edit_active {
                        // At a coarse level of a hierarchy the drag is one edit: its area
                        // and the primitive's translation are marked, so that refining
                        // lands the primitive and keeps the outside still.
                        ctx.doc.mark_hierarchy(|h| session.mark(h))?;
                        let step = self.recipe_step(ctx, delta);
                        self.recorded = Some((delta, ctx.doc.record_step(None, step)));
                        let session = self.session.as_ref().expect("dragged above");
                        let (n, total) = self.drag_updates;
                        ctx.info(format!(
                            "Lee drag: primitive of {} vertices moved by {:.4} over {} \
                             interior vertices at s = {:.2}; MBA fit + evaluation {:.1} ms \
                             per update ({n} updates)",
                            self.primitive.len(),
                            delta.length(),
                            session.area().n_interior(),
                            self.scale,
                            1e3 * total / n.max(1) as f64
                        ));
                    }
                }
            }
            Ok(())
        })();
        self.report(ctx, result);
    }

    fn apply(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.commit(ctx)
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
        for &v in &self.boundary_picks {
            if mesh.is_valid_vertex(v) {
                overlay.marker(mesh.position(v), Overlay::SECONDARY, 1.2);
            }
        }
        if let Some(AreaSource::Disk(v)) = self.source {
            if mesh.is_valid_vertex(v) {
                overlay.marker(mesh.position(v), Overlay::SECONDARY, 1.0);
            }
        }
        match &self.session {
            Some(s) if s.area().check_mesh(mesh).is_ok() => {
                let b = s.area().boundary();
                for k in 0..b.len() {
                    let (p, q) = (b[k], b[(k + 1) % b.len()]);
                    overlay.segment(mesh.position(p), mesh.position(q), BOUNDARY_COLOR);
                }
            }
            _ => {
                // Picks so far, joined straight (the loop is not closed yet).
                for w in self.boundary_picks.windows(2) {
                    if mesh.is_valid_vertex(w[0]) && mesh.is_valid_vertex(w[1]) {
                        overlay.segment(mesh.position(w[0]), mesh.position(w[1]), BOUNDARY_COLOR);
                    }
                }
            }
        }
        for &v in &self.primitive {
            if mesh.is_valid_vertex(v) {
                overlay.marker(mesh.position(v), Overlay::PICK, 1.6);
            }
        }
    }

    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        self.scratch.clear();
        self.edit_active = false;
        self.recorded = None;
        self.boundary_picks.retain(|&v| mesh.is_valid_vertex(v));
        self.primitive.retain(|&v| mesh.is_valid_vertex(v));
        if let Some(session) = &mut self.session {
            // Undo / redo: the restored surface becomes the rest state.
            if session.commit(mesh).is_err() {
                self.session = None;
            }
        }
        if self.session.is_none() {
            self.source = None;
        }
    }

    fn activate(&mut self, ctx: &mut ToolContext<'_>) {
        // Another tool may have moved the area's vertices meanwhile.
        if let Some(session) = &mut self.session {
            if session.commit(ctx.doc.mesh()).is_err() {
                self.session = None;
            }
        }
        self.edit_active = false;
        self.show(ctx);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::fixture::{drag_through, refine_and_land, Expect, Fixture, Landing};
    use crate::tools::Pick;
    use glam::DVec3;

    #[test]
    fn a_lee_drag_at_a_coarse_level_lands_its_primitive_and_keeps_the_outside() {
        // The tool marks the document's hierarchy when the drag ends: the primitive's fine
        // vertices land on the dragged target, the input vertices outside the area's
        // interior do not move, bit for bit.
        let level = 2;
        let mut fixture = Fixture::at_level(level);
        let input = fixture.input.clone();
        let mut ctx = fixture.ctx();
        let mesh = ctx.mesh();
        let top = mesh
            .vertices()
            .max_by(|&a, &b| mesh.position(a).z.total_cmp(&mesh.position(b).z))
            .unwrap();
        let start = mesh.position(top);
        let mut tool = LeeAreaEdit::new();
        tool.radius = 0.3;
        let index = serde_json::json!(mesh.vertex_index(top));
        tool.set_parameter("disk", &index, &mut ctx).unwrap();
        let interior: Vec<usize> = tool
            .area()
            .unwrap()
            .interior()
            .iter()
            .map(|&v| ctx.mesh().vertex_index(v))
            .collect();
        assert!(interior.len() > 10, "{} interior vertices", interior.len());
        let offset = DVec3::new(0.05, 0.0, 0.25);
        let pick = Pick {
            vertex: top,
            face: None,
            point: start,
        };
        drag_through(
            &mut tool,
            &mut ctx,
            Some(pick),
            start,
            offset,
            &[0.0, 0.6, 1.0],
        );
        ctx.doc.end_edit();
        let i_top = ctx.mesh().vertex_index(top);
        let Landing {
            landed: primitive,
            worst,
            ..
        } = refine_and_land(&mut ctx, &input, level, |a| {
            if a == i_top {
                Expect::Lands(glam::DAffine3::from_translation(offset))
            } else if interior.contains(&a) {
                Expect::Free
            } else {
                Expect::Stays
            }
        });
        assert!(
            primitive > 1,
            "{primitive} fine vertices in the primitive's cluster"
        );
        assert!(worst < 1e-9, "the primitive is {worst:e} off its target");
    }
}
