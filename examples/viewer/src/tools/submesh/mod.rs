//! *Sub-mesh edits* — the edits of *Interactive Editing of Multiresolution Meshes* §4.2–4.3
//! on a sub-mesh, with `n` propagation levels (collars of faces beyond the frontier over
//! which the edit fades), and Taubin's λ|μ smoothing (§4.2, Taubin 1995) of the sub-mesh
//! and its collar or of the whole mesh. The library side is [`edit::deform`] and
//! [`edit::deform`].
//!
//! The sub-mesh is the *Multiresolution* tool's labels (the sub-mesh and its frontier),
//! the vertices within a number of rings around a picked vertex, or the whole mesh.
//! *Pull* follows a drag in the view plane; *scale*, *rotate*, *taper*, *twist* and
//! *smooth* act on *Apply*. Scale is about the sub-mesh's centroid; rotate about the
//! axis through the frontier's centroid along the normal of the plane fitted to the
//! frontier (the view direction for a sub-mesh without frontier); taper and twist grow
//! level by level inward from the frontier (Fig. 10 a / 12 a), or along the view's up
//! axis over the whole mesh.

use std::collections::VecDeque;

use edit::deform::{
    Axis, Falloff, Propagation, Smoother, SmoothingWeights, SubMesh, SubmeshEdit, Variation,
};
use edit::HierarchyEdit;
use glam::DVec3;
use halfedge::{Mesh, VertexId};
use multires::recipe::{
    AxisSpec, Falloff as RecipeFalloff, Pull, Region, RotateStep, Scale, Smooth, Step, Taper,
    Twist, Variation as RecipeVariation,
};
use three_d::egui;

use super::recipe_steps;

use super::params::{self, Param, Widget};
use super::{
    bool_param, choice_name, choice_param, frontier_overlay, number_param, Drag, DragPhase,
    Overlay, Pick, SubMeshLabels, Tool, ToolContext, ToolError, ViewInfo,
};
use crate::colors::NO_LABEL;
use crate::format::group;

/// Where the sub-mesh comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The *Multiresolution* tool's labels.
    Labels,
    /// The rings around a picked vertex.
    Ring,
    /// The whole mesh.
    All,
}

/// The operation of the tool.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operation {
    /// Pull by a drag.
    Pull,
    /// Scale about the centroid.
    Scale,
    /// Rotate about the sub-mesh's axis.
    Rotate,
    /// Barr taper.
    Taper,
    /// Barr twist.
    Twist,
    /// Taubin smoothing.
    Smooth,
}

const SOURCES: [(Source, &str); 3] = [
    (Source::Labels, "labels"),
    (Source::Ring, "ring"),
    (Source::All, "all"),
];

const OPERATIONS: [(Operation, &str); 6] = [
    (Operation::Pull, "pull"),
    (Operation::Scale, "scale"),
    (Operation::Rotate, "rotate"),
    (Operation::Taper, "taper"),
    (Operation::Twist, "twist"),
    (Operation::Smooth, "smooth"),
];

/// A pull in progress.
struct PullDrag {
    sub: SubMesh,
    base: Vec<DVec3>,
    work: Mesh,
    touched: Vec<u32>,
}

/// The sub-mesh edit tool (see the module docs).
pub struct SubMeshEdit {
    /// Where the sub-mesh comes from.
    pub source: Source,
    /// Rings around the picked vertex (source `ring`).
    pub rings: usize,
    /// The operation.
    pub operation: Operation,
    /// Propagation levels `n`.
    pub levels: usize,
    /// Smooth (else linear) fall-off over the collars.
    pub smooth_falloff: bool,
    /// Scale factor.
    pub scale: f64,
    /// Rotation angle, degrees.
    pub angle: f64,
    /// Taper factor.
    pub taper: f64,
    /// Twist angle, degrees.
    pub twist: f64,
    /// Taubin λ.
    pub lambda: f64,
    /// Taubin μ.
    pub mu: f64,
    /// Taubin iterations.
    pub iterations: usize,
    /// Cotangent (else uniform) weights.
    pub cotangent: bool,
    /// Smooth the whole mesh (else the sub-mesh and its collar).
    pub smooth_whole: bool,
    /// Collar rings smoothed with the sub-mesh.
    pub smooth_collar: usize,
    centre: Option<VertexId>,
    drag: Option<PullDrag>,
    view: Option<ViewInfo>,
}

