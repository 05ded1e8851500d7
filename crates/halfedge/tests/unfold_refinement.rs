//! `Hierarchy::unfold_refinement`: faces a refinement after an edit turned over are
//! unfolded by relaxing the interpolated vertices of the edit's region around them;
//! vertices outside every region and vertices moved exactly by a mark stay bit for bit.

use glam::{DAffine3, DVec3};
use halfedge::hierarchy::{Hierarchy, HierarchyOptions};
use halfedge::{generators, Mesh, VertexId};

fn bits(p: DVec3) -> [u64; 3] {
    p.to_array().map(f64::to_bits)
}

/// The corners (vertex indices) of the faces whose normal turned over against `rest`.
fn turned_faces(mesh: &Mesh, rest: &[DVec3]) -> Vec<[usize; 3]> {
    mesh.faces()
        .map(|f| mesh.triangle(f).map(|v| mesh.vertex_index(v)))
        .filter(|&[a, b, c]| {
            let p = mesh.positions();
            let now = (p[b] - p[a]).cross(p[c] - p[a]);
            let then = (rest[b] - rest[a]).cross(rest[c] - rest[a]);
            now.dot(then) < 0.0
        })
        .collect()
}

/// Faces whose normal turned over against `rest`.
fn turned(mesh: &Mesh, rest: &[DVec3]) -> usize {
    turned_faces(mesh, rest).len()
}

/// An icosphere (the input) and its hierarchy down to 300 faces, walked to level 2.
fn sphere_at_level_2() -> (Hierarchy, Mesh) {
    let input = generators::icosphere(4);
    let mut h = Hierarchy::build(
        input.clone(),
        &HierarchyOptions::rounds().with_target_faces(300),
    )
    .unwrap();
    h.go_to_level(2).unwrap();
    (h, input)
}

/// A hierarchy of a sphere refined back to the input one split at a time after an edit
/// at level 2: the cap `z > 0.6` lifted rigidly (an affine mark), the band
/// `0 < z <= 0.6` the edit's region (lifted by a ramp), the rest outside; and the role
/// of every input vertex by its ancestor at level 2 (0 outside, 1 band, 2 cap).
fn refined_after_an_edit() -> (Hierarchy, Mesh, Vec<u8>) {
    let (mut h, input) = sphere_at_level_2();
    let lift = DAffine3::from_translation(DVec3::new(0.0, 0.0, 0.3));
    let mesh = h.mesh();
    let cap: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).z > 0.6)
        .collect();
    let band: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).z > 0.0)
        .collect();
    for &v in &band {
        let p = h.mesh().position(v);
        let q = if p.z > 0.6 {
            lift.transform_point3(p)
        } else {
            p + DVec3::Z * (0.5 * p.z)
        };
        h.mesh_mut().set_position(v, q);
    }
    h.mark_region(&band).unwrap();
    h.mark_affine(&cap, lift).unwrap();
    let mut coarse_role = vec![0u8; h.mesh().vertex_slots()];
    for (set, role) in [(&band, 1), (&cap, 2)] {
        for &v in set {
            coarse_role[h.mesh().vertex_index(v)] = role;
        }
    }
    let ancestors = h.ancestors(2).unwrap();
    let role = ancestors.iter().map(|&a| coarse_role[a as usize]).collect();
    while h.applied() > 0 {
        h.split_next().unwrap();
    }
    (h, input, role)
}

