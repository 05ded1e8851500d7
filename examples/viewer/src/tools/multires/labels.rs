//! The sub-mesh labels of the *Multiresolution* tool: the label attribute's values, the
//! colour layer, the frontier drawn, and the cuts that make them.

use super::*;

/// Label of the host (the part outside the sub-mesh).
pub const HOST: u32 = 0;
/// Label of the sub-mesh.
pub const SUBMESH: u32 = 1;

/// Colour of the frontier segments.
const FRONTIER_COLOR: Rgba = [255, 220, 40, 255];

/// Sub-mesh labels of a mesh, read from its label attribute
/// ([`halfedge::labels::LABEL_ATTRIBUTE`], the one place they are stored): one label per
/// vertex slot ([`HOST`], [`SUBMESH`] or [`FRONTIER`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SubMeshLabels {
    /// Label per vertex slot (dead slots: [`NO_LABEL`], which is also [`FRONTIER`]'s
    /// value: ask [`is_live`](Self::is_live)).
    pub labels: Vec<u32>,
    /// Live slots.
    live: Vec<bool>,
}

impl SubMeshLabels {
    /// The labels of `mesh`, if it has a label attribute.
    pub fn of(mesh: &Mesh) -> Option<Self> {
        let attribute = mesh.find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE)?;
        let mut live = vec![false; mesh.vertex_slots()];
        for v in mesh.vertices() {
            live[mesh.vertex_index(v)] = true;
        }
        Some(Self {
            labels: read_labels(mesh, attribute),
            live,
        })
    }

    /// True when vertex slot `i` is live.
    pub fn is_live(&self, i: usize) -> bool {
        self.live.get(i).copied().unwrap_or(false)
    }

    /// A summary: vertices per part.
    pub fn description(&self) -> String {
        let (host, sub, front) = self.counts();
        format!(
            "sub-mesh {} · host {} · frontier {} vertices",
            group(sub),
            group(host),
            group(front)
        )
    }

    /// The sub-mesh as a mask per vertex slot: the sub-mesh and its frontier (the frontier
    /// vertices are shared by the sub-mesh and the host, section 4.1).
    pub fn inside_mask(&self) -> Vec<bool> {
        self.labels
            .iter()
            .zip(&self.live)
            .map(|(&l, &live)| live && (l == SUBMESH || l == FRONTIER))
            .collect()
    }

    /// Number of vertices per label `(host, sub-mesh, frontier)`.
    pub fn counts(&self) -> (usize, usize, usize) {
        let mut c = (0, 0, 0);
        for (&l, _) in self.labels.iter().zip(&self.live).filter(|(_, &live)| live) {
            match l {
                HOST => c.0 += 1,
                SUBMESH => c.1 += 1,
                FRONTIER => c.2 += 1,
                _ => {}
            }
        }
        c
    }

    /// Labels for display: host 0, sub-mesh 1, frontier 2.
    pub fn display_labels(&self) -> Vec<u32> {
        self.labels
            .iter()
            .zip(&self.live)
            .map(|(&l, &live)| match l {
                _ if !live => NO_LABEL,
                HOST => 0,
                SUBMESH => 1,
                FRONTIER => 2,
                _ => NO_LABEL,
            })
            .collect()
    }

    /// The colour layer of these labels (named [`LABEL_LAYER`]).
    pub fn layer(&self) -> ColorLayer {
        ColorLayer::Labels(LabelField {
            name: LABEL_LAYER.into(),
            target: LabelTarget::Vertices,
            labels: self.display_labels(),
            legend: vec![
                (0, "host".into()),
                (1, "sub-mesh".into()),
                (2, "frontier".into()),
            ],
        })
    }

    /// Colours the mesh by these labels.
    pub fn show(&self, ctx: &mut ToolContext<'_>) {
        ctx.display.set(self.layer());
    }
}

/// Name of the colour layer of the sub-mesh labels.
pub const LABEL_LAYER: &str = "sub-mesh labels";

/// The colour layer `layer` should become after the mesh's labels changed (a level
/// change, undo, redo): the labels read again from `mesh` when `layer` shows the sub-mesh
/// labels (none left: the base colour); `None` for any other layer, which stays.
pub fn refreshed_label_layer(layer: &ColorLayer, mesh: &Mesh) -> Option<ColorLayer> {
    if layer.name() != Some(LABEL_LAYER) {
        return None;
    }
    Some(SubMeshLabels::of(mesh).map_or(ColorLayer::None, |l| l.layer()))
}

/// The frontier edges of `mesh`'s labels (both ends on the frontier) as segments.
pub fn frontier_overlay(mesh: &Mesh, overlay: &mut Overlay) {
    let Some(attribute) = mesh.find_attribute::<VertexId, Label>(LABEL_ATTRIBUTE) else {
        return;
    };
    let labels = mesh.attribute_values(attribute).unwrap();
    for e in mesh.edges() {
        let (a, b) = (mesh.from_vertex(e), mesh.to_vertex(e));
        if labels[mesh.vertex_index(a)] == FRONTIER && labels[mesh.vertex_index(b)] == FRONTIER {
            overlay.segment(mesh.position(a), mesh.position(b), FRONTIER_COLOR);
        }
    }
}

