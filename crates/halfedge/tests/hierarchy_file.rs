//! The hierarchy file (`.mrh`, issue 30): round trips on generated meshes (closed, with a
//! boundary, several components; rounds and QEM; local frames and translations; labels
//! attached and constrained) refine to the input bit for bit after loading; an edit made
//! before saving refines after loading exactly as in one process; the bytes are
//! deterministic; every refusal is a typed error naming the file and the section. The
//! real-mesh tier saves and loads hierarchies of the shared meshes.

use glam::{DAffine3, DVec3};
use halfedge::hierarchy::file::{FORMAT_VERSION, OLDEST_READABLE_VERSION};
use halfedge::hierarchy::{DetailMode, Hierarchy, HierarchyOptions, SurvivorPlacement};
use halfedge::{generators, Error, Mesh, VertexId};
use testkit::check::{slot_position_bits as position_bits, snapshot};
use testkit::temp_dir;

fn bytes_of(h: &Hierarchy) -> Vec<u8> {
    let mut out = Vec::new();
    h.write_to(&mut out).unwrap();
    out
}

fn reload(h: &Hierarchy) -> Hierarchy {
    Hierarchy::read_from(&bytes_of(h), "test.mrh").unwrap()
}

/// Two components and a boundary: an icosphere, a torus and a grid side by side.
fn components() -> Mesh {
    let sphere = generators::icosphere(3);
    let mut torus = generators::torus(1.0, 0.3, 24, 12).unwrap();
    for p in torus.positions_mut() {
        *p += DVec3::new(3.0, 0.0, 0.0);
    }
    let mut grid = generators::grid(12, 9, 1.0, 0.8);
    for p in grid.positions_mut() {
        *p += DVec3::new(-4.0, 0.0, 0.0);
    }
    generators::disjoint_union(&[&sphere, &torus, &grid]).unwrap()
}

/// The icosphere with sub-mesh labels (the cap above z = 0.3) defined at the input,
/// attached and made to hold at every level.
fn labelled(options: &HierarchyOptions) -> (Mesh, Hierarchy) {
    let input = generators::icosphere(4);
    let mut h = Hierarchy::build(input.clone(), options).unwrap();
    h.refine_to(0).unwrap();
    let m = h.mesh_mut();
    let frontier = m
        .frontier_from_plane(DVec3::new(0.0, 0.0, 0.3), DVec3::Z)
        .unwrap();
    let (labels, _) = m.label_sides(&frontier, 1, 2).unwrap();
    h.attach_labels(labels).unwrap();
    h.constrain_to_labels().unwrap();
    (h.mesh().clone(), h)
}

/// Generated cases: (name, input, hierarchy built from it at its coarsest level).
fn cases() -> Vec<(&'static str, Mesh, Hierarchy)> {
    let rounds = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(150);
    let qem = HierarchyOptions::qem().with_target_faces(150);
    let mut out = Vec::new();
    for (name, input, options) in [
        ("icosphere rounds", generators::icosphere(4), rounds.clone()),
        ("icosphere QEM", generators::icosphere(4), qem.clone()),
        (
            "grid rounds",
            generators::grid(30, 24, 1.0, 0.8),
            rounds.clone(),
        ),
        ("grid QEM", generators::grid(30, 24, 1.0, 0.8), qem.clone()),
        ("components rounds", components(), rounds.clone()),
        ("components QEM", components(), qem.clone()),
        (
            "icosphere rounds by the quadric",
            generators::icosphere(4),
            rounds.clone().with_placement(SurvivorPlacement::Quadric),
        ),
        (
            "components rounds by the quadric",
            components(),
            rounds.clone().with_placement(SurvivorPlacement::Quadric),
        ),
        (
            "icosphere translations",
            generators::icosphere(4),
            rounds.clone().with_detail_mode(DetailMode::Translation),
        ),
    ] {
        let h = Hierarchy::build(input.clone(), &options).unwrap();
        out.push((name, input, h));
    }
    let (input, mut h) = labelled(&rounds);
    h.go_to_level(h.coarsest_level()).unwrap();
    out.push(("labels constrained", input, h));
    out
}

