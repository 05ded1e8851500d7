//! Pixel masks for the handle and the fixed region of an image edit (Bendels & Klein,
//! Sec. 2: regions drawn over the image).

use glam::DVec2;
use rayon::prelude::*;

use crate::bendels_klein::error::{BendelsKleinError, Result, MAX_PIXELS};
use crate::bendels_klein::image::raster::Raster;

/// A set of pixels of a `width × height` picture: the handle or the fixed region of an
/// image edit.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Secs. 2 and 7.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask {
    width: u32,
    height: u32,
    bits: Vec<bool>,
}

fn pixels(width: u32, height: u32) -> Result<usize> {
    (width as usize)
        .checked_mul(height as usize)
        .filter(|&n| n <= MAX_PIXELS)
        .ok_or(BendelsKleinError::TooLarge {
            width,
            height,
            channels: 1,
        })
}

fn check_polygon(polygon: &[DVec2]) -> Result<()> {
    if polygon.len() < 3 {
        return Err(BendelsKleinError::TooFewPoints {
            points: polygon.len(),
        });
    }
    if let Some(index) = polygon.iter().position(|p| !p.is_finite()) {
        return Err(BendelsKleinError::NonFinitePoint { index });
    }
    Ok(())
}

impl Mask {
    /// The empty mask.
    ///
    /// # Errors
    /// [`BendelsKleinError::TooLarge`] above [`MAX_PIXELS`] pixels (checked before
    /// allocating).
    pub fn empty(width: u32, height: u32) -> Result<Self> {
        Ok(Self {
            width,
            height,
            bits: vec![false; pixels(width, height)?],
        })
    }

    /// The pixels whose centre lies inside `polygon` (even–odd rule; the last point is
    /// joined to the first), in pixel coordinates (see the module docs).
    ///
    /// # Errors
    /// [`BendelsKleinError::TooFewPoints`], [`BendelsKleinError::NonFinitePoint`],
    /// [`BendelsKleinError::TooLarge`].
    pub fn polygon(width: u32, height: u32, polygon: &[DVec2]) -> Result<Self> {
        check_polygon(polygon)?;
        let mut mask = Self::empty(width, height)?;
        let w = width as usize;
        if w == 0 {
            return Ok(mask);
        }
        let n = polygon.len();
        mask.bits
            .par_chunks_mut(w)
            .enumerate()
            .for_each_init(Vec::new, |crossings, (y, row)| {
                let yc = y as f64;
                crossings.clear();
                for k in 0..n {
                    let (a, b) = (polygon[k], polygon[(k + 1) % n]);
                    // Half-open in y, so a vertex on the scan line counts once.
                    if (a.y <= yc) != (b.y <= yc) {
                        crossings.push(a.x + (yc - a.y) / (b.y - a.y) * (b.x - a.x));
                    }
                }
                crossings.sort_by(f64::total_cmp);
                for pair in crossings.chunks_exact(2) {
                    // Pixel centres strictly right of the first crossing and not right
                    // of the second: x0 < x <= x1, clipped to the row.
                    let first = (pair[0].floor() + 1.0).max(0.0);
                    let last = pair[1].floor().min((w - 1) as f64);
                    if first <= last {
                        row[first as usize..=last as usize].fill(true);
                    }
                }
            });
        Ok(mask)
    }

    /// The pixels whose centre lies outside `polygon`: the fixed region of a drawn
    /// border (everything beyond the curve the user drew stays).
    ///
    /// # Errors
    /// As [`Mask::polygon`].
    pub fn outside_polygon(width: u32, height: u32, polygon: &[DVec2]) -> Result<Self> {
        let mut mask = Self::polygon(width, height, polygon)?;
        mask.invert();
        Ok(mask)
    }

    /// The outermost `thickness` rings of pixels: the default fixed region (the image
    /// border stays, everything inside may move).
    ///
    /// # Errors
    /// [`BendelsKleinError::TooLarge`] above [`MAX_PIXELS`] pixels.
    pub fn border(width: u32, height: u32, thickness: u32) -> Result<Self> {
        let mut mask = Self::empty(width, height)?;
        let t = thickness;
        for y in 0..height {
            for x in 0..width {
                if x < t || y < t || x + t >= width || y + t >= height {
                    mask.bits[y as usize * width as usize + x as usize] = true;
                }
            }
        }
        Ok(mask)
    }

    /// The pixels of a mask picture whose first channel exceeds `threshold`.
    #[must_use]
    pub fn from_raster(raster: &Raster, threshold: u8) -> Self {
        let c = raster.channels() as usize;
        Self {
            width: raster.width(),
            height: raster.height(),
            bits: raster
                .data()
                .chunks_exact(c)
                .map(|p| p[0] > threshold)
                .collect(),
        }
    }

    /// Every pixel in exactly one of `self` and the complement: swaps inside and out.
    pub fn invert(&mut self) {
        self.bits.iter_mut().for_each(|b| *b = !*b);
    }

    /// Adds the pixels of `other`.
    ///
    /// # Errors
    /// [`BendelsKleinError::MaskSize`] when the sizes differ (then nothing changes).
    pub fn union_with(&mut self, other: &Mask) -> Result<()> {
        other.check_size(self.width, self.height)?;
        for (a, &b) in self.bits.iter_mut().zip(&other.bits) {
            *a |= b;
        }
        Ok(())
    }

    /// Adds or removes one pixel; outside the picture nothing happens.
    pub fn set(&mut self, x: u32, y: u32, value: bool) {
        if x < self.width && y < self.height {
            self.bits[y as usize * self.width as usize + x as usize] = value;
        }
    }

    /// True when `(x, y)` is in the mask (false outside the picture).
    #[must_use]
    pub fn contains(&self, x: u32, y: u32) -> bool {
        x < self.width
            && y < self.height
            && self.bits[y as usize * self.width as usize + x as usize]
    }
    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }
    /// One flag per pixel, row-major.
    #[must_use]
    pub fn bits(&self) -> &[bool] {
        &self.bits
    }
    /// Number of pixels in the mask.
    #[must_use]
    pub fn count(&self) -> usize {
        self.bits.iter().filter(|&&b| b).count()
    }

    pub(super) fn check_size(&self, width: u32, height: u32) -> Result<()> {
        if (self.width, self.height) != (width, height) {
            return Err(BendelsKleinError::MaskSize {
                got: (self.width, self.height),
                expected: (width, height),
            });
        }
        Ok(())
    }
}
