//! Gradient's packed span loop in assembly, for the 5-6-5 formats over 16-bit depth
//! cells on the Cortex-M cores ([`super::pixel`]'s `write_packed` calls it), and
//! the row loop of a triangle's halves around it ([`packed_565_rows`], which
//! `fill_gradient` takes for the whole triangles of at least [`ROWS`] rows in a
//! target that stores its rows one after another).
//!
//! The compiler unrolls the portable loop four times on M-profile cores and then
//! runs out of registers: the four depths and colour steps are spilled and reloaded
//! at every pixel. Measured on the bench sphere (`cargo xtask qemu`), a written
//! pixel took 20 instructions on the Cortex-M4 and 27 on ARMv6-M; these loops take
//! 16 and 23 (a hidden pixel 8 and 13), with the same pixels and depths. On the
//! Cortex-M4 the spans of six pixels or more in the row loop and in band draws go
//! two pixels a step with the DSP extension ([`thumb2_pair`]): 13 instructions a
//! pixel, written or hidden (the bench sphere's whole-frame draw at 640×480: 3.15 M
//! → 2.85 M instructions). The QEMU
//! images compare every frame with the host's byte for byte, and the mps2 images
//! (Cortex-M4 and ARMv6-M) check that `Rgb565Be` (the byte-swapping store) draws
//! the `Rgb565Le` frame byte-swapped.
//!
//! What a step does, in both: the stored depth `d` of the pixel is read; where
//! `z >> 16 < d` (strictly nearer, as [`crate::target::DepthFormat::write_if_nearer`])
//! the new depth and the pixel are written. The pixel's fields are the integer bits
//! of the packed colour's lanes (red at bit 43, green at 21, blue at 0, each with 16
//! fraction bits): red is bits 59..64 (27..32 of the high word), green 37..43
//! (5..11 of the high word, already where 5-6-5 wants it), blue 16..21 (of the low
//! word). Then the colour steps by `dc` (add with carry across the two words) and
//! the depth by `dz`, wrapping, as the portable loop does.
//!
//! # Why there is `unsafe` here
//!
//! The crate denies `unsafe_code`; each `asm!` block is under its own
//! `#[allow(unsafe_code)]` with a SAFETY comment: it stores only into the cells of
//! the two rows it borrows mutably (the row loop: of the rows whose bounds it
//! checked first) and its own block of words, reads only those and its inputs,
//! pushes nothing.

#[cfg(not(feature = "small-flash"))]
use super::edge::EdgeStepper;
#[cfg(not(feature = "small-flash"))]
use crate::target::{DepthFormat, PixelFormat, Target};
#[cfg(not(feature = "small-flash"))]
use core::ops::Range;

/// One pixel of the span loop of ARMv7-M and later (Thumb-2), at index `{i}`,
/// which then steps by one (the flags set by that step: zero at the span's end);
/// `$skip`: the local label of the step, `$rev`: an instruction applied to the
/// pixel before its store.
#[cfg(fixshade_dsp)]
macro_rules! thumb2_one {
    ($skip:literal $(, $rev:literal)?) => {
        concat!(
            "ldrh {t}, [{dp}, {i}, lsl #1]\n",
            // Stored ≤ new: the pixel stays.
            "cmp {t}, {z}, lsr #16\n",
            "bls ", $skip, "f\n",
            "lsrs {t}, {z}, #16\n",
            "strh {t}, [{dp}, {i}, lsl #1]\n",
            "and {t}, {hi}, #0x7e0\n",
            "lsrs {u}, {hi}, #27\n",
            "orr {t}, {t}, {u}, lsl #11\n",
            "ubfx {u}, {lo}, #16, #5\n",
            "orr {t}, {t}, {u}\n",
            $($rev, "\n",)?
            "strh {t}, [{cp}, {i}, lsl #1]\n",
            $skip, ":\n",
            "adds {lo}, {lo}, {dlo}\n",
            "adc {hi}, {hi}, {dhi}\n",
            "add {z}, {z}, {dz}\n",
            "adds {i}, {i}, #1\n",
        )
    };
}

