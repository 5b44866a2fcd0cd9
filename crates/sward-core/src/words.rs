//! Plain words for a person who mistyped: what the TOML reader says about a scene file or a
//! `--set` value, put as a person would ("a whole number", "true or false", not `u32` and
//! `a boolean`), and the nearest valid name for a mistyped key, value or scene name.

/// Letters to insert, delete or change to turn `a` into `b`.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1).min(row[j] + 1).min(diagonal + usize::from(ca != cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

/// The candidate nearest to `word`, where it is near enough to be what was meant (a third of
/// its letters wrong at most, two for short words).
pub fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .into_iter()
        .map(|c| (edit_distance(c, word), c))
        .filter(|(d, c)| *d <= (c.len().max(word.len()) / 3).max(2))
        .min()
        .map(|(_, c)| c)
}

/// What the TOML reader said (`message`), in plain words: a type mismatch names what is
/// expected as a person would; an unknown field or variant keeps the list of valid ones and
/// adds the nearest. Anything else is left as it is.
pub fn plain(message: &str) -> String {
    if let Some(rest) = message.strip_prefix("invalid type: ") {
        if let Some((found, expected)) = rest.split_once(", expected ") {
            return format!("expected {}, found {}", expected_words(expected), found_words(found));
        }
    }
    if let Some(rest) = message.strip_prefix("invalid value: ") {
        if let Some((found, expected)) = rest.split_once(", expected ") {
            return format!("expected {}, found {}", expected_words(expected), found_words(found));
        }
    }
    for what in ["unknown field `", "unknown variant `"] {
        if let Some(hint) = message.strip_prefix(what).and_then(nearest_listed) {
            return format!("{message}; did you mean `{hint}`?");
        }
    }
    message.to_string()
}

/// The valid name nearest to the one refused, from "`word`, expected one of `a`, `b`, `c`"
/// (or "expected `a` or `b`", as serde lists two).
fn nearest_listed(rest: &str) -> Option<String> {
    let (word, listed) = rest.split_once("`, expected ")?;
    let listed = listed.trim_start_matches("one of ").replace(" or ", ", ");
    let listed: Vec<&str> = listed.split(", ").map(|c| c.trim_matches('`')).collect();
    nearest(word, listed).map(str::to_string)
}

/// Serde's name of an expected type, in plain words.
fn expected_words(expected: &str) -> String {
    let expected = expected.trim();
    let words = match expected {
        "u8" | "u16" | "u32" | "u64" | "usize" => "a whole number from 0 up",
        "i8" | "i16" | "i32" | "i64" | "isize" => "a whole number",
        "f32" | "f64" => "a number",
        "a boolean" => "true or false",
        "a string" | "a borrowed string" => "a word in quotes",
        "a sequence" => "a list in brackets, like [0.5, 1.0]",
        "a map" => "a table",
        _ if expected.starts_with("an array of length ") => {
            return format!(
                "a list of {} numbers in brackets",
                &expected["an array of length ".len()..]
            )
        }
        _ if expected.starts_with("struct ") => "a table",
        _ if expected.starts_with("a tuple of size ") => {
            return format!("a list of {} values in brackets", &expected["a tuple of size ".len()..]);
        }
        _ => return expected.to_string(),
    };
    words.to_string()
}

/// Serde's description of a value found, in plain words.
fn found_words(found: &str) -> String {
    let found = found.trim();
    let quoted = |prefix: &str| found.strip_prefix(prefix).map(|v| v.trim_matches('`').to_string());
    if let Some(word) = found.strip_prefix("string ") {
        return format!("the word {word}");
    }
    if let Some(n) = quoted("integer ") {
        return format!("the whole number {n}");
    }
    if let Some(n) = quoted("floating point ") {
        return format!("the number {n}");
    }
    if let Some(b) = quoted("boolean ") {
        return b;
    }
    match found {
        "sequence" => "a list".into(),
        "map" => "a table".into(),
        other => other.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_mismatches_are_said_in_plain_words() {
        assert_eq!(
            plain("invalid type: string \"lots\", expected u32"),
            "expected a whole number from 0 up, found the word \"lots\""
        );
        assert_eq!(
            plain("invalid type: floating point `0.5`, expected a boolean"),
            "expected true or false, found the number 0.5"
        );
        assert_eq!(
            plain("invalid type: string \"tall\", expected a sequence"),
            "expected a list in brackets, like [0.5, 1.0], found the word \"tall\""
        );
        assert_eq!(
            plain("invalid value: integer `-5`, expected u32"),
            "expected a whole number from 0 up, found the whole number -5"
        );
        assert_eq!(plain("something else"), "something else");
    }

    #[test]
    fn a_mistyped_name_gets_the_nearest_listed_one() {
        let said = plain("unknown variant `instanc`, expected one of `bezier`, `instanced`, `both`");
        assert!(said.ends_with("; did you mean `instanced`?"), "{said}");
        let said = plain("unknown field `densty`, expected one of `bend`, `density`, `radius`");
        assert!(said.ends_with("did you mean `density`?"), "{said}");
        let said = plain("unknown variant `bouldr`, expected `boulder` or `mesh`");
        assert!(said.ends_with("; did you mean `boulder`?"), "{said}");
        // Nothing near: the list alone.
        let far = "unknown variant `zzzzzz`, expected one of `bezier`, `both`";
        assert_eq!(plain(far), far);
        assert_eq!(nearest("prarie", ["meadow", "prairie", "trail"]), Some("prairie"));
        assert_eq!(nearest("xyz", ["meadow", "prairie"]), None);
    }
}
