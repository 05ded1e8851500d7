//! The edits' misuse suite (issue 14): every public entry point that edits a mesh (or
//! builds what edits one) is called with hostile arguments — NaN, infinities, 1e308,
//! subnormals, zero and huge counts, handles of other meshes or removed vertices, arrays
//! of the wrong length, data of another mesh — from a table. For every call:
//!
//! - it does not panic;
//! - it returns a typed error and leaves the mesh as it was (positions bit for bit,
//!   connectivity by its topology stamp), or succeeds and leaves every position that was
//!   finite finite, with a valid mesh;
//! - it takes bounded time, and the whole suite bounded memory (peak resident size).
//!
//! Each case builds what it needs from the mesh it is given, so cases are independent.
//! The meshes: a closed sphere, a grid (boundary), and a sphere with a collapsed edge
//! (a removed vertex: slots and live vertices differ).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use edit::bendels_klein::affine_power::{log, scalar_power, AffinePower};
use edit::bendels_klein::{
    BendelsKleinError, BlendOptions, BlendSession, BorderGrid, CurveOptions, DistanceKind,
    FastMarching, MarchSource, QueryPoints, RefineOptions, Regions, ShapeCurve, ShapeFunction,
};
use edit::deform::{
    apply_deformer, taubin, AttachOptions, Axis, BSplineSurface, Bend, DeformError, Ffd,
    LatticeFrame, Profile, Propagation, Smoother, SmoothingWeights, SubMesh, SubmeshEdit, Taper,
    TaubinOptions, Twist, Variation,
};
use edit::lee::mba::{ControlLattice, Mba};
use edit::lee::{AreaSession, EditingArea, FrameKind, LeeError, LocalFrames, SessionOptions};
use edit::{Result, Snapshot, Vertices};
use glam::{DMat4, DVec2, DVec3};
use halfedge::{generators, Mesh, VertexId};

/// Numbers a hostile caller passes.
const NUMBERS: [f64; 14] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MAX,
    -f64::MAX,
    1e308,
    -1e308,
    1e300,
    1e103,
    1e12,
    1e-310,
    -1e-310,
    0.0,
    -0.0,
];

/// Counts a hostile caller passes.
const COUNTS: [usize; 6] = [0, 1, 3, 1 << 20, 1 << 40, usize::MAX];

fn vectors() -> Vec<DVec3> {
    let mut v: Vec<DVec3> = NUMBERS
        .iter()
        .map(|&x| DVec3::new(x, 0.5 * x, -x))
        .collect();
    v.extend(NUMBERS.iter().map(|&x| DVec3::splat(x)));
    v.push(DVec3::ZERO);
    v
}

type Run = Box<dyn Fn(&mut Mesh, &mut Cx) -> Result<()>>;

struct Case {
    name: String,
    run: Run,
}

/// A case whose run fails with any of the edit crate's errors.
fn case<E: Into<edit::Error>>(
    name: impl Into<String>,
    run: impl Fn(&mut Mesh, &mut Cx) -> std::result::Result<(), E> + 'static,
) -> Case {
    Case {
        name: name.into(),
        run: Box::new(move |m, cx| run(m, cx).map_err(Into::into)),
    }
}

/// Runs the calls that change a mesh and checks each one: refused ⇒ the mesh is as it
/// was; accepted ⇒ a valid mesh, and no position that was finite is not any more.
#[derive(Default)]
struct Cx {
    failures: Vec<String>,
    ok: usize,
    refused: usize,
}

impl Cx {
    fn edit<T, E: std::fmt::Display>(
        &mut self,
        m: &mut Mesh,
        f: impl FnOnce(&mut Mesh) -> std::result::Result<T, E>,
    ) -> std::result::Result<T, E> {
        let before = state(m);
        let finite_before: Vec<bool> = m.positions().iter().map(|p| p.is_finite()).collect();
        let result = f(m);
        match &result {
            Err(e) => {
                self.refused += 1;
                if state(m) != before {
                    self.failures
                        .push(format!("refused ({e}) but changed the mesh"));
                }
                if e.to_string().is_empty() {
                    self.failures.push("an error without a message".into());
                }
            }
            Ok(_) => {
                self.ok += 1;
                if let Err(e) = m.check() {
                    self.failures.push(format!("invalid mesh: {e}"));
                }
                let bad = m
                    .positions()
                    .iter()
                    .zip(&finite_before)
                    .position(|(p, &was)| was && !p.is_finite());
                if let Some(i) = bad {
                    self.failures.push(format!(
                        "accepted, but vertex {i} is now at {}",
                        m.positions()[i]
                    ));
                }
            }
        }
        result
    }
}

