//! Helpers shared by the region-based editing tools (*Lee area editing*, *Bendels–Klein*):
//! a scratch copy of the mesh for the library sessions that write through `&mut Mesh`,
//! Euclidean brush balls, and script parameters naming vertices.

use std::collections::VecDeque;
use std::time::Duration;

use glam::DVec3;
use halfedge::{Binding, Mesh, VertexId};

use super::{ToolContext, ToolError};
use crate::document::Document;

/// A copy of the document's mesh that library sessions may write into (they take
/// `&mut Mesh`); the tool then copies the positions it changed into the document
/// through [`ToolContext::positions_mut`], so that the viewer records one undo step per
/// gesture and only refits its picking structure (no connectivity change).
#[derive(Clone, Default)]
pub struct Scratch {
    mesh: Option<Mesh>,
    /// The document mesh's binding when the copy was made: the copy's connectivity is
    /// the document's while it [fits](halfedge::Binding::fits) (positions aside).
    binding: Option<Binding>,
}

impl Scratch {
    /// The scratch mesh, brought up to date with the document (cloned after a change of
    /// connectivity, else only its positions are copied).
    pub fn sync(&mut self, doc: &Document) -> &mut Mesh {
        let fits = self.binding.as_ref().is_some_and(|b| b.fits(doc.mesh()));
        match &mut self.mesh {
            Some(mesh) if fits => {
                mesh.positions_mut().copy_from_slice(doc.mesh().positions());
            }
            _ => {
                self.mesh = Some(doc.mesh().clone());
                self.binding = Some(doc.mesh().binding());
            }
        }
        self.mesh.as_mut().expect("set above")
    }

    /// The scratch mesh as last synchronised (panics before the first [`sync`](Self::sync)).
    pub fn mesh(&self) -> &Mesh {
        self.mesh.as_ref().expect("Scratch::sync is called first")
    }

    /// Forgets the copy (the next [`sync`](Self::sync) clones again).
    pub fn clear(&mut self) {
        self.mesh = None;
    }
}

/// Copies the positions of `slots` from `source` into the document, inside the open
/// undo step (or a new one named `label`).
pub fn copy_positions(
    ctx: &mut ToolContext<'_>,
    label: &str,
    source: &Mesh,
    slots: impl Iterator<Item = usize>,
) {
    ctx.begin_edit(label);
    let from = source.positions();
    let to = ctx.positions_mut();
    for i in slots {
        to[i] = from[i];
    }
}

/// The vertices reachable from `seed` through edges without leaving the Euclidean ball
/// of radius `radius` around it (a brush stroke that does not jump across thin gaps).
pub fn ball_vertices(mesh: &Mesh, seed: VertexId, radius: f64) -> Vec<VertexId> {
    let centre = mesh.position(seed);
    let mut seen = vec![false; mesh.vertex_slots()];
    seen[mesh.vertex_index(seed)] = true;
    let mut queue = VecDeque::from([seed]);
    let mut out = Vec::new();
    while let Some(v) = queue.pop_front() {
        out.push(v);
        for w in mesh.adjacent_vertices(v) {
            let i = mesh.vertex_index(w);
            if !seen[i] && mesh.position(w).distance(centre) <= radius {
                seen[i] = true;
                queue.push_back(w);
            }
        }
    }
    out
}

/// The bounding-box diagonal (1 for an empty mesh).
pub fn diagonal(mesh: &Mesh) -> f64 {
    mesh.bounding_box()
        .map_or(1.0, |(lo, hi)| (hi - lo).length())
        .max(1e-12)
}

/// Reads a vertex index parameter.
pub fn vertex_param(
    mesh: &Mesh,
    name: &str,
    value: &serde_json::Value,
) -> Result<VertexId, ToolError> {
    let i = value
        .as_u64()
        .ok_or_else(|| ToolError::bad_value(name, "a vertex index", value))?;
    mesh.vertex_at(i as usize)
        .ok_or_else(|| ToolError::new(format!("parameter {name:?}: no vertex {i}")))
}

/// Reads a list of vertex indices.
pub fn vertex_list_param(
    mesh: &Mesh,
    name: &str,
    value: &serde_json::Value,
) -> Result<Vec<VertexId>, ToolError> {
    let list = value
        .as_array()
        .ok_or_else(|| ToolError::bad_value(name, "an array of vertex indices", value))?;
    list.iter().map(|v| vertex_param(mesh, name, v)).collect()
}

/// Reads a 3-vector `[x, y, z]`.
pub fn vec3_param(name: &str, value: &serde_json::Value) -> Result<DVec3, ToolError> {
    let bad = || ToolError::bad_value(name, "[x, y, z] (numbers)", value);
    let list = value.as_array().ok_or_else(bad)?;
    if list.len() != 3 {
        return Err(bad());
    }
    let mut v = [0.0; 3];
    for (x, item) in v.iter_mut().zip(list) {
        *x = item.as_f64().filter(|x| x.is_finite()).ok_or_else(bad)?;
    }
    Ok(DVec3::from_array(v))
}

/// A duration for the status line.
pub fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1e3)
}
