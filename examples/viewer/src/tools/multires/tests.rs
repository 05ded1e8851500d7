//! Tests of the *Multiresolution* tool.

use super::*;
use crate::document::Document;
use crate::tools::Headless;
use halfedge::generators;

/// A document on `mesh` and the rest of what a tool context borrows, for tests
/// without a window.
fn fixture(mesh: Mesh) -> Headless {
    Headless::new(Document::new(mesh, None, None))
}

/// Polls `tool` like the viewer does every frame until its build is done.
fn poll_until_idle(tool: &mut Multires, ctx: &mut ToolContext<'_>) -> Background {
    let start = Instant::now();
    loop {
        match tool.poll(ctx) {
            Background::Running => {
                assert!(
                    start.elapsed() < Duration::from_secs(120),
                    "the build does not end"
                );
                std::thread::sleep(Duration::from_millis(5));
            }
            done => return done,
        }
    }
}

#[test]
fn a_cancelled_build_leaves_the_tool_idle_and_the_mesh_unchanged() {
    // Large enough that the first level takes far longer than asking to cancel.
    let input = generators::icosphere(7);
    let mut fixture = fixture(input.clone());
    let mut ctx = fixture.ctx();
    let mut tool = Multires::new();
    tool.target_faces = 200;
    tool.apply(&mut ctx).unwrap();
    tool.cancel_build();
    assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
    assert!(
        ctx.status.message.starts_with("Build cancelled"),
        "{}",
        ctx.status.message
    );
    assert!(ctx.doc.hierarchy().is_none());
    assert!(ctx.mesh().positions() == input.positions());
    assert_eq!(ctx.mesh().n_faces(), input.n_faces());
    // The tool builds again afterwards.
    tool.target_faces = 20_000;
    tool.apply(&mut ctx).unwrap();
    assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
    assert!(ctx.doc.hierarchy().is_some());
}

#[test]
fn the_detail_switch_reaches_the_hierarchy() {
    let mut fixture = fixture(generators::icosphere(3));
    let mut ctx = fixture.ctx();
    let mut tool = Multires::new();
    tool.target_faces = 100;
    assert!(tool
        .set_parameter("detail", &"sideways".into(), &mut ctx)
        .is_err());
    for (name, mode) in [
        ("translation", DetailMode::Translation),
        ("local", DetailMode::LocalFrame),
    ] {
        tool.set_parameter("detail", &name.into(), &mut ctx)
            .unwrap();
        assert!(tool.parameters().contains(&("detail", name.into())));
        tool.apply(&mut ctx).unwrap();
        assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
        assert_eq!(ctx.doc.hierarchy().unwrap().detail_mode(), mode);
    }
}

#[test]
fn background_build_gives_the_levels_of_a_direct_build_and_undo_works() {
    let input = generators::icosphere(4);
    let mut fixture = fixture(input.clone());
    let mut ctx = fixture.ctx();
    let mut tool = Multires::new();
    tool.target_faces = 200;
    tool.apply(&mut ctx).unwrap();
    assert!(tool.is_building());
    assert!(ctx.status.message.starts_with("Building rounds hierarchy"));
    // The rest of the tool waits for the build.
    assert!(tool.set_parameter("level", &1.into(), &mut ctx).is_err());
    assert!(tool.apply(&mut ctx).is_err());
    assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
    assert!(!tool.is_building());
    assert!(
        ctx.status.message.starts_with("Built rounds hierarchy"),
        "{}",
        ctx.status.message
    );
    let direct = Hierarchy::build(
        input.clone(),
        &HierarchyOptions::rounds()
            .with_max_normal_deviation(90f64.to_radians())
            .with_target_faces(200),
    )
    .unwrap();
    let h = ctx.doc.hierarchy().expect("built");
    assert_eq!(h.level_face_counts(), direct.level_face_counts());
    assert!(h.coarsest_level() >= 2);
    let coarsest = h.coarsest_level();
    // The document stays the input, bit for bit.
    assert_eq!(ctx.mesh().positions(), input.positions());
    // Level changes and undo work on the hierarchy from the thread.
    tool.set_parameter("level", &coarsest.into(), &mut ctx)
        .unwrap();
    ctx.doc.end_edit();
    assert_eq!(ctx.mesh().n_faces(), direct.level_face_counts()[coarsest]);
    ctx.mesh().check().unwrap();
    assert!(ctx.doc.undo().is_some());
    assert_eq!(ctx.mesh().positions(), input.positions());
    assert_eq!(ctx.mesh().n_faces(), input.n_faces());
    assert!(ctx.doc.redo().is_some());
    assert_eq!(ctx.mesh().n_faces(), direct.level_face_counts()[coarsest]);
}

