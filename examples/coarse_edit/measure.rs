//! The measurement behind the `coarse_edit` example (and its tests): one edit made at a
//! coarse level of a [`Hierarchy`] and refined back, against the same edit made directly
//! on the full-resolution mesh. See the example's module docs for the region rule and
//! the reported fields.

#![allow(dead_code)] // shared with tests/coarse_edit.rs; each uses part of it

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::fmt;
use std::time::Instant;

use edit::bendels_klein::{BlendOptions, BlendSession, Regions};
use edit::deform::{
    AttachOptions, Axis, BSplineSurface, DeformError, Ffd, LatticeFrame, Propagation, SubMesh,
    SubmeshEdit, Variation,
};
use edit::lee::{
    AreaSession, EditingArea, EmbeddingOptions, EmbeddingWeights, LeeError, SessionOptions,
};
use edit::{HierarchyEdit, HierarchyMarks, Vertices};
use glam::{DAffine3, DMat3, DQuat, DVec3};
use halfedge::hierarchy::{DetailMode, Hierarchy, HierarchyOptions, Method};
use halfedge::{Mesh, VertexData, VertexId};

/// The edits the example measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EditKind {
    /// Sub-mesh rotation about an axis across the region (n = 0): rigid.
    Rotate,
    /// Sub-mesh Barr twist about the region's axis, strength along the axis.
    Twist,
    /// Sub-mesh Barr taper about the region's axis, strength along the axis.
    Taper,
    /// Sub-mesh scaling about the frontier's centroid (n = 0), re-seated: affine.
    Scale,
    /// Sub-mesh pull along the region's axis (n = 0): a translation.
    Pull,
    /// Lee 1999 area drag of the tip.
    Lee,
    /// Bendels & Klein handle rotation and lift.
    Bk,
    /// Shape/height-surface FFD bend.
    Ffd,
}

impl EditKind {
    /// Every edit, in the order the example lists them.
    pub const ALL: [EditKind; 8] = [
        EditKind::Rotate,
        EditKind::Twist,
        EditKind::Taper,
        EditKind::Scale,
        EditKind::Pull,
        EditKind::Lee,
        EditKind::Bk,
        EditKind::Ffd,
    ];

    /// The name on the command line and in the JSON.
    pub fn name(self) -> &'static str {
        match self {
            EditKind::Rotate => "rotate",
            EditKind::Twist => "twist",
            EditKind::Taper => "taper",
            EditKind::Scale => "scale",
            EditKind::Pull => "pull",
            EditKind::Lee => "lee",
            EditKind::Bk => "bk",
            EditKind::Ffd => "ffd",
        }
    }
}

/// What went wrong, and which option to change.
#[derive(Debug)]
pub struct Failure {
    /// What went wrong.
    pub message: String,
    /// What to try instead (a flag to change).
    pub hint: String,
}

impl Failure {
    fn new(message: impl Into<String>, hint: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            hint: hint.into(),
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}\nhint: {}", self.message, self.hint)
    }
}

impl std::error::Error for Failure {}

/// A library error, with the hint for this step.
fn lib<E: fmt::Display>(hint: &'static str) -> impl Fn(E) -> Failure {
    move |e| Failure::new(e.to_string(), hint)
}

/// Region and strength options.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// The edit.
    pub edit: EditKind,
    /// An input vertex (file index) whose ancestor at the edited level is the tip;
    /// `None`: the rule of the module docs.
    pub seed_vertex: Option<usize>,
    /// Fraction of the component's coarse vertices in the region (default 0.2).
    pub region_fraction: f64,
    /// Multiplies every magnitude of the edit (angles, offsets, log factors); 1 by
    /// default.
    pub amount: f64,
}

impl Options {
    /// The default region and strength for `edit`.
    pub fn new(edit: EditKind) -> Self {
        Self {
            edit,
            seed_vertex: None,
            region_fraction: 0.2,
            amount: 1.0,
        }
    }
}

/// The input, its hierarchy at the edited level, and the ancestor map.
#[derive(Clone)]
pub struct Prepared {
    /// The input mesh (level 0).
    pub input: Mesh,
    /// The hierarchy, at `level`.
    pub hierarchy: Hierarchy,
    /// The edited level.
    pub level: usize,
    /// Ancestor at `level` of every input vertex slot.
    pub ancestors: Vec<u32>,
    /// The input's bounding-box diagonal.
    pub diagonal: f64,
    /// Seconds to build the hierarchy and go to `level`.
    pub build_seconds: f64,
}

/// Builds the hierarchy of `input` down to `level` with `method` and `detail`.
pub fn prepare(
    input: Mesh,
    method: Method,
    detail: DetailMode,
    level: usize,
) -> Result<Prepared, Failure> {
    if level == 0 {
        return Err(Failure::new(
            "--level 0 is the input itself: there is no coarse level to edit",
            "pass --level 1 or more (2 to 4 are typical)",
        ));
    }
    let (lo, hi) = input
        .bounding_box()
        .ok_or_else(|| Failure::new("the mesh has no vertices", "pass a mesh file with faces"))?;
    let diagonal = (hi - lo).length();
    if !(diagonal > 0.0 && diagonal.is_finite()) {
        return Err(Failure::new(
            format!("the mesh's bounding-box diagonal is {diagonal}"),
            "pass a mesh with finite, distinct vertex positions",
        ));
    }
    let options = match method {
        Method::Rounds => HierarchyOptions::rounds(),
        Method::Qem => HierarchyOptions::qem(),
    }
    .with_max_levels(level)
    .with_detail_mode(detail);
    let clock = Instant::now();
    let mut hierarchy = Hierarchy::build(input.clone(), &options)
        .map_err(lib("check the mesh with the topology example"))?;
    if hierarchy.coarsest_level() < level {
        return Err(Failure::new(
            format!(
                "the hierarchy of this mesh stops at level {} ({:?} faces per level)",
                hierarchy.coarsest_level(),
                hierarchy.level_face_counts()
            ),
            format!(
                "pass --level {} or less, or try the other --method",
                hierarchy.coarsest_level().max(1)
            ),
        ));
    }
    hierarchy
        .go_to_level(level)
        .map_err(lib("this is a bug of the hierarchy; report it"))?;
    let build_seconds = clock.elapsed().as_secs_f64();
    let ancestors = hierarchy
        .ancestors(level)
        .map_err(lib("this is a bug of the hierarchy; report it"))?;
    Ok(Prepared {
        input,
        hierarchy,
        level,
        ancestors,
        diagonal,
        build_seconds,
    })
}

/// What one measurement found (see the example's module docs for each field).
#[derive(Clone, Debug)]
pub struct Report {
    /// The edit.
    pub edit: EditKind,
    /// The edited level.
    pub level: usize,
    /// Simplification method.
    pub method: Method,
    /// Detail mode.
    pub detail: DetailMode,
    /// Input face count.
    pub faces: usize,
    /// Face count at the edited level.
    pub level_faces: usize,
    /// The tip (a vertex index, live at the edited level and at level 0).
    pub tip: usize,
    /// Vertices of the region at the edited level and at level 0 (the edit's own
    /// region: sub-mesh, Lee area interior, B&K handle ∪ deformable, FFD attached).
    pub region_vertices: [usize; 2],
    /// Faces flipped against the input by the coarse edit refined back.
    pub flips_coarse_path: usize,
    /// Faces flipped against the input by the same edit made at full resolution.
    pub flips_full_res: usize,
    /// Fine vertices outside the edit's coarse region that moved at all.
    pub outside_moved: usize,
    /// Largest distance of a rigidly or affinely moved fine vertex from its target,
    /// divided by the diagonal; `None` without a rigid part.
    pub handle_error: Option<f64>,
    /// Fine vertices measured by `handle_error`.
    pub handle_vertices: usize,
    /// RMS distance between the two results over all vertices, divided by the diagonal.
    pub rms_vs_full_res: f64,
    /// Largest distance between the two results, divided by the diagonal.
    pub max_vs_full_res: f64,
    /// Seconds to refine the edited hierarchy back to level 0.
    pub refine_seconds: f64,
    /// Seconds to build the hierarchy (from [`Prepared`]).
    pub build_seconds: f64,
    /// Affine marks given to the hierarchy (0 in translation mode).
    pub marks: usize,
    /// The factor the edit's magnitudes were multiplied by (the `--amount`, halved while
    /// a smooth edit turned a face of the coarse mesh over).
    pub amount: f64,
    /// Faces of the coarse mesh the coarse edit turned over.
    pub coarse_flips: usize,
    /// Input vertices that moved at all: refined back from the coarse edit, and edited at
    /// full resolution.
    pub moved: [usize; 2],
}

