//! A recipe refused part-way leaves a plain mesh as it was: the steps before the failing
//! one are undone (positions bit for bit, the sub-mesh labels as they were).

use std::path::Path;

use halfedge::generators;
use halfedge::labels::LABEL_ATTRIBUTE;
use halfedge::VertexId;
use multires::progress::Silent;
use multires::recipe::{apply_to_mesh, Recipe, RecipeError};
use testkit::check::slot_position_bits;

const RECIPE: &str = r#"
version = 1

[[step]]
method = "pull"
region = { kind = "cut", axis = "+z", at = 0.6 }
offset = [0.0, 0.0, 0.25]
propagation = 1

[[step]]
method = "scale"
region = { kind = "all" }
factor = 1.5

[[step]]
method = "smooth"
region = { kind = "ball", around = { vertex = 999999 }, radius = 0.1 }
"#;

#[test]
fn a_refused_recipe_leaves_the_mesh_as_it_was() {
    let mut mesh = generators::torus(2.0, 0.7, 40, 20).unwrap();
    let recipe = Recipe::from_toml(RECIPE, Path::new("r.toml")).unwrap();
    let before = slot_position_bits(&mesh);
    assert!(mesh
        .find_attribute::<VertexId, u32>(LABEL_ATTRIBUTE)
        .is_none());
    let e = apply_to_mesh(&mut mesh, &recipe, &mut Silent).unwrap_err();
    assert!(matches!(e, RecipeError::Step { step: 3, .. }), "{e}");
    let after = slot_position_bits(&mesh);
    let differ = before.iter().zip(&after).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "positions put back bit for bit: {differ} differ");
    assert!(
        mesh.find_attribute::<VertexId, u32>(LABEL_ATTRIBUTE)
            .is_none(),
        "no labels left behind"
    );
    mesh.check().unwrap();

    // with labels already there, they come back as they were
    let mut recipe_ok = recipe.clone();
    recipe_ok.steps.truncate(1);
    apply_to_mesh(&mut mesh, &recipe_ok, &mut Silent).unwrap();
    let labels = mesh
        .find_attribute::<VertexId, u32>(LABEL_ATTRIBUTE)
        .expect("the cut labelled the mesh");
    let labelled = mesh.attribute_values(labels).unwrap().to_vec();
    let moved = slot_position_bits(&mesh);
    assert_ne!(moved, before, "the pull moved the cut-off part");
    let mut relabel = recipe.clone();
    relabel.steps[0] = Recipe::from_toml(
        "version = 1\n[[step]]\nmethod = \"pull\"\nregion = { kind = \"cut\", axis = \"-x\", at = 0.5 }\noffset = [0.1, 0.0, 0.0]\n",
        Path::new("r2.toml"),
    )
    .unwrap()
    .steps
    .remove(0);
    apply_to_mesh(&mut mesh, &relabel, &mut Silent).unwrap_err();
    let now = mesh
        .find_attribute::<VertexId, u32>(LABEL_ATTRIBUTE)
        .unwrap();
    assert_eq!(
        mesh.attribute_values(now).unwrap(),
        &labelled[..],
        "labels put back"
    );
    let after = slot_position_bits(&mesh);
    assert!(
        after == moved,
        "positions put back bit for bit after the second refusal"
    );
}
