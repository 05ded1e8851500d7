//! Applying a recipe's steps to a hierarchy (each at its level, marked so that refinement
//! brings the edit back at full resolution) or to a plain mesh.

use std::time::Instant;

use edit::bendels_klein::{BlendOptions, BlendSession, DistanceKind, Regions, ShapeFunction};
use edit::deform::{Axis, Propagation, Smoother, SmoothingWeights, SubMesh, SubmeshEdit};
use edit::lee::{AreaSession, FrameKind, SessionOptions};
use edit::HierarchyEdit;
use glam::{DMat4, DVec3};
use halfedge::hierarchy::Hierarchy;
use halfedge::labels::LABEL_ATTRIBUTE;
use halfedge::{Mesh, VertexId};

use super::region::{
    region_centre, resolve_area, resolve_place, resolve_region, resolve_submesh, Frame,
};
use super::schema::{AxisSpec, Falloff, Recipe, Region, Step, Variation};
use super::{RecipeError, RecipeResult};
use crate::progress::Progress;

/// What one step did.
#[derive(Clone, Debug, PartialEq)]
pub struct StepOutcome {
    /// The step, from 1.
    pub step: usize,
    /// Its method.
    pub method: &'static str,
    /// The level it was made at (0 on a plain mesh).
    pub level: usize,
    /// Vertices of that level whose position changed.
    pub moved: usize,
    /// What it did, in words.
    pub detail: String,
    /// Seconds it took.
    pub seconds: f64,
}

/// Where a step is applied: a hierarchy (at the step's level, with marks) or a plain mesh.
enum Target<'a> {
    Hierarchy(&'a mut Hierarchy),
    Mesh(&'a mut Mesh),
}

impl Target<'_> {
    fn mesh(&self) -> &Mesh {
        match self {
            Target::Hierarchy(h) => h.mesh(),
            Target::Mesh(m) => m,
        }
    }
    fn mesh_mut(&mut self) -> &mut Mesh {
        match self {
            Target::Hierarchy(h) => h.mesh_mut(),
            Target::Mesh(m) => m,
        }
    }
    /// Tells the hierarchy what the edit did (nothing for a plain mesh).
    fn mark(&mut self, edit: &dyn HierarchyEdit) -> Result<(), String> {
        match self {
            Target::Hierarchy(h) => edit.mark(h).map_err(|e| e.to_string()),
            Target::Mesh(_) => Ok(()),
        }
    }
    /// Attaches the mesh's labels to the hierarchy, defined at its current level, after a
    /// region labelled the mesh (so that refinement classifies the vertices it brings
    /// back).
    fn labels_changed(&mut self) {
        if let Target::Hierarchy(h) = self {
            if let Some(attribute) = h.mesh().find_attribute::<VertexId, u32>(LABEL_ATTRIBUTE) {
                if h.attach_labels(attribute).is_ok() {
                    h.labels_defined_here();
                }
            }
        }
    }
}

/// Applies `recipe`'s steps to `hierarchy`, each at its level (clamped to the coarsest;
/// a step without a level is made at the current one), marked in the hierarchy. The
/// hierarchy is left at the last step's level: refine it (`go_to_level(0)`) for the
/// full-resolution result, or save it.
///
/// # Errors
/// [`RecipeError::Invalid`] for a parameter out of range and [`RecipeError::Step`] for a
/// region that selects nothing usable or an edit its method refused, naming the step;
/// the steps before it stay applied.
pub fn apply(
    hierarchy: &mut Hierarchy,
    recipe: &Recipe,
    progress: &mut dyn Progress,
) -> RecipeResult<Vec<StepOutcome>> {
    let mut outcomes = Vec::with_capacity(recipe.steps.len());
    for (k, step) in recipe.steps.iter().enumerate() {
        let fail = |reason: String| RecipeError::Step {
            step: k + 1,
            method: step.method(),
            reason,
        };
        let level = step
            .level()
            .unwrap_or_else(|| hierarchy.level_at_or_finer())
            .min(hierarchy.coarsest_level());
        if hierarchy.current_level() != Some(level) {
            hierarchy
                .go_to_level(level)
                .map_err(|e| fail(e.to_string()))?;
        }
        progress.start(&format!("step {}: {}", k + 1, step.method()), None);
        let result = run_step(Target::Hierarchy(hierarchy), k + 1, step, level);
        progress.finish();
        outcomes.push(result?);
    }
    Ok(outcomes)
}

