//! The 2-D image view: a PNG edited with Bendels & Klein's method on pictures
//! ([`edit::bendels_klein::image`]).
//!
//! When the viewer opens a `.png`, the central area shows the picture (fitted to the
//! panel) instead of the 3-D scene. The user draws a **handle** polygon (the part that
//! moves rigidly) and optionally a **fixed** polygon (everything outside it stays; by
//! default the image border stays, as in `examples/image_edit.rs`), then drags the
//! handle and sets its rotation and scale. Every change re-applies the edit to the
//! input picture through an [`ImageSession`] and shows the result; the transform, the
//! regions and the shape function are kept in a history with undo and redo; the result
//! is saved as a PNG.
//!
//! The edit state and its history live in [`ImageView`], which needs no window (the
//! tests drive it directly); [`ImageUi`] adds what the GUI needs: the texture, the
//! polygon being drawn, the mouse tool, the panel and the painting. Pixel coordinates
//! are the library's: pixel `(x, y)` is the point `(x, y)` (its centre), origin at the
//! top-left corner, `y` down. The handle moves by `T(pivot + translate) · R(rotate) ·
//! S(scale) · T(−pivot)` with the pivot at the centroid of the handle polygon's
//! vertices, as in `examples/image_edit.rs` (a positive angle turns clockwise on screen).
//!
//! Values are passed to the library unchecked; what it refuses (a polygon of two
//! points, regions that touch, a scale of 0, a grid step of 0 …) comes back as its
//! error, shown in the status line, and the edit stays as it was.

use std::path::{Path, PathBuf};

use edit::bendels_klein::image::{ImageOptions, ImageSession, Mask, Raster};
use edit::bendels_klein::{BendelsKleinError, ShapeFunction};
use glam::{DMat3, DVec2};
use three_d::egui;

use crate::tools::Status;

/// True when `path` names a PNG (by its extension, case-insensitive): the viewer opens
/// it in the image view.
#[must_use]
pub fn is_png(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
}

/// What can go wrong in the image view.
#[derive(Debug, thiserror::Error)]
pub enum ImageViewError {
    /// The library refused (its own message).
    #[error(transparent)]
    Edit(#[from] BendelsKleinError),
    /// A transform before any handle polygon.
    #[error("set the handle polygon first (draw it and close it, or `image_handle`)")]
    NoHandle,
    /// Saving the picture under a name that is not a `.png`.
    #[error("{0}: the image view saves PNG pictures (name the file .png)")]
    NotPng(PathBuf),
    /// An unknown shape preset name.
    #[error("unknown shape {0:?}: smoothstep, linear or c2")]
    UnknownShape(String),
}

/// The shape functions the image view offers (the library's presets).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShapePreset {
    /// `3x² − 2x³` (C¹), the library's default.
    #[default]
    Smoothstep,
    /// `x` (creased at both borders).
    Linear,
    /// `6x⁵ − 15x⁴ + 10x³` (C²).
    C2,
}

impl ShapePreset {
    /// Every preset, in menu order.
    pub const ALL: [ShapePreset; 3] = [Self::Smoothstep, Self::Linear, Self::C2];

    /// The name used in the menu and in scripts.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Smoothstep => "smoothstep",
            Self::Linear => "linear",
            Self::C2 => "c2",
        }
    }

    /// The preset named `name` (`smoothstep` or `c1`, `linear`, `c2` or
    /// `smootherstep`, case-insensitive).
    ///
    /// # Errors
    /// [`ImageViewError::UnknownShape`] for any other name.
    pub fn parse(name: &str) -> Result<Self, ImageViewError> {
        match name.to_ascii_lowercase().as_str() {
            "smoothstep" | "c1" => Ok(Self::Smoothstep),
            "linear" => Ok(Self::Linear),
            "c2" | "smootherstep" => Ok(Self::C2),
            _ => Err(ImageViewError::UnknownShape(name.to_owned())),
        }
    }

    /// The library's shape function.
    #[must_use]
    pub fn function(self) -> ShapeFunction {
        match self {
            Self::Smoothstep => ShapeFunction::Smoothstep,
            Self::Linear => ShapeFunction::Linear,
            Self::C2 => ShapeFunction::Smootherstep,
        }
    }
}

