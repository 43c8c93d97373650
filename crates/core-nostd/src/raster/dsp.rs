//! Two pixels per step for the parallel span methods on cores with the ARMv7E-M DSP
//! extension (Cortex-M4/M7): the k-way and segment methods
//! ([`super::parallel`]) pair neighbouring pixels in the two 16-bit halves of a
//! register, where the depth test of both is one `USUB16` and the choice of both
//! depths and both colours one `SEL` each.
//!
//! # What the lanes hold, and why that is exact
//!
//! A 16-bit lane cannot hold a channel value with its 16 fraction bits, so nothing
//! is interpolated in 16-bit lanes. Every pixel's values are stepped exactly as the
//! portable methods step them: depth in its own `i32` (Q16.16), the three colour
//! channels in one `u64` register with lanes of 21, 22 and 21 bits
//! ([`super::span`]'s packed register, the same SWAR form `Gradient` uses): lane `k`
//! of pixel `x0 + i` holds `v_k + i·g_k`, checked at both ends of the span to stay
//! inside its lane, so the register is a carry-free digit string and each lane's
//! integer bits are exactly `(v_k + i·g_k) >> 16`. Only those integer results meet in
//! 16-bit lanes: the depth's integer part, `(z as u32 >> 16) as u16`, which is what
//! the buffer holds, and the 5-6-5 pixel, which is 16 bits. On them the DSP
//! instructions are exact by definition:
//!
//! - [`pair_of_tops`] (`PKHTB`) puts the integer parts of two depths side by side;
//! - [`nearer`] (`USUB16`, then `SEL` twice): `USUB16` sets the GE flags of a half
//!   when `new ≥ stored` (no borrow), `SEL` then takes the stored depth and colour
//!   there and the new ones elsewhere: strictly nearer wins, a tie keeps the stored
//!   pixel, as in [`super::span::pack_pixel`];
//! - [`pixel_pair`] gathers the 5-6-5 fields of two packed registers with one
//!   half-word pack and one mask per channel (red and blue `PKHTB`, green `PKHBT`).
//!
//! The pixels are then written through the format ([`PixelFormat::pack`]) from
//! these fields, and the stored pixels it keeps are read through
//! [`PixelFormat::unpack`]: the path is taken only for formats with 5-6-5 channels
//! whose stored pixel is two bytes ([`is_565`]); their `pack` maps the 2¹⁶ channel
//! triples one-to-one onto the 2¹⁶ values of a two-byte pixel, so
//! `pack(unpack(p)) == p` for every stored `p` and the pixels the depth test keeps
//! are written back unchanged. On `Rgb565Le` the compiler folds both into the bare
//! 16-bit halves, and the two halves into one 32-bit load and store.
//!
//! On every other core the same functions are plain integer code (the portable
//! [`nearer`] is the specification of the assembly one); the host tests run the span
//! loops with it against the pixel-at-a-time reference, and the QEMU image
//! (`boards/qemu-mps2-an386`, `cargo xtask qemu`) checks the Cortex-M4 frames
//! against the host byte for byte.
//!
//! # Why there is `unsafe` here
//!
//! The crate denies `unsafe_code`. Stable Rust has no intrinsics for the DSP
//! instructions (`core::arch::arm`'s are unstable), so [`nearer`] and the two
//! half-word packs are `core::arch::asm!` blocks, each under its own
//! `#[allow(unsafe_code)]` with a SAFETY comment: they read and write registers only
//! (`options(pure, nomem, nostack)`), and `USUB16` and the `SEL`s that read its GE
//! flags sit in one block, so no flag state is expected across blocks.

use super::setup::ATTRS;
use super::span::DepthMode;
use crate::target::{DepthFormat, PixelFormat};

pub use crate::target::is_565;

/// `(hi & 0xFFFF_0000) | (lo >> 16)`: the top halves of `hi` and `lo`, `hi`'s on
/// top (`PKHTB hi, lo, ASR #16`).
///
/// ```
/// use fixshade::raster::dsp::pair_of_tops;
/// assert_eq!(pair_of_tops(0xAAAA_1111, 0xBBBB_2222), 0xAAAA_BBBB);
/// ```
#[inline(always)]
pub fn pair_of_tops(hi: u32, lo: u32) -> u32 {
    #[cfg(fixshade_dsp)]
    {
        let r: u32;
        // SAFETY: one register-only instruction (no memory, no stack, no flags).
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "pkhtb {r}, {hi}, {lo}, asr #16",
                r = lateout(reg) r,
                hi = in(reg) hi,
                lo = in(reg) lo,
                options(pure, nomem, nostack, preserves_flags),
            );
        }
        r
    }
    #[cfg(not(fixshade_dsp))]
    {
        (hi & 0xFFFF_0000) | (lo >> 16)
    }
}

