//! The hierarchy file's mutation suite (issue 30, with the loaders' suite of issue 14):
//! truncated, bit-flipped, other-version and hostile `.mrh` files never make the reader
//! panic, hang or allocate what the file does not hold. A mutated file gives an
//! [`Error::Format`] naming the file, or a hierarchy whose mesh passes `Mesh::check` and
//! that walks to level 0 and back to its coarsest level (each walk succeeding or refused
//! with a typed error) with the mesh still passing `Mesh::check` after every walk.
//!
//! Mutations: cuts at random and at (and around) every section boundary; random bit flips
//! (which the CRC-32s refuse); bit flips, words set to chosen values (0, 1, `u32::MAX`,
//! other indices) and counts set huge with every CRC-32 computed again, so that they reach
//! the validators and the walks; records copied over others (a forged but well-formed
//! record); the format version changed. Seeds are fixed; `MULTIRES_HOSTILE_CASES` sets
//! the number of cases per test for a long run (and `MULTIRES_HOSTILE_SEED` another
//! seed).

use glam::{DAffine3, DVec3};
use halfedge::hierarchy::{DetailMode, Hierarchy, HierarchyOptions};
use halfedge::{generators, Error, VertexId};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

fn config(default_cases: u32) -> Config {
    Config {
        cases: std::env::var("MULTIRES_HOSTILE_CASES")
            .ok()
            .and_then(|c| c.parse().ok())
            .unwrap_or(default_cases),
        rng_seed: RngSeed::Fixed(
            std::env::var("MULTIRES_HOSTILE_SEED")
                .ok()
                .and_then(|c| c.parse().ok())
                .unwrap_or(0x6d72_685f_6675_7a7a),
        ),
        failure_persistence: None,
        ..Config::default()
    }
}

fn bytes_of(h: &Hierarchy) -> Vec<u8> {
    let mut out = Vec::new();
    h.write_to(&mut out).unwrap();
    out
}

/// Valid files of small hierarchies: rounds and QEM, closed and with a boundary, at the
/// coarsest and a middle level, with edits (marks and positions before an edit), with
/// labels, with the paper's translations.
fn valid_files() -> Vec<Vec<u8>> {
    let rounds = HierarchyOptions::rounds()
        .with_max_normal_deviation(90f64.to_radians())
        .with_target_faces(30);
    let qem = HierarchyOptions::qem().with_target_faces(30);
    let mut files = Vec::new();
    let sphere = Hierarchy::build(generators::icosphere(2), &rounds).unwrap();
    files.push(bytes_of(&sphere));
    let mut grid = Hierarchy::build(generators::grid(9, 7, 1.0, 0.8), &qem).unwrap();
    grid.go_to_level(grid.coarsest_level() / 2).unwrap();
    files.push(bytes_of(&grid));
    let mut edited = Hierarchy::build(generators::icosphere(2), &qem).unwrap();
    let m = edited.mesh();
    let cap: Vec<VertexId> = m.vertices().filter(|&v| m.position(v).z > 0.3).collect();
    let lift = DAffine3::from_translation(DVec3::Z * 0.2);
    for &v in &cap {
        let p = edited.mesh().position(v);
        edited.mesh_mut().set_position(v, lift.transform_point3(p));
    }
    edited.mark_affine(&cap, lift).unwrap();
    let ring: Vec<VertexId> = m_vertices(&edited, |p| p.z.abs() < 0.3);
    edited.mark_region(&ring).unwrap();
    edited.go_to_level(1).unwrap();
    let v = edited.mesh().vertices().next().unwrap();
    let p = edited.mesh().position(v);
    edited.mesh_mut().set_position(v, p + DVec3::X * 0.05);
    files.push(bytes_of(&edited));
    let mut labelled = Hierarchy::build(generators::icosphere(2), &rounds).unwrap();
    labelled.refine_to(0).unwrap();
    let mesh = labelled.mesh_mut();
    let frontier = mesh.frontier_from_plane(DVec3::ZERO, DVec3::Z).unwrap();
    let (labels, _) = mesh.label_sides(&frontier, 1, 2).unwrap();
    labelled.attach_labels(labels).unwrap();
    labelled.constrain_to_labels().unwrap();
    labelled.go_to_level(labelled.coarsest_level()).unwrap();
    files.push(bytes_of(&labelled));
    let paper = Hierarchy::build(
        generators::bow_tie(3),
        &rounds.clone().with_detail_mode(DetailMode::Translation),
    )
    .unwrap();
    files.push(bytes_of(&paper));
    files
}

fn m_vertices(h: &Hierarchy, keep: impl Fn(DVec3) -> bool) -> Vec<VertexId> {
    let m = h.mesh();
    m.vertices().filter(|&v| keep(m.position(v))).collect()
}

