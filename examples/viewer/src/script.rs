//! Scripted mode: a JSON list of actions replayed one per frame, for tests and pictures.
//!
//! A script is either a JSON array of actions or an object `{"actions": [...]}`. Each
//! action is an object whose `"action"` field names it; the other fields are its
//! arguments (unknown fields are errors). Paths are relative to the current directory.
//! Angles are in degrees; `x`/`y` screen fractions run from the top-left corner of the
//! 3D view (0, 0) to its bottom-right corner (1, 1); pixel offsets are `dx` to the right
//! and `dy` **down**.
//!
//! | action | fields | effect |
//! |---|---|---|
//! | `load` | `path` | read a mesh (OBJ, PLY), frame it, clear the history; a `.png` opens in the 2-D image view |
//! | `save` | `path` | write the mesh (`.obj`, `.ply`); in the image view the edited picture (`.png`) |
//! | `save_recipe` | `path` | write the edits made since the load (or the hierarchy build) as an edit recipe (TOML, `multires::recipe`) that `multires edit` replays bit for bit; fails, naming them, when edits without a recipe step (FFD, Bendels–Klein refine) or edits before the hierarchy build are in the history |
//! | `screenshot` | `path` | write what the window shows (PNG), panels included |
//! | `orbit` | `yaw`, `pitch` (default 0) | turn the camera around its target |
//! | `zoom` | `factor` | multiply the camera distance (< 1 zooms in) |
//! | `pan` | `dx`, `dy` (pixels, default 0) | move the view as a right-button drag would |
//! | `frame` | — | centre the mesh and fit it to the view, keeping the direction |
//! | `reset_view` | — | frame the mesh from the default direction |
//! | `view` | `shading` (`"flat"`/`"smooth"`), `wireframe`, `up` (`"y"`/`"z"`), all optional | display settings |
//! | `select_tool` | `tool` | activate a tool by name (case-insensitive; a unique prefix is enough) |
//! | `set` | `param`, `value` | set a parameter of the active tool |
//! | `pick_vertex` | `index` | pick vertex `index` (its `vertex_index`, = its number in the file) |
//! | `pick_face` | `index` | pick face `index` (at its centroid) |
//! | `pick_screen` | `x`, `y` | ray-cast at a point of the view, like a click |
//! | `drag` | `vector` `[x, y, z]`, `steps` (default 8), `x`, `y` (optional) | drag the picked vertex (or what a press at `x`, `y` grabs) by a world-space vector |
//! | `drag_screen` | `dx`, `dy` (pixels), `steps` (default 8), `x`, `y` (optional) | drag the picked vertex (or what a press at `x`, `y` grabs) in the view plane, like the mouse |
//! | `apply` | — | the active tool's main action |
//! | `undo` / `redo` | — | one step of the history (in the image view: of the image edit) |
//! | `image_handle` | `points` `[[x, y], …]` | image view: set the handle polygon (pixels, origin top-left, `y` down) |
//! | `image_fixed` | `points` (optional) | image view: everything outside this polygon stays; without `points` (or `null`), the image border |
//! | `image_transform` | `translate` `[dx, dy]` (default `[0, 0]`), `rotate` (degrees, default 0), `scale` (default 1) | image view: **set** the handle transform `T(c + t) R S T(−c)`, `c` the centroid of the handle polygon's points, and show the result (one history step) |
//! | `image_drag` | `dx`, `dy` (pixels), `steps` (default 8) | image view: add `(dx, dy)` to the translation in `steps` moves, as a mouse drag of the handle does (one history step) |
//! | `image_options` | `shape` (`"smoothstep"`, `"linear"`, `"c2"`), `grid_step`, both optional | image view: shape function and grid of the edit |
//! | `clear_colors` | — | back to the base colour |
//! | `wait` | `frames` | render frames without doing anything |
//! | `measure` | `frames` (default 60) | render frames while orbiting slowly, print frame-time statistics |
//! | `quit` | — | stop the script here |
//!
//! A drag starts with a press: at `x`, `y` when given (the mouse ray there goes to the
//! active tool, which may grab something off the mesh, such as an FFD control point),
//! else on the picked point. An action whose tool keeps working in the background (the
//! hierarchy build) holds the next action back until that work is done.
//!
//! The `image_*` actions fail when no image is open. Their values go to the library
//! (`edit::bendels_klein::image`) unchecked: what it refuses (a polygon of fewer than 3 points,
//! regions that overlap or touch, a scale of 0, a grid step of 0) fails the action with
//! its message, and the edit stays as it was.
//!
//! The viewer exits when the script ends (with status 1 and a message if an action
//! failed), unless started with `--keep-open`.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::Deserialize;

