//! Effects: what a scene calls for, derived from its content by named rules,
//! overridable in the scene file (`[render] effects = "-depth,+specular"`) and on the
//! command line (`--effects LIST`), and applied so that a frame pays for the effects
//! it uses and nothing else.
//!
//! The rules ([`derive()`]) only switch off work whose result the scene cannot show,
//! so a derived frame has the pixels of the frame the scene file describes (the
//! tests check this); a forced setting may change the pixels (`-specular` drops the
//! highlights). The run-time choice becomes a type of the core's pipeline: depth test
//! [`fixshade::raster::span::DepthTest`] or `NoDepth`, lighting with a specular model
//! or [`fixshade::effects::NoSpecular`], the shading mode; see
//! [`crate::pipeline::specular_pipeline`].

use std::fmt::Write as _;
use std::time::Duration;

use crate::desc::{LightKind, MeshData, Named, Projection, SceneDesc, ShadingName};
use crate::pipeline::{self, LoadedScene};

/// How much lighting a frame computes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Lighting {
    /// No lights: every colour is emission + global ambient · k_a.
    Unlit,
    /// Ambient and diffuse terms, no specular term.
    Diffuse,
    /// Ambient, diffuse and specular terms.
    Specular,
}

impl Lighting {
    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Lighting::Unlit => "none",
            Lighting::Diffuse => "diffuse",
            Lighting::Specular => "diffuse+specular",
        }
    }
}

/// An effect that `--effects` and the scene file's `effects` key can force.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Effect {
    /// The depth test.
    Depth,
    /// Back-face culling.
    Cull,
    /// The specular term.
    Specular,
    /// Lighting at all (`-lighting`: unlit).
    Lighting,
    /// The local viewer.
    LocalViewer,
    /// Perspective-correct interpolation of Gouraud colours and Phong normals.
    Perspective,
}

impl Named for Effect {
    const WHAT: &'static str = "effect";
    const ALL: &'static [(Self, &'static str)] = &[
        (Effect::Depth, "depth"),
        (Effect::Cull, "cull"),
        (Effect::Specular, "specular"),
        (Effect::Lighting, "lighting"),
        (Effect::LocalViewer, "local-viewer"),
        (Effect::Perspective, "perspective"),
    ];
}

/// Where a forced setting comes from.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// The scene file's `[render] effects` key.
    SceneFile,
    /// `--effects` on the command line.
    CommandLine,
}

impl Source {
    fn why(self) -> &'static str {
        match self {
            Source::SceneFile => "forced by the scene file (effects = ...)",
            Source::CommandLine => "forced by --effects",
        }
    }
}

/// Forced settings, in order (a later one wins).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Overrides(pub Vec<(Effect, bool, Source)>);

impl Overrides {
    /// Parses `+name,-name,...` (a bare `name` means `+name`). The error is one
    /// sentence naming the bad item and the valid names.
    pub fn parse(list: &str, source: Source) -> Result<Overrides, String> {
        let mut out = Vec::new();
        for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (on, name) = match item.as_bytes()[0] {
                b'+' => (true, &item[1..]),
                b'-' => (false, &item[1..]),
                _ => (true, item),
            };
            let effect = Effect::parse(name.trim()).map_err(|e| {
                format!("effects: `{item}`: {e} (each item is +NAME or -NAME, comma-separated)")
            })?;
            out.push((effect, on, source));
        }
        Ok(Overrides(out))
    }

    /// The last forced value of `e`, with its source.
    pub fn get(&self, e: Effect) -> Option<(bool, Source)> {
        self.0
            .iter()
            .rev()
            .find(|(x, _, _)| *x == e)
            .map(|(_, on, s)| (*on, *s))
    }

    /// Appends `other` (its settings win).
    pub fn extend(&mut self, other: &Overrides) {
        self.0.extend(other.0.iter().copied());
    }
}

/// One chosen setting and the rule that chose it.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting<T> {
    /// The value.
    pub value: T,
    /// The rule, in words.
    pub why: String,
}

fn set<T>(value: T, why: impl Into<String>) -> Setting<T> {
    Setting {
        value,
        why: why.into(),
    }
}

/// The effects of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Effects {
    /// Depth test.
    pub depth: Setting<bool>,
    /// Back-face culling.
    pub cull: Setting<bool>,
    /// Lighting.
    pub lighting: Setting<Lighting>,
    /// Shading mode.
    pub shading: Setting<ShadingName>,
    /// Directional and point lights in use.
    pub lights: Setting<(usize, usize)>,
    /// Local viewer.
    pub local_viewer: Setting<bool>,
    /// Perspective-correct interpolation of Gouraud colours and Phong normals.
    pub perspective: Setting<bool>,
}

