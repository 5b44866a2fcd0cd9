//! The pages (README.md and docs/) hold to the program. `scripts/pictures.sh` makes every
//! picture they show, each picture's caption names the command that made it, word for word, and
//! every command they write uses only flags and scene keys sward has.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A picture as `scripts/pictures.sh --list` gives it.
struct Picture {
    /// `lavapipe` or `gpu`.
    made_on: String,
    /// Run one after another from the repository root; the last writes `docs/NAME.png`.
    commands: Vec<String>,
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every picture the script makes, by name (`docs/NAME.png`).
fn listed() -> BTreeMap<String, Picture> {
    let output = Command::new("bash")
        .arg("scripts/pictures.sh")
        .arg("--list")
        .current_dir(root())
        .output()
        .expect("bash runs scripts/pictures.sh");
    assert!(
        output.status.success(),
        "scripts/pictures.sh --list failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let mut pictures = BTreeMap::<String, Picture>::new();
    for line in String::from_utf8(output.stdout).unwrap().lines() {
        let fields: Vec<&str> = line.splitn(3, '\t').collect();
        let [name, made_on, command] = fields[..] else {
            panic!("not NAME<tab>WHERE<tab>COMMAND: {line:?}");
        };
        let picture = pictures.entry(name.to_string()).or_insert_with(|| Picture {
            made_on: made_on.to_string(),
            commands: Vec::new(),
        });
        picture.commands.push(command.to_string());
    }
    pictures
}

/// The page of earlier measurements: its commands are written as they were run at their
/// commit, so they are not held to today's flags (its links are).
const HISTORY: &str = "benchmarks-history.md";

/// README.md, BENCHMARKS.md and every page in docs/, with their paths.
fn pages() -> Vec<(String, String)> {
    let mut paths = vec![root().join("README.md"), root().join("BENCHMARKS.md")];
    for entry in std::fs::read_dir(root().join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            paths.push(path);
        }
    }
    paths
        .into_iter()
        .map(|path| {
            let text = std::fs::read_to_string(&path).unwrap();
            (path.file_name().unwrap().to_string_lossy().into_owned(), text)
        })
        .collect()
}

/// The page's paragraphs, each on one line with its whitespace collapsed.
fn paragraphs(text: &str) -> Vec<String> {
    text.split("\n\n")
        .map(|p| p.split_whitespace().collect::<Vec<_>>().join(" "))
        .filter(|p| !p.is_empty())
        .collect()
}

/// The names (`NAME` of `NAME.png`) of the pictures a paragraph links to or shows.
fn linked_pictures(paragraph: &str) -> Vec<String> {
    link_targets(paragraph)
        .iter()
        .filter_map(|target| target.strip_suffix(".png"))
        .map(|path| path.rsplit('/').next().unwrap().to_string())
        .collect()
}

/// Every picture's captions: each paragraph that shows or links to it, with the paragraph after
/// it (a picture's caption is the italic paragraph below the picture). The history's plots are
/// the bench's own output, kept in docs/bench/ with the runs they came from.
fn captions() -> BTreeMap<String, Vec<String>> {
    let mut captions = BTreeMap::<String, Vec<String>>::new();
    for (_, text) in pages().into_iter().filter(|(page, _)| page != HISTORY) {
        let paragraphs = paragraphs(&text);
        for (i, paragraph) in paragraphs.iter().enumerate() {
            for name in linked_pictures(paragraph) {
                let next = paragraphs.get(i + 1).map_or("", String::as_str);
                captions.entry(name).or_default().push(format!("{paragraph} {next}"));
            }
        }
    }
    captions
}

#[test]
fn every_picture_in_the_docs_is_made_by_the_pictures_script() {
    let pictures = listed();
    let in_docs: BTreeSet<String> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .filter_map(|entry| {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            name.strip_suffix(".png").map(str::to_string)
        })
        .collect();
    let listed: BTreeSet<String> = pictures.keys().cloned().collect();
    assert_eq!(
        in_docs, listed,
        "the pictures in docs/ (left) and those scripts/pictures.sh makes (right) differ"
    );
    for (name, picture) in &pictures {
        assert!(
            ["lavapipe", "gpu"].contains(&picture.made_on.as_str()),
            "{name} is made on {:?}, not lavapipe or gpu",
            picture.made_on
        );
        let last = picture.commands.last().unwrap();
        assert!(
            last.contains(&format!(" docs/{name}.png")),
            "the last command for {name} does not write docs/{name}.png: {last}"
        );
    }
    let shown: BTreeSet<String> = captions().into_keys().collect();
    let missing: Vec<_> = shown.difference(&in_docs).collect();
    assert!(missing.is_empty(), "the docs show pictures docs/ lacks: {missing:?}");
    let unshown: Vec<_> = in_docs.difference(&shown).collect();
    assert!(unshown.is_empty(), "pictures in docs/ no page shows: {unshown:?}");
}

#[test]
fn every_caption_names_the_command_that_made_its_picture() {
    let captions = captions();
    let mut wrong = Vec::new();
    for (name, picture) in listed() {
        // A picture of one command names it; one joined from pieces names the script.
        let named = match &picture.commands[..] {
            [command] => command.clone(),
            _ => format!("scripts/pictures.sh {name}"),
        };
        let texts = captions.get(&name).map(Vec::as_slice).unwrap_or_default();
        if !texts.iter().any(|text| text.contains(&named)) {
            wrong.push(format!("{name}: no caption says `{named}`"));
        }
    }
    assert!(
        wrong.is_empty(),
        "captions without their command:\n{}",
        wrong.join("\n")
    );
}

/// The words of a command, its shell quotes removed (the commands quote only whole words).
fn words(command: &str) -> Vec<String> {
    command
        .split_whitespace()
        .map(|w| w.trim_matches('\'').to_string())
        .collect()
}

/// What `sward ARGS` prints.
fn sward_says(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_sward"))
        .args(args)
        .output()
        .expect("sward runs");
    assert!(output.status.success(), "sward {args:?} failed");
    String::from_utf8(output.stdout).unwrap()
}

/// Checks commands against sward's own word: its subcommands' flags and its scene keys.
struct Sward {
    helps: BTreeMap<String, String>,
    reference: String,
}

impl Sward {
    fn new() -> Self {
        let subcommands = ["view", "render", "bench", "info", "soak", "scene"];
        let helps = subcommands
            .iter()
            .map(|s| (s.to_string(), sward_says(&[s, "--help"])))
            .collect();
        let reference = sward_says(&["scene", "--markdown"]);
        Sward { helps, reference }
    }

