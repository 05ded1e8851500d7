//! The orbit camera, in `f64` like the kernel: orbit / pan / zoom, framing, rays for
//! picking, projection of points to the screen, and the conversion to a `three-d`
//! (cgmath, `f32`) camera at the rendering boundary.
//!
//! Pixel coordinates follow `three-d`: physical pixels, origin at the **bottom-left**
//! corner of the window. A [`Viewport`] is the part of the window the 3D view occupies
//! (the window minus the side panel and the status bar).

use glam::DVec3;

/// The part of the window (physical pixels, origin bottom-left) where the scene is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    /// Left edge.
    pub x: f64,
    /// Bottom edge.
    pub y: f64,
    /// Width (> 0).
    pub width: f64,
    /// Height (> 0).
    pub height: f64,
}

impl Viewport {
    /// Width over height.
    pub fn aspect(&self) -> f64 {
        self.width / self.height.max(1.0)
    }
    /// True when the pixel `(px, py)` lies inside.
    pub fn contains(&self, px: f64, py: f64) -> bool {
        px >= self.x && px < self.x + self.width && py >= self.y && py < self.y + self.height
    }
    /// The viewport as `three-d` wants it.
    pub fn to_three_d(self) -> three_d::Viewport {
        three_d::Viewport {
            x: self.x.round() as i32,
            y: self.y.round() as i32,
            width: self.width.round().max(1.0) as u32,
            height: self.height.round().max(1.0) as u32,
        }
    }
}

/// Which world axis points up on the screen while orbiting.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// +Y up (OBJ convention of most scans, e.g. the Stanford bunny).
    Y,
    /// +Z up (CAD convention).
    Z,
}

impl UpAxis {
    /// `(side, front, up)` world axes: yaw 0 and pitch 0 look along `-front`.
    fn frame(self) -> (DVec3, DVec3, DVec3) {
        match self {
            UpAxis::Y => (DVec3::X, DVec3::Z, DVec3::Y),
            UpAxis::Z => (DVec3::X, DVec3::NEG_Y, DVec3::Z),
        }
    }
}

/// A ray `origin + t·direction` with a unit direction: the library's picking ray.
pub use halfedge::bvh::Ray;

/// An orbit camera around a target point, with a fixed up axis (no roll).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point the camera looks at and orbits around.
    pub target: DVec3,
    /// Distance from the eye to the target.
    pub distance: f64,
    /// Rotation about the up axis, radians.
    pub yaw: f64,
    /// Elevation above the horizontal plane, radians, within ±89°.
    pub pitch: f64,
    /// The world axis kept vertical on screen.
    pub up_axis: UpAxis,
    /// Vertical field of view, radians.
    pub fov_y: f64,
    /// Radius of the scene's bounding sphere, used for the clipping planes.
    pub scene_radius: f64,
}

/// Default yaw and pitch of a freshly framed view (a three-quarter view from the front).
const DEFAULT_YAW: f64 = 0.35;
const DEFAULT_PITCH: f64 = 0.25;
const MAX_PITCH: f64 = 89.0 * std::f64::consts::PI / 180.0;

impl Default for OrbitCamera {
    fn default() -> Self {
        Self {
            target: DVec3::ZERO,
            distance: 3.0,
            yaw: DEFAULT_YAW,
            pitch: DEFAULT_PITCH,
            up_axis: UpAxis::Y,
            fov_y: 35f64.to_radians(),
            scene_radius: 1.0,
        }
    }
}

impl OrbitCamera {
    /// A camera that frames the box `(lo, hi)` from the default direction.
    pub fn framing(lo: DVec3, hi: DVec3, up_axis: UpAxis) -> Self {
        let mut camera = Self {
            up_axis,
            ..Self::default()
        };
        camera.frame(lo, hi);
        camera
    }

    /// Re-targets on the centre of the box `(lo, hi)` and backs off until its bounding
    /// sphere fits the narrower field of view (with a small margin); keeps the direction.
    pub fn frame(&mut self, lo: DVec3, hi: DVec3) {
        let radius = (0.5 * (hi - lo).length()).max(1e-9);
        self.target = 0.5 * (lo + hi);
        self.scene_radius = radius;
        self.distance = 1.08 * radius / (0.5 * self.fov_y).sin();
    }

