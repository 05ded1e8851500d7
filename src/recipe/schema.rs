//! The recipe's TOML schema (serde types). Every table refuses unknown keys.

use serde::{Deserialize, Serialize};

use super::{RecipeError, RecipeResult};

/// The recipe format this program reads and writes.
pub const RECIPE_VERSION: u32 = 1;

fn one() -> u32 {
    1
}

/// A recipe: what to simplify (for a plain mesh) and the editing steps, in order.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recipe {
    /// The recipe format ([`RECIPE_VERSION`]).
    #[serde(default = "one")]
    pub version: u32,
    /// How a plain mesh is simplified before the steps (`multires batch`); a saved
    /// hierarchy keeps its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hierarchy: Option<HierarchySpec>,
    /// The steps, applied in order.
    #[serde(default, rename = "step", skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<Step>,
}

/// How to build the hierarchy of a plain mesh.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HierarchySpec {
    /// `rounds` (the paper's, default) or `qem`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<String>,
    /// Stop at this many faces (default 2,000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_faces: Option<usize>,
    /// Detail coefficients: `local` (local frames, default) or `translation` (the seed
    /// paper's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub detail: Option<String>,
    /// The bound on a face normal's turn in one collapse, in degrees (default: the
    /// method's, `HierarchyOptions::max_normal_deviation`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_normal_deviation: Option<f64>,
}

/// A vertex given in terms that carry over between meshes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Place {
    /// The vertex nearest to a point (ties: the lowest index).
    Nearest([f64; 3]),
    /// The vertex furthest along an axis: `+x`, `-x`, `+y`, `-y`, `+z`, `-z`.
    Extreme(String),
    /// The vertex of this index in the mesh the step is made on (exact, not portable).
    Vertex(usize),
}

/// A set of vertices given in terms that carry over between meshes. Radii are fractions
/// of the bounding-box diagonal of the mesh the step is made on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Region {
    /// About `vertices` vertices around a place, grown in rings (Lee's disk-shaped
    /// editing area).
    Disk {
        /// The centre.
        around: Place,
        /// About how many vertices.
        vertices: usize,
    },
    /// The vertices within an edge-path distance of a place.
    Ball {
        /// The centre.
        around: Place,
        /// The radius, as a fraction of the diagonal.
        radius: f64,
    },
    /// The vertices farther than an edge-path distance from a place (and those it does
    /// not reach): a Bendels & Klein fixed region around a handle.
    Beyond {
        /// The centre.
        around: Place,
        /// The radius, as a fraction of the diagonal.
        radius: f64,
    },
    /// The workflow's sub-mesh rule: the part cut off by a plane perpendicular to `axis`
    /// at `at` of the mesh's extent along it (a closed frontier; labelled).
    Cut {
        /// `+x`, `-x`, `+y`, `-y`, `+z` or `-z`: the part furthest along it.
        axis: String,
        /// The plane's height as a fraction of the extent, in `[0, 1)`.
        at: f64,
    },
    /// The part on the side a plane's normal points to, cut along the plane's section
    /// (a closed frontier; labelled).
    Plane {
        /// A point of the plane.
        point: [f64; 3],
        /// Its normal (towards the part).
        normal: [f64; 3],
    },
    /// The vertices with this sub-mesh label (the mesh's label attribute).
    Label {
        /// The label.
        label: u32,
    },
    /// These vertex indices of the mesh the step is made on (exact, not portable).
    Vertices {
        /// The indices.
        indices: Vec<u32>,
    },
    /// Every vertex with a face.
    All,
    /// The area bounded by the closed loop of shortest edge paths through these places,
    /// in order (the last joined to the first), on its side of smaller surface area: a
    /// Lee editing area given by its boundary picks, as the viewer makes one (the picks
    /// also place the area's embedding onto the rectangle). For other methods, the
    /// area's vertices.
    Loop {
        /// The picks, at least 3.
        through: Vec<Place>,
    },
}

