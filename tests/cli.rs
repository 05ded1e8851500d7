//! The `multires` command line, run as a user runs it: every subcommand's exit code
//! (0 done, 1 input or job error with one line naming the file and the reason, 2 usage),
//! its outputs, and its refusals of bad input — never a panic or a backtrace. Hierarchy
//! files round-trip through `simplify` → `refine` bit for bit and `simplify` → `edit` →
//! `refine` equals the same steps in this process; batches run in parallel, in shards
//! that partition the corpus, and resume. Every mesh is generated here.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use halfedge::hierarchy::Hierarchy;
use halfedge::{generators, Mesh};
use multires::recipe::{self, Recipe};

fn multires() -> Command {
    Command::new(env!("CARGO_BIN_EXE_multires"))
}

use testkit::temp_dir as temp;

/// `multires simplify MESH -o H [options] -q`, which must succeed.
fn simplify(mesh: &Path, h: &Path, options: &[&str]) {
    let o = multires()
        .arg("simplify")
        .arg(mesh)
        .arg("-o")
        .arg(h)
        .args(options)
        .arg("-q")
        .output()
        .unwrap();
    assert_exit(&o, 0);
}

fn run(args: &[&dyn AsRef<std::ffi::OsStr>]) -> Output {
    let mut command = multires();
    for a in args {
        command.arg(a);
    }
    command.output().unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Exit code `code`, and on failure one line on stderr without a panic or backtrace.
fn assert_exit(o: &Output, code: i32) {
    assert_eq!(
        o.status.code(),
        Some(code),
        "exit code; stdout: {}\nstderr: {}",
        stdout(o),
        stderr(o)
    );
    let err = stderr(o);
    assert!(
        !err.contains("panicked")
            && !err.contains("RUST_BACKTRACE")
            && !err.contains("internal error"),
        "a panic reached the user: {err}"
    );
    if code == 1 {
        assert_eq!(
            err.trim_end().lines().count(),
            1,
            "one line saying file, place and reason: {err}"
        );
        assert!(err.starts_with("error: "), "{err}");
    }
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(stdout(o).trim()).unwrap_or_else(|e| panic!("{e}: {}", stdout(o)))
}

/// A torus of `nu × nv` quads split into triangles, written to `dir/name`.
fn torus_file(dir: &Path, name: &str, nu: usize, nv: usize) -> PathBuf {
    let path = dir.join(name);
    halfedge::io::write(&path, &generators::torus(2.0, 0.7, nu, nv).unwrap()).unwrap();
    path
}

fn read(path: &Path) -> Mesh {
    halfedge::io::read(path).unwrap().0
}

/// Positions and faces, in the writers' numbering.
fn arrays(mesh: &Mesh) -> (Vec<[u64; 3]>, Vec<[u32; 3]>) {
    let (v, f) = mesh.to_arrays();
    (v.iter().map(|p| p.map(f64::to_bits)).collect(), f)
}

#[test]
fn version_help_and_usage_errors() {
    let o = run(&[&"--version"]);
    assert_exit(&o, 0);
    let text = stdout(&o);
    assert!(text.contains(env!("CARGO_PKG_VERSION")), "{text}");
    assert!(
        text.contains(&format!(
            "hierarchy file format {}",
            halfedge::hierarchy::file::FORMAT_VERSION
        )),
        "{text}"
    );
    assert!(text.contains("recipe format 1"), "{text}");
    assert_exit(&run(&[&"--help"]), 0);
    for usage in [
        vec!["info"],
        vec!["frobnicate"],
        vec!["info", "x.obj", "--no-such-flag"],
        vec!["simplify", "x.obj"],
        vec!["simplify", "x.obj", "-o", "h.mrh", "--method", "best"],
        vec!["info", "x.obj", "--weld", "-1"],
        vec![
            "simplify",
            "x.obj",
            "-o",
            "h.mrh",
            "--max-normal-deviation",
            "0",
        ],
        vec![
            "simplify",
            "x.obj",
            "-o",
            "h.mrh",
            "--max-normal-deviation",
            "nan",
        ],
        vec![],
    ] {
        let o = multires().args(&usage).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{usage:?}: {}", stderr(&o));
    }
}

#[test]
fn info_reports_counts_and_topology() {
    let dir = temp("info");
    let torus = torus_file(&dir, "torus.off", 24, 12);
    let o = run(&[&"info", &torus, &"--json"]);
    assert_exit(&o, 0);
    let r = json(&o);
    assert_eq!(r["vertices"], 24 * 12);
    assert_eq!(r["faces"], 2 * 24 * 12);
    assert_eq!(r["edges"], 3 * 24 * 12);
    assert_eq!(r["boundary_loops"], 0);
    assert_eq!(r["components"], 1);
    assert_eq!(r["genus"], 1);
    // a grid: a disk with one boundary loop
    let grid = dir.join("grid.obj");
    halfedge::io::write(&grid, &generators::grid(5, 4, 1.0, 1.0)).unwrap();
    let r = json(&run(&[&"info", &grid, &"--json"]));
    assert_eq!(r["boundary_loops"], 1);
    assert_eq!(r["genus"], 0);
    assert_eq!(r["faces"], 2 * 5 * 4);
    // text output names the file
    let o = run(&[&"info", &grid]);
    assert_exit(&o, 0);
    assert!(stdout(&o).contains("grid.obj"), "{}", stdout(&o));
}

#[test]
fn bad_input_is_one_line_exit_1() {
    let dir = temp("bad");
    let missing = dir.join("missing.obj");
    let o = run(&[&"info", &missing]);
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("missing.obj"), "{}", stderr(&o));
    // garbage in every format the reader knows, and an unknown extension
    for (name, bytes) in [
        ("garbage.obj", b"v 1 2\nf 1 2 3 4 5\nv nan\n".to_vec()),
        (
            "garbage.ply",
            b"ply\nformat ascii 1.0\nelement vertex 99999999999\n".to_vec(),
        ),
        ("garbage.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n".to_vec()),
        ("garbage.stl", vec![0u8; 100]),
        ("garbage.mrh", b"MRH\0not really".to_vec()),
        ("garbage.xyz", b"1 2 3\n".to_vec()),
        ("garbage.obj.gz", b"\x1f\x8b\x08\0garbage".to_vec()),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        for sub in ["info", "check"] {
            let o = run(&[&sub, &path]);
            assert_exit(&o, 1);
            assert!(stderr(&o).contains(name), "{sub} {name}: {}", stderr(&o));
        }
        let o = run(&[&"convert", &path, &dir.join("out.ply")]);
        assert_exit(&o, 1);
    }
    // a good mesh to an unknown output format
    let torus = torus_file(&dir, "t.obj", 8, 6);
    let o = run(&[&"convert", &torus, &dir.join("t.xyz")]);
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("t.xyz"), "{}", stderr(&o));
    // a hierarchy command on a mesh file, a level past the coarsest is clamped
    let o = run(&[&"refine", &torus, &"-o", &dir.join("r.ply")]);
    assert_exit(&o, 1);
}

