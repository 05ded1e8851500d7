//! The workflow's Lee 1999 rule: an editing area around a front vertex, dragged along its
//! normal, marked in the hierarchy.

use edit::lee::{AreaSession, EditingArea, SessionOptions};
use edit::HierarchyEdit;
use halfedge::hierarchy::Hierarchy;

use super::picks;
use crate::progress::{self, Progress};

/// The smallest Lee area tried: a vertex and its ring.
const MIN_AREA: usize = 7;

/// The Lee rule of the module docs: an editing area around a front vertex, dragged along
/// its normal. Returns the table's detail and a note when the rule had to adapt.
pub(super) fn lee_drag(
    hierarchy: &mut Hierarchy,
    diagonal: f64,
    progress: &mut dyn Progress,
) -> Result<(String, Option<String>), String> {
    let mesh = hierarchy.mesh();
    // The extreme vertices, then (`None`: found only if they all fail) the vertex
    // farthest from the boundary.
    let centres = picks::drag_candidates(mesh)
        .into_iter()
        .map(Some)
        .chain([None]);
    let n = mesh.n_vertices();
    let first_size = (n / 12).clamp(30, 5_000).min(n / 3).max(MIN_AREA);
    let mut first_failure: Option<String> = None;
    for (attempt, candidate) in centres.enumerate() {
        let Some((centre, what)) =
            candidate.or_else(|| picks::farthest_candidate(hierarchy.mesh()))
        else {
            continue;
        };
        let mut size = first_size;
        while size >= MIN_AREA {
            let mesh = hierarchy.mesh();
            let tried = EditingArea::disk_around(mesh, centre, size).and_then(|area| {
                let options = SessionOptions::default().with_scale(0.6);
                progress::step(progress, "Lee: embedding the editing area", || {
                    AreaSession::new(mesh, area, &options)
                })
            });
            match tried {
                Ok(mut session) => {
                    let pull = mesh.vertex_normal(centre) * 0.15 * diagonal;
                    // The drag tells the hierarchy its area and the primitive's
                    // translation: refined back, the primitive lands on its target and
                    // nothing outside the area moves.
                    session
                        .set_primitive(hierarchy.mesh(), &[centre])
                        .and_then(|()| session.drag(hierarchy.mesh_mut(), pull))
                        .map_err(edit::Error::from)
                        .and_then(|()| session.mark(hierarchy))
                        .and_then(|()| Ok(session.commit(hierarchy.mesh())?))
                        .map_err(|e| e.to_string())?;
                    let mesh = hierarchy.mesh();
                    let detail = format!(
                        "area of {} vertices around v{} ({what}), pulled by {:.3} along its \
                         normal at s = 0.6",
                        session.area().vertices().len(),
                        mesh.vertex_index(centre),
                        pull.length()
                    );
                    let note = (attempt > 0 || size != first_size).then(|| {
                        format!(
                            "the Lee area of {first_size} vertices around the front vertex \
                             could not be used ({}); used {size} vertices around {what}",
                            first_failure.as_deref().unwrap_or("?")
                        )
                    });
                    return Ok((detail, note));
                }
                Err(e) => {
                    first_failure.get_or_insert_with(|| e.to_string());
                }
            }
            size /= 2;
        }
    }
    Err(format!(
        "no disk of {MIN_AREA} or more vertices around an extreme vertex or the vertex \
         farthest from the boundary is a valid editing area (first: {})",
        first_failure.unwrap_or_default()
    ))
}
