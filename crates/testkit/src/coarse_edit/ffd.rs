//! The `ffd` edit: a shape/height-surface FFD bend, the same frame and lattice at both
//! resolutions.

use edit::deform::{AttachOptions, BSplineSurface, DeformError, Ffd, LatticeFrame, SubMesh};
use edit::Vertices;
use glam::DVec3;
use halfedge::{Mesh, VertexData};

use super::region::{fine_mask, mean_normal, perpendicular};
use super::{lib, Applied, Failure};

/// Shape/height-surface FFD: the lattice over the region's footprint, attached to the
/// larger ball, bent inside its two outer layers of control points ([`bend_inside`]);
/// the same frame and lattice at both levels.
pub(super) fn ffd_edit(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    ancestors: &[u32],
    tip: usize,
    mask: &[bool],
    ball: &[bool],
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
    let d = (positions[tip] - centre).normalize_or_zero();
    if d == DVec3::ZERO {
        return Err(Failure::new(
            "the region's tip is at the centroid of its frontier: the region has no axis",
            hint,
        ));
    }
    let up = perpendicular(d, mean_normal(coarse, &mask));
    let frame = LatticeFrame::new(centre, d, up).map_err(lib(hint))?;
    let (lo, hi) = sub
        .vertex_indices()
        .iter()
        .map(|&i| frame.to_local(positions[i as usize]))
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), l| {
            (lo.min(l), hi.max(l))
        });
    // (a flat footprint gets a thickness of a millionth of its extent, at any scale)
    let size = (hi - lo).max(DVec3::splat(1e-6 * (hi - lo).max_element()));
    let margin = 0.05;
    let min = [lo.x - margin * size.x, lo.z - margin * size.z];
    let max = [hi.x + margin * size.x, hi.z + margin * size.z];
    let grid = ([3, 3], [8, 8]);
    let shape = BSplineSurface::planar(&frame, grid.0, grid.1, min, max, 0.0).map_err(lib(hint))?;
    let height =
        BSplineSurface::planar(&frame, grid.0, grid.1, min, max, 1.0).map_err(lib(hint))?;
    let angle = 45f64.to_radians() * amount;
    let ball_data = VertexData::new(coarse, ball.to_vec()).map_err(lib(hint))?;
    let mut ffd = Ffd::attach(
        coarse,
        Vertices::Mask(&ball_data),
        frame,
        shape.clone(),
        height.clone(),
        AttachOptions::default(),
    )
    .map_err(lib(hint))?;
    bend_inside(&mut ffd, angle).map_err(lib(hint))?;
    ffd.deform(coarse).map_err(lib(hint))?;
    let movable: Vec<bool> = (0..coarse.vertex_slots())
        .map(|i| ffd.parameters(i).is_some())
        .collect();

    let mut fine_region = 0;
    if let Some(fine) = fine {
        let fine_ball =
            VertexData::new(fine, fine_mask(fine, ancestors, ball)).map_err(lib(hint))?;
        let mut fine_ffd = Ffd::attach(
            fine,
            Vertices::Mask(&fine_ball),
            frame,
            shape,
            height,
            AttachOptions::default(),
        )
        .map_err(lib(hint))?;
        bend_inside(&mut fine_ffd, angle).map_err(lib(hint))?;
        fine_ffd.deform(fine).map_err(lib(hint))?;
        fine_region = fine_ffd.attached();
    }
    Ok(Applied {
        movable,
        fine_region,
        rigid: Vec::new(),
        marks: None,
    })
}

/// Bends the FFD's shape surface ([`Ffd::bend`]) and puts the two outer layers of
/// control points on every side back where they were: the surface and its normal stay
/// unchanged along the lattice's border, so the deformation fades to nothing there
/// whichever borders the attached vertices cross (the library pins crossed borders
/// only, and which ones are crossed can differ between resolutions).
fn bend_inside(ffd: &mut Ffd, angle: f64) -> Result<(), DeformError> {
    ffd.bend(angle)?;
    let rest = ffd.rest().0.clone();
    let [cu, cv] = rest.count();
    for i in 0..cu {
        for j in 0..cv {
            if i < 2 || j < 2 || i + 2 >= cu || j + 2 >= cv {
                if let Some(p) = rest.control_point(i, j) {
                    ffd.shape_mut().set_control_point(i, j, p)?;
                }
            }
        }
    }
    Ok(())
}