/// The vertex with the largest z: a point inside the sphere's cap, or a grid vertex.
fn top(mesh: &Mesh) -> VertexId {
    mesh.vertices()
        .max_by(|&a, &b| {
            let (p, q) = (mesh.position(a), mesh.position(b));
            (p.z + 1e-3 * p.x).total_cmp(&(q.z + 1e-3 * q.x))
        })
        .unwrap()
}

fn bottom(mesh: &Mesh) -> VertexId {
    mesh.vertices()
        .min_by(|&a, &b| {
            let (p, q) = (mesh.position(a), mesh.position(b));
            (p.z + 1e-3 * p.x).total_cmp(&(q.z + 1e-3 * q.x))
        })
        .unwrap()
}

/// A vertex handle that is not live in the mesh: removed by a collapse (on a clone, so
/// the mesh itself keeps it when it is the sphere) or of a larger mesh.
fn stale_vertex() -> VertexId {
    generators::icosphere(4).vertices().last().unwrap()
}

/// Vertices with z above `h` as a mask.
fn cap_mask(mesh: &Mesh, h: f64) -> halfedge::VertexData<bool> {
    halfedge::VertexData::from_fn(mesh, false, |v| mesh.position(v).z > h)
}

fn area(mesh: &Mesh) -> Result<EditingArea, LeeError> {
    EditingArea::disk_around(mesh, top(mesh), 60)
}

fn session(mesh: &Mesh, options: &SessionOptions) -> Result<AreaSession, LeeError> {
    let mut s = AreaSession::new(mesh, area(mesh)?, options)?;
    s.set_primitive(mesh, &[top(mesh)])?;
    Ok(s)
}

fn regions(mesh: &Mesh) -> Result<Regions, BendelsKleinError> {
    let handle: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).z > 0.8)
        .collect();
    let fixed: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| mesh.position(v).z < -0.2)
        .collect();
    Regions::from_sets(mesh, &handle, &fixed)
}

fn blend(mesh: &Mesh, distance: DistanceKind) -> Result<BlendSession, BendelsKleinError> {
    BlendSession::new(
        mesh,
        regions(mesh)?,
        BlendOptions::default().with_distance(distance),
    )
}

fn submesh(mesh: &Mesh) -> Result<SubMesh, DeformError> {
    SubMesh::from_mask(mesh, &cap_mask(mesh, 0.3))
}

fn ffd(mesh: &Mesh) -> Result<Ffd, DeformError> {
    let frame = LatticeFrame::new(DVec3::ZERO, DVec3::X, DVec3::Z)?;
    Ffd::covering(
        mesh,
        Vertices::All,
        frame,
        ([3, 3], [5, 5]),
        ([3, 3], [5, 5]),
        0.1,
        AttachOptions::default(),
    )
}

fn translation(t: DVec3) -> DMat4 {
    DMat4::from_translation(t)
}

