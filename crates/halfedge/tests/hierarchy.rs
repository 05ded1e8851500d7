//! The progressive hierarchy: exact round trips, level sizes, walking, detail
//! coefficients carrying coarse edits.

mod common;

use common::{load, snapshot};
use halfedge::{Hierarchy, HierarchyOptions};

#[test]
fn explore() {
    for name in ["nefertiti.obj"] {
        for (deg, flip) in [(45.0f64, 20.0f64), (45.0, 45.0), (60.0, 30.0), (90.0, 30.0), (90.0, 45.0)] {
            let mut opts = HierarchyOptions::rounds().with_max_normal_deviation(deg.to_radians());
            opts.max_flip_angle = flip.to_radians();
            let mesh = load(name);
            let before = snapshot(&mesh);
            let t = std::time::Instant::now();
            let mut h = Hierarchy::build(mesh, &opts.clone().with_target_faces(200)).unwrap();
            let tb = t.elapsed();
            h.mesh().check().unwrap();
            let t = std::time::Instant::now();
            h.refine_to(0).unwrap();
            let tr = t.elapsed();
            h.mesh().check().unwrap();
            let same = snapshot(h.mesh()) == before;
            println!("{name} {deg} {flip} {:?} {:?} build {tb:?} refine {tr:?} identical {same}", opts.method, h.level_face_counts());
        }
    }
}