/// Two pixels of the span loop at indices `{i}` and `{i} + 1`, whose cells are
/// word-aligned, with the DSP extension (see [`super::dsp`] for why each step is
/// exact): the integer parts of both depths side by side (`PKHTB`), both depth
/// tests in one `USUB16` (a half's GE flags set where new ≥ stored: the stored
/// pixel stays), both depths and both pixels chosen by one `SEL` each and stored as
/// one word. The second pixel's colour is the first's plus `dc` (the 64-bit add of
/// the single step), and the colour moves on from it by `dc` again; the 5-6-5
/// fields of both are gathered by one half-word pack and one mask per channel (red
/// and blue `PKHTB`, green `PKHBT`). `$v`: the third temporary; `$loop`: the
/// label of the loop.
#[cfg(fixshade_dsp)]
macro_rules! thumb2_pair {
    ($v:literal, $loop:literal $(, $rev:literal)?) => {
        concat!(
            $loop, ":\n",
            "add {t}, {z}, {dz}\n",
            "pkhtb {u}, {t}, {z}, asr #16\n",
            "add {z}, {t}, {dz}\n",
            "ldr {t}, [{dp}, {i}, lsl #1]\n",
            "usub16 ", $v, ", {u}, {t}\n",
            "sel {t}, {t}, {u}\n",
            "str {t}, [{dp}, {i}, lsl #1]\n",
            // The second pixel's colour (u, v), then the colour two pixels on.
            "adds {u}, {lo}, {dlo}\n",
            "adc ", $v, ", {hi}, {dhi}\n",
            "pkhtb {t}, {u}, {lo}, asr #16\n",
            "adds {lo}, {u}, {dlo}\n",
            "and {t}, {t}, #0x001F001F\n",
            "pkhtb {u}, ", $v, ", {hi}, asr #16\n",
            "and {u}, {u}, #0xF800F800\n",
            "orr {t}, {t}, {u}\n",
            "pkhbt {u}, {hi}, ", $v, ", lsl #16\n",
            // The carry of the `adds` above: no instruction between sets flags.
            "adc {hi}, ", $v, ", {dhi}\n",
            "lsr {u}, {u}, #5\n",
            "and {u}, {u}, #0x003F003F\n",
            "orr {t}, {t}, {u}, lsl #5\n",
            $($rev, "\n",)?
            "ldr {u}, [{cp}, {i}, lsl #1]\n",
            "sel {t}, {u}, {t}\n",
            "str {t}, [{cp}, {i}, lsl #1]\n",
            "adds {i}, {i}, #2\n",
            "bne ", $loop, "b\n",
        )
    };
}

/// The span loop of ARMv7-M and later (Thumb-2), as one template for both loops
/// that run it ([`thumb2`], [`packed_565_rows`]): both rows indexed from their ends
/// by a negative pixel index `{i}` (scaled by two in the address) that steps up to
/// zero, so one register and one flag-setting add count the loop. A span is drawn
/// two pixels a step ([`thumb2_pair`]) over word-aligned cells: a first pixel
/// whose cells are not aligned goes alone first, and an odd pixel left at the end
/// goes alone last (the pair loop then runs with both rows' ends moved back by a
/// pixel). The caller sends to label `3` (one pixel a step, [`thumb2_one`]) the
/// spans of fewer than six pixels, which cost more in the alignment and the odd
/// pixel than the pairs save, and those of a target whose colour and depth cells
/// are not aligned alike (their addresses differ by 2 modulo 4: no pair is
/// word-aligned in both), so that no word access is unaligned (ARMv7-M allows
/// unaligned `LDR`/`STR` only to normal memory and only while `CCR.UNALIGN_TRP` is
/// clear). `$v`: the pair loop's third temporary; `$rev`: an instruction applied
/// to the pixel before its store. Labels 3 and 5 to 13 are its own.
#[cfg(fixshade_dsp)]
macro_rules! thumb2_span {
    ($v:literal $(, $rev:literal)?) => {
        concat!(
            "add {t}, {dp}, {i}, lsl #1\n",
            "tst {t}, #2\n",
            "beq 6f\n",
            thumb2_one!("5" $(, $rev)?),
            "6:\n",
            "tst {i}, #1\n",
            "bne 12f\n",
            thumb2_pair!($v, "7" $(, $rev)?),
            "b 9f\n",
            "12:\n",
            "subs {dp}, {dp}, #2\n",
            "subs {cp}, {cp}, #2\n",
            "adds {i}, {i}, #1\n",
            thumb2_pair!($v, "13" $(, $rev)?),
            "adds {dp}, {dp}, #2\n",
            "adds {cp}, {cp}, #2\n",
            "subs {i}, {i}, #1\n",
            "3:\n",
            thumb2_one!("8" $(, $rev)?),
            "bne 3b\n",
            "9:\n",
        )
    };
}