impl Report {
    /// True when the four targets of the example hold: nothing outside moved, the rigid
    /// parts landed within 1e-9 of the diagonal, no more flips than at full resolution,
    /// and the RMS distance to the full-resolution edit is at most 1 % of the diagonal.
    pub fn meets_targets(&self) -> bool {
        self.region_is_exact() && self.handles_land() && self.no_extra_flips() && self.is_close()
    }

    /// `outside_moved` = 0.
    pub fn region_is_exact(&self) -> bool {
        self.outside_moved == 0
    }

    /// `handle_error` ≤ 1e-9 (or no rigid part).
    pub fn handles_land(&self) -> bool {
        self.handle_error.is_none_or(|e| e <= 1e-9)
    }

    /// `flips_coarse_path` ≤ `flips_full_res`.
    pub fn no_extra_flips(&self) -> bool {
        self.flips_coarse_path <= self.flips_full_res
    }

    /// `rms_vs_full_res` ≤ 0.01.
    pub fn is_close(&self) -> bool {
        self.rms_vs_full_res <= 0.01
    }

    /// The JSON object the example prints.
    pub fn to_json(&self, mesh: &str) -> serde_json::Value {
        serde_json::json!({
            "mesh": mesh,
            "edit": self.edit.name(),
            "level": self.level,
            "method": match self.method { Method::Rounds => "rounds", Method::Qem => "qem" },
            "detail": match self.detail {
                DetailMode::LocalFrame => "local",
                DetailMode::Translation => "translation",
            },
            "faces": self.faces,
            "level_faces": self.level_faces,
            "tip": self.tip,
            "region_vertices_coarse": self.region_vertices[0],
            "region_vertices_fine": self.region_vertices[1],
            "flips_coarse_path": self.flips_coarse_path,
            "flips_full_res": self.flips_full_res,
            "outside_moved": self.outside_moved,
            "handle_error": self.handle_error,
            "handle_vertices": self.handle_vertices,
            "rms_vs_full_res": self.rms_vs_full_res,
            "max_vs_full_res": self.max_vs_full_res,
            "refine_seconds": self.refine_seconds,
            "build_seconds": self.build_seconds,
            "marks": self.marks,
            "amount": self.amount,
            "coarse_flips": self.coarse_flips,
            "moved_coarse_path": self.moved[0],
            "moved_full_res": self.moved[1],
            "meets_targets": self.meets_targets(),
        })
    }
}

/// The region rule's result at the edited level.
struct Region {
    /// The tip's vertex index.
    tip: usize,
    /// How many rings from the mesh boundary the rule asked the tip to be.
    tip_depth: u32,
    /// Vertex indices of the tip's component by increasing edge-path distance from the
    /// tip (ties by index), with the distances.
    order: Vec<(u32, f64)>,
}

impl Region {
    /// The first `fraction` of the component (at least `min`, at most all but one
    /// vertex) as a mask over vertex slots, and the distance of its farthest vertex.
    fn ball(&self, slots: usize, fraction: f64, min: usize) -> Result<(Vec<bool>, f64), Failure> {
        let n = self.order.len();
        let count = ((fraction * n as f64).round() as usize)
            .max(min)
            .min(n.saturating_sub(1));
        if count < min {
            return Err(Failure::new(
                format!(
                    "the tip's component has only {n} vertices at this level: too few for a region of {min}"
                ),
                "pass a finer --level, or a --seed-vertex on a larger component",
            ));
        }
        let mut mask = vec![false; slots];
        for &(i, _) in &self.order[..count] {
            mask[i as usize] = true;
        }
        Ok((mask, self.order[count - 1].1))
    }
}

/// Ring distance of every vertex slot from the mesh boundary (`u32::MAX` on closed
/// components and for removed slots).
fn boundary_depth(mesh: &Mesh) -> Vec<u32> {
    let mut depth = vec![u32::MAX; mesh.vertex_slots()];
    let mut queue = std::collections::VecDeque::new();
    for v in mesh.vertices() {
        if mesh.is_boundary_vertex(v) && !mesh.is_isolated(v) {
            depth[mesh.vertex_index(v)] = 0;
            queue.push_back(v);
        }
    }
    while let Some(v) = queue.pop_front() {
        let next = depth[mesh.vertex_index(v)] + 1;
        for w in mesh.adjacent_vertices(v) {
            let d = &mut depth[mesh.vertex_index(w)];
            if *d == u32::MAX {
                *d = next;
                queue.push_back(w);
            }
        }
    }
    depth
}

/// How many times a smooth edit's magnitudes are halved at most while it turns a face
/// of the coarse mesh over.
const MAX_HALVINGS: usize = 4;

/// How many rings from the mesh boundary a tip should be, at most (see the docs).
const TIP_DEPTH: u32 = 3;

/// Why a twist or taper refuses a region (see the docs; the rule then tries a tip on
/// the boundary).
const FLAT_REGION: &str = "the region is flat: it does not reach beyond its frontier along the axis towards its tip nor along its frontier's normal, so a twist or taper along it moves nothing";

