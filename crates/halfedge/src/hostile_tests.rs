//! The kernel's hostile suite (issue 14): proptest state machines that drive collapses,
//! vertex splits in and out of order, records split twice, records of clones,
//! `split_edge`, `add_triangle` (on live, removed and foreign vertices) and garbage
//! collection in random order, and the hierarchy's walks with edits behind its back.
//! After every step the mesh passes [`Mesh::check`]; every refused operation leaves the
//! mesh bit for bit as it was (all arrays, tombstones, slot states and generations,
//! counts, position bits and the topology stamp); every accepted split gives `v0` back
//! the very one-ring it had before its collapse.
//!
//! The seeds are fixed, so CI runs the same sequences every time in a few seconds; set
//! `MULTIRES_HOSTILE_CASES` to a number of sequences per test for a long run (with a
//! seed of its own: `MULTIRES_HOSTILE_SEED`).

use glam::DVec3;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

use crate::handle::Slots;
use crate::mesh::HalfedgeRec;
use crate::{generators, CollapseRecord, Error, FaceId, HalfedgeId, Mesh, VertexId};

/// Proptest configuration: `default_cases` sequences with a fixed seed, or as many as
/// `MULTIRES_HOSTILE_CASES` says.
pub(crate) fn config(default_cases: u32) -> Config {
    let cases = std::env::var("MULTIRES_HOSTILE_CASES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(default_cases);
    let seed = std::env::var("MULTIRES_HOSTILE_SEED")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(0x686f_7374_696c_6531);
    Config {
        cases,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        ..Config::default()
    }
}

/// Everything a mesh is made of, bit for bit (attribute values aside: no operation
/// here writes them).
#[derive(Debug, PartialEq)]
pub(crate) struct Raw {
    vertex_conn: Vec<u32>,
    vertex_slots: Slots,
    he: Vec<HalfedgeRec>,
    halfedge_slots: Slots,
    face_conn: Vec<u32>,
    face_slots: Slots,
    positions: Vec<[u64; 3]>,
    counts: [usize; 3],
    binding: crate::Binding,
    lineage: Vec<(u64, u64)>,
    attribute_columns: [usize; 3],
}

/// The whole state of `m`.
pub(crate) fn raw(m: &Mesh) -> Raw {
    Raw {
        vertex_conn: m.vertex_conn.clone(),
        vertex_slots: m.vertex_slots_.clone(),
        he: m.he.clone(),
        halfedge_slots: m.halfedge_slots_.clone(),
        face_conn: m.face_conn.clone(),
        face_slots: m.face_slots_.clone(),
        positions: m
            .positions
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect(),
        counts: [m.n_vertices, m.n_halfedges, m.n_faces],
        binding: m.binding(),
        lineage: m.provenance.lineage().to_vec(),
        attribute_columns: [
            m.vertex_attributes.column_count(),
            m.halfedge_attributes.column_count(),
            m.face_attributes.column_count(),
        ],
    }
}

/// The one-ring of `v`: its outgoing halfedges from its vertex halfedge on, each with
/// its target and face.
type Ring = Vec<(HalfedgeId, VertexId, Option<FaceId>)>;

fn ring(m: &Mesh, v: VertexId) -> Ring {
    m.outgoing_halfedges(v)
        .map(|h| (h, m.to_vertex(h), m.face(h)))
        .collect()
}

/// The test meshes: closed, with a boundary, with a bow-tie; small, so that random
/// operations meet each other's neighbourhoods often.
pub(crate) fn test_mesh(kind: u8) -> Mesh {
    match kind % 4 {
        0 => generators::icosphere(1),
        1 => generators::grid(5, 4, 1.0, 0.8),
        2 => {
            // Two grids sharing one corner vertex: a bow-tie.
            let g = generators::grid(2, 2, 1.0, 1.0);
            let mut positions: Vec<DVec3> = g.positions().to_vec();
            let mut triangles: Vec<[u32; 3]> = g
                .faces()
                .map(|f| g.triangle(f).map(|v| g.vertex_index(v) as u32))
                .collect();
            let n = positions.len() as u32;
            let corner = 8; // (2, 2)
            for p in g.positions() {
                positions.push(*p + DVec3::new(1.0, 1.0, 0.0));
            }
            for t in triangles.clone() {
                triangles.push(t.map(|i| if i == 0 { corner } else { i + n }));
            }
            Mesh::from_triangles(&positions, &triangles).unwrap().0
        }
        _ => generators::icosphere(0),
    }
}

/// One step of the kernel machine; the numbers pick among the candidates of the moment.
#[derive(Clone, Debug)]
enum Op {
    /// Collapse a legal halfedge.
    Collapse(u32),
    /// Collapse any halfedge (often refused).
    CollapseAny(u32),
    /// Split the last record.
    SplitLast,
    /// Split any record (out of order, already split, foreign).
    SplitAny(u32),
    /// `split_edge` at the midpoint.
    SplitEdge(u32),
    /// A new vertex and a triangle on a boundary edge and it.
    AddEar(u32),
    /// A triangle on three picked vertices (live, removed or foreign).
    AddTriangle(u32, u32, u32),
    /// `garbage_collection`.
    Collect,
    /// The mesh is replaced by its clone (records made before stay its history).
    CloneSwap,
    /// A collapse on a clone: its record belongs to another mesh.
    ForeignRecord(u32),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        6 => any::<u32>().prop_map(Op::Collapse),
        1 => any::<u32>().prop_map(Op::CollapseAny),
        3 => Just(Op::SplitLast),
        4 => any::<u32>().prop_map(Op::SplitAny),
        1 => any::<u32>().prop_map(Op::SplitEdge),
        1 => any::<u32>().prop_map(Op::AddEar),
        1 => (any::<u32>(), any::<u32>(), any::<u32>()).prop_map(|(a, b, c)| Op::AddTriangle(a, b, c)),
        1 => Just(Op::Collect),
        1 => Just(Op::CloneSwap),
        1 => any::<u32>().prop_map(Op::ForeignRecord),
    ]
}

