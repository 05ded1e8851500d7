//! The application: one [`App`] holds the document, the tools, the camera, picking and
//! the scene, and runs one frame at a time (GUI, input, script step, rendering,
//! screenshot).
//!
//! Mouse in the 3D view: a left press goes to the active tool when it
//! [grabs something](crate::tools::Tool::grab) along the mouse ray (by default: a vertex
//! of the mesh it [wants to drag](crate::tools::Tool::wants_drag)), otherwise a left drag
//! orbits and a left click picks; right or middle drag (or shift + left) pans; the wheel
//! zooms; ctrl/alt + left always orbits. While a tool works in the background
//! ([`Tool::poll`]) the view still orbits, pans and zooms, but nothing picks or edits. Keys: `F` frame, `R` reset the view, `W` wireframe,
//! `L` flat / smooth, `P` or F12 screenshot (`viewer-screenshot-N.png` in the current
//! directory), ctrl+Z undo, ctrl+Y or ctrl+shift+Z redo.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::{DVec2, DVec3};
use halfedge::{generators, Mesh};
use three_d::egui;
use three_d::{ClearState, Event, FrameInput, FrameOutput, Key, MouseButton, GUI};

use crate::camera::{OrbitCamera, Ray, UpAxis, Viewport};
use crate::colors::{legend_ui, ColorLayer, Colormap, Display};
use crate::document::Document;
use crate::format::{format_duration, group};
use crate::image_view::{ImageUi, ImageView, ShapePreset, Transform};
use crate::pick::Bvh;
use crate::render::{RenderSettings, SceneRenderer};
use crate::script::{Action, DragTarget, Shading, Step};
use crate::tools::{
    default_tools, Background, Drag, DragPhase, Overlay, Pick, Press, Status, Tool, ToolContext,
    ViewInfo,
};

/// Frames rendered before a script starts (egui lays out its panels on the first ones).
const WARMUP_FRAMES: u64 = 3;

/// Shortest frame while only background work keeps the viewer repainting, so that the
/// repaints leave the worker most of the CPU.
const BACKGROUND_FRAME: Duration = Duration::from_millis(50);

/// How the application was started.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// Replay these actions, then exit (unless `keep_open`).
    pub script: Option<VecDeque<Step>>,
    /// Write a screenshot here at the end (after the script, if any), then exit.
    pub screenshot: Option<PathBuf>,
    /// Stay open after the script.
    pub keep_open: bool,
}

/// What the mouse is doing in the 3D view.
#[derive(Clone, Copy, Debug)]
enum Gesture {
    Idle,
    /// Left button down, not yet a drag: a click if released in place.
    Pending {
        press: (f64, f64),
        hit: Option<Pick>,
    },
    Orbit,
    Pan,
    /// A tool drag: the grabbed point moves in the plane through `start` facing the camera.
    ToolDrag {
        pick: Option<Pick>,
        start: DVec3,
        normal: DVec3,
        current: DVec3,
    },
}

struct PendingScreenshot {
    path: PathBuf,
    /// Frames to render before reading (lets the GUI settle).
    frames_left: u32,
    then_exit: bool,
}

/// Frame-time statistics for the `measure` action.
struct Measurement {
    samples: Vec<f64>,
    cpu_start: Option<f64>,
}

/// CPU time (user + system, all threads: llvmpipe renders on threads of this process)
/// used by this process so far, in ms; Linux only.
fn process_cpu_ms() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    // Linux reports clock ticks of 1/100 s (USER_HZ) on every common configuration.
    Some((utime + stime) * 10.0)
}

/// The viewer application (see the module docs).
pub struct App {
    doc: Document,
    tools: Vec<Box<dyn Tool>>,
    active: usize,
    display: Display,
    status: Status,
    last_op: Option<(String, Duration)>,
    camera: OrbitCamera,
    renderer: SceneRenderer,
    settings: RenderSettings,
    bvh: Option<Bvh>,
    pick: Option<Pick>,
    gesture: Gesture,
    viewport: Viewport,
    open_path: String,
    save_path: String,
    frame_index: u64,
    frame_ms: Option<f64>,
    last_frame_polled: bool,
    script: Option<VecDeque<Step>>,
    script_failed: bool,
    /// The script step run last, for messages.
    last_step: String,
    /// True while a tool works in the background (see [`Tool::poll`]).
    background: bool,
    keep_open: bool,
    final_screenshot: Option<PathBuf>,
    screenshot: Option<PendingScreenshot>,
    screenshots_taken: u32,
    measurement: Option<Measurement>,
    /// The 2-D image view, while a PNG is open (it replaces the 3-D view).
    image: Option<ImageUi>,
}

impl App {
    /// The application on `doc`, drawing with `context`.
    pub fn new(context: &three_d::Context, doc: Document, options: Options) -> Self {
        let mut app = Self {
            tools: default_tools(),
            active: 0,
            display: Display::default(),
            status: Status::default(),
            last_op: None,
            camera: OrbitCamera::default(),
            renderer: SceneRenderer::new(context),
            settings: RenderSettings::default(),
            bvh: None,
            pick: None,
            gesture: Gesture::Idle,
            viewport: Viewport {
                x: 0.0,
                y: 0.0,
                width: 1.0,
                height: 1.0,
            },
            open_path: String::new(),
            save_path: String::new(),
            frame_index: 0,
            frame_ms: None,
            last_frame_polled: false,
            script: options.script,
            script_failed: false,
            last_step: String::new(),
            background: false,
            keep_open: options.keep_open,
            final_screenshot: options.screenshot,
            screenshot: None,
            screenshots_taken: 0,
            measurement: None,
            image: None,
            doc,
        };
        app.after_new_mesh();
        app.status = Status {
            message: app.describe_mesh(),
            is_error: false,
        };
        app
    }

    /// A one-line summary of the mesh and where it came from.
    fn describe_mesh(&self) -> String {
        let mesh = self.doc.mesh();
        let name = self
            .doc
            .source()
            .and_then(|p| p.file_name())
            .map_or("generated icosphere".into(), |n| {
                n.to_string_lossy().into_owned()
            });
        format!(
            "{name}: {} vertices, {} faces",
            group(mesh.n_vertices()),
            group(mesh.n_faces())
        )
    }