/// Applies `recipe`'s steps to a plain mesh (no hierarchy: every step at the mesh's own
/// resolution; a step's `level` must be absent or 0).
///
/// # Errors
/// As [`apply`]; [`RecipeError::Invalid`] for a step at a level above 0. On an error the
/// mesh is as it was: its positions and its sub-mesh labels are put back (no step
/// changes its connectivity).
pub fn apply_to_mesh(
    mesh: &mut Mesh,
    recipe: &Recipe,
    progress: &mut dyn Progress,
) -> RecipeResult<Vec<StepOutcome>> {
    let positions = mesh.positions().to_vec();
    let labels = mesh
        .find_attribute::<VertexId, u32>(LABEL_ATTRIBUTE)
        .and_then(|a| Some((a, mesh.attribute_values(a).ok()?.to_vec())));
    let result = apply_to_mesh_steps(mesh, recipe, progress);
    if result.is_err() {
        // put back what the steps before the failing one changed
        mesh.positions_mut().copy_from_slice(&positions);
        let now = mesh.find_attribute::<VertexId, u32>(LABEL_ATTRIBUTE);
        match (&labels, now) {
            (Some((_, values)), Some(a)) => {
                if let Ok(slot) = mesh.attribute_values_mut(a) {
                    if slot.len() == values.len() {
                        slot.copy_from_slice(values);
                    }
                }
            }
            (None, Some(a)) => {
                let _ = mesh.remove_attribute(a);
            }
            _ => {}
        }
    }
    result
}

fn apply_to_mesh_steps(
    mesh: &mut Mesh,
    recipe: &Recipe,
    progress: &mut dyn Progress,
) -> RecipeResult<Vec<StepOutcome>> {
    let mut outcomes = Vec::with_capacity(recipe.steps.len());
    for (k, step) in recipe.steps.iter().enumerate() {
        if step.level().is_some_and(|l| l > 0) {
            return Err(RecipeError::Invalid {
                step: k + 1,
                method: step.method(),
                key: "level",
                reason: "a plain mesh has no coarser level: simplify it first (multires \
                         simplify), or leave the level out"
                    .to_owned(),
            });
        }
        progress.start(&format!("step {}: {}", k + 1, step.method()), None);
        let result = run_step(Target::Mesh(mesh), k + 1, step, 0);
        progress.finish();
        outcomes.push(result?);
    }
    Ok(outcomes)
}