struct Entry {
    record: CollapseRecord,
    /// `v0`'s one-ring before the collapse; `None` for a record of another mesh.
    ring: Option<Ring>,
}

fn pick<T: Copy>(items: &[T], k: u32) -> Option<T> {
    (!items.is_empty()).then(|| items[k as usize % items.len()])
}

/// How often each outcome occurred, to check that the machines reach every case.
#[derive(Default, Debug)]
struct Stats(std::collections::BTreeMap<&'static str, usize>);

impl Stats {
    fn count(&mut self, what: &'static str) {
        *self.0.entry(what).or_default() += 1;
    }
    /// Counts a split refusal by its reason.
    fn refused(&mut self, e: &Error) {
        let text = e.to_string();
        let reason = [
            ("another mesh", "split refused: another mesh"),
            ("already split", "split refused: already split"),
            (
                "garbage_collection",
                "split refused: freed by garbage collection",
            ),
            ("link", "split refused: a link changed"),
            ("neighbourhood", "split refused: the fingerprint differs"),
        ]
        .into_iter()
        .find(|(key, _)| text.contains(key))
        .map_or("split refused: other reasons", |(_, name)| name);
        self.count(reason);
    }
    fn get(&self, what: &str) -> usize {
        self.0.get(what).copied().unwrap_or(0)
    }
}

/// Runs `ops` on `mesh`, checking the machine's properties after every step.
fn run_kernel(
    mut mesh: Mesh,
    ops: &[Op],
    stats: &mut Stats,
) -> std::result::Result<(), TestCaseError> {
    let mut entries: Vec<Entry> = Vec::new();
    // A vertex of another mesh instance, for add_triangle.
    let foreign_vertex = generators::icosphere(2).vertices().last().unwrap();
    for op in ops {
        let before = raw(&mesh);
        match *op {
            Op::Collapse(k) | Op::CollapseAny(k) => {
                let candidates: Vec<HalfedgeId> = if matches!(op, Op::Collapse(_)) {
                    mesh.halfedges()
                        .filter(|&h| mesh.is_collapse_ok(h).is_ok())
                        .collect()
                } else {
                    mesh.halfedges().collect()
                };
                let Some(h) = pick(&candidates, k) else {
                    continue;
                };
                let v0 = mesh.from_vertex(h);
                let ring0 = ring(&mesh, v0);
                match mesh.collapse(h) {
                    Ok(record) => {
                        stats.count("collapse accepted");
                        let p = 0.5 * (record.p0 + record.p1);
                        mesh.set_position(record.v1, p);
                        entries.push(Entry {
                            record,
                            ring: Some(ring0),
                        });
                    }
                    Err(e) => {
                        stats.count("collapse refused");
                        prop_assert!(matches!(e, Error::CollapseRefused { .. }), "{e}");
                        prop_assert!(raw(&mesh) == before, "a refused collapse changed the mesh");
                    }
                }
            }
            Op::SplitLast | Op::SplitAny(_) => {
                let i = match *op {
                    Op::SplitAny(k) if !entries.is_empty() => k as usize % entries.len(),
                    _ if !entries.is_empty() => entries.len() - 1,
                    _ => continue,
                };
                let entry = &entries[i];
                let res = mesh.vertex_split(&entry.record);
                match res {
                    Ok(()) => {
                        stats.count(if i + 1 == entries.len() {
                            "split of the last record accepted"
                        } else {
                            "split out of order accepted"
                        });
                        let Some(ring0) = &entry.ring else {
                            return Err(TestCaseError::fail(
                                "a record of another mesh was accepted",
                            ));
                        };
                        mesh.check()
                            .map_err(|e| TestCaseError::fail(format!("after a split: {e}")))?;
                        prop_assert_eq!(&ring(&mesh, entry.record.v0), ring0);
                        prop_assert_eq!(mesh.position(entry.record.v0), entry.record.p0);
                        prop_assert_eq!(mesh.position(entry.record.v1), entry.record.p1);
                    }
                    Err(e) => {
                        stats.refused(&e);
                        prop_assert!(matches!(e, Error::SplitRefused(_)), "{e}");
                        prop_assert!(
                            raw(&mesh) == before,
                            "a refused split changed the mesh: {e}"
                        );
                    }
                }
            }
            Op::SplitEdge(k) => {
                let hs: Vec<HalfedgeId> = mesh.halfedges().collect();
                let Some(h) = pick(&hs, k) else { continue };
                let p =
                    0.5 * (mesh.position(mesh.from_vertex(h)) + mesh.position(mesh.to_vertex(h)));
                if mesh.split_edge(h, p).is_err() {
                    stats.count("split_edge refused");
                    prop_assert!(
                        raw(&mesh) == before,
                        "a refused split_edge changed the mesh"
                    );
                } else {
                    stats.count("split_edge accepted");
                }
            }
            Op::AddEar(k) => {
                let boundary: Vec<HalfedgeId> = mesh
                    .halfedges()
                    .filter(|&h| mesh.is_boundary_halfedge(h))
                    .collect();
                let Some(h) = pick(&boundary, k) else {
                    continue;
                };
                let (a, b) = (mesh.from_vertex(h), mesh.to_vertex(h));
                let p = 0.5 * mesh.position(a) + 0.5 * mesh.position(b) + DVec3::Z;
                let c = mesh.add_vertex(p);
                let after_vertex = raw(&mesh);
                match mesh.add_triangle(a, b, c) {
                    Ok(_) => stats.count("ear added"),
                    Err(_) => prop_assert!(raw(&mesh) == after_vertex),
                }
            }
            Op::AddTriangle(a, b, c) => {
                let mut pool: Vec<VertexId> = mesh.vertices().collect();
                pool.extend(entries.iter().map(|e| e.record.v0));
                pool.push(foreign_vertex);
                let (Some(a), Some(b), Some(c)) = (pick(&pool, a), pick(&pool, b), pick(&pool, c))
                else {
                    continue;
                };
                if mesh.add_triangle(a, b, c).is_err() {
                    stats.count("add_triangle refused");
                    prop_assert!(
                        raw(&mesh) == before,
                        "a refused add_triangle changed the mesh"
                    );
                }
            }
            Op::Collect => mesh.garbage_collection(),
            Op::CloneSwap => mesh = mesh.clone(),
            Op::ForeignRecord(k) => {
                let mut other = mesh.clone();
                let candidates: Vec<HalfedgeId> = other
                    .halfedges()
                    .filter(|&h| other.is_collapse_ok(h).is_ok())
                    .collect();
                let Some(h) = pick(&candidates, k) else {
                    continue;
                };
                let record = other.collapse(h).unwrap();
                entries.push(Entry { record, ring: None });
                continue;
            }
        }
        mesh.check()
            .map_err(|e| TestCaseError::fail(format!("after {op:?}: {e}")))?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(160))]

    #[test]
    fn kernel_sequences_keep_the_mesh_valid_and_refusals_change_nothing(
        kind in 0u8..4,
        ops in proptest::collection::vec(op(), 1..120),
    ) {
        run_kernel(test_mesh(kind), &ops, &mut Stats::default())?;
    }
}

