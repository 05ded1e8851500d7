//! Writes the small meshes in `data/` that the project makes itself (used by the README
//! job, the tests and the OpenMesh comparison). Deterministic: running it again gives the
//! same files.
//!
//! ```text
//! cargo run --release --example make_data            # writes into data/
//! cargo run --release --example make_data -- OUT_DIR
//! ```
//!
//! - `blob.obj`: an icosphere (level 5, 20,480 triangles) displaced along the normal by a
//!   few smooth waves: a closed genus-0 surface with bumps, for the README job.
//! - `patch.ply`: binary little-endian PLY, an open 40 × 30 grid patch with a raised bump
//!   (one boundary loop).
//! - `strips.ply`: ASCII PLY with a `tristrips` element (as some scanners write), strips
//!   separated by `-1` and one pair of rows stitched by degenerate triangles, plus extra
//!   per-vertex properties (`confidence`, `intensity`) and an extra element the reader
//!   must skip. OpenMesh reads no faces from it.
//! - `quads_hole.obj`: a curved 8 × 6 patch of quads and triangles with one quad missing
//!   (two boundary loops) and an unreferenced vertex.
//! - `creature.obj`: a character of several components: a bumpy head (closed, genus 0,
//!   5,120 triangles) with two ears pointing up (+y) and a snout to the front (+z), and
//!   two eyes that are separate spheres (320 triangles each).
//! - `torus.obj`: a bumpy torus (genus 1, closed, 1,920 triangles) around the z axis.
//! - `cup.obj`: an open surface: a sphere with its bottom cut away and two holes in its
//!   side (three boundary loops, ragged as a scan's), 3,885 triangles.
//! - `dirty.obj`: what scanners and modellers really write: quads, a pentagon, a fin of
//!   three faces on one edge (non-manifold edge), two triangles meeting at one vertex (a
//!   bow-tie), a face listed twice, a face with a repeated vertex, a zero-area face and
//!   unreferenced vertices.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::DVec3;
use halfedge::io::{write_obj, write_ply, PlyFormat};
use halfedge::{generators, Mesh};

/// Rounds to 6 decimals so that the text files stay small.
fn round6(p: DVec3) -> DVec3 {
    (p * 1e6).round() / 1e6
}

fn blob() -> Mesh {
    let mut mesh = generators::icosphere(5);
    for p in mesh.positions_mut() {
        let n = *p;
        let r = 1.0
            + 0.12 * (5.0 * n.x + 1.0).sin() * (4.0 * n.y + 2.0).sin() * (3.0 * n.z).sin()
            + 0.05 * (11.0 * n.x).sin() * (9.0 * n.y + 1.0).sin() * (13.0 * n.z + 2.0).sin()
            + 0.08 * (2.0 * n.y).cos();
        *p = round6(n * r);
    }
    mesh
}

fn patch() -> Mesh {
    let mut mesh = generators::grid(40, 30, 4.0, 3.0);
    for p in mesh.positions_mut() {
        let d2 = (p.x - 2.0).powi(2) + (p.y - 1.5).powi(2);
        p.z = 0.6 * (-d2 / 0.4).exp();
        *p = round6(*p);
    }
    mesh
}

/// Grid vertex `(i, j)` of an `(nx + 1) × (ny + 1)` grid.
fn grid_index(i: usize, j: usize, nx: usize) -> usize {
    i + j * (nx + 1)
}

fn strips_ply() -> String {
    let (nx, ny) = (12usize, 8usize);
    let mut vertices = String::new();
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64 / 4.0, j as f64 / 4.0);
            let z = 0.2 * (x * 1.3).sin() * (y * 1.7).cos();
            let confidence = 1.0 - 0.01 * (i + j) as f64;
            writeln!(
                vertices,
                "{x} {y} {z:.6} {confidence} {}",
                (i * 7 + j * 3) % 256
            )
            .unwrap();
        }
    }
    // One strip per row of quads: v(0, j+1), v(0, j), v(1, j+1), v(1, j), …: the first
    // triangle is counter-clockwise seen from +z, and the strip rule keeps them all so.
    let row = |j: usize| -> Vec<i64> {
        (0..=nx)
            .flat_map(|i| [grid_index(i, j + 1, nx) as i64, grid_index(i, j, nx) as i64])
            .collect()
    };
    let mut indices: Vec<i64> = Vec::new();
    // Rows 0 and 1 stitched: [A…, last(A), first(B), B…] (A has even length, so B keeps
    // its parity; the four stitching triangles are degenerate).
    let (a, b) = (row(0), row(1));
    indices.extend(&a);
    indices.push(*a.last().unwrap());
    indices.push(b[0]);
    indices.extend(&b);
    for j in 2..ny {
        indices.push(-1);
        indices.extend(row(j));
    }
    let list: Vec<String> = indices.iter().map(i64::to_string).collect();
    let n_vertices = (nx + 1) * (ny + 1);
    format!(
        "ply\nformat ascii 1.0\ncomment tristrips test mesh written by multires make_data\n\
         element vertex {n_vertices}\nproperty float x\nproperty float y\nproperty float z\n\
         property float confidence\nproperty uchar intensity\n\
         element tristrips 1\nproperty list int int vertex_indices\n\
         element camera 1\nproperty float view_px\nproperty float view_py\n\
         end_header\n{vertices}{} {}\n0.5 0.25\n",
        indices.len(),
        list.join(" ")
    )
}

