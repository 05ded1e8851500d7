//! The 2-D image view (`viewer::image_view`): its state driven directly (no window),
//! and the viewer binary editing a PNG in scripted mode, both compared with
//! `edit::bendels_klein::image` applied directly.
//!
//! The scripted tests need an X display, as those of `scripted.rs` (same skip rules:
//! see `common::display_command`).

mod common;

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use common::{display, display_command, image_stats, run_script, run_viewer};
use edit::bendels_klein::image::{test_pattern, ImageOptions, ImageSession, Mask, Raster};
use edit::bendels_klein::ShapeFunction;
use glam::{DMat3, DVec2};
use testkit::temp_dir as scratch_dir;
use viewer::image_view::{
    display_rgba, pivot, Fit, ImageUi, ImageView, ImageViewError, MouseTool, ShapePreset, Transform,
};

/// The test picture of `examples/image_edit.rs`.
fn picture() -> Raster {
    test_pattern(160, 120).unwrap()
}

fn points(p: &[[f64; 2]]) -> Vec<DVec2> {
    p.iter().map(|&q| DVec2::from_array(q)).collect()
}

/// A rectangle around the head of the test picture.
const HANDLE: [[f64; 2]; 4] = [[56.0, 36.0], [104.0, 36.0], [104.0, 84.0], [56.0, 84.0]];
/// A fixed border polygon well away from the handle.
const FIXED: [[f64; 2]; 4] = [[20.0, 10.0], [145.0, 14.0], [150.0, 110.0], [12.0, 105.0]];

/// The library applied directly: what the view must show.
fn library(
    source: &Raster,
    handle: &[DVec2],
    fixed: Option<&[DVec2]>,
    shape: ShapeFunction,
    t: Transform,
) -> Raster {
    let (w, h) = (source.width(), source.height());
    let fixed = match fixed {
        Some(p) => Mask::outside_polygon(w, h, p).unwrap(),
        None => Mask::border(w, h, 1).unwrap(),
    };
    let options = ImageOptions::default().with_shape(shape);
    let mut session = ImageSession::new(
        source.clone(),
        Mask::polygon(w, h, handle).unwrap(),
        fixed,
        options,
    )
    .unwrap();
    let c = handle.iter().sum::<DVec2>() / handle.len() as f64;
    let a = DMat3::from_translation(c + t.translate)
        * DMat3::from_angle(t.rotate.to_radians())
        * DMat3::from_scale(DVec2::splat(t.scale))
        * DMat3::from_translation(-c);
    session.apply(a).unwrap();
    session.render()
}

/// Asserts that every pixel of `mask` is the same in `a` and `b`; returns how many.
fn assert_same_on(a: &Raster, b: &Raster, mask: &Mask) -> usize {
    let mut n = 0;
    for y in 0..a.height() {
        for x in 0..a.width() {
            if mask.contains(x, y) {
                assert_eq!(a.pixel(x, y), b.pixel(x, y), "pixel ({x}, {y})");
                n += 1;
            }
        }
    }
    n
}

fn changed_pixels(a: &Raster, b: &Raster) -> usize {
    a.data()
        .chunks(a.channels() as usize)
        .zip(b.data().chunks(b.channels() as usize))
        .filter(|(p, q)| p != q)
        .count()
}

fn moved() -> Transform {
    Transform {
        translate: DVec2::new(9.0, -6.0),
        rotate: 12.0,
        scale: 1.15,
    }
}

#[test]
fn the_view_shows_what_the_library_computes() {
    let source = picture();
    let mut view = ImageView::new(source.clone(), "pattern.png".into());
    assert_eq!(view.result().data(), source.data());
    view.set_handle(points(&HANDLE)).unwrap();
    // A handle alone moves nothing.
    assert_eq!(view.result().data(), source.data());
    view.set_transform(moved()).unwrap();
    view.commit();
    let expected = library(
        &source,
        &points(&HANDLE),
        None,
        ShapeFunction::Smoothstep,
        moved(),
    );
    assert_eq!(view.result().data(), expected.data());
    assert!(changed_pixels(&source, view.result()) > 1000);
    // The fixed region (the border) is the input bit for bit.
    let border = Mask::border(160, 120, 1).unwrap();
    assert_eq!(
        assert_same_on(&source, view.result(), &border),
        2 * 160 + 2 * 118
    );
    assert_eq!(view.pivot(), Some(pivot(&points(&HANDLE))));
    assert_eq!(view.pivot(), Some(DVec2::new(80.0, 60.0)));

    // A fixed polygon: everything outside it stays; the result is still the library's.
    view.set_fixed(Some(points(&FIXED))).unwrap();
    let expected = library(
        &source,
        &points(&HANDLE),
        Some(&points(&FIXED)),
        ShapeFunction::Smoothstep,
        moved(),
    );
    assert_eq!(view.result().data(), expected.data());
    let outside = Mask::outside_polygon(160, 120, &points(&FIXED)).unwrap();
    assert!(assert_same_on(&source, view.result(), &outside) > 2000);

    // Another shape: another picture, again the library's.
    view.set_shape(ShapePreset::Linear).unwrap();
    let linear = library(
        &source,
        &points(&HANDLE),
        Some(&points(&FIXED)),
        ShapeFunction::Linear,
        moved(),
    );
    assert_eq!(view.result().data(), linear.data());
    assert_ne!(linear.data(), expected.data());
}

