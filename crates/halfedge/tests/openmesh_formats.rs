//! The OpenMesh tier for OFF and STL: files generated here (from `data/`'s meshes,
//! generated ones and the shared meshes of `../shared/meshes`) are read by this kernel
//! and by OpenMesh 1.2.1 (python3, pip package `openmesh==1.2.1`, through the
//! workspace's `tests/openmesh/report.py` and `faces.py`), and the topology reports must
//! agree (vertex, edge, face and halfedge
//! counts, boundary vertices and loops, components, Euler characteristic, valence
//! histogram), and so must the triangles, in order: vertex for vertex for OFF, corner
//! position for corner position for STL (`face_points.py`; see below).
//!
//! What is comparable:
//! - **OFF** in the layout every writer uses (keyword alone on the first line, counts on
//!   the next, one vertex or face per line). OpenMesh reads no vertices when the counts
//!   are on the keyword's line and refuses a comment before the keyword, which this
//!   reader accepts: those variants are tested in `io_off.rs` only. Polygons, faces with
//!   repeated vertices (dropped by both), non-manifold faces (put on copies by both),
//!   unreferenced vertices, `COFF` colours and `NOFF` normals are compared.
//! - **STL**, ASCII and binary (a binary one with a header beginning with `solid`).
//!   OpenMesh always merges corners at the same `f32` position; this reader merges them
//!   when that closes boundaries (the rule of `Mesh::welded_seams`) and else keeps the
//!   soup. On the files compared here (closed, open, several components, genus 1,
//!   non-manifold, the shared scans) both merge and agree. They differ only on a file
//!   where merging closes nothing: OpenMesh merges and the builder puts the faces that
//!   no longer fit on copies, this reader keeps the soup. For the same triangle given
//!   twice both end with 6 vertices and 2 separate faces (`io_stl.rs` tests ours);
//!   other such files may differ in their vertex count.
//!
//! These tests are `#[ignore]`d like the workspace's `tests/openmesh*.rs`, but live in
//! the kernel so that they build with it alone: run them with `cargo test -p multires-halfedge
//! --release --test openmesh_formats -- --include-ignored` where python3 has
//! `openmesh==1.2.1` and numpy, and the shared meshes are beside the workspace for the
//! third test (`.ci/run` sets both up; the full suite's
//! `cargo test --workspace --release -- --include-ignored` runs them too).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{data_dir, temp_dir};
use halfedge::io::{self, StlFormat};
use halfedge::{generators, Mesh};
use serde_json::Value;

/// The report keys OpenMesh and this kernel both compute.
const KEYS: [&str; 9] = [
    "vertices",
    "edges",
    "faces",
    "halfedges",
    "boundary_vertices",
    "boundary_loops",
    "components",
    "euler",
    "valence_histogram",
];

fn scripts() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/openmesh")
}

/// Panics with what to install unless python3 can import `openmesh` and `numpy`.
fn require_openmesh() {
    let probe = Command::new("python3")
        .args(["-c", "import openmesh, numpy"])
        .output();
    match probe {
        Ok(out) if out.status.success() => {}
        Ok(out) => panic!(
            "the OpenMesh tier needs the python module openmesh ({}): \
             `python3 -m pip install openmesh==1.2.1 numpy` (it builds from source with cmake \
             and a C++ compiler; .ci/run installs everything)",
            String::from_utf8_lossy(&out.stderr).trim()
        ),
        Err(e) => {
            panic!("the OpenMesh tier needs python3 ({e}) with `pip install openmesh==1.2.1 numpy`")
        }
    }
}

