//! The sphere benchmark (divan): one frame of the built-in scene "bench-sphere" —
//! a UV sphere of radius 1 at z = −3 seen from the origin (fovy 45°, near 1, far 10),
//! one directional light, Blinn n = 32, Gouraud, back-face culling, u16 depth,
//! RGB565 little-endian.
//!
//! Varied: segments (32×20, 64×40, 128×80 → 1216 / 4992 / 20224 triangles) ×
//! resolution (320×240, 640×480) × span method. The sphere turns about y by 7° from
//! one frame to the next (a ring of 360 angles; the model matrix is rebuilt by
//! `prepare` anyway, so turning costs one store).
//!
//! Timed: `Frame::prepare` (vertex stage) + `Frame::draw` (clip, cull, rasterize).
//! Not timed: resetting the depth buffer to 0xFFFF, done by the input generator
//! before each frame (every sample is one frame, `sample_size = 1`; should divan
//! ever batch several frames into a sample, the later ones reset inside the timed
//! part). The colour buffer is not cleared: with the depth reset every pixel of
//! the sphere is written anyway.
//!
//! Two groups with the same frames and different throughput counters:
//! `pixels` counts covered pixels (rasterized, before the depth test; for one
//! convex object with culling that is the sphere's coverage), `triangles` counts
//! triangles submitted.
//!
//! Run: `cargo bench -p fixshade-sim --bench bench_sphere` (add a filter such as
//! `-- 128x80` to run part of it). For a table with per-pixel and per-triangle
//! costs and paired ratios between methods see `examples/bench_table.rs`.

use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::fmt;
use std::path::Path;
use std::sync::{Arc, Mutex, OnceLock};

use divan::counter::ItemsCount;
use divan::Bencher;
use fixshade::fixed::Angle;
use fixshade::raster::span::{Classic, Gradient, SpanMethod};
use fixshade::render::{Frame, XfVertex};
use fixshade::target::{Framebuffer, Rgb565Le};
use fixshade_sim::scene::builtin;
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::desc::MeshSource;
use fixshade_sim::scene::load::{load, LoadedScene};

fn main() {
    divan::main();
}

/// Frames per benchmark (one frame per sample).
const FRAMES: u32 = 200;

/// Rotation step between frames, degrees; 7 and 360 are coprime, so the ring holds
/// every whole degree.
const STEP_DEG: usize = 7;

/// One benchmark configuration.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
struct Config {
    lon: u32,
    lat: u32,
    w: u32,
    h: u32,
}

impl fmt::Display for Config {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}x{}@{}x{}", self.lon, self.lat, self.w, self.h)
    }
}

fn configs() -> Vec<Config> {
    let mut v = Vec::new();
    for (lon, lat) in [(32, 20), (64, 40), (128, 80)] {
        for (w, h) in [(320, 240), (640, 480)] {
            v.push(Config { lon, lat, w, h });
        }
    }
    v
}

/// A configuration loaded once and shared by all its benchmarks: the quantised
/// scene and meshes, and per angle (whole degrees) the pixels a frame covers.
struct Prepared {
    ls: LoadedScene,
    triangles: u32,
    pixels: Vec<u32>,
}

fn prepared(cfg: Config) -> Arc<Prepared> {
    static CACHE: OnceLock<Mutex<HashMap<Config, Arc<Prepared>>>> = OnceLock::new();
    let mut map = CACHE.get_or_init(Default::default).lock().unwrap();
    map.entry(cfg)
        .or_insert_with(|| Arc::new(prepare(cfg)))
        .clone()
}

fn prepare(cfg: Config) -> Prepared {
    let mut d = builtin::scene("bench-sphere").expect("built-in scene bench-sphere");
    d.width = cfg.w;
    d.height = cfg.h;
    d.objects[0].mesh = MeshSource::Sphere {
        lon: cfg.lon,
        lat: cfg.lat,
    };
    let ls = load("bench-sphere", &d, Path::new(".")).expect("load bench-sphere");
    let mut scene = core_scene(&ls.desc, &ls.fixed).expect("core scene");
    let n = (cfg.w * cfg.h) as usize;
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let mut color = vec![0u16; n];
    let mut depth = vec![0xFFFFu16; n];
    let mut triangles = 0;
    let mut pixels = Vec::with_capacity(360);
    for deg in 0..360 {
        scene.objects[0].placement.rotate[1] = Angle::from_degrees(deg);
        depth.fill(0xFFFF);
        let frame = Frame::<Rgb565Le>::prepare(&scene, cfg.w, cfg.h, &mut cache).unwrap();
        let mut fb =
            Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), cfg.w, cfg.h).unwrap();
        let st = frame.draw::<Gradient, _>(&mut fb).unwrap();
        triangles = st.triangles;
        pixels.push(st.pixels);
    }
    drop(scene);
    Prepared {
        ls,
        triangles,
        pixels,
    }
}

/// What the throughput counter counts.
#[derive(Copy, Clone)]
enum Unit {
    Pixels,
    Triangles,
}

fn run<S: SpanMethod>(bencher: Bencher, cfg: &Config, unit: Unit) {
    let cfg = *cfg;
    let p = prepared(cfg);
    let mut scene = core_scene(&p.ls.desc, &p.ls.fixed).unwrap();
    let (w, h) = (cfg.w, cfg.h);
    let n = (w * h) as usize;
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let mut color = vec![0u16; n];
    let depth = RefCell::new(vec![0xFFFFu16; n]);
    let fresh = Cell::new(false);
    let mut k = 0usize;
    // The input is the angle in degrees; generating it resets the depth buffer.
    let b = bencher.with_inputs(|| {
        let deg = (k * STEP_DEG) % 360;
        k += 1;
        depth.borrow_mut().fill(0xFFFF);
        fresh.set(true);
        deg
    });
    let b = match unit {
        Unit::Pixels => {
            let p = p.clone();
            b.input_counter(move |&deg: &usize| ItemsCount::new(p.pixels[deg]))
        }
        Unit::Triangles => b.counter(ItemsCount::new(p.triangles)),
    };
    b.bench_local_refs(|&mut deg| {
        let mut d = depth.borrow_mut();
        if !fresh.replace(false) {
            d.fill(0xFFFF);
        }
        scene.objects[0].placement.rotate[1] = Angle::from_degrees(deg as i32);
        let frame = Frame::<Rgb565Le>::prepare(&scene, w, h, &mut cache).unwrap();
        let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut d[..]), w, h).unwrap();
        frame.draw::<S, _>(&mut fb).unwrap()
    });
}

/// Defines both groups over the span methods listed once: to benchmark a new method,
/// add its type here.
macro_rules! sphere_benches {
    ($($method:ident),+ $(,)?) => {
        /// Throughput in covered pixels per second.
        #[divan::bench(types = [$($method),+], args = configs(), sample_count = FRAMES, sample_size = 1)]
        fn pixels<S: SpanMethod>(bencher: Bencher, cfg: &Config) {
            run::<S>(bencher, cfg, Unit::Pixels);
        }

        /// Throughput in triangles submitted per second.
        #[divan::bench(types = [$($method),+], args = configs(), sample_count = FRAMES, sample_size = 1)]
        fn triangles<S: SpanMethod>(bencher: Bencher, cfg: &Config) {
            run::<S>(bencher, cfg, Unit::Triangles);
        }
    };
}

sphere_benches!(Classic, Gradient);
