//! Generated meshes the tests need and `halfedge::generators` lacks (the grid, the
//! icosphere, the torus, the bow-tie, 1-to-4 subdivision and disjoint unions are
//! generators there).

use std::collections::HashMap;

use glam::DVec3;
use halfedge::Mesh;

/// An elongated bumpy sphere: an "arm" along x with fine detail everywhere (closed,
/// genus 0, the level-5 icosphere's 20,480 faces), for the hierarchy tests.
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

/// A closed box `[lo, hi]` with `n` cells per axis, each square cell split into two
/// triangles, faces facing outwards.
///
/// # Panics
/// When a count of `n` is zero or the box is flat.
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

/// An icosphere of `level` ([`halfedge::generators::icosphere`]) with smooth bumps of
/// relative height `amplitude`: every vertex scaled by
/// `1 + amplitude · sin 5x · sin 4y · sin(3z + 0.5)`, so that the detail of a hierarchy
/// built on it is not radial. Closed, genus 0.
pub fn bumpy_sphere(level: usize, amplitude: f64) -> Mesh {
    let mut mesh = halfedge::generators::icosphere(level);
    for p in mesh.positions_mut() {
        let bump =
            1.0 + amplitude * (5.0 * p.x).sin() * (4.0 * p.y).sin() * (3.0 * p.z + 0.5).sin();
        *p *= bump;
    }
    mesh
}