/// Section table: (offset, length) of every section.
fn table(bytes: &[u8]) -> Vec<(usize, usize)> {
    (0..8)
        .map(|k| {
            let e = &bytes[16 + 24 * k..16 + 24 * (k + 1)];
            let u = |a: usize| u64::from_le_bytes(e[a..a + 8].try_into().unwrap()) as usize;
            (u(8), u(16))
        })
        .collect()
}

/// Recomputes the header's and every section's CRC-32 (after a mutation inside the
/// sections, the table untouched).
fn fix_crcs(bytes: &mut [u8]) {
    let header = 16 + 24 * 8;
    let crc = crc32fast::hash(&bytes[..header]);
    bytes[header..header + 4].copy_from_slice(&crc.to_le_bytes());
    for (offset, length) in table(bytes) {
        let crc = crc32fast::hash(&bytes[offset..offset + length]);
        bytes[offset + length..offset + length + 4].copy_from_slice(&crc.to_le_bytes());
    }
}

/// Reads `bytes`: a format error naming the file, or a hierarchy whose mesh passes its
/// check and that walks to level 0 and back (typed errors allowed), its mesh checked
/// after each walk. Returns whether the file was accepted.
fn exercise(bytes: &[u8]) -> Result<bool, TestCaseError> {
    // The streaming reader of files decides as the reader of bytes does.
    let dir = std::env::temp_dir().join(format!("halfedge-mrh-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!("{:?}.mrh", std::thread::current().id()));
    std::fs::write(&file, bytes).unwrap();
    let streamed = Hierarchy::load(&file);
    std::fs::remove_file(&file).unwrap();
    let read = Hierarchy::read_from(bytes, "fuzz.mrh");
    prop_assert_eq!(
        streamed.is_ok(),
        read.is_ok(),
        "load and read_from disagree: {:?} / {:?}",
        streamed.as_ref().err(),
        read.as_ref().err()
    );
    if let Err(e) = &streamed {
        prop_assert!(matches!(e, Error::Format { .. }), "{e}");
    }
    let mut h = match read {
        Err(Error::Format { path, message }) => {
            prop_assert_eq!(path.to_str(), Some("fuzz.mrh"));
            prop_assert!(
                message.contains("section")
                    || message.contains("header")
                    || message.contains("hierarchy file")
                    || message.contains("bytes"),
                "an error that says where: {}",
                message
            );
            return Ok(false);
        }
        Err(other) => {
            return Err(TestCaseError::fail(format!(
                "not a format error: {other:?}"
            )))
        }
        Ok(h) => h,
    };
    h.mesh()
        .check()
        .map_err(|e| TestCaseError::fail(format!("accepted an invalid mesh: {e}")))?;
    let top = h.coarsest_level();
    for level in [0, top, top / 2, 0] {
        let walked = h.go_to_level(level);
        if let Err(e) = &walked {
            prop_assert!(
                matches!(
                    e,
                    Error::SplitRefused(_)
                        | Error::CollapseRefused { .. }
                        | Error::Overflow(_)
                        | Error::InvalidArgument(_)
                ),
                "{e}"
            );
        }
        h.mesh()
            .check()
            .map_err(|e| TestCaseError::fail(format!("walk to {level} ({walked:?}): {e}")))?;
    }
    Ok(true)
}

#[derive(Clone, Debug)]
enum Mutation {
    /// Keep this fraction (per mille) of the file.
    Cut(u16),
    /// Flip bits (byte position per mille, bit), CRCs left as they are.
    Flip(Vec<(u16, u8)>),
    /// Flip bits in the sections, CRCs computed again.
    FlipFixed(Vec<(u16, u8)>),
    /// A 32-bit word of a section set to a value, CRCs computed again.
    Word(u8, u16, WordValue),
    /// A 64-bit count-sized field set huge, CRCs computed again.
    Huge(u8, u16, u8),
    /// Record `a` copied over record `b`, CRCs computed again.
    CopyRecord(u16, u16),
    /// Another format version.
    Version(u32),
}

#[derive(Clone, Debug)]
enum WordValue {
    Zero,
    One,
    Max,
    Plus(u8),
    Minus(u8),
    Any(u32),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let flips = proptest::collection::vec((0u16..1000, 0u8..8), 1..4);
    let word = prop_oneof![
        Just(WordValue::Zero),
        Just(WordValue::One),
        Just(WordValue::Max),
        (1u8..8).prop_map(WordValue::Plus),
        (1u8..8).prop_map(WordValue::Minus),
        any::<u32>().prop_map(WordValue::Any),
    ];
    prop_oneof![
        2 => (0u16..1000).prop_map(Mutation::Cut),
        2 => flips.clone().prop_map(Mutation::Flip),
        6 => flips.prop_map(Mutation::FlipFixed),
        8 => (0u8..8, 0u16..1000, word).prop_map(|(s, at, w)| Mutation::Word(s, at, w)),
        3 => (0u8..8, 0u16..1000, 0u8..4).prop_map(|(s, at, k)| Mutation::Huge(s, at, k)),
        3 => (any::<u16>(), any::<u16>()).prop_map(|(a, b)| Mutation::CopyRecord(a, b)),
        1 => (2u32..1000).prop_map(Mutation::Version),
    ]
}

/// `bytes` mutated; whether the mutation must be refused (CRCs not computed again).
fn mutate(bytes: &[u8], m: &Mutation) -> (Vec<u8>, bool) {
    let mut out = bytes.to_vec();
    let sections = table(bytes);
    let body = sections[0].0..bytes.len();
    let at = |permille: u16, range: std::ops::Range<usize>| {
        range.start + (range.len().saturating_sub(1)) * permille as usize / 1000
    };
    match m {
        Mutation::Cut(permille) => {
            out.truncate(bytes.len() * *permille as usize / 1000);
            (out, true)
        }
        Mutation::Flip(flips) => {
            for &(p, bit) in flips {
                out[at(p, 0..bytes.len())] ^= 1 << bit;
            }
            (out, true)
        }
        Mutation::FlipFixed(flips) => {
            for &(p, bit) in flips {
                out[at(p, body.clone())] ^= 1 << bit;
            }
            fix_crcs(&mut out);
            (out, false)
        }
        Mutation::Word(s, p, value) => {
            let (offset, length) = sections[*s as usize];
            if length >= 4 {
                let i = offset + (at(*p, 0..length - 3) / 4) * 4;
                let old = u32::from_le_bytes(out[i..i + 4].try_into().unwrap());
                let new = match value {
                    WordValue::Zero => 0,
                    WordValue::One => 1,
                    WordValue::Max => u32::MAX,
                    WordValue::Plus(k) => old.wrapping_add(u32::from(*k)),
                    WordValue::Minus(k) => old.wrapping_sub(u32::from(*k)),
                    WordValue::Any(x) => *x,
                };
                out[i..i + 4].copy_from_slice(&new.to_le_bytes());
                fix_crcs(&mut out);
            }
            (out, false)
        }
        Mutation::Huge(s, p, k) => {
            let (offset, length) = sections[*s as usize];
            if length >= 8 {
                let i = offset + (at(*p, 0..length - 7) / 8) * 8;
                let value = [u64::MAX, 1 << 40, 1 << 32, u64::MAX / 24][*k as usize];
                out[i..i + 8].copy_from_slice(&value.to_le_bytes());
                fix_crcs(&mut out);
            }
            (out, false)
        }
        Mutation::CopyRecord(a, b) => {
            let (offset, length) = sections[3];
            let n = u64::from_le_bytes(out[offset..offset + 8].try_into().unwrap()) as usize;
            const STEP: usize = 85;
            if n > 1 && length >= 8 + n * STEP {
                let (a, b) = (*a as usize % n, *b as usize % n);
                let (a, b) = (offset + 8 + a * STEP, offset + 8 + b * STEP);
                let record = out[a..a + STEP].to_vec();
                out[b..b + STEP].copy_from_slice(&record);
                fix_crcs(&mut out);
            }
            (out, false)
        }
        Mutation::Version(v) => {
            out[8..12].copy_from_slice(&v.to_le_bytes());
            (out, true)
        }
    }
}

proptest! {
    #![proptest_config(config(96))]

    #[test]
    fn mutated_hierarchy_files_are_refused_or_walk_safely(
        file in 0usize..5,
        mutations in proptest::collection::vec(mutation(), 1..3),
    ) {
        let files = files();
        let mut bytes = files[file].clone();
        let mut refuse = false;
        for m in &mutations {
            let (mutated, must_refuse) = mutate(&bytes, m);
            refuse |= must_refuse;
            bytes = mutated;
            if refuse {
                break;
            }
        }
        let accepted = exercise(&bytes)?;
        if std::env::var_os("MRH_FUZZ_STATS").is_some() {
            eprintln!("accepted={accepted} {mutations:?}");
        }
        prop_assert!(!(refuse && accepted), "a damaged file was accepted: {:?}", mutations);
    }
}

/// The valid files, made once.
fn files() -> &'static [Vec<u8>] {
    static FILES: std::sync::OnceLock<Vec<Vec<u8>>> = std::sync::OnceLock::new();
    FILES.get_or_init(valid_files)
}

#[test]
fn the_valid_files_load_and_walk() {
    for bytes in files() {
        assert!(exercise(bytes).unwrap());
    }
}

#[test]
fn cuts_at_and_around_every_section_boundary_are_refused() {
    for bytes in files() {
        let mut cuts = vec![0, 1, 8, 12, 16, 100, 16 + 24 * 8, 16 + 24 * 8 + 4];
        for (offset, length) in table(bytes) {
            for c in [offset, offset + length, offset + length + 4] {
                cuts.extend([c.saturating_sub(1), c, c + 1]);
            }
        }
        for cut in cuts.into_iter().filter(|&c| c < bytes.len()) {
            assert!(!exercise(&bytes[..cut]).unwrap(), "cut at {cut} accepted");
        }
    }
}
