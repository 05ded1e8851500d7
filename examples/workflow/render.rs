//! A small software renderer for the workflow's before/after pictures: perspective
//! projection, z-buffer, Lambert shading with per-vertex colours, PNG output. No GPU or
//! display needed, so the pictures come out the same on a headless CI machine.

use std::path::Path;

use glam::{DMat3, DVec3};
use halfedge::Mesh;

/// How to look at the mesh.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Unit direction from the mesh centre towards the eye.
    pub eye_direction: DVec3,
    /// Up vector (need not be orthogonal to the eye direction).
    pub up: DVec3,
    /// Vertical field of view in radians.
    pub fov_y: f64,
}

impl Default for View {
    fn default() -> Self {
        Self {
            eye_direction: DVec3::new(0.35, 0.3, 1.0).normalize(),
            up: DVec3::Y,
            fov_y: 0.6,
        }
    }
}

/// An RGB image.
pub struct Image {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Row-major RGB bytes.
    pub rgb: Vec<u8>,
}

impl Image {
    /// Writes the image as PNG.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        let file = std::io::BufWriter::new(std::fs::File::create(path)?);
        let mut encoder = png::Encoder::new(file, self.width as u32, self.height as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
        writer
            .write_image_data(&self.rgb)
            .map_err(std::io::Error::other)?;
        Ok(())
    }

    /// Places images side by side.
    pub fn side_by_side(images: &[&Image]) -> Image {
        let height = images.iter().map(|i| i.height).max().unwrap_or(0);
        let width: usize = images.iter().map(|i| i.width).sum();
        let mut rgb = vec![255u8; width * height * 3];
        let mut x0 = 0;
        for image in images {
            for y in 0..image.height {
                let src = &image.rgb[y * image.width * 3..(y + 1) * image.width * 3];
                let dst = (y * width + x0) * 3;
                rgb[dst..dst + src.len()].copy_from_slice(src);
            }
            x0 += image.width;
        }
        Image { width, height, rgb }
    }
}

/// Renders `mesh` seen from `view`, framed on `frame` (min, max of the box to fit), with a
/// colour per vertex slot (`None`: a neutral clay colour).
pub fn render(
    mesh: &Mesh,
    view: View,
    frame: (DVec3, DVec3),
    colors: Option<&[DVec3]>,
    width: usize,
    height: usize,
) -> Image {
    let (lo, hi) = frame;
    let center = 0.5 * (lo + hi);
    let radius = 0.5 * (hi - lo).length().max(1e-12);
    let distance = radius / (0.5 * view.fov_y).tan() * 0.8;
    let eye = center + view.eye_direction * distance;
    let forward = (center - eye).normalize();
    let right = forward.cross(view.up).normalize();
    let up = right.cross(forward);
    let to_camera = DMat3::from_cols(right, up, -forward).transpose();
    let focal = 0.5 * height as f64 / (0.5 * view.fov_y).tan();
    let project = |p: DVec3| -> DVec3 {
        let q = to_camera * (p - eye);
        let depth = -q.z;
        DVec3::new(
            0.5 * width as f64 + focal * q.x / depth,
            0.5 * height as f64 - focal * q.y / depth,
            depth,
        )
    };

    let normals = mesh.vertex_normals();
    let light = (view.eye_direction + 0.6 * view.up + 0.3 * right).normalize();
    let shade = |i: usize| -> DVec3 {
        let base = colors.map_or(DVec3::new(0.78, 0.74, 0.68), |c| c[i]);
        let n = normals[i];
        let lambert = n.dot(light).abs();
        base * (0.25 + 0.75 * lambert)
    };

    let mut depth = vec![f64::INFINITY; width * height];
    let mut color = vec![DVec3::ZERO; width * height];
    for f in mesh.faces() {
        let vs = mesh.triangle(f);
        let idx = vs.map(|v| mesh.vertex_index(v));
        let s = idx.map(|i| project(mesh.positions()[i]));
        if s.iter().any(|p| p.z <= 1e-9) {
            continue;
        }
        let c = idx.map(shade);
        let area = (s[1].x - s[0].x) * (s[2].y - s[0].y) - (s[2].x - s[0].x) * (s[1].y - s[0].y);
        if area.abs() < 1e-12 {
            continue;
        }
        let xmin = s
            .iter()
            .map(|p| p.x)
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0) as usize;
        let xmax = s
            .iter()
            .map(|p| p.x)
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil()
            .min(width as f64 - 1.0);
        let ymin = s
            .iter()
            .map(|p| p.y)
            .fold(f64::INFINITY, f64::min)
            .floor()
            .max(0.0) as usize;
        let ymax = s
            .iter()
            .map(|p| p.y)
            .fold(f64::NEG_INFINITY, f64::max)
            .ceil()
            .min(height as f64 - 1.0);
        if xmax < 0.0 || ymax < 0.0 {
            continue;
        }
        for y in ymin..=ymax as usize {
            for x in xmin..=xmax as usize {
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
                    color[k] = w0 * c[0] + w1 * c[1] + w2 * c[2];
                }
            }
        }
    }
    let mut rgb = Vec::with_capacity(width * height * 3);
    for (k, c) in color.iter().enumerate() {
        let c = if depth[k].is_finite() {
            *c
        } else {
            // Background: a soft vertical gradient.
            let t = (k / width) as f64 / height as f64;
            DVec3::new(0.93, 0.94, 0.96) * (1.0 - 0.15 * t)
        };
        rgb.extend(
            c.to_array()
                .map(|x| (x.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8),
        );
    }
    Image { width, height, rgb }
}