use crate::camera::UpAxis;

/// Shading for the `view` action.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Shading {
    /// Face normals.
    Flat,
    /// Vertex normals.
    Smooth,
}

fn default_steps() -> usize {
    8
}

fn default_frames() -> usize {
    60
}

fn default_scale() -> f64 {
    1.0
}

/// One scripted action (see the module docs for the table).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "action", rename_all = "snake_case", deny_unknown_fields)]
pub enum Action {
    /// Read a mesh.
    Load {
        /// The file.
        path: PathBuf,
    },
    /// Write the mesh.
    Save {
        /// The file.
        path: PathBuf,
    },
    /// Write the edits as a recipe (TOML).
    SaveRecipe {
        /// The file.
        path: PathBuf,
    },
    /// Write a PNG of the window.
    Screenshot {
        /// The file.
        path: PathBuf,
    },
    /// Turn the camera.
    Orbit {
        /// Degrees about the up axis.
        #[serde(default)]
        yaw: f64,
        /// Degrees of elevation.
        #[serde(default)]
        pitch: f64,
    },
    /// Scale the camera distance.
    Zoom {
        /// Factor (< 1 zooms in).
        factor: f64,
    },
    /// Pan as a mouse drag of `(dx, dy)` pixels would.
    Pan {
        /// Pixels to the right.
        #[serde(default)]
        dx: f64,
        /// Pixels down.
        #[serde(default)]
        dy: f64,
    },
    /// Fit the mesh in the view.
    Frame,
    /// Default direction, mesh fitted.
    ResetView,
    /// Display settings.
    View {
        /// Flat or smooth.
        #[serde(default)]
        shading: Option<Shading>,
        /// Wireframe overlay.
        #[serde(default)]
        wireframe: Option<bool>,
        /// Up axis.
        #[serde(default)]
        up: Option<UpAxis>,
    },
    /// Activate a tool.
    SelectTool {
        /// Its name (case-insensitive, unique prefix accepted).
        tool: String,
    },
    /// Set a parameter of the active tool.
    Set {
        /// Parameter name.
        param: String,
        /// Value (number, bool, string, array: as the tool wants).
        value: serde_json::Value,
    },
    /// Pick a vertex by index.
    PickVertex {
        /// `vertex_index`.
        index: usize,
    },
    /// Pick a face by index.
    PickFace {
        /// `face_index`.
        index: usize,
    },
    /// Ray-cast at a point of the view.
    PickScreen {
        /// 0 left … 1 right.
        x: f64,
        /// 0 top … 1 bottom.
        y: f64,
    },
    /// Drag the picked vertex (or what a press at `x`, `y` grabs) by a world vector.
    Drag {
        /// Displacement.
        vector: [f64; 3],
        /// Frames over which the drag is spread.
        #[serde(default = "default_steps")]
        steps: usize,
        /// Press here (0 left … 1 right) instead of on the picked point.
        #[serde(default)]
        x: Option<f64>,
        /// Press here (0 top … 1 bottom) instead of on the picked point.
        #[serde(default)]
        y: Option<f64>,
    },
    /// Drag the picked vertex (or what a press at `x`, `y` grabs) by pixels in the view
    /// plane.
    DragScreen {
        /// Pixels right.
        dx: f64,
        /// Pixels down.
        dy: f64,
        /// Frames over which the drag is spread.
        #[serde(default = "default_steps")]
        steps: usize,
        /// Press here (0 left … 1 right) instead of on the picked point.
        #[serde(default)]
        x: Option<f64>,
        /// Press here (0 top … 1 bottom) instead of on the picked point.
        #[serde(default)]
        y: Option<f64>,
    },
    /// The active tool's main action.
    Apply,
    /// Undo one step.
    Undo,
    /// Redo one step.
    Redo,
    /// Base colour.
    ClearColors,
    /// Render frames.
    Wait {
        /// How many.
        frames: usize,
    },
    /// Measure frame times.
    Measure {
        /// How many frames.
        #[serde(default = "default_frames")]
        frames: usize,
    },
    /// Image view: set the handle polygon.
    ImageHandle {
        /// Its points `[x, y]` in pixels.
        points: Vec<[f64; 2]>,
    },
    /// Image view: set the fixed region.
    ImageFixed {
        /// Everything outside this polygon stays (`None`: the image border).
        #[serde(default)]
        points: Option<Vec<[f64; 2]>>,
    },
    /// Image view: set the handle transform.
    ImageTransform {
        /// Translation `[dx, dy]` in pixels (`dy` down).
        #[serde(default)]
        translate: [f64; 2],
        /// Rotation in degrees about the handle's centroid (clockwise on screen).
        #[serde(default)]
        rotate: f64,
        /// Uniform scale about the handle's centroid.
        #[serde(default = "default_scale")]
        scale: f64,
    },
    /// Image view: drag the handle as the mouse does.
    ImageDrag {
        /// Pixels right.
        dx: f64,
        /// Pixels down.
        dy: f64,
        /// Moves.
        #[serde(default = "default_steps")]
        steps: usize,
    },
    /// Image view: shape function and grid.
    ImageOptions {
        /// `smoothstep`, `linear` or `c2`.
        #[serde(default)]
        shape: Option<String>,
        /// Pixels between grid vertices.
        #[serde(default)]
        grid_step: Option<u32>,
    },
    /// Stop the script.
    Quit,
}

