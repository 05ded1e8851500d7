//! Sections `MESH` (the mesh at the saved level: every slot, live, removed by a collapse
//! or vacant, with its links, state and generation, and every position) and `LABL` (the
//! sub-mesh label attributes).

use super::bytes::{get_u32, get_u64, get_vec3, put_u32, put_u64, put_vec3, In, Out};
use crate::error::{Error, Result};
use crate::handle::{Slots, NONE};
use crate::hierarchy::Hierarchy;
use crate::labels::{Label, LABEL_ATTRIBUTE};
use crate::mesh::{HalfedgeRec, Mesh};

/// Writes a slot table.
fn write_slots(slots: &Slots, out: &mut impl Out) {
    let (states, len, generations, free) = slots.raw_parts();
    out.usize(len);
    out.array(states, 8, |&w, b| put_u64(b, w));
    out.array(generations, 4, |&g, b| put_u32(b, g));
    out.array(free, 4, |&i, b| put_u32(b, i));
}

/// Reads a slot table (`what`: the element kind, for messages).
fn read_slots(input: &mut In<'_>, pairs: bool, what: &str) -> Result<Slots> {
    let len = input.usize_at_most(
        u32::MAX as usize - 1,
        &format!("the number of {what} slots"),
    )?;
    let states = input.array(8, &format!("{what} slot states"), get_u64)?;
    let generations = input.array(4, &format!("{what} generations"), get_u32)?;
    let free = input.array(4, &format!("free {what} slots"), get_u32)?;
    input
        .check(Slots::from_raw_parts(states, len, generations, free, pairs))
        .map_err(|e| prefix(e, what))
}

/// `e` with "`what` slots: " before its message.
fn prefix(e: Error, what: &str) -> Error {
    match e {
        Error::Format { path, message } => Error::Format {
            path,
            message: message.replacen(": ", &format!(": {what} slots: "), 1),
        },
        e => e,
    }
}

/// The numbers of vertex and halfedge slots of section `MESH`, read ahead of the rest
/// (the records' indices are checked against them while the mesh is read).
pub(super) fn slot_counts(input: &mut In<'_>) -> Result<(usize, usize)> {
    let limit = u32::MAX as usize - 1;
    let nv = input.usize_at_most(limit, "the number of vertex slots")?;
    for (size, what) in [
        (8, "vertex slot states"),
        (4, "vertex generations"),
        (4, "free vertex slots"),
    ] {
        input.skip_array(size, what)?;
    }
    let nh = input.usize_at_most(limit, "the number of halfedge slots")?;
    Ok((nv, nh))
}

/// Writes section `MESH` of `mesh`.
pub(super) fn write(mesh: &Mesh, out: &mut impl Out) {
    write_slots(&mesh.vertex_slots_, out);
    write_slots(&mesh.halfedge_slots_, out);
    write_slots(&mesh.face_slots_, out);
    out.array(&mesh.vertex_conn, 4, |&h, b| put_u32(b, h));
    out.array(&mesh.positions, 24, |&p, b| put_vec3(b, p));
    out.array(&mesh.he, 16, |r, b| {
        put_u32(b, r.to);
        put_u32(&mut b[4..], r.next);
        put_u32(&mut b[8..], r.prev);
        put_u32(&mut b[12..], r.face);
    });
    out.array(&mesh.face_conn, 4, |&h, b| put_u32(b, h));
    out.usize(mesh.n_vertices);
    out.usize(mesh.n_halfedges);
    out.usize(mesh.n_faces);
}

/// Reads section `MESH`: the slot tables sound, the arrays as long as their tables,
/// every link of every slot (live or not) `NONE` or in range, every position finite,
/// and the live mesh passing [`Mesh::check`] (links, faces, fans, counts).
pub(super) fn read(input: &mut In<'_>) -> Result<Mesh> {
    let vertex_slots_ = read_slots(input, false, "vertex")?;
    let halfedge_slots_ = read_slots(input, true, "halfedge")?;
    let face_slots_ = read_slots(input, false, "face")?;
    let vertex_conn = input.array(4, "vertex halfedges", get_u32)?;
    let positions = input.array(24, "positions", get_vec3)?;
    let he = input.array(16, "halfedges", |b| HalfedgeRec {
        to: get_u32(b),
        next: get_u32(&b[4..]),
        prev: get_u32(&b[8..]),
        face: get_u32(&b[12..]),
    })?;
    let face_conn = input.array(4, "face halfedges", get_u32)?;
    let n_vertices = input.usize("the vertex count")?;
    let n_halfedges = input.usize("the halfedge count")?;
    let n_faces = input.usize("the face count")?;
    input.end()?;
    let (nv, nh, nf) = (
        vertex_slots_.len(),
        halfedge_slots_.len(),
        face_slots_.len(),
    );
    if vertex_conn.len() != nv || positions.len() != nv {
        return Err(input.error(format!(
            "{} vertex halfedges and {} positions for {nv} vertex slots",
            vertex_conn.len(),
            positions.len()
        )));
    }
    if he.len() != nh || nh % 2 != 0 {
        return Err(input.error(format!(
            "{} halfedges for {nh} halfedge slots (an even number)",
            he.len()
        )));
    }
    if face_conn.len() != nf {
        return Err(input.error(format!(
            "{} face halfedges for {nf} face slots",
            face_conn.len()
        )));
    }
    let ok = |i: u32, n: usize| i == NONE || (i as usize) < n;
    if let Some(v) = vertex_conn.iter().position(|&h| !ok(h, nh)) {
        return Err(input.error(format!("vertex slot {v} names a halfedge out of range")));
    }
    if let Some(h) = he
        .iter()
        .position(|r| !(ok(r.to, nv) && ok(r.next, nh) && ok(r.prev, nh) && ok(r.face, nf)))
    {
        return Err(input.error(format!("halfedge slot {h} has a link out of range")));
    }
    if let Some(f) = face_conn.iter().position(|&h| !ok(h, nh)) {
        return Err(input.error(format!("face slot {f} names a halfedge out of range")));
    }
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        return Err(input.error(format!("vertex slot {v} has a non-finite position")));
    }
    let mut mesh = Mesh {
        vertex_conn,
        vertex_slots_,
        he,
        halfedge_slots_,
        face_conn,
        face_slots_,
        positions,
        n_vertices,
        n_halfedges,
        n_faces,
        ..Mesh::default()
    };
    mesh.vertex_attributes.ensure_len(nv);
    mesh.halfedge_attributes.ensure_len(nh);
    mesh.face_attributes.ensure_len(nf);
    if let Err(e) = mesh.check() {
        return Err(input.error(format!("the mesh is not valid: {e}")));
    }
    Ok(mesh)
}