#[test]
fn build_errors_reach_the_status_line() {
    let mut fixture = fixture(generators::icosphere(2));
    let mut ctx = fixture.ctx();
    let mut tool = Multires::new();
    // Out of range: the library refuses it.
    tool.max_normal_deviation = 200.0;
    tool.start_build(&mut ctx).unwrap();
    match poll_until_idle(&mut tool, &mut ctx) {
        Background::Failed(e) => assert!(e.0.contains("max_normal_deviation"), "{e}"),
        other => panic!("expected a failure, got {other:?}"),
    }
    assert!(ctx.status.is_error);
    assert!(ctx.status.message.starts_with("Build failed"));
    assert!(ctx.doc.hierarchy().is_none() && !tool.is_building());
    assert_eq!(ctx.doc.undo_len(), 0);
}

#[test]
fn a_mesh_changed_during_the_build_refuses_the_result() {
    let mut fixture = fixture(generators::icosphere(2));
    let mut ctx = fixture.ctx();
    let mut tool = Multires::new();
    tool.target_faces = 40;
    tool.start_build(&mut ctx).unwrap();
    ctx.positions_mut()[0] += DVec3::X;
    ctx.doc.end_edit();
    assert!(matches!(
        poll_until_idle(&mut tool, &mut ctx),
        Background::Failed(_)
    ));
    assert!(ctx.doc.hierarchy().is_none());
}

#[test]
fn progress_fraction_counts_the_faces_removed_towards_the_target() {
    assert_eq!(build_fraction(1000, 100, 1000), 0.0);
    assert_eq!(build_fraction(1000, 100, 550), 0.5);
    assert_eq!(build_fraction(1000, 100, 100), 1.0);
    assert_eq!(build_fraction(1000, 100, 50), 1.0);
    assert_eq!(build_fraction(50, 100, 50), 1.0);
}

/// Builds a hierarchy of `mesh` in the document through the tool, down to `target`.
fn built(fixture: &mut Headless, target: usize) -> Multires {
    let mut tool = Multires::new();
    tool.target_faces = target;
    let mut ctx = fixture.ctx();
    tool.apply(&mut ctx).unwrap();
    assert_eq!(poll_until_idle(&mut tool, &mut ctx), Background::Idle);
    tool
}

#[test]
fn the_document_shows_the_hierarchys_own_mesh_at_every_level() {
    let mut fixture = fixture(generators::icosphere(3));
    let mut tool = built(&mut fixture, 100);
    let mut ctx = fixture.ctx();
    let coarsest = ctx.doc.hierarchy().unwrap().coarsest_level();
    for level in [coarsest, 1, 0, coarsest] {
        tool.go_to_level(level, &mut ctx).unwrap();
        let h = ctx.doc.hierarchy().unwrap();
        // One mesh: the document's mesh is the hierarchy's, not a copy of it.
        assert!(std::ptr::eq(ctx.mesh(), h.mesh()));
        assert_eq!(h.current_level(), Some(level));
        assert_eq!(ctx.mesh().n_faces(), h.level_face_counts()[level]);
        assert_eq!(tool.parameters()[4], ("level", level.into()));
    }
}