// ---------------------------------------------------------------------------------------
// The hierarchy machine.

use crate::{Hierarchy, HierarchyOptions};

/// One step of the hierarchy machine.
#[derive(Clone, Debug)]
enum HOp {
    SplitNext,
    CollapseNext,
    GoToLevel(u32),
    Seek(u32),
    /// `split_edge` on the mesh behind the hierarchy's back.
    SplitEdge(u32),
    /// A collapse on the mesh behind its back.
    Collapse(u32),
    /// An ear on a boundary edge behind its back.
    AddEar(u32),
    Collect,
    /// The mesh is replaced by its clone.
    CloneMesh,
    /// The mesh is replaced by an unrelated one.
    SwapMesh(u8),
    /// The hierarchy is replaced by its clone.
    CloneHierarchy,
    /// A vertex moved by a vector of length 10^|e|, either way.
    Move(u32, i16),
    /// Every position scaled by 10^e.
    Scale(i16),
    /// Sub-mesh labels attached here.
    AttachLabels,
    /// The label attribute removed from the mesh.
    RemoveLabels,
    /// An attribute of another type in the place of the removed labels.
    OtherAttribute,
    /// A vertex marked (composed when the flag is set) with a translation of 10^e, or
    /// (composed, odd e) with the field `p (1 + 10^e) + 10^e y`.
    Mark(u32, i16, bool),
    /// The ancestors of a level (some out of range).
    Ancestors(u32),
    /// `edit_input` moving an input vertex, or refusing in the closure.
    EditInput(u32, bool),
    /// A bookmark of where the hierarchy is.
    Bookmark,
    /// Back to one of the bookmarks taken so far (some no longer fit).
    ReturnTo(u32),
    /// `unfold_refinement` where the hierarchy is.
    Unfold,
}

