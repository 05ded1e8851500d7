//! The image editing session: grid mesh, distances, blend and resampling (Bendels &
//! Klein, Secs. 2–5 and 7 on a picture; see the module docs of [`super`]).

use glam::{DMat3, DVec2};
use rayon::prelude::*;

use crate::bendels_klein::blend::BlendCore;
use crate::bendels_klein::error::{BendelsKleinError, RegionKind, Result, Site};
use crate::bendels_klein::image::edt::squared_distances_at;
use crate::bendels_klein::image::mask::Mask;
use crate::bendels_klein::image::raster::{RasterOf, Sample};
use crate::bendels_klein::regions::Role;
use crate::bendels_klein::shape::ShapeFunction;

/// Options of an [`ImageSession`].
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 7 and Fig. 6.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ImageOptions {
    /// Pixels between grid vertices (the paper: "a regular grid mesh"). Smaller steps
    /// follow the regions' outlines and the shape function more closely and cost more
    /// per drag. Default 4.
    pub grid_step: u32,
    /// The shape function. Default: C¹ smoothstep.
    pub shape: ShapeFunction,
}

impl ImageOptions {
    /// The same options with the pixels between grid vertices set to `grid_step`.
    #[must_use]
    pub fn with_grid_step(mut self, grid_step: u32) -> Self {
        self.grid_step = grid_step;
        self
    }

    /// The same options with the shape function set to `shape`.
    #[must_use]
    pub fn with_shape(mut self, shape: ShapeFunction) -> Self {
        self.shape = shape;
        self
    }
}

impl Default for ImageOptions {
    fn default() -> Self {
        Self {
            grid_step: 4,
            shape: ShapeFunction::Smoothstep,
        }
    }
}

/// What one [`ImageSession::render_into`] did.
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 7.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Triangles drawn: the two of every grid cell with a corner that moved.
    pub triangles: usize,
    /// Output pixels resampled (neither fixed nor under an unmoved triangle).
    pub pixels: usize,
}

/// Rows per band of the parallel resampling.
const BAND: usize = 16;
/// Tolerance of the inside test, in barycentric units: shared edges are drawn by both
/// triangles, so no pixel centre falls between them.
const INSIDE: f64 = 1e-9;

/// A Bendels & Klein image edit of a picture of samples `S`: the picture, its regions,
/// the grid mesh with its weights, and the current handle transform (see the module
/// docs of [`super`]). [`ImageSession`] edits 8-bit pictures, [`ImageSession16`] 16-bit
/// ones.
#[derive(Clone, Debug)]
pub struct ImageSessionOf<S: Sample> {
    source: RasterOf<S>,
    handle: Mask,
    fixed: Mask,
    xs: Vec<u32>,
    ys: Vec<u32>,
    original: Vec<DVec2>,
    deformed: Vec<DVec2>,
    /// Roles, distances, weights, shape function and transform of the grid vertices
    /// (shared with the mesh and polyline sessions).
    core: BlendCore<DVec2>,
}

/// Grid coordinates along one side: `0, step, 2 step, …` and the last pixel.
fn grid_line(len: u32, step: u32) -> Vec<u32> {
    let mut line: Vec<u32> = (0..len).step_by(step as usize).collect();
    if line.last() != Some(&(len - 1)) {
        line.push(len - 1);
    }
    line
}

/// The edit of an 8-bit picture ([`super::Raster`]).
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 7 and Fig. 6.
pub type ImageSession = ImageSessionOf<u8>;

/// The edit of a 16-bit picture ([`super::Raster16`]).
///
/// Paper: Bendels & Klein 2003, *Image and 3D-object editing with precisely specified
/// editing regions*, Sec. 7 and Fig. 6.
pub type ImageSession16 = ImageSessionOf<u16>;

