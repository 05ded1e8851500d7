//! Grey, grey + alpha, RGB and RGBA pictures of 8 or 16 bits per channel, PNG in and
//! out, bilinear sampling.

use std::path::Path;

use crate::bendels_klein::error::{BendelsKleinError, Result, MAX_PIXELS};

/// The sample type of a [`Raster`]: `u8` (8 bits per channel, the default) or `u16`
/// (16 bits, as 16-bit PNGs hold them). Sealed: only these two.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 7 (pictures).
pub trait Sample:
    Copy + Default + PartialEq + Eq + std::fmt::Debug + Send + Sync + 'static + sealed::Sealed
{
    /// The largest value (full intensity, opaque).
    const MAX: f32;
    /// The value as `f32`.
    fn to_f32(self) -> f32;
    /// The value nearest to `v`, saturating to `0..=MAX` (NaN gives 0).
    fn from_f32(v: f32) -> Self;
    /// The samples and channel count of a decoded picture at this depth (palettes
    /// expanded; another depth converted by the `image` crate).
    #[doc(hidden)]
    fn decode(image: image::DynamicImage) -> (u8, Vec<Self>);
    /// Writes `data` (`channels` samples per pixel) as a PNG of this depth.
    #[doc(hidden)]
    fn encode(
        path: &Path,
        data: &[Self],
        width: u32,
        height: u32,
        channels: u8,
    ) -> image::ImageResult<()>;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for u8 {}
    impl Sealed for u16 {}
}

/// `Sample` for one sample type: its largest value and the `image` crate's conversions
/// to it (`$luma` … `$rgba`: `DynamicImage::into_luma8` … for `u8`, which keep the
/// buffer of a picture already of that type).
macro_rules! sample {
    ($t:ty, $max:expr, $luma:ident, $luma_alpha:ident, $rgb:ident, $rgba:ident) => {
        impl Sample for $t {
            const MAX: f32 = $max;
            #[inline(always)]
            fn to_f32(self) -> f32 {
                f32::from(self)
            }
            #[inline(always)]
            fn from_f32(v: f32) -> Self {
                // `as` saturates (NaN to 0).
                (v + 0.5) as $t
            }
            fn decode(image: image::DynamicImage) -> (u8, Vec<Self>) {
                match image.color().channel_count() {
                    1 => (1, image.$luma().into_raw()),
                    2 => (2, image.$luma_alpha().into_raw()),
                    3 => (3, image.$rgb().into_raw()),
                    _ => (4, image.$rgba().into_raw()),
                }
            }
            fn encode(
                path: &Path,
                data: &[Self],
                width: u32,
                height: u32,
                channels: u8,
            ) -> image::ImageResult<()> {
                use image::{ImageBuffer, Luma, LumaA, Rgb, Rgba};
                let data = data.to_vec();
                let mismatch = || {
                    image::ImageError::Parameter(image::error::ParameterError::from_kind(
                        image::error::ParameterErrorKind::DimensionMismatch,
                    ))
                };
                match channels {
                    1 => ImageBuffer::<Luma<$t>, _>::from_raw(width, height, data)
                        .ok_or_else(mismatch)?
                        .save_with_format(path, image::ImageFormat::Png),
                    2 => ImageBuffer::<LumaA<$t>, _>::from_raw(width, height, data)
                        .ok_or_else(mismatch)?
                        .save_with_format(path, image::ImageFormat::Png),
                    3 => ImageBuffer::<Rgb<$t>, _>::from_raw(width, height, data)
                        .ok_or_else(mismatch)?
                        .save_with_format(path, image::ImageFormat::Png),
                    _ => ImageBuffer::<Rgba<$t>, _>::from_raw(width, height, data)
                        .ok_or_else(mismatch)?
                        .save_with_format(path, image::ImageFormat::Png),
                }
            }
        }
    };
}

