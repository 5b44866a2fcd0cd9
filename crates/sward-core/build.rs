//! Reads what each scene parameter means from where it is written, the `///` comment over its
//! field in `src/*.rs`, into a table the scene file's reference is made from
//! (`src/reference.rs`): `(type, key, meaning)`, the key as the scene file spells it (a
//! `#[serde(rename = "…")]` followed), and for an enum each variant's own fields under the
//! enum's name (`Surface` holds every surface's keys).

use std::fmt::Write as _;
use std::path::Path;

fn main() {
    let mut table = String::from("pub(crate) static FIELD_DOCS: &[(&str, &str, &str)] = &[\n");
    let mut files: Vec<_> = std::fs::read_dir("src")
        .expect("the crate's src directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    files.sort();
    for path in &files {
        println!("cargo:rerun-if-changed={}", path.display());
        let text = std::fs::read_to_string(path).expect("a source file");
        for (owner, key, meaning) in documented_fields(&text) {
            writeln!(table, "    ({owner:?}, {key:?}, {meaning:?}),").unwrap();
        }
    }
    table.push_str("];\n");
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("field_docs.rs");
    std::fs::write(out, table).expect("writing the field docs");
}

/// Every field of every struct and enum variant in `text` with its doc comment: (type, key,
/// meaning).
fn documented_fields(text: &str) -> Vec<(String, String, String)> {
    let mut found = Vec::new();
    // The type being read and the brace depth its body opened at.
    let mut owner: Option<(String, usize)> = None;
    let mut depth = 0usize;
    let mut doc: Vec<String> = Vec::new();
    let mut rename: Option<String> = None;
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("").trim();
        let trimmed = line.trim();
        if let Some(d) = trimmed.strip_prefix("///") {
            doc.push(d.trim().to_string());
            continue;
        }
        if trimmed.starts_with("#[") {
            rename = rename.or_else(|| serde_rename(trimmed));
            continue;
        }
        if let Some(name) = type_start(code) {
            owner = Some((name, depth + 1));
        } else if let Some((name, at)) = &owner {
            let in_body = depth == *at || depth == at + 1;
            if let (true, Some(field)) = (in_body, field_name(code)) {
                let key = rename.clone().unwrap_or(field);
                found.push((name.clone(), key, doc.join(" ")));
            }
        }
        depth += code.matches('{').count();
        depth = depth.saturating_sub(code.matches('}').count());
        if owner.as_ref().is_some_and(|(_, at)| depth < *at) {
            owner = None;
        }
        doc.clear();
        rename = None;
    }
    found
}

/// `pub struct Name {` or `pub enum Name {` (or without `pub`): the type's name.
fn type_start(code: &str) -> Option<String> {
    let rest = code.strip_prefix("pub ").unwrap_or(code);
    let rest = rest.strip_prefix("struct ").or_else(|| rest.strip_prefix("enum "))?;
    let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
    (!name.is_empty() && rest.trim_end().ends_with('{')).then_some(name)
}

/// `pub name: Type,` or `name: Type,` (a variant's field): the field's name.
fn field_name(code: &str) -> Option<String> {
    let rest = code.strip_prefix("pub ").unwrap_or(code);
    let (name, ty) = rest.split_once(':')?;
    let plain = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    (plain && !ty.starts_with(':') && code.ends_with(',')).then(|| name.to_string())
}

/// The name a `#[serde(rename = "…")]` attribute gives a field.
fn serde_rename(attribute: &str) -> Option<String> {
    let at = attribute.find("rename = \"")? + "rename = \"".len();
    let name = &attribute[at..];
    Some(name[..name.find('"')?].to_string())
}