impl<S: Sample> ImageSessionOf<S> {
    /// Sets up the edit of `image` with the `handle` and `fixed` masks: builds the grid,
    /// the two exact distance fields at its vertices and the weights. Every grid vertex
    /// on a handle pixel is handle, on a fixed pixel fixed, the others deformable.
    ///
    /// # Errors
    /// [`BendelsKleinError::TooSmall`] for a picture under 2×2 pixels,
    /// [`BendelsKleinError::GridStep`] for a step of 0, [`BendelsKleinError::MaskSize`],
    /// [`BendelsKleinError::EmptyRegion`], [`BendelsKleinError::Overlap`],
    /// [`BendelsKleinError::HandleTouchesFixed`].
    pub fn new(
        image: RasterOf<S>,
        handle: Mask,
        fixed: Mask,
        options: ImageOptions,
    ) -> Result<Self> {
        let (w, h) = (image.width(), image.height());
        if w < 2 || h < 2 {
            return Err(BendelsKleinError::TooSmall {
                width: w,
                height: h,
            });
        }
        if options.grid_step == 0 {
            return Err(BendelsKleinError::GridStep);
        }
        handle.check_size(w, h)?;
        fixed.check_size(w, h)?;
        check_regions(&handle, &fixed)?;
        let xs = grid_line(w, options.grid_step);
        let ys = grid_line(h, options.grid_step);
        let dh = squared_distances_at(&handle, &xs, &ys);
        let df = squared_distances_at(&fixed, &xs, &ys);
        let nx = xs.len();
        let n = nx * ys.len();
        let mut roles = Vec::with_capacity(n);
        let mut original = Vec::with_capacity(n);
        for &y in &ys {
            for &x in &xs {
                roles.push(if handle.contains(x, y) {
                    Role::Handle
                } else if fixed.contains(x, y) {
                    Role::Fixed
                } else {
                    Role::Deformable
                });
                original.push(DVec2::new(f64::from(x), f64::from(y)));
            }
        }
        let core = BlendCore::new(
            roles,
            dh.into_iter().map(f64::sqrt).collect(),
            df.into_iter().map(f64::sqrt).collect(),
            vec![0.0; n],
            options.shape,
        );
        Ok(Self {
            source: image,
            handle,
            fixed,
            xs,
            ys,
            deformed: original.clone(),
            original,
            core,
        })
    }

    /// The input picture.
    #[must_use]
    pub fn source(&self) -> &RasterOf<S> {
        &self.source
    }
    /// The handle mask.
    #[must_use]
    pub fn handle_mask(&self) -> &Mask {
        &self.handle
    }
    /// The fixed mask.
    #[must_use]
    pub fn fixed_mask(&self) -> &Mask {
        &self.fixed
    }
    /// Grid vertices per row and per column.
    #[must_use]
    pub fn grid_size(&self) -> (usize, usize) {
        (self.xs.len(), self.ys.len())
    }
    /// Grid vertices before the edit, row-major.
    #[must_use]
    pub fn original_grid(&self) -> &[DVec2] {
        &self.original
    }
    /// Grid vertices after the current transform, row-major.
    #[must_use]
    pub fn deformed_grid(&self) -> &[DVec2] {
        &self.deformed
    }
    /// The role of every grid vertex.
    #[must_use]
    pub fn roles(&self) -> &[Role] {
        self.core.roles()
    }
    /// The weight α of every grid vertex (0 fixed, 1 handle).
    #[must_use]
    pub fn alpha(&self) -> &[f64] {
        self.core.alpha()
    }
    /// Distances of the grid vertices to the nearest handle pixel.
    #[must_use]
    pub fn handle_distances(&self) -> &[f64] {
        self.core.handle_distances()
    }
    /// Distances of the grid vertices to the nearest fixed pixel.
    #[must_use]
    pub fn fixed_distances(&self) -> &[f64] {
        self.core.fixed_distances()
    }
    /// The current handle transform (identity before the first edit).
    #[must_use]
    pub fn transform(&self) -> DMat3 {
        self.core.transform()
    }
    /// The shape function.
    #[must_use]
    pub fn shape(&self) -> &ShapeFunction {
        self.core.shape()
    }

    /// Applies the handle transform `a` (3×3 homogeneous, pixel coordinates) to the
    /// grid: handle vertices to `A p`, deformable ones to `exp(α log A) p`, fixed ones
    /// stay. `log A` once, the vertices in parallel. Call [`ImageSession::render`] for
    /// the picture. On error nothing changes.
    ///
    /// # Errors
    /// [`BendelsKleinError::NoRealLogarithm`] (a reflection, a singular map, a half turn),
    /// [`BendelsKleinError::NotAffine`] or [`BendelsKleinError::NonFiniteMatrix`];
    /// [`BendelsKleinError::Overflow`] naming the first grid vertex that would leave the
    /// finite range (then nothing changes).
    pub fn apply(&mut self, a: DMat3) -> Result<()> {
        let previous = self.core.set_transform(a)?;
        let saved = self.deformed.clone();
        self.deform();
        if let Some(index) = self.deformed.iter().position(|p| !p.is_finite()) {
            let position = self.deformed[index].extend(0.0);
            self.deformed = saved;
            self.core.restore(previous);
            return Err(BendelsKleinError::Overflow {
                what: "the blended transform",
                site: Site::GridVertex(index),
                position,
            });
        }
        Ok(())
    }

