//! Unit tests of collapse and split.

use super::*;
use crate::generators;

#[test]
fn a_hierarchy_keeps_88_bytes_per_collapse_record() {
    // The compact record is what a hierarchy stores per collapse (its fingerprint
    // apart): slot indices, the two positions, and nothing the tombstones keep.
    assert_eq!(std::mem::size_of::<Step>(), 88);
}

#[test]
fn a_record_whose_fields_were_changed_is_refused() {
    let mut mesh = generators::icosphere(2);
    let v = mesh.vertices().nth(5).unwrap();
    let h = mesh.vertex_halfedge(v).unwrap();
    let r = mesh.collapse(h).unwrap();
    let before = mesh.binding();
    for edit in 0..3 {
        let mut bad = r.clone();
        match edit {
            0 => bad.p0.x += 1.0,
            1 => bad.v1 = bad.vl.unwrap(),
            _ => bad.fl = None,
        }
        let e = mesh.vertex_split(&bad).unwrap_err();
        assert!(e.to_string().contains("fields were changed"), "{e}");
        assert!(before.same_connectivity(&mesh));
    }
    mesh.vertex_split(&r).unwrap();
    mesh.check().unwrap();
    assert_eq!(mesh.position(r.v0), r.p0);
}

#[test]
fn the_split_reads_back_what_the_collapse_rewrote_from_the_tombstones() {
    // Every edge of a mesh with a boundary, collapsed and split again: the two
    // triangles and the links derived from the removed halfedges are what the
    // collapse used, and the split restores every field bit for bit.
    let mesh = generators::grid(5, 4, 1.0, 1.0);
    for h in mesh.halfedges().collect::<Vec<_>>() {
        let mut m = mesh.clone();
        if m.is_collapse_ok(h).is_err() {
            continue;
        }
        let (he, vc, fc) = (m.he.clone(), m.vertex_conn.clone(), m.face_conn.clone());
        let hi = Mesh::ix(h);
        let sides = m.sides(hi);
        let links = m.links_of(hi, &sides);
        let (step, _) = m.collapse_unchecked(h);
        assert_eq!(m.sides(hi), sides);
        assert_eq!(m.links_of(hi, &sides), links);
        m.vertex_split_unchecked(&step);
        assert!(m.he == he && m.vertex_conn == vc && m.face_conn == fc);
        m.check().unwrap();
    }
}