/// The packed values of a triangle's rows (`pixel::packed_channels`): the packed
/// colour and the depth at x = 0 of the current row, their steps along a row
/// (`pgx`, `gzx`) and from row to row (`pgy`, `gzy`), all wrapping.
#[cfg(all(any(fixshade_dsp, fixshade_v6m), not(feature = "small-flash")))]
#[derive(Copy, Clone)]
pub(crate) struct PackedRows {
    pub(crate) c_row: u64,
    pub(crate) pgx: u64,
    pub(crate) pgy: u64,
    pub(crate) z_row: i32,
    pub(crate) gzx: i32,
    pub(crate) gzy: i32,
}

#[cfg(all(fixshade_v6m, not(feature = "small-flash")))]
impl PackedRows {
    /// The packed colour and the depth at pixel `x0 ≥ 0` of the current row.
    #[inline(always)]
    pub(crate) fn at(&self, x0: i32) -> (u64, i32) {
        (
            crate::math::packed_at(self.c_row, self.pgx, x0),
            self.z_row.wrapping_add(x0.wrapping_mul(self.gzx)),
        )
    }

    /// Moves on to the next row.
    #[inline(always)]
    pub(crate) fn next_row(&mut self) {
        self.c_row = self.c_row.wrapping_add(self.pgy);
        self.z_row = self.z_row.wrapping_add(self.gzy);
    }
}

/// The rows `ys` of a half of a triangle between the edges `left` and `right`:
/// `row(y, Some((x0, x1)))` with the row's covered pixels `[x0, x1)` clipped to
/// `[0, width)`, or `row(y, None)` for a row with none; both edges step on after
/// each row (the row loop of `walk_rows`, for a loop that finds the rows' cells
/// itself).
#[cfg(all(fixshade_v6m, not(feature = "small-flash")))]
#[inline(always)]
pub(crate) fn each_row(
    left: &mut EdgeStepper,
    right: &mut EdgeStepper,
    ys: Range<i32>,
    width: i32,
    mut row: impl FnMut(i32, Option<(i32, i32)>),
) {
    for y in ys {
        let x0 = left.q.max(0);
        let x1 = right.q.min(width);
        row(y, if x0 < x1 { Some((x0, x1)) } else { None });
        left.step();
        right.step();
    }
}

/// The rows' first `n = min(color.len(), depth.len())` pixels as the packed loop
/// writes them; `swap`: store the pixel byte-swapped (`Rgb565Be`). On ARMv6-M the
/// loop is inlined into each fill, except with `small-flash` (the micro:bit
/// images), where every span calls the one copy in [`v6m_outlined`]. `pairs`: on
/// ARMv7E-M, spans of six pixels or more go two pixels a step ([`thumb2_span`]);
/// for the fills of band draws, whose triangles do not take [`packed_565_rows`].
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn packed_565_span(
    color: &mut [u16],
    depth: &mut [u16],
    c: u64,
    dc: u64,
    z: i32,
    dz: i32,
    swap: bool,
    pairs: bool,
) {
    span::<{ cfg!(feature = "small-flash") }>(color, depth, c, dc, z, dz, swap, pairs);
}

