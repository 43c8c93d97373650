//! Host rendering: load a scene (file or built-in), run the fixed-point core on it,
//! run the f64 reference on the same quantised input, and turn either into an
//! [`Image`].

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::convert::{core_scene, quantize_mesh, quantize_scene, FixedMesh};
use crate::desc::{
    DivideName, FormatName, MeshData, SceneDesc, ShadingName, SpanName, SpecularName,
};
use crate::host_divide::HostDivide;
use crate::image::{channel_max, expand, Image};
use crate::reference::{render_reference, RefOptions};
use crate::{mesh, scene_file};
use fixshade::raster::perspective::Perspective;
use fixshade::raster::span::NoDepth;
use fixshade::render::{Frame, Stats, XfVertex};
use fixshade::shade::Flat;
use fixshade::specular::Specular;
use fixshade::target::{Framebuffer, Gray8, PixelFormat, Rgb565Be, Rgb565Le, Rgb888, Strip};

/// A scene with its meshes built and quantised, ready for both renderers.
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// Where the scene came from (file path or built-in name).
    pub name: String,
    /// The description, quantised to the core's grid.
    pub desc: SceneDesc,
    /// The meshes in f64, quantised (for the reference).
    pub meshes: Vec<MeshData>,
    /// The meshes in the core's formats.
    pub fixed: Vec<FixedMesh>,
}

/// Reads a scene: `arg` is a built-in scene name or a scene file path.
pub fn read_scene(arg: &str) -> Result<(SceneDesc, PathBuf), String> {
    if let Some(d) = scene_file::builtin_scene(arg) {
        return Ok((d, PathBuf::from(".")));
    }
    let path = Path::new(arg);
    if !path.exists() {
        return Err(format!(
            "{arg}: no such scene file, and not a built-in scene (built-ins: {})",
            scene_file::BUILTIN_SCENES.join(", ")
        ));
    }
    let d = scene_file::load_scene(path).map_err(|e| e.to_string())?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    Ok((d, dir))
}

/// Builds the meshes of `desc` (OBJ paths relative to `base_dir`) and quantises
/// everything.
pub fn load(name: &str, desc: &SceneDesc, base_dir: &Path) -> Result<LoadedScene, String> {
    let mut meshes = Vec::new();
    let mut fixed = Vec::new();
    for o in &desc.objects {
        let m = mesh::build(&o.mesh, base_dir).map_err(|e| e.to_string())?;
        let q = quantize_mesh(&m);
        fixed.push(FixedMesh::from_mesh(&q)?);
        meshes.push(q);
    }
    Ok(LoadedScene {
        name: name.to_string(),
        desc: quantize_scene(desc),
        meshes,
        fixed,
    })
}

/// [`read_scene`] then [`load`].
pub fn load_arg(arg: &str) -> Result<LoadedScene, String> {
    let (d, dir) = read_scene(arg)?;
    load(arg, &d, &dir)
}

/// Channel integers of the background in `format` (rounded to nearest).
pub fn background_channels(format: FormatName, bg: [u8; 3]) -> [u32; 3] {
    let m = channel_max(format);
    if format == FormatName::Gray8 {
        let y = (77 * bg[0] as u32 + 150 * bg[1] as u32 + 29 * bg[2] as u32 + 128) / 256;
        return [y; 3];
    }
    [0, 1, 2].map(|i| (bg[i] as u32 * m[i] + 127) / 255)
}

/// The background as it appears in the image: quantised to the format, expanded.
pub fn background8(desc: &SceneDesc) -> [u8; 3] {
    expand(
        desc.format,
        background_channels(desc.format, desc.background),
    )
}

/// The exact f64 reference that matches the scene's shading: per-pixel lighting
/// for Phong and the quadratic surface, the scene's own shading otherwise.
pub fn matching_reference(ls: &LoadedScene) -> Image {
    reference(ls, ls.desc.shading.phong_reference())
}

