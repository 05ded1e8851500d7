//! Resolving a recipe's places and regions on the mesh a step is made on.

use edit::deform::SubMesh;
use edit::lee::{AreaSide, EditingArea};
use glam::DVec3;
use halfedge::labels::LABEL_ATTRIBUTE;
use halfedge::{Mesh, VertexId};

use super::schema::{Place, Region};
use crate::cut as submesh;

/// What fractions of a step are fractions of: the bounding-box diagonal of the mesh the
/// step is made on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// The bounding-box diagonal.
    pub diagonal: f64,
}

impl Frame {
    /// The frame of `mesh` (`None` for a mesh without vertices).
    #[must_use]
    pub fn of(mesh: &Mesh) -> Option<Self> {
        let (lo, hi) = mesh.bounding_box()?;
        Some(Self {
            diagonal: lo.distance(hi),
        })
    }
}

/// The vertex a place names on `mesh`.
///
/// # Errors
/// A message: a point that is not finite, an unknown axis, an index that is not a live
/// vertex, a mesh without a vertex with a face.
pub fn resolve_place(mesh: &Mesh, place: &Place) -> Result<VertexId, String> {
    match place {
        Place::Nearest(p) => mesh
            .nearest_vertex(DVec3::from_array(*p))
            .map_err(|e| e.to_string())?
            .ok_or_else(|| "the mesh has no vertex with a face".to_owned()),
        Place::Extreme(axis) => mesh
            .extreme_vertex(parse_axis(axis)?)
            .map_err(|e| e.to_string())?
            .ok_or_else(|| "the mesh has no vertex with a face".to_owned()),
        Place::Vertex(i) => mesh
            .vertex_at(*i)
            .filter(|&v| !mesh.is_isolated(v))
            .ok_or_else(|| format!("vertex {i} is not a vertex with a face of this mesh")),
    }
}

fn fraction(name: &str, value: f64) -> Result<f64, String> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(format!(
            "{name} must be finite and not negative, got {value}"
        ))
    }
}

/// The vertices of a region on `mesh` (sorted by index). A `cut` or `plane` region labels
/// the mesh (its label attribute) to find its part.
///
/// # Errors
/// A message saying why the region selects nothing on this mesh.
pub fn resolve_region(
    mesh: &mut Mesh,
    region: &Region,
    frame: Frame,
) -> Result<Vec<VertexId>, String> {
    let mut vertices = match region {
        Region::Disk { around, vertices } => {
            let centre = resolve_place(mesh, around)?;
            EditingArea::disk_around(mesh, centre, *vertices)
                .map_err(|e| e.to_string())?
                .vertices()
                .to_vec()
        }
        Region::Ball { around, radius } => {
            let centre = resolve_place(mesh, around)?;
            let r = fraction("radius", *radius)? * frame.diagonal;
            let ball = mesh
                .select_edge_ball(&[centre], r)
                .map_err(|e| e.to_string())?;
            ball.vertices(mesh)
        }
        Region::Beyond { around, radius } => {
            let centre = resolve_place(mesh, around)?;
            let r = fraction("radius", *radius)? * frame.diagonal;
            let near = mesh
                .select_edge_ball(&[centre], r)
                .map_err(|e| e.to_string())?;
            mesh.vertices()
                .filter(|&v| !near.contains(mesh, v))
                .collect()
        }
        Region::Cut { .. } | Region::Plane { .. } | Region::Label { .. } => {
            let sub = resolve_submesh(mesh, region, frame)?;
            sub.vertex_indices()
                .iter()
                .filter_map(|&i| mesh.vertex_at(i as usize))
                .collect()
        }
        Region::Vertices { indices } => indices
            .iter()
            .map(|&i| {
                mesh.vertex_at(i as usize)
                    .ok_or_else(|| format!("vertex {i} is not a vertex of this mesh"))
            })
            .collect::<Result<_, _>>()?,
        Region::All => mesh.vertices().filter(|&v| !mesh.is_isolated(v)).collect(),
        Region::Loop { .. } => resolve_area(mesh, region, frame)?.vertices().to_vec(),
    };
    vertices.sort_by_key(|&v| mesh.vertex_index(v));
    vertices.dedup();
    if vertices.is_empty() {
        return Err("the region selects no vertex".to_owned());
    }
    Ok(vertices)
}