/// Every case of the table.
fn cases() -> Vec<Case> {
    let mut cases = Vec::new();
    let numbers = NUMBERS;

    // ---- Lee 1999 area editing ----
    for &n in &COUNTS {
        cases.push(case(format!("disk_around({n})"), move |m, _cx| {
            EditingArea::disk_around(m, top(m), n).map(drop)
        }));
        cases.push(case(format!("session levels Some({n})"), move |m, cx| {
            let options = SessionOptions::default().with_levels(n);
            let mut s = session(m, &options)?;
            cx.edit(m, |m| s.drag(m, DVec3::new(0.0, 0.0, 0.1)))
        }));
        cases.push(case(format!("session set_levels({n})"), move |m, cx| {
            let mut s = session(m, &SessionOptions::default())?;
            s.set_levels(n)?;
            cx.edit(m, |m| s.drag(m, DVec3::Z))
        }));
        cases.push(case(
            format!("session parallel_threshold {n}"),
            move |m, cx| {
                let options = SessionOptions::default().with_parallel_threshold(n);
                cx.edit(m, |m| session(m, &options)?.drag(m, DVec3::Z))
            },
        ));
    }
    for level in [14, 12, 11] {
        cases.push(case(
            format!("session levels Some({level}) drag"),
            move |m, cx| {
                let options = SessionOptions::default().with_levels(level);
                cx.edit(m, |m| {
                    session(m, &options)?.drag(m, DVec3::new(0.0, 0.0, 0.1))
                })
            },
        ));
    }
    for d in vectors() {
        cases.push(case(format!("session drag {d}"), move |m, cx| {
            cx.edit(m, |m| session(m, &SessionOptions::default())?.drag(m, d))
        }));
        cases.push(case(
            format!("session move_vertex {d} + apply"),
            move |m, cx| {
                let mut s = session(m, &SessionOptions::default())?;
                s.move_vertex(m, top(m), d)?;
                cx.edit(m, |m| s.apply(m))
            },
        ));
        cases.push(case(
            format!("session normal frames x_axis {d}"),
            move |m, cx| {
                let options = SessionOptions::default().with_frames(FrameKind::Normal {
                    seed: None,
                    x_axis: Some(d),
                });
                cx.edit(m, |m| session(m, &options)?.drag(m, DVec3::Z))
            },
        ));
    }
    for &x in &numbers {
        cases.push(case(format!("session scale {x}"), move |m, cx| {
            let options = SessionOptions::default().with_scale(x);
            cx.edit(m, |m| session(m, &options)?.drag(m, DVec3::Z))
        }));
        cases.push(case(format!("session set_scale {x}"), move |m, cx| {
            let mut s = session(m, &SessionOptions::default())?;
            s.set_scale(x)?;
            cx.edit(m, |m| s.drag(m, DVec3::Z))
        }));
    }
    cases.push(case(
        "session primitive: stale, empty, boundary",
        |m, cx| {
            let mut s = AreaSession::new(m, area(m)?, &SessionOptions::default())?;
            assert!(s.set_primitive(m, &[stale_vertex()]).is_err());
            assert!(s.set_primitive(m, &[]).is_err());
            let boundary = s.area().boundary()[0];
            assert!(s.set_primitive(m, &[boundary]).is_err());
            assert!(cx.edit(m, |m| s.drag(m, DVec3::Z)).is_err());
            cx.edit(m, |m| s.cancel(m))
        },
    ));
    cases.push(case("session on another mesh", |m, cx| {
        let other = generators::icosphere(2);
        let mut s = session(&other, &SessionOptions::default())?;
        cx.edit(m, |m| s.drag(m, DVec3::Z))?;
        cx.edit(m, |m| s.cancel(m))?;
        s.commit(m)
    }));
    cases.push(case("area from stale picks and faces", |m, _cx| {
        let picks = [stale_vertex(), top(m), bottom(m)];
        let a = EditingArea::from_picks(m, &picks, edit::lee::AreaSide::Smaller);
        let faces = [generators::icosphere(4).faces().last().unwrap()];
        let b = EditingArea::from_faces(m, &faces);
        a.and(b).map(drop)
    }));
    cases.push(case(
        "local frames: wrong lengths, seeds out of range",
        |m, _cx| {
            let a = area(m)?;
            let positions: Vec<DVec3> = a.vertices().iter().map(|&v| m.position(v)).collect();
            let kind = FrameKind::Normal {
                seed: None,
                x_axis: None,
            };
            assert!(LocalFrames::new(m, &a, &positions[1..], &kind, 0).is_err());
            assert!(LocalFrames::new(m, &a, &positions, &kind, usize::MAX).is_err());
            let other = generators::icosphere(1);
            assert!(LocalFrames::new(&other, &a, &positions, &kind, 0).is_err());
            let f = LocalFrames::new(m, &a, &positions, &kind, 0)?;
            let d = f.to_displacement(usize::MAX, f.to_offset(usize::MAX, DVec3::ONE));
            assert_eq!(
                (f.frame(usize::MAX), d),
                (glam::DMat3::IDENTITY, DVec3::ONE)
            );
            Ok::<_, LeeError>(())
        },
    ));
    cases.push(case("area grown by foreign faces", |m, _cx| {
        let faces = [generators::icosphere(4).faces().last().unwrap()];
        area(m)?.grown(m, &faces).map(drop)
    }));

    // ---- multilevel B-splines ----
    for &n in &COUNTS {
        cases.push(case(format!("Mba::new levels {n}"), move |_, _| {
            let mba = Mba::new(DVec2::ZERO, DVec2::ONE, n)?;
            mba.fit(&[DVec2::splat(0.5)], &[DVec3::ONE]).map(drop)
        }));
        cases.push(case(
            format!("ControlLattice::zeros({n}) refined"),
            move |_, _| {
                let lattice = ControlLattice::zeros(n, DVec2::ZERO, DVec2::ONE)?;
                lattice.refined()?.refined().map(drop)
            },
        ));
    }
    for &x in &numbers {
        cases.push(case(format!("Mba fit of values {x}"), move |_, _| {
            let mba = Mba::new(DVec2::ZERO, DVec2::ONE, 6)?;
            let points = [
                DVec2::new(0.2, 0.3),
                DVec2::new(0.7, 0.6),
                DVec2::splat(0.5),
            ];
            let values = [DVec3::splat(x), DVec3::splat(-x), DVec3::splat(x)];
            let f = mba.fit(&points, &values)?;
            let v = f.evaluate(DVec2::splat(0.4));
            assert!(v.is_finite(), "an Ok fit evaluates to {v}");
            assert!(f.evaluate_data_point(usize::MAX).is_none());
            Ok::<_, LeeError>(())
        }));
        cases.push(case(format!("Mba domain {x}"), move |_, _| {
            let mba = Mba::new(DVec2::splat(-x), DVec2::splat(x), 6)?;
            mba.fit_scaled(0.5, &[DVec2::ZERO], &[DVec3::ONE]).map(drop)
        }));
        cases.push(case(format!("Mba fit_scaled s = {x}"), move |_, _| {
            let mba = Mba::new(DVec2::ZERO, DVec2::ONE, 6)?;
            mba.fit_scaled(x, &[DVec2::splat(0.5)], &[DVec3::ONE])
                .map(drop)
        }));
    }

    // ---- Bendels & Klein regions and blends ----
    for distance in [DistanceKind::Geodesic, DistanceKind::Euclidean] {
        let moves: Vec<(String, DMat4)> = vec![
            ("translation 1e308".into(), translation(DVec3::splat(1e308))),
            (
                "translation f64::MAX".into(),
                translation(DVec3::new(f64::MAX, 0.0, 0.0)),
            ),
            (
                "uniform scale 1e103".into(),
                DMat4::from_scale(DVec3::splat(1e103)),
            ),
            (
                "uniform scale 1e-103".into(),
                DMat4::from_scale(DVec3::splat(1e-103)),
            ),
            ("shear 1e12".into(), {
                let mut m = DMat4::IDENTITY;
                m.y_axis.x = 1e12;
                m
            }),
            (
                "reflection".into(),
                DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0)),
            ),
            (
                "singular".into(),
                DMat4::from_scale(DVec3::new(1.0, 0.0, 1.0)),
            ),
            ("NaN".into(), translation(DVec3::NAN)),
            (
                "half turn".into(),
                DMat4::from_rotation_z(std::f64::consts::PI),
            ),
            ("rotation 1e300 turns".into(), DMat4::from_rotation_z(1e300)),
            ("projective".into(), {
                let mut m = DMat4::IDENTITY;
                m.x_axis.w = 0.5;
                m
            }),
        ];
        for (name, a) in moves {
            cases.push(case(
                format!("blend {distance:?} apply {name}"),
                move |m, cx| {
                    let mut s = blend(m, distance)?;
                    cx.edit(m, |m| s.apply(m, a))?;
                    cx.edit(m, |m| s.reapply(m))
                },
            ));
        }
        for &x in &numbers {
            cases.push(case(
                format!("blend {distance:?} refine {x}"),
                move |m, cx| {
                    let mut s = blend(m, distance)?;
                    cx.edit(m, |m| {
                        s.apply(m, DMat4::from_translation(DVec3::new(0.0, 0.0, 0.5)))
                    })?;
                    // (A budget of its own: the default, a million vertices, is legitimate
                    // work that takes seconds.)
                    let options = RefineOptions::new(x).with_max_new_vertices(20_000);
                    cx.edit(m, |m| s.refine(m, options)).map(drop)
                },
            ));
        }
        for &n in &COUNTS {
            cases.push(case(
                format!("blend {distance:?} refine budget {n}"),
                move |m, cx| {
                    let mut s = blend(m, distance)?;
                    cx.edit(m, |m| {
                        s.apply(m, DMat4::from_translation(DVec3::new(0.0, 0.0, 0.5)))
                    })?;
                    let options = RefineOptions::default()
                        .with_max_edge_length(0.05)
                        .with_max_new_vertices(n);
                    cx.edit(m, |m| s.refine(m, options)).map(drop)
                },
            ));
        }
    }
    cases.push(case("blend with regions of another mesh", |m, cx| {
        let other = generators::icosphere(2);
        let mut s = blend(&other, DistanceKind::Geodesic)?;
        cx.edit(m, |m| s.apply(m, translation(DVec3::Z)))?;
        cx.edit(m, |m| s.reset(m))
    }));
    cases.push(case(
        "regions: stale, wrong lengths, same vertex twice",
        |m, _cx| {
            let v = top(m);
            assert!(Regions::from_sets(m, &[stale_vertex()], &[]).is_err());
            assert!(Regions::from_sets(m, &[v], &[v]).is_err());
            let foreign_roles = halfedge::VertexData::filled(
                &generators::icosphere(1),
                edit::bendels_klein::Role::Deformable,
            );
            assert!(Regions::from_roles(m, foreign_roles).is_err());
            assert!(Regions::from_picks(m, &[v], &[stale_vertex()]).is_err());
            Regions::from_loops(m, &[], &[]).map(drop)
        },
    ));
    for &x in &numbers {
        cases.push(case(format!("scalar_power alpha {x}"), move |_, _| {
            let m = scalar_power(x, DMat4::from_scale(DVec3::splat(2.0)))?;
            assert!(m.to_cols_array().iter().all(|c| c.is_finite()), "{m}");
            Ok::<_, edit::Error>(())
        }));
        cases.push(case(format!("log of scale {x}"), move |_, _| {
            let l = log(DMat4::from_scale(DVec3::splat(x)))?;
            assert!(l.to_cols_array().iter().all(|c| c.is_finite()), "{l}");
            AffinePower::new(DMat4::from_scale(DVec3::splat(x))).map(drop)
        }));
        cases.push(case(format!("shape curve through {x}"), move |_, _| {
            let c = ShapeCurve::new(&[(0.5, x)], CurveOptions::default())?;
            let y = c.eval(0.25);
            assert!(y.is_finite(), "{y}");
            ShapeCurve::new(&[(x, 0.5)], CurveOptions::default()).map(drop)
        }));
        cases.push(case(format!("blend shape curve {x}"), move |m, cx| {
            let mut s = blend(m, DistanceKind::Geodesic)?;
            let mut c = ShapeCurve::new(&[(0.5, 0.5)], CurveOptions::default())?;
            c.move_point(usize::MAX, (0.5, x))?;
            c.move_point(1, (x, 0.5))?;
            s.set_shape(ShapeFunction::Curve(c));
            cx.edit(m, |m| s.apply(m, translation(DVec3::Z)))
        }));
    }

    // ---- distances ----
    cases.push(case(
        "fast marching: wrong mask, sources out of range",
        |m, _cx| {
            let fm = FastMarching::new(m);
            // A mask of another mesh (even of the same size) is stale; a mask of the
            // wrong length cannot be made.
            let (positions, triangles) = m.to_arrays();
            let other = halfedge::Mesh::from_arrays(&positions, &triangles)?.0;
            assert!(matches!(
                fm.distances(
                    &[MarchSource::point(0)],
                    Some(&halfedge::VertexData::filled(&other, true))
                ),
                Err(BendelsKleinError::Stale(_))
            ));
            assert!(halfedge::VertexData::new(m, vec![true]).is_err());
            assert!(fm
                .distances(&[MarchSource::point(usize::MAX)], None)
                .is_err());
            let nan = MarchSource {
                vertex: 0,
                distance: f64::NAN,
                radius: 0.0,
            };
            assert!(fm.distances(&[nan], None).is_err());
            assert!(fm
                .distances_from_points(m, &[stale_vertex()], None)
                .is_err());
            fm.distances_from_curve(
                m,
                &[top(m)],
                Some(&halfedge::VertexData::new(m, vec![false])?),
            )
            .map(drop)
        },
    ));
    for &x in &numbers {
        cases.push(case(format!("border grid cell {x}"), move |m, _cx| {
            let mut grid = BorderGrid::new(x)?;
            grid.insert_segment(DVec3::splat(-1e300), DVec3::splat(1e300))?;
            grid.set_segments([(DVec3::ZERO, DVec3::ONE)])?;
            let d = grid.distance(DVec3::splat(x));
            let q = QueryPoints::new(m.positions(), x);
            let _ = (d, grid.distances_to(&q));
            Ok::<_, edit::Error>(())
        }));
    }

    // ---- sub-mesh edits ----
    for &x in &numbers {
        let edits = [
            SubmeshEdit::Pull {
                offset: DVec3::splat(x),
            },
            SubmeshEdit::Scale {
                centre: DVec3::ZERO,
                factor: x,
            },
            SubmeshEdit::Scale {
                centre: DVec3::splat(x),
                factor: 2.0,
            },
            SubmeshEdit::Rotate {
                axis: Axis::new(DVec3::ZERO, DVec3::Z).unwrap(),
                angle: x,
                bounded: true,
            },
            SubmeshEdit::Taper {
                axis: None,
                factor: x,
                variation: Variation::Along { start: 0.0, end: x },
            },
            SubmeshEdit::Twist {
                axis: None,
                angle: x,
                variation: Variation::Levels(Some(usize::MAX)),
            },
        ];
        for edit in edits {
            for propagation in [
                Propagation::NONE,
                Propagation::smooth(usize::MAX),
                Propagation::linear(3),
            ] {
                cases.push(case(
                    format!("submesh {edit:?} {propagation:?}"),
                    move |m, cx| {
                        let snapshot = submesh(m)?.apply(m, &edit, propagation)?;
                        if let Some(inverse) = edit.inverse() {
                            let _ = cx.edit(m, |m| submesh(m)?.apply(m, &inverse, propagation));
                        }
                        cx.edit(m, |m| Ok::<_, DeformError>(snapshot.restore(m)?))
                    },
                ));
            }
        }
        cases.push(case(format!("axis through {x}"), move |m, cx| {
            let axis = Axis::new(DVec3::splat(x), DVec3::new(x, 1.0, 0.0))?;
            let edit = SubmeshEdit::Twist {
                axis: Some(axis),
                angle: 1.0,
                variation: Variation::Uniform,
            };
            cx.edit(m, |m| submesh(m)?.apply(m, &edit, Propagation::linear(2)))
                .map(drop)
        }));
    }
    cases.push(case(
        "submesh: wrong mask, stale vertices, collars usize::MAX",
        |m, _cx| {
            // A mask of the wrong length cannot be made; one of another mesh is stale.
            assert!(halfedge::VertexData::new(m, vec![true]).is_err());
            let foreign = halfedge::VertexData::filled(&generators::icosphere(1), true);
            assert!(matches!(
                SubMesh::from_mask(m, &foreign),
                Err(DeformError::Stale(_))
            ));
            assert!(SubMesh::from_vertices(m, &[stale_vertex()]).is_err());
            let s = submesh(m)?;
            s.collars(m, usize::MAX)?;
            s.collars(&generators::icosphere(1), 2).map(drop)
        },
    ));

    // ---- Barr deformers ----
    for &x in &numbers {
        cases.push(case(
            format!("taper factor {x} and inverse"),
            move |m, cx| {
                let t = Taper::linear(DVec3::ZERO, DVec3::Z, -1.0, 1.0, x)?;
                cx.edit(m, |m| apply_deformer(m, &t, Vertices::All))?;
                cx.edit(m, |m| apply_deformer(m, &t.inverse(), Vertices::All))
            },
        ));
        cases.push(case(format!("global taper {x}"), move |m, cx| {
            let t = Taper::new(DVec3::ZERO, DVec3::Z, Profile::global(0.0, 1.0, 1.0, x)?)?;
            cx.edit(m, |m| apply_deformer(m, &t, Vertices::All))
        }));
        cases.push(case(format!("twist {x}"), move |m, cx| {
            let t = Twist::linear(DVec3::ZERO, DVec3::Z, -x, x, x)?;
            apply_deformer(m, &t, Vertices::Mask(&cap_mask(m, 0.0)))?;
            cx.edit(m, |m| apply_deformer(m, &t.inverse(), Vertices::All))
        }));
        cases.push(case(format!("bend rate {x}"), move |m, cx| {
            let b = Bend::new(DVec3::ZERO, DVec3::X, DVec3::Z, x, Some((-x, x)))?;
            cx.edit(m, |m| apply_deformer(m, &b, Vertices::All))?;
            cx.edit(m, |m| apply_deformer(m, &b.inverse(), Vertices::All))
        }));
        cases.push(case(format!("bend about {x}"), move |m, cx| {
            let b = Bend::new(
                DVec3::splat(x),
                DVec3::new(x, 1.0, 0.0),
                DVec3::Z,
                1.0,
                None,
            )?;
            let v = top(m);
            cx.edit(m, |m| apply_deformer(m, &b, Vertices::List(&[v])))
        }));
    }
    cases.push(case("deform: wrong mask, stale list", |m, cx| {
        let t = Taper::linear(DVec3::ZERO, DVec3::Z, -1.0, 1.0, 2.0)?;
        // A mask of another mesh of the same size is stale.
        let (positions, triangles) = m.to_arrays();
        let other = Mesh::from_arrays(&positions, &triangles)?.0;
        let foreign = halfedge::VertexData::filled(&other, true);
        assert!(matches!(
            cx.edit(m, |m| apply_deformer(m, &t, Vertices::Mask(&foreign))),
            Err(DeformError::Stale(_))
        ));
        cx.edit(m, |m| {
            apply_deformer(m, &t, Vertices::List(&[stale_vertex()]))
        })
    }));

    // ---- smoothing ----
    for &x in &numbers {
        for &n in &[1usize, 100, 1 << 21, usize::MAX] {
            cases.push(case(format!("taubin lambda {x} x{n}"), move |m, cx| {
                let options = TaubinOptions::default().with_lambda(x);
                cx.edit(m, |m| taubin(m, Vertices::All, &options, n))
            }));
        }
        cases.push(case(
            format!("laplacian lambda {x}, cotangent"),
            move |m, cx| {
                let mut s = Smoother::new(m, Vertices::All, SmoothingWeights::Cotangent, false)?;
                cx.edit(m, |m| s.laplacian(m, x, 50))
            },
        ));
    }
    cases.push(case(
        "smoother of another mesh, submesh collars usize::MAX",
        |m, cx| {
            let other = generators::icosphere(1);
            let mut s = Smoother::new(&other, Vertices::All, SmoothingWeights::Uniform, true)?;
            assert!(cx.edit(m, |m| s.taubin(m, 0.33, -0.34, 3)).is_err());
            let mut s = Smoother::for_submesh(
                m,
                &submesh(m)?,
                usize::MAX,
                SmoothingWeights::Uniform,
                true,
            )?;
            cx.edit(m, |m| s.taubin(m, 0.33, -0.34, 3))
        },
    ));

    // ---- FFD ----
    for &n in &COUNTS {
        for degree in [0usize, 1, 3, 40, usize::MAX] {
            cases.push(case(
                format!("BSplineSurface::planar degree {degree} count {n}"),
                move |_, _| {
                    let frame = LatticeFrame::new(DVec3::ZERO, DVec3::X, DVec3::Z)?;
                    BSplineSurface::planar(&frame, [degree, 3], [n, n], [0.0, 0.0], [1.0, 1.0], 0.0)
                        .map(drop)
                },
            ));
        }
        cases.push(case(
            format!("BSplineSurface::new count {n}"),
            move |_, _| BSplineSurface::new([1, 1], [n, n], vec![DVec3::ZERO; 4]).map(drop),
        ));
        cases.push(case(format!("ffd attach iterations {n}"), move |m, cx| {
            let frame = LatticeFrame::new(DVec3::ZERO, DVec3::X, DVec3::Z)?;
            let options = AttachOptions::default()
                .with_max_iterations(n.min(1 << 20))
                .with_shape_layers(n)
                .with_height_layers(n);
            let f = Ffd::covering(
                m,
                Vertices::All,
                frame,
                ([3, 3], [5, 5]),
                ([3, 3], [5, 5]),
                -0.2,
                options,
            )?;
            cx.edit(m, |m| f.deform(m))
        }));
    }
    for &x in &numbers {
        cases.push(case(format!("ffd translate {x}"), move |m, cx| {
            let mut f = ffd(m)?;
            f.translate(DVec3::splat(x))?;
            cx.edit(m, |m| f.deform(m))
        }));
        cases.push(case(format!("ffd scale_heights {x}"), move |m, cx| {
            let mut f = ffd(m)?;
            f.scale_heights(x)?;
            cx.edit(m, |m| f.deform(m))
        }));
        cases.push(case(format!("ffd bend, twist, taper {x}"), move |m, cx| {
            let mut f = ffd(m)?;
            let bend = f.bend(x);
            let twist = f.twist(x);
            let taper = f.taper(x, 1.0);
            cx.edit(m, |m| f.deform(m))?;
            bend.and(twist).and(taper)
        }));
        cases.push(case(
            format!("ffd control point written {x}"),
            move |m, cx| {
                let mut f = ffd(m)?;
                f.shape_mut().control_points_mut()[3] = DVec3::splat(x);
                f.height_mut().control_points_mut()[0] = DVec3::new(0.0, x, 0.0);
                cx.edit(m, |m| f.deform(m))
            },
        ));
        cases.push(case(format!("ffd covering margin {x}"), move |m, cx| {
            let frame = LatticeFrame::new(DVec3::ZERO, DVec3::X, DVec3::Z)?;
            let f = Ffd::covering(
                m,
                Vertices::All,
                frame,
                ([3, 3], [5, 5]),
                ([3, 3], [5, 5]),
                x,
                AttachOptions::default(),
            )?;
            cx.edit(m, |m| f.deform(m))
        }));
        cases.push(case(format!("frame {x}"), move |m, cx| {
            let frame = LatticeFrame::new(DVec3::splat(x), DVec3::new(x, 1.0, 0.0), DVec3::Z)?;
            let f = Ffd::covering(
                m,
                Vertices::All,
                frame,
                ([3, 3], [5, 5]),
                ([3, 3], [5, 5]),
                0.1,
                AttachOptions::default(),
            )?;
            cx.edit(m, |m| f.deform(m))
        }));
    }
    cases.push(case("ffd of another mesh", |m, cx| {
        let other = generators::icosphere(2);
        cx.edit(m, |m| ffd(&other)?.deform(m))
    }));

    // ---- snapshots ----
    cases.push(case("snapshot of another mesh, stale list", |m, cx| {
        let other = generators::icosphere(1);
        let s = Snapshot::take(&other, Vertices::All)?;
        assert!(cx.edit(m, |m| s.restore(m)).is_err());
        Snapshot::take(m, Vertices::List(&[stale_vertex()])).map(drop)
    }));
    cases
}