fn quads_hole_obj() -> String {
    let (nx, ny) = (8usize, 6usize);
    let mut s = String::from("# quads and triangles with a hole, written by multires make_data\n");
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
            let z = 0.1 * (x - 2.0).powi(2) - 0.05 * (y - 1.5).powi(2);
            writeln!(s, "v {x} {y} {}", round6(DVec3::splat(z)).x).unwrap();
        }
    }
    s.push_str("v 10 10 10\n"); // unreferenced
    let v = |i: usize, j: usize| grid_index(i, j, nx) + 1;
    for j in 0..ny {
        for i in 0..nx {
            if (i, j) == (4, 3) {
                continue; // the hole
            }
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            if (i + 2 * j) % 5 == 0 {
                writeln!(s, "f {a} {b} {c}\nf {a} {c} {d}").unwrap();
            } else {
                writeln!(s, "f {a} {b} {c} {d}").unwrap();
            }
        }
    }
    s
}

/// Moves each vertex of `mesh` along its direction from the origin to radius
/// `radius(direction)`.
fn displace_radially(mesh: &mut Mesh, radius: impl Fn(DVec3) -> f64) {
    for p in mesh.positions_mut() {
        let d = p.normalize();
        *p = round6(d * radius(d));
    }
}

/// A bump of height `height` around `centre` (a unit direction), Gaussian in the angle
/// from it with width `width` radians.
fn bump(d: DVec3, centre: DVec3, height: f64, width: f64) -> f64 {
    let angle = d.dot(centre.normalize()).clamp(-1.0, 1.0).acos();
    height * (-(angle / width).powi(2)).exp()
}

fn creature() -> Mesh {
    let mut head = generators::icosphere(4);
    let ears = [DVec3::new(-0.45, 1.0, -0.1), DVec3::new(0.45, 1.0, -0.1)];
    displace_radially(&mut head, |d| {
        1.0 + 0.03 * (7.0 * d.x).sin() * (5.0 * d.y + 1.0).sin() * (6.0 * d.z).sin()
            + bump(d, ears[0], 0.9, 0.22)
            + bump(d, ears[1], 0.9, 0.22)
            + bump(d, DVec3::Z, 0.6, 0.12)
    });
    let eye = |x: f64| {
        let mut eye = generators::icosphere(2);
        let centre = DVec3::new(x, 0.35, 0.0);
        let centre = 1.08 * DVec3::new(centre.x, centre.y, (1.0 - x * x - 0.35 * 0.35).sqrt());
        for p in eye.positions_mut() {
            *p = round6(*p * 0.13 + centre);
        }
        eye
    };
    generators::disjoint_union(&[&head, &eye(-0.32), &eye(0.32)]).expect("three meshes")
}

fn torus() -> Mesh {
    let mut t = generators::torus(1.0, 0.4, 48, 20).expect("valid torus");
    for p in t.positions_mut() {
        let u = p.y.atan2(p.x);
        let ring = DVec3::new(u.cos(), u.sin(), 0.0);
        let tube = *p - ring;
        let wave = 1.0 + 0.15 * (5.0 * u).sin() * (tube.z * 4.0).cos();
        *p = round6(ring + tube * wave);
    }
    t
}

