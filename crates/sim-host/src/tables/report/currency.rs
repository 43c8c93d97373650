//! Whether the committed documents are current: [`check_report`] recomputes every
//! deterministic column of `docs/accuracy-vs-time.*` (one render per configuration
//! and one reference per figure and kind, no timing; the MCU cells from the
//! committed `docs/mcu-instructions.csv`), takes the host times from the committed
//! CSV itself, regenerates the markdown, CSV and per-core charts, and compares them
//! byte for byte with the committed files, the provenance line excepted.
//! [`check_specular`] does the same for the deterministic columns of
//! `docs/specular.{csv,md}` (error statistics, NMSE, instructions per evaluation).
//! A mismatch names the file, row and column.

use std::collections::HashMap;
use std::path::Path;
use std::time::Duration;

use super::text::CSV_HEADER;
use super::{assemble, chart, documents, mcu, measure, ReportOptions, STEM};
use crate::tables::{claims, provenance, specular};

fn read(p: &Path) -> Result<String, String> {
    std::fs::read_to_string(p).map_err(|e| format!("cannot read {}: {e}", p.display()))
}

/// The first difference of two line-oriented texts: for a table or CSV line, the
/// column (by the latest header line of `fresh`); lines starting with
/// [`provenance::PREFIX`] are skipped.
pub fn first_difference(file: &str, committed: &str, fresh: &str, sep: char) -> Option<String> {
    let (a, b): (Vec<&str>, Vec<&str>) = (
        committed
            .lines()
            .filter(|l| !l.starts_with(provenance::PREFIX))
            .collect(),
        fresh
            .lines()
            .filter(|l| !l.starts_with(provenance::PREFIX))
            .collect(),
    );
    let mut header: Vec<&str> = Vec::new();
    for i in 0..a.len().max(b.len()) {
        let (x, y) = (
            a.get(i).copied().unwrap_or(""),
            b.get(i).copied().unwrap_or(""),
        );
        let cells = |l: &'static str, s: &str| -> Vec<String> {
            let _ = l;
            s.trim_matches('|')
                .split(sep)
                .map(|c| c.trim().to_string())
                .collect()
        };
        let is_row = sep == ',' || y.starts_with('|');
        if is_row && (i == 0 || (sep == '|' && !y.starts_with("|-") && header.is_empty())) {
            header = y.trim_matches('|').split(sep).map(str::trim).collect();
        }
        if !y.starts_with('|') && sep == '|' {
            header.clear();
        }
        if x == y {
            continue;
        }
        if is_row && !header.is_empty() {
            let (cx, cy) = (cells("", x), cells("", y));
            let k = (0..cx.len().max(cy.len()))
                .find(|&k| cx.get(k) != cy.get(k))
                .unwrap_or(0);
            return Some(format!(
                "{file}, line {} (row `{}`), column `{}`: committed `{}`, now `{}`",
                i + 1,
                cy.iter().take(3).cloned().collect::<Vec<_>>().join(" "),
                header.get(k).copied().unwrap_or("?"),
                cx.get(k).map_or("", String::as_str),
                cy.get(k).map_or("", String::as_str)
            ));
        }
        return Some(format!(
            "{file}, line {}: committed `{x}`, now `{y}`",
            i + 1
        ));
    }
    None
}