/// A label attribute's name and values, by vertex slot.
pub(super) type LabelColumn<'a> = (&'a str, &'a [Label]);

/// The label attributes section `LABL` keeps: the attached one (first) and the mesh's
/// [`LABEL_ATTRIBUTE`] when it is another, each with its name and values.
///
/// # Errors
/// [`Error::InvalidArgument`] when the attached attribute was removed from the mesh.
pub(super) fn label_attributes(h: &Hierarchy) -> Result<(Vec<LabelColumn<'_>>, bool)> {
    let mesh = &h.mesh;
    let mut out = Vec::new();
    if let Some(binding) = h.labels {
        let (Some(name), Ok(values)) = (
            mesh.attribute_name(binding.attribute),
            mesh.attribute_values(binding.attribute),
        ) else {
            return Err(Error::InvalidArgument(
                "save: the label attribute attached to the hierarchy was removed from its mesh \
                 (detach_labels, or attach_labels again)"
                    .into(),
            ));
        };
        out.push((name, values));
    }
    if let Some(a) = mesh.find_attribute::<crate::handle::VertexId, Label>(LABEL_ATTRIBUTE) {
        if h.labels.is_none_or(|b| b.attribute != a) {
            if let (Some(name), Ok(values)) = (mesh.attribute_name(a), mesh.attribute_values(a)) {
                out.push((name, values));
            }
        }
    }
    Ok((out, h.labels.is_some()))
}

/// Writes section `LABL`: the attributes of [`label_attributes`] and whether the first
/// is attached.
pub(super) fn write_labels(attributes: &[LabelColumn<'_>], attached: bool, out: &mut impl Out) {
    out.usize(attributes.len());
    for (name, values) in attributes {
        out.array(name.as_bytes(), 1, |&c, b| b[0] = c);
        out.array(values, 4, |&l, b| put_u32(b, l));
    }
    out.bool(attached);
}

/// Section `LABL` read back: the attributes (name, values by vertex slot) and whether
/// the first is attached.
pub(super) struct Labels {
    pub(super) attributes: Vec<(String, Vec<Label>)>,
    pub(super) attached: bool,
}

/// Longest attribute name read.
const MAX_NAME: usize = 4096;

/// Reads section `LABL` for a mesh of `vertex_slots` vertex slots: at most two
/// attributes, UTF-8 names of different text, a value per vertex slot.
pub(super) fn read_labels(input: &mut In<'_>, vertex_slots: usize) -> Result<Labels> {
    let n = input.usize_at_most(2, "the number of label attributes")?;
    let mut attributes: Vec<(String, Vec<Label>)> = Vec::with_capacity(n);
    for _ in 0..n {
        let name = input.array(1, "an attribute name", |b| b[0])?;
        if name.len() > MAX_NAME {
            return Err(input.error(format!("an attribute name of {} bytes", name.len())));
        }
        let Ok(name) = String::from_utf8(name) else {
            return Err(input.error("an attribute name is not UTF-8"));
        };
        if attributes.iter().any(|(other, _)| *other == name) {
            return Err(input.error(format!("the attribute {name:?} is there twice")));
        }
        let values = input.array(4, "label values", get_u32)?;
        if values.len() != vertex_slots {
            return Err(input.error(format!(
                "{} label values for {vertex_slots} vertex slots",
                values.len()
            )));
        }
        attributes.push((name, values));
    }
    let attached = input.bool("the attached flag")?;
    if attached && attributes.is_empty() {
        return Err(input.error("labels are attached, but no attribute is kept"));
    }
    input.end()?;
    Ok(Labels {
        attributes,
        attached,
    })
}
