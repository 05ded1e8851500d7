//! The OpenMesh comparison: every mesh in `../shared/meshes/` and in `data/` is loaded
//! by this kernel and by OpenMesh (`tests/openmesh/report.py`, pip package
//! `openmesh==1.2.1`), and the topology reports must agree: vertex, edge, face and
//! halfedge counts, boundary vertices and loops, components, Euler characteristic and the
//! valence histogram. OpenMesh cannot read PLY `tristrips` (it reports no faces); there
//! the vertex counts must agree and this kernel must find faces.
//!
//! Also: OpenMesh reads the files this kernel writes (OBJ, ASCII PLY, binary PLY) with
//! the same counts as the mesh that was written; and files whose faces repeat vertex
//! indices, generated here, give the very same triangles with both readers
//! (`tests/openmesh/faces.py`).
//!
//! These tests are the OpenMesh tier (`#[ignore]`d): run them with `cargo test --release
//! -- --include-ignored` where python3 has `openmesh==1.2.1` and the shared meshes are
//! beside the workspace (`.ci/run` sets both up); without them they fail and say what to
//! install.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use halfedge::io::{self, PlyFormat};
use halfedge::{generators, Mesh};
use serde_json::Value;
use testkit::openmesh::KEYS;
use testkit::{shared_meshes, workspace_root as root};

fn mesh_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("obj" | "ply")))
        .collect();
    files.sort();
    files
}

