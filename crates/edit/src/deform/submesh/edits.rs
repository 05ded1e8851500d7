//! The sub-mesh edits of *Interactive editing of multiresolution meshes* §4.3 with the
//! propagation levels of §4.2 (see [`SubMesh`]).

use glam::{DAffine3, DMat3, DQuat, DVec3};
use halfedge::{Mesh, VertexId};
use rayon::prelude::*;

use crate::deform::barr::twist::rotation_displacement;
use crate::deform::checks::{check_finite_positions, finite, finite_point};
use crate::deform::error::{DeformError, Result};
use crate::deform::submesh::axis::Axis;
use crate::deform::submesh::frontier::SubMesh;
use crate::deform::submesh::plane::Plane;
use crate::error::Error;
use crate::hierarchy_edit::{HierarchyEdit, HierarchyMarks};
use crate::vertices::{scatter, Snapshot};

/// How the strength of an edit decreases across the propagation collars.
///
/// Paper: *Interactive editing of multiresolution meshes* §4.2.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Falloff {
    /// `w_k = 1 − k/(n+1)`.
    #[default]
    Linear,
    /// `w_k = 1 − smoothstep(k/(n+1))`: flat next to the frontier and at the far end.
    Smooth,
}

/// The number `n` of propagation levels (collars of faces beyond the frontier over which
/// an edit fades, §4.2) and the fall-off across them. `n = 0` confines the edit to the
/// sub-mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Propagation {
    /// Number of collars `n`.
    pub levels: usize,
    /// Fall-off across the collars.
    pub falloff: Falloff,
}

impl Propagation {
    /// No propagation: nothing outside the sub-mesh moves.
    pub const NONE: Propagation = Propagation {
        levels: 0,
        falloff: Falloff::Linear,
    };

    /// `n` collars with linear fall-off.
    pub fn linear(levels: usize) -> Self {
        Self {
            levels,
            falloff: Falloff::Linear,
        }
    }

    /// `n` collars with smooth fall-off.
    pub fn smooth(levels: usize) -> Self {
        Self {
            levels,
            falloff: Falloff::Smooth,
        }
    }

    /// The strength on collar `k` (1 inside, `k = 0`; strictly decreasing over
    /// `1..=n`; 0 beyond `n`).
    pub fn weight(&self, k: usize) -> f64 {
        if k == 0 {
            return 1.0;
        }
        if k > self.levels {
            return 0.0;
        }
        // (`levels + 1` in f64: it does not wrap for `usize::MAX`.)
        let t = k as f64 / (self.levels as f64 + 1.0);
        match self.falloff {
            Falloff::Linear => 1.0 - t,
            Falloff::Smooth => 1.0 - t * t * (3.0 - 2.0 * t),
        }
    }
}

/// How the taper factor or twist angle varies over the sub-mesh (Barr's progressive
/// scaling and rotation, §4.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variation {
    /// Along the axis: strength `clamp((s − start)/(end − start), 0, 1)` with `s` the
    /// axial coordinate, inside the sub-mesh and (times the collar weight) on the
    /// propagation collars.
    Along {
        /// Axial coordinate where the edit starts (strength 0).
        start: f64,
        /// Axial coordinate where it is complete (strength 1).
        end: f64,
    },
    /// Level by level inward from the frontier: strength `min(ℓ / L, 1)` at level `ℓ`,
    /// so the factor is progressive over `L` levels and constant beyond (the paper's
    /// Fig. 10 b / 12 b); `None` takes `L` = the maximum level, the usual taper and
    /// twist (Fig. 10 a / 12 a). The frontier (level 0) does not move, so the host stays
    /// untouched whatever the propagation.
    Levels(Option<usize>),
    /// The whole sub-mesh at full strength, fading over the propagation collars.
    Uniform,
}

