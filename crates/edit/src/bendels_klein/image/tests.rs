use glam::{DMat3, DVec2};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::edt::{squared_distance_transform, squared_distances_at};
use super::*;
use crate::bendels_klein::error::{BendelsKleinError, RegionKind, Site};
use crate::bendels_klein::regions::Role;
use crate::bendels_klein::shape::ShapeFunction;

fn circle(centre: DVec2, radius: f64, n: usize) -> Vec<DVec2> {
    (0..n)
        .map(|k| {
            let t = k as f64 / n as f64 * std::f64::consts::TAU;
            centre + radius * DVec2::new(t.cos(), t.sin())
        })
        .collect()
}

/// A 256² test picture with a round handle of radius `r_handle` around the head and
/// everything beyond radius `r_fixed` fixed.
fn head_session(channels: u8, r_handle: f64, r_fixed: f64, step: u32) -> ImageSession {
    let (w, h) = (256, 256);
    let rgb = test_pattern(w, h).unwrap();
    let image = match channels {
        3 => rgb,
        1 => Raster::new(
            w,
            h,
            1,
            rgb.data()
                .chunks_exact(3)
                .map(|p| {
                    ((u32::from(p[0]) * 3 + u32::from(p[1]) * 5 + u32::from(p[2]) * 2) / 10) as u8
                })
                .collect(),
        )
        .unwrap(),
        _ => Raster::new(
            w,
            h,
            4,
            rgb.data()
                .chunks_exact(3)
                .enumerate()
                .flat_map(|(i, p)| [p[0], p[1], p[2], (i % 251) as u8])
                .collect(),
        )
        .unwrap(),
    };
    let centre = DVec2::new(127.5, 127.5);
    let handle = Mask::polygon(w, h, &circle(centre, r_handle, 48)).unwrap();
    let fixed = Mask::outside_polygon(w, h, &circle(centre, r_fixed, 96)).unwrap();
    let options = ImageOptions {
        grid_step: step,
        shape: ShapeFunction::Smoothstep,
    };
    ImageSession::new(image, handle, fixed, options).unwrap()
}

/// Asserts the paper's properties of an edited picture: fixed pixels bit for bit,
/// the handle the affine image of its source (within one grey level) wherever the
/// source grid cell lies wholly in the handle, no fold-over. Returns the number of
/// handle pixels checked.
fn assert_edit_properties(session: &ImageSession, out: &Raster) -> usize {
    let src = session.source();
    let (w, h) = (src.width(), src.height());
    let c = src.channels() as usize;
    for y in 0..h {
        for x in 0..w {
            if session.fixed_mask().contains(x, y) {
                assert_eq!(out.pixel(x, y), src.pixel(x, y), "fixed pixel ({x}, {y})");
            }
        }
    }
    assert!(session.min_area_ratio() > 0.0, "a grid cell folded over");
    assert_eq!(session.folded_triangles(), 0);
    let inverse = session.transform().inverse();
    let (nx, _) = session.grid_size();
    let xs: Vec<f64> = session.original_grid()[..nx].iter().map(|p| p.x).collect();
    let ys: Vec<f64> = session
        .original_grid()
        .iter()
        .step_by(nx)
        .map(|p| p.y)
        .collect();
    let mut checked = 0;
    let mut reference = [0.0; 4];
    for y in 0..h {
        for x in 0..w {
            if session.fixed_mask().contains(x, y) {
                continue;
            }
            let q = inverse.transform_point2(DVec2::new(f64::from(x), f64::from(y)));
            // The source cell holding q, all four corners on the handle.
            let i = xs.partition_point(|&g| g <= q.x);
            let j = ys.partition_point(|&g| g <= q.y);
            if i == 0 || j == 0 || i >= xs.len() || j >= ys.len() {
                continue;
            }
            let corners = [
                (j - 1) * nx + i - 1,
                (j - 1) * nx + i,
                j * nx + i - 1,
                j * nx + i,
            ];
            if !corners.iter().all(|&v| session.roles()[v] == Role::Handle) {
                continue;
            }
            src.sample_bilinear(q.x, q.y, &mut reference);
            let got = out.pixel(x, y).unwrap();
            for k in 0..c {
                let diff = (f64::from(got[k]) - reference[k]).abs();
                assert!(
                    diff <= 1.0,
                    "pixel ({x}, {y}) channel {k}: {} vs {}",
                    got[k],
                    reference[k]
                );
            }
            checked += 1;
        }
    }
    checked
}

