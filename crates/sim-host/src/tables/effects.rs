//! The effects table (`fixshade effects`, docs/effects.md) and `--explain`: what
//! each effect of a frame costs, measured by switching it the other way.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Duration;

use crate::image::compare::compare;
use crate::render;
use crate::scene::desc::{Named, ShadingName};
use crate::scene::effects::{apply, derive, everything_on, Effects, Lighting};
use crate::scene::load::{self, LoadedScene};

/// Median ratio `time(b) / time(a)` over `pairs` paired runs (each the median of
/// `runs` frames), a and b alternating so drift hits both alike.
pub fn paired_ratio(
    a: &LoadedScene,
    b: &LoadedScene,
    pairs: usize,
    runs: usize,
) -> Result<(f64, Duration), String> {
    let mut ratios = Vec::new();
    let mut ta = Vec::new();
    for _ in 0..pairs.max(1) {
        let x = render::time_frame(a, runs)?;
        let y = render::time_frame(b, runs)?;
        ratios.push(y.as_secs_f64() / x.as_secs_f64().max(1e-12));
        ta.push(x);
    }
    ratios.sort_by(f64::total_cmp);
    ta.sort();
    Ok((ratios[ratios.len() / 2], ta[ta.len() / 2]))
}

/// The cost of one effect: the chosen frame and the same frame with the effect
/// switched the other way.
#[derive(Clone, Debug)]
pub struct Cost {
    /// Effect name.
    pub name: &'static str,
    /// `1 − time(effect off) / time(chosen)`: the share of the frame the effect
    /// costs (negative: it saves time, as culling does).
    pub share: f64,
}

/// Measures the cost share of every effect that is on in `e` (paired runs).
pub fn costs(
    ls: &LoadedScene,
    e: &Effects,
    pairs: usize,
    runs: usize,
) -> Result<Vec<Cost>, String> {
    let chosen = apply(ls, e);
    let mut out = Vec::new();
    let mut measure = |name: &'static str, f: &dyn Fn(&mut Effects)| -> Result<(), String> {
        let mut off = e.clone();
        f(&mut off);
        let (r, _) = paired_ratio(&chosen, &apply(ls, &off), pairs, runs)?;
        out.push(Cost {
            name,
            share: 1.0 - r,
        });
        Ok(())
    };
    if e.depth.value {
        measure("depth test", &|x| x.depth.value = false)?;
    }
    if e.cull.value {
        measure("back-face culling", &|x| x.cull.value = false)?;
    }
    if e.lighting.value == Lighting::Specular {
        measure("specular term", &|x| x.lighting.value = Lighting::Diffuse)?;
    }
    if e.lighting.value != Lighting::Unlit {
        measure("lighting", &|x| {
            x.lighting.value = Lighting::Unlit;
            x.shading.value = ShadingName::FLAT;
        })?;
    }
    if matches!(
        e.shading.value,
        ShadingName::PHONG
            | ShadingName::PHONG_EVEN_ODD
            | ShadingName::QUADRATIC
            | ShadingName::ADAPTIVE
    ) {
        measure("per-pixel shading (vs gouraud)", &|x| {
            x.shading.value = ShadingName::GOURAUD
        })?;
    }
    if e.local_viewer.value {
        measure("local viewer", &|x| x.local_viewer.value = false)?;
    }
    if e.perspective.value {
        measure("perspective correction", &|x| x.perspective.value = false)?;
    }
    if e.two_sided.value {
        measure("two-sided lighting", &|x| x.two_sided.value = false)?;
    }
    Ok(out)
}