#[test]
fn a_pure_translation_moves_the_handle_by_it() {
    let source = picture();
    let mut view = ImageView::new(source.clone(), "pattern.png".into());
    view.set_handle(points(&HANDLE)).unwrap();
    let t = DVec2::new(7.0, -5.0);
    view.set_transform(Transform {
        translate: t,
        ..Transform::IDENTITY
    })
    .unwrap();
    // Inside the handle, away from its outline (two grid cells), every pixel moved by
    // `t`, bit for bit.
    let mut checked = 0;
    for ys in 44..=76u32 {
        for xs in 64..=96u32 {
            let (x, y) = ((f64::from(xs) + t.x) as u32, (f64::from(ys) + t.y) as u32);
            assert_eq!(
                view.result().pixel(x, y),
                source.pixel(xs, ys),
                "({xs}, {ys}) to ({x}, {y})"
            );
            checked += 1;
        }
    }
    // And the picture did change there (the test pattern is not uniform).
    assert!(changed_pixels(&source, view.result()) > 500);
    assert_eq!(checked, 33 * 33);
}

#[test]
fn undo_returns_the_input_bit_for_bit_and_redo_the_edit() {
    let source = picture();
    let mut view = ImageView::new(source.clone(), "pattern.png".into());
    assert!(view.undo().is_none());
    view.set_handle(points(&HANDLE)).unwrap();
    view.set_transform(moved()).unwrap();
    view.commit();
    let edited = view.result().clone();
    assert_ne!(edited.data(), source.data());
    assert_eq!(view.undo().as_deref(), Some("transform"));
    assert_eq!(view.result().data(), source.data());
    assert_eq!(view.state().transform, Transform::IDENTITY);
    assert_eq!(view.redo().as_deref(), Some("transform"));
    assert_eq!(view.result().data(), edited.data());
    // Back past the handle too, then forward again.
    view.undo();
    assert_eq!(view.undo().as_deref(), Some("handle polygon"));
    assert!(view.state().handle.is_none());
    assert_eq!(view.result().data(), source.data());
    view.redo();
    view.redo();
    assert_eq!(view.result().data(), edited.data());
    // A new change drops the redo steps.
    view.undo();
    view.set_shape(ShapePreset::C2).unwrap();
    assert_eq!(view.redo_len(), 0);
}

#[test]
fn a_continuous_change_is_one_history_step() {
    let source = picture();
    let mut view = ImageView::new(source.clone(), "pattern.png".into());
    view.set_handle(points(&HANDLE)).unwrap();
    let before = view.undo_len();
    for k in 1..=5 {
        view.set_transform(Transform {
            rotate: 3.0 * k as f64,
            ..Transform::IDENTITY
        })
        .unwrap();
    }
    view.commit();
    assert_eq!(view.undo_len(), before + 1);
    view.set_transform(moved()).unwrap();
    view.commit();
    assert_eq!(view.undo_len(), before + 2);
    view.undo();
    assert_eq!(view.state().transform.rotate, 15.0);
    view.undo();
    assert_eq!(view.result().data(), source.data());

    // The GUI's scripted drag: the steps add up to the drag, one history step.
    let mut ui = ImageUi::new(view);
    let n = ui.view.undo_len();
    ui.drag_by(DVec2::new(6.0, 4.0), 5).unwrap();
    ui.drag_by(DVec2::new(-2.0, 1.0), 3).unwrap();
    assert_eq!(ui.view.undo_len(), n + 2);
    assert_eq!(ui.view.state().transform.translate, DVec2::new(4.0, 5.0));
    let expected = library(
        &source,
        &points(&HANDLE),
        None,
        ShapeFunction::Smoothstep,
        Transform {
            translate: DVec2::new(4.0, 5.0),
            ..Transform::IDENTITY
        },
    );
    assert_eq!(ui.view.result().data(), expected.data());
}