/// An edit of a sub-mesh (*Interactive editing of multiresolution meshes* §4.3); see
/// [`SubMesh`] for the strength `τ` each vertex receives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SubmeshEdit {
    /// Pull the vertices along a vector: `p + τ·offset`.
    Pull {
        /// The displacement at full strength.
        offset: DVec3,
    },
    /// Scale about a point by `factor^τ` (`factor > 0`). Without propagation the scaled
    /// sub-mesh is re-seated on the plane fitted to its frontier (Fig. 9 b).
    Scale {
        /// The fixed point of the scaling.
        centre: DVec3,
        /// The scale factor at full strength.
        factor: f64,
    },
    /// Rotate about an axis by `τ·angle` (radians, counter-clockwise seen from the tip of
    /// the axis direction); default axis: [`Axis::vertex_normal`].
    Rotate {
        /// The rotation axis.
        axis: Axis,
        /// The angle at full strength.
        angle: f64,
        /// Keep every moved vertex on its side of the plane fitted to the frontier
        /// (a vertex that would cross it stops on it), as in Fig. 11 c–d.
        bounded: bool,
    },
    /// Barr taper: scale the components perpendicular to the axis by `factor^τ`
    /// (`factor > 0`), `τ` given by the variation.
    Taper {
        /// The taper axis; `None`: [`SubMesh::axis`].
        axis: Option<Axis>,
        /// The factor at full strength.
        factor: f64,
        /// How the strength varies.
        variation: Variation,
    },
    /// Barr twist: rotate about the axis by `τ·angle`, `τ` given by the variation.
    Twist {
        /// The twist axis; `None`: [`SubMesh::axis`].
        axis: Option<Axis>,
        /// The angle at full strength (radians).
        angle: f64,
        /// How the strength varies.
        variation: Variation,
    },
}

impl SubmeshEdit {
    /// The variation of a taper or twist, `None` for the other edits.
    pub fn variation(&self) -> Option<Variation> {
        match *self {
            SubmeshEdit::Taper { variation, .. } | SubmeshEdit::Twist { variation, .. } => {
                Some(variation)
            }
            _ => None,
        }
    }

    /// True when the edit moves nothing (zero offset or angle, factor 1).
    pub fn is_identity(&self) -> bool {
        match *self {
            SubmeshEdit::Pull { offset } => offset == DVec3::ZERO,
            SubmeshEdit::Scale { factor, .. } | SubmeshEdit::Taper { factor, .. } => factor == 1.0,
            SubmeshEdit::Rotate { angle, .. } | SubmeshEdit::Twist { angle, .. } => angle == 0.0,
        }
    }

    /// The edit that undoes this one (up to rounding) when applied with the same
    /// propagation: opposite offset or angle, reciprocal factor. `None` for a bounded
    /// rotation (clamping onto the plane loses information: restore the
    /// [`Snapshot`] instead). With a default axis (`None`) the inverse is exact when the
    /// frontier does not move (always for [`Variation::Levels`]); give the axis
    /// explicitly otherwise.
    pub fn inverse(&self) -> Option<SubmeshEdit> {
        Some(match *self {
            SubmeshEdit::Pull { offset } => SubmeshEdit::Pull { offset: -offset },
            SubmeshEdit::Scale { centre, factor } => SubmeshEdit::Scale {
                centre,
                factor: 1.0 / factor,
            },
            SubmeshEdit::Rotate {
                axis,
                angle,
                bounded: false,
            } => SubmeshEdit::Rotate {
                axis,
                angle: -angle,
                bounded: false,
            },
            SubmeshEdit::Rotate { bounded: true, .. } => return None,
            SubmeshEdit::Taper {
                axis,
                factor,
                variation,
            } => SubmeshEdit::Taper {
                axis,
                factor: 1.0 / factor,
                variation,
            },
            SubmeshEdit::Twist {
                axis,
                angle,
                variation,
            } => SubmeshEdit::Twist {
                axis,
                angle: -angle,
                variation,
            },
        })
    }
}

/// An edit with its parameters checked and its axis resolved.
#[derive(Clone, Copy, Debug)]
enum Map {
    Pull(DVec3),
    Scale { centre: DVec3, factor: f64 },
    Rotate { axis: Axis, angle: f64 },
    Taper { axis: Axis, factor: f64 },
    Twist { axis: Axis, angle: f64 },
}

/// `factor^τ`, exact at τ = 1.
#[inline]
fn power(factor: f64, tau: f64) -> f64 {
    if tau == 1.0 {
        factor
    } else {
        factor.powf(tau)
    }
}

