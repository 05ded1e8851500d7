//! *Bendels–Klein* — Bendels & Klein, *Image and 3D-object editing with precisely
//! specified editing regions* (`edit::bendels_klein`): the user gives a
//! **handle** and a **fixed** region (Sec. 2), either by their borders — closed loops
//! through clicked vertices, joined by shortest edge paths — or by painting vertices
//! with a brush of radius `r`; every other vertex is deformable. The distance of each
//! deformable vertex to both borders (geodesic by fast marching, or Euclidean; Sec. 4)
//! gives the blend weight `α = f(d_fixed / (d_fixed + d_handle))` with the shape function
//! `f` (Sec. 5, edited in a curve editor), shown as a colour map. The handle transform
//! `A` (translate, rotate about an axis through the handle's centroid, scale) is applied
//! live as the fields change: each vertex moves to `exp(α log A) p` (Sec. 3, after Alexa
//! 2002), the handle to `A p`, the fixed region never moves. Dragging the handle in the
//! view plane translates it. Adaptive refinement (Sec. 6) splits stretched edges. On the
//! mesh of a multiresolution hierarchy (at any level) it is made at the hierarchy's input
//! (`BlendSession::refine_in_hierarchy`): the hierarchy is built again and stays the
//! document's, at its level; the regions are then given again.
//!
//! One change gesture (a drag of a field, of the handle or of a curve point) is one undo
//! step. After undo / redo the restored surface becomes the new rest state and the
//! transform restarts at the identity.

use std::time::Instant;

use edit::bendels_klein::{BlendOptions, BlendSession, DistanceKind, RefineOptions, Regions, Role};
use edit::HierarchyEdit;
use glam::{DMat4, DVec3};
use halfedge::{Mesh, VertexId};
use three_d::egui;

use super::recipe_steps;
use crate::recipe_log::RecordId;

use super::curve_editor::{CurveEditor, Preset};
use super::edit_support::{
    ball_vertices, copy_positions, diagonal, ms, vec3_param, vertex_list_param, vertex_param,
    Scratch,
};
use super::params::{self, Param, Widget};
use super::{
    bool_param, choice_name, choice_param, number_param, string_param, Drag, DragPhase, Overlay,
    Pick, Tool, ToolContext, ToolError,
};
use crate::colors::{Colormap, Rgba, NO_LABEL};

mod parameters;
mod refine;
#[cfg(test)]
mod tests;

use parameters::*;

/// What a click on the mesh does in the Bendels–Klein tool.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BkMode {
    /// Adds a vertex to the handle's border loop.
    #[default]
    HandleLoop,
    /// Adds a vertex to the fixed region's border loop.
    FixedLoop,
    /// Paints the handle with the brush.
    PaintHandle,
    /// Paints the fixed region with the brush.
    PaintFixed,
    /// Erases painted vertices with the brush.
    Erase,
    /// A press on the handle drags it (a translation in the view plane).
    Drag,
}

impl BkMode {
    const ALL: [(BkMode, &'static str, &'static str); 6] = [
        (BkMode::HandleLoop, "handle_loop", "handle loop"),
        (BkMode::FixedLoop, "fixed_loop", "fixed loop"),
        (BkMode::PaintHandle, "paint_handle", "paint handle"),
        (BkMode::PaintFixed, "paint_fixed", "paint fixed"),
        (BkMode::Erase, "erase", "erase"),
        (BkMode::Drag, "drag", "drag handle"),
    ];

    fn key(self) -> &'static str {
        Self::ALL.iter().find(|m| m.0 == self).expect("listed").1
    }

    fn parse(s: &str) -> Option<Self> {
        Self::ALL.iter().find(|m| m.1 == s).map(|m| m.0)
    }
}

/// How the regions were given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RegionSource {
    Loops,
    Painted,
}

const PAINT_NONE: u8 = 0;
const PAINT_HANDLE: u8 = 1;
const PAINT_FIXED: u8 = 2;
const HANDLE_COLOR: Rgba = [255, 120, 20, 255];
const FIXED_COLOR: Rgba = [40, 140, 255, 255];

