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

mod ui;

pub use ui::{display_rgba, Fit, ImageUi, MouseTool};

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