/// What a failed call must leave as it was.
fn state(m: &Mesh) -> (Vec<[u64; 3]>, halfedge::Binding) {
    (
        m.positions()
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect(),
        m.binding(),
    )
}

fn meshes() -> Vec<(&'static str, Mesh)> {
    let mut holey = generators::icosphere(3);
    let h = holey
        .halfedges()
        .find(|&h| holey.is_collapse_ok(h).is_ok())
        .unwrap();
    holey.collapse(h).unwrap();
    vec![
        ("sphere", generators::icosphere(3)),
        ("grid", generators::grid(16, 16, 2.0, 2.0)),
        ("sphere with a removed vertex", holey),
    ]
}

/// Peak resident memory of this process in kB (Linux), if known.
fn peak_kb() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

#[test]
fn every_edit_entry_point_survives_hostile_arguments() {
    let cases = cases();
    assert!(cases.len() > 400, "{} cases", cases.len());
    let mut failures = Vec::new();
    let mut cx = Cx::default();
    let mut slowest = (Duration::ZERO, String::new());
    for (mesh_name, mesh) in meshes() {
        for c in &cases {
            let name = format!("{} on the {mesh_name}", c.name);
            let mut m = mesh.clone();
            let start = Instant::now();
            let outcome = catch_unwind(AssertUnwindSafe(|| (c.run)(&mut m, &mut cx)));
            let took = start.elapsed();
            if took > slowest.0 {
                slowest = (took, name.clone());
            }
            if let Err(panic) = outcome {
                let what = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                failures.push(format!("{name}: panicked: {what}"));
            }
            failures.extend(cx.failures.drain(..).map(|f| format!("{name}: {f}")));
            if took > Duration::from_secs(20) {
                failures.push(format!("{name}: took {took:?}"));
            }
        }
    }
    eprintln!(
        "{} cases × 3 meshes: {} calls accepted, {} refused; slowest {:?} ({})",
        cases.len(),
        cx.ok,
        cx.refused,
        slowest.0,
        slowest.1
    );
    if let Some(kb) = peak_kb() {
        eprintln!("peak resident memory {} MB", kb >> 10);
        assert!(kb < 1_500_000, "peak resident memory {} MB", kb >> 10);
    }
    assert!(
        cx.ok > 500 && cx.refused > 500,
        "{} / {}",
        cx.ok,
        cx.refused
    );
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The oracle catches what it must: a call that changes the mesh and fails, or succeeds
/// with a NaN position.
#[test]
fn the_oracle_catches_broken_edits() {
    let mut m = generators::icosphere(1);
    let mut cx = Cx::default();
    let _ = cx.edit(&mut m, |m| -> Result<(), DeformError> {
        m.positions_mut()[0].x += 1.0;
        Err(DeformError::EmptySubMesh)
    });
    assert_eq!(cx.failures.len(), 1);
    let _ = cx.edit(&mut m, |m| {
        m.positions_mut()[1] = DVec3::NAN;
        Ok::<_, DeformError>(())
    });
    assert_eq!(cx.failures.len(), 2, "{:?}", cx.failures);
    let _ = cx.edit(&mut m, |_| Ok::<_, DeformError>(()));
    assert_eq!(cx.failures.len(), 2);
}
