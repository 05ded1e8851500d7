//! Kernel benches: building from indexed triangles (bunny, and nefertiti subdivided twice
//! ≈ 1.6 M faces), loading that mesh from a binary PLY and the bunny from OBJ, one-ring
//! circulation over all vertices, vertex normals.
//!
//! Loading the bunny OBJ has its reference too: a plain hand-written reader of `v` and
//! `f` lines feeding the same builder.
//!
//! Traversal rows come in pairs: the work written with the public API (element
//! iterators, circulators, handles) and the same work as a plain index loop over copies
//! of the kernel's own arrays (`Arrays`: 16-byte halfedge records, `opposite = h ^ 1`),
//! which is the reference (target: API ≤ 1.1 × the index loop).
//!
//! ```text
//! cargo bench --bench kernel
//! python3 benches/openmesh_reference.py   # OpenMesh on the same work, for comparison
//! ```
//!
//! The 1.6 M-face PLY is generated once into `bench-cache/` (git-ignored) at the
//! workspace root by `benches/common` (`cargo run --release --example bench_cache` prepares
//! it ahead). Builds and loads are timed without dropping the result
//! (`iter_with_large_drop`), as `openmesh_reference.py` times OpenMesh.

use std::hint::black_box;

use testkit::bench as common;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::DVec3;
use halfedge::io;
use halfedge::Mesh;

fn soup(mesh: &Mesh) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let index = io::file_vertex_indices(mesh);
    let positions = mesh.vertices().map(|v| mesh.position(v)).collect();
    let triangles = mesh
        .faces()
        .map(|f| mesh.triangle(f).map(|v| index[mesh.vertex_index(v)]))
        .collect();
    (positions, triangles)
}

/// The reference for loading an OBJ: what a plain hand-written reader does — `v x y z`
/// and `f a b c` lines (1-based triangles, `a/t/n` tokens cut at the first `/`), nothing
/// checked — then the same builder.
fn read_obj_plain_loop(path: &std::path::Path) -> Mesh {
    let text = std::fs::read_to_string(path).unwrap();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for line in text.lines() {
        let mut tokens = line.split_ascii_whitespace();
        match tokens.next() {
            Some("v") => {
                let mut x = tokens.map(|t| t.parse::<f64>().unwrap());
                positions.push(DVec3::new(
                    x.next().unwrap(),
                    x.next().unwrap(),
                    x.next().unwrap(),
                ));
            }
            Some("f") => {
                let mut i =
                    tokens.map(|t| t.split('/').next().unwrap().parse::<u32>().unwrap() - 1);
                triangles.push([i.next().unwrap(), i.next().unwrap(), i.next().unwrap()]);
            }
            _ => {}
        }
    }
    Mesh::from_triangles(&positions, &triangles).unwrap().0
}

fn one_ring_sum(mesh: &Mesh) -> usize {
    mesh.vertices()
        .map(|v| {
            mesh.adjacent_vertices(v)
                .map(|w| mesh.vertex_index(w))
                .sum::<usize>()
        })
        .sum()
}

/// A copy of the kernel's arrays, read through the public API: the reference for the
/// traversal rows (what a hand-written loop over pmp-style arrays does).
struct Arrays {
    /// Outgoing halfedge per vertex slot (`NONE`: isolated or removed).
    vertex_halfedge: Vec<u32>,
    /// `[to, next, prev, face]` per halfedge slot (`face == NONE`: boundary).
    halfedges: Vec<[u32; 4]>,
    /// A halfedge per face slot (`NONE`: removed).
    face_halfedge: Vec<u32>,
    positions: Vec<DVec3>,
}

const NONE: u32 = u32::MAX;

impl Arrays {
    fn new(mesh: &Mesh) -> Self {
        let h_ix = |h| mesh.halfedge_index(h) as u32;
        let mut vertex_halfedge = vec![NONE; mesh.vertex_slots()];
        for v in mesh.vertices() {
            vertex_halfedge[mesh.vertex_index(v)] = mesh.vertex_halfedge(v).map_or(NONE, h_ix);
        }
        let mut halfedges = vec![[NONE; 4]; mesh.halfedge_slots()];
        for h in mesh.halfedges() {
            halfedges[mesh.halfedge_index(h)] = [
                mesh.vertex_index(mesh.to_vertex(h)) as u32,
                h_ix(mesh.next(h)),
                h_ix(mesh.prev(h)),
                mesh.face(h).map_or(NONE, |f| mesh.face_index(f) as u32),
            ];
        }
        let mut face_halfedge = vec![NONE; mesh.face_slots()];
        for f in mesh.faces() {
            face_halfedge[mesh.face_index(f)] = h_ix(mesh.face_halfedge(f));
        }
        Self {
            vertex_halfedge,
            halfedges,
            face_halfedge,
            positions: mesh.positions().to_vec(),
        }
    }