    /// What sward would refuse in `command`: in `sward SUBCOMMAND …` or `scripts/run.sh
    /// SUBCOMMAND …`, flags its subcommand lacks; anywhere, `--set` keys the scene reference
    /// does not list (`--set KEY=VALUE`, a placeholder, aside).
    fn refusals(&self, command: &str) -> Vec<String> {
        let words = words(command);
        let mut refused = Vec::new();
        let program = words.first().map(String::as_str);
        let help = words.get(1).and_then(|s| self.helps.get(s));
        if let (Some("sward" | "scripts/run.sh"), Some(help)) = (program, help) {
            for flag in words.iter().filter(|w| w.starts_with("--")) {
                let flag = flag.split('=').next().unwrap();
                if !help.contains(&format!("{flag} ")) && !help.contains(&format!("{flag}\n")) {
                    refused.push(format!("sward {} has no {flag}", words[1]));
                }
            }
        }
        for set in words.windows(2).filter(|w| w[0] == "--set").map(|w| &w[1]) {
            let dotted = set.split('=').next().unwrap();
            let placeholder = dotted.chars().all(|c| c.is_ascii_uppercase());
            if !placeholder && !self.lists_key(dotted) {
                refused.push(format!("the scene reference has no key {dotted}"));
            }
        }
        refused
    }