impl Default for SubMeshEdit {
    fn default() -> Self {
        Self::new()
    }
}

impl SubMeshEdit {
    /// The tool (it reads the sub-mesh labels from the mesh's label attribute).
    pub fn new() -> Self {
        Self {
            source: Source::Labels,
            rings: 4,
            operation: Operation::Pull,
            levels: 2,
            smooth_falloff: true,
            scale: 1.3,
            angle: 30.0,
            taper: 0.6,
            twist: 60.0,
            lambda: 0.33,
            mu: -0.34,
            iterations: 10,
            cotangent: false,
            smooth_whole: false,
            smooth_collar: 1,
            centre: None,
            drag: None,
            view: None,
        }
    }

    fn propagation(&self) -> Propagation {
        Propagation {
            levels: self.levels,
            falloff: if self.smooth_falloff {
                Falloff::Smooth
            } else {
                Falloff::Linear
            },
        }
    }

    /// The sub-mesh the tool acts on.
    pub fn submesh(&self, mesh: &Mesh) -> Result<SubMesh, ToolError> {
        let mask = match self.source {
            Source::Labels => SubMeshLabels::of(mesh)
                .ok_or_else(|| {
                    ToolError::new(
                        "no sub-mesh labels for this mesh: make a frontier with the \
                         Multiresolution tool, or choose the ring or all source",
                    )
                })?
                .inside_mask(),
            Source::Ring => {
                let centre = self
                    .centre
                    .filter(|&v| mesh.is_valid_vertex(v))
                    .ok_or_else(|| ToolError::new("pick the centre vertex of the ring"))?;
                rings_around(mesh, centre, self.rings)
            }
            Source::All => {
                let mut mask = vec![false; mesh.vertex_slots()];
                for v in mesh.vertices() {
                    mask[mesh.vertex_index(v)] = true;
                }
                mask
            }
        };
        let mask = halfedge::VertexData::new(mesh, mask)?;
        Ok(SubMesh::from_mask(mesh, &mask)?)
    }

    /// The edit of the current operation (not pull, not smooth) on `sub`.
    fn edit(&self, mesh: &Mesh, sub: &SubMesh) -> Result<SubmeshEdit, ToolError> {
        let positions = mesh.positions();
        let centroid = sub
            .vertex_indices()
            .iter()
            .map(|&i| positions[i as usize])
            .sum::<DVec3>()
            / sub.len() as f64;
        let view = self.view_or_default();
        let has_frontier = !sub.frontier_indices().is_empty();
        // Taper and twist: inward levels from the frontier, or along the view's up axis.
        let barr = |sub: &SubMesh| -> Result<(Option<Axis>, Variation), ToolError> {
            if has_frontier {
                Ok((None, Variation::Levels(None)))
            } else {
                let axis = Axis::new(centroid, view.up)?;
                let (lo, hi) = sub.axial_extent(mesh, &axis)?;
                Ok((Some(axis), Variation::Along { start: lo, end: hi }))
            }
        };
        Ok(match self.operation {
            Operation::Scale => SubmeshEdit::Scale {
                centre: centroid,
                factor: self.scale,
            },
            Operation::Rotate => {
                let axis = if has_frontier {
                    sub.axis(mesh)?
                } else {
                    Axis::new(centroid, view.forward)?
                };
                SubmeshEdit::Rotate {
                    axis,
                    angle: self.angle.to_radians(),
                    bounded: false,
                }
            }
            Operation::Taper => {
                let (axis, variation) = barr(sub)?;
                SubmeshEdit::Taper {
                    axis,
                    factor: self.taper,
                    variation,
                }
            }
            Operation::Twist => {
                let (axis, variation) = barr(sub)?;
                SubmeshEdit::Twist {
                    axis,
                    angle: self.twist.to_radians(),
                    variation,
                }
            }
            Operation::Pull | Operation::Smooth => {
                return Err(ToolError::new("internal: not a one-shot edit"));
            }
        })
    }

