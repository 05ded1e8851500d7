//! Helpers shared by the kernel's integration tests.
#![allow(dead_code, missing_docs)]

use std::path::{Path, PathBuf};

use halfedge::{FaceId, HalfedgeId, Mesh, VertexId};

/// `../shared/meshes` seen from the workspace (the first ancestor of this crate that has
/// `shared/meshes`), or `$MULTIRES_MESHES`. Only the real-mesh tier (`#[ignore]`d tests)
/// reads it; it panics, saying how to get the meshes, when there are none.
pub fn shared_meshes() -> PathBuf {
    if let Some(dir) = std::env::var_os("MULTIRES_MESHES") {
        return PathBuf::from(dir);
    }
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .map(|a| a.join("shared/meshes"))
        .find(|d| d.is_dir())
        .expect(
            "the real-mesh tier needs the shared test meshes: a `shared/meshes` folder above \
             the workspace, or MULTIRES_MESHES=DIR",
        )
}

/// The workspace's `data/` directory.
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data")
}

/// A fresh temporary directory for one test.
pub fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("halfedge-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// PLY encodings for [`PlyBuilder`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Enc {
    Ascii,
    Le,
    Be,
}

/// Writes PLY files by hand, with any header and any property types, to test readers.
pub struct PlyBuilder {
    enc: Enc,
    header: Vec<String>,
    body: Vec<u8>,
    first_in_line: bool,
}

impl PlyBuilder {
    pub fn new(enc: Enc) -> Self {
        let format = match enc {
            Enc::Ascii => "ascii",
            Enc::Le => "binary_little_endian",
            Enc::Be => "binary_big_endian",
        };
        Self {
            enc,
            header: vec!["ply".into(), format!("format {format} 1.0")],
            body: Vec::new(),
            first_in_line: true,
        }
    }
    /// Adds a raw header line.
    pub fn line(mut self, line: &str) -> Self {
        self.header.push(line.into());
        self
    }
    pub fn element(self, name: &str, count: usize) -> Self {
        self.line(&format!("element {name} {count}"))
    }
    pub fn property(self, ty: &str, name: &str) -> Self {
        self.line(&format!("property {ty} {name}"))
    }
    pub fn list_property(self, count: &str, item: &str, name: &str) -> Self {
        self.line(&format!("property list {count} {item} {name}"))
    }
    /// Appends one value of type `ty`.
    pub fn value(&mut self, ty: &str, v: f64) -> &mut Self {
        match self.enc {
            Enc::Ascii => {
                if !self.first_in_line {
                    self.body.push(b' ');
                }
                let text = match ty {
                    "float" | "float32" | "double" | "float64" => format!("{v}"),
                    _ => format!("{}", v as i64),
                };
                self.body.extend(text.as_bytes());
                self.first_in_line = false;
            }
            Enc::Le | Enc::Be => {
                let le = self.enc == Enc::Le;
                macro_rules! put {
                    ($x:expr) => {{
                        let x = $x;
                        self.body
                            .extend(if le { x.to_le_bytes() } else { x.to_be_bytes() })
                    }};
                }
                match ty {
                    "char" | "int8" => put!(v as i8),
                    "uchar" | "uint8" => put!(v as u8),
                    "short" | "int16" => put!(v as i16),
                    "ushort" | "uint16" => put!(v as u16),
                    "int" | "int32" => put!(v as i32),
                    "uint" | "uint32" => put!(v as u32),
                    "float" | "float32" => put!(v as f32),
                    "double" | "float64" => put!(v),
                    other => panic!("unknown type {other}"),
                }
            }
        }
        self
    }
    /// Appends a list: its length as `count`, then the items as `item`.
    pub fn list(&mut self, count: &str, item: &str, items: &[f64]) -> &mut Self {
        self.value(count, items.len() as f64);
        for &x in items {
            self.value(item, x);
        }
        self
    }
    /// Ends an element (a line in ASCII).
    pub fn end(&mut self) -> &mut Self {
        if self.enc == Enc::Ascii {
            self.body.push(b'\n');
            self.first_in_line = true;
        }
        self
    }
    pub fn bytes(&self) -> Vec<u8> {
        let mut out = self.header.join("\n").into_bytes();
        out.extend(b"\nend_header\n");
        out.extend(&self.body);
        out
    }
}

/// A binary or ASCII PLY of a unit square split into two triangles, with float `x y z`,
/// a `uchar int` face list, and `extra` header lines / values left to the caller.
pub fn square(enc: Enc) -> PlyBuilder {
    let mut b = PlyBuilder::new(enc)
        .element("vertex", 4)
        .property("float", "x")
        .property("float", "y")
        .property("float", "z")
        .element("face", 2)
        .list_property("uchar", "int", "vertex_indices");
    for p in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        for c in p {
            b.value("float", c);
        }
        b.end();
    }
    b.list("uchar", "int", &[0.0, 1.0, 2.0]).end();
    b.list("uchar", "int", &[0.0, 2.0, 3.0]).end();
    b
}