/// Runs the OpenMesh report script on the files (one python process) while `ours`
/// computes this kernel's reports, and returns both.
fn reports(files: &[PathBuf], ours: impl FnOnce() -> Vec<Value>) -> (Vec<Value>, Vec<Value>) {
    let child = Command::new("python3")
        .arg(root().join("tests/openmesh/report.py"))
        .args(files)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot start python3");
    let ours = ours();
    let out = child.wait_with_output().expect("python3 did not finish");
    assert!(
        out.status.success(),
        "report.py failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let theirs: Vec<Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).expect("report.py printed invalid JSON"))
        .collect();
    assert_eq!(theirs.len(), files.len(), "one OpenMesh report per file");
    (ours, theirs)
}

/// Our report as the `topology` example prints it, parsed back (so the JSON is checked too).
fn our_report(mesh: &Mesh, build: Option<&halfedge::BuildReport>) -> Value {
    serde_json::from_str(&mesh.topology_report().to_json(build))
        .expect("TopologyReport::to_json printed invalid JSON")
}

fn differences(name: &str, ours: &Value, theirs: &Value) -> Vec<String> {
    KEYS.iter()
        .filter(|k| ours[**k] != theirs[**k])
        .map(|k| format!("{name}: {k}: ours {} / OpenMesh {}", ours[*k], theirs[*k]))
        .collect()
}

fn has_tristrips(path: &Path) -> bool {
    let bytes = std::fs::read(path).unwrap();
    let header_end = bytes
        .windows(10)
        .position(|w| w == b"end_header")
        .unwrap_or(0);
    String::from_utf8_lossy(&bytes[..header_end]).contains("element tristrips")
}

#[test]
#[ignore = "OpenMesh tier: needs python3 with openmesh==1.2.1 and numpy (pip; builds with cmake and a C++ compiler) and ../shared/meshes; run with cargo test --release -- --include-ignored (.ci/run installs them)"]
fn topology_matches_openmesh_on_every_mesh() {
    testkit::openmesh::require_openmesh();
    let mut files = mesh_files(&shared_meshes());
    assert!(
        files.len() >= 9,
        "expected the shared meshes, found {files:?}"
    );
    files.extend(mesh_files(&root().join("data")));
    let (ours, theirs) = reports(&files, || {
        files
            .iter()
            .map(|f| {
                let (mesh, build) = io::read(f).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
                mesh.check().unwrap();
                our_report(&mesh, Some(&build))
            })
            .collect()
    });
    let mut problems = Vec::new();
    let mut strips = 0;
    for ((file, ours), theirs) in files.iter().zip(&ours).zip(&theirs) {
        let name = file.file_name().unwrap().to_string_lossy();
        if has_tristrips(file) {
            // OpenMesh reads the vertices but no faces from tristrips.
            strips += 1;
            assert_eq!(
                theirs["faces"], 0,
                "{name}: OpenMesh learned to read tristrips"
            );
            assert_eq!(ours["vertices"], theirs["vertices"], "{name}: vertex count");
            assert!(
                ours["faces"].as_u64().unwrap() > 0,
                "{name}: no faces from tristrips"
            );
            continue;
        }
        problems.extend(differences(&name, ours, theirs));
    }
    assert!(strips >= 1, "data/ should hold a tristrips PLY");
    assert!(
        problems.is_empty(),
        "topology differs from OpenMesh:\n{}",
        problems.join("\n")
    );
}

#[test]
#[ignore = "OpenMesh tier: needs python3 with openmesh==1.2.1 and numpy (pip; builds with cmake and a C++ compiler) and ../shared/meshes; run with cargo test --release -- --include-ignored (.ci/run installs them)"]
fn openmesh_reads_what_we_write() {
    testkit::openmesh::require_openmesh();
    let shared = shared_meshes();
    let mut meshes: Vec<(String, Mesh)> = ["suzanne.obj", "stanford-bunny.obj", "horse.ply"]
        .iter()
        .map(|name| (name.to_string(), io::read(shared.join(name)).unwrap().0))
        .collect();
    meshes.push((
        "strips.ply".into(),
        io::read(root().join("data/strips.ply")).unwrap().0,
    ));
    meshes.push(("icosphere3".into(), generators::icosphere(3)));

    let dir = std::env::temp_dir().join(format!("multires-openmesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut files = Vec::new();
    let mut expected = Vec::new();
    for (i, (name, mesh)) in meshes.iter().enumerate() {
        let report = our_report(mesh, None);
        let stem = dir.join(format!("{i}-{}", name.replace('.', "_")));
        let obj = stem.with_extension("obj");
        io::write_obj(&obj, mesh).unwrap();
        let ascii = stem.with_extension("ascii.ply");
        io::write_ply(&ascii, mesh, PlyFormat::Ascii).unwrap();
        let binary = stem.with_extension("ply");
        io::write_ply(&binary, mesh, PlyFormat::BinaryLittleEndian).unwrap();
        for file in [obj, ascii, binary] {
            files.push(file);
            expected.push(report.clone());
        }
    }
    let (_, theirs) = reports(&files, Vec::new);
    let problems: Vec<String> = files
        .iter()
        .zip(&expected)
        .zip(&theirs)
        .flat_map(|((file, ours), theirs)| {
            differences(&file.file_name().unwrap().to_string_lossy(), ours, theirs)
        })
        .collect();
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        problems.is_empty(),
        "OpenMesh reads our files differently:\n{}",
        problems.join("\n")
    );
}

/// Faces that name a vertex more than once, in every pattern (a repeat next to itself, at
/// the ends, in the middle, several, everything the same) and on top of each other so that
/// some become non-manifold: written as OBJ, ASCII PLY and binary PLY, our reader and
/// OpenMesh's must give the same triangles in the same order. OpenMesh's OBJ reader drops
/// the repeats of a face (`f 1 2 4 2 3` is `1 2 4 3`); its PLY reader drops such faces.
/// The OBJ file also has polylines (`l`), which neither reads as faces.
#[test]
#[ignore = "OpenMesh tier: needs python3 with openmesh==1.2.1 and numpy (pip; builds with cmake and a C++ compiler); run with cargo test --release -- --include-ignored (.ci/run installs them)"]
fn repeated_face_indices_read_as_openmesh_reads_them() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(14);
    let n = 6usize;
    let positions: Vec<[f64; 3]> = (0..n * n)
        .map(|i| [(i % n) as f64, (i / n) as f64, ((i * 7) % 5) as f64 * 0.1])
        .collect();
    let mut polygons: Vec<Vec<u32>> = vec![
        vec![0, 1, 1, 7],
        vec![1, 2, 8, 1],
        vec![2, 3, 2, 9],
        vec![3, 4, 10, 10, 3],
        vec![4, 5, 11, 5, 10],
        vec![6, 6, 7],
        vec![12, 13, 12],
        vec![14, 14, 14],
        vec![15, 16, 22, 16, 21, 15],
    ];
    for _ in 0..60 {
        // A quad or triangle of the grid, with repeats put in at random.
        let (x, y) = (rng.random_range(0..n - 1), rng.random_range(0..n - 1));
        let c = (x + y * n) as u32;
        let mut p = if rng.random_bool(0.5) {
            vec![c, c + 1, c + 1 + n as u32, c + n as u32]
        } else {
            vec![c, c + 1, c + 1 + n as u32]
        };
        for _ in 0..rng.random_range(0..3) {
            let from = rng.random_range(0..p.len());
            let to = rng.random_range(0..=p.len());
            p.insert(to, p[from]);
        }
        if rng.random_bool(0.2) {
            p.reverse();
        }
        polygons.push(p);
    }
    let dir = std::env::temp_dir().join(format!("multires-repeats-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let obj = dir.join("repeats.obj");
    let mut text = String::new();
    for p in &positions {
        text.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
    }
    for f in &polygons {
        let indices: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        text.push_str(&format!("f {}\n", indices.join(" ")));
    }
    // Polylines: OpenMesh ignores them.
    text.push_str("l 1 2 3\nl 4 5 11 10\n");
    std::fs::write(&obj, text).unwrap();
    let mut files = vec![obj];
    for (name, format) in [("ascii", "ascii"), ("binary", "binary_little_endian")] {
        let mut bytes = format!(
            "ply\nformat {format} 1.0\nelement vertex {}\nproperty double x\nproperty double y\n\
             property double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
            positions.len(),
            polygons.len()
        )
        .into_bytes();
        for p in &positions {
            if name == "ascii" {
                bytes.extend(format!("{} {} {}\n", p[0], p[1], p[2]).bytes());
            } else {
                p.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
            }
        }
        for f in &polygons {
            if name == "ascii" {
                let indices: Vec<String> = f.iter().map(u32::to_string).collect();
                bytes.extend(format!("{} {}\n", f.len(), indices.join(" ")).bytes());
            } else {
                bytes.push(f.len() as u8);
                f.iter()
                    .for_each(|&i| bytes.extend((i as i32).to_le_bytes()));
            }
        }
        let file = dir.join(format!("repeats-{name}.ply"));
        std::fs::write(&file, bytes).unwrap();
        files.push(file);
    }
    let out = Command::new("python3")
        .arg(root().join("tests/openmesh/faces.py"))
        .args(&files)
        .output()
        .expect("cannot start python3");
    assert!(
        out.status.success(),
        "faces.py failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let theirs: Vec<Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(theirs.len(), files.len());
    let mut kept = [0usize; 2];
    for (file, theirs) in files.iter().zip(&theirs) {
        let (mesh, _) = io::read(file).unwrap();
        mesh.check().unwrap();
        let faces: Vec<Vec<usize>> = mesh
            .faces()
            .map(|f| {
                let t: Vec<usize> = mesh
                    .triangle(f)
                    .iter()
                    .map(|&v| mesh.vertex_index(v))
                    .collect();
                let k = (0..3).min_by_key(|&i| t[i]).unwrap();
                vec![t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect();
        let ours = serde_json::json!({ "vertices": mesh.n_vertices(), "faces": faces });
        assert_eq!(&ours, theirs, "{}", file.display());
        kept[usize::from(file.extension().unwrap() == "ply")] = faces.len();
    }
    std::fs::remove_dir_all(&dir).ok();
    // OBJ keeps the faces that have three distinct vertices after dropping repeats.
    assert!(kept[0] > kept[1], "{kept:?}");
}
