//! The scene file's reference: every key of every table, with what kind of value it takes,
//! its default, what the scene's checks allow and what it means — made from the parameter
//! types themselves, so it cannot drift from them. The keys and defaults are the default
//! scene's, serialised, with every optional table filled in from an example; what each allows
//! is what the scene's own checks say of it (`Checks::recording`); what each means is the
//! `///` comment over its field, read by the build script. `sward scene` prints it as a
//! commented scene file, and `docs/scene-reference.md` is its Markdown (a test keeps it fresh).

use crate::validate::Checks;
use crate::Scene;

include!(concat!(env!("OUT_DIR"), "/field_docs.rs"));

/// One key of the scene file.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyDoc {
    /// The table it is in (`field`, `paint.stroke`; empty: the file's top level).
    pub table: String,
    /// Whether that table is one of a list (`[[collider]]`).
    pub listed: bool,
    /// The surface or body kind it belongs to (`sphere`), where it depends on the `type`.
    pub kind_of: Option<String>,
    /// The key.
    pub key: String,
    /// What it takes, in plain words ("a number", "one of `waves`, `noise`").
    pub takes: String,
    /// Its default in TOML, where left out it has one; else an example.
    pub value: String,
    /// What the key is when a scene file leaves it out.
    pub left_out: LeftOut,
    /// Whether the default scene writes it (the commented scene sets it, uncommented).
    pub in_default_scene: bool,
    /// What the scene's checks allow of it, where they check it.
    pub allowed: Option<String>,
    /// What it means.
    pub meaning: String,
}

/// What a key is when a scene file leaves it out of its table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LeftOut {
    /// Its default, the key's `value`.
    Default,
    /// Unset: the key is optional, and its `value` is an example.
    Unset,
    /// The table cannot be read without it; its `value` is an example.
    Required,
}

/// The Rust types that hold each table of the scene file (a flattened grid: two).
const TABLES: &[(&str, &[&str])] = &[
    ("", &["Scene"]),
    ("surface", &["Surface"]),
    ("field", &["FieldDesc"]),
    ("camera", &["Camera"]),
    ("camera_path", &["CameraPath"]),
    ("simulation", &["SimParams"]),
    ("simulation.forces", &["Forces"]),
    ("wind", &["Wind"]),
    ("collider", &["Collider"]),
    ("body", &["Body"]),
    ("body.shape", &["BodyShape"]),
    ("cull", &["CullParams"]),
    ("lod", &["LodParams"]),
    ("blades", &["BladeStyle"]),
    ("shading", &["Shading"]),
    ("instanced", &["InstancedParams", "GridParams"]),
    ("billboard", &["BillboardParams", "GridParams"]),
    ("quality", &["Quality"]),
    ("trample", &["TrampleParams"]),
    ("paint", &["PaintParams"]),
    ("paint.noise", &["PaintNoise"]),
    ("paint.tint_noise", &["TintNoise"]),
    ("paint.stroke", &["Stroke"]),
    ("species", &["Species"]),
    ("species.seed_heads", &["SeedHeads"]),
];

/// Every optional table and key filled in, as an example: what the default scene leaves out.
const EXAMPLE: &str = r#"
[camera_path]
points = [[0.0, 2.0, -9.0], [6.0, 2.0, -6.0]]

[[collider]]
center = [0.0, 0.5, 0.0]
radius = 0.5
path = [[0.0, 0.5, 0.0], [4.0, 0.5, 0.0]]
speed = 2.0
cut = true
clear = true

[[body]]
spheres = 8
center = [3.0, 0.6, 3.0]
path = [[3.0, 0.6, 3.0], [3.0, 0.6, 6.0]]
speed = 1.0
roll = true
clear = true
[body.shape]
type = "boulder"
radius = 1.0
seed = 1

[paint]
density = "density.png"
length = "length.png"
color = "color.png"
[paint.noise]
scale = 0.1
cover = 0.8
softness = 0.2
[paint.tint_noise]
scale = 0.05
cover = 0.3
softness = 0.3
color = [1.3, 1.1, 0.6]
[[paint.stroke]]
points = [[0.0, 0.0], [10.0, 0.0]]
radius = 1.0
softness = 0.5
density = 0.0
length = 0.3
color = [0.5, 0.5, 0.5]
species = "meadow"

[[species]]
name = "meadow"
weight = 1.0
weight_map = "meadow.png"
painted_only = true
[species.seed_heads]
share = 0.2
length = 0.15
color = [0.8, 0.7, 0.5]
"#;

