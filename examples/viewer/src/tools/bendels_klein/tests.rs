//! Tests of the *Bendels–Klein* tool.

use super::*;
use crate::tools::fixture::{bits, refine_and_land, Expect, Fixture, Landing};
use crate::tools::Status;

/// The number in "… refine: N new vertices …" of the status line.
fn new_vertices(status: &Status) -> usize {
    let rest = status
        .message
        .split("refine: ")
        .nth(1)
        .unwrap_or_else(|| panic!("no refine report: {}", status.message));
    rest.split(' ').next().unwrap().parse().unwrap()
}

/// Paints the top cap (z > 0.7) of `mesh` as the handle and its lower half as the
/// fixed part.
fn paint_cap_and_lower_half(tool: &mut BendelsKlein, mesh: &Mesh) {
    tool.paint = (0..mesh.vertex_slots())
        .map(|i| match mesh.vertex_at(i).map(|v| mesh.position(v).z) {
            Some(z) if z > 0.7 => PAINT_HANDLE,
            Some(z) if z < 0.0 => PAINT_FIXED,
            _ => PAINT_NONE,
        })
        .collect();
    tool.source = Some(RegionSource::Painted);
}

/// Paints the handle (the top cap) and the fixed part (the lower half) of the level
/// shown, pulls the handle up, refines, and checks that the hierarchy survives.
fn refine_keeps_the_hierarchy(level: usize) {
    let mut fixture = Fixture::at_level(level);
    let input = fixture.input.clone();
    let mut ctx = fixture.ctx();
    let mut tool = BendelsKlein::default();
    paint_cap_and_lower_half(&mut tool, ctx.mesh());
    tool.build(&mut ctx).unwrap();
    assert!(tool.session.is_some());
    tool.set_parameter("translate", &serde_json::json!([0.0, 0.0, 1.0]), &mut ctx)
        .unwrap();
    ctx.doc.end_edit();
    let roles = tool.session.as_ref().unwrap().regions().roles().to_vec();
    let ancestors = ctx.doc.hierarchy().unwrap().ancestors(level).unwrap();
    let before_positions = bits(ctx.mesh().positions());
    let before_vertices = ctx.mesh().n_vertices();
    let steps = ctx.doc.undo_len();
    tool.refine_threshold = 1.5;
    tool.apply(&mut ctx).unwrap();
    assert!(!ctx.status.is_error, "{}", ctx.status.message);
    let added = new_vertices(&*ctx.status);
    assert!(added > 0, "{}", ctx.status.message);

    // The document still holds the hierarchy, at the same level, with levels.
    let h = ctx
        .doc
        .hierarchy()
        .expect("the refinement dropped the hierarchy");
    assert_eq!(h.current_level(), Some(level));
    assert!(h.n_levels() > 1);
    assert!(std::ptr::eq(ctx.mesh(), h.mesh()));
    let coarsest = h.coarsest_level();
    let after_vertices = ctx.mesh().n_vertices();
    assert_eq!(ctx.doc.undo_len(), steps + 1);
    assert_eq!(ctx.doc.undo_labels().last(), Some("Bendels–Klein refine"));

    // Every level is reachable, the new vertices are at the input (one slider drag).
    ctx.doc.go_to_level(0, "levels").unwrap();
    ctx.mesh().check().unwrap();
    assert_eq!(ctx.mesh().n_vertices(), input.n_vertices() + added);
    // The edit reached the input as the library carries it: the fixed part did not
    // move, the handle is its translated input (local-frame detail, marked handle).
    let fine = ctx.mesh();
    let mut handle = 0;
    for v in input.vertices() {
        let (p, q) = (input.position(v), fine.position(v));
        match roles[ancestors[input.vertex_index(v)] as usize] {
            Role::Fixed => assert_eq!(q, p, "fixed vertex {v} moved"),
            Role::Handle => {
                handle += 1;
                assert!(
                    (q - p - DVec3::Z).length() < 1e-9,
                    "handle vertex {v} at {q}"
                );
            }
            Role::Deformable => {}
        }
    }
    assert!(handle > 10, "{handle} handle vertices");
    ctx.doc.go_to_level(coarsest, "levels").unwrap();
    ctx.mesh().check().unwrap();
    ctx.doc.go_to_level(level, "levels").unwrap();
    ctx.mesh().check().unwrap();
    ctx.doc.end_edit();
    assert_eq!(ctx.mesh().n_vertices(), after_vertices);

    // Undo: the level walk, then the refinement, gives the hierarchy as it was.
    assert_eq!(ctx.doc.undo().as_deref(), Some("levels"));
    assert_eq!(ctx.doc.undo().as_deref(), Some("Bendels–Klein refine"));
    tool.on_mesh_replaced(ctx.doc.mesh());
    let h = ctx.doc.hierarchy().expect("undo gives the hierarchy back");
    assert_eq!(h.current_level(), Some(level));
    assert_eq!(ctx.mesh().n_vertices(), before_vertices);
    assert_eq!(bits(ctx.mesh().positions()), before_positions);
    // Redo gives the refined hierarchy again, undo the one before.
    assert_eq!(ctx.doc.redo().as_deref(), Some("Bendels–Klein refine"));
    assert_eq!(ctx.doc.hierarchy().unwrap().current_level(), Some(level));
    assert_eq!(ctx.mesh().n_vertices(), after_vertices);
    ctx.doc.undo();
    assert_eq!(bits(ctx.mesh().positions()), before_positions);
    ctx.doc.go_to_level(0, "levels").unwrap();
    assert_eq!(ctx.mesh().n_vertices(), input.n_vertices());
}