/// [`packed_565_span`]; `OUTLINED`: on ARMv6-M through [`v6m_outlined`] (one copy
/// for the spans of every fill), else with the loop inlined (each fill's spans, and
/// the row loop [`packed_565_rows`], itself one copy).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn span<const OUTLINED: bool>(
    color: &mut [u16],
    depth: &mut [u16],
    c: u64,
    dc: u64,
    z: i32,
    dz: i32,
    swap: bool,
    pairs: bool,
) {
    let n = color.len().min(depth.len());
    if n == 0 {
        return;
    }
    let (lo, hi) = (c as u32, (c >> 32) as u32);
    let (dlo, dhi) = (dc as u32, (dc >> 32) as u32);
    #[cfg(fixshade_dsp)]
    thumb2(color, depth, n, [lo, hi, dlo, dhi], z, dz, swap, pairs);
    #[cfg(fixshade_v6m)]
    let _ = pairs;
    #[cfg(fixshade_v6m)]
    if OUTLINED {
        v6m_outlined(color, depth, n, [lo, hi, dlo, dhi], z, dz, swap);
    } else {
        v6m(color, depth, n, [lo, hi, dlo, dhi], z, dz, swap);
    }
}

/// A target's rows for [`packed_565_rows`]: its colour and depth cells, row after
/// row, `width` cells a row, the first of frame row `y0`.
#[cfg(all(any(fixshade_dsp, fixshade_v6m), not(feature = "small-flash")))]
pub(crate) struct Rows565<'b> {
    pub(crate) color: &'b mut [u16],
    pub(crate) depth: &'b mut [u16],
    pub(crate) width: i32,
    pub(crate) y0: i32,
}

/// The least height in rows of a triangle drawn by [`packed_565_rows`]: each half
/// costs a block to set up (on the Cortex-M4) or a call (on ARMv6-M), which the
/// rows of a smaller triangle do not save back.
#[cfg(all(any(fixshade_dsp, fixshade_v6m), not(feature = "small-flash")))]
pub(crate) const ROWS: i32 = 6;

