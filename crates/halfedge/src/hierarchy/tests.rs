//! Unit tests of the hierarchy.

use glam::{DAffine3, DVec3};

use super::buffers::{prefaulted, PREFAULT_RECORDS};
use super::build::Prefaulted;
use super::*;
use crate::handle::{HalfedgeId, VertexId};

/// What identifies every record of `h`: its edge, positions and fingerprint.
fn record_keys(h: &Hierarchy) -> Vec<(HalfedgeId, DVec3, DVec3, u64)> {
    h.records()
        .iter()
        .map(|r| (r.v0v1, r.p0, r.p1, r.fingerprint))
        .collect()
}

/// An icosphere of level 4 with smooth bumps (detail that is not radial).
fn bumpy_icosphere() -> Mesh {
    let mut input = crate::generators::icosphere(4);
    for p in input.positions_mut() {
        *p *= 1.0 + 0.1 * (7.0 * p.x).sin() * (5.0 * p.y + 0.3).sin();
    }
    input
}

/// Output buffers made and mapped on another thread, adopted in the middle of a build
/// (large enough for the QEM build to do so itself) or afterwards, hold the same
/// records: the hierarchy refines back to its input bit for bit.
#[test]
fn adopted_prefaulted_buffers_keep_every_record() {
    let input = crate::generators::icosphere(6);
    let options = HierarchyOptions::qem().with_target_faces(500);
    let mut h = Hierarchy::build(input.clone(), &options).unwrap();
    assert!(h.n_records() > 4 * PREFAULT_RECORDS);
    let records = h.n_records();
    let bytes = h.record_bytes();
    let before = record_keys(&h);
    // Adopt buffers by hand (as large as the records, and larger).
    for extra in [0, 1000] {
        let sizes = (records + extra, records);
        let details = h.details.prefaulted_sizes(records);
        h.adopt_prefaulted(Prefaulted {
            steps: prefaulted(sizes),
            fingerprints: prefaulted(sizes),
            rules: prefaulted(sizes),
            stored: prefaulted(sizes),
            details: details.make(),
        });
    }
    assert_eq!(h.n_records(), records);
    assert!(h.record_bytes() >= bytes);
    let after = record_keys(&h);
    assert_eq!(after, before);
    h.refine_to(0).unwrap();
    h.mesh().check().unwrap();
    let bits = |m: &Mesh| -> Vec<[u64; 3]> {
        m.positions()
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect()
    };
    assert_eq!(bits(h.mesh()), bits(&input));
    // And a build that adopted them at its own pace gives the same records.
    let again = Hierarchy::build(input, &options).unwrap();
    let records_again = record_keys(&again);
    assert_eq!(records_again, before);
}

#[test]
fn a_field_mark_places_every_fine_vertex_of_its_clusters_at_the_field_of_its_input_position() {
    // A twist whose angle ramps along z (not affine), then a translation: the fine
    // vertices of the marked cap are exactly the composed deformation of the input,
    // the rest did not move; a mark that does not fit falls back to the local frame.
    let input = bumpy_icosphere();
    let twist = |p: DVec3| {
        let angle = 1.5 * (p.z - 0.2).clamp(0.0, 1.0);
        glam::DQuat::from_rotation_z(angle) * p
    };
    let shift = DVec3::new(0.05, -0.02, 0.1);
    for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
        let mut h = Hierarchy::build(input.clone(), &options.with_target_faces(100)).unwrap();
        let level = 2;
        h.go_to_level(level).unwrap();
        let ancestors = h.ancestors(level).unwrap();
        let cap: Vec<VertexId> = h
            .mesh()
            .vertices()
            .filter(|&v| h.mesh().position(v).z > 0.1)
            .collect();
        let mut in_cap = vec![false; h.mesh().vertex_slots()];
        for &v in &cap {
            in_cap[h.mesh().vertex_index(v)] = true;
            let p = h.mesh().position(v);
            h.mesh_mut().set_position(v, twist(p) + shift);
        }
        h.mark_field(&cap, twist).unwrap();
        h.mark_affine(&cap, DAffine3::from_translation(shift))
            .unwrap();
        h.go_to_level(0).unwrap();
        h.mesh().check().unwrap();
        for v in input.vertices() {
            let i = input.vertex_index(v);
            let (p, q) = (input.position(v), h.mesh().position(v));
            if in_cap[ancestors[i] as usize] {
                assert!(
                    q.distance(twist(p) + shift) < 1e-12,
                    "{v}: {q} against {}",
                    twist(p) + shift
                );
            } else {
                assert_eq!(q, p, "{v} outside the cap moved");
            }
        }
    }
    // Refused in translation mode, nothing marked.
    let options = HierarchyOptions::rounds().with_detail_mode(DetailMode::Translation);
    let mut h = Hierarchy::build(input.clone(), &options.with_target_faces(100)).unwrap();
    h.go_to_level(1).unwrap();
    let v = h.mesh().vertices().next().unwrap();
    assert!(h.mark_field(&[v], twist).is_err());
    assert!(h.marks.is_empty());
}

