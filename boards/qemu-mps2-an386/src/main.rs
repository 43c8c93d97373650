//! fixshade on QEMU's mps2-an386 (Cortex-M4F at 25 MHz, 4 MiB RAM): renders every
//! built-in figure with every span method into a whole framebuffer (Rgb565
//! little-endian, u16 depth), writes each frame to the host file
//! `<figure>-<method>.rgb565` through semihosting, logs a `FRAME` line with its
//! instruction counts, and exits with status 0 (1 on a render error).
//!
//! Run: `cargo run --release` in this directory (needs `qemu-system-arm`); the frame
//! files land in the current directory. `cargo xtask qemu` runs it and compares every
//! frame with the host.
#![no_std]
#![no_main]

use core::ffi::CStr;
use core::fmt::Write as _;

use cortex_m_rt::{entry, exception};
use fixshade::clip::signed_area;
use fixshade::geometry::MeshError;
use fixshade::raster::setup::setup;
use fixshade::render::{Frame, XfVertex, NEEDED, OUTSIDE};
use fixshade::scene::Scene;
use fixshade::target::{Framebuffer, PixelFormat, Rgb565Le};
use fixshade_boards_common::{cases, Counter, FrameLog, SceneSettings};
use semihosting::io::Write as _;

/// The built-in scenes, baked by `fixshade bake` (see `boards/baked/README.md`).
mod baked {
    pub(crate) use super::{bench_sphere, robot, sphere, teapot};
}
#[path = "../../baked/full/bench_sphere.rs"]
mod bench_sphere;
#[path = "../../baked/full/robot.rs"]
mod robot;
#[path = "../../baked/full/sphere.rs"]
mod sphere;
#[path = "../../baked/full/teapot.rs"]
mod teapot;

const BOARD: &str = "mps2-an386";
/// The core clock SysTick counts (QEMU's mps2 SYSCLK).
const CORE_HZ: u32 = 25_000_000;
/// QEMU's `-icount shift`, as in `.cargo/config.toml`.
const ICOUNT_SHIFT: u32 = 10;

/// A figure: its name on the host, its baked scene and its frame size.
struct Figure {
    name: &'static str,
    scene: fn() -> Result<Scene<'static>, MeshError>,
    width: u32,
    height: u32,
    background: [u32; 3],
}

const FIGURES: [Figure; 4] = [
    Figure {
        name: "sphere",
        scene: baked::sphere::scene,
        width: baked::sphere::WIDTH,
        height: baked::sphere::HEIGHT,
        background: baked::sphere::BACKGROUND,
    },
    Figure {
        name: "teapot",
        scene: baked::teapot::scene,
        width: baked::teapot::WIDTH,
        height: baked::teapot::HEIGHT,
        background: baked::teapot::BACKGROUND,
    },
    Figure {
        name: "robot",
        scene: baked::robot::scene,
        width: baked::robot::WIDTH,
        height: baked::robot::HEIGHT,
        background: baked::robot::BACKGROUND,
    },
    // The benchmark's fill-bound case: 32 x 20 segments at 640 x 480.
    Figure {
        name: "bench-sphere",
        scene: baked::bench_sphere::scene,
        width: 640,
        height: 480,
        background: baked::bench_sphere::BACKGROUND,
    },
];

const MAX_PIXELS: usize = 640 * 480;
/// Vertices of the largest baked mesh (the teapot).
const MAX_VERTICES: usize = baked::teapot::MAX_CHUNK_VERTICES;

static mut COLOR: [u16; MAX_PIXELS] = [0; MAX_PIXELS];
static mut DEPTH: [u16; MAX_PIXELS] = [0; MAX_PIXELS];
static mut CACHE: [XfVertex; MAX_VERTICES] = [XfVertex {
    s: fixshade::raster::ScreenVertex {
        x: 0,
        y: 0,
        z: 0,
        c: [0; 3],
    },
    flags: 0,
}; MAX_VERTICES];

/// The semihosting console as a `core::fmt::Write`.
struct Console;

impl core::fmt::Write for Console {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        semihosting::print!("{s}");
        Ok(())
    }
}

#[exception]
fn SysTick() {
    fixshade_boards_common::on_systick();
}

/// `<figure>-<case>.rgb565` as a C string in `buf`.
fn file_name<'b>(buf: &'b mut [u8; 64], figure: &str, case: &str) -> &'b CStr {
    let mut n = 0;
    for part in [figure.as_bytes(), b"-", case.as_bytes(), b".rgb565"] {
        buf[n..n + part.len()].copy_from_slice(part);
        n += part.len();
    }
    buf[n] = 0;
    // One NUL at the end, none inside: names are ASCII identifiers.
    CStr::from_bytes_with_nul(&buf[..=n]).unwrap_or(c"frame.rgb565")
}

