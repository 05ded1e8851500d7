//! A procedurally drawn test picture, so that tests, examples, benches and the guide
//! edit images the project makes itself.

use crate::bendels_klein::error::Result;
use crate::bendels_klein::image::raster::Raster;

/// An RGB test picture of `width × height`: a checkerboard of 16-pixel squares under a
/// soft diagonal gradient (straight lines that show every bend of an edit), with a
/// "head" in the middle (a disc of radius `0.18 · min(width, height)` with an outline,
/// two eyes and a mouth), the stand-in for the Mona Lisa of Bendels & Klein's Fig. 6.
/// Deterministic.
///
/// # Errors
/// [`BendelsKleinError::TooLarge`](crate::bendels_klein::BendelsKleinError::TooLarge)
/// above [`MAX_PIXELS`](super::MAX_PIXELS) pixels.
pub fn test_pattern(width: u32, height: u32) -> Result<Raster> {
    let mut out = Raster::filled(width, height, &[0, 0, 0])?;
    let (w, h) = (f64::from(width), f64::from(height));
    let (cx, cy) = (0.5 * (w - 1.0), 0.5 * (h - 1.0));
    let r = 0.18 * w.min(h);
    let data = out.data_mut();
    for y in 0..height as usize {
        for x in 0..width as usize {
            let (xf, yf) = (x as f64, y as f64);
            let t = (xf / w.max(1.0) + yf / h.max(1.0)) * 0.5;
            let checker = ((x / 16) + (y / 16)) % 2 == 0;
            let mut rgb = if checker {
                [70.0 + 120.0 * t, 110.0 + 60.0 * t, 170.0 - 60.0 * t]
            } else {
                [225.0 - 40.0 * t, 215.0 - 30.0 * t, 190.0 + 30.0 * t]
            };
            let (dx, dy) = ((xf - cx) / r, (yf - cy) / r);
            let d = (dx * dx + dy * dy).sqrt();
            if d <= 1.0 {
                rgb = [235.0, 190.0, 140.0 - 40.0 * dy];
                let eye = |ex: f64| ((dx - ex).powi(2) + (dy + 0.25).powi(2)).sqrt() < 0.14;
                let mouth = (dx * dx + (dy - 0.05).powi(2)).sqrt();
                if eye(-0.38) || eye(0.38) {
                    rgb = [40.0, 60.0, 90.0];
                } else if dy > 0.3 && (mouth - 0.5).abs() < 0.06 {
                    rgb = [170.0, 40.0, 50.0];
                }
                if d > 0.93 {
                    rgb = [90.0, 50.0, 30.0];
                }
            }
            let i = (y * width as usize + x) * 3;
            for k in 0..3 {
                data[i + k] = rgb[k].clamp(0.0, 255.0) as u8;
            }
        }
    }
    Ok(out)
}
