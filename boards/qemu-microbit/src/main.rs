//! fixshade on QEMU's microbit (nRF51, Cortex-M0 at 16 MHz, 16 KiB RAM): renders
//! one built-in figure (chosen by a cargo feature) with every span method, strip by
//! strip, and streams each strip to the host file `<figure>-<method>.rgb565`
//! through semihosting; logs a `FRAME` line per frame with its instruction counts and
//! exits with status 0 (1 on a render error).
//!
//! A 320×240 frame (150 KiB of colour) does not fit in 16 KiB, and neither does a
//! vertex cache for a whole mesh (28 bytes per vertex: 58 KiB for the teapot). So:
//!
//! - the target is a [`Strip`] of `STRIP_PIXELS / width` rows with its own depth
//!   rows, drawn once per strip;
//! - the mesh is baked in chunks of consecutive triangles that use at most
//!   `MAX_CHUNK_VERTICES` vertices each (`fixshade bake --chunk`), and the vertex
//!   stage runs per chunk into a chunk-sized cache. A first pass per frame records
//!   each chunk's screen rows; a strip then runs the vertex stage and the draw only
//!   for the chunks whose rows reach it. Every vertex is transformed and lit by the
//!   same arithmetic whatever chunk it is in, and triangles are drawn in the mesh's
//!   order, so the frame has the host's bytes; the vertex stage is simply repeated
//!   (its instructions are in the `prepare` column).
//!
//! Run: `cargo run --release --no-default-features --features teapot` in this
//! directory (default: sphere); frame files land in the current directory.
#![no_std]
#![no_main]

use core::ffi::CStr;
use core::fmt::Write as _;

use cortex_m_rt::{entry, exception};
use fixshade::raster::span::DepthTest;
use fixshade::render::{Frame, Stats, XfVertex, OUTSIDE};
use fixshade::scene::Scene;
use fixshade::scene::ShadingMode;
use fixshade::shade::Gouraud;
use fixshade::target::{PixelFormat, Rgb565Le, Strip, Target};
use fixshade_boards_common::{cases, Counter, DrawFn, Fixed, FrameLog};
use semihosting::io::Write as _;

#[cfg(feature = "sphere")]
#[path = "../../baked/chunk/sphere.rs"]
mod fig;
#[cfg(feature = "sphere")]
const FIGURE: (&str, u32, u32) = ("sphere", fig::WIDTH, fig::HEIGHT);

#[cfg(feature = "teapot")]
#[path = "../../baked/chunk/teapot.rs"]
mod fig;
#[cfg(feature = "teapot")]
const FIGURE: (&str, u32, u32) = ("teapot", fig::WIDTH, fig::HEIGHT);

#[cfg(feature = "robot")]
#[path = "../../baked/chunk/robot.rs"]
mod fig;
#[cfg(feature = "robot")]
const FIGURE: (&str, u32, u32) = ("robot", fig::WIDTH, fig::HEIGHT);

// The benchmark's fill-bound case: 32 x 20 segments at 640 x 480.
#[cfg(feature = "bench-sphere")]
#[path = "../../baked/chunk/bench_sphere.rs"]
mod fig;
#[cfg(feature = "bench-sphere")]
const FIGURE: (&str, u32, u32) = ("bench-sphere", 640, 480);

const BOARD: &str = "microbit";
/// The core clock SysTick counts (QEMU's nRF51 HCLK).
const CORE_HZ: u32 = 16_000_000;
/// QEMU's `-icount shift`, as in `.cargo/config.toml`.
const ICOUNT_SHIFT: u32 = 10;

/// Pixels in a strip: 2 rows of 320, 1 of 640 (1.25 KiB colour + 1.25 KiB depth).
const STRIP_PIXELS: usize = 640;
/// Q12.4 units a span method may move a vertex by (two pixels: more than
/// sierpinski's snapping to even pixels).
const SNAP_MARGIN: i32 = 32;
/// Chunks per mesh at most (the baked figures have at most 31).
const MAX_CHUNKS: usize = 64;

const EMPTY: XfVertex = XfVertex {
    s: fixshade::raster::ScreenVertex {
        x: 0,
        y: 0,
        z: 0,
        c: [0; 3],
    },
    flags: 0,
};

static mut COLOR: [u16; STRIP_PIXELS] = [0; STRIP_PIXELS];
static mut DEPTH: [u16; STRIP_PIXELS] = [0; STRIP_PIXELS];
static mut CACHE: [XfVertex; fig::MAX_CHUNK_VERTICES] = [EMPTY; fig::MAX_CHUNK_VERTICES];

/// Word written over the free RAM between the statics and the stack at start; the
/// lowest word that no longer holds it shows how deep the stack went.
const PAINT: u32 = 0x5AA5_C33C;

extern "C" {
    static mut __ebss: u32;
    static mut _stack_start: u32;
}

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