/// A scene with every optional table of the file filled in (the reference's example), for
/// tests that change every value of a scene.
pub fn example_scene() -> Scene {
    toml::from_str(EXAMPLE).expect("the reference's example is a scene")
}

/// The other kinds of surface and body, each with its own keys.
const KINDS: &[(&str, &str)] = &[
    ("surface", "[surface]\ntype = \"sphere\"\ncenter = [0.0, -30.0, 0.0]\nradius = 30.0\n"),
    ("surface", "[surface]\ntype = \"terrain\"\nsize = [200.0, 200.0]\nheight = 8.0\nresolution = 256\nseed = 1\n"),
    ("surface", "[surface]\ntype = \"mesh\"\npath = \"bunny.obj\"\nscale = 1.0\n"),
    ("surface", "[surface]\ntype = \"heightmap\"\npath = \"hills.png\"\nsize = [200.0, 200.0]\nheight = 8.0\n"),
    ("body.shape", "[[body]]\nspheres = 8\ncenter = [0.0, 0.0, 0.0]\n[body.shape]\ntype = \"mesh\"\npath = \"rock.obj\"\nscale = 1.0\n"),
];

/// Every key of the scene file, table by table: the default scene's, then the optional ones.
/// `Err` names the keys whose field has no doc comment.
pub fn reference() -> Result<Vec<KeyDoc>, String> {
    let defaults = table_of(&Scene::default());
    let example = example_scene();
    let filled = table_of(&example);
    let mut checks = Checks::recording("reference");
    example.validate_into(&mut checks);
    let mut keys = Vec::new();
    walk(&filled, "", false, &mut |table, listed, key, value| {
        let kind = kind_of_key(&filled, table, key);
        keys.push(key_doc(table, listed, key, value, (&defaults, &filled, &checks), kind));
    });
    for (table, text) in KINDS {
        let scene: Scene = toml::from_str(text).expect("a kind of surface or body");
        let kind_table = table_of(&scene);
        let mut kind_checks = Checks::recording("reference");
        scene.validate_into(&mut kind_checks);
        walk(&kind_table, "", false, &mut |t, listed, key, value| {
            if t == *table && key != "type" {
                let kind = kind_of_key(&kind_table, t, key);
                let sources = (&defaults, &kind_table, &kind_checks);
                keys.push(key_doc(t, listed, key, value, sources, kind));
            }
        });
    }
    // Each kind's keys right after its table's `type`.
    let first_of = |table: &str| keys.iter().position(|k| k.table == table).unwrap_or(usize::MAX);
    let order: Vec<(usize, bool)> = keys.iter().map(|k| (first_of(&k.table), k.kind_of.is_some())).collect();
    let mut ordered: Vec<((usize, bool), KeyDoc)> = order.into_iter().zip(keys).collect();
    ordered.sort_by_key(|(place, _)| *place);
    let keys: Vec<KeyDoc> = ordered.into_iter().map(|(_, k)| k).collect();
    let missing: Vec<String> = keys
        .iter()
        .filter(|k| k.meaning.is_empty())
        .map(|k| dotted(&k.table, &k.key))
        .collect();
    match missing.is_empty() {
        true => Ok(keys),
        false => Err(format!("no documentation for {}", missing.join(", "))),
    }
}

fn table_of(scene: &Scene) -> toml::Table {
    toml::from_str(&scene.to_toml()).expect("a scene serialises to a TOML table")
}

/// The kind (`sphere`) whose key `key` of `table` is: the `type` its table names, for a key
/// beside it.
fn kind_of_key(filled: &toml::Table, table: &str, key: &str) -> Option<String> {
    let kinded = matches!(table, "surface" | "body.shape") && key != "type";
    let kind = value_at(filled, &dotted(table, "type"))?.as_str()?;
    kinded.then(|| kind.to_string())
}

/// Visit every key that holds a value (not a table): its table (list tables by name), whether
/// that is one of a list, the key and the value.
/// A table's own keys come before its inner tables', as a TOML file writes them.
fn walk(table: &toml::Table, at: &str, listed: bool, visit: &mut dyn FnMut(&str, bool, &str, &toml::Value)) {
    fn inner(v: &toml::Value) -> Option<(&toml::Table, bool)> {
        match v {
            toml::Value::Table(t) => Some((t, false)),
            toml::Value::Array(list) => list.first()?.as_table().map(|t| (t, true)),
            _ => None,
        }
    }
    for (key, value) in table.iter().filter(|(_, v)| inner(v).is_none()) {
        visit(at, listed, key, value);
    }
    for (key, value) in table {
        if let Some((t, is_list)) = inner(value) {
            walk(t, &dotted(at, key), is_list, visit);
        }
    }
}