fn nonzero(c: &[f64; 3]) -> bool {
    c.iter().any(|v| *v > 0.0)
}

/// True if some light and some material both have a specular colour, so the
/// specular term can light a pixel.
pub fn has_specular(d: &SceneDesc) -> bool {
    d.lights.iter().any(|l| nonzero(&l.specular))
        && d.objects.iter().any(|o| nonzero(&o.material.specular))
}

/// True if every triangle of `m` has every vertex on or behind its plane (within
/// 1e-6 of the mesh's size, and at least four Q16.16 units): a convex surface, whose front faces never overlap on
/// screen from any viewpoint.
pub fn is_convex(m: &MeshData) -> bool {
    let size = m
        .positions
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(1e-12);
    // The meshes are quantised to Q16.16: a flat pair of triangles may bend by a
    // few units of 2^-16, which is not a concavity.
    let eps = (1e-6 * size).max(4.0 / 65536.0);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        let (u, v) = (sub(b, a), sub(c, a));
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if len == 0.0 {
            continue;
        }
        for p in &m.positions {
            let d = sub(*p, a);
            if (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]) / len > eps {
                return false;
            }
        }
    }
    true
}

/// Derives the effects of `ls` by the rules, then applies the overrides of
/// `ls.desc.effects` (scene file and command line). Errors for an override that
/// cannot be honoured (`+lighting` or `+specular` without lights).
pub fn derive(ls: &LoadedScene) -> Result<Effects, String> {
    let d = &ls.desc;
    let forced = |e: Effect| d.effects.get(e);

    // Lighting.
    let mut lighting = if d.lights.is_empty() {
        set(
            Lighting::Unlit,
            "no lights: every colour is emission + global ambient·k_a",
        )
    } else if has_specular(d) {
        set(
            Lighting::Specular,
            "a light and a material both have a specular colour",
        )
    } else if !d.lights.iter().any(|l| nonzero(&l.specular)) {
        set(Lighting::Diffuse, "no light has a specular colour")
    } else {
        set(Lighting::Diffuse, "k_s = 0 on every material")
    };
    if let Some((on, src)) = forced(Effect::Lighting) {
        if on && d.lights.is_empty() {
            return Err("effects: +lighting: the scene has no lights".into());
        }
        if !on {
            lighting = set(Lighting::Unlit, src.why());
        }
    }
    if let Some((on, src)) = forced(Effect::Specular) {
        if on && d.lights.is_empty() {
            return Err("effects: +specular: the scene has no lights".into());
        }
        if on {
            lighting = set(Lighting::Specular, src.why());
        } else if lighting.value == Lighting::Specular {
            lighting = set(Lighting::Diffuse, src.why());
        }
    }

    // Shading.
    let shading = match (lighting.value, d.shading) {
        (_, ShadingName::Raycast) => set(d.shading, "as set (the ray caster has its own pipeline)"),
        (Lighting::Unlit, s) if s != ShadingName::Flat => set(
            ShadingName::Flat,
            "unlit: the colour is constant over each object",
        ),
        (Lighting::Diffuse, ShadingName::Adaptive) => set(
            ShadingName::Gouraud,
            "adaptive without a specular term: no triangle can hold a highlight",
        ),
        (_, s) => set(s, "as set by the scene file or --shading"),
    };

    // Lights.
    let lights = if lighting.value == Lighting::Unlit {
        set((0, 0), "unlit")
    } else {
        let dir = d
            .lights
            .iter()
            .filter(|l| matches!(l.kind, LightKind::Directional { .. }))
            .count();
        set((dir, d.lights.len() - dir), "the scene's [[light]] tables")
    };

    // Local viewer.
    let mut local_viewer = if !d.local_viewer {
        set(
            false,
            "the scene sets local_viewer = false (or leaves it out)",
        )
    } else if lighting.value != Lighting::Specular {
        set(
            false,
            "no specular term: the direction to the viewer is unused",
        )
    } else {
        set(true, "the scene sets local_viewer = true")
    };
    if let Some((on, src)) = forced(Effect::LocalViewer) {
        local_viewer = set(on, src.why());
    }

    // Culling.
    let mut cull = set(
        d.cull_back,
        if d.cull_back {
            "the scene sets cull = \"back\" (or leaves it out)"
        } else {
            "the scene sets cull = \"none\""
        },
    );
    if let Some((on, src)) = forced(Effect::Cull) {
        cull = set(on, src.why());
    }

    // Depth test.
    let mut depth = if !d.depth_test {
        set(false, "the scene sets depth_test = false")
    } else if !cull.value {
        set(
            true,
            "back faces are drawn (no culling): surfaces may overlap",
        )
    } else if ls.meshes.len() != 1 {
        set(true, "several objects may overlap")
    } else if !is_convex(&ls.meshes[0]) {
        set(true, "the mesh is not convex: its front faces may overlap")
    } else {
        set(
            false,
            "one convex mesh with back-face culling: front faces never overlap",
        )
    };
    if let Some((on, src)) = forced(Effect::Depth) {
        depth = set(on, src.why());
    }

    // Perspective correction.
    let mut perspective = match d.camera.projection {
        Projection::Orthographic { .. } => set(
            false,
            "orthographic camera: screen-space interpolation is exact",
        ),
        Projection::Perspective { .. } if d.perspective_correct => set(
            true,
            "asked for by the scene (perspective_correct = true)",
        ),
        Projection::Perspective { .. } => set(
            false,
            "the scene interpolates in screen space (perspective_correct = false, the seeds' Gouraud)",
        ),
    };
    if let Some((on, src)) = forced(Effect::Perspective) {
        perspective = set(on, src.why());
    }
    // Gouraud colours and Phong normals and positions are corrected.
    let corrected = match shading.value {
        ShadingName::Gouraud | ShadingName::PhongEvenOdd | ShadingName::Adaptive => Ok(()),
        ShadingName::Phong if !d.raycast.sampled => Ok(()),
        ShadingName::Phong => Err(
            "sampled Phong lighting (the segment sampler): its attributes interpolate in \
             screen space",
        ),
        ShadingName::Flat => Err("flat shading: one colour per triangle, nothing to correct"),
        ShadingName::Quadratic => {
            Err("the quadratic surface interpolates in screen space (not corrected)")
        }
        ShadingName::Raycast => Err("ray casting: each pixel is cast, nothing to correct"),
    };
    if let (true, Err(why)) = (perspective.value, corrected) {
        perspective = set(false, why);
    }

    Ok(Effects {
        depth,
        cull,
        lighting,
        shading,
        lights,
        local_viewer,
        perspective,
    })
}

