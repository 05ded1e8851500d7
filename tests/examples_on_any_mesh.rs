//! The single-method examples (`area_edit`, `blend_edit`) run with their defaults on
//! meshes whose first choice does not fit: a flat open mesh (every extreme vertex on the
//! boundary, no plane loop closes), a body with a loose part furthest out, and the data
//! folder's open and dirty meshes. Each adapts (smaller area, other vertex, smaller loops,
//! edge-path balls), says so in a note, and writes a valid mesh.

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::DVec3;
use halfedge::{generators, Mesh};

/// A flat open 2D mesh with a protruding tongue: a 30 × 12 grid and a 6 × 4 strip.
fn flat_with_tongue() -> Mesh {
    let grid = generators::grid(30, 12, 3.0, 1.2);
    let mut tongue = generators::grid(6, 4, 0.6, 0.4);
    for p in tongue.positions_mut() {
        *p += DVec3::new(3.0, 0.4, 0.0);
    }
    // Weld the tongue onto the grid's right side through the shared positions.
    let (mut positions, mut triangles) = grid.to_arrays();
    let (tp, tt) = tongue.to_arrays();
    let mut index = Vec::with_capacity(tp.len());
    for p in &tp {
        let found = positions
            .iter()
            .position(|q| DVec3::from_array(*q).distance(DVec3::from_array(*p)) < 1e-9);
        index.push(found.unwrap_or_else(|| {
            positions.push(*p);
            positions.len() - 1
        }) as u32);
    }
    triangles.extend(tt.iter().map(|t| t.map(|i| index[i as usize])));
    Mesh::from_arrays(&positions, &triangles).unwrap().0
}

/// A bumpy sphere and, furthest along −x and +z, a small loose sphere.
fn body_and_loose_part() -> Mesh {
    let mut body = generators::icosphere(4);
    for p in body.positions_mut() {
        *p *= 1.0 + 0.05 * (5.0 * p.y).sin();
    }
    let mut loose = generators::icosphere(1);
    for p in loose.positions_mut() {
        *p = 0.05 * *p + DVec3::new(-1.3, 0.0, 1.3);
    }
    generators::disjoint_union(&[&body, &loose]).unwrap()
}

/// Runs `example` on `input` with its defaults (plus the output flag), asserts success,
/// and returns stdout and the mesh written.
fn run(example: &str, input: &Path, output_flag: &str, tag: &str) -> (String, Mesh) {
    let out = std::env::temp_dir().join(format!(
        "multires-{example}-{tag}-{}.obj",
        std::process::id()
    ));
    let result = Command::new(testkit::example_binary(example))
        .arg(input)
        .arg(output_flag)
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&result.stdout).into_owned();
    assert!(
        result.status.success(),
        "{example} on {}: {}\n{stdout}",
        input.display(),
        String::from_utf8_lossy(&result.stderr)
    );
    let (mesh, _) = halfedge::io::read(&out).unwrap();
    mesh.check().unwrap();
    std::fs::remove_file(&out).ok();
    (stdout, mesh)
}

fn write_temp(mesh: &Mesh, tag: &str) -> PathBuf {
    let path =
        std::env::temp_dir().join(format!("multires-input-{tag}-{}.obj", std::process::id()));
    halfedge::io::write(&path, mesh).unwrap();
    path
}