fn dotted(table: &str, key: &str) -> String {
    match table {
        "" => key.to_string(),
        _ => format!("{table}.{key}"),
    }
}

/// One key's documentation: what it takes, its default or example, what the checks allow,
/// and what its field's comment says.
fn key_doc(
    table: &str,
    listed: bool,
    key: &str,
    value: &toml::Value,
    (defaults, filled, checks): (&toml::Table, &toml::Table, &Checks),
    kind_of: Option<String>,
) -> KeyDoc {
    let in_default_scene = value_at(defaults, &dotted(table, key)).cloned();
    let (left_out, default) = match in_default_scene.clone() {
        Some(default) => (LeftOut::Default, Some(default)),
        None => left_out_of(filled, table, key, value),
    };
    KeyDoc {
        table: table.to_string(),
        listed,
        key: key.to_string(),
        takes: takes(filled, table, key, value),
        value: shown(default.as_ref().unwrap_or(value)),
        left_out,
        in_default_scene: in_default_scene.is_some(),
        allowed: checks.allowed(&dotted(table, key)).map(|a| a.into_owned()),
        meaning: meaning(table, key, kind_of.as_deref()),
        kind_of,
    }
}

/// What a key the default scene does not write is when left out of its table (the first of a
/// list), and its default there: the example without it, read and written back. A key not
/// written back is unset (an `Option`) unless the scene read with it empty (`false`, `[]`) is
/// the same: a default serde leaves unwritten.
fn left_out_of(filled: &toml::Table, table: &str, key: &str, example: &toml::Value) -> (LeftOut, Option<toml::Value>) {
    let with = |value: Option<toml::Value>| {
        let mut probe = toml::Value::Table(filled.clone());
        let at = table_in(&mut probe, table)?;
        match value {
            Some(value) => at.insert(key.into(), value),
            None => at.remove(key),
        };
        toml::from_str::<Scene>(&toml::to_string(&probe).ok()?).ok()
    };
    let Some(scene) = with(None) else {
        return (LeftOut::Required, None);
    };
    if let Some(default) = value_at(&table_of(&scene), &dotted(table, key)) {
        return (LeftOut::Default, Some(default.clone()));
    }
    let empty = match example {
        toml::Value::Boolean(_) => Some(toml::Value::Boolean(false)),
        toml::Value::Array(_) => Some(toml::Value::Array(Vec::new())),
        _ => None,
    };
    match empty {
        Some(empty) if with(Some(empty.clone())).as_ref() == Some(&scene) => (LeftOut::Default, Some(empty)),
        _ => (LeftOut::Unset, None),
    }
}

/// The table at a dotted path of `value` (the first of a list of tables).
fn table_in<'a>(value: &'a mut toml::Value, table: &str) -> Option<&'a mut toml::Table> {
    let mut at = value;
    for part in table.split('.').filter(|p| !p.is_empty()) {
        at = at.as_table_mut()?.get_mut(part)?;
        if let toml::Value::Array(list) = at {
            at = list.first_mut()?;
        }
    }
    at.as_table_mut()
}

/// A value as a scene file would write it: numbers as the `f32`s the scene holds (`0.03`, not
/// the `0.029999999329447746` widening them gives).
fn shown(value: &toml::Value) -> String {
    match value {
        toml::Value::Float(f) => format!("{:?}", *f as f32),
        toml::Value::Array(list) => format!("[{}]", list.iter().map(shown).collect::<Vec<_>>().join(", ")),
        other => other.to_string(),
    }
}

/// The value at a dotted key of `table`, through the first element of a list of tables.
fn value_at<'a>(table: &'a toml::Table, key: &str) -> Option<&'a toml::Value> {
    let mut parts = key.split('.');
    let mut value = table.get(parts.next()?)?;
    for part in parts {
        if let toml::Value::Array(list) = value {
            value = list.first()?;
        }
        value = value.as_table()?.get(part)?;
    }
    Some(value)
}

/// What a key takes, in plain words: an enum's values where the scene refuses another word.
fn takes(filled: &toml::Table, table: &str, key: &str, value: &toml::Value) -> String {
    match value {
        toml::Value::Integer(_) => "a whole number".into(),
        toml::Value::Float(_) => "a number".into(),
        toml::Value::Boolean(_) => "true or false".into(),
        toml::Value::String(_) => match variants(filled, table, key) {
            Some(words) => format!("one of {words}"),
            None => "text".into(),
        },
        toml::Value::Array(list) => match list.first() {
            Some(toml::Value::Array(point)) => format!("a list of points of {} numbers", point.len()),
            Some(toml::Value::String(_)) => "a list of words".into(),
            _ => format!("{} numbers", list.len()),
        },
        _ => "a table".into(),
    }
}

