//! Pictures of meshes without a GPU: a small software renderer (perspective projection,
//! z-buffer, Lambert shading with per-vertex colours) that writes PNG files, so before /
//! after pictures come out the same on a headless machine. Behind the `render` cargo
//! feature (on by default).
//!
//! A picture is one or more meshes side by side ([`render_side_by_side`]), each in a
//! panel of the same size, seen by the same [`Camera`] and framed on the same box — by
//! default the union of the meshes' bounding boxes, so that a part an edit pulled out
//! stays in the frame and the panels compare.
//!
//! ```
//! use multires::halfedge::generators;
//! use multires::render::{render_side_by_side, Camera, Panel};
//! let before = generators::icosphere(3);
//! let mut after = before.clone();
//! for p in after.positions_mut() {
//!     p.x *= 1.5; // stretched: the frame grows to hold it
//! }
//! let picture = render_side_by_side(
//!     &[Panel::new(&before), Panel::new(&after)],
//!     &Camera::default(),
//!     None,
//!     160,
//!     120,
//! )
//! .unwrap();
//! assert_eq!((picture.width, picture.height), (320, 120));
//! picture.save_png(std::env::temp_dir().join("multires-doc-render.png")).unwrap();
//! ```

use std::path::{Path, PathBuf};

use glam::{DMat3, DVec3};
use halfedge::Mesh;
use rayon::prelude::*;

/// The largest picture side, in pixels.
pub const MAX_SIDE: usize = 16_384;

/// The largest picture, in pixels (all panels together): 2²³, e.g. 4096 × 2048. A
/// render needs about 35 bytes a pixel while it draws, so this keeps one under 300 MB.
pub const MAX_PIXELS: usize = 1 << 23;

/// What can go wrong making a picture.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A width or height of zero, or above [`MAX_SIDE`], or more than [`MAX_PIXELS`]
    /// pixels in all.
    #[error("picture size {width} × {height} is out of range (1 to {MAX_SIDE} pixels a side, at most {MAX_PIXELS} pixels)")]
    Size {
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
    },
    /// A colour array shorter than the mesh's vertex slots.
    #[error("panel {panel}: {found} colours for {expected} vertex slots")]
    Colors {
        /// Index of the panel.
        panel: usize,
        /// [`Mesh::vertex_slots`] of its mesh.
        expected: usize,
        /// Colours given.
        found: usize,
    },
    /// Nothing to frame: no panel, no vertex, or a frame that is not finite.
    #[error("nothing to frame: {0}")]
    Frame(String),
    /// A camera with a zero or non-finite direction or up vector, the two parallel, or a
    /// field of view outside (0, π).
    #[error("invalid camera: {0}")]
    Camera(String),
    /// Writing the PNG failed.
    #[error("{path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// Shorthand for results of this module.
pub type Result<T, E = RenderError> = std::result::Result<T, E>;

/// How to look at the framed box: from its centre along `direction` to the eye, at the
/// distance where the box's bounding sphere fills the view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Direction from the centre of the frame towards the eye (any length).
    pub direction: DVec3,
    /// Up vector (need not be orthogonal to `direction`, must not be parallel to it).
    pub up: DVec3,
    /// Vertical field of view in radians.
    pub fov_y: f64,
}

impl Default for Camera {
    /// Three-quarter view from the front (+z), a little from the right and above, +y up.
    fn default() -> Self {
        Self {
            direction: DVec3::new(0.35, 0.3, 1.0),
            up: DVec3::Y,
            fov_y: 0.6,
        }
    }
}

impl Camera {
    /// A camera looking at the frame from `direction` with `up` up (field of view 0.6).
    pub fn along(direction: DVec3, up: DVec3) -> Self {
        Self {
            direction,
            up,
            ..Self::default()
        }
    }

    /// The unit eye direction, right and up vectors.
    fn basis(&self) -> Result<(DVec3, DVec3, DVec3)> {
        let bad = |why: &str| {
            Err(RenderError::Camera(format!(
                "{why} (direction {}, up {}, fov_y {})",
                self.direction, self.up, self.fov_y
            )))
        };
        if !(self.fov_y > 0.0 && self.fov_y < std::f64::consts::PI) {
            return bad("the field of view must be in (0, π)");
        }
        let Some(back) = self.direction.try_normalize() else {
            return bad("the direction must be finite and non-zero");
        };
        let Some(right) = (-back).cross(self.up).try_normalize() else {
            return bad("the up vector must be finite and not parallel to the direction");
        };
        Ok((back, right, right.cross(-back)))
    }
}

