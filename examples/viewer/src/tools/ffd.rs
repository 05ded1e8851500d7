//! *FFD* — the shape- and height-surface free-form deformation of Feng, Ma & Peng, *A new
//! free-form deformation through the control of parametric surfaces* ([`edit::deform`]).
//!
//! *Attach* fits a placement frame to the bounding box of the mesh (or of the sub-mesh of
//! the *Multiresolution* labels): `u` along the longest side, heights along the shortest,
//! the shape surface `S` a flat bicubic B-spline under the object, the height surface `H`
//! at height 1. In **global** mode `S` covers the whole object (grown by 5 %); in
//! **local** mode it covers the middle 60 % of it, the object crosses its borders and the
//! border control points stay fixed (two layers, §4), so the deformed part stays joined to
//! the rest.
//!
//! The control nets are drawn over the mesh: `S` in orange at its place under the object,
//! `H` in blue on top of it (its frame height is drawn scaled by the object's height;
//! pinned points are grey). Press near a control point and drag: the press grabs the
//! unpinned control point nearest to the mouse ray (within about 2°), whether or not the
//! ray meets the mesh, so points beyond the silhouette can be grabbed too; the mesh
//! follows live, one undo step per drag; for `H` only the height counts (`h ↦ H_y h`). The ready operations *bend*, *taper* and *twist* act on the current surfaces.
//! Undo and redo bring the surfaces back with the positions they produced.

use std::cell::Cell;

use edit::deform::{AttachOptions, BSplineSurface, Ffd, FfdReach, LatticeFrame};
use edit::{HierarchyEdit, Vertices};
use glam::DVec3;
use halfedge::Mesh;
use three_d::egui;

use super::params::{self, Param, Widget};
use super::{
    bool_param, choice_name, choice_param, number_param, Drag, DragPhase, Overlay, Pick, Press,
    SubMeshLabels, Tool, ToolContext, ToolError,
};
use crate::camera::Ray;
use crate::colors::Rgba;
use crate::format::group;

/// Which control net.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Net {
    /// The shape surface `S`.
    Shape,
    /// The height surface `H`.
    Height,
}

/// The ready operation of *Apply*.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operation {
    /// Bend the shape surface along `u`.
    Bend,
    /// Narrow `S` and slope `H` along `u`.
    Taper,
    /// Twist `S` about its `u` axis.
    Twist,
}

const OPERATIONS: [(Operation, &str); 3] = [
    (Operation::Bend, "bend"),
    (Operation::Taper, "taper"),
    (Operation::Twist, "twist"),
];

const SHAPE_COLOR: Rgba = [255, 140, 30, 255];
const HEIGHT_COLOR: Rgba = [60, 150, 255, 255];
const PINNED_COLOR: Rgba = [140, 140, 140, 255];
const SELECTED_COLOR: Rgba = [230, 30, 60, 255];

/// Largest angle (radians, about 2°) between the mouse ray and the direction from the eye
/// to a control point for a press to grab it.
pub const GRAB_ANGLE: f64 = 0.035;

/// The key of the point nearest to `ray` by the angle seen from its origin, among the
/// points in front of the origin within `max_angle` radians (`None` if there is none).
/// Used to grab control points with the mouse ray, on the mesh or beyond it.
pub fn nearest_to_ray<K>(
    ray: &Ray,
    points: impl IntoIterator<Item = (K, DVec3)>,
    max_angle: f64,
) -> Option<K> {
    let mut best: Option<(f64, K)> = None;
    for (key, p) in points {
        let d = p - ray.origin;
        let along = d.dot(ray.direction);
        if along <= 0.0 {
            continue;
        }
        let angle = (d - along * ray.direction).length().atan2(along);
        if angle <= max_angle && best.as_ref().is_none_or(|(b, _)| angle < *b) {
            best = Some((angle, key));
        }
    }
    best.map(|(_, key)| key)
}

/// An attached FFD with what the tool needs around it.
struct Attached {
    ffd: Ffd,
    /// Scratch copy of the mesh that `deform` writes into.
    work: Mesh,
    /// Slots of the attached vertices.
    attached: Vec<usize>,
    /// Height of the object along the frame's `y`, to draw `H` on top of it.
    display_height: f64,
    /// Surfaces and the hash of the positions they produced, for undo / redo.
    history: Vec<(BSplineSurface, BSplineSurface, u64)>,
}

