//! Checks on the viewer's module structure, read from its sources: the application
//! ([`viewer::app`]) sits on top; the tools (and the other modules below it) never import
//! it, so the modules form no import loop through `app`.

use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, recursively.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
    out.sort();
    out
}

/// The lines of `source` (comments dropped) that name the module `app` of the crate:
/// `crate::app`, or `app` inside a `use crate::{…}` group.
fn imports_of_app(source: &str) -> Vec<String> {
    let code: String = source
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n");
    let mut found: Vec<String> = code
        .lines()
        .filter(|l| l.contains("crate::app") || l.contains("super::app"))
        .map(|l| l.trim().to_owned())
        .collect();
    // `use crate::{app, …}` or `use crate::{\n app::…`.
    let mut rest = code.as_str();
    while let Some(i) = rest.find("crate::{") {
        let group = &rest[i + "crate::{".len()..];
        let end = group.find("};").unwrap_or(group.len());
        let names = &group[..end];
        if names
            .split(|c: char| !(c.is_alphanumeric() || c == '_'))
            .any(|w| w == "app")
        {
            found.push(format!("crate::{{{}}}", names.trim()));
        }
        rest = &group[end..];
    }
    found
}

#[test]
fn the_scanner_sees_every_form_of_import() {
    assert!(imports_of_app("use crate::format::group;\n").is_empty());
    assert_eq!(imports_of_app("use crate::app::group;\n").len(), 1);
    assert_eq!(imports_of_app("let x = crate::app::group(3);\n").len(), 1);
    assert_eq!(
        imports_of_app("use crate::{\n    app::group,\n    colors::Rgba,\n};\n").len(),
        1
    );
    assert!(imports_of_app("// see crate::app for the frame loop\n").is_empty());
    assert!(imports_of_app("use crate::{colors::Rgba, format::group};\n").is_empty());
}

#[test]
fn no_tool_imports_the_app() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let tools = rust_files(&src.join("tools"));
    assert!(tools.len() >= 6, "the tools are under src/tools: {tools:?}");
    let mut offenders = Vec::new();
    // The tools, and every other module the app uses (only lib.rs, the binary and the
    // app's own files may name it).
    for path in rust_files(&src) {
        let rel = path.strip_prefix(&src).unwrap();
        let top = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        if matches!(top.as_ref(), "lib.rs" | "main.rs" | "app.rs" | "app") {
            continue;
        }
        let source = std::fs::read_to_string(&path).unwrap();
        for line in imports_of_app(&source) {
            offenders.push(format!("{}: {line}", rel.display()));
        }
    }
    assert!(
        offenders.is_empty(),
        "modules below the app import it (an import loop):\n{}",
        offenders.join("\n")
    );
}

/// Widgets bound straight to a tool's fields: a parameter drawn this way bypasses its
/// table entry (and so the setter scripts use).
const FIELD_WIDGETS: &[&str] = &[
    "Slider::new(&mut self.",
    "DragValue::new(&mut self.",
    "checkbox(&mut self.",
    "selectable_value(&mut self.",
    "radio_value(&mut self.",
];

#[test]
fn tool_parameters_are_declared_once_in_their_table() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/tools");
    let mut offenders = Vec::new();
    let mut tables = 0;
    for path in rust_files(&src) {
        let source = std::fs::read_to_string(&path).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        for pattern in FIELD_WIDGETS {
            if source.contains(pattern) {
                offenders.push(format!("{name}: a widget on a field ({pattern}…)"));
            }
        }
        if !source.contains("impl Tool for ") {
            continue;
        }
        if let Some(i) = source.find("fn set_parameter(") {
            // The body of every tool's setter is the table's.
            let body = &source[i..source[i..]
                .find("\n    }\n")
                .map_or(source.len(), |e| i + e)];
            if !body.contains("params::set(") || body.contains("match name") {
                offenders.push(format!("{name}: set_parameter does not use the table"));
            }
            tables += usize::from(source.contains("const PARAMS: &[Param<"));
        }
        if let Some(i) = source.find("fn parameters(&self)") {
            let body = &source[i..source[i..]
                .find("\n    }\n")
                .map_or(source.len(), |e| i + e)];
            if !body.contains("params::list(") {
                offenders.push(format!("{name}: parameters() does not use the table"));
            }
        }
    }
    assert!(tables >= 6, "only {tables} tools have a parameter table");
    assert!(offenders.is_empty(), "{}", offenders.join("\n"));
}

