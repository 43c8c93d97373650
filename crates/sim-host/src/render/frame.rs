//! The core's frame loop on the host: prepare a loaded scene (vertex stage) and draw
//! it ([`super::dispatch`]) whole or strip by strip, into an [`Image`] with its
//! coverage; time it; or draw it chunk by chunk as a board with little RAM does.
//!
//! Every frame is drawn in the core's [`Covered`] form of its pixel format, which
//! flags each pixel the draw writes: the image's coverage comes from the same pass as
//! its pixels, and the bytes are the plain format's. Rendering, timing and the
//! chunked render share one compiled pipeline per format.

use std::ops::Range;
use std::time::{Duration, Instant};

use fixshade::present::eg::{Covered, CoveredPixel};
use fixshade::present::linebuf::{render_bands, LineBufferProvider};
use fixshade::present::DrawError;
use fixshade::raster::setup::Record;
use fixshade::raster::span::Gradient;
use fixshade::raster::Walk;
use fixshade::render::{BandMemory, Frame, Stats, XfVertex};
use fixshade::target::{DepthFormat, Gray8, PixelFormat, Rgb565Be, Rgb565Le, Rgb888, Strip};

use super::dispatch::{choose, DepthStrip, Draw};
use super::host::{with_selection, HostSpecular, Selection};
use super::output::Render;
use crate::image::Image;
use crate::scene::convert::{background8, background_channels, core_scene, FixedMesh};
use crate::scene::desc::{DivideName, FormatName, SceneDesc, ShadingName};
use crate::scene::effects::{forced_specular, has_specular};
use crate::scene::load::LoadedScene;
use fixshade::scene::Scene;

/// True if the frame runs the specular term: some light and some material have a
/// specular colour, or `+specular` is forced, or the divider is approximate, or the
/// lighting is two-sided. Otherwise the frame skips the specular code, as the core's
/// [`fixshade::effects::NoSpecular`] does (the selection's `specular_term`, see
/// [`super::host`]). The pixels are the same either way (without a specular colour
/// the term is zero); only the time differs (`fixshade effects`, `--explain`).
pub fn specular_pipeline(d: &SceneDesc) -> bool {
    has_specular(d) || forced_specular(d) || d.divide != DivideName::EXACT || d.two_sided
}

/// The frames a scene description asks for, chosen once ([`super::dispatch`]) with
/// the divider, specular model, specular term and sides of lighting it selects:
/// prepares (vertex stage) and draws frames of a scene in `P` with coverage
/// ([`Covered`]), lit with [`HostSpecular`].
pub struct Pipeline<P: PixelFormat> {
    draw: Draw<Covered<P>>,
    selection: Selection,
}

impl<P: PixelFormat> Pipeline<P> {
    /// The pipeline of `d` (not ray casting).
    pub fn new(d: &SceneDesc) -> Result<Self, String> {
        Ok(Pipeline {
            draw: choose(d)?,
            selection: Selection {
                divide: d.divide,
                specular: d.specular,
                specular_term: specular_pipeline(d),
                two_sided: d.two_sided,
            },
        })
    }

    /// The vertex cache entries a frame of `scene` needs (twice the vertices under
    /// two-sided lighting).
    pub fn cache_len(&self, scene: &Scene<'_>) -> usize {
        with_selection(self.selection, || {
            Frame::<Covered<P>, HostSpecular>::cache_len(scene)
        })
    }

    /// The vertex stage of `scene` for a `width` x `height` frame.
    pub fn prepare<'s, 'a, 'c>(
        &self,
        scene: &'s Scene<'a>,
        width: u32,
        height: u32,
        cache: &'c mut [XfVertex],
    ) -> Result<Frame<'s, 'a, 'c, Covered<P>, HostSpecular>, String> {
        with_selection(self.selection, || {
            Frame::<Covered<P>>::prepare_with::<HostSpecular>(scene, width, height, cache)
        })
        .map_err(|e| e.to_string())
    }

    /// Runs `f` with the pipeline's divider, specular model, specular term and
    /// sides of lighting selected: to draw a prepared frame by other means than
    /// [`Pipeline::draw`], such as the core's band loop
    /// (`fixshade::present::linebuf::render_lines`).
    pub fn selected<R>(&self, f: impl FnOnce() -> R) -> R {
        with_selection(self.selection, f)
    }

    /// True if the frames draw the pixels of the core's [`Gradient`], so that a
    /// binned frame can draw its bands from records (see
    /// [`super::dispatch::Draw::records`]).
    pub fn records(&self) -> bool {
        self.draw.records()
    }

    /// True if the frames draw into strips with 32-bit depth cells.
    pub fn depth32(&self) -> bool {
        self.draw.depth32()
    }

    /// Draws a prepared frame into a strip (of every row, or of some) whose depth
    /// cells are the pipeline's ([`Pipeline::depth32`]).
    pub fn draw(
        &self,
        frame: &Frame<'_, '_, '_, Covered<P>, HostSpecular>,
        strip: DepthStrip<'_, '_, Covered<P>>,
    ) -> Result<Stats, String> {
        with_selection(self.selection, || self.draw.run(frame, strip))
    }
}

