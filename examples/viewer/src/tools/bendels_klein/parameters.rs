//! What the parameter table of the *Bendels–Klein* tool (see [`params`](super::params))
//! calls: the handle-transform setter, the script-only loop and paint setters, the
//! distance choices.

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
