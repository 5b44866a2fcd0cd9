//! Reads what each scene parameter means from where it is written, the `///` comment over its
//! field in `src/*.rs`, into a table the scene file's reference is made from
//! (`src/reference.rs`): `(type, variant, key, meaning)`, the key as the scene file spells it
//! (a `#[serde(rename = "…")]` followed); an enum's variants' fields under the enum's name and
//! the variant's (`Surface`, `Heightmap`, `path`), and each variant's own comment with an empty
//! key.

// It runs where the crate is built, never in a game: it reads the sources.
#![allow(clippy::disallowed_methods)]

use std::fmt::Write as _;
use std::path::Path;

fn main() {
    let mut table = String::from("pub(crate) static FIELD_DOCS: &[(&str, &str, &str, &str)] = &[\n");
    let mut files: Vec<_> = std::fs::read_dir("src")
        .expect("the crate's src directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "rs"))
        .collect();
    files.sort();
    for path in &files {
        println!("cargo:rerun-if-changed={}", path.display());
        let text = std::fs::read_to_string(path).expect("a source file");
        for Documented {
            owner,
            variant,
            key,
            meaning,
        } in documented_fields(&text)
        {
            writeln!(table, "    ({owner:?}, {variant:?}, {key:?}, {meaning:?}),").unwrap();
        }
    }
    table.push_str("];\n");
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("field_docs.rs");
    std::fs::write(out, table).expect("writing the field docs");
}

/// A field (or, with an empty key, an enum variant) and its doc comment.
struct Documented {
    owner: String,
    /// The enum variant the field is in; empty for a struct's field.
    variant: String,
    key: String,
    meaning: String,
}

/// Every field of every struct and enum variant in `text` with its doc comment, and every
/// enum variant's own comment.
fn documented_fields(text: &str) -> Vec<Documented> {
    let mut found = Vec::new();
    // The type being read and the brace depth its body opened at.
    let mut owner: Option<(String, usize)> = None;
    // The enum variant being read (a line `Name {` or `Name,` in an enum's body).
    let mut variant = String::new();
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
            variant.clear();
        } else if let Some((name, at)) = &owner {
            if depth == *at {
                variant = variant_name(code).unwrap_or_default();
                if !variant.is_empty() {
                    let (owner, variant, meaning) = (name.clone(), variant.clone(), doc.join(" "));
                    found.push(Documented {
                        owner,
                        variant,
                        key: String::new(),
                        meaning,
                    });
                }
            }
            let in_body = depth == *at || depth == at + 1;
            if let (true, Some(field)) = (in_body, field_name(code)) {
                let key = rename.clone().unwrap_or(field);
                let variant = if depth == *at { String::new() } else { variant.clone() };
                found.push(Documented {
                    owner: name.clone(),
                    variant,
                    key,
                    meaning: doc.join(" "),
                });
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

/// `Name {` or `Name,` (an enum's variant): its name.
fn variant_name(code: &str) -> Option<String> {
    let name: String = code.chars().take_while(|c| c.is_alphanumeric()).collect();
    let rest = code[name.len()..].trim();
    let variant = name.starts_with(|c: char| c.is_ascii_uppercase()) && matches!(rest, "{" | "," | "");
    variant.then_some(name)
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