fn hop() -> impl Strategy<Value = HOp> {
    prop_oneof![
        16 => Just(HOp::SplitNext),
        10 => Just(HOp::CollapseNext),
        6 => any::<u32>().prop_map(HOp::GoToLevel),
        4 => any::<u32>().prop_map(HOp::Seek),
        1 => any::<u32>().prop_map(HOp::SplitEdge),
        1 => any::<u32>().prop_map(HOp::Collapse),
        1 => any::<u32>().prop_map(HOp::AddEar),
        1 => Just(HOp::Collect),
        1 => Just(HOp::CloneMesh),
        1 => any::<u8>().prop_map(HOp::SwapMesh),
        2 => Just(HOp::CloneHierarchy),
        4 => (any::<u32>(), -308i16..=308).prop_map(|(v, e)| HOp::Move(v, e)),
        2 => prop_oneof![306i16..=308, -320i16..=-300, -3i16..=3].prop_map(HOp::Scale),
        2 => Just(HOp::AttachLabels),
        1 => Just(HOp::RemoveLabels),
        1 => Just(HOp::OtherAttribute),
        2 => (any::<u32>(), -320i16..=308, any::<bool>()).prop_map(|(v, e, c)| HOp::Mark(v, e, c)),
        1 => any::<u32>().prop_map(HOp::Ancestors),
        1 => (any::<u32>(), any::<bool>()).prop_map(|(v, ok)| HOp::EditInput(v, ok)),
        2 => Just(HOp::Bookmark),
        2 => any::<u32>().prop_map(HOp::ReturnTo),
        1 => Just(HOp::Unfold),
    ]
}

fn hierarchy_mesh(kind: u8) -> Mesh {
    match kind % 3 {
        0 => generators::icosphere(2),
        1 => generators::grid(9, 7, 1.0, 0.8),
        _ => generators::subdivide(&test_mesh(2)),
    }
}

fn live_positions_finite(m: &Mesh) -> bool {
    m.vertices().all(|v| m.position(v).is_finite())
}