fn about(pivot: DVec2, m: DMat3) -> DMat3 {
    DMat3::from_translation(pivot) * m * DMat3::from_translation(-pivot)
}

#[test]
fn fig6_translation_of_the_head() {
    for channels in [1, 3, 4] {
        let mut session = head_session(channels, 50.0, 118.0, 4);
        let a = DMat3::from_translation(DVec2::new(20.0, -12.0));
        session.apply(a).unwrap();
        let out = session.render();
        let checked = assert_edit_properties(&session, &out);
        // The handle disc has ~7,850 pixels; most lie in whole handle cells.
        assert!(checked > 6000, "only {checked} handle pixels checked");
        // Integer translation: the inner handle is an exact copy, moved.
        let src = session.source();
        assert_eq!(out.pixel(147, 116), src.pixel(127, 128));
        // Between the regions the picture did change.
        let changed = (0..256u32)
            .flat_map(|y| (0..256u32).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                !session.handle_mask().contains(x, y) && out.pixel(x, y) != src.pixel(x, y)
            })
            .count();
        assert!(changed > 5000, "{changed}");
        assert_eq!(out.channels(), channels);
    }
}

#[test]
fn fig6_rotation_of_the_head() {
    let mut session = head_session(3, 50.0, 118.0, 4);
    let centre = DVec2::new(127.5, 127.5);
    let a = about(centre, DMat3::from_angle(30f64.to_radians()));
    session.apply(a).unwrap();
    let mut out = session.source().clone();
    let stats = session.render_into(&mut out).unwrap();
    assert!(stats.pixels > 30_000 && stats.triangles > 2000, "{stats:?}");
    let checked = assert_edit_properties(&session, &out);
    assert!(checked > 6000, "only {checked} handle pixels checked");
}

#[test]
fn no_fold_over_for_translations_rotations_and_scales() {
    // Handle radius 28, fixed beyond 124: a band wide enough for scale 2.
    let mut session = head_session(3, 28.0, 124.0, 4);
    let centre = DVec2::new(127.5, 127.5);
    let mut transforms = Vec::new();
    for k in 0..8 {
        let t = k as f64 / 8.0 * std::f64::consts::TAU;
        transforms.push(DMat3::from_translation(40.0 * DVec2::new(t.cos(), t.sin())));
    }
    for deg in [-90.0, -45.0, 15.0, 60.0, 90.0] {
        transforms.push(about(centre, DMat3::from_angle(f64::to_radians(deg))));
    }
    for s in [0.5, 0.7, 1.4, 2.0] {
        transforms.push(about(centre, DMat3::from_scale(DVec2::splat(s))));
    }
    for a in transforms {
        session.apply(a).unwrap();
        let ratio = session.min_area_ratio();
        assert!(ratio > 0.0, "fold-over for {a:?}: area ratio {ratio}");
        let out = session.render();
        assert_edit_properties(&session, &out);
    }
}

#[test]
fn identity_changes_nothing_and_reset_restores() {
    let mut session = head_session(4, 40.0, 110.0, 5);
    session.apply(DMat3::IDENTITY).unwrap();
    assert_eq!(&session.render(), session.source());
    session
        .apply(DMat3::from_translation(DVec2::new(7.0, 3.0)))
        .unwrap();
    assert_ne!(&session.render(), session.source());
    session.reset();
    assert_eq!(session.deformed_grid(), session.original_grid());
    assert_eq!(&session.render(), session.source());
}

