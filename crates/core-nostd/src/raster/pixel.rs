//! The pixel stage shared by every span method: the depth test against the depth
//! row (`u16` or `u32` cells, [`DepthFormat`]; strictly nearer wins), packing to the
//! pixel format, the store ([`pack_pixel`], [`write_run`]); the depth modes
//! ([`DepthTest`], [`NoDepth`]) that choose whether a draw tests depth.

use super::setup::ATTRS;
use super::shading::Shading;
use crate::target::{DepthFormat, PixelFormat};

/// Depth handling, chosen once per draw call.
///
/// ```
/// use fixshade::raster::span::{DepthMode, DepthTest, NoDepth};
/// // Chosen by type, so a frame without depth has no depth code in its pixel loop.
/// assert!(DepthTest::TEST && !NoDepth::TEST);
/// ```
pub trait DepthMode {
    /// True to test and write the target's depth buffer.
    const TEST: bool;
}

/// Test and write depth: a pixel is drawn when its depth is strictly below the
/// stored one.
///
/// ```
/// use fixshade::raster::span::{pack_pixel, DepthTest};
/// use fixshade::target::Gray8;
/// let (mut c, mut d) = (0u8, 0xFFFFu16);
/// pack_pixel::<Gray8, DepthTest>(&mut c, &mut d, &[200 << 16, 0, 0, 9 << 16]);
/// assert_eq!((c, d), (200, 9));
/// // A tie is not nearer: the first writer keeps the pixel.
/// pack_pixel::<Gray8, DepthTest>(&mut c, &mut d, &[50 << 16, 0, 0, 9 << 16]);
/// assert_eq!(c, 200);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct DepthTest;
/// Ignore depth; later triangles overwrite earlier ones.
///
/// ```
/// use fixshade::raster::span::{pack_pixel, NoDepth};
/// use fixshade::target::Gray8;
/// let (mut c, mut d) = (0u8, 0u16);
/// pack_pixel::<Gray8, NoDepth>(&mut c, &mut d, &[77 << 16, 0, 0, 9 << 16]);
/// assert_eq!((c, d), (77, 0)); // written regardless of depth; depth untouched
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct NoDepth;

impl DepthMode for DepthTest {
    const TEST: bool = true;
}
impl DepthMode for NoDepth {
    const TEST: bool = false;
}

/// Packs the rounded channels `r >> 16`, `g >> 16`, `b >> 16`. Channel values are in
/// [0, MAX + 0.57) by the setup bound, so the shifts give 0..=MAX.
#[inline(always)]
fn pack<P: PixelFormat>(r: i32, g: i32, b: i32) -> P::Raw {
    P::pack((r >> 16) as u32, (g >> 16) as u32, (b >> 16) as u32)
}

/// The pixel stage for one pixel: depth test (strictly nearer wins), pack, store.
/// `d` is ignored without a depth test.
///
/// ```
/// use fixshade::raster::span::{pack_pixel, DepthTest};
/// use fixshade::target::{PixelFormat, Rgb565Le};
/// let (mut c, mut d) = (0u16, 0xFFFFu16);
/// // Channels in Q.16 5-6-5 units (rounded), depth Q16.16.
/// pack_pixel::<Rgb565Le, DepthTest>(&mut c, &mut d, &[31 << 16, 32 << 16, 0, 100 << 16]);
/// assert_eq!((Rgb565Le::unpack(c), d), ([31, 32, 0], 100));
/// // A 32-bit depth cell keeps the fraction too.
/// let mut d32 = u32::MAX;
/// pack_pixel::<Rgb565Le, DepthTest>(&mut c, &mut d32, &[0, 0, 0, (99 << 16) + 7]);
/// assert_eq!(d32, (99 << 16) + 7);
/// ```
#[inline(always)]
pub fn pack_pixel<P: PixelFormat, Z: DepthMode>(
    c: &mut P::Raw,
    d: &mut impl DepthFormat,
    v: &[i32; ATTRS],
) {
    if Z::TEST && !d.write_if_nearer(v[3]) {
        return;
    }
    P::store(c, pack::<P>(v[0], v[1], v[2]));
}