/// Bendels & Klein editing with precisely specified regions (see the module docs).
#[derive(Clone)]
pub struct BendelsKlein {
    /// What a click does.
    pub mode: BkMode,
    /// Brush radius as a fraction of the bounding-box diagonal.
    pub brush: f64,
    /// Geodesic (true) or Euclidean distances.
    pub geodesic: bool,
    /// The shape function and its editor.
    pub curve: CurveEditor,
    /// Translation of the handle (world units).
    pub translate: DVec3,
    /// Rotation axis (through the handle's centroid).
    pub axis: DVec3,
    /// Rotation angle, degrees.
    pub angle: f64,
    /// Uniform scale about the handle's centroid.
    pub scale: f64,
    /// Refinement threshold, a multiple of the mesh's mean edge length (on a hierarchy's
    /// mesh: of the full-resolution mesh's, estimated from the level shown).
    pub refine_threshold: f64,
    handle_picks: Vec<VertexId>,
    fixed_picks: Vec<VertexId>,
    paint: Vec<u8>,
    source: Option<RegionSource>,
    regions: Option<Regions>,
    session: Option<BlendSession>,
    /// The session must be rebuilt on the current surface (after undo / redo).
    stale: bool,
    pivot: DVec3,
    scratch: Scratch,
    drag_base: DVec3,
    /// The recipe entry of the session's edit: each new transform replaces it (the
    /// session applies every transform to the same rest positions).
    recorded: Option<RecordId>,
}

impl Default for BendelsKlein {
    fn default() -> Self {
        Self {
            mode: BkMode::HandleLoop,
            brush: 0.04,
            geodesic: true,
            curve: CurveEditor::default(),
            translate: DVec3::ZERO,
            axis: DVec3::Z,
            angle: 0.0,
            scale: 1.0,
            refine_threshold: 2.0,
            handle_picks: Vec::new(),
            fixed_picks: Vec::new(),
            paint: Vec::new(),
            source: None,
            regions: None,
            session: None,
            stale: false,
            pivot: DVec3::ZERO,
            scratch: Scratch::default(),
            drag_base: DVec3::ZERO,
            recorded: None,
        }
    }
}

impl BendelsKlein {
    /// The handle transform `A = T(c + t) · R(axis, angle) · S(scale) · T(−c)` about the
    /// handle's centroid `c`.
    pub fn transform(&self) -> DMat4 {
        let rotation = match self.axis.try_normalize() {
            Some(axis) if self.angle != 0.0 => {
                DMat4::from_axis_angle(axis, self.angle.to_radians())
            }
            _ => DMat4::IDENTITY,
        };
        DMat4::from_translation(self.pivot + self.translate)
            * rotation
            * DMat4::from_scale(DVec3::splat(self.scale))
            * DMat4::from_translation(-self.pivot)
    }

    fn reset_transform(&mut self) {
        self.translate = DVec3::ZERO;
        self.angle = 0.0;
        self.scale = 1.0;
    }

    fn options(&self) -> BlendOptions {
        BlendOptions::default()
            .with_distance(if self.geodesic {
                DistanceKind::Geodesic
            } else {
                DistanceKind::Euclidean
            })
            .with_shape(self.curve.model.shape())
    }

    /// Builds the regions from their source (when complete) and a session on the
    /// current surface; the transform restarts at the identity.
    fn build(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.session = None;
        self.regions = None;
        self.stale = false;
        let mesh = ctx.doc.mesh();
        let start = Instant::now();
        let regions = match self.source {
            Some(RegionSource::Loops)
                if self.handle_picks.len() >= 3 && self.fixed_picks.len() >= 3 =>
            {
                Regions::from_picks(mesh, &self.handle_picks, &self.fixed_picks)?
            }
            Some(RegionSource::Painted) => {
                let (handle, fixed) = self.painted_sets(mesh);
                if handle.is_empty() || fixed.is_empty() {
                    self.show(ctx);
                    return Ok(());
                }
                Regions::from_sets(mesh, &handle, &fixed)?
            }
            _ => {
                self.show(ctx);
                return Ok(());
            }
        };
        let t_regions = start.elapsed();
        self.regions = Some(regions.clone());
        self.start_session(ctx, regions)?;
        let s = self.session.as_ref().expect("started");
        let r = s.regions();
        let message = format!(
            "Bendels–Klein: handle {}, deformable {}, fixed {} vertices (regions in {}), \
             {} distances in {}",
            r.handle().len(),
            r.deformable().len(),
            r.n_fixed(),
            ms(t_regions),
            if self.geodesic {
                "geodesic"
            } else {
                "Euclidean"
            },
            ms(start.elapsed() - t_regions)
        );
        ctx.info(message);
        Ok(())
    }

