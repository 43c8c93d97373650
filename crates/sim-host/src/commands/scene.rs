//! `fixshade render`, `reference` and `compare`: a scene (file or built-in) with the
//! command line's overrides, rendered by the core or by the f64 reference, and two
//! images compared.

use std::path::{Path, PathBuf};

use super::{fail, usage, CliError};
use crate::image::compare::compare;
use crate::image::Image;
use crate::render;
use crate::scene::desc::{
    DivideName, FormatName, Named, Overrides, ShadingName, Source, SpanName, SpecularName,
    MAX_SEGMENT, MAX_THRESHOLD,
};
use crate::scene::effects;
use crate::scene::load::{self, LoadedScene};
use crate::tables;
use fixshade::render::Stats;

/// A scene and the settings the command line overrides in it.
#[derive(Clone, Debug, Default, clap::Args)]
pub struct SceneOptions {
    /// A scene file (TOML, see docs/scene-files.md) or a built-in scene: sphere,
    /// teapot, robot, bench-sphere, spheres-plane.
    #[arg(value_name = "SCENE")]
    pub scene: String,
    /// Span method (`fixshade list` names them).
    #[arg(long, value_name = "METHOD", value_parser = SpanName::parse)]
    pub span: Option<SpanName>,
    /// Shading mode.
    #[arg(long, value_name = "MODE", value_parser = ShadingName::parse)]
    pub shading: Option<ShadingName>,
    /// Pixel format.
    #[arg(long, value_name = "FMT", value_parser = FormatName::parse)]
    pub format: Option<FormatName>,
    /// Specular model.
    #[arg(long, value_name = "MODEL", value_parser = SpecularName::parse)]
    pub specular: Option<SpecularName>,
    /// Divider of the classic span, the setup reciprocal and Schlick's denominator.
    #[arg(long, value_name = "DIV", value_parser = DivideName::parse)]
    pub divide: Option<DivideName>,
    /// Perspective-correct Gouraud colours and Phong normals and positions
    /// (adaptive: both).
    #[arg(long, value_name = "on|off", value_parser = on_off)]
    pub perspective: Option<bool>,
    /// Pixels per perspective division: 1, 2, 4, 8, 16, 32 or 64.
    #[arg(long, value_name = "N", value_parser = perspective_span)]
    pub perspective_span: Option<u32>,
    /// Effects forced on or off, comma-separated: +NAME or -NAME with NAME one of
    /// depth, cull, specular, lighting, local-viewer, perspective.
    #[arg(long, value_name = "LIST", allow_hyphen_values = true, value_parser = effects_list)]
    pub effects: Option<Overrides>,
    /// Ray casting and sampled Phong: segment length L in pixels.
    #[arg(long, value_name = "L", value_parser = segment)]
    pub segment: Option<u32>,
    /// Ray casting and sampled Phong: threshold K in 8-bit levels.
    #[arg(long, value_name = "K", value_parser = threshold)]
    pub threshold: Option<f64>,
}

fn on_off(v: &str) -> Result<bool, String> {
    match v {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("--perspective takes on or off, found `{v}`")),
    }
}

fn perspective_span(v: &str) -> Result<u32, String> {
    v.parse::<u32>()
        .ok()
        .filter(|n| n.is_power_of_two() && *n <= 64)
        .ok_or_else(|| {
            format!("--perspective-span takes 1, 2, 4, 8, 16, 32 or 64 pixels, found `{v}`")
        })
}

fn effects_list(v: &str) -> Result<Overrides, String> {
    Overrides::parse(v, Source::CommandLine)
}

fn segment(v: &str) -> Result<u32, String> {
    v.parse::<u32>()
        .ok()
        .filter(|n| (1..=MAX_SEGMENT).contains(n))
        .ok_or_else(|| format!("--segment takes a length 1..={MAX_SEGMENT}, found `{v}`"))
}

fn threshold(v: &str) -> Result<f64, String> {
    v.parse::<f64>()
        .ok()
        .filter(|k| (0.0..=MAX_THRESHOLD).contains(k))
        .ok_or_else(|| format!("--threshold takes 8-bit levels 0..={MAX_THRESHOLD}, found `{v}`"))
}

