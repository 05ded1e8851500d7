//! Helpers shared by the `deform_*` integration tests.
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::PathBuf;

use glam::DVec3;
use halfedge::Mesh;

/// `shared/meshes` found by walking up from the crate (or `MULTIRES_MESHES`); only the
/// real-mesh tier (`#[ignore]`d tests) reads it.
pub fn meshes_dir() -> PathBuf {
    if let Ok(dir) = std::env::var("MULTIRES_MESHES") {
        return PathBuf::from(dir);
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .map(|a| a.join("shared/meshes"))
        .find(|d| d.is_dir())
        .expect(
            "the real-mesh tier needs the shared test meshes: a `shared/meshes` folder above \
             the workspace, or MULTIRES_MESHES=DIR",
        )
}

/// Loads a shared mesh (real-mesh tier).
pub fn load(name: &str) -> Mesh {
    halfedge::io::read(meshes_dir().join(name)).unwrap().0
}

/// Loads a mesh of the workspace's `data/` folder.
pub fn data(name: &str) -> Mesh {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data")
        .join(name);
    halfedge::io::read(path).unwrap().0
}

/// The default tier's stand-in for a shared mesh: `spot` → `data/creature.obj` (closed,
/// about Spot's size, separate eyes); `stanford-bunny` → [`bunny_stand_in`].
pub fn stand_in(name: &str) -> Mesh {
    match name {
        "spot.obj" => data("creature.obj"),
        "stanford-bunny.obj" => bunny_stand_in(2),
        other => panic!("no stand-in for {other}"),
    }
}

/// The bunny's stand-in: `data/creature.obj` (ears up, snout along +z) subdivided
/// `times` times (twice: 92,160 faces, the bunny's density), turned to look along −x as
/// the bunny does, and placed in the bunny's bounding box (same centre and diagonal), so
/// that the bunny's regions — the ear above `y = 0.16`, the head at `x < −0.04`,
/// `y > 0.09` — are the creature's ear and head.
pub fn bunny_stand_in(times: usize) -> Mesh {
    let mut mesh = data("creature.obj");
    for _ in 0..times {
        mesh = halfedge::generators::subdivide(&mesh);
    }
    for p in mesh.positions_mut() {
        *p = DVec3::new(-p.z, p.y, p.x);
    }
    let (lo, hi) = mesh.bounding_box().unwrap();
    let (bunny_lo, bunny_hi) = (
        DVec3::new(-0.0947, 0.0330, -0.0619),
        DVec3::new(0.0610, 0.1873, 0.0588),
    );
    let scale = bunny_lo.distance(bunny_hi) / lo.distance(hi);
    let (from, to) = (0.5 * (lo + hi), 0.5 * (bunny_lo + bunny_hi));
    for p in mesh.positions_mut() {
        *p = to + scale * (*p - from);
    }
    mesh
}

/// A closed box `[lo, hi]` with `n` cells per axis, triangulated, outward faces.
pub fn closed_box(lo: DVec3, hi: DVec3, n: [usize; 3]) -> Mesh {
    let coord = |axis: usize, i: usize| -> f64 {
        lo[axis] + (hi[axis] - lo[axis]) * i as f64 / n[axis] as f64
    };
    let mut index: HashMap<[usize; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut id = |g: [usize; 3], positions: &mut Vec<DVec3>| -> u32 {
        *index.entry(g).or_insert_with(|| {
            positions.push(DVec3::new(coord(0, g[0]), coord(1, g[1]), coord(2, g[2])));
            (positions.len() - 1) as u32
        })
    };
    let centre = 0.5 * (lo + hi);
    let mut triangles = Vec::new();
    for axis in 0..3 {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n[axis]] {
            for i in 0..n[a] {
                for j in 0..n[b] {
                    let corner = |di: usize, dj: usize| {
                        let mut g = [0; 3];
                        g[axis] = side;
                        g[a] = i + di;
                        g[b] = j + dj;
                        g
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
                        .map(|g| id(g, &mut positions));
                    for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
                        let [p0, p1, p2] = t.map(|k| positions[k as usize]);
                        let normal = (p1 - p0).cross(p2 - p0);
                        let outward = (p0 + p1 + p2) / 3.0 - centre;
                        triangles.push(if normal.dot(outward) > 0.0 {
                            t
                        } else {
                            [t[0], t[2], t[1]]
                        });
                    }
                }
            }
        }
    }
    let mesh = Mesh::from_triangles(&positions, &triangles).unwrap().0;
    mesh.check().unwrap();
    mesh
}

/// Signed volume enclosed by a closed mesh.
pub fn volume(mesh: &Mesh) -> f64 {
    mesh.faces()
        .map(|f| {
            let [a, b, c] = mesh.triangle_positions(f);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// Largest distance between corresponding positions.
pub fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max)
}

/// Bit-for-bit equality of position arrays.
pub fn bit_identical(a: &[DVec3], b: &[DVec3]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits))
}

/// The connected component (through vertices with `mask` set) containing slot `seed`, as
/// a mask.
pub fn component(mesh: &Mesh, mask: &[bool], seed: usize) -> Vec<bool> {
    let mut out = vec![false; mesh.vertex_slots()];
    let mut stack = vec![mesh.vertex_at(seed).unwrap()];
    out[seed] = true;
    while let Some(v) = stack.pop() {
        for w in mesh.adjacent_vertices(v) {
            let j = mesh.vertex_index(w);
            if mask[j] && !out[j] {
                out[j] = true;
                stack.push(w);
            }
        }
    }
    out
}

/// Slot of the vertex with the largest `key`, among vertices with faces.
pub fn argmax(mesh: &Mesh, key: impl Fn(DVec3) -> f64) -> usize {
    mesh.vertices()
        .filter(|&v| !mesh.is_isolated(v))
        .map(|v| mesh.vertex_index(v))
        .max_by(|&a, &b| key(mesh.positions()[a]).total_cmp(&key(mesh.positions()[b])))
        .unwrap()
}

/// The bunny's ear (as the paper's Fig. 5 sub-mesh): the vertices above the cutting plane
/// `y = 0.16` connected to the highest vertex (the ear tip).
pub fn bunny_ear(mesh: &Mesh) -> Vec<bool> {
    let above: Vec<bool> = mesh.positions().iter().map(|p| p.y > 0.16).collect();
    component(mesh, &above, argmax(mesh, |p| p.y))
}

/// The bunny's head: the vertices with `x < −0.04` and `y > 0.09` connected to the
/// highest of them.
pub fn bunny_head(mesh: &Mesh) -> Vec<bool> {
    let region: Vec<bool> = mesh
        .positions()
        .iter()
        .map(|p| p.x < -0.04 && p.y > 0.09)
        .collect();
    let seed = argmax(mesh, |p| {
        if p.x < -0.04 && p.y > 0.09 {
            p.y
        } else {
            f64::NEG_INFINITY
        }
    });
    component(mesh, &region, seed)
}