/// A drag of a control point in progress.
struct ControlDrag {
    net: Net,
    index: (usize, usize),
    /// Displayed position at the start.
    start: DVec3,
    /// The mesh's positions at the start.
    base: Vec<DVec3>,
}

/// The FFD tool (see the module docs).
pub struct FfdTool {
    /// Attach to the sub-mesh of the labels (else the whole mesh).
    pub submesh: bool,
    /// Local mode (the surface covers the middle of the object).
    pub local: bool,
    /// Control grid `[u, v]` of both surfaces (bicubic).
    pub grid: [usize; 2],
    /// The operation of *Apply*.
    pub operation: Operation,
    /// Bend angle, degrees.
    pub bend: f64,
    /// Taper factors at `u = 0` and `u = 1`.
    pub taper: [f64; 2],
    /// Twist angle, degrees.
    pub twist: f64,
    state: Option<Attached>,
    /// Control point chosen by a script (`control`) or by the last press.
    pending: Cell<Option<(Net, usize, usize)>>,
    /// Chosen by a script: the next drag moves it wherever the press is.
    armed: bool,
    selected: Option<(Net, usize, usize)>,
    drag: Option<ControlDrag>,
    note: Option<String>,
}

impl Default for FfdTool {
    fn default() -> Self {
        Self::new()
    }
}

impl FfdTool {
    /// The tool (it reads the sub-mesh labels from the mesh's label attribute).
    pub fn new() -> Self {
        Self {
            submesh: false,
            local: false,
            grid: [7, 5],
            operation: Operation::Bend,
            bend: 45.0,
            taper: [1.0, 0.5],
            twist: 60.0,
            state: None,
            pending: Cell::new(None),
            armed: false,
            selected: None,
            drag: None,
            note: None,
        }
    }

    /// Attaches the FFD to the mesh (or the sub-mesh).
    pub fn attach(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        let mesh = ctx.mesh();
        let mask = if self.submesh {
            Some(
                SubMeshLabels::of(mesh)
                    .ok_or_else(|| {
                        ToolError::new(
                            "no sub-mesh labels for this mesh: cut one with Multiresolution",
                        )
                    })?
                    .inside_mask(),
            )
        } else {
            None
        };
        let mask = mask
            .map(|m| halfedge::VertexData::new(mesh, m))
            .transpose()?;
        let vertices = match &mask {
            Some(m) => Vertices::Mask(m),
            None => Vertices::All,
        };
        // The bounding box of the selected vertices.
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for v in mesh.vertices() {
            let i = mesh.vertex_index(v);
            if mask.as_ref().is_none_or(|m| m[i]) {
                lo = lo.min(mesh.positions()[i]);
                hi = hi.max(mesh.positions()[i]);
            }
        }
        if !lo.is_finite() {
            return Err(ToolError::new("nothing to attach: the mesh is empty"));
        }
        let extent = hi - lo;
        let mut axes = [0usize, 1, 2];
        axes.sort_by(|&a, &b| extent[b].total_cmp(&extent[a]));
        let (long, short) = (axes[0], axes[2]);
        let frame = LatticeFrame::new(lo, DVec3::AXES[long], DVec3::AXES[short])?;
        let margin = if self.local { -0.2 } else { 0.05 };
        let grid = self.grid;
        let ffd = Ffd::covering(
            mesh,
            vertices,
            frame,
            ([3, 3], grid),
            ([3, 3], grid),
            margin,
            AttachOptions::default(),
        )?;
        let attached: Vec<usize> = mesh
            .vertices()
            .map(|v| mesh.vertex_index(v))
            .filter(|&i| ffd.parameters(i).is_some())
            .collect();
        let display_height = extent[short]
            .max(1e-3 * extent[long])
            .max(f64::MIN_POSITIVE);
        let (s, h) = (ffd.shape().clone(), ffd.height().clone());
        let mode = ffd.reach();
        let n = ffd.attached();
        self.state = Some(Attached {
            ffd,
            work: mesh.clone(),
            attached,
            display_height,
            history: vec![(s, h, positions_hash(mesh))],
        });
        self.selected = None;
        ctx.info(format!(
            "FFD attached: {} vertices ({}), S and H {}×{} bicubic",
            group(n),
            match mode {
                FfdReach::Global => "global",
                FfdReach::Local => "local: border control points fixed",
            },
            grid[0],
            grid[1]
        ));
        Ok(())
    }