    /// Calls `visit(h)` for every outgoing halfedge of the vertex whose first one is
    /// `start`, counter-clockwise (`opposite(prev(h))`), as the kernel's circulator turns.
    #[inline(always)]
    fn ring(&self, start: u32, mut visit: impl FnMut(&[u32; 4])) {
        if start == NONE {
            return;
        }
        let mut h = start;
        loop {
            let r = &self.halfedges[h as usize];
            visit(r);
            h = r[2] ^ 1;
            if h == start {
                break;
            }
        }
    }

    fn one_ring_sum(&self) -> usize {
        let mut sum = 0;
        for &start in &self.vertex_halfedge {
            self.ring(start, |r| sum += r[0] as usize);
        }
        sum
    }

    /// Sum of the neighbour positions of every vertex (a gather).
    fn gather(&self) -> DVec3 {
        let mut total = DVec3::ZERO;
        for &start in &self.vertex_halfedge {
            let mut s = DVec3::ZERO;
            self.ring(start, |r| s += self.positions[r[0] as usize]);
            total += s;
        }
        total
    }

    /// Uniform Laplacian per vertex slot: mean of the neighbours minus the vertex.
    fn laplacian(&self) -> Vec<DVec3> {
        self.vertex_halfedge
            .iter()
            .zip(&self.positions)
            .map(|(&start, &p)| {
                let (mut s, mut n) = (DVec3::ZERO, 0u32);
                self.ring(start, |r| {
                    s += self.positions[r[0] as usize];
                    n += 1;
                });
                if n == 0 {
                    DVec3::ZERO
                } else {
                    s / f64::from(n) - p
                }
            })
            .collect()
    }

    fn face_normals(&self) -> Vec<DVec3> {
        self.face_halfedge
            .iter()
            .map(|&h0| {
                if h0 == NONE {
                    return DVec3::ZERO;
                }
                let r0 = &self.halfedges[h0 as usize];
                let r1 = &self.halfedges[r0[1] as usize];
                let r2 = &self.halfedges[r1[1] as usize];
                let [a, b, c] = [r0[0], r1[0], r2[0]].map(|v| self.positions[v as usize]);
                (b - a).cross(c - a).normalize_or_zero()
            })
            .collect()
    }

    /// Face normals, then per vertex the normalised sum of its faces' normals (the
    /// kernel's `vertex_normals`, on one thread).
    fn vertex_normals(&self) -> Vec<DVec3> {
        let face_normals = self.face_normals();
        self.vertex_halfedge
            .iter()
            .map(|&start| {
                let mut n = DVec3::ZERO;
                self.ring(start, |r| {
                    if r[3] != NONE {
                        n += face_normals[r[3] as usize];
                    }
                });
                n.normalize_or_zero()
            })
            .collect()
    }
}

/// The API versions of the `Arrays` loops.
fn gather(mesh: &Mesh) -> DVec3 {
    mesh.vertices()
        .map(|v| {
            mesh.adjacent_vertices(v)
                .map(|w| mesh.position(w))
                .sum::<DVec3>()
        })
        .sum()
}

fn laplacian(mesh: &Mesh) -> Vec<DVec3> {
    let mut out = vec![DVec3::ZERO; mesh.vertex_slots()];
    for v in mesh.vertices() {
        let (mut s, mut n) = (DVec3::ZERO, 0u32);
        for w in mesh.adjacent_vertices(v) {
            s += mesh.position(w);
            n += 1;
        }
        if n > 0 {
            out[mesh.vertex_index(v)] = s / f64::from(n) - mesh.position(v);
        }
    }
    out
}

fn vertex_normals_one_thread(mesh: &Mesh) -> Vec<DVec3> {
    let mut face_normals = vec![DVec3::ZERO; mesh.face_slots()];
    for f in mesh.faces() {
        face_normals[mesh.face_index(f)] = mesh.face_normal(f);
    }
    let mut out = vec![DVec3::ZERO; mesh.vertex_slots()];
    for v in mesh.vertices() {
        out[mesh.vertex_index(v)] = mesh
            .adjacent_faces(v)
            .map(|f| face_normals[mesh.face_index(f)])
            .sum::<DVec3>()
            .normalize_or_zero();
    }
    out
}

