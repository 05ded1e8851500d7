//! The panels: the status line at the bottom, the side panel (file, view, tools, history)
//! and the colour legend over the 3-D view.

use std::path::{Path, PathBuf};

use three_d::egui;

use crate::camera::UpAxis;
use crate::colors::{legend_ui, ColorLayer, Colormap};
use crate::format::{format_duration, group};
use crate::tools::Status;

use super::App;

impl App {
    /// The side panel, the status bar and the legend; returns the rectangle left for the
    /// 3D view (points).
    pub(super) fn ui(&mut self, ui: &mut egui::Ui) -> egui::Rect {
        let frame_ms = self.clock.ms;
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

    pub(super) fn side_panel(&mut self, ui: &mut egui::Ui) {
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
                        egui::TextEdit::singleline(&mut self.paths.open)
                            .hint_text("path to .obj / .ply / .png")
                            .desired_width(200.0),
                    );
                    let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    ui.button("Open").clicked() || enter
                });
                if open.inner {
                    let path = PathBuf::from(self.paths.open.trim());
                    if let Err(e) = self.load(&path) {
                        self.status = Status {
                            message: format!("Open failed: {e}"),
                            is_error: true,
                        };
                    }
                }
                let save = ui.horizontal(|ui| {
                    ui.add(
                        egui::TextEdit::singleline(&mut self.paths.save)
                            .hint_text("path to .obj / .png")
                            .desired_width(200.0),
                    );
                    ui.button("Save").clicked()
                });
                if save.inner {
                    let path = PathBuf::from(self.paths.save.trim());
                    if let Err(e) = self.save(&path) {
                        self.status = Status {
                            message: format!("Save failed: {e}"),
                            is_error: true,
                        };
                    }
                }
                let recipe = ui.horizontal(|ui| {
                    ui.add(
                        egui::TextEdit::singleline(&mut self.paths.recipe)
                            .hint_text("path to .toml")
                            .desired_width(200.0),
                    );
                    ui.button("Save recipe…")
                        .on_hover_text(
                            "Write the edits as an edit recipe that `multires edit` replays \
                             on the hierarchy (or `apply_to_mesh` on the mesh)",
                        )
                        .clicked()
                });
                if recipe.inner {
                    let path = PathBuf::from(self.paths.recipe.trim());
                    if let Err(e) = self.save_recipe(&path) {
                        self.status = Status {
                            message: format!("Save recipe failed: {e}"),
                            is_error: true,
                        };
                    }
                }
                let (steps, without) = self.doc.recipe_log().counts();
                if steps + without > 0 {
                    ui.weak(format!(
                        "Recipe: {steps} step(s){}",
                        if without > 0 {
                            format!(", {without} edit(s) without a step")
                        } else {
                            String::new()
                        }
                    ));
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
                self.paths.save = Path::new(self.paths.save.trim())
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
                    ui.selectable_value(&mut self.scene.settings.flat, false, "smooth");
                    ui.selectable_value(&mut self.scene.settings.flat, true, "flat");
                });
                ui.checkbox(&mut self.scene.settings.wireframe, "Wireframe  (W)");
                ui.horizontal(|ui| {
                    ui.label("Up axis");
                    ui.selectable_value(&mut self.scene.camera.up_axis, UpAxis::Y, "Y");
                    ui.selectable_value(&mut self.scene.camera.up_axis, UpAxis::Z, "Z");
                });
                ui.horizontal(|ui| {
                    if ui.button("Frame  (F)").clicked() {
                        self.scene.frame_mesh(self.doc.mesh(), false);
                    }
                    if ui.button("Reset view  (R)").clicked() {
                        self.scene.frame_mesh(self.doc.mesh(), true);
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
}