/// `(lo & 0xFFFF) | ((hi << S) & 0xFFFF_0000)`: the bottom half of `lo` under the
/// top half of `hi << S` (`PKHBT lo, hi, LSL #S`, 1 ≤ S ≤ 31).
///
/// ```
/// use fixshade::raster::dsp::pair_of_bottoms;
/// assert_eq!(pair_of_bottoms::<16>(0xAAAA_1111, 0xBBBB_2222), 0x2222_1111);
/// assert_eq!(pair_of_bottoms::<4>(0xAAAA_1111, 0xBBBB_2222), 0xBBB2_1111);
/// ```
#[inline(always)]
pub fn pair_of_bottoms<const S: u32>(lo: u32, hi: u32) -> u32 {
    const { assert!(S >= 1 && S <= 31) };
    #[cfg(fixshade_dsp)]
    {
        let r: u32;
        // SAFETY: one register-only instruction (no memory, no stack, no flags).
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "pkhbt {r}, {lo}, {hi}, lsl #{s}",
                r = lateout(reg) r,
                lo = in(reg) lo,
                hi = in(reg) hi,
                s = const S,
                options(pure, nomem, nostack, preserves_flags),
            );
        }
        r
    }
    #[cfg(not(fixshade_dsp))]
    {
        (lo & 0xFFFF) | ((hi << S) & 0xFFFF_0000)
    }
}

/// The depth test of two pixels at once. `z` and `old_z` hold two depths each (the
/// first pixel in the low half), `c` and `old_c` the two new and the two stored
/// pixels. Returns the depths and pixels to store: in each half where `z` is
/// strictly below `old_z`, the new depth and pixel; elsewhere the stored ones.
///
/// On ARMv7E-M this is `USUB16` (GE flags of a half set where `z ≥ old_z`) and two
/// `SEL`s; elsewhere the same per half in plain code.
///
/// ```
/// use fixshade::raster::dsp::nearer;
/// // Low half: 5 < 9, the new pixel wins; high half: 7 = 7, the stored one stays.
/// let (z, c) = nearer(0x0007_0005, 0x0007_0009, 0xBBBB_AAAA, 0x2222_1111);
/// assert_eq!((z, c), (0x0007_0005, 0x2222_AAAA));
/// ```
#[inline(always)]
pub fn nearer(z: u32, old_z: u32, c: u32, old_c: u32) -> (u32, u32) {
    #[cfg(fixshade_dsp)]
    {
        let (nz, nc): (u32, u32);
        // SAFETY: register-only instructions (no memory, no stack); the GE flags
        // USUB16 sets are read by the SELs of the same block, and the flags are
        // declared clobbered (no `preserves_flags`).
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "usub16 {nz}, {z}, {oz}",
                "sel {nz}, {oz}, {z}",
                "sel {nc}, {oc}, {c}",
                nz = out(reg) nz,
                nc = lateout(reg) nc,
                z = in(reg) z,
                oz = in(reg) old_z,
                c = in(reg) c,
                oc = in(reg) old_c,
                options(pure, nomem, nostack),
            );
        }
        (nz, nc)
    }
    #[cfg(not(fixshade_dsp))]
    {
        let (mut nz, mut nc) = (0, 0);
        for h in [0, 16] {
            let m = 0xFFFFu32 << h;
            let keep = (z & m) < (old_z & m);
            nz |= if keep { z } else { old_z } & m;
            nc |= if keep { c } else { old_c } & m;
        }
        (nz, nc)
    }
}

/// `z + dz`, wrapping: one `ADD` that the compiler cannot see through. The depth
/// lanes of [`kway`] all step by the same `dz`, and the compiler would otherwise
/// rewrite them as one counter plus a base per lane kept on the stack (two loads and
/// two adds more per pair in the loop); through this each lane stays an
/// accumulator in a register, as the method has it.
#[inline(always)]
fn accumulate(z: i32, dz: i32) -> i32 {
    #[cfg(fixshade_dsp)]
    {
        let mut z = z;
        // SAFETY: one register-only instruction (no memory, no stack, no flags).
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "add {z}, {z}, {dz}",
                z = inout(reg) z,
                dz = in(reg) dz,
                options(pure, nomem, nostack, preserves_flags),
            );
        }
        z
    }
    #[cfg(not(fixshade_dsp))]
    {
        z.wrapping_add(dz)
    }
}

/// The 5-6-5 fields of two packed registers (red at bit 43, green at 21, blue at 0,
/// 16 fraction bits each; see the module docs), `c0`'s pixel in the low half:
/// `r << 11 | g << 5 | b` in each half.
///
/// In the high words the integer bits of red lie at 27..32 and of green at 5..11,
/// in the low words blue's at 16..21: the tops of the two high words put both reds
/// in place, the bottoms both greens, the tops of the two low words both blues;
/// one mask each clears the fraction bits around them.
///
/// ```
/// use fixshade::raster::dsp::pixel_pair;
/// let packed = |r: u64, g: u64, b: u64| (r << 43) + (g << 21) + b;
/// // Channels in Q.16 with fractions: (31.5, 2.25, 7.75) and (1.0, 63.5, 0.5).
/// let a = packed(31 << 16 | 0x8000, 2 << 16 | 0x4000, 7 << 16 | 0xC000);
/// let b = packed(1 << 16, 63 << 16 | 0x8000, 0x8000);
/// assert_eq!(pixel_pair(a, b), (1 << 11 | 63 << 5) << 16 | (31 << 11 | 2 << 5 | 7));
/// ```
#[inline(always)]
pub fn pixel_pair(c0: u64, c1: u64) -> u32 {
    let (lo0, hi0) = (c0 as u32, (c0 >> 32) as u32);
    let (lo1, hi1) = (c1 as u32, (c1 >> 32) as u32);
    #[cfg(fixshade_dsp)]
    {
        // The same steps as below in one block: the compiler would fold green's shifts
        // back into the mask 0x07E0_07E0, which is no immediate and takes a register
        // inside the pair loops.
        let (w, _t): (u32, u32);
        // SAFETY: register-only instructions (no memory, no stack); the flags are
        // left alone (no flag-setting forms).
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                "pkhtb {w}, {hi1}, {hi0}, asr #16",
                "and {w}, {w}, #0xF800F800",
                "pkhtb {t}, {lo1}, {lo0}, asr #16",
                "and {t}, {t}, #0x001F001F",
                "orr {w}, {w}, {t}",
                "lsr {t}, {hi0}, #5",
                "pkhbt {t}, {t}, {hi1}, lsl #11",
                "and {t}, {t}, #0x003F003F",
                "orr {w}, {w}, {t}, lsl #5",
                w = out(reg) w,
                t = out(reg) _t,
                lo0 = in(reg) lo0,
                hi0 = in(reg) hi0,
                lo1 = in(reg) lo1,
                hi1 = in(reg) hi1,
                options(pure, nomem, nostack, preserves_flags),
            );
        }
        w
    }
    #[cfg(not(fixshade_dsp))]
    {
        let red = pair_of_tops(hi1, hi0) & 0xF800_F800;
        // Green moved down by 5 bits first, so that its mask is an immediate.
        let green = pair_of_bottoms::<11>(hi0 >> 5, hi1) & 0x003F_003F;
        let blue = pair_of_tops(lo1, lo0) & 0x001F_001F;
        red | green << 5 | blue
    }
}