sample!(
    u8,
    255.0,
    into_luma8,
    into_luma_alpha8,
    into_rgb8,
    into_rgba8
);
sample!(
    u16,
    65535.0,
    to_luma16,
    to_luma_alpha16,
    to_rgb16,
    to_rgba16
);

/// A picture of `width × height` pixels, `channels` samples each (1 grey, 2 grey +
/// alpha, 3 RGB, 4 RGBA) of type `S`, rows top to bottom: the input and output of an
/// image edit (Bendels & Klein, Sec. 7). [`Raster`] holds 8 bits per channel,
/// [`Raster16`] 16.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RasterOf<S: Sample> {
    width: u32,
    height: u32,
    channels: u8,
    data: Vec<S>,
}

/// A picture of 8 bits per channel (what most PNGs hold).
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 7 (pictures).
pub type Raster = RasterOf<u8>;

/// A picture of 16 bits per channel (16-bit PNGs: scans, medical and scientific
/// pictures).
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 7 (pictures).
pub type Raster16 = RasterOf<u16>;

/// A PNG read at its own depth: 8 bits per channel or 16 ([`Picture::read_png`]).
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 7 (pictures).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Picture {
    /// 8 bits per channel (and palette pictures, expanded).
    Eight(Raster),
    /// 16 bits per channel.
    Sixteen(Raster16),
}

impl Picture {
    /// Reads a PNG, keeping 16-bit samples as 16-bit ([`Raster::read_png`] reduces them
    /// to 8 bits).
    ///
    /// # Errors
    /// [`BendelsKleinError::Png`] when the file cannot be read or decoded;
    /// [`BendelsKleinError::TooLarge`] above [`MAX_PIXELS`] pixels.
    pub fn read_png(path: impl AsRef<Path>) -> Result<Self> {
        let decoded = decode_png(path.as_ref())?;
        use image::DynamicImage as D;
        Ok(match decoded {
            D::ImageLuma16(_) | D::ImageLumaA16(_) | D::ImageRgb16(_) | D::ImageRgba16(_) => {
                Picture::Sixteen(RasterOf::from_decoded(decoded)?)
            }
            _ => Picture::Eight(RasterOf::from_decoded(decoded)?),
        })
    }
}

/// Decodes the PNG at `path` (errors name the file).
fn decode_png(path: &Path) -> Result<image::DynamicImage> {
    let wrap = |source: image::ImageError| BendelsKleinError::Png {
        path: path.to_path_buf(),
        source,
    };
    image::ImageReader::open(path)
        .map_err(|e| wrap(e.into()))?
        .with_guessed_format()
        .map_err(|e| wrap(e.into()))?
        .decode()
        .map_err(wrap)
}

/// `width × height × channels`, checked.
fn byte_len(width: u32, height: u32, channels: u8) -> Result<usize> {
    if !(1..=4).contains(&channels) {
        return Err(BendelsKleinError::Channels(channels));
    }
    (width as usize)
        .checked_mul(height as usize)
        .filter(|&n| n <= MAX_PIXELS)
        .and_then(|n| n.checked_mul(channels as usize))
        .ok_or(BendelsKleinError::TooLarge {
            width,
            height,
            channels,
        })
}