/// `ls` with its description set to the effects `e`: depth test, culling, shading,
/// local viewer; unlit drops the lights; diffuse zeroes every specular colour (so
/// the pipeline runs without the specular term); `+specular` is kept in the
/// overrides so [`crate::pipeline::specular_pipeline`] runs the specular term even
/// when nothing in the scene has one.
pub fn apply(ls: &LoadedScene, e: &Effects) -> LoadedScene {
    let mut out = ls.clone();
    let d = &mut out.desc;
    d.depth_test = e.depth.value;
    d.cull_back = e.cull.value;
    d.shading = e.shading.value;
    d.local_viewer = e.local_viewer.value;
    d.perspective_correct = e.perspective.value;
    match e.lighting.value {
        Lighting::Unlit => d.lights.clear(),
        Lighting::Diffuse => {
            for l in &mut d.lights {
                l.specular = [0.0; 3];
            }
            for o in &mut d.objects {
                o.material.specular = [0.0; 3];
            }
        }
        Lighting::Specular => {}
    }
    let mut keep = Overrides::default();
    if e.lighting.value == Lighting::Specular {
        keep.0.push((Effect::Specular, true, Source::CommandLine));
    }
    d.effects = keep;
    out
}

/// The scene with every effect on: depth test, the specular term with the exact
/// model, Phong shading; culling, lights and local viewer as the scene sets.
pub fn everything_on(ls: &LoadedScene) -> LoadedScene {
    let mut out = ls.clone();
    let d = &mut out.desc;
    d.depth_test = true;
    d.shading = ShadingName::Phong;
    d.specular = crate::desc::SpecularName::Exact;
    d.effects = Overrides(vec![(Effect::Specular, true, Source::CommandLine)]);
    out
}

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
        let x = pipeline::time_frame(a, runs)?;
        let y = pipeline::time_frame(b, runs)?;
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
            x.shading.value = ShadingName::Flat;
        })?;
    }
    if matches!(
        e.shading.value,
        ShadingName::Phong
            | ShadingName::PhongEvenOdd
            | ShadingName::Quadratic
            | ShadingName::Adaptive
    ) {
        measure("per-pixel shading (vs gouraud)", &|x| {
            x.shading.value = ShadingName::Gouraud
        })?;
    }
    if e.local_viewer.value {
        measure("local viewer", &|x| x.local_viewer.value = false)?;
    }
    if e.perspective.value {
        measure("perspective correction", &|x| x.perspective.value = false)?;
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
    use crate::desc::DivideName;
    let path = table_scene_path(name);
    let mut correct = pipeline::load_arg(&path.display().to_string())?;
    correct.desc.perspective_correct = true;
    let reference = pipeline::matching_reference(&correct);
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
        let r = pipeline::render(&ls, None)?;
        let c = crate::compare::compare(&reference, &r.image)?;
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
    let scene = pipeline::load_arg(&path.display().to_string())?;
    let e = derive(&scene)?;
    let ls = apply(&scene, &e);
    let r = pipeline::render(&ls, None)?;
    let reference = pipeline::matching_reference(&ls);
    let nmse = crate::compare::compare(&reference, &r.image)?.nmse;
    let (ratio_on, t_on) = paired_ratio(&everything_on(&scene), &ls, pairs, runs)?;
    let costs = costs(&scene, &e, pairs, runs)?;
    Ok(Row {
        scene: name.to_string(),
        explain: explain(name, &e, Some(&costs)),
        nmse,
        time: t_on.mul_f64(ratio_on),
        ratio: ratio_on,
        adaptive: (ls.desc.shading == ShadingName::Adaptive)
            .then_some((r.stats.per_pixel, r.stats.triangles - r.stats.culled)),
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
    let mut phong = pipeline::load_arg(figure)?;
    phong.desc.shading = ShadingName::Phong;
    let mut adaptive = phong.clone();
    adaptive.desc.shading = ShadingName::Adaptive;
    let rp = pipeline::render(&phong, None)?;
    let ra = pipeline::render(&adaptive, None)?;
    let vs_phong = crate::compare::compare(&rp.image, &ra.image)?.nmse;
    let vs_ref = crate::compare::compare(&pipeline::matching_reference(&adaptive), &ra.image)?.nmse;
    let (ratio, _) = paired_ratio(&phong, &adaptive, pairs, runs)?;
    Ok((
        vs_phong,
        vs_ref,
        ra.stats.per_pixel,
        ra.stats.triangles - ra.stats.culled,
        ratio,
    ))
}

/// `fixshade effects [--out FILE] [--quick]`: writes the effects table (markdown).
pub fn run_cli(args: &[String]) -> Result<String, crate::cli::CliError> {
    let mut quick = false;
    let mut out = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--quick" => quick = true,
            "--out" => {
                out =
                    Some(std::path::PathBuf::from(it.next().ok_or_else(|| {
                        crate::cli::usage("option --out needs a value")
                    })?))
            }
            other => {
                return Err(crate::cli::usage(format!(
                    "unexpected `{other}` here; effects takes: --out FILE, --quick"
                )))
            }
        }
    }
    let out = out.unwrap_or_else(|| {
        if quick {
            "out/effects-quick.md".into()
        } else {
            "docs/effects.md".into()
        }
    });
    let (pairs, runs) = if quick { (3, 1) } else { (7, 5) };
    let md = table_markdown(pairs, runs, quick).map_err(crate::cli::fail)?;
    if let Some(dir) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| crate::cli::fail(format!("cannot create {}: {e}", dir.display())))?;
    }
    std::fs::write(&out, &md)
        .map_err(|e| crate::cli::fail(format!("cannot write {}: {e}", out.display())))?;
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
mode, the shading mode and the lighting model (with or without the specular term) \
are type parameters of the core's `Frame`, so the inner loops contain only the \
chosen work (`fixshade::effects` lists the types a firmware names to pick a \
combination at compile time). `--explain` prints each effect, the rule that chose \
it, and its measured share of the frame time; `--effects -depth,+specular` (or \
`[render] effects = \"...\"` in a scene file) forces effects on or off.

