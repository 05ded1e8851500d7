//! Drawing the mesh with `three-d`: the `f64` kernel mesh becomes `f32` buffers on the
//! GPU, either indexed (one GPU vertex per vertex slot: the fast default) or as a
//! triangle soup (three corners per face) when the wireframe (barycentric coordinates)
//! or per-face colours need it. Updates use the `*_partially(0, …)` setters, which
//! accept indexed meshes (`set_positions` does not).
//!
//! One material ([`SurfaceMaterial`]) does the shading itself: smooth (vertex normals)
//! or flat (the face normal from screen-space derivatives of the position, so switching
//! costs nothing), a key light and a fill light attached to the camera, a hemisphere
//! ambient term, a soft specular highlight, back faces in a distinct colour (holes show
//! as such), and an anti-aliased wireframe from barycentric coordinates.
//!
//! Positions are uploaded relative to an origin near the mesh (the bounding-box centre
//! when the connectivity was last uploaded) so that `f32` keeps its precision for meshes
//! far from the world origin; the camera uses the same offset.

use glam::DVec3;
use halfedge::{FaceId, Mesh};
use rayon::prelude::*;
use three_d::*;

use crate::camera::to_cg;
use crate::colors::{ColorLayer, LabelTarget, Rgba};
use crate::document::Revision;
use crate::tools::Overlay;

/// How the surface is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderSettings {
    /// Face normals (true) or interpolated vertex normals (false).
    pub flat: bool,
    /// Draw the edges over the surface.
    pub wireframe: bool,
}

/// The shading of the mesh and of the overlay glyphs (see the module docs).
pub struct SurfaceMaterial {
    /// Geometry has barycentric coordinates in its uvs: enables the wireframe.
    pub barycentric: bool,
    /// Flat shading.
    pub flat: bool,
    /// Wireframe on (needs `barycentric`).
    pub wireframe: bool,
    /// Wire colour.
    pub wire_color: Srgba,
    /// Colour of back faces.
    pub back_color: Srgba,
    /// Unit direction towards the key light (render space).
    pub key_light: Vec3,
    /// Unit direction towards the fill light.
    pub fill_light: Vec3,
    /// Screen-up direction, for the hemisphere ambient term.
    pub sky: Vec3,
    /// Specular strength.
    pub specular: f32,
}

impl SurfaceMaterial {
    fn new(barycentric: bool) -> Self {
        Self {
            barycentric,
            flat: false,
            wireframe: false,
            wire_color: Srgba::new(30, 34, 44, 150),
            back_color: Srgba::new(120, 130, 165, 255),
            key_light: vec3(0.0, 0.0, 1.0),
            fill_light: vec3(0.0, 0.0, 1.0),
            sky: vec3(0.0, 1.0, 0.0),
            specular: 0.18,
        }
    }
}

const SURFACE_SHADER: &str = r#"
uniform vec3 eyePosition;
uniform vec3 keyLight;
uniform vec3 fillLight;
uniform vec3 skyDir;
uniform float flatShading;
uniform float specular;
uniform vec4 backColor;
#ifdef USE_BARY
uniform float wireframe;
uniform vec4 wireColor;
in vec2 uvs;
#endif
in vec3 pos;
in vec3 nor;
in vec4 col;
layout (location = 0) out vec4 outColor;

