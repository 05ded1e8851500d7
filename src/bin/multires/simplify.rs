//! `multires simplify`: builds the progressive hierarchy of a mesh and saves it (.mrh).

use std::time::Instant;

use halfedge::hierarchy::{
    BuildProgress, DetailMode, Hierarchy, HierarchyOptions, SurvivorPlacement,
};
use multires::load;
use multires::progress::{self, Progress};
use serde_json::json;

use crate::args::SimplifyArgs;
use crate::output::Output;

pub fn run(a: SimplifyArgs, out: &Output) -> multires::Result<()> {
    let clock = Instant::now();
    let mut bars = out.bars(load::is_large_file(&a.mesh));
    let loaded = load::load(&a.mesh, a.weld.weld, &mut bars)?;
    let load_seconds = clock.elapsed().as_secs_f64();
    bars.set_shown(progress::LARGE_FACES < loaded.mesh.n_faces() && !out.quiet && !out.json);
    let mut options = match a.method.as_str() {
        "qem" => HierarchyOptions::qem(),
        _ => HierarchyOptions::rounds(),
    }
    .with_target_faces(a.target_faces)
    .with_detail_mode(if a.detail == "translation" {
        DetailMode::Translation
    } else {
        DetailMode::LocalFrame
    })
    .with_placement(if a.placement == "quadric" {
        SurvivorPlacement::Quadric
    } else {
        SurvivorPlacement::Midpoint
    });
    if let Some(levels) = a.max_levels {
        options = options.with_max_levels(levels);
    }
    if let Some(degrees) = a.max_normal_deviation {
        options = options.with_max_normal_deviation(degrees.to_radians());
    }
    let input_faces = loaded.mesh.n_faces();
    let clock = Instant::now();
    bars.start("simplifying (faces removed)", Some(input_faces as u64));
    let built = Hierarchy::build_with_progress(loaded.mesh, &options, &mut |p: BuildProgress| {
        bars.advance(
            (p.input_faces - p.faces) as u64,
            &format!("simplifying (level {})", p.levels),
        );
    });
    bars.finish();
    let mut hierarchy = built?;
    let build_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    progress::step(&mut bars, &format!("saving {}", a.output.display()), || {
        hierarchy.save(&a.output)
    })?;
    let write_seconds = clock.elapsed().as_secs_f64();
    let file_bytes = std::fs::metadata(&a.output).map(|m| m.len()).unwrap_or(0);
    let mut level_files = Vec::new();
    let clock = Instant::now();
    if let Some(dir) = &a.levels {
        std::fs::create_dir_all(dir).map_err(|source| multires::Error::Io {
            path: dir.clone(),
            source,
        })?;
        let stem = multires::workflow::file_stem(&a.mesh);
        for level in (0..=hierarchy.coarsest_level()).rev() {
            hierarchy.go_to_level(level)?;
            let path = dir.join(format!("{stem}-level{level}.{}", a.format));
            halfedge::io::write(&path, hierarchy.mesh())?;
            level_files.push(path.display().to_string());
        }
    }
    let levels_seconds = clock.elapsed().as_secs_f64();
    out.json(json!({
        "input": a.mesh.display().to_string(),
        "output": a.output.display().to_string(),
        "method": a.method,
        "placement": a.placement,
        "input_faces": input_faces,
        "levels": hierarchy.n_levels(),
        "level_face_counts": hierarchy.level_face_counts(),
        "records": hierarchy.n_records(),
        "file_bytes": file_bytes,
        "level_files": level_files,
        "load_seconds": load_seconds,
        "build_seconds": build_seconds,
        "write_seconds": write_seconds,
        "levels_seconds": levels_seconds,
        "build_outcome": hierarchy.build_outcome().to_string(),
    }));
    out.text(format!(
        "{} -> {}: {} levels, faces per level {:?}; {} records, {} bytes\n  load {:.3} s, \
         build {:.3} s, write {:.3} s{}\n  {}",
        a.mesh.display(),
        a.output.display(),
        hierarchy.n_levels(),
        hierarchy.level_face_counts(),
        hierarchy.n_records(),
        file_bytes,
        load_seconds,
        build_seconds,
        write_seconds,
        if level_files.is_empty() {
            String::new()
        } else {
            format!(
                ", {} level meshes {:.3} s",
                level_files.len(),
                levels_seconds
            )
        },
        hierarchy.build_outcome()
    ));
    Ok(())
}