/// Fills the RAM from the end of the statics to 256 bytes below the current stack
/// pointer with [`PAINT`].
#[allow(unsafe_code)]
fn paint_stack() {
    let sp = cortex_m::register::msp::read() as usize - 256;
    // SAFETY: the words between the end of .bss and (SP − 256) belong to no static
    // and lie below every live stack frame.
    unsafe {
        let mut p = core::ptr::addr_of_mut!(__ebss);
        while (p as usize) < sp {
            p.write_volatile(PAINT);
            p = p.add(1);
        }
    }
}

/// Bytes of stack used at the deepest point since [`paint_stack`].
#[allow(unsafe_code)]
fn stack_used() -> usize {
    // SAFETY: reads words between the end of .bss and the top of RAM.
    unsafe {
        let top = core::ptr::addr_of_mut!(_stack_start) as usize;
        let mut p = core::ptr::addr_of_mut!(__ebss);
        while (p as usize) < top && p.read_volatile() == PAINT {
            p = p.add(1);
        }
        top - p as usize
    }
}

/// `<figure>-<case>.rgb565` as a C string in `buf`.
fn file_name<'b>(buf: &'b mut [u8; 64], figure: &str, case: &str) -> &'b CStr {
    let mut n = 0;
    for part in [figure.as_bytes(), b"-", case.as_bytes(), b".rgb565"] {
        buf[n..n + part.len()].copy_from_slice(part);
        n += part.len();
    }
    buf[n] = 0;
    CStr::from_bytes_with_nul(&buf[..=n]).unwrap_or(c"frame.rgb565")
}

/// The strip's bytes in memory order (Rgb565Le keeps little-endian bytes in each
/// `u16`, the M0 is little-endian).
fn as_bytes(p: &[u16]) -> &[u8] {
    // SAFETY: u16 has no padding and every byte pattern is a valid u8; the length in
    // bytes is twice the length in u16; alignment of u8 is 1.
    #[allow(unsafe_code)]
    unsafe {
        core::slice::from_raw_parts(p.as_ptr().cast::<u8>(), p.len() * 2)
    }
}

#[inline(never)]
fn run() -> Result<(), &'static str> {
    let cp = cortex_m::Peripherals::take().ok_or("peripherals taken twice")?;
    let mut counter = Counter::start(cp.SYST, CORE_HZ, ICOUNT_SHIFT);
    fixshade_boards_common::calibrate(&mut counter, &mut Console, BOARD);
    // The only references to the buffers, taken once before any use.
    #[allow(unsafe_code)]
    let (color, depth, cache) = unsafe {
        (
            &mut *core::ptr::addr_of_mut!(COLOR),
            &mut *core::ptr::addr_of_mut!(DEPTH),
            &mut *core::ptr::addr_of_mut!(CACHE),
        )
    };
    let (name, w, h) = FIGURE;
    let rows = STRIP_PIXELS as u32 / w;
    if rows == 0 || h % rows != 0 || fig::OBJECTS.len() != 1 {
        return Err("strip rows must divide the frame height; one object per figure");
    }
    let chunks = fig::OBJECTS[0];
    if chunks.len() > MAX_CHUNKS {
        return Err("too many chunks");
    }
    let scene = init_scene()?;
    // How this image cuts the frame: strip rows and the chunks' vertex limit, for the
    // host render it is compared with.
    let _ = writeln!(Console, "LAYOUT {BOARD} {name} {rows} {}", fig::CHUNK_LIMIT);
    let bg = Rgb565Le::pack(fig::BACKGROUND[0], fig::BACKGROUND[1], fig::BACKGROUND[2]);
    let n = (w * rows) as usize;
    let mut strip = Strip::<Rgb565Le>::new(&mut color[..n], Some(&mut depth[..n]), w, h, 0, rows)
        .map_err(|_| "strip")?;
    // The built-in scenes test depth and shade Gouraud: the draw call `Frame::draw`
    // makes for them, with only that code in flash.
    if !scene.depth_test || scene.shading != ShadingMode::Gouraud {
        return Err("this image draws Gouraud with the depth test only");
    }
    for (case, draw) in cases::<Fixed<DepthTest, Gouraud>, Rgb565Le, Strip<'_, Rgb565Le>>() {
        let log = frame(
            case,
            draw,
            scene,
            chunks,
            &mut strip,
            bg,
            &mut cache[..],
            &mut counter,
        )?;
        let _ = log.write(&mut Console, BOARD, name, case);
    }
    Ok(())
}

/// The scene lives in a static so the stack holds no copy of it (2 KiB).
static mut SCENE: Option<Scene<'static>> = None;

/// Builds the scene into [`SCENE`] (the temporary is on this function's stack,
/// released before any drawing).
#[inline(never)]
fn init_scene() -> Result<&'static mut Scene<'static>, &'static str> {
    let s = fig::scene().map_err(|_| "baked mesh rejected")?;
    // SAFETY: called once, before anything else refers to SCENE.
    #[allow(unsafe_code)]
    let slot = unsafe { &mut *core::ptr::addr_of_mut!(SCENE) };
    *slot = Some(s);
    slot.as_mut().ok_or("no scene")
}