/// The `--explain` text: every effect, its value and its rule, then the measured
/// cost shares (when `costs` is given).
pub fn explain(name: &str, e: &Effects, costs: Option<&[Cost]>) -> String {
    let mut s = format!("effects of {name}:\n");
    let on = |b: bool| if b { "on" } else { "off" };
    let mut row = |what: &str, value: String, why: &str| {
        let _ = writeln!(s, "  {what:<21} {value:<17} {why}");
    };
    row("depth test", on(e.depth.value).into(), &e.depth.why);
    row("back-face culling", on(e.cull.value).into(), &e.cull.why);
    row("lighting", e.lighting.value.name().into(), &e.lighting.why);
    row(
        "lights",
        format!("{} dir, {} point", e.lights.value.0, e.lights.value.1),
        &e.lights.why,
    );
    row("shading", e.shading.value.name().into(), &e.shading.why);
    row(
        "local viewer",
        on(e.local_viewer.value).into(),
        &e.local_viewer.why,
    );
    row(
        "perspective correction",
        on(e.perspective.value).into(),
        &e.perspective.why,
    );
    row(
        "two-sided lighting",
        on(e.two_sided.value).into(),
        &e.two_sided.why,
    );
    if let Some(costs) = costs {
        let _ = writeln!(
            s,
            "cost share of the frame (1 - time with it off / time with it on, paired runs):"
        );
        for c in costs {
            let _ = writeln!(s, "  {:<32} {:>6.1} %", c.name, 100.0 * c.share);
        }
    }
    s.trim_end().to_string()
}

/// The scenes of the effects table, in `crates/sim-host/scenes/effects/`.
pub const TABLE_SCENES: &[&str] = &[
    "figures-diffuse",
    "figures-specular",
    "figures-phong",
    "figures-adaptive",
    "ground-plane",
    "ground-fine",
    "hud-gauge",
];

/// The scenes of the perspective-correction section: one large plane of two
/// triangles, and the same plane as a 32 × 32 grid; Gouraud, and Phong with a
/// specular point light.
pub const PERSPECTIVE_SCENES: &[&str] = &[
    "ground-plane",
    "ground-fine",
    "ground-plane-phong",
    "ground-fine-phong",
];

/// One configuration of the perspective-correction section.
#[derive(Clone, Debug)]
pub struct PerspectiveRow {
    /// What was drawn: `screen space (affine)`, `every pixel`, `16 pixels`, ...
    pub label: String,
    /// NMSE against the perspective-correct exact reference.
    pub nmse: f64,
    /// Largest 8-bit channel error against it.
    pub max_error: u8,
    /// Time / time of the affine frame (paired runs).
    pub ratio: f64,
}

/// A table scene drawn affinely and perspective-correctly with several
/// perspective spans (and one approximate divider), each compared with the
/// perspective-correct reference and timed against the affine frame.
pub fn perspective_rows(
    name: &str,
    pairs: usize,
    runs: usize,
) -> Result<Vec<PerspectiveRow>, String> {
    use crate::scene::desc::DivideName;
    let path = table_scene_path(name);
    let mut correct = load::load_arg(&path.display().to_string())?;
    correct.desc.perspective_correct = true;
    let reference = render::matching_reference(&correct);
    let mut affine = correct.clone();
    affine.desc.perspective_correct = false;
    let mut configs = vec![("screen space (affine)".to_string(), affine.clone())];
    for span in [1u32, 8, 16, 32] {
        let mut ls = correct.clone();
        ls.desc.perspective_span = span;
        let label = if span == 1 {
            "every pixel".to_string()
        } else {
            format!("every {span} pixels")
        };
        configs.push((label, ls));
    }
    let mut approx = correct.clone();
    approx.desc.perspective_span = 16;
    approx.desc.divide = DivideName::parse("shift-add-8")?;
    configs.push(("every 16 pixels, shift-add-8".to_string(), approx));
    let mut out = Vec::new();
    for (label, ls) in configs {
        let r = render::render(&ls, None)?;
        let c = compare(&reference, &r.image)?;
        let (ratio, _) = paired_ratio(&affine, &ls, pairs, runs)?;
        out.push(PerspectiveRow {
            label,
            nmse: c.nmse,
            max_error: c.max_channel_error,
            ratio,
        });
    }
    Ok(out)
}

/// Path of a table scene.
pub fn table_scene_path(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/effects")
        .join(format!("{name}.toml"))
}

/// One row of the effects table.
#[derive(Clone, Debug)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// The `--explain` text.
    pub explain: String,
    /// NMSE of the derived frame against the matching exact reference.
    pub nmse: f64,
    /// Median time of the derived frame.
    pub time: Duration,
    /// Time of the derived frame / time of the everything-on frame (paired runs).
    pub ratio: f64,
    /// Triangles lit per pixel and triangles drawn (adaptive scenes).
    pub adaptive: Option<(u32, u32)>,
}