/// How the sub-mesh frontier is made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrontierMode {
    /// (a) Picked vertices joined into a closed loop.
    Loop,
    /// (b) The collar of faces around the loop through the picked vertices.
    Collar,
    /// (c) A cutting plane through the picked point.
    Plane,
}

impl FrontierMode {
    pub(super) const ALL: [(FrontierMode, &'static str); 3] = [
        (FrontierMode::Loop, "loop"),
        (FrontierMode::Collar, "collar"),
        (FrontierMode::Plane, "plane"),
    ];
    pub(super) fn name(self) -> &'static str {
        choice_name(&Self::ALL, self)
    }
}

/// The normal of the cutting plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlaneNormal {
    /// World x.
    X,
    /// World y.
    Y,
    /// World z.
    Z,
    /// The viewing direction at the time of the pick.
    View,
}

impl PlaneNormal {
    pub(super) const ALL: [(PlaneNormal, &'static str); 4] = [
        (PlaneNormal::X, "x"),
        (PlaneNormal::Y, "y"),
        (PlaneNormal::Z, "z"),
        (PlaneNormal::View, "view"),
    ];
    pub(super) fn name(self) -> &'static str {
        choice_name(&Self::ALL, self)
    }
    pub(super) fn vector(self, view: &ViewInfo) -> DVec3 {
        match self {
            PlaneNormal::X => DVec3::X,
            PlaneNormal::Y => DVec3::Y,
            PlaneNormal::Z => DVec3::Z,
            PlaneNormal::View => view.forward,
        }
    }
}

/// What a cut of the mesh into sub-mesh and host is made from.
pub(super) struct Cut<'a> {
    pub(super) frontier: FrontierMode,
    pub(super) picks: &'a [VertexId],
    pub(super) plane: Option<(DVec3, DVec3)>,
    pub(super) flip: bool,
}

impl Cut<'_> {
    /// Makes the frontier and labels the two sides in `mesh`'s label attribute; returns
    /// the collar (collar mode) and a description.
    pub(super) fn label(&self, mesh: &mut Mesh) -> Result<(Vec<FaceId>, String), ToolError> {
        let mut collar = Vec::new();
        let frontier = match self.frontier {
            FrontierMode::Loop => {
                if self.picks.len() < 3 {
                    return Err(ToolError::new(format!(
                        "a loop needs at least 3 picked vertices ({} so far)",
                        self.picks.len()
                    )));
                }
                mesh.frontier_through(self.picks)?
            }
            FrontierMode::Collar => {
                if self.picks.len() < 3 {
                    return Err(ToolError::new(format!(
                        "a collar needs at least 3 picked vertices ({} so far)",
                        self.picks.len()
                    )));
                }
                let path = mesh.closed_loop_through(self.picks)?;
                let mut seen = vec![false; mesh.face_slots()];
                for &e in &path {
                    for f in mesh.adjacent_faces(mesh.from_vertex(e)) {
                        if !std::mem::replace(&mut seen[mesh.face_index(f)], true) {
                            collar.push(f);
                        }
                    }
                }
                mesh.frontier_from_collar(&collar)?
            }
            FrontierMode::Plane => {
                let (point, normal) = self
                    .plane
                    .ok_or_else(|| ToolError::new("pick a point of the cutting plane"))?;
                mesh.frontier_from_plane(point, normal)?
            }
        };
        let (attribute, mut counts) = mesh.label_sides(&frontier, SUBMESH, HOST)?;
        let mut swap = match (self.frontier, self.plane) {
            (FrontierMode::Plane, Some((point, normal))) => {
                // The sub-mesh is on the normal's side of the plane.
                let values = mesh.attribute_values(attribute).unwrap();
                let side: f64 = mesh
                    .vertices()
                    .filter(|&v| values[mesh.vertex_index(v)] == SUBMESH)
                    .map(|v| (mesh.position(v) - point).dot(normal))
                    .sum();
                side < 0.0
            }
            _ => counts.left_vertices > counts.right_vertices,
        };
        swap ^= self.flip;
        if swap {
            (_, counts) = mesh.label_sides(&frontier, HOST, SUBMESH)?;
        }
        let (sub, host) = if swap {
            (counts.right_vertices, counts.left_vertices)
        } else {
            (counts.left_vertices, counts.right_vertices)
        };
        let description = format!(
            "{} frontier of {} edges: sub-mesh {} vertices, host {}, frontier {}",
            self.frontier.name(),
            frontier.halfedges().len(),
            group(sub),
            group(host),
            group(counts.frontier_vertices)
        );
        Ok((collar, description))
    }
}

pub(super) fn method_name(m: Method) -> &'static str {
    match m {
        Method::Rounds => "rounds",
        Method::Qem => "QEM",
    }
}

/// The labels of the live vertices ([`NO_LABEL`] for dead slots).
pub(super) fn read_labels(mesh: &Mesh, attribute: halfedge::Attribute<VertexId, u32>) -> Vec<u32> {
    let values = mesh.attribute_values(attribute).unwrap();
    let mut labels = vec![NO_LABEL; mesh.vertex_slots()];
    for v in mesh.vertices() {
        let i = mesh.vertex_index(v);
        labels[i] = values[i];
    }
    labels
}
