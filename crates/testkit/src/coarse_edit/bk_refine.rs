//! `--edit bk-refine`: the Bendels & Klein edit with adaptive refinement inside the
//! hierarchy, then a walk to every level and back.

use std::time::Instant;

use edit::bendels_klein::{BlendOptions, BlendSession, Regions};
use edit::HierarchyEdit;
use glam::{DAffine3, DQuat, DVec3};
use halfedge::hierarchy::{DetailMode, Method};

use super::region::{choose_region, listed, mean_normal, TIP_DEPTH};
use super::{lib, Failure, Options, Prepared};

/// `--edit bk-refine`: the Bendels & Klein edit of `bk` made at the level with adaptive
/// refinement inside the hierarchy (`BlendSession::apply` and `HierarchyEdit::mark`, then
/// `refine_in_hierarchy`, which splits the long edges at the input and builds the
/// hierarchy again), then a walk to every level and back. Returns one JSON object:
/// `new_vertices`, `levels`, `levels_reachable` (every level reached and back, the mesh
/// valid at each), `handle_error` (the handle's input vertices against the rigid image of
/// their input positions, over the diagonal), `refine_seconds`.
///
/// # Errors
/// A [`Failure`] with a hint when no region or regions fit, or the library refuses.
pub fn measure_bk_refine(
    prepared: &Prepared,
    options: &Options,
    name: &str,
) -> Result<serde_json::Value, Failure> {
    let hint = "pass a larger --region-fraction or another --seed-vertex";
    let mut hierarchy = prepared.hierarchy.clone();
    if hierarchy.detail_mode() != DetailMode::LocalFrame {
        return Err(Failure::new(
            "bk-refine needs local-frame detail (the handle is marked as it moves)",
            "leave out --detail translation",
        ));
    }
    let level = prepared.level;
    let input = &prepared.input;
    let f = options.region_fraction;
    let region = choose_region(
        hierarchy.mesh(),
        &prepared.ancestors,
        options.seed_vertex,
        TIP_DEPTH,
    )?;
    let coarse = hierarchy.mesh();
    let slots = coarse.vertex_slots();
    let (handle, _) = region.ball(slots, 0.15 * f, 1)?;
    let (ball, radius) = region.ball(slots, 1.25 * f, 4)?;
    let fixed: Vec<bool> = (0..slots)
        .map(|i| {
            coarse.vertex_at(i).is_some_and(|v| {
                !coarse.is_isolated(v)
                    && !ball[i]
                    && !coarse
                        .adjacent_vertices(v)
                        .any(|w| handle[coarse.vertex_index(w)])
            })
        })
        .collect();
    let regions = Regions::from_sets(coarse, &listed(coarse, &handle), &listed(coarse, &fixed))
        .map_err(lib(hint))?;
    let centre = listed(coarse, &handle)
        .iter()
        .map(|&v| coarse.position(v))
        .sum::<DVec3>()
        / regions.handle().len().max(1) as f64;
    let normal = match mean_normal(coarse, &handle) {
        n if n == DVec3::ZERO => DVec3::Z,
        n => n,
    };
    let amount = options.amount;
    let a = DAffine3::from_translation(0.4 * amount * radius * normal)
        * DAffine3::from_translation(centre)
        * DAffine3::from_quat(DQuat::from_axis_angle(
            normal.any_orthonormal_vector(),
            30f64.to_radians() * amount,
        ))
        * DAffine3::from_translation(-centre);
    let mut session =
        BlendSession::new(coarse, regions, BlendOptions::default()).map_err(lib(hint))?;
    session
        .apply(hierarchy.mesh_mut(), glam::DMat4::from(a))
        .map_err(lib(hint))?;
    session.mark(&mut hierarchy).map_err(lib(hint))?;
    // Split what the edit stretched beyond the input's mean edge length, at the input.
    let mean_edge = {
        let (sum, n) = input
            .edges()
            .fold((0.0, 0usize), |(s, n), h| (s + input.edge_length(h), n + 1));
        sum / n.max(1) as f64
    };
    let clock = Instant::now();
    let report = session
        .refine_in_hierarchy(
            &mut hierarchy,
            edit::bendels_klein::RefineOptions::new(1.5 * mean_edge),
        )
        .map_err(lib(
            "this is a bug of the library; report it with the command line",
        ))?;
    let refine_seconds = clock.elapsed().as_secs_f64();
    // The handle at full resolution against the rigid image of its input vertices.
    hierarchy.go_to_level(0).map_err(lib(
        "this is a bug of the library; report it with the command line",
    ))?;
    let fine = hierarchy.mesh();
    let mut worst: f64 = 0.0;
    let mut handle_vertices = 0;
    for v in input.vertices() {
        let i = input.vertex_index(v);
        if handle[prepared.ancestors[i] as usize] {
            let target = a.transform_point3(input.position(v));
            worst = worst.max(fine.positions()[i].distance(target) / prepared.diagonal);
            handle_vertices += 1;
        }
    }
    let faces = fine.n_faces();
    // Every level and back.
    let levels = hierarchy.n_levels();
    let mut reachable = true;
    for l in (0..levels).chain((0..levels).rev()) {
        reachable &= hierarchy.go_to_level(l).is_ok() && hierarchy.mesh().check().is_ok();
    }
    Ok(serde_json::json!({
        "mesh": name,
        "edit": "bk-refine",
        "level": level,
        "method": match hierarchy.method() {
            Method::Rounds => "rounds",
            Method::Qem => "qem",
        },
        "input_faces": input.n_faces(),
        "faces": faces,
        "new_vertices": report.new_vertices,
        "longest_edge": report.longest_edge,
        "levels": levels,
        "levels_reachable": reachable,
        "handle_vertices": handle_vertices,
        "handle_error": worst,
        "refine_seconds": refine_seconds,
    }))
}