/// Derives, renders, compares and times one scene.
pub fn table_row(name: &str, pairs: usize, runs: usize) -> Result<Row, String> {
    let path = table_scene_path(name);
    let scene = load::load_arg(&path.display().to_string())?;
    let e = derive(&scene)?;
    let ls = apply(&scene, &e);
    let r = render::render(&ls, None)?;
    let reference = render::matching_reference(&ls);
    let nmse = compare(&reference, &r.image)?.nmse;
    let (ratio_on, t_on) = paired_ratio(&everything_on(&scene), &ls, pairs, runs)?;
    let costs = costs(&scene, &e, pairs, runs)?;
    Ok(Row {
        scene: name.to_string(),
        explain: explain(name, &e, Some(&costs)),
        nmse,
        time: t_on.mul_f64(ratio_on),
        ratio: ratio_on,
        adaptive: (ls.desc.shading == ShadingName::ADAPTIVE)
            .then_some((r.stats.per_pixel, r.stats.triangles - r.stats.skipped())),
    })
}

/// Adaptive against full Phong on one built-in figure: NMSE of the adaptive frame
/// against the fixed-point Phong frame and against the exact reference, the
/// triangles that paid, and time(adaptive) / time(Phong) in paired runs.
pub fn adaptive_row(
    figure: &str,
    pairs: usize,
    runs: usize,
) -> Result<(f64, f64, u32, u32, f64), String> {
    let mut phong = load::load_arg(figure)?;
    phong.desc.shading = ShadingName::PHONG;
    let mut adaptive = phong.clone();
    adaptive.desc.shading = ShadingName::ADAPTIVE;
    let rp = render::render(&phong, None)?;
    let ra = render::render(&adaptive, None)?;
    let vs_phong = compare(&rp.image, &ra.image)?.nmse;
    let vs_ref = compare(&render::matching_reference(&adaptive), &ra.image)?.nmse;
    let (ratio, _) = paired_ratio(&phong, &adaptive, pairs, runs)?;
    Ok((
        vs_phong,
        vs_ref,
        ra.stats.per_pixel,
        ra.stats.triangles - ra.stats.skipped(),
        ratio,
    ))
}

/// `fixshade effects`: writes the effects table (markdown) to `out` (`None`:
/// docs/effects.md, or out/effects-quick.md with `quick`); returns what to print.
pub fn write_table(out: Option<&Path>, quick: bool) -> Result<String, String> {
    let out = out.map(Path::to_path_buf).unwrap_or_else(|| {
        if quick {
            "out/effects-quick.md".into()
        } else {
            "docs/effects.md".into()
        }
    });
    let (pairs, runs) = if quick { (3, 1) } else { (7, 5) };
    let md = table_markdown(pairs, runs, quick)?;
    if let Some(dir) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    std::fs::write(&out, &md).map_err(|e| format!("cannot write {}: {e}", out.display()))?;
    Ok(format!("wrote {}", out.display()))
}

