//! The sub-mesh rule of the workflow and of the recipes' `cut` regions: the part cut off by a plane perpendicular to an axis,
//! labelled (a closed frontier) or, on an open mesh, given as a vertex mask.

use edit::deform::SubMesh;
use glam::DVec3;
use halfedge::{Mesh, VertexId};

use crate::recipe::axis_name;

/// The sub-mesh cut off by a plane, with what the table and the notes say about it.
// The workflow (feature `render`) reads every field; recipes need only the sub-mesh.
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub(crate) struct Labelled {
    pub(crate) attribute: halfedge::Attribute<VertexId, halfedge::labels::Label>,
    pub(crate) sub: SubMesh,
    pub(crate) detail: String,
    pub(crate) note: Option<String>,
}

/// The smallest sub-mesh the taper is worth making on.
const MIN_SUBMESH: usize = 4;

/// One plane the sub-mesh rule tries: perpendicular to `axis` at `height` along it
/// (`fraction` of the mesh's extent), near `tip`, the vertex furthest along the axis at
/// `top`; `first_axis` when the axis is the one asked for.
struct CuttingPlane {
    axis: DVec3,
    tip: VertexId,
    fraction: f64,
    height: f64,
    top: f64,
    first_axis: bool,
}

/// The planes of the sub-mesh rule, in the order it tries them: perpendicular to `axis`
/// from `fraction` of the extent towards the tip in steps of 4 %, then away from it; then
/// the same for the other axes from 72 %.
fn cutting_planes(mesh: &Mesh, axis: DVec3, fraction: f64) -> Result<Vec<CuttingPlane>, String> {
    let mut axes = vec![axis];
    for a in [
        DVec3::Y,
        DVec3::Z,
        DVec3::X,
        DVec3::NEG_Y,
        DVec3::NEG_Z,
        DVec3::NEG_X,
    ] {
        if a != axis {
            axes.push(a);
        }
    }
    let mut planes = Vec::new();
    for (k, &a) in axes.iter().enumerate() {
        let tip = mesh
            .extreme_vertex(a)
            .map_err(|e| e.to_string())?
            .ok_or("the mesh has no vertex with a face")?;
        let top = mesh.position(tip).dot(a);
        let bottom = mesh
            .vertices()
            .filter(|&v| !mesh.is_isolated(v))
            .map(|v| mesh.position(v).dot(a))
            .fold(f64::INFINITY, f64::min);
        let start = if k == 0 { fraction } else { 0.72 };
        let up = (0..)
            .map(|i| start + 0.04 * i as f64)
            .take_while(|&f| f < 0.99);
        let down = (1..)
            .map(|i| start - 0.04 * i as f64)
            .take_while(|&f| f > 0.01);
        planes.extend(up.chain(down).map(|f| CuttingPlane {
            axis: a,
            tip,
            fraction: f,
            height: bottom + f * (top - bottom),
            top,
            first_axis: k == 0,
        }));
    }
    Ok(planes)
}

/// The sub-mesh rule of the module docs: planes perpendicular to `axis` (then to the
/// other axes), from `fraction` of the extent towards the tip.
pub(crate) fn label_submesh(
    mesh: &mut Mesh,
    axis: DVec3,
    fraction: f64,
) -> Result<Labelled, String> {
    let mut first_failure: Option<String> = None;
    for cut in cutting_planes(mesh, axis, fraction)? {
        let CuttingPlane {
            axis: a,
            tip,
            fraction: f,
            height,
            top,
            first_axis,
        } = cut;
        let point = mesh.position(tip) - a * (top - height);
        let attempt = mesh.frontier_from_plane(point, a).and_then(|frontier| {
            let (attribute, counts) = mesh.label_sides(&frontier, 1, 2)?;
            Ok((frontier, attribute, counts))
        });
        match attempt {
            Ok((frontier, attribute, counts)) => {
                let values = mesh.attribute_values(attribute).unwrap();
                if values[mesh.vertex_index(tip)] == 1 && counts.left_vertices >= MIN_SUBMESH {
                    let sub = SubMesh::from_labels(mesh, attribute, |&l| l == 1)
                        .map_err(|e| e.to_string())?;
                    let moved = !first_axis || f != fraction;
                    let detail = format!(
                        "plane {} = {height:.3} ({:.0} % of the extent): frontier of {} \
                             edges, sub-mesh on the {} side {} vertices, the rest {}",
                        axis_name(a),
                        100.0 * f,
                        frontier.halfedges().len(),
                        axis_name(a),
                        counts.left_vertices,
                        counts.right_vertices
                    );
                    let note = moved.then(|| {
                        format!(
                            "the cutting plane {} at {:.0} % could not cut off a part ({}); \
                                 used {} at {:.0} % instead (--axis, --plane)",
                            axis_name(axis),
                            100.0 * fraction,
                            first_failure.as_deref().unwrap_or("no part on its side"),
                            axis_name(a),
                            100.0 * f
                        )
                    });
                    return Ok(Labelled {
                        attribute,
                        sub,
                        detail,
                        note,
                    });
                }
                first_failure.get_or_insert_with(|| {
                    format!(
                        "the section nearest to the tip cuts off {} vertices without the tip",
                        counts.left_vertices
                    )
                });
            }
            Err(e) => {
                first_failure.get_or_insert_with(|| e.to_string());
            }
        }
    }
    Err(format!(
        "no plane perpendicular to ±x, ±y or ±z cuts off a part of the mesh (along {} at \
         {:.0} %: {}); --axis and --plane choose the plane, --skip taper leaves the step out",
        axis_name(axis),
        100.0 * fraction,
        first_failure.unwrap_or_default()
    ))
}

/// The sub-mesh of an open mesh no plane section closes around: the vertices beyond a
/// plane perpendicular to an axis, reached from the vertex furthest along it without
/// crossing the plane, tried in the order of [`label_submesh`] (axes, then heights).
#[cfg_attr(not(feature = "render"), allow(dead_code))]
pub(crate) fn mask_submesh(
    mesh: &Mesh,
    axis: DVec3,
    fraction: f64,
) -> Result<(SubMesh, String), String> {
    let live = mesh.vertices().filter(|&v| !mesh.is_isolated(v)).count();
    for cut in cutting_planes(mesh, axis, fraction)? {
        let (a, tip, f, height) = (cut.axis, cut.tip, cut.fraction, cut.height);
        // Flood from the tip over the vertices beyond the plane.
        let mut inside = vec![false; mesh.vertex_slots()];
        let mut stack = vec![tip];
        inside[mesh.vertex_index(tip)] = true;
        let mut count = 1;
        while let Some(v) = stack.pop() {
            for w in mesh.adjacent_vertices(v) {
                let i = mesh.vertex_index(w);
                if !inside[i] && mesh.position(w).dot(a) >= height {
                    inside[i] = true;
                    count += 1;
                    stack.push(w);
                }
            }
        }
        if count < MIN_SUBMESH || live - count < MIN_SUBMESH {
            continue;
        }
        let mask = halfedge::VertexData::new(mesh, inside).map_err(|e| e.to_string())?;
        let sub = SubMesh::from_mask(mesh, &mask).map_err(|e| e.to_string())?;
        let detail = format!(
            "plane {} = {height:.3} ({:.0} % of the extent): the {count} vertices beyond \
                 it reached from the vertex furthest along {} (an open cut: vertex mask), \
                 the rest {}",
            axis_name(a),
            100.0 * f,
            axis_name(a),
            live - count
        );
        return Ok((sub, detail));
    }
    Err("no plane perpendicular to ±x, ±y or ±z has vertices beyond it".into())
}