/// At level 2 of the fixture: paints the handle (top cap) and the fixed part (lower
/// half), turns the handle by 40° about x and lifts it, as one undo step. Returns the
/// tool (its session made).
fn rotate_the_cap(ctx: &mut ToolContext<'_>) -> BendelsKlein {
    let mut tool = BendelsKlein::default();
    paint_cap_and_lower_half(&mut tool, ctx.mesh());
    tool.build(ctx).unwrap();
    for (name, value) in [
        ("axis", serde_json::json!([1.0, 0.0, 0.0])),
        ("angle", serde_json::json!(40.0)),
        ("translate", serde_json::json!([0.0, 0.1, 0.3])),
    ] {
        tool.set_parameter(name, &value, ctx).unwrap();
    }
    assert!(!ctx.status.is_error, "{}", ctx.status.message);
    ctx.doc.end_edit();
    tool
}

#[test]
fn a_handle_rotated_at_a_coarse_level_lands_exactly_at_full_resolution() {
    // Refined to the input, the handle is exactly the handle's rigid transform of its
    // input vertices and the fixed half has not moved, bit for bit: the tool marks the
    // document's hierarchy with the handle's transform and the moved region.
    let level = 2;
    let mut fixture = Fixture::at_level(level);
    let input = fixture.input.clone();
    let mut ctx = fixture.ctx();
    let tool = rotate_the_cap(&mut ctx);
    let a_map = glam::DAffine3::from_mat4(tool.transform());
    let roles = tool.session.as_ref().unwrap().regions().roles().to_vec();
    let Landing {
        landed: handle,
        stayed: fixed,
        worst,
    } = refine_and_land(&mut ctx, &input, level, |a| match roles[a] {
        Role::Fixed => Expect::Stays,
        Role::Handle => Expect::Lands(a_map),
        Role::Deformable => Expect::Free,
    });
    assert!(handle > 10 && fixed > 100, "{handle} handle, {fixed} fixed");
    // The icosphere's diagonal is about 3.5.
    assert!(
        worst < 1e-9,
        "a handle vertex is {worst:e} off its rigid target"
    );
}

#[test]
fn undoing_a_coarse_edit_drops_its_marks() {
    // The edit undone at its level, the hierarchy refines to the input bit for bit:
    // the handle's mark went with the positions it described.
    let mut fixture = Fixture::at_level(2);
    let input = fixture.input.clone();
    let mut ctx = fixture.ctx();
    rotate_the_cap(&mut ctx);
    assert_eq!(ctx.doc.undo().as_deref(), Some("Bendels–Klein transform"));
    ctx.doc.go_to_level(0, "levels").unwrap();
    assert_eq!(bits(ctx.mesh().positions()), bits(input.positions()));
}

#[test]
fn refinement_at_a_coarse_level_keeps_the_hierarchy_and_undoes_exactly() {
    refine_keeps_the_hierarchy(2);
}

#[test]
fn refinement_at_level_0_of_a_hierarchy_keeps_the_hierarchy() {
    refine_keeps_the_hierarchy(0);
}
