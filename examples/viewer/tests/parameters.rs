//! The tools' parameters are declared once (a table per tool, `viewer::tools::params`):
//! the listing, the script setter and the widget come from the same entries. These tests
//! check, for every tool, that what is listed can be set back through the same name, that
//! a set value is what the listing shows, that unknown names are refused with the table's
//! names, and that values out of a method's range pass through to the library, whose
//! error is shown.

use std::time::{Duration, Instant};

use halfedge::generators;
use viewer::document::Document;
use viewer::tools::{default_tools, Background, Headless, Tool};

/// The tools on a small sphere, without a window.
fn fixture() -> Headless {
    Headless::new(Document::new(generators::icosphere(2), None, None))
}

fn listed(tool: &dyn Tool, name: &str) -> Option<serde_json::Value> {
    tool.parameters()
        .into_iter()
        .find(|(n, _)| *n == name)
        .map(|(_, v)| v)
}

/// Parameters whose setter needs state the fresh tool lacks (a hierarchy to walk).
const NEEDS_STATE: &[(&str, &str)] = &[("Multiresolution", "level")];

#[test]
fn every_listed_parameter_is_set_back_by_its_name() {
    let mut fixture = fixture();
    for mut tool in default_tools() {
        let listing = tool.parameters();
        let mut names: Vec<&str> = listing.iter().map(|(n, _)| *n).collect();
        names.sort_unstable();
        let before = names.len();
        names.dedup();
        assert_eq!(names.len(), before, "{}: a name listed twice", tool.name());
        for (name, value) in listing {
            if NEEDS_STATE.contains(&(tool.name(), name)) {
                continue;
            }
            let mut ctx = fixture.ctx();
            if let Err(e) = tool.set_parameter(name, &value, &mut ctx) {
                // Read-only values (counts) say so; a setter may also fail at what the
                // value sets off (a transform with no region yet), but never at the
                // value itself, nor at its name.
                let refused = ["has no parameter", "wants", "one of"];
                assert!(
                    e.0.contains("read-only") || !refused.iter().any(|r| e.0.contains(r)),
                    "{}: {name} = {value} refused: {e}",
                    tool.name()
                );
            }
            assert_eq!(
                listed(tool.as_ref(), name),
                Some(value.clone()),
                "{}: {name} set to its own value reads back otherwise",
                tool.name()
            );
        }
    }
}

#[test]
fn unknown_parameters_are_refused_with_the_tables_names() {
    let mut fixture = fixture();
    for mut tool in default_tools() {
        let mut ctx = fixture.ctx();
        let e = tool
            .set_parameter("no_such_parameter", &1.into(), &mut ctx)
            .unwrap_err();
        for (name, _) in tool.parameters() {
            assert!(
                e.0.contains(name),
                "{}: the error {e} does not name {name}",
                tool.name()
            );
        }
    }
}

/// A value set by a script is the value listed, for one parameter of every kind.
#[test]
fn set_values_are_the_listed_values() {
    let cases: &[(&str, &str, serde_json::Value)] = &[
        ("Inspect", "color", "valence".into()),
        ("Multiresolution", "target_faces", 123.into()),
        ("Multiresolution", "method", "qem".into()),
        ("Multiresolution", "flip", true.into()),
        ("Lee area editing", "scale", 0.25.into()),
        ("Lee area editing", "frames", "normal".into()),
        ("Bendels–Klein", "brush", 0.125.into()),
        ("Bendels–Klein", "distance", "euclidean".into()),
        ("Sub-mesh edits", "iterations", 7.into()),
        ("Sub-mesh edits", "smooth_region", "mesh".into()),
        ("FFD", "grid_u", 9.into()),
        ("FFD", "twist", 45.0.into()),
    ];
    let mut fixture = fixture();
    let mut tools = default_tools();
    for (tool_name, name, value) in cases {
        let tool = tools
            .iter_mut()
            .find(|t| t.name() == *tool_name)
            .unwrap_or_else(|| panic!("no tool {tool_name}"));
        assert_ne!(listed(tool.as_ref(), name).as_ref(), Some(value), "{name}");
        tool.set_parameter(name, value, &mut fixture.ctx())
            .unwrap_or_else(|e| panic!("{tool_name}: {name}: {e}"));
        let shown = listed(tool.as_ref(), name).unwrap();
        assert_eq!(
            shown
                .as_f64()
                .zip(value.as_f64())
                .map_or(shown.clone(), |(a, _)| a.into()),
            value.as_f64().map_or(value.clone(), |b| b.into()),
            "{tool_name}: {name}"
        );
    }
}

/// Range checks are the library's: the viewer passes an out-of-range planarity bound
/// through, and the hierarchy's build refuses it with its own message.
#[test]
fn out_of_range_values_reach_the_library_which_refuses_them() {
    let mut fixture = fixture();
    let mut tools = default_tools();
    let tool = tools
        .iter_mut()
        .find(|t| t.name() == "Multiresolution")
        .unwrap();
    tool.set_parameter("max_normal_deviation", &200.0.into(), &mut fixture.ctx())
        .unwrap();
    assert_eq!(
        listed(tool.as_ref(), "max_normal_deviation"),
        Some(200.0.into())
    );
    tool.apply(&mut fixture.ctx()).unwrap();
    let start = Instant::now();
    let failed = loop {
        match tool.poll(&mut fixture.ctx()) {
            Background::Running => {
                assert!(start.elapsed() < Duration::from_secs(60));
                std::thread::sleep(Duration::from_millis(5));
            }
            other => break other,
        }
    };
    match failed {
        Background::Failed(e) => assert!(e.0.contains("max_normal_deviation"), "{e}"),
        other => panic!("the build accepted 200°: {other:?}"),
    }
    assert!(fixture.status.is_error);
    // A value that is no number at all is the viewer's to refuse.
    assert!(tool
        .set_parameter("target_faces", &"many".into(), &mut fixture.ctx())
        .is_err());
}

/// The same for a sub-mesh edit: a negative scale factor passes through the table and the
/// edit refuses it (nothing moves).
#[test]
fn a_negative_scale_is_refused_by_the_sub_mesh_edit() {
    let mut fixture = fixture();
    let before = fixture.doc.mesh().positions().to_vec();
    let mut tools = default_tools();
    let tool = tools
        .iter_mut()
        .find(|t| t.name() == "Sub-mesh edits")
        .unwrap();
    for (name, value) in [
        ("source", serde_json::Value::from("all")),
        ("operation", "scale".into()),
        ("scale", (-1.0).into()),
    ] {
        tool.set_parameter(name, &value, &mut fixture.ctx())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
    }
    assert_eq!(listed(tool.as_ref(), "scale"), Some((-1.0).into()));
    let e = tool.apply(&mut fixture.ctx()).unwrap_err();
    assert!(e.0.contains("not positive"), "{e}");
    assert_eq!(fixture.doc.mesh().positions(), &before[..]);
}
