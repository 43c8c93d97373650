//! The `fixshade` command line through `fixshade_sim::cli::run`: exit codes (2 bad
//! usage, 1 failure), one-line messages that name the problem, and a render →
//! reference → compare round trip in a temporary directory.

use std::path::{Path, PathBuf};

use fixshade_sim::cli::{run, CliError};
use fixshade_sim::image::Image;
use fixshade_tests::*;

fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

fn err(a: &[&str]) -> CliError {
    match run(&args(a)) {
        Ok(out) => panic!("`fixshade {}` succeeded: {out}", a.join(" ")),
        Err(e) => e,
    }
}

/// The error has code `code`, is one non-empty line, and mentions every `needle`.
fn expect_err(a: &[&str], code: i32, needles: &[&str]) -> String {
    let e = err(a);
    let cmd = format!("`fixshade {}`", a.join(" "));
    assert_eq!(e.code, code, "{cmd}: exit code {} ({})", e.code, e.message);
    assert!(!e.message.trim().is_empty(), "{cmd}: empty message");
    assert!(
        !e.message.trim_end().contains('\n'),
        "{cmd}: message is not one line: {:?}",
        e.message
    );
    for n in needles {
        assert!(
            e.message.contains(n),
            "{cmd}: message {:?} does not mention {n:?}",
            e.message
        );
    }
    e.message
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn help_and_list() {
    let h = run(&args(&["help"])).unwrap();
    assert!(h.contains("USAGE") && h.contains("fixshade render"), "{h}");
    let l = run(&args(&["list"])).unwrap();
    for w in [
        "sphere",
        "teapot",
        "robot",
        "gradient",
        "classic",
        "rgb565le",
        "phong",
        "schlick-mod",
        "cos-quad-energy",
        "shift-add-rounded-16",
        "table",
    ] {
        assert!(l.contains(w), "list does not mention {w}: {l}");
    }
    // Every listed name has its line of description.
    for line in l.lines().filter(|l| l.starts_with("  ")) {
        assert!(
            line.split_whitespace().count() > 1,
            "no description: {line}"
        );
    }
    // `COMMAND --help` prints the usage instead of failing on an unknown option.
    for cmd in ["render", "reference", "compare", "report"] {
        let h = run(&args(&[cmd, "--help"])).unwrap();
        assert!(h.contains("USAGE"), "{cmd} --help: {h}");
    }
}

#[test]
fn bad_usage_exits_2() {
    let dir = temp_dir("cli-usage");
    let out = dir.join("o.png");
    let o = s(&out);
    expect_err(&["frobnicate"], 2, &["frobnicate"]);
    expect_err(&["render", "sphere", "-o", o, "--bogus"], 2, &["--bogus"]);
    expect_err(&["compare", "a.png", "b.png", "--phong"], 2, &["--phong"]);
    expect_err(&["reference", "sphere"], 2, &["-o"]);
    let m = expect_err(
        &["render", "sphere", "-o", o, "--span", "bresenham"],
        2,
        &["bresenham"],
    );
    assert!(
        m.contains("gradient") && m.contains("classic"),
        "valid span methods not listed: {m}"
    );
    expect_err(&["render", "sphere", "-o", o, "--span"], 2, &["--span"]);
    let m = expect_err(
        &["render", "sphere", "-o", o, "--divide", "shift-add-17"],
        2,
        &["divider", "shift-add-17"],
    );
    assert!(
        m.contains("shift-add-16") && m.contains("table") && m.contains("shift-add-rounded-4"),
        "valid dividers not listed: {m}"
    );
    expect_err(&["render", "sphere", "-o", o, "--divide"], 2, &["--divide"]);
    expect_err(
        &["render", "sphere", "-o", o, "--format", "rgb555"],
        2,
        &["rgb555"],
    );
    expect_err(
        &["render", "sphere", "-o", o, "--strip", "0"],
        2,
        &["--strip"],
    );
    expect_err(&["render", "-o", o], 2, &["SCENE"]);
    expect_err(&["compare", "only-one.png"], 2, &["two"]);
    assert!(!out.exists(), "a failed command wrote its output");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn missing_scene_file_exits_1() {
    let dir = temp_dir("cli-missing");
    let out = dir.join("o.png");
    let missing = dir.join("no-such-scene.toml");
    expect_err(
        &["render", s(&missing), "-o", s(&out)],
        1,
        &["no-such-scene.toml"],
    );
    expect_err(
        &["reference", s(&missing), "-o", s(&out)],
        1,
        &["no-such-scene.toml"],
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(dir);
}

fn bad_scenes_dir() -> PathBuf {
    package_path("../crates/sim-host/tests/data/scenes/bad")
}

/// Every malformed scene of the sim-host corpus fails with exit code 1 and a
/// message naming the file and, where the file says `# expect-line: N`, the line.
#[test]
fn malformed_scene_files_name_file_and_line() {
    let dir = temp_dir("cli-bad");
    let out = dir.join("o.png");
    let mut files: Vec<PathBuf> = std::fs::read_dir(bad_scenes_dir())
        .expect("the bad-scene corpus")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10, "only {} bad scenes", files.len());
    let mut with_line = 0;
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let line = text
            .lines()
            .find_map(|l| l.strip_prefix("# expect-line:"))
            .map(|v| v.trim().to_string());
        let name = f.file_name().unwrap().to_str().unwrap();
        let mut needles = vec![name.to_string()];
        if let Some(n) = line.as_deref().filter(|n| *n != "none") {
            needles.push(format!("{name}:{n}:"));
            with_line += 1;
        }
        let needles: Vec<&str> = needles.iter().map(String::as_str).collect();
        expect_err(&["render", s(f), "-o", s(&out)], 1, &needles);
    }
    assert!(with_line >= 5, "only {with_line} bad scenes name a line");
    assert!(!out.exists());
    println!(
        "{} malformed scenes, {with_line} with a line number",
        files.len()
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn compare_failures() {
    let dir = temp_dir("cli-compare");
    let a = dir.join("a.png");
    let b = dir.join("b.png");
    Image::new(32, 24, [10, 20, 30]).write_png(&a).unwrap();
    Image::new(24, 32, [10, 20, 30]).write_png(&b).unwrap();
    let missing = dir.join("missing.png");
    expect_err(&["compare", s(&missing), s(&a)], 1, &["missing.png"]);
    expect_err(&["compare", s(&a), s(&missing)], 1, &["missing.png"]);
    expect_err(
        &["compare", s(&a), s(&b)],
        1,
        &["size mismatch", "32x24", "24x32"],
    );
    let not_png = dir.join("not.png");
    std::fs::write(&not_png, "hello").unwrap();
    expect_err(&["compare", s(&a), s(&not_png)], 1, &["not.png"]);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn render_reference_compare_round_trip() {
    let dir = temp_dir("cli-round-trip");
    let test = dir.join("sub/test.png");
    let reference = dir.join("ref.png");
    let msg = run(&args(&[
        "render",
        "sphere",
        "-o",
        s(&test),
        "--span",
        "classic",
        "--strip",
        "16",
    ]))
    .unwrap();
    assert!(msg.contains("covered pixels"), "{msg}");
    run(&args(&["reference", "sphere", "-o", s(&reference)])).unwrap();
    assert!(test.exists() && reference.exists());

    let text = run(&args(&["compare", s(&reference), s(&test)])).unwrap();
    let first = text.lines().next().unwrap();
    assert!(first.starts_with("NMSE "), "{text}");
    let verdicts = ["indistinguishable", "minor", "noticeable", "significant"];
    let words: Vec<&str> = first.split_whitespace().collect();
    assert_eq!(words.len(), 3, "{first}");
    assert!(verdicts.contains(&words[2]), "no verdict word in {first:?}");
    let nmse: f64 = words[1].parse().unwrap();
    assert!(nmse <= 1e-5, "{first}");
    assert!(text.contains("coverage mismatch 0"), "{text}");

    let json = run(&args(&["compare", s(&reference), s(&test), "--json"])).unwrap();
    assert!(
        json.starts_with('{') && json.contains("\"verdict\": \"indistinguishable\""),
        "{json}"
    );

    // An image compared with itself.
    let same = run(&args(&["compare", s(&test), s(&test)])).unwrap();
    assert!(same.starts_with("NMSE 0.000e0 indistinguishable"), "{same}");
    let _ = std::fs::remove_dir_all(dir);
}
