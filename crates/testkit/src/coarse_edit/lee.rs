//! The `lee` edit: a Lee 1999 area drag of the tip at both resolutions, and the editing
//! areas it uses (a disk around the tip, its preimage at full resolution).

use std::cmp::Reverse;

use edit::lee::{
    AreaSession, EditingArea, EmbeddingOptions, EmbeddingWeights, LeeError, SessionOptions,
};
use glam::{DAffine3, DVec3};
use halfedge::{Mesh, VertexId};

use super::region::{boundary_depth, Region};
use super::{lib, Applied, Failure, Rigid};

/// Lee 1999 area drag of the tip at both levels.
pub(super) fn lee_edit(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    ancestors: &[u32],
    region: &Region,
    fraction: f64,
    amount: f64,
) -> Result<Applied, Failure> {
    let tip = region.tip;
    let tip_v = coarse
        .vertex_at(tip)
        .ok_or_else(|| Failure::new("the tip is not a live vertex", "report this bug"))?;
    // mean-value weights: the harmonic map of a coarse area with obtuse triangles can
    // fold (and put the tip outside the rectangle)
    let options = SessionOptions::default()
        .with_embedding(EmbeddingOptions::default().with_weights(EmbeddingWeights::MeanValue));
    let rest = coarse.position(tip_v);
    let normal = coarse.vertex_normal(tip_v);
    let normal = if normal == DVec3::ZERO {
        DVec3::Z
    } else {
        normal
    };
    // the largest disk (shrunk by a quarter at a time) that is accepted and whose
    // lattice reaches the tip: the tip lands on its target
    let mut size = ((fraction * region.order.len() as f64).round() as usize).max(7);
    let (area, session, drag) = loop {
        let attempt = EditingArea::from_faces(coarse, &disk_faces(coarse, region, size))
            .and_then(|area| {
                let mut session = AreaSession::new(coarse, area.clone(), &options)?;
                let reach = area
                    .boundary()
                    .iter()
                    .map(|&v| coarse.position(v).distance(rest))
                    .fold(0.0, f64::max);
                let drag = 0.3 * amount * reach * normal;
                session.set_primitive(coarse, &[tip_v])?;
                session.drag(coarse, drag)?;
                let miss = coarse.position(tip_v).distance(rest + drag) / drag.length();
                if miss > 1e-9 {
                    session.cancel(coarse)?;
                    return Err(LeeError::InvalidParameter {
                        name: "area",
                        reason: format!(
                            "its B-spline lattice does not reach the tip (the tip missed its target by {miss:.3e} of the drag)"
                        ),
                    });
                }
                Ok((area, session, drag))
            });
        match attempt {
            Ok(found) => break found,
            Err(e) if size <= 7 => {
                return Err(Failure::new(
                    format!("no Lee editing area around the tip (vertex {tip}) is accepted: {e}"),
                    "pass a --seed-vertex away from the mesh boundary and thin parts, or a finer --level",
                ))
            }
            Err(_) => size = size * 3 / 4,
        }
    };
    let hint = "pass another --seed-vertex or --region-fraction";
    coarse.set_position(tip_v, rest + drag);

    let slots = coarse.vertex_slots();
    let mut interior = vec![false; slots];
    for &v in area.interior() {
        interior[coarse.vertex_index(v)] = true;
    }
    let mut fine_region = 0;
    if let Some(fine) = fine {
        // the same area at full resolution (the input faces the hierarchy collapses
        // into it), with the same lattice (levels) and scale
        let fine_area =
            preimage_area(coarse, fine, ancestors, &area, &interior).map_err(lib(hint))?;
        let fine_options = options.with_levels(session.levels());
        fine_region = fine_area.n_interior();
        let mut fine_session =
            AreaSession::new(fine, fine_area, &fine_options).map_err(lib(hint))?;
        let primitive: Vec<VertexId> = fine
            .vertices()
            .filter(|&v| ancestors[fine.vertex_index(v)] as usize == tip)
            .collect();
        fine_session
            .set_primitive(fine, &primitive)
            .map_err(lib(hint))?;
        fine_session.drag(fine, drag).map_err(lib(hint))?;
    }
    Ok(Applied {
        movable: interior,
        fine_region,
        rigid: vec![Rigid {
            vertices: vec![tip as u32],
            map: DAffine3::from_translation(drag),
        }],
        marks: None,
    })
}

/// The faces of a disk around the tip: the first `size` vertices of the region order
/// (a ball by edge-path distance), the faces around those of them that are at least two
/// rings from the mesh boundary and whose neighbours are all in the ball, and the
/// pockets those faces enclose within the tip's component that do not reach the mesh
/// boundary (like `EditingArea::disk_around`, which grows rings instead and also fills
/// every other component of the mesh as a pocket).
fn disk_faces(mesh: &Mesh, region: &Region, size: usize) -> Vec<halfedge::FaceId> {
    let size = size.min(region.order.len());
    let depth = boundary_depth(mesh);
    let mut ball = vec![false; mesh.vertex_slots()];
    for &(i, _) in &region.order[..size] {
        ball[i as usize] = true;
    }
    let mut in_area = vec![false; mesh.face_slots()];
    for &(i, _) in &region.order[..size] {
        let Some(v) = mesh.vertex_at(i as usize) else {
            continue;
        };
        if depth[i as usize] >= 2
            && mesh
                .adjacent_vertices(v)
                .all(|w| ball[mesh.vertex_index(w)])
        {
            for f in mesh.adjacent_faces(v) {
                in_area[mesh.face_index(f)] = true;
            }
        }
    }
    let mut component = vec![false; mesh.face_slots()];
    for &(i, _) in &region.order {
        if let Some(v) = mesh.vertex_at(i as usize) {
            for f in mesh.adjacent_faces(v) {
                component[mesh.face_index(f)] = true;
            }
        }
    }
    fill_pockets(mesh, &mut in_area, &component);
    faces_of(mesh, &in_area)
}