#[test]
fn weights_follow_the_distance_ratio_and_the_shape() {
    let mut session = head_session(3, 30.0, 110.0, 4);
    let (nx, _) = session.grid_size();
    for (i, &role) in session.roles().iter().enumerate() {
        let a = session.alpha()[i];
        match role {
            Role::Fixed => assert_eq!(a, 0.0),
            Role::Handle => assert_eq!(a, 1.0),
            Role::Deformable => {
                let (dh, df) = (session.handle_distances()[i], session.fixed_distances()[i]);
                assert!(dh > 0.0 && df > 0.0);
                let x = df / (df + dh);
                assert!((a - ShapeFunction::Smoothstep.eval(x)).abs() < 1e-15);
            }
        }
    }
    // Along the row through the centre, α rises from the fixed border to the handle.
    let row = nx * (session.grid_size().1 / 2);
    let alpha: Vec<f64> = session.alpha()[row..row + nx / 2].to_vec();
    assert!(alpha.windows(2).all(|p| p[1] >= p[0]), "{alpha:?}");
    session.set_shape(ShapeFunction::Linear);
    let i = row + nx / 4;
    let (dh, df) = (session.handle_distances()[i], session.fixed_distances()[i]);
    assert!((session.alpha()[i] - df / (df + dh)).abs() < 1e-15);
}

#[test]
fn exact_edt_matches_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(16);
    for (w, h, density) in [
        (1, 1, 0.5),
        (7, 3, 0.2),
        (40, 33, 0.02),
        (64, 17, 0.0),
        (31, 29, 0.9),
    ] {
        let mut mask = Mask::empty(w, h).unwrap();
        let mut points = Vec::new();
        for y in 0..h {
            for x in 0..w {
                if rng.random::<f64>() < density {
                    mask.set(x, y, true);
                    points.push((x as f64, y as f64));
                }
            }
        }
        let d = squared_distance_transform(&mask);
        for y in 0..h {
            for x in 0..w {
                let brute = points
                    .iter()
                    .map(|&(px, py)| (px - x as f64).powi(2) + (py - y as f64).powi(2))
                    .fold(f64::INFINITY, f64::min);
                assert_eq!(d[(y * w + x) as usize], brute, "({x}, {y}) of {w}×{h}");
            }
        }
        let columns: Vec<u32> = (0..w).step_by(3).chain([w + 5]).collect();
        let rows: Vec<u32> = (0..h).step_by(2).collect();
        let sampled = squared_distances_at(&mask, &columns, &rows);
        for (j, &y) in rows.iter().enumerate() {
            for (i, &x) in columns.iter().enumerate() {
                let expected = if x < w {
                    d[(y * w + x) as usize]
                } else {
                    f64::INFINITY
                };
                assert_eq!(sampled[j * columns.len() + i], expected);
            }
        }
    }
}

#[test]
fn polygon_masks_take_pixel_centres() {
    let square = [
        DVec2::new(1.5, 1.5),
        DVec2::new(5.5, 1.5),
        DVec2::new(5.5, 4.5),
        DVec2::new(1.5, 4.5),
    ];
    let mask = Mask::polygon(8, 6, &square).unwrap();
    for y in 0..6 {
        for x in 0..8 {
            let inside = (2..=5).contains(&x) && (2..=4).contains(&y);
            assert_eq!(mask.contains(x, y), inside, "({x}, {y})");
        }
    }
    assert_eq!(mask.count(), 12);
    let outside = Mask::outside_polygon(8, 6, &square).unwrap();
    assert_eq!(outside.count(), 48 - 12);
    // A polygon beyond the picture is clipped; a triangle fills half a square.
    let big = Mask::polygon(
        8,
        6,
        &[
            DVec2::new(-10.0, -10.0),
            DVec2::new(30.0, -10.0),
            DVec2::new(-10.0, 30.0),
        ],
    )
    .unwrap();
    assert_eq!(big.count(), 48);
    let border = Mask::border(8, 6, 1).unwrap();
    assert_eq!(border.count(), 48 - 6 * 4);
    assert!(matches!(
        Mask::polygon(8, 6, &square[..2]),
        Err(BendelsKleinError::TooFewPoints { points: 2 })
    ));
    let mut bad = square;
    bad[2].y = f64::NAN;
    assert!(matches!(
        Mask::polygon(8, 6, &bad),
        Err(BendelsKleinError::NonFinitePoint { index: 2 })
    ));
}