#[test]
fn area_and_blend_edits_adapt_to_flat_open_and_loose_meshes() {
    let flat = write_temp(&flat_with_tongue(), "flat");
    let loose = write_temp(&body_and_loose_part(), "loose");
    let data = testkit::data_dir();
    let inputs = [
        (flat.clone(), "flat"),
        (loose.clone(), "loose"),
        (data.join("strips.ply"), "strips"),
        (data.join("quads_hole.obj"), "quads"),
        (data.join("patch.ply"), "patch"),
    ];
    for (input, tag) in &inputs {
        let (before, _) = halfedge::io::read(input).unwrap();
        // quads_hole (64 vertices around a hole) has no vertex two rings from its
        // boundary: no editing area fits, and area_edit says so (below).
        if *tag != "quads" {
            let (stdout, after) = run("area_edit", input, "--output", tag);
            assert_eq!(after.n_vertices(), before.n_vertices(), "{tag}\n{stdout}");
            assert!(stdout.contains("dragged vertex"), "{tag}\n{stdout}");
        }
        let (stdout, after) = run("blend_edit", input, "--out", tag);
        assert!(after.n_vertices() >= before.n_vertices(), "{tag}\n{stdout}");
        assert!(stdout.contains("regions ("), "{tag}\n{stdout}");
    }
    // On the flat mesh the first choices do not fit, and the notes say what was used.
    let (stdout, _) = run("area_edit", &flat, "--output", "flat-note");
    assert!(stdout.contains("note:"), "{stdout}");
    let (stdout, _) = run("blend_edit", &flat, "--out", "flat-note");
    assert!(stdout.contains("note:"), "{stdout}");
    let refused = Command::new(testkit::example_binary("area_edit"))
        .arg(data.join("quads_hole.obj"))
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(1));
    let message = String::from_utf8_lossy(&refused.stderr);
    assert!(message.contains("--vertex"), "{message}");
    std::fs::remove_file(flat).ok();
    std::fs::remove_file(loose).ok();
}

/// A triangle soup (every face on its own three vertices, as STL exports and some OBJ
/// exporters write) falls apart into single faces: the single-method examples weld it
/// first (`--weld auto`, a note says so) and edit the welded surface; `--weld off` keeps
/// the pieces, which no editing region can span.
#[test]
fn single_method_examples_weld_a_triangle_soup() {
    let sphere = generators::icosphere(3);
    let (positions, triangles) = generators::triangle_soup(&sphere);
    let (soup, _) = Mesh::from_arrays(&positions, &triangles).unwrap();
    assert_eq!(soup.n_vertices(), 3 * sphere.n_faces());
    let input = write_temp(&soup, "soup");
    for (example, flag) in [
        ("area_edit", "--output"),
        ("blend_edit", "--out"),
        ("deform", "--out"),
    ] {
        let (stdout, after) = run(example, &input, flag, "soup");
        assert!(stdout.contains("note: welded"), "{example}\n{stdout}");
        assert_eq!(
            after.n_vertices(),
            sphere.n_vertices(),
            "{example}\n{stdout}"
        );
        assert_eq!(after.topology_report().boundary_loops, 0, "{example}");
    }
    let refused = Command::new(testkit::example_binary("blend_edit"))
        .arg(&input)
        .args(["--weld", "off", "--out"])
        .arg(std::env::temp_dir().join(format!("multires-soup-off-{}.obj", std::process::id())))
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(1));
    std::fs::remove_file(input).ok();
}

/// A torus of six long segments around its axis: the edges along the axis are longer
/// than blend_edit's radii, so the loops do not close and every edge-path ball puts a
/// handle vertex beside a fixed one. The example falls back to rings of edges around
/// the tip, says so, and edits.
#[test]
fn blend_edit_falls_back_to_rings_where_edges_are_longer_than_its_radii() {
    let torus = generators::torus(1.0, 0.3, 6, 32).unwrap();
    let input = write_temp(&torus, "long-edges");
    let (stdout, after) = run("blend_edit", &input, "--out", "long-edges");
    assert!(stdout.contains("ring(s) around it"), "{stdout}");
    assert!(after.n_faces() >= torus.n_faces(), "{stdout}");
    let moved = torus
        .vertices()
        .filter(|&v| {
            let i = torus.vertex_index(v);
            after
                .vertex_at(i)
                .is_some_and(|w| after.position(w) != torus.position(v))
        })
        .count();
    assert!(moved > 0, "nothing moved\n{stdout}");
    std::fs::remove_file(input).ok();
}
