//! Unit tests of the detail coefficients.

use super::frame::LINK;
use super::interpolate::turned_over;
use super::*;
use glam::DAffine3;

#[test]
fn zero_translation_keeps_signed_zero() {
    let p = DVec3::new(-0.0, 1.0, -2.5);
    let q = translate_exact(p, DVec3::ZERO);
    assert_eq!(
        q.to_array().map(f64::to_bits),
        p.to_array().map(f64::to_bits)
    );
    let q = translate_exact(p, DVec3::new(0.0, 1.0, 0.0));
    assert_eq!(q.y, 2.0);
    assert_eq!(q.x.to_bits(), (-0.0f64).to_bits());
}

#[test]
fn centroid_is_order_deterministic() {
    let positions = vec![
        DVec3::new(0.1, 0.2, 0.3),
        DVec3::new(1e16, -3.0, 0.7),
        DVec3::new(-1e16, 5.0, 0.1),
    ];
    let at = Collapsed {
        p0: DVec3::X,
        p1: DVec3::Y,
        placed: DVec3::Z,
    };
    let mut d = Details::with_capacity(DetailMode::Translation, 1);
    d.push(
        &positions,
        [0u32, 1, 2].into_iter(),
        [2u32].into_iter(),
        [7, 8],
        at,
    );
    assert_eq!(
        d.placement(0, &positions, None, DVec3::Z, at, false, false),
        Placement::At([at.p0, at.p1])
    );
    let (a, b) = d.lists(0);
    assert_eq!((a, b), (&[0u32, 1, 2][..], &[2u32][..]));
}

/// A hexagon ring around the origin, in the plane z = 0.
fn ring() -> Vec<DVec3> {
    (0..6)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 6.0;
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect()
}

#[test]
fn local_frames_follow_a_similarity_of_the_neighbourhood() {
    let positions = ring();
    let at = Collapsed {
        p0: DVec3::new(0.3, 0.1, 0.2),
        p1: DVec3::new(-0.2, 0.05, -0.1),
        placed: DVec3::new(0.05, 0.07, 0.04),
    };
    let mut d = Details::with_capacity(DetailMode::LocalFrame, 1);
    d.push(
        &positions,
        [0u32, 1, 2, 3].into_iter(),
        [3u32, 4, 5, 0].into_iter(),
        [7, 8],
        at,
    );
    // Unmoved survivor: the recorded positions, exactly.
    assert_eq!(
        d.placement(0, &positions, None, at.placed, at, false, false),
        Placement::Recorded
    );
    // Rotate, scale and translate everything: the endpoints follow exactly.
    let t = DAffine3::from_scale_rotation_translation(
        DVec3::splat(1.7),
        glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 1.1),
        DVec3::new(4.0, -2.0, 3.0),
    );
    let moved: Vec<DVec3> = positions.iter().map(|&p| t.transform_point3(p)).collect();
    let Placement::At([q0, q1]) = d.placement(
        0,
        &moved,
        None,
        t.transform_point3(at.placed),
        at,
        false,
        false,
    ) else {
        panic!("a moved survivor is placed")
    };
    assert!((q0 - t.transform_point3(at.p0)).length() < 1e-12);
    assert!((q1 - t.transform_point3(at.p1)).length() < 1e-12);
    // The translation scheme keeps the detail unrotated.
    let mut paper = Details::with_capacity(DetailMode::Translation, 1);
    paper.push(
        &positions,
        [0u32, 1, 2, 3].into_iter(),
        [3u32, 4, 5, 0].into_iter(),
        [7, 8],
        at,
    );
    let Placement::At([r0, _]) = paper.placement(
        0,
        &moved,
        None,
        t.transform_point3(at.placed),
        at,
        false,
        false,
    ) else {
        panic!()
    };
    assert!((r0 - t.transform_point3(at.p0)).length() > 1e-3);
}