#[test]
fn build_save_load_refine_gives_the_input_bit_for_bit() {
    for (name, input, built) in cases() {
        for level in [built.coarsest_level(), built.coarsest_level() / 2] {
            let mut h = built.clone();
            h.go_to_level(level).unwrap();
            let mut loaded = reload(&h);
            loaded.mesh().check().unwrap();
            assert_eq!(loaded.applied(), h.applied(), "{name}");
            assert_eq!(loaded.level_ends(), h.level_ends(), "{name}");
            assert_eq!(loaded.level_face_counts(), h.level_face_counts(), "{name}");
            assert_eq!(loaded.method(), h.method(), "{name}");
            assert_eq!(loaded.detail_mode(), h.detail_mode(), "{name}");
            assert_eq!(loaded.options().placement, h.options().placement, "{name}");
            assert_eq!(loaded.build_outcome(), h.build_outcome(), "{name}");
            assert_eq!(
                snapshot(loaded.mesh()),
                snapshot(h.mesh()),
                "{name} level {level}"
            );
            loaded.refine_to(0).unwrap();
            loaded.mesh().check().unwrap();
            assert_eq!(
                snapshot(loaded.mesh()),
                snapshot(&input),
                "{name} from level {level}"
            );
            h.refine_to(0).unwrap();
            assert_eq!(
                position_bits(loaded.mesh()),
                position_bits(h.mesh()),
                "{name}: every slot's position"
            );
            // And back down: the walk coarser collapses the records again, as in one
            // process.
            let top = h.coarsest_level();
            loaded.go_to_level(top).unwrap();
            h.go_to_level(top).unwrap();
            assert_eq!(
                snapshot(loaded.mesh()),
                snapshot(h.mesh()),
                "{name} coarsest again"
            );
            assert_eq!(
                position_bits(loaded.mesh()),
                position_bits(h.mesh()),
                "{name}"
            );
        }
    }
}

#[test]
fn labels_come_back_attached_with_their_values_and_hold_after_loading() {
    let options = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(150);
    let (input, mut h) = labelled(&options);
    h.go_to_level(2).unwrap();
    let mut loaded = reload(&h);
    let a = loaded
        .label_attribute()
        .expect("labels attached after loading");
    let b = h.label_attribute().unwrap();
    assert_eq!(
        loaded.mesh().attribute_values(a).unwrap(),
        h.mesh().attribute_values(b).unwrap()
    );
    // Labels defined at level 2 and attached there: refinement classifies the split
    // vertices after loading exactly as it does in one process.
    let m = h.mesh_mut();
    let frontier = m
        .frontier_from_plane(DVec3::new(0.0, 0.0, -0.2), DVec3::Z)
        .unwrap();
    let (labels, _) = m.label_sides(&frontier, 5, 6).unwrap();
    h.attach_labels(labels).unwrap();
    let mut loaded_here = reload(&h);
    h.refine_to(0).unwrap();
    loaded_here.refine_to(0).unwrap();
    let la = loaded_here.label_attribute().unwrap();
    let lb = h.label_attribute().unwrap();
    assert_eq!(
        loaded_here.mesh().attribute_values(la).unwrap(),
        h.mesh().attribute_values(lb).unwrap(),
        "labels classified by the splits"
    );
    assert_eq!(snapshot(loaded_here.mesh()), snapshot(h.mesh()));
    loaded.refine_to(0).unwrap();
    assert_eq!(snapshot(loaded.mesh()), snapshot(&input));
}

/// Edits at a coarse level as a user makes them: positions through `mesh_mut`, an affine
/// mark, a region mark, at two levels (so two copies of the positions before an edit).
fn edit(h: &mut Hierarchy, seed: u64) {
    let top = h.coarsest_level();
    h.go_to_level(top).unwrap();
    let lift = DAffine3::from_rotation_z(0.3 + seed as f64 * 0.01)
        * DAffine3::from_translation(DVec3::new(0.0, 0.0, 0.2));
    let m = h.mesh();
    let cap: Vec<VertexId> = m.vertices().filter(|&v| m.position(v).z > 0.4).collect();
    let band: Vec<VertexId> = m
        .vertices()
        .filter(|&v| (-0.1..0.4).contains(&m.position(v).z))
        .collect();
    let mesh = h.mesh_mut();
    for &v in &cap {
        let p = mesh.position(v);
        mesh.set_position(v, lift.transform_point3(p));
    }
    for &v in &band {
        let p = mesh.position(v);
        mesh.set_position(v, p + DVec3::new(0.05 * (p.z + 0.1), 0.0, 0.0));
    }
    if h.detail_mode() == DetailMode::LocalFrame {
        h.mark_affine(&cap, lift).unwrap();
        h.mark_region(&band).unwrap();
    }
    // A second edit two levels finer.
    h.go_to_level(top.saturating_sub(2)).unwrap();
    let mesh = h.mesh_mut();
    let vs: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).x > 0.5)
        .collect();
    for &v in &vs {
        let p = mesh.position(v);
        mesh.set_position(v, p + DVec3::new(0.03, 0.01, 0.0));
    }
    if h.detail_mode() == DetailMode::LocalFrame {
        h.mark_region(&vs).unwrap();
    }
}