    /// Frames the box and resets the direction to the default three-quarter view.
    pub fn reset(&mut self, lo: DVec3, hi: DVec3) {
        self.yaw = DEFAULT_YAW;
        self.pitch = DEFAULT_PITCH;
        self.frame(lo, hi);
    }

    /// Unit vector from the target to the eye.
    fn eye_direction(&self) -> DVec3 {
        let (side, front, up) = self.up_axis.frame();
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        cp * (sy * side + cy * front) + sp * up
    }

    /// Eye position.
    pub fn eye(&self) -> DVec3 {
        self.target + self.distance * self.eye_direction()
    }

    /// Unit viewing direction (from the eye towards the target).
    pub fn forward(&self) -> DVec3 {
        -self.eye_direction()
    }

    /// `(right, up, forward)`: the camera's orthonormal frame.
    pub fn basis(&self) -> (DVec3, DVec3, DVec3) {
        let forward = self.forward();
        let world_up = self.up_axis.frame().2;
        let right = forward.cross(world_up).normalize_or_zero();
        let right = if right == DVec3::ZERO {
            self.up_axis.frame().0
        } else {
            right
        };
        (right, right.cross(forward), forward)
    }

    /// Orbits by the given yaw and pitch increments (radians); pitch stays within ±89°.
    pub fn orbit(&mut self, d_yaw: f64, d_pitch: f64) {
        self.yaw = (self.yaw + d_yaw).rem_euclid(std::f64::consts::TAU);
        self.pitch = (self.pitch + d_pitch).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Moves target and eye together so that the scene follows a mouse motion of
    /// `(dx, dy)` pixels (screen axes: x right, y **up**) in a viewport `height` pixels tall.
    pub fn pan(&mut self, dx: f64, dy: f64, height: f64) {
        let (right, up, _) = self.basis();
        let world_per_pixel = 2.0 * self.distance * (0.5 * self.fov_y).tan() / height.max(1.0);
        self.target -= world_per_pixel * (dx * right + dy * up);
    }

    /// Multiplies the distance to the target by `factor` (< 1 zooms in), keeping it within
    /// sensible bounds relative to the scene.
    pub fn zoom(&mut self, factor: f64) {
        let min = 1e-3 * self.scene_radius;
        let max = 100.0 * self.scene_radius / (0.5 * self.fov_y).sin();
        self.distance = (self.distance * factor).clamp(min, max);
    }

    /// Near and far clipping distances covering the scene sphere.
    pub fn clip_planes(&self) -> (f64, f64) {
        let far = self.distance + 3.0 * self.scene_radius;
        let near = (self.distance - 1.5 * self.scene_radius).max(far * 2e-4);
        (near, far)
    }

    /// The ray through the pixel `(px, py)` (physical pixels, origin bottom-left of the
    /// window) of a scene drawn in `viewport`.
    pub fn ray(&self, px: f64, py: f64, viewport: &Viewport) -> Ray {
        let (right, up, forward) = self.basis();
        let sx = 2.0 * (px - viewport.x) / viewport.width.max(1.0) - 1.0;
        let sy = 2.0 * (py - viewport.y) / viewport.height.max(1.0) - 1.0;
        let t = (0.5 * self.fov_y).tan();
        let direction = (forward + sx * t * viewport.aspect() * right + sy * t * up).normalize();
        Ray {
            origin: self.eye(),
            direction,
        }
    }

    /// The pixel (origin bottom-left of the window) where `p` appears, and its depth along
    /// the view direction; `None` when `p` is behind the eye.
    pub fn project(&self, p: DVec3, viewport: &Viewport) -> Option<(f64, f64, f64)> {
        let (right, up, forward) = self.basis();
        let d = p - self.eye();
        let depth = d.dot(forward);
        if depth <= 0.0 {
            return None;
        }
        let t = (0.5 * self.fov_y).tan();
        let sx = d.dot(right) / (depth * t * viewport.aspect());
        let sy = d.dot(up) / (depth * t);
        Some((
            viewport.x + 0.5 * (sx + 1.0) * viewport.width,
            viewport.y + 0.5 * (sy + 1.0) * viewport.height,
            depth,
        ))
    }

    /// The `three-d` camera for this view drawn in `viewport`, in render space: world
    /// coordinates minus `origin` (the renderer uploads positions that way to keep `f32`
    /// precise far from the world origin).
    pub fn to_three_d(&self, viewport: &Viewport, origin: DVec3) -> three_d::Camera {
        let (near, far) = self.clip_planes();
        let (_, up, _) = self.basis();
        three_d::Camera::new_perspective(
            viewport.to_three_d(),
            to_cg(self.eye() - origin),
            to_cg(self.target - origin),
            to_cg(up),
            three_d::radians(self.fov_y as f32),
            near as f32,
            far as f32,
        )
    }
}

/// glam `DVec3` (kernel, `f64`) to cgmath `Vector3<f32>` (`three-d`).
#[inline]
pub fn to_cg(v: DVec3) -> three_d::Vec3 {
    three_d::vec3(v.x as f32, v.y as f32, v.z as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn viewport() -> Viewport {
        Viewport {
            x: 300.0,
            y: 30.0,
            width: 800.0,
            height: 600.0,
        }
    }

    #[test]
    fn framing_puts_the_box_in_view() {
        let cam = OrbitCamera::framing(DVec3::splat(-1.0), DVec3::splat(1.0), UpAxis::Y);
        assert!((cam.target - DVec3::ZERO).length() < 1e-12);
        let vp = viewport();
        for corner in [
            DVec3::splat(-1.0),
            DVec3::splat(1.0),
            DVec3::new(1.0, -1.0, 1.0),
        ] {
            let (px, py, _) = cam.project(corner, &vp).unwrap();
            assert!(vp.contains(px, py), "{corner} projects outside: {px} {py}");
        }
    }

    #[test]
    fn ray_and_project_are_inverse() {
        let mut cam = OrbitCamera::framing(DVec3::ZERO, DVec3::ONE, UpAxis::Z);
        cam.orbit(0.7, -0.3);
        let vp = viewport();
        for &(px, py) in &[(350.0, 60.0), (700.0, 330.0), (1090.0, 620.0)] {
            let ray = cam.ray(px, py, &vp);
            let p = ray.at(2.5);
            let (qx, qy, depth) = cam.project(p, &vp).unwrap();
            assert!((qx - px).abs() < 1e-9 && (qy - py).abs() < 1e-9);
            assert!(depth > 0.0);
        }
        // The centre pixel looks at the target.
        let ray = cam.ray(vp.x + 0.5 * vp.width, vp.y + 0.5 * vp.height, &vp);
        assert!(ray.direction.dot(cam.forward()) > 1.0 - 1e-12);
    }

    #[test]
    fn basis_is_orthonormal_and_keeps_up() {
        let mut cam = OrbitCamera::default();
        for i in 0..20 {
            cam.orbit(0.4, if i % 2 == 0 { 0.9 } else { -0.5 });
            let (r, u, f) = cam.basis();
            assert!((r.length() - 1.0).abs() < 1e-12 && (u.length() - 1.0).abs() < 1e-12);
            assert!(r.dot(u).abs() < 1e-12 && r.dot(f).abs() < 1e-12 && u.dot(f).abs() < 1e-12);
            assert!(r.dot(DVec3::Y).abs() < 1e-12, "no roll");
            assert!(cam.pitch.abs() <= MAX_PITCH);
        }
    }

    #[test]
    fn pan_moves_the_scene_with_the_mouse() {
        let mut cam = OrbitCamera::framing(DVec3::splat(-1.0), DVec3::splat(1.0), UpAxis::Y);
        let vp = viewport();
        let (x0, y0, _) = cam.project(DVec3::ZERO, &vp).unwrap();
        cam.pan(25.0, -40.0, vp.height);
        let (x1, y1, _) = cam.project(DVec3::ZERO, &vp).unwrap();
        assert!((x1 - x0 - 25.0).abs() < 1e-6 && (y1 - y0 + 40.0).abs() < 1e-6);
    }

    #[test]
    fn plane_intersection() {
        let ray = Ray {
            origin: DVec3::new(0.0, 0.0, 5.0),
            direction: DVec3::NEG_Z,
        };
        let p = ray
            .intersect_plane(DVec3::new(0.0, 0.0, 1.0), DVec3::Z)
            .unwrap();
        assert!((p - DVec3::new(0.0, 0.0, 1.0)).length() < 1e-12);
        assert!(ray
            .intersect_plane(DVec3::new(0.0, 0.0, 9.0), DVec3::Z)
            .is_none());
        assert!(ray.intersect_plane(DVec3::ZERO, DVec3::X).is_none());
    }
}
