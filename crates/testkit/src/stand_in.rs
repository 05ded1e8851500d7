//! The default tier's stand-ins for the shared real meshes: small meshes of `data/` (or
//! made from them) with the character a test relies on, so that a test written once as
//! `test_with(load: &dyn Fn(&str) -> Mesh)` runs on a stand-in by default and on the real
//! mesh in the `#[ignore]`d real-mesh tier ([`crate::load_shared`]).
//!
//! Each name means one mesh. What a test needs of a shared mesh decides the table it takes
//! its stand-ins from: [`by_topology`] (the kernel's tests: closed or open, genus,
//! components, defects) or [`by_shape`] (the editing tests: where Spot's snout, the
//! bunny's ear and head are).

use glam::DVec3;
use halfedge::Mesh;

use crate::data;

/// `data/blob.obj`: an icosphere displaced by smooth waves — closed, genus 0, one
/// component, 20,480 triangles.
pub fn blob() -> Mesh {
    data("blob.obj")
}

/// `data/creature.obj`: a bumpy head (closed, genus 0) with two ears up (+y) and a snout
/// to the front (+z), and two eyes that are separate spheres — three components, 5,760
/// triangles.
pub fn creature() -> Mesh {
    data("creature.obj")
}

/// `data/cup.obj`: a sphere with its bottom cut away and two holes in its side — open,
/// three ragged boundary loops, 3,885 triangles.
pub fn cup() -> Mesh {
    data("cup.obj")
}

/// `data/torus.obj`: a bumpy torus around the z axis — closed, genus 1, 1,920 triangles.
pub fn torus() -> Mesh {
    data("torus.obj")
}

/// `data/dirty.obj` as the reader welds it: quads, a pentagon, a non-manifold fin, a
/// bow-tie vertex, a duplicated face, a degenerate face and unreferenced vertices.
pub fn dirty() -> Mesh {
    data("dirty.obj")
}

/// `data/patch.ply`: a binary little-endian PLY of an open 40 × 30 grid with a bump — one
/// boundary loop.
pub fn patch() -> Mesh {
    data("patch.ply")
}

/// The stand-in with the same topological character as the shared mesh `name`: `spot`
/// (closed, genus 0) → [`blob`]; `stanford-bunny` (holes) and `teapot` (boundary loops) →
/// [`cup`]; `cow` and `fandisk` (several components) → [`creature`]; `nefertiti` →
/// [`torus`] (closed, genus 1); `suzanne`, `beast` (quads, non-manifold) → [`dirty`];
/// `horse.ply` → [`patch`] (binary PLY).
///
/// # Panics
/// For a shared mesh without a stand-in.
pub fn by_topology(name: &str) -> Mesh {
    match name {
        "spot.obj" => blob(),
        "stanford-bunny.obj" | "teapot.obj" => cup(),
        "cow.obj" | "fandisk.obj" => creature(),
        "nefertiti.obj" => torus(),
        "suzanne.obj" | "beast.obj" => dirty(),
        "horse.ply" => patch(),
        other => panic!("no stand-in by topology for {other}"),
    }
}

/// The stand-in with the same shape where the editing tests look, for the shared mesh
/// `name`: `spot` (closed, a snout along +z) → [`creature`] (a snout as pointed as Spot's,
/// and separate eyes); `stanford-bunny` → [`bunny_in_box`]`(2)` (ear and head where the
/// bunny has them); `cow` → [`torus`] (a second mesh with nothing the tests look at).
///
/// # Panics
/// For a shared mesh without a stand-in.
pub fn by_shape(name: &str) -> Mesh {
    match name {
        "spot.obj" => creature(),
        "stanford-bunny.obj" => bunny_in_box(2),
        "cow.obj" => torus(),
        other => panic!("no stand-in by shape for {other}"),
    }
}

/// The creature subdivided 1-to-4 `times` times, turned to look along −x as the bunny
/// does (`(x, y, z) → (−z, y, x)`).
fn creature_facing_minus_x(times: usize) -> Mesh {
    let mut mesh = creature();
    for _ in 0..times {
        mesh = halfedge::generators::subdivide(&mesh);
    }
    for p in mesh.positions_mut() {
        *p = DVec3::new(-p.z, p.y, p.x);
    }
    mesh
}

/// The Stanford bunny's stand-in for region edits: [`creature`] (ears up, snout along +z)
/// subdivided `times` times (twice: 92,160 faces, the bunny's density), turned to look
/// along −x as the bunny does, and placed in the bunny's bounding box (same centre and
/// diagonal), so that the bunny's regions — the ear above `y = 0.16`, the head at
/// `x < −0.04`, `y > 0.09` ([`crate::regions::bunny_ear`], [`crate::regions::bunny_head`])
/// — are the creature's ear and head.
pub fn bunny_in_box(times: usize) -> Mesh {
    let mut mesh = creature_facing_minus_x(times);
    let (lo, hi) = mesh.bounding_box().expect("the creature has vertices");
    let (bunny_lo, bunny_hi) = (
        DVec3::new(-0.0947, 0.0330, -0.0619),
        DVec3::new(0.0610, 0.1873, 0.0588),
    );
    let scale = bunny_lo.distance(bunny_hi) / lo.distance(hi);
    let (from, to) = (0.5 * (lo + hi), 0.5 * (bunny_lo + bunny_hi));
    for p in mesh.positions_mut() {
        *p = to + scale * (*p - from);
    }
    mesh
}

/// The Stanford bunny's stand-in for the nose and ear pulls of Bendels & Klein (Fig. 7
/// and 8): [`creature`] subdivided twice (92,160 faces, the bunny's density), turned to
/// look along −x as the bunny does, and scaled about the origin a little below the
/// bunny's size (bounding-box diagonal 0.225, the bunny's is 0.25: the creature's snout is
/// slimmer than the bunny's nose).
pub fn bunny_at_origin() -> Mesh {
    let mut mesh = halfedge::generators::subdivide(&halfedge::generators::subdivide(&creature()));
    let (lo, hi) = mesh.bounding_box().expect("the creature has vertices");
    let scale = 0.225 / lo.distance(hi);
    for p in mesh.positions_mut() {
        *p = scale * DVec3::new(-p.z, p.y, p.x);
    }
    mesh
}