#[test]
fn clicks_draw_the_polygons_and_a_drag_moves_the_handle() {
    let source = picture();
    let mut ui = ImageUi::new(ImageView::new(source.clone(), "pattern.png".into()));
    assert_eq!(ui.tool(), MouseTool::DrawHandle);
    for p in points(&HANDLE) {
        ui.click(p);
    }
    assert_eq!(ui.draft(), &points(&HANDLE)[..]);
    ui.close_as_handle().unwrap();
    assert_eq!(
        ui.view.state().handle.as_deref(),
        Some(&points(&HANDLE)[..])
    );
    assert!(ui.draft().is_empty());
    assert_eq!(ui.tool(), MouseTool::MoveHandle);
    // With the move tool, clicks draw nothing.
    ui.click(DVec2::new(5.0, 5.0));
    assert!(ui.draft().is_empty());

    // Two points do not make a fixed polygon: the library says so, the points stay.
    ui.set_tool(MouseTool::DrawFixed);
    ui.click(DVec2::new(10.0, 10.0));
    ui.click(DVec2::new(150.0, 10.0));
    assert!(ui.close_as_fixed().is_err());
    assert_eq!(ui.draft().len(), 2);
    assert!(ui.view.state().fixed.is_none());
    // A press with a drawing tool drags nothing.
    ui.begin_drag(DVec2::new(80.0, 60.0));
    ui.drag_to(DVec2::new(90.0, 60.0)).unwrap();
    assert_eq!(ui.view.state().transform, Transform::IDENTITY);
    ui.end_drag();

    // The drag follows the pointer from the press; one history step.
    ui.set_tool(MouseTool::MoveHandle);
    let n = ui.view.undo_len();
    let press = DVec2::new(81.3, 59.2);
    ui.begin_drag(press);
    for d in [[1.0, 0.5], [3.0, 2.0], [5.0, 3.0]] {
        ui.drag_to(press + DVec2::from_array(d)).unwrap();
    }
    ui.end_drag();
    assert_eq!(ui.view.undo_len(), n + 1);
    let t = Transform {
        translate: DVec2::new(5.0, 3.0),
        ..Transform::IDENTITY
    };
    assert!((ui.view.state().transform.translate - t.translate).length() < 1e-12);
    let expected = library(
        &source,
        &points(&HANDLE),
        None,
        ShapeFunction::Smoothstep,
        ui.view.state().transform,
    );
    assert_eq!(ui.view.result().data(), expected.data());
    ui.view.undo();
    assert_eq!(ui.view.result().data(), source.data());
}

#[test]
fn the_library_refuses_and_nothing_changes() {
    let source = picture();
    let mut view = ImageView::new(source.clone(), "pattern.png".into());
    assert!(matches!(
        view.set_transform(moved()),
        Err(ImageViewError::NoHandle)
    ));
    // Two points: the library's PolygonTooShort, with its message.
    let err = view
        .set_handle(points(&[[10.0, 10.0], [20.0, 20.0]]))
        .unwrap_err();
    let library_err = Mask::polygon(160, 120, &points(&[[10.0, 10.0], [20.0, 20.0]])).unwrap_err();
    assert_eq!(err.to_string(), library_err.to_string());
    assert_eq!(view.undo_len(), 0);

    view.set_handle(points(&HANDLE)).unwrap();
    view.set_transform(moved()).unwrap();
    view.commit();
    let edited = view.result().clone();
    let state = view.state().clone();
    let n = view.undo_len();
    // A fixed region that overlaps the handle (all but a small triangle in it); a scale
    // of 0; a grid step of 0.
    let err = view
        .set_fixed(Some(points(&[[70.0, 50.0], [90.0, 50.0], [80.0, 70.0]])))
        .unwrap_err();
    assert!(
        err.to_string().contains("both the handle and the fixed"),
        "{err}"
    );
    let err = view
        .set_transform(Transform {
            scale: 0.0,
            ..moved()
        })
        .unwrap_err();
    assert!(matches!(err, ImageViewError::Edit(_)), "{err}");
    let err = view.set_grid_step(0).unwrap_err();
    assert!(err.to_string().contains("grid step"), "{err}");
    assert!(ShapePreset::parse("cubic").is_err());
    let dir = scratch_dir("image-save");
    let err = view.save(&dir.join("out.obj")).unwrap_err();
    assert!(matches!(err, ImageViewError::NotPng(_)), "{err}");
    assert!(!dir.join("out.obj").exists());
    view.save(&dir.join("out.png")).unwrap();
    assert_eq!(
        Raster::read_png(dir.join("out.png")).unwrap().data(),
        edited.data()
    );
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(view.state(), &state);
    assert_eq!(view.undo_len(), n);
    assert_eq!(view.result().data(), edited.data());
}