/// A rotation for a Bendels & Klein handle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rotate {
    /// The axis direction.
    pub axis: [f64; 3],
    /// The angle in degrees (counter-clockwise about the axis).
    pub degrees: f64,
    /// The centre of the rotation (and of `scale`); default: the handle's place.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f64; 3]>,
}

/// A 4×4 affine matrix by rows (the last row `0, 0, 0, 1`).
pub type Matrix = [[f64; 4]; 4];

/// How a taper's or twist's strength varies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Variation {
    /// Ramps over the frontier distance levels of the sub-mesh (the paper's).
    Levels,
    /// The same everywhere.
    Uniform,
    /// Ramps along the axis from `start` to `end` (axial coordinates).
    Along {
        /// Where the ramp starts.
        start: f64,
        /// Where it reaches full strength.
        end: f64,
    },
}

/// How a sub-mesh edit fades over its propagation collars.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Falloff {
    /// Linearly (the paper's).
    #[default]
    Linear,
    /// Smoothly (C¹).
    Smooth,
}

/// A sub-mesh axis: a point and a direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisSpec {
    /// A point on the axis.
    pub point: [f64; 3],
    /// Its direction.
    pub direction: [f64; 3],
}

/// One editing step: a method, the level it is made at, its region and parameters.
// A recipe holds a handful of steps, read once: boxing the larger variants would only
// make them harder to build and match.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "method", rename_all = "snake_case")]
pub enum Step {
    /// Lee 1999: an editing area embedded by a harmonic map, its primitive dragged and
    /// the drag spread by multilevel B-splines at scale `s`.
    LeeDrag(LeeDrag),
    /// Bendels & Klein: a handle moved by an affine map, a fixed region, and the blend
    /// `exp(α log A)` between them.
    Blend(Blend),
    /// A sub-mesh pulled along a vector.
    Pull(Pull),
    /// A sub-mesh scaled about a centre.
    Scale(Scale),
    /// A sub-mesh rotated about an axis.
    Rotate(RotateStep),
    /// A sub-mesh tapered (Barr).
    Taper(Taper),
    /// A sub-mesh twisted (Barr).
    Twist(Twist),
    /// Taubin λ|μ smoothing of a region and its collar.
    Smooth(Smooth),
}

/// What every step has: the level it is made at.
fn no_level() -> Option<usize> {
    None
}

/// [`Step::LeeDrag`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LeeDrag {
    /// The hierarchy level (clamped to the coarsest; none: the current level).
    #[serde(default = "no_level", skip_serializing_if = "Option::is_none")]
    pub level: Option<usize>,
    /// The editing area (a disk, ball or vertex set that is a topological disk).
    pub area: Region,
    /// The primitive's vertices (default: the area's centre).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub primitive: Vec<Place>,
    /// The drag in model units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pull: Option<[f64; 3]>,
    /// The drag along the primitive's first vertex normal, as a fraction of the diagonal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub along_normal: Option<f64>,
    /// Lee's scale parameter `s` in `[0, 1]` (default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Local frames: `global` (default) or `normal`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frames: Option<String>,
}

/// [`Step::Blend`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Blend {
    /// The hierarchy level (clamped to the coarsest; none: the current level).
    #[serde(default = "no_level", skip_serializing_if = "Option::is_none")]
    pub level: Option<usize>,
    /// The handle.
    pub handle: Region,
    /// The fixed region.
    pub fixed: Region,
    /// The handle's affine map, exactly (by rows); else made of `scale`, `rotate` and
    /// `translate`, in that order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<Matrix>,
    /// A rotation about an axis through the centre.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotate: Option<Rotate>,
    /// A uniform scale about the centre.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// A translation in model units, after the rotation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translate: Option<[f64; 3]>,
    /// `geodesic` (default) or `euclidean` distances.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance: Option<String>,
    /// The shape function: `smoothstep` (default), `linear` or `smootherstep`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<String>,
}