/// Checks `ROOT/docs/accuracy-vs-time.{md,csv}` and the per-core charts against
/// what `fixshade report` would write from the tree at `root`.
pub fn check_report(root: &Path) -> Result<(), String> {
    let docs = root.join("docs");
    let opts = ReportOptions {
        out_dir: docs.clone(),
        progress: false,
        mcu_csv: root.join(super::MCU_CSV),
        specular_csv: root.join(super::SPECULAR_CSV),
        mcu_specular_csv: root.join(super::MCU_SPECULAR_CSV),
        ..ReportOptions::full()
    };
    let rerun = "rerun `cargo run --release -- report`";
    let csv = read(&docs.join(format!("{STEM}.csv")))?;
    let md = read(&docs.join(format!("{STEM}.md")))?;
    let mut lines = csv.lines();
    if lines.next() != Some(CSV_HEADER) {
        return Err(format!(
            "docs/{STEM}.csv has another header than the report writes; {rerun}"
        ));
    }
    // Host inputs of the committed CSV: frame ns and spread by (figure, kind, name).
    let mut host: HashMap<(String, String, String), (Duration, f64)> = HashMap::new();
    for l in lines {
        let c: Vec<&str> = l.split(',').collect();
        let n = CSV_HEADER.split(',').count();
        if c.len() != n {
            return Err(format!("docs/{STEM}.csv: malformed row `{l}`; {rerun}"));
        }
        let frame = c[n - 4]
            .parse::<u64>()
            .map_err(|_| format!("docs/{STEM}.csv: frame_ns of `{l}`"))?;
        let spread = c[n - 1]
            .parse::<f64>()
            .map_err(|_| format!("docs/{STEM}.csv: timing_spread of `{l}`"))?;
        host.insert(
            (c[0].to_string(), c[1].to_string(), c[2].to_string()),
            (Duration::from_nanos(frame), spread),
        );
    }
    let counts = mcu::McuTable::read(&opts.mcu_csv).map_err(|e| format!("{e}; {rerun}"))?;
    let inputs = claims::Inputs::read(&opts)?;
    let items = measure(&opts)?;
    let times = items
        .iter()
        .map(|m| {
            let key = (
                m.figure.clone(),
                m.config.kind.as_str().to_string(),
                m.config.name(),
            );
            host.get(&key).copied().ok_or_else(|| {
                format!(
                    "docs/{STEM}.csv has no row {} {} `{}`; {rerun}",
                    key.0, key.1, key.2
                )
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let rows = assemble(&items, &times, &counts).map_err(|e| format!("{e}; {rerun}"))?;
    let fresh = documents(&opts, &rows, &inputs)?;
    let mut problems = Vec::new();
    if let Some(d) = first_difference(&format!("docs/{STEM}.csv"), &csv, &fresh.csv, ',') {
        problems.push(d);
    }
    if let Some(d) = first_difference(&format!("docs/{STEM}.md"), &md, &fresh.markdown, '|') {
        problems.push(d);
    }
    for k in 0..mcu::BOARDS.len() {
        let name = chart::core_file(k);
        let have = std::fs::read(docs.join(&name)).unwrap_or_default();
        if let Some((_, bytes)) = fresh.charts.iter().find(|(n, _)| *n == name) {
            if &have != bytes {
                problems.push(format!("docs/{name} differs from the chart of the rows"));
            }
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!("{}; {rerun}", problems.join("; ")))
    }
}

/// Checks the deterministic columns of `ROOT/docs/specular.csv` (error
/// statistics, NMSE, instructions per evaluation) against a fresh computation.
pub fn check_specular(root: &Path) -> Result<(), String> {
    let rerun = "rerun `cargo run --release -- specular`";
    let docs = root.join("docs");
    let opts = specular::TableOptions {
        mcu_csv: root.join(super::MCU_SPECULAR_CSV),
        ..specular::TableOptions::full()
    };
    let committed = read(&docs.join("specular.csv"))?;
    let fresh = specular::deterministic_csv(&opts)?;
    let skip = ["ns_per_eval", "cost_vs_exact"];
    let header: Vec<&str> = specular::CSV_HEADER.split(',').collect();
    let mask = |t: &str| -> String {
        t.lines()
            .map(|l| {
                l.split(',')
                    .enumerate()
                    .map(|(i, c)| {
                        if header.get(i).is_some_and(|h| skip.contains(h)) {
                            "·"
                        } else {
                            c
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    match first_difference("docs/specular.csv", &mask(&committed), &mask(&fresh), ',') {
        Some(d) => Err(format!("{d}; {rerun}")),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn differences_name_row_and_column() {
        let a = "a,b,c\nsphere,span,1\n";
        let b = "a,b,c\nsphere,span,2\n";
        let d = first_difference("x.csv", a, b, ',').unwrap();
        assert!(
            d.contains("column `c`") && d.contains("committed `1`, now `2`"),
            "{d}"
        );
        let m1 = "# T\n\nMade from commit `a`.\n\n| k | v |\n|---|---|\n| x | 1 |\n";
        let m2 = "# T\n\nMade from commit `b`.\n\n| k | v |\n|---|---|\n| x | 2 |\n";
        let d = first_difference("x.md", m1, m2, '|').unwrap();
        assert!(d.contains("column `v`"), "{d}");
        assert!(first_difference("x.md", m1, &m1.replace("`a`", "`c`"), '|').is_none());
    }
}