#[test]
fn shapes_parse_by_their_names() {
    for s in ShapePreset::ALL {
        assert_eq!(ShapePreset::parse(s.name()).unwrap(), s);
    }
    assert_eq!(ShapePreset::parse("C1").unwrap(), ShapePreset::Smoothstep);
    assert_eq!(
        ShapePreset::parse("smootherstep").unwrap().function(),
        ShapeFunction::Smootherstep
    );
}

#[test]
fn the_fit_maps_pixels_to_the_panel_and_back() {
    // A 200×100 picture in a 400×400 panel at (10, 20), margin 0: 2 points per pixel,
    // centred vertically.
    let fit = Fit::new(DVec2::new(10.0, 20.0), DVec2::splat(400.0), 200, 100, 0.0);
    assert_eq!(fit.scale, 2.0);
    assert_eq!(fit.origin, DVec2::new(10.0, 120.0));
    // Pixel (0, 0)'s centre is half a pixel into the picture.
    assert_eq!(fit.to_screen(DVec2::ZERO), DVec2::new(11.0, 121.0));
    let p = DVec2::new(37.25, 81.5);
    assert!((fit.to_pixel(fit.to_screen(p)) - p).length() < 1e-12);
    // With a margin, the picture stays inside the panel.
    let fit = Fit::new(DVec2::ZERO, DVec2::new(300.0, 500.0), 640, 480, 12.0);
    let corner = fit.to_screen(DVec2::new(639.5, 479.5));
    assert!(
        fit.origin.x >= 12.0 - 1e-9 && corner.x <= 288.0 + 1e-9,
        "{fit:?}"
    );
    assert!(fit.origin.y >= 0.0 && corner.y <= 500.0);
}

#[test]
fn the_texture_is_the_picture_or_every_kth_pixel_of_it() {
    // Grey + alpha, 5×3: pixel (x, y) = (10 y + x, 200).
    let data: Vec<u8> = (0..3u8)
        .flat_map(|y| (0..5u8).flat_map(move |x| [10 * y + x, 200]))
        .collect();
    let raster = Raster::new(5, 3, 2, data).unwrap();
    let (size, bytes) = display_rgba(&raster, 16);
    assert_eq!(size, [5, 3]);
    assert_eq!(&bytes[4 * 7..4 * 8], &[12, 12, 12, 200]); // pixel (2, 1)
                                                          // A texture side of 2: every third pixel of every third row.
    let (size, bytes) = display_rgba(&raster, 2);
    assert_eq!(size, [2, 1]);
    assert_eq!(bytes, vec![0, 0, 0, 200, 3, 3, 3, 200]);
    let rgb = picture();
    let (size, bytes) = display_rgba(&rgb, 4096);
    assert_eq!(size, [160, 120]);
    let p = rgb.pixel(17, 33).unwrap();
    let i = 4 * (33 * 160 + 17);
    assert_eq!(&bytes[i..i + 4], &[p[0], p[1], p[2], 255]);
}

fn write_input(dir: &Path) -> (std::path::PathBuf, Raster) {
    let source = picture();
    let path = dir.join("in.png");
    source.write_png(&path).unwrap();
    // The file holds the picture exactly.
    assert_eq!(Raster::read_png(&path).unwrap().data(), source.data());
    (path, source)
}