/// The region rule (see the example's module docs), with tips at least `tip_depth`
/// rings from the mesh boundary where there are such vertices.
fn choose_region(
    mesh: &Mesh,
    ancestors: &[u32],
    seed: Option<usize>,
    tip_depth: u32,
) -> Result<Region, Failure> {
    let (component, _) = mesh.connected_components();
    let tip = match seed {
        Some(s) => {
            let a = *ancestors.get(s).ok_or_else(|| {
                Failure::new(
                    format!(
                        "--seed-vertex {s} is not a vertex of the mesh ({} vertex slots)",
                        ancestors.len()
                    ),
                    "pass a vertex index below the mesh's vertex count",
                )
            })? as usize;
            match mesh.vertex_at(a) {
                Some(v) if !mesh.is_isolated(v) => a,
                _ => {
                    return Err(Failure::new(
                        format!("--seed-vertex {s} is not a vertex of any face"),
                        "pass the index of a vertex on the surface",
                    ))
                }
            }
        }
        None => {
            // the largest component (ties: the first found)
            let mut size = std::collections::HashMap::<usize, usize>::new();
            let mut first = Vec::new();
            for v in mesh.vertices().filter(|&v| !mesh.is_isolated(v)) {
                let c = component[mesh.vertex_index(v)];
                let s = size.entry(c).or_insert(0);
                if *s == 0 {
                    first.push(c);
                }
                *s += 1;
            }
            let largest = first
                .iter()
                .copied()
                .max_by(|a, b| size[a].cmp(&size[b]).then(b.cmp(a)))
                .ok_or_else(|| Failure::new("the mesh has no faces", "pass a mesh with faces"))?;
            let members: Vec<VertexId> = mesh
                .vertices()
                .filter(|&v| component[mesh.vertex_index(v)] == largest)
                .collect();
            let centroid =
                members.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / members.len() as f64;
            let depth = boundary_depth(mesh);
            let mut best: Option<(u32, f64, usize)> = None;
            for &v in &members {
                let i = mesh.vertex_index(v);
                let key = (depth[i].min(tip_depth), mesh.position(v).distance(centroid));
                if best.is_none_or(|(d, r, _)| key.0 > d || (key.0 == d && key.1 > r)) {
                    best = Some((key.0, key.1, i));
                }
            }
            best.map(|b| b.2)
                .ok_or_else(|| Failure::new("the mesh has no faces", "pass a mesh with faces"))?
        }
    };
    // Dijkstra over edge lengths from the tip, ties by index
    let positions = mesh.positions();
    let mut distance = vec![f64::INFINITY; mesh.vertex_slots()];
    let mut done = vec![false; mesh.vertex_slots()];
    let mut heap = BinaryHeap::new();
    distance[tip] = 0.0;
    heap.push(Reverse((Ordered(0.0), tip as u32)));
    let mut order = Vec::new();
    while let Some(Reverse((Ordered(d), i))) = heap.pop() {
        if std::mem::replace(&mut done[i as usize], true) {
            continue;
        }
        order.push((i, d));
        let Some(v) = mesh.vertex_at(i as usize) else {
            continue;
        };
        for w in mesh.adjacent_vertices(v) {
            let j = mesh.vertex_index(w);
            let e = d + positions[i as usize].distance(positions[j]);
            if !done[j] && e < distance[j] {
                distance[j] = e;
                heap.push(Reverse((Ordered(e), j as u32)));
            }
        }
    }
    Ok(Region {
        tip,
        tip_depth,
        order,
    })
}

/// A totally ordered `f64` for the Dijkstra heap.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Ordered(f64);
impl Eq for Ordered {}
impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The fine mask of a coarse mask: the live input vertices whose ancestor is in it.
fn fine_mask(input: &Mesh, ancestors: &[u32], coarse: &[bool]) -> Vec<bool> {
    let mut mask = vec![false; input.vertex_slots()];
    for v in input.vertices() {
        let i = input.vertex_index(v);
        mask[i] = coarse[ancestors[i] as usize];
    }
    mask
}

/// The live vertices of a mask.
fn listed(mesh: &Mesh, mask: &[bool]) -> Vec<VertexId> {
    mesh.vertices()
        .filter(|&v| mask[mesh.vertex_index(v)])
        .collect()
}

/// A unit vector perpendicular to `d`, towards `w` where `w` is well away from `d`.
fn perpendicular(d: DVec3, w: DVec3) -> DVec3 {
    let p = w - w.dot(d) * d;
    if p.length() > 0.3 * w.length() {
        p.normalize()
    } else {
        d.any_orthonormal_vector()
    }
}

/// The normalised sum of the vertex normals of the masked vertices (zero if they cancel).
fn mean_normal(mesh: &Mesh, mask: &[bool]) -> DVec3 {
    mesh.vertices()
        .filter(|&v| mask[mesh.vertex_index(v)])
        .map(|v| mesh.vertex_normal(v))
        .sum::<DVec3>()
        .normalize_or_zero()
}

/// A part of the coarse edit moved by one affine map: the coarse vertex indices and
/// the map.
struct Rigid {
    vertices: Vec<u32>,
    map: DAffine3,
}

/// What an edit did at both levels.
struct Applied {
    /// Coarse vertices the method may move.
    movable: Vec<bool>,
    /// Fine vertices the full-resolution edit acted on (for the report).
    fine_region: usize,
    /// Rigid or affine parts of the coarse edit.
    rigid: Vec<Rigid>,
    /// What the library's method tells the hierarchy about the edit, where it says it
    /// (sub-mesh edits: `SubMesh::apply_with_marks`); `None`: the example marks `rigid`
    /// and `movable` itself.
    marks: Option<HierarchyMarks>,
}

/// Checks that `map` takes every listed vertex from `before` to `after` (to 1e-12 of
/// the diagonal, plus the rounding of coordinates far from the origin: a mesh placed
/// 10⁷ units away, as georeferenced scans are, rounds its positions to about 10⁻⁹): the
/// affine part found from the edit's parameters is the one the library applied.
fn verify(rigid: &Rigid, before: &[DVec3], after: &[DVec3], diagonal: f64) -> Result<(), Failure> {
    for &i in &rigid.vertices {
        let i = i as usize;
        let target = rigid.map.transform_point3(before[i]);
        let off = (target - after[i]).length();
        let magnitude = before[i]
            .abs()
            .max(after[i].abs())
            .max(target.abs())
            .max_element();
        if off > 1e-12 * diagonal + 64.0 * f64::EPSILON * magnitude {
            return Err(Failure::new(
                format!(
                    "vertex {i} was not moved by the edit's affine map (off by {:.3e} of the diagonal)",
                    off / diagonal
                ),
                "this is a bug of the example or the edit; report it with the command line",
            ));
        }
    }
    Ok(())
}

/// A measurement and the two meshes it compared.
pub struct Measured {
    /// The numbers.
    pub report: Report,
    /// (a): edited at the coarse level and refined back.
    pub coarse_path: Mesh,
    /// (b): edited at full resolution.
    pub full_res: Mesh,
}