#[test]
fn an_edit_made_before_saving_refines_after_loading_as_in_one_process() {
    let rounds = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(150);
    for (name, input, options) in [
        ("rounds", generators::icosphere(4), rounds.clone()),
        (
            "QEM",
            generators::icosphere(4),
            HierarchyOptions::qem().with_target_faces(150),
        ),
        (
            "translations",
            generators::icosphere(4),
            rounds.clone().with_detail_mode(DetailMode::Translation),
        ),
        ("components", components(), rounds.clone()),
    ] {
        let mut one = Hierarchy::build(input.clone(), &options).unwrap();
        let mut two = Hierarchy::build(input, &options).unwrap();
        edit(&mut one, 1);
        edit(&mut two, 1);
        let mut loaded = reload(&two);
        drop(two);
        one.refine_to(0).unwrap();
        loaded.refine_to(0).unwrap();
        loaded.mesh().check().unwrap();
        assert_eq!(snapshot(loaded.mesh()), snapshot(one.mesh()), "{name}");
        assert_eq!(
            position_bits(loaded.mesh()),
            position_bits(one.mesh()),
            "{name}"
        );
        // Walking coarser again (records made anew from the edited input) agrees too.
        let top = one.coarsest_level();
        one.go_to_level(top).unwrap();
        loaded.go_to_level(top).unwrap();
        assert_eq!(
            position_bits(loaded.mesh()),
            position_bits(one.mesh()),
            "{name}"
        );
    }
}

/// One scenario run twice, in one process and through a file at the point `save_at`
/// of its steps: both must end with the same positions, bit for bit.
fn same_after_loading(name: &str, steps: &[&dyn Fn(&mut Hierarchy)], save_at: usize) {
    let options = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(150);
    let mut one = Hierarchy::build(generators::icosphere(4), &options).unwrap();
    let mut two = Hierarchy::build(generators::icosphere(4), &options).unwrap();
    for (k, step) in steps.iter().enumerate() {
        if k == save_at {
            two = reload(&two);
        }
        step(&mut one);
        step(&mut two);
    }
    one.refine_to(0).unwrap();
    two.refine_to(0).unwrap();
    two.mesh().check().unwrap();
    assert_eq!(snapshot(two.mesh()), snapshot(one.mesh()), "{name}");
    assert_eq!(
        position_bits(two.mesh()),
        position_bits(one.mesh()),
        "{name}"
    );
}

/// A translation of the cap of the current level, told as an affine mark.
fn lift_cap(h: &mut Hierarchy) {
    let lift = DAffine3::from_translation(DVec3::new(0.02, 0.0, 0.1));
    let m = h.mesh();
    let cap: Vec<VertexId> = m.vertices().filter(|&v| m.position(v).z > 0.5).collect();
    let mesh = h.mesh_mut();
    for &v in &cap {
        let p = mesh.position(v);
        mesh.set_position(v, lift.transform_point3(p));
    }
    h.mark_affine(&cap, lift).unwrap();
}

/// A bump of the vertices near the equator, unmarked (refinement interpolates).
fn bump(h: &mut Hierarchy) {
    let mesh = h.mesh_mut();
    let vs: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).z.abs() < 0.2)
        .collect();
    for &v in &vs {
        let p = mesh.position(v);
        mesh.set_position(v, p * 1.05);
    }
}