    fn start_session(
        &mut self,
        ctx: &mut ToolContext<'_>,
        regions: Regions,
    ) -> Result<(), ToolError> {
        // Made on the document's mesh (a session is bound to its mesh: see
        // `halfedge::Binding`): it applies to the scratch copy made since and marks
        // the document's hierarchy (see `apply_transform`).
        let options = self.options();
        self.scratch.sync(ctx.doc);
        let mesh = ctx.doc.mesh();
        let session = BlendSession::new(mesh, regions, options)?;
        let handle = session.regions().handle();
        self.pivot =
            handle.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / handle.len().max(1) as f64;
        self.session = Some(session);
        self.stale = false;
        self.recorded = None;
        self.reset_transform();
        self.show(ctx);
        Ok(())
    }

    /// Rebuilds the session on the current surface if undo / redo made it stale.
    fn ensure_session(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        if self.stale {
            self.stale = false;
            match self.regions.clone() {
                Some(r) if r.roles().len() == ctx.mesh().vertex_slots() => {
                    self.start_session(ctx, r)?
                }
                _ => self.build(ctx)?,
            }
        }
        Ok(())
    }

    fn painted_sets(&self, mesh: &Mesh) -> (Vec<VertexId>, Vec<VertexId>) {
        let mut handle = Vec::new();
        let mut fixed = Vec::new();
        for (i, &p) in self.paint.iter().enumerate() {
            if let Some(v) = mesh.vertex_at(i) {
                match p {
                    PAINT_HANDLE => handle.push(v),
                    PAINT_FIXED => fixed.push(v),
                    _ => {}
                }
            }
        }
        (handle, fixed)
    }

    /// Paints the brush ball around `v` with `value`.
    fn paint_at(
        &mut self,
        ctx: &mut ToolContext<'_>,
        v: VertexId,
        value: u8,
    ) -> Result<(), ToolError> {
        let mesh = ctx.mesh();
        self.paint.resize(mesh.vertex_slots(), PAINT_NONE);
        let ball = ball_vertices(mesh, v, self.brush * diagonal(mesh));
        for w in ball {
            self.paint[mesh.vertex_index(w)] = value;
        }
        self.source = Some(RegionSource::Painted);
        self.build(ctx)
    }

    /// Colours the mesh: α with a colour bar when a session exists (the fixed region in
    /// the base colour), else the painted regions as labels.
    fn show(&self, ctx: &mut ToolContext<'_>) {
        let mesh = ctx.mesh();
        if let Some(s) = &self.session {
            if s.alpha().len() == mesh.vertex_slots() {
                let roles = s.regions().roles();
                let values = (0..mesh.vertex_slots())
                    .map(|i| {
                        if mesh.vertex_at(i).is_none() || roles[i] == Role::Fixed {
                            f64::NAN
                        } else {
                            s.alpha()[i]
                        }
                    })
                    .collect();
                ctx.show_scalar(
                    "α = f(d_fixed / (d_fixed + d_handle))",
                    values,
                    Colormap::Viridis,
                );
                return;
            }
        }
        if self.paint.contains(&PAINT_HANDLE) || self.paint.contains(&PAINT_FIXED) {
            let labels = (0..mesh.vertex_slots())
                .map(|i| match self.paint.get(i) {
                    Some(&PAINT_HANDLE) => 0,
                    Some(&PAINT_FIXED) => 1,
                    _ => NO_LABEL,
                })
                .collect();
            ctx.show_vertex_labels(
                "painted regions",
                labels,
                vec![(0, "handle".into()), (1, "fixed".into())],
            );
        } else {
            ctx.clear_colors();
        }
    }

