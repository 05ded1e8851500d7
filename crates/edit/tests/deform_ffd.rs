//! Shape- and height-surface FFD (Feng, Ma & Peng).

use std::collections::HashMap;

use edit::deform::DeformError;
use edit::deform::{AttachOptions, BSplineSurface, Ffd, FfdReach, LatticeFrame};
use edit::deform::{Deformer, Twist};
use edit::Vertices;
use glam::DVec3;
use halfedge::Mesh;
use testkit::check::max_distance;
use testkit::meshes::closed_box;

/// Degrees and control-grid sizes of a B-spline surface.
type Grid = ([usize; 2], [usize; 2]);

/// `Ffd::covering` of every vertex of `mesh` in the world frame, default attach options.
fn world_ffd(mesh: &Mesh, shape: Grid, height: Grid, margin: f64) -> Ffd {
    Ffd::covering(
        mesh,
        Vertices::All,
        LatticeFrame::WORLD,
        shape,
        height,
        margin,
        AttachOptions::default(),
    )
    .unwrap()
}

fn box_mesh() -> Mesh {
    closed_box(
        DVec3::new(-1.0, 0.1, -0.5),
        DVec3::new(1.0, 0.5, 0.5),
        [20, 4, 10],
    )
}

#[test]
fn undisplaced_surfaces_reproduce_the_bunny_to_1e9() {
    undisplaced_surfaces_reproduce_the_bunny_to_1e9_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn undisplaced_surfaces_reproduce_the_bunny_to_1e9_on_real_meshes() {
    undisplaced_surfaces_reproduce_the_bunny_to_1e9_with(&testkit::load_shared);
}

fn undisplaced_surfaces_reproduce_the_bunny_to_1e9_with(load: &dyn Fn(&str) -> Mesh) {
    let mut mesh = load("stanford-bunny.obj");
    let before = mesh.positions().to_vec();
    // S cubic 6×5, H quadratic 4×4: the two surfaces differ
    let ffd = world_ffd(&mesh, ([3, 3], [6, 5]), ([2, 2], [4, 4]), 0.05);
    assert_eq!(ffd.reach(), FfdReach::Global);
    assert_eq!(ffd.attached(), mesh.n_vertices());
    ffd.deform(&mut mesh).unwrap();
    assert!(max_distance(&before, mesh.positions()) < 1e-9);

    // in a tilted frame, with the shape surface already curved at attach time
    let mut mesh = load("spot.obj");
    let before = mesh.positions().to_vec();
    let frame = LatticeFrame::new(
        DVec3::new(0.1, -1.0, 0.2),
        DVec3::new(1.0, 0.2, 0.1),
        DVec3::new(0.1, 1.0, 0.3),
    )
    .unwrap();
    let (lo, hi) = before
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            let l = frame.to_local(*p);
            (lo.min(l), hi.max(l))
        });
    let mut shape = BSplineSurface::planar(
        &frame,
        [3, 2],
        [7, 5],
        [lo.x - 0.8, lo.z - 0.8],
        [hi.x + 0.8, hi.z + 0.8],
        0.0,
    )
    .unwrap();
    for (k, p) in shape.control_points_mut().iter_mut().enumerate() {
        *p += 0.05 * (k as f64).sin() * frame.axes().1;
    }
    let height =
        BSplineSurface::planar(&frame, [1, 3], [3, 6], [lo.x, lo.z], [hi.x, hi.z], 1.0).unwrap();
    let ffd = Ffd::attach(
        &mesh,
        Vertices::All,
        frame,
        shape,
        height,
        AttachOptions::default(),
    )
    .unwrap();
    assert_eq!(ffd.reach(), FfdReach::Global);
    ffd.deform(&mut mesh).unwrap();
    assert!(max_distance(&before, mesh.positions()) < 1e-9);
}

