//! A shape-function curve editor (Bendels & Klein, Sec. 5 and Fig. 8: "the shape
//! function is interactively modified"): an egui canvas showing `f` on [0, 1]², with the
//! presets *linear*, *C¹* (smoothstep) and *C²* (smootherstep), and a user curve through
//! draggable control points (`edit::bendels_klein::ShapeCurve`, a piecewise cubic Hermite curve
//! through (0, 0), the points and (1, 1), with flat ends).
//!
//! [`CurveModel`] is the model without GUI: it keeps the control points valid for
//! `ShapeCurve` (x strictly increasing inside (0, 1), y in [0, 1], and, with the
//! *monotone* option, y non-decreasing), so that `f(0) = 0`, `f(1) = 1` always, and the
//! curve is monotone when asked. [`CurveEditor`] draws it and turns mouse input into
//! model changes: drag a point to move it, click on empty space to add a point,
//! right-click a point to remove it.

use edit::bendels_klein::{CurveOptions, ShapeCurve, ShapeFunction};
use three_d::egui;

/// Smallest gap in x between control points (and to the ends).
pub const MIN_GAP: f64 = 0.02;

/// Which shape function the model gives.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Preset {
    /// `f(x) = x`.
    Linear,
    /// Smoothstep `3x² − 2x³` (C¹ joins).
    #[default]
    C1,
    /// Smootherstep `6x⁵ − 15x⁴ + 10x³` (C² joins).
    C2,
    /// The user curve through the control points.
    Curve,
}

impl Preset {
    /// All presets with their script names and labels.
    pub const ALL: [(Preset, &'static str, &'static str); 4] = [
        (Preset::Linear, "linear", "linear"),
        (Preset::C1, "c1", "C¹"),
        (Preset::C2, "c2", "C²"),
        (Preset::Curve, "curve", "curve"),
    ];

    /// Script name.
    pub fn key(self) -> &'static str {
        Self::ALL.iter().find(|p| p.0 == self).expect("listed").1
    }

    /// Parses a script name.
    pub fn parse(s: &str) -> Option<Self> {
        let s = s.to_ascii_lowercase();
        Self::ALL.iter().find(|p| p.1 == s).map(|p| p.0)
    }
}

/// The shape function being edited (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct CurveModel {
    preset: Preset,
    points: Vec<(f64, f64)>,
    monotone: bool,
}

impl Default for CurveModel {
    fn default() -> Self {
        Self {
            preset: Preset::C1,
            points: Vec::new(),
            monotone: true,
        }
    }
}

impl CurveModel {
    /// The current preset.
    pub fn preset(&self) -> Preset {
        self.preset
    }

    /// The interior control points of the user curve.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// Whether the user curve is kept monotone.
    pub fn monotone(&self) -> bool {
        self.monotone
    }

    /// The shape function for `edit::bendels_klein`.
    pub fn shape(&self) -> ShapeFunction {
        match self.preset {
            Preset::Linear => ShapeFunction::Linear,
            Preset::C1 => ShapeFunction::Smoothstep,
            Preset::C2 => ShapeFunction::Smootherstep,
            Preset::Curve => {
                let options = CurveOptions::default()
                    .with_monotone(self.monotone)
                    .with_flat_ends(true);
                // The model keeps the points valid; a refusal would be a bug, shown as C¹.
                ShapeCurve::new(&self.points, options)
                    .map_or(ShapeFunction::Smoothstep, ShapeFunction::Curve)
            }
        }
    }

    /// `f(x)`.
    pub fn eval(&self, x: f64) -> f64 {
        self.shape().eval(x)
    }

    /// Chooses a preset. Switching to the curve with no points starts from the current
    /// function sampled at x = ¼, ½, ¾.
    pub fn set_preset(&mut self, preset: Preset) {
        if preset == Preset::Curve && self.points.is_empty() {
            let f = self.shape();
            self.points = [0.25, 0.5, 0.75].iter().map(|&x| (x, f.eval(x))).collect();
        }
        self.preset = preset;
    }

    /// Keeps the curve monotone (or not); switching it on makes the points'
    /// y non-decreasing (each at least its left neighbour's).
    pub fn set_monotone(&mut self, monotone: bool) {
        self.monotone = monotone;
        if monotone {
            let mut low = 0.0f64;
            for p in &mut self.points {
                p.1 = p.1.max(low).min(1.0);
                low = p.1;
            }
        }
    }

