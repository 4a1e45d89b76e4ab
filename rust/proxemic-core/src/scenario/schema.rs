//! The scenario reference: a JSON Schema of the file format emitted from the raw types
//! ([`super::raw`], `schemars`), and what a field accepts, in words, for error messages.

use serde_json::{Value, json};

use super::load::APPENDABLE;
use super::raw::RawScenario;

/// The JSON Schema (draft 2020-12) of a scenario file: every table and field with its type,
/// default and description, unknown fields refused. `extends` and `append` (read before the
/// tables, see [`super::Scenario::from_file`]) are in it too, so an editor completes them.
pub fn json_schema() -> Value {
    let mut schema = schemars::schema_for!(RawScenario).to_value();
    if let Some(props) = schema.get_mut("properties").and_then(Value::as_object_mut) {
        props.insert(
            "extends".into(),
            json!({
                "type": "string",
                "description": "A base scenario file (a path relative to this one) whose tables this file \
                    starts from: its [scene] keys override the base's one by one, every other table or \
                    array replaces the base's whole, except the arrays listed in `append`."
            }),
        );
        props.insert(
            "append".into(),
            json!({
                "type": "array",
                "items": { "enum": APPENDABLE },
                "description": "Arrays of tables whose entries follow the base's instead of replacing them."
            }),
        );
    }
    schema
}

fn collect_names(v: &Value, out: &mut Vec<String>) {
    if let Some(values) = v.get("enum").and_then(Value::as_array) {
        out.extend(values.iter().filter_map(Value::as_str).map(str::to_string));
    }
    if let Some(c) = v.get("const").and_then(Value::as_str) {
        out.push(c.to_string());
    }
    for key in ["oneOf", "anyOf"] {
        for sub in v.get(key).and_then(Value::as_array).into_iter().flatten() {
            collect_names(sub, out);
        }
    }
    if let Some(props) = v.get("properties").and_then(Value::as_object) {
        // A tagged variant: the tag's const.
        for tag in props.values() {
            if tag.get("const").is_some() {
                collect_names(tag, out);
            }
        }
    }
}

/// What the file accepts at a dotted field path (`object[0].interaction`), in words, from the
/// schema: the names of an enum, the shapes of a tagged table, or the fields of a table. `None`
/// when the path is not in the schema.
pub(super) fn describe_field(path: &str) -> Option<String> {
    let schema = json_schema();
    let mut node = resolve(&schema, &schema);
    for part in path.split('.') {
        let (name, indexed) = match part.find('[') {
            Some(i) => (&part[..i], true),
            None => (part, false),
        };
        node = resolve(&schema, node.get("properties")?.get(name)?);
        if indexed {
            node = resolve(&schema, node.get("items")?);
        }
    }
    describe(&schema, node)
}

fn resolve<'a>(root: &'a Value, v: &'a Value) -> &'a Value {
    let def = v.get("$ref").and_then(Value::as_str).and_then(|r| r.strip_prefix("#/$defs/"));
    if let Some(def) = def.and_then(|name| root.get("$defs").and_then(|d| d.get(name))) {
        return resolve(root, def);
    }
    if let Some(alts) = v.get("anyOf").and_then(Value::as_array) {
        let some: Vec<&Value> = alts.iter().filter(|a| a.get("type") != Some(&json!("null"))).collect();
        if let [one] = some.as_slice() {
            return resolve(root, one);
        }
    }
    v
}

fn quoted(names: &[String]) -> String {
    names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
}

fn describe(root: &Value, v: &Value) -> Option<String> {
    let mut names = Vec::new();
    collect_names(v, &mut names);
    if let Some(variants) = v.get("oneOf").and_then(Value::as_array) {
        let tagged: Vec<String> = variants
            .iter()
            .filter_map(|var| {
                let props = var.get("properties")?.as_object()?;
                let (tag, value) = props.iter().find(|(_, p)| p.get("const").is_some())?;
                let fields: Vec<String> = props.keys().filter(|k| *k != tag).cloned().collect();
                Some(format!("{tag} = {:?} with {}", value.get("const")?.as_str()?, quoted(&fields)))
            })
            .collect();
        if tagged.len() == variants.len() && !tagged.is_empty() {
            return Some(format!("a table, one of: {}", tagged.join("; ")));
        }
    }
    if !names.is_empty() {
        return Some(format!("one of {}", quoted(&names)));
    }
    if let Some(props) = v.get("properties").and_then(Value::as_object) {
        let fields: Vec<String> = props.keys().cloned().collect();
        return Some(format!("a table with the fields {}", quoted(&fields)));
    }
    let _ = root;
    None
}
