//! `sward bench --compare OLD NEW`: two result folders' `summary.csv` side by side, case by case —
//! the ratio of each case's median GPU frame, its p99 before and after — and a failure when a
//! case got slower than the tolerance allows. Run the regression set before and after a change
//! on one device, then compare the two folders.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Context as _;

/// One case of a summary: what identifies it across runs and what is compared.
#[derive(Clone, Debug, PartialEq)]
pub struct SummaryRow {
    /// The regression set's name of the case, or its set-up written out.
    pub key: String,
    pub frame_ms: f64,
    pub frame_p99_ms: f64,
    pub memory_mib: f64,
    pub device: String,
}

/// The columns that name a case where it has no regression-set name.
const KEY_COLUMNS: [&str; 8] = [
    "preset",
    "technique",
    "route",
    "quality",
    "blades",
    "culling",
    "speed",
    "width",
];

/// The cases of `summary.csv` text, in its order.
pub fn parse_summary(text: &str) -> Result<Vec<SummaryRow>, String> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header = split_csv(lines.next().ok_or("it is empty")?);
    let column = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format!("it has no column {name} (written by an older sward: run the bench again)"))
    };
    let frame = column("gpu_frame_median_ms")?;
    let p99 = column("gpu_frame_p99_ms")?;
    let memory = column("gpu_memory_mib")?;
    let device = column("device")?;
    let case = column("case")?;
    let keys = KEY_COLUMNS.iter().map(|k| column(k)).collect::<Result<Vec<_>, _>>()?;
    let mut rows = Vec::new();
    let mut setups = Vec::new();
    for (n, line) in lines.enumerate() {
        let cells = split_csv(line);
        let cell = |i: usize| cells.get(i).map(String::as_str).unwrap_or("");
        let number = |i: usize| {
            cell(i)
                .parse::<f64>()
                .map_err(|_| format!("row {} has {:?} where {} takes a number", n + 2, cell(i), header[i]))
        };
        let setup = keys.iter().map(|&i| cell(i)).collect::<Vec<_>>().join(" ");
        let key = match cell(case) {
            "" => setup.clone(),
            name => name.to_string(),
        };
        setups.push(setup);
        rows.push(SummaryRow {
            key,
            frame_ms: number(frame)?,
            frame_p99_ms: number(p99)?,
            memory_mib: number(memory)?,
            device: cell(device).to_string(),
        });
    }
    tell_apart(&mut rows, &setups);
    Ok(rows)
}

/// Cases of one name (the shipped open world standing and walking) told apart by their set-up
/// written out after the name, so each is compared with its own kind.
fn tell_apart(rows: &mut [SummaryRow], setups: &[String]) {
    let names: Vec<String> = rows.iter().map(|r| r.key.clone()).collect();
    for (row, setup) in rows.iter_mut().zip(setups) {
        if names.iter().filter(|n| **n == row.key).count() > 1 {
            row.key = format!("{} ({setup})", row.key);
        }
    }
}

/// A CSV line's cells: commas split them, except inside double quotes (which are dropped).
fn split_csv(line: &str) -> Vec<String> {
    let mut cells = vec![String::new()];
    let mut quoted = false;
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => cells.push(String::new()),
            c => cells.last_mut().expect("one cell at least").push(c),
        }
    }
    cells
}

/// What the comparison found: its Markdown table, and the cases slower than the tolerance.
pub struct Comparison {
    pub markdown: String,
    pub slower: Vec<String>,
    pub compared: usize,
}