/// The handle transform as the user sets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Translation in pixels (`y` down).
    pub translate: DVec2,
    /// Rotation in degrees about the pivot (clockwise on screen).
    pub rotate: f64,
    /// Uniform scale about the pivot.
    pub scale: f64,
}

impl Transform {
    /// No motion.
    pub const IDENTITY: Self = Self {
        translate: DVec2::ZERO,
        rotate: 0.0,
        scale: 1.0,
    };

    /// `T(pivot + translate) · R(rotate) · S(scale) · T(−pivot)`, 3×3 homogeneous.
    #[must_use]
    pub fn matrix(&self, pivot: DVec2) -> DMat3 {
        DMat3::from_translation(pivot + self.translate)
            * DMat3::from_angle(self.rotate.to_radians())
            * DMat3::from_scale(DVec2::splat(self.scale))
            * DMat3::from_translation(-pivot)
    }
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// Everything that defines the edited picture besides the input: one history entry.
#[derive(Clone, Debug, PartialEq)]
pub struct EditState {
    /// The handle polygon (`None`: not set yet, the picture shows unedited).
    pub handle: Option<Vec<DVec2>>,
    /// The fixed polygon: everything outside it stays (`None`: the image border stays).
    pub fixed: Option<Vec<DVec2>>,
    /// The shape function.
    pub shape: ShapePreset,
    /// Pixels between grid vertices (the library's [`ImageOptions::grid_step`]).
    pub grid_step: u32,
    /// The handle transform.
    pub transform: Transform,
}

impl Default for EditState {
    fn default() -> Self {
        Self {
            handle: None,
            fixed: None,
            shape: ShapePreset::default(),
            grid_step: ImageOptions::default().grid_step,
            transform: Transform::IDENTITY,
        }
    }
}

/// The centroid of a polygon's vertices: the pivot of rotation and scale.
#[must_use]
pub fn pivot(polygon: &[DVec2]) -> DVec2 {
    polygon.iter().sum::<DVec2>() / polygon.len().max(1) as f64
}

/// What the last render did, for the panel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderInfo {
    /// Pixels resampled.
    pub pixels: usize,
    /// Grid triangles that folded over (see [`ImageSession::folded_triangles`]).
    pub folded: usize,
    /// Time of the apply and render, in ms.
    pub ms: f64,
}

/// The image edit without the GUI: input picture, edit state, session, result and
/// history (see the module docs).
pub struct ImageView {
    path: PathBuf,
    source: Raster,
    state: EditState,
    session: Option<ImageSession>,
    result: Raster,
    revision: u64,
    info: Option<RenderInfo>,
    undo: Vec<(String, EditState)>,
    redo: Vec<(String, EditState)>,
    /// True while a continuous change (a drag, a slider) adds to the last history
    /// entry instead of making new ones.
    open: bool,
}

impl ImageView {
    /// Reads the PNG at `path`.
    ///
    /// # Errors
    /// The library's [`BendelsKleinError::Png`] (or a size error) when it cannot be read.
    pub fn open(path: &Path) -> Result<Self, ImageViewError> {
        Ok(Self::new(Raster::read_png(path)?, path.to_owned()))
    }

    /// The view of `source`, named `path` (for messages and the default save path).
    #[must_use]
    pub fn new(source: Raster, path: PathBuf) -> Self {
        Self {
            path,
            result: source.clone(),
            source,
            state: EditState::default(),
            session: None,
            revision: 0,
            info: None,
            undo: Vec::new(),
            redo: Vec::new(),
            open: false,
        }
    }