/// The lists of a record, stored one after the other.
fn lists<'a>(l0: &'a [u32], l1: &'a [u32]) -> Lists<'a> {
    let link: Vec<u32> = l0.iter().chain(l1).copied().collect();
    Lists {
        l0,
        l1,
        link: Box::leak(link.into_boxed_slice()),
    }
}

#[test]
fn degenerate_neighbourhoods_have_no_frame() {
    let line = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
    assert_eq!(Frame::choose(&line, lists(&[0, 1, 2], &[])), None);
    let point = [DVec3::ONE; 3];
    assert_eq!(Frame::choose(&point, lists(&[0, 1, 2], &[2])), None);
    let nan = [DVec3::ZERO, DVec3::X, DVec3::new(0.0, f64::NAN, 0.0)];
    assert_eq!(Frame::choose(&nan, lists(&[0, 1, 2], &[])), None);
    assert_eq!(
        Frame::choose(&ring(), lists(&[0, 1, 2, 3, 4, 5], &[]))
            .unwrap()
            .0,
        LINK
    );
    assert_eq!(
        Frame::choose(&ring(), lists(&[0, 2, 4], &[0, 2, 4]))
            .unwrap()
            .0,
        1
    );
}

#[test]
fn local_frames_follow_an_affine_map_of_the_tangent_plane() {
    // A shear and stretch within the ring's plane: tangential offsets follow exactly.
    let positions = ring();
    let at = Collapsed {
        p0: DVec3::new(0.3, 0.1, 0.0),
        p1: DVec3::new(-0.2, 0.05, 0.0),
        placed: DVec3::new(0.05, 0.07, 0.0),
    };
    let mut d = Details::with_capacity(DetailMode::LocalFrame, 1);
    d.push(
        &positions,
        [0u32, 1, 2, 3, 4, 5].into_iter(),
        [0u32, 2].into_iter(),
        [7, 8],
        at,
    );
    let t = glam::DAffine3::from_mat3(glam::DMat3::from_cols(
        DVec3::new(2.0, 0.3, 0.0),
        DVec3::new(0.5, 0.7, 0.0),
        DVec3::Z,
    ));
    let moved: Vec<DVec3> = positions.iter().map(|&p| t.transform_point3(p)).collect();
    let Placement::At([q0, q1]) = d.placement(
        0,
        &moved,
        None,
        t.transform_point3(at.placed),
        at,
        false,
        false,
    ) else {
        panic!()
    };
    assert!((q0 - t.transform_point3(at.p0)).length() < 1e-12);
    assert!((q1 - t.transform_point3(at.p1)).length() < 1e-12);
}

#[test]
fn affine_marks_need_the_survivor_to_match() {
    let at = Collapsed {
        p0: DVec3::new(1.0, 2.0, 3.0),
        p1: DVec3::new(2.0, 2.0, 3.0),
        placed: DVec3::new(1.5, 2.0, 3.0),
    };
    let t = DAffine3::from_rotation_z(0.7) * DAffine3::from_translation(DVec3::X);
    let anchor = t.transform_point3(at.placed);
    let [q0, q1] = Details::motion_placement(&Motion::Affine(t), anchor, at).unwrap();
    assert_eq!(q0, t.transform_point3(at.p0));
    assert_eq!(q1, t.transform_point3(at.p1));
    assert!(Details::motion_placement(&Motion::Affine(t), anchor + DVec3::Y * 1e-6, at).is_none());
}