#[test]
fn an_edit_at_a_coarse_level_is_carried_to_the_fine_level() {
    let input = generators::icosphere(3);
    let mut fixture = fixture(input.clone());
    let mut tool = built(&mut fixture, 100);
    let mut ctx = fixture.ctx();
    let coarsest = ctx.doc.hierarchy().unwrap().coarsest_level();
    tool.go_to_level(coarsest, &mut ctx).unwrap();
    ctx.doc.end_edit();
    let t = DVec3::new(0.25, -0.5, 0.125);
    ctx.begin_edit("move");
    for p in ctx.positions_mut() {
        *p += t;
    }
    ctx.doc.end_edit();
    tool.go_to_level(0, &mut ctx).unwrap();
    ctx.doc.end_edit();
    assert_eq!(ctx.mesh().n_faces(), input.n_faces());
    for v in input.vertices() {
        let d = ctx.mesh().position(v) - input.position(v) - t;
        assert!(d.length() < 1e-9, "{v}: off by {d}");
    }
    // Undo: level 0, the move, the coarsening, the build; each exact.
    let labels: Vec<String> = ctx.doc.undo_labels().map(str::to_owned).collect();
    assert_eq!(
        labels,
        [
            "Build hierarchy",
            &format!("Level {coarsest}"),
            "move",
            "Level 0"
        ]
    );
    for _ in 0..3 {
        ctx.doc.undo().unwrap();
    }
    assert_eq!(ctx.mesh().positions(), input.positions());
    assert_eq!(ctx.mesh().n_faces(), input.n_faces());
    assert!(ctx.doc.hierarchy().is_some());
    ctx.doc.undo().unwrap();
    assert!(
        ctx.doc.hierarchy().is_none(),
        "undoing the build gives the plain mesh"
    );
    assert_eq!(ctx.mesh().positions(), input.positions());
    ctx.doc.redo().unwrap();
    assert!(ctx.doc.hierarchy().is_some());
}

#[test]
fn labels_live_in_the_mesh_and_ride_along_through_the_levels() {
    let mut fixture = fixture(generators::icosphere(3));
    let mut tool = built(&mut fixture, 100);
    let mut ctx = fixture.ctx();
    tool.set_parameter("frontier", &"plane".into(), &mut ctx)
        .unwrap();
    tool.set_parameter("normal", &"x".into(), &mut ctx).unwrap();
    let v = ctx.mesh().vertices().next().unwrap();
    let pick = Pick {
        vertex: v,
        face: None,
        point: DVec3::ZERO,
    };
    tool.on_pick(Some(&pick), &mut ctx);
    let fine = SubMeshLabels::of(ctx.mesh()).expect("labelled");
    let (host, sub, front) = fine.counts();
    assert!(host > 0 && sub > 0 && front > 0, "{:?}", fine.counts());
    assert_eq!(host + sub + front, ctx.mesh().n_vertices());
    let coarsest = ctx.doc.hierarchy().unwrap().coarsest_level();
    tool.go_to_level(coarsest, &mut ctx).unwrap();
    // The same attribute, at the coarse level: every live vertex labelled.
    let coarse = SubMeshLabels::of(ctx.mesh()).expect("labels ride along");
    let (h, s, f) = coarse.counts();
    assert_eq!(h + s + f, ctx.mesh().n_vertices());
    assert!(s > 0 && h > 0);
    // The other tools read them there.
    let mut sub_tool = super::super::SubMeshEdit::new();
    sub_tool
        .set_parameter("source", &"labels".into(), &mut ctx)
        .unwrap();
    assert!(sub_tool.submesh(ctx.mesh()).is_ok());
    // Back at level 0 the labels are the ones made there.
    tool.go_to_level(0, &mut ctx).unwrap();
    assert_eq!(SubMeshLabels::of(ctx.mesh()), Some(fine));
    // Clearing removes them from the mesh.
    tool.set_parameter("clear_picks", &true.into(), &mut ctx)
        .unwrap();
    assert!(SubMeshLabels::of(ctx.mesh()).is_none());
}

#[test]
fn the_label_layer_follows_the_mesh_through_undo() {
    let mut fixture = fixture(generators::icosphere(3));
    let mut tool = built(&mut fixture, 100);
    let mut ctx = fixture.ctx();
    tool.set_parameter("frontier", &"plane".into(), &mut ctx)
        .unwrap();
    let v = ctx.mesh().vertices().next().unwrap();
    let pick = Pick {
        vertex: v,
        face: None,
        point: DVec3::ZERO,
    };
    tool.on_pick(Some(&pick), &mut ctx);
    let fine_layer = ctx.display.layer().clone();
    assert_eq!(fine_layer.name(), Some(LABEL_LAYER));
    tool.go_to_level(2, &mut ctx).unwrap();
    ctx.doc.end_edit();
    let coarse_layer = ctx.display.layer().clone();
    assert_ne!(coarse_layer, fine_layer);
    // Undo walks back to level 0: the layer shown is stale until refreshed.
    ctx.doc.undo().unwrap();
    let refreshed = refreshed_label_layer(ctx.display.layer(), ctx.mesh()).unwrap();
    assert_eq!(refreshed, fine_layer);
    // Other layers stay as they are.
    assert!(refreshed_label_layer(&ColorLayer::None, ctx.mesh()).is_none());
}