/// The f64 reference render, with the background quantised like the core's.
pub fn reference(ls: &LoadedScene, phong: bool) -> Image {
    let mut img = render_reference(&ls.desc, &ls.meshes, &RefOptions { phong });
    let bg = background8(&ls.desc);
    img.background = bg;
    for (p, c) in img.pixels.iter_mut().zip(&img.covered) {
        if !c {
            *p = bg;
        }
    }
    img
}

/// A pixel format that records coverage: every store writes 1.
struct Mask;

impl PixelFormat for Mask {
    type Raw = u8;
    const MAX: [u32; 3] = [1, 1, 1];
    const GRAY: bool = true;
    const BYTES: usize = 1;
    const NAME: &'static str = "mask";
    fn pack(_: u32, _: u32, _: u32) -> u8 {
        1
    }
    fn unpack(p: u8) -> [u32; 3] {
        [p as u32; 3]
    }
    fn bytes(p: u8) -> [u8; 3] {
        [p, 0, 0]
    }
}

/// The result of a fixed-point render.
#[derive(Clone, Debug)]
pub struct Render {
    /// The image (with coverage).
    pub image: Image,
    /// The framebuffer bytes in memory order.
    pub bytes: Vec<u8>,
    /// Draw statistics.
    pub stats: Stats,
}

/// Runs `$body` with the type `$S` bound to the span method named by `$name`.
#[macro_export]
macro_rules! with_span_method {
    ($name:expr, $S:ident => $body:expr) => {{
        use fixshade::raster::parallel::{Counter, EvenOdd, KWay, Segment};
        use fixshade::raster::sierpinski::{Sierpinski, SierpinskiExact};
        use fixshade::raster::span::{Classic, Gradient};
        use $crate::desc::SpanName as N;
        match $name {
            N::Classic => {
                type $S = Classic;
                $body
            }
            N::Gradient => {
                type $S = Gradient;
                $body
            }
            N::EvenOdd => {
                type $S = EvenOdd;
                $body
            }
            N::KWay2 => {
                type $S = KWay<2>;
                $body
            }
            N::KWay3 => {
                type $S = KWay<3>;
                $body
            }
            N::KWay4 => {
                type $S = KWay<4>;
                $body
            }
            N::Counter => {
                type $S = Counter;
                $body
            }
            N::Segment2 => {
                type $S = Segment<2>;
                $body
            }
            N::Segment4 => {
                type $S = Segment<4>;
                $body
            }
            N::Segment8 => {
                type $S = Segment<8>;
                $body
            }
            N::Segment16 => {
                type $S = Segment<16>;
                $body
            }
            N::Segment32 => {
                type $S = Segment<32>;
                $body
            }
            N::Segment64 => {
                type $S = Segment<64>;
                $body
            }
            N::Sierpinski => {
                type $S = Sierpinski;
                $body
            }
            N::SierpinskiExact => {
                type $S = SierpinskiExact;
                $body
            }
        }
    }};
}

/// Runs `$body` with the type `$Sp` bound to the specular model named by `$name`.
#[macro_export]
macro_rules! with_specular {
    ($name:expr, $Sp:ident => $body:expr) => {{
        use fixshade::specular::{
            BlinnExact, CosQuadratic, CosQuadraticEnergy, Quadratic, Schlick, SchlickModified,
        };
        use $crate::desc::SpecularName as N;
        match $name {
            N::Exact => {
                type $Sp = BlinnExact;
                $body
            }
            N::Schlick => {
                type $Sp = Schlick;
                $body
            }
            N::SchlickMod => {
                type $Sp = SchlickModified;
                $body
            }
            N::Quadratic => {
                type $Sp = Quadratic;
                $body
            }
            N::CosQuad => {
                type $Sp = CosQuadratic;
                $body
            }
            N::CosQuadEnergy => {
                type $Sp = CosQuadraticEnergy;
                $body
            }
        }
    }};
}