#[test]
fn an_interpolated_split_that_folds_its_faces_is_drawn_back_towards_the_survivor() {
    // The hexagon at rest and now, the survivor at its centre: endpoints that stay
    // inside the ring turn nothing over and are kept as they are; an endpoint thrown
    // beyond the ring (as an interpolation between very different motions can)
    // turns its fan over and is drawn back until nothing is turned over.
    let positions = ring();
    let rest: Vec<[f64; 3]> = positions.iter().map(|p| p.to_array()).collect();
    let at = Collapsed {
        p0: DVec3::new(-0.25, 0.0, 0.0),
        p1: DVec3::new(0.35, 0.0, 0.0),
        placed: DVec3::ZERO,
    };
    let lists = lists(&[0, 1, 2, 3], &[3, 4, 5, 0]);
    let lifted = DVec3::new(0.0, 0.0, 0.2);
    let inside = [at.p0 + lifted, at.p1 + DVec3::new(0.1, 0.05, 0.1)];
    assert_eq!(turned_over(&positions, &rest, lists, at, inside), 0);
    assert_eq!(unfold(&positions, &rest, lists, lifted, at, inside), inside);
    let folded = [at.p0, DVec3::new(-2.5, 0.0, 0.0)];
    assert!(turned_over(&positions, &rest, lists, at, folded) > 0);
    let drawn = unfold(&positions, &rest, lists, lifted, at, folded);
    assert_eq!(turned_over(&positions, &rest, lists, at, drawn), 0);
    // drawn back along the way to the survivor's translation of the record
    let direction = (folded[1] - (at.p1 + lifted)).normalize();
    let back = drawn[1] - (at.p1 + lifted);
    assert!(back.cross(direction).length() < 1e-12 && back.dot(direction) >= 0.0);
}

#[test]
fn a_survivor_moved_apart_from_its_ring_spreads_its_motion_over_its_endpoints() {
    // The hexagon at rest, the survivor at the centre lifted by 1 along z: each
    // endpoint takes `max(1 − 2λ, 0)` of the lift, `λ` its hat coordinate (its
    // fraction of the way to the ring): the motion falls to zero half-way to the
    // still ring, where the ring's own (exact) descendants begin.
    let positions = ring();
    let rest: Vec<[f64; 3]> = positions.iter().map(|p| p.to_array()).collect();
    let at = Collapsed {
        p0: DVec3::new(-0.25, 0.0, 0.0),
        p1: DVec3::new(0.75, 0.0, 0.0),
        placed: DVec3::ZERO,
    };
    let mut d = Details::with_capacity(DetailMode::LocalFrame, 1);
    d.push(
        &positions,
        [0u32, 1, 2, 3].into_iter(),
        [3u32, 4, 5, 0].into_iter(),
        [7, 8],
        at,
    );
    // The ring's vertices stay where they were (their clusters do not move).
    let still = |i: u32, _: DVec3| (i < 6).then_some(DVec3::ZERO);
    let lifted = DVec3::Z;
    let Placement::At([q0, q1]) = d.placement(
        0,
        &positions,
        Some((&rest, &still)),
        lifted,
        at,
        false,
        false,
    ) else {
        panic!("a moved survivor is placed")
    };
    for (q, p, lambda) in [(q0, at.p0, 0.25), (q1, at.p1, 0.75)] {
        let motion = q - p;
        assert!(
            (motion - f64::max(1.0 - 2.0 * lambda, 0.0) * DVec3::Z).length() < 1e-12,
            "{motion} at λ = {lambda}"
        );
    }
    // Unmoved and outside any region: exactly where it was; in a region with its
    // ring moved, it takes its share of the ring's motion.
    assert_eq!(
        d.placement(
            0,
            &positions,
            Some((&rest, &still)),
            at.placed,
            at,
            false,
            false
        ),
        Placement::Recorded
    );
    let mut moved = positions.clone();
    moved[0] += DVec3::Z;
    let others_still = |i: u32, _: DVec3| (i > 0 && i < 6).then_some(DVec3::ZERO);
    let Placement::At([_, q1]) = d.placement(
        0,
        &moved,
        Some((&rest, &others_still)),
        at.placed,
        at,
        true,
        false,
    ) else {
        panic!("a survivor in a region is placed")
    };
    assert!(q1.z > 0.1 && q1.z < 1.0, "{q1}");
}