impl Map {
    /// The map at full strength (`τ = 1`) as an affine map: `p ↦ p + displacement(p, 1)`.
    fn full_strength(&self) -> DAffine3 {
        let about = |point: DVec3, linear: DAffine3| {
            DAffine3::from_translation(point) * linear * DAffine3::from_translation(-point)
        };
        match *self {
            Map::Pull(offset) => DAffine3::from_translation(offset),
            Map::Scale { centre, factor } => {
                about(centre, DAffine3::from_scale(DVec3::splat(factor)))
            }
            Map::Rotate { axis, angle } | Map::Twist { axis, angle } => about(
                axis.point,
                DAffine3::from_quat(DQuat::from_axis_angle(axis.direction, angle)),
            ),
            Map::Taper { axis, factor } => {
                // q ↦ (q·d) d + factor (q − (q·d) d)
                let d = axis.direction;
                let outer = DMat3::from_cols(d * d.x, d * d.y, d * d.z);
                let linear = DMat3::from_diagonal(DVec3::splat(factor)) + (1.0 - factor) * outer;
                about(axis.point, DAffine3::from_mat3(linear))
            }
        }
    }

    /// The displacement of `p` at strength `tau`; exactly zero for identity parameters.
    #[inline]
    fn displacement(&self, p: DVec3, tau: f64) -> DVec3 {
        match *self {
            Map::Pull(offset) => tau * offset,
            Map::Scale { centre, factor } => (power(factor, tau) - 1.0) * (p - centre),
            Map::Rotate { axis, angle } => {
                rotation_displacement(axis.direction, p - axis.point, tau * angle)
            }
            Map::Taper { axis, factor } => {
                let q = p - axis.point;
                let perpendicular = q - q.dot(axis.direction) * axis.direction;
                (power(factor, tau) - 1.0) * perpendicular
            }
            Map::Twist { axis, angle } => {
                rotation_displacement(axis.direction, p - axis.point, tau * angle)
            }
        }
    }
}

fn positive_factor(name: &'static str, factor: f64) -> Result<f64> {
    finite(name, factor)?;
    if factor <= 0.0 {
        return Err(DeformError::InvalidParameter {
            name,
            reason: format!("{factor} is not positive (a reflection has no place here)"),
        });
    }
    Ok(factor)
}

fn check_variation(v: &Variation) -> Result<()> {
    if let Variation::Along { start, end } = *v {
        finite("variation start", start)?;
        finite("variation end", end)?;
    }
    Ok(())
}

/// A sub-mesh edit as [`SubMesh::apply_with_marks`] applied it: the positions it changed
/// (to undo it exactly) and what it means for a [`Hierarchy`](halfedge::hierarchy::Hierarchy)
/// whose current level the mesh was, given to the hierarchy through [`HierarchyEdit`].
///
/// Paper: *Interactive editing of multiresolution meshes* §4.
#[derive(Clone, Debug)]
pub struct AppliedSubmeshEdit {
    snapshot: Snapshot,
    marks: HierarchyMarks,
}

impl AppliedSubmeshEdit {
    /// The positions the edit changed, as they were before it.
    #[must_use]
    pub fn snapshot(&self) -> &Snapshot {
        &self.snapshot
    }

    /// The positions the edit changed, by value.
    #[must_use]
    pub fn into_snapshot(self) -> Snapshot {
        self.snapshot
    }
}

impl HierarchyEdit for AppliedSubmeshEdit {
    /// The marks worked out when the edit was applied (see
    /// [`SubMesh::apply_with_marks`]), for a hierarchy whose current level `mesh` is.
    ///
    /// # Errors
    /// [`DeformError::Stale`] when the sub-mesh was not made on `mesh` at its current
    /// level.
    fn hierarchy_marks(&self, mesh: &Mesh) -> std::result::Result<HierarchyMarks, Error> {
        self.marks.check(mesh).map_err(DeformError::from)?;
        Ok(self.marks.clone())
    }
}

/// What an edit does, worked out on the mesh before it moves: the map, every vertex it
/// reaches with its strength `τ > 0` (sorted by slot), the re-seating translation of a
/// scale without propagation and the plane a bounded rotation keeps to.
struct Plan {
    map: Map,
    targets: Vec<(u32, f64)>,
    reseat: DVec3,
    bound: Option<Plane>,
    /// Nothing moves (identity parameters or no vertex reached).
    idle: bool,
    /// The vertices of the propagation collars the edit reaches (moved or not; none for
    /// a variation by levels, which does not propagate).
    collars: Vec<u32>,
}

