//! Mouse and keyboard in the 3-D view: [`Input`] holds the gesture under way, the
//! viewport and the viewer's pick; the `impl App` below turns window events into camera
//! moves, picks and tool drags (see the [module docs](super) for the bindings).

use std::path::PathBuf;

use glam::DVec3;
use three_d::egui;
use three_d::{Event, Key, MouseButton};

use crate::camera::Viewport;
use crate::tools::{Drag, DragPhase, Pick, Press, Status};

use super::script_runner::PendingScreenshot;
use super::App;

/// What the mouse is doing in the 3D view.
#[derive(Clone, Copy, Debug)]
pub(super) enum Gesture {
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

/// The mouse and keyboard state of the 3-D view.
#[derive(Clone, Copy, Debug)]
pub(super) struct Input {
    /// What the mouse is doing.
    pub(super) gesture: Gesture,
    /// The 3-D view's rectangle in window pixels (origin bottom-left).
    pub(super) viewport: Viewport,
    /// The viewer's current pick.
    pub(super) pick: Option<Pick>,
}

impl Default for Input {
    fn default() -> Self {
        Self {
            gesture: Gesture::Idle,
            viewport: Viewport {
                x: 0.0,
                y: 0.0,
                width: 1.0,
                height: 1.0,
            },
            pick: None,
        }
    }
}

impl Input {
    /// The window pixel (origin bottom-left) of a script's screen fraction (origin
    /// top-left of the 3D view).
    pub(super) fn script_pixel(&self, x: f64, y: f64) -> (f64, f64) {
        let vp = self.viewport;
        (vp.x + x * vp.width, vp.y + (1.0 - y) * vp.height)
    }

    /// True while the mouse is doing something (a press, an orbit, a pan, a drag).
    pub(super) fn active(&self) -> bool {
        !matches!(self.gesture, Gesture::Idle)
    }
}

impl App {
    /// Ray-casts at a pixel of the window.
    pub(super) fn pick_at(&mut self, px: f64, py: f64) -> Option<Pick> {
        let ray = self.scene.camera.ray(px, py, &self.input.viewport);
        self.scene.cast(self.doc.mesh(), &ray)
    }

    /// A click: the pick goes to the viewer and the active tool.
    pub(super) fn click(&mut self, pick: Option<Pick>) {
        self.input.pick = pick;
        self.with_tool(|tool, ctx| tool.on_pick(pick.as_ref(), ctx));
    }

    /// The press at a pixel of the window: the mouse ray and what it hits.
    pub(super) fn press_at(&mut self, px: f64, py: f64) -> Press {
        let ray = self.scene.camera.ray(px, py, &self.input.viewport);
        let hit = self.scene.cast(self.doc.mesh(), &ray);
        Press { ray, hit }
    }

    /// Starts a tool drag if the active tool grabs something at `press`.
    pub(super) fn begin_tool_drag(&mut self, press: Press) -> bool {
        let Some(start) = self.tools[self.active].grab(&press, self.doc.mesh()) else {
            return false;
        };
        let pick = press.hit;
        if pick.is_some() {
            self.click(pick);
        }
        let normal = self.scene.camera.forward();
        self.input.gesture = Gesture::ToolDrag {
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
    pub(super) fn tool_drag_to(&mut self, current: DVec3, phase: DragPhase) {
        let Gesture::ToolDrag {
            pick,
            start,
            normal,
            ..
        } = self.input.gesture
        else {
            return;
        };
        let drag = Drag {
            phase,
            pick,
            start,
            current,
        };
        self.input.gesture = if phase == DragPhase::End {
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
    pub(super) fn drag_point_at(&self, px: f64, py: f64) -> Option<DVec3> {
        let Gesture::ToolDrag { start, normal, .. } = self.input.gesture else {
            return None;
        };
        self.scene
            .camera
            .ray(px, py, &self.input.viewport)
            .intersect_plane(start, normal)
    }

    /// Handles mouse and keyboard events aimed at the 3D view.
    pub(super) fn handle_events(
        &mut self,
        events: &mut [Event],
        egui_ctx: &egui::Context,
        dpr: f64,
    ) {
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
                    if *handled || over_egui || image || !self.input.viewport.contains(px, py) {
                        continue;
                    }
                    *handled = true;
                    self.input.gesture = match button {
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
                    match self.input.gesture {
                        Gesture::Idle => continue,
                        Gesture::Pending { press, .. } => {
                            if (px - press.0).hypot(py - press.1) > 4.0 * dpr {
                                self.input.gesture = Gesture::Orbit;
                                self.scene.camera.orbit(-dx * 0.008, dy * 0.008);
                            }
                        }
                        Gesture::Orbit => self.scene.camera.orbit(-dx * 0.008, dy * 0.008),
                        Gesture::Pan => {
                            self.scene
                                .camera
                                .pan(dx * dpr, -dy * dpr, self.input.viewport.height)
                        }
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
                    match self.input.gesture {
                        Gesture::Idle => continue,
                        Gesture::Pending { hit, .. } => self.click(hit),
                        Gesture::ToolDrag { current, .. } => {
                            let p = self.drag_point_at(px, py).unwrap_or(current);
                            self.tool_drag_to(p, DragPhase::End);
                        }
                        Gesture::Orbit | Gesture::Pan => {}
                    }
                    self.input.gesture = Gesture::Idle;
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
                    if *handled || over_egui || image || !self.input.viewport.contains(px, py) {
                        continue;
                    }
                    self.scene.camera.zoom((-delta.1 as f64 * 0.004).exp());
                    *handled = true;
                }
                Event::MouseLeave => {
                    // The release may never come: finish what the mouse was doing.
                    if let Gesture::ToolDrag { current, .. } = self.input.gesture {
                        self.tool_drag_to(current, DragPhase::End);
                    }
                    self.input.gesture = Gesture::Idle;
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
                        Key::F if !command => self.scene.frame_mesh(self.doc.mesh(), false),
                        Key::R if !command => self.scene.frame_mesh(self.doc.mesh(), true),
                        Key::W if !command => {
                            self.scene.settings.wireframe = !self.scene.settings.wireframe
                        }
                        Key::L if !command => self.scene.settings.flat = !self.scene.settings.flat,
                        // (Not over a screenshot that a script is waiting for.)
                        Key::P | Key::F12 if !command && self.script.screenshot.is_none() => {
                            self.script.screenshots_taken += 1;
                            let path = PathBuf::from(format!(
                                "viewer-screenshot-{}.png",
                                self.script.screenshots_taken
                            ));
                            self.status = Status {
                                message: format!("Screenshot {}", path.display()),
                                is_error: false,
                            };
                            self.script.screenshot = Some(PendingScreenshot {
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn script_fractions_map_to_window_pixels_of_the_view() {
        let input = Input {
            viewport: Viewport {
                x: 300.0,
                y: 20.0,
                width: 800.0,
                height: 600.0,
            },
            ..Input::default()
        };
        // Script fractions: origin top-left of the view; pixels: origin bottom-left.
        assert_eq!(input.script_pixel(0.0, 0.0), (300.0, 620.0));
        assert_eq!(input.script_pixel(1.0, 1.0), (1100.0, 20.0));
        assert_eq!(input.script_pixel(0.5, 0.25), (700.0, 470.0));
        assert!(!input.active());
    }
}