/// A stored pixel as its 5-6-5 fields (for [`is_565`] formats).
#[inline(always)]
fn fields<P: PixelFormat>(p: P::Raw) -> u32 {
    let [r, g, b] = P::unpack(p);
    (r << 11) | (g << 5) | b
}

/// The pixel of the 5-6-5 fields in the low half of `w`.
#[inline(always)]
fn pixel<P: PixelFormat>(w: u32) -> P::Raw {
    P::pack((w >> 11) & 31, (w >> 5) & 63, w & 31)
}

/// One pixel: depth test, then the pixel of the packed register `c`.
#[inline(always)]
fn single<P: PixelFormat, Z: DepthMode>(color: &mut P::Raw, depth: &mut [u16], c: u64, z: i32) {
    if Z::TEST && !depth[0].write_if_nearer(z) {
        return;
    }
    P::store(color, pixel::<P>(pixel_pair(c, c)));
}

/// Everything of a depth-tested pair between its loads and its stores: the depths
/// and pixels to store over `old_z` and `old_c`, for the packed registers `c` and the
/// depths `z` of the two pixels: [`nearer`] of [`pair_of_tops`] of the depths and
/// [`pixel_pair`]. On ARMv7E-M one block of 13 instructions with two scratch
/// registers (the depth test first, its GE flags kept across the pixel's gather for
/// the colour `SEL`).
#[inline(always)]
fn tested_pair(c: [u64; 2], z: [i32; 2], old_z: u32, old_c: u32) -> (u32, u32) {
    #[cfg(fixshade_dsp)]
    {
        let (lo0, hi0) = (c[0] as u32, (c[0] >> 32) as u32);
        let (lo1, hi1) = (c[1] as u32, (c[1] >> 32) as u32);
        let (mut nz, mut nc) = (old_z, old_c);
        // SAFETY: register-only instructions (no memory, no stack). USUB16 sets the
        // GE flags the two SELs read; nothing between them writes GE (PKH, AND, ORR
        // and LSR do not), and the flags are declared clobbered.
        #[allow(unsafe_code)]
        unsafe {
            core::arch::asm!(
                // Depths: the integer parts side by side, nearer where strictly below.
                "pkhtb {t}, {z1}, {z0}, asr #16",
                "usub16 {w}, {t}, {nz}",
                "sel {nz}, {nz}, {t}",
                // The two 5-6-5 pixels (as `pixel_pair`).
                "pkhtb {w}, {hi1}, {hi0}, asr #16",
                "and {w}, {w}, #0xF800F800",
                "pkhtb {t}, {lo1}, {lo0}, asr #16",
                "and {t}, {t}, #0x001F001F",
                "orr {w}, {w}, {t}",
                "lsr {t}, {hi0}, #5",
                "pkhbt {t}, {t}, {hi1}, lsl #11",
                "and {t}, {t}, #0x003F003F",
                "orr {w}, {w}, {t}, lsl #5",
                // The pixels where the depth test passed.
                "sel {nc}, {nc}, {w}",
                nz = inout(reg) nz,
                nc = inout(reg) nc,
                w = out(reg) _,
                t = out(reg) _,
                lo0 = in(reg) lo0,
                hi0 = in(reg) hi0,
                lo1 = in(reg) lo1,
                hi1 = in(reg) hi1,
                z0 = in(reg) z[0],
                z1 = in(reg) z[1],
                options(pure, nomem, nostack),
            );
        }
        (nz, nc)
    }
    #[cfg(not(fixshade_dsp))]
    {
        let zz = pair_of_tops(z[1] as u32, z[0] as u32);
        nearer(zz, old_z, pixel_pair(c[0], c[1]), old_c)
    }
}