fn run_hierarchy(
    kind: u8,
    qem: bool,
    ops: &[HOp],
    stats: &mut Stats,
) -> std::result::Result<(), TestCaseError> {
    let options = if qem {
        HierarchyOptions::qem()
    } else {
        HierarchyOptions::rounds().with_max_normal_deviation(90f64.to_radians())
    };
    let mut h = Hierarchy::build(hierarchy_mesh(kind), &options.with_target_faces(20)).unwrap();
    let n_records = h.records().len() as u32 + 1;
    let n_levels = h.n_levels() as u32;
    let mut bookmarks: Vec<crate::LevelBookmark> = Vec::new();
    for op in ops {
        let before = raw(h.mesh());
        let single = |r: crate::Result<bool>,
                      h: &Hierarchy,
                      stats: &mut Stats|
         -> std::result::Result<(), TestCaseError> {
            match r {
                Ok(_) => {
                    stats.count("step accepted");
                    prop_assert!(
                        live_positions_finite(h.mesh()),
                        "a step made a position non-finite"
                    )
                }
                Err(e) => {
                    stats.count(match e {
                        Error::SplitRefused(_) => "split refused",
                        Error::CollapseRefused { .. } => "collapse refused",
                        Error::Overflow(_) => "overflow refused",
                        _ => "other refusal",
                    });
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
                    prop_assert!(
                        raw(h.mesh()) == before,
                        "a refused step changed the mesh: {e}"
                    );
                }
            }
            Ok(())
        };
        match *op {
            HOp::SplitNext => {
                let r = h.split_next();
                single(r, &h, stats)?;
            }
            HOp::CollapseNext => {
                let r = h.collapse_next();
                single(r, &h, stats)?;
            }
            HOp::GoToLevel(k) => {
                if h.go_to_level((k % (n_levels + 1)) as usize).is_ok() {
                    prop_assert!(live_positions_finite(h.mesh()));
                }
            }
            HOp::Seek(k) => {
                if h.seek((k % (n_records + 1)) as usize).is_ok() {
                    prop_assert!(live_positions_finite(h.mesh()));
                }
            }
            HOp::SplitEdge(k) => {
                let mesh = h.mesh_mut();
                let hs: Vec<HalfedgeId> = mesh.halfedges().collect();
                let Some(e) = pick(&hs, k) else { continue };
                let p =
                    0.5 * (mesh.position(mesh.from_vertex(e)) + mesh.position(mesh.to_vertex(e)));
                let _ = mesh.split_edge(e, p);
            }
            HOp::Collapse(k) => {
                let mesh = h.mesh_mut();
                let hs: Vec<HalfedgeId> = mesh
                    .halfedges()
                    .filter(|&e| mesh.is_collapse_ok(e).is_ok())
                    .collect();
                let Some(e) = pick(&hs, k) else { continue };
                mesh.collapse(e).unwrap();
            }
            HOp::AddEar(k) => {
                let mesh = h.mesh_mut();
                let boundary: Vec<HalfedgeId> = mesh
                    .halfedges()
                    .filter(|&e| mesh.is_boundary_halfedge(e))
                    .collect();
                let Some(e) = pick(&boundary, k) else {
                    continue;
                };
                let (a, b) = (mesh.from_vertex(e), mesh.to_vertex(e));
                let c = mesh.add_vertex(0.5 * mesh.position(a) + 0.5 * mesh.position(b) + DVec3::Z);
                let _ = mesh.add_triangle(a, b, c);
            }
            HOp::Collect => h.mesh_mut().garbage_collection(),
            HOp::CloneMesh => {
                let copy = h.mesh().clone();
                *h.mesh_mut() = copy;
            }
            HOp::SwapMesh(k) => *h.mesh_mut() = test_mesh(k),
            HOp::CloneHierarchy => h = h.clone(),
            HOp::Move(k, e) => {
                let mesh = h.mesh_mut();
                let vs: Vec<VertexId> = mesh.vertices().collect();
                let Some(v) = pick(&vs, k) else { continue };
                let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                let d = DVec3::new(1.0, -0.5, 0.25) * sign * 10f64.powi(i32::from(e.abs()));
                let p = mesh.position(v) + d;
                if p.is_finite() {
                    mesh.set_position(v, p);
                }
            }
            HOp::Scale(e) => {
                let s = 10f64.powi(i32::from(e));
                for p in h.mesh_mut().positions_mut() {
                    let q = *p * s;
                    if q.is_finite() {
                        *p = q;
                    }
                }
            }
            HOp::AttachLabels => {
                if let Ok(a) = h.mesh_mut().label_attribute() {
                    h.mesh_mut().attribute_values_mut(a).unwrap().fill(1);
                    h.attach_labels(a).unwrap();
                }
            }
            HOp::RemoveLabels => {
                if let Some(a) = h.label_attribute() {
                    // A second removal is refused (the handle is stale), changing nothing.
                    let _refused_when_removed_already = h.mesh_mut().remove_attribute(a);
                }
            }
            HOp::OtherAttribute => {
                let _ = h.mesh_mut().add_vertex_attribute("other", 0.5f64);
            }
            HOp::Mark(k, e, compose) => {
                let vs: Vec<VertexId> = h.mesh().vertices().collect();
                let Some(v) = pick(&vs, k) else { continue };
                let s = 10f64.powi(i32::from(e));
                let t = glam::DAffine3::from_translation(DVec3::X * s);
                let r = match (compose, e % 2 == 0) {
                    (true, true) => h.mark_affine(&[v], t),
                    // a field that overflows for large `s`
                    (true, false) => h.mark_field(&[v], move |p| p * (1.0 + s) + DVec3::Y * s),
                    (false, _) => h.set_affine_mark(&[v], t),
                };
                stats.count(if r.is_ok() {
                    "mark accepted"
                } else {
                    "mark refused"
                });
                prop_assert!(raw(h.mesh()) == before, "a mark changed the mesh");
            }
            HOp::Ancestors(k) => {
                if let Ok(a) = h.ancestors((k % (n_levels + 2)) as usize) {
                    prop_assert_eq!(a.len(), h.mesh().vertex_slots());
                }
            }
            HOp::EditInput(k, ok) => {
                let level = h.current_level();
                let r = h.edit_input(|m| {
                    if !ok {
                        return Err("refused by the closure");
                    }
                    let vs: Vec<VertexId> = m.vertices().collect();
                    if let Some(v) = pick(&vs, k) {
                        m.set_position(v, m.position(v) + DVec3::X * 1e-3);
                    }
                    Ok(())
                });
                match r {
                    Ok(()) => {
                        stats.count("edit_input accepted");
                        prop_assert!(live_positions_finite(h.mesh()));
                    }
                    Err(e) => {
                        stats.count("edit_input refused");
                        prop_assert!(
                            raw(h.mesh()) == before && h.current_level() == level,
                            "a refused edit_input changed the hierarchy: {e}"
                        );
                    }
                }
            }
            HOp::Bookmark => bookmarks.push(h.bookmark()),
            HOp::ReturnTo(k) => {
                if bookmarks.is_empty() {
                    continue;
                }
                let b = &bookmarks[k as usize % bookmarks.len()];
                let applied = h.applied();
                match h.return_to(b) {
                    Ok(()) => {
                        stats.count("return_to accepted");
                        prop_assert_eq!(h.applied(), b.applied());
                        prop_assert!(h.mesh().positions() == b.positions());
                    }
                    // A walk back finer stops where a marked field overflows, as a
                    // walk does.
                    Err(crate::Error::Overflow(_)) => stats.count("overflow refused"),
                    Err(e) => {
                        stats.count("return_to refused");
                        prop_assert!(
                            raw(h.mesh()) == before && h.applied() == applied,
                            "a refused return_to changed the hierarchy: {e}"
                        );
                    }
                }
            }
            HOp::Unfold => {
                let finite = live_positions_finite(h.mesh());
                h.unfold_refinement();
                prop_assert!(!finite || live_positions_finite(h.mesh()));
            }
        }
        h.mesh()
            .check()
            .map_err(|e| TestCaseError::fail(format!("after {op:?}: {e}")))?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(48))]

    #[test]
    fn hierarchy_walks_with_edits_behind_its_back_never_corrupt_the_mesh(
        kind in 0u8..3,
        qem in any::<bool>(),
        ops in proptest::collection::vec(hop(), 1..60),
    ) {
        run_hierarchy(kind, qem, &ops, &mut Stats::default())?;
    }
}