/// Renders one frame with one case, strip by strip, into its host file.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn frame<'s>(
    case: &str,
    draw: DrawFn<Rgb565Le, Strip<'s, Rgb565Le>>,
    scene: &mut Scene<'static>,
    chunks: &[fig::Chunk],
    strip: &mut Strip<'s, Rgb565Le>,
    bg: u16,
    cache: &mut [XfVertex],
    counter: &mut Counter,
) -> Result<FrameLog, &'static str> {
    let (name, w, h) = FIGURE;
    let rows = strip.rows().len() as u32;
    let mut log = FrameLog {
        width: w,
        height: h,
        ..FrameLog::default()
    };
    // Pass 1: the screen rows (Q12.4) each chunk's vertices reach; a chunk with a
    // vertex outside the guard band or depth range may reach any row.
    let mut reach = [(i32::MIN, i32::MAX); MAX_CHUNKS];
    for (k, c) in chunks.iter().enumerate() {
        log.prepare += prepare(scene, c, cache, counter)?;
        let v = &cache[..c.0.len()];
        if v.iter().all(|x| x.flags & OUTSIDE == 0) {
            let lo = v.iter().map(|x| x.s.y).min().unwrap_or(i32::MAX);
            let hi = v.iter().map(|x| x.s.y).max().unwrap_or(i32::MIN);
            reach[k] = (lo, hi);
        }
    }
    let mut buf = [0u8; 64];
    let mut file = semihosting::fs::File::create(file_name(&mut buf, name, case))
        .map_err(|_| "cannot create the frame file")?;
    let mut y0 = 0;
    while y0 < h {
        strip.set_y0(y0).map_err(|_| "strip rows")?;
        strip.clear(bg);
        let r = strip.rows();
        for (k, c) in chunks.iter().enumerate() {
            // The rasterizer skips a triangle whose rows miss the target's (pixel
            // centres at 16·y + 8): so does this, per chunk, with a margin of
            // `SNAP_MARGIN` for span methods that move vertices (sierpinski snaps
            // them to even pixels, up to one pixel away).
            let (lo, hi) = reach[k];
            let (lo, hi) = (
                lo.saturating_sub(SNAP_MARGIN),
                hi.saturating_add(SNAP_MARGIN),
            );
            if hi < 16 * r.start + 8 || lo > 16 * r.end - 8 {
                continue;
            }
            let (prepare, draw, stats) = prepare_and_draw(scene, c, draw, strip, cache, counter)?;
            log.prepare += prepare;
            log.draw += draw;
            log.stats.drawn += stats.drawn;
            log.stats.pixels += stats.pixels;
        }
        file.write_all(as_bytes(strip.color()))
            .map_err(|_| "cannot write the frame file")?;
        y0 += rows;
    }
    log.stats.triangles = chunks.iter().map(|c| c.2.len() as u32).sum();
    Ok(log)
}

/// Runs the vertex stage of chunk `c` into `cache`; returns its instructions.
#[inline(never)]
fn prepare(
    scene: &mut Scene<'static>,
    c: &fig::Chunk,
    cache: &mut [XfVertex],
    counter: &mut Counter,
) -> Result<u64, &'static str> {
    let (_, w, h) = FIGURE;
    scene.objects[0].mesh = fig::chunk_mesh(c).map_err(|_| "chunk rejected")?;
    let (frame, cost) = counter.measure(|| Frame::<Rgb565Le>::prepare(scene, w, h, cache));
    frame.map_err(|_| "prepare failed")?;
    Ok(cost)
}

/// Runs the vertex stage of chunk `c` and draws it into the strip; returns the
/// instructions of both and the draw's statistics.
#[inline(never)]
fn prepare_and_draw<'s>(
    scene: &mut Scene<'static>,
    c: &fig::Chunk,
    draw: DrawFn<Rgb565Le, Strip<'s, Rgb565Le>>,
    strip: &mut Strip<'s, Rgb565Le>,
    cache: &mut [XfVertex],
    counter: &mut Counter,
) -> Result<(u64, u64, Stats), &'static str> {
    let (_, w, h) = FIGURE;
    scene.objects[0].mesh = fig::chunk_mesh(c).map_err(|_| "chunk rejected")?;
    let (frame, prepare) = counter.measure(|| Frame::<Rgb565Le>::prepare(scene, w, h, cache));
    let frame = frame.map_err(|_| "prepare failed")?;
    let (stats, draw) = counter.measure(|| draw(&frame, strip));
    Ok((prepare, draw, stats.map_err(|_| "draw failed")?))
}

#[entry]
fn main() -> ! {
    paint_stack();
    let r = run();
    let _ = writeln!(Console, "STACK {BOARD} {} {}", FIGURE.0, stack_used());
    match r {
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
