//! Tools: one per editing method, each a [`Tool`] with its parameters in the side panel.
//!
//! The viewer owns the mesh ([`Document`], with undo / redo), the camera, picking and the
//! colour layer; a tool only reacts:
//!
//! - [`Tool::ui`] draws its parameters and buttons in the side panel, every frame;
//! - [`Tool::on_pick`] hears about clicks on the mesh (the viewer ray-casts: the face hit,
//!   the nearest corner, the point) or on empty space;
//! - [`Tool::grab`] hears about every left press in the 3D view (the mouse ray and what
//!   it hit) and decides whether it starts a drag for the tool (otherwise the left button
//!   orbits); by default it grabs the picked vertex when [`Tool::wants_drag`] accepts the
//!   hit, and tools with handles off the mesh (FFD control points) grab along the ray.
//!   [`Tool::on_drag`] then receives the grabbed point moved in the view plane (start,
//!   every move, end);
//! - [`Tool::apply`] is the tool's main action (its *Apply* button, the script's `apply`);
//! - [`Tool::set_parameter`] / [`Tool::parameters`] expose the parameters to scripts;
//!   each tool declares its parameters once, in a table of [`params::Param`]s that also
//!   draws their widgets;
//! - [`Tool::overlay`] adds markers and segments drawn over the mesh;
//! - [`Tool::on_mesh_replaced`] drops state that refers to a mesh that is gone (after
//!   loading a file, undo or redo);
//! - [`Tool::poll`] reports work running on another thread (the hierarchy build of
//!   *Multiresolution*): while it runs the viewer keeps repainting, keeps the mesh and
//!   the history from changing (no picks, tool switches, undo or loading), and a script
//!   waits for it before its next action.
//!
//! Every callback receives a [`ToolContext`]: the document (edits go through
//! [`ToolContext::begin_edit`] / [`ToolContext::positions_mut`] / [`ToolContext::mesh_mut`],
//! which record undo steps; one gesture is one step), the colour layer
//! ([`ToolContext::show_scalar`], [`ToolContext::show_vertex_labels`],
//! [`ToolContext::show_face_labels`]), the status line and the view. The viewer times
//! every callback that changes the mesh and shows it in the status line.
//!
//! To add a method, implement [`Tool`] in a new module and list it in [`default_tools`].

mod bendels_klein;
pub mod curve_editor;
mod edit_support;
mod ffd;
mod inspect;
mod lee;
mod multires;
pub mod params;
mod recipe_steps;
mod submesh;

pub use bendels_klein::{BendelsKlein, BkMode};
pub use ffd::FfdTool;
pub use inspect::Inspect;
pub use lee::{LeeAreaEdit, LeeMode};
pub use multires::{
    frontier_overlay, refreshed_label_layer, Multires, SubMeshLabels, HOST, LABEL_LAYER, SUBMESH,
};
pub use submesh::SubMeshEdit;

use glam::DVec3;
use halfedge::{FaceId, Mesh, VertexId};
use three_d::egui;

use crate::camera::Ray;
use crate::colors::{ColorLayer, Colormap, Display, LabelField, LabelTarget, Rgba, ScalarField};
use crate::document::Document;

/// The tools of the viewer, in selector order. Add new methods here.
pub fn default_tools() -> Vec<Box<dyn Tool>> {
    vec![
        Box::new(Inspect::default()),
        Box::new(Multires::new()),
        Box::new(LeeAreaEdit::new()),
        Box::new(BendelsKlein::default()),
        Box::new(SubMeshEdit::new()),
        Box::new(FfdTool::new()),
    ]
}

/// A picked point on the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pick {
    /// The vertex picked: the corner of the hit face nearest to the hit point (or the
    /// vertex named by a script).
    pub vertex: VertexId,
    /// The face hit (`None` for an isolated vertex picked by index).
    pub face: Option<FaceId>,
    /// The hit point on the surface (the vertex position when picked by index).
    pub point: DVec3,
}

/// A left-button press in the 3D view (or the start of a scripted drag).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Press {
    /// The ray from the eye through the pressed pixel (unit direction).
    pub ray: Ray,
    /// What the ray hit on the mesh, if anything.
    pub hit: Option<Pick>,
}