/// The machines reach every outcome they are meant to test: splits accepted in and out of
/// order and refused for each reason, refused collapses and steps, overflows, labels.
#[test]
fn the_machines_reach_every_case() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::new(config(1));
    let mut kernel = Stats::default();
    for case in 0..300u32 {
        let ops = proptest::collection::vec(op(), 1..120)
            .new_tree(&mut runner)
            .unwrap()
            .current();
        run_kernel(test_mesh(case as u8), &ops, &mut kernel).unwrap();
    }
    for what in [
        "collapse accepted",
        "collapse refused",
        "split of the last record accepted",
        "split out of order accepted",
        "split refused: another mesh",
        "split refused: already split",
        "split refused: freed by garbage collection",
        "split refused: a link changed",
        "split refused: the fingerprint differs",
        "split_edge accepted",
        "split_edge refused",
        "ear added",
        "add_triangle refused",
    ] {
        assert!(kernel.get(what) > 0, "never: {what} ({kernel:?})");
    }
    let mut hierarchy = Stats::default();
    for case in 0..200u32 {
        let ops = proptest::collection::vec(hop(), 1..60)
            .new_tree(&mut runner)
            .unwrap()
            .current();
        run_hierarchy(case as u8, case % 2 == 1, &ops, &mut hierarchy).unwrap();
    }
    for what in [
        "step accepted",
        "split refused",
        "collapse refused",
        "overflow refused",
        "other refusal",
        "mark accepted",
        "edit_input refused",
        "return_to accepted",
        "return_to refused",
    ] {
        assert!(hierarchy.get(what) > 0, "never: {what} ({hierarchy:?})");
    }
    eprintln!("kernel: {kernel:?}\nhierarchy: {hierarchy:?}");
}

/// A coarse edit so large that the refined positions would overflow is refused, and the
/// mesh is left as it was.
#[test]
fn translations_that_overflow_are_refused() {
    let mut h = Hierarchy::build(
        generators::icosphere(2),
        &HierarchyOptions::rounds().with_target_faces(40),
    )
    .unwrap();
    for p in h.mesh_mut().positions_mut() {
        *p *= 1.5e308;
    }
    let before = raw(h.mesh());
    let e = h.split_next().unwrap_err();
    assert!(matches!(e, Error::Overflow(_)), "{e}");
    assert!(raw(h.mesh()) == before);
    h.mesh().check().unwrap();
}

// ---------------------------------------------------------------------------------------
// The cases of issue 14, one by one.

/// A legal collapse of an edge leaving `v`.
fn collapse_at(mesh: &mut Mesh, v: VertexId) -> CollapseRecord {
    let h = mesh
        .outgoing_halfedges(v)
        .find(|&h| mesh.is_collapse_ok(h).is_ok())
        .expect("a legal collapse");
    mesh.collapse(h).unwrap()
}

