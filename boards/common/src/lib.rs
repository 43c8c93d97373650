//! What the QEMU firmware images share: the tables of span methods and dividers each
//! frame is drawn with, a deterministic instruction counter on SysTick, and the line
//! each frame logs.
//!
//! Instruction counts: QEMU runs the firmware with `-icount shift=10`, so every
//! instruction advances the virtual clock by 2¹⁰ ns and SysTick, clocked from the
//! core clock `F`, advances `F · 1024 / 10⁹` ticks per instruction (25.6 at 25 MHz
//! on mps2-an386, 16.384 at 16 MHz on the nRF51). [`SysTickCounter`] counts SysTick's wraps
//! in its exception handler and converts ticks to instructions. The handler's own
//! few instructions per wrap (one wrap per 2²⁴ ticks: ≥ 600 000 instructions) are
//! counted too, a bias below 0.01 %. Under `-icount` the counts do not depend on the
//! host or the run (see [`SysTickCounter`]).
#![no_std]
#![deny(missing_docs, unsafe_code)]

#[cfg(feature = "catalogue")]
pub mod catalogue;
pub mod report;
#[cfg(feature = "scenes")]
pub mod scenes;

use core::marker::PhantomData;
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::{SCB, SYST};
use fixshade::divide::{Divide, Exact, ShiftAdd, ShiftAddRounded, Table};
use fixshade::raster::perspective::Perspective;
use fixshade::raster::span::{Classic, DepthMode, Gradient, SpanMethod, WithDivide};
use fixshade::render::{Frame, RenderError, Stats};
use fixshade::shade::Shading;
use fixshade::specular::{BlinnExact, Specular};
use fixshade::target::{PixelFormat, Target};

/// SysTick reload: the full 24 bits.
const RELOAD: u32 = 0x00FF_FFFF;

/// Ticks after a wrap in which [`SysTickCounter::ticks`] waits (about 256 instructions on
/// the nRF51, 160 on mps2): a read this close to the reload may precede the wrap's
/// exception. A read that lands there waits out the rest of the window, which the
/// measurement then includes (at most `GUARD` ticks, for one read in 4 096).
const GUARD: u32 = 4096;

static WRAPS: AtomicU32 = AtomicU32::new(0);

/// To be called from the board's `SysTick` exception handler.
pub fn on_systick() {
    // Only this handler writes WRAPS; load + store is enough on one core (thumbv6m
    // has no atomic read-modify-write).
    WRAPS.store(WRAPS.load(Ordering::Relaxed) + 1, Ordering::Relaxed);
}

/// A moment of a [`SysTickCounter`]: SysTick ticks since the start.
#[derive(Copy, Clone, Debug)]
pub struct Mark(u64);

/// An instruction counter on SysTick, valid under QEMU's `-icount shift=SHIFT`.
///
/// The same image gives the same counts in every run. What runs before a span
/// (code placed elsewhere, say, by a build from another directory) moves where
/// it starts against the ticks and the wraps, and the counter is built so that
/// this changes the span's count as little as it can:
/// - Each instruction advances the virtual clock by 2^shift ns, which is not a
///   whole number of ticks (25.6 at 25 MHz): a span of `n` instructions reads
///   `25.6·n` ticks give or take one, depending on where the clock stood when it
///   began. Rounding to the nearest instruction gives `n` (a tick is far shorter
///   than half an instruction on every board here).
/// - A read in the `GUARD` window after a reload waits there; the wait is left
///   outside the span (before its start, after its end).
///
/// What remains: a span holds as many wrap exceptions as wraps fall in it, which
/// depends on where it began, and each costs it the handler's instructions (and
/// QEMU reloads SysTick when it next checks its timers, a few instructions after
/// the wrap): on mps2 a loop of 6 000 001 instructions holding nine wraps measures
/// 6 000 136 on the M4 and 6 000 128 on ARMv6-M where an empty span measures 57
/// and 63, under 9 instructions a wrap. A span's count may move by about that much
/// per wrap when what ran before it changes; `cargo xtask qemu` compares committed
/// counts within that spread.
pub struct SysTickCounter {
    syst: SYST,
    /// Core clock in Hz (SysTick's clock source) times 2^shift, QEMU's icount
    /// shift (one instruction = 2^shift ns).
    per: u64,
    /// The ticks of the last read.
    last: u64,
}