    /// The recipe step of the current operation on `sub` (for pull: by `offset`), as
    /// [`edit`](Self::edit) and [`run`](Self::run) compute it: the sub-mesh's vertices, the
    /// centre and the axis the tool used (`Err`: why it has no exact step).
    fn recipe_step(
        &self,
        ctx: &ToolContext<'_>,
        sub: Option<&SubMesh>,
        offset: DVec3,
    ) -> Result<Step, String> {
        let mesh = ctx.mesh();
        let level = recipe_steps::level(ctx)?;
        let region = match sub {
            Some(sub) => Region::Vertices {
                indices: sub.vertex_indices().to_vec(),
            },
            None => Region::All,
        };
        if self.operation == Operation::Smooth {
            return Ok(Step::Smooth(Smooth {
                level,
                region,
                collar: if self.smooth_whole {
                    0
                } else {
                    self.smooth_collar
                },
                iterations: self.iterations,
                lambda: self.lambda,
                mu: self.mu,
                weights: self.cotangent.then(|| "cotangent".to_owned()),
            }));
        }
        let sub = sub.ok_or("no sub-mesh")?;
        let propagation = self.levels;
        let falloff = if self.smooth_falloff {
            RecipeFalloff::Smooth
        } else {
            RecipeFalloff::Linear
        };
        // What `edit` computes, as the recipe names it.
        let centroid = sub
            .vertex_indices()
            .iter()
            .map(|&i| mesh.positions()[i as usize])
            .sum::<DVec3>()
            / sub.len() as f64;
        let view = self.view_or_default();
        let has_frontier = !sub.frontier_indices().is_empty();
        let axis_along = |direction: DVec3| AxisSpec {
            point: recipe_steps::array(centroid),
            direction: recipe_steps::array(direction),
        };
        let barr = || -> Result<(Option<AxisSpec>, Option<RecipeVariation>), String> {
            if has_frontier {
                Ok((None, None))
            } else {
                let axis = Axis::new(centroid, view.up).map_err(|e| e.to_string())?;
                let (start, end) = sub.axial_extent(mesh, &axis).map_err(|e| e.to_string())?;
                Ok((
                    Some(axis_along(view.up)),
                    Some(RecipeVariation::Along { start, end }),
                ))
            }
        };
        Ok(match self.operation {
            Operation::Pull => Step::Pull(Pull {
                level,
                region,
                propagation,
                falloff,
                offset: recipe_steps::array(offset),
            }),
            Operation::Scale => Step::Scale(Scale {
                level,
                region,
                propagation,
                falloff,
                factor: self.scale,
                centre: Some(recipe_steps::array(centroid)),
            }),
            Operation::Rotate => Step::Rotate(RotateStep {
                level,
                region,
                propagation,
                falloff,
                degrees: self.angle,
                // With a frontier the recipe's default axis is the tool's.
                axis: (!has_frontier).then(|| axis_along(view.forward)),
                bounded: false,
            }),
            Operation::Taper => {
                let (axis, variation) = barr()?;
                Step::Taper(Taper {
                    level,
                    region,
                    propagation,
                    falloff,
                    factor: self.taper,
                    axis,
                    variation,
                })
            }
            Operation::Twist => {
                let (axis, variation) = barr()?;
                Step::Twist(Twist {
                    level,
                    region,
                    propagation,
                    falloff,
                    degrees: self.twist,
                    axis,
                    variation,
                })
            }
            Operation::Smooth => unreachable!("handled above"),
        })
    }

    /// The view the axes of edits without a frontier follow (a default one before the
    /// panel was drawn).
    fn view_or_default(&self) -> ViewInfo {
        self.view.unwrap_or(ViewInfo {
            eye: DVec3::Z,
            forward: -DVec3::Z,
            right: DVec3::X,
            up: DVec3::Y,
            scene_radius: 1.0,
        })
    }

