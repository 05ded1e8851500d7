//! Runs the workflow example (the README's main job) on a `data/` mesh and checks its
//! outputs: the files exist, the mesh passes `check()` with the input's connectivity
//! counts, the edits moved part of the mesh and left the rest bit for bit, and the
//! pictures are not blank. Then on every mesh of `data/` (closed, open, several
//! components, genus 1, quads, dirty input) with its defaults, and — in the real-mesh
//! tier — on every shared mesh: it must finish, and say why when it leaves a step out.

use std::path::PathBuf;
use std::process::Command;

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

/// Runs the workflow with its defaults on `input` into a fresh folder; returns the
/// folder and the printed table.
fn run_workflow(input: &std::path::Path, tag: &str) -> (PathBuf, String) {
    let out = std::env::temp_dir().join(format!("multires-workflow-{tag}-{}", std::process::id()));
    let output = Command::new(testkit::example_binary("workflow"))
        .arg(input)
        .arg("--out")
        .arg(&out)
        .arg("--picture")
        .arg("160")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    assert!(
        output.status.success(),
        "{}: {}\n{stdout}",
        input.display(),
        String::from_utf8_lossy(&output.stderr)
    );
    (out, stdout)
}

/// The workflow's result read back: same connectivity as the input (welded, when the
/// job welded it), valid, pictures not blank; a step left out is explained in a note naming a flag.
fn check_run(input: &std::path::Path, out: &std::path::Path, stdout: &str) -> usize {
    let (before, _) = halfedge::io::read(input).unwrap();
    // A mesh the job welded (its note says so) is compared welded.
    let before = if stdout.contains("note: welded") {
        before.welded(0.0).unwrap().0
    } else {
        before
    };
    let stem = input.file_stem().unwrap().to_str().unwrap();
    let (after, _) = halfedge::io::read(out.join(format!("{stem}-edited.ply"))).unwrap();
    after.check().unwrap();
    assert_eq!(
        (after.n_vertices(), after.n_faces()),
        (before.n_vertices(), before.n_faces()),
        "{}",
        input.display()
    );
    for picture in ["before-after.png", "coarse-edit.png"] {
        assert!(
            png_pixel_spread(&out.join(picture)) > 5.0,
            "{picture} is blank"
        );
    }
    for line in stdout.lines().filter(|l| l.contains("skipped:")) {
        if !line.contains("--skip") {
            assert!(
                stdout
                    .lines()
                    .any(|n| n.starts_with("note:") && n.contains("--")),
                "{}: a step was left out without a note naming a flag:\n{stdout}",
                input.display()
            );
        }
    }
    before
        .vertices()
        .filter(|&v| {
            before.position(v) != after.position(after.vertex_at(before.vertex_index(v)).unwrap())
        })
        .count()
}

#[test]
fn workflow_runs_with_its_defaults_on_every_data_mesh() {
    let data = testkit::data_dir();
    let mut edited = 0;
    for name in [
        "blob.obj",
        "creature.obj",
        "torus.obj",
        "cup.obj",
        "patch.ply",
        "quads_hole.obj",
        "strips.ply",
        "dirty.obj",
    ] {
        let input = data.join(name);
        let (out, stdout) = run_workflow(&input, name);
        let moved = check_run(&input, &out, &stdout);
        // Meshes with room for the edits get all three.
        if ["blob.obj", "creature.obj", "torus.obj", "cup.obj"].contains(&name) {
            for step in ["Lee drag", "B&K rotate", "taper"] {
                let row = stdout.lines().find(|l| l.starts_with(step)).unwrap();
                assert!(!row.contains("skipped"), "{name}: {row}\n{stdout}");
            }
            assert!(moved > 0, "{name}: nothing moved");
        }
        // Every one has a sub-mesh to taper: a closed plane section, or on the open
        // meshes the part beyond the plane as a vertex mask.
        let row = stdout
            .lines()
            .find(|l| l.starts_with("taper"))
            .unwrap_or_else(|| panic!("{name}: no taper step\n{stdout}"));
        assert!(!row.contains("skipped"), "{name}: {row}\n{stdout}");
        edited += usize::from(moved > 0);
        std::fs::remove_dir_all(&out).ok();
    }
    assert!(edited >= 6, "only {edited} data meshes were edited");
}