impl SubMesh {
    /// Applies `edit` with `propagation` and returns the positions it changed, to undo it
    /// exactly with [`Snapshot::restore`]. On error nothing is changed: for parameters
    /// out of range, and [`DeformError::Overflow`] when a moved vertex would not land on a
    /// finite position (a pull of 1e308, a scale factor of 1e300).
    pub fn apply(
        &self,
        mesh: &mut Mesh,
        edit: &SubmeshEdit,
        propagation: Propagation,
    ) -> Result<Snapshot> {
        self.check_mesh(mesh)?;
        let plan = self.plan(mesh, edit, propagation)?;
        self.apply_plan(mesh, &plan)
    }

    /// [`apply`](Self::apply), keeping what the edit means for a
    /// [`Hierarchy`](halfedge::hierarchy::Hierarchy) whose current level `mesh` is (worked out on
    /// `mesh` before the edit moves it): give it to the hierarchy with
    /// [`HierarchyEdit::mark`] on the result. The region is the sub-mesh and its `n`
    /// propagation collars (all of them, moved or not: the edit's transition is spread
    /// over their fine vertices), and the vertices at full strength (`τ = 1`: the whole
    /// sub-mesh without a variation, the part of a taper or twist beyond its ramp) form
    /// one affine part, moved by the edit's map at full strength (a translation, a scale
    /// about the centre with the re-seating translation, a rotation about the axis, Barr's
    /// taper or twist at its full factor or angle). A taper or twist whose strength ramps
    /// along its axis ([`Variation::Along`]) is a map of space: the whole sub-mesh is
    /// marked with it ([`Hierarchy::mark_field`](halfedge::hierarchy::Hierarchy::mark_field)), so
    /// every fine vertex collapsed into the sub-mesh gets its own strength from its own
    /// input position, ramp and rigid end included, as the same edit made at full
    /// resolution. A bounded rotation's vertices stopped on the frontier plane are not at
    /// the map's image: the hierarchy finds that and carries them by their local frame.
    /// Refined back, the sub-mesh's part at full strength is, at full resolution, the
    /// exact image of its original fine vertices, and nothing outside the sub-mesh and its
    /// collars moves. The edit may be applied to a clone of the hierarchy's mesh (an
    /// interactive application's working copy) and marked on the hierarchy.
    ///
    /// # Errors
    /// As [`apply`](Self::apply); nothing is changed then.
    pub fn apply_with_marks(
        &self,
        mesh: &mut Mesh,
        edit: &SubmeshEdit,
        propagation: Propagation,
    ) -> Result<AppliedSubmeshEdit> {
        self.check_mesh(mesh)?;
        let plan = self.plan(mesh, edit, propagation)?;
        let marks = self.marks_of_plan(mesh, edit, &plan)?;
        let snapshot = self.apply_plan(mesh, &plan)?;
        Ok(AppliedSubmeshEdit { snapshot, marks })
    }

    /// Moves the vertices of `plan` (worked out on `mesh` as it is).
    fn apply_plan(&self, mesh: &mut Mesh, plan: &Plan) -> Result<Snapshot> {
        let indices: Vec<u32> = plan.targets.iter().map(|&(i, _)| i).collect();
        let snapshot = Snapshot::of_indices(mesh, indices);
        if plan.idle {
            return Ok(snapshot);
        }
        let positions = mesh.positions();
        let new: Vec<DVec3> = plan
            .targets
            .par_iter()
            .with_min_len(1024)
            .map(|&(i, tau)| {
                let p = positions[i as usize];
                let mut d = plan.map.displacement(p, tau);
                if self.inside[i as usize] {
                    d += plan.reseat;
                }
                let mut q = if d == DVec3::ZERO { p } else { p + d };
                if let Some(plane) = plan.bound {
                    q = keep_side(&plane, p, q);
                }
                q
            })
            .collect();
        let indices = snapshot.indices().to_vec();
        check_finite_positions("the sub-mesh edit", &indices, &new)?;
        scatter(mesh.positions_mut(), &indices, &new);
        Ok(snapshot)
    }