#[test]
fn scripted_image_edit_matches_the_library_and_undo_restores_the_input() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("image");
    let (input, source) = write_input(&dir);
    let mesh = dir.join("sphere.obj");
    halfedge::io::write_obj(&mesh, &halfedge::generators::icosphere(2)).unwrap();
    let (a, b, c, d, shot) = (
        dir.join("a.png"),
        dir.join("b.png"),
        dir.join("c.png"),
        dir.join("d.png"),
        dir.join("shot.png"),
    );
    let script = dir.join("script.json");
    let t = moved();
    let text = serde_json::json!({"actions": [
        {"action": "load", "path": input},
        {"action": "image_handle", "points": HANDLE},
        {"action": "image_transform", "translate": [t.translate.x, t.translate.y],
         "rotate": t.rotate, "scale": t.scale},
        {"action": "save", "path": a},
        {"action": "undo"},
        {"action": "save", "path": b},
        {"action": "redo"},
        {"action": "save", "path": c},
        {"action": "image_fixed", "points": FIXED},
        {"action": "image_options", "shape": "linear"},
        {"action": "image_drag", "dx": 3, "dy": 4, "steps": 4},
        {"action": "save", "path": d},
        {"action": "screenshot", "path": shot}
    ]});
    run_script(prefix, &mesh, &script, &text, "800x600");

    let read = |p: &Path| Raster::read_png(p).unwrap_or_else(|e| panic!("{e}"));
    let (a, b, c, d) = (read(&a), read(&b), read(&c), read(&d));
    let expected = library(
        &source,
        &points(&HANDLE),
        None,
        ShapeFunction::Smoothstep,
        t,
    );
    assert_eq!(
        a.data(),
        expected.data(),
        "the viewer's edit is the library's"
    );
    assert!(changed_pixels(&source, &a) > 1000);
    let border = Mask::border(160, 120, 1).unwrap();
    assert_same_on(&source, &a, &border);
    assert_eq!(
        b.data(),
        source.data(),
        "undo returns the input bit for bit"
    );
    assert_eq!(c.data(), a.data(), "redo returns the edit");
    let dragged = Transform {
        translate: t.translate + DVec2::new(3.0, 4.0),
        ..t
    };
    let expected = library(
        &source,
        &points(&HANDLE),
        Some(&points(&FIXED)),
        ShapeFunction::Linear,
        dragged,
    );
    assert_eq!(d.data(), expected.data());
    let outside = Mask::outside_polygon(160, 120, &points(&FIXED)).unwrap();
    assert!(assert_same_on(&source, &d, &outside) > 2000);
    // The window shows the picture (many colours), not an empty view.
    let (spread, colours, size) = image_stats(&shot);
    assert_eq!(size, (800, 600));
    assert!(spread > 10.0 && colours > 200, "{spread} {colours}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_png_on_the_command_line_opens_in_the_image_view_and_library_errors_fail_the_script() {
    let Some(prefix) = display_command() else {
        return;
    };
    let dir = scratch_dir("image-errors");
    let (input, source) = write_input(&dir);
    let out = dir.join("out.png");
    let script = dir.join("script.json");
    let text = serde_json::json!([
        {"action": "image_handle", "points": HANDLE},
        {"action": "image_transform", "translate": [5, 0]},
        {"action": "save", "path": out},
        {"action": "image_transform", "scale": 0}
    ]);
    std::fs::write(&script, text.to_string()).unwrap();
    let result = run_viewer(
        prefix,
        &[
            input.as_os_str(),
            "--script".as_ref(),
            script.as_os_str(),
            "--size".as_ref(),
            "640x480".as_ref(),
            "--msaa".as_ref(),
            "0".as_ref(),
        ],
        Duration::from_secs(300),
    );
    assert_eq!(result.status.code(), Some(1), "{}", display(&result));
    // The library's message for a scale of 0, through the viewer.
    let mut session = ImageSession::new(
        source.clone(),
        Mask::polygon(160, 120, &points(&HANDLE)).unwrap(),
        Mask::border(160, 120, 1).unwrap(),
        ImageOptions::default(),
    )
    .unwrap();
    let c = pivot(&points(&HANDLE));
    let singular = Transform {
        scale: 0.0,
        ..Transform::IDENTITY
    }
    .matrix(c);
    let message = session.apply(singular).unwrap_err().to_string();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("action 3 (image_transform)") && stderr.contains(&message),
        "{}",
        display(&result)
    );
    // What came before the failure was done: the translation, saved.
    let expected = library(
        &source,
        &points(&HANDLE),
        None,
        ShapeFunction::Smoothstep,
        Transform {
            translate: DVec2::new(5.0, 0.0),
            ..Transform::IDENTITY
        },
    );
    assert_eq!(Raster::read_png(&out).unwrap().data(), expected.data());

    // No image open: the image actions say so.
    let mesh = dir.join("sphere.obj");
    halfedge::io::write_obj(&mesh, &halfedge::generators::icosphere(1)).unwrap();
    std::fs::write(
        &script,
        serde_json::json!([{"action": "image_handle", "points": HANDLE}]).to_string(),
    )
    .unwrap();
    let result = run_viewer(
        display_command().unwrap_or_else(|| Command::new("env")),
        &[
            mesh.as_os_str(),
            "--script".as_ref(),
            script.as_os_str(),
            "--msaa".as_ref(),
            "0".as_ref(),
        ],
        Duration::from_secs(300),
    );
    assert_eq!(result.status.code(), Some(1), "{}", display(&result));
    assert!(
        String::from_utf8_lossy(&result.stderr).contains("no image is open"),
        "{}",
        display(&result)
    );
    std::fs::remove_dir_all(&dir).ok();
}