    /// Attaches if needed or if another tool changed the mesh since.
    fn ensure_attached(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        let fresh = self.state.as_ref().is_some_and(|s| {
            s.work.vertex_slots() == ctx.mesh().vertex_slots()
                && s.history.last().map(|h| h.2) == Some(positions_hash(ctx.mesh()))
        });
        if !fresh {
            self.attach(ctx)?;
        }
        Ok(())
    }

    /// Deforms the mesh by the current surfaces (inside the open undo step).
    fn deform(&mut self, ctx: &mut ToolContext<'_>, label: &str) -> Result<usize, ToolError> {
        let st = self.state.as_mut().expect("attached");
        st.ffd.deform(&mut st.work)?;
        ctx.begin_edit(label);
        let positions = ctx.positions_mut();
        let mut moved = 0;
        for &i in &st.attached {
            let p = st.work.positions()[i];
            if positions[i] != p {
                moved += 1;
            }
            positions[i] = p;
        }
        // At a coarse level of a hierarchy the footprint is the edit's region: refining
        // moves its fine vertices with it and nothing else.
        ctx.doc.mark_hierarchy(|h| st.ffd.mark(h))?;
        Ok(moved)
    }

    /// Records the surfaces with the positions they produced (end of a gesture).
    fn record(&mut self, mesh: &Mesh) {
        if let Some(st) = &mut self.state {
            let entry = (
                st.ffd.shape().clone(),
                st.ffd.height().clone(),
                positions_hash(mesh),
            );
            st.history.push(entry);
            if st.history.len() > 256 {
                st.history.remove(1);
            }
        }
    }

    /// Applies the ready operation to the current surfaces and deforms.
    pub fn run(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.ensure_attached(ctx)?;
        let st = self.state.as_mut().expect("attached");
        let what = match self.operation {
            Operation::Bend => {
                st.ffd.bend(self.bend.to_radians())?;
                format!("bend {}°", self.bend)
            }
            Operation::Taper => {
                st.ffd.taper(self.taper[0], self.taper[1])?;
                format!("taper {} to {}", self.taper[0], self.taper[1])
            }
            Operation::Twist => {
                st.ffd.twist(self.twist.to_radians())?;
                format!("twist {}°", self.twist)
            }
        };
        let moved = self.deform(ctx, &format!("FFD {what}"))?;
        ctx.doc.end_edit();
        self.record(ctx.mesh());
        ctx.info(format!("FFD {what}: {} vertices moved", group(moved)));
        Ok(())
    }

    /// Surfaces back to rest, and the mesh with them.
    fn reset(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.ensure_attached(ctx)?;
        self.state.as_mut().expect("attached").ffd.reset();
        let moved = self.deform(ctx, "FFD reset")?;
        ctx.doc.end_edit();
        self.record(ctx.mesh());
        ctx.info(format!("FFD reset: {} vertices moved", group(moved)));
        Ok(())
    }

    /// Where control point `(i, j)` of `net` is drawn.
    fn displayed(st: &Attached, net: Net, i: usize, j: usize) -> Option<DVec3> {
        match net {
            Net::Shape => st.ffd.shape().control_point(i, j),
            Net::Height => {
                let frame = st.ffd.frame();
                let l = frame.to_local(st.ffd.height().control_point(i, j)?);
                Some(frame.to_world(DVec3::new(l.x, l.y * st.display_height, l.z)))
            }
        }
    }

    fn is_pinned(st: &Attached, net: Net, i: usize, j: usize) -> bool {
        match net {
            Net::Shape => st.ffd.is_shape_pinned(i, j),
            Net::Height => st.ffd.is_height_pinned(i, j),
        }
    }