fn run() -> Result<(), &'static str> {
    let cp = cortex_m::Peripherals::take().ok_or("peripherals taken twice")?;
    let mut counter = Counter::start(cp.SYST, CORE_HZ, ICOUNT_SHIFT);
    // SAFETY-free from here on: the only references to the buffers are these, taken
    // once before any use.
    #[allow(unsafe_code)]
    let (color, depth, cache) = unsafe {
        (
            &mut *core::ptr::addr_of_mut!(COLOR),
            &mut *core::ptr::addr_of_mut!(DEPTH),
            &mut *core::ptr::addr_of_mut!(CACHE),
        )
    };

    fixshade_boards_common::calibrate(&mut counter, &mut Console, BOARD);

    for fig in &FIGURES {
        let scene = (fig.scene)().map_err(|_| "baked mesh rejected")?;
        let (w, h) = (fig.width, fig.height);
        let n = (w * h) as usize;
        let bg = Rgb565Le::pack(fig.background[0], fig.background[1], fig.background[2]);
        let mut fb = Framebuffer::<Rgb565Le>::new(&mut color[..n], Some(&mut depth[..n]), w, h)
            .map_err(|_| "framebuffer")?;
        for (case, draw) in cases::<SceneSettings, Rgb565Le, Framebuffer<'_, Rgb565Le>>() {
            fb.clear(bg);
            let (frame, prepare) =
                counter.measure(|| Frame::<Rgb565Le>::prepare(&scene, w, h, &mut cache[..]));
            let frame = frame.map_err(|_| "prepare failed")?;
            let (stats, draw) = counter.measure(|| draw(&frame, &mut fb));
            let log = FrameLog {
                width: w,
                height: h,
                prepare,
                draw,
                stats: stats.map_err(|_| "draw failed")?,
            };
            let _ = log.write(&mut Console, BOARD, fig.name, case);
            let mut name = [0u8; 64];
            let mut f = semihosting::fs::File::create(file_name(&mut name, fig.name, case))
                .map_err(|_| "cannot create the frame file")?;
            let bytes: &[u8] = bytemuck_u16(&fb.color()[..n]);
            f.write_all(bytes)
                .map_err(|_| "cannot write the frame file")?;
        }
        if fig.name == "bench-sphere" {
            setup_cost(&scene, w, h, cache, &mut counter)?;
        }
    }
    Ok(())
}

/// The frame's bytes in memory order (Rgb565Le keeps little-endian bytes in each
/// `u16`, the M4 is little-endian).
fn bytemuck_u16(p: &[u16]) -> &[u8] {
    // SAFETY: u16 has no padding and every byte pattern is a valid u8; the length in
    // bytes is twice the length in u16; alignment of u8 is 1.
    #[allow(unsafe_code)]
    unsafe {
        core::slice::from_raw_parts(p.as_ptr().cast::<u8>(), p.len() * 2)
    }
}

/// Instructions of triangle setup alone: the same loop over the frame's drawable
/// front faces with and without the call to `setup`, the difference divided by the
/// triangles. Logged as `SETUP board figure triangles with without`.
fn setup_cost(
    scene: &Scene<'_>,
    w: u32,
    h: u32,
    cache: &mut [XfVertex],
    counter: &mut Counter,
) -> Result<(), &'static str> {
    let frame =
        Frame::<Rgb565Le>::prepare(scene, w, h, &mut cache[..]).map_err(|_| "prepare failed")?;
    drop(frame);
    let mesh = &scene.objects[0].mesh;
    let n_vert = mesh.positions().len();
    let verts = &cache[..n_vert];
    let pass = |with: bool, counter: &mut Counter| {
        let mut n = 0u32;
        let ((), cost) = counter.measure(|| {
            for t in mesh.triangles() {
                let v = t.map(|i| verts[i as usize]);
                if v.iter()
                    .any(|x| x.flags & OUTSIDE != 0 || x.flags & NEEDED == 0)
                {
                    continue;
                }
                let s = v.map(|x| x.s);
                if signed_area((s[0].x, s[0].y), (s[1].x, s[1].y), (s[2].x, s[2].y)) >= 0 {
                    continue;
                }
                n += 1;
                if with {
                    core::hint::black_box(setup(core::hint::black_box(s)));
                } else {
                    core::hint::black_box(core::hint::black_box(s));
                }
            }
        });
        (n, cost)
    };
    let (n, with) = pass(true, counter);
    let (_, without) = pass(false, counter);
    let _ = writeln!(Console, "SETUP {BOARD} bench-sphere {n} {with} {without}");
    Ok(())
}

#[entry]
fn main() -> ! {
    match run() {
        Ok(()) => {
            let _ = writeln!(Console, "DONE {BOARD}");
            semihosting::process::exit(0)
        }
        Err(e) => {
            let _ = writeln!(Console, "ERROR {BOARD}: {e}");
            semihosting::process::exit(1)
        }
    }
}