/// A region as a sub-mesh: `cut`, `plane` and `label` regions by their labels (a closed
/// frontier), the others by their vertices.
///
/// # Errors
/// A message saying why the region is no sub-mesh here.
pub(crate) fn resolve_submesh(
    mesh: &mut Mesh,
    region: &Region,
    frame: Frame,
) -> Result<SubMesh, String> {
    match region {
        Region::Cut { axis, at } => {
            let axis = parse_axis(axis)?;
            if !(*at >= 0.0 && *at < 1.0) {
                return Err(format!("at must be in [0, 1), got {at}"));
            }
            Ok(submesh::label_submesh(mesh, axis, *at)?.sub)
        }
        Region::Plane { point, normal } => {
            let frontier = mesh
                .frontier_from_plane(DVec3::from_array(*point), DVec3::from_array(*normal))
                .map_err(|e| e.to_string())?;
            let (attribute, _) = mesh
                .label_sides(&frontier, 1, 2)
                .map_err(|e| e.to_string())?;
            SubMesh::from_labels(mesh, attribute, |&l| l == 1).map_err(|e| e.to_string())
        }
        Region::Label { label } => {
            let attribute = mesh
                .find_attribute::<VertexId, u32>(LABEL_ATTRIBUTE)
                .ok_or_else(|| "the mesh has no sub-mesh labels".to_owned())?;
            SubMesh::from_labels(mesh, attribute, |&l| l == *label).map_err(|e| e.to_string())
        }
        other => {
            let vertices = resolve_region(mesh, other, frame)?;
            SubMesh::from_vertices(mesh, &vertices).map_err(|e| e.to_string())
        }
    }
}

/// A region as a Lee editing area: a `disk` grown around its centre, a `loop` filled on
/// its smaller side, any other region by the faces whose three corners it holds.
///
/// # Errors
/// A message saying why the region is no editing area here (not a disk, touching the
/// mesh boundary).
pub(crate) fn resolve_area(
    mesh: &mut Mesh,
    region: &Region,
    frame: Frame,
) -> Result<EditingArea, String> {
    if let Region::Disk { around, vertices } = region {
        let centre = resolve_place(mesh, around)?;
        return EditingArea::disk_around(mesh, centre, *vertices).map_err(|e| e.to_string());
    }
    if let Region::Loop { through } = region {
        if through.len() < 3 {
            return Err(format!(
                "a loop needs at least 3 places, got {}",
                through.len()
            ));
        }
        let picks = through
            .iter()
            .map(|p| resolve_place(mesh, p))
            .collect::<Result<Vec<_>, _>>()?;
        return EditingArea::from_picks(mesh, &picks, AreaSide::Smaller).map_err(|e| e.to_string());
    }
    let vertices = resolve_region(mesh, region, frame)?;
    let mut inside = vec![false; mesh.vertex_slots()];
    for &v in &vertices {
        inside[mesh.vertex_index(v)] = true;
    }
    let faces: Vec<_> = mesh
        .faces()
        .filter(|&f| mesh.face_vertices(f).all(|v| inside[mesh.vertex_index(v)]))
        .collect();
    EditingArea::from_faces(mesh, &faces).map_err(|e| e.to_string())
}

/// The centre of a region: its place when it has one (disk, ball, beyond), else the
/// centroid of `vertices`.
pub(crate) fn region_centre(mesh: &Mesh, region: &Region, vertices: &[VertexId]) -> DVec3 {
    let around = match region {
        Region::Disk { around, .. }
        | Region::Ball { around, .. }
        | Region::Beyond { around, .. } => resolve_place(mesh, around).ok(),
        _ => None,
    };
    around.map_or_else(
        || vertices.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / vertices.len().max(1) as f64,
        |v| mesh.position(v),
    )
}

/// Parses an axis name: `x`, `y`, `z` (or `+x`, …), `-x`, `-y`, `-z`.
///
/// # Errors
/// A message naming the unknown axis.
pub fn parse_axis(s: &str) -> std::result::Result<DVec3, String> {
    match s.trim() {
        "x" | "+x" => Ok(DVec3::X),
        "y" | "+y" => Ok(DVec3::Y),
        "z" | "+z" => Ok(DVec3::Z),
        "-x" => Ok(DVec3::NEG_X),
        "-y" => Ok(DVec3::NEG_Y),
        "-z" => Ok(DVec3::NEG_Z),
        other => Err(format!("unknown axis {other:?} (x, y, z, -x, -y or -z)")),
    }
}

/// The name of a coordinate axis (`"?"` for another direction).
pub(crate) fn axis_name(d: DVec3) -> &'static str {
    [
        (DVec3::X, "x"),
        (DVec3::Y, "y"),
        (DVec3::Z, "z"),
        (DVec3::NEG_X, "-x"),
        (DVec3::NEG_Y, "-y"),
        (DVec3::NEG_Z, "-z"),
    ]
    .iter()
    .find(|(a, _)| *a == d)
    .map_or("?", |(_, n)| n)
}