/// One JSON line per file from `script` (report.py or faces.py).
fn run(script: &str, files: &[PathBuf]) -> Vec<Value> {
    let out = Command::new("python3")
        .arg(scripts().join(script))
        .args(files)
        .output()
        .expect("cannot start python3");
    assert!(
        out.status.success(),
        "{script} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).expect("invalid JSON"))
        .collect();
    assert_eq!(lines.len(), files.len(), "one line per file from {script}");
    lines
}

/// Our topology report.
fn our_report(mesh: &Mesh) -> Value {
    serde_json::from_str(&mesh.topology_report().to_json(None)).unwrap()
}

/// Our triangles by vertex index, each rotated to start at its smallest index (as
/// faces.py prints them).
fn our_faces(mesh: &Mesh) -> Value {
    let faces: Vec<Vec<usize>> = mesh
        .faces()
        .map(|f| {
            let t = mesh.triangle(f).map(|v| mesh.vertex_index(v));
            let k = (0..3).min_by_key(|&i| t[i]).unwrap();
            vec![t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        })
        .collect();
    serde_json::json!({ "vertices": mesh.n_vertices(), "faces": faces })
}

/// Our triangles by corner positions, each rotated to start at its smallest corner (as
/// face_points.py prints them).
fn our_face_points(mesh: &Mesh) -> Value {
    let faces: Vec<Vec<[f64; 3]>> = mesh
        .faces()
        .map(|f| {
            let t = mesh.triangle(f).map(|v| mesh.position(v).to_array());
            let k = (0..3)
                .min_by(|&a, &b| t[a].partial_cmp(&t[b]).unwrap())
                .unwrap();
            vec![t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        })
        .collect();
    serde_json::json!({ "faces": faces })
}

/// Corner positions of face_points.py's or [`our_face_points`]'s JSON as `f32` (what STL
/// holds; JSON's decimals are parsed back within an `f64` ulp, which `f32` rounding
/// removes).
fn as_f32(faces: &Value) -> Vec<Vec<[f32; 3]>> {
    faces["faces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            t.as_array()
                .unwrap()
                .iter()
                .map(|c| {
                    let c = c.as_array().unwrap();
                    std::array::from_fn(|i| c[i].as_f64().unwrap() as f32)
                })
                .collect()
        })
        .collect()
}

/// How the triangles are compared.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Faces {
    /// By vertex index: formats whose vertices are the file's (OFF).
    ByIndex,
    /// By corner positions: STL, where OpenMesh numbers the merged vertices in the order
    /// it meets them, copies for non-manifold faces among them, while this reader puts
    /// such copies after the merged vertices (as for every format).
    ByPosition,
}

/// Reads every file with this kernel and with OpenMesh and lists what differs.
fn compare(files: &[PathBuf], by: Faces) -> Vec<String> {
    let reports = run("report.py", files);
    let faces = match by {
        Faces::ByIndex => run("faces.py", files),
        Faces::ByPosition => run("face_points.py", files),
    };
    let mut problems = Vec::new();
    for ((file, theirs), their_faces) in files.iter().zip(&reports).zip(&faces) {
        let name = file.file_name().unwrap().to_string_lossy();
        let (mesh, _) = io::read(file).unwrap_or_else(|e| panic!("{e}"));
        mesh.check().unwrap();
        let report = our_report(&mesh);
        for k in KEYS {
            if report[k] != theirs[k] {
                problems.push(format!(
                    "{name}: {k}: ours {} / OpenMesh {}",
                    report[k], theirs[k]
                ));
            }
        }
        let our_faces = match by {
            Faces::ByIndex => our_faces(&mesh),
            Faces::ByPosition => our_face_points(&mesh),
        };
        let same = match by {
            Faces::ByIndex => our_faces == *their_faces,
            Faces::ByPosition => as_f32(&our_faces) == as_f32(their_faces),
        };
        if !same {
            let a = our_faces["faces"].as_array().unwrap();
            let b = their_faces["faces"].as_array().unwrap();
            let first = (0..a.len().min(b.len())).find(|&i| a[i] != b[i]);
            problems.push(format!(
                "{name}: the triangles differ ({} / {} faces, the first at {first:?}: {:?} / {:?})",
                a.len(),
                b.len(),
                first.map(|i| &a[i]),
                first.map(|i| &b[i])
            ));
        }
        assert!(
            theirs["faces"].as_u64().unwrap() > 0,
            "{name}: OpenMesh read no faces"
        );
    }
    problems
}

/// The positions and polygons of an OBJ file of `data/`, as they are.
fn obj_polygons(name: &str) -> (Vec<String>, Vec<Vec<usize>>) {
    let text = std::fs::read_to_string(data_dir().join(name)).unwrap();
    let mut positions = Vec::new();
    let mut polygons = Vec::new();
    for line in text.lines() {
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => positions.push(tokens.take(3).collect::<Vec<_>>().join(" ")),
            Some("f") => polygons.push(
                tokens
                    .map(|t| t.split('/').next().unwrap().parse::<usize>().unwrap() - 1)
                    .collect(),
            ),
            _ => {}
        }
    }
    (positions, polygons)
}

/// An OFF file of an OBJ's polygons: plain, `COFF` (colours after vertices and faces)
/// or `NOFF` (normals after vertices).
fn off_of(name: &str, keyword: &str) -> String {
    let (positions, polygons) = obj_polygons(name);
    let mut text = format!("{keyword}\n{} {} 0\n", positions.len(), polygons.len());
    for (i, p) in positions.iter().enumerate() {
        match keyword {
            "COFF" => text.push_str(&format!("{p} {} 128 0 255\n", i % 256)),
            "NOFF" => text.push_str(&format!("{p} 0 0 1\n")),
            _ => text.push_str(&format!("{p}\n")),
        }
    }
    for (k, f) in polygons.iter().enumerate() {
        let indices: Vec<String> = f.iter().map(usize::to_string).collect();
        text.push_str(&format!("{} {}", f.len(), indices.join(" ")));
        if keyword == "COFF" && k % 2 == 0 {
            text.push_str(" 255 0 0");
        }
        text.push('\n');
    }
    text
}