#[test]
fn bilinear_sampling_is_premultiplied_with_alpha() {
    let image = Raster::new(
        2,
        2,
        4,
        vec![255, 0, 0, 255, 0, 255, 0, 0, 255, 0, 0, 255, 0, 255, 0, 0],
    )
    .unwrap();
    let mut v = [0.0; 4];
    image.sample_bilinear(0.5, 0.5, &mut v);
    assert_eq!(v, [255.0, 0.0, 0.0, 127.5]);
    image.sample_bilinear(0.0, 1.0, &mut v);
    assert_eq!(v, [255.0, 0.0, 0.0, 255.0]);
    // Clamped outside the picture.
    image.sample_bilinear(-3.0, 9.0, &mut v);
    assert_eq!(v, [255.0, 0.0, 0.0, 255.0]);
    let grey = Raster::new(2, 1, 1, vec![10, 20]).unwrap();
    grey.sample_bilinear(0.25, 0.0, &mut v);
    assert_eq!(v[0], 12.5);
}

#[test]
fn fast_sampler_agrees_with_the_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let rgb = test_pattern(23, 17).unwrap();
    for channels in 1..=4u8 {
        let data: Vec<u8> = rgb
            .data()
            .chunks_exact(3)
            .enumerate()
            .flat_map(|(i, p)| {
                [p[0], p[1], p[2], ((i * 37) % 256) as u8]
                    .into_iter()
                    .take(channels as usize)
            })
            .collect();
        let image = Raster::new(23, 17, channels, data).unwrap();
        let mut reference = [0.0; 4];
        for _ in 0..2000 {
            let (x, y) = (rng.random_range(-2.0..25.0), rng.random_range(-2.0..19.0));
            image.sample_bilinear(x, y, &mut reference);
            let fast: Vec<f32> = match channels {
                1 => image.sample_bilinear_fast::<1>(x, y).to_vec(),
                2 => image.sample_bilinear_fast::<2>(x, y).to_vec(),
                3 => image.sample_bilinear_fast::<3>(x, y).to_vec(),
                _ => image.sample_bilinear_fast::<4>(x, y).to_vec(),
            };
            for (k, &v) in fast.iter().enumerate() {
                assert!(
                    (f64::from(v) - reference[k]).abs() < 1e-3,
                    "{channels} channels at ({x}, {y})"
                );
            }
        }
    }
}