/// The faces whose entry is true.
fn faces_of(mesh: &Mesh, in_area: &[bool]) -> Vec<halfedge::FaceId> {
    mesh.faces()
        .filter(|&f| in_area[mesh.face_index(f)])
        .collect()
}

/// Adds to `in_area` the pockets it encloses: the groups of other faces of `component`
/// (edge-connected), all but the largest, that do not reach the mesh boundary. Returns
/// true when a face was added.
fn fill_pockets(mesh: &Mesh, in_area: &mut [bool], component: &[bool]) -> bool {
    let mut group = vec![u32::MAX; mesh.face_slots()];
    let mut sizes: Vec<usize> = Vec::new();
    let mut open: Vec<bool> = Vec::new();
    for f in mesh.faces() {
        let fi = mesh.face_index(f);
        if !component[fi] || in_area[fi] || group[fi] != u32::MAX {
            continue;
        }
        let id = sizes.len() as u32;
        sizes.push(0);
        open.push(false);
        group[fi] = id;
        let mut stack = vec![f];
        while let Some(g) = stack.pop() {
            sizes[id as usize] += 1;
            open[id as usize] |= mesh.is_boundary_face(g);
            for n in mesh.face_neighbors(g) {
                let ni = mesh.face_index(n);
                if !in_area[ni] && group[ni] == u32::MAX {
                    group[ni] = id;
                    stack.push(n);
                }
            }
        }
    }
    let largest = (0..sizes.len()).max_by_key(|&i| (sizes[i], Reverse(i)));
    let mut changed = false;
    for f in mesh.faces() {
        let fi = mesh.face_index(f);
        let g = group[fi] as usize;
        if component[fi] && !in_area[fi] && Some(g) != largest && !open[g] {
            in_area[fi] = true;
            changed = true;
        }
    }
    changed
}

/// The input faces that the hierarchy collapses into the coarse editing `area`, as an
/// editing area: a face whose ancestors are three distinct vertices belongs when they
/// span a face of the area; one collapsed onto an edge, when both faces of that edge are
/// in the area; one collapsed onto a vertex, when the vertex is interior to the area.
/// (Collapses map every triangle onto a triangle, an edge or a vertex.) Pinches and
/// pockets of that set are repaired ([`accept_area`]).
fn preimage_area(
    coarse: &Mesh,
    fine: &Mesh,
    ancestors: &[u32],
    area: &EditingArea,
    interior: &[bool],
) -> Result<EditingArea, LeeError> {
    let mut in_area = vec![false; coarse.face_slots()];
    for &f in area.faces() {
        in_area[coarse.face_index(f)] = true;
    }
    let face_in_area = |h: Option<halfedge::HalfedgeId>| {
        h.and_then(|h| coarse.face(h))
            .is_some_and(|f| in_area[coarse.face_index(f)])
    };
    let vertex = |i: u32| coarse.vertex_at(i as usize);
    let image = |f: halfedge::FaceId| fine.triangle(f).map(|v| ancestors[fine.vertex_index(v)]);
    let faces: Vec<halfedge::FaceId> = fine
        .faces()
        .filter(|&f| {
            let [a, b, c] = image(f);
            let (Some(va), Some(vb), Some(vc)) = (vertex(a), vertex(b), vertex(c)) else {
                return false;
            };
            if a != b && b != c && c != a {
                // the coarse face a → b → c
                let h = coarse.find_halfedge(va, vb);
                h.is_some_and(|h| coarse.to_vertex(coarse.next(h)) == vc) && face_in_area(h)
            } else if a == b && b == c {
                interior[a as usize]
            } else {
                let (p, q) = if a == b { (va, vc) } else { (va, vb) };
                face_in_area(coarse.find_halfedge(p, q)) && face_in_area(coarse.find_halfedge(q, p))
            }
        })
        .collect();
    let mut in_area = vec![false; fine.face_slots()];
    for &f in &faces {
        in_area[fine.face_index(f)] = true;
    }
    accept_area(fine, &mut in_area)
}

/// The editing area of the faces in `in_area`, repaired where a finer mesh makes the
/// image of a coarse disk pinch (the faces around the pinch vertex are added) or enclose
/// a pocket (filled), a few times at most.
fn accept_area(mesh: &Mesh, in_area: &mut [bool]) -> Result<EditingArea, LeeError> {
    let (vertex_component, _) = mesh.connected_components();
    let mut result = EditingArea::from_faces(mesh, &faces_of(mesh, in_area));
    for _ in 0..64 {
        let changed = match &result {
            Ok(_) => break,
            Err(LeeError::AreaPinched { vertex }) => {
                let mut changed = false;
                for f in mesh.adjacent_faces(*vertex) {
                    changed |= !std::mem::replace(&mut in_area[mesh.face_index(f)], true);
                }
                changed
            }
            Err(LeeError::AreaNotDisk { .. }) => {
                let seed = mesh
                    .faces()
                    .find(|&f| in_area[mesh.face_index(f)])
                    .map(|f| vertex_component[mesh.vertex_index(mesh.triangle(f)[0])]);
                let component: Vec<bool> = (0..mesh.face_slots())
                    .map(|i| {
                        mesh.face_at(i).is_some_and(|f| {
                            Some(vertex_component[mesh.vertex_index(mesh.triangle(f)[0])]) == seed
                        })
                    })
                    .collect();
                fill_pockets(mesh, in_area, &component)
            }
            Err(_) => false,
        };
        if !changed {
            break;
        }
        result = EditingArea::from_faces(mesh, &faces_of(mesh, in_area));
    }
    result
}
