//! The parameters of the *Bendels–Klein* tool (see [`params`](super::params)): the table
//! and the script-only setters.

use super::*;

/// The distance choices: `(geodesic, script name)`.
pub(super) const DISTANCES: [(bool, &str); 2] = [(true, "geodesic"), (false, "euclidean")];

/// Sets a handle-transform parameter and applies the transform.
pub(super) fn transform_param(
    t: &mut BendelsKlein,
    ctx: &mut ToolContext<'_>,
    set: impl FnOnce(&mut BendelsKlein) -> Result<(), ToolError>,
) -> Result<(), ToolError> {
    set(t)?;
    t.apply_transform(ctx, "Bendels–Klein transform")
}

/// Sets the loop of the handle or of the fixed region from a script.
pub(super) fn loop_param(
    t: &mut BendelsKlein,
    name: &str,
    value: &serde_json::Value,
    ctx: &mut ToolContext<'_>,
) -> Result<(), ToolError> {
    let picks = vertex_list_param(ctx.mesh(), name, value)?;
    if name == "handle_loop" {
        t.handle_picks = picks;
    } else {
        t.fixed_picks = picks;
    }
    t.source = Some(RegionSource::Loops);
    t.build(ctx)
}

/// Paints (or erases) at a vertex from a script.
pub(super) fn paint_param(
    t: &mut BendelsKlein,
    name: &str,
    value: &serde_json::Value,
    ctx: &mut ToolContext<'_>,
) -> Result<(), ToolError> {
    let v = vertex_param(ctx.mesh(), name, value)?;
    let p = match name {
        "paint_handle" => PAINT_HANDLE,
        "paint_fixed" => PAINT_FIXED,
        _ => PAINT_NONE,
    };
    t.paint_at(ctx, v, p)
}

/// The parameters of [`BendelsKlein`] (see [`params`]). The curve editor draws the
/// shape's widgets; the editing method checks the values.
pub(super) const PARAMS: &[Param<BendelsKlein>] = &[
    Param::new(
        "mode",
        "Click:",
        Widget::Choice(|| BkMode::ALL.iter().map(|m| m.1).collect()),
        |t| t.mode.key().into(),
        |t, v, _| {
            let s = string_param("mode", v)?;
            t.mode = BkMode::parse(s).ok_or_else(|| {
                ToolError::bad_value(
                    "mode",
                    "handle_loop, fixed_loop, paint_handle, paint_fixed, erase or drag",
                    v,
                )
            })?;
            Ok(())
        },
    ),
    Param::new(
        "brush",
        "brush radius (of the diagonal)",
        params::log_slider(0.005, 0.3),
        |t| t.brush.into(),
        |t, v, _| {
            t.brush = number_param("brush", v)?;
            Ok(())
        },
    ),
    Param::new(
        "distance",
        "Distance:",
        Widget::Choice(|| params::names(&DISTANCES)),
        |t| choice_name(&DISTANCES, t.geodesic).into(),
        |t, v, ctx| {
            t.geodesic = choice_param(&DISTANCES, "distance", v)?;
            t.rebuild_keep_transform(ctx)
        },
    ),
    Param::new(
        "shape",
        "shape",
        Widget::None,
        |t| t.curve.model.preset().key().into(),
        |t, v, ctx| {
            let s = string_param("shape", v)?;
            let preset = Preset::parse(s)
                .ok_or_else(|| ToolError::bad_value("shape", "linear, c1, c2 or curve", v))?;
            t.curve.model.set_preset(preset);
            t.shape_changed(ctx)
        },
    ),
    Param::new(
        "curve_points",
        "curve points",
        Widget::None,
        |t| {
            let points: Vec<serde_json::Value> = t
                .curve
                .model
                .points()
                .iter()
                .map(|&(x, y)| serde_json::json!([x, y]))
                .collect();
            points.into()
        },
        |t, v, ctx| {
            let bad = || ToolError::bad_value("curve_points", "[[x, y], ...]", v);
            let list = v.as_array().ok_or_else(bad)?;
            let mut points = Vec::with_capacity(list.len());
            for p in list {
                let xy = p.as_array().filter(|a| a.len() == 2).ok_or_else(bad)?;
                let x = xy[0].as_f64().ok_or_else(bad)?;
                let y = xy[1].as_f64().ok_or_else(bad)?;
                points.push((x, y));
            }
            t.curve.model.set_points(points).map_err(ToolError::new)?;
            t.shape_changed(ctx)
        },
    ),
    Param::new(
        "monotone",
        "monotone",
        Widget::None,
        |t| t.curve.model.monotone().into(),
        |t, v, ctx| {
            t.curve.model.set_monotone(bool_param("monotone", v)?);
            t.shape_changed(ctx)
        },
    ),
    Param::new(
        "translate",
        "translate",
        Widget::Vector {
            speed: 0.004,
            relative: true,
        },
        |t| t.translate.to_array().to_vec().into(),
        |t, v, ctx| {
            transform_param(t, ctx, |t| {
                t.translate = vec3_param("translate", v)?;
                Ok(())
            })
        },
    ),
    Param::new(
        "axis",
        "axis",
        Widget::Vector {
            speed: 0.01,
            relative: false,
        },
        |t| t.axis.to_array().to_vec().into(),
        |t, v, ctx| {
            transform_param(t, ctx, |t| {
                t.axis = vec3_param("axis", v)?;
                Ok(())
            })
        },
    ),
    Param::new(
        "angle",
        "angle (°)",
        params::drag(-179.0, 179.0, 0.5),
        |t| t.angle.into(),
        |t, v, ctx| {
            transform_param(t, ctx, |t| {
                t.angle = number_param("angle", v)?;
                Ok(())
            })
        },
    ),
    Param::new(
        "scale",
        "scale ×",
        params::drag(0.05, 20.0, 0.005),
        |t| t.scale.into(),
        |t, v, ctx| {
            transform_param(t, ctx, |t| {
                t.scale = number_param("scale", v)?;
                Ok(())
            })
        },
    ),
    Param::new(
        "refine_threshold",
        "refine edges longer than × mean",
        params::drag(0.5, 20.0, 0.05),
        |t| t.refine_threshold.into(),
        |t, v, _| {
            t.refine_threshold = number_param("refine_threshold", v)?;
            Ok(())
        },
    ),
    Param::script("handle_loop", None, |t, v, ctx| {
        loop_param(t, "handle_loop", v, ctx)
    }),
    Param::script("fixed_loop", None, |t, v, ctx| {
        loop_param(t, "fixed_loop", v, ctx)
    }),
    Param::script("paint_handle", None, |t, v, ctx| {
        paint_param(t, "paint_handle", v, ctx)
    }),
    Param::script("paint_fixed", None, |t, v, ctx| {
        paint_param(t, "paint_fixed", v, ctx)
    }),
    Param::script("erase", None, |t, v, ctx| paint_param(t, "erase", v, ctx)),
    Param::action("clear", "Clear regions", |t, v, ctx| {
        if bool_param("clear", v)? {
            t.clear(ctx);
        }
        Ok(())
    }),
    Param::info("pivot", |t| t.pivot.to_array().to_vec().into()),
];