    /// Whether the scene reference lists `table.key` (`wind.1.type`: the second `[[wind]]`).
    fn lists_key(&self, dotted: &str) -> bool {
        let parts: Vec<&str> = dotted.split('.').filter(|p| p.parse::<u32>().is_err()).collect();
        let (key, table) = parts.split_last().unwrap();
        let table = table.join(".");
        let row = format!("| `{key}` |");
        self.reference.split("\n## ").any(|section| {
            let named = section.starts_with(&format!("`[{table}]`")) || section.starts_with(&format!("`[[{table}]]`"));
            let top = table.is_empty() && section.starts_with("The top level");
            (named || top) && section.contains(&row)
        })
    }
}

#[test]
fn the_pictures_commands_use_flags_and_keys_sward_has() {
    let sward = Sward::new();
    let mut wrong = Vec::new();
    for (name, picture) in listed() {
        for command in &picture.commands {
            wrong.extend(sward.refusals(command).into_iter().map(|r| format!("{name}: {r}")));
        }
    }
    assert!(wrong.is_empty(), "commands sward would refuse:\n{}", wrong.join("\n"));
}

/// Every command written in the pages: each code span, and each line of a code block.
fn written_commands() -> Vec<(String, String)> {
    let mut commands = Vec::new();
    for (page, text) in pages().into_iter().filter(|(page, _)| page != HISTORY) {
        let mut prose = String::new();
        for (i, part) in text.split("```").enumerate() {
            if i % 2 == 1 {
                commands.extend(part.lines().map(|line| (page.clone(), line.to_string())));
            } else {
                prose.push_str(part);
            }
        }
        let prose = prose.split_whitespace().collect::<Vec<_>>().join(" ");
        let spans = prose.split('`').skip(1).step_by(2);
        commands.extend(spans.map(|span| (page.clone(), span.to_string())));
    }
    commands
}

#[test]
fn every_sward_command_in_the_pages_uses_flags_and_keys_sward_has() {
    let sward = Sward::new();
    let commands = written_commands();
    let checked = commands
        .iter()
        .filter(|(_, c)| c.starts_with("sward ") || c.starts_with("scripts/run.sh "))
        .count();
    assert!(checked > 30, "only {checked} commands found in the pages");
    let wrong: Vec<String> = commands
        .iter()
        .flat_map(|(page, command)| {
            sward
                .refusals(command)
                .into_iter()
                .map(move |r| format!("{page}: {r}: {command}"))
        })
        .collect();
    assert!(wrong.is_empty(), "commands sward would refuse:\n{}", wrong.join("\n"));
}

/// GitHub's anchor for a heading: lower case, punctuation dropped, spaces as hyphens.
fn anchor(heading: &str) -> String {
    heading
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, ' ' | '-' | '_'))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The targets of a page's Markdown links and pictures, `[text](target)`.
fn link_targets(text: &str) -> Vec<String> {
    text.match_indices("](")
        .filter_map(|(at, _)| {
            let rest = &text[at + 2..];
            Some(rest[..rest.find(')')?].to_string())
        })
        .collect()
}

/// The anchors of a page's headings.
fn headings(text: &str) -> BTreeSet<String> {
    text.lines()
        .filter_map(|l| l.strip_prefix('#'))
        .map(|l| anchor(l.trim_start_matches('#').trim()))
        .collect()
}

/// Every link leads to a file that is there and, where it names a heading (on its own page or
/// another), to that heading: pages that moved keep their links.
#[test]
fn every_link_in_the_pages_leads_somewhere() {
    let mut broken = Vec::new();
    for (page, text) in pages() {
        let dir = if page == "README.md" || page == "BENCHMARKS.md" {
            root()
        } else {
            root().join("docs")
        };
        for target in link_targets(&text) {
            if target.starts_with("http") {
                continue;
            }
            let (path, fragment) = target.split_once('#').unwrap_or((&target, ""));
            let file = dir.join(path);
            let file_found = path.is_empty() || file.exists();
            let anchors = if path.is_empty() {
                headings(&text)
            } else if path.ends_with(".md") && file_found {
                headings(&std::fs::read_to_string(&file).unwrap())
            } else {
                BTreeSet::new()
            };
            let anchor_found = fragment.is_empty() || anchors.contains(fragment);
            if !file_found || !anchor_found {
                broken.push(format!("{page}: {target}"));
            }
        }
    }
    assert!(broken.is_empty(), "links that lead nowhere:\n{}", broken.join("\n"));
}

