//! *Smooth pull* — a **placeholder demo tool**, to be replaced by the real editing
//! methods (Lee area editing, Bendels–Klein, sub-mesh edits). It proves the [`Tool`]
//! trait on the kernel alone: drag a picked vertex and its neighbourhood follows with a
//! Gaussian falloff of the Euclidean distance, `w(d) = exp(−4 (d / r)²)` for `d < 1.5 r`
//! (so `w(r) ≈ 0.018`), where `r` is the radius as a fraction of the bounding-box
//! diagonal. No paper: this is not one of the project's methods.

use glam::DVec3;
use halfedge::Mesh;
use rayon::prelude::*;
use three_d::egui;

use super::{
    bool_param, number_param, Drag, DragPhase, Overlay, Pick, Tool, ToolContext, ToolError,
};
use crate::colors::Colormap;

/// Cut-off of the falloff, in radii.
const CUTOFF: f64 = 1.5;

/// Drag a vertex with a Gaussian falloff (placeholder; see the module docs).
#[derive(Clone, Debug)]
pub struct SmoothPull {
    /// Falloff radius as a fraction of the bounding-box diagonal.
    pub radius: f64,
    /// Colour the mesh by the falloff weights of the picked vertex.
    pub show_weights: bool,
    pick: Option<Pick>,
    /// Vertices moved by the current drag: slot, position at the start, weight.
    moving: Vec<(u32, DVec3, f64)>,
}

impl Default for SmoothPull {
    fn default() -> Self {
        Self {
            radius: 0.08,
            show_weights: true,
            pick: None,
            moving: Vec::new(),
        }
    }
}