/// `shared/meshes` next to the repository (or `MULTIRES_MESHES`); see [`shared_meshes`].
pub fn meshes_dir() -> PathBuf {
    shared_meshes()
}

/// Loads a shared mesh by file name (real-mesh tier).
pub fn load(name: &str) -> Mesh {
    halfedge::io::read(meshes_dir().join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
}

/// Loads a mesh of `data/` by file name.
pub fn data(name: &str) -> Mesh {
    halfedge::io::read(data_dir().join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .0
}

/// The generated mesh of `data/` that stands in for a shared mesh in the default tier,
/// with the same character: `spot` (closed, genus 0) → `blob`; `stanford-bunny` (holes)
/// → `cup`; `cow` (several components) → `creature`; `teapot` (boundary loops) → `cup`;
/// `nefertiti` → `torus` (closed, genus 1); `fandisk` → `creature`; `suzanne`, `beast`
/// (quads, non-manifold) → `dirty`; `horse.ply` → `patch.ply` (binary PLY).
pub fn stand_in(name: &str) -> Mesh {
    data(match name {
        "spot.obj" => "blob.obj",
        "stanford-bunny.obj" | "teapot.obj" => "cup.obj",
        "cow.obj" | "fandisk.obj" => "creature.obj",
        "nefertiti.obj" => "torus.obj",
        "suzanne.obj" | "beast.obj" => "dirty.obj",
        "horse.ply" => "patch.ply",
        other => panic!("no stand-in for {other}"),
    })
}

/// Complete connectivity + positions snapshot, handle for handle.
#[derive(Debug, PartialEq, Clone)]
pub struct Snapshot {
    counts: (usize, usize, usize),
    vertices: Vec<(VertexId, Option<HalfedgeId>, [u64; 3])>,
    halfedges: Vec<(
        HalfedgeId,
        VertexId,
        HalfedgeId,
        HalfedgeId,
        HalfedgeId,
        Option<FaceId>,
    )>,
    faces: Vec<(FaceId, HalfedgeId)>,
}

/// Snapshot of everything `collapse` / `vertex_split` touch.
pub fn snapshot(mesh: &Mesh) -> Snapshot {
    Snapshot {
        counts: (mesh.n_vertices(), mesh.n_halfedges(), mesh.n_faces()),
        vertices: mesh
            .vertices()
            .map(|v| {
                (
                    v,
                    mesh.vertex_halfedge(v),
                    mesh.position(v).to_array().map(f64::to_bits),
                )
            })
            .collect(),
        halfedges: mesh
            .halfedges()
            .map(|h| {
                (
                    h,
                    mesh.to_vertex(h),
                    mesh.next(h),
                    mesh.prev(h),
                    mesh.opposite(h),
                    mesh.face(h),
                )
            })
            .collect(),
        faces: mesh.faces().map(|f| (f, mesh.face_halfedge(f))).collect(),
    }
}

/// `V − E + F`.
pub fn euler(mesh: &Mesh) -> i64 {
    mesh.n_vertices() as i64 - mesh.n_edges() as i64 + mesh.n_faces() as i64
}

/// An elongated bumpy sphere: an "arm" along x with fine detail everywhere (closed,
/// genus 0), for the hierarchy tests.
pub fn bumpy_capsule() -> Mesh {
    let mut mesh = halfedge::generators::icosphere(5);
    for p in mesh.positions_mut() {
        let bump = 1.0
            + 0.04 * (11.0 * p.x).sin() * (9.0 * p.y).sin() * (13.0 * p.z).cos()
            + 0.01 * (37.0 * p.x + 23.0 * p.y).sin();
        *p = glam::DVec3::new(3.0 * p.x, p.y, p.z) * bump;
    }
    mesh
}

/// Edges joining two vertices of different sub-meshes (neither on the frontier).
pub fn crossing_edges(mesh: &Mesh) -> usize {
    let a = mesh
        .find_attribute::<VertexId, u32>(halfedge::labels::LABEL_ATTRIBUTE)
        .unwrap();
    let labels = mesh.attribute_values(a).unwrap();
    mesh.halfedges()
        .filter(|&e| {
            let l = |v| labels[mesh.vertex_index(v)];
            let (x, y) = (l(mesh.from_vertex(e)), l(mesh.to_vertex(e)));
            x != y && x != halfedge::labels::FRONTIER && y != halfedge::labels::FRONTIER
        })
        .count()
}