/// How the host draws frames of a pixel format.
pub trait Drawn: PixelFormat {
    /// The format the pipeline draws in: the format itself, or for [`Rgb565Be`]
    /// [`Rgb565Le`], whose bytes are then swapped in pairs (`Rgb565Be::pack` is the
    /// byte swap of `Rgb565Le::pack`; the test `rgb565be_is_rgb565le_swapped` checks
    /// a frame).
    type As: PixelFormat;
    /// True if the bytes of `As` are swapped in pairs.
    const SWAP: bool = false;
}

impl Drawn for Rgb565Le {
    type As = Self;
}

impl Drawn for Rgb565Be {
    type As = Rgb565Le;
    const SWAP: bool = true;
}

impl Drawn for Rgb888 {
    type As = Self;
}

impl Drawn for Gray8 {
    type As = Self;
}

/// Swaps the bytes of `b` in pairs, if `swap`.
fn swapped(mut b: Vec<u8>, swap: bool) -> Vec<u8> {
    if swap {
        for pair in b.chunks_exact_mut(2) {
            pair.swap(0, 1);
        }
    }
    b
}

/// The arm of [`with_types`] for each pixel format of the registry.
macro_rules! pick_format {
    ([$d:expr, $P:ident, $swap:ident, $body:expr] $($F:ty),* $(,)?) => {{
        let d: &SceneDesc = $d;
        let mut at = 0;
        $(
            if d.format.index() == at {
                type $P = <$F as Drawn>::As;
                let $swap = <$F as Drawn>::SWAP;
                return $body;
            }
            at += 1;
        )*
        unreachable!("pixel format {} of {at}", d.format.index())
    }};
}

/// Runs `$body` (and returns its value) with `$P` bound to the format the scene's
/// pixel format is drawn in ([`Drawn`]) and `$swap` to whether its bytes are
/// swapped.
macro_rules! with_types {
    ($d:expr, $P:ident, $swap:ident => $body:expr) => {
        fixshade::for_each_pixel_format!(pick_format[$d, $P, $swap, $body])
    };
}

/// Renders with the fixed-point core, whole frame (`strip_rows = None`) or strip by
/// strip; coverage comes from the same pass (the pixels the draw wrote).
pub fn render(ls: &LoadedScene, strip_rows: Option<u32>) -> Result<Render, String> {
    if ls.desc.shading == ShadingName::RAYCAST {
        return super::raycast::render(ls);
    }
    with_types!(&ls.desc, P, swap => render_as::<P>(ls, strip_rows).map(|r| Render {
        bytes: swapped(r.bytes, swap),
        ..r
    }))
}

/// Median wall time of one frame (vertex stage + rasterization, framebuffer clear
/// excluded) over `runs` runs.
pub fn time_frame(ls: &LoadedScene, runs: usize) -> Result<Duration, String> {
    if ls.desc.shading == ShadingName::RAYCAST {
        return super::raycast::time_frame(ls, runs);
    }
    with_types!(&ls.desc, P, _swap => time_as::<P>(ls, runs))
}

/// A frame's pixels, each with its written flag.
type Pixels<P> = Vec<CoveredPixel<<P as PixelFormat>::Raw>>;