    /// Resets camera, pick, colours and paths for a freshly loaded mesh.
    fn after_new_mesh(&mut self) {
        let mesh = self.doc.mesh();
        if let Some((lo, hi)) = mesh.bounding_box() {
            self.camera.reset(lo, hi);
        }
        self.pick = None;
        self.display.set(ColorLayer::None);
        for tool in &mut self.tools {
            tool.on_mesh_replaced(self.doc.mesh());
        }
        self.with_tool(|tool, ctx| tool.activate(ctx));
        let source = self.doc.source().cloned();
        self.open_path = source
            .as_ref()
            .map_or(String::new(), |p| p.display().to_string());
        self.save_path = match source {
            Some(p) => {
                let stem = p
                    .file_stem()
                    .map_or("mesh".into(), |s| s.to_string_lossy().into_owned());
                p.with_file_name(format!("{stem}-edited.obj"))
                    .display()
                    .to_string()
            }
            None => "edited.obj".into(),
        };
    }

    /// Reads a mesh file and makes it the document; a `.png` opens in the image view
    /// instead ([`crate::image_view`]).
    pub fn load(&mut self, path: &Path) -> Result<(), String> {
        let start = Instant::now();
        if crate::image_view::is_png(path) {
            let view = ImageView::open(path).map_err(|e| e.to_string())?;
            let image = ImageUi::new(view);
            self.open_path = path.display().to_string();
            let stem = path
                .file_stem()
                .map_or("image".into(), |s| s.to_string_lossy().into_owned());
            self.save_path = path
                .with_file_name(format!("{stem}-edited.png"))
                .display()
                .to_string();
            self.last_op = Some(("load".into(), start.elapsed()));
            self.status = Status {
                message: format!("Loaded {}", image.describe()),
                is_error: false,
            };
            self.image = Some(image);
            return Ok(());
        }
        let (mesh, report) = halfedge::io::read(path).map_err(|e| e.to_string())?;
        let elapsed = start.elapsed();
        self.doc.replace(mesh, Some(path.to_owned()), Some(report));
        self.image = None;
        self.after_new_mesh();
        self.last_op = Some(("load".into(), elapsed));
        let mut msg = format!("Loaded {}", self.describe_mesh());
        if report.duplicated_vertices > 0 || report.dropped_faces > 0 {
            msg += &format!(
                " ({} vertices duplicated, {} faces dropped to make it manifold)",
                report.duplicated_vertices, report.dropped_faces
            );
        }
        self.status = Status {
            message: msg,
            is_error: false,
        };
        Ok(())
    }

    /// Writes the mesh (in the image view: the edited picture, as a PNG).
    pub fn save(&mut self, path: &Path) -> Result<(), String> {
        let start = Instant::now();
        if let Some(image) = &self.image {
            image.view.save(path).map_err(|e| e.to_string())?;
            self.last_op = Some(("save".into(), start.elapsed()));
            self.status = Status {
                message: format!("Saved {}", path.display()),
                is_error: false,
            };
            return Ok(());
        }
        crate::save::save(self.doc.mesh(), path).map_err(|e| e.to_string())?;
        self.last_op = Some(("save".into(), start.elapsed()));
        self.status = Status {
            message: format!("Saved {}", path.display()),
            is_error: false,
        };
        Ok(())
    }

    fn view_info(&self) -> ViewInfo {
        let (right, up, forward) = self.camera.basis();
        ViewInfo {
            eye: self.camera.eye(),
            forward,
            right,
            up,
            scene_radius: self.camera.scene_radius,
        }
    }