    /// Changes the shape function (the paper's Fig. 8) and re-deforms the grid.
    pub fn set_shape(&mut self, shape: ShapeFunction) {
        self.core.set_shape(shape);
        self.deform();
    }

    /// Back to the identity: the grid undeformed.
    pub fn reset(&mut self) {
        self.core.reset_transform();
        self.deformed.clone_from(&self.original);
    }

    /// Moves every grid vertex from its original by the blend.
    fn deform(&mut self) {
        let core = &self.core;
        self.deformed
            .par_iter_mut()
            .zip(self.original.par_iter())
            .zip(core.alpha().par_iter())
            .zip(core.roles().par_iter())
            .with_min_len(4096)
            .for_each(|(((d, &o), &alpha), &role)| *d = core.place(role, alpha, o));
    }

    /// The three vertices of triangle `t` (two per cell, `(00, 10, 11)` and
    /// `(00, 11, 01)`, counter-clockwise with `y` up, positive with `y` down).
    #[inline]
    fn triangle(&self, t: usize) -> [usize; 3] {
        let nx = self.xs.len();
        let cell = t / 2;
        let (i, j) = (cell % (nx - 1), cell / (nx - 1));
        let v00 = j * nx + i;
        let (v10, v01) = (v00 + 1, v00 + nx);
        let v11 = v01 + 1;
        if t % 2 == 0 {
            [v00, v10, v11]
        } else {
            [v00, v11, v01]
        }
    }

    fn n_triangles(&self) -> usize {
        2 * (self.xs.len() - 1) * (self.ys.len() - 1)
    }

    /// Signed area (`y` down, so positive for the undeformed grid) of triangle `t`.
    fn area(points: &[DVec2], [a, b, c]: [usize; 3]) -> f64 {
        (points[b] - points[a]).perp_dot(points[c] - points[a])
    }

    /// The smallest ratio of deformed to original signed area over all grid
    /// triangles: positive when no cell folded over (every triangle keeps its
    /// orientation), 1 for the undeformed grid.
    #[must_use]
    pub fn min_area_ratio(&self) -> f64 {
        (0..self.n_triangles())
            .into_par_iter()
            .map(|t| {
                let tri = self.triangle(t);
                Self::area(&self.deformed, tri) / Self::area(&self.original, tri)
            })
            .reduce(|| f64::INFINITY, f64::min)
    }

    /// Number of grid triangles that lost their orientation (fold-over).
    #[must_use]
    pub fn folded_triangles(&self) -> usize {
        (0..self.n_triangles())
            .into_par_iter()
            .filter(|&t| Self::area(&self.deformed, self.triangle(t)) <= 0.0)
            .count()
    }

    /// The edited picture (see [`ImageSession::render_into`]).
    #[must_use]
    pub fn render(&self) -> RasterOf<S> {
        let mut out = self.source.clone();
        self.draw(&mut out);
        out
    }

    /// Resamples the edited picture into `out` (same size and channels as the input),
    /// reusing its memory: the input copied, then every pixel under a triangle that
    /// moved and not in the fixed region is drawn by inverse mapping and bilinear
    /// sampling (see the module docs of [`super`]).
    ///
    /// # Errors
    /// [`BendelsKleinError::OutputMismatch`] for another size or channel count.
    pub fn render_into(&self, out: &mut RasterOf<S>) -> Result<RenderStats> {
        let shape = |r: &RasterOf<S>| (r.width(), r.height(), r.channels());
        if shape(out) != shape(&self.source) {
            return Err(BendelsKleinError::OutputMismatch {
                got: shape(out),
                expected: shape(&self.source),
            });
        }
        out.data_mut()
            .par_chunks_mut(1 << 16)
            .zip(self.source.data().par_chunks(1 << 16))
            .for_each(|(o, s)| o.copy_from_slice(s));
        Ok(self.draw(out))
    }