    /// Applies the current transform live (inside the open undo step).
    fn apply_transform(&mut self, ctx: &mut ToolContext<'_>, label: &str) -> Result<(), ToolError> {
        self.ensure_session(ctx)?;
        let a = self.transform();
        let Some(session) = &mut self.session else {
            return Err(ToolError::new(
                "Bendels–Klein: give a handle and a fixed region first",
            ));
        };
        let start = Instant::now();
        let scratch = self.scratch.sync(ctx.doc);
        session.apply(scratch, a)?;
        let t = start.elapsed();
        let roles = session.regions().roles();
        let slots: Vec<usize> = (0..roles.len())
            .filter(|&i| roles[i] != Role::Fixed)
            .collect();
        let n = slots.len();
        copy_positions(ctx, label, self.scratch.mesh(), slots.into_iter());
        // At a coarse level of a hierarchy the handle's transform and the moved region are
        // marked: refining lands the handle exactly and keeps the fixed region still.
        ctx.doc.mark_hierarchy(|h| session.mark(h))?;
        self.record(ctx);
        ctx.info(format!(
            "Bendels–Klein: handle transform applied to {n} vertices (exp(α log A)) in {}",
            ms(t)
        ));
        Ok(())
    }

    /// The shape function changed: new α, and the mesh follows.
    fn shape_changed(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.ensure_session(ctx)?;
        let shape = self.curve.model.shape();
        if let Some(session) = &mut self.session {
            let start = Instant::now();
            session.set_shape(shape);
            let scratch = self.scratch.sync(ctx.doc);
            session.reapply(scratch)?;
            let t = start.elapsed();
            let roles = session.regions().roles();
            let slots: Vec<usize> = (0..roles.len())
                .filter(|&i| roles[i] != Role::Fixed)
                .collect();
            if self.transform() != DMat4::IDENTITY {
                copy_positions(
                    ctx,
                    "Bendels–Klein shape",
                    self.scratch.mesh(),
                    slots.into_iter(),
                );
                self.record(ctx);
            }
            ctx.info(format!(
                "Bendels–Klein: shape function {} (α and mesh updated in {})",
                self.curve.model.preset().key(),
                ms(t)
            ));
        }
        self.show(ctx);
        Ok(())
    }

    /// Records the session's edit as a recipe step (replacing the step of this session's
    /// previous transform).
    fn record(&mut self, ctx: &mut ToolContext<'_>) {
        let Some(session) = &self.session else {
            return;
        };
        let distance = if self.geodesic {
            DistanceKind::Geodesic
        } else {
            DistanceKind::Euclidean
        };
        let step = recipe_steps::level(ctx).and_then(|level| {
            recipe_steps::blend(
                ctx.mesh(),
                level,
                session.regions(),
                self.transform(),
                distance,
                &self.curve.model.shape(),
            )
        });
        let step = step.map_err(|why| format!("Bendels–Klein transform ({why})"));
        self.recorded = Some(ctx.doc.record_step(self.recorded, step));
    }

    fn clear(&mut self, ctx: &mut ToolContext<'_>) {
        self.handle_picks.clear();
        self.fixed_picks.clear();
        self.paint.clear();
        self.source = None;
        self.regions = None;
        self.session = None;
        self.reset_transform();
        ctx.clear_colors();
    }

    fn report(ctx: &mut ToolContext<'_>, result: Result<(), ToolError>) {
        if let Err(e) = result {
            ctx.error(format!("Bendels–Klein: {e}"));
        }
    }

    fn is_handle(&self, mesh: &Mesh, v: VertexId) -> bool {
        self.session
            .as_ref()
            .is_some_and(|s| s.regions().roles().get(mesh.vertex_index(v)) == Some(&Role::Handle))
    }
}

