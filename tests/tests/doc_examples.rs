//! Every public item of the core that a firmware author meets at the top level of a
//! module — function, type, trait, struct, enum — carries an example in its docs (a
//! code block that rustdoc compiles and runs), or points to its module's example.
//! Methods, constants and fields are covered by their type's example.

use std::path::Path;

/// Top-level public items of `src` whose doc comment has no code block.
fn missing_examples(src: &str) -> Vec<String> {
    let lines: Vec<&str> = src.lines().collect();
    let mut missing = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        if line.starts_with("#[cfg(test)]") || line.starts_with("#[cfg(doctest)]") {
            // Test modules come last; the README doctest holder is not API.
            if line.starts_with("#[cfg(test)]") {
                break;
            }
            continue;
        }
        let Some(rest) = line.strip_prefix("pub ") else {
            continue;
        };
        let rest = rest
            .strip_prefix("const fn ")
            .or_else(|| rest.strip_prefix("fn "));
        let (kind, name) = match rest {
            Some(r) => ("fn", r),
            None => {
                let r = line.strip_prefix("pub ").unwrap();
                match ["struct ", "enum ", "trait ", "type "]
                    .iter()
                    .find_map(|k| r.strip_prefix(k).map(|n| (k.trim(), n)))
                {
                    Some(x) => x,
                    None => continue,
                }
            }
        };
        let name: String = name
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        // The doc block above the item (attributes in between are skipped).
        let mut doc = Vec::new();
        let mut j = i;
        let mut hidden = false;
        while j > 0 {
            j -= 1;
            let l = lines[j].trim_start();
            if l.starts_with("#[") {
                hidden |= l.starts_with("#[doc(hidden)]") || l.starts_with("#[cfg(doctest)]");
                continue;
            }
            if l.starts_with("///") {
                doc.push(l);
                continue;
            }
            break;
        }
        let has_example = doc
            .iter()
            .any(|l| l.contains("```") || l.contains("[module docs](self)"));
        if !hidden && !has_example {
            missing.push(format!("{kind} {name}"));
        }
    }
    missing
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn every_public_item_has_an_example() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../crates/core-nostd/src");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    files.sort();
    let mut report = Vec::new();
    let mut items = 0;
    for f in &files {
        let name = f.strip_prefix(&root).unwrap().display().to_string();
        // Unit-test files and the hidden fixtures of the examples are not API.
        if name.ends_with("tests.rs") || name == "doc_support.rs" || name == "defmt_impls.rs" {
            continue;
        }
        let src = std::fs::read_to_string(f).unwrap();
        items += src.lines().filter(|l| l.starts_with("pub ")).count();
        for m in missing_examples(&src) {
            report.push(format!("{name}: {m}"));
        }
    }
    assert!(
        items > 100,
        "the scan found only {items} public lines: is the path right?"
    );
    assert!(
        report.is_empty(),
        "{} public items without an example:\n{}",
        report.len(),
        report.join("\n")
    );
}

#[test]
fn the_scan_sees_a_missing_example() {
    let src = "/// Documented.\n///\n/// ```\n/// assert!(true);\n/// ```\npub fn a() {}\n\n\
               /// No example.\n#[inline]\npub fn b() {}\n\n/// See the [module docs](self) for an example.\npub struct C;\n";
    assert_eq!(missing_examples(src), vec!["fn b".to_string()]);
}
