//! The script runner: [`ScriptRunner`] holds the steps left, what failed, the screenshots
//! and the frame-time measurement; the `impl App` below runs one step per frame when it
//! is the script's turn (see [`crate::script`] for the actions).

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use glam::DVec2;
use three_d::FrameInput;

use crate::camera::{Ray, Viewport};
use crate::colors::ColorLayer;
use crate::image_view::{ImageUi, ShapePreset, Transform};
use crate::script::{Action, DragTarget, Shading, Step};
use crate::tools::{DragPhase, Pick, Press, Status};

use super::input::Gesture;
use super::{App, Options, WARMUP_FRAMES};

/// The state of a script run (and of screenshots, which the keyboard asks for too).
pub(super) struct ScriptRunner {
    /// The steps left; `None` when no script runs.
    pub(super) steps: Option<VecDeque<Step>>,
    /// A step failed (the viewer stays open only with `keep_open`).
    pub(super) failed: bool,
    /// The script step run last, for messages.
    pub(super) last_step: String,
    /// Stay open after the script.
    pub(super) keep_open: bool,
    /// The screenshot to take at the end.
    pub(super) final_screenshot: Option<PathBuf>,
    /// A screenshot waiting for the GUI to settle.
    pub(super) screenshot: Option<PendingScreenshot>,
    /// Screenshots taken with the keyboard (for their names).
    pub(super) screenshots_taken: u32,
    /// The `measure` action under way.
    pub(super) measurement: Option<Measurement>,
}

impl ScriptRunner {
    /// The runner of `options`' script (if any).
    pub(super) fn new(options: Options) -> Self {
        Self {
            steps: options.script,
            failed: false,
            last_step: String::new(),
            keep_open: options.keep_open,
            final_screenshot: options.screenshot,
            screenshot: None,
            screenshots_taken: 0,
            measurement: None,
        }
    }

    /// True when the next step may run at frame `frame_index`: after the warm-up, not
    /// over a pending screenshot, not after a failure, not while background work runs.
    pub(super) fn ready(&self, frame_index: u64, background: bool) -> bool {
        frame_index > WARMUP_FRAMES
            && self.screenshot.is_none()
            && !self.failed
            && !background
            && self.steps.is_some()
    }
}

/// A screenshot to take once the GUI has settled.
pub(super) struct PendingScreenshot {
    /// Where to write it.
    pub(super) path: PathBuf,
    /// Frames to render before reading (lets the GUI settle).
    pub(super) frames_left: u32,
    /// Exit after writing it.
    pub(super) then_exit: bool,
}

/// Frame-time statistics for the `measure` action.
pub(super) struct Measurement {
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

/// Prints the frame-time summary of `m`.
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

impl App {
    /// Runs one script step; `Err` fails the script.
    pub(super) fn run_step(&mut self, step: Step, frame: &FrameInput) -> Result<(), String> {
        match step {
            Step::Idle => Ok(()),
            Step::MeasureFrame { remaining } => {
                self.scene.camera.orbit(0.5f64.to_radians(), 0.0);
                let m = self.script.measurement.get_or_insert_with(|| Measurement {
                    samples: Vec::new(),
                    cpu_start: process_cpu_ms(),
                });
                m.samples.push(frame.elapsed_time);
                if remaining == 0 {
                    let m = self.script.measurement.take().expect("just inserted");
                    print_measurement(
                        &m,
                        self.scene.renderer.triangle_count(),
                        &self.input.viewport,
                    );
                }
                Ok(())
            }
            Step::DragBegin {
                at: Some((x, y)), ..
            } => {
                let (px, py) = self.input.script_pixel(x, y);
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
                    .input
                    .pick
                    .ok_or("drag: nothing is picked (use pick_vertex, pick_face or pick_screen)")?;
                // The press a click on the picked point would make.
                let origin = self.scene.camera.eye();
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
                let Gesture::ToolDrag { start, normal, .. } = self.input.gesture else {
                    return Err("drag: no drag in progress".into());
                };
                let p = match target {
                    DragTarget::World(v) => start + v,
                    DragTarget::Screen(dx, dy) => {
                        let (sx, sy, _) = self
                            .scene
                            .camera
                            .project(start, &self.input.viewport)
                            .ok_or("drag_screen: the picked vertex is behind the camera")?;
                        self.scene
                            .camera
                            .ray(sx + dx, sy - dy, &self.input.viewport)
                            .intersect_plane(start, normal)
                            .ok_or("drag_screen: the drag plane is not in view")?
                    }
                };
                self.tool_drag_to(p, DragPhase::Move);
                Ok(())
            }
            Step::DragEnd => {
                let Gesture::ToolDrag { current, .. } = self.input.gesture else {
                    return Err("drag: no drag in progress".into());
                };
                self.tool_drag_to(current, DragPhase::End);
                Ok(())
            }
            Step::Action { action, .. } => self.run_action(action),
        }
    }

