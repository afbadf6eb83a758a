//! The scene file reference chapter (`docs/manual/src/reference/scene-reference.md`),
//! written from the JSON Schema of scene files (`tumble::scene::json_schema()`,
//! shipped as `docs/scene.schema.json`), so that every key, type, default and
//! description in the manual is the one the loader uses.
//!
//! One section per schema object: the top level, then the definitions in the
//! order a reader meets them, then any definition not in that list
//! (alphabetically), so that a new type shows up without touching this file.

use serde_json::{Map, Value};

/// Definitions in reading order; others follow alphabetically.
const ORDER: &[&str] = &[
    "WorldSettings",
    "Integrator",
    "SolverKind",
    "MaterialDesc",
    "BodySpec",
    "KindSpec",
    "InertiaSpec",
    "RotationSpec",
    "GridSpec",
    "RobotSpec",
    "ShapeSpec",
    "PoseSpec",
    "MeshSource",
    "BoxMesh",
    "SphereMesh",
    "IcosphereMesh",
    "CylinderMesh",
    "CapsuleMesh",
    "ConeMesh",
    "TorusMesh",
];

/// Where each definition is used, for the reader (shown under its heading).
fn used_as(def: &str) -> &'static str {
    match def {
        "WorldSettings" => "the `[settings]` table",
        "Integrator" => "`settings.integrator`",
        "SolverKind" => "`settings.solver`",
        "MaterialDesc" => "each entry of `[materials]`: `[materials.NAME]`",
        "BodySpec" => "each `[[bodies]]` entry",
        "KindSpec" => "a body's `kind`",
        "InertiaSpec" => "a body's `inertia`",
        "RotationSpec" => "each factor of a `rotation` list",
        "GridSpec" => "a body's `grid`",
        "RobotSpec" => "each `[[robots]]` entry",
        "ShapeSpec" => "each entry of `[shapes]` (`[shapes.NAME]`) and of a body's `shapes` list",
        "PoseSpec" => "a shape's `local_pose`",
        "MeshSource" => "the `mesh` of a `mesh` or `convex_hull` shape: exactly one key",
        "BoxMesh" => "`mesh.box`",
        "SphereMesh" => "`mesh.sphere`",
        "IcosphereMesh" => "`mesh.icosphere`",
        "CylinderMesh" => "`mesh.cylinder`",
        "CapsuleMesh" => "`mesh.capsule`",
        "ConeMesh" => "`mesh.cone`",
        "TorusMesh" => "`mesh.torus`",
        _ => "",
    }
}

/// An error in the schema's shape (not a scene error): what was expected where.
#[derive(Debug)]
pub struct SchemaShapeError(pub String);

impl std::fmt::Display for SchemaShapeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "unexpected scene schema: {}", self.0)
    }
}

impl std::error::Error for SchemaShapeError {}

fn bad(what: impl Into<String>) -> SchemaShapeError {
    SchemaShapeError(what.into())
}

/// One line of table text: newlines joined, pipes escaped.
fn cell(text: &str) -> String {
    text.split('\n')
        .map(str::trim)
        .collect::<Vec<_>>()
        .join(" ")
        .replace('|', "\\|")
}

fn anchor(def: &str) -> String {
    def.to_ascii_lowercase()
}

fn ref_name(v: &Value) -> Option<&str> {
    v.get("$ref")?.as_str()?.strip_prefix("#/$defs/")
}

/// The non-null member of a `type` list or an `anyOf` with null.
fn strip_null(v: &Value) -> &Value {
    if let Some(any) = v.get("anyOf").and_then(Value::as_array) {
        let rest: Vec<&Value> = any
            .iter()
            .filter(|x| x.get("type") != Some(&Value::from("null")))
            .collect();
        if rest.len() == 1 {
            return rest[0];
        }
    }
    v
}

fn type_name(v: &Value) -> String {
    let v = strip_null(v);
    if let Some(name) = ref_name(v) {
        return format!("[{name}](#{})", anchor(name));
    }
    if let Some(c) = v.get("const") {
        return format!("`{c}`");
    }
    let ty = match v.get("type") {
        Some(Value::String(s)) => s.as_str(),
        Some(Value::Array(list)) => list
            .iter()
            .filter_map(Value::as_str)
            .find(|s| *s != "null")
            .unwrap_or("null"),
        _ => "any",
    };
    match ty {
        "array" => {
            let items = v.get("items").map(type_name).unwrap_or_else(|| "any".into());
            match (v.get("minItems"), v.get("maxItems")) {
                (Some(a), Some(b)) if a == b => format!("[{items}; {a}]"),
                _ => format!("array of {items}"),
            }
        }
        "object" => match v.get("additionalProperties") {
            Some(extra) if extra.is_object() => format!("table of {}", type_name(extra)),
            _ => "table".into(),
        },
        "integer" => match (v.get("minimum"), v.get("maximum")) {
            (Some(lo), Some(hi)) => format!("integer {lo}..={hi}"),
            (Some(lo), None) => format!("integer >= {lo}"),
            _ => "integer".into(),
        },
        other => other.into(),
    }
}

