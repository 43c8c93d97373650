//! The whole-pipeline hard cases (tests/catalogue/scenes.toml) on QEMU: `cargo xtask
//! bake` writes them to boards/baked/scenes/ (`fixshade_tests::scenes`), and
//! `cargo xtask qemu` runs the scene images (boards/*/src/bin/scenes.rs) and compares
//! every frame they write with the host render of the same case, span method,
//! shading and strip/chunk layout: [`render::render`] for whole frames, and for the
//! Cortex-M0's strips and chunks [`host_chunked`], which draws as that image does.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use fixshade::effects::TwoSided;
use fixshade::render::{Frame, XfVertex};
use fixshade::scene::Scene;
use fixshade::specular::{BlinnExact, Specular};
use fixshade::target::{PixelFormat, Rgb565Le, Strip};
use fixshade_sim::render;
use fixshade_sim::render::bake::chunks;
use fixshade_sim::scene::convert::background_channels;
use fixshade_sim::scene::convert::{core_scene, FixedMesh};
use fixshade_sim::scene::desc::{FormatName, Named, SceneDesc, ShadingName, SpanName};
use fixshade_sim::scene::load::LoadedScene;
use fixshade_tests::catalogue::scene_cases;

/// The frame a board that keeps neither the frame nor a whole mesh in RAM draws:
/// strip by strip (`rows` rows each), and per strip object by object and chunk by
/// chunk (at most `limit` vertices, `fixshade bake --chunk`), each chunk with its own
/// vertex stage in a scene holding that object alone. Rgb565 little-endian bytes.
pub fn host_chunked(ls: &LoadedScene, limit: usize, rows: u32) -> Result<Vec<u8>, String> {
    let d = &ls.desc;
    if d.format != FormatName::RGB565LE {
        return Err(format!("{}: the scene images draw rgb565le only", ls.name));
    }
    if d.perspective_correct && d.shading == ShadingName::GOURAUD {
        return Err(format!(
            "{}: the strip-and-chunk scene images draw no perspective-correct frames",
            ls.name
        ));
    }
    let (w, h) = (d.width, d.height);
    let rows = rows.clamp(1, h);
    let mut parts: Vec<(usize, FixedMesh)> = Vec::new();
    for (i, m) in ls.fixed.iter().enumerate() {
        for c in chunks(m, Some(limit))? {
            parts.push((
                i,
                FixedMesh {
                    positions: c.positions,
                    normals: c.normals,
                    triangles: c.triangles,
                },
            ));
        }
    }
    let scenes = parts
        .iter()
        .map(|(i, m)| {
            let mut one = d.clone();
            one.objects = vec![d.objects[*i].clone()];
            core_scene(&one, std::slice::from_ref(m))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let bgc = background_channels(d.format, d.background);
    let bg = Rgb565Le::pack(bgc[0], bgc[1], bgc[2]);
    let mut out = Vec::with_capacity(w as usize * h as usize * 2);
    // Two-sided lighting keeps the back colours in a second half of the cache.
    let mut cache = vec![XfVertex::default(); if d.two_sided { 2 * limit } else { limit }];
    let mut color = vec![bg; w as usize * rows as usize];
    let mut depth = vec![0xFFFFu16; w as usize * rows as usize];
    let mut y0 = 0;
    while y0 < h {
        let hh = rows.min(h - y0);
        let n = (w * hh) as usize;
        let mut strip = Strip::<Rgb565Le>::new(
            &mut color[..n],
            d.depth_test.then_some(&mut depth[..n]),
            w,
            h,
            y0,
            hh,
        )
        .map_err(|e| e.to_string())?;
        strip.clear(bg);
        for scene in &scenes {
            if d.two_sided {
                draw_chunk::<TwoSided>(scene, d, &mut strip, &mut cache)?;
            } else {
                draw_chunk::<BlinnExact>(scene, d, &mut strip, &mut cache)?;
            }
        }
        out.extend(
            strip
                .color()
                .iter()
                .flat_map(|p| Rgb565Le::bytes(*p).into_iter().take(2)),
        );
        y0 += hh;
    }
    Ok(out)
}

/// The vertex stage of one chunk's `scene`, lit with `Sp`, drawn into `strip` with
/// the span method of `d`.
fn draw_chunk<Sp: Specular>(
    scene: &Scene<'_>,
    d: &SceneDesc,
    strip: &mut Strip<'_, Rgb565Le>,
    cache: &mut [XfVertex],
) -> Result<(), String> {
    let frame = Frame::<Rgb565Le>::prepare_with::<Sp>(scene, d.width, d.height, cache)
        .map_err(|e| e.to_string())?;
    fixshade_sim::with_span_method!(d.span, S => frame.draw::<S, _>(strip))
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// The boards whose scene images draw perspective-correct Gouraud frames (span
/// names `perspective-N`) for every case with a perspective camera.
const PERSPECTIVE_BOARDS: &[&str] = &["mps2-an386"];

/// The perspective spans those images draw.
const PERSPECTIVE_SPANS: &[&str] = &["perspective-1", "perspective-16"];

/// The banded frames those images draw (flat and Gouraud, `gradient`, bands of N
/// rows from one binning).
const BAND_SPANS: &[&str] = &[
    "gradient.bands-1",
    "gradient.bands-2",
    "gradient.bands-16",
    "gradient.bands-240",
];

/// `perspective-N` → `N`.
fn perspective_span(span: &str) -> Option<u32> {
    span.strip_prefix("perspective-")?.parse().ok()
}

/// One `SCENE` line.
#[derive(Clone)]
struct SceneRow {
    board: String,
    case: String,
    shading: String,
    span: String,
    width: u32,
    height: u32,
    rows: u32,
    chunk: usize,
    pixels: u64,
    instructions: u64,
}

impl SceneRow {
    fn parse(rest: &str) -> Option<SceneRow> {
        let f: Vec<&str> = rest.split_whitespace().collect();
        if f.len() != 13 {
            return None;
        }
        let n = |i: usize| f[i].parse::<u64>().ok();
        Some(SceneRow {
            board: f[0].into(),
            case: f[1].into(),
            shading: f[2].into(),
            span: f[3].into(),
            width: n(4)? as u32,
            height: n(5)? as u32,
            rows: n(6)? as u32,
            chunk: n(7)? as usize,
            pixels: n(10)?,
            instructions: n(11)? + n(12)?,
        })
    }
}

/// One case of one image: name, frames, shading modes, the `gradient` frame of the
/// first (Gouraud if drawn) and the first frame.
type PerCase = (String, usize, Vec<String>, Option<SceneRow>, SceneRow);

/// What [`check`] found on one image.
#[derive(Default)]
pub struct Checked {
    /// Frames compared.
    pub frames: usize,
    /// Mismatches, one line each.
    pub bad: Vec<String>,
    /// Markdown table rows, one per case of the image.
    pub rows: Vec<String>,
    /// Frames compared: (board, case, shading, span).
    pub seen: Vec<(String, String, String, String)>,
    /// Skipped cases: `board case why`.
    pub skipped: Vec<String>,
    /// Cases drawn: (board, case).
    pub drawn: Vec<(String, String)>,
    /// `STACK` lines.
    pub stack: Vec<String>,
    /// Strip-and-chunk frames whose host render differs from the host's whole-frame
    /// render of the same case (the MCU is compared with the former).
    pub layout_differs: Vec<String>,
}

/// Checks every `SCENE` frame of `log` against the host, deleting each frame's file
/// once compared.
pub fn check(log: &str, out_dir: &Path) -> Result<Checked, String> {
    let mut loaded: HashMap<String, LoadedScene> = HashMap::new();
    for c in scene_cases() {
        loaded.insert(c.name.clone(), c.load()?);
    }
    let mut out = Checked::default();
    // Per case: frames, the shading modes drawn, and the `gradient` frame of the
    // first of them (Gouraud on the boards that draw it).
    let mut per_case: Vec<PerCase> = Vec::new();
    for line in log.lines() {
        if let Some(rest) = line.strip_prefix("SCENESKIP ") {
            out.skipped.push(rest.to_string());
            continue;
        }
        if let Some(rest) = line.strip_prefix("STACK ") {
            out.stack.push(rest.to_string());
            continue;
        }
        let Some(rest) = line.strip_prefix("SCENE ") else {
            continue;
        };
        let r = SceneRow::parse(rest).ok_or_else(|| format!("bad line: {line}"))?;
        let mut ls = loaded
            .get(&r.case)
            .ok_or_else(|| format!("unknown scene case {}", r.case))?
            .clone();
        if (ls.desc.width, ls.desc.height) != (r.width, r.height) {
            return Err(format!(
                "{} {}: the image draws {}x{}, the catalogue {}x{}",
                r.board, r.case, r.width, r.height, ls.desc.width, ls.desc.height
            ));
        }
        ls.desc.shading = ShadingName::parse(&r.shading)?;
        // A banded frame (`span.bands-N`): the whole frame's bytes.
        let span = r
            .span
            .split_once(".bands-")
            .map_or(r.span.as_str(), |(s, _)| s);
        match perspective_span(span) {
            // `fixshade render --perspective on --perspective-span N` (coverage of
            // `gradient`, the scene's divider).
            Some(n) => {
                ls.desc.span = SpanName::GRADIENT;
                ls.desc.perspective_correct = true;
                ls.desc.perspective_span = n;
            }
            None => ls.desc.span = SpanName::parse(span)?,
        }
        let whole = render::render(&ls, None)?.bytes;
        let host = if r.chunk == 0 && r.rows == 0 {
            whole
        } else {
            let cut = host_chunked(&ls, r.chunk, r.rows)?;
            if cut != whole {
                out.layout_differs.push(format!(
                    "{} {} {} {}: strips of {} rows and chunks of {} vertices ({})",
                    r.board,
                    r.case,
                    r.shading,
                    r.span,
                    r.rows,
                    r.chunk,
                    crate::qemu::first_difference(&cut, &whole)
                ));
            }
            cut
        };
        let file = out_dir.join(format!("{}-{}-{}.rgb565", r.case, r.shading, r.span));
        let mcu = std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?;
        if mcu != host {
            out.bad.push(format!(
                "{} scene {} {} {} (strip rows {}, chunk {}): {} bytes on the MCU, {} on the host, {}",
                r.board,
                r.case,
                r.shading,
                r.span,
                r.rows,
                r.chunk,
                mcu.len(),
                host.len(),
                crate::qemu::first_difference(&mcu, &host)
            ));
        }
        let _ = std::fs::remove_file(&file);
        out.frames += 1;
        out.seen.push((
            r.board.clone(),
            r.case.clone(),
            r.shading.clone(),
            r.span.clone(),
        ));
        let grad = r.span == "gradient";
        match per_case.iter_mut().find(|p| p.0 == r.case) {
            Some(p) => {
                p.1 += 1;
                if !p.2.contains(&r.shading) {
                    p.2.push(r.shading.clone());
                }
                if grad && (p.3.is_none() || r.shading == "gouraud") {
                    p.3 = Some(r);
                }
            }
            None => per_case.push((
                r.case.clone(),
                1,
                vec![r.shading.clone()],
                grad.then(|| r.clone()),
                r,
            )),
        }
    }
    for (case, frames, shadings, gg, first) in &per_case {
        let strip = if first.rows == 0 {
            "whole".to_string()
        } else {
            first.rows.to_string()
        };
        let chunk = if first.chunk == 0 {
            "whole".to_string()
        } else {
            first.chunk.to_string()
        };
        let (gs, px, ins) = gg
            .as_ref()
            .map_or(("-".into(), "-".into(), "-".into()), |g| {
                (
                    g.shading.clone(),
                    g.pixels.to_string(),
                    g.instructions.to_string(),
                )
            });
        out.drawn.push((first.board.clone(), case.clone()));
        out.rows.push(format!(
            "| {} | {case} | {}×{} | {strip} | {chunk} | {} | {frames} | {gs} | {px} | {ins} |",
            first.board,
            first.width,
            first.height,
            shadings.join(", ")
        ));
    }
    Ok(out)
}

/// Checks that every board drew or named as skipped every catalogue case, over all
/// its images, and drew every case it drew with every span method in flat and
/// Gouraud shading; returns the scene section of docs/mcu-instructions.md.
pub fn finish(c: &Checked) -> Result<String, String> {
    let cases = scene_cases();
    let mut boards: Vec<&str> = c.drawn.iter().map(|(b, _)| b.as_str()).collect();
    boards.dedup();
    for board in &boards {
        for case in &cases {
            let drawn = c.drawn.iter().any(|(b, n)| b == board && *n == case.name);
            let skipped = c.skipped.iter().any(|s| {
                let f: Vec<&str> = s.split_whitespace().collect();
                f.first() == Some(board) && f.get(1) == Some(&case.name.as_str())
            });
            for shading in ["flat", "gouraud"] {
                for (_, span) in SpanName::ALL {
                    let have = c.seen.iter().any(|(b, n, sh, sp)| {
                        b == board && *n == case.name && sh == shading && sp == span
                    });
                    if drawn && !have {
                        return Err(format!(
                            "{board}: scene case {}: no {shading} frame with {span}",
                            case.name
                        ));
                    }
                }
            }
            let perspective_camera = drawn
                && PERSPECTIVE_BOARDS.contains(board)
                && matches!(
                    case.load()?.desc.camera.projection,
                    fixshade_sim::scene::desc::Projection::Perspective { .. }
                );
            for span in BAND_SPANS
                .iter()
                .filter(|_| drawn && PERSPECTIVE_BOARDS.contains(board))
            {
                for shading in ["flat", "gouraud"] {
                    let have = c.seen.iter().any(|(b, n, sh, sp)| {
                        b == board && *n == case.name && sh == shading && sp == span
                    });
                    if !have {
                        return Err(format!(
                            "{board}: scene case {}: no {shading} frame {span} (bands from one binning)",
                            case.name
                        ));
                    }
                }
            }
            for span in PERSPECTIVE_SPANS.iter().filter(|_| perspective_camera) {
                let have = c.seen.iter().any(|(b, n, sh, sp)| {
                    b == board && *n == case.name && sh == "gouraud" && sp == span
                });
                if !have {
                    return Err(format!(
                        "{board}: scene case {}: no perspective-correct Gouraud frame {span}",
                        case.name
                    ));
                }
            }
            if drawn == skipped {
                return Err(format!(
                    "{board}: scene case {}: {}",
                    case.name,
                    if drawn {
                        "both drawn and named as skipped"
                    } else {
                        "neither drawn nor named as skipped"
                    }
                ));
            }
        }
    }
    let mut md = table(c.frames, &c.rows, &c.skipped, &c.stack);
    if c.layout_differs.is_empty() {
        md.push_str(
            "\nEvery strip-and-chunk frame is also identical to the host's whole-frame render.\n",
        );
    } else {
        md.push_str(
            "\nStrip-and-chunk frames whose host render differs from the host's whole-frame\n\
             render (a property of the core, reproducible on the host alone):\n\n",
        );
        for l in &c.layout_differs {
            let _ = writeln!(md, "- {l}");
        }
    }
    Ok(md)
}

/// The scene section of docs/mcu-instructions.md.
fn table(frames: usize, rows: &[String], skipped: &[String], stack: &[String]) -> String {
    let mut md = format!(
        "\n## Whole-pipeline hard cases\n\n\
         Every case of tests/catalogue/scenes.toml (baked into boards/baked/scenes/ by\n\
         `cargo xtask bake`) rendered by the scene images with every span method in\n\
         flat and Gouraud shading (and on the Cortex-M4 once more in quadratic, Phong,\n\
         Phong even/odd and adaptive shading, whose fills ignore the span method; and for\n\
         the cases with a perspective camera in Gouraud shading with perspective-correct\n\
         colours, `Frame::draw_perspective` with `exact` at every pixel and per 16 pixels,\n\
         spans `perspective-1` and `perspective-16`; and on the Cortex-M4 in flat and\n\
         Gouraud shading with `gradient` in bands of 1, 2, 16 and 240 rows from one\n\
         binning, spans `gradient.bands-N`, compared with the whole frame) and compared byte for byte with the host render of the same case, method, shading and\n\
         layout: {frames} frames, all identical. The Cortex-M4 draws whole frames from whole\n\
         meshes (compared with `render::render`); the Cortex-M0 draws strips of `strip rows`\n\
         rows and meshes in chunks of at most `chunk` vertices (compared with the host\n\
         drawing the same strips and chunks; each Cortex-M0 image holds one shading mode and\n\
         half of the meshes, see boards/qemu-microbit/src/bin/scenes.rs). `pixels` and\n\
         `instructions` (vertex stage and draw, summed over strips and chunks) are those of\n\
         the `gradient` frame in the shading named.\n\n\
         | board | case | size | strip rows | chunk | shadings | frames | shading | pixels | instructions |\n\
         | --- | --- | --- | ---: | ---: | --- | ---: | --- | ---: | ---: |\n"
    );
    for r in rows {
        md.push_str(r);
        md.push('\n');
    }
    // Several images of a board may name the same case.
    let mut skipped = skipped.to_vec();
    skipped.sort();
    skipped.dedup();
    if !skipped.is_empty() {
        md.push_str("\nNot drawn:\n\n");
        for s in &skipped {
            let f: Vec<&str> = s.split_whitespace().collect();
            if let [board, name, why] = f.as_slice() {
                let why = match *why {
                    "ram" => "one row with its depth row does not fit the board's strip buffers",
                    "flash" => "its baked mesh does not fit the image's flash with the code",
                    "ram-two-sided" => {
                        "two-sided lighting's back colours double the vertex cache, more \
                         than the RAM the stack leaves"
                    }
                    "flash-depth32" => {
                        "the scene images carry the span methods for 16-bit depth cells \
                         only; the same code for 32-bit cells does not fit the flash beside them"
                    }
                    w => w,
                };
                let _ = writeln!(md, "- {board}: {name} ({why})");
            }
        }
    }
    if !stack.is_empty() {
        md.push_str(
            "\nPeak stack of the images that paint it (`STACK board scenes used room`, bytes;\n\
             an image whose stack reaches its statics fails):\n\n```text\n",
        );
        for s in stack {
            md.push_str(s);
            md.push('\n');
        }
        md.push_str("```\n");
    }
    md
}