/// How the span methods divide: [`ExactSpans`] draws the plain types (the default
/// `exact` divider), [`DividedSpans`] the approximate dividers through
/// [`HostDivide`] (the setup reciprocal for every method, the classic span
/// division too).
trait SpanDispatch {
    fn dispatch<P: PixelFormat, Sp: Specular>(
        frame: &Frame<'_, '_, '_, P, Sp>,
        span: SpanName,
        fb: &mut impl fixshade::target::Target<P>,
    ) -> Result<Stats, String>;

    /// [`Frame::draw_perspective`] with this dispatch's divider.
    fn perspective<P: PixelFormat, Sp: Specular>(
        frame: &Frame<'_, '_, '_, P, Sp>,
        mode: Perspective,
        fb: &mut impl fixshade::target::Target<P>,
    ) -> Result<Stats, String>;
}

struct ExactSpans;
struct DividedSpans;

impl SpanDispatch for ExactSpans {
    fn dispatch<P: PixelFormat, Sp: Specular>(
        frame: &Frame<'_, '_, '_, P, Sp>,
        span: SpanName,
        fb: &mut impl fixshade::target::Target<P>,
    ) -> Result<Stats, String> {
        with_span_method!(span, S => frame.draw::<S, _>(fb)).map_err(|e| e.to_string())
    }

    fn perspective<P: PixelFormat, Sp: Specular>(
        frame: &Frame<'_, '_, '_, P, Sp>,
        mode: Perspective,
        fb: &mut impl fixshade::target::Target<P>,
    ) -> Result<Stats, String> {
        draw_perspective::<fixshade::divide::Exact, _, _>(frame, mode, fb)
    }
}

impl SpanDispatch for DividedSpans {
    fn dispatch<P: PixelFormat, Sp: Specular>(
        frame: &Frame<'_, '_, '_, P, Sp>,
        span: SpanName,
        fb: &mut impl fixshade::target::Target<P>,
    ) -> Result<Stats, String> {
        use fixshade::raster::span::{Classic, WithDivide};
        if span == SpanName::Classic {
            frame.draw::<WithDivide<Classic<HostDivide>, HostDivide>, _>(fb)
        } else {
            with_span_method!(span, S => frame.draw::<WithDivide<S, HostDivide>, _>(fb))
        }
        .map_err(|e| e.to_string())
    }

    fn perspective<P: PixelFormat, Sp: Specular>(
        frame: &Frame<'_, '_, '_, P, Sp>,
        mode: Perspective,
        fb: &mut impl fixshade::target::Target<P>,
    ) -> Result<Stats, String> {
        draw_perspective::<HostDivide, _, _>(frame, mode, fb)
    }
}

/// Draws a prepared frame as [`render`] draws the scene `d` with the default
/// specular pipeline: its span method and divider, perspective-correct Gouraud
/// colours when it asks for them, sampled Phong when it asks for that (for
/// [`crate::bake::render_chunked`]).
pub(crate) fn draw_span<P: PixelFormat, Sp: Specular>(
    frame: &Frame<'_, '_, '_, P, Sp>,
    d: &SceneDesc,
    fb: &mut impl fixshade::target::Target<P>,
) -> Result<Stats, String> {
    if d.divide == DivideName::Exact {
        span_dispatch::<ExactSpans, _, _>(frame, d, fb)
    } else {
        crate::host_divide::select(d.divide);
        span_dispatch::<DividedSpans, _, _>(frame, d, fb)
    }
}

fn draw_perspective<D: fixshade::divide::Divide, P: PixelFormat, Sp: Specular>(
    frame: &Frame<'_, '_, '_, P, Sp>,
    mode: Perspective,
    fb: &mut impl fixshade::target::Target<P>,
) -> Result<Stats, String> {
    frame
        .draw_perspective::<D, _>(fb, mode)
        .map_err(|e| e.to_string())
}

