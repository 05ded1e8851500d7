//! Adaptive refinement (Sec. 6) in the *Bendels–Klein* tool, on a plain mesh or at the
//! input of the document's hierarchy.

use super::*;

/// What a refinement is logged as in the recipe (it has no step).
const REFINE_HAS_NO_STEP: &str =
    "Bendels–Klein refine (adaptive refinement changes the connectivity: no recipe step)";

impl BendelsKlein {
    /// Adaptive refinement (Sec. 6) of the stretched deformable area.
    pub(super) fn refine(&mut self, ctx: &mut ToolContext<'_>) -> Result<(), ToolError> {
        self.ensure_session(ctx)?;
        if ctx.doc.hierarchy().is_some() {
            return self.refine_in_hierarchy(ctx);
        }
        let Some(session) = &mut self.session else {
            return Err(ToolError::new("Bendels–Klein: no edit to refine"));
        };
        let max = self.refine_threshold * ctx.mesh().mean_edge_length();
        let start = Instant::now();
        let scratch = self.scratch.sync(ctx.doc);
        let report = session.refine(scratch, RefineOptions::new(max))?;
        let t = start.elapsed();
        if report.new_vertices > 0 {
            ctx.begin_topology_edit("Bendels–Klein refine");
            *ctx.mesh_mut() = self.scratch.mesh().clone();
            ctx.doc
                .record_step(None, Err(REFINE_HAS_NO_STEP.to_owned()));
            self.recorded = None;
            self.regions = Some(session.regions().clone());
            self.paint.resize(ctx.mesh().vertex_slots(), PAINT_NONE);
        }
        ctx.info(format!(
            "Bendels–Klein refine: {} new vertices in {} passes ({}), longest edge {:.3e} \
             (threshold {max:.3e})",
            report.new_vertices,
            report.passes,
            ms(t),
            report.longest_edge
        ));
        self.show(ctx);
        Ok(())
    }

    /// Adaptive refinement of an edit made on the mesh of the document's hierarchy (at
    /// any level): through `BlendSession::refine_in_hierarchy`, which splits the stretched
    /// edges at the input and builds the hierarchy again, so that the document keeps the
    /// hierarchy at its level, every level stays reachable, and undo gives back the
    /// hierarchy as it was ([`Document::edit_hierarchy`](crate::document::Document::edit_hierarchy)).
    /// The threshold is a multiple of the mean edge length at full resolution, estimated
    /// from the current level's (scaled by the square root of the ratio of the face
    /// counts; exact at level 0). The rebuilt levels have other vertices than the ones the
    /// regions were given on: the regions are cleared, give them again to edit further.
    pub(super) fn refine_in_hierarchy(
        &mut self,
        ctx: &mut ToolContext<'_>,
    ) -> Result<(), ToolError> {
        let Some(session) = &self.session else {
            return Err(ToolError::new("Bendels–Klein: no edit to refine"));
        };
        let Some(h) = ctx.doc.hierarchy() else {
            return Err(ToolError::new("Bendels–Klein: no hierarchy"));
        };
        let faces = h.level_face_counts();
        let level = h.level_at_or_finer();
        let ratio = match (faces.get(level), faces.first()) {
            (Some(&here), Some(&input)) if input > 0 => here as f64 / input as f64,
            _ => 1.0,
        };
        let max = self.refine_threshold * ctx.mesh().mean_edge_length() * ratio.sqrt();
        let regions = session.regions().clone();
        let original = session.original_positions().to_vec();
        let a = session.transform();
        let options = self.options();
        let start = Instant::now();
        let report = ctx.doc.edit_hierarchy("Bendels–Klein refine", |h| {
            // The library refines through a session made on the hierarchy's own mesh
            // (this tool's session is bound to its scratch copy): the same regions,
            // rest positions, shape and transform (the blend is applied again, to the
            // same positions).
            let mesh = h.mesh_mut();
            if original.len() != mesh.vertex_slots() {
                return Err(ToolError::new(
                    "Bendels–Klein: the session does not fit the mesh; give the regions again",
                ));
            }
            mesh.positions_mut().copy_from_slice(&original);
            let mut s = BlendSession::new(h.mesh(), regions, options)?;
            s.apply(h.mesh_mut(), a)?;
            let report = s.refine_in_hierarchy(h, RefineOptions::new(max))?;
            let keep = report.new_vertices > 0;
            Ok::<_, ToolError>((report, keep))
        })?;
        let t = start.elapsed();
        if report.new_vertices > 0 {
            ctx.doc
                .record_step(None, Err(REFINE_HAS_NO_STEP.to_owned()));
            self.recorded = None;
            // The rebuilt hierarchy's levels have vertices of their own.
            self.handle_picks.clear();
            self.fixed_picks.clear();
            self.paint.clear();
            self.source = None;
            self.regions = None;
            self.session = None;
            self.stale = false;
            self.scratch.clear();
            self.reset_transform();
            ctx.clear_colors();
        } else {
            self.show(ctx);
        }
        let h = ctx.doc.hierarchy();
        ctx.info(format!(
            "Bendels–Klein refine: {} new vertices in {} passes ({}, at the input of the \
             hierarchy, rebuilt: {} levels, back at level {}), longest edge {:.3e} \
             (threshold {max:.3e}){}",
            report.new_vertices,
            report.passes,
            ms(t),
            h.map_or(0, |h| h.n_levels()),
            h.map_or(0, |h| h.level_at_or_finer()),
            report.longest_edge,
            if report.new_vertices > 0 {
                "; give the regions again to edit further"
            } else {
                ""
            }
        ));
        Ok(())
    }
}