impl SysTickCounter {
    /// Starts SysTick on the core clock `hz`, wrapping every 2²⁴ ticks with its
    /// exception enabled.
    pub fn start(mut syst: SYST, hz: u32, shift: u32) -> SysTickCounter {
        syst.disable_counter();
        syst.set_clock_source(SystClkSource::Core);
        syst.set_reload(RELOAD);
        syst.clear_current();
        syst.enable_interrupt();
        syst.enable_counter();
        SysTickCounter {
            syst,
            per: (hz as u64) << shift,
            last: 0,
        }
    }

    /// The start of a span, for [`SysTickCounter::since`].
    pub fn begin(&mut self) -> Mark {
        self.read(false)
    }

    /// Instructions from `start` to now: ticks · 10⁹ / (hz · 2^shift), rounded to
    /// the nearest. Differences (spans), not totals: the product stays in u64.
    pub fn since(&mut self, start: Mark) -> u64 {
        let end = self.read(true);
        let per = self.per;
        // ticks < 2^34 (an hour of virtual time), 10^9 < 2^30, per / 2 < 2^45: the
        // sum < 2^64.
        ((end.0 - start.0) * 1_000_000_000 + per / 2) / per
    }

    /// The moment now. A read within `GUARD` ticks after a reload may precede the
    /// wrap's exception (QEMU raises it at the next instruction boundary it
    /// checks): it waits with interrupts enabled until the reading leaves the
    /// window, and the moment is the first read when `at_first` (the end of a span,
    /// the wait after it), else the last (the start of a span, the wait before it).
    ///
    /// QEMU may also show the reloaded value for a whole translation block before
    /// it raises the exception, longer than `GUARD` on the Cortex-M0 (whose
    /// straight-line blocks are long). Such a read lacks one wrap and falls below
    /// the previous one: a decrease can only mean a missed wrap, and it gets the
    /// wrap back. (A read that misses a wrap more than a wrap after the previous
    /// read would not be caught; with `GUARD` covering blocks of 256 instructions
    /// that needs a longer block there.)
    fn read(&mut self, at_first: bool) -> Mark {
        // The first read, if it fell in the window (u32::MAX: none).
        let mut v0 = u32::MAX;
        let (v, w) = loop {
            let (v, w) = cortex_m::interrupt::free(|_| {
                let mut v = SYST::get_current();
                let mut w = WRAPS.load(Ordering::Relaxed);
                // A wrap whose exception is pending (masked here) has happened: count
                // it, and re-read the value, which is then certainly after the wrap.
                if SCB::is_pendst_pending() {
                    v = SYST::get_current();
                    w += 1;
                }
                (v, w)
            });
            if v < RELOAD - GUARD {
                // The first read lies in the same wrap as this one: the window is
                // far shorter than a wrap.
                break (if at_first && v0 != u32::MAX { v0 } else { v }, w);
            }
            if v0 == u32::MAX {
                v0 = v;
            }
        };
        let mut ticks = w as u64 * (RELOAD as u64 + 1) + (RELOAD - v) as u64;
        if ticks < self.last {
            ticks += RELOAD as u64 + 1;
        }
        self.last = ticks;
        Mark(ticks)
    }

    /// Runs `f` and returns its result with the instructions it took (marked for
    /// the helper count, see [`mark_on`]).
    pub fn measure<R>(&mut self, f: impl FnOnce() -> R) -> (R, u64) {
        let a = self.begin();
        mark_on();
        let r = f();
        mark_off();
        (r, self.since(a))
    }

    /// Gives SysTick back.
    pub fn free(self) -> SYST {
        self.syst
    }
}

/// Runs a loop of exactly `2·n + 1` instructions (`subs` and `bne` per turn, the
/// last `bne` falls through; plus one `mov`), to check the counter's scale.
#[allow(unsafe_code)]
#[inline(never)]
pub fn known_loop(n: u32) {
    if n == 0 {
        return;
    }
    // SAFETY: touches only the scratch register it declares.
    unsafe {
        core::arch::asm!(
            "mov {r}, {n}",
            "2:",
            "subs {r}, #1",
            "bne 2b",
            n = in(reg) n,
            r = out(reg) _,
            options(nomem, nostack),
        );
    }
}