    /// The file the picture came from.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }
    /// The input picture.
    #[must_use]
    pub fn source(&self) -> &Raster {
        &self.source
    }
    /// The edited picture (the input while no handle is set or the transform is the
    /// identity).
    #[must_use]
    pub fn result(&self) -> &Raster {
        &self.result
    }
    /// The current edit state.
    #[must_use]
    pub fn state(&self) -> &EditState {
        &self.state
    }
    /// Counts the changes of [`ImageView::result`] (the GUI re-uploads its texture when
    /// it changes).
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }
    /// What the last render did (`None` before the first edit).
    #[must_use]
    pub fn info(&self) -> Option<RenderInfo> {
        self.info
    }
    /// The pivot of rotation and scale (centroid of the handle polygon), if set.
    #[must_use]
    pub fn pivot(&self) -> Option<DVec2> {
        self.state.handle.as_deref().map(pivot)
    }
    /// The current handle matrix (identity without a handle).
    #[must_use]
    pub fn matrix(&self) -> DMat3 {
        self.pivot()
            .map_or(DMat3::IDENTITY, |p| self.state.transform.matrix(p))
    }
    /// Labels of the steps that can be undone, oldest first.
    pub fn undo_labels(&self) -> impl Iterator<Item = &str> {
        self.undo.iter().map(|(label, _)| label.as_str())
    }
    /// Steps that can be undone.
    #[must_use]
    pub fn undo_len(&self) -> usize {
        self.undo.len()
    }
    /// Steps that can be redone.
    #[must_use]
    pub fn redo_len(&self) -> usize {
        self.redo.len()
    }

    /// Sets the handle polygon (closed: the last point joins the first).
    ///
    /// # Errors
    /// The library's errors for the polygon or the regions (too few points, not finite,
    /// empty, overlapping or touching the fixed region); nothing changes then.
    pub fn set_handle(&mut self, polygon: Vec<DVec2>) -> Result<(), ImageViewError> {
        let state = EditState {
            handle: Some(polygon),
            ..self.state.clone()
        };
        self.change("handle polygon", state)
    }

    /// Removes the handle polygon: the picture shows unedited.
    pub fn clear_handle(&mut self) {
        if self.state.handle.is_some() {
            let state = EditState {
                handle: None,
                ..self.state.clone()
            };
            // Without a handle nothing is built, so nothing can fail.
            let _ = self.change("clear handle", state);
        }
    }

    /// Sets the fixed polygon (`None`: the image border stays).
    ///
    /// # Errors
    /// As [`ImageView::set_handle`].
    pub fn set_fixed(&mut self, polygon: Option<Vec<DVec2>>) -> Result<(), ImageViewError> {
        let state = EditState {
            fixed: polygon,
            ..self.state.clone()
        };
        self.change("fixed region", state)
    }

    /// Sets the shape function.
    ///
    /// # Errors
    /// As [`ImageView::set_handle`] (the session is built again).
    pub fn set_shape(&mut self, shape: ShapePreset) -> Result<(), ImageViewError> {
        let state = EditState {
            shape,
            ..self.state.clone()
        };
        self.change("shape", state)
    }

    /// Sets the grid step (passed to the library as it is).
    ///
    /// # Errors
    /// The library's [`BendelsKleinError::GridStep`] for 0.
    pub fn set_grid_step(&mut self, grid_step: u32) -> Result<(), ImageViewError> {
        let state = EditState {
            grid_step,
            ..self.state.clone()
        };
        self.change("grid step", state)
    }

    /// Sets the handle transform and shows the result. Successive calls until
    /// [`ImageView::commit`] (a drag, a slider being moved) make one history entry.
    ///
    /// # Errors
    /// [`ImageViewError::NoHandle`] without a handle polygon; the library's errors for
    /// a transform it cannot blend (a scale of 0 or below, a non-finite value); nothing
    /// changes then.
    pub fn set_transform(&mut self, transform: Transform) -> Result<(), ImageViewError> {
        if self.state.handle.is_none() {
            return Err(ImageViewError::NoHandle);
        }
        if transform == self.state.transform {
            return Ok(());
        }
        let state = EditState {
            transform,
            ..self.state.clone()
        };
        let keep_open = self.open;
        self.change("transform", state)?;
        if keep_open {
            // One entry for the whole continuous change.
            self.undo.pop();
        }
        self.open = true;
        Ok(())
    }

    /// Ends a continuous change of the transform (see [`ImageView::set_transform`]).
    pub fn commit(&mut self) {
        self.open = false;
    }

    /// Undoes one step; returns its label (`None`: nothing to undo).
    pub fn undo(&mut self) -> Option<String> {
        self.commit();
        let (label, state) = self.undo.pop()?;
        // A state that was shown once builds again.
        if let Err(e) = self.rebuild(&state) {
            debug_assert!(false, "an undone state failed to build: {e}");
        }
        let current = std::mem::replace(&mut self.state, state);
        self.redo.push((label.clone(), current));
        Some(label)
    }

    /// Redoes one step; returns its label (`None`: nothing to redo).
    pub fn redo(&mut self) -> Option<String> {
        self.commit();
        let (label, state) = self.redo.pop()?;
        if let Err(e) = self.rebuild(&state) {
            debug_assert!(false, "a redone state failed to build: {e}");
        }
        let current = std::mem::replace(&mut self.state, state);
        self.undo.push((label.clone(), current));
        Some(label)
    }

    /// Writes the edited picture as a PNG.
    ///
    /// # Errors
    /// [`ImageViewError::NotPng`] for a name without the `.png` extension; the
    /// library's [`BendelsKleinError::Png`].
    pub fn save(&self, path: &Path) -> Result<(), ImageViewError> {
        if !is_png(path) {
            return Err(ImageViewError::NotPng(path.to_owned()));
        }
        Ok(self.result.write_png(path)?)
    }

    /// Moves to `state` (shown), recording the current one under `label`.
    fn change(&mut self, label: &str, state: EditState) -> Result<(), ImageViewError> {
        self.rebuild(&state)?;
        let previous = std::mem::replace(&mut self.state, state);
        self.undo.push((label.to_owned(), previous));
        self.redo.clear();
        self.open = false;
        Ok(())
    }

    /// Makes the session and the result those of `state`; on error nothing changes.
    /// The session is built again only when the regions, the shape or the grid
    /// changed; a new transform only applies and renders.
    fn rebuild(&mut self, state: &EditState) -> Result<(), ImageViewError> {
        let start = std::time::Instant::now();
        let Some(handle) = &state.handle else {
            self.session = None;
            self.show_source();
            return Ok(());
        };
        let same_regions = self.session.is_some()
            && self.state.handle == state.handle
            && self.state.fixed == state.fixed
            && self.state.shape == state.shape
            && self.state.grid_step == state.grid_step;
        let mut fresh = None;
        if !same_regions {
            let (w, h) = (self.source.width(), self.source.height());
            let handle_mask = Mask::polygon(w, h, handle)?;
            let fixed_mask = match &state.fixed {
                Some(polygon) => Mask::outside_polygon(w, h, polygon)?,
                None => Mask::border(w, h, 1)?,
            };
            let options = ImageOptions::default()
                .with_grid_step(state.grid_step)
                .with_shape(state.shape.function());
            fresh = Some(ImageSession::new(
                self.source.clone(),
                handle_mask,
                fixed_mask,
                options,
            )?);
        }
        // (`same_regions` holds only with a session.)
        let Some(session) = fresh.as_mut().or(self.session.as_mut()) else {
            return Ok(());
        };
        session.apply(state.transform.matrix(pivot(handle)))?;
        if state.transform == Transform::IDENTITY {
            // The identity edit is the input, bit for bit.
            self.show_source();
            self.info = None;
        } else {
            let stats = session.render_into(&mut self.result)?;
            self.revision += 1;
            self.info = Some(RenderInfo {
                pixels: stats.pixels,
                folded: session.folded_triangles(),
                ms: start.elapsed().as_secs_f64() * 1e3,
            });
        }
        if fresh.is_some() {
            self.session = fresh;
        }
        Ok(())
    }

    fn show_source(&mut self) {
        self.result.data_mut().copy_from_slice(self.source.data());
        self.revision += 1;
    }
}

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