void main()
{
    vec3 n;
    if (flatShading > 0.5) {
        n = normalize(cross(dFdx(pos), dFdy(pos)));
    } else {
        n = normalize(nor);
        if (!gl_FrontFacing) n = -n;
    }
    vec3 v = normalize(eyePosition - pos);
    if (dot(n, v) < 0.0) n = -n;
    vec3 albedo = gl_FrontFacing ? col.rgb : backColor.rgb;
    float key = max(dot(n, keyLight), 0.0);
    float fill = max(dot(n, fillLight), 0.0);
    float hemi = 0.5 + 0.5 * dot(n, skyDir);
    vec3 h = normalize(keyLight + v);
    // pow(x, 40) by squaring: llvmpipe evaluates pow as exp(log), far slower.
    float x = max(dot(n, h), 0.0);
    float x2 = x * x; float x4 = x2 * x2; float x8 = x4 * x4; float x32 = x8 * x8 * x8 * x8;
    float spec = specular * x32 * x8;
    vec3 c = albedo * (0.16 + 0.10 * hemi + 0.70 * key + 0.22 * fill) + vec3(spec);
#ifdef USE_BARY
    if (wireframe > 0.5) {
        vec3 b = vec3(uvs.x, 1.0 - uvs.y, uvs.y - uvs.x);
        vec3 w = fwidth(b);
        vec3 a = smoothstep(vec3(0.0), 1.3 * w, b);
        float edge = 1.0 - min(min(a.x, a.y), a.z);
        c = mix(c, wireColor.rgb, edge * wireColor.a);
    }
#endif
    // Linear to display with gamma 2 (sqrt): close to sRGB and much cheaper than its pow
    // on software OpenGL.
    outColor = vec4(sqrt(clamp(c, 0.0, 1.0)), 1.0);
}
"#;

impl Material for SurfaceMaterial {
    fn id(&self) -> EffectMaterialId {
        EffectMaterialId(0x0100 | u16::from(self.barycentric))
    }

    fn fragment_shader_source(&self, _lights: &[&dyn Light]) -> String {
        let mut s = String::new();
        if self.barycentric {
            s.push_str("#define USE_BARY\n");
        }
        s.push_str(SURFACE_SHADER);
        s
    }

    fn use_uniforms(&self, program: &Program, viewer: &dyn Viewer, _lights: &[&dyn Light]) {
        program.use_uniform_if_required("eyePosition", viewer.position());
        program.use_uniform_if_required("keyLight", self.key_light);
        program.use_uniform_if_required("fillLight", self.fill_light);
        program.use_uniform_if_required("skyDir", self.sky);
        program.use_uniform_if_required("flatShading", if self.flat { 1.0f32 } else { 0.0 });
        program.use_uniform_if_required("specular", self.specular);
        program.use_uniform_if_required("backColor", self.back_color.to_linear_srgb());
        if self.barycentric {
            program.use_uniform_if_required("wireframe", if self.wireframe { 1.0f32 } else { 0.0 });
            program.use_uniform_if_required("wireColor", self.wire_color.to_linear_srgb());
        }
    }

    fn render_states(&self) -> RenderStates {
        RenderStates {
            cull: Cull::None,
            ..Default::default()
        }
    }

    fn material_type(&self) -> MaterialType {
        MaterialType::Opaque
    }
}

/// A vertical gradient behind the scene.
pub struct BackgroundMaterial {
    /// Colour at the top.
    pub top: Srgba,
    /// Colour at the bottom.
    pub bottom: Srgba,
}

impl Material for BackgroundMaterial {
    fn id(&self) -> EffectMaterialId {
        EffectMaterialId(0x0110)
    }

    fn fragment_shader_source(&self, _lights: &[&dyn Light]) -> String {
        // Interpolated in display space: no colour mapping per pixel (cheap on llvmpipe).
        r#"
uniform vec4 topColor;
uniform vec4 bottomColor;
in vec2 uvs;
layout (location = 0) out vec4 outColor;
void main() {
    outColor = vec4(mix(bottomColor.rgb, topColor.rgb, uvs.y), 1.0);
}
"#
        .to_string()
    }

    fn use_uniforms(&self, program: &Program, _viewer: &dyn Viewer, _lights: &[&dyn Light]) {
        let display = |c: Srgba| vec4(c.r as f32, c.g as f32, c.b as f32, 255.0) / 255.0;
        program.use_uniform("topColor", display(self.top));
        program.use_uniform("bottomColor", display(self.bottom));
    }

    fn render_states(&self) -> RenderStates {
        RenderStates {
            depth_test: DepthTest::Always,
            write_mask: WriteMask::COLOR,
            cull: Cull::None,
            ..Default::default()
        }
    }

