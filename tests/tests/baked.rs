//! `fixshade bake`: the source it writes for flash, and what it reports. (The files
//! the firmware includes are generated, not committed: `cargo xtask bake` writes
//! `boards/baked/`.)

#[test]
fn bake_cli_writes_a_file_and_reports_its_size() {
    let out = std::env::temp_dir().join(format!("fixshade-bake-{}.rs", std::process::id()));
    let args: Vec<String> = ["bake", "robot", "--chunk", "100", "-o"]
        .iter()
        .map(|s| s.to_string())
        .chain([out.display().to_string()])
        .collect();
    let msg = fixshade_sim::cli::run(&args).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    std::fs::remove_file(&out).ok();
    // The reported size is what the arrays hold: 18 bytes per stored vertex, 6 per
    // triangle, counted from the file itself.
    let vertices: usize = text
        .lines()
        .filter(|l| l.trim_start().starts_with("[q("))
        .count();
    let triangles: usize = text
        .lines()
        .filter(|l| {
            let t = l.trim_start();
            t.starts_with('[')
                && !t.starts_with("[q(")
                && !t.starts_with("[n(")
                && t.ends_with("],")
        })
        .count();
    let normals = text
        .lines()
        .filter(|l| l.trim_start().starts_with("[n("))
        .count();
    assert_eq!(vertices, normals);
    assert!(
        msg.contains(&format!("{} bytes of flash", 18 * vertices + 6 * triangles)),
        "{msg}"
    );
    assert!(text.contains("pub const CHUNK_LIMIT: usize = 100;"));
    // Bad usage is exit code 2.
    let e = fixshade_sim::cli::run(&["bake".to_string(), "robot".to_string()]).unwrap_err();
    assert_eq!(e.code, 2);
}