fn run_step(
    mut target: Target<'_>,
    k: usize,
    step: &Step,
    level: usize,
) -> RecipeResult<StepOutcome> {
    let clock = Instant::now();
    let method = step.method();
    let fail = |reason: String| RecipeError::Step {
        step: k,
        method,
        reason,
    };
    let invalid = |key: &'static str, reason: String| RecipeError::Invalid {
        step: k,
        method,
        key,
        reason,
    };
    let frame = Frame::of(target.mesh()).ok_or_else(|| fail("the mesh has no vertices".into()))?;
    let before = target.mesh().positions().to_vec();
    let detail = match step {
        Step::LeeDrag(s) => {
            let scale = s.scale.unwrap_or(0.5);
            if !(0.0..=1.0).contains(&scale) {
                return Err(invalid("scale", format!("must be in [0, 1], got {scale}")));
            }
            let frames = match s.frames.as_deref().unwrap_or("global") {
                "global" => FrameKind::Global,
                "normal" => FrameKind::Normal {
                    seed: None,
                    x_axis: None,
                },
                other => {
                    return Err(invalid(
                        "frames",
                        format!("{other:?} is not global or normal"),
                    ))
                }
            };
            let area = resolve_area(target.mesh_mut(), &s.area, frame).map_err(fail)?;
            let primitive: Vec<VertexId> = if s.primitive.is_empty() {
                match &s.area {
                    Region::Disk { around, .. } | Region::Ball { around, .. } => {
                        vec![resolve_place(target.mesh(), around).map_err(fail)?]
                    }
                    _ => {
                        return Err(invalid(
                            "primitive",
                            "an area that is not a disk or ball needs its primitive's places"
                                .into(),
                        ))
                    }
                }
            } else {
                s.primitive
                    .iter()
                    .map(|p| resolve_place(target.mesh(), p))
                    .collect::<Result<_, _>>()
                    .map_err(fail)?
            };
            let pull = match (s.pull, s.along_normal) {
                (Some(p), None) => DVec3::from_array(p),
                (None, Some(f)) => target.mesh().vertex_normal(primitive[0]) * f * frame.diagonal,
                _ => {
                    return Err(invalid(
                        "pull",
                        "give exactly one of pull (model units) and along_normal (a fraction \
                         of the diagonal)"
                            .into(),
                    ))
                }
            };
            if !pull.is_finite() {
                return Err(invalid("pull", format!("the drag {pull} is not finite")));
            }
            let options = SessionOptions::default()
                .with_scale(scale)
                .with_frames(frames);
            let n_area = area.vertices().len();
            let mut session =
                AreaSession::new(target.mesh(), area, &options).map_err(|e| fail(e.to_string()))?;
            session
                .set_primitive(target.mesh(), &primitive)
                .and_then(|()| session.drag(target.mesh_mut(), pull))
                .map_err(|e| fail(e.to_string()))?;
            target.mark(&session).map_err(&fail)?;
            session
                .commit(target.mesh())
                .map_err(|e| fail(e.to_string()))?;
            format!(
                "area of {n_area} vertices, primitive of {}, dragged by {:.6} at s = {scale}",
                primitive.len(),
                pull.length()
            )
        }
        Step::Blend(s) => {
            let handle = resolve_region(target.mesh_mut(), &s.handle, frame)
                .map_err(|e| fail(format!("handle: {e}")))?;
            let fixed = resolve_region(target.mesh_mut(), &s.fixed, frame)
                .map_err(|e| fail(format!("fixed: {e}")))?;
            let distance = match s.distance.as_deref().unwrap_or("geodesic") {
                "geodesic" => DistanceKind::Geodesic,
                "euclidean" => DistanceKind::Euclidean,
                other => {
                    return Err(invalid(
                        "distance",
                        format!("{other:?} is not geodesic or euclidean"),
                    ))
                }
            };
            let shape = match s.shape.as_deref().unwrap_or("smoothstep") {
                "smoothstep" => ShapeFunction::Smoothstep,
                "linear" => ShapeFunction::Linear,
                "smootherstep" | "c2" => ShapeFunction::Smootherstep,
                other => {
                    return Err(invalid(
                        "shape",
                        format!("{other:?} is not smoothstep, linear or smootherstep"),
                    ))
                }
            };
            let centre = s
                .rotate
                .as_ref()
                .and_then(|r| r.center)
                .map(DVec3::from_array)
                .unwrap_or_else(|| region_centre(target.mesh(), &s.handle, &handle));
            let a = match &s.transform {
                Some(rows) => DMat4::from_cols_array_2d(rows).transpose(),
                None => {
                    let mut a = DMat4::IDENTITY;
                    if let Some(f) = s.scale {
                        if !(f.is_finite() && f > 0.0) {
                            return Err(invalid(
                                "scale",
                                format!("must be finite and positive, got {f}"),
                            ));
                        }
                        a = DMat4::from_scale(DVec3::splat(f)) * a;
                    }
                    if let Some(r) = &s.rotate {
                        let axis = DVec3::from_array(r.axis);
                        if !(axis.is_finite() && axis.length() > 0.0 && r.degrees.is_finite()) {
                            return Err(invalid(
                                "rotate",
                                "needs a finite, non-zero axis and a finite angle".into(),
                            ));
                        }
                        a = DMat4::from_axis_angle(axis.normalize(), r.degrees.to_radians()) * a;
                    }
                    a = DMat4::from_translation(centre) * a * DMat4::from_translation(-centre);
                    if let Some(t) = s.translate {
                        a = DMat4::from_translation(DVec3::from_array(t)) * a;
                    }
                    a
                }
            };
            let regions = Regions::from_sets(target.mesh(), &handle, &fixed)
                .map_err(|e| fail(e.to_string()))?;
            let (n_handle, n_deformable) = (regions.handle().len(), regions.deformable().len());
            let options = BlendOptions::default()
                .with_distance(distance)
                .with_shape(shape);
            let mut blend = BlendSession::new(target.mesh(), regions, options)
                .map_err(|e| fail(e.to_string()))?;
            blend
                .apply(target.mesh_mut(), a)
                .map_err(|e| fail(e.to_string()))?;
            target.mark(&blend).map_err(&fail)?;
            format!("handle of {n_handle} vertices moved, {n_deformable} deformable")
        }
        Step::Smooth(s) => {
            let weights = match s.weights.as_deref().unwrap_or("uniform") {
                "uniform" => SmoothingWeights::Uniform,
                "cotangent" => SmoothingWeights::Cotangent,
                other => {
                    return Err(invalid(
                        "weights",
                        format!("{other:?} is not uniform or cotangent"),
                    ))
                }
            };
            let sub = resolve_submesh(target.mesh_mut(), &s.region, frame).map_err(&fail)?;
            target.labels_changed();
            let mut smoother = Smoother::for_submesh(target.mesh(), &sub, s.collar, weights, true)
                .map_err(|e| fail(e.to_string()))?;
            smoother
                .taubin(target.mesh_mut(), s.lambda, s.mu, s.iterations)
                .map_err(|e| fail(e.to_string()))?;
            format!(
                "{} iterations of Taubin λ|μ = {}|{} over {} vertices",
                s.iterations,
                s.lambda,
                s.mu,
                smoother.moving()
            )
        }
        submesh_step => {
            let (region, propagation, falloff) = match submesh_step {
                Step::Pull(s) => (&s.region, s.propagation, s.falloff),
                Step::Scale(s) => (&s.region, s.propagation, s.falloff),
                Step::Rotate(s) => (&s.region, s.propagation, s.falloff),
                Step::Taper(s) => (&s.region, s.propagation, s.falloff),
                Step::Twist(s) => (&s.region, s.propagation, s.falloff),
                _ => unreachable!("the other methods are handled above"),
            };
            let sub = resolve_submesh(target.mesh_mut(), region, frame).map_err(&fail)?;
            target.labels_changed();
            let edit = submesh_edit(target.mesh(), &sub, submesh_step)
                .map_err(|(key, reason)| invalid(key, reason))?;
            let propagation = match falloff {
                Falloff::Linear => Propagation::linear(propagation),
                Falloff::Smooth => Propagation::smooth(propagation),
            };
            let applied = sub
                .apply_with_marks(target.mesh_mut(), &edit, propagation)
                .map_err(|e| fail(e.to_string()))?;
            target.mark(&applied).map_err(&fail)?;
            format!("sub-mesh of {} vertices", sub.len())
        }
    };
    let moved = target
        .mesh()
        .positions()
        .iter()
        .zip(&before)
        .filter(|(a, b)| a != b)
        .count();
    Ok(StepOutcome {
        step: k,
        method,
        level,
        moved,
        detail,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

fn axis(spec: &Option<AxisSpec>) -> Result<Option<Axis>, (&'static str, String)> {
    spec.as_ref()
        .map(|a| {
            Axis::new(DVec3::from_array(a.point), DVec3::from_array(a.direction))
                .map_err(|e| ("axis", e.to_string()))
        })
        .transpose()
}

fn variation(v: &Option<Variation>) -> edit::deform::Variation {
    match v {
        None | Some(Variation::Levels) => edit::deform::Variation::Levels(None),
        Some(Variation::Uniform) => edit::deform::Variation::Uniform,
        Some(Variation::Along { start, end }) => edit::deform::Variation::Along {
            start: *start,
            end: *end,
        },
    }
}

/// The sub-mesh edit a step asks for, on `mesh` (for defaults that need it).
fn submesh_edit(
    mesh: &Mesh,
    sub: &SubMesh,
    step: &Step,
) -> Result<SubmeshEdit, (&'static str, String)> {
    Ok(match step {
        Step::Pull(s) => SubmeshEdit::Pull {
            offset: DVec3::from_array(s.offset),
        },
        Step::Scale(s) => SubmeshEdit::Scale {
            centre: match s.centre {
                Some(c) => DVec3::from_array(c),
                None => {
                    sub.vertex_indices()
                        .iter()
                        .map(|&i| mesh.positions()[i as usize])
                        .sum::<DVec3>()
                        / sub.len().max(1) as f64
                }
            },
            factor: s.factor,
        },
        Step::Rotate(s) => SubmeshEdit::Rotate {
            axis: match axis(&s.axis)? {
                Some(a) => a,
                None => {
                    let plane = sub
                        .frontier_plane(mesh)
                        .map_err(|e| ("axis", format!("no axis given and {e}")))?;
                    Axis::new(plane.point, plane.normal).map_err(|e| ("axis", e.to_string()))?
                }
            },
            angle: s.degrees.to_radians(),
            bounded: s.bounded,
        },
        Step::Taper(s) => SubmeshEdit::Taper {
            axis: axis(&s.axis)?,
            factor: s.factor,
            variation: variation(&s.variation),
        },
        Step::Twist(s) => SubmeshEdit::Twist {
            axis: axis(&s.axis)?,
            angle: s.degrees.to_radians(),
            variation: variation(&s.variation),
        },
        _ => return Err(("method", "not a sub-mesh edit".to_owned())),
    })
}