    /// The image view for an `image_*` action, or the error that no image is open.
    pub(super) fn image_for(&mut self, action: &str) -> Result<&mut ImageUi, String> {
        self.image
            .as_mut()
            .ok_or_else(|| format!("{action}: no image is open (load a .png first)"))
    }

    pub(super) fn run_action(&mut self, action: Action) -> Result<(), String> {
        let action_name = action.name();
        match action {
            Action::Load { path } => self.load(&path),
            Action::Save { path } => self.save(&path),
            Action::SaveRecipe { path } => self.save_recipe(&path),
            Action::Screenshot { path } => {
                self.script.screenshot = Some(PendingScreenshot {
                    path,
                    frames_left: 1,
                    then_exit: false,
                });
                Ok(())
            }
            Action::Orbit { yaw, pitch } => {
                self.scene
                    .camera
                    .orbit(yaw.to_radians(), pitch.to_radians());
                Ok(())
            }
            Action::Zoom { factor } => {
                if !(factor > 0.0 && factor.is_finite()) {
                    return Err(format!("zoom: factor {factor} must be positive"));
                }
                self.scene.camera.zoom(factor);
                Ok(())
            }
            Action::Pan { dx, dy } => {
                self.scene.camera.pan(dx, -dy, self.input.viewport.height);
                Ok(())
            }
            Action::Frame => {
                self.scene.frame_mesh(self.doc.mesh(), false);
                Ok(())
            }
            Action::ResetView => {
                self.scene.frame_mesh(self.doc.mesh(), true);
                Ok(())
            }
            Action::View {
                shading,
                wireframe,
                up,
            } => {
                if let Some(s) = shading {
                    self.scene.settings.flat = s == Shading::Flat;
                }
                if let Some(w) = wireframe {
                    self.scene.settings.wireframe = w;
                }
                if let Some(u) = up {
                    self.scene.camera.up_axis = u;
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
                let (px, py) = self.input.script_pixel(x, y);
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
                if let Some(s) = &mut self.script.steps {
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
    pub(super) fn script_tick(&mut self, frame: &FrameInput) {
        if !self.script.ready(self.clock.index, self.background) {
            return;
        }
        let Some(script) = &mut self.script.steps else {
            return;
        };
        let Some(step) = script.pop_front() else {
            self.script.steps = None;
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
        self.script.last_step = what;
        // Work the step started in the background holds the next step back.
        self.poll_tools();
    }

    /// Stops the script at `what` (exits with status 1 unless kept open).
    pub(super) fn fail_script(&mut self, what: &str, error: &str) {
        eprintln!("viewer: script failed at {what}: {error}");
        self.script.failed = true;
        self.status = Status {
            message: format!("Script failed at {what}: {error}"),
            is_error: true,
        };
        if !self.script.keep_open {
            std::process::exit(1);
        }
    }

    pub(super) fn finish_script(&mut self) {
        if let Some(path) = self.script.final_screenshot.take() {
            self.script.screenshot = Some(PendingScreenshot {
                path,
                frames_left: 1,
                then_exit: !self.script.keep_open,
            });
        } else if !self.script.keep_open {
            std::process::exit(0);
        }
    }
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

    #[test]
    fn steps_wait_for_the_warm_up_screenshots_failures_and_background_work() {
        let mut runner = ScriptRunner::new(Options {
            script: Some(VecDeque::from([Step::Idle])),
            screenshot: None,
            keep_open: false,
        });
        assert!(!runner.ready(WARMUP_FRAMES, false), "warming up");
        assert!(runner.ready(WARMUP_FRAMES + 1, false));
        assert!(!runner.ready(WARMUP_FRAMES + 1, true), "background work");
        runner.screenshot = Some(PendingScreenshot {
            path: PathBuf::from("x.png"),
            frames_left: 1,
            then_exit: false,
        });
        assert!(
            !runner.ready(WARMUP_FRAMES + 1, false),
            "a screenshot pending"
        );
        runner.screenshot = None;
        runner.failed = true;
        assert!(!runner.ready(WARMUP_FRAMES + 1, false), "failed");
        assert!(
            !ScriptRunner::new(Options::default()).ready(100, false),
            "no script"
        );
    }
}
