//! The GUI side of the image view: the picture fitted to the central area, the mouse
//! tools (draw the handle or the fixed polygon, drag the handle), the panel.

use super::*;

/// Where the picture lies in the central area: pixel `(x, y)`'s centre is at
/// `origin + (x + ½, y + ½) · scale` (screen points, `y` down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// The picture's top-left corner on screen.
    pub origin: DVec2,
    /// Screen points per pixel.
    pub scale: f64,
}

impl Fit {
    /// The largest picture of `width × height` pixels that fits in the panel
    /// (`min`, `size`) with a margin of `margin` points, centred.
    #[must_use]
    pub fn new(min: DVec2, size: DVec2, width: u32, height: u32, margin: f64) -> Self {
        let image = DVec2::new(f64::from(width.max(1)), f64::from(height.max(1)));
        let room = (size - DVec2::splat(2.0 * margin)).max(DVec2::ONE);
        let scale = (room.x / image.x).min(room.y / image.y);
        let origin = min + 0.5 * (size - image * scale);
        Self { origin, scale }
    }

    /// The screen point of the pixel coordinates `p`.
    #[must_use]
    pub fn to_screen(&self, p: DVec2) -> DVec2 {
        self.origin + (p + DVec2::splat(0.5)) * self.scale
    }

    /// The pixel coordinates of the screen point `s`.
    #[must_use]
    pub fn to_pixel(&self, s: DVec2) -> DVec2 {
        (s - self.origin) / self.scale - DVec2::splat(0.5)
    }
}

/// What a click or a drag in the picture does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MouseTool {
    /// Clicks add vertices to the handle polygon being drawn.
    #[default]
    DrawHandle,
    /// Clicks add vertices to the fixed polygon being drawn.
    DrawFixed,
    /// A drag translates the handle.
    MoveHandle,
}

/// The image view in the GUI: an [`ImageView`] with its texture, the mouse tool, the
/// polygon being drawn and the drag in progress.
pub struct ImageUi {
    /// The edit.
    pub view: ImageView,
    texture: Option<(egui::TextureHandle, u64)>,
    tool: MouseTool,
    draft: Vec<DVec2>,
    /// The translation and the pointer (pixels) where the drag started.
    drag: Option<(DVec2, DVec2)>,
}

fn to_pos(p: DVec2) -> egui::Pos2 {
    egui::pos2(p.x as f32, p.y as f32)
}

fn from_pos(p: egui::Pos2) -> DVec2 {
    DVec2::new(f64::from(p.x), f64::from(p.y))
}

/// The picture as RGBA bytes for a texture of at most `max_side` pixels a side: every
/// `k`-th pixel of every `k`-th row, `k` the smallest step that fits (1 for pictures
/// that fit, so they show exactly). Returns `[width, height]` and the bytes.
#[must_use]
pub fn display_rgba(raster: &Raster, max_side: usize) -> ([usize; 2], Vec<u8>) {
    let (w, h) = (raster.width() as usize, raster.height() as usize);
    let k = w.max(h).div_ceil(max_side.max(1)).max(1);
    let (dw, dh) = (w.div_ceil(k), h.div_ceil(k));
    let c = raster.channels() as usize;
    let data = raster.data();
    let mut out = Vec::with_capacity(dw * dh * 4);
    for y in (0..h).step_by(k) {
        for x in (0..w).step_by(k) {
            let i = (y * w + x) * c;
            out.extend_from_slice(&match data[i..i + c] {
                [g] => [g, g, g, 255],
                [g, a] => [g, g, g, a],
                [r, g, b] => [r, g, b, 255],
                [r, g, b, a, ..] => [r, g, b, a],
                [] => [0, 0, 0, 255],
            });
        }
    }
    ([dw, dh], out)
}

impl ImageUi {
    /// The GUI of `view`, drawing the handle first.
    #[must_use]
    pub fn new(view: ImageView) -> Self {
        Self {
            view,
            texture: None,
            tool: MouseTool::DrawHandle,
            draft: Vec::new(),
            drag: None,
        }
    }

    /// A one-line description: file, size, channels.
    #[must_use]
    pub fn describe(&self) -> String {
        let s = self.view.source();
        let name = self
            .view
            .path()
            .file_name()
            .map_or("image".into(), |n| n.to_string_lossy().into_owned());
        format!(
            "{name}: {}×{} pixels, {} channels",
            s.width(),
            s.height(),
            s.channels()
        )
    }