/// Runs `$body` with `$Sp` bound to the scene's specular model and `$Sd` to its
/// [`SpanDispatch`]; an approximate divider is selected for [`HostDivide`] and
/// reaches Schlick's denominators too.
macro_rules! with_specular_divide {
    ($desc:expr, $Sp:ident, $Sd:ident => $body:expr) => {{
        use fixshade::specular::{Schlick, SchlickModified};
        let d = &$desc;
        if d.divide == DivideName::Exact {
            type $Sd = ExactSpans;
            with_specular!(d.specular, $Sp => $body)
        } else {
            type $Sd = DividedSpans;
            crate::host_divide::select(d.divide);
            match d.specular {
                SpecularName::Schlick => {
                    type $Sp = Schlick<HostDivide>;
                    $body
                }
                SpecularName::SchlickMod => {
                    type $Sp = SchlickModified<HostDivide>;
                    $body
                }
                other => with_specular!(other, $Sp => $body),
            }
        }
    }};
}

/// Draws a prepared frame with the scene's span method (dividing as `Sd` says), with
/// sampled Phong lighting when the scene asks for Phong with a segment sampler
/// ([`crate::raycast::RaycastDesc::sampled`]), or with perspective-correct colours
/// or normals when a Gouraud, Phong or adaptive scene asks for them (coverage then
/// follows `gradient`).
fn span_dispatch<Sd: SpanDispatch, P: PixelFormat, Sp: Specular>(
    frame: &Frame<'_, '_, '_, P, Sp>,
    d: &SceneDesc,
    fb: &mut impl fixshade::target::Target<P>,
) -> Result<Stats, String> {
    if d.shading == ShadingName::Phong && d.raycast.sampled {
        let sampling = fixshade::raster::phong::Sampling {
            segment: d.raycast.segment,
            threshold: fixshade::sampler::Threshold::from_q8(
                crate::raycast::threshold_q8(d.raycast.threshold),
                P::MAX,
            ),
        };
        return frame
            .draw_phong_sampled(fb, sampling)
            .map_err(|e| e.to_string());
    }
    if d.perspective_correct && perspective_shading(d.shading) {
        let mode = Perspective::new(d.perspective_span).ok_or_else(|| {
            format!(
                "perspective span {} is not a power of two from 1 to 64",
                d.perspective_span
            )
        })?;
        return Sd::perspective(frame, mode, fb);
    }
    Sd::dispatch(frame, d.span, fb)
}

/// True for the shadings [`Frame::draw_perspective`] corrects: Gouraud colours,
/// Phong normals and positions, adaptive (both).
fn perspective_shading(s: ShadingName) -> bool {
    matches!(
        s,
        ShadingName::Gouraud
            | ShadingName::Phong
            | ShadingName::PhongEvenOdd
            | ShadingName::Adaptive
    )
}

/// True if the frame needs the specular term: some light and some material have a
/// specular colour, or `+specular` is forced. Otherwise the frame runs with
/// [`fixshade::effects::NoSpecular`] (the same pixels, no specular code).
pub fn specular_pipeline(d: &SceneDesc) -> bool {
    crate::effects::has_specular(d)
        || matches!(
            d.effects.get(crate::effects::Effect::Specular),
            Some((true, _))
        )
}

fn run_core<P: PixelFormat>(
    ls: &LoadedScene,
    strip_rows: Option<u32>,
) -> Result<(Vec<P::Raw>, Stats), String> {
    if !specular_pipeline(&ls.desc) {
        if ls.desc.divide == DivideName::Exact {
            return run_core_with::<P, fixshade::effects::NoSpecular, ExactSpans>(ls, strip_rows);
        }
        crate::host_divide::select(ls.desc.divide);
        return run_core_with::<P, fixshade::effects::NoSpecular, DividedSpans>(ls, strip_rows);
    }
    with_specular_divide!(ls.desc, Sp, Sd => run_core_with::<P, Sp, Sd>(ls, strip_rows))
}

