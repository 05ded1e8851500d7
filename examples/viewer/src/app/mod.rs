//! The application: one [`App`] holds the document and the tools, and three parts: the
//! scene and its rendering state (camera, renderer, picking), the input state (gesture,
//! viewport, pick) and the script runner (steps, screenshots, measurements), each a
//! struct in a submodule with the `impl App` methods that use it; the panels are a
//! submodule too. It runs one frame at a time (GUI, input, script step, rendering,
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

use halfedge::{generators, Mesh};
use three_d::egui;
use three_d::{ClearState, FrameInput, FrameOutput, GUI};

use crate::camera::Viewport;
use crate::colors::{ColorLayer, Display};
use crate::document::Document;
use crate::format::group;
use crate::image_view::{ImageUi, ImageView};
use crate::script::Step;

mod input;
mod panels;
mod scene;
mod script_runner;

use input::{Gesture, Input};
use scene::Scene;
pub use script_runner::save_png;
use script_runner::ScriptRunner;

use crate::tools::{
    default_tools, refreshed_label_layer, Background, Overlay, Status, Tool, ToolContext,
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

/// Where the mesh was read from and where it will be saved (the File panel's fields).
#[derive(Clone, Debug, Default)]
struct Paths {
    open: String,
    save: String,
    recipe: String,
}

/// Frame counting and timing.
#[derive(Clone, Copy, Debug, Default)]
struct Clock {
    /// Frames rendered so far.
    index: u64,
    /// Smoothed frame time, ms (frames the viewer asked for only).
    ms: Option<f64>,
    /// The last frame asked for the next one without waiting for input.
    last_polled: bool,
}

/// The viewer application (see the module docs): the document and its tools, and three
/// parts of its own, each a struct in a module of its own: the scene (camera, renderer,
/// picking; `app/scene.rs`), the mouse and keyboard (`app/input.rs`) and the script runner
/// (`app/script_runner.rs`); the panels are drawn by `app/panels.rs`.
pub struct App {
    doc: Document,
    tools: Vec<Box<dyn Tool>>,
    active: usize,
    display: Display,
    status: Status,
    last_op: Option<(String, Duration)>,
    paths: Paths,
    clock: Clock,
    /// True while a tool works in the background (see [`Tool::poll`]).
    background: bool,
    /// The 2-D image view, while a PNG is open (it replaces the 3-D view).
    image: Option<ImageUi>,
    scene: Scene,
    input: Input,
    script: ScriptRunner,
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
            paths: Paths::default(),
            clock: Clock::default(),
            background: false,
            image: None,
            scene: Scene::new(context),
            input: Input::default(),
            script: ScriptRunner::new(options),
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
            self.scene.camera.reset(lo, hi);
        }
        self.input.pick = None;
        self.display.set(ColorLayer::None);
        for tool in &mut self.tools {
            tool.on_mesh_replaced(self.doc.mesh());
        }
        self.with_tool(|tool, ctx| tool.activate(ctx));
        let source = self.doc.source().cloned();
        self.paths.open = source
            .as_ref()
            .map_or(String::new(), |p| p.display().to_string());
        self.paths.save = match source {
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
        self.paths.recipe = Path::new(&self.paths.save)
            .with_extension("toml")
            .display()
            .to_string();
    }

    /// Reads a mesh file and makes it the document; a `.png` opens in the image view
    /// instead ([`crate::image_view`]).
    pub fn load(&mut self, path: &Path) -> Result<(), String> {
        let start = Instant::now();
        if crate::image_view::is_png(path) {
            let view = ImageView::open(path).map_err(|e| e.to_string())?;
            let image = ImageUi::new(view);
            self.paths.open = path.display().to_string();
            let stem = path
                .file_stem()
                .map_or("image".into(), |s| s.to_string_lossy().into_owned());
            self.paths.save = path
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
        let (mesh, report, welded) = crate::document::read_mesh(path)?;
        let elapsed = start.elapsed();
        self.doc.replace(mesh, Some(path.to_owned()), Some(report));
        self.image = None;
        self.after_new_mesh();
        self.last_op = Some(("load".into(), elapsed));
        let mut msg = format!("Loaded {}", self.describe_mesh());
        if welded > 0 {
            msg += &format!(
                " ({welded} vertices welded onto others at the same position: the file's \
                 faces were on separate copies of them)"
            );
        }
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

    /// Writes the edits made so far as a recipe (TOML, `multires::recipe::Recipe::write`),
    /// or refuses, saying why: edits without a recipe step (named), edits made before the
    /// hierarchy was built (see [`crate::recipe_log`]).
    pub fn save_recipe(&mut self, path: &Path) -> Result<(), String> {
        if self.image.is_some() {
            return Err("the image view's edits have no recipe steps".into());
        }
        let recipe = self
            .doc
            .recipe_log()
            .recipe()
            .map_err(|e| format!("the recipe cannot be saved: {e}"))?;
        recipe.write(path).map_err(|e| e.to_string())?;
        self.status = Status {
            message: format!(
                "Saved the recipe of {} step(s) to {}",
                recipe.steps.len(),
                path.display()
            ),
            is_error: false,
        };
        Ok(())
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
        let view = self.scene.view_info();
        let mut ctx = ToolContext {
            doc: &mut self.doc,
            display: &mut self.display,
            status: &mut self.status,
            view,
            pick: self.input.pick,
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
                    if self.script.steps.is_some() {
                        let what = self.script.last_step.clone();
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
        self.input.gesture = Gesture::Idle;
        for tool in &mut self.tools {
            tool.on_mesh_replaced(self.doc.mesh());
        }
        if self
            .input
            .pick
            .is_some_and(|p| !self.doc.mesh().is_valid_vertex(p.vertex))
        {
            self.input.pick = None;
        }
    }

    /// Keeps a colour layer of sub-mesh labels in step with the mesh's label attribute,
    /// which level changes, undo and redo change.
    fn refresh_label_layer(&mut self) {
        let labels = self.doc.revision().labels;
        if self.scene.labels_shown == Some(labels) {
            return;
        }
        self.scene.labels_shown = Some(labels);
        if let Some(layer) = refreshed_label_layer(self.display.layer(), self.doc.mesh()) {
            self.display.set(layer);
        }
    }

    /// True while something needs frames without user input.
    fn busy(&self) -> bool {
        self.clock.index <= WARMUP_FRAMES
            || self.background
            || self.script.steps.is_some()
            || self.script.screenshot.is_some()
            || self.input.active()
    }

    /// One frame: script step, GUI, input, scene update, rendering, screenshot.
    pub fn frame(&mut self, mut input: FrameInput, gui: &mut GUI) -> FrameOutput {
        let frame_start = Instant::now();
        self.clock.index += 1;
        self.poll_tools();
        if self.clock.last_polled && self.clock.index > WARMUP_FRAMES {
            let ms = input.elapsed_time;
            self.clock.ms = Some(self.clock.ms.map_or(ms, |f| 0.8 * f + 0.2 * ms));
        }
        if self.script.steps.is_none()
            && self.script.final_screenshot.is_some()
            && self.clock.index > WARMUP_FRAMES
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
            self.input.viewport = Viewport {
                x: central.min.x as f64 * dpr,
                y: window_height - central.max.y as f64 * dpr,
                width: (central.width() as f64 * dpr).max(1.0),
                height: (central.height() as f64 * dpr).max(1.0),
            };
        }
        self.handle_events(&mut input.events, gui.context(), dpr);
        let pointer_down = gui.context().input(|i| i.pointer.any_down());
        if matches!(self.input.gesture, Gesture::Idle) && !pointer_down {
            self.doc.end_edit();
        }

        self.refresh_label_layer();
        let mut overlay = Overlay::default();
        self.tools[self.active].overlay(self.doc.mesh(), &mut overlay);
        self.scene.renderer.sync(
            self.doc.mesh(),
            self.doc.revision(),
            self.display.layer(),
            self.display.revision(),
            self.scene.settings,
        );
        // Glyphs keep about the same size on screen whatever the zoom.
        let glyph = self.scene.glyph_size();
        self.scene.renderer.set_overlay(&overlay, glyph);

        let camera = self
            .scene
            .camera
            .to_three_d(&self.input.viewport, self.scene.renderer.origin());
        let screen = input.screen();
        screen.clear(ClearState::color_and_depth(0.09, 0.10, 0.12, 1.0, 1.0));
        if self.image.is_none() {
            self.scene
                .renderer
                .render(&screen, &camera, self.scene.settings);
        }
        screen
            .write(|| gui.render())
            .expect("the GUI renders into the window");

        if let Some(shot) = &mut self.script.screenshot {
            if shot.frames_left == 0 {
                let shot = self.script.screenshot.take().expect("checked");
                let pixels = screen.read_color::<[u8; 4]>();
                let result = save_png(&shot.path, &pixels, screen.width(), screen.height());
                match result {
                    Ok(()) => println!("screenshot: {}", shot.path.display()),
                    Err(e) if !shot.then_exit && self.script.steps.is_none() => {
                        self.status = Status {
                            message: e,
                            is_error: true,
                        };
                    }
                    Err(e) => {
                        eprintln!("viewer: {e}");
                        if self.script.steps.is_some() || shot.then_exit {
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
        if self.background && !matches!(self.input.gesture, Gesture::Orbit | Gesture::Pan) {
            // Repaint for the progress, but leave the worker the CPU.
            if let Some(rest) = BACKGROUND_FRAME.checked_sub(frame_start.elapsed()) {
                std::thread::sleep(rest);
            }
        }
        self.clock.last_polled = busy;
        FrameOutput {
            exit: false,
            swap_buffers: true,
            wait_next_event: !busy,
        }
    }
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
