//! The sphere benchmark as a table: per configuration and span method, the median
//! time of one frame, covered pixels per frame, the cost per covered pixel and per
//! submitted triangle, and each method's time relative to `classic` and to
//! `gradient`. The rows are the core's registry: every span method with Gouraud
//! shading, then the shadings with fills of their own (quadratic, the two Phong
//! fills, adaptive), run with the scene's shading switched, then `cleared` and
//! `bands-16`. `cleared` is `gradient` with the frame's colour and depth cleared
//! inside the timed part, as a firmware with a whole framebuffer does every frame.
//! `bands-16` is `gradient` drawn by the core's band loop (`render_lines` of
//! `fixshade::present::linebuf`, what a firmware with a small band buffer runs) in
//! bands of 16 rows, binned once per frame with a record and a walk per triangle. Its time
//! includes binning and clearing each band's colour and depth (the other rows'
//! depth reset is outside the timed part); the band buffer is not copied out. The
//! line after each configuration gives `bands-16` against `cleared` (paired
//! per round, as the ratio columns): the band loop against the whole frame, both
//! with their clears. `bands-16` and `cleared`
//! draws with the plain `Gradient` (records need the exact setup as a type, see
//! `SpanMethod::RECORDS`), where the `gradient` row takes the dispatch's
//! `WithDivide<Gradient, HostDivide>` with the exact divider selected: the same
//! pixels (the pixel counts are compared).
//!
//! The scene of `benches/bench_sphere.rs`: the built-in scene "bench-sphere" with
//! segments 32×20, 64×40, 128×80 at 320×240 and 640×480. One frame is what the
//! simulator runs for `fixshade render` and the report: the vertex stage and the
//! draw of the core (`Frame::prepare_with`, `Frame::draw_with`), chosen once per
//! row by the simulator's dispatch (`fixshade_sim::render::Pipeline`), into an
//! Rgb565 frame that records coverage; the depth buffer is reset to 0xFFFF before
//! each frame, outside the timed part; the sphere turns about y by 7° from one round
//! to the next.
//!
//! The methods are interleaved: every round draws the same angle once with each
//! method, starting with a different method each round (AB, BA, AB, … for two), so
//! drifts in machine speed hit all methods alike. The ratio columns are the medians
//! of the per-round ratios `t(method) / t(classic)` and `t(method) / t(gradient)`,
//! i.e. paired within a round.
//!
//! Run: `cargo run --release -p fixshade-sim --example bench_table [-- FRAMES [CONFIG
//! [METHODS]]]` (FRAMES per method and configuration, default 201, at least 50;
//! CONFIG such as `128x80@320x240` runs that configuration only, `all` every one;
//! METHODS such as `classic,gradient,phong` runs those rows only, in table order,
//! the first of them being the baseline of both ratio columns if `classic` or
//! `gradient` is left out).
//!
//! The default build targets any x86-64 (SSE2). Built for the CPU it runs on,
//! `RUSTFLAGS="-C target-cpu=native" cargo run --release -p fixshade-sim --example
//! bench_table`, a core with AVX-512 (BW and VL) turns the packed, depth-tested pixel
//! loop of `gradient` (and of the methods that share it) into vector lanes of eight
//! pixels with masked 16-bit stores, which shortens the fill-bound frames; the frames
//! are the same, bit for bit (integer arithmetic only). The flag applies to the whole
//! build, so use a separate `CARGO_TARGET_DIR` to keep the portable build's cache.

use std::ops::Range;
use std::path::Path;
use std::time::Instant;

use fixshade::fixed::Angle;
use fixshade::present::eg::{Covered, CoveredPixel};
use fixshade::present::linebuf::{render_lines, LineBufferProvider};
use fixshade::raster::setup::Record;
use fixshade::raster::span::Gradient;
use fixshade::raster::Walk;
use fixshade::render::BandMemory;
use fixshade::target::{Rgb565Le, Strip};
use fixshade_sim::render::dispatch::DepthStrip;
use fixshade_sim::render::Pipeline;
use fixshade_sim::scene::builtin;
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::desc::{MeshSource, Named, SceneDesc, ShadingName, SpanName};
use fixshade_sim::scene::load::load;

/// The pipeline of one row: the simulator's dispatch for the scene (Rgb565Le, the
/// exact specular term of the scene, run-time chosen as `fixshade render` does).
type Row = Pipeline<Rgb565Le>;

/// Rows per band of the `bands-16` row.
const BAND_ROWS: u32 = 16;