/// The three colour channels of a span held in one `u64`, one add per pixel (SWAR).
///
/// Channel `k` takes a lane of `16 + bits(MAX[k])` bits (blue lowest): for
/// Rgb565 21 + 22 + 21 = 64 bits. The packed start is `Σ v_k·2^off_k` and the packed
/// increment `Σ g_k·2^off_k` (signed, modulo 2⁶⁴), so after `i` adds the register
/// holds `Σ (v_k + i·g_k)·2^off_k` modulo 2⁶⁴ exactly. When every channel value
/// `v_k + i·g_k` lies in `[0, 2^L_k)`, that sum is a base-2^L digit string without
/// borrows or carries between lanes, and each lane's top `bits(MAX[k])` bits are
/// exactly `(v_k + i·g_k) >> 16`, the value the scalar loop packs. The values are
/// linear in `i`, so checking both ends of the span (in `i64`, no wrapping) covers
/// every pixel; a span that fails the check or is shorter than four pixels (or a
/// format whose lanes do not fit 64 bits) takes the scalar loop. With the check at both ends, the values are the true
/// unwrapped ones: a span of two or more pixels has `|g_k| < 2^L_k`, so the wrapped
/// `i32` increment equals the true one.
struct Packed<P>(core::marker::PhantomData<P>);

/// Bits of the integer part of a channel whose largest value is `max`.
const fn int_bits(max: u32) -> u32 {
    32 - max.leading_zeros()
}

impl<P: PixelFormat> Packed<P> {
    /// Lane widths, blue (channel 2) lowest.
    const L: [u32; 3] = [
        16 + int_bits(P::MAX[0]),
        16 + int_bits(P::MAX[1]),
        16 + int_bits(P::MAX[2]),
    ];
    /// Lane offsets: blue at 0, green above it, red on top.
    const OFF: [u32; 3] = [Self::L[2] + Self::L[1], Self::L[2], 0];
    /// True when the three lanes fit one `u64` and the format has three channels.
    const FITS: bool = !P::GRAY && Self::L[0] + Self::L[1] + Self::L[2] <= 64;

    /// The packed start and increment of a span of `n` pixels, or `None` if the
    /// span takes the scalar loop.
    #[inline(always)]
    fn start(v: [i32; ATTRS], g: &[i32; ATTRS], n: usize) -> Option<(u64, u64)> {
        // Below 4 pixels the range checks cost more than the adds they save.
        if !Self::FITS || n < 4 {
            return None;
        }
        // n ≤ 4096 (the guard band), |g| < 2^31: |(n − 1)·g| < 2^43 fits i64.
        let last = (n - 1) as i64;
        let mut p = 0u64;
        let mut d = 0u64;
        // Bits outside the lanes: `a` and `e` lie in [0, 2^L) exactly when
        // `(a | e) as u64 >> L` is 0 (a negative value has its top bit set), so the
        // three channels need one branch instead of twelve.
        let mut out = 0u64;
        for k in 0..3 {
            let (a, e) = (v[k] as i64, v[k] as i64 + last * g[k] as i64);
            out |= (a | e) as u64 >> Self::L[k];
            // Modulo 2^64 by design: the sum of the shifted lanes is exact mod 2^64.
            p = p.wrapping_add((a as u64) << Self::OFF[k]);
            d = d.wrapping_add((g[k] as i64 as u64) << Self::OFF[k]);
        }
        (out == 0).then_some((p, d))
    }

    /// Integer bits of the three channels (`B` = b0 + b1 + b2 ≤ 16 when the lanes
    /// fit, since 48 + B ≤ 64).
    const B: [u32; 3] = [
        int_bits(P::MAX[0]),
        int_bits(P::MAX[1]),
        int_bits(P::MAX[2]),
    ];
    /// The integer fields of the three lanes: channel k at bits
    /// `[OFF[k] + 16, OFF[k] + 16 + B[k])`.
    /// Zero (unused) for a format whose lanes do not fit.
    #[cfg(any(test, target_pointer_width = "64"))]
    const FIELDS: u64 = {
        let mut m = 0u64;
        let mut k = 0;
        while Self::FITS && k < 3 {
            m |= ((1u64 << Self::B[k]) - 1) << (Self::OFF[k] + 16);
            k += 1;
        }
        m
    };