    fn report(status: &mut Status, result: Result<(), ImageViewError>, done: &str) {
        *status = match result {
            Ok(()) => Status {
                message: done.to_owned(),
                is_error: false,
            },
            Err(e) => Status {
                message: e.to_string(),
                is_error: true,
            },
        };
    }

    /// The side panel section; returns true when the user closes the image (back to
    /// the mesh).
    pub fn panel(&mut self, ui: &mut egui::Ui, status: &mut Status) -> bool {
        let mut close = false;
        egui::CollapsingHeader::new("Image edit (Bendels & Klein)")
            .default_open(true)
            .show(ui, |ui| {
                ui.weak(self.describe());
                ui.horizontal(|ui| {
                    ui.label("Mouse");
                    ui.selectable_value(&mut self.tool, MouseTool::DrawHandle, "handle");
                    ui.selectable_value(&mut self.tool, MouseTool::DrawFixed, "fixed");
                    ui.selectable_value(&mut self.tool, MouseTool::MoveHandle, "move");
                });
                match self.tool {
                    MouseTool::DrawHandle | MouseTool::DrawFixed => {
                        ui.weak(format!(
                            "Click in the picture to add points ({} so far).",
                            self.draft.len()
                        ));
                    }
                    MouseTool::MoveHandle => {
                        ui.weak("Drag in the picture to move the handle.");
                    }
                }
                ui.horizontal(|ui| {
                    if ui.button("Close as handle").clicked() {
                        let result = self.close_as_handle();
                        Self::report(status, result, "Handle set");
                    }
                    if ui.button("Close as fixed").clicked() {
                        let result = self.close_as_fixed();
                        Self::report(status, result, "Fixed region set");
                    }
                    if ui.button("Clear points").clicked() {
                        self.draft.clear();
                    }
                });
                let state = self.view.state().clone();
                ui.horizontal(|ui| {
                    match &state.handle {
                        Some(p) => ui.label(format!("Handle: {} points", p.len())),
                        None => ui.label("Handle: none"),
                    };
                    if ui
                        .add_enabled(state.handle.is_some(), egui::Button::new("Clear"))
                        .clicked()
                    {
                        self.view.clear_handle();
                    }
                });
                ui.horizontal(|ui| {
                    match &state.fixed {
                        Some(p) => ui.label(format!("Fixed: outside {} points", p.len())),
                        None => ui.label("Fixed: the image border"),
                    };
                    if ui
                        .add_enabled(state.fixed.is_some(), egui::Button::new("Border"))
                        .clicked()
                    {
                        let result = self.view.set_fixed(None);
                        Self::report(status, result, "Fixed region: the image border");
                    }
                });
                let mut shape = state.shape;
                let mut grid_step = state.grid_step;
                ui.horizontal(|ui| {
                    ui.label("Shape");
                    egui::ComboBox::from_id_salt("image-shape")
                        .selected_text(shape.name())
                        .show_ui(ui, |ui| {
                            for s in ShapePreset::ALL {
                                ui.selectable_value(&mut shape, s, s.name());
                            }
                        });
                    ui.label("Grid step");
                    ui.add(egui::DragValue::new(&mut grid_step).range(0..=64));
                });
                if shape != state.shape {
                    let result = self.view.set_shape(shape);
                    Self::report(status, result, &format!("Shape: {}", shape.name()));
                }
                if grid_step != state.grid_step {
                    let result = self.view.set_grid_step(grid_step);
                    Self::report(status, result, &format!("Grid step: {grid_step} pixels"));
                }

                ui.separator();
                let mut t = state.transform;
                ui.add_enabled_ui(state.handle.is_some(), |ui| {
                    ui.horizontal(|ui| {
                        ui.label("Translate");
                        ui.add(egui::DragValue::new(&mut t.translate.x).prefix("x "));
                        ui.add(egui::DragValue::new(&mut t.translate.y).prefix("y "));
                    });
                    ui.add(
                        egui::Slider::new(&mut t.rotate, -180.0..=180.0)
                            .text("rotate")
                            .suffix("°"),
                    );
                    ui.add(
                        egui::Slider::new(&mut t.scale, 0.1..=10.0)
                            .logarithmic(true)
                            .text("scale"),
                    );
                    if ui.button("Reset transform").clicked() {
                        t = Transform::IDENTITY;
                    }
                });
                if t != state.transform {
                    let result = self.view.set_transform(t);
                    if result.is_err() {
                        Self::report(status, result, "");
                    }
                }
                if let Some(info) = self.view.info() {
                    ui.weak(format!(
                        "{} pixels resampled, {} folded triangles, {:.1} ms",
                        crate::format::group(info.pixels),
                        info.folded,
                        info.ms
                    ));
                }

                ui.separator();
                ui.horizontal(|ui| {
                    let undo =
                        ui.add_enabled(self.view.undo_len() > 0, egui::Button::new("⟲ Undo"));
                    let redo =
                        ui.add_enabled(self.view.redo_len() > 0, egui::Button::new("⟳ Redo"));
                    if undo.clicked() {
                        if let Some(label) = self.view.undo() {
                            Self::report(status, Ok(()), &format!("Undid {label}"));
                        }
                    }
                    if redo.clicked() {
                        if let Some(label) = self.view.redo() {
                            Self::report(status, Ok(()), &format!("Redid {label}"));
                        }
                    }
                    if ui.button("Back to the mesh").clicked() {
                        close = true;
                    }
                });
                let labels: Vec<&str> = self.view.undo_labels().collect();
                for label in labels.iter().rev().take(5) {
                    ui.label(egui::RichText::new(*label).small());
                }
            });
        if !ui.input(|i| i.pointer.any_down()) {
            self.view.commit();
        }
        close
    }

