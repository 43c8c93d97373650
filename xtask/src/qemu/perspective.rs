//! The perspective-correct Gouraud fill in `cargo xtask qemu`. The images built with
//! the feature `perspective` draw `boards/common`'s `perspective_cases`, the
//! accuracy report's perspective rows: `Frame::draw_perspective` at every pixel
//! (`perspective-1@exact`), per sub-span of 8 and 16 pixels (`perspective-8@exact`,
//! `perspective-16@D` with `exact`, `table`, `shift-add-8`), and the affine
//! `gradient` fill of the same image (`affine@exact`) as reference. The host renders
//! them as `fixshade render --perspective on --perspective-span N --divide D`
//! (`--perspective off --span gradient` for `affine@exact`).
//!
//! The Cortex-M4 and the full-frame ARMv6-M images draw sphere, teapot, robot and
//! the effects table's ground plane (baked into boards/baked/full/ground_plane.rs).
//! A missing frame fails the task, as a differing one does.

use std::fmt::Write as _;

use fixshade_sim::scene::desc::{DivideName, Named, SceneDesc, SpanName};

use super::{fmt_per, m4, v6m, FrameRow, Image, Kind};

/// The perspective images, run after the others: the Cortex-M4, then ARMv6-M.
pub(super) const IMAGES: &[Image] = &[
    m4("perspective", "fixshade-qemu-mps2-an386", Kind::Figures),
    v6m("perspective", "fixshade-qemu-mps2-an386", Kind::Figures),
];

/// What each image must draw: (board, figures).
const EXPECTED: &[(&str, &[&str])] = &[
    ("mps2-an386", &["sphere", "teapot", "robot", "ground-plane"]),
    (
        "mps2-an385-v6m",
        &["sphere", "teapot", "robot", "ground-plane"],
    ),
];

/// The cases of `perspective_cases` (boards/common), in its order.
const CASES: &[&str] = &[
    "affine@exact",
    "perspective-1@exact",
    "perspective-8@exact",
    "perspective-16@exact",
    "perspective-16@table",
    "perspective-16@shift-add-8",
];

/// The scene file of a figure only the perspective images draw, relative to the
/// workspace root.
const GROUND_PLANE: &str = "crates/sim-host/scenes/effects/ground-plane.toml";

/// What `load::load_arg` loads for a figure: a built-in scene's name, or the
/// ground plane's scene file.
pub(super) fn source(figure: &str) -> String {
    match figure {
        "ground-plane" => super::root().join(GROUND_PLANE).display().to_string(),
        // The benchmark sphere at other segment counts (the image draws them at
        // 320×240; the host frame takes its size from the FRAME line).
        "bench-sphere-32x20" => "bench-sphere".to_string(),
        "bench-sphere-64x40" | "bench-sphere-128x80" => super::root()
            .join(format!("crates/sim-host/scenes/{figure}.toml"))
            .display()
            .to_string(),
        _ => figure.to_string(),
    }
}

/// `perspective-N@D` → `(N, D)`.
fn split(case: &str) -> Option<(&str, &str)> {
    case.strip_prefix("perspective-")?.split_once('@')
}

/// True for a case of the perspective images.
pub(super) fn is_case(case: &str) -> bool {
    case == "affine@exact" || split(case).is_some()
}

/// Sets the host scene for a case of the perspective images; `false` (scene
/// untouched) for any other case.
pub(super) fn apply(desc: &mut SceneDesc, case: &str) -> Result<bool, String> {
    if case == "affine@exact" {
        desc.span = SpanName::GRADIENT;
        desc.divide = DivideName::EXACT;
        desc.perspective_correct = false;
        return Ok(true);
    }
    let Some((n, d)) = split(case) else {
        return Ok(false);
    };
    desc.span = SpanName::GRADIENT;
    desc.divide = DivideName::parse(d)?;
    desc.perspective_correct = true;
    desc.perspective_span = n
        .parse()
        .map_err(|_| format!("bad perspective case {case}"))?;
    Ok(true)
}

/// The CSV's `method`, `divide` and `sweep` of a case of the perspective images:
/// method `gradient` (affine) or `perspective-N`, sweep `perspective`.
pub(super) fn csv_names(case: &str) -> Option<(&str, &str, &str)> {
    if case == "affine@exact" {
        return Some(("gradient", "exact", "perspective"));
    }
    let (_, d) = split(case)?;
    Some((&case[..case.len() - d.len() - 1], d, "perspective"))
}

/// Fails unless every expected board and figure has a frame of every case.
pub(super) fn check(rows: &[FrameRow]) -> Result<(), String> {
    for (board, figures) in EXPECTED {
        for figure in *figures {
            for case in CASES {
                if !rows
                    .iter()
                    .any(|r| r.board == *board && r.figure == *figure && r.case == *case)
                {
                    return Err(format!(
                        "{board} {figure}: no perspective frame {case} (expected from the `perspective` images)"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The markdown section: per board and figure, each case against the same image's
/// affine `gradient`.
pub(super) fn section(rows: &[FrameRow]) -> String {
    let here: Vec<&FrameRow> = rows.iter().filter(|r| is_case(&r.case)).collect();
    if here.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n## Perspective-correct Gouraud\n\n\
         `Frame::draw_perspective` (`fixshade render --perspective on --perspective-span N\n\
         --divide D`): one reciprocal per pixel (`perspective-1`) or per sub-span of 8 or\n\
         16 pixels with linear colours in between, with the dividers of the accuracy\n\
         report's perspective rows, next to the affine `gradient` fill (`gradient`, what\n\
         the correction replaces; same coverage and depth) drawn by the same image: code\n\
         layout alone moves counts between images by a few per cent, so each ratio is to\n\
         that image's own `gradient`. Every frame was compared byte for byte with the host\n\
         render of the same settings. The Cortex-M4 and the full-frame ARMv6-M images draw\n\
         sphere, teapot, robot and the effects table's ground plane\n\
         (crates/sim-host/scenes/effects/ground-plane.toml, a 40 × 40 plane at a grazing\n\
         angle: the case where the correction matters). The micro:bit images draw no\n\
         perspective-correct frames. `draw per pixel` is the rasterizer alone per covered pixel,\n\
         `per pixel` the whole frame (vertex stage and draw); `draw × gradient` the draw\n\
         against the image's affine `gradient` draw.\n",
    );
    for mine in super::by_board_figure(&here) {
        let (board, figure) = (mine[0].board.as_str(), mine[0].figure.as_str());
        let affine = mine.iter().find(|r| r.case == "affine@exact");
        let _ = writeln!(
            md,
            "\n### {board} — {figure} at {}×{} ({} triangles)\n\n\
             | fill | divider | drawn | pixels | draw | per pixel | draw per pixel | draw × gradient |\n\
             | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |",
            mine[0].width, mine[0].height, mine[0].triangles
        );
        for r in &mine {
            let (method, divide, _) = csv_names(&r.case).unwrap_or(("?", "?", ""));
            let ratio = match affine {
                Some(a) if a.draw > 0 => format!("{:.2}", r.draw as f64 / a.draw as f64),
                _ => "-".into(),
            };
            let _ = writeln!(
                md,
                "| {method} | {divide} | {} | {} | {} | {} | {} | {ratio} |",
                r.drawn,
                r.pixels,
                r.draw,
                fmt_per(r.total(), r.pixels),
                fmt_per(r.draw, r.pixels),
            );
        }
    }
    md
}
