//! 8-bit grey, grey + alpha, RGB and RGBA pictures, PNG in and out, bilinear sampling.

use std::path::Path;

use super::{ImageEditError, ImageResult};

/// A picture of `width × height` pixels, `channels` bytes each (1 grey, 2 grey + alpha,
/// 3 RGB, 4 RGBA), rows top to bottom: the input and output of an image edit
/// (Bendels & Klein, Sec. 7). 16-bit PNGs are read as 8-bit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Raster {
    width: u32,
    height: u32,
    channels: u8,
    data: Vec<u8>,
}

/// `width × height × channels`, checked.
fn byte_len(width: u32, height: u32, channels: u8) -> ImageResult<usize> {
    if !(1..=4).contains(&channels) {
        return Err(ImageEditError::Channels(channels));
    }
    (width as usize)
        .checked_mul(height as usize)
        .filter(|&n| n <= super::MAX_PIXELS)
        .and_then(|n| n.checked_mul(channels as usize))
        .ok_or(ImageEditError::TooLarge {
            width,
            height,
            channels,
        })
}

impl Raster {
    /// A picture from its bytes (row-major, channels interleaved).
    ///
    /// # Errors
    /// [`ImageEditError::Channels`] for a channel count outside 1..=4,
    /// [`ImageEditError::TooLarge`] above [`super::MAX_PIXELS`] pixels,
    /// [`ImageEditError::DataLength`] when `data` has another length.
    pub fn new(width: u32, height: u32, channels: u8, data: Vec<u8>) -> ImageResult<Self> {
        let expected = byte_len(width, height, channels)?;
        if data.len() != expected {
            return Err(ImageEditError::DataLength {
                got: data.len(),
                expected,
            });
        }
        Ok(Self {
            width,
            height,
            channels,
            data,
        })
    }

    /// A picture with every pixel `value` (`value.len()` is the channel count).
    ///
    /// # Errors
    /// As [`Raster::new`].
    pub fn filled(width: u32, height: u32, value: &[u8]) -> ImageResult<Self> {
        let channels = u8::try_from(value.len()).unwrap_or(u8::MAX);
        let len = byte_len(width, height, channels)?;
        let data = value.iter().copied().cycle().take(len).collect();
        Self::new(width, height, channels, data)
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
    /// Bytes per pixel: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA.
    #[must_use]
    pub fn channels(&self) -> u8 {
        self.channels
    }
    /// True when the last channel is alpha (2 or 4 channels).
    #[must_use]
    pub fn has_alpha(&self) -> bool {
        self.channels % 2 == 0
    }
    /// The bytes, row-major, channels interleaved.
    #[must_use]
    pub fn data(&self) -> &[u8] {
        &self.data
    }
    /// The bytes, mutable.
    pub fn data_mut(&mut self) -> &mut [u8] {
        &mut self.data
    }
    /// The pixel at `(x, y)`, or `None` outside the picture.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Option<&[u8]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let c = self.channels as usize;
        let i = (y as usize * self.width as usize + x as usize) * c;
        Some(&self.data[i..i + c])
    }
    /// Sets the pixel at `(x, y)`; outside the picture, or with a value of another
    /// channel count, nothing happens.
    pub fn set_pixel(&mut self, x: u32, y: u32, value: &[u8]) {
        if x >= self.width || y >= self.height || value.len() != self.channels as usize {
            return;
        }
        let c = self.channels as usize;
        let i = (y as usize * self.width as usize + x as usize) * c;
        self.data[i..i + c].copy_from_slice(value);
    }

    /// Reads a PNG (any bit depth and colour type; 16-bit samples are reduced to
    /// 8-bit, palettes expanded).
    ///
    /// # Errors
    /// [`ImageEditError::Png`] when the file cannot be read or decoded.
    pub fn read_png(path: impl AsRef<Path>) -> ImageResult<Self> {
        let path = path.as_ref();
        let wrap = |source: image::ImageError| ImageEditError::Png {
            path: path.to_path_buf(),
            source,
        };
        let decoded = image::ImageReader::open(path)
            .map_err(|e| wrap(e.into()))?
            .with_guessed_format()
            .map_err(|e| wrap(e.into()))?
            .decode()
            .map_err(wrap)?;
        let (width, height) = (decoded.width(), decoded.height());
        use image::DynamicImage as D;
        let (channels, data) = match decoded {
            D::ImageLuma8(b) => (1, b.into_raw()),
            D::ImageLumaA8(b) => (2, b.into_raw()),
            D::ImageRgb8(b) => (3, b.into_raw()),
            D::ImageRgba8(b) => (4, b.into_raw()),
            D::ImageLuma16(_) => (1, decoded.to_luma8().into_raw()),
            D::ImageLumaA16(_) => (2, decoded.to_luma_alpha8().into_raw()),
            D::ImageRgb16(_) | D::ImageRgb32F(_) => (3, decoded.to_rgb8().into_raw()),
            _ => (4, decoded.to_rgba8().into_raw()),
        };
        Self::new(width, height, channels, data)
    }