/// `vertex_split(r)` is refused with a reason containing `why`, and changes nothing.
fn assert_refused(mesh: &mut Mesh, r: &CollapseRecord, why: &str) {
    let before = raw(mesh);
    match mesh.vertex_split(r) {
        Err(Error::SplitRefused(reason)) => assert!(reason.contains(why), "{reason}"),
        other => panic!("expected a refusal ({why}), got {other:?}"),
    }
    assert!(raw(mesh) == before, "the refusal changed the mesh");
    mesh.check().unwrap();
}

#[test]
fn a_split_after_split_edge_in_its_neighbourhood_is_refused() {
    // On the kept edge v1 → vl: the links the collapse wrote change.
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(20).unwrap();
    let r = collapse_at(&mut mesh, v);
    mesh.split_edge(r.v1vl.unwrap(), DVec3::ZERO).unwrap();
    assert_refused(&mut mesh, &r, "link");
    // On the middle one of the three edges the collapse moved from v0 to v1 (counter-
    // clockwise after v1 → vl): only the fingerprint sees it.
    let mut mesh = generators::icosphere(1);
    assert_eq!(mesh.valence(v), 6);
    let r = collapse_at(&mut mesh, v);
    let moved = mesh.ccw_rotated(mesh.ccw_rotated(r.v1vl.unwrap()));
    mesh.split_edge(moved, DVec3::ZERO).unwrap();
    assert_refused(&mut mesh, &r, "neighbourhood");
    // Far away: the record still fits, and the split gives v0 its ring back.
    let mut mesh = generators::icosphere(2);
    let v = mesh.vertices().next().unwrap();
    let ring0 = ring(&mesh, v);
    let r = collapse_at(&mut mesh, v);
    let far = mesh
        .halfedges()
        .find(|&h| mesh.position(mesh.from_vertex(h)).distance(r.p0) > 1.0)
        .unwrap();
    mesh.split_edge(far, DVec3::ZERO).unwrap();
    mesh.vertex_split(&r).unwrap();
    mesh.check().unwrap();
    assert_eq!(ring(&mesh, v), ring0);
}

#[test]
fn out_of_order_splits_are_refused_where_the_collapses_meet() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(15).unwrap();
    let a = collapse_at(&mut mesh, v);
    let b = collapse_at(&mut mesh, a.v1);
    assert_refused(&mut mesh, &a, "");
    mesh.vertex_split(&b).unwrap();
    mesh.vertex_split(&a).unwrap();
    mesh.check().unwrap();
    // Collapses that do not meet may be undone in any order.
    let mut mesh = generators::icosphere(2);
    let original = raw(&mesh);
    let v = mesh.vertices().next().unwrap();
    let a = collapse_at(&mut mesh, v);
    let far = mesh
        .vertices()
        .find(|&w| mesh.position(w).distance(a.p0) > 1.5)
        .unwrap();
    let b = collapse_at(&mut mesh, far);
    mesh.vertex_split(&a).unwrap();
    mesh.check().unwrap();
    mesh.vertex_split(&b).unwrap();
    mesh.check().unwrap();
    let restored = raw(&mesh);
    assert_eq!(
        (&restored.he, &restored.vertex_conn, &restored.face_conn),
        (&original.he, &original.vertex_conn, &original.face_conn)
    );
}

#[test]
fn a_record_split_twice_is_refused() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(3).unwrap();
    let r = collapse_at(&mut mesh, v);
    mesh.vertex_split(&r).unwrap();
    assert_refused(&mut mesh, &r, "already split");
    // Even when v0 was removed again by another collapse.
    let other = mesh
        .outgoing_halfedges(r.v0)
        .find(|&h| h != r.v0v1 && mesh.is_collapse_ok(h).is_ok())
        .unwrap();
    mesh.collapse(other).unwrap();
    assert_refused(&mut mesh, &r, "");
}

#[test]
fn records_of_other_meshes_are_refused() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(7).unwrap();
    // The same collapse on a clone made before it: the record is not the mesh's.
    let mut clone = mesh.clone();
    let theirs = collapse_at(&mut clone, v);
    let ours = collapse_at(&mut mesh, v);
    assert_refused(&mut mesh, &theirs, "another mesh");
    assert_refused(&mut clone, &ours, "another mesh");
    // A clone made after the collapse shares its history and accepts the record.
    let mut later = mesh.clone();
    later.vertex_split(&ours).unwrap();
    later.check().unwrap();
    // An unrelated mesh of the same shape refuses it.
    let mut unrelated = generators::icosphere(1);
    collapse_at(&mut unrelated, v);
    assert_refused(&mut unrelated, &ours, "another mesh");
}

#[test]
fn records_freed_by_garbage_collection_are_refused() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(9).unwrap();
    let r = collapse_at(&mut mesh, v);
    mesh.garbage_collection();
    assert_refused(&mut mesh, &r, "garbage_collection");
    // Slots reused by new elements are refused too.
    let h = mesh.halfedges().next().unwrap();
    mesh.split_edge(h, DVec3::ZERO).unwrap();
    assert_refused(&mut mesh, &r, "");
}