fn table_markdown(pairs: usize, runs: usize, quick: bool) -> Result<String, String> {
    let mut m = String::new();
    let cmd = if quick {
        "fixshade effects --quick"
    } else {
        "cargo run --release -p fixshade-sim -- effects"
    };
    let _ = writeln!(m, "# Effects: what each scene pays for\n");
    let _ = writeln!(m, "{}\n", crate::tables::provenance::made_line(cmd));
    let _ = writeln!(
        m,
        "Generated by `{cmd}` ({pairs} paired runs of {runs} frames per ratio; \
         times are host wall time and vary by machine, the ratios less so).\n"
    );
    let _ = writeln!(m, "{}", INTRO.trim_end());
    let _ = writeln!(m, "\n## The table\n");
    let _ = writeln!(
        m,
        "NMSE is against the matching exact (f64) reference of the frame as derived \
         (Phong for Phong and adaptive shading); time is relative to the same scene \
         with every effect on (depth test, the exact specular term, Phong shading).\n"
    );
    let _ = writeln!(m, "| scene | NMSE vs exact reference | time per frame | vs everything on | per-pixel polygons |");
    let _ = writeln!(m, "| --- | --- | --- | --- | --- |");
    let mut rows = Vec::new();
    for name in TABLE_SCENES {
        let r = table_row(name, pairs, runs)?;
        let _ = writeln!(
            m,
            "| `{}` | {:.2e} | {:.3} ms | {:.2} | {} |",
            r.scene,
            r.nmse,
            r.time.as_secs_f64() * 1e3,
            r.ratio,
            r.adaptive
                .map(|(x, y)| format!("{x} of {y}"))
                .unwrap_or_else(|| "—".into())
        );
        rows.push(r);
    }
    let _ = writeln!(m, "\n## `--explain` output\n");
    for r in &rows {
        let _ = writeln!(
            m,
            "`fixshade render crates/sim-host/scenes/effects/{}.toml --explain`:\n\n```text\n{}\n```\n",
            r.scene, r.explain
        );
    }
    let _ = writeln!(m, "## Perspective correction\n");
    let _ = writeln!(
        m,
        "Gouraud colours and Phong normals and eye positions interpolated in screen \
         space (the seeds' methods) against perspective-correct ones \
         (`perspective_correct = true`, `--perspective on`): the screen-affine \
         weights `b_i` become `(b_i/w_i) / Σ b_j/w_j`, three planes per triangle and \
         one reciprocal wherever the attributes are sampled, every pixel or every \
         `perspective_span` pixels with linear interpolation between \
         (`fixshade::raster::perspective`; Phong then renormalises and lights every \
         pixel, adaptive shading corrects both kinds of triangle, the quadratic \
         surface stays in screen space). Depth needs no correction (the buffer \
         holds the projection's z/w, which is affine in screen space). NMSE and \
         the largest 8-bit channel error are against the perspective-correct f64 \
         reference of the same scene; time is relative to the screen-space frame \
         (paired runs).\n"
    );
    for name in PERSPECTIVE_SCENES {
        let what = match *name {
            "ground-plane" => "Gouraud, two large triangles",
            "ground-fine" => "Gouraud, the same plane as 2 048 small triangles",
            "ground-plane-phong" => "Phong, a specular point light, two large triangles",
            _ => "Phong, the same plane as 2 048 small triangles",
        };
        let _ = writeln!(m, "`{name}` ({what}):\n");
        let _ = writeln!(
            m,
            "| interpolation | NMSE | max error | time vs screen space |"
        );
        let _ = writeln!(m, "| --- | --- | --- | --- |");
        for r in perspective_rows(name, pairs, runs)? {
            let _ = writeln!(
                m,
                "| {} | {:.2e} | {} | {:.2} |",
                r.label, r.nmse, r.max_error, r.ratio
            );
        }
        let _ = writeln!(m);
    }
    let _ = writeln!(m, "## Adaptive shading against full Phong\n");
    let _ = writeln!(
        m,
        "The built-in figures with `--shading adaptive` and with `--shading phong` \
         (fixed-point, exact specular). Acceptance: NMSE against full Phong ≤ 1e-4.\n"
    );
    let _ = writeln!(m, "| figure | NMSE vs fixed-point Phong | NMSE vs exact Phong reference | per-pixel polygons | time adaptive / Phong |");
    let _ = writeln!(m, "| --- | --- | --- | --- | --- |");
    for fig in ["sphere", "teapot", "robot"] {
        // Three times the pairs: the ratio is this table's acceptance figure.
        let (vp, vr, x, y, ratio) = adaptive_row(fig, 3 * pairs, runs)?;
        let _ = writeln!(
            m,
            "| {fig} | {vp:.2e} | {vr:.2e} | {x} of {y} | {ratio:.2} |"
        );
    }
    // The firmware comparison is made by boards/effects-size/compare.sh (it needs the
    // thumbv7em target); its last output is included as committed.
    let fw =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../boards/effects-size/size.md");
    if let Ok(text) = std::fs::read_to_string(&fw) {
        let _ = writeln!(m, "\n{}", text.trim_end());
    }
    Ok(m)
}