#[test]
fn walks_and_edits_after_loading_are_those_of_one_process() {
    let top = |h: &mut Hierarchy| h.go_to_level(h.coarsest_level()).unwrap();
    let level = |l: usize| move |h: &mut Hierarchy| h.go_to_level(l).unwrap();
    let touch = |h: &mut Hierarchy| {
        let _ = h.mesh_mut();
    };
    // Walked to the input and back to the coarsest level after loading (the records made
    // again by the loaded hierarchy's checked collapses), then edited.
    same_after_loading("walk, then edit", &[&level(0), &top, &lift_cap, &bump], 0);
    // Edited, refined part way, saved, walked coarser and edited again.
    same_after_loading(
        "edit, refine, save, coarsen, edit",
        &[&lift_cap, &level(1), &level(3), &bump],
        2,
    );
    // The mesh handed out without a change at the coarsest level, refined, saved: the
    // hierarchy's positions are still clean, and the next edit's copy of the positions
    // serves every record below (the clean flag is saved).
    same_after_loading("clean, then edit", &[&touch, &level(2), &bump], 2);
    // Saved between two edits at two levels.
    same_after_loading(
        "edit, save, refine, edit",
        &[&bump, &level(2), &lift_cap, &level(1), &bump],
        1,
    );
}

#[test]
fn the_same_hierarchy_gives_the_same_bytes() {
    let options = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(150);
    let mut a = Hierarchy::build(generators::icosphere(4), &options).unwrap();
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| Hierarchy::build(generators::icosphere(4), &options).unwrap());
    assert_eq!(bytes_of(&a), bytes_of(&a), "saved twice");
    assert_eq!(
        bytes_of(&a),
        bytes_of(&single),
        "built twice, on one thread and on all"
    );
    edit(&mut a, 2);
    let mut b = Hierarchy::build(generators::icosphere(4), &options).unwrap();
    edit(&mut b, 2);
    let saved = bytes_of(&a);
    assert_eq!(saved, bytes_of(&b), "the same edits on two builds");
    // A loaded hierarchy saves to the same bytes.
    assert_eq!(bytes_of(&reload(&a)), saved, "loaded and saved again");
    // Files on disk too.
    let dir = temp_dir("hierarchy_file_bytes");
    let path = dir.join("a.mrh");
    a.save(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), saved);
    let mut from_disk = Hierarchy::load(&path).unwrap();
    a.refine_to(0).unwrap();
    from_disk.refine_to(0).unwrap();
    assert_eq!(position_bits(from_disk.mesh()), position_bits(a.mesh()));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn the_header_holds_the_magic_and_the_format_version() {
    let h = Hierarchy::build(generators::icosphere(2), &HierarchyOptions::rounds()).unwrap();
    let bytes = bytes_of(&h);
    assert_eq!(&bytes[..8], b"\x89MRH\r\n\x1a\n");
    assert_eq!(
        u32::from_le_bytes(bytes[8..12].try_into().unwrap()),
        FORMAT_VERSION
    );
}

/// A file of version 1 (before the quadric placement's codes) reads as it did: the same
/// bytes with version 1 in the header give the same hierarchy, which refines to the input.
#[test]
fn version_1_files_still_read() {
    assert_eq!(OLDEST_READABLE_VERSION, 1);
    for (name, input, h) in cases() {
        if h.options().placement != SurvivorPlacement::Midpoint {
            continue;
        }
        let mut old = bytes_of(&h);
        old[8..12].copy_from_slice(&1u32.to_le_bytes());
        fix_crcs(&mut old);
        let mut loaded = Hierarchy::read_from(&old, "old.mrh").unwrap();
        assert_eq!(bytes_of(&loaded), bytes_of(&h), "{name}");
        loaded.refine_to(0).unwrap();
        assert_eq!(snapshot(loaded.mesh()), snapshot(&input), "{name}");
    }
}

/// The message of a format error, checked to name the file.
fn format_message(e: Error, file: &str) -> String {
    match e {
        Error::Format { path, message } => {
            assert_eq!(path.to_str(), Some(file));
            message
        }
        other => panic!("expected a format error, got {other:?}"),
    }
}

fn small() -> Hierarchy {
    let mut h = Hierarchy::build(
        generators::icosphere(3),
        &HierarchyOptions::rounds().with_target_faces(100),
    )
    .unwrap();
    edit(&mut h, 0);
    h
}