    /// Paints the picture, the polygons and the handle's outline in `rect` and handles
    /// the mouse there.
    pub fn central(&mut self, ui: &mut egui::Ui, rect: egui::Rect, status: &mut Status) {
        let (w, h) = (self.view.source().width(), self.view.source().height());
        let fit = Fit::new(
            from_pos(rect.min),
            DVec2::new(f64::from(rect.width()), f64::from(rect.height())),
            w,
            h,
            12.0,
        );
        let revision = self.view.revision();
        let options = if fit.scale >= 1.0 {
            egui::TextureOptions::NEAREST
        } else {
            egui::TextureOptions::LINEAR
        };
        if self.texture.as_ref().is_none_or(|(_, r)| *r != revision) {
            let max_side = ui.input(|i| i.max_texture_side);
            let (size, bytes) = display_rgba(self.view.result(), max_side);
            let image = egui::ColorImage::from_rgba_unmultiplied(size, &bytes);
            match &mut self.texture {
                Some((handle, r)) => {
                    handle.set(image, options);
                    *r = revision;
                }
                None => {
                    let handle = ui.ctx().load_texture("image-view", image, options);
                    self.texture = Some((handle, revision));
                }
            }
        }
        let response = ui.interact(
            rect,
            egui::Id::new("image-view-area"),
            egui::Sense::click_and_drag(),
        );
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 0.0, egui::Color32::from_rgb(23, 26, 31));
        let corner = |x: f64, y: f64| to_pos(fit.origin + DVec2::new(x, y) * fit.scale);
        let image_rect =
            egui::Rect::from_min_max(corner(0.0, 0.0), corner(f64::from(w), f64::from(h)));
        if let Some((texture, _)) = &self.texture {
            painter.image(
                texture.id(),
                image_rect,
                egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                egui::Color32::WHITE,
            );
        }
        let screen = |points: &[DVec2]| -> Vec<egui::Pos2> {
            points.iter().map(|&p| to_pos(fit.to_screen(p))).collect()
        };
        let state = self.view.state();
        let blue = egui::Color32::from_rgb(60, 120, 255);
        let orange = egui::Color32::from_rgb(255, 150, 20);
        if let Some(fixed) = &state.fixed {
            painter.add(egui::Shape::closed_line(
                screen(fixed),
                egui::Stroke::new(2.0, blue),
            ));
        }
        if let Some(handle) = &state.handle {
            painter.add(egui::Shape::closed_line(
                screen(handle),
                egui::Stroke::new(1.0, orange.gamma_multiply(0.5)),
            ));
            let m = self.view.matrix();
            let moved: Vec<DVec2> = handle.iter().map(|&p| m.transform_point2(p)).collect();
            painter.add(egui::Shape::closed_line(
                screen(&moved),
                egui::Stroke::new(2.0, orange),
            ));
            if let Some(p) = self.view.pivot() {
                painter.circle_filled(to_pos(fit.to_screen(m.transform_point2(p))), 3.0, orange);
            }
        }
        if !self.draft.is_empty() {
            let colour = match self.tool {
                MouseTool::DrawFixed => blue,
                _ => orange,
            };
            let points = screen(&self.draft);
            painter.add(egui::Shape::line(
                points.clone(),
                egui::Stroke::new(1.5, egui::Color32::YELLOW),
            ));
            for p in points {
                painter.circle_filled(p, 3.5, colour);
            }
        }