    /// Runs `f` on the active tool with a context; times it when it changes the mesh.
    fn with_tool<R>(&mut self, f: impl FnOnce(&mut dyn Tool, &mut ToolContext<'_>) -> R) -> R {
        self.with_tool_at(self.active, f)
    }

    /// Runs `f` on tool `index` with a context; times it when it changes the mesh.
    fn with_tool_at<R>(
        &mut self,
        index: usize,
        f: impl FnOnce(&mut dyn Tool, &mut ToolContext<'_>) -> R,
    ) -> R {
        let before = self.doc.revision();
        let start = Instant::now();
        let view = self.view_info();
        let mut ctx = ToolContext {
            doc: &mut self.doc,
            display: &mut self.display,
            status: &mut self.status,
            view,
            pick: self.pick,
        };
        let tool = self.tools[index].as_mut();
        let result = f(tool, &mut ctx);
        if self.doc.revision() != before {
            let label = self
                .doc
                .open_edit()
                .map_or_else(|| self.tools[index].name().to_owned(), str::to_owned);
            self.last_op = Some((label, start.elapsed()));
        }
        result
    }

    /// Polls every tool's background work (see [`Tool::poll`]); a failure shows in the
    /// status line and fails a running script.
    fn poll_tools(&mut self) {
        let mut running = false;
        for i in 0..self.tools.len() {
            match self.with_tool_at(i, |tool, ctx| tool.poll(ctx)) {
                Background::Idle => {}
                Background::Running => running = true,
                Background::Failed(e) => {
                    let message = format!("{}: {e}", self.tools[i].name());
                    if self.script.is_some() {
                        let what = self.last_step.clone();
                        self.fail_script(&what, &message);
                    } else {
                        self.status = Status {
                            message,
                            is_error: true,
                        };
                    }
                }
            }
        }
        self.background = running;
    }

    fn select_tool(&mut self, index: usize) {
        if index == self.active || index >= self.tools.len() {
            return;
        }
        self.doc.end_edit();
        self.with_tool(|tool, ctx| tool.deactivate(ctx));
        self.display.set(ColorLayer::None);
        self.active = index;
        self.with_tool(|tool, ctx| tool.activate(ctx));
    }

    fn find_tool(&self, name: &str) -> Result<usize, String> {
        let lower = name.to_lowercase();
        let names: Vec<String> = self.tools.iter().map(|t| t.name().to_lowercase()).collect();
        if let Some(i) = names.iter().position(|n| *n == lower) {
            return Ok(i);
        }
        let matches: Vec<usize> = (0..names.len())
            .filter(|&i| names[i].starts_with(&lower))
            .collect();
        match matches[..] {
            [i] => Ok(i),
            _ => Err(format!(
                "no single tool named {name:?} (tools: {})",
                self.tools
                    .iter()
                    .map(|t| t.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }

    fn undo(&mut self) -> Option<String> {
        let label = match &mut self.image {
            Some(image) => image.view.undo()?,
            None => {
                let label = self.doc.undo()?;
                self.after_history_step();
                label
            }
        };
        self.status = Status {
            message: format!("Undid {label}"),
            is_error: false,
        };
        Some(label)
    }

    fn redo(&mut self) -> Option<String> {
        let label = match &mut self.image {
            Some(image) => image.view.redo()?,
            None => {
                let label = self.doc.redo()?;
                self.after_history_step();
                label
            }
        };
        self.status = Status {
            message: format!("Redid {label}"),
            is_error: false,
        };
        Some(label)
    }

    fn after_history_step(&mut self) {
        self.gesture = Gesture::Idle;
        for tool in &mut self.tools {
            tool.on_mesh_replaced(self.doc.mesh());
        }
        if self
            .pick
            .is_some_and(|p| !self.doc.mesh().is_valid_vertex(p.vertex))
        {
            self.pick = None;
        }
    }

    /// Brings the picking structure up to date with the mesh (a refit after moves, a
    /// rebuild after a topology change or a new mesh).
    fn bvh(&mut self) {
        match &mut self.bvh {
            Some(bvh) => bvh.update(self.doc.mesh()),
            None => self.bvh = Some(Bvh::build(self.doc.mesh())),
        }
    }

    /// Ray-casts at a pixel of the window.
    fn pick_at(&mut self, px: f64, py: f64) -> Option<Pick> {
        let ray = self.camera.ray(px, py, &self.viewport);
        self.cast(&ray)
    }

    /// What `ray` hits on the mesh.
    fn cast(&mut self, ray: &Ray) -> Option<Pick> {
        self.bvh();
        let bvh = self.bvh.as_ref()?;
        let hit = bvh.intersect(self.doc.mesh(), ray).ok()??;
        Some(Pick {
            vertex: hit.nearest_vertex,
            face: Some(hit.face),
            point: hit.point,
        })
    }

    /// A click: the pick goes to the viewer and the active tool.
    fn click(&mut self, pick: Option<Pick>) {
        self.pick = pick;
        self.with_tool(|tool, ctx| tool.on_pick(pick.as_ref(), ctx));
    }

    /// The press at a pixel of the window: the mouse ray and what it hits.
    fn press_at(&mut self, px: f64, py: f64) -> Press {
        let ray = self.camera.ray(px, py, &self.viewport);
        let hit = self.cast(&ray);
        Press { ray, hit }
    }

    /// The window pixel (origin bottom-left) of a script's screen fraction (origin
    /// top-left of the 3D view).
    fn script_pixel(&self, x: f64, y: f64) -> (f64, f64) {
        let vp = self.viewport;
        (vp.x + x * vp.width, vp.y + (1.0 - y) * vp.height)
    }

    /// Starts a tool drag if the active tool grabs something at `press`.
    fn begin_tool_drag(&mut self, press: Press) -> bool {
        let Some(start) = self.tools[self.active].grab(&press, self.doc.mesh()) else {
            return false;
        };
        let pick = press.hit;
        if pick.is_some() {
            self.click(pick);
        }
        let normal = self.camera.forward();
        self.gesture = Gesture::ToolDrag {
            pick,
            start,
            normal,
            current: start,
        };
        let drag = Drag {
            phase: DragPhase::Start,
            pick,
            start,
            current: start,
        };
        self.with_tool(|tool, ctx| tool.on_drag(&drag, ctx));
        true
    }

    /// Moves the tool drag to `current` (`End` releases it).
    fn tool_drag_to(&mut self, current: DVec3, phase: DragPhase) {
        let Gesture::ToolDrag {
            pick,
            start,
            normal,
            ..
        } = self.gesture
        else {
            return;
        };
        let drag = Drag {
            phase,
            pick,
            start,
            current,
        };
        self.gesture = if phase == DragPhase::End {
            Gesture::Idle
        } else {
            Gesture::ToolDrag {
                pick,
                start,
                normal,
                current,
            }
        };
        self.with_tool(|tool, ctx| tool.on_drag(&drag, ctx));
        if phase == DragPhase::End {
            self.doc.end_edit();
        }
    }

    /// Where the view-plane drag is under the pixel, if the plane is in front.
    fn drag_point_at(&self, px: f64, py: f64) -> Option<DVec3> {
        let Gesture::ToolDrag { start, normal, .. } = self.gesture else {
            return None;
        };
        self.camera
            .ray(px, py, &self.viewport)
            .intersect_plane(start, normal)
    }

    fn frame_mesh(&mut self, reset: bool) {
        if let Some((lo, hi)) = self.doc.mesh().bounding_box() {
            if reset {
                self.camera.reset(lo, hi);
            } else {
                self.camera.frame(lo, hi);
            }
        }
    }

    /// Handles mouse and keyboard events aimed at the 3D view.
    fn handle_events(&mut self, events: &mut [Event], egui_ctx: &egui::Context, dpr: f64) {
        let over_egui = egui_ctx.is_pointer_over_egui() || egui_ctx.egui_is_using_pointer();
        let keyboard_taken = egui_ctx.egui_wants_keyboard_input();
        for event in events.iter_mut() {
            match event {
                Event::MousePress {
                    button,
                    position,
                    modifiers,
                    handled,
                } => {
                    let (px, py) = (position.x as f64, position.y as f64);
                    // The image view takes the mouse through egui.
                    let image = self.image.is_some();
                    if *handled || over_egui || image || !self.viewport.contains(px, py) {
                        continue;
                    }
                    *handled = true;
                    self.gesture = match button {
                        MouseButton::Left if modifiers.shift => Gesture::Pan,
                        MouseButton::Left if modifiers.ctrl || modifiers.alt => Gesture::Orbit,
                        // Nothing may change the mesh while a tool works in the background.
                        MouseButton::Left if self.background => Gesture::Orbit,
                        MouseButton::Left => {
                            let press = self.press_at(px, py);
                            if self.begin_tool_drag(press) {
                                continue;
                            }
                            Gesture::Pending {
                                press: (px, py),
                                hit: press.hit,
                            }
                        }
                        MouseButton::Right | MouseButton::Middle => Gesture::Pan,
                    };
                }
                Event::MouseMotion {
                    delta,
                    position,
                    handled,
                    ..
                } => {
                    let (px, py) = (position.x as f64, position.y as f64);
                    let (dx, dy) = (delta.0 as f64, delta.1 as f64);
                    match self.gesture {
                        Gesture::Idle => continue,
                        Gesture::Pending { press, .. } => {
                            if (px - press.0).hypot(py - press.1) > 4.0 * dpr {
                                self.gesture = Gesture::Orbit;
                                self.camera.orbit(-dx * 0.008, dy * 0.008);
                            }
                        }
                        Gesture::Orbit => self.camera.orbit(-dx * 0.008, dy * 0.008),
                        Gesture::Pan => self.camera.pan(dx * dpr, -dy * dpr, self.viewport.height),
                        Gesture::ToolDrag { .. } => {
                            if let Some(p) = self.drag_point_at(px, py) {
                                self.tool_drag_to(p, DragPhase::Move);
                            }
                        }
                    }
                    *handled = true;
                }
                Event::MouseRelease {
                    position, handled, ..
                } => {
                    let (px, py) = (position.x as f64, position.y as f64);
                    match self.gesture {
                        Gesture::Idle => continue,
                        Gesture::Pending { hit, .. } => self.click(hit),
                        Gesture::ToolDrag { current, .. } => {
                            let p = self.drag_point_at(px, py).unwrap_or(current);
                            self.tool_drag_to(p, DragPhase::End);
                        }
                        Gesture::Orbit | Gesture::Pan => {}
                    }
                    self.gesture = Gesture::Idle;
                    *handled = true;
                }
                Event::MouseWheel {
                    delta,
                    position,
                    handled,
                    ..
                } => {
                    let (px, py) = (position.x as f64, position.y as f64);
                    // The image view takes the mouse through egui.
                    let image = self.image.is_some();
                    if *handled || over_egui || image || !self.viewport.contains(px, py) {
                        continue;
                    }
                    self.camera.zoom((-delta.1 as f64 * 0.004).exp());
                    *handled = true;
                }
                Event::MouseLeave => {
                    // The release may never come: finish what the mouse was doing.
                    if let Gesture::ToolDrag { current, .. } = self.gesture {
                        self.tool_drag_to(current, DragPhase::End);
                    }
                    self.gesture = Gesture::Idle;
                }
                Event::KeyPress {
                    kind,
                    modifiers,
                    handled,
                } => {
                    if *handled || keyboard_taken {
                        continue;
                    }
                    let command = modifiers.ctrl || modifiers.command;
                    if command && matches!(kind, Key::Z | Key::Y) && self.background {
                        self.status = Status {
                            message: "Busy: undo and redo wait for the tool's work to finish"
                                .into(),
                            is_error: true,
                        };
                        *handled = true;
                        continue;
                    }
                    match kind {
                        Key::Z if command && modifiers.shift => {
                            self.redo();
                        }
                        Key::Z if command => {
                            self.undo();
                        }
                        Key::Y if command => {
                            self.redo();
                        }
                        Key::F if !command => self.frame_mesh(false),
                        Key::R if !command => self.frame_mesh(true),
                        Key::W if !command => self.settings.wireframe = !self.settings.wireframe,
                        Key::L if !command => self.settings.flat = !self.settings.flat,
                        // (Not over a screenshot that a script is waiting for.)
                        Key::P | Key::F12 if !command && self.screenshot.is_none() => {
                            self.screenshots_taken += 1;
                            let path = PathBuf::from(format!(
                                "viewer-screenshot-{}.png",
                                self.screenshots_taken
                            ));
                            self.status = Status {
                                message: format!("Screenshot {}", path.display()),
                                is_error: false,
                            };
                            self.screenshot = Some(PendingScreenshot {
                                path,
                                frames_left: 1,
                                then_exit: false,
                            });
                        }
                        _ => continue,
                    }
                    *handled = true;
                }
                _ => {}
            }
        }
    }

    /// The side panel, the status bar and the legend; returns the rectangle left for the
    /// 3D view (points).
    fn ui(&mut self, ui: &mut egui::Ui) -> egui::Rect {
        let frame_ms = self.frame_ms;
        egui::Panel::bottom("status")
            .resizable(false)
            .show_inside(ui, |ui| {
                // Right-hand figures first; the message gets the rest of the line and is
                // cut short (full text on hover) rather than running under them.
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    let mesh = self.doc.mesh();
                    match &self.image {
                        Some(image) => {
                            let s = image.view.source();
                            ui.weak(format!("{}×{} px", s.width(), s.height()))
                        }
                        None => ui.weak(format!(
                            "{} V · {} F",
                            group(mesh.n_vertices()),
                            group(mesh.n_faces())
                        )),
                    };
                    if let Some(ms) = frame_ms {
                        ui.weak(format!("frame {ms:.0} ms ·"));
                    }
                    if let Some((label, d)) = &self.last_op {
                        ui.label(format!("{label}: {} ·", format_duration(*d)));
                    }
                    ui.with_layout(egui::Layout::left_to_right(egui::Align::Center), |ui| {
                        let mut text = egui::RichText::new(&self.status.message);
                        if self.status.is_error {
                            text = text.color(egui::Color32::from_rgb(255, 110, 100));
                        }
                        ui.add(egui::Label::new(text).truncate())
                            .on_hover_text(&self.status.message);
                    });
                });
            });
        egui::Panel::left("side")
            .resizable(true)
            .default_size(310.0)
            .show_inside(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.side_panel(ui));
            });
        let central = ui.available_rect_before_wrap();
        if let Some(image) = &mut self.image {
            image.central(ui, central, &mut self.status);
        }
        if self.display.layer() != &ColorLayer::None {
            egui::Area::new(egui::Id::new("legend"))
                .anchor(egui::Align2::RIGHT_BOTTOM, egui::vec2(-14.0, -14.0))
                .constrain_to(central)
                .show(ui.ctx(), |ui| {
                    egui::Frame::popup(ui.style()).show(ui, |ui| {
                        ui.set_max_width(240.0);
                        legend_ui(ui, self.display.layer());
                    });
                });
        }
        central
    }

    fn side_panel(&mut self, ui: &mut egui::Ui) {
        ui.add_space(6.0);
        ui.heading("multires viewer");
        match &self.image {
            Some(image) => ui.weak(image.describe()),
            None => ui.weak(self.describe_mesh()),
        };
        ui.add_space(4.0);

        // Nothing may change the mesh or the history while a tool works in the background.
        let busy = self.background;
        egui::CollapsingHeader::new("File")
            .default_open(true)
            .show(ui, |ui| {
                if busy {
                    ui.disable();
                }
                let open = ui.horizontal(|ui| {
                    let field = ui.add(
                        egui::TextEdit::singleline(&mut self.open_path)
                            .hint_text("path to .obj / .ply / .png")
                            .desired_width(200.0),
                    );
                    let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    ui.button("Open").clicked() || enter
                });
                if open.inner {
                    let path = PathBuf::from(self.open_path.trim());
                    if let Err(e) = self.load(&path) {
                        self.status = Status {
                            message: format!("Open failed: {e}"),
                            is_error: true,
                        };
                    }
                }
                let save = ui.horizontal(|ui| {
                    ui.add(
                        egui::TextEdit::singleline(&mut self.save_path)
                            .hint_text("path to .obj / .png")
                            .desired_width(200.0),
                    );
                    ui.button("Save").clicked()
                });
                if save.inner {
                    let path = PathBuf::from(self.save_path.trim());
                    if let Err(e) = self.save(&path) {
                        self.status = Status {
                            message: format!("Save failed: {e}"),
                            is_error: true,
                        };
                    }
                }
                if let Some(r) = self.doc.build_report() {
                    if r.duplicated_vertices + r.dropped_faces + r.dropped_triangles > 0 {
                        ui.weak(format!(
                            "Repairs on reading: {} vertices duplicated, {} faces dropped, \
                             {} triangles dropped",
                            r.duplicated_vertices, r.dropped_faces, r.dropped_triangles
                        ));
                    }
                    if r.unreferenced_vertices > 0 {
                        ui.weak(format!(
                            "{} unreferenced vertices kept",
                            group(r.unreferenced_vertices)
                        ));
                    }
                }
            });

        if let Some(image) = &mut self.image {
            if image.panel(ui, &mut self.status) {
                self.image = None;
                // The mesh is written as OBJ.
                self.save_path = Path::new(self.save_path.trim())
                    .with_extension("obj")
                    .display()
                    .to_string();
                self.status = Status {
                    message: self.describe_mesh(),
                    is_error: false,
                };
            }
            return;
        }

        egui::CollapsingHeader::new("View")
            .default_open(true)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.label("Shading");
                    ui.selectable_value(&mut self.settings.flat, false, "smooth");
                    ui.selectable_value(&mut self.settings.flat, true, "flat");
                });
                ui.checkbox(&mut self.settings.wireframe, "Wireframe  (W)");
                ui.horizontal(|ui| {
                    ui.label("Up axis");
                    ui.selectable_value(&mut self.camera.up_axis, UpAxis::Y, "Y");
                    ui.selectable_value(&mut self.camera.up_axis, UpAxis::Z, "Z");
                });
                ui.horizontal(|ui| {
                    if ui.button("Frame  (F)").clicked() {
                        self.frame_mesh(false);
                    }
                    if ui.button("Reset view  (R)").clicked() {
                        self.frame_mesh(true);
                    }
                });
            });

        egui::CollapsingHeader::new("Tool")
            .default_open(true)
            .show(ui, |ui| {
                let mut chosen = self.active;
                ui.add_enabled_ui(!busy, |ui| {
                    for (i, tool) in self.tools.iter().enumerate() {
                        ui.radio_value(&mut chosen, i, tool.name());
                    }
                });
                if chosen != self.active {
                    self.select_tool(chosen);
                }
                ui.separator();
                ui.weak(self.tools[self.active].description());
                ui.add_space(4.0);
                self.with_tool(|tool, ctx| tool.ui(ui, ctx));
            });

        egui::CollapsingHeader::new("Colours")
            .default_open(true)
            .show(ui, |ui| match self.display.layer() {
                ColorLayer::None => {
                    ui.weak("Base colour (tools colour the mesh by their data).");
                }
                ColorLayer::Scalar(field) => {
                    let mut map = field.colormap;
                    ui.horizontal(|ui| {
                        ui.label("Colour map");
                        egui::ComboBox::from_id_salt("colormap")
                            .selected_text(map.name())
                            .show_ui(ui, |ui| {
                                for m in Colormap::ALL {
                                    ui.selectable_value(&mut map, m, m.name());
                                }
                            });
                    });
                    if map != field.colormap {
                        if let ColorLayer::Scalar(f) = self.display.layer_mut() {
                            f.colormap = map;
                        }
                    }
                    if ui.button("Clear colours").clicked() {
                        self.display.set(ColorLayer::None);
                    }
                }
                ColorLayer::Labels(_) => {
                    if ui.button("Clear colours").clicked() {
                        self.display.set(ColorLayer::None);
                    }
                }
            });

        egui::CollapsingHeader::new("History")
            .default_open(true)
            .show(ui, |ui| {
                if busy {
                    ui.disable();
                }
                ui.horizontal(|ui| {
                    let undo = ui.add_enabled(self.doc.undo_len() > 0, egui::Button::new("⟲ Undo"));
                    let redo = ui.add_enabled(self.doc.redo_len() > 0, egui::Button::new("⟳ Redo"));
                    if undo.clicked() {
                        self.undo();
                    }
                    if redo.clicked() {
                        self.redo();
                    }
                });
                let labels: Vec<&str> = self.doc.undo_labels().collect();
                let shown = labels.len().min(6);
                for label in labels[labels.len() - shown..].iter().rev() {
                    ui.label(egui::RichText::new(*label).small());
                }
                if labels.len() > shown {
                    ui.weak(format!("… {} older", labels.len() - shown));
                }
            });

        egui::CollapsingHeader::new("Controls")
            .default_open(false)
            .show(ui, |ui| {
                for line in [
                    "Left drag: orbit (on the mesh: the tool's drag, if it has one)",
                    "Left click: pick",
                    "Right / middle drag, shift + left: pan",
                    "Wheel: zoom",
                    "F: frame · R: reset view · W: wireframe · L: flat / smooth",
                    "P or F12: screenshot (viewer-screenshot-N.png)",
                    "Ctrl+Z: undo · Ctrl+Y, Ctrl+Shift+Z: redo",
                ] {
                    ui.label(egui::RichText::new(line).small());
                }
            });
    }

    /// Runs one script step; `Err` fails the script.
    fn run_step(&mut self, step: Step, frame: &FrameInput) -> Result<(), String> {
        match step {
            Step::Idle => Ok(()),
            Step::MeasureFrame { remaining } => {
                self.camera.orbit(0.5f64.to_radians(), 0.0);
                let m = self.measurement.get_or_insert_with(|| Measurement {
                    samples: Vec::new(),
                    cpu_start: process_cpu_ms(),
                });
                m.samples.push(frame.elapsed_time);
                if remaining == 0 {
                    let m = self.measurement.take().expect("just inserted");
                    print_measurement(&m, self.renderer.triangle_count(), &self.viewport);
                }
                Ok(())
            }
            Step::DragBegin {
                at: Some((x, y)), ..
            } => {
                let (px, py) = self.script_pixel(x, y);
                let press = self.press_at(px, py);
                if self.begin_tool_drag(press) {
                    Ok(())
                } else {
                    Err(format!(
                        "drag: tool {:?} grabs nothing at ({x}, {y})",
                        self.tools[self.active].name()
                    ))
                }
            }
            Step::DragBegin { at: None, .. } => {
                let pick = self
                    .pick
                    .ok_or("drag: nothing is picked (use pick_vertex, pick_face or pick_screen)")?;
                // The press a click on the picked point would make.
                let origin = self.camera.eye();
                let direction = (pick.point - origin)
                    .try_normalize()
                    .ok_or("drag: the picked point is at the eye")?;
                let press = Press {
                    ray: Ray { origin, direction },
                    hit: Some(pick),
                };
                if self.begin_tool_drag(press) {
                    Ok(())
                } else {
                    Err(format!(
                        "drag: tool {:?} does not drag",
                        self.tools[self.active].name()
                    ))
                }
            }
            Step::DragTo(target) => {
                let Gesture::ToolDrag { start, normal, .. } = self.gesture else {
                    return Err("drag: no drag in progress".into());
                };
                let p = match target {
                    DragTarget::World(v) => start + v,
                    DragTarget::Screen(dx, dy) => {
                        let (sx, sy, _) = self
                            .camera
                            .project(start, &self.viewport)
                            .ok_or("drag_screen: the picked vertex is behind the camera")?;
                        self.camera
                            .ray(sx + dx, sy - dy, &self.viewport)
                            .intersect_plane(start, normal)
                            .ok_or("drag_screen: the drag plane is not in view")?
                    }
                };
                self.tool_drag_to(p, DragPhase::Move);
                Ok(())
            }
            Step::DragEnd => {
                let Gesture::ToolDrag { current, .. } = self.gesture else {
                    return Err("drag: no drag in progress".into());
                };
                self.tool_drag_to(current, DragPhase::End);
                Ok(())
            }
            Step::Action { action, .. } => self.run_action(action),
        }
    }

    /// The image view for an `image_*` action, or the error that no image is open.
    fn image_for(&mut self, action: &str) -> Result<&mut ImageUi, String> {
        self.image
            .as_mut()
            .ok_or_else(|| format!("{action}: no image is open (load a .png first)"))
    }

    fn run_action(&mut self, action: Action) -> Result<(), String> {
        let action_name = action.name();
        match action {
            Action::Load { path } => self.load(&path),
            Action::Save { path } => self.save(&path),
            Action::Screenshot { path } => {
                self.screenshot = Some(PendingScreenshot {
                    path,
                    frames_left: 1,
                    then_exit: false,
                });
                Ok(())
            }
            Action::Orbit { yaw, pitch } => {
                self.camera.orbit(yaw.to_radians(), pitch.to_radians());
                Ok(())
            }
            Action::Zoom { factor } => {
                if !(factor > 0.0 && factor.is_finite()) {
                    return Err(format!("zoom: factor {factor} must be positive"));
                }
                self.camera.zoom(factor);
                Ok(())
            }
            Action::Pan { dx, dy } => {
                self.camera.pan(dx, -dy, self.viewport.height);
                Ok(())
            }
            Action::Frame => {
                self.frame_mesh(false);
                Ok(())
            }
            Action::ResetView => {
                self.frame_mesh(true);
                Ok(())
            }
            Action::View {
                shading,
                wireframe,
                up,
            } => {
                if let Some(s) = shading {
                    self.settings.flat = s == Shading::Flat;
                }
                if let Some(w) = wireframe {
                    self.settings.wireframe = w;
                }
                if let Some(u) = up {
                    self.camera.up_axis = u;
                }
                Ok(())
            }
            Action::SelectTool { tool } => {
                let i = self.find_tool(&tool)?;
                self.select_tool(i);
                Ok(())
            }
            Action::Set { param, value } => {
                let result = self.with_tool(|tool, ctx| tool.set_parameter(&param, &value, ctx));
                self.doc.end_edit();
                result.map_err(|e| e.to_string())
            }
            Action::PickVertex { index } => {
                let mesh = self.doc.mesh();
                let v = mesh.vertex_at(index).ok_or_else(|| {
                    format!(
                        "pick_vertex: no vertex {index} (the mesh has {} slots)",
                        mesh.vertex_slots()
                    )
                })?;
                let pick = Pick {
                    vertex: v,
                    face: mesh.adjacent_faces(v).next(),
                    point: mesh.position(v),
                };
                self.click(Some(pick));
                Ok(())
            }
            Action::PickFace { index } => {
                let mesh = self.doc.mesh();
                let f = mesh.face_at(index).ok_or_else(|| {
                    format!(
                        "pick_face: no face {index} (the mesh has {} slots)",
                        mesh.face_slots()
                    )
                })?;
                let pick = Pick {
                    vertex: mesh.triangle(f)[0],
                    face: Some(f),
                    point: mesh.face_centroid(f),
                };
                self.click(Some(pick));
                Ok(())
            }
            Action::PickScreen { x, y } => {
                let (px, py) = self.script_pixel(x, y);
                let hit = self.pick_at(px, py);
                self.click(hit);
                if hit.is_none() {
                    println!("pick_screen ({x}, {y}): nothing under this point");
                }
                Ok(())
            }
            Action::Apply => {
                let result = self.with_tool(|tool, ctx| tool.apply(ctx));
                self.doc.end_edit();
                result.map_err(|e| e.to_string())
            }
            Action::Undo => self
                .undo()
                .map(|_| ())
                .ok_or_else(|| "undo: nothing to undo".into()),
            Action::Redo => self
                .redo()
                .map(|_| ())
                .ok_or_else(|| "redo: nothing to redo".into()),
            Action::ClearColors => {
                self.display.set(ColorLayer::None);
                Ok(())
            }
            Action::ImageHandle { points } => {
                let image = self.image_for(action_name)?;
                let polygon = points.iter().map(|&p| DVec2::from_array(p)).collect();
                image.view.set_handle(polygon).map_err(|e| e.to_string())
            }
            Action::ImageFixed { points } => {
                let image = self.image_for(action_name)?;
                let polygon = points.map(|p| p.iter().map(|&p| DVec2::from_array(p)).collect());
                image.view.set_fixed(polygon).map_err(|e| e.to_string())
            }
            Action::ImageTransform {
                translate,
                rotate,
                scale,
            } => {
                let image = self.image_for(action_name)?;
                let result = image.view.set_transform(Transform {
                    translate: DVec2::from_array(translate),
                    rotate,
                    scale,
                });
                image.view.commit();
                result.map_err(|e| e.to_string())
            }
            Action::ImageDrag { dx, dy, steps } => {
                let image = self.image_for(action_name)?;
                image
                    .drag_by(DVec2::new(dx, dy), steps)
                    .map_err(|e| e.to_string())
            }
            Action::ImageOptions { shape, grid_step } => {
                let image = self.image_for(action_name)?;
                if let Some(name) = shape {
                    let preset = ShapePreset::parse(&name).map_err(|e| e.to_string())?;
                    image.view.set_shape(preset).map_err(|e| e.to_string())?;
                }
                if let Some(step) = grid_step {
                    image.view.set_grid_step(step).map_err(|e| e.to_string())?;
                }
                Ok(())
            }
            Action::Quit => {
                if let Some(s) = &mut self.script {
                    s.clear();
                }
                Ok(())
            }
            Action::Drag { .. }
            | Action::DragScreen { .. }
            | Action::Wait { .. }
            | Action::Measure { .. } => Err(format!(
                "{}: internal error, this action should have been expanded into steps",
                action.name()
            )),
        }
    }

    /// Advances the script by one step (when it is its turn: after the warm-up, the
    /// screenshot of the previous step, and the background work it started).
    fn script_tick(&mut self, frame: &FrameInput) {
        if self.frame_index <= WARMUP_FRAMES
            || self.screenshot.is_some()
            || self.script_failed
            || self.background
        {
            return;
        }
        let Some(script) = &mut self.script else {
            return;
        };
        let Some(step) = script.pop_front() else {
            self.script = None;
            self.finish_script();
            return;
        };
        let what = match &step {
            Step::Action { index, action } => format!("action {index} ({})", action.name()),
            Step::DragBegin { index, .. } => format!("action {index} (drag)"),
            _ => "drag".into(),
        };
        if let Err(e) = self.run_step(step, frame) {
            self.fail_script(&what, &e);
        }
        self.last_step = what;
        // Work the step started in the background holds the next step back.
        self.poll_tools();
    }

    /// Stops the script at `what` (exits with status 1 unless kept open).
    fn fail_script(&mut self, what: &str, error: &str) {
        eprintln!("viewer: script failed at {what}: {error}");
        self.script_failed = true;
        self.status = Status {
            message: format!("Script failed at {what}: {error}"),
            is_error: true,
        };
        if !self.keep_open {
            std::process::exit(1);
        }
    }

    fn finish_script(&mut self) {
        if let Some(path) = self.final_screenshot.take() {
            self.screenshot = Some(PendingScreenshot {
                path,
                frames_left: 1,
                then_exit: !self.keep_open,
            });
        } else if !self.keep_open {
            std::process::exit(0);
        }
    }

    /// True while something needs frames without user input.
    fn busy(&self) -> bool {
        self.frame_index <= WARMUP_FRAMES
            || self.background
            || self.script.is_some()
            || self.screenshot.is_some()
            || !matches!(self.gesture, Gesture::Idle)
    }

    /// One frame: script step, GUI, input, scene update, rendering, screenshot.
    pub fn frame(&mut self, mut input: FrameInput, gui: &mut GUI) -> FrameOutput {
        let frame_start = Instant::now();
        self.frame_index += 1;
        self.poll_tools();
        if self.last_frame_polled && self.frame_index > WARMUP_FRAMES {
            let ms = input.elapsed_time;
            self.frame_ms = Some(self.frame_ms.map_or(ms, |f| 0.8 * f + 0.2 * ms));
        }
        if self.script.is_none()
            && self.final_screenshot.is_some()
            && self.frame_index > WARMUP_FRAMES
        {
            self.finish_script();
        }
        self.script_tick(&input);

        let dpr = input.device_pixel_ratio as f64;
        let mut central = egui::Rect::NOTHING;
        gui.update(
            &mut input.events,
            input.accumulated_time,
            input.viewport,
            input.device_pixel_ratio,
            |ui| central = self.ui(ui),
        );
        // A build started from the panel holds the mouse back from this frame on.
        self.poll_tools();
        let window_height = input.viewport.height as f64;
        if central.is_positive() {
            self.viewport = Viewport {
                x: central.min.x as f64 * dpr,
                y: window_height - central.max.y as f64 * dpr,
                width: (central.width() as f64 * dpr).max(1.0),
                height: (central.height() as f64 * dpr).max(1.0),
            };
        }
        self.handle_events(&mut input.events, gui.context(), dpr);
        let pointer_down = gui.context().input(|i| i.pointer.any_down());
        if matches!(self.gesture, Gesture::Idle) && !pointer_down {
            self.doc.end_edit();
        }

        let mut overlay = Overlay::default();
        self.tools[self.active].overlay(self.doc.mesh(), &mut overlay);
        self.renderer.sync(
            self.doc.mesh(),
            self.doc.revision(),
            self.display.layer(),
            self.display.revision(),
            self.settings,
        );
        // Glyphs keep about the same size on screen whatever the zoom.
        let glyph = 0.006 * self.camera.distance * (0.5 * self.camera.fov_y).tan() / 0.315;
        self.renderer.set_overlay(&overlay, glyph);

        let camera = self
            .camera
            .to_three_d(&self.viewport, self.renderer.origin());
        let screen = input.screen();
        screen.clear(ClearState::color_and_depth(0.09, 0.10, 0.12, 1.0, 1.0));
        if self.image.is_none() {
            self.renderer.render(&screen, &camera, self.settings);
        }
        screen
            .write(|| gui.render())
            .expect("the GUI renders into the window");

        if let Some(shot) = &mut self.screenshot {
            if shot.frames_left == 0 {
                let shot = self.screenshot.take().expect("checked");
                let pixels = screen.read_color::<[u8; 4]>();
                let result = save_png(&shot.path, &pixels, screen.width(), screen.height());
                match result {
                    Ok(()) => println!("screenshot: {}", shot.path.display()),
                    Err(e) if !shot.then_exit && self.script.is_none() => {
                        self.status = Status {
                            message: e,
                            is_error: true,
                        };
                    }
                    Err(e) => {
                        eprintln!("viewer: {e}");
                        if self.script.is_some() || shot.then_exit {
                            std::process::exit(1);
                        }
                    }
                }
                if shot.then_exit {
                    std::process::exit(0);
                }
            } else {
                shot.frames_left -= 1;
            }
        }

        let busy = self.busy();
        if self.background && !matches!(self.gesture, Gesture::Orbit | Gesture::Pan) {
            // Repaint for the progress, but leave the worker the CPU.
            if let Some(rest) = BACKGROUND_FRAME.checked_sub(frame_start.elapsed()) {
                std::thread::sleep(rest);
            }
        }
        self.last_frame_polled = busy;
        FrameOutput {
            exit: false,
            swap_buffers: true,
            wait_next_event: !busy,
        }
    }
}