/// The README reads on one screen's width and in a sitting, and BENCHMARKS.md says what to
/// expect, its history in docs/.
#[test]
fn the_readme_and_the_benchmarks_stay_short() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 400, "README.md has {lines} lines, more than 400");
    let wide: Vec<_> = readme
        .lines()
        .enumerate()
        .filter(|(_, l)| l.chars().count() > 100)
        .map(|(i, _)| i + 1)
        .collect();
    assert!(wide.is_empty(), "README.md's lines wider than 100 columns: {wide:?}");
    let benchmarks = std::fs::read_to_string(root().join("BENCHMARKS.md")).unwrap();
    let lines = benchmarks.lines().count();
    assert!(lines <= 300, "BENCHMARKS.md has {lines} lines, more than 300");
}

/// The README's first screen, before the tour: a picture, the two set-up commands, what a
/// machine needs (the Rust version the workspace declares) and the contents.
#[test]
fn the_readme_s_first_screen_shows_starts_and_says_what_it_needs() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let first = &readme[..readme.find("\n## What it does").expect("a What it does section")];
    assert!(
        first.contains("![") && first.contains(".png)"),
        "no picture on the first screen"
    );
    let start = first.split("```sh").nth(1).expect("a shell block on the first screen");
    let start = &start[..start.find("```").unwrap()];
    for script in ["scripts/run.sh", "scripts/test.sh"] {
        assert!(start.contains(script), "the first screen's commands lack {script}");
        assert!(root().join(script).exists(), "{script} does not exist");
    }
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let rust = manifest
        .lines()
        .find_map(|l| l.strip_prefix("rust-version = "))
        .expect("the workspace declares its Rust version")
        .trim_matches('"');
    let needs = &first[first.find("## What you need").expect("a What you need section")..];
    assert!(
        needs.contains(&format!("Rust {rust}")),
        "What you need does not say Rust {rust}"
    );
    assert!(needs.contains("lavapipe") && needs.contains("Vulkan 1.3"), "{needs}");
    assert!(first.contains("## Contents"), "no contents on the first screen");
    let platforms = &first[first.find("## Where it runs").expect("a Where it runs section")..];
    for platform in ["Linux, Vulkan", "Windows", "Metal", "WebGPU"] {
        assert!(
            platforms.contains(&format!("| {platform}")) || platforms.contains(platform),
            "the platforms table lacks {platform}"
        );
    }
}

/// The licences the manifest declares are there, and what `bench` writes by default is ignored
/// by git, so a first `bench` changes no tracked file.
#[test]
fn the_declared_licences_are_there_and_bench_s_output_is_ignored() {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    assert!(
        manifest.contains("license = \"MIT OR Apache-2.0\""),
        "the licence changed"
    );
    let mit = std::fs::read_to_string(root().join("LICENSE-MIT")).unwrap();
    assert!(mit.starts_with("MIT License"), "LICENSE-MIT is not the MIT licence");
    let apache = std::fs::read_to_string(root().join("LICENSE-APACHE")).unwrap();
    assert!(apache.contains("Apache License") && apache.contains("Version 2.0"));
    let help = sward_says(&["bench", "--help"]);
    // `--out <OUT>`, its description, then `[default: FOLDER]`.
    let out = &help[help.find("--out <").expect("bench has --out")..];
    let out = &out[..out.find("\n      --").unwrap_or(out.len())];
    let default = out
        .split_once("[default: ")
        .and_then(|(_, rest)| rest.split_once(']'))
        .map(|(folder, _)| folder)
        .expect("bench's --out has a default folder");
    let ignored = std::fs::read_to_string(root().join(".gitignore")).unwrap();
    assert!(
        ignored.lines().any(|l| l.trim_matches('/') == default),
        ".gitignore does not ignore bench's default output {default}/"
    );
}

/// A picture the script does not know is one sentence and exit 2, before anything is built.
#[test]
fn the_pictures_script_refuses_an_unknown_picture_in_one_sentence() {
    let output = Command::new("bash")
        .args(["scripts/pictures.sh", "savanna"])
        .current_dir(root())
        .output()
        .expect("bash runs scripts/pictures.sh");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("no picture savanna") && stderr.contains("meadow"),
        "{stderr}"
    );
}

#[test]
fn a_paragraph_s_picture_links_are_found() {
    let found = linked_pictures("see ![a](docs/meadow.png) and [b](trail.png), not `out.png` (x.png)");
    assert_eq!(found, ["meadow", "trail"]);
}