/// Calibrates [`SysTickCounter`]: instructions it measures for an empty span and for
/// [`known_loop`] of `n` turns (long enough to hold wraps), logged as
/// `CALIBRATE board empty loop expected`.
pub fn calibrate(counter: &mut SysTickCounter, out: &mut impl core::fmt::Write, board: &str) {
    let ((), empty) = counter.measure(|| ());
    // Ten or more wraps (a wrap per 655 360 instructions at 25 MHz).
    let n = 3_000_000;
    let ((), looped) = counter.measure(|| known_loop(n));
    let _ = writeln!(
        out,
        "CALIBRATE {board} {empty} {looped} {}",
        2 * n as u64 + 1
    );
    mark_discard();
}

/// Markers in QEMU's execution log for counting the instructions spent in compiler
/// runtime helpers (`cargo xtask qemu`, the `helpers` column): the log holds every
/// executed block, and these functions' addresses (from the ELF's symbols) split it.
/// [`SysTickCounter::measure`] wraps what it measures in [`mark_on`] and [`mark_off`];
/// [`FrameLog::write`] calls [`mark_frame`], which closes the frame whose line it
/// writes; [`mark_discard`] drops what was counted since the last frame (the
/// calibration, the setup-cost passes). Each is out of line with a body of its own,
/// so each has its own address.
#[inline(never)]
pub fn mark_on() {
    core::hint::black_box(0x5EED_0001u32);
}

/// See [`mark_on`].
#[inline(never)]
pub fn mark_off() {
    core::hint::black_box(0x5EED_0002u32);
}

/// See [`mark_on`].
#[inline(never)]
pub fn mark_frame() {
    core::hint::black_box(0x5EED_0003u32);
}

/// See [`mark_on`].
#[inline(never)]
pub fn mark_discard() {
    core::hint::black_box(0x5EED_0004u32);
}