impl<S: Sample> RasterOf<S> {
    /// A picture from its samples (row-major, channels interleaved).
    ///
    /// # Errors
    /// [`BendelsKleinError::Channels`] for a channel count outside 1..=4,
    /// [`BendelsKleinError::TooLarge`] above [`MAX_PIXELS`] pixels,
    /// [`BendelsKleinError::DataLength`] when `data` has another length.
    pub fn new(width: u32, height: u32, channels: u8, data: Vec<S>) -> Result<Self> {
        let expected = byte_len(width, height, channels)?;
        if data.len() != expected {
            return Err(BendelsKleinError::DataLength {
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
    pub fn filled(width: u32, height: u32, value: &[S]) -> Result<Self> {
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
    /// Samples per pixel: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA.
    #[must_use]
    pub fn channels(&self) -> u8 {
        self.channels
    }
    /// True when the last channel is alpha (2 or 4 channels).
    #[must_use]
    pub fn has_alpha(&self) -> bool {
        self.channels % 2 == 0
    }
    /// The samples, row-major, channels interleaved.
    #[must_use]
    pub fn data(&self) -> &[S] {
        &self.data
    }
    /// The samples, mutable.
    pub fn data_mut(&mut self) -> &mut [S] {
        &mut self.data
    }
    /// The pixel at `(x, y)`, or `None` outside the picture.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Option<&[S]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let c = self.channels as usize;
        let i = (y as usize * self.width as usize + x as usize) * c;
        Some(&self.data[i..i + c])
    }
    /// Sets the pixel at `(x, y)`; outside the picture, or with a value of another
    /// channel count, nothing happens.
    pub fn set_pixel(&mut self, x: u32, y: u32, value: &[S]) {
        if x >= self.width || y >= self.height || value.len() != self.channels as usize {
            return;
        }
        let c = self.channels as usize;
        let i = (y as usize * self.width as usize + x as usize) * c;
        self.data[i..i + c].copy_from_slice(value);
    }

    /// Reads a PNG at this raster's depth, any bit depth and colour type: palettes
    /// expanded; a [`Raster`] reduces 16-bit samples to 8 bits, a [`Raster16`] widens
    /// 8-bit samples (× 257). [`Picture::read_png`] keeps a file's own depth.
    ///
    /// # Errors
    /// [`BendelsKleinError::Png`] when the file cannot be read or decoded;
    /// [`BendelsKleinError::TooLarge`] above [`MAX_PIXELS`] pixels.
    pub fn read_png(path: impl AsRef<Path>) -> Result<Self> {
        Self::from_decoded(decode_png(path.as_ref())?)
    }

    /// The raster of a decoded picture, at this depth.
    fn from_decoded(decoded: image::DynamicImage) -> Result<Self> {
        let (width, height) = (decoded.width(), decoded.height());
        let (channels, data) = S::decode(decoded);
        Self::new(width, height, channels, data)
    }

    /// Writes a PNG with the picture's channels (grey, grey + alpha, RGB or RGBA) and
    /// depth (8 or 16 bits).
    ///
    /// # Errors
    /// [`BendelsKleinError::Png`] when the file cannot be written.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        S::encode(path, &self.data, self.width, self.height, self.channels).map_err(|source| {
            BendelsKleinError::Png {
                path: path.to_path_buf(),
                source,
            }
        })
    }

    /// Bilinear sample at `(x, y)` (pixel centres at integers, clamped to the
    /// picture) into `out` (`channels` values in `0..=S::MAX`, not rounded). With alpha the
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
                    .map(|(&i, &wt)| wt * f64::from(d[i + k].to_f32()))
                    .sum();
            }
        } else {
            let a = c - 1;
            let alphas = taps.map(|i| f64::from(d[i + a].to_f32()));
            let alpha: f64 = alphas.iter().zip(&weights).map(|(x, w)| x * w).sum();
            out[a] = alpha;
            for k in 0..a {
                out[k] = if alpha > 0.0 {
                    let premultiplied: f64 = taps
                        .iter()
                        .zip(&weights)
                        .zip(&alphas)
                        .map(|((&i, &wt), &al)| wt * al * f64::from(d[i + k].to_f32()))
                        .sum();
                    premultiplied / alpha
                } else {
                    // Wholly transparent: the straight mean keeps the stored colour.
                    taps.iter()
                        .zip(&weights)
                        .map(|(&i, &wt)| wt * f64::from(d[i + k].to_f32()))
                        .sum()
                };
            }
        }
    }
}

impl<S: Sample> RasterOf<S> {
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
        let tap = |i: usize| -> [f32; C] { std::array::from_fn(|k| d[i + k].to_f32()) };
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