#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -- --include-ignored"]
fn workflow_runs_with_its_defaults_on_every_shared_mesh() {
    let dir = testkit::shared_meshes();
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj" || e == "ply"))
        .collect();
    names.sort();
    assert!(names.len() >= 9, "{names:?}");
    for input in names {
        let tag = input.file_name().unwrap().to_str().unwrap().to_owned();
        let (out, stdout) = run_workflow(&input, &tag);
        let moved = check_run(&input, &out, &stdout);
        assert!(moved > 0, "{tag}: nothing moved\n{stdout}");
        std::fs::remove_dir_all(&out).ok();
    }
}

#[test]
fn workflow_runs_on_the_data_mesh() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let input = root.join("data/blob.obj");
    let out = std::env::temp_dir().join(format!("multires-workflow-{}", std::process::id()));
    let output = Command::new(testkit::example_binary("workflow"))
        .arg(&input)
        .arg("--out")
        .arg(&out)
        .arg("--picture")
        .arg("320")
        .output()
        .unwrap();
    assert!(output.status.success());
    // The B&K handle, rotated at the coarse level in the hierarchy, is at full resolution
    // the rigid image of its input vertices (the refine row says within what).
    let table = String::from_utf8_lossy(&output.stdout);
    let within: f64 = table
        .split("rigid image within ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("no handle landing in the table:\n{table}"));
    assert!(
        within <= 1e-9,
        "the handle is off by {within} of the diagonal"
    );

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

#[test]
fn workflow_edits_the_main_body_when_a_loose_part_is_furthest_out() {
    // A body and, furthest along -x and +z, a loose part small enough for the B&K
    // handle to cover whole (as a figure's fingernails): the handle and the Lee area
    // go on the body, and every step is made.
    let mut body = halfedge::generators::icosphere(4);
    let loose = halfedge::generators::icosphere(1);
    let offset = body.n_vertices();
    let mut positions: Vec<glam::DVec3> = body.positions().to_vec();
    positions.extend(
        loose
            .positions()
            .iter()
            .map(|&p| 0.05 * p + glam::DVec3::new(-1.3, 0.0, 0.9)),
    );
    let mut triangles: Vec<[u32; 3]> = body
        .faces()
        .map(|f| body.triangle(f).map(|v| body.vertex_index(v) as u32))
        .collect();
    triangles.extend(loose.faces().map(|f| {
        loose
            .triangle(f)
            .map(|v| (offset + loose.vertex_index(v)) as u32)
    }));
    body = halfedge::Mesh::from_polygons(&positions, triangles.iter().map(|t| t.to_vec()))
        .unwrap()
        .0;
    let input = std::env::temp_dir().join(format!("multires-loose-{}.obj", std::process::id()));
    halfedge::io::write(&input, &body).unwrap();
    let (out, stdout) = run_workflow(&input, "loose");
    check_run(&input, &out, &stdout);
    for step in ["Lee drag", "B&K rotate", "taper"] {
        let row = stdout.lines().find(|l| l.starts_with(step)).unwrap();
        assert!(!row.contains("skipped"), "{row}\n{stdout}");
    }
    assert!(stdout.contains("largest component"), "{stdout}");
    std::fs::remove_dir_all(&out).ok();
    std::fs::remove_file(&input).ok();
}

#[test]
fn workflow_welds_a_triangle_soup_and_edits_it() {
    // A data mesh written as a soup (every face on its own copies of its corners, as
    // STL exports are): nothing could be simplified or edited across its cuts. The job
    // welds it back, says so, and makes every edit; with --weld off it keeps the soup.
    let data = testkit::data_dir().join("blob.obj");
    let (mesh, _) = halfedge::io::read(&data).unwrap();
    let (corners, faces) = halfedge::generators::triangle_soup(&mesh);
    let (soup, _) = halfedge::Mesh::from_arrays(&corners, &faces).unwrap();
    let input = std::env::temp_dir().join(format!("multires-soup-{}.obj", std::process::id()));
    halfedge::io::write(&input, &soup).unwrap();
    let (out, stdout) = run_workflow(&input, "soup");
    assert!(stdout.contains("note: welded"), "{stdout}");
    let moved = check_run(&input, &out, &stdout);
    assert!(moved > 0, "{stdout}");
    let stem = input.file_stem().unwrap().to_str().unwrap();
    let (after, _) = halfedge::io::read(out.join(format!("{stem}-edited.ply"))).unwrap();
    assert_eq!(
        (after.n_vertices(), after.n_faces()),
        (mesh.n_vertices(), mesh.n_faces())
    );
    for step in ["Lee drag", "B&K rotate", "taper"] {
        let row = stdout.lines().find(|l| l.starts_with(step)).unwrap();
        assert!(!row.contains("skipped"), "{row}\n{stdout}");
    }
    std::fs::remove_dir_all(&out).ok();
    let kept = Command::new(testkit::example_binary("workflow"))
        .arg(&input)
        .args(["--weld", "off", "--out"])
        .arg(&out)
        .args(["--picture", "160"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&kept.stdout);
    assert!(
        kept.status.success() && !stdout.contains("note: welded"),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!("{} component(s)", soup.n_faces())),
        "{stdout}"
    );
    std::fs::remove_dir_all(&out).ok();
    std::fs::remove_file(&input).ok();
}

/// The library job keeps one full-resolution mesh at a time, and says so truthfully: its
/// `original` (made again at the end) is the loaded mesh bit for bit — the same triangles
/// in the same face slots, the same positions — its pictures' copies of the edited level
/// are compact (no tombstone slots) with that level's faces, and every step that ran
/// reports a peak within the job's (on Linux, where `/proc` says).
#[test]
fn workflow_library_job_gives_the_input_back_and_reports_its_peaks() {
    use multires::load::{self, Weld};
    use multires::progress::Silent;
    use multires::workflow::{self, WorkflowOptions};
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/blob.obj");
    let loaded = load::load(&path, Weld::Auto, &mut Silent).unwrap();
    let input = loaded.mesh.clone();
    let done = workflow::run(loaded, &path, &WorkflowOptions::default(), &mut Silent).unwrap();
    let faces = |m: &halfedge::Mesh| -> Vec<(usize, [usize; 3])> {
        m.faces()
            .map(|f| (m.face_index(f), m.triangle(f).map(|v| m.vertex_index(v))))
            .collect()
    };
    assert_eq!(faces(&done.original), faces(&input));
    assert_eq!(done.original.vertex_slots(), input.vertex_slots());
    assert!(input
        .vertices()
        .all(|v| done.original.position(v).to_array() == input.position(v).to_array()));
    assert!(done.original.positions() != done.result.positions());
    for coarse in [&done.coarse_before, &done.coarse_after] {
        coarse.check().unwrap();
        assert_eq!(coarse.vertex_slots(), coarse.n_vertices());
        assert_eq!(coarse.face_slots(), coarse.n_faces());
        assert!(coarse.n_faces() < input.n_faces());
    }
    assert_eq!(done.coarse_before.n_faces(), done.coarse_after.n_faces());
    if cfg!(target_os = "linux") && multires::memory::peak_resident_bytes().is_some() {
        let peak = done.peak_bytes().unwrap();
        for row in done
            .rows
            .iter()
            .filter(|r| !r.detail.starts_with("skipped"))
        {
            let p = row
                .peak_bytes
                .unwrap_or_else(|| panic!("{} has no peak", row.step));
            assert!(p > 0 && p <= peak, "{}: {p} of {peak}", row.step);
        }
        assert!(done.table().contains("peak GB"));
    }
}