/// The parameters of [`BendelsKlein`] (see [`params`]). The curve editor draws the
/// shape's widgets; the editing method checks the values.
const PARAMS: &[Param<BendelsKlein>] = &[
    Param::new(
        "mode",
        "Click:",
        Widget::Choice(|| BkMode::ALL.iter().map(|m| m.1).collect()),
        |t| t.mode.key().into(),
        |t, v, _| {
            let s = string_param("mode", v)?;
            t.mode = BkMode::parse(s).ok_or_else(|| {
                ToolError::bad_value(
                    "mode",
                    "handle_loop, fixed_loop, paint_handle, paint_fixed, erase or drag",
                    v,
                )
            })?;
            Ok(())
        },
    ),
    Param::new(
        "brush",
        "brush radius (of the diagonal)",
        params::log_slider(0.005, 0.3),
        |t| t.brush.into(),
        |t, v, _| {
            t.brush = number_param("brush", v)?;
            Ok(())
        },
    ),
    Param::new(
        "distance",
        "Distance:",
        Widget::Choice(|| params::names(&DISTANCES)),
        |t| choice_name(&DISTANCES, t.geodesic).into(),
        |t, v, ctx| {
            t.geodesic = choice_param(&DISTANCES, "distance", v)?;
            t.rebuild_keep_transform(ctx)
        },
    ),
    Param::new(
        "shape",
        "shape",
        Widget::None,
        |t| t.curve.model.preset().key().into(),
        |t, v, ctx| {
            let s = string_param("shape", v)?;
            let preset = Preset::parse(s)
                .ok_or_else(|| ToolError::bad_value("shape", "linear, c1, c2 or curve", v))?;
            t.curve.model.set_preset(preset);
            t.shape_changed(ctx)
        },
    ),
    Param::new(
        "curve_points",
        "curve points",
        Widget::None,
        |t| {
            let points: Vec<serde_json::Value> = t
                .curve
                .model
                .points()
                .iter()
                .map(|&(x, y)| serde_json::json!([x, y]))
                .collect();
            points.into()
        },
        |t, v, ctx| {
            let bad = || ToolError::bad_value("curve_points", "[[x, y], ...]", v);
            let list = v.as_array().ok_or_else(bad)?;
            let mut points = Vec::with_capacity(list.len());
            for p in list {
                let xy = p.as_array().filter(|a| a.len() == 2).ok_or_else(bad)?;
                let x = xy[0].as_f64().ok_or_else(bad)?;
                let y = xy[1].as_f64().ok_or_else(bad)?;
                points.push((x, y));
            }
            t.curve.model.set_points(points).map_err(ToolError::new)?;
            t.shape_changed(ctx)
        },
    ),
    Param::new(
        "monotone",
        "monotone",
        Widget::None,
        |t| t.curve.model.monotone().into(),
        |t, v, ctx| {
            t.curve.model.set_monotone(bool_param("monotone", v)?);
            t.shape_changed(ctx)
        },
    ),
    Param::new(
        "translate",
        "translate",
        Widget::Vector {
            speed: 0.004,
            relative: true,
        },
        |t| t.translate.to_array().to_vec().into(),
        |t, v, ctx| {
            transform_param(t, ctx, |t| {
                t.translate = vec3_param("translate", v)?;
                Ok(())
            })
        },
    ),
    Param::new(
        "axis",
        "axis",
        Widget::Vector {
            speed: 0.01,
            relative: false,
        },
        |t| t.axis.to_array().to_vec().into(),
        |t, v, ctx| {
            transform_param(t, ctx, |t| {
                t.axis = vec3_param("axis", v)?;
                Ok(())
            })
        },
    ),
    Param::new(
        "angle",
        "angle (°)",
        params::drag(-179.0, 179.0, 0.5),
        |t| t.angle.into(),
        |t, v, ctx| {
            transform_param(t, ctx, |t| {
                t.angle = number_param("angle", v)?;
                Ok(())
            })
        },
    ),
    Param::new(
        "scale",
        "scale ×",
        params::drag(0.05, 20.0, 0.005),
        |t| t.scale.into(),
        |t, v, ctx| {
            transform_param(t, ctx, |t| {
                t.scale = number_param("scale", v)?;
                Ok(())
            })
        },
    ),
    Param::new(
        "refine_threshold",
        "refine edges longer than × mean",
        params::drag(0.5, 20.0, 0.05),
        |t| t.refine_threshold.into(),
        |t, v, _| {
            t.refine_threshold = number_param("refine_threshold", v)?;
            Ok(())
        },
    ),
    Param::script("handle_loop", None, |t, v, ctx| {
        loop_param(t, "handle_loop", v, ctx)
    }),
    Param::script("fixed_loop", None, |t, v, ctx| {
        loop_param(t, "fixed_loop", v, ctx)
    }),
    Param::script("paint_handle", None, |t, v, ctx| {
        paint_param(t, "paint_handle", v, ctx)
    }),
    Param::script("paint_fixed", None, |t, v, ctx| {
        paint_param(t, "paint_fixed", v, ctx)
    }),
    Param::script("erase", None, |t, v, ctx| paint_param(t, "erase", v, ctx)),
    Param::action("clear", "Clear regions", |t, v, ctx| {
        if bool_param("clear", v)? {
            t.clear(ctx);
        }
        Ok(())
    }),
    Param::info("pivot", |t| t.pivot.to_array().to_vec().into()),
];