/// The words an enum key allows, as the TOML reader lists them when given another.
fn variants(filled: &toml::Table, table: &str, key: &str) -> Option<String> {
    // Put a word no enum has at the key, in the key's table (the first of a list) of a copy.
    let mut probe = toml::Value::Table(filled.clone());
    table_in(&mut probe, table)?.insert(key.into(), toml::Value::String("\u{1}".into()));
    let text = toml::to_string(&probe).ok()?;
    let message = toml::from_str::<Scene>(&text).err()?.message().to_string();
    // "unknown variant `…`, expected one of `a`, `b`, `c`", or "expected `a` or `b`" for two.
    let (_, after) = message.split_once("unknown variant")?;
    let (_, listed) = after.split_once(", expected ")?;
    let listed = listed.trim().trim_start_matches("one of ");
    Some(listed.replace(" or ", ", "))
}

/// What the field behind `table.key` means, from its doc comment; a kind's key (`kind`: the
/// `type`, `heightmap`) from the field of that kind's enum variant. An empty key: what the kind
/// itself is.
fn meaning(table: &str, key: &str, kind: Option<&str>) -> String {
    if key == "type" && matches!(table, "surface" | "body.shape") {
        return "What kind it is; the keys beside it depend on it.".into();
    }
    // `heightmap` names the variant `Heightmap`, `snake_case` names `SnakeCase`.
    let of_kind = |variant: &str| match kind {
        Some(kind) => variant.eq_ignore_ascii_case(&kind.replace('_', "")),
        None => variant.is_empty(),
    };
    let owners = TABLES.iter().find(|(t, _)| *t == table).map_or(&[][..], |(_, o)| *o);
    owners
        .iter()
        .find_map(|owner| {
            FIELD_DOCS
                .iter()
                .find(|(o, variant, k, _)| o == owner && of_kind(variant) && *k == key)
                .map(|(_, _, _, doc)| doc.to_string())
        })
        .unwrap_or_default()
}

/// The reference as a scene file: the default scene, every key over a comment saying what it
/// means and takes; the optional tables and keys after, commented out, with example values.
/// Read back, it is the default scene.
pub fn commented_scene(keys: &[KeyDoc]) -> String {
    let mut out = String::from(
        "# A sward scene file with every key: what each means and takes, and its default.\n\
         # Keys left out keep their defaults. Commented-out keys and tables are optional; their\n\
         # values are examples. Made by `sward scene`; also docs/scene-reference.md.\n",
    );
    let mut last = None;
    for k in keys {
        let header = (k.table.clone(), k.listed, k.kind_of.clone());
        let live = k.in_default_scene && !k.listed && k.kind_of.is_none();
        let hash = if live { "" } else { "# " };
        if last.as_ref() != Some(&header) {
            out.push('\n');
            if let Some(kind) = &k.kind_of {
                out.push_str(&format!(
                    "# With type = \"{kind}\": {}\n",
                    meaning(&k.table, "", Some(kind))
                ));
            } else if !k.table.is_empty() {
                let brackets = if k.listed { ("[[", "]]") } else { ("[", "]") };
                out.push_str(&format!("{hash}{}{}{}\n", brackets.0, k.table, brackets.1));
            }
            last = Some(header);
        }
        out.push_str(&format!("# {}\n", k.meaning));
        let allowed = k.allowed.as_ref().map_or(String::new(), |a| format!("; allowed: {a}"));
        let left_out = match (k.left_out, live) {
            (_, true) => String::new(),
            (LeftOut::Default, false) => format!("; left out, it is {}", k.value),
            (LeftOut::Unset, false) => "; optional".into(),
            (LeftOut::Required, false) => "; required".into(),
        };
        out.push_str(&format!("# Takes {}{allowed}{left_out}.\n", k.takes));
        out.push_str(&format!("{hash}{} = {}\n", k.key, k.value));
    }
    out
}

