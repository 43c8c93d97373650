//! The perspective-correct Gouraud fill in `cargo xtask qemu`. The images built with
//! the feature `perspective` draw `boards/common`'s `perspective_cases`:
//! `Frame::draw_perspective` at every pixel (`perspective-1@D`) and per sub-span of
//! 16 pixels (`perspective-16@D`) with the dividers `exact` and `shift-add-8`, and
//! the affine `gradient` fill of the same image (`affine@exact`) as reference. The
//! host renders them as `fixshade render --perspective on --perspective-span N
//! --divide D` (`--perspective off --span gradient` for `affine@exact`); the
//! Cortex-M0 frames through `render_chunked` (its strips and mesh chunks).
//!
//! The Cortex-M4 image draws sphere, teapot, robot and the effects table's ground
//! plane (baked into boards/baked/full/ground_plane.rs), the Cortex-M0 images one
//! figure each. A missing frame fails the task, as a differing one does.

use std::fmt::Write as _;

use fixshade_sim::scene::desc::{DivideName, Named, SceneDesc, SpanName};

use super::{fmt_per, FrameRow, Image, Kind};

/// The perspective images, run after the others.
pub(super) const IMAGES: &[Image] = &[
    Image {
        krate: "qemu-mps2-an386",
        features: "perspective",
        target: "thumbv7em-none-eabihf",
        bin: "fixshade-qemu-mps2-an386",
        machine: "mps2-an386",
        cpu: "cortex-m4",
        kind: Kind::Figures,
    },
    m0("sphere,perspective"),
];

/// What each image must draw: (board, figures).
const EXPECTED: &[(&str, &[&str])] = &[
    ("mps2-an386", &["sphere", "teapot", "robot", "ground-plane"]),
    ("microbit", &["sphere"]),
];

/// The cases of `perspective_cases` (boards/common), in its order.
const CASES: &[&str] = &[
    "affine@exact",
    "perspective-1@exact",
    "perspective-16@exact",
    "perspective-1@shift-add-8",
    "perspective-16@shift-add-8",
];

/// The scene file of a figure only the perspective images draw, relative to the
/// workspace root.
const GROUND_PLANE: &str = "crates/sim-host/scenes/effects/ground-plane.toml";

/// A Cortex-M0 (micro:bit) image with these features.
const fn m0(features: &'static str) -> Image {
    Image {
        krate: "qemu-microbit",
        features,
        target: "thumbv6m-none-eabi",
        bin: "fixshade-qemu-microbit",
        machine: "microbit",
        cpu: "cortex-m0",
        kind: Kind::Figures,
    }
}

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
pub(super) fn section(rows: &[FrameRow], sizes: &[(String, u64, u64)]) -> String {
    let here: Vec<&FrameRow> = rows.iter().filter(|r| is_case(&r.case)).collect();
    if here.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n## Perspective-correct Gouraud\n\n\
         `Frame::draw_perspective` (`fixshade render --perspective on --perspective-span N\n\
         --divide D`): one reciprocal per pixel (`perspective-1`) or per sub-span of 16\n\
         pixels with linear colours in between (`perspective-16`), with the dividers `exact`\n\
         and `shift-add-8`, next to the affine `gradient` fill (`gradient`, what the\n\
         correction replaces; same coverage and depth) drawn by the same image: code layout\n\
         alone moves counts between images by a few per cent, so each ratio is to that\n\
         image's own `gradient`. Every frame was compared byte for byte with the host\n\
         render of the same settings (on the Cortex-M0, rendering the same strips and mesh\n\
         chunks). The Cortex-M4 image draws sphere, teapot, robot and the effects table's\n\
         ground plane (crates/sim-host/scenes/effects/ground-plane.toml, a 40 × 40 plane at\n\
         a grazing angle: the case where the correction matters), the Cortex-M0 image the\n\
         sphere (sizes of both images in the firmware table above, their stack in the\n\
         calibration lines). `draw per pixel` is the rasterizer alone per covered pixel,\n\
         `per pixel` the whole frame (vertex stage and draw); `draw × gradient` the draw\n\
         against the image's affine `gradient` draw.\n",
    );
    let mut keys: Vec<(&str, &str)> = Vec::new();
    for r in &here {
        if !keys.contains(&(r.board.as_str(), r.figure.as_str())) {
            keys.push((&r.board, &r.figure));
        }
    }
    for (board, figure) in keys {
        let mine: Vec<&&FrameRow> = here
            .iter()
            .filter(|r| r.board == board && r.figure == figure)
            .collect();
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
    md.push_str(&m0_room(sizes));
    md
}

/// What the Cortex-M0 leaves out, from the measured image sizes: the perspective
/// fill's flash (the sphere's perspective image minus its span image) against the
/// room the scene images leave.
fn m0_room(sizes: &[(String, u64, u64)]) -> String {
    const FLASH: u64 = 256 * 1024;
    let flash = |label: &str| sizes.iter().find(|s| s.0 == label).map(|s| s.1);
    let (Some(persp), Some(spans)) = (
        flash("qemu-microbit (sphere,perspective)"),
        flash("qemu-microbit (sphere)"),
    ) else {
        return String::new();
    };
    let fill = persp.saturating_sub(spans);
    let others = ["teapot", "robot"]
        .iter()
        .filter_map(|f| Some((*f, flash(&format!("qemu-microbit ({f})"))?)))
        .map(|(f, b)| format!("{f} {b} B + {fill} B = {} B", b + fill))
        .collect::<Vec<_>>()
        .join(", ");
    let mut md = format!(
        "\nOn the Cortex-M0 the perspective image of the sphere takes {persp} B of the {FLASH} B\n\
         of flash, {fill} B more than the sphere's span-method image ({spans} B). Teapot and\n\
         robot are not drawn, to keep the task's time down; by the same difference their\n\
         images would take about {others} (estimated, not built). The scene catalogue's\n\
         Cortex-M0 images draw no perspective-correct frames. Free flash of their Gouraud\n\
         images against the {fill} B the fill added to the sphere's image (the fill, and\n\
         `Frame::draw`'s fallback for the other shading modes, which `draw_perspective`\n\
         carries): "
    );
    let list = sizes
        .iter()
        .filter(|s| s.0.starts_with("qemu-microbit (scenes") && !s.0.contains("flat"))
        .map(|(l, f, _)| {
            let free = FLASH.saturating_sub(*f);
            format!(
                "{l} {free} B free ({})",
                if free > fill {
                    "room for it, not done"
                } else {
                    "no room"
                }
            )
        })
        .collect::<Vec<_>>()
        .join("; ");
    let _ = writeln!(md, "{list}.");
    md
}