impl SmoothPull {
    /// The falloff weight of every vertex slot around `centre` (0 beyond the cut-off).
    pub fn weights(&self, mesh: &Mesh, centre: DVec3) -> Vec<f64> {
        let r = self.radius_world(mesh);
        let live: Vec<bool> = (0..mesh.vertex_slots())
            .map(|i| mesh.vertex_at(i).is_some())
            .collect();
        mesh.positions()
            .par_iter()
            .zip(live.par_iter())
            .map(|(p, &alive)| {
                if alive {
                    falloff(p.distance(centre), r)
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// The radius in world units.
    pub fn radius_world(&self, mesh: &Mesh) -> f64 {
        let diagonal = mesh
            .bounding_box()
            .map_or(1.0, |(lo, hi)| (hi - lo).length());
        (self.radius * diagonal).max(1e-12)
    }

    fn show(&self, ctx: &mut ToolContext<'_>) {
        if !self.show_weights {
            return;
        }
        if let Some(pick) = self.pick.filter(|p| ctx.mesh().is_valid_vertex(p.vertex)) {
            let w = self.weights(ctx.mesh(), ctx.mesh().position(pick.vertex));
            // Unaffected vertices keep the base colour.
            let w = w
                .into_iter()
                .map(|w| if w > 0.0 { w } else { f64::NAN })
                .collect();
            ctx.show_scalar("pull weight", w, Colormap::Viridis);
        }
    }
}

/// `exp(−4 (d/r)²)` within `CUTOFF · r`, else 0.
fn falloff(d: f64, r: f64) -> f64 {
    if d >= CUTOFF * r {
        0.0
    } else {
        (-4.0 * (d / r) * (d / r)).exp()
    }
}

impl Tool for SmoothPull {
    fn name(&self) -> &str {
        "Smooth pull (demo)"
    }

    fn description(&self) -> &str {
        "PLACEHOLDER demo tool, not one of the project's methods: drag a vertex and its \
         neighbourhood follows with a Gaussian falloff. It will be replaced by the real \
         editing tools."
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut ToolContext<'_>) {
        ui.colored_label(
            egui::Color32::from_rgb(230, 160, 40),
            "⚠ Placeholder demo tool",
        );
        let r = ui.add(
            egui::Slider::new(&mut self.radius, 0.01..=0.5)
                .text("radius")
                .logarithmic(true)
                .custom_formatter(|x, _| format!("{:.1} %", 100.0 * x)),
        );
        let w = ui.checkbox(&mut self.show_weights, "show weights");
        if r.changed() || w.changed() {
            if self.show_weights {
                self.show(ctx);
            } else {
                ctx.clear_colors();
            }
        }
        ui.weak("Press on the mesh and drag: the point follows the mouse in the view plane.");
    }

    fn on_pick(&mut self, pick: Option<&Pick>, ctx: &mut ToolContext<'_>) {
        self.pick = pick.copied();
        self.show(ctx);
    }

    fn wants_drag(&self, _pick: &Pick) -> bool {
        true
    }

    fn on_drag(&mut self, drag: &Drag, ctx: &mut ToolContext<'_>) {
        match drag.phase {
            DragPhase::Start => {
                self.pick = Some(drag.pick);
                ctx.begin_edit("Smooth pull (demo)");
                let mesh = ctx.mesh();
                let w = self.weights(mesh, drag.start);
                self.moving = w
                    .iter()
                    .enumerate()
                    .filter(|(_, &w)| w > 0.0)
                    .map(|(i, &w)| (i as u32, mesh.positions()[i], w))
                    .collect();
            }
            DragPhase::Move | DragPhase::End => {
                let delta = drag.delta();
                let positions = ctx.positions_mut();
                for &(i, base, w) in &self.moving {
                    positions[i as usize] = base + w * delta;
                }
                if drag.phase == DragPhase::End {
                    let n = self.moving.len();
                    self.moving.clear();
                    ctx.info(format!(
                        "Smooth pull: moved {n} vertices, displacement {:.4}",
                        delta.length()
                    ));
                    self.show(ctx);
                }
            }
        }
    }

    fn set_parameter(
        &mut self,
        name: &str,
        value: &serde_json::Value,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        match name {
            "radius" => {
                let r = number_param(name, value)?;
                if !(r > 0.0 && r <= 1.0) {
                    return Err(ToolError::new(format!(
                        "radius {r} out of range: it is a fraction of the diagonal in (0, 1]"
                    )));
                }
                self.radius = r;
            }
            "show_weights" => self.show_weights = bool_param(name, value)?,
            _ => {
                return Err(ToolError::unknown_parameter(
                    self.name(),
                    name,
                    &["radius", "show_weights"],
                ))
            }
        }
        self.show(ctx);
        Ok(())
    }

    fn parameters(&self) -> Vec<(&'static str, serde_json::Value)> {
        vec![
            ("radius", self.radius.into()),
            ("show_weights", self.show_weights.into()),
        ]
    }

    fn overlay(&self, mesh: &Mesh, overlay: &mut Overlay) {
        if let Some(pick) = self.pick.filter(|p| mesh.is_valid_vertex(p.vertex)) {
            overlay.marker(mesh.position(pick.vertex), Overlay::PICK, 1.3);
        }
    }

    fn on_mesh_replaced(&mut self, mesh: &Mesh) {
        self.moving.clear();
        if self.pick.is_some_and(|p| !mesh.is_valid_vertex(p.vertex)) {
            self.pick = None;
        }
    }

    fn activate(&mut self, ctx: &mut ToolContext<'_>) {
        self.show(ctx);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falloff_is_one_at_the_centre_and_zero_beyond_the_cutoff() {
        assert_eq!(falloff(0.0, 2.0), 1.0);
        assert!((falloff(2.0, 2.0) - (-4.0f64).exp()).abs() < 1e-15);
        assert_eq!(falloff(3.0, 2.0), 0.0);
        assert!(falloff(1.0, 2.0) > falloff(1.5, 2.0));
    }

    #[test]
    fn weights_are_zero_for_far_vertices() {
        let mesh = halfedge::generators::icosphere(3);
        let tool = SmoothPull::default();
        let v = mesh.vertices().next().unwrap();
        let w = tool.weights(&mesh, mesh.position(v));
        assert_eq!(w[mesh.vertex_index(v)], 1.0);
        let r = tool.radius_world(&mesh);
        for u in mesh.vertices() {
            let d = mesh.position(u).distance(mesh.position(v));
            assert_eq!(w[mesh.vertex_index(u)] == 0.0, d >= CUTOFF * r);
        }
    }
}