/// How a row draws its frame.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Layout {
    /// Into the whole frame, depth reset outside the timed part.
    Whole,
    /// Into the whole frame, colour and depth cleared inside the timed part.
    Cleared,
    /// Through the core's band loop, in bands of [`BAND_ROWS`] rows.
    Bands,
}

/// The rows compared, as (name, span method, shading, layout); the first
/// two are the baselines of the ratio columns: every span method of the core's
/// registry with Gouraud shading, then every shading mode with a fill of its own
/// (which ignore the span method), with `gradient`, then `gradient` cleared and in
/// bands.
fn methods() -> Vec<(&'static str, SpanName, ShadingName, Layout)> {
    let mut rows: Vec<_> = SpanName::ALL
        .iter()
        .map(|&(s, name)| (name, s, ShadingName::GOURAUD, Layout::Whole))
        .collect();
    rows.extend(
        ShadingName::ALL
            .iter()
            .filter(|(sh, _)| sh.own_fill())
            .map(|&(sh, name)| (name, SpanName::GRADIENT, sh, Layout::Whole)),
    );
    rows.push((
        "cleared",
        SpanName::GRADIENT,
        ShadingName::GOURAUD,
        Layout::Cleared,
    ));
    rows.push((
        "bands-16",
        SpanName::GRADIENT,
        ShadingName::GOURAUD,
        Layout::Bands,
    ));
    rows
}

/// A display fed band by band: one band buffer, drawn and not sent.
struct Bands {
    size: (u32, u32),
    buffer: Vec<CoveredPixel<u16>>,
}

impl LineBufferProvider for Bands {
    type Format = Covered<Rgb565Le>;
    fn size(&self) -> (u32, u32) {
        self.size
    }
    fn process_lines(&mut self, lines: Range<u32>, render: impl FnOnce(&mut [CoveredPixel<u16>])) {
        let n = self.size.0 as usize * lines.len();
        render(&mut self.buffer[..n]);
        std::hint::black_box(&self.buffer[..n]);
    }
}

const SEGMENTS: [(u32, u32); 3] = [(32, 20), (64, 40), (128, 80)];
const SIZES: [(u32, u32); 2] = [(320, 240), (640, 480)];
const STEP_DEG: i32 = 7;
const WARMUP_ROUNDS: usize = 5;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