const INTRO: &str = "\
`fixshade render SCENE` derives the effects a scene calls for from its content, by \
named rules, and runs the pipeline monomorphised for that combination: the depth \
mode, the shading mode and the lighting model (with or without the specular term, \
one- or two-sided) are type parameters of the core's `Frame`, so the inner loops contain only the \
chosen work (`fixshade::effects` lists the types a firmware names to pick a \
combination at compile time). `--explain` prints each effect, the rule that chose \
it, and its measured share of the frame time; `--effects -depth,+specular` (or \
`[render] effects = \"...\"` in a scene file) forces effects on or off.

Rules (`crates/sim-host/src/scene/effects.rs`, `derive`); each switches off only work \
whose result the scene cannot show, so a derived frame has the pixels of the frame \
as written (tested in `tests/tests/effects.rs`):

| effect | rule | result |
| --- | --- | --- |
| lighting | no `[[light]]` | unlit (emission + global ambient·k_a) |
| lighting | k_s = 0 on every material, or no light with a specular colour | diffuse only: `NoSpecular` (the host skips the same code at run time), no specular code in the vertex stage or per-pixel lighting |
| shading | unlit | flat (the colour is constant per object) |
| shading | adaptive without a specular term | Gouraud (no triangle can hold a highlight) |
| local viewer | no specular term | off (the viewer direction only enters the half vector) |
| depth test | one convex mesh with back-face culling | off (front faces of a convex surface never overlap) |
| depth test, culling | otherwise | as the scene file sets them |
| perspective correction | orthographic camera | off (screen-space interpolation is exact) |
| perspective correction | perspective camera | as the scene sets `perspective_correct` (default off: the seeds' screen-space interpolation); on: Gouraud colours, Phong normals and eye positions (adaptive: both) through one reciprocal per `perspective_span` pixels |
| perspective correction | flat, quadratic or ray-cast shading, sampled Phong | off (flat and ray casting have nothing to correct; the quadratic surface and the segment sampler interpolate in screen space) |
| two-sided lighting | the scene leaves out `two_sided = true` (in `[lighting]`) | off: one-sided lighting, no back colours |
| two-sided lighting | back faces culled (`cull = \"back\"`) | off (no back face is drawn to show it) |
| two-sided lighting | unlit and no `[object.back_material]` | off (both sides have the same colour) |
| two-sided lighting | otherwise | on: `fixshade::effects::TwoSided` (the host selects it at run time), the vertex stage also lights each needed vertex with its normal negated and the back material (the second half of the vertex cache), and back faces take those colours (flat, Gouraud, perspective-correct Gouraud) or light per pixel with the interpolated normal negated (Phong, and the quadratic surface's midpoints); adaptive shading and ray casting do not support it and report an error |

Forced settings (`+NAME`/`-NAME`, NAME: `depth`, `cull`, `specular`, `lighting`, \
`local-viewer`, `perspective`) win over the rules; `-specular` drops the highlights, \
`-lighting` draws unlit, `+perspective` corrects Gouraud colours and Phong normals.

Adaptive shading bounds the specular term over each triangle \
(`LightingSetup::specular_bound`: the vertex normals in a cone around their \
normalised sum, the directions to a point light or a local viewer in cones around \
theirs, `N·H ≤ (max N·L + max N·V) / sqrt(2 + 2 min L·V)`, the model's value at \
that bound) and lights a triangle per pixel when it reaches half a step of the \
target's finest channel, so no highlight is lost. It also bounds how far Gouraud's \
ambient and diffuse light can be from the per-pixel one \
(`LightingSetup::diffuse_bound`: the shorter interpolated normal, a directional \
light's terminator crossing the triangle by how far its vertices lie behind it, a \
point light's varying direction and attenuation) and lights \
per pixel where that bound reaches 8 steps (the bound is loose: with a limit of half \
a step, the first design, most triangles paid and adaptive cost more than Phong on \
the teapot and the robot; without it the teapot's NMSE against Phong was 1.4e-4). \
The other triangles take the Gouraud colours of the vertex stage. Triangles that go \
through the clipper, and triangles of fewer than 4 pixels (where the bounds cost more \
than Phong's pixels), are always lit per pixel.
";