Rules (`crates/sim-host/src/effects.rs`, `derive`); each switches off only work \
whose result the scene cannot show, so a derived frame has the pixels of the frame \
as written (tested in `tests/tests/effects.rs`):

| effect | rule | result |
| --- | --- | --- |
| lighting | no `[[light]]` | unlit (emission + global ambient·k_a) |
| lighting | k_s = 0 on every material, or no light with a specular colour | diffuse only: `NoSpecular`, no specular code in the vertex stage or per-pixel lighting |
| shading | unlit | flat (the colour is constant per object) |
| shading | adaptive without a specular term | Gouraud (no triangle can hold a highlight) |
| local viewer | no specular term | off (the viewer direction only enters the half vector) |
| depth test | one convex mesh with back-face culling | off (front faces of a convex surface never overlap) |
| depth test, culling | otherwise | as the scene file sets them |
| perspective correction | orthographic camera | off (screen-space interpolation is exact) |
| perspective correction | perspective camera | as the scene sets `perspective_correct` (default off: the seeds' screen-space interpolation); on: Gouraud colours, Phong normals and eye positions (adaptive: both) through one reciprocal per `perspective_span` pixels |
| perspective correction | flat, quadratic or ray-cast shading, sampled Phong | off (flat and ray casting have nothing to correct; the quadratic surface and the segment sampler interpolate in screen space) |

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
