//! The workflow's Bendels & Klein rule: a handle around the vertex furthest along −x,
//! rotated and pulled, marked in the hierarchy so that it lands exactly at full
//! resolution.

use edit::bendels_klein::{BlendOptions, BlendSession, DistanceKind, Regions, ShapeFunction};
use edit::HierarchyEdit;
use glam::{DMat4, DVec3};
use halfedge::hierarchy::Hierarchy;
use halfedge::{Mesh, VertexId};

use crate::progress::{self, Progress};

/// Where the Bendels & Klein handle should land: its coarse vertex slots and the rigid
/// map the user gave it.
pub(super) struct Landing {
    pub(super) handle: Vec<u32>,
    map: glam::DAffine3,
}

/// The Bendels & Klein rule of the module docs: a handle around the vertex furthest
/// along −x of the hierarchy's current mesh, rotated and pulled, in the hierarchy
/// (`BlendSession::apply` and `HierarchyEdit::mark`: the handle lands exactly at full resolution, the
/// fixed part stays where it was). Returns the table's detail and a note when the radii
/// had to shrink.
pub(super) fn blend_rotate(
    hierarchy: &mut Hierarchy,
    diagonal: f64,
    progress: &mut dyn Progress,
) -> Result<(String, Option<String>, Landing), String> {
    let mesh = hierarchy.mesh();
    let side = mesh
        .extreme_vertex(DVec3::NEG_X)
        .map_err(|e| e.to_string())?
        .ok_or("the mesh has no vertex with a face")?;
    // The same rule on the largest component, for a mesh whose extreme vertex is on a
    // small part (an eye, a loose piece) that the handle would cover whole.
    let mut sides = vec![(side, "the mesh")];
    let largest = mesh.select_largest_component();
    if let Some(v) = largest
        .extreme_vertex(mesh, DVec3::NEG_X)
        .map_err(|e| e.to_string())?
        .filter(|&v| v != side)
    {
        sides.push((v, "its largest component"));
    }
    let mut first_failure: Option<String> = None;
    for (k, &(side, whose)) in sides.iter().enumerate() {
        let centre = hierarchy.mesh().position(side);
        let side_index = hierarchy.mesh().vertex_index(side);
        for halvings in 0..4 {
            let scale = 0.5f64.powi(halvings);
            let (r_handle, r_fixed) = (0.08 * diagonal * scale, 0.3 * diagonal * scale);
            let attempt = (|| -> Result<(usize, usize, Landing), String> {
                let mesh = hierarchy.mesh();
                let handle = mesh
                    .select_edge_ball(&[side], r_handle)
                    .map_err(|e| e.to_string())?;
                let near = mesh
                    .select_edge_ball(&[side], r_fixed)
                    .map_err(|e| e.to_string())?;
                let fixed: Vec<VertexId> = mesh
                    .vertices()
                    .filter(|&v| !near.contains(mesh, v))
                    .collect();
                let regions = Regions::from_sets(mesh, &handle.vertices(mesh), &fixed)
                    .map_err(|e| e.to_string())?;
                let n_deformable = regions.deformable().len();
                let n_handle = regions.handle().len();
                let handle_slots: Vec<u32> = regions
                    .handle()
                    .iter()
                    .map(|&v| mesh.vertex_index(v) as u32)
                    .collect();
                let options = BlendOptions::default()
                    .with_distance(DistanceKind::Geodesic)
                    .with_shape(ShapeFunction::Smoothstep);
                let mut blend =
                    progress::step(progress, "B&K: geodesic distances (fast marching)", || {
                        BlendSession::new(mesh, regions, options)
                    })
                    .map_err(|e| e.to_string())?;
                let rotation = DMat4::from_translation(centre)
                    * DMat4::from_axis_angle(DVec3::Z, 25f64.to_radians())
                    * DMat4::from_translation(-centre)
                    * DMat4::from_translation(-DVec3::X * 0.05 * diagonal * scale);
                blend
                    .apply(hierarchy.mesh_mut(), rotation)
                    .map_err(edit::Error::from)
                    .and_then(|()| blend.mark(hierarchy))
                    .map_err(|e| e.to_string())?;
                let landing = Landing {
                    handle: handle_slots,
                    map: glam::DAffine3::from_mat4(rotation),
                };
                Ok((n_handle, n_deformable, landing))
            })();
            match attempt {
                Ok((n_handle, n_deformable, landing)) => {
                    let detail = format!(
                        "handle of {n_handle} vertices within {r_handle:.3} of v{} (furthest \
                     along -x of {whose}) rotated 25° and pulled; {n_deformable} deformable \
                     vertices, fixed beyond {r_fixed:.3}",
                        side_index
                    );
                    let note = (k > 0 || halvings > 0).then(|| {
                        format!(
                            "the Bendels & Klein regions at 8 % / 30 % of the diagonal around the \
                         vertex furthest along -x could not be used ({}); used {:.1} % / \
                         {:.1} % around the one of {whose}",
                            first_failure.as_deref().unwrap_or("?"),
                            8.0 * scale,
                            30.0 * scale
                        )
                    });
                    return Ok((detail, note, landing));
                }
                Err(e) => {
                    first_failure.get_or_insert(e);
                }
            }
        }
    }
    Err(format!(
        "no handle and fixed region around the vertex furthest along -x of the mesh or of its \
         largest component work, down to 1 % / 3.75 % of the diagonal (first: {})",
        first_failure.unwrap_or_default()
    ))
}

impl Landing {
    /// How exactly the handle landed: the number of fine vertices whose ancestor at the
    /// edited level is a handle vertex, and the largest distance (over the diagonal)
    /// between such a vertex and the rigid image of its input position.
    pub(super) fn measure(
        &self,
        original: &Mesh,
        result: &Mesh,
        ancestors: &[u32],
        diagonal: f64,
    ) -> (usize, f64) {
        let mut in_handle = vec![false; result.vertex_slots()];
        for &i in &self.handle {
            if let Some(x) = in_handle.get_mut(i as usize) {
                *x = true;
            }
        }
        let (mut count, mut worst) = (0usize, 0.0f64);
        for v in original.vertices() {
            let i = original.vertex_index(v);
            if ancestors.get(i).is_some_and(|&a| in_handle[a as usize]) {
                let target = self.map.transform_point3(original.position(v));
                worst = worst.max(result.positions()[i].distance(target) / diagonal);
                count += 1;
            }
        }
        (count, worst)
    }
}