/// The frame `d` describes, drawn band by band by the core's band loop
/// ([`render_bands`]): `rows` rows at a time into one [`Covered`] strip cleared to
/// the background, with 32-bit depth cells if `depth32`, `draw(band, strip)`
/// filling each band; returns the bands' pixels in frame order and the statistics
/// summed.
fn bands<P: PixelFormat>(
    d: &SceneDesc,
    rows: u32,
    depth32: bool,
    mut draw: impl FnMut(u32, DepthStrip<'_, '_, Covered<P>>) -> Result<Stats, String>,
) -> Result<(Pixels<P>, Stats), String> {
    if depth32 {
        bands_with::<P, u32>(d, rows, |b, s| draw(b, DepthStrip::D32(s)))
    } else {
        bands_with::<P, u16>(d, rows, |b, s| draw(b, DepthStrip::D16(s)))
    }
}

/// A frame collected band by band: the display the core's band loop fills.
struct Collect<P: PixelFormat> {
    width: u32,
    height: u32,
    /// The band buffer lent to the loop.
    band: Pixels<P>,
    /// The rows sent so far, in frame order.
    frame: Pixels<P>,
}

impl<P: PixelFormat> LineBufferProvider for Collect<P> {
    type Format = Covered<P>;

    fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    fn process_lines(
        &mut self,
        lines: Range<u32>,
        render: impl FnOnce(&mut [CoveredPixel<P::Raw>]),
    ) {
        let n = self.width as usize * lines.len();
        render(&mut self.band[..n]);
        self.frame.extend_from_slice(&self.band[..n]);
    }
}

/// An error of a band's draw, or of the band loop itself.
struct BandError(String);

impl From<DrawError> for BandError {
    fn from(e: DrawError) -> BandError {
        BandError(e.to_string())
    }
}

/// [`bands`] with depth cells `C`.
fn bands_with<P: PixelFormat, C: DepthFormat>(
    d: &SceneDesc,
    rows: u32,
    mut draw: impl FnMut(u32, &mut Strip<'_, Covered<P>, C>) -> Result<Stats, String>,
) -> Result<(Pixels<P>, Stats), String> {
    let (w, h) = (d.width, d.height);
    let rows = rows.clamp(1, h);
    let bgc = background_channels(d.format, d.background);
    let bg = CoveredPixel {
        raw: P::pack(bgc[0], bgc[1], bgc[2]),
        written: false,
    };
    let mut out = Collect::<P> {
        width: w,
        height: h,
        band: vec![bg; w as usize * rows as usize],
        frame: Vec::with_capacity(w as usize * h as usize),
    };
    let mut depth = vec![C::FAR; w as usize * rows as usize];
    let stats = render_bands(
        rows,
        d.depth_test.then_some(&mut depth[..]),
        bg,
        &mut out,
        |band, strip| draw(band, strip).map_err(BandError),
    )
    .map_err(|e| e.0)?;
    Ok((out.frame, stats))
}

/// The bytes of `P` pixels in memory order.
fn raw_bytes<P: PixelFormat>(color: &[CoveredPixel<P::Raw>]) -> Vec<u8> {
    color
        .iter()
        .flat_map(|p| P::bytes(p.raw).into_iter().take(P::BYTES))
        .collect()
}

/// The frame of `ls` in `P` with coverage, drawn whole or in
/// strips of `strip_rows` rows.
fn render_as<P: PixelFormat>(ls: &LoadedScene, strip_rows: Option<u32>) -> Result<Render, String> {
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed)?;
    let pipeline = Pipeline::<P>::new(d)?;
    let mut cache = vec![XfVertex::default(); pipeline.cache_len(&scene)];
    let frame = pipeline.prepare(&scene, d.width, d.height, &mut cache)?;
    let rows = strip_rows.unwrap_or(d.height);
    let (color, stats) = if rows < d.height && pipeline.records() {
        strips_binned::<P>(d, &scene, &pipeline, &frame, rows)?
    } else {
        bands::<P>(d, rows, pipeline.depth32(), |_, strip| {
            pipeline.draw(&frame, strip)
        })?
    };
    let bg8 = background8(d);
    Ok(Render {
        image: Image {
            width: d.width,
            height: d.height,
            pixels: color
                .iter()
                .map(|p| {
                    if p.written {
                        d.format.expand(P::unpack(p.raw))
                    } else {
                        bg8
                    }
                })
                .collect(),
            covered: color.iter().map(|p| p.written).collect(),
            background: bg8,
        },
        bytes: raw_bytes::<P>(&color),
        stats,
    })
}