impl Action {
    /// The action's name as written in scripts.
    pub fn name(&self) -> &'static str {
        match self {
            Action::Load { .. } => "load",
            Action::Save { .. } => "save",
            Action::SaveRecipe { .. } => "save_recipe",
            Action::Screenshot { .. } => "screenshot",
            Action::Orbit { .. } => "orbit",
            Action::Zoom { .. } => "zoom",
            Action::Pan { .. } => "pan",
            Action::Frame => "frame",
            Action::ResetView => "reset_view",
            Action::View { .. } => "view",
            Action::SelectTool { .. } => "select_tool",
            Action::Set { .. } => "set",
            Action::PickVertex { .. } => "pick_vertex",
            Action::PickFace { .. } => "pick_face",
            Action::PickScreen { .. } => "pick_screen",
            Action::Drag { .. } => "drag",
            Action::DragScreen { .. } => "drag_screen",
            Action::Apply => "apply",
            Action::Undo => "undo",
            Action::Redo => "redo",
            Action::ClearColors => "clear_colors",
            Action::Wait { .. } => "wait",
            Action::Measure { .. } => "measure",
            Action::ImageHandle { .. } => "image_handle",
            Action::ImageFixed { .. } => "image_fixed",
            Action::ImageTransform { .. } => "image_transform",
            Action::ImageDrag { .. } => "image_drag",
            Action::ImageOptions { .. } => "image_options",
            Action::Quit => "quit",
        }
    }
}

/// How a scripted drag moves the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DragTarget {
    /// Total world displacement from the start.
    World(DVec3),
    /// Total pixel offset from the start point's pixel (`dx` right, `dy` down).
    Screen(f64, f64),
}

/// One frame's worth of script work: an action, or a piece of an expanded one.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// A whole action (`drag`, `drag_screen`, `wait` and `measure` are expanded).
    Action {
        /// Index of the action in the script, for messages.
        index: usize,
        /// The action.
        action: Action,
    },
    /// Press on the picked vertex, or at a point of the view.
    DragBegin {
        /// Index of the action in the script.
        index: usize,
        /// Screen fractions `(x, y)` of the press (`None`: on the picked point).
        at: Option<(f64, f64)>,
    },
    /// Move the dragged point.
    DragTo(DragTarget),
    /// Release.
    DragEnd,
    /// Render a frame doing nothing.
    Idle,
    /// Render a frame while orbiting a little, and record its frame time.
    MeasureFrame {
        /// Frames left after this one (0: print the statistics).
        remaining: usize,
    },
}