/// One pair with the depth test: the packed registers and depths of two
/// neighbouring pixels, the first in `color[0]`.
#[inline(always)]
fn pair_tested<P: PixelFormat>(
    color: &mut [P::Raw; 2],
    depth: &mut [u16; 2],
    c: [u64; 2],
    z: [i32; 2],
) {
    let old_z = depth[0] as u32 | (depth[1] as u32) << 16;
    let old_c = fields::<P>(color[0]) | fields::<P>(color[1]) << 16;
    let (nz, nc) = tested_pair(c, z, old_z, old_c);
    depth[0] = nz as u16;
    depth[1] = (nz >> 16) as u16;
    P::store(&mut color[0], pixel::<P>(nc));
    P::store(&mut color[1], pixel::<P>(nc >> 16));
}

/// One pair without depth.
#[inline(always)]
fn pair_plain<P: PixelFormat>(color: &mut [P::Raw; 2], c: [u64; 2]) {
    let w = pixel_pair(c[0], c[1]);
    P::store(&mut color[0], pixel::<P>(w));
    P::store(&mut color[1], pixel::<P>(w >> 16));
}

/// The pixel where a paired loop starts: 1 if the first pixel's depth (or, without
/// depth, colour) lies at an odd half-word address, so that the pairs' 32-bit loads
/// and stores are word-aligned (an unaligned one costs extra bus cycles on the M4).
#[inline(always)]
fn peel<P: PixelFormat, Z: DepthMode>(color: &[P::Raw], depth: &[u16]) -> usize {
    let addr = if Z::TEST {
        depth.as_ptr() as usize
    } else {
        color.as_ptr() as usize
    };
    (addr >> 1) & 1
}

/// The k-way method (`K` accumulators, the j-th starting at pixel `j` and stepping
/// `K·ΔI`, seed 000 §3.1) in pairs of pixels: `c`/`z` are the lanes' packed colours
/// and depths at the span's first `K` pixels, `dc`/`dz` their step. Pixel `q` takes
/// lane `q mod K`, which then steps; consecutive pixels are tested and stored two at
/// a time. Values as [`super::span::write_run`]'s, provided every channel stays in
/// its lane over the span (the caller checks both ends).
///
/// ```
/// use fixshade::raster::dsp::kway;
/// use fixshade::raster::span::DepthTest;
/// use fixshade::target::{PixelFormat, Rgb565Le};
/// let packed = |r: u64, g: u64, b: u64| (r << 43) + (g << 21) + b;
/// // Red 0, 1, 2, … in two lanes stepping two pixels; depth 9 at the first pixel, +1.
/// let d = packed(1 << 16, 0, 0);
/// let (mut color, mut depth) = ([0u16; 7], [8u16; 7]);
/// kway::<2, Rgb565Le, DepthTest>(&mut color, &mut depth, [0, d], [9 << 16, 10 << 16], 2 * d, 2 << 16);
/// assert!(color.iter().all(|&p| p == 0)); // every depth ≥ 8: nothing drawn
/// let mut depth = [100u16; 7];
/// kway::<2, Rgb565Le, DepthTest>(&mut color, &mut depth, [0, d], [9 << 16, 10 << 16], 2 * d, 2 << 16);
/// assert_eq!(color.map(|p| Rgb565Le::unpack(p)[0]), [0, 1, 2, 3, 4, 5, 6]);
/// assert_eq!(depth, [9, 10, 11, 12, 13, 14, 15]);
/// ```
#[inline(always)]
pub fn kway<const K: usize, P: PixelFormat, Z: DepthMode>(
    color: &mut [P::Raw],
    depth: &mut [u16],
    mut c: [u64; K],
    mut z: [i32; K],
    dc: u64,
    dz: i32,
) {
    let (color, depth) = if !color.is_empty() && peel::<P, Z>(color, depth) == 1 {
        let d = if Z::TEST { &mut depth[..1] } else { &mut [] };
        single::<P, Z>(&mut color[0], d, c[0], z[0]);
        c[0] = c[0].wrapping_add(dc);
        z[0] = z[0].wrapping_add(dz);
        // Pixel 1 is now the first: lane 1 takes the place of lane 0.
        c.rotate_left(1);
        z.rotate_left(1);
        (
            &mut color[1..],
            if Z::TEST { &mut depth[1..] } else { depth },
        )
    } else {
        (color, depth)
    };
    let gp = group_pairs(K);
    // Whole groups of GP pairs in the loop, then fewer than GP pairs, then maybe one
    // pixel, each taking the lanes in the same order.
    let (pairs, odd) = (color.len() / 2, color.len() % 2 == 1);
    let rest = pairs % gp;
    let (cfull, crest) = color.split_at_mut(2 * (pairs - rest));
    let mut unused = [0u16; 2];
    if Z::TEST {
        let (dfull, drest) = depth.split_at_mut(cfull.len().min(depth.len()));
        for (cc, dd) in cfull
            .chunks_exact_mut(2 * gp)
            .zip(dfull.chunks_exact_mut(2 * gp))
        {
            for p in 0..gp {
                lane_pair::<K, P, Z>(pair_at(cc, p), pair_at(dd, p), &mut c, &mut z, p, dc, dz);
            }
        }
        for p in 0..rest.min(gp) {
            lane_pair::<K, P, Z>(
                pair_at(crest, p),
                pair_at(drest, p),
                &mut c,
                &mut z,
                p,
                dc,
                dz,
            );
        }
        if odd {
            last_pixel::<K, P, Z>(crest, drest, &c, &z, rest);
        }
    } else {
        for cc in cfull.chunks_exact_mut(2 * gp) {
            for p in 0..gp {
                lane_pair::<K, P, Z>(pair_at(cc, p), &mut unused, &mut c, &mut z, p, dc, dz);
            }
        }
        for p in 0..rest.min(gp) {
            lane_pair::<K, P, Z>(pair_at(crest, p), &mut unused, &mut c, &mut z, p, dc, dz);
        }
        if odd {
            last_pixel::<K, P, Z>(crest, &mut [], &c, &z, rest);
        }
    }
}