/// Strips of `rows` rows of a frame whose draw has records ([`Pipeline::records`]):
/// binned once ([`Frame::bin`]), each strip drawn from the records that reach it
/// with the edge walks carried from strip to strip, as a board draws its bands.
/// The records are sized for every triangle (clipped into at most seven pieces)
/// and the bins' index for the bands each reaches, within bounds; a frame that
/// does not fit re-walks its triangles per strip (the same pixels).
fn strips_binned<P: PixelFormat>(
    d: &SceneDesc,
    scene: &Scene<'_>,
    pipeline: &Pipeline<P>,
    frame: &Frame<'_, '_, '_, Covered<P>, HostSpecular>,
    rows: u32,
) -> Result<(Pixels<P>, Stats), String> {
    let triangles: usize = scene.objects.iter().map(|o| o.mesh.triangles().len()).sum();
    let n = (7 * triangles + 1).min(1 << 16);
    let per = BandMemory::bands(d.height, rows);
    let mut records = vec![Record::EMPTY; n];
    let mut index = vec![0u16; (n * per).min(1 << 22)];
    let mut starts = vec![0u32; BandMemory::starts_len(d.height, rows)];
    let mut walks = vec![Walk::EMPTY; n];
    let mem = BandMemory::new(&mut records, &mut index, &mut starts).with_walks(&mut walks);
    let mut binned = pipeline
        .selected(|| frame.bin(rows, mem))
        .map_err(|e| e.to_string())?;
    let binning = binned.stats();
    let (color, mut stats) = bands::<P>(d, rows, pipeline.depth32(), |band, strip| {
        pipeline
            .selected(|| match strip {
                DepthStrip::D16(s) => binned.draw_band_resuming::<Gradient, _>(band, s),
                DepthStrip::D32(s) => binned.draw_band_resuming::<Gradient, _>(band, s),
            })
            .map_err(|e| e.to_string())
    })?;
    stats += binning;
    Ok((color, stats))
}

/// One frame timed as [`render_as`] draws it (whole frame, the coverage flag
/// included: it costs about 1 % of a frame, `examples/bench_table.rs`).
fn time_as<P: PixelFormat>(ls: &LoadedScene, runs: usize) -> Result<Duration, String> {
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed)?;
    let (w, h) = (d.width, d.height);
    let n = w as usize * h as usize;
    let pipeline = Pipeline::<P>::new(d)?;
    let mut cache = vec![XfVertex::default(); pipeline.cache_len(&scene)];
    let mut color = vec![CoveredPixel::<P::Raw>::default(); n];
    let (mut depth16, mut depth32) = (Vec::new(), Vec::new());
    if pipeline.depth32() {
        depth32 = vec![u32::FAR; n];
    } else {
        depth16 = vec![u16::FAR; n];
    }
    let mut times = Vec::with_capacity(runs);
    for _ in 0..runs.max(1) {
        depth16.fill(u16::FAR);
        depth32.fill(u32::FAR);
        let t = Instant::now();
        let frame = pipeline.prepare(&scene, w, h, &mut cache)?;
        let stats = if pipeline.depth32() {
            let depth = d.depth_test.then_some(&mut depth32[..]);
            let mut fb = Strip::<Covered<P>, u32>::with_depth_format(&mut color, depth, w, h, 0, h)
                .map_err(|e| e.to_string())?;
            pipeline.draw(&frame, DepthStrip::D32(&mut fb))?
        } else {
            let depth = d.depth_test.then_some(&mut depth16[..]);
            let mut fb = Strip::<Covered<P>>::new(&mut color, depth, w, h, 0, h)
                .map_err(|e| e.to_string())?;
            pipeline.draw(&frame, DepthStrip::D16(&mut fb))?
        };
        std::hint::black_box(stats);
        times.push(t.elapsed());
    }
    times.sort();
    Ok(times[times.len() / 2])
}

/// Renders a one-object scene (its span method, divider and perspective correction)
/// the way a board with little RAM does: strip by strip (`rows` rows each), and per
/// strip chunk by chunk (`fixshade bake --chunk max_vertices`, [`super::bake::chunks`]),
/// each chunk with its own vertex stage. Returns the frame's bytes (Rgb565
/// little-endian scenes only). The QEMU Cortex-M0 firmware renders this way;
/// `cargo xtask qemu` compares its frames with this.
pub fn render_chunked(ls: &LoadedScene, max_vertices: usize, rows: u32) -> Result<Vec<u8>, String> {
    let d = &ls.desc;
    if d.format != FormatName::RGB565LE || ls.fixed.len() != 1 {
        return Err("render_chunked takes one-object rgb565le scenes".into());
    }
    let bound = super::bake::mesh_bound(&ls.fixed[0]);
    let meshes: Vec<FixedMesh> = super::bake::chunks(&ls.fixed[0], Some(max_vertices))?
        .into_iter()
        .map(|c| FixedMesh {
            positions: c.positions,
            normals: c.normals,
            triangles: c.triangles,
        })
        .collect();
    with_types!(d, P, swap => chunked_as::<P>(d, &meshes, bound, max_vertices, rows)
        .map(|b| swapped(b, swap)))
}

