//! The sphere benchmark as a table: per configuration and span method, the median
//! time of one frame, covered pixels per frame, the cost per covered pixel and per
//! submitted triangle, and each method's time relative to `classic` and to
//! `gradient`. The quadratic surface and the two Phong fills (which ignore the span
//! method) are rows of their own, run with the scene's shading switched.
//!
//! Same scene and timed part as `benches/bench_sphere.rs`: the built-in scene
//! "bench-sphere" with segments 32×20, 64×40, 128×80 at 320×240 and 640×480; one
//! frame = `Frame::prepare` + `Frame::draw`; the depth buffer is reset to 0xFFFF
//! before each frame, outside the timed part; the sphere turns about y by 7° from
//! one round to the next.
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

use std::path::Path;
use std::time::Instant;

use fixshade::fixed::Angle;
use fixshade::raster::parallel::{Counter, EvenOdd, KWay, Segment};
use fixshade::raster::sierpinski::{Sierpinski, SierpinskiExact};
use fixshade::raster::span::{Classic, Gradient, SpanMethod};
use fixshade::render::{Frame, Stats, XfVertex};
use fixshade::scene::{Scene, ShadingMode};
use fixshade::target::{Framebuffer, Rgb565Le};
use fixshade_sim::scene::builtin;
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::desc::MeshSource;
use fixshade_sim::scene::load::load;

/// One timed frame: vertex stage + rasterization into `fb`.
type FrameFn = fn(&Scene<'_>, &mut [XfVertex], &mut Framebuffer<'_, Rgb565Le>) -> Stats;

fn frame<S: SpanMethod>(
    scene: &Scene<'_>,
    cache: &mut [XfVertex],
    fb: &mut Framebuffer<'_, Rgb565Le>,
) -> Stats {
    use fixshade::target::Target;
    let (w, h) = (fb.width(), fb.frame_height());
    let f = Frame::<Rgb565Le>::prepare(scene, w, h, cache).expect("prepare");
    f.draw::<S, _>(fb).expect("draw")
}

/// The methods compared, with the shading each runs under; the first two are the
/// baselines of the ratio columns. To add a method, add a line.
const METHODS: &[(&str, FrameFn, ShadingMode)] = &[
    (<Classic>::NAME, frame::<Classic>, ShadingMode::Gouraud),
    (Gradient::NAME, frame::<Gradient>, ShadingMode::Gouraud),
    (EvenOdd::NAME, frame::<EvenOdd>, ShadingMode::Gouraud),
    (KWay::<2>::NAME, frame::<KWay<2>>, ShadingMode::Gouraud),
    (KWay::<3>::NAME, frame::<KWay<3>>, ShadingMode::Gouraud),
    (KWay::<4>::NAME, frame::<KWay<4>>, ShadingMode::Gouraud),
    (Counter::NAME, frame::<Counter>, ShadingMode::Gouraud),
    (
        Segment::<2>::NAME,
        frame::<Segment<2>>,
        ShadingMode::Gouraud,
    ),
    (
        Segment::<4>::NAME,
        frame::<Segment<4>>,
        ShadingMode::Gouraud,
    ),
    (
        Segment::<8>::NAME,
        frame::<Segment<8>>,
        ShadingMode::Gouraud,
    ),
    (
        Segment::<16>::NAME,
        frame::<Segment<16>>,
        ShadingMode::Gouraud,
    ),
    (
        Segment::<32>::NAME,
        frame::<Segment<32>>,
        ShadingMode::Gouraud,
    ),
    (
        Segment::<64>::NAME,
        frame::<Segment<64>>,
        ShadingMode::Gouraud,
    ),
    (Sierpinski::NAME, frame::<Sierpinski>, ShadingMode::Gouraud),
    (
        SierpinskiExact::NAME,
        frame::<SierpinskiExact>,
        ShadingMode::Gouraud,
    ),
    ("quadratic", frame::<Gradient>, ShadingMode::Quadratic),
    ("phong", frame::<Gradient>, ShadingMode::Phong),
    (
        "phong-even-odd",
        frame::<Gradient>,
        ShadingMode::PhongEvenOdd,
    ),
];

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
    let chosen: Vec<usize> = match std::env::args().nth(3) {
        Some(list) => {
            let names: Vec<&str> = list.split(',').collect();
            (0..METHODS.len())
                .filter(|&k| names.contains(&METHODS[k].0))
                .collect()
        }
        None => (0..METHODS.len()).collect(),
    };
    assert!(!chosen.is_empty(), "no method of that name");
    let base_of = |name: &str| {
        chosen
            .iter()
            .position(|&k| METHODS[k].0 == name)
            .unwrap_or(0)
    };
    let (b_classic, b_gradient) = (base_of(<Classic>::NAME), base_of(Gradient::NAME));
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
            let n = (w * h) as usize;
            let mut cache = vec![XfVertex::default(); scene.vertex_count()];
            let mut color = vec![0u16; n];
            let mut depth = vec![0xFFFFu16; n];

            // times[method][round], pixels[method] summed, triangles per frame.
            let mut times = vec![Vec::with_capacity(frames); m];
            let mut pixels = vec![0u64; m];
            let mut tris = 0u32;
            for round in 0..WARMUP_ROUNDS + frames {
                let deg = (round as i32 * STEP_DEG) % 360;
                scene.objects[0].placement.rotate[1] = Angle::from_degrees(deg);
                for j in 0..m {
                    let k = (round + j) % m;
                    scene.shading = METHODS[chosen[k]].2;
                    depth.fill(0xFFFF);
                    let mut fb =
                        Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), w, h).unwrap();
                    let t = Instant::now();
                    let st =
                        std::hint::black_box((METHODS[chosen[k]].1)(&scene, &mut cache, &mut fb));
                    let ns = t.elapsed().as_nanos() as f64;
                    if round >= WARMUP_ROUNDS {
                        times[k].push(ns);
                        pixels[k] += u64::from(st.pixels);
                        tris = st.triangles;
                    }
                }
            }
            for k in 0..m {
                let ratio = |base: usize| {
                    let mut r: Vec<f64> = times[k]
                        .iter()
                        .zip(&times[base])
                        .map(|(t, b)| t / b)
                        .collect();
                    median(&mut r)
                };
                let t = median(&mut times[k].clone());
                let px = pixels[k] as f64 / frames as f64;
                println!(
                    "{:<9} {:<8} {:>6} {:<16} {:>11.0} {:>9.0} {:>9.2} {:>9.1} {:>9.3} {:>9.3}",
                    format!("{lon}x{lat}"),
                    format!("{w}x{h}"),
                    tris,
                    METHODS[chosen[k]].0,
                    t,
                    px,
                    t / px,
                    t / f64::from(tris),
                    ratio(b_classic),
                    ratio(b_gradient)
                );
            }
        }
    }
}
