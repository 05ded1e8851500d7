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

use crate::collapse::CollapseRecord;
use crate::error::Error;
use crate::generators;
use crate::handle::Slots;
use crate::handle::{FaceId, HalfedgeId, VertexId};
use crate::mesh::HalfedgeRec;
use crate::mesh::Mesh;

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
    binding: crate::binding::Binding,
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
            (
                "later collapse still waits",
                "split refused: a later collapse waits",
            ),
            (
                "earlier collapse",
                "split refused: an earlier collapse of the edge",
            ),
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

mod cases;
mod hierarchy;