#[test]
fn turned_faces_are_unfolded_and_exact_vertices_stay() {
    let (mut h, input, role) = refined_after_an_edit();
    let rest = input.positions().to_vec();
    assert_eq!(
        turned(h.mesh(), &rest),
        0,
        "the refinement itself turned faces"
    );
    // Fold a fan of the band over: throw one of its interpolated vertices across it.
    let mesh = h.mesh();
    let folded = mesh
        .vertices()
        .find(|&v| {
            let i = mesh.vertex_index(v);
            role[i] == 1
                && mesh
                    .adjacent_vertices(v)
                    .all(|w| role[mesh.vertex_index(w)] == 1)
        })
        .unwrap();
    let i = mesh.vertex_index(folded);
    let ring: Vec<usize> = mesh
        .adjacent_vertices(folded)
        .map(|w| mesh.vertex_index(w))
        .collect();
    let before = h.mesh().positions().to_vec();
    let across = before[i] + 3.0 * (before[ring[0]] - before[i]);
    h.mesh_mut().positions_mut()[i] = across;
    let edited = h.mesh().positions().to_vec();
    assert!(turned(h.mesh(), &rest) > 0);

    h.unfold_refinement();
    assert_eq!(turned(h.mesh(), &rest), 0, "the fold is undone");
    let after = h.mesh().positions();
    let mut changed = 0;
    for v in h.mesh().vertices() {
        let j = h.mesh().vertex_index(v);
        if role[j] != 1 {
            // Outside the region, or in the rigid cap (moved exactly by its mark).
            assert_eq!(
                bits(after[j]),
                bits(edited[j]),
                "vertex {j}, role {}",
                role[j]
            );
        }
        changed += usize::from(bits(after[j]) != bits(edited[j]));
    }
    assert!(changed > 0);
    // Only around the fold.
    assert!(
        changed < h.mesh().n_vertices() / 4,
        "{changed} vertices moved"
    );
    h.mesh().check().unwrap();
}

#[test]
fn nothing_is_done_without_an_edit_or_without_turned_faces() {
    let (mut h, _, _) = refined_after_an_edit();
    let before: Vec<[u64; 3]> = h.mesh().positions().iter().map(|&p| bits(p)).collect();
    h.unfold_refinement();
    let after: Vec<[u64; 3]> = h.mesh().positions().iter().map(|&p| bits(p)).collect();
    assert_eq!(before, after);

    let input = generators::icosphere(3);
    let mut clean = Hierarchy::build(
        input.clone(),
        &HierarchyOptions::rounds().with_target_faces(100),
    )
    .unwrap();
    clean.go_to_level(0).unwrap();
    clean.unfold_refinement();
    assert_eq!(clean.mesh().positions(), input.positions());
}

/// A fold the coarse edit itself made is the edit's, not the refinement's: a walk finer
/// leaves the descendants of the faces the edit turned over where the splits put them
/// (as refining one split at a time, with no unfolding, does), and the fold stays.
#[test]
fn folds_made_by_the_edit_itself_are_left_as_made() {
    let (mut h, input) = sphere_at_level_2();
    let mesh = h.mesh();
    let band: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).z > 0.0)
        .collect();
    // The band lifted by a ramp, and one of its vertices thrown across its ring: the
    // faces around it turn over at the coarse level already.
    let inner = band
        .iter()
        .copied()
        .find(|&v| {
            mesh.position(v).z > 0.3 && mesh.adjacent_vertices(v).all(|w| mesh.position(w).z > 0.0)
        })
        .unwrap();
    let ring0 = mesh.adjacent_vertices(inner).next().unwrap();
    let rest = mesh.positions().to_vec();
    for &v in &band {
        let p = h.mesh().position(v);
        h.mesh_mut().set_position(v, p + DVec3::Z * (0.5 * p.z));
    }
    let (p, q) = (h.mesh().position(inner), h.mesh().position(ring0));
    h.mesh_mut().set_position(inner, p + 3.0 * (q - p));
    h.mark_region(&band).unwrap();
    let coarse_turned = turned(h.mesh(), &rest);
    assert!(coarse_turned > 0, "the edit turns coarse faces over");
    let mut by_edit = vec![false; h.mesh().vertex_slots()];
    for i in turned_faces(h.mesh(), &rest).into_iter().flatten() {
        by_edit[i] = true;
    }
    let ancestors = h.ancestors(2).unwrap();

    let mut split = h.clone();
    while split.applied() > 0 {
        split.split_next().unwrap();
    }
    h.go_to_level(0).unwrap();
    let (walked, stepped) = (h.mesh().positions(), split.mesh().positions());
    let mut descendants = 0;
    for v in h.mesh().vertices() {
        let i = h.mesh().vertex_index(v);
        if by_edit[ancestors[i] as usize] {
            descendants += 1;
            assert_eq!(bits(walked[i]), bits(stepped[i]), "vertex {i}");
        }
    }
    assert!(descendants > coarse_turned);
    assert!(turned(h.mesh(), input.positions()) > 0, "the fold stays");
    h.mesh().check().unwrap();
}
