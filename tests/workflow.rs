//! Runs the workflow example (the README's main job) on a `data/` mesh and checks its
//! outputs: the files exist, the mesh passes `check()` with the input's connectivity
//! counts, the edits moved part of the mesh and left the rest bit for bit, and the
//! pictures are not blank.

use std::path::PathBuf;
use std::process::Command;

/// The workflow example binary, built by `cargo test` next to the test binaries.
fn workflow_binary() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().unwrap().parent().unwrap();
    let path = profile_dir
        .join("examples")
        .join(format!("workflow{}", std::env::consts::EXE_SUFFIX));
    assert!(
        path.exists(),
        "{} not built (cargo test builds examples)",
        path.display()
    );
    path
}

fn png_pixel_spread(path: &PathBuf) -> f64 {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let bytes = &buf[..info.buffer_size()];
    let mean = bytes.iter().map(|&b| b as f64).sum::<f64>() / bytes.len() as f64;
    (bytes
        .iter()
        .map(|&b| (b as f64 - mean).powi(2))
        .sum::<f64>()
        / bytes.len() as f64)
        .sqrt()
}

#[test]
fn workflow_runs_on_the_data_mesh() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let input = root.join("data/blob.obj");
    let out = std::env::temp_dir().join(format!("multires-workflow-{}", std::process::id()));
    let status = Command::new(workflow_binary())
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .arg("--picture")
        .arg("320")
        .status()
        .unwrap();
    assert!(status.success());

    let (before, _) = halfedge::io::read(&input).unwrap();
    let (after, _) = halfedge::io::read(out.join("blob-edited.ply")).unwrap();
    after.check().unwrap();
    assert_eq!(
        (after.n_vertices(), after.n_edges(), after.n_faces()),
        (before.n_vertices(), before.n_edges(), before.n_faces())
    );
    // Connectivity is the input's, face for face.
    let tri = |m: &halfedge::Mesh| -> Vec<[usize; 3]> {
        m.faces()
            .map(|f| m.triangle(f).map(|v| m.vertex_index(v)))
            .collect()
    };
    assert_eq!(tri(&after), tri(&before));
    let moved = before
        .vertices()
        .filter(|&v| {
            let w = after.vertex_at(before.vertex_index(v)).unwrap();
            before.position(v) != after.position(w)
        })
        .count();
    assert!(
        moved > before.n_vertices() / 50,
        "the edits moved only {moved} vertices"
    );
    assert!(
        moved < before.n_vertices(),
        "every vertex moved: the edits leaked everywhere"
    );
    for picture in [
        "before.png",
        "after.png",
        "before-after.png",
        "coarse-edit.png",
    ] {
        let path = out.join(picture);
        assert!(png_pixel_spread(&path) > 5.0, "{picture} is blank");
    }
    std::fs::remove_dir_all(&out).ok();
}