fn chunked_as<P: PixelFormat>(
    d: &SceneDesc,
    meshes: &[FixedMesh],
    bound: i32,
    max_vertices: usize,
    rows: u32,
) -> Result<Vec<u8>, String> {
    // Each chunk transformed as the whole mesh (its bound), as the firmware does.
    let scenes = meshes
        .iter()
        .map(|m| {
            let mut s = core_scene(d, std::slice::from_ref(m))?;
            s.objects[0].mesh = s.objects[0].mesh.with_bound(bound);
            Ok(s)
        })
        .collect::<Result<Vec<_>, String>>()?;
    let pipeline = Pipeline::<P>::new(d)?;
    // Two-sided lighting keeps the back colours in a second half of the cache.
    let sides = if d.two_sided { 2 } else { 1 };
    let mut cache = vec![XfVertex::default(); sides * max_vertices];
    let (color, _) = bands::<P>(d, rows, pipeline.depth32(), |_, mut strip| {
        let mut stats = Stats::default();
        for scene in &scenes {
            let frame = pipeline.prepare(scene, d.width, d.height, &mut cache)?;
            stats += pipeline.draw(&frame, strip.reborrow())?;
        }
        Ok(stats)
    })?;
    Ok(raw_bytes::<P>(&color))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::desc::SpanName;
    use crate::scene::load::load_arg;

    /// Strips of a `gradient` frame are drawn from one binning (each triangle set up
    /// once, not once per strip), with the whole frame's bytes; strips of another
    /// span method walk the triangles per strip.
    #[test]
    fn gradient_strips_draw_from_one_binning() {
        let mut ls = load_arg("teapot").unwrap();
        for (span, binned) in [(SpanName::GRADIENT, true), (SpanName::CLASSIC, false)] {
            ls.desc.span = span;
            let whole = render(&ls, None).unwrap();
            let strips = render(&ls, Some(16)).unwrap();
            assert!(whole.bytes == strips.bytes, "{span:?}: strips differ");
            assert_eq!(strips.stats.pixels, whole.stats.pixels);
            assert_eq!(strips.stats.rewalked, 0);
            let per_strip = ls.desc.height.div_ceil(16);
            let triangles = if binned {
                whole.stats.triangles
            } else {
                whole.stats.triangles * per_strip
            };
            assert_eq!(strips.stats.triangles, triangles, "{span:?}");
        }
    }

    /// A frame drawn in the core's `Rgb565Be` has the bytes of the same frame in
    /// `Rgb565Le`, swapped in pairs: what [`Drawn`] relies on.
    #[test]
    fn rgb565be_is_rgb565le_swapped() {
        fn bytes<P: PixelFormat>(ls: &LoadedScene) -> Vec<u8> {
            let scene = core_scene(&ls.desc, &ls.fixed).unwrap();
            let (w, h) = (ls.desc.width, ls.desc.height);
            let n = w as usize * h as usize;
            let mut cache = vec![XfVertex::default(); scene.vertex_count()];
            let (mut color, mut depth) = (vec![P::Raw::default(); n], vec![0xFFFF; n]);
            let frame = Frame::<P>::prepare(&scene, w, h, &mut cache).unwrap();
            let mut fb = Strip::<P>::new(&mut color, Some(&mut depth), w, h, 0, h).unwrap();
            frame
                .draw::<fixshade::raster::span::Gradient, _>(&mut fb)
                .unwrap();
            color
                .iter()
                .flat_map(|p| P::bytes(*p).into_iter().take(P::BYTES))
                .collect()
        }
        let ls = load_arg("teapot").unwrap();
        let le = bytes::<Rgb565Le>(&ls);
        assert!(le.chunks(2).any(|p| p[0] != p[1]));
        assert_eq!(swapped(le, true), bytes::<Rgb565Be>(&ls));
    }
}
