//! The measurement behind the `coarse_edit` example and `tests/coarse_edit.rs` (issue 12):
//! one edit made at a coarse level of a [`Hierarchy`] and refined back, against the same
//! edit made directly on the full-resolution mesh. See the example's module docs
//! (`examples/coarse_edit/main.rs`) for the region rule, the edits and the reported
//! fields.
//!
//! [`prepare`] builds the hierarchy once; [`measure`] makes one edit ([`Options`]) and
//! returns a [`Report`] and both meshes; [`measure_bk_refine`] is `--edit bk-refine`.
//! The parts: `region.rs` chooses the region, `report.rs` is the [`Report`], and one file
//! per family of edits applies it at both resolutions (`submesh.rs`, `lee.rs`,
//! `bendels_klein.rs`, `ffd.rs`); `bk_refine.rs` is the B&K edit with adaptive refinement.

mod bendels_klein;
mod bk_refine;
mod ffd;
mod lee;
mod region;
mod report;
mod submesh;

use std::fmt;
use std::time::Instant;

use edit::HierarchyMarks;
use glam::{DAffine3, DVec3};
use halfedge::hierarchy::{DetailMode, Hierarchy, HierarchyOptions, Method};
use halfedge::{Mesh, VertexId};

pub use bk_refine::measure_bk_refine;
pub use report::Report;

use bendels_klein::bk_edit;
use ffd::ffd_edit;
use lee::lee_edit;
use region::{choose_region, Region, FLAT_REGION, TIP_DEPTH};
use submesh::submesh_edit;

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

/// How many times a smooth edit's magnitudes are halved at most while it turns a face
/// of the coarse mesh over.
const MAX_HALVINGS: usize = 4;

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
