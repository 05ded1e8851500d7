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

fn write_text(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

fn main() -> halfedge::Result<()> {
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
    println!("wrote data meshes into {}", out.display());
    Ok(())
}