/// Writes RGBA pixels as read by `three-d` (rows top-down: it flips OpenGL's order) as an
/// opaque PNG.
pub fn save_png(path: &Path, pixels: &[[u8; 4]], width: u32, height: u32) -> Result<(), String> {
    let (w, h) = (width as usize, height as usize);
    if pixels.len() != w * h {
        return Err(format!(
            "screenshot: read {} pixels for a {width}×{height} window",
            pixels.len()
        ));
    }
    let data: Vec<u8> = pixels
        .iter()
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    image::save_buffer(path, &data, width, height, image::ColorType::Rgba8)
        .map_err(|e| format!("{}: {e}", path.display()))
}

fn print_measurement(m: &Measurement, triangles: usize, viewport: &Viewport) {
    let mut s = m.samples.clone();
    s.sort_by(f64::total_cmp);
    let n = s.len().max(1);
    let mean = s.iter().sum::<f64>() / n as f64;
    let median = s.get(n / 2).copied().unwrap_or(0.0);
    let p90 = s.get((n * 9) / 10).copied().unwrap_or(0.0);
    let cpu = match (m.cpu_start, process_cpu_ms()) {
        (Some(a), Some(b)) => format!(", CPU {:.1} ms per frame", (b - a) / n as f64),
        _ => String::new(),
    };
    println!(
        "measure: {} frames, {} triangles, view {}x{}: mean {mean:.1} ms, median {median:.1} ms, \
         p90 {p90:.1} ms ({:.1} fps){cpu}",
        s.len(),
        triangles,
        viewport.width.round(),
        viewport.height.round(),
        1000.0 / mean.max(1e-9)
    );
}