        let pointer = response
            .interact_pointer_pos()
            .map(|p| fit.to_pixel(from_pos(p)));
        if let Some(p) = pointer {
            if response.clicked() {
                self.click(p);
            }
            if response.drag_started() {
                // From the press, not from where the motion passed egui's threshold.
                let origin = ui.input(|i| i.pointer.press_origin());
                self.begin_drag(origin.map_or(p, |o| fit.to_pixel(from_pos(o))));
            }
            if response.dragged() {
                if let Err(e) = self.drag_to(p) {
                    Self::report(status, Err(e), "");
                }
            }
        }
        if response.drag_stopped() {
            self.end_drag();
        }
        if let Some(p) = response.hover_pos() {
            let p = fit.to_pixel(from_pos(p)).round();
            if p.x >= 0.0 && p.y >= 0.0 && p.x < f64::from(w) && p.y < f64::from(h) {
                painter.text(
                    rect.left_top() + egui::vec2(8.0, 6.0),
                    egui::Align2::LEFT_TOP,
                    format!("({}, {})", p.x, p.y),
                    egui::FontId::monospace(12.0),
                    egui::Color32::LIGHT_GRAY,
                );
            }
        }
    }

    /// What the mouse does.
    #[must_use]
    pub fn tool(&self) -> MouseTool {
        self.tool
    }

    /// Sets what the mouse does.
    pub fn set_tool(&mut self, tool: MouseTool) {
        self.tool = tool;
    }

    /// The polygon being drawn (pixels).
    #[must_use]
    pub fn draft(&self) -> &[DVec2] {
        &self.draft
    }

    /// A click at pixel coordinates `p`: a new point of the polygon being drawn (with
    /// the move tool, nothing).
    pub fn click(&mut self, p: DVec2) {
        if self.tool != MouseTool::MoveHandle {
            self.draft.push(p);
        }
    }

    /// Makes the drawn polygon the handle and switches to the move tool; on error the
    /// points stay for another try.
    ///
    /// # Errors
    /// As [`ImageView::set_handle`].
    pub fn close_as_handle(&mut self) -> Result<(), ImageViewError> {
        self.view.set_handle(self.draft.clone())?;
        self.draft.clear();
        self.tool = MouseTool::MoveHandle;
        Ok(())
    }

    /// Makes the drawn polygon the fixed border (everything outside it stays); on
    /// error the points stay.
    ///
    /// # Errors
    /// As [`ImageView::set_fixed`].
    pub fn close_as_fixed(&mut self) -> Result<(), ImageViewError> {
        self.view.set_fixed(Some(self.draft.clone()))?;
        self.draft.clear();
        Ok(())
    }

    /// A press at pixel coordinates `p` starts a drag of the handle (move tool only).
    pub fn begin_drag(&mut self, p: DVec2) {
        if self.tool == MouseTool::MoveHandle {
            self.drag = Some((self.view.state().transform.translate, p));
        }
    }

    /// The pointer of the drag is at pixel coordinates `p`: the handle's translation
    /// is the one at the press plus the pointer's motion since.
    ///
    /// # Errors
    /// As [`ImageView::set_transform`].
    pub fn drag_to(&mut self, p: DVec2) -> Result<(), ImageViewError> {
        let Some((start, at)) = self.drag else {
            return Ok(());
        };
        self.view.set_transform(Transform {
            translate: start + (p - at),
            ..self.view.state().transform
        })
    }

    /// The release: the drag is one history step.
    pub fn end_drag(&mut self) {
        self.drag = None;
        self.view.commit();
    }

    /// A scripted drag of the handle by `(dx, dy)` pixels in `steps` moves, through
    /// the mouse's path (with the move tool): one history step.
    ///
    /// # Errors
    /// As [`ImageView::set_transform`].
    pub fn drag_by(&mut self, d: DVec2, steps: usize) -> Result<(), ImageViewError> {
        let steps = steps.max(1);
        let tool = std::mem::replace(&mut self.tool, MouseTool::MoveHandle);
        self.begin_drag(DVec2::ZERO);
        let result = (1..=steps).try_for_each(|k| self.drag_to(d * (k as f64 / steps as f64)));
        self.end_drag();
        self.tool = tool;
        result
    }
}