#[cfg(all(any(fixshade_dsp, fixshade_v6m), not(feature = "small-flash")))]
impl<'b> Rows565<'b> {
    /// The rows of a 5-6-5 target `T` with 16-bit depth cells, if it stores them
    /// one after another ([`Target::rows_contiguous`]).
    #[inline(always)]
    pub(crate) fn of<P: PixelFormat, T: Target<P>>(target: &'b mut T) -> Option<Self>
    where
        P::Raw: 'b,
        T::Depth: 'b,
    {
        let width = target.width() as i32;
        let y0 = target.rows().start;
        let (color, depth) = target.rows_contiguous()?;
        Some(Rows565 {
            color: P::as_u16(color)?,
            depth: DepthFormat::as_u16(depth)?,
            width,
            y0,
        })
    }
}

/// The rows `ys` (inside the target's rows) of a half of a triangle between the
/// edges `left` and `right` ([`each_row`]), each span drawn by the packed
/// loop from the values `p` (moved on by a row per row, as the portable fill
/// does); `SWAP` as [`packed_565_span`]'s `swap`. Returns the pixels covered.
///
/// On ARMv6-M the row loop is compiled, with the span loop inlined (no call per
/// span) and the rows' cells found by stepping from row to row; not inlined, one
/// copy for each byte order serves every fill (flash). On the bench sphere at
/// 640×480 (`cargo xtask qemu`) the draw takes 7 % fewer instructions than with a
/// call to the span loop for each row.
#[cfg(all(fixshade_v6m, not(feature = "small-flash")))]
#[inline(never)]
pub(crate) fn packed_565_rows<const SWAP: bool>(
    buf: &mut Rows565<'_>,
    p: &mut PackedRows,
    left: &mut EdgeStepper,
    right: &mut EdgeStepper,
    ys: Range<i32>,
) -> u32 {
    let w = buf.width as usize;
    // ys.start ≥ y0 when the range is not empty: the first row's first cell.
    let mut at = (ys.start.wrapping_sub(buf.y0) as usize).wrapping_mul(w);
    let mut q = *p;
    let mut covered = 0u32;
    each_row(left, right, ys, buf.width, |_, cover| {
        if let Some((x0, x1)) = cover {
            let (a, e) = (at + x0 as usize, at + x1 as usize);
            if let (Some(cr), Some(dr)) = (buf.color.get_mut(a..e), buf.depth.get_mut(a..e)) {
                let (c, z) = q.at(x0);
                span::<false>(cr, dr, c, q.pgx, z, q.gzx, SWAP, false);
                covered += (x1 - x0) as u32;
            }
        }
        q.next_row();
        at = at.wrapping_add(w);
    });
    *p = q;
    covered
}

/// The rows `ys` of a half of a triangle between the edges `left` and `right`,
/// drawn from the packed values `p` (see [`each_row`] and
/// [`PackedRows`]: the same rows, spans and pixels as the portable fill), with
/// the whole row loop in assembly; `SWAP` as [`packed_565_span`]'s `swap`.
/// Returns the pixels covered.
///
/// The row loop keeps its state in a block of words and every register but the
/// block's address for the span loop, which is [`thumb2`]'s with the index
/// counting pixels. A row:
/// - `x0 = max(left.q, 0)`, `x1 = min(right.q, width)`; a row without pixels
///   goes straight to the steps;
/// - the span's colour `c_row + x0·pgx` (an `UMLAL` for the low word of `pgx`,
///   an `MLA` for the high word, modulo 2⁶⁴ as `math::packed_at`), its depth
///   `z_row + x0·gzx`, the two rows' ends, the index `−n`, then the span loop;
/// - `c_row += pgy`, `z_row += gzy`; each edge steps as [`EdgeStepper::step`]
///   (`q += a; r −= b`; a negative `r` takes `d` back and `q` one more); both
///   rows' addresses move on by a row.
///
/// On the bench sphere at 640×480 (`cargo xtask qemu`) a row takes about 62
/// instructions besides the span loop, the half's block included, against about
/// 104 for the loop compiled from the portable fill (with the same span loop).
#[cfg(all(fixshade_dsp, not(feature = "small-flash")))]
#[inline(never)]
pub(crate) fn packed_565_rows<const SWAP: bool>(
    buf: &mut Rows565<'_>,
    p: &mut PackedRows,
    left: &mut EdgeStepper,
    right: &mut EdgeStepper,
    ys: Range<i32>,
) -> u32 {
    // Empty, or not inside the buffers (never: the rows are the target's): none.
    let (Ok(first), Ok(end), Ok(rows)) = (
        usize::try_from(ys.start.wrapping_sub(buf.y0)),
        usize::try_from(ys.end.wrapping_sub(buf.y0)),
        u32::try_from(ys.end.wrapping_sub(ys.start)),
    ) else {
        return 0;
    };
    let w = buf.width as usize;
    // width ≤ 4096 and the buffers hold whole rows: the products fit.
    if rows == 0 || end * w > buf.color.len() || end * w > buf.depth.len() {
        return 0;
    }
    let cp = buf.color.as_mut_ptr().wrapping_add(first * w);
    let dp = buf.depth.as_mut_ptr().wrapping_add(first * w);
    // The block the loop works on (word offsets in the assembly).
    #[rustfmt::skip]
    let mut st: [u32; 26] = [
        left.q as u32, left.r as u32, left.a as u32, left.b as u32, left.d as u32,      // 0
        right.q as u32, right.r as u32, right.a as u32, right.b as u32, right.d as u32, // 20
        p.c_row as u32, (p.c_row >> 32) as u32, p.z_row as u32, buf.width as u32,     // 40
        p.pgx as u32, (p.pgx >> 32) as u32, p.gzx as u32,                             // 56
        p.pgy as u32, (p.pgy >> 32) as u32, p.gzy as u32,                             // 68
        cp as u32, dp as u32, 2 * buf.width as u32, rows, 0,                          // 80
        pair_limit(cp, dp) as u32,                                                    // 100
    ];
    let s = st.as_mut_ptr();
    macro_rules! run {
        ($($rev:literal)?) => {
            // SAFETY: the stores are into the block `st` (borrowed here) and into
            // the cells `[x0, x1)` of the `rows` rows from `cp` and `dp`: each row
            // `width` cells, the first `first` rows into the buffers, the last
            // ending at `end·width`, within both (checked above); 0 ≤ x0 < x1 ≤
            // width by the clamps (a pair's word: two cells of one span). Loads
            // from the same cells and the block only; registers otherwise (flags
            // clobbered; one word pushed before each span and popped after it).
            #[allow(unsafe_code)]
            unsafe {
                core::arch::asm!(
                    "1:",
                    "ldr {t}, [{s}, #0]",
                    "ldr {u}, [{s}, #20]",
                    "ldr {i}, [{s}, #52]",
                    // x0 = max(left.q, 0), x1 = min(right.q, width), n = x1 − x0.
                    "bic {t}, {t}, {t}, asr #31",
                    "cmp {u}, {i}",
                    "it gt",
                    "movgt {u}, {i}",
                    "subs {u}, {u}, {t}",
                    "ble 4f",
                    "ldr {i}, [{s}, #96]",
                    "add {i}, {i}, {u}",
                    "str {i}, [{s}, #96]",
                    // The span's colour and depth at x0.
                    "ldrd {lo}, {hi}, [{s}, #40]",
                    "ldrd {dlo}, {dhi}, [{s}, #56]",
                    "umlal {lo}, {hi}, {t}, {dlo}",
                    "mla {hi}, {t}, {dhi}, {hi}",
                    "ldr {z}, [{s}, #48]",
                    "ldr {dz}, [{s}, #64]",
                    "mla {z}, {t}, {dz}, {z}",
                    // Both rows' cells from the span's end, indexed by −n … −1.
                    "add {t}, {t}, {u}",
                    "ldrd {cp}, {dp}, [{s}, #80]",
                    "add {cp}, {cp}, {t}, lsl #1",
                    "add {dp}, {dp}, {t}, lsl #1",
                    "rsb {i}, {u}, #0",
                    // The span loop takes the block's address for its third
                    // temporary: it waits on the stack.
                    "ldr {t}, [{s}, #100]",
                    "str {s}, [sp, #-4]!",
                    // A pixel a step below the fill's limit (`pair_limit`).
                    "cmp {i}, {t}",
                    "bgt 3f",
                    thumb2_span!("{s}" $(, $rev)?),
                    "ldr {s}, [sp], #4",
                    "4:",
                    // The next row's values.
                    "ldrd {lo}, {hi}, [{s}, #40]",
                    "ldrd {t}, {u}, [{s}, #68]",
                    "adds {lo}, {lo}, {t}",
                    "adc {hi}, {hi}, {u}",
                    "strd {lo}, {hi}, [{s}, #40]",
                    "ldr {z}, [{s}, #48]",
                    "ldr {t}, [{s}, #76]",
                    "add {z}, {z}, {t}",
                    "str {z}, [{s}, #48]",
                    // The edges step: q += a, r −= b; r < 0: r += d, q += 1.
                    "ldrd {t}, {u}, [{s}, #0]",
                    "ldrd {lo}, {hi}, [{s}, #8]",
                    "ldr {z}, [{s}, #16]",
                    "add {t}, {t}, {lo}",
                    "subs {u}, {u}, {hi}",
                    "itt mi",
                    "addmi {u}, {u}, {z}",
                    "addmi {t}, {t}, #1",
                    "strd {t}, {u}, [{s}, #0]",
                    "ldrd {t}, {u}, [{s}, #20]",
                    "ldrd {lo}, {hi}, [{s}, #28]",
                    "ldr {z}, [{s}, #36]",
                    "add {t}, {t}, {lo}",
                    "subs {u}, {u}, {hi}",
                    "itt mi",
                    "addmi {u}, {u}, {z}",
                    "addmi {t}, {t}, #1",
                    "strd {t}, {u}, [{s}, #20]",
                    // Both rows move on; the count of rows left.
                    "ldrd {cp}, {dp}, [{s}, #80]",
                    "ldr {t}, [{s}, #88]",
                    "add {cp}, {cp}, {t}",
                    "add {dp}, {dp}, {t}",
                    "strd {cp}, {dp}, [{s}, #80]",
                    "ldr {t}, [{s}, #92]",
                    "subs {t}, {t}, #1",
                    "str {t}, [{s}, #92]",
                    "bne 1b",
                    s = in(reg) s,
                    lo = out(reg) _,
                    hi = out(reg) _,
                    dlo = out(reg) _,
                    dhi = out(reg) _,
                    z = out(reg) _,
                    dz = out(reg) _,
                    cp = out(reg) _,
                    dp = out(reg) _,
                    i = out(reg) _,
                    t = out(reg) _,
                    u = out(reg) _,
                );
            }
        };
    }
    if SWAP {
        run!("rev16 {t}, {t}");
    } else {
        run!();
    }
    (left.q, left.r) = (st[0] as i32, st[1] as i32);
    (right.q, right.r) = (st[5] as i32, st[6] as i32);
    p.c_row = st[10] as u64 | (st[11] as u64) << 32;
    p.z_row = st[12] as i32;
    st[24]
}

/// The most a span's negative pixel index `−n` may be for [`thumb2_span`] to draw
/// it in pairs, for rows of colour cells `cp` and depth cells `dp`: −6 (six pixels
/// or more) when the cells are aligned alike, which holds for every row of a
/// target (colour and depth rows are both `width` cells apart); `i32::MIN` (never)
/// when they are not.
#[cfg(all(fixshade_dsp, not(feature = "small-flash")))]
#[inline(always)]
fn pair_limit(cp: *mut u16, dp: *mut u16) -> i32 {
    if (cp as usize ^ dp as usize) & 2 == 0 {
        -6
    } else {
        i32::MIN
    }
}

/// ARMv7-M and later (Thumb-2): one span, two pixels a step ([`thumb2_span`]) if
/// `pairs` and it has six pixels or more, else a pixel a step ([`thumb2_one`]).
/// Whole-frame fills pass `pairs` false: their triangles of six rows or more take
/// [`packed_565_rows`], and the others' spans are short (about two pixels a span
/// on the bench sphere at 128×80 @ 320×240), where the pair loop's twelfth
/// register costs the fill more than the pairs save (its draw 1.5 % more
/// instructions).
#[cfg(fixshade_dsp)]
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn thumb2(
    color: &mut [u16],
    depth: &mut [u16],
    n: usize,
    [lo, hi, dlo, dhi]: [u32; 4],
    z: i32,
    dz: i32,
    swap: bool,
    pairs: bool,
) {
    let (cp, dp) = (color[n..].as_mut_ptr(), depth[n..].as_mut_ptr());
    // 1 ≤ n ≤ 4096 (the guard band): −n fits i32 and is below zero.
    let i = -(n as i32);
    // The assembly of `$tpl` over the span's registers; `$v`: the pair loop's
    // third temporary.
    macro_rules! span_asm {
        ($($tpl:expr),+ ; $($v:ident)?) => {
            core::arch::asm!(
                $($tpl),+,
                cp = in(reg) cp,
                dp = in(reg) dp,
                i = inout(reg) i => _,
                lo = inout(reg) lo => _,
                hi = inout(reg) hi => _,
                dlo = in(reg) dlo,
                dhi = in(reg) dhi,
                z = inout(reg) z => _,
                dz = in(reg) dz,
                t = out(reg) _,
                u = out(reg) _,
                $($v = out(reg) _,)?
                options(nostack),
            )
        };
    }
    macro_rules! run {
        ($($rev:literal)?) => {
            // SAFETY: the loads and stores are at `cp + 2i` and `dp + 2i` for
            // i = −n, −n + 1, …, −1: the n two-byte cells of `color[..n]` and
            // `depth[..n]` (the pairs' words: cells i and i + 1, both of them),
            // borrowed mutably here; registers otherwise (flags clobbered, stack
            // untouched).
            #[allow(unsafe_code)]
            if pairs && n >= 6 {
                // Cells not aligned alike: a pixel a step (as `pair_limit`).
                unsafe {
                    span_asm!(
                        "eor {t}, {cp}, {dp}",
                        "tst {t}, #2",
                        "bne 3f",
                        thumb2_span!("{v}" $(, $rev)?);
                        v
                    )
                }
            } else {
                unsafe { span_asm!("2:", thumb2_one!("3" $(, $rev)?), "bne 2b";) }
            }
        };
    }
    if swap {
        run!("rev16 {t}, {t}");
    } else {
        run!();
    }
}

/// ARMv6-M (Thumb-1): most instructions reach only r0–r7, of which the compiler
/// lends six (and Thumb-1 code may name r8 and above only as clobbers). The depth
/// pointer, the colour row's offset from it, two temporaries and the colour's two
/// words take the six; the depth, the steps, the row's end and green's mask are
/// moved into r8–r12 and lr first (`MOV`, `ADD` and `CMP` reach those), read from a
/// block on the stack. Not inlined, for `small-flash` builds: one copy serves
/// every span, as the micro:bit images have only a few hundred bytes of flash to
/// spare. The call and the saving of r4–r11 cost about 40 instructions a span
/// (35 a span on the bench sphere at 128×80: 16.43 M against 15.92 M inlined for
/// the draw), so the other builds inline the loop.
#[cfg(fixshade_v6m)]
#[inline(never)]
fn v6m_outlined(
    color: &mut [u16],
    depth: &mut [u16],
    n: usize,
    c: [u32; 4],
    z: i32,
    dz: i32,
    swap: bool,
) {
    v6m(color, depth, n, c, z, dz, swap);
}

/// The loop of [`v6m_outlined`], inlined where it is called.
#[cfg(fixshade_v6m)]
#[inline(always)]
fn v6m(
    color: &mut [u16],
    depth: &mut [u16],
    n: usize,
    [lo, hi, dlo, dhi]: [u32; 4],
    z: i32,
    dz: i32,
    swap: bool,
) {
    let dp = depth.as_mut_ptr();
    let end = depth[n..].as_mut_ptr();
    // The colour row's byte offset from the depth row (modulo 2³²).
    let k = (color.as_mut_ptr() as usize).wrapping_sub(dp as usize);
    let block: [u32; 5] = [z as u32, dz as u32, dlo, dhi, end as u32];
    macro_rules! run {
        ($($rev:literal)?) => {
            // SAFETY: the loads and stores are at `p` (depth) and `p + k` (colour)
            // for p = dp, dp + 2, …, end − 2: the n two-byte cells of
            // `depth[..n]` and `color[..n]`, borrowed mutably here, and the five
            // words of `block`, read; registers otherwise (flags clobbered, the
            // stack pointer untouched).
            #[allow(unsafe_code)]
            unsafe {
                core::arch::asm!(
                    "ldr r3, [r2]",
                    "mov r8, r3",
                    "ldr r3, [r2, #4]",
                    "mov r9, r3",
                    "ldr r3, [r2, #8]",
                    "mov r10, r3",
                    "ldr r3, [r2, #12]",
                    "mov r11, r3",
                    "ldr r3, [r2, #16]",
                    "mov r12, r3",
                    "movs r3, #0x7e",
                    "lsls r3, r3, #4",
                    "mov lr, r3",
                    "2:",
                    "ldrh r2, [r0]",
                    "mov r3, r8",
                    "lsrs r3, r3, #16",
                    // Stored ≤ new: the pixel stays.
                    "cmp r2, r3",
                    "bls 3f",
                    "strh r3, [r0]",
                    "mov r2, lr",
                    "ands r2, r5",
                    "lsrs r3, r5, #27",
                    "lsls r3, r3, #11",
                    "orrs r2, r3",
                    "lsls r3, r4, #11",
                    "lsrs r3, r3, #27",
                    "orrs r2, r3",
                    $($rev,)?
                    "strh r2, [r0, r1]",
                    "3:",
                    "mov r2, r10",
                    "adds r4, r4, r2",
                    "mov r2, r11",
                    "adcs r5, r2",
                    "add r8, r9",
                    "adds r0, #2",
                    "cmp r0, r12",
                    "bne 2b",
                    inout("r0") dp => _,
                    in("r1") k,
                    inout("r2") block.as_ptr() => _,
                    out("r3") _,
                    inout("r4") lo => _,
                    inout("r5") hi => _,
                    out("r8") _,
                    out("r9") _,
                    out("r10") _,
                    out("r11") _,
                    out("r12") _,
                    out("lr") _,
                    options(nostack),
                );
            }
        };
    }
    if swap {
        run!("rev16 r2, r2");
    } else {
        run!();
    }
}