#[test]
fn check_passes_good_meshes_and_reports_fixes() {
    let dir = temp("check");
    let torus = torus_file(&dir, "t.ply", 10, 8);
    let o = run(&[&"check", &torus, &"--json"]);
    assert_exit(&o, 0);
    let r = json(&o);
    assert_eq!(r["valid"], true, "{r}");
    // a soup of the same torus: welded by default to the same surface
    let (v, f) = generators::triangle_soup(&generators::torus(2.0, 0.7, 10, 8).unwrap());
    let mut text = String::new();
    for p in &v {
        text += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in &f {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    let soup = dir.join("soup.obj");
    std::fs::write(&soup, text).unwrap();
    let r = json(&run(&[&"info", &soup, &"--json"]));
    assert_eq!(r["vertices"], 80, "welded: {r}");
    assert_eq!(r["genus"], 1);
    let r = json(&run(&[&"info", &soup, &"--json", &"--weld", &"off"]));
    assert_eq!(r["vertices"], 3 * 160, "not welded: {r}");
}

#[test]
fn convert_round_trips_every_format() {
    let dir = temp("convert");
    let torus = torus_file(&dir, "t.ply", 12, 9);
    let reference = arrays(&read(&torus));
    for name in [
        "a.obj", "a.ply", "a.off", "a.stl", "a.obj.gz", "a.ply.gz", "a.off.gz", "a.stl.gz",
    ] {
        let out = dir.join(name);
        let o = run(&[&"convert", &torus, &out, &"--quiet"]);
        assert_exit(&o, 0);
        let back = read(&out);
        if name.starts_with("a.stl") {
            // STL stores f32 corners and no vertex list: the same surface after welding
            let (v, f) = arrays(&back);
            assert_eq!(
                (v.len(), f.len()),
                (reference.0.len(), reference.1.len()),
                "{name}"
            );
            assert_eq!(back.topology_report().components, 1);
        } else {
            assert_eq!(arrays(&back), reference, "{name}: bit for bit");
        }
    }
    // ascii PLY and STL too
    for name in ["b.ply", "b.stl"] {
        let out = dir.join(name);
        assert_exit(&run(&[&"convert", &torus, &out, &"--ascii"]), 0);
        let head = std::fs::read(&out).unwrap();
        assert!(
            head.starts_with(b"ply\nformat ascii") || head.starts_with(b"solid"),
            "{name} is text"
        );
        assert_eq!(read(&out).n_faces(), reference.1.len());
    }
}

#[test]
fn simplify_then_refine_gives_the_input_bit_for_bit() {
    let dir = temp("simplify");
    let torus = torus_file(&dir, "t.obj", 40, 20);
    for method in ["rounds", "qem"] {
        let h = dir.join(format!("{method}.mrh"));
        let levels = dir.join(format!("levels-{method}"));
        let o = run(&[
            &"simplify",
            &torus,
            &"-o",
            &h,
            &"--method",
            &method,
            &"--target-faces",
            &"200",
            &"--levels",
            &levels,
            &"--json",
        ]);
        assert_exit(&o, 0);
        let r = json(&o);
        for phase in ["load_seconds", "build_seconds", "write_seconds"] {
            assert!(r[phase].as_f64().is_some_and(|s| s >= 0.0), "{phase}: {r}");
        }
        // the same bytes for the same input and options
        let again = dir.join(format!("{method}-again.mrh"));
        simplify(
            &torus,
            &again,
            &["--method", method, "--target-faces", "200"],
        );
        assert_eq!(
            std::fs::read(&h).unwrap(),
            std::fs::read(&again).unwrap(),
            "{method}: deterministic file"
        );
        // info on the file lists the levels; every level's mesh was written
        let info = json(&run(&[&"info", &h, &"--json"]));
        let counts: Vec<u64> = info["hierarchy"]["level_face_counts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_u64().unwrap())
            .collect();
        assert_eq!(counts[0], 1600);
        assert!(*counts.last().unwrap() <= 400, "{counts:?}");
        for (level, &faces) in counts.iter().enumerate() {
            let file = std::fs::read_dir(&levels)
                .unwrap()
                .map(|e| e.unwrap().path())
                .find(|p| {
                    p.file_name()
                        .unwrap()
                        .to_string_lossy()
                        .contains(&format!("-level{level}."))
                })
                .unwrap_or_else(|| panic!("level {level} written into {}", levels.display()));
            assert_eq!(read(&file).n_faces() as u64, faces, "level {level}");
            let out = dir.join(format!("{method}-l{level}.off"));
            assert_exit(
                &run(&[&"level", &h, &"--level", &level.to_string(), &"-o", &out]),
                0,
            );
            assert_eq!(read(&out).n_faces() as u64, faces);
        }
        // a looser normal bound is accepted and the hierarchy still refines exactly
        let loose = dir.join(format!("{method}-loose.mrh"));
        simplify(
            &torus,
            &loose,
            &[
                "--method",
                method,
                "--target-faces",
                "200",
                "--max-normal-deviation",
                "120",
            ],
        );
        let loose_full = dir.join(format!("{method}-loose.ply"));
        assert_exit(&run(&[&"refine", &loose, &"-o", &loose_full]), 0);
        assert_eq!(arrays(&read(&loose_full)), arrays(&read(&torus)));
        // refine: the input, bit for bit
        let full = dir.join(format!("{method}-full.ply"));
        let o = run(&[&"refine", &h, &"-o", &full, &"--json"]);
        assert_exit(&o, 0);
        assert!(json(&o)["refine_seconds"].is_number());
        assert_eq!(arrays(&read(&full)), arrays(&read(&torus)), "{method}");
    }
}

/// `simplify --placement quadric` refines back bit for bit, keeps its placement in the
/// file, and `distance` measures its coarsest level nearer the input than the midpoint
/// rounds' (the same surfaces give zero; the report has both sides).
#[test]
fn quadric_placement_and_distance() {
    let dir = temp("distance");
    let torus = torus_file(&dir, "t.obj", 40, 20);
    let mut coarse = Vec::new();
    for placement in ["midpoint", "quadric"] {
        let h = dir.join(format!("{placement}.mrh"));
        let o = run(&[
            &"simplify",
            &torus,
            &"-o",
            &h,
            &"--target-faces",
            &"200",
            &"--placement",
            &placement,
            &"--json",
        ]);
        assert_exit(&o, 0);
        assert_eq!(json(&o)["placement"], placement);
        let level = dir.join(format!("{placement}-coarsest.ply"));
        assert_exit(&run(&[&"level", &h, &"--level", &"99", &"-o", &level]), 0);
        coarse.push(level);
        let full = dir.join(format!("{placement}-full.ply"));
        assert_exit(&run(&[&"refine", &h, &"-o", &full]), 0);
        assert_eq!(arrays(&read(&full)), arrays(&read(&torus)), "{placement}");
    }
    let measure = |other: &Path| {
        let o = run(&[
            &"distance",
            &torus,
            &other,
            &"--samples",
            &"20000",
            &"--json",
        ]);
        assert_exit(&o, 0);
        json(&o)
    };
    let same = measure(&torus);
    assert!(same["hausdorff"].as_f64().unwrap() < 1e-12, "{same}");
    let (by_midpoint, by_quadric) = (measure(&coarse[0]), measure(&coarse[1]));
    for r in [&by_midpoint, &by_quadric] {
        for side in ["first_to_second", "second_to_first"] {
            assert!(r[side]["samples"].as_u64().unwrap() >= 20_000, "{r}");
            assert!(r[side]["mean"].as_f64().unwrap() <= r[side]["max"].as_f64().unwrap());
        }
        let d = r["diagonal"].as_f64().unwrap();
        let h = r["hausdorff"].as_f64().unwrap();
        assert!((r["hausdorff_over_diagonal"].as_f64().unwrap() - h / d).abs() < 1e-15);
    }
    assert!(
        by_quadric["mean"].as_f64().unwrap() < by_midpoint["mean"].as_f64().unwrap(),
        "{by_quadric} against {by_midpoint}"
    );
    // text output names both sides; nothing sampled or no file is an error
    let o = run(&[&"distance", &torus, &coarse[1]]);
    assert_exit(&o, 0);
    assert!(stdout(&o).contains("Hausdorff") && stdout(&o).contains("second -> first"));
    let o = run(&[
        &"distance",
        &torus,
        &coarse[1],
        &"--samples",
        &"0",
        &"--no-vertices",
    ]);
    assert_exit(&o, 1);
    assert!(
        stderr(&o).contains("neither vertices nor face samples"),
        "{}",
        stderr(&o)
    );
    assert_exit(&run(&[&"distance", &torus, &dir.join("missing.obj")]), 1);
    assert_exit(
        &run(&[
            &"simplify",
            &torus,
            &"-o",
            &dir.join("x.mrh"),
            &"--placement",
            &"centroid",
        ]),
        2,
    );
}

const RECIPE: &str = r#"
version = 1

[[step]]
method = "lee_drag"
level = 2
area = { kind = "disk", around = { extreme = "+z" }, vertices = 40 }
along_normal = 0.05
scale = 0.6

[[step]]
method = "blend"
level = 2
handle = { kind = "ball", around = { extreme = "+x" }, radius = 0.08 }
fixed = { kind = "beyond", around = { extreme = "+x" }, radius = 0.35 }
rotate = { axis = [0.0, 0.0, 1.0], degrees = 20.0 }

[[step]]
method = "twist"
level = 1
region = { kind = "cut", axis = "+y", at = 0.6 }
degrees = 30.0
propagation = 1
"#;

#[test]
fn edit_replays_a_recipe_as_the_library_does() {
    let dir = temp("edit");
    let torus = torus_file(&dir, "t.obj", 48, 24);
    let h = dir.join("h.mrh");
    simplify(&torus, &h, &["--target-faces", "300"]);
    let recipe_path = dir.join("r.toml");
    std::fs::write(&recipe_path, RECIPE).unwrap();
    let h2 = dir.join("h2.mrh");
    let mesh_out = dir.join("edited.ply");
    let o = run(&[
        &"edit",
        &h,
        &"--recipe",
        &recipe_path,
        &"-o",
        &h2,
        &"--mesh",
        &mesh_out,
    ]);
    assert_exit(&o, 0);
    // refine of the saved edited hierarchy = the mesh written by edit
    let refined = dir.join("refined.ply");
    assert_exit(&run(&[&"refine", &h2, &"-o", &refined]), 0);
    let cli = arrays(&read(&mesh_out));
    assert_eq!(arrays(&read(&refined)), cli);
    // = the same steps in this process
    let mut hierarchy = Hierarchy::load(&h).unwrap();
    let recipe = Recipe::from_toml(RECIPE, Path::new("r.toml")).unwrap();
    recipe::apply(&mut hierarchy, &recipe, &mut multires::progress::Silent).unwrap();
    hierarchy.refine_to(0).unwrap();
    assert_eq!(arrays(hierarchy.mesh()), cli, "CLI = library, bit for bit");
    // and the edits moved something
    assert_ne!(cli, arrays(&read(&torus)));
}

#[test]
fn recipe_errors_name_the_step_and_the_key() {
    let dir = temp("recipe-errors");
    let torus = torus_file(&dir, "t.obj", 16, 8);
    let h = dir.join("h.mrh");
    simplify(&torus, &h, &["--target-faces", "64"]);
    let cases = [
        // (recipe text, words the one-line error must contain)
        ("version = 1\n[[step]]\nmethod = \"pull\"\nregion = { kind = \"all\" }\noffset = [1.0, 0.0, 0.0]\n[[step]]\nmethod = \"scale\"\nregion = { kind = \"all\" }\nfactr = 2.0\n", vec!["step 2", "factr"]),
        ("version = 7\n", vec!["version 7"]),
        ("version = 1\n[[step]]\nmethod = \"melt\"\n", vec!["step 1", "melt"]),
        ("version = 1\n[[step]]\nmethod = \"blend\"\nhandle = { kind = \"ball\", around = { extreme = \"+w\" }, radius = 0.1 }\nfixed = { kind = \"all\" }\n", vec!["step 1", "blend", "+w"]),
        ("version = 1\n[[step]]\nmethod = \"smooth\"\nregion = { kind = \"ball\", around = { vertex = 99999 }, radius = 0.1 }\n", vec!["step 1", "smooth", "99999"]),
        ("this is not toml = = =", vec!["line 1"]),
    ];
    for (text, words) in cases {
        let r = dir.join("r.toml");
        std::fs::write(&r, text).unwrap();
        let out = dir.join("out.mrh");
        let _ = std::fs::remove_file(&out);
        let o = run(&[&"edit", &h, &"--recipe", &r, &"-o", &out]);
        assert_exit(&o, 1);
        let err = stderr(&o);
        for w in &words {
            assert!(err.contains(w), "{text:?}: the error names {w:?}: {err}");
        }
        assert!(!out.exists(), "nothing written after a refused recipe");
    }
}

#[test]
fn damaged_hierarchy_files_are_refused() {
    let dir = temp("damaged");
    let torus = torus_file(&dir, "t.obj", 16, 8);
    let h = dir.join("h.mrh");
    simplify(&torus, &h, &["--target-faces", "64"]);
    let bytes = std::fs::read(&h).unwrap();
    let mut flipped = bytes.clone();
    let middle = flipped.len() / 2;
    flipped[middle] ^= 0x10;
    let mut other_version = bytes.clone();
    // the version follows the 8-byte magic (see docs/guide/hierarchy-file.md)
    other_version[8] = other_version[8].wrapping_add(1);
    for (name, damaged) in [
        ("truncated.mrh", bytes[..bytes.len() / 3].to_vec()),
        ("flipped.mrh", flipped),
        ("version.mrh", other_version),
        ("empty.mrh", Vec::new()),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, damaged).unwrap();
        for args in [
            vec![
                "refine".as_ref(),
                path.as_os_str(),
                "-o".as_ref(),
                dir.join("x.ply").as_os_str(),
            ],
            vec!["info".as_ref(), path.as_os_str()],
            vec![
                "level".as_ref(),
                path.as_os_str(),
                "--level".as_ref(),
                "1".as_ref(),
                "-o".as_ref(),
                dir.join("x.ply").as_os_str(),
            ],
        ] {
            let o = multires().args(&args).output().unwrap();
            assert_exit(&o, 1);
            assert!(stderr(&o).contains(name), "{name}: {}", stderr(&o));
        }
    }
}

#[test]
fn workflow_runs_and_reports_its_phases() {
    let dir = temp("workflow");
    let torus = torus_file(&dir, "t.obj", 48, 24);
    let out = dir.join("out");
    let o = run(&[
        &"workflow",
        &torus,
        &"--out",
        &out,
        &"--picture",
        &"80",
        &"--json",
    ]);
    assert_exit(&o, 0);
    let r = json(&o);
    let text = r.to_string();
    for phase in ["load", "simplify", "refine", "write"] {
        assert!(text.contains(phase), "{phase}: {text}");
    }
    let written: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    let mesh = written
        .iter()
        .find(|p| p.extension().is_some_and(|e| e == "ply"))
        .expect("the edited mesh");
    let edited = read(mesh);
    assert_eq!(edited.n_faces(), 2 * 48 * 24);
    edited.check().unwrap();
    assert!(written
        .iter()
        .any(|p| p.extension().is_some_and(|e| e == "png")));
}

/// A corpus: three tori of different sizes, an OFF, and a file that is not a mesh.
fn corpus(dir: &Path) -> PathBuf {
    let corpus = dir.join("corpus");
    std::fs::create_dir_all(corpus.join("sub")).unwrap();
    torus_file(&corpus, "a.obj", 30, 14);
    torus_file(&corpus, "b.ply", 36, 12);
    torus_file(&corpus.join("sub"), "c.off", 24, 16);
    torus_file(&corpus, "d.stl", 20, 10);
    std::fs::write(corpus.join("broken.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    std::fs::write(corpus.join("notes.txt.bak"), "not a mesh").unwrap();
    corpus
}

const BATCH_RECIPE: &str = r#"
version = 1
[hierarchy]
target_faces = 150

[[step]]
method = "scale"
level = 1
region = { kind = "cut", axis = "+x", at = 0.7 }
factor = 1.2
propagation = 1
"#;

fn report_rows(out: &Path) -> Vec<serde_json::Value> {
    std::fs::read_to_string(out.join("report.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn outputs(out: &Path) -> Vec<(String, Vec<u8>)> {
    fn walk(root: &Path, dir: &Path, files: &mut Vec<(String, Vec<u8>)>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(root, &path, files);
            } else if path.extension().is_some_and(|e| e == "ply") {
                let name = path
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                files.push((name, std::fs::read(&path).unwrap()));
            }
        }
    }
    let mut files = Vec::new();
    walk(out, out, &mut files);
    files.sort();
    files
}

#[test]
fn batch_runs_in_parallel_and_resumes() {
    let dir = temp("batch");
    let corpus = corpus(&dir);
    let recipe = dir.join("r.toml");
    std::fs::write(&recipe, BATCH_RECIPE).unwrap();
    let out = dir.join("out");
    let o = run(&[
        &"batch",
        &corpus,
        &"--recipe",
        &recipe,
        &"--out",
        &out,
        &"--jobs",
        &"2",
        &"--json",
    ]);
    // one bad mesh: exit 1, and every other mesh done
    assert_exit(&o, 1);
    assert!(stderr(&o).contains("broken.obj") || stdout(&o).contains("broken.obj"));
    let rows = report_rows(&out);
    assert_eq!(rows.len(), 5, "{rows:?}");
    for row in &rows {
        for key in ["input", "status", "seconds", "faces", "error"] {
            assert!(row.get(key).is_some(), "{key} in {row}");
        }
        let broken = row["input"].as_str().unwrap().ends_with("broken.obj");
        assert_eq!(row["status"], if broken { "error" } else { "ok" }, "{row}");
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        (summary["ok"].as_u64(), summary["errors"].as_u64()),
        (Some(4), Some(1))
    );
    let first = outputs(&out);
    assert_eq!(first.len(), 4);

    // the same outputs with one job
    let serial = dir.join("serial");
    let o = run(&[
        &"batch",
        &corpus,
        &"--recipe",
        &recipe,
        &"--out",
        &serial,
        &"--jobs",
        &"1",
        &"-q",
    ]);
    assert_exit(&o, 1);
    assert_eq!(outputs(&serial), first, "1 job = 2 jobs, byte for byte");

    // resumed: everything done is skipped
    let o = run(&[
        &"batch",
        &corpus,
        &"--recipe",
        &recipe,
        &"--out",
        &out,
        &"--json",
    ]);
    assert_exit(&o, 1);
    let rows = report_rows(&out);
    let last: Vec<_> = rows[5..]
        .iter()
        .map(|r| r["status"].as_str().unwrap().to_owned())
        .collect();
    assert_eq!(
        last.iter().filter(|s| *s == "skipped").count(),
        4,
        "{last:?}"
    );

    // interrupted: one output lost (and a half-written one) → only that mesh runs again
    let (lost, _) = &first[0];
    std::fs::remove_file(out.join(lost)).unwrap();
    let (half, bytes) = &first[1];
    std::fs::write(out.join(half), &bytes[..bytes.len() / 2]).unwrap();
    let o = run(&[
        &"batch",
        &corpus,
        &"--recipe",
        &recipe,
        &"--out",
        &out,
        &"--json",
    ]);
    assert_exit(&o, 1);
    let rows = report_rows(&out);
    let ran: Vec<_> = rows[10..]
        .iter()
        .filter(|r| r["status"] == "ok")
        .map(|r| r["input"].as_str().unwrap().to_owned())
        .collect();
    assert_eq!(ran.len(), 2, "{ran:?}");
    assert_eq!(outputs(&out), first, "the redone outputs are the same");

    // a changed recipe runs everything again
    std::fs::write(&recipe, BATCH_RECIPE.replace("1.2", "1.3")).unwrap();
    let o = run(&[
        &"batch",
        &corpus,
        &"--recipe",
        &recipe,
        &"--out",
        &out,
        &"--json",
    ]);
    assert_exit(&o, 1);
    let rows = report_rows(&out);
    assert_eq!(rows[15..].iter().filter(|r| r["status"] == "ok").count(), 4);
}

#[test]
fn shards_partition_the_corpus() {
    let dir = temp("shards");
    let corpus = corpus(&dir);
    let recipe = dir.join("r.toml");
    std::fs::write(&recipe, BATCH_RECIPE).unwrap();
    let mut seen = Vec::new();
    for i in 1..=3 {
        let out = dir.join(format!("out-{i}"));
        let o = run(&[
            &"batch",
            &corpus,
            &"--recipe",
            &recipe,
            &"--out",
            &out,
            &"--shard",
            &format!("{i}/3"),
            &"-q",
        ]);
        assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
        let rows = if out.join("report.jsonl").exists() {
            report_rows(&out)
        } else {
            Vec::new()
        };
        seen.extend(rows.iter().map(|r| r["input"].as_str().unwrap().to_owned()));
        assert!(out.join(format!("summary-{i}-of-3.json")).exists());
    }
    seen.sort();
    let before = seen.len();
    seen.dedup();
    assert_eq!(
        (before, seen.len()),
        (5, 5),
        "every mesh in exactly one shard: {seen:?}"
    );
    for bad in ["0/3", "4/3", "1/0", "a/b", "1-3"] {
        let o = run(&[
            &"batch",
            &corpus,
            &"--recipe",
            &recipe,
            &"--out",
            &dir.join("x"),
            &"--shard",
            &bad,
        ]);
        assert_exit(&o, 1);
        assert!(stderr(&o).contains(bad), "{bad}: {}", stderr(&o));
    }
}

#[test]
fn batch_takes_globs_and_manifests() {
    let dir = temp("batch-inputs");
    let corpus = corpus(&dir);
    let out = dir.join("out");
    let manifest = dir.join("list.txt");
    std::fs::write(
        &manifest,
        format!(
            "# two meshes\n{}\n\n{}\n",
            corpus.join("a.obj").display(),
            corpus.join("sub/c.off").display()
        ),
    )
    .unwrap();
    let recipe = dir.join("r.toml");
    std::fs::write(&recipe, BATCH_RECIPE).unwrap();
    let glob = format!("{}/*.ply", corpus.display());
    let o = run(&[
        &"batch",
        &manifest,
        &glob,
        &"--recipe",
        &recipe,
        &"--out",
        &out,
        &"-q",
    ]);
    assert_exit(&o, 0);
    let mut inputs: Vec<_> = report_rows(&out)
        .iter()
        .map(|r| {
            Path::new(r["input"].as_str().unwrap())
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    inputs.sort();
    assert_eq!(inputs, ["a.obj", "b.ply", "c.off"]);
    // without a recipe: the workflow, on each mesh
    let wf = dir.join("wf");
    let o = run(&[
        &"batch",
        &corpus.join("a.obj"),
        &"--out",
        &wf,
        &"--picture",
        &"64",
        &"-q",
    ]);
    assert_exit(&o, 0);
    let rows = report_rows(&wf);
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0]["status"], "ok");
    let edited = read(&wf.join("a-edited.ply"));
    assert_eq!(edited.n_faces(), 2 * 30 * 14);
    assert_ne!(
        arrays(&edited),
        arrays(&read(&corpus.join("a.obj"))),
        "the workflow edited it"
    );
    assert!(wf.join("a-pictures").is_dir());
    // a glob that matches nothing and a missing manifest are input errors
    let o = run(&[
        &"batch",
        &format!("{}/*.nothing", corpus.display()),
        &"--out",
        &out,
    ]);
    assert_exit(&o, 1);
}

/// OpenMesh tier: `check --openmesh` agrees with OpenMesh on a generated mesh in each
/// format OpenMesh 1.2.1 reads (OBJ, PLY, OFF, STL, and gzip through a temporary file).
/// Run with `cargo test --release --test cli -- --ignored` (needs python3 with
/// `pip install openmesh==1.2.1 numpy`).
#[test]
#[ignore = "OpenMesh tier: needs python3 with openmesh==1.2.1 (see the doc comment)"]
fn check_agrees_with_openmesh() {
    let dir = temp("openmesh");
    let torus = generators::torus(2.0, 0.7, 20, 9).unwrap();
    let grid = generators::grid(7, 5, 1.0, 1.0);
    for (mesh, stem) in [(&torus, "torus"), (&grid, "grid")] {
        for ext in ["obj", "ply", "off", "stl", "off.gz"] {
            let path = dir.join(format!("{stem}.{ext}"));
            halfedge::io::write(&path, mesh).unwrap();
            let o = run(&[&"check", &path, &"--openmesh", &"--json"]);
            assert_exit(&o, 0);
            let r = json(&o);
            assert_eq!(r["openmesh_agrees"], true, "{stem}.{ext}: {r}");
            assert_eq!(r["counts"]["faces"].as_u64(), Some(mesh.n_faces() as u64));
        }
    }
}

/// Every output file is the same bytes whatever the thread count (`RAYON_NUM_THREADS` 1,
/// 2 and 5): the hierarchy file of both methods and of the rounds placed by the quadric,
/// the workflow's mesh and its four pictures, and the edited meshes of a batch.
#[test]
fn files_do_not_depend_on_the_thread_count() {
    let dir = temp("threads");
    let torus = torus_file(&dir, "t.ply", 60, 30);
    let corpus = dir.join("corpus");
    std::fs::create_dir_all(&corpus).unwrap();
    torus_file(&corpus, "a.ply", 40, 20);
    torus_file(&corpus, "b.obj", 30, 24);
    use std::ffi::OsStr;
    let with_threads = |threads: &str, args: &[&OsStr]| {
        let o = multires()
            .env("RAYON_NUM_THREADS", threads)
            .args(args)
            .output()
            .unwrap();
        assert_exit(&o, 0);
    };
    let runs: [(&str, &[&str]); 3] = [
        ("rounds", &["--method", "rounds"]),
        ("qem", &["--method", "qem"]),
        ("quadric", &["--method", "rounds", "--placement", "quadric"]),
    ];
    for (name, options) in runs {
        let mut files = Vec::new();
        for threads in ["1", "2", "5"] {
            let h = dir.join(format!("{name}-{threads}.mrh"));
            let mut args = vec![OsStr::new("simplify")];
            args.extend(options.iter().map(OsStr::new));
            args.extend(["--target-faces", "100", "-q", "-o"].map(OsStr::new));
            args.extend([h.as_os_str(), torus.as_os_str()]);
            with_threads(threads, &args);
            files.push(std::fs::read(&h).unwrap());
        }
        assert!(
            files.windows(2).all(|w| w[0] == w[1]),
            "{name}: the same bytes on 1, 2 and 5 threads"
        );
    }
    // The workflow (mesh and pictures) and a batch of the workflow over two meshes.
    let outputs = |threads: &str| -> Vec<(String, Vec<u8>)> {
        let out = dir.join(format!("workflow-{threads}"));
        let workflow = ["workflow", "--picture", "120", "-q", "--out"].map(OsStr::new);
        with_threads(
            threads,
            &[&workflow[..], &[out.as_os_str(), torus.as_os_str()]].concat(),
        );
        let batch = dir.join(format!("batch-{threads}"));
        let run = ["batch", "-q", "--out"].map(OsStr::new);
        with_threads(
            threads,
            &[&run[..], &[batch.as_os_str(), corpus.as_os_str()]].concat(),
        );
        let mut files = Vec::new();
        for folder in [out, batch] {
            let mut names: Vec<_> = std::fs::read_dir(&folder)
                .unwrap()
                .map(|e| e.unwrap().path())
                .filter(|p| {
                    // The batch's reports hold timings; its meshes are the output.
                    !matches!(
                        p.extension().and_then(|e| e.to_str()),
                        Some("jsonl" | "json")
                    )
                })
                .collect();
            names.sort();
            for path in names {
                let name = path.file_name().unwrap().to_string_lossy().into_owned();
                files.push((name, std::fs::read(&path).unwrap()));
            }
        }
        files
    };
    let one = outputs("1");
    let names: Vec<&str> = one.iter().map(|(n, _)| n.as_str()).collect();
    assert!(
        names.iter().filter(|n| n.ends_with(".png")).count() >= 4
            && names.iter().filter(|n| n.ends_with(".ply")).count() >= 3,
        "the workflow's mesh and pictures and the batch's meshes: {names:?}"
    );
    for threads in ["2", "5"] {
        let other = outputs(threads);
        assert_eq!(
            other.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>(),
            names,
            "the same files on {threads} threads"
        );
        for ((name, a), (_, b)) in one.iter().zip(&other) {
            assert!(a == b, "{name}: the same bytes on 1 and {threads} threads");
        }
    }
}

/// A portable recipe (places by extreme vertex, radii as fractions of the diagonal) made
/// for one resolution does the same edit on another: on two resolutions of a sphere, each
/// simplified to the same size and edited at its coarsest level, the handle's tip moves
/// by the recipe's translation and the far side stays, within a tenth of it.
#[test]
fn a_portable_recipe_carries_over_between_resolutions() {
    let dir = temp("resolutions");
    let recipe_path = dir.join("r.toml");
    std::fs::write(
        &recipe_path,
        r#"
version = 1
[[step]]
method = "blend"
level = 99
handle = { kind = "ball", around = { extreme = "+x" }, radius = 0.15 }
fixed = { kind = "beyond", around = { extreme = "+x" }, radius = 0.6 }
translate = [0.2, 0.0, 0.0]
"#,
    )
    .unwrap();
    for level in [4, 5] {
        let sphere = dir.join(format!("sphere-{level}.ply"));
        halfedge::io::write(&sphere, &generators::icosphere(level)).unwrap();
        let h = dir.join(format!("sphere-{level}.mrh"));
        simplify(&sphere, &h, &["--target-faces", "320"]);
        let out = dir.join(format!("edited-{level}.ply"));
        let h2 = dir.join(format!("edited-{level}.mrh"));
        assert_exit(
            &run(&[
                &"edit",
                &h,
                &"--recipe",
                &recipe_path,
                &"-o",
                &h2,
                &"--mesh",
                &out,
            ]),
            0,
        );
        let before = read(&sphere);
        let after = read(&out);
        assert_eq!(before.n_vertices(), after.n_vertices());
        let nearest = |target: [f64; 3]| {
            (0..before.n_vertices())
                .min_by(|&a, &b| {
                    let d =
                        |i: usize| before.positions()[i].distance(glam::DVec3::from_array(target));
                    d(a).total_cmp(&d(b))
                })
                .unwrap()
        };
        let moved = |i: usize| after.positions()[i] - before.positions()[i];
        let tip = moved(nearest([1.0, 0.0, 0.0]));
        let far = moved(nearest([-1.0, 0.0, 0.0]));
        assert!(
            (tip.x - 0.2).abs() < 0.02 && tip.y.abs() < 0.02 && tip.z.abs() < 0.02,
            "level {level}: the tip moved {tip}"
        );
        assert!(
            far.length() < 0.02,
            "level {level}: the far side moved {far}"
        );
    }
}