    /// The marks of an edit whose plan on `mesh` (before the edit) is `plan` (see
    /// [`apply_with_marks`](Self::apply_with_marks)).
    fn marks_of_plan(
        &self,
        mesh: &Mesh,
        edit: &SubmeshEdit,
        plan: &Plan,
    ) -> Result<HierarchyMarks> {
        let live = |i: u32| mesh.vertex_at(i as usize);
        let mut region: Vec<u32> = self.vertices.clone();
        region.extend_from_slice(&plan.collars);
        region.sort_unstable();
        region.dedup();
        let region: Vec<VertexId> = region.into_iter().filter_map(live).collect();
        let marks = HierarchyMarks::new(mesh, region, Vec::new())?.bound_to(self.binding);
        if plan.idle {
            return Ok(marks);
        }
        // A taper or twist whose strength ramps along its axis is a map of space: every
        // fine vertex of the sub-mesh's clusters is moved by it from its own input
        // position, as the same edit at full resolution moves it (the ramp and the rigid
        // end included).
        if let (
            map @ (Map::Taper { .. } | Map::Twist { .. }),
            Some(Variation::Along { start, end }),
        ) = (plan.map, edit.variation())
        {
            let inside: Vec<VertexId> = self.vertices.iter().copied().filter_map(live).collect();
            let field = move |p: DVec3| {
                let d = map.displacement(p, along(&map, p, start, end));
                if d == DVec3::ZERO {
                    p
                } else {
                    p + d
                }
            };
            return Ok(marks.with_field(inside, std::sync::Arc::new(field)));
        }
        let full: Vec<VertexId> = plan
            .targets
            .iter()
            .filter(|&&(i, tau)| tau == 1.0 && self.inside[i as usize])
            .filter_map(|&(i, _)| live(i))
            .collect();
        if full.is_empty() {
            return Ok(marks);
        }
        let map = DAffine3::from_translation(plan.reseat) * plan.map.full_strength();
        Ok(marks.with_affine(full, map))
    }

    /// The plan of `edit` with `propagation` on `mesh` as it is (see [`Plan`]).
    fn plan(&self, mesh: &Mesh, edit: &SubmeshEdit, propagation: Propagation) -> Result<Plan> {
        let (map, variation) = self.resolve(mesh, edit)?;
        let positions = mesh.positions();

        // strengths: inside, then the collars
        let inside_strength = |i: u32| -> f64 {
            match variation {
                None | Some(Variation::Uniform) => 1.0,
                Some(Variation::Along { start, end }) => {
                    along(&map, positions[i as usize], start, end)
                }
                Some(Variation::Levels(levels)) => {
                    let total = levels.unwrap_or(self.max_level as usize);
                    match self.level(i as usize) {
                        // inside vertices no frontier reaches: full strength
                        None => 1.0,
                        Some(l) if total == 0 || l as usize >= total => 1.0,
                        Some(l) => l as f64 / total as f64,
                    }
                }
            }
        };
        let mut targets: Vec<(u32, f64)> = self
            .vertices
            .iter()
            .map(|&i| (i, inside_strength(i)))
            .collect();
        let propagates = !matches!(variation, Some(Variation::Levels(_)));
        let mut collars = Vec::new();
        if propagates && propagation.levels > 0 {
            let rings = self.collars(mesh, propagation.levels)?;
            for (k, collar) in rings.iter().enumerate() {
                let w = propagation.weight(k + 1);
                for &i in collar {
                    let v = match variation {
                        Some(Variation::Along { start, end }) => {
                            along(&map, positions[i as usize], start, end)
                        }
                        _ => 1.0,
                    };
                    targets.push((i, w * v));
                }
            }
            collars = rings.concat();
        }
        targets.retain(|&(_, tau)| tau > 0.0);
        targets.sort_unstable_by_key(|&(i, _)| i);
        let idle = edit.is_identity() || targets.is_empty();
        if idle {
            return Ok(Plan {
                map,
                targets,
                reseat: DVec3::ZERO,
                bound: None,
                idle,
                collars,
            });
        }

        // geometry needed before moving: the frontier plane
        let reseat = match *edit {
            SubmeshEdit::Scale { centre, factor } if propagation.levels == 0 => {
                self.reseat_translation(mesh, centre, factor)?
            }
            _ => DVec3::ZERO,
        };
        let bound = match *edit {
            SubmeshEdit::Rotate { bounded: true, .. } => Some(self.frontier_plane(mesh)?),
            _ => None,
        };
        Ok(Plan {
            map,
            targets,
            reseat,
            bound,
            idle,
            collars,
        })
    }