/// What a tool's background work is doing (see [`Tool::poll`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Background {
    /// Nothing runs (or it just finished well: the tool has updated the status line).
    Idle,
    /// Work is running on another thread.
    Running,
    /// The work just failed: the viewer shows the error and fails a running script.
    Failed(ToolError),
}

/// Phase of a drag gesture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DragPhase {
    /// The button went down on what the tool grabbed (`current == start`).
    Start,
    /// The mouse moved.
    Move,
    /// The button was released (`current` is the final point).
    End,
}

/// A drag of a grabbed point in the view plane: the plane through the point facing the
/// camera, so the point stays under the mouse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drag {
    /// Start, move or end.
    pub phase: DragPhase,
    /// What was picked on the mesh when the drag started (`None` when the tool grabbed
    /// something off the mesh, see [`Tool::grab`]).
    pub pick: Option<Pick>,
    /// Where the dragged point started (what [`Tool::grab`] returned: by default the
    /// picked vertex's position).
    pub start: DVec3,
    /// Where it is now.
    pub current: DVec3,
}

impl Drag {
    /// Total displacement since the start of the drag.
    pub fn delta(&self) -> DVec3 {
        self.current - self.start
    }
}

/// What the camera shows, for tools that work in screen terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewInfo {
    /// Eye position.
    pub eye: DVec3,
    /// Unit viewing direction.
    pub forward: DVec3,
    /// Unit screen-right direction.
    pub right: DVec3,
    /// Unit screen-up direction.
    pub up: DVec3,
    /// Radius of the mesh's bounding sphere.
    pub scene_radius: f64,
}

/// A sphere drawn at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Marker {
    /// Centre.
    pub position: DVec3,
    /// Colour.
    pub color: Rgba,
    /// Size relative to the default marker size (a fraction of the mean edge length).
    pub scale: f32,
}

/// A line segment drawn as a thin cylinder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// One end.
    pub a: DVec3,
    /// The other end.
    pub b: DVec3,
    /// Colour.
    pub color: Rgba,
}

/// Markers and segments a tool draws over the mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overlay {
    /// Spheres at points.
    pub markers: Vec<Marker>,
    /// Segments.
    pub segments: Vec<Segment>,
}

impl Overlay {
    /// Colour of the primary picked point.
    pub const PICK: Rgba = [255, 120, 20, 255];
    /// Colour of secondary points (neighbours, selections).
    pub const SECONDARY: Rgba = [40, 140, 255, 255];

    /// Adds a marker.
    pub fn marker(&mut self, position: DVec3, color: Rgba, scale: f32) {
        self.markers.push(Marker {
            position,
            color,
            scale,
        });
    }

    /// Adds a segment.
    pub fn segment(&mut self, a: DVec3, b: DVec3, color: Rgba) {
        self.segments.push(Segment { a, b, color });
    }
}

/// The status line: the last message and whether it is an error.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Status {
    /// The message.
    pub message: String,
    /// True for an error.
    pub is_error: bool,
}

/// An error reported by a tool; shown in the status line (and fails a script).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolError(pub String);

impl std::fmt::Display for ToolError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl<E: std::error::Error> From<E> for ToolError {
    fn from(e: E) -> Self {
        ToolError(e.to_string())
    }
}

impl ToolError {
    /// An error with a message.
    pub fn new(message: impl Into<String>) -> Self {
        ToolError(message.into())
    }

    /// The error for a parameter the tool does not have.
    pub fn unknown_parameter(tool: &str, name: &str, known: &[&str]) -> Self {
        ToolError(format!(
            "tool {tool:?} has no parameter {name:?} (it has: {})",
            known.join(", ")
        ))
    }

    /// The error for a parameter value of the wrong kind.
    pub fn bad_value(name: &str, expected: &str, value: &serde_json::Value) -> Self {
        ToolError(format!("parameter {name:?} wants {expected}, got {value}"))
    }
}

/// Reads a number parameter.
pub fn number_param(name: &str, value: &serde_json::Value) -> Result<f64, ToolError> {
    value
        .as_f64()
        .ok_or_else(|| ToolError::bad_value(name, "a number", value))
}

/// Reads a boolean parameter.
pub fn bool_param(name: &str, value: &serde_json::Value) -> Result<bool, ToolError> {
    value
        .as_bool()
        .ok_or_else(|| ToolError::bad_value(name, "true or false", value))
}