/// Measures `options.edit` on `prepared` (see the example's module docs).
pub fn measure(prepared: &Prepared, options: &Options) -> Result<Measured, Failure> {
    let f = options.region_fraction;
    if !(f > 0.0 && f < 0.8) {
        return Err(Failure::new(
            format!("--region-fraction {f} is outside (0, 0.8)"),
            "pass a fraction such as 0.2 (B&K's fixed area starts at 1.25 times it)",
        ));
    }
    if !(options.amount > 0.0 && options.amount.is_finite()) {
        return Err(Failure::new(
            format!("--amount {} is not a positive number", options.amount),
            "pass --amount 1 (the default strength) or a fraction of it",
        ));
    }
    let mut hierarchy = prepared.hierarchy.clone();
    let input = &prepared.input;
    let diagonal = prepared.diagonal;
    let mut region = choose_region(
        hierarchy.mesh(),
        &prepared.ancestors,
        options.seed_vertex,
        TIP_DEPTH,
    )?;
    let before: Vec<DVec3> = hierarchy.mesh().positions().to_vec();
    let level_faces = hierarchy.mesh().n_faces();
    // a smooth edit that turns a face of the coarse mesh over is too strong for it: halve
    let mut amount = options.amount;
    if !matches!(
        options.edit,
        EditKind::Rotate | EditKind::Scale | EditKind::Pull
    ) {
        let mut halvings = 0;
        while halvings < MAX_HALVINGS {
            let mut trial = hierarchy.mesh().clone();
            match apply(&mut trial, None, prepared, &region, options, amount) {
                // a region enclosed by its frontier (a flat or open mesh's inside) has
                // nothing to twist: the tip may then be on the boundary, where a flat
                // mesh protrudes (once, and only for the rule's own tip)
                Err(e)
                    if e.message == FLAT_REGION
                        && options.seed_vertex.is_none()
                        && region.tip_depth > 0 =>
                {
                    region = choose_region(hierarchy.mesh(), &prepared.ancestors, None, 0)?;
                    continue;
                }
                result => {
                    result?;
                }
            }
            if flips(hierarchy.mesh(), &trial) == 0 {
                break;
            }
            amount *= 0.5;
            halvings += 1;
        }
    }
    let mut fine = input.clone();
    let applied = apply(
        hierarchy.mesh_mut(),
        Some(&mut fine),
        prepared,
        &region,
        options,
        amount,
    )?;
    let coarse_flips = {
        let mut original = hierarchy.mesh().clone();
        original.positions_mut().copy_from_slice(&before);
        flips(&original, hierarchy.mesh())
    };
    hierarchy.mesh().check().map_err(lib(
        "this is a bug of the edit; report it with the command line",
    ))?;
    for rigid in &applied.rigid {
        verify(rigid, &before, hierarchy.mesh().positions(), diagonal)?;
    }
    let mut marks = 0;
    if let (DetailMode::LocalFrame, Some(given)) = (hierarchy.detail_mode(), &applied.marks) {
        // The library's own marks of the edit (region, affine parts, fields).
        given
            .mark(&mut hierarchy)
            .map_err(lib("this is a bug of the library; report it"))?;
        marks = given.affine_parts().len() + given.field_parts().len();
    } else if hierarchy.detail_mode() == DetailMode::LocalFrame {
        for rigid in applied.rigid.iter().filter(|r| !r.vertices.is_empty()) {
            let list: Vec<VertexId> = rigid
                .vertices
                .iter()
                .filter_map(|&i| hierarchy.mesh().vertex_at(i as usize))
                .collect();
            hierarchy
                .mark_affine(&list, rigid.map)
                .map_err(lib("this is a bug of the example; report it"))?;
            marks += 1;
        }
        // The edit's region: its finer vertices follow the motion of their neighbourhood
        // (the edit's own transition), everything else stays exactly where it was.
        let region: Vec<VertexId> = applied
            .movable
            .iter()
            .enumerate()
            .filter(|&(_, &m)| m)
            .filter_map(|(i, _)| hierarchy.mesh().vertex_at(i))
            .collect();
        hierarchy
            .mark_region(&region)
            .map_err(lib("this is a bug of the example; report it"))?;
    }
    let clock = Instant::now();
    hierarchy.refine_to(0).map_err(lib(
        "this is a bug of the hierarchy; report it with the command line",
    ))?;
    let refine_seconds = clock.elapsed().as_secs_f64();
    let coarse_path = hierarchy.into_mesh();

    // measurements
    let ancestors = &prepared.ancestors;
    let (a, b, p) = (coarse_path.positions(), fine.positions(), input.positions());
    let mut outside_moved = 0;
    let mut moved = [0, 0];
    let mut squared = 0.0;
    let mut largest: f64 = 0.0;
    let mut count = 0usize;
    for v in input.vertices() {
        let i = input.vertex_index(v);
        if !applied.movable[ancestors[i] as usize]
            && a[i].to_array().map(f64::to_bits) != p[i].to_array().map(f64::to_bits)
        {
            outside_moved += 1;
        }
        moved[0] += usize::from(a[i] != p[i]);
        moved[1] += usize::from(b[i] != p[i]);
        let d = a[i].distance(b[i]);
        squared += d * d;
        largest = largest.max(d);
        count += 1;
    }
    let mut handle_error: Option<f64> = None;
    let mut handle_vertices = 0;
    if applied.rigid.iter().any(|r| !r.vertices.is_empty()) {
        let mut part = vec![u32::MAX; input.vertex_slots()];
        for (k, rigid) in applied.rigid.iter().enumerate() {
            for &i in &rigid.vertices {
                part[i as usize] = k as u32;
            }
        }
        let mut worst: f64 = 0.0;
        for v in input.vertices() {
            let i = input.vertex_index(v);
            let k = part[ancestors[i] as usize];
            if k != u32::MAX {
                let target = applied.rigid[k as usize].map.transform_point3(p[i]);
                worst = worst.max(a[i].distance(target) / diagonal);
                handle_vertices += 1;
            }
        }
        handle_error = Some(worst);
    }
    let movable_coarse = applied.movable.iter().filter(|&&m| m).count();
    let report = Report {
        edit: options.edit,
        level: prepared.level,
        method: prepared.hierarchy.method(),
        detail: prepared.hierarchy.detail_mode(),
        faces: input.n_faces(),
        level_faces,
        tip: region.tip,
        region_vertices: [movable_coarse, applied.fine_region],
        flips_coarse_path: flips(input, &coarse_path),
        flips_full_res: flips(input, &fine),
        outside_moved,
        handle_error,
        handle_vertices,
        rms_vs_full_res: (squared / count.max(1) as f64).sqrt() / diagonal,
        max_vs_full_res: largest / diagonal,
        refine_seconds,
        build_seconds: prepared.build_seconds,
        marks,
        amount,
        coarse_flips,
        moved,
    };
    Ok(Measured {
        report,
        coarse_path,
        full_res: fine,
    })
}

/// Faces of `after` whose normal points against their normal in `input`.
fn flips(input: &Mesh, after: &Mesh) -> usize {
    let normal = |m: &Mesh, f| {
        let [x, y, z] = m.triangle(f).map(|v| m.position(v));
        (y - x).cross(z - x)
    };
    input
        .faces()
        .filter(|&f| normal(input, f).dot(normal(after, f)) < 0.0)
        .count()
}

/// Applies the edit with magnitude factor `amount` at the coarse level and, given the
/// input's copy `fine`, at full resolution.
fn apply(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    prepared: &Prepared,
    region: &Region,
    options: &Options,
    amount: f64,
) -> Result<Applied, Failure> {
    let slots = coarse.vertex_slots();
    let f = options.region_fraction;
    let ancestors = &prepared.ancestors;
    match options.edit {
        EditKind::Rotate | EditKind::Twist | EditKind::Taper | EditKind::Scale | EditKind::Pull => {
            let (mask, radius) = region.ball(slots, f, 4)?;
            submesh_edit(
                coarse,
                fine,
                ancestors,
                region.tip,
                &mask,
                radius,
                options.edit,
                amount,
            )
        }
        EditKind::Lee => lee_edit(coarse, fine, ancestors, region, f, amount),
        EditKind::Bk => {
            let (handle, _) = region.ball(slots, 0.15 * f, 1)?;
            let (ball, radius) = region.ball(slots, 1.25 * f, 4)?;
            bk_edit(coarse, fine, ancestors, &handle, &ball, radius, amount)
        }
        EditKind::Ffd => {
            let (mask, _) = region.ball(slots, f, 4)?;
            let (ball, _) = region.ball(slots, 2.0 * f, 4)?;
            ffd_edit(coarse, fine, ancestors, region.tip, &mask, &ball, amount)
        }
    }
}