/// Draws a prepared frame (lit with `Sp`: one-sided exact Blinn unless named)
/// into a target with one span method.
pub type DrawFn<P, T, Sp = BlinnExact> =
    fn(&Frame<'_, '_, '_, P, Sp>, &mut T) -> Result<Stats, RenderError>;

/// How a case is drawn: the call into the core every case of a table shares.
pub trait Mode {
    /// Draws `f` into `t` with span method `S`.
    fn run<S: SpanMethod, P: PixelFormat, T: Target<P>, Sp: Specular>(
        f: &Frame<'_, '_, '_, P, Sp>,
        t: &mut T,
    ) -> Result<Stats, RenderError>;
    /// Draws `f` into `t` with perspective-correct colours, divider `D`.
    fn perspective<D: Divide, P: PixelFormat, T: Target<P>>(
        f: &Frame<'_, '_, '_, P>,
        t: &mut T,
        mode: Perspective,
    ) -> Result<Stats, RenderError>;
}

/// [`Frame::draw`]: the scene's depth and shading settings.
pub struct SceneSettings;

impl Mode for SceneSettings {
    fn run<S: SpanMethod, P: PixelFormat, T: Target<P>, Sp: Specular>(
        f: &Frame<'_, '_, '_, P, Sp>,
        t: &mut T,
    ) -> Result<Stats, RenderError> {
        f.draw::<S, T>(t)
    }
    fn perspective<D: Divide, P: PixelFormat, T: Target<P>>(
        f: &Frame<'_, '_, '_, P>,
        t: &mut T,
        mode: Perspective,
    ) -> Result<Stats, RenderError> {
        f.draw_perspective::<D, T>(t, mode)
    }
}

/// [`Frame::draw_with`] for one depth mode and shading fixed by type: what
/// [`Frame::draw`] calls for a scene with those settings, with the code of the other
/// settings left out of the image (for small flash).
pub struct Fixed<Z, Sh>(PhantomData<(Z, Sh)>);

impl<Z: DepthMode, Sh: Shading> Mode for Fixed<Z, Sh> {
    fn run<S: SpanMethod, P: PixelFormat, T: Target<P>, Sp: Specular>(
        f: &Frame<'_, '_, '_, P, Sp>,
        t: &mut T,
    ) -> Result<Stats, RenderError> {
        f.draw_with::<S, Z, Sh, T>(t)
    }
    fn perspective<D: Divide, P: PixelFormat, T: Target<P>>(
        f: &Frame<'_, '_, '_, P>,
        t: &mut T,
        mode: Perspective,
    ) -> Result<Stats, RenderError> {
        f.draw_perspective_as::<D, Z, Sh, T>(t, mode)
    }
}

fn entry<S: SpanMethod, M: Mode, P: PixelFormat, T: Target<P>, Sp: Specular>(
    f: &Frame<'_, '_, '_, P, Sp>,
    t: &mut T,
) -> Result<Stats, RenderError> {
    M::run::<S, P, T, Sp>(f, t)
}

/// Number of cases in [`cases`]: every span method of the core's registry.
pub const CASES: usize = fixshade::registry::SPAN_METHODS.len();

/// The span methods of a registry list (`fixshade::for_each_span_method!`) as
/// cases: each named as the host names it (`fixshade render --span NAME`) and drawn
/// by `entry` with the mode `M`.
macro_rules! cases {
    ([$M:ty, $P:ty, $T:ty, $Sp:ty] $($S:ty),* $(,)?) => {
        [$((<$S as SpanMethod>::NAME, entry::<$S, $M, $P, $T, $Sp> as DrawFn<$P, $T, $Sp>)),*]
    };
}

/// The first `$n` (unary, one `x` each) entries of a registry list, then `$cb!`.
macro_rules! take {
    ([$cb:ident [$($a:tt)*] [$($n:tt)*] $($acc:ty,)*] $($S:ty),* $(,)?) => {
        take!(@go $cb [$($a)*] [$($n)*] [$($acc,)*] $($S,)*)
    };
    (@go $cb:ident [$($a:tt)*] [] [$($acc:ty,)*] $($rest:ty,)*) => {
        $cb!([$($a)*] $($acc),*)
    };
    (@go $cb:ident [$($a:tt)*] [x $($n:tt)*] [$($acc:ty,)*] $S:ty, $($rest:ty,)*) => {
        take!(@go $cb [$($a)*] [$($n)*] [$($acc,)* $S,] $($rest,)*)
    };
}

/// The entries of a registry list after the first `$n` (unary), then `$cb!`.
macro_rules! skip {
    ([$cb:ident [$($a:tt)*] [$($n:tt)*]] $($S:ty),* $(,)?) => {
        skip!(@go $cb [$($a)*] [$($n)*] $($S,)*)
    };
    (@go $cb:ident [$($a:tt)*] [] $($rest:ty,)*) => {
        $cb!([$($a)*] $($rest),*)
    };
    (@go $cb:ident [$($a:tt)*] [x $($n:tt)*] $S:ty, $($rest:ty,)*) => {
        skip!(@go $cb [$($a)*] [$($n)*] $($rest,)*)
    };
}

/// Every span method, in the host's order (`fixshade list`), drawn by `M`.
pub fn cases<M: Mode, P: PixelFormat, T: Target<P>>() -> [(&'static str, DrawFn<P, T>); CASES] {
    fixshade::for_each_span_method!(cases[M, P, T, BlinnExact])
}

/// [`cases`] for frames lit with `Sp` (e.g. two-sided lighting,
/// `fixshade::effects::TwoSided`).
pub fn cases_lit<M: Mode, P: PixelFormat, T: Target<P>, Sp: Specular>(
) -> [(&'static str, DrawFn<P, T, Sp>); CASES] {
    fixshade::for_each_span_method!(cases[M, P, T, Sp])
}

/// Span methods in each third of [`cases`] ([`cases_first`], [`cases_second`],
/// [`cases_third`]): for an image whose flash holds the code of a third of them.
pub const THIRD_CASES: usize = 5;

const _: () = assert!(3 * THIRD_CASES == CASES);

/// The first [`THIRD_CASES`] span methods of [`cases`].
pub fn cases_first<M: Mode, P: PixelFormat, T: Target<P>>(
) -> [(&'static str, DrawFn<P, T>); THIRD_CASES] {
    fixshade::for_each_span_method!(take[cases [M, P, T, BlinnExact] [x x x x x]])
}

/// The next [`THIRD_CASES`] span methods of [`cases`].
pub fn cases_second<M: Mode, P: PixelFormat, T: Target<P>>(
) -> [(&'static str, DrawFn<P, T>); THIRD_CASES] {
    fixshade::for_each_span_method!(skip[take [cases [M, P, T, BlinnExact] [x x x x x]] [x x x x x]])
}

/// The last [`THIRD_CASES`] span methods of [`cases`].
pub fn cases_third<M: Mode, P: PixelFormat, T: Target<P>>(
) -> [(&'static str, DrawFn<P, T>); THIRD_CASES] {
    fixshade::for_each_span_method!(skip[cases [M, P, T, BlinnExact] [x x x x x x x x x x]])
}

/// Number of cases in [`divider_cases`].
pub const DIVIDER_CASES: usize = 56;

/// Whether two names are equal, at compile time.
const fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// Two cases per divider `D` named `$name`: `classic@$name` (the divider in the
/// per-span division and in the setup's reciprocal) and `gradient@$name` (in the
/// setup's reciprocal), drawn as the host draws `--divide $name`. A name that is not
/// `D::NAME` does not compile.
macro_rules! divider_cases {
    ($M:ty, $P:ty, $T:ty; $($D:ty => $name:literal),* $(,)?) => {
        [$(
            {
                const _: () = assert!(same(<$D>::NAME, $name), "divider name");
                (
                    concat!("classic@", $name),
                    entry::<WithDivide<Classic<$D>, $D>, $M, $P, $T, BlinnExact> as DrawFn<$P, $T>,
                )
            },
            (
                concat!("gradient@", $name),
                entry::<WithDivide<Gradient, $D>, $M, $P, $T, BlinnExact> as DrawFn<$P, $T>,
            ),
        )*]
    };
}

/// `classic` and `gradient` with every divider, in the host's order of dividers
/// (`fixshade list`), named `span@divider`. The `exact` pair draws what the
/// [`cases`] `classic` and `gradient` draw: the reference of the others in the same
/// image.
pub fn divider_cases<M: Mode, P: PixelFormat, T: Target<P>>(
) -> [(&'static str, DrawFn<P, T>); DIVIDER_CASES] {
    divider_cases!(M, P, T;
        Exact => "exact",
        Table => "table",
        ShiftAdd<4> => "shift-add-4",
        ShiftAdd<5> => "shift-add-5",
        ShiftAdd<6> => "shift-add-6",
        ShiftAdd<7> => "shift-add-7",
        ShiftAdd<8> => "shift-add-8",
        ShiftAdd<9> => "shift-add-9",
        ShiftAdd<10> => "shift-add-10",
        ShiftAdd<11> => "shift-add-11",
        ShiftAdd<12> => "shift-add-12",
        ShiftAdd<13> => "shift-add-13",
        ShiftAdd<14> => "shift-add-14",
        ShiftAdd<15> => "shift-add-15",
        ShiftAdd<16> => "shift-add-16",
        ShiftAddRounded<4> => "shift-add-rounded-4",
        ShiftAddRounded<5> => "shift-add-rounded-5",
        ShiftAddRounded<6> => "shift-add-rounded-6",
        ShiftAddRounded<7> => "shift-add-rounded-7",
        ShiftAddRounded<8> => "shift-add-rounded-8",
        ShiftAddRounded<9> => "shift-add-rounded-9",
        ShiftAddRounded<10> => "shift-add-rounded-10",
        ShiftAddRounded<11> => "shift-add-rounded-11",
        ShiftAddRounded<12> => "shift-add-rounded-12",
        ShiftAddRounded<13> => "shift-add-rounded-13",
        ShiftAddRounded<14> => "shift-add-rounded-14",
        ShiftAddRounded<15> => "shift-add-rounded-15",
        ShiftAddRounded<16> => "shift-add-rounded-16",
    )
}

/// Number of cases in [`perspective_cases`].
pub const PERSPECTIVE_CASES: usize = 6;

/// [`Frame::draw_perspective`] with divider `D` and one division per `SPAN` pixels
/// (a power of two up to 64, checked at compile time).
fn perspective_entry<D: Divide, const SPAN: u32, M: Mode, P: PixelFormat, T: Target<P>>(
    f: &Frame<'_, '_, '_, P>,
    t: &mut T,
) -> Result<Stats, RenderError> {
    let mode = const {
        match Perspective::new(SPAN) {
            Some(m) => m,
            None => panic!("perspective span: a power of two up to 64"),
        }
    };
    M::perspective::<D, P, T>(f, t, mode)
}

/// Perspective-correct Gouraud colours (`fixshade render --perspective on
/// --perspective-span N --divide NAME`), named `perspective-N@NAME`: the accuracy
/// report's perspective rows (every pixel, sub-spans of 8 and 16 with `exact`, and
/// sub-spans of 16 with `table` and `shift-add-8`); and first `affine@exact`, the
/// affine `gradient` fill drawn by `M` (whose coverage and depth the perspective fill
/// shares), the report's "off" row and the reference of the others in the same image.
pub fn perspective_cases<M: Mode, P: PixelFormat, T: Target<P>>(
) -> [(&'static str, DrawFn<P, T>); PERSPECTIVE_CASES] {
    const _: () = assert!(same(<ShiftAdd<8>>::NAME, "shift-add-8"), "divider name");
    const _: () = assert!(same(<Table>::NAME, "table"), "divider name");
    [
        (
            "affine@exact",
            entry::<Gradient, M, P, T, BlinnExact> as DrawFn<P, T>,
        ),
        (
            "perspective-1@exact",
            perspective_entry::<Exact, 1, M, P, T>,
        ),
        (
            "perspective-8@exact",
            perspective_entry::<Exact, 8, M, P, T>,
        ),
        (
            "perspective-16@exact",
            perspective_entry::<Exact, 16, M, P, T>,
        ),
        (
            "perspective-16@table",
            perspective_entry::<Table, 16, M, P, T>,
        ),
        (
            "perspective-16@shift-add-8",
            perspective_entry::<ShiftAdd<8>, 16, M, P, T>,
        ),
    ]
}

/// The measurements of one frame, as the `FRAME` log line carries them.
#[derive(Copy, Clone, Debug, Default)]
pub struct FrameLog {
    /// How the frame was drawn: `full` (one target), `bands-N` (bands of N rows
    /// from one binning), `strips-N` (strips of N rows, each walking the triangles).
    pub layout: &'static str,
    /// Frame width.
    pub width: u32,
    /// Frame height.
    pub height: u32,
    /// Instructions in `Frame::prepare` (vertex stage), summed over its runs.
    pub prepare: u64,
    /// Instructions in `Frame::draw`, summed over strips and chunks.
    pub draw: u64,
    /// Draw statistics, summed.
    pub stats: Stats,
}

impl FrameLog {
    /// Writes the line `FRAME board figure case w h triangles drawn pixels prepare
    /// draw layout` that `cargo xtask qemu` reads.
    pub fn write(
        &self,
        out: &mut impl core::fmt::Write,
        board: &str,
        figure: &str,
        case: &str,
    ) -> core::fmt::Result {
        mark_frame();
        writeln!(
            out,
            "FRAME {board} {figure} {case} {} {} {} {} {} {} {} {}",
            self.width,
            self.height,
            self.stats.triangles,
            self.stats.drawn,
            self.stats.pixels,
            self.prepare,
            self.draw,
            self.layout
        )
    }
}

/// A case name composed in place (at most 64 bytes; longer text is cut).
#[derive(Clone, Copy)]
pub struct Name {
    buf: [u8; 64],
    len: usize,
}

impl Name {
    /// An empty name.
    pub const fn new() -> Name {
        Name {
            buf: [0; 64],
            len: 0,
        }
    }

    /// The name so far.
    pub fn as_str(&self) -> &str {
        // Only whole `&str`s are appended, cut at a character boundary.
        core::str::from_utf8(&self.buf[..self.len]).unwrap_or("")
    }
}

impl Default for Name {
    fn default() -> Name {
        Name::new()
    }
}

impl core::fmt::Write for Name {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let mut take = s.len().min(self.buf.len() - self.len);
        while !s.is_char_boundary(take) {
            take -= 1;
        }
        self.buf[self.len..self.len + take].copy_from_slice(&s.as_bytes()[..take]);
        self.len += take;
        if take < s.len() {
            Err(core::fmt::Error)
        } else {
            Ok(())
        }
    }
}