#[test]
fn a_split_after_add_triangle_in_its_neighbourhood_is_refused() {
    let mut mesh = generators::grid(4, 4, 1.0, 1.0);
    // A boundary vertex in the middle of the bottom side: collapse an edge into it.
    let v = mesh.vertices().nth(2).unwrap();
    let h = mesh
        .outgoing_halfedges(v)
        .find(|&h| mesh.is_boundary_halfedge(h) && mesh.is_collapse_ok(h).is_ok())
        .unwrap();
    let r = mesh.collapse(h).unwrap();
    // An ear on the boundary edge the collapse moved to v1.
    let b = mesh
        .outgoing_halfedges(r.v1)
        .find(|&k| mesh.is_boundary_halfedge(k))
        .unwrap();
    let (x, y) = (mesh.from_vertex(b), mesh.to_vertex(b));
    let c = mesh.add_vertex(DVec3::new(0.5, -1.0, 0.0));
    mesh.add_triangle(x, y, c).unwrap();
    assert_refused(&mut mesh, &r, "");
}

#[test]
fn a_removed_label_attribute_is_refused_before_the_split() {
    let mut h = Hierarchy::build(
        generators::icosphere(2),
        &HierarchyOptions::rounds().with_target_faces(40),
    )
    .unwrap();
    let labels = h.mesh_mut().label_attribute().unwrap();
    h.attach_labels(labels).unwrap();
    h.coarsen_to(h.coarsest_level()).unwrap();
    h.mesh_mut().remove_attribute(labels).unwrap();
    for replaced in [false, true] {
        if replaced {
            // Its place taken by an attribute of another type.
            h.mesh_mut().add_vertex_attribute("x", 0.5f64).unwrap();
        }
        let before = raw(h.mesh());
        let applied = h.applied();
        assert!(matches!(h.split_next(), Err(Error::InvalidArgument(_))));
        assert!(matches!(h.go_to_level(0), Err(Error::InvalidArgument(_))));
        assert!(matches!(h.seek(0), Err(Error::InvalidArgument(_))));
        assert!(raw(h.mesh()) == before);
        assert_eq!(h.applied(), applied);
    }
    h.detach_labels();
    h.refine_to(0).unwrap();
    h.mesh().check().unwrap();
}

#[test]
fn a_hierarchy_refuses_cleanly_after_split_edge_behind_its_back() {
    // Every edge of the coarsest mesh in turn.
    let built = Hierarchy::build(
        generators::icosphere(2),
        &HierarchyOptions::rounds().with_target_faces(60),
    )
    .unwrap();
    let edges: Vec<HalfedgeId> = built.mesh().edges().collect();
    let mut refused = 0;
    for e in edges {
        let mut h = built.clone();
        let mesh = h.mesh_mut();
        let p = 0.5 * (mesh.position(mesh.from_vertex(e)) + mesh.position(mesh.to_vertex(e)));
        mesh.split_edge(e, p).unwrap();
        loop {
            let before = raw(h.mesh());
            match h.split_next() {
                Ok(true) => h.mesh().check().unwrap(),
                Ok(false) => break,
                Err(err) => {
                    assert!(matches!(err, Error::SplitRefused(_)), "{err}");
                    assert!(raw(h.mesh()) == before);
                    refused += 1;
                    break;
                }
            }
        }
        h.mesh().check().unwrap();
    }
    assert!(refused > 0);
}

#[test]
fn a_hierarchy_of_non_finite_positions_is_refused() {
    let mut mesh = generators::icosphere(1);
    let v = mesh.vertices().nth(4).unwrap();
    mesh.set_position(v, DVec3::new(0.0, f64::NAN, 0.0));
    let e = Hierarchy::build(mesh, &HierarchyOptions::rounds()).unwrap_err();
    assert!(
        matches!(e, Error::NonFiniteCoordinate { vertex: 4, .. }),
        "{e}"
    );
}

/// Coordinates near the largest `f64`: a midpoint or a quadric's optimum of two of them
/// overflows, and such a collapse is refused; every level keeps finite positions (the
/// hierarchy machine found a QEM build that did not).
#[test]
fn huge_coordinates_never_give_an_overflowed_placement() {
    for options in [HierarchyOptions::rounds(), HierarchyOptions::qem()] {
        let mut mesh = generators::icosphere(2);
        for p in mesh.positions_mut() {
            *p *= 1.5e308;
        }
        let mut h = Hierarchy::build(mesh, &options.with_target_faces(20)).unwrap();
        for level in (0..h.n_levels()).rev() {
            h.go_to_level(level).unwrap();
            assert!(live_positions_finite(h.mesh()), "level {level}");
            h.mesh().check().unwrap();
        }
    }
}