    /// The edit's map with its axis resolved, and the taper/twist variation.
    fn resolve(&self, mesh: &Mesh, edit: &SubmeshEdit) -> Result<(Map, Option<Variation>)> {
        let axis_or_default = |axis: Option<Axis>| match axis {
            Some(a) => Ok(a),
            None => self.axis(mesh),
        };
        Ok(match *edit {
            SubmeshEdit::Pull { offset } => (Map::Pull(finite_point("pull offset", offset)?), None),
            SubmeshEdit::Scale { centre, factor } => (
                Map::Scale {
                    centre: finite_point("scale centre", centre)?,
                    factor: positive_factor("scale factor", factor)?,
                },
                None,
            ),
            SubmeshEdit::Rotate { axis, angle, .. } => (
                Map::Rotate {
                    axis,
                    angle: finite("rotation angle", angle)?,
                },
                None,
            ),
            SubmeshEdit::Taper {
                axis,
                factor,
                variation,
            } => {
                check_variation(&variation)?;
                let factor = positive_factor("taper factor", factor)?;
                (
                    Map::Taper {
                        axis: axis_or_default(axis)?,
                        factor,
                    },
                    Some(variation),
                )
            }
            SubmeshEdit::Twist {
                axis,
                angle,
                variation,
            } => {
                check_variation(&variation)?;
                let angle = finite("twist angle", angle)?;
                (
                    Map::Twist {
                        axis: axis_or_default(axis)?,
                        angle,
                    },
                    Some(variation),
                )
            }
        })
    }

    /// The translation that puts the sub-mesh scaled by `factor` about `centre` back on
    /// the plane of its original frontier (§4.3, Fig. 9 b): the scaled frontier centroid
    /// `c + s (f − c)` is moved back onto the plane along its normal. With a frontier too
    /// small or straight to fit a plane, the scaled frontier centroid is moved back onto
    /// the original centroid; without frontier nothing is re-seated.
    fn reseat_translation(&self, mesh: &Mesh, centre: DVec3, factor: f64) -> Result<DVec3> {
        if self.frontier.is_empty() {
            return Ok(DVec3::ZERO);
        }
        let shift = |f: DVec3| -(factor - 1.0) * (f - centre);
        match self.frontier_plane(mesh) {
            Ok(plane) => Ok(shift(plane.point).dot(plane.normal) * plane.normal),
            Err(DeformError::DegenerateFrontier { .. }) => {
                let positions = mesh.positions();
                let centroid = self
                    .frontier
                    .iter()
                    .map(|&i| positions[i as usize])
                    .sum::<DVec3>()
                    / self.frontier.len() as f64;
                Ok(shift(centroid))
            }
            Err(e) => Err(e),
        }
    }
}

/// The strength of [`Variation::Along`] at `p` for a taper or twist map.
#[inline]
fn along(map: &Map, p: DVec3, start: f64, end: f64) -> f64 {
    let s = match map {
        Map::Taper { axis, .. } | Map::Twist { axis, .. } => axis.coordinate(p),
        _ => return 1.0,
    };
    if start == end {
        return if s < start { 0.0 } else { 1.0 };
    }
    ((s - start) / (end - start)).clamp(0.0, 1.0)
}

/// `q` (the edited position of `p`) kept on the side of `plane` where `p` was: a vertex
/// that would cross the plane stops on it (Fig. 11). The projection is nudged by a few
/// units in the last place when rounding would leave it a hair across.
#[inline]
fn keep_side(plane: &Plane, p: DVec3, q: DVec3) -> DVec3 {
    let before = plane.signed_distance(p);
    let wrong = |d: f64| (before >= 0.0 && d < 0.0) || (before < 0.0 && d > 0.0);
    let after = plane.signed_distance(q);
    if !wrong(after) {
        return q;
    }
    let mut r = q - after * plane.normal;
    let side = if before >= 0.0 { 1.0 } else { -1.0 };
    let mut nudge = f64::EPSILON * (r.abs().max_element() + plane.point.abs().max_element());
    for _ in 0..64 {
        if !wrong(plane.signed_distance(r)) {
            break;
        }
        r += side * nudge * plane.normal;
        nudge *= 2.0;
    }
    r
}