    /// The pixel of a packed register: each lane's integer bits.
    ///
    /// The fields are gathered by one multiply instead of three shift-and-masks:
    /// with `m = c & FIELDS`, red lies at `[48 + b2 + b1, 48 + B)`, green at
    /// `[32 + b2, 32 + b2 + b1)`, blue at `[16, 16 + b2)`. Times `1 + 2¹⁶ + 2³²`
    /// (modulo 2⁶⁴) red stays, green moves to `[48 + b2, 48 + b2 + b1)` and blue to
    /// `[48, 48 + b2)`: `(m·K) >> 48` is `red·2^(b1+b2) + green·2^b2 + blue`. The
    /// other partial products land below bit 48 (green at `[32 + b2, 48)`, blue at
    /// `[16, 16 + b2)` and `[32, 32 + b2)`) or at bit 64 and above: all the fields
    /// are disjoint, so the sum has no carries and the top 16 bits hold only the
    /// three gathered fields.
    ///
    /// On 32-bit cores the 64-bit multiply takes three, and the three shift-and-masks
    /// of [`Packed::pack_shifts`] are cheaper: they are kept there (same bits, tested).
    #[cfg(any(test, target_pointer_width = "64"))]
    #[inline(always)]
    fn pack_gather(c: u64) -> P::Raw {
        const K: u64 = 1 + (1 << 16) + (1 << 32);
        let m = ((c & Self::FIELDS).wrapping_mul(K) >> 48) as u32;
        let [_, b1, b2] = Self::B;
        P::pack(
            m >> (b1 + b2),
            (m >> b2) & ((1 << b1) - 1),
            m & ((1 << b2) - 1),
        )
    }

    /// The pixel of a packed register: each lane's integer bits, by shift and mask.
    #[cfg(any(test, not(target_pointer_width = "64")))]
    #[inline(always)]
    fn pack_shifts(c: u64) -> P::Raw {
        let ch = |k: usize| ((c >> (Self::OFF[k] + 16)) as u32) & ((1 << Self::B[k]) - 1);
        P::pack(ch(0), ch(1), ch(2))
    }

    /// The pixel of a packed register, by the cheaper gather of the target.
    #[inline(always)]
    fn pack(c: u64) -> P::Raw {
        #[cfg(target_pointer_width = "64")]
        return Self::pack_gather(c);
        #[cfg(not(target_pointer_width = "64"))]
        return Self::pack_shifts(c);
    }
}

/// The three colour channels `v` as one packed register (see [`Packed`]): `Σ vₖ·2^offₖ`
/// modulo 2⁶⁴, blue lowest. Linear: the packed value of a lattice point is the sum of
/// the packed anchor and the packed increments (all modulo 2⁶⁴), and where every
/// channel of the point lies in its lane's range `[0, 2^Lₖ)` the lanes hold the
/// channels exactly. `None` for a format whose lanes do not fit 64 bits.
#[inline(always)]
pub(crate) fn packed_channels<P: PixelFormat>(v: &[i32; ATTRS]) -> Option<u64> {
    if !Packed::<P>::FITS {
        return None;
    }
    // The images built for size keep the loop and shift by a variable (a runtime
    // call on ARMv6-M, three times a triangle): they take the lanes written out.
    // Written out everywhere, the optimised images' fills compile differently
    // (+2.7 % for the teapot's draw on the Cortex-M4).
    #[cfg(feature = "small-flash")]
    return Some(packed_unrolled::<P>(v));
    #[cfg(not(feature = "small-flash"))]
    {
        let mut p = 0u64;
        for (c, off) in v.iter().zip(Packed::<P>::OFF) {
            p = p.wrapping_add((*c as i64 as u64) << off);
        }
        Some(p)
    }
}

/// [`packed_channels`]' sum with its three lanes written out (tested equal).
#[cfg(any(test, feature = "small-flash"))]
#[inline(always)]
fn packed_unrolled<P: PixelFormat>(v: &[i32; ATTRS]) -> u64 {
    let o = Packed::<P>::OFF;
    let lane = |k: usize| (v[k] as i64 as u64) << o[k];
    lane(0).wrapping_add(lane(1)).wrapping_add(lane(2))
}

/// Whether the span loops in assembly (`super::asm`) draw the format: a 5-6-5
/// format whose packed lanes put red at bit 43 and green at bit 21.
#[cfg(any(fixshade_dsp, fixshade_v6m))]
pub(crate) const fn asm_565<P: PixelFormat>() -> bool {
    crate::target::is_565::<P>() && Packed::<P>::OFF[0] == 43 && Packed::<P>::OFF[1] == 21
}

