//! Colouring the mesh by data: scalar fields per vertex (distances, weights, errors)
//! with a colour bar, and labels per vertex or per face (sub-meshes, regions) with a
//! legend.
//!
//! A tool shows data through [`ColorLayer`]s (see `ToolContext::show_scalar` and
//! friends); the renderer turns the active layer into one colour per triangle corner.
//! Values are indexed like the kernel's per-element arrays: by `Mesh::vertex_index` /
//! `Mesh::face_index`. A scalar that is NaN, and a label equal to [`NO_LABEL`], are drawn
//! in the mesh's base colour.

use halfedge::Mesh;

/// An sRGB colour with alpha, 8 bits per channel.
pub type Rgba = [u8; 4];

/// The mesh's base colour (a warm light grey).
pub const BASE_COLOR: Rgba = [206, 200, 188, 255];

/// Label value meaning "no label".
pub const NO_LABEL: u32 = u32::MAX;

/// Colour maps for scalar fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Colormap {
    /// Perceptually uniform, dark blue → green → yellow (matplotlib's viridis).
    Viridis,
    /// Diverging blue → white → red, for signed data centred on zero.
    Diverging,
    /// Perceptually ordered, black → red → yellow → white (matplotlib's inferno).
    Inferno,
}

impl Colormap {
    /// All colour maps, for selectors.
    pub const ALL: [Colormap; 3] = [Colormap::Viridis, Colormap::Diverging, Colormap::Inferno];

    /// Display name.
    pub fn name(self) -> &'static str {
        match self {
            Colormap::Viridis => "viridis",
            Colormap::Diverging => "blue-white-red",
            Colormap::Inferno => "inferno",
        }
    }

    fn stops(self) -> &'static [[u8; 3]] {
        match self {
            Colormap::Viridis => &[
                [68, 1, 84],
                [72, 40, 120],
                [62, 74, 137],
                [49, 104, 142],
                [38, 130, 142],
                [31, 158, 137],
                [53, 183, 121],
                [110, 206, 88],
                [181, 222, 43],
                [253, 231, 37],
            ],
            Colormap::Diverging => &[
                [59, 76, 192],
                [98, 130, 234],
                [141, 176, 254],
                [184, 208, 249],
                [221, 221, 221],
                [245, 196, 173],
                [244, 154, 123],
                [222, 96, 77],
                [180, 4, 38],
            ],
            Colormap::Inferno => &[
                [0, 0, 4],
                [40, 11, 84],
                [101, 21, 110],
                [159, 42, 99],
                [212, 72, 66],
                [245, 125, 21],
                [250, 193, 39],
                [252, 255, 164],
            ],
        }
    }

    /// The colour at `t ∈ [0, 1]` (clamped), interpolated linearly between stops.
    pub fn sample(self, t: f64) -> Rgba {
        let stops = self.stops();
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let x = t * (stops.len() - 1) as f64;
        let i = (x.floor() as usize).min(stops.len() - 2);
        let f = x - i as f64;
        let (a, b) = (stops[i], stops[i + 1]);
        let mix = |k: usize| (a[k] as f64 + f * (b[k] as f64 - a[k] as f64)).round() as u8;
        [mix(0), mix(1), mix(2), 255]
    }
}

/// Colour of label `k`: a qualitative palette (Okabe–Ito, then Tableau) that stays
/// distinguishable for the first dozen labels and cycles after.
pub fn label_color(label: u32) -> Rgba {
    const PALETTE: [[u8; 3]; 12] = [
        [230, 159, 0],
        [86, 180, 233],
        [0, 158, 115],
        [240, 228, 66],
        [0, 114, 178],
        [213, 94, 0],
        [204, 121, 167],
        [148, 103, 189],
        [140, 86, 75],
        [127, 127, 127],
        [188, 189, 34],
        [23, 190, 207],
    ];
    if label == NO_LABEL {
        return BASE_COLOR;
    }
    let [r, g, b] = PALETTE[label as usize % PALETTE.len()];
    [r, g, b, 255]
}

/// A scalar value per vertex, drawn through a colour map over `range`.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalarField {
    /// Name shown above the colour bar.
    pub name: String,
    /// One value per vertex slot (`Mesh::vertex_index`); NaN: no value.
    pub values: Vec<f64>,
    /// Values mapped to the two ends of the colour map.
    pub range: (f64, f64),
    /// The colour map.
    pub colormap: Colormap,
}

impl ScalarField {
    /// A field with its range set to the finite values' extent.
    pub fn new(name: impl Into<String>, values: Vec<f64>, colormap: Colormap) -> Self {
        let range = finite_range(&values);
        Self {
            name: name.into(),
            values,
            range,
            colormap,
        }
    }

    /// Colour of a value.
    pub fn color(&self, value: f64) -> Rgba {
        if !value.is_finite() {
            return BASE_COLOR;
        }
        let (lo, hi) = self.range;
        let t = if hi > lo {
            (value - lo) / (hi - lo)
        } else {
            0.5
        };
        self.colormap.sample(t)
    }
}

