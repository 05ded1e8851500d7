//! `multires info`: what a mesh (or a saved hierarchy) is made of.

use std::time::Instant;

use halfedge::hierarchy::Hierarchy;
use halfedge::Mesh;
use multires::load;
use serde_json::json;

use crate::args::InfoArgs;
use crate::output::Output;

/// The genus of a mesh from its Euler characteristic, components and boundary loops
/// (`χ = Σ (2 − 2 g_c − b_c)`, so `g = (2C − B − χ) / 2`; for non-manifold or
/// non-orientable input the value is the formula's, which may be a half).
pub fn genus(components: usize, boundary_loops: usize, euler: i64) -> f64 {
    (2.0 * components as f64 - boundary_loops as f64 - euler as f64) / 2.0
}

/// The report of a mesh: counts, topology, bounding box.
pub fn mesh_report(mesh: &Mesh) -> serde_json::Value {
    let t = mesh.topology_report();
    let (lo, hi) = mesh
        .bounding_box()
        .map_or(([f64::NAN; 3], [f64::NAN; 3]), |(lo, hi)| {
            (lo.to_array(), hi.to_array())
        });
    let diagonal = mesh.bounding_box().map_or(0.0, |(lo, hi)| lo.distance(hi));
    let g = genus(t.components, t.boundary_loops, t.euler);
    let genus_json = if g.fract() == 0.0 {
        json!(g as i64)
    } else {
        json!(g)
    };
    json!({
        "vertices": t.vertices,
        "faces": t.faces,
        "edges": t.edges,
        "boundary_loops": t.boundary_loops,
        "boundary_vertices": t.boundary_vertices,
        "components": t.components,
        "euler": t.euler,
        "genus": genus_json,
        "non_manifold_vertices": t.non_manifold_vertices,
        "bbox_min": if lo[0].is_finite() { json!(lo) } else { json!(null) },
        "bbox_max": if hi[0].is_finite() { json!(hi) } else { json!(null) },
        "diagonal": diagonal,
    })
}

pub fn run(a: InfoArgs, out: &Output) -> multires::Result<()> {
    let bytes = std::fs::metadata(&a.mesh).map(|m| m.len()).ok();
    let is_hierarchy = a
        .mesh
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mrh"));
    let clock = Instant::now();
    let mut bars = out.bars(load::is_large_file(&a.mesh));
    if is_hierarchy {
        let h = multires::progress::step(&mut bars, "loading the hierarchy", || {
            Hierarchy::load(&a.mesh)
        })?;
        let load_seconds = clock.elapsed().as_secs_f64();
        let mut report = mesh_report(h.mesh());
        report["file"] = json!(a.mesh.display().to_string());
        report["file_bytes"] = json!(bytes);
        report["hierarchy"] = json!({
            "method": format!("{:?}", h.method()).to_lowercase(),
            "levels": h.n_levels(),
            "coarsest_level": h.coarsest_level(),
            "level_face_counts": h.level_face_counts(),
            "current_level": h.current_level(),
            "records": h.n_records(),
        });
        report["load_seconds"] = json!(load_seconds);
        out.json(report.clone());
        out.text(format!(
            "{}: hierarchy ({} method) of {} levels, faces per level {:?}; at level {} \
             ({} vertices, {} faces, {} edges); {} records; {} bytes",
            a.mesh.display(),
            report["hierarchy"]["method"].as_str().unwrap_or("?"),
            h.n_levels(),
            h.level_face_counts(),
            h.current_level()
                .map_or_else(|| "between levels".to_owned(), |l| l.to_string()),
            report["vertices"],
            report["faces"],
            report["edges"],
            h.n_records(),
            bytes.unwrap_or(0)
        ));
        return Ok(());
    }
    let loaded = load::load(&a.mesh, a.weld.weld, &mut bars)?;
    let load_seconds = clock.elapsed().as_secs_f64();
    let mut report = mesh_report(&loaded.mesh);
    let b = &loaded.build;
    report["file"] = json!(a.mesh.display().to_string());
    report["file_bytes"] = json!(bytes);
    report["fixes"] = json!({
        "duplicated_vertices": b.duplicated_vertices,
        "duplicated_faces": b.duplicated_faces,
        "dropped_faces": b.dropped_faces,
        "dropped_triangles": b.dropped_triangles,
        "unreferenced_vertices": b.unreferenced_vertices,
        "merged_vertices": b.merged_vertices,
        "welded_vertices": loaded.welding.as_ref().map_or(0, |w| w.merged_vertices),
    });
    report["load_seconds"] = json!(load_seconds);
    out.json(report.clone());
    let fixes = &report["fixes"];
    out.text(format!(
        "{}\n  vertices {}, faces {}, edges {}\n  components {}, boundary loops {}, Euler \
         characteristic {}, genus {}\n  bounding box {} to {} (diagonal {:.6})\n  reader's \
         fixes: {} vertices duplicated (non-manifold faces), {} faces dropped, {} \
         unreferenced vertices, {} corners merged, {} vertices welded\n  {} bytes, read in \
         {:.3} s{}",
        a.mesh.display(),
        report["vertices"],
        report["faces"],
        report["edges"],
        report["components"],
        report["boundary_loops"],
        report["euler"],
        report["genus"],
        report["bbox_min"],
        report["bbox_max"],
        report["diagonal"].as_f64().unwrap_or(0.0),
        fixes["duplicated_vertices"],
        fixes["dropped_faces"],
        fixes["unreferenced_vertices"],
        fixes["merged_vertices"],
        fixes["welded_vertices"],
        bytes.unwrap_or(0),
        load_seconds,
        loaded
            .welding
            .map_or(String::new(), |w| format!("\n  note: {}", w.note))
    ));
    Ok(())
}