impl SceneOptions {
    /// Reads the scene, applies the overrides and loads it.
    pub fn load(&self) -> Result<LoadedScene, CliError> {
        let (mut d, dir) = load::read_scene(&self.scene).map_err(fail)?;
        if let Some(s) = self.span {
            d.span = s;
        }
        if let Some(s) = self.shading {
            d.shading = s;
        }
        if let Some(f) = self.format {
            d.format = f;
        }
        if let Some(s) = self.specular {
            d.specular = s;
        }
        if let Some(v) = self.divide {
            d.divide = v;
        }
        if let Some(v) = self.perspective {
            d.perspective_correct = v;
        }
        if let Some(v) = self.perspective_span {
            d.perspective_span = v;
        }
        if let Some(forced) = &self.effects {
            d.effects.extend(forced);
        }
        d.raycast.segment = self.segment.unwrap_or(d.raycast.segment);
        d.raycast.threshold = self.threshold.unwrap_or(d.raycast.threshold);
        d.raycast.sampled |= self.segment.is_some() || self.threshold.is_some();
        load::load(&self.scene, &d, &dir).map_err(fail)
    }

    /// `out/<scene name>.png` (the file stem of a scene file).
    fn default_output(&self) -> PathBuf {
        let stem = Path::new(&self.scene)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scene");
        PathBuf::from("out").join(format!("{stem}.png"))
    }
}

/// `fixshade render`: renders with the fixed-point core into `output` (default
/// `out/SCENE.png`) whole or in strips of `strip` rows; the effects derived from the
/// scene, with `explain` their rules and measured shares of the frame.
pub fn render(
    o: &SceneOptions,
    output: Option<&Path>,
    strip: Option<u32>,
    explain: bool,
) -> Result<String, CliError> {
    let scene = o.load()?;
    let effects = effects::derive(&scene).map_err(usage)?;
    let ls = effects::apply(&scene, &effects);
    let out = output.map_or_else(|| o.default_output(), Path::to_path_buf);
    let r = render::render(&ls, strip).map_err(fail)?;
    r.image.write_png(&out).map_err(fail)?;
    // Sampled Phong lights only some pixels: say how many.
    let evals = match r.stats.evaluations {
        0 => String::new(),
        e => format!(", {e} lighting evaluations"),
    };
    let mut text = format!(
        "{}: {} triangles ({} drawn, {}, {} clipped), {} covered pixels{evals} -> {}",
        ls.name,
        r.stats.triangles,
        r.stats.drawn,
        skipped_words(&r.stats, ls.desc.cull_back),
        r.stats.clipped,
        r.image.covered_count(),
        out.display()
    );
    if ls.desc.shading == ShadingName::ADAPTIVE {
        text.push_str(&format!(
            "\nadaptive: {} of {} polygons lit per pixel",
            r.stats.per_pixel,
            r.stats.triangles - r.stats.skipped()
        ));
    }
    if explain {
        let costs = tables::effects::costs(&scene, &effects, 5, 3).map_err(fail)?;
        text.push('\n');
        text.push_str(&tables::effects::explain(&ls.name, &effects, Some(&costs)));
    }
    Ok(text)
}

/// The triangles the core dropped before rasterizing, by reason, in words: back
/// faces culled (only with culling on: without it none is), zero area after
/// snapping, off the frame.
pub fn skipped_words(st: &Stats, cull_back: bool) -> String {
    let rest = format!(
        "{} of zero area after snapping, {} off the frame",
        st.degenerate, st.outside
    );
    if cull_back {
        format!("{} culled as back faces, {rest}", st.culled)
    } else {
        rest
    }
}

/// `fixshade reference`: the f64 reference render (per-pixel lighting with `phong`).
pub fn reference(o: &SceneOptions, output: &Path, phong: bool) -> Result<String, CliError> {
    let ls = o.load()?;
    let img = render::reference(&ls, phong);
    img.write_png(output).map_err(fail)?;
    Ok(format!(
        "{}: reference{} with {} covered pixels -> {}",
        ls.name,
        if phong { " (Phong)" } else { "" },
        img.covered_count(),
        output.display()
    ))
}

/// `fixshade compare`: NMSE, verdict, largest channel error and coverage mismatch of
/// `test` against `reference`, as text or JSON.
pub fn compare_files(reference: &Path, test: &Path, json: bool) -> Result<String, CliError> {
    let ra = Image::read_png(reference).map_err(fail)?;
    let rb = Image::read_png(test).map_err(fail)?;
    let c = compare(&ra, &rb).map_err(fail)?;
    Ok(if json { c.to_json() } else { c.to_text() })
}