    /// Applies the current operation (pull needs a drag).
    pub fn run(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        let mesh = ctx.mesh();
        let op = choice_name(&OPERATIONS, self.operation);
        let mut work = mesh.clone();
        // What the edit tells a hierarchy (its region and the part moved at full
        // strength), so that refining lands it as made.
        let mut marks = None;
        let mut sub_used = None;
        let (sub_len, what) = match self.operation {
            Operation::Pull => {
                return Err(ToolError::new(
                    "pull follows a drag: press on the mesh and drag",
                ))
            }
            Operation::Smooth => {
                let weights = if self.cotangent {
                    SmoothingWeights::Cotangent
                } else {
                    SmoothingWeights::Uniform
                };
                let mut smoother = if self.smooth_whole {
                    Smoother::new(mesh, edit::Vertices::All, weights, true)?
                } else {
                    let sub = self.submesh(mesh)?;
                    let smoother =
                        Smoother::for_submesh(mesh, &sub, self.smooth_collar, weights, true)?;
                    sub_used = Some(sub);
                    smoother
                };
                smoother.taubin(&mut work, self.lambda, self.mu, self.iterations)?;
                (
                    smoother.moving(),
                    format!(
                        "Taubin λ {} μ {} × {} ({}) over {}",
                        self.lambda,
                        self.mu,
                        self.iterations,
                        if self.cotangent {
                            "cotangent"
                        } else {
                            "uniform"
                        },
                        if self.smooth_whole {
                            "the whole mesh".to_string()
                        } else {
                            format!("the sub-mesh + {} collar rings", self.smooth_collar)
                        }
                    ),
                )
            }
            _ => {
                let sub = self.submesh(mesh)?;
                let edit = self.edit(mesh, &sub)?;
                marks = Some(sub.apply_with_marks(&mut work, &edit, self.propagation())?);
                let n = sub.len();
                sub_used = Some(sub);
                (n, format!("{op}, n = {}", self.levels))
            }
        };
        let step = self
            .recipe_step(ctx, sub_used.as_ref(), DVec3::ZERO)
            .map_err(|why| format!("Sub-mesh {op} ({why})"));
        // Copy what changed (bit for bit) into the document, as one undo step.
        let changed: Vec<usize> = mesh
            .vertices()
            .map(|v| mesh.vertex_index(v))
            .filter(|&i| mesh.positions()[i] != work.positions()[i])
            .collect();
        ctx.begin_edit(&format!("Sub-mesh {op}"));
        let positions = ctx.positions_mut();
        for &i in &changed {
            positions[i] = work.positions()[i];
        }
        ctx.doc.end_edit();
        if let Some(marks) = marks {
            ctx.doc.mark_hierarchy(|h| marks.mark(h))?;
        }
        ctx.doc.record_step(None, step);
        ctx.info(format!(
            "Sub-mesh {what}: {} vertices moved (sub-mesh {} vertices)",
            group(changed.len()),
            group(sub_len)
        ));
        Ok(())
    }

    /// Colours the sub-mesh, its frontier and its propagation collars.
    fn show(&self, ctx: &mut ToolContext<'_>) {
        let mesh = ctx.mesh();
        let Ok(sub) = self.submesh(mesh) else {
            return;
        };
        let mut labels = vec![NO_LABEL; mesh.vertex_slots()];
        for &i in sub.vertex_indices() {
            labels[i as usize] = 0;
        }
        for &i in sub.frontier_indices() {
            labels[i as usize] = 1;
        }
        let mut legend = vec![(0, "sub-mesh".to_string()), (1, "frontier".to_string())];
        if let Ok(collars) = sub.collars(mesh, self.levels) {
            for (k, collar) in collars.iter().enumerate() {
                for &i in collar {
                    labels[i as usize] = 2 + k as u32;
                }
                legend.push((2 + k as u32, format!("collar {}", k + 1)));
            }
        }
        ctx.show_vertex_labels("sub-mesh and collars", labels, legend);
    }
}

/// The vertices within `rings` rings of `centre` (breadth-first over the one-rings).
pub fn rings_around(mesh: &Mesh, centre: VertexId, rings: usize) -> Vec<bool> {
    let mut mask = vec![false; mesh.vertex_slots()];
    let mut queue = VecDeque::from([(centre, 0usize)]);
    mask[mesh.vertex_index(centre)] = true;
    while let Some((v, d)) = queue.pop_front() {
        if d == rings {
            continue;
        }
        for w in mesh.adjacent_vertices(v) {
            let i = mesh.vertex_index(w);
            if !mask[i] {
                mask[i] = true;
                queue.push_back((w, d + 1));
            }
        }
    }
    mask
}