/// The odd last pixel of [`kway`], after `rest` pairs of a group: pixel `2·rest` of
/// the group, at the end of `color` (and `depth`), takes lane `2·rest mod K`. The
/// lane is chosen among constant indices: a variable index would keep the lanes in
/// memory throughout the loop.
#[inline(always)]
fn last_pixel<const K: usize, P: PixelFormat, Z: DepthMode>(
    color: &mut [P::Raw],
    depth: &mut [u16],
    c: &[u64; K],
    z: &[i32; K],
    rest: usize,
) {
    let a = (2 * rest) % K;
    let dl = depth.len();
    if let Some(px) = color.last_mut() {
        for j in 0..K {
            if j == a {
                let d = if Z::TEST {
                    &mut depth[dl - 1..]
                } else {
                    &mut []
                };
                single::<P, Z>(px, d, c[j], z[j]);
            }
        }
    }
}

/// Pair `p` of `s`: its elements `2p` and `2p + 1`.
#[inline(always)]
fn pair_at<T>(s: &mut [T], p: usize) -> &mut [T; 2] {
    match (&mut s[2 * p..2 * p + 2]).try_into() {
        Ok(pair) => pair,
        Err(_) => unreachable!("a range of two elements"),
    }
}

/// Pairs per group of [`kway`]: a group uses every lane equally often (once for even
/// `K`, twice for odd `K`), so the lanes are back in order at its end.
const fn group_pairs(k: usize) -> usize {
    if k % 2 == 0 {
        k / 2
    } else {
        k
    }
}

/// Pair `p` of a [`kway`] group: pixels `2p` and `2p + 1` of the group take lanes
/// `2p mod K` and `(2p + 1) mod K`, which then step.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn lane_pair<const K: usize, P: PixelFormat, Z: DepthMode>(
    color: &mut [P::Raw; 2],
    depth: &mut [u16; 2],
    c: &mut [u64; K],
    z: &mut [i32; K],
    p: usize,
    dc: u64,
    dz: i32,
) {
    let (a, b) = ((2 * p) % K, (2 * p + 1) % K);
    if Z::TEST {
        pair_tested::<P>(color, depth, [c[a], c[b]], [z[a], z[b]]);
    } else {
        pair_plain::<P>(color, [c[a], c[b]]);
    }
    for j in [a, b] {
        c[j] = c[j].wrapping_add(dc);
        z[j] = accumulate(z[j], dz);
    }
}

/// The per-triangle offsets of one pair of a [`segment`]: pixels `k` and `k + 1` of
/// the segment at `base + k·ΔI` and `base + (k + 1)·ΔI`, packed colours and depths
/// side by side (one pointer walks them).
///
/// ```
/// use fixshade::raster::dsp::PairOffsets;
/// let p = PairOffsets { c: [0, 5], z: [0, 7] };
/// assert_eq!(p.c[1] + p.z[1] as u64, 12);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct PairOffsets {
    /// Packed colour offsets of the two pixels.
    pub c: [u64; 2],
    /// Depth offsets of the two pixels.
    pub z: [i32; 2],
}