/// For a 5-6-5 format: whether it stores the 5-6-5 value byte-swapped
/// (`Rgb565Be`; `Rgb565Le` stores it as it is).
#[cfg(any(fixshade_dsp, fixshade_v6m))]
#[inline(always)]
pub(crate) fn swapped_565<P: PixelFormat>() -> bool {
    P::bytes(P::pack(0, 0, 1))[0] != 1
}

/// The pixel stage of a packed span ([`packed_channels`]): `color.len()` pixels from
/// the packed colour `c` and depth `z`, stepping by `dc` and `dz` per pixel. The
/// caller guarantees that every channel of every pixel lies in its lane (true at
/// covered pixels of a triangle whose increments are unwrapped, by the setup bound).
///
/// `pairs`: on ARMv7E-M, the long spans two pixels a step (band draws; see
/// `super::asm::packed_565_span`).
#[inline(always)]
pub(crate) fn write_packed<P: PixelFormat, Z: DepthMode>(
    color: &mut [P::Raw],
    depth: &mut [impl DepthFormat],
    mut c: u64,
    dc: u64,
    mut z: i32,
    dz: i32,
    pairs: bool,
) {
    // On the Cortex-M cores the 5-6-5 formats over 16-bit depth take the loop in
    // assembly (see `super::asm`): the same pixels in fewer instructions.
    #[cfg(any(fixshade_dsp, fixshade_v6m))]
    if Z::TEST && asm_565::<P>() {
        if let (Some(cr), Some(dr)) = (P::as_u16(&mut *color), DepthFormat::as_u16(&mut *depth)) {
            super::asm::packed_565_span(cr, dr, c, dc, z, dz, swapped_565::<P>(), pairs);
            return;
        }
    }
    #[cfg(not(any(fixshade_dsp, fixshade_v6m)))]
    let _ = pairs;
    if Z::TEST {
        for (px, d) in color.iter_mut().zip(depth.iter_mut()) {
            if d.write_if_nearer(z) {
                P::store(px, Packed::<P>::pack(c));
            }
            c = c.wrapping_add(dc);
            z = z.wrapping_add(dz);
        }
    } else {
        for px in color.iter_mut() {
            P::store(px, Packed::<P>::pack(c));
            c = c.wrapping_add(dc);
        }
    }
}