/// The reference as Markdown: a table of keys per table of the scene file.
pub fn markdown(keys: &[KeyDoc]) -> String {
    let mut out = String::from(
        "# Scene file reference\n\n\
         Every key of a sward scene file: what it takes, its default (else whether it is\n\
         required or unset when left out, with an example), what is allowed and what it means.\n\
         A table of a list (`[[collider]]`) has the defaults of each of its entries. Made from\n\
         the parameter types by `sward scene --markdown`; a test fails when this page is stale or\n\
         a key has no meaning. `sward scene` prints the same as a commented scene file.\n",
    );
    let mut last = None;
    for k in keys {
        let header = (k.table.clone(), k.listed, k.kind_of.clone());
        if last.as_ref() != Some(&header) {
            let name = match (&k.table[..], k.listed) {
                ("", _) => "The top level".to_string(),
                (t, true) => format!("`[[{t}]]` (any number)"),
                (t, false) => format!("`[{t}]`"),
            };
            let kind = k
                .kind_of
                .as_ref()
                .map_or(String::new(), |k| format!(", `type = \"{k}\"`"));
            out.push_str(&format!("\n## {name}{kind}\n\n"));
            if let Some(kind) = &k.kind_of {
                out.push_str(&format!("{}\n\n", meaning(&k.table, "", Some(kind))));
            }
            out.push_str("| key | takes | default | allowed | meaning |\n|---|---|---|---|---|\n");
            last = Some(header);
        }
        let value = match k.left_out {
            LeftOut::Default => format!("`{}`", k.value),
            LeftOut::Unset => format!("unset (e.g. `{}`)", k.value),
            LeftOut::Required => format!("required (e.g. `{}`)", k.value),
        };
        let cell = |s: &str| s.replace('|', "\\|");
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} |\n",
            k.key,
            cell(&k.takes),
            cell(&value),
            cell(k.allowed.as_deref().unwrap_or("")),
            cell(&k.meaning)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_has_a_meaning_and_the_page_is_fresh() {
        let keys = reference().unwrap_or_else(|missing| panic!("{missing}"));
        assert!(keys.len() > 150, "{} keys", keys.len());
        let blades = keys.iter().find(|k| k.table == "field" && k.key == "blades").unwrap();
        assert_eq!(blades.value, "8192");
        assert!(blades.allowed.as_deref().unwrap().contains("67108864"));
        let wind = keys.iter().find(|k| k.table == "wind" && k.key == "type").unwrap();
        assert!(wind.takes.contains("`whirl`"), "{}", wind.takes);
        let body = keys
            .iter()
            .find(|k| k.table == "body.shape" && k.key == "type")
            .unwrap();
        assert_eq!(body.takes, "one of `boulder`, `mesh`");
        let key = |table: &str, key: &str, kind: Option<&str>| {
            keys.iter()
                .find(|k| k.table == table && k.key == key && k.kind_of.as_deref() == kind)
                .unwrap_or_else(|| panic!("no key {table}.{key} of kind {kind:?}"))
        };
        // A list table's keys: required, defaulted in each entry, or unset.
        assert_eq!(key("collider", "radius", None).left_out, LeftOut::Required);
        let cut = key("collider", "cut", None);
        assert_eq!((cut.left_out, cut.value.as_str()), (LeftOut::Default, "false"));
        assert_eq!(key("paint", "density", None).left_out, LeftOut::Unset);
        // Defaults serde leaves unwritten are defaults all the same; an unset Option is not.
        let clear = key("collider", "clear", None);
        assert_eq!((clear.left_out, clear.value.as_str()), (LeftOut::Default, "false"));
        let path = key("body", "path", None);
        assert_eq!((path.left_out, path.value.as_str()), (LeftOut::Default, "[]"));
        assert_eq!(key("paint.stroke", "color", None).left_out, LeftOut::Unset);
        // A kind's keys mean what its own variant's fields say.
        let heightmap = key("surface", "path", Some("heightmap"));
        assert_eq!(heightmap.meaning, "The grey PNG.");
        assert_eq!(key("surface", "path", Some("mesh")).meaning, "The mesh file.");
        assert!(key("surface", "resolution", Some("terrain")).allowed.is_some());
        let page = include_str!("../../../docs/scene-reference.md");
        assert!(
            page == markdown(&keys),
            "docs/scene-reference.md is stale: make it again with `sward scene --markdown > docs/scene-reference.md`"
        );
    }

    #[test]
    fn the_commented_scene_reads_back_as_the_default_scene() {
        let keys = reference().unwrap();
        let text = commented_scene(&keys);
        let scene = Scene::from_toml(&text, "sward scene").unwrap();
        assert_eq!(scene, Scene::default());
        assert!(text.contains("# [[collider]]"), "the optional tables are shown");
    }
}