macro_rules! submesh_step {
    ($(#[$doc:meta])* $name:ident { $($(#[$fdoc:meta])* $field:ident : $ty:ty),* $(,)? }) => {
        $(#[$doc])*
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            /// The hierarchy level (clamped to the coarsest; none: the current level).
            #[serde(default = "no_level", skip_serializing_if = "Option::is_none")]
            pub level: Option<usize>,
            /// The sub-mesh.
            pub region: Region,
            /// Propagation levels: collars of faces beyond the frontier the edit fades
            /// over (0: nothing outside moves).
            #[serde(default)]
            pub propagation: usize,
            /// How it fades over them.
            #[serde(default)]
            pub falloff: Falloff,
            $($(#[$fdoc])* pub $field: $ty,)*
        }
    };
}

submesh_step!(
    /// [`Step::Pull`].
    Pull {
        /// The translation in model units.
        offset: [f64; 3],
    }
);
submesh_step!(
    /// [`Step::Scale`].
    Scale {
        /// The factor.
        factor: f64,
        /// The centre (default: the sub-mesh's centroid).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        centre: Option<[f64; 3]>,
    }
);
submesh_step!(
    /// [`Step::Rotate`].
    RotateStep {
        /// The angle in degrees.
        degrees: f64,
        /// The axis (default: the normal of the plane fitted to the frontier, through its
        /// centroid).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis: Option<AxisSpec>,
        /// Keep every vertex on its side of the frontier's plane.
        #[serde(default)]
        bounded: bool,
    }
);
submesh_step!(
    /// [`Step::Taper`].
    Taper {
        /// The factor at full strength.
        factor: f64,
        /// The axis (default: the sub-mesh's own).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis: Option<AxisSpec>,
        /// How the strength varies (default: by levels).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        variation: Option<Variation>,
    }
);
submesh_step!(
    /// [`Step::Twist`].
    Twist {
        /// The angle at full strength, in degrees.
        degrees: f64,
        /// The axis (default: the sub-mesh's own).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        axis: Option<AxisSpec>,
        /// How the strength varies (default: by levels).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        variation: Option<Variation>,
    }
);

/// [`Step::Smooth`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Smooth {
    /// The hierarchy level (clamped to the coarsest; none: the current level).
    #[serde(default = "no_level", skip_serializing_if = "Option::is_none")]
    pub level: Option<usize>,
    /// The region smoothed (with its collar).
    pub region: Region,
    /// Rings of faces beyond the region that smooth too (default 1).
    #[serde(default = "default_collar")]
    pub collar: usize,
    /// λ|μ pairs (default 10).
    #[serde(default = "default_iterations")]
    pub iterations: usize,
    /// λ (default 0.5).
    #[serde(default = "default_lambda")]
    pub lambda: f64,
    /// μ (default −0.53).
    #[serde(default = "default_mu")]
    pub mu: f64,
    /// The Laplacian's weights: `uniform` (default) or `cotangent`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<String>,
}

fn default_collar() -> usize {
    1
}
fn default_iterations() -> usize {
    10
}
fn default_lambda() -> f64 {
    0.5
}
fn default_mu() -> f64 {
    -0.53
}

impl Step {
    /// The method's name, as the recipe writes it.
    #[must_use]
    pub fn method(&self) -> &'static str {
        match self {
            Step::LeeDrag(_) => "lee_drag",
            Step::Blend(_) => "blend",
            Step::Pull(_) => "pull",
            Step::Scale(_) => "scale",
            Step::Rotate(_) => "rotate",
            Step::Taper(_) => "taper",
            Step::Twist(_) => "twist",
            Step::Smooth(_) => "smooth",
        }
    }

    /// The level the step is made at (none: the current level).
    #[must_use]
    pub fn level(&self) -> Option<usize> {
        match self {
            Step::LeeDrag(s) => s.level,
            Step::Blend(s) => s.level,
            Step::Pull(s) => s.level,
            Step::Scale(s) => s.level,
            Step::Rotate(s) => s.level,
            Step::Taper(s) => s.level,
            Step::Twist(s) => s.level,
            Step::Smooth(s) => s.level,
        }
    }
}

/// The kinds of step (for listings and messages).
pub type StepKind = &'static str;

impl Recipe {
    /// Parses a recipe from TOML text; `path` names it in errors.
    ///
    /// # Errors
    /// [`RecipeError::Parse`] for TOML that is not a recipe (naming the step, the key,
    /// the line and the column), [`RecipeError::Version`] for another version.
    pub fn from_toml(text: &str, path: &std::path::Path) -> RecipeResult<Self> {
        let parse = |message: String| RecipeError::Parse {
            path: path.to_owned(),
            message,
        };
        // TOML syntax first (located by line and column), then the version, then the
        // top-level keys, then each step on its own so that errors name it.
        let mut table: toml::Table =
            toml::from_str(text).map_err(|e| parse(describe_toml_error(text, &e)))?;
        let version = match table.get("version") {
            None => 1,
            Some(toml::Value::Integer(v)) => u32::try_from(*v).unwrap_or(u32::MAX),
            Some(other) => {
                return Err(parse(format!(
                    "version: expected an integer, found {}",
                    other.type_str()
                )))
            }
        };
        if version != RECIPE_VERSION {
            return Err(RecipeError::Version {
                found: version,
                supported: RECIPE_VERSION,
            });
        }
        let steps = match table.remove("step") {
            None => Vec::new(),
            Some(toml::Value::Array(steps)) => steps,
            Some(other) => {
                return Err(parse(format!(
                    "step: expected a list of [[step]] tables, found {}",
                    other.type_str()
                )))
            }
        };
        let mut recipe: Recipe = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| parse(e.message().trim().to_owned()))?;
        let headers: Vec<usize> = text
            .lines()
            .enumerate()
            .filter(|(_, l)| l.trim_start().starts_with("[[step]]"))
            .map(|(i, _)| i + 1)
            .collect();
        for (k, step) in steps.into_iter().enumerate() {
            let step: Step = step.try_into().map_err(|e: toml::de::Error| {
                let place = headers
                    .get(k)
                    .map_or(String::new(), |line| format!(" (line {line})"));
                parse(format!("step {}{place}: {}", k + 1, e.message().trim()))
            })?;
            recipe.steps.push(step);
        }
        Ok(recipe)
    }

    /// Reads a recipe file.
    ///
    /// # Errors
    /// [`RecipeError::Io`] when the file cannot be read (or is larger than 16 MiB), and
    /// those of [`from_toml`](Self::from_toml).
    pub fn read(path: &std::path::Path) -> RecipeResult<Self> {
        let io = |source| RecipeError::Io {
            path: path.to_owned(),
            source,
        };
        let len = std::fs::metadata(path).map_err(io)?.len();
        if len > 1 << 24 {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("{len} bytes: a recipe is at most 16 MiB"),
            )));
        }
        let bytes = std::fs::read(path).map_err(io)?;
        let text = String::from_utf8_lossy(&bytes);
        Self::from_toml(&text, path)
    }

    /// The recipe as TOML text (every `f64` with the digits that give it back exactly).
    #[must_use]
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_else(|e| format!("# not serializable: {e}\n"))
    }

    /// Writes the recipe as TOML.
    ///
    /// # Errors
    /// [`RecipeError::Io`] when the file cannot be written.
    pub fn write(&self, path: &std::path::Path) -> RecipeResult<()> {
        std::fs::write(path, self.to_toml()).map_err(|source| RecipeError::Io {
            path: path.to_owned(),
            source,
        })
    }
}

/// The TOML parser's message, with the step (from 1) when the error is inside one.
fn describe_toml_error(text: &str, e: &toml::de::Error) -> String {
    let mut message = e.message().trim().to_owned();
    if let Some(span) = e.span() {
        let before = &text[..span.start.min(text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
        let through = &text[..(span.start + "[[step]]".len()).min(text.len())];
        let step = through.matches("[[step]]").count();
        let key = text[span.start.min(text.len())..span.end.min(text.len())]
            .lines()
            .next()
            .unwrap_or("")
            .trim();
        let place = if step > 0 {
            format!("step {step}, ")
        } else {
            String::new()
        };
        message = format!("{place}line {line}, column {column} (at `{key}`): {message}");
    }
    message
}