/// Reads a string parameter.
pub fn string_param<'v>(name: &str, value: &'v serde_json::Value) -> Result<&'v str, ToolError> {
    value
        .as_str()
        .ok_or_else(|| ToolError::bad_value(name, "a string", value))
}

/// The name of `x` in a table of choices `(value, name)` (a tool's modes and operations).
///
/// # Panics
/// If `x` is not in the table (a programming error: every variant is listed).
pub fn choice_name<T: PartialEq + Copy>(table: &[(T, &'static str)], x: T) -> &'static str {
    table.iter().find(|(t, _)| *t == x).expect("listed").1
}

/// Reads a string parameter naming one of the choices of `table` (case-insensitive).
pub fn choice_param<T: Copy>(
    table: &[(T, &'static str)],
    name: &str,
    value: &serde_json::Value,
) -> Result<T, ToolError> {
    let s = string_param(name, value)?;
    table
        .iter()
        .find(|(_, n)| n.eq_ignore_ascii_case(s))
        .map(|(t, _)| *t)
        .ok_or_else(|| {
            let names: Vec<&str> = table.iter().map(|(_, n)| *n).collect();
            ToolError::new(format!("{name} {s:?}: one of {}", names.join(", ")))
        })
}

/// A document with the display and status line a tool context borrows, and a camera
/// looking down −z from 5 units: tools driven without a window (tests, headless scripts).
pub struct Headless {
    /// The document.
    pub doc: Document,
    /// What colours the mesh.
    pub display: Display,
    /// The status line.
    pub status: Status,
}

impl Headless {
    /// Headless tools on `doc`.
    pub fn new(doc: Document) -> Self {
        Self {
            doc,
            display: Display::default(),
            status: Status::default(),
        }
    }

    /// The context a tool callback gets (no pick).
    pub fn ctx(&mut self) -> ToolContext<'_> {
        ToolContext {
            doc: &mut self.doc,
            display: &mut self.display,
            status: &mut self.status,
            view: ViewInfo {
                eye: DVec3::new(0.0, 0.0, 5.0),
                forward: DVec3::NEG_Z,
                right: DVec3::X,
                up: DVec3::Y,
                scene_radius: 1.0,
            },
            pick: None,
        }
    }
}

/// What a tool callback can see and change.
pub struct ToolContext<'a> {
    /// The mesh and its history. Prefer the helper methods below for edits.
    pub doc: &'a mut Document,
    /// What colours the mesh (use the `show_*` methods).
    pub display: &'a mut Display,
    /// The status line.
    pub status: &'a mut Status,
    /// The camera.
    pub view: ViewInfo,
    /// The viewer's current pick, if any.
    pub pick: Option<Pick>,
}

impl ToolContext<'_> {
    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        self.doc.mesh()
    }

    /// Opens an undo step named `label` (a no-op while one is open: one gesture, one step).
    pub fn begin_edit(&mut self, label: &str) {
        self.doc.begin_edit(label);
    }

    /// Opens an undo step that may change the connectivity (stores the whole mesh).
    pub fn begin_topology_edit(&mut self, label: &str) {
        self.doc.begin_topology_edit(label);
    }

    /// Mutable positions (indexed by `vertex_index`), inside an undo step.
    pub fn positions_mut(&mut self) -> &mut [DVec3] {
        self.doc.positions_mut()
    }

    /// The mesh, mutably, inside an undo step that stores the whole mesh.
    pub fn mesh_mut(&mut self) -> &mut Mesh {
        self.doc.mesh_mut()
    }

    /// Colours the mesh by a scalar per vertex slot (NaN: no value) over its range.
    pub fn show_scalar(&mut self, name: &str, values: Vec<f64>, colormap: Colormap) {
        self.display
            .set(ColorLayer::Scalar(ScalarField::new(name, values, colormap)));
    }

    /// Colours the mesh by a label per vertex slot ([`crate::colors::NO_LABEL`]: none);
    /// `legend` names the labels (empty: "label k" for each label in use).
    pub fn show_vertex_labels(&mut self, name: &str, labels: Vec<u32>, legend: Vec<(u32, String)>) {
        self.display.set(ColorLayer::Labels(LabelField {
            name: name.into(),
            target: LabelTarget::Vertices,
            labels,
            legend,
        }));
    }

    /// Colours the mesh by a label per face slot.
    pub fn show_face_labels(&mut self, name: &str, labels: Vec<u32>, legend: Vec<(u32, String)>) {
        self.display.set(ColorLayer::Labels(LabelField {
            name: name.into(),
            target: LabelTarget::Faces,
            labels,
            legend,
        }));
    }

    /// Back to the base colour.
    pub fn clear_colors(&mut self) {
        self.display.set(ColorLayer::None);
    }

    /// Shows a message in the status line.
    pub fn info(&mut self, message: impl Into<String>) {
        *self.status = Status {
            message: message.into(),
            is_error: false,
        };
    }

    /// Shows an error in the status line.
    pub fn error(&mut self, message: impl Into<String>) {
        *self.status = Status {
            message: message.into(),
            is_error: true,
        };
    }
}

/// An interactive tool: one editing method with its parameters (see the module docs).
///
/// Only [`name`](Tool::name), [`description`](Tool::description) and [`ui`](Tool::ui)
/// are required; the other callbacks default to doing nothing.
pub trait Tool {
    /// Name in the tool selector; scripts select tools by it (case-insensitive).
    fn name(&self) -> &str;

    /// One or two sentences under the selector: what the tool does, which paper.
    fn description(&self) -> &str;

    /// Draws the parameters and buttons into the side panel (every frame).
    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>);

    /// A click on the mesh (`Some`) or on empty space (`None`).
    fn on_pick(&mut self, pick: Option<&Pick>, ctx: &mut ToolContext<'_>) {
        let _ = (pick, ctx);
    }

    /// True when a left-button press on `pick` starts a drag for this tool (then
    /// [`on_pick`](Tool::on_pick) and [`on_drag`](Tool::on_drag) follow); false lets the
    /// press orbit the camera. Only asked by the default [`grab`](Tool::grab).
    fn wants_drag(&self, pick: &Pick) -> bool {
        let _ = pick;
        false
    }

    /// A left-button press: returns the point a drag for this tool starts from (the drag
    /// moves it in the plane through it facing the camera), or `None` to let the press
    /// orbit the camera (and click when released in place). The default grabs the picked
    /// vertex when the ray hit the mesh and [`wants_drag`](Tool::wants_drag) accepts the
    /// hit; tools with handles off the surface look along `press.ray` instead.
    fn grab(&self, press: &Press, mesh: &Mesh) -> Option<DVec3> {
        let pick = press.hit.as_ref()?;
        (mesh.is_valid_vertex(pick.vertex) && self.wants_drag(pick))
            .then(|| mesh.position(pick.vertex))
    }

    /// A drag in the view plane (start, moves, end).
    fn on_drag(&mut self, drag: &Drag, ctx: &mut ToolContext<'_>) {
        let _ = (drag, ctx);
    }

    /// The tool's main action (its Apply button; the script action `apply`).
    fn apply(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        let _ = ctx;
        Err(ToolError::new(format!(
            "tool {:?} has no apply action",
            self.name()
        )))
    }

    /// Sets a parameter by name (scripts; the same names as [`parameters`](Tool::parameters)).
    fn set_parameter(
        &mut self,
        name: &str,
        value: &serde_json::Value,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        let _ = (value, ctx);
        Err(ToolError::unknown_parameter(self.name(), name, &[]))
    }

    /// The parameters and their current values.
    fn parameters(&self) -> Vec<(&'static str, serde_json::Value)> {
        Vec::new()
    }

    /// Markers and segments to draw over the mesh.
    fn overlay(&self, mesh: &Mesh, overlay: &mut Overlay) {
        let _ = (mesh, overlay);
    }

    /// The mesh was replaced (file loaded, undo, redo): drop state tied to the old one.
    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        let _ = mesh;
    }

    /// The tool became the active one.
    fn activate(&mut self, ctx: &mut ToolContext<'_>) {
        let _ = ctx;
    }

    /// Another tool became the active one.
    fn deactivate(&mut self, ctx: &mut ToolContext<'_>) {
        let _ = ctx;
    }

    /// Called every frame (for every tool, active or not): checks on work running on
    /// another thread and takes in its result when it is done. While it returns
    /// [`Background::Running`], the viewer keeps the mesh, the history and the active tool
    /// as they are and a script waits before its next action.
    fn poll(&mut self, ctx: &mut ToolContext<'_>) -> Background {
        let _ = ctx;
        Background::Idle
    }
}