fn main() {
    let frames: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("FRAMES must be a number"))
        .unwrap_or(201)
        .max(50);
    let only = std::env::args().nth(2).filter(|c| c != "all");
    let all = methods();
    let chosen: Vec<usize> = match std::env::args().nth(3) {
        Some(list) => {
            let names: Vec<&str> = list.split(',').collect();
            (0..all.len())
                .filter(|&k| names.contains(&all[k].0))
                .collect()
        }
        None => (0..all.len()).collect(),
    };
    assert!(!chosen.is_empty(), "no method of that name");
    let base_of = |name: &str| chosen.iter().position(|&k| all[k].0 == name).unwrap_or(0);
    let (b_classic, b_gradient) = (
        base_of(SpanName::CLASSIC.name()),
        base_of(SpanName::GRADIENT.name()),
    );
    let m = chosen.len();
    println!(
        "bench-sphere: median of {frames} frames per method, methods interleaved, \
         depth reset outside the timed part"
    );
    println!(
        "{:<9} {:<8} {:>6} {:<16} {:>11} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "segments",
        "size",
        "tris",
        "method",
        "ns/frame",
        "px/frame",
        "ns/px",
        "ns/tri",
        "/classic",
        "/gradient"
    );
    for (lon, lat) in SEGMENTS {
        for (w, h) in SIZES {
            if only
                .as_deref()
                .is_some_and(|o| o != format!("{lon}x{lat}@{w}x{h}"))
            {
                continue;
            }
            let mut d = builtin::scene("bench-sphere").expect("built-in scene bench-sphere");
            d.width = w;
            d.height = h;
            d.objects[0].mesh = MeshSource::Sphere { lon, lat };
            let ls = load("bench-sphere", &d, Path::new(".")).expect("load bench-sphere");
            let mut scene = core_scene(&ls.desc, &ls.fixed).expect("core scene");
            let rows: Vec<Row> = chosen
                .iter()
                .map(|&k| {
                    let d = SceneDesc {
                        span: all[k].1,
                        shading: all[k].2,
                        ..ls.desc.clone()
                    };
                    Row::new(&d).expect("a raster pipeline")
                })
                .collect();
            let n = (w * h) as usize;
            let mut cache = vec![fixshade::render::XfVertex::default(); scene.vertex_count()];
            let mut color = vec![CoveredPixel::<u16>::default(); n];
            let mut depth = vec![0xFFFFu16; n];
            // The band memory: a record and a walk per triangle.
            let records = scene
                .objects
                .iter()
                .map(|o| o.mesh.triangles().len())
                .sum::<usize>();
            let mut record = vec![Record::EMPTY; records];
            let mut walk = vec![Walk::EMPTY; records];
            let mut index = vec![0u16; BandMemory::index_len(records, h, BAND_ROWS, h)];
            let mut starts = vec![0u32; BandMemory::starts_len(h, BAND_ROWS)];
            let mut band_depth = vec![0xFFFFu16; w as usize * BAND_ROWS as usize];
            let mut bands = Bands {
                size: (w, h),
                buffer: vec![CoveredPixel::default(); w as usize * BAND_ROWS as usize],
            };

            // times[method][round], pixels[method] summed, triangles per frame.
            let mut times = vec![Vec::with_capacity(frames); m];
            let mut pixels = vec![0u64; m];
            let mut tris = 0u32;
            for round in 0..WARMUP_ROUNDS + frames {
                let deg = (round as i32 * STEP_DEG) % 360;
                scene.objects[0].placement.rotate[1] = Angle::from_degrees(deg);
                for j in 0..m {
                    let k = (round + j) % m;
                    scene.shading = all[chosen[k]].2.core().expect("a raster shading");
                    depth.fill(0xFFFF);
                    let mut fb = Strip::new(&mut color, Some(&mut depth), w, h, 0, h).unwrap();
                    let layout = all[chosen[k]].3;
                    let t = Instant::now();
                    if layout == Layout::Cleared {
                        fb.clear(CoveredPixel::default());
                    }
                    let frame = rows[k].prepare(&scene, w, h, &mut cache).expect("prepare");
                    let st = if layout == Layout::Bands {
                        let mem = BandMemory::new(&mut record, &mut index, &mut starts)
                            .with_walks(&mut walk);
                        let st = rows[k].selected(|| {
                            render_lines::<Gradient, _, _, _>(
                                &frame,
                                BAND_ROWS,
                                mem,
                                Some(&mut band_depth[..]),
                                CoveredPixel::default(),
                                &mut bands,
                            )
                            .expect("draw in bands")
                        });
                        assert_eq!(st.rewalked, 0, "every band drawn from the records");
                        std::hint::black_box(st)
                    } else {
                        std::hint::black_box(
                            rows[k]
                                .draw(&frame, DepthStrip::D16(&mut fb))
                                .expect("draw"),
                        )
                    };
                    let ns = t.elapsed().as_nanos() as f64;
                    if round >= WARMUP_ROUNDS {
                        times[k].push(ns);
                        pixels[k] += u64::from(st.pixels);
                        tris = st.triangles;
                    }
                }
            }
            // The bands cover the pixels the whole frame covers.
            let row = |name: &str| (0..m).find(|&k| all[chosen[k]].0 == name);
            for name in ["bands-16", "cleared"] {
                if let (Some(b), Some(g)) = (row(name), row(SpanName::GRADIENT.name())) {
                    assert_eq!(
                        pixels[b], pixels[g],
                        "{name} and gradient cover different pixels"
                    );
                }
            }
            // Median of the per-round ratios t(k) / t(base).
            let ratio_of = |k: usize, base: usize| {
                let mut r: Vec<f64> = times[k]
                    .iter()
                    .zip(&times[base])
                    .map(|(t, b)| t / b)
                    .collect();
                median(&mut r)
            };
            for k in 0..m {
                let ratio = |base: usize| ratio_of(k, base);
                let t = median(&mut times[k].clone());
                let px = pixels[k] as f64 / frames as f64;
                println!(
                    "{:<9} {:<8} {:>6} {:<16} {:>11.0} {:>9.0} {:>9.2} {:>9.1} {:>9.3} {:>9.3}",
                    format!("{lon}x{lat}"),
                    format!("{w}x{h}"),
                    tris,
                    all[chosen[k]].0,
                    t,
                    px,
                    t / px,
                    t / f64::from(tris),
                    ratio(b_classic),
                    ratio(b_gradient)
                );
            }
            if let (Some(b), Some(c)) = (row("bands-16"), row("cleared")) {
                println!(
                    "{:<9} {:<8} bands-16 / cleared: {:.3}",
                    format!("{lon}x{lat}"),
                    format!("{w}x{h}"),
                    ratio_of(b, c)
                );
            }
        }
    }
}