/// The mesh shown when no file is given: the first `.obj` / `.ply` in the workspace's
/// `data/` folder (by name), else an icosphere.
pub fn default_mesh() -> (Mesh, Option<PathBuf>) {
    let roots = [
        PathBuf::from("data"),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data"),
    ];
    for dir in roots {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.extension()
                    .and_then(|e| e.to_str())
                    .is_some_and(|e| e.eq_ignore_ascii_case("obj") || e.eq_ignore_ascii_case("ply"))
            })
            .collect();
        files.sort();
        for file in files {
            if let Ok((mesh, _)) = halfedge::io::read(&file) {
                return (mesh, Some(file));
            }
        }
    }
    (generators::icosphere(4), None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_keeps_rows_and_is_opaque() {
        let dir = std::env::temp_dir().join(format!("viewer-png-{}", std::process::id()));
        let path = dir.join("x.png");
        // 2×2: top row blue, bottom row red.
        let pixels = [
            [0, 0, 255, 0],
            [0, 0, 255, 0],
            [255, 0, 0, 0],
            [255, 0, 0, 0],
        ];
        save_png(&path, &pixels, 2, 2).unwrap();
        let img = image::open(&path).unwrap().to_rgba8();
        assert_eq!(img.get_pixel(0, 0).0, [0, 0, 255, 255]);
        assert_eq!(img.get_pixel(1, 1).0, [255, 0, 0, 255]);
        assert!(save_png(&path, &pixels[..3], 2, 2).is_err());
        std::fs::remove_dir_all(&dir).ok();
    }
}
