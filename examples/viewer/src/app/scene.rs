//! The scene and its rendering state: the orbit camera, the GPU side
//! ([`SceneRenderer`]) and its settings, and the picking structure kept current with the
//! document's mesh.

use halfedge::Mesh;

use crate::camera::{OrbitCamera, Ray};
use crate::pick::Bvh;
use crate::render::{RenderSettings, SceneRenderer};
use crate::tools::{Pick, ViewInfo};

/// The camera, the renderer and its settings, and the picking structure.
pub(super) struct Scene {
    /// The orbit camera.
    pub(super) camera: OrbitCamera,
    /// The GPU side.
    pub(super) renderer: SceneRenderer,
    /// Shading and wireframe.
    pub(super) settings: RenderSettings,
    /// Ray casting on the document's mesh (built on the first pick).
    bvh: Option<Bvh>,
    /// The document's label revision the colour layer was last refreshed for.
    pub(super) labels_shown: Option<u64>,
}

impl Scene {
    /// A scene drawing with `context`.
    pub(super) fn new(context: &three_d::Context) -> Self {
        Self {
            camera: OrbitCamera::default(),
            renderer: SceneRenderer::new(context),
            settings: RenderSettings::default(),
            bvh: None,
            labels_shown: None,
        }
    }

    /// What the camera shows, for the tools.
    pub(super) fn view_info(&self) -> ViewInfo {
        let (right, up, forward) = self.camera.basis();
        ViewInfo {
            eye: self.camera.eye(),
            forward,
            right,
            up,
            scene_radius: self.camera.scene_radius,
        }
    }

    pub(super) fn frame_mesh(&mut self, mesh: &Mesh, reset: bool) {
        if let Some((lo, hi)) = mesh.bounding_box() {
            if reset {
                self.camera.reset(lo, hi);
            } else {
                self.camera.frame(lo, hi);
            }
        }
    }

    /// Brings the picking structure up to date with the mesh (a refit after moves, a
    /// rebuild after a topology change or a new mesh).
    fn update_bvh(&mut self, mesh: &Mesh) {
        match &mut self.bvh {
            Some(bvh) => bvh.update(mesh),
            None => self.bvh = Some(Bvh::build(mesh)),
        }
    }

    /// What `ray` hits on the mesh.
    pub(super) fn cast(&mut self, mesh: &Mesh, ray: &Ray) -> Option<Pick> {
        self.update_bvh(mesh);
        let bvh = self.bvh.as_ref()?;
        let hit = bvh.intersect(mesh, ray).ok()??;
        Some(Pick {
            vertex: hit.nearest_vertex,
            face: Some(hit.face),
            point: hit.point,
        })
    }

    /// Size of the overlay glyphs: about the same on screen whatever the zoom.
    pub(super) fn glyph_size(&self) -> f64 {
        0.006 * self.camera.distance * (0.5 * self.camera.fov_y).tan() / 0.315
    }
}
