//! The *Inspect* tool: what is under the mouse (vertex index, position, valence,
//! boundary, normal; face index, corners, area), and colourings that show the display
//! API at work: valence and connected components as labels, the distance from the picked
//! vertex as a scalar field.

use std::collections::VecDeque;

use halfedge::{Mesh, VertexId};
use three_d::egui;

use super::params::{self, Param, Widget};
use super::{choice_name, choice_param, Overlay, Pick, Tool, ToolContext, ToolError};
use crate::colors::{format_value, Colormap, NO_LABEL};

/// What the Inspect tool colours the mesh by.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum InspectColoring {
    /// Nothing (the base colour).
    #[default]
    None,
    /// Valence classes (labels).
    Valence,
    /// Connected components (labels).
    Components,
    /// Boundary vs interior vertices (labels).
    Boundary,
    /// Euclidean distance from the picked vertex (scalar field).
    Distance,
}

impl InspectColoring {
    const ALL: [(InspectColoring, &'static str); 5] = [
        (InspectColoring::None, "none"),
        (InspectColoring::Valence, "valence"),
        (InspectColoring::Components, "components"),
        (InspectColoring::Boundary, "boundary"),
        (InspectColoring::Distance, "distance"),
    ];

    fn name(self) -> &'static str {
        choice_name(&Self::ALL, self)
    }
}

/// Shows information on the picked vertex and face (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct Inspect {
    pick: Option<Pick>,
    coloring: InspectColoring,
}