fn benches(c: &mut Criterion) {
    let bunny_path = common::meshes_dir().join("stanford-bunny.obj");
    let (bunny, _) = io::read(&bunny_path).unwrap();
    let big_path = common::NEFERTITI_X2.cached();
    let (big, _) = io::read(&big_path).unwrap();
    assert_eq!(big.n_faces(), 1_599_008);

    let mut group = c.benchmark_group("kernel");
    group.sample_size(10);

    let (positions, triangles) = soup(&bunny);
    group.bench_function("build bunny (69 k faces)", |b| {
        b.iter_with_large_drop(|| {
            Mesh::from_triangles(black_box(&positions), black_box(&triangles)).unwrap()
        })
    });
    let (positions, triangles) = soup(&big);
    group.bench_function("build nefertiti×2 (1.6 M faces)", |b| {
        b.iter_with_large_drop(|| {
            Mesh::from_triangles(black_box(&positions), black_box(&triangles)).unwrap()
        })
    });
    drop((positions, triangles));
    let plain = read_obj_plain_loop(&bunny_path);
    assert_eq!(plain.positions(), bunny.positions());
    group.bench_function("plain loop (reference): load bunny OBJ", |b| {
        b.iter_with_large_drop(|| read_obj_plain_loop(black_box(&bunny_path)))
    });
    group.bench_function("load bunny OBJ", |b| {
        b.iter_with_large_drop(|| io::read(black_box(&bunny_path)).unwrap())
    });
    group.bench_function("load nefertiti×2 binary PLY (1.6 M faces)", |b| {
        b.iter_with_large_drop(|| io::read(black_box(&big_path)).unwrap())
    });
    let arrays = Arrays::new(&big);
    assert_eq!(arrays.one_ring_sum(), one_ring_sum(&big));
    assert_eq!(arrays.gather(), gather(&big));
    assert_eq!(arrays.laplacian(), laplacian(&big));
    assert_eq!(arrays.vertex_normals(), vertex_normals_one_thread(&big));
    assert_eq!(arrays.vertex_normals(), big.vertex_normals().values());
    group.bench_function("index loop (reference): one-ring sum", |b| {
        b.iter(|| black_box(&arrays).one_ring_sum())
    });
    group.bench_function("one-ring circulation, all vertices (0.8 M)", |b| {
        b.iter(|| one_ring_sum(black_box(&big)))
    });
    group.bench_function("index loop (reference): gather neighbour positions", |b| {
        b.iter(|| black_box(&arrays).gather())
    });
    group.bench_function("gather neighbour positions", |b| {
        b.iter(|| gather(black_box(&big)))
    });
    group.bench_function("index loop (reference): uniform Laplacian", |b| {
        b.iter(|| black_box(&arrays).laplacian())
    });
    group.bench_function("uniform Laplacian", |b| {
        b.iter(|| laplacian(black_box(&big)))
    });
    group.bench_function("index loop (reference): vertex normals, one thread", |b| {
        b.iter(|| black_box(&arrays).vertex_normals())
    });
    group.bench_function("vertex normals, one thread", |b| {
        b.iter(|| vertex_normals_one_thread(black_box(&big)))
    });
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    group.bench_function("vertex normals, Mesh::vertex_normals on one thread", |b| {
        b.iter(|| one_thread.install(|| black_box(&big).vertex_normals()))
    });
    group.bench_function("one-ring circulation, all vertices (0.8 M), rayon", |b| {
        b.iter(|| common::one_ring_sum_parallel(black_box(&big)))
    });
    group.bench_function("vertex normals (0.8 M vertices)", |b| {
        b.iter(|| black_box(&big).vertex_normals())
    });
    group.bench_function("vertex normals bunny", |b| {
        b.iter(|| black_box(&bunny).vertex_normals())
    });
    group.bench_function("check every invariant, nefertiti×2", |b| {
        b.iter(|| black_box(&big).check().unwrap())
    });
    group.bench_function("topology report, nefertiti×2", |b| {
        b.iter(|| black_box(&big).topology_report())
    });
    group.finish();
}

criterion_group!(kernel, benches);
criterion_main!(kernel);