#[test]
fn png_round_trips_every_channel_count() {
    let dir = std::env::temp_dir().join(format!("edit-image-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rgb = test_pattern(37, 21).unwrap();
    for channels in 1..=4u8 {
        let data: Vec<u8> = rgb
            .data()
            .chunks_exact(3)
            .flat_map(|p| {
                [p[0], p[1], p[2], p[0] ^ p[2]]
                    .into_iter()
                    .take(channels as usize)
            })
            .collect();
        let image = Raster::new(37, 21, channels, data).unwrap();
        let path = dir.join(format!("c{channels}.png"));
        image.write_png(&path).unwrap();
        assert_eq!(Raster::read_png(&path).unwrap(), image);
    }
    assert!(matches!(
        Raster::read_png(dir.join("missing.png")),
        Err(BendelsKleinError::Png { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_input_is_refused_and_refusals_change_nothing() {
    assert!(matches!(
        Raster::new(2, 2, 5, vec![0; 20]),
        Err(BendelsKleinError::Channels(5))
    ));
    assert!(matches!(
        Raster::new(2, 2, 3, vec![0; 11]),
        Err(BendelsKleinError::DataLength {
            got: 11,
            expected: 12
        })
    ));
    assert!(matches!(
        Raster::new(u32::MAX, u32::MAX, 4, vec![]),
        Err(BendelsKleinError::TooLarge { .. }) | Err(BendelsKleinError::DataLength { .. })
    ));
    let image = test_pattern(32, 32).unwrap();
    let fixed = Mask::border(32, 32, 1).unwrap();
    let handle = Mask::polygon(32, 32, &circle(DVec2::splat(16.0), 5.0, 12)).unwrap();
    let options = ImageOptions::default();
    let tiny = Raster::filled(1, 5, &[0]).unwrap();
    assert!(matches!(
        ImageSession::new(
            tiny,
            Mask::empty(1, 5).unwrap(),
            Mask::empty(1, 5).unwrap(),
            options.clone()
        ),
        Err(BendelsKleinError::TooSmall {
            width: 1,
            height: 5
        })
    ));
    let step0 = ImageOptions {
        grid_step: 0,
        ..options.clone()
    };
    assert!(matches!(
        ImageSession::new(image.clone(), handle.clone(), fixed.clone(), step0),
        Err(BendelsKleinError::GridStep)
    ));
    assert!(matches!(
        ImageSession::new(
            image.clone(),
            Mask::empty(31, 32).unwrap(),
            fixed.clone(),
            options.clone()
        ),
        Err(BendelsKleinError::MaskSize { .. })
    ));
    assert!(matches!(
        ImageSession::new(
            image.clone(),
            Mask::empty(32, 32).unwrap(),
            fixed.clone(),
            options.clone()
        ),
        Err(BendelsKleinError::EmptyRegion(RegionKind::Handle))
    ));
    assert!(matches!(
        ImageSession::new(
            image.clone(),
            handle.clone(),
            Mask::empty(32, 32).unwrap(),
            options.clone()
        ),
        Err(BendelsKleinError::EmptyRegion(RegionKind::Fixed))
    ));
    let mut overlapping = fixed.clone();
    overlapping.set(16, 16, true);
    assert!(matches!(
        ImageSession::new(image.clone(), handle.clone(), overlapping, options.clone()),
        Err(BendelsKleinError::Overlap {
            site: Site::Pixel { x: 16, y: 16 }
        })
    ));
    let bottom = (0..32).rev().find(|&y| handle.contains(16, y)).unwrap();
    let mut touching = fixed.clone();
    touching.set(17, bottom + 1, true);
    let result = ImageSession::new(image.clone(), handle.clone(), touching, options.clone());
    assert!(
        matches!(result, Err(BendelsKleinError::HandleTouchesFixed { fixed, .. }) if fixed == Site::Pixel { x: 17, y: bottom + 1 }),
        "{:?}",
        result.err()
    );
    let mut session = ImageSession::new(image.clone(), handle, fixed, options).unwrap();
    let a = DMat3::from_translation(DVec2::new(2.0, 1.0));
    session.apply(a).unwrap();
    let grid = session.deformed_grid().to_vec();
    assert!(matches!(
        session.apply(DMat3::from_scale(DVec2::new(1.0, -1.0))),
        Err(BendelsKleinError::NoRealLogarithm(_))
    ));
    let mut nan = a;
    nan.z_axis.x = f64::NAN;
    assert!(session.apply(nan).is_err());
    assert_eq!(session.deformed_grid(), &grid[..]);
    assert_eq!(session.transform(), a);
    let mut wrong = Raster::filled(32, 32, &[0, 0, 0, 0]).unwrap();
    assert!(matches!(
        session.render_into(&mut wrong),
        Err(BendelsKleinError::OutputMismatch { .. })
    ));
    assert_eq!(wrong, Raster::filled(32, 32, &[0, 0, 0, 0]).unwrap());
}

/// A 16-bit RGB version of the 256² test picture: each 8-bit value `v` becomes
/// `257 v` plus a low byte that varies across the picture, so 8 bits cannot hold it.
fn sixteen_bit_picture() -> Raster16 {
    let rgb = test_pattern(256, 256).unwrap();
    let data = rgb
        .data()
        .iter()
        .enumerate()
        .map(|(i, &v)| (u16::from(v) * 257).saturating_add((i % 97) as u16 * 3))
        .collect();
    Raster16::new(256, 256, 3, data).unwrap()
}

#[test]
fn a_sixteen_bit_picture_is_edited_at_sixteen_bits() {
    let image = sixteen_bit_picture();
    let centre = DVec2::new(127.5, 127.5);
    let handle = Mask::polygon(256, 256, &circle(centre, 30.0, 48)).unwrap();
    let fixed = Mask::outside_polygon(256, 256, &circle(centre, 100.0, 96)).unwrap();
    let options = ImageOptions {
        grid_step: 4,
        shape: ShapeFunction::Smoothstep,
    };
    let mut session = ImageSession16::new(image.clone(), handle, fixed, options).unwrap();
    // A whole-pixel translation: the handle's inside is copied sample for sample.
    session
        .apply(DMat3::from_translation(DVec2::new(8.0, -5.0)))
        .unwrap();
    let out = session.render();
    let (mut fixed_pixels, mut copied) = (0, 0);
    for y in 0..256 {
        for x in 0..256 {
            if session.fixed_mask().contains(x, y) {
                assert_eq!(out.pixel(x, y), image.pixel(x, y), "fixed ({x}, {y})");
                fixed_pixels += 1;
            }
            // Well inside the moved handle (its source 4 pixels inside the circle).
            let source = DVec2::new(f64::from(x) - 8.0, f64::from(y) + 5.0);
            if source.distance(centre) < 26.0 {
                assert_eq!(
                    out.pixel(x, y),
                    image.pixel(source.x as u32, source.y as u32),
                    "handle ({x}, {y})"
                );
                copied += 1;
            }
        }
    }
    assert!(
        fixed_pixels > 20_000 && copied > 1_500,
        "{fixed_pixels} {copied}"
    );
    // The blend between them keeps 16-bit values (not multiples of 257).
    let changed: Vec<u16> = out
        .data()
        .iter()
        .zip(image.data())
        .filter(|(a, b)| a != b)
        .map(|(&a, _)| a)
        .collect();
    assert!(changed.len() > 1_000);
    assert!(changed.iter().filter(|&&v| v % 257 != 0).count() > changed.len() / 2);
}

#[test]
fn sixteen_bit_pngs_keep_their_depth() {
    let image = sixteen_bit_picture();
    let path = std::env::temp_dir().join(format!("edit-16-bit-{}.png", std::process::id()));
    image.write_png(&path).unwrap();
    let read = Picture::read_png(&path).unwrap();
    let eight = Raster::read_png(&path).unwrap();
    let widened = Raster16::read_png(&path).unwrap();
    std::fs::remove_file(&path).ok();
    assert_eq!(read, Picture::Sixteen(image.clone()));
    assert_eq!(widened, image);
    // Read as 8 bits: every sample within one level of the 16-bit one.
    assert_eq!(eight.data().len(), image.data().len());
    for (&a, &b) in eight.data().iter().zip(image.data()) {
        assert!(
            (f32::from(a) * 257.0 - f32::from(b)).abs() <= 257.0,
            "{a} {b}"
        );
    }
    // An 8-bit file stays 8-bit, and reads widened as 16 bits (× 257).
    let small = test_pattern(16, 8).unwrap();
    let path = std::env::temp_dir().join(format!("edit-8-bit-{}.png", std::process::id()));
    small.write_png(&path).unwrap();
    let read = Picture::read_png(&path).unwrap();
    let widened = Raster16::read_png(&path).unwrap();
    std::fs::remove_file(&path).ok();
    assert_eq!(read, Picture::Eight(small.clone()));
    assert!(widened
        .data()
        .iter()
        .zip(small.data())
        .all(|(&w, &s)| w == u16::from(s) * 257));
}

#[test]
fn samples_round_and_saturate() {
    assert_eq!(u8::from_f32(254.6), 255);
    assert_eq!(u8::from_f32(300.0), 255);
    assert_eq!(u8::from_f32(-3.0), 0);
    assert_eq!(u8::from_f32(f32::NAN), 0);
    assert_eq!(u16::from_f32(1234.4), 1234);
    assert_eq!(u16::from_f32(70_000.0), 65_535);
    assert_eq!(u16::from_f32(f32::NAN), 0);
}