impl Tool for BendelsKlein {
    fn name(&self) -> &str {
        "Bendels–Klein"
    }

    fn description(&self) -> &str {
        "Bendels & Klein, precisely specified editing regions: handle and fixed region \
         (loops or brush), blend weight α = f(distance ratio), handle transform A; the \
         rest moves by exp(α log A)."
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>) {
        params::widget(ui, PARAMS, "mode", self, ctx);
        params::widget(ui, PARAMS, "brush", self, ctx);
        ui.horizontal(|ui| {
            ui.label(format!(
                "loops: handle {}, fixed {} picks",
                self.handle_picks.len(),
                self.fixed_picks.len()
            ));
            params::widget(ui, PARAMS, "clear", self, ctx);
        });
        match &self.session {
            Some(s) => {
                let r = s.regions();
                ui.label(format!(
                    "handle {} · deformable {} · fixed {}",
                    r.handle().len(),
                    r.deformable().len(),
                    r.n_fixed()
                ));
            }
            None => {
                ui.weak("Give a handle and a fixed region (3 loop picks each, or paint).");
            }
        }
        params::widget(ui, PARAMS, "distance", self, ctx);
        ui.separator();
        if self.curve.ui(ui) {
            let result = self.shape_changed(ctx);
            Self::report(ctx, result);
        }
        ui.separator();
        for name in ["translate", "axis", "angle", "scale"] {
            params::widget(ui, PARAMS, name, self, ctx);
        }
        if ui.button("Reset transform").clicked() && self.session.is_some() {
            self.reset_transform();
            let result = self.apply_transform(ctx, "Bendels–Klein reset");
            Self::report(ctx, result);
        }
        ui.separator();
        ui.horizontal(|ui| {
            params::widget(ui, PARAMS, "refine_threshold", self, ctx);
            if ui
                .add_enabled(self.session.is_some(), egui::Button::new("Refine"))
                .on_hover_text(
                    "Adaptive refinement (Sec. 6): split stretched edges (on a hierarchy: at \
                     its input, and the hierarchy is built again)",
                )
                .clicked()
            {
                let result = self.refine(ctx);
                Self::report(ctx, result);
            }
        });
    }

    fn on_pick(&mut self, pick: Option<&Pick>, ctx: &mut ToolContext<'_>) {
        let Some(pick) = pick else {
            return;
        };
        let v = pick.vertex;
        let result = match self.mode {
            BkMode::HandleLoop | BkMode::FixedLoop => {
                let list = if self.mode == BkMode::HandleLoop {
                    &mut self.handle_picks
                } else {
                    &mut self.fixed_picks
                };
                if list.last() == Some(&v) {
                    return;
                }
                list.push(v);
                self.source = Some(RegionSource::Loops);
                self.build(ctx)
            }
            BkMode::PaintHandle => self.paint_at(ctx, v, PAINT_HANDLE),
            BkMode::PaintFixed => self.paint_at(ctx, v, PAINT_FIXED),
            BkMode::Erase => self.paint_at(ctx, v, PAINT_NONE),
            BkMode::Drag => Ok(()),
        };
        Self::report(ctx, result);
    }