/// Sub-mesh edits with no propagation (the paper's §4.3), at both levels.
#[allow(clippy::too_many_arguments)]
fn submesh_edit(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    ancestors: &[u32],
    tip: usize,
    mask: &[bool],
    radius: f64,
    kind: EditKind,
    amount: f64,
) -> Result<Applied, Failure> {
    let hint = "pass another --region-fraction or --seed-vertex";
    let mask = VertexData::new(coarse, mask.to_vec()).map_err(lib(hint))?;
    let sub = SubMesh::from_mask(coarse, &mask).map_err(lib(hint))?;
    let positions = coarse.positions();
    let frontier = sub.frontier_indices();
    if frontier.is_empty() {
        return Err(Failure::new(
            "the region covers its whole component: it has no frontier",
            "pass a smaller --region-fraction",
        ));
    }
    let centre = frontier
        .iter()
        .map(|&i| positions[i as usize])
        .sum::<DVec3>()
        / frontier.len() as f64;
    let towards_tip = positions[tip] - centre;
    let length = towards_tip.length();
    if length.is_nan() || length <= 1e-6 * radius {
        return Err(Failure::new(
            "the region's tip is at the centroid of its frontier: the region has no axis",
            hint,
        ));
    }
    let d = towards_tip.normalize();
    let axis_along = Axis::new(centre, d).map_err(lib(hint))?;
    let inside: Vec<u32> = sub.vertex_indices().to_vec();
    let (edit, rigid_part, map) = match kind {
        EditKind::Pull => {
            let offset = 0.3 * amount * radius * d;
            (
                SubmeshEdit::Pull { offset },
                inside.clone(),
                DAffine3::from_translation(offset),
            )
        }
        EditKind::Rotate => {
            let across = d.cross(perpendicular(d, mean_normal(coarse, &mask)));
            let angle = 30f64.to_radians() * amount;
            let axis = Axis::new(centre, across).map_err(lib(hint))?;
            let map = DAffine3::from_translation(centre)
                * DAffine3::from_quat(DQuat::from_axis_angle(axis.direction(), angle))
                * DAffine3::from_translation(-centre);
            (
                SubmeshEdit::Rotate {
                    axis,
                    angle,
                    bounded: false,
                },
                inside.clone(),
                map,
            )
        }
        EditKind::Scale => {
            let factor = 0.8f64.powf(amount);
            // the re-seating translation is the library's: measured below
            (
                SubmeshEdit::Scale { centre, factor },
                inside.clone(),
                DAffine3::from_translation(centre)
                    * DAffine3::from_mat3(DMat3::from_diagonal(DVec3::splat(factor)))
                    * DAffine3::from_translation(-centre),
            )
        }
        EditKind::Twist | EditKind::Taper => {
            // the axis along which the region reaches farthest beyond its frontier: the
            // one towards the tip or the frontier plane's normal
            let extent = |axis: &Axis| {
                let start = frontier
                    .iter()
                    .map(|&i| axis.coordinate(positions[i as usize]))
                    .fold(f64::NEG_INFINITY, f64::max);
                let top = inside
                    .iter()
                    .map(|&i| axis.coordinate(positions[i as usize]))
                    .fold(f64::NEG_INFINITY, f64::max);
                (start, top)
            };
            let (axis_along, (start, top)) = [Some(axis_along), sub.axis(coarse).ok()]
                .into_iter()
                .flatten()
                .map(|a| (a, extent(&a)))
                .max_by(|x, y| (x.1 .1 - x.1 .0).total_cmp(&(y.1 .1 - y.1 .0)))
                .unwrap_or((axis_along, extent(&axis_along)));
            let reach = top - start;
            if reach.is_nan() || reach <= 0.05 * radius {
                return Err(Failure::new(
                    FLAT_REGION,
                    "pass a --seed-vertex on a protruding part, or another --region-fraction",
                ));
            }
            let (centre, d) = (axis_along.point(), axis_along.direction());
            let end = start + 0.7 * (top - start);
            let variation = Variation::Along { start, end };
            // The rigid end: the coarse vertices beyond the ramp whose whole cluster of
            // fine vertices is beyond it too (a cluster reaching down the ramp would
            // take the full map where the full-resolution edit gives less).
            let mut lowest = vec![f64::INFINITY; positions.len()];
            if let Some(fine) = fine.as_deref() {
                for v in fine.vertices() {
                    let i = fine.vertex_index(v);
                    let a = ancestors[i] as usize;
                    let s = axis_along.coordinate(fine.positions()[i]);
                    lowest[a] = lowest[a].min(s);
                }
            }
            let rigid: Vec<u32> = inside
                .iter()
                .copied()
                .filter(|&i| {
                    axis_along.coordinate(positions[i as usize]) >= end && lowest[i as usize] >= end
                })
                .collect();
            let to_axis = DAffine3::from_translation(-centre);
            let from_axis = DAffine3::from_translation(centre);
            if kind == EditKind::Twist {
                let angle = 60f64.to_radians() * amount;
                let map =
                    from_axis * DAffine3::from_quat(DQuat::from_axis_angle(d, angle)) * to_axis;
                (
                    SubmeshEdit::Twist {
                        axis: Some(axis_along),
                        angle,
                        variation,
                    },
                    rigid,
                    map,
                )
            } else {
                let factor = 0.6f64.powf(amount);
                // q ↦ (q·d) d + factor (q − (q·d) d)
                let linear =
                    DMat3::from_diagonal(DVec3::splat(factor)) + (1.0 - factor) * outer(d, d);
                let map = from_axis * DAffine3::from_mat3(linear) * to_axis;
                (
                    SubmeshEdit::Taper {
                        axis: Some(axis_along),
                        factor,
                        variation,
                    },
                    rigid,
                    map,
                )
            }
        }
        _ => unreachable!("submesh_edit is called for sub-mesh edits only"),
    };
    let before = coarse.positions().to_vec();
    let applied = sub
        .apply_with_marks(coarse, &edit, Propagation::NONE)
        .map_err(lib(hint))?;
    let marks = applied.hierarchy_marks(coarse).map_err(lib(hint))?;
    // The library re-seats a scaled sub-mesh by a translation fitted to its frontier:
    // the mean offset of the scaled vertices from the plain scale.
    let reseat = |list: &[u32], before: &[DVec3], after: &[DVec3]| {
        list.iter()
            .map(|&i| after[i as usize] - map.transform_point3(before[i as usize]))
            .sum::<DVec3>()
            / list.len() as f64
    };
    let coarse_shift = reseat(&inside, &before, coarse.positions());
    let mut fine_region = 0;
    if let Some(fine) = fine {
        let fine_mask =
            VertexData::new(fine, fine_mask(fine, ancestors, &mask)).map_err(lib(hint))?;
        let fine_sub = SubMesh::from_mask(fine, &fine_mask).map_err(lib(hint))?;
        let fine_before = fine.positions().to_vec();
        fine_sub
            .apply(fine, &edit, Propagation::NONE)
            .map_err(lib(hint))?;
        if kind == EditKind::Scale {
            // the same map at both resolutions: the coarse edit's re-seating (the fitted
            // frontier plane differs a little between resolutions)
            let fine_shift = reseat(fine_sub.vertex_indices(), &fine_before, fine.positions());
            let offset = coarse_shift - fine_shift;
            fine_sub
                .apply(fine, &SubmeshEdit::Pull { offset }, Propagation::NONE)
                .map_err(lib(hint))?;
        }
        fine_region = fine_sub.len();
    }
    let map = if kind == EditKind::Scale {
        DAffine3::from_translation(coarse_shift) * map
    } else {
        map
    };
    Ok(Applied {
        movable: sub.mask().to_vec(),
        fine_region,
        rigid: vec![Rigid {
            vertices: rigid_part,
            map,
        }],
        marks: Some(marks),
    })
}