const DATA: [&str; 6] = [
    "blob.obj",
    "creature.obj",
    "cup.obj",
    "torus.obj",
    "quads_hole.obj",
    "dirty.obj",
];

#[test]
#[ignore = "OpenMesh tier: needs python3 with openmesh==1.2.1 and numpy (pip; builds with cmake and a C++ compiler); run with cargo test -p multires-halfedge --release --test openmesh_formats -- --include-ignored (.ci/run installs them)"]
fn off_files_read_as_openmesh_reads_them() {
    require_openmesh();
    let dir = temp_dir("openmesh-off");
    let mut files = Vec::new();
    for name in DATA {
        for keyword in ["OFF", "COFF", "NOFF"] {
            let path = dir.join(format!("{}-{keyword}.off", name.trim_end_matches(".obj")));
            std::fs::write(&path, off_of(name, keyword)).unwrap();
            files.push(path);
        }
    }
    // What our writer writes.
    for (name, mesh) in [
        ("icosphere3", generators::icosphere(3)),
        ("torus", generators::torus(1.0, 0.3, 32, 16).unwrap()),
        ("grid", generators::grid(9, 7, 1.0, 1.0)),
    ] {
        let path = dir.join(format!("written-{name}.off"));
        io::write_off(&path, &mesh).unwrap();
        files.push(path);
    }
    let problems = compare(&files, Faces::ByIndex);
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        problems.is_empty(),
        "OFF topology differs from OpenMesh:\n{}",
        problems.join("\n")
    );
}

#[test]
#[ignore = "OpenMesh tier: needs python3 with openmesh==1.2.1 and numpy (pip; builds with cmake and a C++ compiler); run with cargo test -p multires-halfedge --release --test openmesh_formats -- --include-ignored (.ci/run installs them)"]
fn stl_files_read_as_openmesh_reads_them() {
    require_openmesh();
    let dir = temp_dir("openmesh-stl");
    let mut files = Vec::new();
    let mut meshes: Vec<(String, Mesh)> = DATA
        .iter()
        .map(|name| {
            let (mesh, _) = io::read(data_dir().join(name)).unwrap();
            (name.trim_end_matches(".obj").to_string(), mesh)
        })
        .collect();
    meshes.push(("torus".into(), generators::torus(1.0, 0.3, 32, 16).unwrap()));
    meshes.push(("grid".into(), generators::grid(9, 7, 1.0, 1.0)));
    for (name, mesh) in &meshes {
        for (format, tag) in [(StlFormat::Binary, "binary"), (StlFormat::Ascii, "ascii")] {
            let path = dir.join(format!("{name}-{tag}.stl"));
            io::write_stl(&path, mesh, format).unwrap();
            files.push(path);
        }
    }
    // A binary file whose header begins with `solid`, as many exporters write them.
    let mut bytes = Vec::new();
    io::write_stl_to(&mut bytes, &meshes[0].1, StlFormat::Binary).unwrap();
    bytes[..80].fill(b' ');
    bytes[..20].copy_from_slice(b"solid blob, binary  ");
    let path = dir.join("blob-binary-solid.stl");
    std::fs::write(&path, bytes).unwrap();
    files.push(path);
    let problems = compare(&files, Faces::ByPosition);
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        problems.is_empty(),
        "STL topology differs from OpenMesh:\n{}",
        problems.join("\n")
    );
}

/// The shared meshes (scans and models, some with holes, several components or
/// non-manifold parts), written as OFF and as binary STL, read alike by both.
#[test]
#[ignore = "OpenMesh tier: needs python3 with openmesh==1.2.1 and numpy (pip; builds with cmake and a C++ compiler) and ../shared/meshes (or MULTIRES_MESHES); run with cargo test -p multires-halfedge --release --test openmesh_formats -- --include-ignored (.ci/run installs them)"]
fn shared_meshes_as_off_and_stl_read_as_openmesh_reads_them() {
    require_openmesh();
    let shared = common::shared_meshes();
    let dir = temp_dir("openmesh-shared");
    let (mut off, mut stl) = (Vec::new(), Vec::new());
    let mut names: Vec<PathBuf> = std::fs::read_dir(&shared)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("obj" | "ply")))
        .collect();
    names.sort();
    assert!(
        names.len() >= 9,
        "expected the shared meshes, found {names:?}"
    );
    for path in names {
        let (mesh, _) = io::read(&path).unwrap();
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let file = dir.join(format!("{stem}.off"));
        io::write_off(&file, &mesh).unwrap();
        off.push(file);
        let file = dir.join(format!("{stem}.stl"));
        io::write_stl(&file, &mesh, StlFormat::Binary).unwrap();
        stl.push(file);
    }
    let mut problems = compare(&off, Faces::ByIndex);
    problems.extend(compare(&stl, Faces::ByPosition));
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        problems.is_empty(),
        "topology differs from OpenMesh:\n{}",
        problems.join("\n")
    );
}
