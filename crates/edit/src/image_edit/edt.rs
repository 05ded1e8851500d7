//! The exact Euclidean distance transform of a pixel mask, after Felzenszwalb &
//! Huttenlocher (2012), *Distance transforms of sampled functions*, Sec. 2–3: the
//! squared distance is separable, so a pass along every row (the nearest mask pixel of
//! the row, by two sweeps) is followed by a pass along the columns, where the lower
//! envelope of the parabolas `(y − q)² + g(q)` gives the exact minimum in linear time.
//! All values are integers below 2⁵³, computed exactly in `f64`.
//!
//! Bendels & Klein (Sec. 4.1) obtain the same field for images from graphics hardware;
//! the image edit ([`super::ImageSession`]) needs it only at its grid vertices, so
//! [`squared_distances_at`] runs the column pass only for the grid's columns and keeps
//! only the grid's rows.

use rayon::prelude::*;

use super::mask::Mask;

/// Squared horizontal distance to the nearest mask pixel of each row (`∞` for rows
/// without one).
fn row_pass(mask: &Mask) -> Vec<f64> {
    let w = mask.width() as usize;
    let mut g = vec![f64::INFINITY; mask.bits().len()];
    if w == 0 {
        return g;
    }
    g.par_chunks_mut(w)
        .zip(mask.bits().par_chunks(w))
        .with_min_len(16)
        .for_each(|(out, bits)| {
            let mut last: Option<usize> = None;
            for x in 0..w {
                if bits[x] {
                    last = Some(x);
                }
                if let Some(l) = last {
                    out[x] = (x - l) as f64;
                }
            }
            let mut next: Option<usize> = None;
            for x in (0..w).rev() {
                if bits[x] {
                    next = Some(x);
                }
                if let Some(r) = next {
                    out[x] = out[x].min((r - x) as f64);
                }
                out[x] *= out[x];
            }
        });
    g
}

/// One column of the second pass: `d(y) = min_q (y − q)² + f(q)` over the finite `f(q)`,
/// by the lower envelope of parabolas; scratch vectors reused.
fn envelope(f: &[f64], d: &mut [f64], v: &mut Vec<usize>, z: &mut Vec<f64>) {
    let n = f.len();
    v.clear();
    z.clear();
    for q in 0..n {
        if !f[q].is_finite() {
            continue;
        }
        let qf = q as f64;
        let mut s = f64::NEG_INFINITY;
        while let Some(&p) = v.last() {
            let pf = p as f64;
            s = ((f[q] + qf * qf) - (f[p] + pf * pf)) / (2.0 * (qf - pf));
            if s <= *z.last().expect("one boundary per parabola") {
                v.pop();
                z.pop();
                s = f64::NEG_INFINITY;
            } else {
                break;
            }
        }
        v.push(q);
        z.push(s);
    }
    if v.is_empty() {
        d.fill(f64::INFINITY);
        return;
    }
    let mut j = 0;
    for (y, out) in d.iter_mut().enumerate() {
        let yf = y as f64;
        while j + 1 < v.len() && z[j + 1] < yf {
            j += 1;
        }
        let q = v[j] as f64;
        *out = (yf - q) * (yf - q) + f[v[j]];
    }
}

/// The squared Euclidean distance from every pixel to the nearest pixel of `mask`
/// (0 on the mask, `+∞` everywhere when the mask is empty), row-major.
#[must_use]
pub fn squared_distance_transform(mask: &Mask) -> Vec<f64> {
    let columns: Vec<u32> = (0..mask.width()).collect();
    let rows: Vec<u32> = (0..mask.height()).collect();
    squared_distances_at(mask, &columns, &rows)
}

/// The squared Euclidean distance transform of `mask` at the pixels `(columns[i],
/// rows[j])`, row-major over `rows × columns` (entry `j · columns.len() + i`): the
/// exact field sampled on a grid, for a fraction of the work of the whole field.
/// Columns or rows outside the mask's picture get `+∞`.
#[must_use]
pub fn squared_distances_at(mask: &Mask, columns: &[u32], rows: &[u32]) -> Vec<f64> {
    let (w, h) = (mask.width() as usize, mask.height() as usize);
    let g = row_pass(mask);
    let per_column: Vec<Vec<f64>> = columns
        .par_iter()
        .map_init(
            || (vec![0.0; h], vec![0.0; h], Vec::new(), Vec::new()),
            |(f, d, v, z), &x| {
                let x = x as usize;
                if x >= w {
                    return vec![f64::INFINITY; rows.len()];
                }
                for (y, fy) in f.iter_mut().enumerate() {
                    *fy = g[y * w + x];
                }
                envelope(f, d, v, z);
                rows.iter()
                    .map(|&y| d.get(y as usize).copied().unwrap_or(f64::INFINITY))
                    .collect()
            },
        )
        .collect();
    let nc = columns.len();
    let mut out = vec![0.0; nc * rows.len()];
    for (i, column) in per_column.iter().enumerate() {
        for (j, &value) in column.iter().enumerate() {
            out[j * nc + i] = value;
        }
    }
    out
}