/// Every case of `new` that `old` has too, by its key: the ratio new / old of the median GPU
/// frame, slower where it exceeds 1 + `tolerance`.
pub fn compare(old: &[SummaryRow], new: &[SummaryRow], tolerance: f64) -> Comparison {
    let mut md = String::new();
    let devices = |rows: &[SummaryRow]| rows.first().map_or(String::new(), |r| r.device.clone());
    let _ = writeln!(md, "old: {} — new: {}\n", devices(old), devices(new));
    let _ = writeln!(
        md,
        "| case | old median ms | new median ms | new / old | old p99 ms | new p99 ms | GPU memory MiB, old → new | |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    let mut slower = Vec::new();
    let mut compared = 0;
    for n in new {
        let Some(o) = old.iter().find(|o| o.key == n.key) else {
            let _ = writeln!(
                md,
                "| {} | – | {:.3} | new case | – | {:.3} | {:.0} | |",
                n.key, n.frame_ms, n.frame_p99_ms, n.memory_mib
            );
            continue;
        };
        compared += 1;
        let ratio = n.frame_ms / o.frame_ms;
        let verdict = if ratio > 1.0 + tolerance {
            slower.push(format!(
                "{} ({:.3} → {:.3} ms, ×{ratio:.3})",
                n.key, o.frame_ms, n.frame_ms
            ));
            "SLOWER"
        } else if ratio < 1.0 - tolerance {
            "faster"
        } else {
            ""
        };
        let _ = writeln!(
            md,
            "| {} | {:.3} | {:.3} | {ratio:.3} | {:.3} | {:.3} | {:.0} → {:.0} | {verdict} |",
            n.key, o.frame_ms, n.frame_ms, o.frame_p99_ms, n.frame_p99_ms, o.memory_mib, n.memory_mib
        );
    }
    for o in old.iter().filter(|o| !new.iter().any(|n| n.key == o.key)) {
        let _ = writeln!(
            md,
            "| {} | {:.3} | – | not in new | {:.3} | – | {:.0} | |",
            o.key, o.frame_ms, o.frame_p99_ms, o.memory_mib
        );
    }
    Comparison {
        markdown: md,
        slower,
        compared,
    }
}

/// Read `dir/summary.csv`.
fn read_summary(dir: &Path) -> anyhow::Result<Vec<SummaryRow>> {
    let path = dir.join("summary.csv");
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {} (a folder `sward bench --out` wrote)", path.display()))?;
    parse_summary(&text).map_err(|e| anyhow::anyhow!("{} is not a bench summary: {e}", path.display()))
}

/// Compare the folders `old` and `new`, print the table, and fail when a case is more than
/// `tolerance` slower or nothing could be compared.
pub fn run(old: &Path, new: &Path, tolerance: f64) -> anyhow::Result<()> {
    let (before, after) = (read_summary(old)?, read_summary(new)?);
    let device = |rows: &[SummaryRow]| rows.first().map(|r| r.device.clone());
    if device(&before) != device(&after) {
        anyhow::bail!(
            "{} ran on {} and {} on {}: compare runs made on one device",
            old.display(),
            device(&before).unwrap_or_else(|| "nothing".into()),
            new.display(),
            device(&after).unwrap_or_else(|| "nothing".into())
        );
    }
    let comparison = compare(&before, &after, tolerance);
    println!("{}", comparison.markdown);
    if comparison.compared == 0 {
        anyhow::bail!(
            "{} and {} share no case: run the same set (e.g. --regression-set) into both",
            old.display(),
            new.display()
        );
    }
    if !comparison.slower.is_empty() {
        anyhow::bail!(
            "{} of {} cases are more than {:.0} % slower in {} than in {}: {}",
            comparison.slower.len(),
            comparison.compared,
            tolerance * 100.0,
            new.display(),
            old.display(),
            comparison.slower.join("; ")
        );
    }
    println!(
        "all {} cases within {:.0} % or faster",
        comparison.compared,
        tolerance * 100.0
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(rows: &[(&str, f64)]) -> String {
        let mut text = String::from(
            "device,driver,width,height,commit,case,preset,technique,route,quality,msaa,blades,culling,speed,frames,gpu_frame_median_ms,gpu_frame_p99_ms,gpu_memory_mib\n",
        );
        for (case, ms) in rows {
            let _ = writeln!(
                text,
                "\"GPU, 1\",\"driver 1.0\",1920,1080,abc,{case},meadow,instanced,strips,high,4,1024,all,0,60,{ms},{},100",
                ms * 1.1
            );
        }
        text
    }

    #[test]
    fn a_case_slower_than_the_tolerance_is_named_and_others_pass() {
        let old = parse_summary(&summary(&[("a", 10.0), ("b", 5.0), ("c", 2.0)])).unwrap();
        let new = parse_summary(&summary(&[("a", 10.29), ("b", 5.2), ("c", 1.0)])).unwrap();
        let c = compare(&old, &new, 0.03);
        assert_eq!(c.compared, 3);
        assert_eq!(c.slower.len(), 1, "{:?}", c.slower);
        assert!(c.slower[0].starts_with("b "), "{:?}", c.slower);
        assert!(c.markdown.contains("| b | 5.000 | 5.200 | 1.040 |"), "{}", c.markdown);
        assert!(c.markdown.contains("faster"), "{}", c.markdown);
        assert!(
            c.markdown.contains("GPU, 1"),
            "quoted cells keep their commas: {}",
            c.markdown
        );
    }

    /// The shipped open world is measured standing and walking, both named `openworld`: each is
    /// compared with its own kind, not both with the first.
    #[test]
    fn cases_of_one_name_are_told_apart_by_their_set_up() {
        let text = |standing: f64, walking: f64| {
            // The second row walks at 1.5 m/s.
            let rows = summary(&[("openworld", standing), ("openworld", walking)]);
            let (head, walked) = rows.rsplit_once(",0,60,").expect("the second row's speed");
            format!("{head},1.5,60,{walked}")
        };
        let old = parse_summary(&text(5.8, 6.4)).unwrap();
        let new = parse_summary(&text(5.8, 6.4)).unwrap();
        assert_ne!(old[0].key, old[1].key);
        let c = compare(&old, &new, 0.03);
        assert_eq!(c.compared, 2);
        assert!(c.slower.is_empty(), "{:?}", c.slower);
    }

    #[test]
    fn cases_only_in_one_folder_are_listed_not_compared() {
        let old = parse_summary(&summary(&[("a", 1.0), ("gone", 1.0)])).unwrap();
        let new = parse_summary(&summary(&[("a", 1.0), ("added", 9.0)])).unwrap();
        let c = compare(&old, &new, 0.03);
        assert_eq!(c.compared, 1);
        assert!(c.slower.is_empty());
        assert!(c.markdown.contains("| added | – | 9.000 | new case"), "{}", c.markdown);
        assert!(c.markdown.contains("| gone | 1.000 | – | not in new"), "{}", c.markdown);
    }

    #[test]
    fn an_unnamed_case_is_keyed_by_its_set_up() {
        let text = summary(&[("", 3.0)]);
        let rows = parse_summary(&text).unwrap();
        assert_eq!(rows[0].key, "meadow instanced strips high 1024 all 0 1920");
    }

    #[test]
    fn a_summary_without_the_columns_says_which_is_missing() {
        let e = parse_summary("device,preset\n\"x\",meadow\n").unwrap_err();
        assert!(e.contains("gpu_frame_median_ms"), "{e}");
        let e = parse_summary(&summary(&[("a", 1.0)]).replace(",1.1,", ",fast,")).unwrap_err();
        assert!(e.contains("takes a number") || e.contains("no column"), "{e}");
    }
}