    /// The unpinned control points with where they are drawn.
    fn grabbable(st: &Attached) -> impl Iterator<Item = ((Net, usize, usize), DVec3)> + '_ {
        let [cu, cv] = st.ffd.shape().count();
        [Net::Shape, Net::Height].into_iter().flat_map(move |net| {
            (0..cu).flat_map(move |i| {
                (0..cv).filter_map(move |j| {
                    if Self::is_pinned(st, net, i, j) {
                        return None;
                    }
                    Some(((net, i, j), Self::displayed(st, net, i, j)?))
                })
            })
        })
    }

    /// The unpinned control point nearest to `ray`, within [`GRAB_ANGLE`] of it.
    fn nearest(&self, ray: &Ray) -> Option<(Net, usize, usize)> {
        let st = self.state.as_ref()?;
        nearest_to_ray(ray, Self::grabbable(st), GRAB_ANGLE)
    }

    /// Moves control point `c` so that it is drawn at `target`.
    fn move_control(
        st: &mut Attached,
        c: (Net, usize, usize),
        target: DVec3,
    ) -> Result<(), ToolError> {
        let (net, i, j) = c;
        match net {
            Net::Shape => st.ffd.shape_mut().set_control_point(i, j, target)?,
            Net::Height => {
                let frame = *st.ffd.frame();
                let old = frame.to_local(st.ffd.height().control_point(i, j).expect("valid"));
                let y = frame.to_local(target).y / st.display_height;
                st.ffd.height_mut().set_control_point(
                    i,
                    j,
                    frame.to_world(DVec3::new(old.x, y, old.z)),
                )?;
            }
        }
        Ok(())
    }
}

/// A hash of the positions (bits), to recognise the state a surface produced.
fn positions_hash(mesh: &Mesh) -> u64 {
    let mut h: u64 = 0x8422_2325_CBF2_9CE4;
    for p in mesh.positions() {
        for x in [p.x, p.y, p.z] {
            h = (h ^ x.to_bits())
                .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                .rotate_left(31);
        }
    }
    h
}

fn net_name(net: Net) -> &'static str {
    match net {
        Net::Shape => "shape",
        Net::Height => "height",
    }
}

/// The scope choices: `(attach to the sub-mesh, script name)`.
const SCOPES: [(bool, &str); 2] = [(false, "mesh"), (true, "submesh")];
/// The mode choices: `(local, script name)`.
const MODES: [(bool, &str); 2] = [(false, "global"), (true, "local")];

/// Stores a number parameter with `store` (the FFD checks it when it is used).
fn number(
    t: &mut FfdTool,
    name: &str,
    v: &serde_json::Value,
    store: fn(&mut FfdTool, f64),
) -> Result<(), ToolError> {
    store(t, number_param(name, v)?);
    Ok(())
}

/// The parameters of [`FfdTool`] (see [`params`]); the FFD checks grid sizes and the
/// operations' values.
const PARAMS: &[Param<FfdTool>] = &[
    Param::new(
        "scope",
        "Attach to",
        Widget::Choice(|| params::names(&SCOPES)),
        |t| choice_name(&SCOPES, t.submesh).into(),
        |t, v, _| {
            t.submesh = choice_param(&SCOPES, "scope", v)?;
            Ok(())
        },
    ),
    Param::new(
        "mode",
        "Mode",
        Widget::Choice(|| params::names(&MODES)),
        |t| choice_name(&MODES, t.local).into(),
        |t, v, _| {
            t.local = choice_param(&MODES, "mode", v)?;
            Ok(())
        },
    ),
    Param::new(
        "grid_u",
        "control points along u",
        params::count(4.0, 20.0),
        |t| t.grid[0].into(),
        |t, v, _| {
            t.grid[0] = params::whole("grid_u", v)?;
            Ok(())
        },
    ),
    Param::new(
        "grid_v",
        "control points along v",
        params::count(4.0, 20.0),
        |t| t.grid[1].into(),
        |t, v, _| {
            t.grid[1] = params::whole("grid_v", v)?;
            Ok(())
        },
    ),
    Param::new(
        "operation",
        "Operation",
        Widget::Choice(|| params::names(&OPERATIONS)),
        |t| choice_name(&OPERATIONS, t.operation).into(),
        |t, v, _| {
            t.operation = choice_param(&OPERATIONS, "operation", v)?;
            Ok(())
        },
    ),
    Param::new(
        "bend",
        "angle (°)",
        params::slider(-180.0, 180.0),
        |t| t.bend.into(),
        |t, v, _| number(t, "bend", v, |t, x| t.bend = x),
    ),
    Param::new(
        "taper_start",
        "factor at u = 0",
        params::slider(0.0, 2.0),
        |t| t.taper[0].into(),
        |t, v, _| number(t, "taper_start", v, |t, x| t.taper[0] = x),
    ),
    Param::new(
        "taper_end",
        "factor at u = 1",
        params::slider(0.0, 2.0),
        |t| t.taper[1].into(),
        |t, v, _| number(t, "taper_end", v, |t, x| t.taper[1] = x),
    ),
    Param::new(
        "twist",
        "angle (°)",
        params::slider(-360.0, 360.0),
        |t| t.twist.into(),
        |t, v, _| number(t, "twist", v, |t, x| t.twist = x),
    ),
    Param::action("attach", "Attach", |t, v, ctx| {
        if bool_param("attach", v)? {
            t.attach(ctx)?;
        }
        Ok(())
    }),
    Param::action("reset", "Reset surfaces", |t, v, ctx| {
        if bool_param("reset", v)? {
            t.reset(ctx)?;
        }
        Ok(())
    }),
    Param::script("control", None, |t, value, ctx| {
        let bad = || ToolError::bad_value("control", "[\"shape\" or \"height\", i, j]", value);
        let a = value.as_array().filter(|a| a.len() == 3).ok_or_else(bad)?;
        let net = match a[0].as_str() {
            Some("shape") => Net::Shape,
            Some("height") => Net::Height,
            _ => return Err(bad()),
        };
        let i = a[1].as_u64().ok_or_else(bad)? as usize;
        let j = a[2].as_u64().ok_or_else(bad)? as usize;
        t.ensure_attached(ctx)?;
        let Some(state) = t.state.as_ref() else {
            return Err(ToolError::new("control: the FFD is not attached"));
        };
        let [cu, cv] = state.ffd.shape().count();
        if i >= cu || j >= cv {
            return Err(ToolError::new(format!(
                "control point ({i}, {j}) outside the {cu}×{cv} grid"
            )));
        }
        t.pending.set(Some((net, i, j)));
        t.selected = Some((net, i, j));
        t.armed = true;
        Ok(())
    }),
];