/// The outer product `a bᵀ`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Lee 1999 area drag of the tip at both levels.
fn lee_edit(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    ancestors: &[u32],
    region: &Region,
    fraction: f64,
    amount: f64,
) -> Result<Applied, Failure> {
    let tip = region.tip;
    let tip_v = coarse
        .vertex_at(tip)
        .ok_or_else(|| Failure::new("the tip is not a live vertex", "report this bug"))?;
    // mean-value weights: the harmonic map of a coarse area with obtuse triangles can
    // fold (and put the tip outside the rectangle)
    let options = SessionOptions::default()
        .with_embedding(EmbeddingOptions::default().with_weights(EmbeddingWeights::MeanValue));
    let rest = coarse.position(tip_v);
    let normal = coarse.vertex_normal(tip_v);
    let normal = if normal == DVec3::ZERO {
        DVec3::Z
    } else {
        normal
    };
    // the largest disk (shrunk by a quarter at a time) that is accepted and whose
    // lattice reaches the tip: the tip lands on its target
    let mut size = ((fraction * region.order.len() as f64).round() as usize).max(7);
    let (area, session, drag) = loop {
        let attempt = EditingArea::from_faces(coarse, &disk_faces(coarse, region, size))
            .and_then(|area| {
                let mut session = AreaSession::new(coarse, area.clone(), &options)?;
                let reach = area
                    .boundary()
                    .iter()
                    .map(|&v| coarse.position(v).distance(rest))
                    .fold(0.0, f64::max);
                let drag = 0.3 * amount * reach * normal;
                session.set_primitive(coarse, &[tip_v])?;
                session.drag(coarse, drag)?;
                let miss = coarse.position(tip_v).distance(rest + drag) / drag.length();
                if miss > 1e-9 {
                    session.cancel(coarse)?;
                    return Err(LeeError::InvalidParameter {
                        name: "area",
                        reason: format!(
                            "its B-spline lattice does not reach the tip (the tip missed its target by {miss:.3e} of the drag)"
                        ),
                    });
                }
                Ok((area, session, drag))
            });
        match attempt {
            Ok(found) => break found,
            Err(e) if size <= 7 => {
                return Err(Failure::new(
                    format!("no Lee editing area around the tip (vertex {tip}) is accepted: {e}"),
                    "pass a --seed-vertex away from the mesh boundary and thin parts, or a finer --level",
                ))
            }
            Err(_) => size = size * 3 / 4,
        }
    };
    let hint = "pass another --seed-vertex or --region-fraction";
    coarse.set_position(tip_v, rest + drag);

    let slots = coarse.vertex_slots();
    let mut interior = vec![false; slots];
    for &v in area.interior() {
        interior[coarse.vertex_index(v)] = true;
    }
    let mut fine_region = 0;
    if let Some(fine) = fine {
        // the same area at full resolution (the input faces the hierarchy collapses
        // into it), with the same lattice (levels) and scale
        let fine_area =
            preimage_area(coarse, fine, ancestors, &area, &interior).map_err(lib(hint))?;
        let fine_options = options.with_levels(session.levels());
        fine_region = fine_area.n_interior();
        let mut fine_session =
            AreaSession::new(fine, fine_area, &fine_options).map_err(lib(hint))?;
        let primitive: Vec<VertexId> = fine
            .vertices()
            .filter(|&v| ancestors[fine.vertex_index(v)] as usize == tip)
            .collect();
        fine_session
            .set_primitive(fine, &primitive)
            .map_err(lib(hint))?;
        fine_session.drag(fine, drag).map_err(lib(hint))?;
    }
    Ok(Applied {
        movable: interior,
        fine_region,
        rigid: vec![Rigid {
            vertices: vec![tip as u32],
            map: DAffine3::from_translation(drag),
        }],
        marks: None,
    })
}

/// The faces of a disk around the tip: the first `size` vertices of the region order
/// (a ball by edge-path distance), the faces around those of them that are at least two
/// rings from the mesh boundary and whose neighbours are all in the ball, and the
/// pockets those faces enclose within the tip's component that do not reach the mesh
/// boundary (like `EditingArea::disk_around`, which grows rings instead and also fills
/// every other component of the mesh as a pocket).
fn disk_faces(mesh: &Mesh, region: &Region, size: usize) -> Vec<halfedge::FaceId> {
    let size = size.min(region.order.len());
    let depth = boundary_depth(mesh);
    let mut ball = vec![false; mesh.vertex_slots()];
    for &(i, _) in &region.order[..size] {
        ball[i as usize] = true;
    }
    let mut in_area = vec![false; mesh.face_slots()];
    for &(i, _) in &region.order[..size] {
        let Some(v) = mesh.vertex_at(i as usize) else {
            continue;
        };
        if depth[i as usize] >= 2
            && mesh
                .adjacent_vertices(v)
                .all(|w| ball[mesh.vertex_index(w)])
        {
            for f in mesh.adjacent_faces(v) {
                in_area[mesh.face_index(f)] = true;
            }
        }
    }
    let mut component = vec![false; mesh.face_slots()];
    for &(i, _) in &region.order {
        if let Some(v) = mesh.vertex_at(i as usize) {
            for f in mesh.adjacent_faces(v) {
                component[mesh.face_index(f)] = true;
            }
        }
    }
    fill_pockets(mesh, &mut in_area, &component);
    faces_of(mesh, &in_area)
}

/// The faces whose entry is true.
fn faces_of(mesh: &Mesh, in_area: &[bool]) -> Vec<halfedge::FaceId> {
    mesh.faces()
        .filter(|&f| in_area[mesh.face_index(f)])
        .collect()
}

/// Adds to `in_area` the pockets it encloses: the groups of other faces of `component`
/// (edge-connected), all but the largest, that do not reach the mesh boundary. Returns
/// true when a face was added.
fn fill_pockets(mesh: &Mesh, in_area: &mut [bool], component: &[bool]) -> bool {
    let mut group = vec![u32::MAX; mesh.face_slots()];
    let mut sizes: Vec<usize> = Vec::new();
    let mut open: Vec<bool> = Vec::new();
    for f in mesh.faces() {
        let fi = mesh.face_index(f);
        if !component[fi] || in_area[fi] || group[fi] != u32::MAX {
            continue;
        }
        let id = sizes.len() as u32;
        sizes.push(0);
        open.push(false);
        group[fi] = id;
        let mut stack = vec![f];
        while let Some(g) = stack.pop() {
            sizes[id as usize] += 1;
            open[id as usize] |= mesh.is_boundary_face(g);
            for n in mesh.face_neighbors(g) {
                let ni = mesh.face_index(n);
                if !in_area[ni] && group[ni] == u32::MAX {
                    group[ni] = id;
                    stack.push(n);
                }
            }
        }
    }
    let largest = (0..sizes.len()).max_by_key(|&i| (sizes[i], Reverse(i)));
    let mut changed = false;
    for f in mesh.faces() {
        let fi = mesh.face_index(f);
        let g = group[fi] as usize;
        if component[fi] && !in_area[fi] && Some(g) != largest && !open[g] {
            in_area[fi] = true;
            changed = true;
        }
    }
    changed
}

/// The input faces that the hierarchy collapses into the coarse editing `area`, as an
/// editing area: a face whose ancestors are three distinct vertices belongs when they
/// span a face of the area; one collapsed onto an edge, when both faces of that edge are
/// in the area; one collapsed onto a vertex, when the vertex is interior to the area.
/// (Collapses map every triangle onto a triangle, an edge or a vertex.) Pinches and
/// pockets of that set are repaired ([`accept_area`]).
fn preimage_area(
    coarse: &Mesh,
    fine: &Mesh,
    ancestors: &[u32],
    area: &EditingArea,
    interior: &[bool],
) -> Result<EditingArea, LeeError> {
    let mut in_area = vec![false; coarse.face_slots()];
    for &f in area.faces() {
        in_area[coarse.face_index(f)] = true;
    }
    let face_in_area = |h: Option<halfedge::HalfedgeId>| {
        h.and_then(|h| coarse.face(h))
            .is_some_and(|f| in_area[coarse.face_index(f)])
    };
    let vertex = |i: u32| coarse.vertex_at(i as usize);
    let image = |f: halfedge::FaceId| fine.triangle(f).map(|v| ancestors[fine.vertex_index(v)]);
    let faces: Vec<halfedge::FaceId> = fine
        .faces()
        .filter(|&f| {
            let [a, b, c] = image(f);
            let (Some(va), Some(vb), Some(vc)) = (vertex(a), vertex(b), vertex(c)) else {
                return false;
            };
            if a != b && b != c && c != a {
                // the coarse face a → b → c
                let h = coarse.find_halfedge(va, vb);
                h.is_some_and(|h| coarse.to_vertex(coarse.next(h)) == vc) && face_in_area(h)
            } else if a == b && b == c {
                interior[a as usize]
            } else {
                let (p, q) = if a == b { (va, vc) } else { (va, vb) };
                face_in_area(coarse.find_halfedge(p, q)) && face_in_area(coarse.find_halfedge(q, p))
            }
        })
        .collect();
    let mut in_area = vec![false; fine.face_slots()];
    for &f in &faces {
        in_area[fine.face_index(f)] = true;
    }
    accept_area(fine, &mut in_area)
}

