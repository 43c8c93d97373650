//! `docs/scene-files.md` is the scene-file reference from the module docs of
//! `scene::file`; this test fails when they drift apart. `FIXSHADE_BLESS=1`
//! regenerates the markdown.

use std::path::Path;

fn generated() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(root.join("src/scene/file.rs")).unwrap();
    let mut lines = Vec::new();
    for l in src.lines() {
        let Some(rest) = l.strip_prefix("//!") else {
            break;
        };
        lines.push(rest.strip_prefix(' ').unwrap_or(rest).to_string());
    }
    let mut text = lines.join("\n");
    // Intra-doc links become plain code spans.
    while let Some(start) = text.find("[`") {
        let Some(end) = text[start..].find("`]") else {
            break;
        };
        let inner = text[start + 1..start + end + 1].to_string();
        text.replace_range(start..start + end + 2, &inner);
    }
    format!(
        "<!-- Generated from the docs of crates/sim-host/src/scene/file.rs; a test checks they agree. -->\n{text}\n"
    )
}

#[test]
fn scene_file_reference_matches_module_docs() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene-files.md");
    let want = generated();
    if std::env::var("FIXSHADE_BLESS").as_deref() == Ok("1") {
        std::fs::write(&path, &want).unwrap();
        return;
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/scene-files.md is out of date; run FIXSHADE_BLESS=1 cargo test -p fixshade-sim --test docs_drift"
    );
}