impl Tool for FfdTool {
    fn name(&self) -> &str {
        "FFD"
    }

    fn description(&self) -> &str {
        "Feng, Ma & Peng: free-form deformation by a shape surface S and a height surface H. \
         Attach, drag the control points of S (orange) or H (blue), or bend, taper, twist."
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>) {
        if let Some(note) = self.note.take() {
            ctx.info(note);
        }
        for name in ["scope", "mode", "grid_u", "grid_v"] {
            params::widget(ui, PARAMS, name, self, ctx);
        }
        ui.horizontal(|ui| {
            params::widget(ui, PARAMS, "attach", self, ctx);
            if ui
                .add_enabled(self.state.is_some(), egui::Button::new("Reset surfaces"))
                .clicked()
            {
                if let Err(e) = self.reset(ctx) {
                    ctx.error(format!("FFD: {e}"));
                }
            }
        });
        match &self.state {
            Some(st) => {
                ui.weak(format!(
                    "{} vertices attached ({})",
                    group(st.ffd.attached()),
                    if st.ffd.reach() == FfdReach::Global {
                        "global"
                    } else {
                        "local"
                    }
                ));
            }
            None => {
                ui.weak("Not attached.");
            }
        }
        ui.weak("Press near a control point and drag it (H: up and down).");
        ui.separator();
        params::widget(ui, PARAMS, "operation", self, ctx);
        let shown: &[&str] = match self.operation {
            Operation::Bend => &["bend"],
            Operation::Taper => &["taper_start", "taper_end"],
            Operation::Twist => &["twist"],
        };
        for name in shown {
            params::widget(ui, PARAMS, name, self, ctx);
        }
        if ui.button("Apply").clicked() {
            if let Err(e) = self.run(ctx) {
                ctx.error(format!("FFD: {e}"));
            }
        }
    }

    fn on_pick(&mut self, pick: Option<&Pick>, ctx: &mut ToolContext<'_>) {
        let (Some(p), false) = (pick, self.armed) else {
            return;
        };
        let origin = ctx.view.eye;
        let Some(direction) = (p.point - origin).try_normalize() else {
            return;
        };
        if let Some(c) = self.nearest(&Ray { origin, direction }) {
            self.selected = Some(c);
        }
    }

    fn grab(&self, press: &Press, _mesh: &Mesh) -> Option<DVec3> {
        let st = self.state.as_ref()?;
        // A control point chosen by a script goes wherever the press is.
        let c = match self.pending.get() {
            Some(c) if self.armed => c,
            _ => self.nearest(&press.ray)?,
        };
        self.pending.set(Some(c));
        Self::displayed(st, c.0, c.1, c.2)
    }