    fn draw(&self, out: &mut RasterOf<S>) -> RenderStats {
        let h = self.source.height() as usize;
        let (nx, ny) = (self.xs.len(), self.ys.len());
        // The cells that moved, binned by the bands of rows their deformed bounding
        // boxes reach; unmoved cells keep the copied input, which is exact.
        let moved: Vec<(u32, usize, usize)> = (0..(nx - 1) * (ny - 1))
            .into_par_iter()
            .filter_map(|cell| {
                let v00 = (cell / (nx - 1)) * nx + cell % (nx - 1);
                let corners = [v00, v00 + 1, v00 + nx, v00 + nx + 1];
                if corners.iter().all(|&v| self.core.alpha()[v] == 0.0) {
                    return None;
                }
                let ys = corners.map(|v| self.deformed[v].y);
                let (top, bottom) = pixel_range(
                    ys.iter().copied().fold(f64::INFINITY, f64::min),
                    ys.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                    h,
                )?;
                Some((cell as u32, top / BAND, bottom / BAND))
            })
            .collect();
        let mut bins: Vec<Vec<u32>> = vec![Vec::new(); h.div_ceil(BAND)];
        for &(cell, b0, b1) in &moved {
            for bin in &mut bins[b0..=b1] {
                bin.push(cell);
            }
        }
        let pixels = match self.source.channels() {
            1 => self.draw_bands::<1>(out, &bins),
            2 => self.draw_bands::<2>(out, &bins),
            3 => self.draw_bands::<3>(out, &bins),
            _ => self.draw_bands::<4>(out, &bins),
        };
        RenderStats {
            triangles: 2 * moved.len(),
            pixels,
        }
    }

    /// Draws the binned cells band by band in parallel, for `C` channels; returns the
    /// number of pixels drawn.
    fn draw_bands<const C: usize>(&self, out: &mut RasterOf<S>, bins: &[Vec<u32>]) -> usize {
        let (w, h) = (self.source.width() as usize, self.source.height() as usize);
        let fixed = self.fixed.bits();
        let source = &self.source;
        out.data_mut()
            .par_chunks_mut(BAND * w * C)
            .zip(bins.par_iter())
            .enumerate()
            .map(|(band, (rows, bin))| {
                let y0 = band * BAND;
                let y1 = (y0 + BAND).min(h);
                let mut depth = vec![f32::NEG_INFINITY; (y1 - y0) * w];
                for &cell in bin {
                    for half in 0..2 {
                        let tri = self.triangle(2 * cell as usize + half);
                        let Some(t) = Triangle::new(
                            tri.map(|v| self.deformed[v]),
                            tri.map(|v| self.original[v]),
                            tri.iter().map(|&v| self.core.alpha()[v]).sum::<f64>() as f32,
                            h,
                        ) else {
                            continue;
                        };
                        for y in t.rows.0.max(y0)..=t.rows.1.min(y1 - 1) {
                            let yf = y as f64;
                            let Some((xa, xb)) = t.span(yf, w) else {
                                continue;
                            };
                            let fixed_row = &fixed[y * w..(y + 1) * w];
                            let depth_row = &mut depth[(y - y0) * w..(y - y0 + 1) * w];
                            let out_row = &mut rows[(y - y0) * w * C..(y - y0 + 1) * w * C];
                            let (bx, by) = (t.map[1] * yf + t.map[2], t.map[4] * yf + t.map[5]);
                            for x in xa..=xb {
                                if fixed_row[x] || depth_row[x] > t.priority {
                                    continue;
                                }
                                depth_row[x] = t.priority;
                                let xf = x as f64;
                                let value = source.sample_bilinear_fast::<C>(
                                    t.map[0] * xf + bx,
                                    t.map[3] * xf + by,
                                );
                                for (dst, &v) in out_row[x * C..(x + 1) * C].iter_mut().zip(&value)
                                {
                                    // Rounded, saturating (NaN to 0).
                                    *dst = S::from_f32(v);
                                }
                            }
                        }
                    }
                }
                // Pixels drawn by several triangles count once.
                depth.iter().filter(|d| d.is_finite()).count()
            })
            .sum()
    }
}

/// The pixel rows (or columns) `⌈lo⌉ ..= ⌊hi⌋` within `0..len`, or `None` when empty.
/// Casts instead of `ceil` / `floor` (library calls without SSE 4.1).
#[inline]
fn pixel_range(lo: f64, hi: f64, len: usize) -> Option<(usize, usize)> {
    if lo.is_nan() || hi.is_nan() || lo > hi || hi < 0.0 || lo > (len - 1) as f64 {
        return None;
    }
    let lo = lo.max(0.0);
    let mut first = lo as usize;
    if (first as f64) < lo {
        first += 1;
    }
    let last = hi.min((len - 1) as f64) as usize;
    (first <= last).then_some((first, last))
}

