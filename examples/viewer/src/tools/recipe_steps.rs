//! The recipe steps of the tools' edits (see [`crate::recipe_log`]), in the schema's exact
//! forms: vertex indices for places and regions, the handle's matrix, the drag vector, an
//! axis as the tool computed it, so that replaying a step computes what the tool did, bit
//! for bit.

use edit::bendels_klein::{DistanceKind, Regions, Role, ShapeFunction};
use edit::lee::EditingArea;
use glam::{DMat4, DVec3};
use halfedge::{Mesh, VertexId};
use multires::recipe::{Blend, LeeDrag, Place, Region, Step};

use super::ToolContext;

/// The level a step made now is made at (see `Document::recipe_level`).
pub fn level(ctx: &ToolContext<'_>) -> Result<Option<usize>, String> {
    ctx.doc.recipe_level()
}

/// The indices of `vertices`, sorted.
pub fn indices(mesh: &Mesh, vertices: impl IntoIterator<Item = VertexId>) -> Vec<u32> {
    let mut out: Vec<u32> = vertices
        .into_iter()
        .map(|v| mesh.vertex_index(v) as u32)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// The place of a vertex, exactly.
pub fn place(mesh: &Mesh, v: VertexId) -> Place {
    Place::Vertex(mesh.vertex_index(v))
}

/// A 3-vector as the schema writes it.
pub fn array(v: DVec3) -> [f64; 3] {
    v.to_array()
}

/// A Lee editing area as a region the recipe resolves to the same area (the same faces in
/// the same order, the same picks): its boundary picks for a loop, else its vertices when
/// the faces they span are exactly the area's.
///
/// # Errors
/// Why the area has no exact region (then the edit cannot be recorded).
pub fn lee_area(
    mesh: &Mesh,
    area: &EditingArea,
    picks: Option<&[VertexId]>,
) -> Result<Region, String> {
    if let Some(picks) = picks {
        return Ok(Region::Loop {
            through: picks.iter().map(|&v| place(mesh, v)).collect(),
        });
    }
    let mut inside = vec![false; mesh.vertex_slots()];
    for &v in area.vertices() {
        inside[mesh.vertex_index(v)] = true;
    }
    let spanned: Vec<usize> = mesh
        .faces()
        .filter(|&f| mesh.face_vertices(f).all(|v| inside[mesh.vertex_index(v)]))
        .map(|f| mesh.face_index(f))
        .collect();
    let faces: Vec<usize> = area.faces().iter().map(|&f| mesh.face_index(f)).collect();
    if spanned != faces {
        return Err(format!(
            "its vertices span {} faces, the area has {}",
            spanned.len(),
            faces.len()
        ));
    }
    Ok(Region::Vertices {
        indices: indices(mesh, area.vertices().iter().copied()),
    })
}

/// A Lee drag: the area, the primitive, the drag vector, the scale and the frames.
pub fn lee_drag(
    level: Option<usize>,
    area: Region,
    primitive: Vec<Place>,
    pull: DVec3,
    scale: f64,
    normal_frames: bool,
) -> Step {
    Step::LeeDrag(LeeDrag {
        level,
        area,
        primitive,
        pull: Some(array(pull)),
        along_normal: None,
        scale: Some(scale),
        frames: normal_frames.then(|| "normal".to_owned()),
    })
}

/// A Bendels–Klein edit: the handle and fixed vertices of `regions` (the recipe makes the
/// same roles of them), the handle's matrix, the distances and the shape function.
///
/// # Errors
/// A shape function the recipe cannot name (a curve drawn in the editor).
pub fn blend(
    mesh: &Mesh,
    level: Option<usize>,
    regions: &Regions,
    a: DMat4,
    distance: DistanceKind,
    shape: &ShapeFunction,
) -> Result<Step, String> {
    let shape = match shape {
        ShapeFunction::Smoothstep => None,
        ShapeFunction::Linear => Some("linear"),
        ShapeFunction::Smootherstep => Some("smootherstep"),
        ShapeFunction::Curve(_) => {
            return Err("a shape function drawn in the curve editor".to_owned());
        }
    };
    let roles = regions.roles();
    let of = |role: Role| {
        indices(
            mesh,
            mesh.vertices()
                .filter(|&v| !mesh.is_isolated(v) && roles[mesh.vertex_index(v)] == role),
        )
    };
    Ok(Step::Blend(Blend {
        level,
        handle: Region::Vertices {
            indices: of(Role::Handle),
        },
        fixed: Region::Vertices {
            indices: of(Role::Fixed),
        },
        transform: Some(a.transpose().to_cols_array_2d()),
        rotate: None,
        scale: None,
        translate: None,
        distance: match distance {
            DistanceKind::Euclidean => Some("euclidean".to_owned()),
            _ => None,
        },
        shape: shape.map(str::to_owned),
    }))
}