/// The segment method (`P` units filling a segment of `w` pixels, pixel `k` of a
/// segment at `base + k·ΔI`, seed 000 §3.2) in pairs of pixels: `lanes` are the
/// per-triangle offsets `k·ΔI` of the `w = 2·lanes.len()` pixels, `c`/`z` the values
/// at the span's first pixel and `dc`/`dz` one pixel's increment (the segments start
/// at the first pixel of the first aligned pair). Values as
/// [`super::span::write_run`]'s, provided every channel stays in its lane over the
/// span.
///
/// ```
/// use fixshade::raster::dsp::{segment, PairOffsets};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::target::{PixelFormat, Rgb565Le};
/// let packed = |r: u64, g: u64, b: u64| (r << 43) + (g << 21) + b;
/// // Green 0, 1, 2, … in segments of 4 pixels.
/// let d = packed(0, 1 << 16, 0);
/// let lanes = [PairOffsets { c: [0, d], z: [0; 2] }, PairOffsets { c: [2 * d, 3 * d], z: [0; 2] }];
/// let mut color = [0u16; 11];
/// segment::<Rgb565Le, NoDepth>(&mut color, &mut [], &lanes, 0, 0, d, 0);
/// assert_eq!(color.map(|p| Rgb565Le::unpack(p)[1]), [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10]);
/// ```
#[inline(always)]
pub fn segment<P: PixelFormat, Z: DepthMode>(
    color: &mut [P::Raw],
    depth: &mut [u16],
    lanes: &[PairOffsets],
    mut c: u64,
    mut z: i32,
    dc: u64,
    dz: i32,
) {
    let wp = lanes.len();
    if color.is_empty() || wp == 0 {
        return;
    }
    // The segment step w·ΔI: the last offset plus one increment.
    let (step_c, step_z) = (
        lanes[wp - 1].c[1].wrapping_add(dc),
        lanes[wp - 1].z[1].wrapping_add(dz),
    );
    let (color, depth) = if peel::<P, Z>(color, depth) == 1 {
        let d = if Z::TEST { &mut depth[..1] } else { &mut [] };
        single::<P, Z>(&mut color[0], d, c, z);
        c = c.wrapping_add(dc);
        z = z.wrapping_add(dz);
        (
            &mut color[1..],
            if Z::TEST { &mut depth[1..] } else { depth },
        )
    } else {
        (color, depth)
    };
    let pairs = color.len() / 2;
    let (cpairs, ctail) = color.split_at_mut(2 * pairs);
    if Z::TEST {
        let dpairs = &mut depth[..2 * pairs];
        for (cs, ds) in cpairs.chunks_mut(2 * wp).zip(dpairs.chunks_mut(2 * wp)) {
            let pairs = cs.chunks_exact_mut(2).zip(ds.chunks_exact_mut(2));
            for ((cc, dd), o) in pairs.zip(lanes) {
                let cc2 = [c.wrapping_add(o.c[0]), c.wrapping_add(o.c[1])];
                let zz2 = [z.wrapping_add(o.z[0]), z.wrapping_add(o.z[1])];
                // In two blocks: the offsets' sums are the loop's temporaries here,
                // and one block would need all six at once.
                let old_z = dd[0] as u32 | (dd[1] as u32) << 16;
                let old_c = fields::<P>(cc[0]) | fields::<P>(cc[1]) << 16;
                let w = pixel_pair(cc2[0], cc2[1]);
                let zz = pair_of_tops(zz2[1] as u32, zz2[0] as u32);
                let (nz, nc) = nearer(zz, old_z, w, old_c);
                dd[0] = nz as u16;
                dd[1] = (nz >> 16) as u16;
                P::store(&mut cc[0], pixel::<P>(nc));
                P::store(&mut cc[1], pixel::<P>(nc >> 16));
            }
            c = c.wrapping_add(step_c);
            z = z.wrapping_add(step_z);
        }
    } else {
        for cs in cpairs.chunks_mut(2 * wp) {
            for (cc, o) in cs.chunks_exact_mut(2).zip(lanes) {
                let cc = pair_at(cc, 0);
                pair_plain::<P>(cc, [c.wrapping_add(o.c[0]), c.wrapping_add(o.c[1])]);
            }
            c = c.wrapping_add(step_c);
            z = z.wrapping_add(step_z);
        }
    }
    // An odd last pixel: pixel k of the last segment (a new one when k = 0).
    if let Some(px) = ctail.first_mut() {
        let k = pairs % wp;
        let (c, z) = if k == 0 {
            (c, z)
        } else {
            (c.wrapping_sub(step_c), z.wrapping_sub(step_z))
        };
        let d = if Z::TEST {
            &mut depth[2 * pairs..]
        } else {
            &mut []
        };
        let o = &lanes[k];
        single::<P, Z>(px, d, c.wrapping_add(o.c[0]), z.wrapping_add(o.z[0]));
    }
}

/// The shortest span the paired loops take: below it the lane set-up and the range
/// check cost more than the pairs save (on the Cortex-M4 the triangle-bound
/// benchmark, spans of two to four pixels, draws faster with the portable loops).
pub const MIN_SPAN: usize = 8;

/// Lane widths of the packed 5-6-5 channels (R, G, B): 16 fraction bits above the
/// 5, 6 and 5 integer bits.
const LANE: [u32; 3] = [21, 22, 21];
/// Where each lane starts: blue at bit 0, green above it, red on top.
const OFFSET: [u32; 3] = [43, 21, 0];

/// The packed form of the three colour channels of `v` in the 5-6-5 lanes,
/// `Σ vₖ·2^offsetₖ` modulo 2⁶⁴ (signed values sign-extended): for an increment, once
/// per triangle. Linear, like `super::pixel`'s `packed_channels` for the 5-6-5
/// formats, which it equals.
///
/// ```
/// use fixshade::raster::dsp::packed_565;
/// assert_eq!(packed_565(&[1, 2, 3, 0]), (1 << 43) + (2 << 21) + 3);
/// assert_eq!(packed_565(&[0, 0, -1, 0]), u64::MAX); // −1 in the lowest lane
/// ```
pub fn packed_565(v: &[i32; ATTRS]) -> u64 {
    let mut p = 0u64;
    for k in 0..3 {
        p = p.wrapping_add((v[k] as i64 as u64) << OFFSET[k]);
    }
    p
}