    /// Writes a PNG with the picture's channels (grey, grey + alpha, RGB or RGBA).
    ///
    /// # Errors
    /// [`ImageEditError::Png`] when the file cannot be written.
    pub fn write_png(&self, path: impl AsRef<Path>) -> ImageResult<()> {
        let path = path.as_ref();
        let color = match self.channels {
            1 => image::ExtendedColorType::L8,
            2 => image::ExtendedColorType::La8,
            3 => image::ExtendedColorType::Rgb8,
            _ => image::ExtendedColorType::Rgba8,
        };
        image::save_buffer_with_format(
            path,
            &self.data,
            self.width,
            self.height,
            color,
            image::ImageFormat::Png,
        )
        .map_err(|source| ImageEditError::Png {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Bilinear sample at `(x, y)` (pixel centres at integers, clamped to the
    /// picture) into `out` (`channels` values in 0..=255, not rounded). With alpha the
    /// colour channels are interpolated premultiplied and divided back (where all four
    /// taps are transparent, straight).
    ///
    /// The reference the tests hold the resampling's `f32` sampler to.
    #[cfg(test)]
    pub(super) fn sample_bilinear(&self, x: f64, y: f64, out: &mut [f64; 4]) {
        let (w, h) = (self.width as usize, self.height as usize);
        let x = x.clamp(0.0, (w - 1) as f64);
        let y = y.clamp(0.0, (h - 1) as f64);
        let x0 = (x as usize).min(w.saturating_sub(2));
        let y0 = (y as usize).min(h.saturating_sub(2));
        let (fx, fy) = (x - x0 as f64, y - y0 as f64);
        let c = self.channels as usize;
        let row = w * c;
        // A picture one pixel wide or high repeats its only column or row.
        let (dx, dy) = (if w > 1 { c } else { 0 }, if h > 1 { row } else { 0 });
        let i00 = y0 * row + x0 * c;
        let (i10, i01) = (i00 + dx, i00 + dy);
        let i11 = i01 + dx;
        let weights = [
            (1.0 - fx) * (1.0 - fy),
            fx * (1.0 - fy),
            (1.0 - fx) * fy,
            fx * fy,
        ];
        let taps = [i00, i10, i01, i11];
        let d = &self.data;
        if c % 2 == 1 {
            for k in 0..c {
                out[k] = taps
                    .iter()
                    .zip(&weights)
                    .map(|(&i, &wt)| wt * f64::from(d[i + k]))
                    .sum();
            }
        } else {
            let a = c - 1;
            let alphas = taps.map(|i| f64::from(d[i + a]));
            let alpha: f64 = alphas.iter().zip(&weights).map(|(x, w)| x * w).sum();
            out[a] = alpha;
            for k in 0..a {
                out[k] = if alpha > 0.0 {
                    let premultiplied: f64 = taps
                        .iter()
                        .zip(&weights)
                        .zip(&alphas)
                        .map(|((&i, &wt), &al)| wt * al * f64::from(d[i + k]))
                        .sum();
                    premultiplied / alpha
                } else {
                    // Wholly transparent: the straight mean keeps the stored colour.
                    taps.iter()
                        .zip(&weights)
                        .map(|(&i, &wt)| wt * f64::from(d[i + k]))
                        .sum()
                };
            }
        }
    }
}

impl Raster {
    /// [`Raster::sample_bilinear`] for `C` channels in `f32` arithmetic, unrolled: the
    /// resampling's inner loop. Agrees with the `f64` version to about 1e-4.
    #[inline(always)]
    pub(super) fn sample_bilinear_fast<const C: usize>(&self, x: f64, y: f64) -> [f32; C] {
        let (w, h) = (self.width as usize, self.height as usize);
        let x = x.max(0.0).min((w - 1) as f64);
        let y = y.max(0.0).min((h - 1) as f64);
        let x0 = (x as usize).min(w.saturating_sub(2));
        let y0 = (y as usize).min(h.saturating_sub(2));
        let (fx, fy) = ((x - x0 as f64) as f32, (y - y0 as f64) as f32);
        let row = w * C;
        let (dx, dy) = (if w > 1 { C } else { 0 }, if h > 1 { row } else { 0 });
        let i00 = y0 * row + x0 * C;
        let d = &self.data;
        let tap = |i: usize| -> [f32; C] { std::array::from_fn(|k| f32::from(d[i + k])) };
        let (p00, p10, p01, p11) = (tap(i00), tap(i00 + dx), tap(i00 + dy), tap(i00 + dy + dx));
        let (w00, w10) = ((1.0 - fx) * (1.0 - fy), fx * (1.0 - fy));
        let (w01, w11) = ((1.0 - fx) * fy, fx * fy);
        if C % 2 == 1 {
            return std::array::from_fn(|k| {
                w00 * p00[k] + w10 * p10[k] + w01 * p01[k] + w11 * p11[k]
            });
        }
        let a = C - 1;
        let (a00, a10, a01, a11) = (w00 * p00[a], w10 * p10[a], w01 * p01[a], w11 * p11[a]);
        let alpha = a00 + a10 + a01 + a11;
        std::array::from_fn(|k| {
            if k == a {
                alpha
            } else if alpha > 0.0 {
                (a00 * p00[k] + a10 * p10[k] + a01 * p01[k] + a11 * p11[k]) / alpha
            } else {
                w00 * p00[k] + w10 * p10[k] + w01 * p01[k] + w11 * p11[k]
            }
        })
    }
}