/// `(min, max)` of the finite values; `(0, 1)` when there is none.
pub fn finite_range(values: &[f64]) -> (f64, f64) {
    let (lo, hi) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    if lo <= hi {
        (lo, hi)
    } else {
        (0.0, 1.0)
    }
}

/// Which elements a label field colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LabelTarget {
    /// One label per vertex slot; colours blend across faces between labels.
    Vertices,
    /// One label per face slot; every face has one colour.
    Faces,
}

/// A label per vertex or per face, drawn with [`label_color`], with a legend.
#[derive(Clone, Debug, PartialEq)]
pub struct LabelField {
    /// Name shown above the legend.
    pub name: String,
    /// Vertex or face labels.
    pub target: LabelTarget,
    /// One label per slot; [`NO_LABEL`]: unlabelled.
    pub labels: Vec<u32>,
    /// Legend entries `(label, text)`; empty: the legend lists the labels in use.
    pub legend: Vec<(u32, String)>,
}

/// What colours the mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ColorLayer {
    /// The base colour.
    #[default]
    None,
    /// A scalar field per vertex.
    Scalar(ScalarField),
    /// Labels per vertex or per face.
    Labels(LabelField),
}

impl ColorLayer {
    /// One colour per corner of each of `triangles` (vertex slots per face, in the order
    /// of `faces`, their face slots), three per triangle.
    pub fn corner_colors(&self, triangles: &[[u32; 3]], faces: &[u32]) -> Vec<Rgba> {
        let per_vertex = |f: &dyn Fn(usize) -> Rgba| -> Vec<Rgba> {
            triangles
                .iter()
                .flat_map(|t| t.map(|v| f(v as usize)))
                .collect()
        };
        match self {
            ColorLayer::None => vec![BASE_COLOR; 3 * triangles.len()],
            ColorLayer::Scalar(field) => {
                per_vertex(&|v| field.values.get(v).map_or(BASE_COLOR, |&x| field.color(x)))
            }
            ColorLayer::Labels(field) => match field.target {
                LabelTarget::Vertices => {
                    per_vertex(&|v| field.labels.get(v).map_or(BASE_COLOR, |&l| label_color(l)))
                }
                LabelTarget::Faces => faces
                    .iter()
                    .flat_map(|&f| {
                        let c = field
                            .labels
                            .get(f as usize)
                            .map_or(BASE_COLOR, |&l| label_color(l));
                        [c, c, c]
                    })
                    .collect(),
            },
        }
    }

    /// One colour per vertex slot (`slots` of them); face labels give the base colour.
    pub fn vertex_colors(&self, slots: usize) -> Vec<Rgba> {
        match self {
            ColorLayer::Scalar(field) => (0..slots)
                .map(|v| field.values.get(v).map_or(BASE_COLOR, |&x| field.color(x)))
                .collect(),
            ColorLayer::Labels(field) if field.target == LabelTarget::Vertices => (0..slots)
                .map(|v| field.labels.get(v).map_or(BASE_COLOR, |&l| label_color(l)))
                .collect(),
            _ => vec![BASE_COLOR; slots],
        }
    }

    /// The layer's name, if it has one.
    pub fn name(&self) -> Option<&str> {
        match self {
            ColorLayer::None => None,
            ColorLayer::Scalar(f) => Some(&f.name),
            ColorLayer::Labels(f) => Some(&f.name),
        }
    }

    /// Checks that the layer has one value per slot of `mesh`.
    pub fn check_size(&self, mesh: &Mesh) -> Result<(), String> {
        let (len, want, what) = match self {
            ColorLayer::None => return Ok(()),
            ColorLayer::Scalar(f) => (f.values.len(), mesh.vertex_slots(), "vertex"),
            ColorLayer::Labels(f) if f.target == LabelTarget::Vertices => {
                (f.labels.len(), mesh.vertex_slots(), "vertex")
            }
            ColorLayer::Labels(f) => (f.labels.len(), mesh.face_slots(), "face"),
        };
        if len == want {
            Ok(())
        } else {
            Err(format!(
                "colour layer {:?} has {len} values for {want} {what} slots",
                self.name().unwrap_or("")
            ))
        }
    }
}

/// The active colour layer with a revision counter bumped by every change, so the
/// renderer re-uploads colours only when they changed.
#[derive(Clone, Debug, Default)]
pub struct Display {
    layer: ColorLayer,
    revision: u64,
}

impl Display {
    /// Replaces the layer.
    pub fn set(&mut self, layer: ColorLayer) {
        self.layer = layer;
        self.revision += 1;
    }

    /// The layer.
    pub fn layer(&self) -> &ColorLayer {
        &self.layer
    }

    /// Mutable access to the layer (counts as a change).
    pub fn layer_mut(&mut self) -> &mut ColorLayer {
        self.revision += 1;
        &mut self.layer
    }

    /// Changes so far.
    pub fn revision(&self) -> u64 {
        self.revision
    }
}