/// The packed colour of a span's first pixel, `v` its values and `g` the increment,
/// when every channel of its `n` pixels stays inside its lane, so that the packed
/// register stepped by [`packed_565`]`(g)` holds every pixel's channels exactly;
/// `None` otherwise (the span takes the portable loop). The values are linear in the
/// pixel, so the first and the last pixel are checked (in `i64`, one multiply-add
/// each), and in range the lanes are packed by three shifts without carries.
///
/// ```
/// use fixshade::raster::dsp::span_start_565;
/// // Red 31.9 falling by 1 per pixel: in range over 32 pixels, not over 33.
/// let v = [(31 << 16) + 0xE000, 0, 0, 0];
/// let g = [-(1 << 16), 0, 0, 0];
/// assert_eq!(span_start_565(&v, &g, 32), Some(((31 << 16) + 0xE000) << 43));
/// assert_eq!(span_start_565(&v, &g, 33), None);
/// ```
#[inline(always)]
pub fn span_start_565(v: &[i32; ATTRS], g: &[i32; ATTRS], n: usize) -> Option<u64> {
    // A span lies in one row of at most 4096 pixels; anything longer is refused
    // before (n − 1) is taken as an i32.
    if n == 0 || n > 1 << 16 {
        return None;
    }
    let last = (n - 1) as i32 as i64;
    let mut out = 0u64;
    for k in 0..3 {
        // |g| < 2^31 and last < 2^16: the product and the sum fit i64.
        let e = v[k] as i64 + last * g[k] as i64;
        out |= (e as u64 | v[k] as u32 as u64) >> LANE[k];
    }
    if out != 0 {
        return None;
    }
    // 0 ≤ vₖ < 2^LANEₖ: blue fills bits 0..21 and green's low 11 bits lie above it
    // in the low word, green's high bits and red (shifted 11) in the high word.
    let (r, g, b) = (v[0] as u32, v[1] as u32, v[2] as u32);
    let lo = b | g << 21;
    let hi = g >> 11 | r << 11;
    Some(lo as u64 | (hi as u64) << 32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::pixel::packed_channels;
    use crate::raster::span::{pack_pixel, DepthTest, NoDepth};
    use crate::target::{Rgb565Be, Rgb565Le};

    /// The portable `nearer` is the per-half specification, for every order of the
    /// two halves (including ties and the ends of the u16 range).
    #[test]
    fn nearer_is_the_per_half_depth_test() {
        let vals = [0u32, 1, 2, 0x7FFF, 0x8000, 0xFFFE, 0xFFFF];
        for &z0 in &vals {
            for &o0 in &vals {
                for &z1 in &vals {
                    for &o1 in &vals {
                        let (nz, nc) =
                            nearer(z1 << 16 | z0, o1 << 16 | o0, 0xAAAA_BBBB, 0x1111_2222);
                        let lo = if z0 < o0 { (z0, 0xBBBB) } else { (o0, 0x2222) };
                        let hi = if z1 < o1 { (z1, 0xAAAA) } else { (o1, 0x1111) };
                        assert_eq!((nz, nc), (hi.0 << 16 | lo.0, hi.1 << 16 | lo.1));
                    }
                }
            }
        }
    }

    /// The lanes `pixel_pair` reads are `Packed`'s for both 5-6-5 formats.
    #[test]
    fn pixel_pair_reads_the_packed_lanes() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for _ in 0..100_000 {
            let ch = |r: u64, max: u32| (r % (((max as u64) + 1) << 16)) as i32;
            let a = [ch(rnd(), 31), ch(rnd(), 63), ch(rnd(), 31), 0];
            let b = [ch(rnd(), 31), ch(rnd(), 63), ch(rnd(), 31), 0];
            let (pa, pb) = (
                packed_channels::<Rgb565Le>(&a).unwrap(),
                packed_channels::<Rgb565Le>(&b).unwrap(),
            );
            assert_eq!(Some(pa), packed_channels::<Rgb565Be>(&a));
            let f = |v: [i32; 4]| ((v[0] >> 16) << 11 | (v[1] >> 16) << 5 | (v[2] >> 16)) as u32;
            assert_eq!(pixel_pair(pa, pb), f(b) << 16 | f(a));
        }
    }

    /// `span_start_565` accepts a span exactly when every pixel's channels lie in
    /// their lanes (checked pixel by pixel here), and then packs the first pixel as
    /// `packed_channels` does; `packed_565` is `packed_channels` for the 5-6-5
    /// formats, for signed increments too.
    #[test]
    fn span_start_is_the_lane_check() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let (mut some, mut none) = (0, 0);
        for _ in 0..100_000 {
            let n = match rng.next() % 8 {
                0 => 4096,
                1 => (rng.next() % 4096 + 1) as usize,
                _ => (rng.next() % 64 + 1) as usize,
            };
            let mut v = [0i32; ATTRS];
            let mut g = [0i32; ATTRS];
            for k in 0..3 {
                let lane = 1i64 << LANE[k];
                // Mostly in range, sometimes just outside or anywhere.
                v[k] = match rng.next() % 8 {
                    0 => rng.next() as i32,
                    1 => (lane + (rng.next() % 4) as i64 - 2) as i32,
                    2 => (rng.next() % 4) as i32 - 2,
                    _ => (rng.next() as i64).rem_euclid(lane) as i32,
                };
                // Towards a random end value, give or take one unit.
                let end = (rng.next() as i64).rem_euclid(lane);
                let to_end = (end - v[k] as i64) / (n as i64 - 1).max(1);
                g[k] = match rng.next() % 8 {
                    0 => rng.next() as i32,
                    _ => to_end as i32 + (rng.next() % 3) as i32 - 1,
                };
            }
            v[3] = rng.next() as i32;
            g[3] = rng.next() as i32;
            let inside = (0..3).all(|k| {
                (0..n as i64)
                    .all(|i| (0..1i64 << LANE[k]).contains(&(v[k] as i64 + i * g[k] as i64)))
            });
            let want = inside.then(|| packed_channels::<Rgb565Le>(&v).unwrap());
            assert_eq!(span_start_565(&v, &g, n), want, "v {v:?} g {g:?} n {n}");
            assert_eq!(Some(packed_565(&g)), packed_channels::<Rgb565Le>(&g));
            if inside {
                some += 1;
            } else {
                none += 1;
            }
        }
        assert!(some > 5_000 && none > 5_000, "{some} {none}");
        assert_eq!(span_start_565(&[0; 4], &[0; 4], 0), None);
    }

    /// xorshift64.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
    }

    /// A random span of `n` pixels whose channels stay in range (as the setup
    /// guarantees at covered pixels), depth anywhere in u32.
    fn span_values<P: PixelFormat>(rng: &mut Rng, n: usize) -> ([i32; ATTRS], [i32; ATTRS]) {
        let mut v = [0i32; ATTRS];
        let mut g = [0i32; ATTRS];
        for k in 0..3 {
            let max = ((P::MAX[k] as i64 + 1) << 16) - 1;
            let a = (rng.next() as i64 % (max + 1)).abs();
            let e = (rng.next() as i64 % (max + 1)).abs();
            v[k] = a as i32;
            g[k] = if n > 1 {
                ((e - a) / (n as i64 - 1)) as i32
            } else {
                0
            };
        }
        v[3] = rng.next() as i32;
        g[3] = (rng.next() as i32) >> (rng.next() % 32);
        (v, g)
    }

    /// The specification: one pixel at a time, value `i` is `v` plus `i` wrapping
    /// adds of `g`, stored where the depth is strictly nearer.
    fn reference<P: PixelFormat, Z: DepthMode>(
        color: &mut [P::Raw],
        depth: &mut [u16],
        v: [i32; ATTRS],
        g: &[i32; ATTRS],
    ) {
        let mut v = v;
        for i in 0..color.len() {
            let mut unused = 0;
            let d = if Z::TEST { &mut depth[i] } else { &mut unused };
            pack_pixel::<P, Z>(&mut color[i], d, &v);
            for k in 0..ATTRS {
                v[k] = v[k].wrapping_add(g[k]);
            }
        }
    }

    /// Random spans of 1..=45 pixels starting at both half-word parities, over random
    /// depth rows and random stored pixels: the paired k-way and segment loops (with
    /// the portable lane operations) write exactly the reference's pixels and depths.
    fn paired_loops_equal_the_reference<P: PixelFormat, Z: DepthMode>() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for _ in 0..30_000 {
            let n = (rng.next() % 45 + 1) as usize;
            let at = (rng.next() % 2) as usize;
            let (v, g) = span_values::<P>(&mut rng, n);
            let old: [u16; 48] = core::array::from_fn(|_| rng.next() as u16);
            let oldc: [P::Raw; 48] = core::array::from_fn(|_| {
                let r = rng.next();
                P::pack((r & 31) as u32, (r >> 8 & 63) as u32, (r >> 16 & 31) as u32)
            });
            let (mut c0, mut d0) = (oldc, old);
            fn part<Z: DepthMode>(d: &mut [u16; 48], at: usize, n: usize) -> &mut [u16] {
                if Z::TEST {
                    &mut d[at..at + n]
                } else {
                    &mut []
                }
            }
            reference::<P, Z>(&mut c0[at..at + n], part::<Z>(&mut d0, at, n), v, &g);
            let p = span_start_565(&v, &g, n).expect("channels in range");
            let d = packed_565(&g);
            macro_rules! check_kway {
                ($k:literal) => {{
                    let c: [u64; $k] =
                        core::array::from_fn(|j| p.wrapping_add(d.wrapping_mul(j as u64)));
                    let z: [i32; $k] =
                        core::array::from_fn(|j| v[3].wrapping_add(g[3].wrapping_mul(j as i32)));
                    let (dc, dzs) = (d.wrapping_mul($k), g[3].wrapping_mul($k));
                    let (mut c1, mut d1) = (oldc, old);
                    kway::<$k, P, Z>(
                        &mut c1[at..at + n],
                        part::<Z>(&mut d1, at, n),
                        c,
                        z,
                        dc,
                        dzs,
                    );
                    assert_eq!(
                        (c1, d1),
                        (c0, d0),
                        "kway{} n {n} at {at} v {v:?} g {g:?}",
                        $k
                    );
                }};
            }
            check_kway!(2);
            check_kway!(3);
            check_kway!(4);
            for w in [2, 4, 8, 14, 22, 32] {
                let lanes: [PairOffsets; 16] = core::array::from_fn(|j| {
                    let k = 2 * j as u64;
                    PairOffsets {
                        c: [d.wrapping_mul(k), d.wrapping_mul(k + 1)],
                        z: [g[3].wrapping_mul(k as i32), g[3].wrapping_mul(k as i32 + 1)],
                    }
                });
                let (mut c1, mut d1) = (oldc, old);
                let lanes = &lanes[..w / 2];
                segment::<P, Z>(
                    &mut c1[at..at + n],
                    part::<Z>(&mut d1, at, n),
                    lanes,
                    p,
                    v[3],
                    d,
                    g[3],
                );
                assert_eq!(
                    (c1, d1),
                    (c0, d0),
                    "segment w {w} n {n} at {at} v {v:?} g {g:?}"
                );
            }
        }
    }

    #[test]
    fn paired_loops_are_bit_identical_to_the_pixel_loop() {
        paired_loops_equal_the_reference::<Rgb565Le, DepthTest>();
        paired_loops_equal_the_reference::<Rgb565Le, NoDepth>();
        paired_loops_equal_the_reference::<Rgb565Be, DepthTest>();
        paired_loops_equal_the_reference::<Rgb565Be, NoDepth>();
    }
}