    /// The allowed range of point `i`'s coordinates given its neighbours.
    fn bounds(&self, i: usize) -> ((f64, f64), (f64, f64)) {
        let (x0, y0) = if i == 0 {
            (0.0, 0.0)
        } else {
            self.points[i - 1]
        };
        let (x1, y1) = self.points.get(i + 1).copied().unwrap_or((1.0, 1.0));
        let x = (x0 + MIN_GAP, x1 - MIN_GAP);
        let y = if self.monotone { (y0, y1) } else { (0.0, 1.0) };
        (x, y)
    }

    /// Adds a control point near `(x, y)` (clamped to keep the curve valid) and switches
    /// to the user curve; returns its index, or `None` when there is no room in x.
    pub fn add_point(&mut self, x: f64, y: f64) -> Option<usize> {
        self.set_preset(Preset::Curve);
        if !(x.is_finite() && y.is_finite()) {
            return None;
        }
        let i = self.points.partition_point(|p| p.0 < x);
        let (x0, y0) = if i == 0 {
            (0.0, 0.0)
        } else {
            self.points[i - 1]
        };
        let (x1, y1) = self.points.get(i).copied().unwrap_or((1.0, 1.0));
        if x1 - x0 < 2.0 * MIN_GAP {
            return None;
        }
        let x = x.clamp(x0 + MIN_GAP, x1 - MIN_GAP);
        let y = if self.monotone {
            y.clamp(y0, y1)
        } else {
            y.clamp(0.0, 1.0)
        };
        self.points.insert(i, (x, y));
        Some(i)
    }

    /// Moves control point `i` towards `(x, y)`, clamped between its neighbours (in x
    /// always, in y when monotone) and to [0, 1] in y. Returns false for a bad index.
    pub fn move_point(&mut self, i: usize, x: f64, y: f64) -> bool {
        if i >= self.points.len() || !(x.is_finite() && y.is_finite()) {
            return false;
        }
        let ((xl, xh), (yl, yh)) = self.bounds(i);
        self.points[i] = (x.clamp(xl, xh.max(xl)), y.clamp(yl, yh.max(yl)));
        self.preset = Preset::Curve;
        true
    }

    /// Removes control point `i`; returns false for a bad index.
    pub fn remove_point(&mut self, i: usize) -> bool {
        if i >= self.points.len() {
            return false;
        }
        self.points.remove(i);
        self.preset = Preset::Curve;
        true
    }

    /// Sets all control points (scripts) and switches to the user curve.
    ///
    /// # Errors
    /// A message when the points are not valid for `ShapeCurve` (x strictly increasing
    /// in (0, 1), y in [0, 1], non-decreasing when monotone).
    pub fn set_points(&mut self, points: Vec<(f64, f64)>) -> Result<(), String> {
        let options = CurveOptions::default()
            .with_monotone(self.monotone)
            .with_flat_ends(true);
        ShapeCurve::new(&points, options).map_err(|e| e.to_string())?;
        self.points = points;
        self.preset = Preset::Curve;
        Ok(())
    }

    /// The index of the control point nearest to `(x, y)` within `radius` (in the same
    /// units), if any.
    pub fn nearest_point(&self, x: f64, y: f64, radius: f64) -> Option<usize> {
        self.points
            .iter()
            .enumerate()
            .map(|(i, p)| (i, (p.0 - x).hypot(p.1 - y)))
            .filter(|&(_, d)| d <= radius)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }
}

/// The curve editor widget: a [`CurveModel`] and the point being dragged.
#[derive(Clone, Debug, Default)]
pub struct CurveEditor {
    /// The model.
    pub model: CurveModel,
    dragging: Option<usize>,
}

/// Pick radius of a control point on the canvas, pixels.
const PICK_PX: f32 = 9.0;