/// Draws the colour bar (scalar field) or legend (labels) of `layer` into `ui`.
pub fn legend_ui(ui: &mut three_d::egui::Ui, layer: &ColorLayer) {
    use three_d::egui;
    match layer {
        ColorLayer::None => {}
        ColorLayer::Scalar(field) => {
            ui.label(egui::RichText::new(&field.name).strong());
            let width = ui.available_width().clamp(120.0, 260.0);
            let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 16.0), egui::Sense::hover());
            let painter = ui.painter_at(rect);
            let steps = 64;
            for k in 0..steps {
                let t0 = k as f32 / steps as f32;
                let t1 = (k + 1) as f32 / steps as f32;
                let [r, g, b, _] = field.colormap.sample((t0 + t1) as f64 * 0.5);
                let strip = egui::Rect::from_min_max(
                    egui::pos2(rect.left() + t0 * rect.width(), rect.top()),
                    egui::pos2(rect.left() + t1 * rect.width() + 0.5, rect.bottom()),
                );
                painter.rect_filled(strip, 0.0, egui::Color32::from_rgb(r, g, b));
            }
            painter.rect_stroke(
                rect,
                0.0,
                egui::Stroke::new(1.0, ui.visuals().widgets.noninteractive.fg_stroke.color),
                egui::StrokeKind::Outside,
            );
            ui.horizontal(|ui| {
                ui.label(format_value(field.range.0));
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    ui.label(format_value(field.range.1));
                });
            });
        }
        ColorLayer::Labels(field) => {
            ui.label(egui::RichText::new(&field.name).strong());
            let entries: Vec<(u32, String)> = if field.legend.is_empty() {
                let mut used: Vec<u32> = field
                    .labels
                    .iter()
                    .copied()
                    .filter(|&l| l != NO_LABEL)
                    .collect();
                used.sort_unstable();
                used.dedup();
                used.into_iter()
                    .map(|l| (l, format!("label {l}")))
                    .collect()
            } else {
                field.legend.clone()
            };
            let shown = entries.len().min(16);
            for (label, text) in &entries[..shown] {
                ui.horizontal(|ui| {
                    let (rect, _) =
                        ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
                    let [r, g, b, _] = label_color(*label);
                    ui.painter()
                        .rect_filled(rect, 2.0, egui::Color32::from_rgb(r, g, b));
                    ui.label(text);
                });
            }
            if entries.len() > shown {
                ui.label(format!("… {} more", entries.len() - shown));
            }
        }
    }
}

/// A number with about four significant digits.
pub fn format_value(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.abs() >= 1e4 || x.abs() < 1e-3 {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colormaps_hit_their_end_stops_and_clamp() {
        for map in Colormap::ALL {
            let stops = map.stops();
            let [r, g, b] = stops[0];
            assert_eq!(map.sample(0.0), [r, g, b, 255]);
            assert_eq!(map.sample(-3.0), [r, g, b, 255]);
            let [r, g, b] = stops[stops.len() - 1];
            assert_eq!(map.sample(1.0), [r, g, b, 255]);
            assert_eq!(map.sample(7.0), [r, g, b, 255]);
        }
        assert_eq!(Colormap::Diverging.sample(0.5), [221, 221, 221, 255]);
    }

    #[test]
    fn scalar_range_ignores_non_finite_values() {
        let f = ScalarField::new(
            "d",
            vec![f64::NAN, 2.0, -1.0, f64::INFINITY],
            Colormap::Viridis,
        );
        assert_eq!(f.range, (-1.0, 2.0));
        assert_eq!(f.color(f64::NAN), BASE_COLOR);
        assert_eq!(f.color(-1.0), Colormap::Viridis.sample(0.0));
        assert_eq!(finite_range(&[]), (0.0, 1.0));
    }

    #[test]
    fn corner_colors_follow_vertices_or_faces() {
        let triangles = [[0, 1, 2], [2, 1, 3]];
        let faces = [0, 1];
        let vertex_labels = ColorLayer::Labels(LabelField {
            name: "v".into(),
            target: LabelTarget::Vertices,
            labels: vec![0, 1, NO_LABEL, 1],
            legend: vec![],
        });
        let c = vertex_labels.corner_colors(&triangles, &faces);
        assert_eq!(c.len(), 6);
        assert_eq!(c[0], label_color(0));
        assert_eq!(c[2], BASE_COLOR);
        assert_eq!(c[5], label_color(1));
        let face_labels = ColorLayer::Labels(LabelField {
            name: "f".into(),
            target: LabelTarget::Faces,
            labels: vec![3, 4],
            legend: vec![],
        });
        let c = face_labels.corner_colors(&triangles, &faces);
        assert!(c[..3].iter().all(|&x| x == label_color(3)));
        assert!(c[3..].iter().all(|&x| x == label_color(4)));
        assert_eq!(
            ColorLayer::None.corner_colors(&triangles, &faces),
            vec![BASE_COLOR; 6]
        );
    }

    #[test]
    fn size_check_names_the_layer() {
        let mesh = halfedge::generators::icosphere(0);
        let layer = ColorLayer::Scalar(ScalarField::new("x", vec![0.0; 3], Colormap::Viridis));
        let err = layer.check_size(&mesh).unwrap_err();
        assert!(err.contains("\"x\"") && err.contains("12 vertex"), "{err}");
    }
}