/// The editing area of the faces in `in_area`, repaired where a finer mesh makes the
/// image of a coarse disk pinch (the faces around the pinch vertex are added) or enclose
/// a pocket (filled), a few times at most.
fn accept_area(mesh: &Mesh, in_area: &mut [bool]) -> Result<EditingArea, LeeError> {
    let (vertex_component, _) = mesh.connected_components();
    let mut result = EditingArea::from_faces(mesh, &faces_of(mesh, in_area));
    for _ in 0..64 {
        let changed = match &result {
            Ok(_) => break,
            Err(LeeError::AreaPinched { vertex }) => {
                let mut changed = false;
                for f in mesh.adjacent_faces(*vertex) {
                    changed |= !std::mem::replace(&mut in_area[mesh.face_index(f)], true);
                }
                changed
            }
            Err(LeeError::AreaNotDisk { .. }) => {
                let seed = mesh
                    .faces()
                    .find(|&f| in_area[mesh.face_index(f)])
                    .map(|f| vertex_component[mesh.vertex_index(mesh.triangle(f)[0])]);
                let component: Vec<bool> = (0..mesh.face_slots())
                    .map(|i| {
                        mesh.face_at(i).is_some_and(|f| {
                            Some(vertex_component[mesh.vertex_index(mesh.triangle(f)[0])]) == seed
                        })
                    })
                    .collect();
                fill_pockets(mesh, in_area, &component)
            }
            Err(_) => false,
        };
        if !changed {
            break;
        }
        result = EditingArea::from_faces(mesh, &faces_of(mesh, in_area));
    }
    result
}

/// Bendels & Klein: the handle (the nearest vertices around the tip) rotated and lifted,
/// everything beyond the ball fixed, at both levels.
fn bk_edit(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    ancestors: &[u32],
    handle: &[bool],
    ball: &[bool],
    radius: f64,
    amount: f64,
) -> Result<Applied, Failure> {
    let hint = "pass a larger --region-fraction or another --seed-vertex";
    // fixed: beyond the ball, except the handle's neighbours (a long edge can reach past
    // the ball; the handle must not touch the fixed area)
    let fixed: Vec<bool> = (0..coarse.vertex_slots())
        .map(|i| {
            coarse.vertex_at(i).is_some_and(|v| {
                !coarse.is_isolated(v)
                    && !ball[i]
                    && !coarse
                        .adjacent_vertices(v)
                        .any(|w| handle[coarse.vertex_index(w)])
            })
        })
        .collect();
    let regions = Regions::from_sets(coarse, &listed(coarse, handle), &listed(coarse, &fixed))
        .map_err(lib(hint))?;
    let positions = coarse.positions();
    let handle_list: Vec<u32> = (0..handle.len() as u32)
        .filter(|&i| handle[i as usize])
        .collect();
    let centre = handle_list
        .iter()
        .map(|&i| positions[i as usize])
        .sum::<DVec3>()
        / handle_list.len() as f64;
    let normal = mean_normal(coarse, handle);
    let normal = if normal == DVec3::ZERO {
        DVec3::Z
    } else {
        normal
    };
    let axis = normal.any_orthonormal_vector();
    let a = DAffine3::from_translation(0.2 * amount * radius * normal)
        * DAffine3::from_translation(centre)
        * DAffine3::from_quat(DQuat::from_axis_angle(axis, 30f64.to_radians() * amount))
        * DAffine3::from_translation(-centre);
    let movable: Vec<bool> = regions
        .roles()
        .iter()
        .map(|&r| r != edit::bendels_klein::Role::Fixed)
        .collect();
    let mut session =
        BlendSession::new(coarse, regions, BlendOptions::default()).map_err(lib(hint))?;
    session
        .apply(coarse, glam::DMat4::from(a))
        .map_err(lib(hint))?;
    let marks = session.hierarchy_marks(coarse).map_err(lib(hint))?;

    let mut fine_region = 0;
    if let Some(fine) = fine {
        let fine_handle = fine_mask(fine, ancestors, handle);
        let fine_fixed = fine_mask(fine, ancestors, &fixed);
        let fine_regions = Regions::from_sets(
            fine,
            &listed(fine, &fine_handle),
            &listed(fine, &fine_fixed),
        )
        .map_err(lib(hint))?;
        fine_region = fine_regions.handle().len() + fine_regions.deformable().len();
        let mut fine_session =
            BlendSession::new(fine, fine_regions, BlendOptions::default()).map_err(lib(hint))?;
        fine_session
            .apply(fine, glam::DMat4::from(a))
            .map_err(lib(hint))?;
    }
    Ok(Applied {
        movable,
        fine_region,
        rigid: vec![Rigid {
            vertices: handle_list,
            map: a,
        }],
        marks: Some(marks),
    })
}

/// Shape/height-surface FFD: the lattice over the region's footprint, attached to the
/// larger ball, bent inside its two outer layers of control points ([`bend_inside`]);
/// the same frame and lattice at both levels.
fn ffd_edit(
    coarse: &mut Mesh,
    fine: Option<&mut Mesh>,
    ancestors: &[u32],
    tip: usize,
    mask: &[bool],
    ball: &[bool],
    amount: f64,
) -> Result<Applied, Failure> {
    let hint = "pass another --region-fraction or --seed-vertex";
    let mask = VertexData::new(coarse, mask.to_vec()).map_err(lib(hint))?;
    let sub = SubMesh::from_mask(coarse, &mask).map_err(lib(hint))?;
    let positions = coarse.positions();
    let frontier = sub.frontier_indices();
    if frontier.is_empty() {
        return Err(Failure::new(
            "the region covers its whole component: it has no frontier",
            "pass a smaller --region-fraction",
        ));
    }
    let centre = frontier
        .iter()
        .map(|&i| positions[i as usize])
        .sum::<DVec3>()
        / frontier.len() as f64;
    let d = (positions[tip] - centre).normalize_or_zero();
    if d == DVec3::ZERO {
        return Err(Failure::new(
            "the region's tip is at the centroid of its frontier: the region has no axis",
            hint,
        ));
    }
    let up = perpendicular(d, mean_normal(coarse, &mask));
    let frame = LatticeFrame::new(centre, d, up).map_err(lib(hint))?;
    let (lo, hi) = sub
        .vertex_indices()
        .iter()
        .map(|&i| frame.to_local(positions[i as usize]))
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), l| {
            (lo.min(l), hi.max(l))
        });
    // (a flat footprint gets a thickness of a millionth of its extent, at any scale)
    let size = (hi - lo).max(DVec3::splat(1e-6 * (hi - lo).max_element()));
    let margin = 0.05;
    let min = [lo.x - margin * size.x, lo.z - margin * size.z];
    let max = [hi.x + margin * size.x, hi.z + margin * size.z];
    let grid = ([3, 3], [8, 8]);
    let shape = BSplineSurface::planar(&frame, grid.0, grid.1, min, max, 0.0).map_err(lib(hint))?;
    let height =
        BSplineSurface::planar(&frame, grid.0, grid.1, min, max, 1.0).map_err(lib(hint))?;
    let angle = 45f64.to_radians() * amount;
    let ball_data = VertexData::new(coarse, ball.to_vec()).map_err(lib(hint))?;
    let mut ffd = Ffd::attach(
        coarse,
        Vertices::Mask(&ball_data),
        frame,
        shape.clone(),
        height.clone(),
        AttachOptions::default(),
    )
    .map_err(lib(hint))?;
    bend_inside(&mut ffd, angle).map_err(lib(hint))?;
    ffd.deform(coarse).map_err(lib(hint))?;
    let movable: Vec<bool> = (0..coarse.vertex_slots())
        .map(|i| ffd.parameters(i).is_some())
        .collect();

    let mut fine_region = 0;
    if let Some(fine) = fine {
        let fine_ball =
            VertexData::new(fine, fine_mask(fine, ancestors, ball)).map_err(lib(hint))?;
        let mut fine_ffd = Ffd::attach(
            fine,
            Vertices::Mask(&fine_ball),
            frame,
            shape,
            height,
            AttachOptions::default(),
        )
        .map_err(lib(hint))?;
        bend_inside(&mut fine_ffd, angle).map_err(lib(hint))?;
        fine_ffd.deform(fine).map_err(lib(hint))?;
        fine_region = fine_ffd.attached();
    }
    Ok(Applied {
        movable,
        fine_region,
        rigid: Vec::new(),
        marks: None,
    })
}