/// Section table entry `k`: (tag, offset, length).
fn table(bytes: &[u8]) -> Vec<(String, usize, usize)> {
    (0..8)
        .map(|k| {
            let e = &bytes[16 + 24 * k..16 + 24 * (k + 1)];
            let u = |a: usize| u64::from_le_bytes(e[a..a + 8].try_into().unwrap()) as usize;
            (String::from_utf8_lossy(&e[..4]).into_owned(), u(8), u(16))
        })
        .collect()
}

/// Recomputes the header's and every section's CRC-32.
fn fix_crcs(bytes: &mut [u8]) {
    let header = 16 + 24 * 8;
    let crc = crc32fast::hash(&bytes[..header]);
    bytes[header..header + 4].copy_from_slice(&crc.to_le_bytes());
    for (_, offset, length) in table(bytes) {
        let crc = crc32fast::hash(&bytes[offset..offset + length]);
        bytes[offset + length..offset + length + 4].copy_from_slice(&crc.to_le_bytes());
    }
}

#[test]
fn damaged_files_are_refused_naming_the_file_and_the_section() {
    let bytes = bytes_of(&small());
    let read = |b: &[u8]| Hierarchy::read_from(b, "bad.mrh").map(|_| ()).unwrap_err();
    // Not a hierarchy file.
    let m = format_message(read(b"ply\nformat ascii 1.0\n"), "bad.mrh");
    assert!(m.contains("not a hierarchy file"), "{m}");
    // Another version: newer, or older than the oldest readable.
    for version in [FORMAT_VERSION + 1, OLDEST_READABLE_VERSION - 1] {
        let mut other = bytes.clone();
        other[8..12].copy_from_slice(&version.to_le_bytes());
        fix_crcs(&mut other);
        let m = format_message(read(&other), "bad.mrh");
        assert!(m.contains(&format!("version {version};")), "{m}");
    }
    // Truncated at every section boundary, and in every section.
    for (tag, offset, length) in table(&bytes) {
        for cut in [
            offset,
            offset + length / 2,
            offset + length,
            offset + length + 2,
        ] {
            let m = format_message(read(&bytes[..cut]), "bad.mrh");
            assert!(m.contains("truncated"), "cut at {cut} ({tag}): {m}");
        }
    }
    for cut in [0, 5, 12, 100] {
        format_message(read(&bytes[..cut]), "bad.mrh");
    }
    // A flipped bit in a section: its CRC says so.
    for (tag, offset, length) in table(&bytes) {
        let mut flipped = bytes.clone();
        flipped[offset + length / 2] ^= 0x10;
        let m = format_message(read(&flipped), "bad.mrh");
        assert!(
            m.contains(&format!("section {tag}")) && m.contains("CRC"),
            "{m}"
        );
    }
    // A flipped bit in the section table.
    let mut flipped = bytes.clone();
    flipped[40] ^= 1;
    let m = format_message(read(&flipped), "bad.mrh");
    assert!(m.contains("header") && m.contains("CRC"), "{m}");
    // Bytes after the last section.
    let mut longer = bytes.clone();
    longer.push(0);
    let m = format_message(read(&longer), "bad.mrh");
    assert!(m.contains("after the last section"), "{m}");
    // An array count set huge, the CRCs recomputed: refused before allocating.
    let (_, mesh_at, _) = table(&bytes)[1];
    let mut huge = bytes.clone();
    // The vertex slot states' count follows the vertex slot count.
    huge[mesh_at + 8..mesh_at + 16].copy_from_slice(&(u64::MAX / 2).to_le_bytes());
    fix_crcs(&mut huge);
    let m = format_message(read(&huge), "bad.mrh");
    assert!(m.contains("section MESH") && m.contains("announced"), "{m}");
    // A record naming a vertex out of range, the CRCs recomputed.
    let (_, recs_at, _) = table(&bytes)[3];
    let mut forged = bytes.clone();
    // Record 0's `v0` (after the count and the two positions).
    let v0_at = recs_at + 8 + 48 + 4;
    forged[v0_at..v0_at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    fix_crcs(&mut forged);
    let m = format_message(read(&forged), "bad.mrh");
    assert!(m.contains("section RECS") && m.contains("record 0"), "{m}");
    // A mesh that fails its check, the CRCs recomputed: a halfedge's `next` redirected.
    let mut forged = bytes.clone();
    let h = Hierarchy::read_from(&bytes, "ok.mrh").unwrap();
    let (nv, nh) = (h.mesh().vertex_slots(), h.mesh().halfedge_slots());
    let live = h.mesh().halfedges().next().unwrap();
    let live = h.mesh().halfedge_index(live);
    // MESH: three slot tables, vertex halfedges, positions, then the halfedges.
    let slots = |n: usize| 8 + 8 + 8 * n.div_ceil(32) + 8 + 8;
    let he_at = mesh_at
        + slots(nv)
        + slots(nh)
        + slots(h.mesh().face_slots())
        + 8
        + 4 * nv
        + 8
        + 24 * nv
        + 8;
    let next_at = he_at + 16 * live + 4;
    let old = u32::from_le_bytes(forged[next_at..next_at + 4].try_into().unwrap());
    forged[next_at..next_at + 4].copy_from_slice(&(old ^ 2).to_le_bytes());
    fix_crcs(&mut forged);
    let m = format_message(read(&forged), "bad.mrh");
    assert!(m.contains("section MESH") && m.contains("not valid"), "{m}");
}

#[test]
fn what_cannot_be_saved_is_refused_before_anything_is_written() {
    let mut h = small();
    let vs: Vec<VertexId> = h.mesh().vertices().take(3).collect();
    h.mark_field(&vs, |p| p * 1.01).unwrap();
    let mut out = Vec::new();
    let e = h.write_to(&mut out).unwrap_err();
    assert!(
        matches!(&e, Error::InvalidArgument(m) if m.contains("field")),
        "{e}"
    );
    assert!(out.is_empty());
    // Refining applies the field: then the hierarchy saves.
    h.refine_to(0).unwrap();
    h.write_to(&mut out).unwrap();

    let options = HierarchyOptions::rounds().with_target_faces(100);
    let (_, mut h) = labelled(&options);
    let a = h.label_attribute().unwrap();
    h.mesh_mut().remove_attribute(a).unwrap();
    let e = h.write_to(&mut Vec::new()).unwrap_err();
    assert!(
        matches!(&e, Error::InvalidArgument(m) if m.contains("label")),
        "{e}"
    );
}

#[test]
fn files_that_cannot_be_read_or_written_are_io_errors_naming_them() {
    let dir = temp_dir("hierarchy_file_io");
    let missing = dir.join("missing.mrh");
    match Hierarchy::load(&missing) {
        Err(Error::Io { path, .. }) => assert_eq!(path, missing),
        other => panic!("{other:?}"),
    }
    let nowhere = dir.join("no such folder").join("h.mrh");
    match small().save(&nowhere) {
        Err(Error::Io { path, .. }) => assert_eq!(path, nowhere),
        other => panic!("{other:?}"),
    }
    // A writer that fails.
    struct Broken;
    impl std::io::Write for Broken {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::Error::other("disk full"))
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    assert!(matches!(small().write_to(Broken), Err(Error::Io { .. })));
    std::fs::remove_dir_all(dir).unwrap();
}

/// Real-mesh tier: every shared mesh (welded where it has seams), built by rounds and by
/// QEM, saved to a file, loaded, refined to the input bit for bit.
#[test]
#[ignore = "real-mesh tier: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -p multires-halfedge --test hierarchy_file -- --include-ignored"]
fn shared_meshes_round_trip_through_files() {
    let dir = temp_dir("hierarchy_file_shared");
    let mut names: Vec<_> = std::fs::read_dir(testkit::shared_meshes())
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .filter(|n| n.ends_with(".obj") || n.ends_with(".ply"))
        .collect();
    names.sort();
    for name in names {
        let (mesh, _) = halfedge::io::read(testkit::shared_meshes().join(&name)).unwrap();
        let mesh = match mesh.welded_seams().unwrap() {
            Some((welded, _)) => welded,
            None => mesh,
        };
        for options in [
            HierarchyOptions::rounds()
                .with_max_normal_deviation(90f64.to_radians())
                .with_target_faces(500),
            HierarchyOptions::qem().with_target_faces(500),
        ] {
            let Ok(mut h) = Hierarchy::build(mesh.clone(), &options) else {
                continue;
            };
            let path = dir.join("h.mrh");
            h.save(&path).unwrap();
            let size = std::fs::metadata(&path).unwrap().len();
            let mut loaded = Hierarchy::load(&path).unwrap();
            loaded.refine_to(0).unwrap();
            h.refine_to(0).unwrap();
            assert_eq!(snapshot(loaded.mesh()), snapshot(&mesh), "{name}");
            assert_eq!(
                position_bits(loaded.mesh()),
                position_bits(h.mesh()),
                "{name}"
            );
            eprintln!(
                "{name} {:?}: {} faces, {} records, {size} bytes ({:.1} per face)",
                options.method,
                mesh.n_faces(),
                h.n_records(),
                size as f64 / mesh.n_faces() as f64
            );
        }
    }
    std::fs::remove_dir_all(dir).unwrap();
}

/// The figures of `benches/README.md` for the bench mesh (nefertiti subdivided twice,
/// 1.6 M faces, rounds to 2,000 faces): build, save, load, the mesh section's decode,
/// the file's size, and what distrusting the loaded mesh costs a refinement.
#[test]
#[ignore = "real-mesh tier, timings: needs ../shared/meshes (or MULTIRES_MESHES); run with cargo test --release -p multires-halfedge --test hierarchy_file -- --ignored --nocapture bench_mesh"]
fn bench_mesh_save_load_figures() {
    use std::time::Instant;
    let mut mesh = testkit::load_shared("nefertiti.obj");
    for _ in 0..2 {
        mesh = generators::subdivide(&mesh);
    }
    let faces = mesh.n_faces() as f64;
    let options = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(2000);
    let best = |runs: usize, f: &mut dyn FnMut()| -> f64 {
        (0..runs)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut built = None;
    let build = best(2, &mut || {
        built = Some(Hierarchy::build(mesh.clone(), &options).unwrap())
    });
    let built = built.unwrap();
    let dir = temp_dir("hierarchy_file_bench");
    let path = dir.join("nefertiti.mrh");
    let save = best(3, &mut || built.save(&path).unwrap());
    let bytes = std::fs::read(&path).unwrap();
    let mut loaded = None;
    let load = best(5, &mut || loaded = Some(Hierarchy::load(&path).unwrap()));
    let read_from = best(5, &mut || {
        Hierarchy::read_from(&bytes, &path).unwrap();
    });
    let mesh_section = best(5, &mut || {
        halfedge::hierarchy::file::read_mesh(&bytes, &path).unwrap();
    });
    let refine_trusted = best(3, &mut || {
        let mut h = built.clone();
        h.refine_to(0).unwrap();
    });
    let loaded = loaded.unwrap();
    let refine_loaded = best(3, &mut || {
        let mut h = Hierarchy::read_from(&bytes, &path).unwrap();
        let t = Instant::now();
        h.refine_to(0).unwrap();
        let _ = t;
    }) - read_from;
    let mut again = loaded.clone();
    again.refine_to(0).unwrap();
    assert_eq!(snapshot(again.mesh()), snapshot(&mesh));
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, &bytes).unwrap();
    let gz = gz.finish().unwrap().len();
    println!(
        "bench mesh: {} faces, {} records, {} levels",
        mesh.n_faces(),
        built.n_records(),
        built.n_levels()
    );
    println!("build (rounds to 2,000 faces): {:.3} s", build);
    println!("save to a file: {:.1} ms", save * 1e3);
    println!(
        "load from a file: {:.1} ms = {:.3} × the build; from bytes in memory {:.1} ms",
        load * 1e3,
        load / build,
        read_from * 1e3
    );
    println!(
        "mesh section alone (CRC, decode, checks): {:.1} ms = {:.1} ns per face",
        mesh_section * 1e3,
        mesh_section * 1e9 / faces
    );
    println!(
        "file: {} bytes = {:.1} bytes per face ({:.1} per record); gzip fast {:.1} per face",
        bytes.len(),
        bytes.len() as f64 / faces,
        bytes.len() as f64 / built.n_records() as f64,
        gz as f64 / faces
    );
    println!(
        "refine to level 0: {:.1} ms as built (trusted), {:.1} ms after loading (checked)",
        refine_trusted * 1e3,
        refine_loaded * 1e3
    );
    std::fs::remove_dir_all(dir).unwrap();
}