/// The document owns the one mesh (and its hierarchy): no tool keeps a hierarchy (a second
/// mesh) of its own, recognises meshes by hashing their connectivity, or keeps labels
/// outside the mesh's label attribute.
#[test]
fn one_mesh_one_hierarchy_one_label_store() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let forbidden = [
        ("connectivity_fingerprint", "a connectivity hash"),
        ("SharedLabels", "labels kept outside the mesh"),
    ];
    let mut offenders = Vec::new();
    for path in rust_files(&src) {
        let source = std::fs::read_to_string(&path).unwrap();
        let rel = path.strip_prefix(&src).unwrap().display().to_string();
        for (word, what) in forbidden {
            if source.contains(word) {
                offenders.push(format!("{rel}: {what} ({word})"));
            }
        }
        if rel.starts_with("tools") {
            for held in ["Option<Hierarchy>", ": Hierarchy,", "Vec<Hierarchy>"] {
                if source.contains(held) {
                    offenders.push(format!("{rel}: a tool holds a hierarchy ({held})"));
                }
            }
        }
    }
    let document = std::fs::read_to_string(src.join("document.rs")).unwrap();
    assert!(
        document.contains("Levels(Box<Hierarchy>)"),
        "the document holds the hierarchy"
    );
    assert!(offenders.is_empty(), "{}", offenders.join("\n"));
}

/// The fields of `pub struct App { … }` in `source`.
fn app_fields(source: &str) -> Vec<String> {
    let start = source.find("pub struct App {").expect("pub struct App");
    let body = &source[start + "pub struct App {".len()..];
    let body = &body[..body.find("\n}").unwrap()];
    body.lines()
        .map(str::trim)
        .filter(|l| !l.starts_with("//") && l.contains(':'))
        .map(|l| l.split(':').next().unwrap().trim().to_owned())
        .collect()
}

/// `App` is split into parts, each a struct in a module of its own: the script runner,
/// the input handling and the scene / render state; `App` holds them and a few fields.
#[test]
fn the_app_is_split_into_a_script_runner_input_and_scene() {
    let app = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/app");
    let read = |name: &str| {
        std::fs::read_to_string(app.join(name)).unwrap_or_else(|e| panic!("src/app/{name}: {e}"))
    };
    let parts = [
        ("script_runner.rs", "struct ScriptRunner {"),
        ("input.rs", "struct Input {"),
        ("scene.rs", "struct Scene {"),
    ];
    for (file, item) in parts {
        assert!(read(file).contains(item), "src/app/{file} defines {item}");
    }
    let fields = app_fields(&read("mod.rs"));
    for part in ["script", "input", "scene"] {
        assert!(
            fields.iter().any(|f| f == part),
            "App holds its {part}: {fields:?}"
        );
    }
    // What moved into the parts stays there.
    for moved in [
        "camera",
        "renderer",
        "bvh",
        "gesture",
        "viewport",
        "pick",
        "screenshot",
        "measurement",
        "keep_open",
    ] {
        assert!(
            !fields.iter().any(|f| f == moved),
            "App holds {moved} itself"
        );
    }
    assert!(
        fields.len() <= 14,
        "App has {} fields: {fields:?}",
        fields.len()
    );
}

#[test]
fn the_field_reader_reads_fields() {
    let source = "pub struct App {\n    /// Doc.\n    a: u32,\n    b: Option<Vec<u8>>,\n}\n";
    assert_eq!(app_fields(source), ["a", "b"]);
}