/// Bends the FFD's shape surface ([`Ffd::bend`]) and puts the two outer layers of
/// control points on every side back where they were: the surface and its normal stay
/// unchanged along the lattice's border, so the deformation fades to nothing there
/// whichever borders the attached vertices cross (the library pins crossed borders
/// only, and which ones are crossed can differ between resolutions).
fn bend_inside(ffd: &mut Ffd, angle: f64) -> Result<(), DeformError> {
    ffd.bend(angle)?;
    let rest = ffd.rest().0.clone();
    let [cu, cv] = rest.count();
    for i in 0..cu {
        for j in 0..cv {
            if i < 2 || j < 2 || i + 2 >= cu || j + 2 >= cv {
                if let Some(p) = rest.control_point(i, j) {
                    ffd.shape_mut().set_control_point(i, j, p)?;
                }
            }
        }
    }
    Ok(())
}

/// `--edit bk-refine`: the Bendels & Klein edit of `bk` made at the level with adaptive
/// refinement inside the hierarchy (`BlendSession::apply` and `HierarchyEdit::mark`, then
/// `refine_in_hierarchy`, which splits the long edges at the input and builds the
/// hierarchy again), then a walk to every level and back. Returns one JSON object:
/// `new_vertices`, `levels`, `levels_reachable` (every level reached and back, the mesh
/// valid at each), `handle_error` (the handle's input vertices against the rigid image of
/// their input positions, over the diagonal), `refine_seconds`.
///
/// # Errors
/// A [`Failure`] with a hint when no region or regions fit, or the library refuses.
pub fn measure_bk_refine(
    prepared: &Prepared,
    options: &Options,
    name: &str,
) -> Result<serde_json::Value, Failure> {
    let hint = "pass a larger --region-fraction or another --seed-vertex";
    let mut hierarchy = prepared.hierarchy.clone();
    if hierarchy.detail_mode() != DetailMode::LocalFrame {
        return Err(Failure::new(
            "bk-refine needs local-frame detail (the handle is marked as it moves)",
            "leave out --detail translation",
        ));
    }
    let level = prepared.level;
    let input = &prepared.input;
    let f = options.region_fraction;
    let region = choose_region(
        hierarchy.mesh(),
        &prepared.ancestors,
        options.seed_vertex,
        TIP_DEPTH,
    )?;
    let coarse = hierarchy.mesh();
    let slots = coarse.vertex_slots();
    let (handle, _) = region.ball(slots, 0.15 * f, 1)?;
    let (ball, radius) = region.ball(slots, 1.25 * f, 4)?;
    let fixed: Vec<bool> = (0..slots)
        .map(|i| {
            coarse.vertex_at(i).is_some_and(|v| {
                !coarse.is_isolated(v)
                    && !ball[i]
                    && !coarse
                        .adjacent_vertices(v)
                        .any(|w| handle[coarse.vertex_index(w)])
            })
        })
        .collect();
    let regions = Regions::from_sets(coarse, &listed(coarse, &handle), &listed(coarse, &fixed))
        .map_err(lib(hint))?;
    let centre = listed(coarse, &handle)
        .iter()
        .map(|&v| coarse.position(v))
        .sum::<DVec3>()
        / regions.handle().len().max(1) as f64;
    let normal = match mean_normal(coarse, &handle) {
        n if n == DVec3::ZERO => DVec3::Z,
        n => n,
    };
    let amount = options.amount;
    let a = DAffine3::from_translation(0.4 * amount * radius * normal)
        * DAffine3::from_translation(centre)
        * DAffine3::from_quat(DQuat::from_axis_angle(
            normal.any_orthonormal_vector(),
            30f64.to_radians() * amount,
        ))
        * DAffine3::from_translation(-centre);
    let mut session =
        BlendSession::new(coarse, regions, BlendOptions::default()).map_err(lib(hint))?;
    session
        .apply(hierarchy.mesh_mut(), glam::DMat4::from(a))
        .map_err(lib(hint))?;
    session.mark(&mut hierarchy).map_err(lib(hint))?;
    // Split what the edit stretched beyond the input's mean edge length, at the input.
    let mean_edge = {
        let (sum, n) = input
            .edges()
            .fold((0.0, 0usize), |(s, n), h| (s + input.edge_length(h), n + 1));
        sum / n.max(1) as f64
    };
    let clock = Instant::now();
    let report = session
        .refine_in_hierarchy(
            &mut hierarchy,
            edit::bendels_klein::RefineOptions::new(1.5 * mean_edge),
        )
        .map_err(lib(
            "this is a bug of the library; report it with the command line",
        ))?;
    let refine_seconds = clock.elapsed().as_secs_f64();
    // The handle at full resolution against the rigid image of its input vertices.
    hierarchy.go_to_level(0).map_err(lib(
        "this is a bug of the library; report it with the command line",
    ))?;
    let fine = hierarchy.mesh();
    let mut worst: f64 = 0.0;
    let mut handle_vertices = 0;
    for v in input.vertices() {
        let i = input.vertex_index(v);
        if handle[prepared.ancestors[i] as usize] {
            let target = a.transform_point3(input.position(v));
            worst = worst.max(fine.positions()[i].distance(target) / prepared.diagonal);
            handle_vertices += 1;
        }
    }
    let faces = fine.n_faces();
    // Every level and back.
    let levels = hierarchy.n_levels();
    let mut reachable = true;
    for l in (0..levels).chain((0..levels).rev()) {
        reachable &= hierarchy.go_to_level(l).is_ok() && hierarchy.mesh().check().is_ok();
    }
    Ok(serde_json::json!({
        "mesh": name,
        "edit": "bk-refine",
        "level": level,
        "method": match hierarchy.method() {
            Method::Rounds => "rounds",
            Method::Qem => "qem",
        },
        "input_faces": input.n_faces(),
        "faces": faces,
        "new_vertices": report.new_vertices,
        "longest_edge": report.longest_edge,
        "levels": levels,
        "levels_reachable": reachable,
        "handle_vertices": handle_vertices,
        "handle_error": worst,
        "refine_seconds": refine_seconds,
    }))
}
