//! The `bk` edit: a Bendels & Klein handle rotated and lifted, at both resolutions.

use edit::bendels_klein::{BlendOptions, BlendSession, Regions};
use edit::HierarchyEdit;
use glam::{DAffine3, DQuat, DVec3};
use halfedge::Mesh;

use super::region::{fine_mask, listed, mean_normal};
use super::{lib, Applied, Failure, Rigid};

/// Bendels & Klein: the handle (the nearest vertices around the tip) rotated and lifted,
/// everything beyond the ball fixed, at both levels.
pub(super) fn bk_edit(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    ancestors: &[u32],
    handle: &[bool],
    ball: &[bool],
    radius: f64,
    amount: f64,
) -> Result<Applied, Failure> {
    let hint = "pass a larger --region-fraction or another --seed-vertex";
    // fixed: beyond the ball, except the handle's neighbours (a long edge can reach past
    // the ball; the handle must not touch the fixed area)
    let fixed: Vec<bool> = (0..coarse.vertex_slots())
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
    let regions = Regions::from_sets(coarse, &listed(coarse, handle), &listed(coarse, &fixed))
        .map_err(lib(hint))?;
    let positions = coarse.positions();
    let handle_list: Vec<u32> = (0..handle.len() as u32)
        .filter(|&i| handle[i as usize])
        .collect();
    let centre = handle_list
        .iter()
        .map(|&i| positions[i as usize])
        .sum::<DVec3>()
        / handle_list.len() as f64;
    let normal = mean_normal(coarse, handle);
    let normal = if normal == DVec3::ZERO {
        DVec3::Z
    } else {
        normal
    };
    let axis = normal.any_orthonormal_vector();
    let a = DAffine3::from_translation(0.2 * amount * radius * normal)
        * DAffine3::from_translation(centre)
        * DAffine3::from_quat(DQuat::from_axis_angle(axis, 30f64.to_radians() * amount))
        * DAffine3::from_translation(-centre);
    let movable: Vec<bool> = regions
        .roles()
        .iter()
        .map(|&r| r != edit::bendels_klein::Role::Fixed)
        .collect();
    let mut session =
        BlendSession::new(coarse, regions, BlendOptions::default()).map_err(lib(hint))?;
    session
        .apply(coarse, glam::DMat4::from(a))
        .map_err(lib(hint))?;
    let marks = session.hierarchy_marks(coarse).map_err(lib(hint))?;

    let mut fine_region = 0;
    if let Some(fine) = fine {
        let fine_handle = fine_mask(fine, ancestors, handle);
        let fine_fixed = fine_mask(fine, ancestors, &fixed);
        let fine_regions = Regions::from_sets(
            fine,
            &listed(fine, &fine_handle),
            &listed(fine, &fine_fixed),
        )
        .map_err(lib(hint))?;
        fine_region = fine_regions.handle().len() + fine_regions.deformable().len();
        let mut fine_session =
            BlendSession::new(fine, fine_regions, BlendOptions::default()).map_err(lib(hint))?;
        fine_session
            .apply(fine, glam::DMat4::from(a))
            .map_err(lib(hint))?;
    }
    Ok(Applied {
        movable,
        fine_region,
        rigid: vec![Rigid {
            vertices: handle_list,
            map: a,
        }],
        marks: Some(marks),
    })
}