    fn wants_drag(&self, pick: &Pick) -> bool {
        self.mode == BkMode::Drag && self.session.is_some() && {
            // The roles are by slot; `pick.vertex` is live (the viewer just picked it).
            self.session
                .as_ref()
                .is_some_and(|s| s.regions().handle().contains(&pick.vertex))
        }
    }

    fn on_drag(&mut self, drag: &Drag, ctx: &mut ToolContext<'_>) {
        let result = match drag.phase {
            DragPhase::Start => {
                self.drag_base = self.translate;
                Ok(())
            }
            DragPhase::Move | DragPhase::End => {
                if !drag
                    .pick
                    .is_some_and(|p| self.is_handle(ctx.mesh(), p.vertex))
                {
                    return;
                }
                let t = self.drag_base + drag.delta();
                if t == self.translate {
                    Ok(())
                } else {
                    self.translate = t;
                    self.apply_transform(ctx, "Bendels–Klein drag")
                }
            }
        };
        Self::report(ctx, result);
    }

    fn apply(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.refine(ctx)
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
        let live = |v: VertexId| mesh.is_valid_vertex(v);
        for (picks, color) in [
            (&self.handle_picks, HANDLE_COLOR),
            (&self.fixed_picks, FIXED_COLOR),
        ] {
            for &v in picks.iter().filter(|&&v| live(v)) {
                overlay.marker(mesh.position(v), color, 1.2);
            }
        }
        match &self.session {
            Some(s) if s.regions().roles().len() == mesh.vertex_slots() => {
                for (border, color) in [
                    (s.regions().handle_border(), HANDLE_COLOR),
                    (s.regions().fixed_border(), FIXED_COLOR),
                ] {
                    for &(a, b) in &border.edges {
                        if a != b && live(a) && live(b) {
                            overlay.segment(mesh.position(a), mesh.position(b), color);
                        }
                    }
                }
            }
            _ => {
                for (picks, color) in [
                    (&self.handle_picks, HANDLE_COLOR),
                    (&self.fixed_picks, FIXED_COLOR),
                ] {
                    for w in picks.windows(2) {
                        if live(w[0]) && live(w[1]) {
                            overlay.segment(mesh.position(w[0]), mesh.position(w[1]), color);
                        }
                    }
                }
            }
        }
    }

    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        self.scratch.clear();
        self.handle_picks.retain(|&v| mesh.is_valid_vertex(v));
        self.fixed_picks.retain(|&v| mesh.is_valid_vertex(v));
        self.paint.resize(mesh.vertex_slots(), PAINT_NONE);
        self.recorded = None;
        if self.session.is_some() {
            // Rebuilt on the restored surface at the next use; the transform restarts.
            self.stale = true;
            self.reset_transform();
        }
    }

    fn activate(&mut self, ctx: &mut ToolContext<'_>) {
        if self.session.is_some() {
            // Another tool may have changed the surface meanwhile.
            self.stale = true;
            let result = self.ensure_session(ctx);
            Self::report(ctx, result);
        }
        self.show(ctx);
    }
}

impl BendelsKlein {
    /// A new distance kind: new fields on the current regions, the transform re-applied
    /// from the session's rest state.
    fn rebuild_keep_transform(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        let Some(session) = &self.session else {
            return Ok(());
        };
        let start = Instant::now();
        let regions = session.regions().clone();
        let original = session.original_positions().to_vec();
        let options = self.options();
        // On the scratch mesh the session is applied to, put back at the rest state.
        let rest = self.scratch.sync(ctx.doc);
        if original.len() == rest.vertex_slots() {
            rest.positions_mut().copy_from_slice(&original);
        }
        let (translate, angle, scale) = (self.translate, self.angle, self.scale);
        let new = BlendSession::new(rest, regions, options)?;
        self.session = Some(new);
        self.translate = translate;
        self.angle = angle;
        self.scale = scale;
        let t = start.elapsed();
        if self.transform() != DMat4::IDENTITY {
            self.apply_transform(ctx, "Bendels–Klein distance")?;
        }
        self.show(ctx);
        ctx.info(format!(
            "Bendels–Klein: {} distances in {}",
            if self.geodesic {
                "geodesic"
            } else {
                "Euclidean"
            },
            ms(t)
        ));
        Ok(())
    }
}