/// One mesh of a picture, with a colour per vertex slot (`None`: clay).
#[derive(Clone, Copy, Debug)]
pub struct Panel<'a> {
    /// The mesh.
    pub mesh: &'a Mesh,
    /// A colour (linear RGB in `[0, 1]`) per [`Mesh::vertex_index`], at least
    /// [`Mesh::vertex_slots`] of them.
    pub colors: Option<&'a [DVec3]>,
}

impl<'a> Panel<'a> {
    /// A panel of `mesh` in clay.
    pub fn new(mesh: &'a Mesh) -> Self {
        Self { mesh, colors: None }
    }
    /// A panel of `mesh` with colours per vertex slot.
    pub fn with_colors(mesh: &'a Mesh, colors: &'a [DVec3]) -> Self {
        Self {
            mesh,
            colors: Some(colors),
        }
    }
}

/// An RGB picture, 8 bits per channel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Row-major RGB bytes, top row first.
    pub rgb: Vec<u8>,
}

impl Image {
    /// Writes the image as a PNG file.
    ///
    /// # Errors
    /// [`RenderError::Write`] naming the file.
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        let fail = |message: String| RenderError::Write {
            path: path.to_owned(),
            message,
        };
        let file = std::fs::File::create(path).map_err(|e| fail(e.to_string()))?;
        let mut encoder = png::Encoder::new(
            std::io::BufWriter::new(file),
            self.width as u32,
            self.height as u32,
        );
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(|e| fail(e.to_string()))?;
        writer
            .write_image_data(&self.rgb)
            .map_err(|e| fail(e.to_string()))?;
        writer.finish().map_err(|e| fail(e.to_string()))
    }

    /// Places images side by side, top-aligned, on white (rows an image lacks bytes for
    /// stay white).
    ///
    /// # Errors
    /// [`RenderError::Size`] when the result would be wider or higher than [`MAX_SIDE`]
    /// or larger than [`MAX_PIXELS`] (checked before allocating).
    pub fn side_by_side(images: &[&Image]) -> Result<Image> {
        let height = images.iter().map(|i| i.height).max().unwrap_or(0);
        let width = images
            .iter()
            .try_fold(0usize, |w, i| w.checked_add(i.width))
            .unwrap_or(usize::MAX);
        if width > MAX_SIDE || height > MAX_SIDE || width * height > MAX_PIXELS {
            return Err(RenderError::Size { width, height });
        }
        let mut rgb = vec![255u8; width * height * 3];
        let mut x0 = 0;
        for image in images {
            for y in 0..image.height {
                let row = y * image.width * 3..(y + 1) * image.width * 3;
                let Some(src) = image.rgb.get(row) else { break };
                let dst = (y * width + x0) * 3;
                rgb[dst..dst + src.len()].copy_from_slice(src);
            }
            x0 += image.width;
        }
        Ok(Image { width, height, rgb })
    }
}