#[test]
fn translating_the_shape_surface_translates_the_object() {
    translating_the_shape_surface_translates_the_object_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn translating_the_shape_surface_translates_the_object_on_real_meshes() {
    translating_the_shape_surface_translates_the_object_with(&testkit::load_shared);
}

fn translating_the_shape_surface_translates_the_object_with(load: &dyn Fn(&str) -> Mesh) {
    let mut mesh = load("spot.obj");
    let before = mesh.positions().to_vec();
    let mut ffd = world_ffd(&mesh, ([3, 3], [5, 5]), ([3, 3], [5, 5]), 0.1);
    let t = DVec3::new(0.3, -1.2, 0.7);
    ffd.translate(t).unwrap();
    ffd.deform(&mut mesh).unwrap();
    for (p, q) in before.iter().zip(mesh.positions()) {
        assert!((*q - (*p + t)).length() < 1e-9);
    }
}

#[test]
fn scaling_the_height_surface_scales_every_height() {
    scaling_the_height_surface_scales_every_height_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn scaling_the_height_surface_scales_every_height_on_real_meshes() {
    scaling_the_height_surface_scales_every_height_with(&testkit::load_shared);
}

fn scaling_the_height_surface_scales_every_height_with(load: &dyn Fn(&str) -> Mesh) {
    let mut mesh = load("spot.obj");
    let mut ffd = world_ffd(&mesh, ([2, 3], [4, 6]), ([3, 1], [5, 3]), 0.1);
    let k = 2.5;
    ffd.scale_heights(k).unwrap();
    // a wavy shape surface too, so that the heights are measured along varying normals
    for (n, p) in ffd.shape_mut().control_points_mut().iter_mut().enumerate() {
        p.y += 0.1 * (n as f64 * 0.7).cos();
    }
    ffd.deform(&mut mesh).unwrap();
    let shape = ffd.shape().clone();
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        let (u, w, h) = ffd.parameters(i).unwrap();
        let s = shape.evaluate(u, w);
        let n = shape.normal(u, w);
        let d = mesh.position(v) - s;
        assert!(
            (d.dot(n) - k * h).abs() < 1e-9,
            "height {} vs {}",
            d.dot(n),
            k * h
        );
        assert!((d - d.dot(n) * n).length() < 1e-9);
    }
}

#[test]
fn a_bent_shape_surface_bends_a_box_with_every_vertex_in_its_column() {
    // the paper's Fig. 7/8: S of degree 2×1 with uniformly distributed control points
    let mut mesh = box_mesh();
    let before = mesh.positions().to_vec();
    let mut ffd = world_ffd(&mesh, ([2, 1], [8, 2]), ([2, 1], [8, 2]), 0.0);
    assert_eq!(ffd.reach(), FfdReach::Global);
    ffd.bend(1.5).unwrap();
    ffd.deform(&mut mesh).unwrap();
    mesh.check().unwrap();

    // columns: vertices sharing their rest (x, z)
    let mut columns: HashMap<[u64; 2], Vec<usize>> = HashMap::new();
    for (i, p) in before.iter().enumerate() {
        columns
            .entry([p.x.to_bits(), p.z.to_bits()])
            .or_default()
            .push(i);
    }
    let shape = ffd.shape().clone();
    let mut tilted = 0;
    for members in columns.values() {
        let (u, v, _) = ffd.parameters(members[0]).unwrap();
        let s = shape.evaluate(u, v);
        let n = shape.normal(u, v);
        for &i in members {
            let (ui, vi, h) = ffd.parameters(i).unwrap();
            assert!((ui - u).abs() < 1e-12 && (vi - v).abs() < 1e-12);
            // the vertex stays on its column: the normal line of S_new at (u, v), at height h
            let q = mesh.positions()[i];
            assert!((q - (s + h * n)).length() < 1e-12);
            assert!((h - before[i].y).abs() < 1e-12);
        }
        if n.dot(DVec3::Y) < 0.9 {
            tilted += 1;
        }
    }
    assert!(
        tilted > columns.len() / 4,
        "the box is bent: {tilted} of {} columns tilted",
        columns.len()
    );
    // the middle of the box stays, its ends rise (bend towards +y)
    let top_end = mesh
        .positions()
        .iter()
        .map(|p| p.y)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(top_end > 0.5 + 0.2);
    // bent, then reset: attach once, deform many times
    ffd.reset();
    ffd.deform(&mut mesh).unwrap();
    assert!(max_distance(&before, mesh.positions()) < 1e-9);
}

#[test]
fn taper_is_barr_taper_along_u() {
    for (degree, count) in [([1, 1], [2, 2]), ([3, 2], [6, 4])] {
        let mut mesh = box_mesh();
        let before = mesh.positions().to_vec();
        let mut ffd = world_ffd(&mesh, (degree, count), (degree, count), 0.0);
        let (start, end) = (0.25, 1.0);
        ffd.taper(start, end).unwrap();
        ffd.deform(&mut mesh).unwrap();
        for (p, q) in before.iter().zip(mesh.positions()) {
            let r = start + (end - start) * (p.x + 1.0) / 2.0;
            let expected = DVec3::new(p.x, r * p.y, r * p.z);
            assert!(
                (*q - expected).length() < 1e-12,
                "{degree:?}: {p} → {q}, expected {expected}"
            );
        }
    }
    // the paper's triangle: the u = 0 border merged into its middle, heights sloped to 0
    let mut mesh = box_mesh();
    let mut ffd = world_ffd(&mesh, ([1, 1], [2, 2]), ([1, 1], [2, 2]), 0.0);
    ffd.taper(0.0, 1.0).unwrap();
    ffd.deform(&mut mesh).unwrap();
    for q in mesh.positions().iter().filter(|q| q.x == -1.0) {
        assert!(q.y.abs() < 1e-15 && q.z.abs() < 1e-15);
    }
}

#[test]
fn twist_is_barr_twist_of_the_shape_surface() {
    let mut mesh = box_mesh();
    let before = mesh.positions().to_vec();
    let mut ffd = world_ffd(&mesh, ([3, 1], [16, 2]), ([1, 1], [2, 2]), 0.0);
    let angle = 1.0;
    ffd.twist(angle).unwrap();
    // the control net is twisted by Barr's twist about the u axis (x, through z = 0, y = 0)
    let barr = Twist::linear(DVec3::new(-1.0, 0.0, 0.0), DVec3::X, 0.0, 2.0, angle).unwrap();
    let (rest, _) = ffd.rest();
    for (p, q) in rest
        .control_points()
        .iter()
        .zip(ffd.shape().control_points())
    {
        assert!(q.distance(barr.deform_point(*p)) < 1e-15);
    }
    ffd.deform(&mut mesh).unwrap();
    // the object follows: its points on S would be twisted exactly; above S they ride on
    // the normal of the twisted surface (a helicoid), which leans by atan(θ'·|z|) from
    // the twisted y axis, so a point at height h departs from Barr's twist by at most
    // h·atan(θ'·|z|) (plus the spline's approximation of the helicoid)
    let rate = angle / 2.0;
    for (p, q) in before.iter().zip(mesh.positions()) {
        let lean = (rate * p.z.abs()).atan();
        let bound = p.y * lean * 1.02 + 1e-3;
        assert!(
            q.distance(barr.deform_point(*p)) <= bound,
            "{p}: {} > {bound}",
            q.distance(barr.deform_point(*p))
        );
    }
    // the far end turned by the full angle: the box's far face centre line
    let end: Vec<DVec3> = mesh
        .positions()
        .iter()
        .zip(&before)
        .filter(|(_, p)| p.x == 1.0 && p.z == 0.0)
        .map(|(q, _)| *q)
        .collect();
    for q in end {
        assert!((q.z.atan2(q.y) - angle).abs() < 1e-9, "{q}");
    }
}

#[test]
fn local_mode_pins_the_crossed_border_and_keeps_the_object_continuous() {
    local_mode_pins_the_crossed_border_and_keeps_the_object_continuous_with(
        &testkit::stand_in::by_shape,
    );
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn local_mode_pins_the_crossed_border_and_keeps_the_object_continuous_on_real_meshes() {
    local_mode_pins_the_crossed_border_and_keeps_the_object_continuous_with(&testkit::load_shared);
}

fn local_mode_pins_the_crossed_border_and_keeps_the_object_continuous_with(
    load: &dyn Fn(&str) -> Mesh,
) {
    let mut mesh = load("stanford-bunny.obj");
    let before = mesh.positions().to_vec();
    let (lo, hi) = mesh.bounding_box().unwrap();
    // the shape surface covers only the half x < −0.02 (the head side)
    let shape = BSplineSurface::planar(
        &LatticeFrame::WORLD,
        [3, 3],
        [8, 6],
        [lo.x - 0.01, lo.z - 0.01],
        [-0.02, hi.z + 0.01],
        0.0,
    )
    .unwrap();
    let height = BSplineSurface::planar(
        &LatticeFrame::WORLD,
        [3, 3],
        [8, 6],
        [lo.x - 0.01, lo.z - 0.01],
        [-0.02, hi.z + 0.01],
        1.0,
    )
    .unwrap();
    let mut ffd = Ffd::attach(
        &mesh,
        Vertices::All,
        LatticeFrame::WORLD,
        shape,
        height,
        AttachOptions::default(),
    )
    .unwrap();
    assert_eq!(ffd.reach(), FfdReach::Local);
    assert_eq!(ffd.crossed_borders(), [false, true, false, false]);
    assert!(ffd.attached() > 1000 && ffd.attached() < mesh.n_vertices());
    for j in 0..6 {
        assert!(
            ffd.is_shape_pinned(7, j) && ffd.is_shape_pinned(6, j) && !ffd.is_shape_pinned(5, j)
        );
        assert!(
            ffd.is_height_pinned(7, j) && ffd.is_height_pinned(6, j) && !ffd.is_height_pinned(5, j)
        );
    }
    // lift the whole surface (pinned points stay) and scale heights
    let edit = |ffd: &mut Ffd| {
        ffd.translate(DVec3::new(0.0, 0.03, 0.0)).unwrap();
        ffd.scale_heights(1.3).unwrap();
    };
    edit(&mut ffd);
    ffd.deform(&mut mesh).unwrap();
    let mut largest: f64 = 0.0;
    for (i, (p, q)) in before.iter().zip(mesh.positions()).enumerate() {
        let moved = p.distance(*q);
        match ffd.parameters(i) {
            None => assert_eq!(moved, 0.0, "unattached vertex {i} moved"),
            Some(_) => largest = largest.max(moved),
        }
    }
    assert!(largest > 0.02);
    // continuity: with the border pinned, the displacement of attached vertices tends
    // to zero at the border (linearly in the distance 1 − u); without, it jumps there
    let free = AttachOptions::default()
        .with_shape_layers(0)
        .with_height_layers(0);
    let mut loose_mesh = load("stanford-bunny.obj");
    let (rest_shape, rest_height) = ffd.rest();
    let mut loose = Ffd::attach(
        &loose_mesh,
        Vertices::All,
        LatticeFrame::WORLD,
        rest_shape.clone(),
        rest_height.clone(),
        free,
    )
    .unwrap();
    assert_eq!(loose.reach(), FfdReach::Local);
    edit(&mut loose);
    loose.deform(&mut loose_mesh).unwrap();
    let near_border = |f: &Ffd, m: &Mesh, delta: f64| {
        (0..before.len())
            .filter(|&i| f.parameters(i).is_some_and(|p| 1.0 - p.0 <= delta))
            .map(|i| before[i].distance(m.positions()[i]))
            .fold(0.0, f64::max)
    };
    let (wide, narrow) = (
        near_border(&ffd, &mesh, 0.05),
        near_border(&ffd, &mesh, 0.002),
    );
    assert!(
        narrow < 0.1 * wide,
        "pinned: {narrow} within 0.002 of the border, {wide} within 0.05"
    );
    let (wide, narrow) = (
        near_border(&loose, &loose_mesh, 0.05),
        near_border(&loose, &loose_mesh, 0.002),
    );
    assert!(
        narrow > 0.5 * wide,
        "unpinned: {narrow} within 0.002 of the border, {wide} within 0.05"
    );
}

#[test]
fn errors_are_typed_and_change_nothing() {
    errors_are_typed_and_change_nothing_with(&testkit::stand_in::by_shape);
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn errors_are_typed_and_change_nothing_on_real_meshes() {
    errors_are_typed_and_change_nothing_with(&testkit::load_shared);
}

fn errors_are_typed_and_change_nothing_with(load: &dyn Fn(&str) -> Mesh) {
    let mut mesh = box_mesh();
    let other = load("spot.obj");
    let ffd = world_ffd(&mesh, ([2, 2], [4, 4]), ([2, 2], [4, 4]), 0.1);
    let mut other_mesh = other.clone();
    assert!(matches!(
        ffd.deform(&mut other_mesh),
        Err(DeformError::Stale(_))
    ));
    assert_eq!(other_mesh.positions(), other.positions());
    // a shape surface far to the side: every vertex projects onto its border
    let far = BSplineSurface::planar(
        &LatticeFrame::WORLD,
        [1, 1],
        [2, 2],
        [10.0, 10.0],
        [11.0, 11.0],
        0.0,
    )
    .unwrap();
    let h = BSplineSurface::planar(
        &LatticeFrame::WORLD,
        [1, 1],
        [2, 2],
        [10.0, 10.0],
        [11.0, 11.0],
        1.0,
    )
    .unwrap();
    assert!(matches!(
        Ffd::attach(
            &mesh,
            Vertices::All,
            LatticeFrame::WORLD,
            far,
            h,
            AttachOptions::default()
        ),
        Err(DeformError::NothingAttached)
    ));
    assert!(matches!(
        LatticeFrame::new(DVec3::ZERO, DVec3::Y, DVec3::Y),
        Err(DeformError::DegenerateDirection { .. })
    ));
    let mut ffd = ffd;
    assert!(ffd.taper(-1.0, 1.0).is_err());
    assert!(ffd.translate(DVec3::NAN).is_err());
    ffd.deform(&mut mesh).unwrap();
}