    fn material_type(&self) -> MaterialType {
        MaterialType::Opaque
    }
}

/// How the mesh is uploaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// Shared vertices and an index buffer: about six times fewer vertices to transform,
    /// which is what software OpenGL spends its time on.
    Indexed,
    /// Three corners per face: needed for the wireframe (barycentric coordinates) and for
    /// per-face colours.
    Soup,
}

/// The GPU side of the scene: the mesh and the overlay glyphs.
pub struct SceneRenderer {
    context: Context,
    surface: Option<Gm<three_d::Mesh, SurfaceMaterial>>,
    /// Vertex slots of each drawn face, in upload order.
    triangles: Vec<[u32; 3]>,
    /// Face slots in upload order.
    face_slots: Vec<u32>,
    origin: DVec3,
    revision: Option<Revision>,
    layer_revision: Option<u64>,
    mode: Option<Mode>,
    markers: Option<Gm<InstancedMesh, SurfaceMaterial>>,
    segments: Option<Gm<InstancedMesh, SurfaceMaterial>>,
    overlay: Overlay,
    glyph_size: f64,
    background: BackgroundMaterial,
}

fn srgba(c: Rgba) -> Srgba {
    Srgba::new(c[0], c[1], c[2], c[3])
}

impl SceneRenderer {
    /// An empty scene on `context`.
    pub fn new(context: &Context) -> Self {
        Self {
            context: context.clone(),
            surface: None,
            triangles: Vec::new(),
            face_slots: Vec::new(),
            origin: DVec3::ZERO,
            revision: None,
            layer_revision: None,
            mode: None,
            markers: None,
            segments: None,
            overlay: Overlay::default(),
            glyph_size: 0.01,
            background: BackgroundMaterial {
                top: Srgba::new(72, 78, 92, 255),
                bottom: Srgba::new(22, 24, 30, 255),
            },
        }
    }

    /// The offset subtracted from world positions before upload (render space).
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Number of triangles drawn.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Brings the GPU buffers up to date with the mesh (`revision`), the colour layer
    /// (`layer_revision`) and the drawing mode the settings need. Returns the time spent.
    pub fn sync(
        &mut self,
        mesh: &Mesh,
        revision: Revision,
        layer: &ColorLayer,
        layer_revision: u64,
        settings: RenderSettings,
    ) -> std::time::Duration {
        let start = std::time::Instant::now();
        let face_colors = matches!(layer, ColorLayer::Labels(f) if f.target == LabelTarget::Faces);
        let mode = if settings.wireframe || face_colors {
            Mode::Soup
        } else {
            Mode::Indexed
        };
        let old = self.revision;
        // three-d checks partial updates of an indexed mesh against the number of indices
        // (3 per triangle), not of vertices: a coarse level of a hierarchy keeps all its
        // vertex slots with fewer triangles, so it is rebuilt instead (it is small).
        let partial_ok = mode == Mode::Soup || 3 * mesh.n_faces() >= mesh.vertex_slots();
        let changed = old.map(|r| r.geometry) != Some(revision.geometry)
            || self.layer_revision != Some(layer_revision);
        if old.map(|r| r.topology) != Some(revision.topology)
            || self.mode != Some(mode)
            || (changed && !partial_ok)
        {
            self.rebuild(
                mesh,
                layer,
                mode,
                old.map(|r| r.topology) != Some(revision.topology),
            );
            self.layer_revision = Some(layer_revision);
        } else if old.map(|r| r.geometry) != Some(revision.geometry) {
            if let Some(surface) = &mut self.surface {
                let (positions, normals) = match mode {
                    Mode::Soup => soup_geometry(mesh, &self.triangles, self.origin),
                    Mode::Indexed => slot_geometry(mesh, self.origin),
                };
                let g = &mut surface.geometry;
                g.set_positions_partially(0, &positions)
                    .expect("sizes match the upload");
                g.set_normals_partially(0, &normals)
                    .expect("sizes match the upload");
            }
        }
        if self.layer_revision != Some(layer_revision) {
            let colors: Vec<Vec4> = self
                .colors(layer, mesh, mode)
                .into_iter()
                .map(|c| srgba(c).to_linear_srgb())
                .collect();
            if let Some(surface) = &mut self.surface {
                surface
                    .geometry
                    .set_colors_partially(0, &colors)
                    .expect("sizes match the upload");
            }
            self.layer_revision = Some(layer_revision);
        }
        self.revision = Some(revision);
        start.elapsed()
    }