/// The union of the bounding boxes of `meshes` (`None` when none has a vertex).
pub fn union_bounds<'a>(meshes: impl IntoIterator<Item = &'a Mesh>) -> Option<(DVec3, DVec3)> {
    meshes
        .into_iter()
        .filter_map(Mesh::bounding_box)
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

/// Renders the panels side by side, each `width × height`, all seen by `camera` and
/// framed on `frame` (default: the union of the panels' bounding boxes).
///
/// # Errors
/// [`RenderError::Size`] for a panel size out of range or more than [`MAX_PIXELS`]
/// pixels in all (checked before allocating);
/// [`RenderError::Frame`] without panels, vertices or a finite frame;
/// [`RenderError::Camera`] for a degenerate camera; [`RenderError::Colors`] for a
/// colour array shorter than its mesh's vertex slots.
pub fn render_side_by_side(
    panels: &[Panel<'_>],
    camera: &Camera,
    frame: Option<(DVec3, DVec3)>,
    width: usize,
    height: usize,
) -> Result<Image> {
    check_size(width, height)?;
    if panels.is_empty() {
        return Err(RenderError::Frame("no panel".into()));
    }
    check_size(width.saturating_mul(panels.len()), height)?;
    let frame = match frame {
        Some(f) => f,
        None => union_bounds(panels.iter().map(|p| p.mesh))
            .ok_or_else(|| RenderError::Frame("the meshes have no vertex".into()))?,
    };
    let images = panels
        .iter()
        .enumerate()
        .map(|(i, p)| render_panel(i, p, camera, frame, width, height))
        .collect::<Result<Vec<_>>>()?;
    Image::side_by_side(&images.iter().collect::<Vec<_>>())
}

/// Renders one mesh (see [`render_side_by_side`]).
///
/// # Errors
/// As [`render_side_by_side`].
pub fn render(
    panel: Panel<'_>,
    camera: &Camera,
    frame: Option<(DVec3, DVec3)>,
    width: usize,
    height: usize,
) -> Result<Image> {
    render_side_by_side(&[panel], camera, frame, width, height)
}

/// Colours that show where `after` moved away from `before` (same vertex slots): clay
/// where a vertex kept its place, shading to orange as its displacement reaches `full`
/// (a distance). Slots missing from either mesh are clay.
pub fn displacement_colors(before: &Mesh, after: &Mesh, full: f64) -> Vec<DVec3> {
    let hot = DVec3::new(0.95, 0.45, 0.15);
    (0..after.vertex_slots())
        .map(|i| match (before.positions().get(i), after.vertex_at(i)) {
            (Some(&p), Some(v)) if full > 0.0 => {
                let t = (after.position(v).distance(p) / full).min(1.0);
                if t.is_finite() {
                    CLAY.lerp(hot, t)
                } else {
                    CLAY
                }
            }
            _ => CLAY,
        })
        .collect()
}

const CLAY: DVec3 = DVec3::new(0.78, 0.74, 0.68);

fn check_size(width: usize, height: usize) -> Result<()> {
    if (1..=MAX_SIDE).contains(&width)
        && (1..=MAX_SIDE).contains(&height)
        && width * height <= MAX_PIXELS
    {
        Ok(())
    } else {
        Err(RenderError::Size { width, height })
    }
}

fn render_panel(
    index: usize,
    panel: &Panel<'_>,
    camera: &Camera,
    (lo, hi): (DVec3, DVec3),
    width: usize,
    height: usize,
) -> Result<Image> {
    let mesh = panel.mesh;
    if let Some(c) = panel.colors {
        if c.len() < mesh.vertex_slots() {
            return Err(RenderError::Colors {
                panel: index,
                expected: mesh.vertex_slots(),
                found: c.len(),
            });
        }
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(RenderError::Frame(format!(
            "the frame {lo} – {hi} is not finite"
        )));
    }
    let (back, right, up) = camera.basis()?;
    let center = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-12);
    let distance = radius / (0.5 * camera.fov_y).tan() * 0.8;
    let eye = center + back * distance;
    let to_camera = DMat3::from_cols(right, up, back).transpose();
    let focal = 0.5 * height as f64 / (0.5 * camera.fov_y).tan();
    let (w, h) = (width as f64, height as f64);
    let project = |p: DVec3| -> DVec3 {
        let q = to_camera * (p - eye);
        let depth = -q.z;
        DVec3::new(
            0.5 * w + focal * q.x / depth,
            0.5 * h - focal * q.y / depth,
            depth,
        )
    };

    let normals = mesh.vertex_normals();
    let light = (back + 0.6 * up + 0.3 * right).normalize();
    let shade = |i: usize| -> DVec3 {
        let base = panel.colors.map_or(CLAY, |c| c[i]);
        base * (0.25 + 0.75 * normals[i].dot(light).abs())
    };

    // The faces rasterised in slot order by runs, one run per core, each into its own
    // buffers; a vertex is projected and shaded by each face that has it (a table of
    // every vertex's would cost as much memory as the mesh's positions).
    let corner = |i: usize| Corner {
        at: project(mesh.positions()[i]),
        color: shade(i),
    };
    let (depth, color) = rasterize(mesh, &corner, width, height, rayon::current_num_threads());
    let mut rgb = Vec::with_capacity(width * height * 3);
    for (k, c) in color.iter().enumerate() {
        let c = if depth[k].is_finite() {
            *c
        } else {
            // Background: a soft vertical gradient.
            let t = (k / width) as f64 / h;
            DVec3::new(0.93, 0.94, 0.96) * (1.0 - 0.15 * t)
        };
        rgb.extend(
            c.to_array()
                .map(|x| (x.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8),
        );
    }
    Ok(Image { width, height, rgb })
}

/// A vertex on the screen: pixel coordinates and depth, and its shaded colour.
#[derive(Clone, Copy, Debug, Default)]
struct Corner {
    at: DVec3,
    color: DVec3,
}

/// The depth and colour buffers of `mesh`'s faces drawn with `corner` (by vertex slot),
/// in face slot order: where faces cover a pixel at the same depth the first one stays.
/// The faces are split into `runs` runs of consecutive slots drawn on all cores, each
/// into its own buffers, merged in run order with the same rule, so the pictures are
/// those of one run, bit for bit.
fn rasterize(
    mesh: &Mesh,
    corner: &(dyn Fn(usize) -> Corner + Sync),
    width: usize,
    height: usize,
    runs: usize,
) -> (Vec<f64>, Vec<DVec3>) {
    let slots = mesh.face_slots();
    let per_run = slots.div_ceil(runs.max(1)).max(1);
    let mut drawn: Vec<(Vec<f64>, Vec<DVec3>)> = (0..slots.div_ceil(per_run).max(1))
        .into_par_iter()
        .map(|run| {
            let mut depth = vec![f64::INFINITY; width * height];
            let mut color = vec![DVec3::ZERO; width * height];
            let end = ((run + 1) * per_run).min(slots);
            for f in (run * per_run..end).filter_map(|i| mesh.face_at(i)) {
                let c = mesh.triangle(f).map(|v| corner(mesh.vertex_index(v)));
                draw_triangle(c, width, height, &mut depth, &mut color);
            }
            (depth, color)
        })
        .collect();
    let (mut depth, mut color) = drawn.remove(0);
    for (d, c) in drawn {
        for k in 0..depth.len() {
            if d[k] < depth[k] {
                depth[k] = d[k];
                color[k] = c[k];
            }
        }
    }
    (depth, color)
}

/// Draws one triangle into the buffers: a pixel whose centre it covers takes its
/// interpolated colour when it is nearer than what the pixel holds.
#[inline]
fn draw_triangle(
    c: [Corner; 3],
    width: usize,
    height: usize,
    depth: &mut [f64],
    color: &mut [DVec3],
) {
    let s = c.map(|c| c.at);
    if s.iter().any(|p| !p.is_finite() || p.z <= 1e-9) {
        return;
    }
    let area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
    if area.abs() < 1e-12 {
        return;
    }
    let (x0, x1) = span(s.map(|p| p.x), width);
    let (y0, y1) = span(s.map(|p| p.y), height);
    for y in y0..y1 {
        for x in x0..x1 {
            let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
            let w0 = ((s[1].x - px) * (s[2].y - py) - (s[2].x - px) * (s[1].y - py)) / area;
            let w1 = ((s[2].x - px) * (s[0].y - py) - (s[0].x - px) * (s[2].y - py)) / area;
            let w2 = 1.0 - w0 - w1;
            if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                continue;
            }
            let z = w0 * s[0].z + w1 * s[1].z + w2 * s[2].z;
            let k = y * width + x;
            if z < depth[k] {
                depth[k] = z;
                color[k] = w0 * c[0].color + w1 * c[1].color + w2 * c[2].color;
            }
        }
    }
}

/// The pixel range `[first, end)` covered by coordinates `v` on an axis of `n` pixels.
fn span(v: [f64; 3], n: usize) -> (usize, usize) {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min).floor();
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max).ceil();
    let first = lo.clamp(0.0, n as f64) as usize;
    let end = (hi + 1.0).clamp(0.0, n as f64) as usize;
    (first, end.max(first))
}