/// The fall-off choices: `(smooth, script name)`.
const FALLOFFS: [(bool, &str); 2] = [(false, "linear"), (true, "smooth")];
/// The smoothing weights: `(cotangent, script name)`.
const WEIGHTS: [(bool, &str); 2] = [(false, "uniform"), (true, "cotangent")];
/// What smoothing covers: `(the whole mesh, script name)`.
const SMOOTH_REGIONS: [(bool, &str); 2] = [(false, "submesh"), (true, "mesh")];

/// Stores a number with `store` and shows the sub-mesh (the editing methods check the
/// values when they run).
fn number(
    t: &mut SubMeshEdit,
    name: &str,
    v: &serde_json::Value,
    ctx: &mut ToolContext<'_>,
    store: fn(&mut SubMeshEdit, f64),
) -> Result<(), ToolError> {
    store(t, number_param(name, v)?);
    t.show(ctx);
    Ok(())
}

/// Stores a whole number with `store` and shows the sub-mesh.
fn whole(
    t: &mut SubMeshEdit,
    name: &str,
    v: &serde_json::Value,
    ctx: &mut ToolContext<'_>,
    store: fn(&mut SubMeshEdit, usize),
) -> Result<(), ToolError> {
    store(t, params::whole(name, v)?);
    t.show(ctx);
    Ok(())
}