    fn on_drag(&mut self, drag: &Drag, ctx: &mut ToolContext<'_>) {
        match drag.phase {
            DragPhase::Start => {
                let Some(c) = self.pending.take() else {
                    return;
                };
                self.armed = false;
                if let Err(e) = self.ensure_attached(ctx) {
                    ctx.error(format!("FFD: {e}"));
                    return;
                }
                let st = self.state.as_ref().expect("attached");
                let Some(start) = Self::displayed(st, c.0, c.1, c.2) else {
                    return;
                };
                self.selected = Some(c);
                self.drag = Some(ControlDrag {
                    net: c.0,
                    index: (c.1, c.2),
                    start,
                    base: ctx.mesh().positions().to_vec(),
                });
                ctx.begin_edit("FFD drag");
            }
            DragPhase::Move | DragPhase::End => {
                let Some(d) = &self.drag else {
                    return;
                };
                let c = (d.net, d.index.0, d.index.1);
                let target = d.start + drag.delta();
                let st = self.state.as_mut().expect("attached");
                let result =
                    Self::move_control(st, c, target).and_then(|()| self.deform(ctx, "FFD drag"));
                match result {
                    Ok(_) if drag.phase == DragPhase::End => {
                        let d = self.drag.take().expect("checked");
                        let moved = d
                            .base
                            .iter()
                            .zip(ctx.mesh().positions())
                            .filter(|(a, b)| a != b)
                            .count();
                        self.record(ctx.mesh());
                        ctx.info(format!(
                            "FFD: moved {} control point ({}, {}) by {:.4}; {} vertices moved",
                            net_name(c.0),
                            c.1,
                            c.2,
                            drag.delta().length(),
                            group(moved)
                        ));
                    }
                    Ok(_) => {}
                    Err(e) => ctx.error(format!("FFD: {e}")),
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

    fn overlay(&self, _mesh: &Mesh, overlay: &mut Overlay) {
        let Some(st) = &self.state else {
            return;
        };
        let [cu, cv] = st.ffd.shape().count();
        for (net, color) in [(Net::Shape, SHAPE_COLOR), (Net::Height, HEIGHT_COLOR)] {
            let p = |i, j| Self::displayed(st, net, i, j).expect("in the grid");
            for i in 0..cu {
                for j in 0..cv {
                    let selected = self.selected == Some((net, i, j));
                    let (c, s) = if selected {
                        (SELECTED_COLOR, 1.8)
                    } else if Self::is_pinned(st, net, i, j) {
                        (PINNED_COLOR, 0.8)
                    } else {
                        (color, 1.1)
                    };
                    overlay.marker(p(i, j), c, s);
                    if i + 1 < cu {
                        overlay.segment(p(i, j), p(i + 1, j), color);
                    }
                    if j + 1 < cv {
                        overlay.segment(p(i, j), p(i, j + 1), color);
                    }
                }
            }
        }
    }

    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        self.drag = None;
        let Some(st) = &mut self.state else {
            return;
        };
        if st.work.vertex_slots() != mesh.vertex_slots() {
            self.state = None;
            self.note = Some("FFD detached: the mesh changed".into());
            return;
        }
        let hash = positions_hash(mesh);
        match st.history.iter().rposition(|e| e.2 == hash) {
            Some(k) => {
                let (s, h, _) = st.history[k].clone();
                *st.ffd.shape_mut() = s;
                *st.ffd.height_mut() = h;
            }
            None => {
                self.state = None;
                self.note = Some("FFD detached: the positions are not ones it made".into());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::colors::Display;
    use crate::document::Document;
    use crate::pick::Bvh;
    use crate::tools::{Status, ViewInfo};
    use halfedge::generators;

    fn ray_towards(origin: DVec3, target: DVec3) -> Ray {
        Ray {
            origin,
            direction: (target - origin).normalize(),
        }
    }

    #[test]
    fn nearest_to_ray_takes_the_smallest_angle_in_front_within_the_limit() {
        let eye = DVec3::new(0.0, 0.0, 10.0);
        let ray = ray_towards(eye, DVec3::ZERO);
        let points = [
            ("far off", DVec3::new(3.0, 0.0, 0.0)),
            // Angle 0.2 / 10 = 0.02 rad.
            ("near", DVec3::new(0.2, 0.0, 0.0)),
            // Angle 0.1 / 5 = 0.02 rad as well, but 0.15 / 5 = 0.03 rad here.
            ("closer to the eye", DVec3::new(0.0, 0.15, 5.0)),
            // On the line but behind the eye.
            ("behind", DVec3::new(0.0, 0.0, 20.0)),
        ];
        assert_eq!(nearest_to_ray(&ray, points, GRAB_ANGLE), Some("near"));
        // The angle, not the distance, decides: 0.1 at depth 9 beats 0.2 at depth 10.
        let closer = [
            ("a", DVec3::new(0.2, 0.0, 0.0)),
            ("b", DVec3::new(0.0, 0.1, 1.0)),
        ];
        assert_eq!(nearest_to_ray(&ray, closer, GRAB_ANGLE), Some("b"));
        assert_eq!(
            nearest_to_ray(&ray, [("x", DVec3::new(0.5, 0.0, 0.0))], GRAB_ANGLE),
            None
        );
        assert_eq!(
            nearest_to_ray(&ray, [("behind", DVec3::new(0.0, 0.0, 11.0))], 1.0),
            None
        );
        assert_eq!(nearest_to_ray::<u8>(&ray, [], GRAB_ANGLE), None);
    }

    #[test]
    fn a_press_grabs_a_control_point_beyond_the_silhouette() {
        // A flat 3 × 2 sheet in the xy plane: the FFD's shape surface is grown by 5 %, so
        // its corner control points lie outside the sheet.
        let mesh = generators::grid(12, 8, 3.0, 2.0);
        let mut doc = Document::new(mesh.clone(), None, None);
        let (mut display, mut status) = (Display::default(), Status::default());
        let eye = DVec3::new(0.4, -0.3, 8.0);
        let mut ctx = ToolContext {
            doc: &mut doc,
            display: &mut display,
            status: &mut status,
            view: ViewInfo {
                eye,
                forward: DVec3::NEG_Z,
                right: DVec3::X,
                up: DVec3::Y,
                scene_radius: 2.0,
            },
            pick: None,
        };
        let mut tool = FfdTool::new();
        tool.grid = [6, 6];
        tool.attach(&mut ctx).unwrap();
        let st = tool.state.as_ref().unwrap();
        let corner = FfdTool::displayed(st, Net::Shape, 0, 0).unwrap();
        let ray = ray_towards(eye, corner);
        let bvh = Bvh::build(&mesh);
        assert!(
            bvh.intersect(&mesh, &ray).unwrap().is_none(),
            "the ray towards the corner control point {corner} should miss the sheet"
        );
        let press = Press { ray, hit: None };
        let grabbed = tool
            .grab(&press, &mesh)
            .expect("the corner control point is grabbed");
        // S(0, 0) or H(0, 0), drawn over it: both sit on the ray through the corner.
        let c = tool.pending.get().unwrap();
        assert_eq!((c.1, c.2), (0, 0));
        assert!(FfdTool::displayed(st, c.0, 0, 0) == Some(grabbed));
        // Dragging it moves the mesh near that corner only.
        let start = grabbed;
        for (phase, t) in [
            (DragPhase::Start, 0.0),
            (DragPhase::Move, 0.3),
            (DragPhase::End, 0.5),
        ] {
            let drag = Drag {
                phase,
                pick: None,
                start,
                current: start + DVec3::new(0.0, 0.0, t),
            };
            tool.on_drag(&drag, &mut ctx);
        }
        ctx.doc.end_edit();
        // (Vertices outside the support are evaluated again too: allow for rounding.)
        let moved: Vec<usize> = (0..mesh.vertex_slots())
            .filter(|&i| (ctx.mesh().positions()[i] - mesh.positions()[i]).length() > 1e-9)
            .collect();
        assert!(!moved.is_empty(), "{}", ctx.status.message);
        let (lo, hi) = mesh.bounding_box().unwrap();
        let centre = 0.5 * (lo + hi);
        let near_corner = |p: DVec3| (p.x - corner.x).abs() < (centre.x - corner.x).abs();
        for &i in &moved {
            assert!(
                near_corner(mesh.positions()[i]),
                "vertex {i} far from the corner moved"
            );
        }
        // One undo step for the drag gives the sheet back.
        assert_eq!(ctx.doc.undo().as_deref(), Some("FFD drag"));
        assert_eq!(ctx.mesh().positions(), mesh.positions());
        // A ray well away from every control point grabs nothing.
        let away = ray_towards(eye, DVec3::new(20.0, 20.0, 0.0));
        assert!(tool
            .grab(
                &Press {
                    ray: away,
                    hit: None
                },
                &mesh
            )
            .is_none());
    }
}