/// The whole frame as one [`Strip`]: the pipelines draw into strips only, so each
/// of them is compiled for one target type ([`Framebuffer`] is a strip of every row
/// and draws the same bytes).
fn whole_frame<'a, P: PixelFormat>(
    color: &'a mut [P::Raw],
    depth: Option<&'a mut [u16]>,
    w: u32,
    h: u32,
) -> Result<Strip<'a, P>, String> {
    Strip::<P>::new(color, depth, w, h, 0, h).map_err(|e| e.to_string())
}

fn run_core_with<P: PixelFormat, Sp: Specular, Sd: SpanDispatch>(
    ls: &LoadedScene,
    strip_rows: Option<u32>,
) -> Result<(Vec<P::Raw>, Stats), String> {
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed)?;
    let (w, h) = (d.width, d.height);
    let n = w as usize * h as usize;
    let bgc = background_channels(d.format, d.background);
    let bg = P::pack(bgc[0], bgc[1], bgc[2]);
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let frame =
        Frame::<P>::prepare_with::<Sp>(&scene, w, h, &mut cache).map_err(|e| e.to_string())?;
    let mut color = vec![bg; n];
    let mut stats = Stats::default();
    match strip_rows {
        None => {
            let mut depth = vec![0xFFFFu16; n];
            let mut fb =
                whole_frame::<P>(&mut color, d.depth_test.then_some(&mut depth[..]), w, h)?;
            stats = span_dispatch::<Sd, _, _>(&frame, d, &mut fb)?;
        }
        Some(rows) => {
            let rows = rows.clamp(1, h);
            let mut buf = vec![bg; w as usize * rows as usize];
            let mut depth = vec![0xFFFFu16; w as usize * rows as usize];
            let mut y0 = 0;
            while y0 < h {
                let hh = rows.min(h - y0);
                let mut strip = Strip::<P>::new(
                    &mut buf,
                    d.depth_test.then_some(&mut depth[..]),
                    w,
                    h,
                    y0,
                    hh,
                )
                .map_err(|e| e.to_string())?;
                strip.clear(bg);
                stats += span_dispatch::<Sd, _, _>(&frame, d, &mut strip)?;
                let len = w as usize * hh as usize;
                let at = y0 as usize * w as usize;
                color[at..at + len].copy_from_slice(&strip.color()[..len]);
                y0 += hh;
            }
        }
    }
    Ok((color, stats))
}

fn coverage(ls: &LoadedScene) -> Result<Vec<bool>, String> {
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed)?;
    let (w, h) = (d.width, d.height);
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let frame = Frame::<Mask>::prepare(&scene, w, h, &mut cache).map_err(|e| e.to_string())?;
    let mut mask = vec![0u8; w as usize * h as usize];
    let mut fb = Framebuffer::<Mask>::new(&mut mask, None, w, h).map_err(|e| e.to_string())?;
    // The same span method as the colour pass: methods that move vertices
    // (sierpinski) change coverage too. The quadratic surface and Phong have their
    // own fills, which ignore the span method and cover what `gradient` covers.
    let perspective = d.perspective_correct && perspective_shading(d.shading);
    if perspective
        || matches!(
            d.shading,
            ShadingName::Quadratic
                | ShadingName::Phong
                | ShadingName::PhongEvenOdd
                | ShadingName::Adaptive
        )
    {
        frame.draw_with::<fixshade::raster::span::Gradient, NoDepth, Flat, _>(&mut fb)
    } else {
        with_span_method!(d.span, S => frame.draw_with::<S, NoDepth, Flat, _>(&mut fb))
    }
    .map_err(|e| e.to_string())?;
    Ok(mask.iter().map(|m| *m != 0).collect())
}

