//! The scene file reference chapter is the one generated from the schema, and
//! the schema it is generated from is the one the loader uses.
//! `TUMBLE_UPDATE_MANUAL=1 cargo test -p tumble-manual --test scene_reference`
//! rewrites the chapter.

use std::path::Path;

fn repo(path: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(path)
}

#[test]
fn scene_reference_chapter_matches_the_schema() {
    let schema = tumble::scene::json_schema();
    let shipped = std::fs::read_to_string(repo("docs/scene.schema.json")).unwrap();
    assert_eq!(
        schema, shipped,
        "docs/scene.schema.json is stale (see crates/tumble/tests/scene_files.rs)"
    );
    let expected = tumble_manual::scene_reference::generate(&schema).unwrap();
    let chapter = repo("docs/manual/src/reference/scene-reference.md");
    if std::env::var_os("TUMBLE_UPDATE_MANUAL").is_some() {
        std::fs::write(&chapter, &expected).unwrap();
    }
    let committed = std::fs::read_to_string(&chapter).unwrap_or_default();
    assert!(
        committed == expected,
        "{} is not the one generated from the schema: run \
         `TUMBLE_UPDATE_MANUAL=1 cargo test -p tumble-manual --test scene_reference`",
        chapter.display()
    );
}

/// Every key of every object in the schema appears in the chapter as a table row:
/// an independent walk of the schema, not the generator's.
#[test]
fn every_schema_key_has_a_row() {
    let schema: serde_json::Value = serde_json::from_str(&tumble::scene::json_schema()).unwrap();
    let chapter = tumble_manual::scene_reference::generate(&tumble::scene::json_schema()).unwrap();
    let mut keys = 0;
    let mut stack = vec![&schema];
    while let Some(v) = stack.pop() {
        match v {
            serde_json::Value::Object(map) => {
                if let Some(props) = map.get("properties").and_then(|p| p.as_object()) {
                    for key in props.keys().filter(|k| *k != "type") {
                        keys += 1;
                        assert!(
                            chapter.contains(&format!("| `{key}` |")),
                            "key `{key}` has no row"
                        );
                    }
                }
                if let Some(c) = map.get("const") {
                    assert!(chapter.contains(&c.to_string()), "value {c} is not listed");
                }
                stack.extend(map.values());
            }
            serde_json::Value::Array(list) => stack.extend(list),
            _ => {}
        }
    }
    assert!(keys > 60, "walked only {keys} keys");
}