    /// Corner colours (soup) or vertex-slot colours (indexed).
    fn colors(&self, layer: &ColorLayer, mesh: &Mesh, mode: Mode) -> Vec<Rgba> {
        let layer = if layer.check_size(mesh).is_ok() {
            layer
        } else {
            &ColorLayer::None
        };
        match mode {
            Mode::Soup => layer.corner_colors(&self.triangles, &self.face_slots),
            Mode::Indexed => layer.vertex_colors(mesh.vertex_slots()),
        }
    }

    fn rebuild(&mut self, mesh: &Mesh, layer: &ColorLayer, mode: Mode, new_topology: bool) {
        if new_topology {
            let faces: Vec<FaceId> = mesh.faces().collect();
            self.triangles = faces
                .iter()
                .map(|&f| mesh.triangle(f).map(|v| mesh.vertex_index(v) as u32))
                .collect();
            self.face_slots = faces.iter().map(|&f| mesh.face_index(f) as u32).collect();
            self.origin = mesh
                .bounding_box()
                .map_or(DVec3::ZERO, |(lo, hi)| 0.5 * (lo + hi));
            // Glyph positions are relative to the origin: rebuild them.
            self.overlay = Overlay {
                markers: vec![],
                segments: vec![],
            };
            self.markers = None;
            self.segments = None;
        }
        self.mode = Some(mode);
        if self.triangles.is_empty() {
            self.surface = None;
            return;
        }
        let colors: Vec<Srgba> = self
            .colors(layer, mesh, mode)
            .into_iter()
            .map(srgba)
            .collect();
        let cpu = match mode {
            Mode::Soup => {
                let (positions, normals) = soup_geometry(mesh, &self.triangles, self.origin);
                // Barycentric corners (1,0,0), (0,1,0), (0,0,1) encoded so that they survive
                // three-d's flip of v: the shader decodes b = (u, 1 − v, v − u).
                let uvs: Vec<Vec2> = (0..self.triangles.len())
                    .flat_map(|_| [vec2(1.0, 0.0), vec2(0.0, 1.0), vec2(0.0, 0.0)])
                    .collect();
                CpuMesh {
                    positions: Positions::F32(positions),
                    normals: Some(normals),
                    uvs: Some(uvs),
                    colors: Some(colors),
                    ..Default::default()
                }
            }
            Mode::Indexed => {
                let (positions, normals) = slot_geometry(mesh, self.origin);
                CpuMesh {
                    positions: Positions::F32(positions),
                    normals: Some(normals),
                    indices: Indices::U32(self.triangles.iter().flatten().copied().collect()),
                    colors: Some(colors),
                    ..Default::default()
                }
            }
        };
        self.surface = Some(Gm::new(
            three_d::Mesh::new(&self.context, &cpu),
            SurfaceMaterial::new(mode == Mode::Soup),
        ));
    }