#[cfg(test)]
mod tests {
    use super::*;
    use halfedge::generators;

    fn covered(image: &Image) -> usize {
        // The background is a grey-blue gradient, the mesh is clay (red > blue).
        image.rgb.chunks(3).filter(|p| p[0] > p[2]).count()
    }

    /// Drawn in runs on several cores, the buffers are those of one run in face order,
    /// bit for bit, also where faces tie in depth: two copies of a sphere in one mesh,
    /// every face covering the pixels of its copy at exactly the same depth.
    #[test]
    fn faces_drawn_in_runs_give_the_picture_of_one_run() {
        let sphere = generators::icosphere(3);
        let mesh = generators::disjoint_union(&[&sphere, &sphere]).unwrap();
        let (w, h) = (96, 72);
        let corners: Vec<Corner> = mesh
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| Corner {
                at: DVec3::new(40.0 * p.x + 48.0, 40.0 * p.y + 36.0, 3.0 + p.z),
                // The two copies in different colours: a tie shows which one stayed.
                color: if i < sphere.vertex_slots() {
                    DVec3::X
                } else {
                    DVec3::Y
                },
            })
            .collect();
        let bits = |(d, c): (Vec<f64>, Vec<DVec3>)| -> Vec<u64> {
            d.iter()
                .map(|x| x.to_bits())
                .chain(c.iter().flat_map(|c| c.to_array().map(f64::to_bits)))
                .collect()
        };
        let corner = |i: usize| corners[i];
        let one = bits(rasterize(&mesh, &corner, w, h, 1));
        // The first copy's faces come first: it is what the picture shows.
        let (_, color) = rasterize(&mesh, &corner, w, h, 1);
        assert!(color.contains(&DVec3::X));
        assert!(!color.iter().any(|&c| c.y > 0.0));
        for runs in [2, 3, 7, 1000] {
            assert!(
                bits(rasterize(&mesh, &corner, w, h, runs)) == one,
                "{runs} runs"
            );
        }
    }

    /// Hostile sizes, cameras, frames and colours (issue 14): typed errors, checked
    /// before allocating; no panic.
    #[test]
    fn hostile_arguments_are_refused_before_allocating() {
        let mesh = generators::icosphere(1);
        let camera = Camera::default();
        // 4096 × 4096 first: were the pixel cap gone, it would render (about 600 MB)
        // and fail here, before the larger sizes are tried.
        let sizes = [
            (4096, 4096),
            (0, 10),
            (10, 0),
            (MAX_SIDE, MAX_SIDE),
            (MAX_SIDE + 1, 1),
            (usize::MAX, usize::MAX),
        ];
        for (w, h) in sizes {
            let r = render(Panel::new(&mesh), &camera, None, w, h);
            assert!(matches!(r, Err(RenderError::Size { .. })), "{w}×{h}: {r:?}");
        }
        let panels = vec![Panel::new(&mesh); 3000];
        let r = render_side_by_side(&panels, &camera, None, 64, 64);
        assert!(matches!(r, Err(RenderError::Size { .. })), "{r:?}");
        let big = Image {
            width: MAX_SIDE / 2,
            height: MAX_SIDE,
            rgb: Vec::new(),
        };
        let r = Image::side_by_side(&[&big, &big]);
        assert!(matches!(r, Err(RenderError::Size { .. })), "{r:?}");
        let bad = [f64::NAN, f64::INFINITY, 0.0, -1.0, 1e308, 4.0];
        for x in bad {
            let cam = Camera {
                direction: DVec3::new(x, 0.0, 1.0),
                up: DVec3::new(0.0, x, 0.0),
                fov_y: x,
            };
            let _ = render(Panel::new(&mesh), &cam, None, 8, 8);
            let frame = Some((DVec3::splat(-x), DVec3::splat(x)));
            let _ = render(Panel::new(&mesh), &camera, frame, 8, 8);
        }
        let nan = vec![DVec3::NAN; mesh.vertex_slots()];
        render(Panel::with_colors(&mesh, &nan), &camera, None, 8, 8).unwrap();
        let short = vec![DVec3::ONE; 2];
        let r = render(Panel::with_colors(&mesh, &short), &camera, None, 8, 8);
        assert!(matches!(r, Err(RenderError::Colors { .. })), "{r:?}");
        let empty = Mesh::new();
        let r = render(Panel::new(&empty), &camera, None, 8, 8);
        assert!(matches!(r, Err(RenderError::Frame(_))), "{r:?}");
        let _ = displacement_colors(&empty, &mesh, f64::NAN);
        let _ = displacement_colors(&mesh, &empty, 0.0);
    }

    #[test]
    fn the_frame_holds_both_meshes_and_the_panels_compare() {
        let before = generators::icosphere(3);
        let mut after = before.clone();
        for p in after.positions_mut() {
            p.x *= 3.0;
        }
        let camera = Camera::along(DVec3::Z, DVec3::Y);
        let image = render_side_by_side(
            &[Panel::new(&before), Panel::new(&after)],
            &camera,
            None,
            200,
            150,
        )
        .unwrap();
        assert_eq!((image.width, image.height), (400, 150));
        let half = |x0: usize| Image {
            width: 200,
            height: 150,
            rgb: (0..150)
                .flat_map(|y| image.rgb[(y * 400 + x0) * 3..(y * 400 + x0 + 200) * 3].to_vec())
                .collect(),
        };
        let (a, b) = (half(0), half(200));
        // The stretched mesh covers about three times the pixels of the sphere, and
        // reaches neither side edge of its panel: the frame holds it.
        let ratio = covered(&b) as f64 / covered(&a) as f64;
        assert!((2.5..3.5).contains(&ratio), "{ratio}");
        for y in 0..150 {
            for x in [0, 199] {
                let p = &b.rgb[(y * 200 + x) * 3..][..3];
                assert!(
                    p[0] <= p[2],
                    "the stretched mesh touches the edge at {x}, {y}"
                );
            }
        }
        // Framed on the sphere alone, the stretched mesh leaves the frame.
        let tight = render(Panel::new(&after), &camera, before.bounding_box(), 200, 150).unwrap();
        let edge = (0..150).any(|y| {
            let p = &tight.rgb[(y * 200) * 3..][..3];
            p[0] > p[2]
        });
        assert!(
            edge,
            "framed on the sphere, the stretched mesh should cross the edge"
        );
    }

    #[test]
    fn displacement_colors_mark_moved_vertices() {
        let before = generators::icosphere(2);
        let mut after = before.clone();
        after.positions_mut()[5].x += 1.0;
        let colors = displacement_colors(&before, &after, 0.5);
        assert_eq!(colors.len(), after.vertex_slots());
        assert_eq!(colors[0], CLAY);
        assert!(colors[5].x > CLAY.x && colors[5].z < CLAY.z);
        let image = render(
            Panel::with_colors(&after, &colors),
            &Camera::default(),
            None,
            64,
            48,
        )
        .unwrap();
        assert!(covered(&image) > 100);
    }

    #[test]
    fn bad_arguments_are_typed_errors() {
        let mesh = generators::icosphere(1);
        let camera = Camera::default();
        let panel = Panel::new(&mesh);
        assert!(matches!(
            render(panel, &camera, None, 0, 10),
            Err(RenderError::Size { .. })
        ));
        assert!(matches!(
            render(panel, &camera, None, 10, MAX_SIDE + 1),
            Err(RenderError::Size { .. })
        ));
        assert!(matches!(
            render_side_by_side(&[panel; 3], &camera, None, MAX_SIDE, 10),
            Err(RenderError::Size { .. })
        ));
        assert!(matches!(
            render_side_by_side(&[], &camera, None, 10, 10),
            Err(RenderError::Frame(_))
        ));
        let empty = Mesh::new();
        assert!(matches!(
            render(Panel::new(&empty), &camera, None, 10, 10),
            Err(RenderError::Frame(_))
        ));
        assert!(matches!(
            render(panel, &camera, Some((DVec3::NAN, DVec3::ONE)), 10, 10),
            Err(RenderError::Frame(_))
        ));
        for bad in [
            Camera::along(DVec3::ZERO, DVec3::Y),
            Camera::along(DVec3::Y, DVec3::Y),
            Camera {
                fov_y: 0.0,
                ..Camera::default()
            },
            Camera {
                up: DVec3::NAN,
                ..Camera::default()
            },
        ] {
            assert!(matches!(
                render(panel, &bad, None, 10, 10),
                Err(RenderError::Camera(_))
            ));
        }
        let short = [DVec3::ONE; 3];
        assert!(matches!(
            render(Panel::with_colors(&mesh, &short), &camera, None, 10, 10),
            Err(RenderError::Colors {
                expected: 42,
                found: 3,
                ..
            })
        ));
        // A mesh with a non-finite position renders (that face is skipped).
        let mut broken = mesh.clone();
        broken.positions_mut()[0] = DVec3::new(f64::NAN, 0.0, 0.0);
        let frame = mesh.bounding_box();
        assert!(render(Panel::new(&broken), &camera, frame, 20, 20).is_ok());
        let dir = std::env::temp_dir()
            .join("multires-no-such-dir")
            .join("x.png");
        let image = render(panel, &camera, None, 4, 4).unwrap();
        assert!(matches!(
            image.save_png(&dir),
            Err(RenderError::Write { .. })
        ));
    }
}