/// Stores one of `table`'s choices with `store` and shows the sub-mesh.
fn choice<T: Copy>(
    t: &mut SubMeshEdit,
    table: &[(T, &'static str)],
    name: &str,
    v: &serde_json::Value,
    ctx: &mut ToolContext<'_>,
    store: fn(&mut SubMeshEdit, T),
) -> Result<(), ToolError> {
    store(t, choice_param(table, name, v)?);
    t.show(ctx);
    Ok(())
}

/// The parameters of [`SubMeshEdit`] (see [`params`]).
const PARAMS: &[Param<SubMeshEdit>] = &[
    Param::new(
        "source",
        "Sub-mesh",
        Widget::Choice(|| params::names(&SOURCES)),
        |t| choice_name(&SOURCES, t.source).into(),
        |t, v, ctx| choice(t, &SOURCES, "source", v, ctx, |t, x| t.source = x),
    ),
    Param::new(
        "rings",
        "rings",
        params::count(0.0, 30.0),
        |t| t.rings.into(),
        |t, v, ctx| whole(t, "rings", v, ctx, |t, x| t.rings = x),
    ),
    Param::new(
        "operation",
        "Operation",
        Widget::Choice(|| params::names(&OPERATIONS)),
        |t| choice_name(&OPERATIONS, t.operation).into(),
        |t, v, ctx| choice(t, &OPERATIONS, "operation", v, ctx, |t, x| t.operation = x),
    ),
    Param::new(
        "levels",
        "propagation n",
        params::count(0.0, 20.0),
        |t| t.levels.into(),
        |t, v, ctx| whole(t, "levels", v, ctx, |t, x| t.levels = x),
    ),
    Param::new(
        "falloff",
        "fall-off",
        Widget::Choice(|| params::names(&FALLOFFS)),
        |t| choice_name(&FALLOFFS, t.smooth_falloff).into(),
        |t, v, ctx| choice(t, &FALLOFFS, "falloff", v, ctx, |t, x| t.smooth_falloff = x),
    ),
    Param::new(
        "scale",
        "factor",
        params::log_slider(0.2, 3.0),
        |t| t.scale.into(),
        |t, v, ctx| number(t, "scale", v, ctx, |t, x| t.scale = x),
    ),
    Param::new(
        "angle",
        "angle (°)",
        params::slider(-180.0, 180.0),
        |t| t.angle.into(),
        |t, v, ctx| number(t, "angle", v, ctx, |t, x| t.angle = x),
    ),
    Param::new(
        "taper",
        "factor",
        params::log_slider(0.1, 3.0),
        |t| t.taper.into(),
        |t, v, ctx| number(t, "taper", v, ctx, |t, x| t.taper = x),
    ),
    Param::new(
        "twist",
        "angle (°)",
        params::slider(-360.0, 360.0),
        |t| t.twist.into(),
        |t, v, ctx| number(t, "twist", v, ctx, |t, x| t.twist = x),
    ),
    Param::new(
        "lambda",
        "λ",
        params::slider(0.01, 0.9),
        |t| t.lambda.into(),
        |t, v, ctx| number(t, "lambda", v, ctx, |t, x| t.lambda = x),
    ),
    Param::new(
        "mu",
        "μ",
        params::slider(-0.95, -0.01),
        |t| t.mu.into(),
        |t, v, ctx| number(t, "mu", v, ctx, |t, x| t.mu = x),
    ),
    Param::new(
        "iterations",
        "iterations",
        params::count(1.0, 200.0),
        |t| t.iterations.into(),
        |t, v, ctx| whole(t, "iterations", v, ctx, |t, x| t.iterations = x),
    ),
    Param::new(
        "weights",
        "weights",
        Widget::Choice(|| params::names(&WEIGHTS)),
        |t| choice_name(&WEIGHTS, t.cotangent).into(),
        |t, v, ctx| choice(t, &WEIGHTS, "weights", v, ctx, |t, x| t.cotangent = x),
    ),
    Param::new(
        "smooth_region",
        "smooth",
        Widget::Choice(|| params::names(&SMOOTH_REGIONS)),
        |t| choice_name(&SMOOTH_REGIONS, t.smooth_whole).into(),
        |t, v, ctx| {
            choice(t, &SMOOTH_REGIONS, "smooth_region", v, ctx, |t, x| {
                t.smooth_whole = x;
            })
        },
    ),
    Param::new(
        "smooth_collar",
        "collar rings",
        params::count(0.0, 10.0),
        |t| t.smooth_collar.into(),
        |t, v, ctx| whole(t, "smooth_collar", v, ctx, |t, x| t.smooth_collar = x),
    ),
    Param::action("apply", "Apply", |t, v, ctx| {
        if bool_param("apply", v)? {
            t.run(ctx)?;
        }
        t.show(ctx);
        Ok(())
    }),
];

impl Tool for SubMeshEdit {
    fn name(&self) -> &str {
        "Sub-mesh edits"
    }

    fn description(&self) -> &str {
        "Seed paper §4.2–4.3: pull (drag), scale, rotate, taper, twist a sub-mesh with n \
         propagation levels; Taubin λ|μ smoothing of the sub-mesh + collar or the mesh."
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>) {
        self.view = Some(ctx.view);
        params::widget(ui, PARAMS, "source", self, ctx);
        match self.source {
            Source::Labels => {
                if SubMeshLabels::of(ctx.mesh()).is_none() {
                    ui.weak("No labels for this mesh: cut one with Multiresolution.");
                }
            }
            Source::Ring => {
                params::widget(ui, PARAMS, "rings", self, ctx);
                ui.weak("Click (or press to pull) the centre vertex.");
            }
            Source::All => {}
        }
        params::widget(ui, PARAMS, "operation", self, ctx);
        if self.operation != Operation::Smooth {
            params::widget(ui, PARAMS, "levels", self, ctx);
            params::widget(ui, PARAMS, "falloff", self, ctx);
        }
        let shown: &[&str] = match self.operation {
            Operation::Pull => {
                ui.weak("Press on the mesh and drag: the sub-mesh follows in the view plane.");
                &[]
            }
            Operation::Scale => &["scale"],
            Operation::Rotate => &["angle"],
            Operation::Taper => &["taper"],
            Operation::Twist => &["twist"],
            Operation::Smooth if self.smooth_whole => {
                &["lambda", "mu", "iterations", "weights", "smooth_region"]
            }
            Operation::Smooth => &[
                "lambda",
                "mu",
                "iterations",
                "weights",
                "smooth_region",
                "smooth_collar",
            ],
        };
        for name in shown {
            params::widget(ui, PARAMS, name, self, ctx);
        }
        if self.operation != Operation::Pull && ui.button("Apply").clicked() {
            if let Err(e) = self.run(ctx) {
                ctx.error(format!("Sub-mesh edit: {e}"));
            }
        }
    }

    fn on_pick(&mut self, pick: Option<&Pick>, ctx: &mut ToolContext<'_>) {
        if let Some(p) = pick {
            if self.source == Source::Ring {
                self.centre = Some(p.vertex);
            }
        }
        self.show(ctx);
    }

    fn wants_drag(&self, _pick: &Pick) -> bool {
        self.operation == Operation::Pull
    }

    fn on_drag(&mut self, drag: &Drag, ctx: &mut ToolContext<'_>) {
        match drag.phase {
            DragPhase::Start => {
                if let (Source::Ring, Some(pick)) = (self.source, drag.pick) {
                    self.centre = Some(pick.vertex);
                }
                match self.submesh(ctx.mesh()) {
                    Ok(sub) => {
                        ctx.begin_edit("Sub-mesh pull");
                        self.drag = Some(PullDrag {
                            sub,
                            base: ctx.mesh().positions().to_vec(),
                            work: ctx.mesh().clone(),
                            touched: Vec::new(),
                        });
                    }
                    Err(e) => ctx.error(format!("Sub-mesh pull: {e}")),
                }
            }
            DragPhase::Move | DragPhase::End => {
                let propagation = self.propagation();
                let Some(d) = &mut self.drag else {
                    return;
                };
                d.work.positions_mut().copy_from_slice(&d.base);
                let edit = SubmeshEdit::Pull {
                    offset: drag.delta(),
                };
                // The whole drag is one edit: its marks are given once, at its end.
                let applied = if drag.phase == DragPhase::End {
                    d.sub
                        .apply_with_marks(&mut d.work, &edit, propagation)
                        .map(|applied| (applied.snapshot().clone(), Some(applied)))
                } else {
                    d.sub
                        .apply(&mut d.work, &edit, propagation)
                        .map(|snapshot| (snapshot, None))
                };
                let mut marks = None;
                match applied {
                    Ok((snapshot, applied)) => {
                        marks = applied;
                        d.touched.extend_from_slice(snapshot.indices());
                        d.touched.sort_unstable();
                        d.touched.dedup();
                        let positions = ctx.positions_mut();
                        for &i in &d.touched {
                            positions[i as usize] = d.work.positions()[i as usize];
                        }
                    }
                    Err(e) => ctx.error(format!("Sub-mesh pull: {e}")),
                }
                let marked = marks.map(|m| ctx.doc.mark_hierarchy(|h| m.mark(h)));
                if let Some(Err(e)) = marked {
                    self.drag = None;
                    ctx.error(format!("Sub-mesh pull: {e}"));
                } else if drag.phase == DragPhase::End {
                    let d = self.drag.take().expect("checked");
                    let step = self
                        .recipe_step(ctx, Some(&d.sub), drag.delta())
                        .map_err(|why| format!("Sub-mesh pull ({why})"));
                    ctx.doc.record_step(None, step);
                    ctx.info(format!(
                        "Sub-mesh pull: {} vertices moved (sub-mesh {}, n = {}), |d| = {:.4}",
                        group(d.touched.len()),
                        group(d.sub.len()),
                        self.levels,
                        drag.delta().length()
                    ));
                }
            }
        }
    }

    fn apply(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.run(ctx)
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
        if self.source == Source::Ring {
            if let Some(v) = self.centre.filter(|&v| mesh.is_valid_vertex(v)) {
                overlay.marker(mesh.position(v), Overlay::PICK, 1.3);
            }
        }
        if self.source == Source::Labels {
            frontier_overlay(mesh, overlay);
        }
    }

    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        self.drag = None;
        if self.centre.is_some_and(|v| !mesh.is_valid_vertex(v)) {
            self.centre = None;
        }
    }

    fn activate(&mut self, ctx: &mut ToolContext<'_>) {
        self.show(ctx);
    }
}

#[cfg(test)]
mod tests;