/// A parse error, naming the action.
#[derive(Debug, thiserror::Error)]
pub enum ScriptError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The script file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// Not JSON, or not an array / `{"actions": [...]}`.
    #[error("{0}")]
    Format(String),
    /// An action could not be parsed.
    #[error("action {index}: {message}")]
    Action {
        /// Index in the script (0-based).
        index: usize,
        /// What is wrong.
        message: String,
    },
}

/// Reads and parses a script file.
pub fn load(path: &Path) -> Result<Vec<Action>, ScriptError> {
    let text = std::fs::read_to_string(path).map_err(|source| ScriptError::Io {
        path: path.to_owned(),
        source,
    })?;
    parse(&text)
}

/// Parses script text (see the module docs).
pub fn parse(text: &str) -> Result<Vec<Action>, ScriptError> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| ScriptError::Format(format!("not JSON: {e}")))?;
    let list = match value {
        serde_json::Value::Array(list) => list,
        serde_json::Value::Object(mut map) => match map.remove("actions") {
            Some(serde_json::Value::Array(list)) if map.is_empty() => list,
            _ => {
                return Err(ScriptError::Format(
                    "a script is an array of actions or {\"actions\": [...]}".into(),
                ))
            }
        },
        _ => {
            return Err(ScriptError::Format(
                "a script is an array of actions or {\"actions\": [...]}".into(),
            ))
        }
    };
    list.into_iter()
        .enumerate()
        .map(|(index, v)| {
            let action = serde_json::from_value::<Action>(v).map_err(|e| ScriptError::Action {
                index,
                message: e.to_string(),
            })?;
            if let Action::Drag { x, y, .. } | Action::DragScreen { x, y, .. } = &action {
                if x.is_some() != y.is_some() {
                    return Err(ScriptError::Action {
                        index,
                        message: format!("{}: give both x and y, or neither", action.name()),
                    });
                }
            }
            Ok(action)
        })
        .collect()
}