/// A deformed triangle prepared for inverse mapping: its barycentric coordinates as
/// affine functions of the output pixel, and the affine map from output to source.
struct Triangle {
    /// `λ_k(x, y) = l[k][0] x + l[k][1] y + l[k][2]`; `l[k][3] = −1 / l[k][0]` (0 when
    /// `l[k][0] = 0`).
    l: [[f64; 4]; 3],
    /// Source `x = m0 x + m1 y + m2`, `y = m3 x + m4 y + m5`.
    map: [f64; 6],
    /// Output rows covered (inclusive), clipped to the picture.
    rows: (usize, usize),
    /// Sum of the corners' α: where triangles overlap, the larger wins.
    priority: f32,
}

impl Triangle {
    #[inline]
    fn new(p: [DVec2; 3], o: [DVec2; 3], priority: f32, height: usize) -> Option<Self> {
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let area = e1.perp_dot(e2);
        if area.abs() < 1e-12 || !area.is_finite() {
            return None;
        }
        let ymin = p[0].y.min(p[1].y).min(p[2].y);
        let ymax = p[0].y.max(p[1].y).max(p[2].y);
        let rows = pixel_range(ymin, ymax, height)?;
        let inv = 1.0 / area;
        let l1 = [
            e2.y * inv,
            -e2.x * inv,
            (p[0].y * e2.x - p[0].x * e2.y) * inv,
        ];
        let l2 = [
            -e1.y * inv,
            e1.x * inv,
            (p[0].x * e1.y - p[0].y * e1.x) * inv,
        ];
        let l0 = [-l1[0] - l2[0], -l1[1] - l2[1], 1.0 - l1[2] - l2[2]];
        let (f1, f2) = (o[1] - o[0], o[2] - o[0]);
        let map = [
            l1[0] * f1.x + l2[0] * f2.x,
            l1[1] * f1.x + l2[1] * f2.x,
            l1[2] * f1.x + l2[2] * f2.x + o[0].x,
            l1[0] * f1.y + l2[0] * f2.y,
            l1[1] * f1.y + l2[1] * f2.y,
            l1[2] * f1.y + l2[2] * f2.y + o[0].y,
        ];
        let with_reciprocal = |l: [f64; 3]| {
            [
                l[0],
                l[1],
                l[2],
                if l[0] != 0.0 { -1.0 / l[0] } else { 0.0 },
            ]
        };
        Some(Self {
            l: [l0, l1, l2].map(with_reciprocal),
            map,
            rows,
            priority,
        })
    }

    /// The pixel columns of row `y` inside the triangle (every `λ ≥ −ε`), clipped to
    /// `0..width`.
    #[inline]
    fn span(&self, y: f64, width: usize) -> Option<(usize, usize)> {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for l in &self.l {
            // l0 x + rest ≥ 0  ⇔  x ≥ −rest / l0 (l0 > 0), x ≤ −rest / l0 (l0 < 0)
            let rest = l[1] * y + l[2] + INSIDE;
            if l[0] > 0.0 {
                lo = lo.max(rest * l[3]);
            } else if l[0] < 0.0 {
                hi = hi.min(rest * l[3]);
            } else if rest < 0.0 {
                return None;
            }
        }
        pixel_range(lo, hi, width)
    }
}

/// The handle and the fixed region: non-empty, disjoint, not touching.
fn check_regions(handle: &Mask, fixed: &Mask) -> Result<()> {
    if handle.count() == 0 {
        return Err(BendelsKleinError::EmptyRegion(RegionKind::Handle));
    }
    if fixed.count() == 0 {
        return Err(BendelsKleinError::EmptyRegion(RegionKind::Fixed));
    }
    let (w, h) = (handle.width(), handle.height());
    let overlap = (0..h).into_par_iter().find_map_first(|y| {
        (0..w)
            .find(|&x| handle.contains(x, y) && fixed.contains(x, y))
            .map(|x| BendelsKleinError::Overlap {
                site: Site::Pixel { x, y },
            })
    });
    if let Some(error) = overlap {
        return Err(error);
    }
    let touching = (0..h).into_par_iter().find_map_first(|y| {
        (0..w).filter(|&x| handle.contains(x, y)).find_map(|x| {
            NEIGHBOURS.iter().find_map(|&(dx, dy)| {
                let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
                let inside = nx >= 0 && ny >= 0 && nx < i64::from(w) && ny < i64::from(h);
                (inside && fixed.contains(nx as u32, ny as u32)).then(|| {
                    BendelsKleinError::HandleTouchesFixed {
                        handle: Site::Pixel { x, y },
                        fixed: Site::Pixel {
                            x: nx as u32,
                            y: ny as u32,
                        },
                    }
                })
            })
        })
    });
    touching.map_or(Ok(()), Err)
}

/// The 8-neighbourhood.
const NEIGHBOURS: [(i64, i64); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];