impl Inspect {
    fn recolor(&self, ctx: &mut ToolContext<'_>) {
        let mesh = ctx.mesh();
        match self.coloring {
            InspectColoring::None => ctx.clear_colors(),
            InspectColoring::Valence => {
                let mut labels = vec![NO_LABEL; mesh.vertex_slots()];
                for v in mesh.vertices() {
                    labels[mesh.vertex_index(v)] = mesh.valence(v).clamp(3, 9) as u32 - 3;
                }
                let legend = (0..7)
                    .map(|k| {
                        let text = match k {
                            0 => "valence ≤ 3".to_string(),
                            6 => "valence ≥ 9".to_string(),
                            _ => format!("valence {}", k + 3),
                        };
                        (k, text)
                    })
                    .collect();
                ctx.show_vertex_labels("valence", labels, legend);
            }
            InspectColoring::Components => {
                let (labels, sizes) = components(mesh);
                let count = sizes.len();
                let mut order: Vec<usize> = (0..count).collect();
                order.sort_by_key(|&c| std::cmp::Reverse(sizes[c]));
                let legend = order
                    .into_iter()
                    .map(|c| (c as u32, format!("{} vertices", sizes[c])))
                    .collect();
                let name = format!("{count} connected component{}", plural(count));
                ctx.show_vertex_labels(&name, labels, legend);
            }
            InspectColoring::Boundary => {
                let mut labels = vec![NO_LABEL; mesh.vertex_slots()];
                for v in mesh.vertices() {
                    labels[mesh.vertex_index(v)] = u32::from(mesh.is_boundary_vertex(v));
                }
                let legend = vec![(0, "interior".into()), (1, "boundary".into())];
                ctx.show_vertex_labels("boundary vertices", labels, legend);
            }
            InspectColoring::Distance => {
                let Some(pick) = self.pick else {
                    ctx.clear_colors();
                    ctx.info("Inspect: pick a vertex to colour by distance");
                    return;
                };
                let origin = mesh.position(pick.vertex);
                let mut values = vec![f64::NAN; mesh.vertex_slots()];
                for v in mesh.vertices() {
                    values[mesh.vertex_index(v)] = mesh.position(v).distance(origin);
                }
                let name = format!("distance from v{}", mesh.vertex_index(pick.vertex));
                ctx.show_scalar(&name, values, Colormap::Viridis);
            }
        }
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// Connected components by breadth-first search over edges: a label per vertex slot
/// (isolated vertices: [`NO_LABEL`]) and the number of vertices of each component.
pub fn components(mesh: &Mesh) -> (Vec<u32>, Vec<usize>) {
    let mut labels = vec![NO_LABEL; mesh.vertex_slots()];
    let mut sizes = Vec::new();
    let mut queue: VecDeque<VertexId> = VecDeque::new();
    for seed in mesh.vertices() {
        if labels[mesh.vertex_index(seed)] != NO_LABEL || mesh.is_isolated(seed) {
            continue;
        }
        let label = sizes.len() as u32;
        let mut size = 1;
        labels[mesh.vertex_index(seed)] = label;
        queue.push_back(seed);
        while let Some(v) = queue.pop_front() {
            for w in mesh.adjacent_vertices(v) {
                let slot = &mut labels[mesh.vertex_index(w)];
                if *slot == NO_LABEL {
                    *slot = label;
                    size += 1;
                    queue.push_back(w);
                }
            }
        }
        sizes.push(size);
    }
    (labels, sizes)
}

/// The parameters of [`Inspect`] (see [`params`]).
const PARAMS: &[Param<Inspect>] = &[Param::new(
    "color",
    "Colour by",
    Widget::Choice(|| params::names(&InspectColoring::ALL)),
    |t| t.coloring.name().into(),
    |t, v, ctx| {
        t.coloring = choice_param(&InspectColoring::ALL, "color", v)?;
        t.recolor(ctx);
        Ok(())
    },
)];

impl Tool for Inspect {
    fn name(&self) -> &str {
        "Inspect"
    }

    fn description(&self) -> &str {
        "Click the mesh to see the vertex and face under the mouse. Colour the mesh by \
         valence, components, boundary or distance."
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>) {
        params::widget(ui, PARAMS, "color", self, ctx);
        ui.add_space(4.0);
        let mesh = ctx.mesh();
        let Some(pick) = self.pick.filter(|p| mesh.is_valid_vertex(p.vertex)) else {
            ui.weak("Nothing picked: click the mesh.");
            return;
        };
        let v = pick.vertex;
        let p = mesh.position(v);
        let n = mesh.vertex_normal(v);
        egui::Grid::new("inspect-vertex")
            .num_columns(2)
            .spacing([12.0, 2.0])
            .show(ui, |ui| {
                ui.strong("Vertex");
                ui.strong(format!("v{}", mesh.vertex_index(v)));
                ui.end_row();
                ui.label("position");
                ui.monospace(format!("{} {} {}", fmt(p.x), fmt(p.y), fmt(p.z)));
                ui.end_row();
                ui.label("normal");
                ui.monospace(format!("{:.3} {:.3} {:.3}", n.x, n.y, n.z));
                ui.end_row();
                ui.label("valence");
                ui.label(mesh.valence(v).to_string());
                ui.end_row();
                ui.label("boundary");
                ui.label(if mesh.is_boundary_vertex(v) {
                    "yes"
                } else {
                    "no"
                });
                ui.end_row();
                let ring: Vec<String> = mesh
                    .adjacent_vertices(v)
                    .take(8)
                    .map(|w| mesh.vertex_index(w).to_string())
                    .collect();
                ui.label("neighbours");
                ui.label(format!(
                    "{}{}",
                    ring.join(", "),
                    if mesh.valence(v) > 8 { ", …" } else { "" }
                ));
                ui.end_row();
                if let Some(f) = pick.face.filter(|&f| mesh.is_valid_face(f)) {
                    ui.strong("Face");
                    ui.strong(format!("f{}", mesh.face_index(f)));
                    ui.end_row();
                    let [a, b, c] = mesh.triangle(f).map(|v| mesh.vertex_index(v));
                    ui.label("corners");
                    ui.label(format!("{a}, {b}, {c}"));
                    ui.end_row();
                    ui.label("area");
                    ui.label(format_value(mesh.face_area(f)));
                    ui.end_row();
                    ui.label("hit point");
                    let q = pick.point;
                    ui.monospace(format!("{} {} {}", fmt(q.x), fmt(q.y), fmt(q.z)));
                    ui.end_row();
                }
            });
    }

    fn on_pick(&mut self, pick: Option<&Pick>, ctx: &mut ToolContext<'_>) {
        self.pick = pick.copied();
        if let Some(p) = pick {
            let mesh = ctx.mesh();
            let msg = format!(
                "v{} (valence {}){}",
                mesh.vertex_index(p.vertex),
                mesh.valence(p.vertex),
                p.face
                    .map(|f| format!(", f{}", mesh.face_index(f)))
                    .unwrap_or_default()
            );
            ctx.info(format!("Picked {msg}"));
        }
        if self.coloring == InspectColoring::Distance {
            self.recolor(ctx);
        }
    }

    fn set_parameter(
        &mut self,
        name: &str,
        value: &serde_json::Value,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        // (The name is copied: the setter borrows the tool mutably.)
        let tool = self.name().to_owned();
        params::set(&tool, PARAMS, self, name, value, ctx)
    }

    fn parameters(&self) -> Vec<(&'static str, serde_json::Value)> {
        params::list(PARAMS, self)
    }

    fn overlay(&self, mesh: &Mesh, overlay: &mut Overlay) {
        let Some(pick) = self.pick.filter(|p| mesh.is_valid_vertex(p.vertex)) else {
            return;
        };
        let p = mesh.position(pick.vertex);
        overlay.marker(p, Overlay::PICK, 1.0);
        for w in mesh.adjacent_vertices(pick.vertex) {
            overlay.marker(mesh.position(w), Overlay::SECONDARY, 0.6);
            overlay.segment(p, mesh.position(w), Overlay::SECONDARY);
        }
    }

    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        if self.pick.is_some_and(|p| !mesh.is_valid_vertex(p.vertex)) {
            self.pick = None;
        }
    }

    fn activate(&mut self, ctx: &mut ToolContext<'_>) {
        if self.coloring != InspectColoring::None {
            self.recolor(ctx);
        }
    }
}

fn fmt(x: f64) -> String {
    format!("{x:.5}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use halfedge::generators;

    #[test]
    fn components_of_two_spheres() {
        let a = generators::icosphere(1);
        let (pa, ta) = generators::weld_exact(&a);
        let mut positions = pa.clone();
        positions.extend(pa.iter().map(|p| *p + glam::DVec3::X * 3.0));
        let offset = pa.len() as u32;
        let mut triangles = ta.clone();
        triangles.extend(ta.iter().map(|t| t.map(|i| i + offset)));
        let (mesh, _) = Mesh::from_triangles(&positions, &triangles).unwrap();
        let (labels, sizes) = components(&mesh);
        assert_eq!(sizes, vec![pa.len(), pa.len()]);
        assert!(labels[..pa.len()].iter().all(|&l| l == 0));
        assert!(labels[pa.len()..].iter().all(|&l| l == 1));
    }
}