/// What the tools' tests share: a document holding a hierarchy at a coarse level.
#[cfg(test)]
pub(crate) mod fixture {
    use super::{Headless, ToolContext};
    use crate::document::Document;
    use glam::DVec3;
    use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
    use halfedge::{generators, Mesh};

    /// A document holding a hierarchy of an icosphere at `level`, and the rest of what a
    /// tool context borrows.
    pub struct Fixture {
        tools: Headless,
        pub input: Mesh,
    }

    impl Fixture {
        pub fn at_level(level: usize) -> Self {
            let input = generators::icosphere(4);
            let h = Hierarchy::build(
                input.clone(),
                &HierarchyOptions::rounds().with_target_faces(150),
            )
            .unwrap();
            assert!(h.coarsest_level() >= 2, "{:?}", h.level_face_counts());
            let mut doc = Document::new(input.clone(), None, None);
            doc.set_hierarchy(h, "build");
            doc.go_to_level(level, "level").unwrap();
            doc.end_edit();
            Self {
                tools: Headless::new(doc),
                input,
            }
        }

        pub fn ctx(&mut self) -> ToolContext<'_> {
            self.tools.ctx()
        }
    }

    /// What a test expects of an input vertex once the hierarchy is refined, by the
    /// index of its ancestor at the edited level.
    pub enum Expect {
        /// At this map of its input position (a part moved rigidly or affinely).
        Lands(glam::DAffine3),
        /// Exactly where the input has it, bit for bit.
        Stays,
        /// Anywhere (the edit's transition).
        Free,
    }

    /// What [`refine_and_land`] saw: vertices expected to land and to stay, and the
    /// largest distance of a landing one from its target.
    pub struct Landing {
        pub landed: usize,
        pub stayed: usize,
        pub worst: f64,
    }

    /// Refines the document's hierarchy from `level` to the input and checks every input
    /// vertex against `expect` of its ancestor: those that should stay did, bit for bit
    /// (asserted), those that should land are measured.
    pub fn refine_and_land(
        ctx: &mut ToolContext<'_>,
        input: &Mesh,
        level: usize,
        expect: impl Fn(usize) -> Expect,
    ) -> Landing {
        let ancestors = ctx.doc.hierarchy().unwrap().ancestors(level).unwrap();
        ctx.doc.go_to_level(0, "levels").unwrap();
        let fine = ctx.mesh();
        let mut seen = Landing {
            landed: 0,
            stayed: 0,
            worst: 0.0,
        };
        for v in input.vertices() {
            let (p, q) = (input.position(v), fine.position(v));
            match expect(ancestors[input.vertex_index(v)] as usize) {
                Expect::Lands(map) => {
                    seen.landed += 1;
                    seen.worst = seen.worst.max(q.distance(map.transform_point3(p)));
                }
                Expect::Stays => {
                    seen.stayed += 1;
                    assert_eq!(bits(&[q]), bits(&[p]), "vertex {v} moved");
                }
                Expect::Free => {}
            }
        }
        seen
    }

    /// Drags `tool` from `start` by `offset`: a start, moves at the inner `fractions`
    /// of the offset, an end at the last, each with `pick` and no error reported.
    pub fn drag_through(
        tool: &mut dyn super::Tool,
        ctx: &mut ToolContext<'_>,
        pick: Option<super::Pick>,
        start: DVec3,
        offset: DVec3,
        fractions: &[f64],
    ) {
        for (k, &fraction) in fractions.iter().enumerate() {
            let phase = if k == 0 {
                super::DragPhase::Start
            } else if k + 1 == fractions.len() {
                super::DragPhase::End
            } else {
                super::DragPhase::Move
            };
            let drag = super::Drag {
                phase,
                pick,
                start,
                current: start + fraction * offset,
            };
            tool.on_drag(&drag, ctx);
            assert!(!ctx.status.is_error, "{}", ctx.status.message);
        }
    }

    pub fn bits(positions: &[DVec3]) -> Vec<[u64; 3]> {
        positions
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect()
    }
}