fn to_render<P: PixelFormat>(ls: &LoadedScene, strip_rows: Option<u32>) -> Result<Render, String> {
    let (color, stats) = run_core::<P>(ls, strip_rows)?;
    let d = &ls.desc;
    let covered = coverage(ls)?;
    let bg = background8(d);
    let pixels = color
        .iter()
        .zip(&covered)
        .map(|(p, c)| {
            if *c {
                expand(d.format, P::unpack(*p))
            } else {
                bg
            }
        })
        .collect();
    let bytes = color
        .iter()
        .flat_map(|p| P::bytes(*p).into_iter().take(P::BYTES))
        .collect();
    Ok(Render {
        image: Image {
            width: d.width,
            height: d.height,
            pixels,
            covered,
            background: bg,
        },
        bytes,
        stats,
    })
}

/// Renders with the fixed-point core, whole frame (`strip_rows = None`) or strip by
/// strip.
pub fn render(ls: &LoadedScene, strip_rows: Option<u32>) -> Result<Render, String> {
    if ls.desc.shading == ShadingName::Raycast {
        return crate::raycast::render(ls);
    }
    match ls.desc.format {
        FormatName::Rgb565Le => to_render::<Rgb565Le>(ls, strip_rows),
        FormatName::Rgb565Be => to_render::<Rgb565Be>(ls, strip_rows),
        FormatName::Rgb888 => to_render::<Rgb888>(ls, strip_rows),
        FormatName::Gray8 => to_render::<Gray8>(ls, strip_rows),
    }
}

/// Median wall time of one frame (vertex stage + rasterization, framebuffer clear
/// excluded) over `runs` runs.
pub fn time_frame(ls: &LoadedScene, runs: usize) -> Result<Duration, String> {
    if ls.desc.shading == ShadingName::Raycast {
        return crate::raycast::time_frame(ls, runs);
    }
    fn go<P: PixelFormat>(ls: &LoadedScene, runs: usize) -> Result<Duration, String> {
        if !specular_pipeline(&ls.desc) {
            if ls.desc.divide == DivideName::Exact {
                return go_with::<P, fixshade::effects::NoSpecular, ExactSpans>(ls, runs);
            }
            crate::host_divide::select(ls.desc.divide);
            return go_with::<P, fixshade::effects::NoSpecular, DividedSpans>(ls, runs);
        }
        with_specular_divide!(ls.desc, Sp, Sd => go_with::<P, Sp, Sd>(ls, runs))
    }
    fn go_with<P: PixelFormat, Sp: Specular, Sd: SpanDispatch>(
        ls: &LoadedScene,
        runs: usize,
    ) -> Result<Duration, String> {
        let d = &ls.desc;
        let scene = core_scene(d, &ls.fixed)?;
        let (w, h) = (d.width, d.height);
        let n = w as usize * h as usize;
        let mut cache = vec![XfVertex::default(); scene.vertex_count()];
        let mut color = vec![P::Raw::default(); n];
        let mut depth = vec![0xFFFFu16; n];
        let mut times = Vec::with_capacity(runs);
        for _ in 0..runs.max(1) {
            depth.fill(0xFFFF);
            let t = Instant::now();
            let frame = Frame::<P>::prepare_with::<Sp>(&scene, w, h, &mut cache)
                .map_err(|e| e.to_string())?;
            let mut fb =
                whole_frame::<P>(&mut color, d.depth_test.then_some(&mut depth[..]), w, h)?;
            std::hint::black_box(span_dispatch::<Sd, _, _>(&frame, d, &mut fb)?);
            times.push(t.elapsed());
        }
        times.sort();
        Ok(times[times.len() / 2])
    }
    match ls.desc.format {
        FormatName::Rgb565Le => go::<Rgb565Le>(ls, runs),
        FormatName::Rgb565Be => go::<Rgb565Be>(ls, runs),
        FormatName::Rgb888 => go::<Rgb888>(ls, runs),
        FormatName::Gray8 => go::<Gray8>(ls, runs),
    }
}
