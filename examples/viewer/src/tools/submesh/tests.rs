//! Tests of the *Sub-mesh edits* tool.

use super::*;
use crate::tools::fixture::{bits, drag_through, refine_and_land, Expect, Fixture};
use halfedge::generators;

#[test]
fn rings_grow_with_the_count() {
    let mesh = generators::icosphere(3);
    let v = mesh.vertices().next().unwrap();
    let zero = rings_around(&mesh, v, 0);
    assert_eq!(zero.iter().filter(|&&b| b).count(), 1);
    let one = rings_around(&mesh, v, 1);
    assert_eq!(one.iter().filter(|&&b| b).count(), 1 + mesh.valence(v));
    let many = rings_around(&mesh, v, 100);
    assert_eq!(many.iter().filter(|&&b| b).count(), mesh.n_vertices());
}

#[test]
fn a_scale_without_propagation_leaves_the_host_alone() {
    let mesh = generators::icosphere(3);
    let mut tool = SubMeshEdit::new();
    tool.source = Source::Ring;
    tool.centre = mesh.vertices().next();
    tool.levels = 0;
    tool.operation = Operation::Scale;
    let sub = tool.submesh(&mesh).unwrap();
    let edit = tool.edit(&mesh, &sub).unwrap();
    let mut work = mesh.clone();
    sub.apply(&mut work, &edit, tool.propagation()).unwrap();
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        if !sub.contains_index(i) {
            assert_eq!(mesh.positions()[i], work.positions()[i]);
        }
    }
    assert_ne!(mesh.positions(), work.positions());
}

/// At level 2 of the fixture, a tool on the two rings around the top vertex with
/// no propagation.
fn top_rings(ctx: &ToolContext<'_>, operation: Operation) -> SubMeshEdit {
    let mesh = ctx.mesh();
    let mut tool = SubMeshEdit::new();
    tool.source = Source::Ring;
    tool.rings = 2;
    tool.centre = mesh
        .vertices()
        .max_by(|&a, &b| mesh.position(a).z.total_cmp(&mesh.position(b).z));
    tool.levels = 0;
    tool.operation = operation;
    tool
}

/// Refines the fixture's document to the input and returns the largest distance of
/// an input vertex whose ancestor at `level` is in `sub` from `map` of its input
/// position, checking that every other input vertex stayed bit for bit.
fn refine_and_measure(
    ctx: &mut ToolContext<'_>,
    input: &Mesh,
    level: usize,
    sub: &SubMesh,
    map: glam::DAffine3,
) -> f64 {
    let seen = refine_and_land(ctx, input, level, |a| {
        if sub.contains_index(a) {
            Expect::Lands(map)
        } else {
            Expect::Stays
        }
    });
    assert!(seen.landed > 20, "{} vertices inside", seen.landed);
    seen.worst
}

#[test]
fn a_submesh_rotated_at_a_coarse_level_lands_exactly_at_full_resolution() {
    // The tool marks the document's hierarchy with the rotation (the whole sub-mesh
    // at full strength) and the sub-mesh as the region.
    let level = 2;
    let mut fixture = Fixture::at_level(level);
    let input = fixture.input.clone();
    let mut ctx = fixture.ctx();
    let mut tool = top_rings(&ctx, Operation::Rotate);
    tool.angle = 35.0;
    let sub = tool.submesh(ctx.mesh()).unwrap();
    let axis = sub.axis(ctx.mesh()).unwrap();
    tool.run(&mut ctx).unwrap();
    let map = glam::DAffine3::from_translation(axis.point())
        * glam::DAffine3::from_axis_angle(axis.direction(), 35f64.to_radians())
        * glam::DAffine3::from_translation(-axis.point());
    let worst = refine_and_measure(&mut ctx, &input, level, &sub, map);
    // The icosphere's diagonal is about 3.5.
    assert!(
        worst < 1e-9,
        "a vertex is {worst:e} off its rotated position"
    );
}

#[test]
fn a_submesh_pulled_by_a_drag_at_a_coarse_level_lands_exactly() {
    let level = 2;
    let mut fixture = Fixture::at_level(level);
    let input = fixture.input.clone();
    let mut ctx = fixture.ctx();
    let mut tool = top_rings(&ctx, Operation::Pull);
    let sub = tool.submesh(ctx.mesh()).unwrap();
    let start = ctx.mesh().position(tool.centre.unwrap());
    let offset = DVec3::new(0.1, -0.05, 0.3);
    drag_through(
        &mut tool,
        &mut ctx,
        None,
        start,
        offset,
        &[0.0, 0.5, 0.8, 1.0],
    );
    ctx.doc.end_edit();
    let map = glam::DAffine3::from_translation(offset);
    let worst = refine_and_measure(&mut ctx, &input, level, &sub, map);
    assert!(
        worst < 1e-9,
        "a vertex is {worst:e} off its pulled position"
    );
}

#[test]
fn the_recorded_steps_replay_on_the_plain_mesh_bit_for_bit_and_follow_undo() {
    // Whole-mesh smoothing (the recipe's `all` region with no collar) and a scale of a
    // ring, recorded without a level; `apply_to_mesh` on the input gives the tool's mesh.
    let mesh = generators::icosphere(3);
    let mut tools =
        crate::tools::Headless::new(crate::document::Document::new(mesh.clone(), None, None));
    let mut ctx = tools.ctx();
    let mut tool = SubMeshEdit::new();
    tool.source = Source::All;
    tool.operation = Operation::Smooth;
    tool.smooth_whole = true;
    tool.run(&mut ctx).unwrap();
    tool.smooth_whole = false;
    tool.source = Source::Ring;
    tool.centre = mesh.vertices().nth(5);
    tool.operation = Operation::Scale;
    tool.run(&mut ctx).unwrap();
    let recipe = ctx.doc.recipe_log().recipe().unwrap();
    assert_eq!(
        recipe.steps.iter().map(|s| s.method()).collect::<Vec<_>>(),
        ["smooth", "scale"]
    );
    assert!(recipe.steps.iter().all(|s| s.level().is_none()));
    let mut replay = mesh.clone();
    multires::recipe::apply_to_mesh(&mut replay, &recipe, &mut multires::progress::Silent).unwrap();
    assert_eq!(bits(replay.positions()), bits(ctx.mesh().positions()));
    ctx.doc.undo();
    assert_eq!(ctx.doc.recipe_log().recipe().unwrap().steps.len(), 1);
    ctx.doc.redo();
    assert_eq!(ctx.doc.recipe_log().recipe().unwrap(), recipe);
}