fn default_text(v: &Value, required: bool) -> String {
    if required {
        return "required".into();
    }
    match v.get("default") {
        None | Some(Value::Null) => String::new(),
        Some(d) if d.as_object().is_some_and(|o| o.is_empty()) => "none".into(),
        Some(d) if d.is_object() => match ref_name(strip_null(v)) {
            Some(name) => format!("as in [{name}](#{})", anchor(name)),
            None => format!("`{d}`"),
        },
        Some(d) => format!("`{d}`"),
    }
}

fn properties_table(out: &mut String, obj: &Value, skip: &[&str]) -> Result<(), SchemaShapeError> {
    let props = obj
        .get("properties")
        .and_then(Value::as_object)
        .ok_or_else(|| bad("an object without properties"))?;
    let required: Vec<&str> = obj
        .get("required")
        .and_then(Value::as_array)
        .map(|r| r.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    out.push_str("| key | type | default | meaning |\n| --- | --- | --- | --- |\n");
    for (key, p) in props {
        if skip.contains(&key.as_str()) {
            continue;
        }
        let description = p.get("description").and_then(Value::as_str).unwrap_or("");
        out.push_str(&format!(
            "| `{key}` | {} | {} | {} |\n",
            type_name(p),
            default_text(p, required.contains(&key.as_str())),
            cell(description)
        ));
    }
    out.push('\n');
    Ok(())
}

fn variants(out: &mut String, alternatives: &[Value], def: &str) -> Result<(), SchemaShapeError> {
    let all_consts = alternatives.iter().all(|a| a.get("const").is_some());
    if all_consts {
        out.push_str("| value | meaning |\n| --- | --- |\n");
        for a in alternatives {
            let description = a.get("description").and_then(Value::as_str).unwrap_or("");
            out.push_str(&format!("| `{}` | {} |\n", a["const"], cell(description)));
        }
        out.push('\n');
        return Ok(());
    }
    // Tagged objects (shapes): one subsection per `type`.
    for a in alternatives {
        let tag = a
            .pointer("/properties/type/const")
            .and_then(Value::as_str)
            .ok_or_else(|| bad(format!("{def}: an alternative without a `type` constant")))?;
        out.push_str(&format!("### `type = \"{tag}\"`\n\n"));
        if let Some(d) = a.get("description").and_then(Value::as_str) {
            out.push_str(&format!("{}\n\n", cell(d)));
        }
        properties_table(out, a, &["type"])?;
    }
    Ok(())
}

fn section(out: &mut String, name: &str, def: &Value) -> Result<(), SchemaShapeError> {
    out.push_str(&format!("## {name}\n\n"));
    let used = used_as(name);
    if !used.is_empty() {
        out.push_str(&format!("Used as {used}.\n\n"));
    }
    if let Some(d) = def.get("description").and_then(Value::as_str) {
        out.push_str(&format!("{}\n\n", cell(d)));
    }
    if let Some(alts) = def.get("oneOf").and_then(Value::as_array) {
        variants(out, alts, name)
    } else if let Some(forms) = def.get("anyOf").and_then(Value::as_array) {
        // Untagged: one value written in one of several forms.
        out.push_str("| form | meaning |\n| --- | --- |\n");
        for f in forms {
            let description = f.get("description").and_then(Value::as_str).unwrap_or("");
            out.push_str(&format!("| {} | {} |\n", type_name(f), cell(description)));
        }
        out.push('\n');
        Ok(())
    } else if def.get("properties").is_some() {
        properties_table(out, def, &[])
    } else {
        Err(bad(format!("{name}: neither properties nor oneOf")))
    }
}

/// The chapter's Markdown for the scene schema `schema_json`.
pub fn generate(schema_json: &str) -> Result<String, SchemaShapeError> {
    let schema: Value = serde_json::from_str(schema_json).map_err(|e| bad(e.to_string()))?;
    let empty = Map::new();
    let defs = schema.get("$defs").and_then(Value::as_object).unwrap_or(&empty);
    let mut out = String::from(
        "<!-- Generated from docs/scene.schema.json by crates/tumble-manual (src/scene_reference.rs).\n     \
         Do not edit: run `TUMBLE_UPDATE_MANUAL=1 cargo test -p tumble-manual --test scene_reference`. -->\n\
         # Scene file reference\n\n\
         Every key of a scene file (TOML or JSON, same keys), with its type, default and meaning, generated\n\
         from the JSON Schema `docs/scene.schema.json`, which is itself generated from the Rust types the\n\
         loader reads; the test suite checks that this page, the schema and the loader agree. Units are SI\n\
         (m, kg, s), angles in `rotation` are degrees, quaternions are `[x, y, z, w]`, z is up. Unknown keys\n\
         are errors. How to use them: [Scene files](../scene-files.md).\n\n\
         ## Top level\n\n",
    );
    properties_table(&mut out, &schema, &[])?;
    let mut names: Vec<&str> = ORDER.iter().copied().filter(|n| defs.contains_key(*n)).collect();
    let mut rest: Vec<&str> = defs
        .keys()
        .map(String::as_str)
        .filter(|n| !ORDER.contains(n))
        .collect();
    rest.sort_unstable();
    names.extend(rest);
    for name in names {
        section(&mut out, name, &defs[name])?;
    }
    while out.ends_with("\n\n") {
        out.pop();
    }
    Ok(out)
}