/// The pixel stage: writes `color.len()` pixels starting from values `v`, stepping
/// by `g` per pixel (wrapping adds: exact modulo 2³², see `setup`). The attributes are
/// held in separate scalars so the loop keeps them in registers.
///
/// ```
/// use fixshade::raster::span::{write_run, NoDepth};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::Gray8;
/// let mut row = [0u8; 5];
/// // Grey 10 at the first pixel, +20 per pixel.
/// write_run::<Gray8, NoDepth, Gouraud>(&mut row, &mut [0u16; 0], [10 << 16, 0, 0, 0], &[20 << 16, 0, 0, 0]);
/// assert_eq!(row, [10, 30, 50, 70, 90]);
/// ```
#[inline(always)]
pub fn write_run<P: PixelFormat, Z: DepthMode, Sh: Shading>(
    color: &mut [P::Raw],
    depth: &mut [impl DepthFormat],
    v: [i32; ATTRS],
    g: &[i32; ATTRS],
) {
    let [mut r, mut gg, mut b, mut z] = v;
    let [dr, dg, db, dz] = *g;
    if Sh::INTERPOLATE {
        if let Some((c3, d3)) = Packed::<P>::start(v, g, color.len()) {
            write_packed::<P, Z>(color, depth, c3, d3, z, dz, false);
            return;
        }
        if Z::TEST {
            for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
                if d.write_if_nearer(z) {
                    P::store(c, pack::<P>(r, gg, b));
                }
                r = r.wrapping_add(dr);
                if !P::GRAY {
                    gg = gg.wrapping_add(dg);
                    b = b.wrapping_add(db);
                }
                z = z.wrapping_add(dz);
            }
        } else {
            for c in color.iter_mut() {
                P::store(c, pack::<P>(r, gg, b));
                r = r.wrapping_add(dr);
                if !P::GRAY {
                    gg = gg.wrapping_add(dg);
                    b = b.wrapping_add(db);
                }
            }
        }
    } else {
        let p = pack::<P>(r, gg, b);
        if Z::TEST {
            for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
                if d.write_if_nearer(z) {
                    P::store(c, p);
                }
                z = z.wrapping_add(dz);
            }
        } else {
            for c in color.iter_mut() {
                P::store(c, p);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade::Gouraud;
    use crate::target::{Rgb565Be, Rgb565Le, Rgb888};

    /// The pixel stage one pixel at a time, as the specification: value `i` is `v`
    /// plus `i` wrapping adds of `g`, stored where the depth is strictly nearer.
    fn reference<P: PixelFormat>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        v: [i32; ATTRS],
        g: &[i32; ATTRS],
    ) {
        let mut v = v;
        for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
            pack_pixel::<P, DepthTest>(c, d, &v);
            for k in 0..ATTRS {
                v[k] = v[k].wrapping_add(g[k]);
            }
        }
    }

    /// Random spans of 1..=40 pixels over random depth rows: `write_run` (packed
    /// registers from four pixels, the scalar loop below) writes exactly the reference's colours and
    /// depths. Channel values stay in range over the span (as the setup guarantees for
    /// covered pixels), depths anywhere in u32 (wrapping included).
    fn blocks_equal_reference<P: PixelFormat>() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for _ in 0..20_000 {
            let n = (rnd() % 40 + 1) as usize;
            let mut v = [0i32; ATTRS];
            let mut g = [0i32; ATTRS];
            for k in 0..3 {
                let max = ((P::MAX[k] as i64 + 1) << 16) - 1;
                let (a, e) = (rnd() as i64 % (max + 1), rnd() as i64 % (max + 1));
                let (a, e) = (a.abs(), e.abs());
                let step = if n > 1 { (e - a) / (n as i64 - 1) } else { 0 };
                v[k] = a as i32;
                g[k] = step as i32;
            }
            v[3] = rnd() as i32;
            g[3] = (rnd() as i32) >> (rnd() % 32);
            let old: [u16; 40] = core::array::from_fn(|_| rnd() as u16);
            let oldc: [P::Raw; 40] = core::array::from_fn(|_| P::pack(1, 2, 3));
            let (mut c1, mut d1) = (oldc, old);
            let (mut c2, mut d2) = (oldc, old);
            write_run::<P, DepthTest, Gouraud>(&mut c1[..n], &mut d1[..n], v, &g);
            reference::<P>(&mut c2[..n], &mut d2[..n], v, &g);
            assert_eq!((c1, d1), (c2, d2), "n {n} v {v:?} g {g:?}");
        }
    }

    /// The multiply gather (64-bit targets) and the shift-and-masks (32-bit targets)
    /// read the same pixel from any register: random bits everywhere, including
    /// between and above the lanes.
    fn gathers_agree<P: PixelFormat>() {
        assert!(Packed::<P>::FITS);
        let mut c = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..100_000 {
            c ^= c << 13;
            c ^= c >> 7;
            c ^= c << 17;
            assert!(
                Packed::<P>::pack_gather(c) == Packed::<P>::pack_shifts(c),
                "{c:#x}"
            );
        }
    }

    #[test]
    fn pack_variants_agree() {
        gathers_agree::<Rgb565Le>();
        gathers_agree::<Rgb565Be>();
        // Rgb888's lanes (3 × 24 bits) do not fit: it takes the scalar loop.
        const { assert!(!Packed::<Rgb888>::FITS) };
    }

    /// The lanes written out (the images built for size) give the loop's sum (the
    /// other builds, these tests among them), for any values, negative included.
    fn unrolled_equals_loop<P: PixelFormat>() {
        let mut c = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..100_000 {
            let v: [i32; ATTRS] = core::array::from_fn(|_| {
                c ^= c << 13;
                c ^= c >> 7;
                c ^= c << 17;
                (c as i32) >> (c >> 59)
            });
            assert_eq!(
                packed_channels::<P>(&v),
                Some(packed_unrolled::<P>(&v)),
                "{v:?}"
            );
        }
    }

    #[test]
    fn packed_lanes_written_out_agree() {
        unrolled_equals_loop::<Rgb565Le>();
        unrolled_equals_loop::<Rgb565Be>();
    }

    #[test]
    fn write_run_blocks_equal_the_pixel_loop() {
        blocks_equal_reference::<Rgb565Le>();
        blocks_equal_reference::<Rgb565Be>();
        blocks_equal_reference::<Rgb888>();
    }
}