impl CurveEditor {
    /// Draws the presets, the monotone toggle and the canvas; returns true when the
    /// shape function changed.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> bool {
        let mut changed = false;
        ui.horizontal(|ui| {
            ui.label("Shape f:");
            for (preset, _, label) in Preset::ALL {
                if ui
                    .selectable_label(self.model.preset == preset, label)
                    .clicked()
                    && self.model.preset != preset
                {
                    self.model.set_preset(preset);
                    changed = true;
                }
            }
        });
        let mut monotone = self.model.monotone;
        if ui
            .checkbox(&mut monotone, "monotone")
            .on_hover_text("Fritsch–Carlson tangents: f never decreases")
            .changed()
        {
            self.model.set_monotone(monotone);
            changed |= self.model.preset == Preset::Curve;
        }
        changed |= self.canvas(ui);
        ui.weak("Drag a point; click to add one; right-click to remove it.");
        changed
    }

    fn canvas(&mut self, ui: &mut egui::Ui) -> bool {
        let width = ui.available_width().clamp(120.0, 280.0);
        let size = egui::vec2(width, (width * 0.5).max(80.0));
        let (response, painter) = ui.allocate_painter(size, egui::Sense::click_and_drag());
        let rect = response.rect.shrink(6.0);
        let to_screen = |x: f64, y: f64| {
            egui::pos2(
                rect.left() + x as f32 * rect.width(),
                rect.bottom() - y as f32 * rect.height(),
            )
        };
        let from_screen = |p: egui::Pos2| {
            (
                ((p.x - rect.left()) / rect.width()) as f64,
                ((rect.bottom() - p.y) / rect.height()) as f64,
            )
        };
        let pick_radius = (PICK_PX / rect.width().min(rect.height())) as f64;
        let mut changed = false;

        if response.drag_started() {
            if let Some(pos) = response.interact_pointer_pos() {
                let (x, y) = from_screen(pos);
                self.dragging = self.model.nearest_point(x, y, pick_radius).or_else(|| {
                    let i = self.model.add_point(x, y);
                    changed |= i.is_some();
                    i
                });
            }
        }
        if response.dragged() {
            if let (Some(i), Some(pos)) = (self.dragging, response.interact_pointer_pos()) {
                let (x, y) = from_screen(pos);
                let before = self.model.points.get(i).copied();
                if self.model.move_point(i, x, y) && self.model.points.get(i).copied() != before {
                    changed = true;
                }
            }
        }
        if response.drag_stopped() {
            self.dragging = None;
        }
        if response.clicked() {
            if let Some(pos) = response.interact_pointer_pos() {
                let (x, y) = from_screen(pos);
                if self.model.nearest_point(x, y, pick_radius).is_none() {
                    changed |= self.model.add_point(x, y).is_some();
                }
            }
        }
        if response.secondary_clicked() {
            if let Some(pos) = response.interact_pointer_pos() {
                let (x, y) = from_screen(pos);
                if let Some(i) = self.model.nearest_point(x, y, pick_radius) {
                    changed |= self.model.remove_point(i);
                }
            }
        }

        // Drawing.
        let visuals = ui.visuals();
        painter.rect_filled(response.rect, 4.0, visuals.extreme_bg_color);
        let grid = egui::Stroke::new(1.0, visuals.weak_text_color().gamma_multiply(0.35));
        for k in 0..=4 {
            let t = k as f64 / 4.0;
            painter.line_segment([to_screen(t, 0.0), to_screen(t, 1.0)], grid);
            painter.line_segment([to_screen(0.0, t), to_screen(1.0, t)], grid);
        }
        let f = self.model.shape();
        let samples: Vec<egui::Pos2> = (0..=128)
            .map(|k| {
                let x = k as f64 / 128.0;
                to_screen(x, f.eval(x))
            })
            .collect();
        painter.add(egui::Shape::line(
            samples,
            egui::Stroke::new(2.0, egui::Color32::from_rgb(250, 190, 60)),
        ));
        let end = egui::Color32::from_gray(150);
        painter.circle_filled(to_screen(0.0, 0.0), 3.5, end);
        painter.circle_filled(to_screen(1.0, 1.0), 3.5, end);
        if self.model.preset == Preset::Curve {
            for (i, &(x, y)) in self.model.points.iter().enumerate() {
                let color = if self.dragging == Some(i) {
                    egui::Color32::from_rgb(255, 120, 20)
                } else {
                    egui::Color32::from_rgb(40, 140, 255)
                };
                painter.circle_filled(to_screen(x, y), 5.0, color);
            }
        }
        painter.text(
            rect.left_top() + egui::vec2(2.0, 0.0),
            egui::Align2::LEFT_TOP,
            "α",
            egui::FontId::proportional(12.0),
            visuals.text_color(),
        );
        painter.text(
            rect.right_bottom() - egui::vec2(2.0, 2.0),
            egui::Align2::RIGHT_BOTTOM,
            "d_fixed / (d_fixed + d_handle)",
            egui::FontId::proportional(10.0),
            visuals.weak_text_color(),
        );
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ends_hold(model: &CurveModel) {
        assert_eq!(model.eval(0.0), 0.0);
        assert_eq!(model.eval(1.0), 1.0);
    }

    fn is_monotone(model: &CurveModel) -> bool {
        let f = model.shape();
        (0..1000).all(|k| f.eval(k as f64 / 1000.0) <= f.eval((k + 1) as f64 / 1000.0) + 1e-12)
    }

    #[test]
    fn presets_hit_zero_and_one() {
        let mut model = CurveModel::default();
        for (preset, _, _) in Preset::ALL {
            model.set_preset(preset);
            ends_hold(&model);
            assert!(is_monotone(&model));
        }
    }

    #[test]
    fn switching_to_the_curve_samples_the_current_function() {
        let mut model = CurveModel::default();
        model.set_preset(Preset::C2);
        model.set_preset(Preset::Curve);
        assert_eq!(model.points().len(), 3);
        let f = ShapeFunction::Smootherstep;
        for &(x, y) in model.points() {
            assert_eq!(y, f.eval(x));
        }
        ends_hold(&model);
    }

    #[test]
    fn adding_and_moving_points_keeps_the_ends_and_monotony() {
        let mut model = CurveModel::default();
        assert!(model.monotone());
        let i = model.add_point(0.3, 0.9).unwrap();
        assert_eq!(model.preset(), Preset::Curve);
        ends_hold(&model);
        assert!(is_monotone(&model));
        // Wild moves: below zero, above one, past the neighbours, backwards in y.
        for &(x, y) in &[
            (-1.0, -1.0),
            (2.0, 2.0),
            (0.9, 0.0),
            (0.05, 1.0),
            (0.5, 0.5),
        ] {
            assert!(model.move_point(i.min(model.points().len() - 1), x, y));
            ends_hold(&model);
            assert!(
                is_monotone(&model),
                "not monotone after moving to ({x}, {y})"
            );
            let xs: Vec<f64> = model.points().iter().map(|p| p.0).collect();
            assert!(
                xs.windows(2).all(|w| w[1] - w[0] >= MIN_GAP - 1e-15),
                "{xs:?}"
            );
            assert!(xs.iter().all(|&x| (MIN_GAP..=1.0 - MIN_GAP).contains(&x)));
        }
        for &(x, y) in &[(0.1, 0.95), (0.95, 0.02), (0.6, 0.0)] {
            model.add_point(x, y);
            ends_hold(&model);
            assert!(is_monotone(&model));
        }
        // The model never produced points ShapeCurve refuses.
        let options = CurveOptions::default()
            .with_monotone(true)
            .with_flat_ends(true);
        assert!(ShapeCurve::new(model.points(), options).is_ok());
    }

    #[test]
    fn without_monotony_the_curve_may_dip_but_keeps_its_ends() {
        let mut model = CurveModel::default();
        model.set_monotone(false);
        model.add_point(0.3, 0.8).unwrap();
        model.add_point(0.6, 0.1).unwrap();
        ends_hold(&model);
        assert!(!is_monotone(&model));
        // Switching monotony back on repairs the points.
        model.set_monotone(true);
        ends_hold(&model);
        assert!(is_monotone(&model));
    }

    #[test]
    fn removing_points_and_bad_indices() {
        let mut model = CurveModel::default();
        model.set_preset(Preset::Curve);
        assert!(model.remove_point(1));
        assert_eq!(model.points().len(), 2);
        assert!(!model.remove_point(5));
        assert!(!model.move_point(7, 0.5, 0.5));
        ends_hold(&model);
        assert!(model.set_points(vec![(0.5, 0.2), (0.4, 0.3)]).is_err());
        assert!(model.set_points(vec![(0.4, 0.6), (0.5, 0.2)]).is_err()); // not monotone
        model.set_points(vec![(0.4, 0.2), (0.5, 0.6)]).unwrap();
        assert_eq!(model.nearest_point(0.41, 0.21, 0.05), Some(0));
        assert_eq!(model.nearest_point(0.9, 0.9, 0.05), None);
    }

    #[test]
    fn a_crowded_interval_refuses_new_points() {
        let mut model = CurveModel::default();
        model.set_points(vec![(0.5, 0.5), (0.52, 0.55)]).unwrap();
        assert_eq!(model.add_point(0.51, 0.52), None);
        assert_eq!(model.points().len(), 2);
    }
}
