//! The sub-mesh edits (`rotate`, `twist`, `taper`, `scale`, `pull`) at both resolutions.

use edit::deform::{Axis, Propagation, SubMesh, SubmeshEdit, Variation};
use edit::HierarchyEdit;
use glam::{DAffine3, DMat3, DQuat, DVec3};
use halfedge::{Mesh, VertexData};

use super::region::{fine_mask, mean_normal, perpendicular, FLAT_REGION};
use super::{lib, Applied, EditKind, Failure, Rigid};

/// Sub-mesh edits with no propagation (the paper's §4.3), at both levels.
#[allow(clippy::too_many_arguments)]
pub(super) fn submesh_edit(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    ancestors: &[u32],
    tip: usize,
    mask: &[bool],
    radius: f64,
    kind: EditKind,
    amount: f64,
) -> Result<Applied, Failure> {
    let hint = "pass another --region-fraction or --seed-vertex";
    let mask = VertexData::new(coarse, mask.to_vec()).map_err(lib(hint))?;
    let sub = SubMesh::from_mask(coarse, &mask).map_err(lib(hint))?;
    let positions = coarse.positions();
    let frontier = sub.frontier_indices();
    if frontier.is_empty() {
        return Err(Failure::new(
            "the region covers its whole component: it has no frontier",
            "pass a smaller --region-fraction",
        ));
    }
    let centre = frontier
        .iter()
        .map(|&i| positions[i as usize])
        .sum::<DVec3>()
        / frontier.len() as f64;
    let towards_tip = positions[tip] - centre;
    let length = towards_tip.length();
    if length.is_nan() || length <= 1e-6 * radius {
        return Err(Failure::new(
            "the region's tip is at the centroid of its frontier: the region has no axis",
            hint,
        ));
    }
    let d = towards_tip.normalize();
    let axis_along = Axis::new(centre, d).map_err(lib(hint))?;
    let inside: Vec<u32> = sub.vertex_indices().to_vec();
    let (edit, rigid_part, map) = match kind {
        EditKind::Pull => {
            let offset = 0.3 * amount * radius * d;
            (
                SubmeshEdit::Pull { offset },
                inside.clone(),
                DAffine3::from_translation(offset),
            )
        }
        EditKind::Rotate => {
            let across = d.cross(perpendicular(d, mean_normal(coarse, &mask)));
            let angle = 30f64.to_radians() * amount;
            let axis = Axis::new(centre, across).map_err(lib(hint))?;
            let map = DAffine3::from_translation(centre)
                * DAffine3::from_quat(DQuat::from_axis_angle(axis.direction(), angle))
                * DAffine3::from_translation(-centre);
            (
                SubmeshEdit::Rotate {
                    axis,
                    angle,
                    bounded: false,
                },
                inside.clone(),
                map,
            )
        }
        EditKind::Scale => {
            let factor = 0.8f64.powf(amount);
            // the re-seating translation is the library's: measured below
            (
                SubmeshEdit::Scale { centre, factor },
                inside.clone(),
                DAffine3::from_translation(centre)
                    * DAffine3::from_mat3(DMat3::from_diagonal(DVec3::splat(factor)))
                    * DAffine3::from_translation(-centre),
            )
        }
        EditKind::Twist | EditKind::Taper => {
            // the axis along which the region reaches farthest beyond its frontier: the
            // one towards the tip or the frontier plane's normal
            let extent = |axis: &Axis| {
                let start = frontier
                    .iter()
                    .map(|&i| axis.coordinate(positions[i as usize]))
                    .fold(f64::NEG_INFINITY, f64::max);
                let top = inside
                    .iter()
                    .map(|&i| axis.coordinate(positions[i as usize]))
                    .fold(f64::NEG_INFINITY, f64::max);
                (start, top)
            };
            let (axis_along, (start, top)) = [Some(axis_along), sub.axis(coarse).ok()]
                .into_iter()
                .flatten()
                .map(|a| (a, extent(&a)))
                .max_by(|x, y| (x.1 .1 - x.1 .0).total_cmp(&(y.1 .1 - y.1 .0)))
                .unwrap_or((axis_along, extent(&axis_along)));
            let reach = top - start;
            if reach.is_nan() || reach <= 0.05 * radius {
                return Err(Failure::new(
                    FLAT_REGION,
                    "pass a --seed-vertex on a protruding part, or another --region-fraction",
                ));
            }
            let (centre, d) = (axis_along.point(), axis_along.direction());
            // The rigid end: the coarse vertices beyond the ramp whose whole cluster of
            // fine vertices is beyond it too (a cluster reaching down the ramp would
            // take the full map where the full-resolution edit gives less).
            let mut lowest = vec![f64::INFINITY; positions.len()];
            if let Some(fine) = fine.as_deref() {
                for v in fine.vertices() {
                    let i = fine.vertex_index(v);
                    let a = ancestors[i] as usize;
                    let s = axis_along.coordinate(fine.positions()[i]);
                    lowest[a] = lowest[a].min(s);
                }
            }
            // Where vertex i's cluster starts along the axis (itself included).
            let from = |i: u32| {
                axis_along
                    .coordinate(positions[i as usize])
                    .min(lowest[i as usize])
            };
            let beyond = |end: f64| -> Vec<u32> {
                inside.iter().copied().filter(|&i| from(i) >= end).collect()
            };
            // The ramp ends at 70 % of the extent; on a coarse level whose clusters all
            // reach below that, it ends where the topmost whole cluster starts, so that
            // the edit always has a rigid end to measure.
            let mut end = start + 0.7 * (top - start);
            let mut rigid = beyond(end);
            if rigid.is_empty() {
                let topmost = inside
                    .iter()
                    .map(|&i| from(i))
                    .fold(f64::NEG_INFINITY, f64::max);
                if topmost > start {
                    end = topmost;
                    rigid = beyond(end);
                }
            }
            let variation = Variation::Along { start, end };
            let to_axis = DAffine3::from_translation(-centre);
            let from_axis = DAffine3::from_translation(centre);
            if kind == EditKind::Twist {
                let angle = 60f64.to_radians() * amount;
                let map =
                    from_axis * DAffine3::from_quat(DQuat::from_axis_angle(d, angle)) * to_axis;
                (
                    SubmeshEdit::Twist {
                        axis: Some(axis_along),
                        angle,
                        variation,
                    },
                    rigid,
                    map,
                )
            } else {
                let factor = 0.6f64.powf(amount);
                // q ↦ (q·d) d + factor (q − (q·d) d)
                let linear =
                    DMat3::from_diagonal(DVec3::splat(factor)) + (1.0 - factor) * outer(d, d);
                let map = from_axis * DAffine3::from_mat3(linear) * to_axis;
                (
                    SubmeshEdit::Taper {
                        axis: Some(axis_along),
                        factor,
                        variation,
                    },
                    rigid,
                    map,
                )
            }
        }
        _ => unreachable!("submesh_edit is called for sub-mesh edits only"),
    };
    let before = coarse.positions().to_vec();
    let applied = sub
        .apply_with_marks(coarse, &edit, Propagation::NONE)
        .map_err(lib(hint))?;
    let marks = applied.hierarchy_marks(coarse).map_err(lib(hint))?;
    // The library re-seats a scaled sub-mesh by a translation fitted to its frontier:
    // the mean offset of the scaled vertices from the plain scale.
    let reseat = |list: &[u32], before: &[DVec3], after: &[DVec3]| {
        list.iter()
            .map(|&i| after[i as usize] - map.transform_point3(before[i as usize]))
            .sum::<DVec3>()
            / list.len() as f64
    };
    let coarse_shift = reseat(&inside, &before, coarse.positions());
    let mut fine_region = 0;
    if let Some(fine) = fine {
        let fine_mask =
            VertexData::new(fine, fine_mask(fine, ancestors, &mask)).map_err(lib(hint))?;
        let fine_sub = SubMesh::from_mask(fine, &fine_mask).map_err(lib(hint))?;
        let fine_before = fine.positions().to_vec();
        fine_sub
            .apply(fine, &edit, Propagation::NONE)
            .map_err(lib(hint))?;
        if kind == EditKind::Scale {
            // the same map at both resolutions: the coarse edit's re-seating (the fitted
            // frontier plane differs a little between resolutions)
            let fine_shift = reseat(fine_sub.vertex_indices(), &fine_before, fine.positions());
            let offset = coarse_shift - fine_shift;
            fine_sub
                .apply(fine, &SubmeshEdit::Pull { offset }, Propagation::NONE)
                .map_err(lib(hint))?;
        }
        fine_region = fine_sub.len();
    }
    let map = if kind == EditKind::Scale {
        DAffine3::from_translation(coarse_shift) * map
    } else {
        map
    };
    Ok(Applied {
        movable: sub.mask().to_vec(),
        fine_region,
        rigid: vec![Rigid {
            vertices: rigid_part,
            map,
        }],
        marks: Some(marks),
    })
}

/// The outer product `a bᵀ`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}