fn cup() -> Mesh {
    let mut sphere = generators::icosphere(4);
    displace_radially(&mut sphere, |d| {
        1.0 + 0.04 * (6.0 * d.x).sin() * (4.0 * d.z + 0.5).sin()
    });
    let holes = [DVec3::new(1.0, 0.0, 0.2), DVec3::new(-0.5, 0.8, 0.0)];
    let keep = |f| {
        let c = sphere.face_centroid(f).normalize();
        c.y > -0.55 && holes.iter().all(|h| c.dot(h.normalize()) < 0.985)
    };
    let (positions, triangles) = sphere.to_arrays();
    let kept: Vec<[u32; 3]> = sphere
        .faces()
        .zip(triangles)
        .filter(|&(f, _)| keep(f))
        .map(|(_, t)| t)
        .collect();
    // Only the vertices the kept faces use, renumbered in order.
    let mut index = vec![u32::MAX; positions.len()];
    let mut used = Vec::new();
    for t in &kept {
        for &i in t {
            if index[i as usize] == u32::MAX {
                index[i as usize] = 0;
            }
        }
    }
    for (i, slot) in index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = used.len() as u32;
            used.push(positions[i]);
        }
    }
    let kept: Vec<[u32; 3]> = kept.iter().map(|t| t.map(|i| index[i as usize])).collect();
    Mesh::from_arrays(&used, &kept)
        .expect("a sphere with holes")
        .0
}

fn dirty_obj() -> String {
    let mut s = String::from(
        "# dirty input, written by multires make_data: quads, a pentagon, a non-manifold\n\
         # edge (a fin), a bow-tie vertex, a face listed twice, a face with a repeated\n\
         # vertex, a zero-area face and unreferenced vertices\n",
    );
    let (nx, ny) = (6usize, 5usize);
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64 * 0.5, j as f64 * 0.5);
            let z = 0.15 * (x * 1.1).sin() * (y * 0.9).cos();
            writeln!(s, "v {x} {y} {}", round6(DVec3::splat(z)).x).unwrap();
        }
    }
    let n = (nx + 1) * (ny + 1);
    let v = |i: usize, j: usize| grid_index(i, j, nx) + 1;
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
            if (i, j) == (2, 2) {
                continue; // room for the pentagon
            }
            if (i, j) == (3, 2) {
                continue;
            }
            if (i + j) % 3 == 0 {
                writeln!(s, "f {a} {b} {c}\nf {a} {c} {d}").unwrap();
            } else {
                writeln!(s, "f {a} {b} {c} {d}").unwrap();
            }
        }
    }
    // A pentagon and a triangle fill the two cells left out.
    writeln!(
        s,
        "f {} {} {} {} {}",
        v(2, 2),
        v(3, 2),
        v(4, 2),
        v(4, 3),
        v(3, 3)
    )
    .unwrap();
    writeln!(s, "f {} {} {}", v(2, 2), v(3, 3), v(2, 3)).unwrap();
    // A fin: a third face on the edge v(1,1)–v(2,1), standing up.
    writeln!(s, "v 0.75 0.4 0.6").unwrap();
    writeln!(s, "f {} {} {}", v(1, 1), v(2, 1), n + 1).unwrap();
    // A bow-tie: two triangles hanging off the corner v(6,5), meeting only there.
    writeln!(
        s,
        "v 3.4 2.6 0.2\nv 3.6 2.4 0.2\nv 3.4 2.4 -0.2\nv 3.2 2.6 -0.2"
    )
    .unwrap();
    writeln!(s, "f {} {} {}", v(6, 5), n + 2, n + 3).unwrap();
    writeln!(s, "f {} {} {}", v(6, 5), n + 4, n + 5).unwrap();
    // The first face of the grid again, a face with a repeated vertex, a zero-area face.
    writeln!(s, "f {} {} {}", v(0, 0), v(1, 0), v(1, 1)).unwrap();
    writeln!(s, "f {} {} {}", v(1, 2), v(1, 2), v(2, 3)).unwrap();
    writeln!(s, "v 0.25 2.75 0\nv 0.5 2.75 0\nv 0.75 2.75 0").unwrap();
    writeln!(s, "f {} {} {}", n + 6, n + 7, n + 8).unwrap();
    // Unreferenced vertices.
    writeln!(s, "v 9 9 9\nv -9 -9 -9").unwrap();
    s
}

fn write_text(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> halfedge::Result<()> {
    let out: PathBuf = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("data"));
    std::fs::create_dir_all(&out).map_err(|source| halfedge::Error::Io {
        path: out.clone(),
        source,
    })?;
    write_obj(out.join("blob.obj"), &blob())?;
    write_ply(
        out.join("patch.ply"),
        &patch(),
        PlyFormat::BinaryLittleEndian,
    )?;
    write_text(&out.join("strips.ply"), &strips_ply());
    write_text(&out.join("quads_hole.obj"), &quads_hole_obj());
    write_obj(out.join("creature.obj"), &creature())?;
    write_obj(out.join("torus.obj"), &torus())?;
    write_obj(out.join("cup.obj"), &cup())?;
    write_text(&out.join("dirty.obj"), &dirty_obj());
    println!("wrote data meshes into {}", out.display());
    Ok(())
}