    /// Replaces the overlay glyphs (markers and segments); `size` is the radius of a
    /// marker of scale 1 in world units (the caller keeps it constant on screen).
    pub fn set_overlay(&mut self, overlay: &Overlay, size: f64) {
        let same_size = (size / self.glyph_size - 1.0).abs() < 0.02;
        if *overlay == self.overlay && same_size {
            return;
        }
        self.overlay = overlay.clone();
        self.glyph_size = size;
        let o = self.origin;
        self.markers = (!overlay.markers.is_empty()).then(|| {
            let instances = Instances {
                transformations: overlay
                    .markers
                    .iter()
                    .map(|m| {
                        Mat4::from_translation(to_cg(m.position - o))
                            * Mat4::from_scale((size * m.scale as f64) as f32)
                    })
                    .collect(),
                colors: Some(overlay.markers.iter().map(|m| srgba(m.color)).collect()),
                texture_transformations: None,
            };
            let mut sphere = CpuMesh::sphere(12);
            sphere.uvs = None;
            Gm::new(
                InstancedMesh::new(&self.context, &instances, &sphere),
                SurfaceMaterial::new(false),
            )
        });
        self.segments = (!overlay.segments.is_empty()).then(|| {
            let radius = (0.3 * size) as f32;
            let instances = Instances {
                transformations: overlay
                    .segments
                    .iter()
                    .map(|s| {
                        let d = s.b - s.a;
                        let len = d.length().max(1e-30);
                        let rotation =
                            Mat4::from(Quat::from_arc(vec3(1.0, 0.0, 0.0), to_cg(d / len), None));
                        Mat4::from_translation(to_cg(s.a - o))
                            * rotation
                            * Mat4::from_nonuniform_scale(len as f32, radius, radius)
                    })
                    .collect(),
                colors: Some(overlay.segments.iter().map(|s| srgba(s.color)).collect()),
                texture_transformations: None,
            };
            Gm::new(
                InstancedMesh::new(&self.context, &instances, &CpuMesh::cylinder(8)),
                SurfaceMaterial::new(false),
            )
        });
    }

    /// Draws background, mesh and overlay into `target` with `camera` (in render space).
    pub fn render(&mut self, target: &RenderTarget<'_>, camera: &Camera, settings: RenderSettings) {
        let forward = camera.view_direction();
        let right = camera.right_direction();
        let up = camera.up_orthogonal();
        // Key light from the upper left behind the viewer, fill from the right.
        let key = (-forward * 1.0 + up * 0.65 - right * 0.45).normalize();
        let fill = (-forward * 0.6 - up * 0.2 + right * 0.8).normalize();
        for m in [
            self.surface.as_mut().map(|g| &mut g.material),
            self.markers.as_mut().map(|g| &mut g.material),
            self.segments.as_mut().map(|g| &mut g.material),
        ]
        .into_iter()
        .flatten()
        {
            m.key_light = key;
            m.fill_light = fill;
            m.sky = up;
        }
        if let Some(s) = &mut self.surface {
            s.material.flat = settings.flat;
            s.material.wireframe = settings.wireframe;
        }
        target.apply_screen_material(&self.background, camera, &[]);
        let objects = self
            .surface
            .iter()
            .map(|g| g as &dyn Object)
            .chain(self.markers.iter().map(|g| g as &dyn Object))
            .chain(self.segments.iter().map(|g| g as &dyn Object));
        target.render(camera, objects, &[]);
    }
}

/// Positions (relative to `origin`) and smooth normals per vertex slot (removed
/// vertices included: no triangle refers to them).
fn slot_geometry(mesh: &Mesh, origin: DVec3) -> (Vec<Vec3>, Vec<Vec3>) {
    let normals = mesh.vertex_normals();
    mesh.positions()
        .par_iter()
        .zip(normals.par_iter())
        .map(|(&p, &n)| (to_cg(p - origin), to_cg(n)))
        .unzip()
}

/// Corner positions (relative to `origin`) and smooth normals of the soup.
fn soup_geometry(mesh: &Mesh, triangles: &[[u32; 3]], origin: DVec3) -> (Vec<Vec3>, Vec<Vec3>) {
    let normals = mesh.vertex_normals();
    let positions = mesh.positions();
    triangles
        .par_iter()
        .flat_map_iter(|t| {
            t.map(|i| {
                let p = positions[i as usize] - origin;
                let n = normals[i as usize];
                (to_cg(p), to_cg(n))
            })
        })
        .unzip()
}