/// Expands actions into per-frame steps.
pub fn expand(actions: Vec<Action>) -> VecDeque<Step> {
    let mut steps = VecDeque::new();
    for (index, action) in actions.into_iter().enumerate() {
        match action {
            Action::Drag {
                vector,
                steps: n,
                x,
                y,
            } => {
                let n = n.max(1);
                let v = DVec3::from_array(vector);
                let at = x.zip(y);
                steps.push_back(Step::DragBegin { index, at });
                for k in 1..=n {
                    steps.push_back(Step::DragTo(DragTarget::World(v * (k as f64 / n as f64))));
                }
                steps.push_back(Step::DragEnd);
            }
            Action::DragScreen {
                dx,
                dy,
                steps: n,
                x,
                y,
            } => {
                let n = n.max(1);
                let at = x.zip(y);
                steps.push_back(Step::DragBegin { index, at });
                for k in 1..=n {
                    let f = k as f64 / n as f64;
                    steps.push_back(Step::DragTo(DragTarget::Screen(dx * f, dy * f)));
                }
                steps.push_back(Step::DragEnd);
            }
            Action::Wait { frames } => steps.extend((0..frames).map(|_| Step::Idle)),
            Action::Measure { frames } => {
                let n = frames.max(1);
                // Two frames to settle after whatever came before, then the measured ones.
                steps.extend([Step::Idle, Step::Idle]);
                steps.extend(
                    (0..n)
                        .rev()
                        .map(|remaining| Step::MeasureFrame { remaining }),
                );
            }
            action => steps.push_back(Step::Action { index, action }),
        }
    }
    steps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_documented_actions() {
        let text = r#"{"actions": [
            {"action": "load", "path": "a.obj"},
            {"action": "orbit", "yaw": 30},
            {"action": "zoom", "factor": 0.8},
            {"action": "view", "shading": "flat", "wireframe": true, "up": "z"},
            {"action": "select_tool", "tool": "smooth"},
            {"action": "set", "param": "radius", "value": 0.2},
            {"action": "pick_vertex", "index": 12},
            {"action": "drag", "vector": [0, 0.1, 0], "steps": 2},
            {"action": "drag_screen", "dx": 10, "dy": -5},
            {"action": "undo"},
            {"action": "save", "path": "out.obj"},
            {"action": "screenshot", "path": "out.png"},
            {"action": "measure", "frames": 3},
            {"action": "quit"}
        ]}"#;
        let actions = parse(text).unwrap();
        assert_eq!(actions.len(), 14);
        assert_eq!(
            actions[1],
            Action::Orbit {
                yaw: 30.0,
                pitch: 0.0
            }
        );
        assert_eq!(
            actions[3],
            Action::View {
                shading: Some(Shading::Flat),
                wireframe: Some(true),
                up: Some(UpAxis::Z)
            }
        );
        assert_eq!(
            actions[8],
            Action::DragScreen {
                dx: 10.0,
                dy: -5.0,
                steps: 8,
                x: None,
                y: None
            }
        );
        let steps = expand(actions);
        // load, orbit, zoom, view, select, set, pick = 7; drag = 1 + 2 + 1; drag_screen =
        // 1 + 8 + 1; undo, save, screenshot = 3; measure = 2 + 3; quit = 1.
        assert_eq!(steps.len(), 7 + 4 + 10 + 3 + 5 + 1);
        assert_eq!(steps[7], Step::DragBegin { index: 7, at: None });
        assert_eq!(
            steps[9],
            Step::DragTo(DragTarget::World(DVec3::new(0.0, 0.1, 0.0)))
        );
    }

    #[test]
    fn drags_may_press_at_a_point_of_the_view() {
        let actions = parse(
            r#"[{"action": "drag_screen", "x": 0.9, "y": 0.25, "dx": 0, "dy": -20, "steps": 2}]"#,
        )
        .unwrap();
        let steps = expand(actions);
        assert_eq!(
            steps[0],
            Step::DragBegin {
                index: 0,
                at: Some((0.9, 0.25))
            }
        );
        assert_eq!(steps.len(), 4);
        let err = parse(r#"[{"action": "drag", "vector": [0, 0, 1], "x": 0.5}]"#).unwrap_err();
        assert!(err.to_string().contains("both x and y"), "{err}");
    }

    #[test]
    fn parses_the_image_actions() {
        let actions = parse(
            r#"[
            {"action": "load", "path": "in.png"},
            {"action": "image_handle", "points": [[10, 10], [20, 10], [15, 20]]},
            {"action": "image_fixed"},
            {"action": "image_fixed", "points": [[0, 0], [50, 0], [50, 50]]},
            {"action": "image_transform", "translate": [3, -2]},
            {"action": "image_transform", "rotate": 15, "scale": 1.5},
            {"action": "image_drag", "dx": 4, "dy": 5},
            {"action": "image_options", "shape": "c2", "grid_step": 2}
        ]"#,
        )
        .unwrap();
        assert_eq!(actions.len(), 8);
        assert_eq!(
            actions[1],
            Action::ImageHandle {
                points: vec![[10.0, 10.0], [20.0, 10.0], [15.0, 20.0]]
            }
        );
        assert_eq!(actions[2], Action::ImageFixed { points: None });
        assert_eq!(
            actions[4],
            Action::ImageTransform {
                translate: [3.0, -2.0],
                rotate: 0.0,
                scale: 1.0
            }
        );
        assert_eq!(
            actions[5],
            Action::ImageTransform {
                translate: [0.0, 0.0],
                rotate: 15.0,
                scale: 1.5
            }
        );
        assert_eq!(
            actions[6],
            Action::ImageDrag {
                dx: 4.0,
                dy: 5.0,
                steps: 8
            }
        );
        assert_eq!(actions[7].name(), "image_options");
        // One frame each: nothing is expanded.
        assert_eq!(expand(actions).len(), 8);
        let err = parse(r#"[{"action": "image_handle", "points": [[1, 2, 3]]}]"#).unwrap_err();
        assert!(err.to_string().starts_with("action 0:"), "{err}");
    }

    #[test]
    fn a_plain_array_is_a_script() {
        assert_eq!(
            parse(r#"[{"action": "frame"}]"#).unwrap(),
            vec![Action::Frame]
        );
    }

    #[test]
    fn errors_name_the_action() {
        let err = parse(r#"[{"action": "frame"}, {"action": "zoom", "factr": 2}]"#).unwrap_err();
        let msg = err.to_string();
        assert!(msg.starts_with("action 1:"), "{msg}");
        let err = parse(r#"[{"action": "fly"}]"#).unwrap_err();
        assert!(err.to_string().contains("fly"), "{err}");
        assert!(parse("{}").is_err());
        assert!(parse("not json").is_err());
    }
}