#[test]
fn cluster_members_are_the_input_positions_of_each_live_vertex_cluster() {
    // At every level of both methods: each member is at its input position bit for bit
    // and has the ancestor `ancestors` gives; every vertex that is not a member is live
    // there, its own ancestor, and still at its input position.
    let input = bumpy_icosphere();
    for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
        let mut h = Hierarchy::build(input.clone(), &options.with_target_faces(100)).unwrap();
        for level in 0..h.n_levels() {
            h.go_to_level(level).unwrap();
            let ancestors = h.ancestors(level).unwrap();
            let members = h.cluster_members();
            let mut member = vec![false; input.vertex_slots()];
            for &(i, a, p) in &members {
                let i = i as usize;
                member[i] = true;
                assert_eq!(a, ancestors[i], "level {level}");
                assert_eq!(
                    p.to_array().map(f64::to_bits),
                    input.positions()[i].to_array().map(f64::to_bits)
                );
            }
            for v in input.vertices() {
                let i = input.vertex_index(v);
                if !member[i] {
                    assert_eq!(ancestors[i] as usize, i);
                    assert!(h.mesh().is_valid_vertex(v));
                    assert_eq!(h.mesh().position(v), input.position(v));
                }
            }
            assert_eq!(!members.is_empty(), level > 0);
        }
    }
}

#[test]
fn the_public_records_fit_their_own_mesh_and_no_other() {
    // The hierarchy keeps compact records; the public ones it makes on demand split
    // like the kernel's: on a clone of its mesh the last record splits and gives back
    // its vertex where it was, on another hierarchy's mesh (same input) it is refused.
    let options = HierarchyOptions::rounds().with_target_faces(60);
    let h = Hierarchy::build(crate::generators::icosphere(3), &options).unwrap();
    let other = Hierarchy::build(crate::generators::icosphere(3), &options).unwrap();
    let records = h.records();
    assert_eq!(records.len(), h.n_records());
    let last = records.last().unwrap();
    let mut mesh = h.mesh().clone();
    mesh.vertex_split(last).unwrap();
    mesh.check().unwrap();
    assert_eq!(mesh.position(last.v0), last.p0);
    assert!(mesh.vertex_split(last).is_err(), "split twice");
    let mut foreign = other.mesh().clone();
    let e = foreign.vertex_split(last).unwrap_err();
    assert!(e.to_string().contains("another mesh"), "{e}");
}

#[test]
fn replacing_a_mark_again_and_again_keeps_the_maps_bounded() {
    // An interactive drag: the handle's map is replaced at every step; maps no
    // vertex uses are dropped, and the last one still lands exactly.
    let mesh = crate::generators::icosphere(3);
    let input = mesh.clone();
    let mut h = Hierarchy::build(mesh, &HierarchyOptions::rounds()).unwrap();
    h.go_to_level(2).unwrap();
    let handle: Vec<VertexId> = h
        .mesh()
        .vertices()
        .filter(|&v| h.mesh().position(v).x > 0.5)
        .collect();
    let before: Vec<DVec3> = handle.iter().map(|&v| h.mesh().position(v)).collect();
    let mut t = DAffine3::IDENTITY;
    for step in 1..=1000 {
        t = DAffine3::from_translation(DVec3::new(0.0, 0.0, 1e-4 * step as f64));
        for (&v, &p) in handle.iter().zip(&before) {
            h.mesh_mut().set_position(v, t.transform_point3(p));
        }
        h.set_affine_mark(&handle, t).unwrap();
        assert!(h.marks.maps.len() <= 67, "{} maps", h.marks.maps.len());
    }
    let ancestors = h.ancestors(2).unwrap();
    let marked: Vec<bool> = {
        let mut m = vec![false; input.vertex_slots()];
        for &v in &handle {
            m[h.mesh().vertex_index(v)] = true;
        }
        m
    };
    h.refine_to(0).unwrap();
    for v in input.vertices() {
        let i = input.vertex_index(v);
        if marked[ancestors[i] as usize] {
            let target = t.transform_point3(input.position(v));
            assert!(h.mesh().position(v).distance(target) < 1e-12);
        }
    }
}
