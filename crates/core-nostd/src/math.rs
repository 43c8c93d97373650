//! Integer maths: square roots, sine and cosine of binary angles, 4×4 matrices with
//! `gluLookAt`/`gluPerspective`/`glOrtho` semantics, and the power function of the
//! specular term.
//!
//! Per-frame work (building matrices) uses `Q32_32` entries in `i64` with `i128`
//! products, so a composed model-view-projection matrix is accurate to about 1e-9;
//! per-vertex work uses the normalised `i32` forms in [`ClipMatrix`] and
//! [`Affine3`].
//!
//! ```
//! use fixshade::fixed::Angle;
//! use fixshade::math::{cos_q30, sin_q30};
//! assert_eq!(sin_q30(Angle::from_degrees(90)), 1 << 30);
//! assert_eq!(cos_q30(Angle::from_degrees(180)), -(1 << 30));
//! let s30 = sin_q30(Angle::from_degrees(30));
//! assert!((s30 - (1 << 29)).abs() <= 2);
//! ```

use crate::fixed::{Angle, Q16_16};

/// One in Q32.32.
pub const ONE_Q32: i64 = 1 << 32;
/// One in Q2.30.
pub const ONE_Q30: i32 = 1 << 30;

/// The exact product of two `i32`, as `i64`.
///
/// Every per-vertex and per-triangle product of the core goes through this (or
/// [`mul_wide_u`]) instead of an `i64 × i64` multiply: on ARMv7-M and the host it is
/// one `SMULL`; on ARMv6-M (`cfg(fixshade_v6m)`, see the crate's build script), which has only
/// `MULS` (32×32→32), it is four 16×16 products and a few adds (about 23 instructions, no call), where an `i64`
/// multiply would call `__aeabi_lmul`. Both give the same bits (tested).
///
/// ```
/// use fixshade::math::mul_wide;
/// assert_eq!(mul_wide(i32::MIN, i32::MIN), 1 << 62);
/// assert_eq!(mul_wide(-3, 1 << 30), -3 << 30);
/// ```
#[inline(always)]
pub const fn mul_wide(a: i32, b: i32) -> i64 {
    #[cfg(fixshade_v6m)]
    {
        mul_wide_split(a, b)
    }
    #[cfg(not(fixshade_v6m))]
    {
        a as i64 * b as i64
    }
}

/// The exact product of two `u32`, as `u64` (see [`mul_wide`]).
///
/// ```
/// use fixshade::math::mul_wide_u;
/// assert_eq!(mul_wide_u(u32::MAX, u32::MAX), (u32::MAX as u64) * (u32::MAX as u64));
/// ```
#[inline(always)]
pub const fn mul_wide_u(a: u32, b: u32) -> u64 {
    #[cfg(fixshade_v6m)]
    {
        mul_wide_u_split(a, b)
    }
    #[cfg(not(fixshade_v6m))]
    {
        a as u64 * b as u64
    }
}

/// The exact product of an `i32` and an `i16`, as `i64`: one `SMULL` on ARMv7-M
/// and the host, two 16×16-bit products on ARMv6-M (see [`mul_wide`]).
///
/// ```
/// use fixshade::math::mul_wide_16;
/// assert_eq!(mul_wide_16(i32::MIN, i16::MIN), 1 << 46);
/// ```
#[inline(always)]
pub fn mul_wide_16(a: i32, b: i16) -> i64 {
    #[cfg(fixshade_v6m)]
    {
        mul_wide_16_split(a, b)
    }
    #[cfg(not(fixshade_v6m))]
    {
        a as i64 * b as i64
    }
}

/// [`mul_wide_16`] from two 16×16-bit products: `a·b = ah·b·2¹⁶ + al·b` with `ah`
/// signed and `al` unsigned; `|ah·b|` ≤ 2³⁰ and `|al·b|` < 2³¹ fit `i32`.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) fn mul_wide_16_split(a: i32, b: i16) -> i64 {
    let b = b as i32;
    (((a >> 16) * b) as i64) * (1 << 16) + ((a & 0xFFFF) * b) as i64
}

/// [`mul_wide`] from 16×16-bit products: `a·b = ah·bh·2³² + (ah·bl + al·bh)·2¹⁶ +
/// al·bl` with `ah`, `bh` the signed high halves and `al`, `bl` the unsigned low
/// halves. Bounds: `|ah·bl|`, `|al·bh|` ≤ 2¹⁵·(2¹⁶ − 1) < 2³¹ fit `i32`; `al·bl` <
/// 2³² fits `u32`; the middle sum is taken in `i64`.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) const fn mul_wide_split(a: i32, b: i32) -> i64 {
    let (ah, al) = (a >> 16, a & 0xFFFF);
    let (bh, bl) = (b >> 16, b & 0xFFFF);
    let lo = (al as u32).wrapping_mul(bl as u32);
    let mid = (ah * bl) as i64 + (al * bh) as i64;
    (((ah * bh) as i64) << 32) + (mid << 16) + lo as i64
}

/// [`mul_wide_u`] from 16×16-bit products (every partial product fits `u32`, the
/// middle sum is taken in `u64`).
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) const fn mul_wide_u_split(a: u32, b: u32) -> u64 {
    let (ah, al) = (a >> 16, a & 0xFFFF);
    let (bh, bl) = (b >> 16, b & 0xFFFF);
    let mid = (ah * bl) as u64 + (al * bh) as u64;
    (((ah * bh) as u64) << 32) + (mid << 16) + (al * bl) as u64
}

/// The exact product of two `i64`, as `i128`: the one multiply on the host and
/// ARMv7-M; on ARMv6-M (`cfg(fixshade_v6m)`), where an `i128` product of two `i64`
/// is six `__aeabi_lmul` calls, four 32×32→64 products ([`mul_wide`],
/// [`mul_wide_u`], 16×16-bit `MULS` there) and the `i128` sum, without a call
/// (the per-frame matrices: [`Mat4::mul`], [`Mat4::transform_dir`], [`Affine3::new`],
/// [`normalize_q32`]). Both give the same bits (tested).
#[inline(always)]
pub(crate) const fn mul_i64_wide(a: i64, b: i64) -> i128 {
    #[cfg(fixshade_v6m)]
    {
        mul_i64_wide_split(a, b)
    }
    #[cfg(not(fixshade_v6m))]
    {
        a as i128 * b as i128
    }
}

/// [`mul_i64_wide`] from 32×32→64 products: `a·b = ah·bh·2⁶⁴ + (ah·bl + al·bh)·2³²
/// + al·bl` with `ah`, `bh` the signed high words and `al`, `bl` the unsigned low
/// words. `|ah·bl|`, `|al·bh|` < 2³¹·2³² fit `i64` ([`mul_su`]); the sum is taken in
/// `i128`, whose range holds every product of two `i64`.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) const fn mul_i64_wide_split(a: i64, b: i64) -> i128 {
    let (ah, al) = ((a >> 32) as i32, a as u32);
    let (bh, bl) = ((b >> 32) as i32, b as u32);
    let mid = mul_su(ah, bl) as i128 + mul_su(bh, al) as i128;
    ((mul_wide(ah, bh) as i128) << 64) + (mid << 32) + mul_wide_u(al, bl) as i128
}

/// The exact product of an `i32` and a `u32`, as `i64` (below 2⁶³ in magnitude):
/// the product of their bits as unsigned, less `l·2³²` when `h` is negative (its
/// bits read as unsigned are `h + 2³²`), modulo 2⁶⁴.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
const fn mul_su(h: i32, l: u32) -> i64 {
    let p = mul_wide_u(h as u32, l) as i64;
    if h < 0 {
        p.wrapping_sub(((l as u64) << 32) as i64)
    } else {
        p
    }
}

/// Leading zero bits of `x` (32 for 0): `CLZ` where the core has it, two halving
/// steps and a 256-byte table on ARMv6-M (which has no `CLZ`; the library's
/// `leading_zeros` would call `__clzsi2` there).
///
/// ```
/// use fixshade::math::leading_zeros;
/// assert_eq!((leading_zeros(0), leading_zeros(1), leading_zeros(u32::MAX)), (32, 31, 0));
/// ```
#[inline(always)]
pub fn leading_zeros(x: u32) -> u32 {
    #[cfg(fixshade_v6m)]
    {
        leading_zeros_search(x)
    }
    #[cfg(not(fixshade_v6m))]
    {
        x.leading_zeros()
    }
}

/// Leading zeros of a byte's values 1..=255 within the byte (`CLZ8[0]` unused):
/// 256 bytes of flash for [`leading_zeros_search`].
#[cfg(any(test, fixshade_v6m))]
const CLZ8: [u8; 256] = {
    let mut t = [8u8; 256];
    let mut i = 1;
    while i < 256 {
        t[i] = (i as u32).leading_zeros() as u8 - 24;
        i += 1;
    }
    t
};

/// [`leading_zeros`] by two halving steps (16, 8 bits) and a table of the top
/// byte's leading zeros.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) fn leading_zeros_search(mut x: u32) -> u32 {
    if x == 0 {
        return 32;
    }
    let mut n = 0;
    if x >> 16 == 0 {
        n += 16;
        x <<= 16;
    }
    if x >> 24 == 0 {
        n += 8;
        x <<= 8;
    }
    n + CLZ8[(x >> 24) as usize] as u32
}

/// `x >> s` for an `i64` and `s` < 64 (arithmetic), from 32-bit shifts: ARMv6-M
/// would call `__aeabi_lasr` for a 64-bit shift by a variable amount.
///
/// ```
/// use fixshade::math::shr_i64;
/// assert_eq!(shr_i64(-(5 << 40), 40), -5);
/// assert_eq!(shr_i64(-1, 63), -1);
/// assert_eq!(shr_i64(1 << 62, 3), 1 << 59);
/// ```
#[inline(always)]
pub fn shr_i64(x: i64, s: u32) -> i64 {
    #[cfg(fixshade_v6m)]
    {
        shr_i64_split(x, s)
    }
    #[cfg(not(fixshade_v6m))]
    {
        x >> s
    }
}

/// [`shr_i64`] on the two 32-bit halves.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) fn shr_i64_split(x: i64, s: u32) -> i64 {
    debug_assert!(s < 64);
    let (hi, lo) = ((x >> 32) as i32, x as u32);
    if s == 0 {
        x
    } else if s < 32 {
        let lo = (lo >> s) | ((hi as u32) << (32 - s));
        (((hi >> s) as i64) << 32) | lo as i64
    } else {
        (hi >> (s - 32)) as i64
    }
}

/// `⌊n / d⌋` and the remainder for `d > 0`: `UDIV` where the core has one, a
/// shift-and-subtract loop over the quotient's bits only on ARMv6-M (which has no
/// divider; the library would call `__aeabi_uidiv`): a few instructions per
/// quotient bit, cheap for the small quotients of the edge walk.
///
/// ```
/// use fixshade::math::div_rem_u32;
/// assert_eq!(div_rem_u32(100, 7), (14, 2));
/// assert_eq!(div_rem_u32(3, 7), (0, 3));
/// assert_eq!(div_rem_u32(u32::MAX, 1), (u32::MAX, 0));
/// ```
#[inline(always)]
pub fn div_rem_u32(n: u32, d: u32) -> (u32, u32) {
    #[cfg(fixshade_v6m)]
    {
        div_rem_u32_shift(n, d)
    }
    #[cfg(not(fixshade_v6m))]
    {
        (n / d, n % d)
    }
}

/// [`div_rem_u32`] by shift and subtract. The divisor is doubled up to the
/// quotient's top bit (no leading-zero count, which ARMv6-M lacks and costs two
/// table lookups to emulate; the edge walk's quotients have a bit or three), then
/// halved back one quotient bit at a time.
#[cfg(any(test, fixshade_v6m))]
#[inline]
pub(crate) fn div_rem_u32_shift(n: u32, d: u32) -> (u32, u32) {
    debug_assert!(d > 0);
    if n < d {
        return (0, n);
    }
    // t = d·2^k, the largest such multiple at most n: t ≤ n/2 before each
    // doubling, so t never overflows, and halving t gives back d·2^(k−1) exactly.
    let (mut t, mut k) = (d, 0u32);
    while t <= n >> 1 {
        t <<= 1;
        k += 1;
    }
    let (mut q, mut r) = (0u32, n);
    loop {
        q <<= 1;
        if r >= t {
            r -= t;
            q |= 1;
        }
        if k == 0 {
            break;
        }
        t >>= 1;
        k -= 1;
    }
    (q, r)
}

/// Seeds of [`recip_q61`]: `RECIP_SEED[i] = ⌊2²⁴ / (i + 256.5) + ½⌋` for the top nine
/// bits `i + 256` of an argument in [2³⁰, 2³¹) (512 bytes of flash; the seed is
/// within 2⁻⁹ of the reciprocal, relatively).
const RECIP_SEED: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        // 2^24 / (i + 256.5) = 2^25 / (2i + 513), rounded.
        t[i] = ((1u32 << 26) / (2 * i as u32 + 513)).div_ceil(2) as u16;
        i += 1;
    }
    t
};

/// `2⁶¹ / m` for `m` in [2³⁰, 2³¹), to within 2 units (result in (2³⁰, 2³¹ − 1]): a table
/// seed and two Newton steps `r ← r + r·(2⁶¹ − m·r)/2⁶¹`, four [`mul_wide`]-class
/// products and no division (seed 002 §2.4's idea of a reciprocal without a divider,
/// refined by Newton as the design asks for ARMv6-M).
///
/// Bounds: the seed `r₀` is within 2⁻⁹ of `2⁶¹/m`, so `e = 2⁶¹ − m·r` is below
/// 2⁵³ in magnitude (2⁴⁴ after the first step) and `e >> 29` fits `i32`; `r`, kept
/// below 2³¹ so that it is an `i32` too, times `e >> 29` is below 2³¹·2²⁴ in
/// magnitude. Each step squares the relative error (2⁻¹⁸, then below 2⁻³⁰ plus the
/// truncations of the shifts, under one unit each), which the tests check over the
/// whole range.
///
/// ```
/// use fixshade::math::recip_q61;
/// assert!(recip_q61(1 << 30).abs_diff(1 << 31) <= 2);
/// let m = 3 << 29; // 1.5·2^30
/// assert!(recip_q61(m).abs_diff(((1u64 << 61) / m as u64) as u32) <= 2);
/// ```
#[inline]
pub fn recip_q61(m: u32) -> u32 {
    #[cfg(fixshade_v6m)]
    {
        recip_q61_split(m)
    }
    #[cfg(not(fixshade_v6m))]
    {
        recip_q61_wide(m)
    }
}

/// [`recip_q61`] with [`mul_wide`]-class products (one `UMULL`/`SMULL` each where
/// the core has them).
#[cfg(any(test, not(fixshade_v6m)))]
#[inline(always)]
fn recip_q61_wide(m: u32) -> u32 {
    debug_assert!((1 << 30..1 << 31).contains(&m));
    // m >> 22 is in [256, 512): its low eight bits index the table.
    let mut r = (RECIP_SEED[((m >> 22) & 0xFF) as usize] as u32) << 15;
    let mut k = 0;
    while k < 2 {
        let e = (1i64 << 61) - mul_wide_u(m, r) as i64;
        let next = r as i64 + (mul_wide(r as i32, (e >> 29) as i32) >> 32);
        // `next` is positive (r moves by less than 2^-8 of itself): the clamp as
        // `u64` tells the compiler the result's high word is zero.
        r = (next as u64).min(i32::MAX as u64) as u32;
        k += 1;
    }
    r
}

/// [`recip_q61`] from 16×16-bit products (ARMv6-M, whose 64-bit products are four
/// `MULS` and their carries): the same two Newton steps, to the same bits, keeping
/// only the words each step uses. Splits are `x = x_h·2¹⁶ + x_l`, `x_l` in [0, 2¹⁶).
///
/// - Step 1 starts from `r₀ = s·2¹⁵` (the seed `s` < 2¹⁶), so
///   `e >> 29 = ⌊(2⁴⁶ − m·s)/2¹⁴⌋`, with `m·s = m_h·s·2¹⁶ + m_l·s` (each product below
///   2³²) and the residual below 2²⁴ in magnitude: modulo 2³² it is exact. Then
///   `(r₀·f) >> 32 = ⌊s·f/2¹⁷⌋ = ⌊(s·f_h + ⌊s·f_l/2¹⁶⌋)/2⌋` (|s·f_h| < 2²⁴,
///   `s·f_l` < 2³²).
/// - Step 2: `m·r = P_h·2³² + P_l` with `P_h = m_h·r_h + ⌊(mid + ⌊lo/2¹⁶⌋)/2¹⁶⌋`
///   (`mid = m_h·r_l + m_l·r_h` and `lo = m_l·r_l` below 2³², the sum too since
///   `m_h`, `r_h` < 2¹⁵), so `e >> 29 = −8·P_h − ⌈P_l/2²⁹⌉` modulo 2³² (below 2¹⁵
///   in magnitude: exact). Then `(r·f) >> 32 = ⌊(r_h·f + ⌊r_l·f/2¹⁶⌋)/2¹⁶⌋`
///   (|r_h·f| < 2³⁰, |r_l·f| < 2³¹).
///
/// The sums with `r` are `i64` (two instructions each) and clamped as in
/// [`recip_q61`]; the tests compare the two on a stride through the whole range,
/// at every seed bucket's ends and on random arguments.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
fn recip_q61_split(m: u32) -> u32 {
    debug_assert!((1 << 30..1 << 31).contains(&m));
    let s = RECIP_SEED[((m >> 22) & 0xFF) as usize] as u32;
    let (mh, ml) = (m >> 16, m & 0xFFFF);
    let clamp = |next: i64| (next as u64).min(i32::MAX as u64) as u32;
    // Step 1: 2^46 − m·s = 2^16·(2^30 − m_h·s) − m_l·s; its floor over 2^14.
    let b = ml * s;
    let ceil = (b >> 14) + (b & 0x3FFF != 0) as u32;
    let f = (4u32.wrapping_mul((1u32 << 30).wrapping_sub(mh * s))).wrapping_sub(ceil) as i32;
    let (fh, fl) = (f >> 16, (f & 0xFFFF) as u32);
    let step = ((s as i32) * fh + ((s * fl) >> 16) as i32) >> 1;
    let r = clamp((s << 15) as i64 + step as i64);
    // Step 2.
    let (rh, rl) = (r >> 16, r & 0xFFFF);
    let lo = ml * rl;
    let mid = mh * rl + ml * rh;
    let ph = (mh * rh).wrapping_add((mid + (lo >> 16)) >> 16);
    let pl = (mid << 16).wrapping_add(lo);
    let ceil = (pl >> 29) + (pl & 0x1FFF_FFFF != 0) as u32;
    let f = 0u32.wrapping_sub(ph.wrapping_mul(8)).wrapping_sub(ceil) as i32;
    let step = ((rh as i32) * f + (((rl as i32) * f) >> 16)) >> 16;
    clamp(r as i64 + step as i64)
}

/// `2³¹ / m` for `m` in [2¹⁵, 2¹⁶), to 16 bits: in [2¹⁵, 2¹⁶ − 1], within 2⁻¹⁵ of
/// the exact quotient relatively. The [`recip_q61`] table's seed (within 2⁻⁹) and
/// one Newton step `r ← r + r·(2³¹ − m·r)/2³¹` in 32-bit products: `m·r` is within
/// 2⁻⁹ of 2³¹, so the residual `e` lies in (−2²³, 2²³) and is exact modulo 2³²;
/// `r·(e >> 8)` is below 2¹⁶·2¹⁵. The step leaves a relative error below 2⁻¹⁷ plus
/// the truncations (under two units), and the result is clamped below 2¹⁶ so that
/// it times a 15-bit value fits `i32`. The same instructions on every core (three
/// `MULS` on ARMv6-M, no division): the triangle setup's reciprocal of a small
/// determinant.
///
/// ```
/// use fixshade::math::recip_q31_16;
/// assert_eq!(recip_q31_16(1 << 15), (1 << 16) - 1);
/// let m = 3 << 14; // 1.5·2^15
/// assert!(recip_q31_16(m).abs_diff((1u32 << 31) / m) <= 2);
/// ```
#[inline(always)]
pub fn recip_q31_16(m: u32) -> u32 {
    debug_assert!((1 << 15..1 << 16).contains(&m));
    // m >> 7 is in [256, 512): its low eight bits index the table; the seed is
    // 2^24/(m/2^7) = 2^31/m to within 2^-9.
    let r = RECIP_SEED[((m >> 7) & 0xFF) as usize] as u32;
    let e = (1u32 << 31).wrapping_sub(m.wrapping_mul(r)) as i32;
    let next = r as i32 + (((r as i32) * (e >> 8) + (1 << 22)) >> 23);
    (next as u32).min(0xFFFF)
}

/// Knots of [`recip_seed`]: `RECIP_KNOTS[j] = ⌊2²⁴/(256 + j) + ½⌋ − 2¹⁵` for
/// j = 0..=256, the reciprocal at the ends of the 256 buckets of [2³⁰, 2³¹) (514
/// bytes of flash; the offset keeps 2¹⁶ at j = 0 within `u16`).
const RECIP_KNOTS: [u16; 257] = {
    let mut t = [0u16; 257];
    let mut j = 0;
    while j < 257 {
        // 2^24/(256 + j) rounded: (2^25/(256 + j) + 1)/2.
        t[j] = (((1u32 << 25) / (256 + j as u32)).div_ceil(2) - (1 << 15)) as u16;
        j += 1;
    }
    t
};

/// The reciprocal of `m` in [2³⁰, 2³¹) as the vertex stage uses it, from 32-bit
/// products only (four `MULS` on ARMv6-M, no 64-bit product, no division): a seed
/// `r0 ≈ 2⁴⁶/m` in (2¹⁵, 2¹⁶], interpolated between the two `RECIP_KNOTS` around
/// `m` (relative error below 2⁻¹⁴·⁵: the chord, the knots' rounding and the
/// rounded slope), and the Newton residual `e ≈ 2³¹·(1 − m·r0/2⁴⁶)`, |e| < 2¹⁷
/// (tested), so that `2⁴⁶/m = r0·(1 + e/2³¹)` to second order
/// ([`recip_refined`] applies the step).
///
/// Bounds: the knots differ by at most 2⁸ + 1 and the bucket fraction is below
/// 2¹⁵ (product below 2²⁴); `(m >> 15)·r0` < 2¹⁶·2¹⁶ fits `u32` (and lies within
/// 2⁻¹⁴ of 2³¹, so its difference from 2³¹ fits `i32`); `(m mod 2¹⁵)·r0` < 2³¹.
///
/// ```
/// use fixshade::math::recip_seed;
/// let (r0, e) = recip_seed(3 << 29); // m = 1.5·2^30: 2^46/m = 43690.67
/// assert!((r0 - 43691).abs() <= 1 && e.abs() < 1 << 17);
/// ```
#[inline(always)]
pub fn recip_seed(m: u32) -> (i32, i32) {
    debug_assert!((1 << 30..1 << 31).contains(&m));
    let i = ((m >> 22) & 0xFF) as usize;
    let f = ((m >> 7) & 0x7FFF) as i32;
    let t0 = RECIP_KNOTS[i] as i32 + (1 << 15);
    let t1 = RECIP_KNOTS[i + 1] as i32 + (1 << 15);
    let r0 = t0 - (((t0 - t1) * f + (1 << 14)) >> 15);
    let a = (1u32 << 31).wrapping_sub((m >> 15) * r0 as u32) as i32;
    let e = a - (((m & 0x7FFF) * r0 as u32) >> 15) as i32;
    (r0, e)
}

/// `2⁶¹/m` for `m` in [2³⁰, 2³¹) from its seed ([`recip_seed`]): `r0·2¹⁵` corrected
/// by one Newton step, `r0·2¹⁵·(1 + e/2³¹)` (the correction from a 17×15-bit
/// product, at least −2³¹), minus 2: within 2⁻²⁷ of the exact value, relatively,
/// and below it, so below 2³¹ (tested). Four 32-bit products in all, no 64-bit one.
///
/// ```
/// use fixshade::math::recip_refined;
/// let m = 1_234_567_890u32;
/// let want = ((1u64 << 61) / m as u64) as i64;
/// assert!((recip_refined(m) as i64 - want).abs() < 32);
/// ```
#[inline(always)]
pub fn recip_refined(m: u32) -> i32 {
    let (r0, e) = recip_seed(m);
    // r0·2^15 ≤ 2^31 and r0·(e >> 2) ≥ −2^31, summed as `u32`. Newton's step
    // approaches 1/m from below, and the truncations add less than one unit: minus
    // 2 the result lies below 2^61/m ≤ 2^31, so it is a positive `i32`.
    ((r0 as u32) << 15)
        .wrapping_add(((r0 * (e >> 2)) >> 14) as u32)
        .wrapping_sub(2) as i32
}

/// `⌊kh·r/2³²⌋` for `kh = k·2¹⁶` with `0 ≤ k < 2¹⁵` and `0 ≤ r < 2³¹`: a
/// per-frame constant times a reciprocal. One `SMMUL` on ARMv7E-M ([`mul_hi`]); on
/// ARMv6-M the low half of `kh` is zero, so two 16×16-bit products suffice:
/// `k·⌊r/2¹⁶⌋ + ⌊k·(r mod 2¹⁶)/2¹⁶⌋` (each product below 2³¹). Both give the
/// same bits (tested).
///
/// ```
/// use fixshade::math::mul_hi_k;
/// assert_eq!(mul_hi_k(3 << 16, 1 << 30), 3 << 14);
/// ```
#[inline(always)]
pub fn mul_hi_k(kh: i32, r: i32) -> i32 {
    debug_assert!(kh & 0xFFFF == 0 && kh >= 0 && r >= 0);
    #[cfg(fixshade_v6m)]
    {
        mul_hi_k_split(kh, r)
    }
    #[cfg(not(fixshade_v6m))]
    {
        mul_hi(kh, r)
    }
}

/// [`mul_hi_k`] from two 16×16-bit products.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) fn mul_hi_k_split(kh: i32, r: i32) -> i32 {
    let k = kh >> 16;
    k * (r >> 16) + ((k * (r & 0xFFFF)) >> 16)
}

/// `⌊a·b / 2³²⌋` exactly: one `SMMUL` on ARMv7E-M (the high word of `SMULL`
/// elsewhere); on ARMv6-M four 16×16-bit products whose carries into the high word
/// are added exactly (see `mul_hi_split`). Both give the same bits (tested).
///
/// ```
/// use fixshade::math::mul_hi;
/// assert_eq!(mul_hi(1 << 30, 1 << 30), 1 << 28);
/// assert_eq!(mul_hi(-1, 1), -1); // the floor
/// ```
#[inline(always)]
pub fn mul_hi(a: i32, b: i32) -> i32 {
    #[cfg(fixshade_v6m)]
    {
        mul_hi_split(a, b)
    }
    #[cfg(not(fixshade_v6m))]
    {
        ((a as i64 * b as i64) >> 32) as i32
    }
}

/// `⌊a·b / 2³²⌋` less 0, 1 or 2, for a value that is corrected afterwards (the
/// projection's estimate, which [`crate::geometry::Projector`] rounds exactly from
/// any estimate within one unit): [`mul_hi`] where the core has a 32×32→64
/// product; on ARMv6-M three 16×16-bit products, `ah·bh + ⌊ah·bl/2¹⁶⌋ +
/// ⌊al·bh/2¹⁶⌋`, without the low product and the carries (each floor drops less
/// than one, `al·bl/2³²` is below one: the sum lies within 3 below the exact
/// quotient, so its floor within 2; tested).
#[inline(always)]
pub(crate) fn mul_hi_estimate(a: i32, b: i32) -> i32 {
    #[cfg(fixshade_v6m)]
    {
        mul_hi_estimate_split(a, b)
    }
    #[cfg(not(fixshade_v6m))]
    {
        mul_hi(a, b)
    }
}

/// [`mul_hi_estimate`] from three 16×16-bit products.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) fn mul_hi_estimate_split(a: i32, b: i32) -> i32 {
    let (ah, al) = (a >> 16, a & 0xFFFF);
    let (bh, bl) = (b >> 16, b & 0xFFFF);
    ah * bh + ((ah * bl) >> 16) + ((al * bh) >> 16)
}

/// `dx1·dy2 − dx2·dy1` from two 32-bit products when every delta lies in [−2¹⁵,
/// 2¹⁵) and `|d| < 2³⁰` (each product then lies in [−2³⁰ + 2¹⁵, 2³⁰], the
/// difference strictly inside ±2³¹); `None` for larger deltas. The small case of
/// [`crate::clip::signed_area_i32`] and of the triangle setup's determinant.
#[inline(always)]
pub(crate) fn cross_small(dx1: i32, dy1: i32, dx2: i32, dy2: i32) -> Option<i32> {
    // |d| < 2^30, so d + 2^15 cannot overflow; it lies in [0, 2^16) exactly for d in
    // [-2^15, 2^15), and any other d sets a bit at 2^16 or above (or the sign).
    let h = 1 << 15;
    let spread = (dx1 + h) | (dy1 + h) | (dx2 + h) | (dy2 + h);
    if spread as u32 >> 16 != 0 {
        return None;
    }
    Some(dx1 * dy2 - dx2 * dy1)
}

/// [`mul_hi`] from 16×16-bit products: with `a = ah·2¹⁶ + al` and `b = bh·2¹⁶ +
/// bl` (high halves signed, low halves unsigned), `a·b = ah·bh·2³² + (ah·bl +
/// al·bh)·2¹⁶ + al·bl`; the middle products (each |·| < 2³¹) are split into their
/// high and low halves, and the low halves, with the high half of `al·bl`, summed
/// (below 3·2¹⁶) to give the carry into the high word.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
pub(crate) fn mul_hi_split(a: i32, b: i32) -> i32 {
    let (ah, al) = (a >> 16, a & 0xFFFF);
    let (bh, bl) = (b >> 16, b & 0xFFFF);
    let (m1, m2) = (ah * bl, al * bh);
    let ll = (al as u32).wrapping_mul(bl as u32);
    let carry = ((ll >> 16) as i32 + (m1 & 0xFFFF) + (m2 & 0xFFFF)) >> 16;
    ah * bh + (m1 >> 16) + (m2 >> 16) + carry
}

/// Floor of the square root of a `u128` (the core library's exact integer root).
///
/// ```
/// assert_eq!(fixshade::math::isqrt_u128(1 << 100), 1 << 50);
/// assert_eq!(fixshade::math::isqrt_u128(99), 9);
/// ```
pub const fn isqrt_u128(n: u128) -> u128 {
    n.isqrt()
}

/// Floor of the square root of a `u64` (the core library's exact integer root).
///
/// ```
/// assert_eq!(fixshade::math::isqrt_u64(u64::MAX), u32::MAX as u64);
/// ```
pub const fn isqrt_u64(n: u64) -> u64 {
    n.isqrt()
}

/// Q.32 product of two Q.32 values (`i128` intermediate; the result saturates).
const fn mul_q32(a: i64, b: i64) -> i64 {
    let p = (mul_i64_wide(a, b) + (1 << 31)) >> 32;
    if p > i64::MAX as i128 {
        i64::MAX
    } else if p < i64::MIN as i128 {
        i64::MIN
    } else {
        p as i64
    }
}

/// Q.32 quotient, rounded to nearest; `b == 0` gives 0.
const fn div_q32(a: i64, b: i64) -> i64 {
    if b == 0 {
        return 0;
    }
    let n = (a as i128) << 32;
    let d = b as i128;
    let q = if (n >= 0) == (d > 0) {
        (n + d / 2) / d
    } else {
        (n - d / 2) / d
    };
    if q > i64::MAX as i128 {
        i64::MAX
    } else if q < i64::MIN as i128 {
        i64::MIN
    } else {
        q as i64
    }
}

/// 2π in Q.32.
const TWO_PI_Q32: i64 = 26_986_075_409;

/// Sine and cosine of `t` radians, 0 ≤ t ≤ π/4, in Q.32 (Taylor series to the 13th /
/// 14th power: truncation error below 1e-13; rounding error a few units of 2⁻³²).
const fn sin_cos_small(t: i64) -> (i64, i64) {
    let t2 = mul_q32(t, t);
    // sin: t - t³/3! + t⁵/5! - …
    let mut term = t;
    let mut s = t;
    let mut k = 1;
    while k <= 6 {
        term = mul_q32(term, t2) / ((2 * k) * (2 * k + 1));
        if k % 2 == 1 {
            s -= term;
        } else {
            s += term;
        }
        k += 1;
    }
    let mut term = ONE_Q32;
    let mut c = ONE_Q32;
    let mut k = 1;
    while k <= 7 {
        term = mul_q32(term, t2) / ((2 * k - 1) * (2 * k));
        if k % 2 == 1 {
            c -= term;
        } else {
            c += term;
        }
        k += 1;
    }
    (s, c)
}

/// Sine and cosine of a binary angle in Q32.32 (|error| ≤ about 3·2⁻³²).
///
/// ```
/// use fixshade::{fixed::Angle, math::{sin_cos_q32, ONE_Q32}};
/// let (s, c) = sin_cos_q32(Angle::from_degrees(60));
/// assert!((c - ONE_Q32 / 2).abs() <= 3);
/// assert!(s > c);
/// ```
pub const fn sin_cos_q32(a: Angle) -> (i64, i64) {
    let bits = a.to_turns_bits();
    let octant = bits >> 29;
    let mut f = (bits & ((1 << 29) - 1)) as i64;
    if octant & 1 == 1 {
        f = (1 << 29) - f;
    }
    // t = f / 2^32 turns · 2π, in Q.32: f · 2π_q32 / 2^32.
    let t = ((f as i128 * TWO_PI_Q32 as i128) >> 32) as i64;
    let (s, c) = sin_cos_small(t);
    // Map the octant: angle = octant·45° ± small.
    let (sin, cos) = match octant {
        0 => (s, c),
        1 => (c, s),
        2 => (c, -s),
        3 => (s, -c),
        4 => (-s, -c),
        5 => (-c, -s),
        6 => (-c, s),
        _ => (-s, c),
    };
    (sin, cos)
}

/// Sine in Q2.30.
///
/// ```
/// use fixshade::{fixed::Angle, math::{sin_q30, ONE_Q30}};
/// assert_eq!(sin_q30(Angle::from_degrees(-90)), -ONE_Q30);
/// ```
pub const fn sin_q30(a: Angle) -> i32 {
    round_q32_to_q30(sin_cos_q32(a).0)
}

/// Cosine in Q2.30.
///
/// ```
/// use fixshade::{fixed::Angle, math::{cos_q30, ONE_Q30}};
/// assert_eq!(cos_q30(Angle::from_degrees(0)), ONE_Q30);
/// ```
pub const fn cos_q30(a: Angle) -> i32 {
    round_q32_to_q30(sin_cos_q32(a).1)
}

const fn round_q32_to_q30(v: i64) -> i32 {
    ((v + 2) >> 2) as i32
}

/// A 4×4 matrix with `Q32_32` entries (`i64`, 32 fraction bits), column-vector
/// convention as in OpenGL: `m[row][col]`, points transform as `M · p`.
///
/// Built once per frame; entries saturate rather than wrap.
///
/// ```
/// use fixshade::fixed::{Angle, Q16_16};
/// use fixshade::math::{Mat4, ONE_Q32};
/// let q = Q16_16::from_int;
/// // Turn a point 90° about z, then move it by (1, 0, 0).
/// let m = Mat4::translate([q(1), q(0), q(0)]).mul(&Mat4::rotate_z(Angle::from_degrees(90)));
/// let p = m.transform_point([q(1), q(0), q(0)]);
/// assert!((p[0] - ONE_Q32).abs() <= 4 && (p[1] - ONE_Q32).abs() <= 4);
/// // A camera at z = 5 looking at the origin maps the origin to z = -5 in eye space.
/// let view = Mat4::look_at([q(0), q(0), q(5)], [q(0); 3], [q(0), q(1), q(0)]).unwrap();
/// assert_eq!(view.transform_point([q(0); 3]), [0, 0, -5 * ONE_Q32]);
/// assert!(Mat4::perspective(Angle::from_degrees(60), 4, 3, q(1), q(10)).is_some());
/// assert!(Mat4::perspective(Angle::from_degrees(60), 4, 3, q(10), q(1)).is_none());
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Mat4 {
    /// Entries, `m[row][col]`, Q32.32.
    pub m: [[i64; 4]; 4],
}

/// A 3-vector of Q16.16 values.
///
/// ```
/// use fixshade::{fixed::Q16_16, math::Vec3};
/// let up: Vec3 = [Q16_16::ZERO, Q16_16::ONE, Q16_16::ZERO];
/// assert_eq!(up[1].to_bits(), 1 << 16);
/// ```
pub type Vec3 = [Q16_16; 3];

fn q16_to_q32(v: Q16_16) -> i64 {
    (v.to_bits() as i64) << 16
}

impl Mat4 {
    /// The identity.
    pub const IDENTITY: Mat4 = Mat4 {
        m: [
            [ONE_Q32, 0, 0, 0],
            [0, ONE_Q32, 0, 0],
            [0, 0, ONE_Q32, 0],
            [0, 0, 0, ONE_Q32],
        ],
    };

    /// Matrix product `self · o`.
    pub fn mul(&self, o: &Mat4) -> Mat4 {
        let mut r = [[0i64; 4]; 4];
        for (i, row) in r.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                let mut acc: i128 = 0;
                for k in 0..4 {
                    acc += mul_i64_wide(self.m[i][k], o.m[k][j]);
                }
                *e = sat_i128_to_i64((acc + (1 << 31)) >> 32);
            }
        }
        Mat4 { m: r }
    }

    /// Translation by `t` (`glTranslate`).
    pub fn translate(t: Vec3) -> Mat4 {
        let mut r = Mat4::IDENTITY;
        for (i, v) in t.iter().enumerate() {
            r.m[i][3] = q16_to_q32(*v);
        }
        r
    }

    /// Scale by `s` per axis (`glScale`).
    pub fn scale(s: Vec3) -> Mat4 {
        let mut r = Mat4::IDENTITY;
        for (i, v) in s.iter().enumerate() {
            r.m[i][i] = q16_to_q32(*v);
        }
        r
    }

    /// Rotation about the x axis (`glRotate(a, 1, 0, 0)`).
    pub fn rotate_x(a: Angle) -> Mat4 {
        let (s, c) = sin_cos_q32(a);
        let mut r = Mat4::IDENTITY;
        r.m[1][1] = c;
        r.m[1][2] = -s;
        r.m[2][1] = s;
        r.m[2][2] = c;
        r
    }

    /// Rotation about the y axis (`glRotate(a, 0, 1, 0)`).
    pub fn rotate_y(a: Angle) -> Mat4 {
        let (s, c) = sin_cos_q32(a);
        let mut r = Mat4::IDENTITY;
        r.m[0][0] = c;
        r.m[0][2] = s;
        r.m[2][0] = -s;
        r.m[2][2] = c;
        r
    }

    /// Rotation about the z axis (`glRotate(a, 0, 0, 1)`).
    pub fn rotate_z(a: Angle) -> Mat4 {
        let (s, c) = sin_cos_q32(a);
        let mut r = Mat4::IDENTITY;
        r.m[0][0] = c;
        r.m[0][1] = -s;
        r.m[1][0] = s;
        r.m[1][1] = c;
        r
    }

    /// The model matrix `T · Rz · Ry · Rx · S` (x rotation applied first).
    pub fn model(translate: Vec3, rotate: [Angle; 3], scale: Vec3) -> Mat4 {
        Mat4::translate(translate)
            .mul(&Mat4::rotate_z(rotate[2]))
            .mul(&Mat4::rotate_y(rotate[1]))
            .mul(&Mat4::rotate_x(rotate[0]))
            .mul(&Mat4::scale(scale))
    }

    /// `gluLookAt(eye, target, up)`. `None` if `eye == target` or `up` is parallel to
    /// the view direction.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Option<Mat4> {
        let e = eye.map(q16_to_q32);
        let t = target.map(q16_to_q32);
        let u = up.map(q16_to_q32);
        let f = normalize_q32([t[0] - e[0], t[1] - e[1], t[2] - e[2]])?;
        let s = normalize_q32(cross_q32(f, u))?;
        let uu = cross_q32(s, f);
        let mut r = Mat4::IDENTITY;
        for i in 0..3 {
            r.m[0][i] = s[i];
            r.m[1][i] = uu[i];
            r.m[2][i] = -f[i];
        }
        for row in 0..3 {
            let mut acc: i128 = 0;
            for (i, ei) in e.iter().enumerate() {
                acc += mul_i64_wide(r.m[row][i], *ei);
            }
            r.m[row][3] = sat_i128_to_i64(-((acc + (1 << 31)) >> 32));
        }
        Some(r)
    }

    /// `gluPerspective(fovy, aspect_w / aspect_h, near, far)`. `None` unless
    /// 0 < fovy < 180°, 0 < near < far and the aspect terms are positive.
    pub fn perspective(
        fovy: Angle,
        aspect_w: u32,
        aspect_h: u32,
        near: Q16_16,
        far: Q16_16,
    ) -> Option<Mat4> {
        let half_turn = 1u32 << 31;
        if fovy.to_turns_bits() == 0 || fovy.to_turns_bits() >= half_turn {
            return None;
        }
        if near.to_bits() <= 0 || far <= near || aspect_w == 0 || aspect_h == 0 {
            return None;
        }
        let (s, c) = sin_cos_q32(fovy.half());
        let f = div_q32(c, s);
        let n = q16_to_q32(near);
        let fa = q16_to_q32(far);
        let mut r = Mat4 { m: [[0; 4]; 4] };
        r.m[0][0] = sat_i128_to_i64(f as i128 * aspect_h as i128 / aspect_w as i128);
        r.m[1][1] = f;
        r.m[2][2] = div_q32(fa + n, n - fa);
        r.m[2][3] = div_q32(2 * mul_q32(fa, n), n - fa);
        r.m[3][2] = -ONE_Q32;
        Some(r)
    }

    /// `glOrtho(-h·a/2, h·a/2, -h/2, h/2, near, far)` with `a = aspect_w / aspect_h`.
    /// `None` unless `height > 0`, `near < far` and the aspect terms are positive.
    pub fn orthographic(
        height: Q16_16,
        aspect_w: u32,
        aspect_h: u32,
        near: Q16_16,
        far: Q16_16,
    ) -> Option<Mat4> {
        if height.to_bits() <= 0 || far <= near || aspect_w == 0 || aspect_h == 0 {
            return None;
        }
        let h = q16_to_q32(height);
        let n = q16_to_q32(near);
        let fa = q16_to_q32(far);
        let mut r = Mat4::IDENTITY;
        // 2 / width with width = h·a: 2·aspect_h / (h·aspect_w).
        r.m[0][0] = div_q32(2 * ONE_Q32 * aspect_h as i64, h * aspect_w as i64);
        r.m[1][1] = div_q32(2 * ONE_Q32, h);
        r.m[2][2] = div_q32(-2 * ONE_Q32, fa - n);
        r.m[2][3] = div_q32(-(fa + n), fa - n);
        Some(r)
    }

    /// Transforms a direction (w = 0) and returns Q32.32 components.
    pub fn transform_dir(&self, d: Vec3) -> [i64; 3] {
        let d = d.map(q16_to_q32);
        let mut r = [0i64; 3];
        for (i, out) in r.iter_mut().enumerate() {
            let mut acc: i128 = 0;
            for (k, dk) in d.iter().enumerate() {
                acc += mul_i64_wide(self.m[i][k], *dk);
            }
            *out = sat_i128_to_i64((acc + (1 << 31)) >> 32);
        }
        r
    }

    /// Transforms a point (w = 1) and returns Q32.32 components of x, y, z.
    pub fn transform_point(&self, p: Vec3) -> [i64; 3] {
        let d = self.transform_dir(p);
        [
            d[0].saturating_add(self.m[0][3]),
            d[1].saturating_add(self.m[1][3]),
            d[2].saturating_add(self.m[2][3]),
        ]
    }
}

fn sat_i128_to_i64(v: i128) -> i64 {
    if v > i64::MAX as i128 {
        i64::MAX
    } else if v < i64::MIN as i128 {
        i64::MIN
    } else {
        v as i64
    }
}

/// Cross product of Q32.32 vectors (saturating).
///
/// ```
/// use fixshade::math::{cross_q32, ONE_Q32};
/// let (x, y) = ([ONE_Q32, 0, 0], [0, ONE_Q32, 0]);
/// assert_eq!(cross_q32(x, y), [0, 0, ONE_Q32]);
/// ```
pub fn cross_q32(a: [i64; 3], b: [i64; 3]) -> [i64; 3] {
    [
        mul_q32(a[1], b[2]) - mul_q32(a[2], b[1]),
        mul_q32(a[2], b[0]) - mul_q32(a[0], b[2]),
        mul_q32(a[0], b[1]) - mul_q32(a[1], b[0]),
    ]
}

/// Unit vector in Q32.32, `None` for the zero vector. Exact to about 2⁻³² per
/// component (the length comes from an exact integer square root of the `i128`
/// sum of squares).
///
/// ```
/// use fixshade::math::{normalize_q32, ONE_Q32};
/// // 3/5 and 4/5 in Q32.32, rounded to nearest.
/// assert_eq!(normalize_q32([3, 0, 4]), Some([(3 * ONE_Q32 + 2) / 5, 0, (4 * ONE_Q32 + 2) / 5]));
/// assert_eq!(normalize_q32([0, 0, 0]), None);
/// ```
pub fn normalize_q32(v: [i64; 3]) -> Option<[i64; 3]> {
    let sq: u128 = v.iter().map(|c| mul_i64_wide(*c, *c) as u128).sum();
    if sq == 0 {
        return None;
    }
    let len = isqrt_u128(sq) as i64; // Q.32, since sq is Q.64
    if len == 0 {
        return None;
    }
    Some(v.map(|c| div_q32(c, len)))
}

/// A 4×4 matrix scaled by a power of two so that every entry fits an `i32` with
/// the largest one in [2³⁰, 2³¹): the per-vertex form of a model-view-projection
/// matrix. Scale is irrelevant to a projective transform (x/w, y/w, z/w are
/// unchanged), so only the relative precision of about 2⁻³⁰ matters.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::math::{ClipMatrix, Mat4};
/// let c = ClipMatrix::new(&Mat4::IDENTITY).unwrap();
/// // The identity is scaled by 2^30: x, y, z, w keep their ratios.
/// let p = c.transform(&[Q16_16::from_int(2), Q16_16::ZERO, Q16_16::ZERO]);
/// assert_eq!(p[0] / p[3], 2);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct ClipMatrix {
    /// Entries, `m[row][col]`.
    pub m: [[i32; 4]; 4],
}

impl ClipMatrix {
    /// Normalises `mat`; `None` if every entry is zero.
    pub fn new(mat: &Mat4) -> Option<ClipMatrix> {
        let max = mat.m.iter().flatten().map(|v| v.unsigned_abs()).max()?;
        if max == 0 {
            return None;
        }
        let bits = 64 - max.leading_zeros() as i32; // max < 2^bits
        let shift = bits - 31; // entries >> shift < 2^31
        let mut m = [[0i32; 4]; 4];
        for (r, row) in m.iter_mut().enumerate() {
            for (c, e) in row.iter_mut().enumerate() {
                let v = mat.m[r][c] as i128;
                let s = if shift >= 0 {
                    (v + ((1i128 << shift) >> 1)) >> shift
                } else {
                    v << -shift
                };
                *e = s.clamp(-(i32::MAX as i128), i32::MAX as i128) as i32;
            }
        }
        Some(ClipMatrix { m })
    }

    /// `M · (p, 1)` for a Q16.16 point with |components| < 2¹⁴: each product is below
    /// 2³¹·2³⁰ = 2⁶¹ and the sum of four below 2⁶³, so the `i64` sums cannot overflow.
    #[inline]
    pub fn transform(&self, p: &Vec3) -> [i64; 4] {
        let (x, y, z) = (p[0].to_bits(), p[1].to_bits(), p[2].to_bits());
        let mut r = [0i64; 4];
        for (i, out) in r.iter_mut().enumerate() {
            let row = &self.m[i];
            *out = mul_wide(row[0], x)
                + mul_wide(row[1], y)
                + mul_wide(row[2], z)
                + ((row[3] as i64) << 16);
        }
        r
    }
}

/// The clip-space z of a perspective projection as a function of w, for the
/// clipper: `z = w·a + ⌊w·frac/2³⁰⌋ + bz`, with `a + frac/2³⁰` the projection's
/// `(far + near)/(far − near)` (`a ≥ 1`) and `bz` its constant term in the frame's
/// clip units. Both terms grow with w, by at least 1 per unit step, so the near
/// and far planes (`z ≥ −w`, `z ≤ w`) are two thresholds on w
/// ([`crate::geometry::Projector`] finds them; the vertex stage tests w against
/// them and needs no z).
///
/// ```
/// use fixshade::math::ZFromW;
/// // z = 2·w − 10: the near plane z = −w at w = 10/3, the far plane z = w at w = 10.
/// let f = ZFromW { a: 2, frac: 0, bz: -10 };
/// assert!(f.z(3) < -3 && f.z(4) >= -4);
/// assert!(f.z(10) <= 10 && f.z(11) > 11);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct ZFromW {
    /// Integer part of the slope, 1..2³¹.
    pub a: i32,
    /// Fraction of the slope, Q0.30.
    pub frac: i32,
    /// Constant term (clip units).
    pub bz: i64,
}

impl ZFromW {
    /// z for a given w (`i64`: |w·a| < 2⁶², the fraction's product below 2⁶¹).
    ///
    /// ```
    /// use fixshade::math::ZFromW;
    /// // z = 1.5·w − 100
    /// let f = ZFromW { a: 1, frac: 1 << 29, bz: -100 };
    /// assert_eq!(f.z(1000), 1400);
    /// ```
    #[inline]
    pub fn z(&self, w: i32) -> i64 {
        mul_wide(w, self.a) + (mul_wide(w, self.frac) >> 30) + self.bz
    }
}

/// `$t.$f::<S, SH>($q)` for the form of the [`VertexTransform`] `$t`.
macro_rules! by_form {
    ($t:expr, $f:ident, $q:expr) => {
        match ($t.s, $t.shift) {
            (13, PositionShift::None) => $t.$f::<13, 0>($q),
            (13, _) => $t.$f::<13, 1>($q),
            (_, PositionShift::Right) => $t.$f::<18, 2>($q),
            _ => $t.$f::<18, 1>($q),
        }
    };
}

/// Where ARMv6-M splits the low part of a [`VertexTransform`] entry for 19-bit
/// positions (see the type).
#[cfg(any(test, fixshade_v6m))]
const LOW_SPLIT: u32 = 9;

/// How [`VertexTransform`] takes a mesh's positions before the products.
///
/// ```
/// use fixshade::math::{Mat4, PositionShift, VertexTransform};
/// // A mesh within ±1/4 (2^14 raw) is shifted left to 17 bits, one within ±1 (17 bits)
/// // taken as it is, one within ±100 rounded to 19 bits.
/// let t = |bound| VertexTransform::new(&Mat4::IDENTITY, 16, bound, 30, None).unwrap();
/// assert_eq!(t(1 << 14).form().1, PositionShift::Left);
/// assert_eq!(t(1 << 16).form().1, PositionShift::None);
/// assert_eq!(t(100 << 16).form().1, PositionShift::Right);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum PositionShift {
    /// As they are (the mesh spans exactly 17 or 19 bits).
    #[default]
    None,
    /// Shifted left (exact; smaller meshes).
    Left,
    /// Rounded to 19 bits (meshes beyond ±8 units).
    Right,
}

/// The vertex stage's transform of one mesh for one frame: clip coordinates
/// (x, y, z, w) in `i32` from Q16.16 positions, with 32-bit products only on
/// ARMv6-M and three `SMULL`/`SMLAL` per row on ARMv7-M, the same bits on both.
///
/// Each row is `C = ⌊Σᵢ Mᵢ·pᵢ / 2ˢ⌋ + t`: the positions `p` are the mesh's
/// brought to `P` = 17 bits (meshes within ±2 units; smaller ones shifted left,
/// exactly) or 19 bits (larger ones; beyond ±8 units rounded,
/// `p = ⌊(q + 2ᵇ⁻¹)/2ᵇ⌋`), so `|p| ≤ 2ᴾ`, and the entries `M` and `t` are the
/// model-view-projection matrix in the frame's clip units
/// ([`crate::geometry::Projector`]), scaled to match and rounded to integers. The
/// frame's scale keeps every `|C|` of the mesh below 2³⁰ (w below 2³⁰ over the
/// guard exponent), so an entry lies below 2^(30 + s − P + 1). The entries carry
/// `s` = 13 fraction bits for `P` = 17 and 18 for `P` = 19 (the most that keeps
/// them in `i32`).
///
/// Error: an entry's rounding (½) moves a row by at most `½·|p|/2ˢ`, so the three
/// move it by at most 3·2^(P−1−s) clip units (24 for P = 17, 3 for P = 19), `t`'s
/// rounding and the floor by 1.5 more. A mesh rounded to 19 bits also errs by
/// half a position step (2ᵇ⁻¹ raw units) in each coordinate.
/// (What this is on screen: [`crate::geometry::Projector`].)
///
/// ARMv6-M splits each entry as `M = h·2ˢ + l` with `l` in [−2ˢ⁻¹, 2ˢ⁻¹): then
/// `⌊Σ M·p/2ˢ⌋ = Σ h·p + ⌊Σ l·p/2ˢ⌋` exactly, and `|Σ h·p|` ≤ |C| + |t| + 3·2ᴾ⁻¹
/// fits `i32`. For `P` = 17, `|Σ l·p|` ≤ 3·2ˢ⁻¹⁺ᴾ = 3·2²⁹. For `P` = 19 that
/// would be 3·2³⁵: `l` is split again as the row is computed, `l = l'·2⁹ + l''`
/// with `l''` in [0, 2⁹), and `⌊Σ l·p/2ˢ⌋ = ⌊(Σ l'·p + ⌊Σ l''·p/2⁹⌋)/2ˢ⁻⁹⌋`,
/// where `|Σ l'·p|` ≤ 3·2²⁷ and `|Σ l''·p|` < 3·2²⁸. ARMv7-M sums the exact
/// 64-bit products (each below 2⁵⁰) and takes the 32 bits above bit `s`.
///
/// For a perspective projection the vertex stage needs only x, y and w; the
/// clipper's z comes from w ([`ZFromW`]).
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::math::{Mat4, VertexTransform};
/// // The identity at 2^20 clip units per unit, for a mesh within ±1: x, y and w in i32.
/// let t = VertexTransform::new(&Mat4::IDENTITY, 20, 1 << 16, 30, None).unwrap();
/// let (s, _) = t.form();
/// let p = [Q16_16::from_ratio(1, 2), Q16_16::ZERO, Q16_16::ZERO];
/// let xyw = if s == 13 { t.xyw::<13, 1>(&p) } else { t.xyw::<18, 1>(&p) };
/// assert_eq!(xyw, [1 << 19, 0, 1 << 20]);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct VertexTransform {
    m: [[i32; 3]; 4],
    hi: [[i32; 3]; 4],
    lo: [[i32; 3]; 4],
    t: [i32; 4],
    s: u32,
    shift: PositionShift,
    /// Left shift, or right shift and its rounding.
    a: u32,
    b: u32,
    round: i32,
    persp: Option<ZFromW>,
}

impl VertexTransform {
    /// The transform of a mesh whose |coordinates| are at most `bound` (raw
    /// Q16.16) under the Q32.32 model-view-projection `clip`, in clip units of
    /// `2^scale` per clip-space unit. `persp` gives z from w (perspective
    /// projections); without it z is the matrix's third row. `None` if an entry
    /// does not fit or a row of the mesh could reach 2³⁰ (2^`w_bits` for w): the
    /// frame's scale is chosen so that neither happens.
    pub fn new(
        clip: &Mat4,
        scale: i32,
        bound: i32,
        w_bits: u32,
        persp: Option<ZFromW>,
    ) -> Option<VertexTransform> {
        let bits = (32 - (bound.max(0) as u32).leading_zeros()) as i32;
        let p = if bits <= 17 { 17 } else { 19 };
        let (a, b) = ((p - bits).max(0), (bits - p).max(0));
        let shift = match (a, b) {
            (0, 0) => PositionShift::None,
            (_, 0) => PositionShift::Left,
            _ => PositionShift::Right,
        };
        let s = if p == 17 { 13 } else { 18 };
        // M = m·2^(scale + b − a − 16 + s − 32) (m in Q32.32, positions Q16.16
        // shifted by a or b), t = m·2^(scale − 32); rounded to nearest.
        let scaled = |v: i64, e: i32| -> Option<i32> {
            let v = v as i128;
            let r = if e >= 0 {
                v.checked_shl(e as u32).filter(|x| (x >> e) == v)?
            } else {
                let k = (-e).min(127) as u32;
                (v + ((1i128 << k) >> 1)) >> k
            };
            i32::try_from(r).ok()
        };
        let mut m = [[0i32; 3]; 4];
        let mut t = [0i32; 4];
        for ((mr, tr), cr) in m.iter_mut().zip(t.iter_mut()).zip(clip.m.iter()) {
            for (e, c) in mr.iter_mut().zip(cr.iter()) {
                *e = scaled(*c, scale + b - a + s - 48)?;
            }
            *tr = scaled(cr[3], scale - 32)?;
        }
        // Every row within its limit for any |position| ≤ pmax (plus the floor).
        let pmax = if b > 0 {
            1i64 << p
        } else {
            (bound.max(0) as i64) << a
        };
        for (r, (row, tr)) in m.iter().zip(t.iter()).enumerate() {
            if r == 2 && persp.is_some() {
                continue; // z comes from w
            }
            let sum: i64 = row
                .iter()
                .map(|v| (v.unsigned_abs() as i64 * pmax) >> s)
                .sum();
            let lim = if r == 3 { 1i64 << w_bits } else { 1 << 30 };
            if sum + tr.unsigned_abs() as i64 + 4 > lim {
                return None;
            }
        }
        let half = 1i64 << (s - 1);
        let hi = m.map(|row| row.map(|v| ((v as i64 + half) >> s) as i32));
        let mut lo = [[0i32; 3]; 4];
        for r in 0..4 {
            for i in 0..3 {
                // |l| ≤ 2^(s−1).
                lo[r][i] = (m[r][i] as i64 - ((hi[r][i] as i64) << s)) as i32;
            }
        }
        Some(VertexTransform {
            m,
            hi,
            lo,
            t,
            s: s as u32,
            shift,
            a: a as u32,
            b: b as u32,
            round: if b > 0 { 1 << (b - 1) } else { 0 },
            persp,
        })
    }

    /// The row shift `s` (13 or 18) and how the positions are taken: the
    /// monomorphisation [`Self::xyw`] and [`Self::xyzw`] need.
    #[inline(always)]
    pub fn form(&self) -> (u32, PositionShift) {
        (self.s, self.shift)
    }

    /// The positions as the products take them (`SH`: 0 none, 1 left, 2 right).
    #[inline(always)]
    fn input<const SH: u8>(&self, q: &Vec3) -> [i32; 3] {
        q.map(|c| match SH {
            0 => c.to_bits(),
            1 => c.to_bits() << self.a,
            _ => (c.to_bits() + self.round) >> self.b,
        })
    }

    /// Row `r` (0 x, 1 y, 2 z, 3 w) for the prepared positions `p`, `S` = `s`.
    #[inline(always)]
    fn row<const S: u32>(&self, r: usize, p: &[i32; 3]) -> i32 {
        #[cfg(fixshade_v6m)]
        {
            // The 19-bit rows' three-part form out of line in the smallest images
            // (`small-flash`: one copy in place of one in every row of every
            // projection loop; the micro:bit's 256 KiB).
            if S != 13 && cfg!(feature = "small-flash") {
                return self.row_split_outlined::<S>(r, p);
            }
            self.row_split::<S>(r, p)
        }
        #[cfg(not(fixshade_v6m))]
        {
            self.row_wide::<S>(r, p)
        }
    }

    /// [`Self::row_split`], not inlined.
    #[cfg(fixshade_v6m)]
    #[inline(never)]
    fn row_split_outlined<const S: u32>(&self, r: usize, p: &[i32; 3]) -> i32 {
        self.row_split::<S>(r, p)
    }

    /// [`Self::row`] from the exact 64-bit sum: `⌊sum/2ˢ⌋` (the result fits `i32`,
    /// see the type's bounds; two instructions from the two words).
    #[cfg_attr(fixshade_v6m, allow(dead_code))]
    #[inline(always)]
    fn row_wide<const S: u32>(&self, r: usize, p: &[i32; 3]) -> i32 {
        let m = &self.m[r];
        let acc = mul_wide(m[0], p[0]) + mul_wide(m[1], p[1]) + mul_wide(m[2], p[2]);
        (acc >> S) as i32 + self.t[r]
    }

    /// [`Self::row`] from the split entries with 32-bit products.
    #[cfg(any(test, fixshade_v6m))]
    #[inline(always)]
    fn row_split<const S: u32>(&self, r: usize, p: &[i32; 3]) -> i32 {
        let (h, l) = (&self.hi[r], &self.lo[r]);
        let high = h[0] * p[0] + h[1] * p[1] + h[2] * p[2];
        if S == 13 {
            let low = l[0] * p[0] + l[1] * p[1] + l[2] * p[2];
            high + (low >> S) + self.t[r]
        } else {
            let (a, b) = (
                l.map(|v| v >> LOW_SPLIT),
                l.map(|v| v & ((1 << LOW_SPLIT) - 1)),
            );
            let low = a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
            let fine = b[0] * p[0] + b[1] * p[1] + b[2] * p[2];
            high + ((low + (fine >> LOW_SPLIT)) >> (S - LOW_SPLIT)) + self.t[r]
        }
    }

    /// x, y and w of a mesh position, for `(S, SH)` matching [`Self::form`] (`SH`: 0
    /// [`PositionShift::None`], 1 `Left`, 2 `Right`).
    #[inline(always)]
    pub fn xyw<const S: u32, const SH: u8>(&self, q: &Vec3) -> [i32; 3] {
        debug_assert_eq!(S, self.s);
        let p = self.input::<SH>(q);
        [
            self.row::<S>(0, &p),
            self.row::<S>(1, &p),
            self.row::<S>(3, &p),
        ]
    }

    /// x, y, z and w of a mesh position (z from the third row), as [`Self::xyw`].
    #[inline(always)]
    pub fn xyzw<const S: u32, const SH: u8>(&self, q: &Vec3) -> [i32; 4] {
        debug_assert_eq!(S, self.s);
        let p = self.input::<SH>(q);
        [
            self.row::<S>(0, &p),
            self.row::<S>(1, &p),
            self.row::<S>(2, &p),
            self.row::<S>(3, &p),
        ]
    }

    /// w of a mesh position, as [`Self::xyw`].
    #[inline(always)]
    fn w_of<const S: u32, const SH: u8>(&self, q: &Vec3) -> i32 {
        debug_assert_eq!(S, self.s);
        self.row::<S>(3, &self.input::<SH>(q))
    }

    /// The clip-space w of a mesh position (the vertex stage's, as
    /// [`Self::transform`] gives it).
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::math::{Mat4, VertexTransform};
    /// let t = VertexTransform::new(&Mat4::IDENTITY, 20, 1 << 16, 30, None).unwrap();
    /// assert_eq!(t.w(&[Q16_16::from_int(1), Q16_16::ZERO, Q16_16::ZERO]), 1 << 20);
    /// ```
    pub fn w(&self, q: &Vec3) -> i32 {
        by_form!(self, w_of, q)
    }

    /// The clip coordinates of a mesh position, as the clipper takes them: the
    /// vertex stage's x, y and w, and z from w under a perspective projection.
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::math::{Mat4, VertexTransform};
    /// // The identity at 2^20 clip units per unit, for a mesh within ±1.
    /// let t = VertexTransform::new(&Mat4::IDENTITY, 20, 1 << 16, 30, None).unwrap();
    /// let p = [Q16_16::from_int(1), Q16_16::ZERO, Q16_16::from_ratio(-1, 2)];
    /// assert_eq!(t.transform(&p), [1 << 20, 0, -(1 << 19), 1 << 20]);
    /// ```
    #[inline(never)]
    pub fn transform(&self, q: &Vec3) -> [i64; 4] {
        match &self.persp {
            // A perspective projection's third row may not fit: z comes from w.
            Some(f) => {
                let [x, y, w] = by_form!(self, xyw, q);
                [x as i64, y as i64, f.z(w), w as i64]
            }
            None => by_form!(self, xyzw, q).map(|c| c as i64),
        }
    }
}

/// An affine 3-D transform for the lighting stage: a Q16.16 linear part and
/// translation (eye-space positions), plus a normal matrix (the cofactor matrix of the
/// linear part, sign-corrected, normalised like [`ClipMatrix`]) for normals.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::math::{Affine3, Mat4};
/// let q = Q16_16::from_int;
/// let a = Affine3::new(&Mat4::translate([q(0), q(0), q(-3)])).unwrap();
/// assert_eq!(a.point(&[q(1), q(2), q(3)]), [1 << 16, 2 << 16, 0]);
/// assert!(Affine3::new(&Mat4::scale([q(0), q(1), q(1)])).is_none());
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Affine3 {
    /// Linear part, Q16.16, `m[row][col]`.
    pub linear: [[i32; 3]; 3],
    /// Translation, Q16.16.
    pub translation: [i32; 3],
    /// Normal matrix, scaled so its largest entry is in [2³⁰, 2³¹).
    pub normal: [[i32; 3]; 3],
}

impl Affine3 {
    /// The upper 3×4 part of a model-view matrix. `None` if its linear part is
    /// singular.
    pub fn new(mat: &Mat4) -> Option<Affine3> {
        let r = |v: i64| -> i32 { crate::fixed::sat_i64_to_i32((v + (1 << 15)) >> 16) };
        let linear: [[i32; 3]; 3] =
            core::array::from_fn(|i| core::array::from_fn(|j| r(mat.m[i][j])));
        let translation: [i32; 3] = core::array::from_fn(|i| r(mat.m[i][3]));
        // Cofactors of the Q32.32 linear part: products of two i64 are below 2^126
        // and their difference below 2^127, so i128 holds them.
        let a = |i: usize, j: usize| mat.m[i][j] as i128;
        let p = |i: usize, j: usize, k: usize, l: usize| mul_i64_wide(mat.m[i][j], mat.m[k][l]);
        let mut cof = [[0i128; 3]; 3];
        for (i, row) in cof.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
                let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
                *e = (p(i1, j1, i2, j2) - p(i1, j2, i2, j1)) >> 32;
            }
        }
        let det: i128 = (0..3).map(|j| a(0, j) * cof[0][j]).sum();
        if det == 0 {
            return None;
        }
        let max = cof.iter().flatten().map(|v| v.unsigned_abs()).max()?;
        if max == 0 {
            return None;
        }
        let bits = 128 - max.leading_zeros() as i32;
        let shift = bits - 31;
        let sign = if det < 0 { -1 } else { 1 };
        let mut normal = [[0i32; 3]; 3];
        for (row, crow) in normal.iter_mut().zip(cof.iter()) {
            for (e, c) in row.iter_mut().zip(crow.iter()) {
                let v = c * sign;
                let s = if shift >= 0 { v >> shift } else { v << -shift };
                *e = s.clamp(-(i32::MAX as i128), i32::MAX as i128) as i32;
            }
        }
        Some(Affine3 {
            linear,
            translation,
            normal,
        })
    }

    /// Eye-space position of a Q16.16 point, Q16.16 (saturating). Products are
    /// i32·i32 < 2⁶², sums of three plus the translation < 2⁶³.
    #[inline]
    pub fn point(&self, p: &Vec3) -> [i32; 3] {
        let mut r = [0i32; 3];
        for (i, out) in r.iter_mut().enumerate() {
            let l = &self.linear[i];
            let acc = mul_wide(l[0], p[0].to_bits())
                + mul_wide(l[1], p[1].to_bits())
                + mul_wide(l[2], p[2].to_bits());
            *out = crate::fixed::sat_i64_to_i32(
                ((acc + (1 << 15)) >> 16) + self.translation[i] as i64,
            );
        }
        r
    }
}

/// Shifts a non-zero vector so its largest component lies in [2²⁹, 2³⁰) and returns
/// the shifted components (now `i32`) with their sum of squares (in [2⁵⁸, 3·2⁶⁰):
/// squares < 2⁶⁰ by [`mul_wide`], sum < 2⁶²). `None` for the zero vector.
#[inline]
fn scale_for_length(v: [i64; 3]) -> Option<(i32, i32, i32, u64)> {
    let max = v[0].unsigned_abs() | v[1].unsigned_abs() | v[2].unsigned_abs();
    if max == 0 {
        return None;
    }
    let hi = (max >> 32) as u32;
    let bits = if hi != 0 {
        64 - leading_zeros(hi)
    } else {
        32 - leading_zeros(max as u32)
    } as i32;
    // bits in [1, 64]: the shift in [−29, 34]. The results fit i32: only the low
    // words are kept (a left shift of the low word alone; `shr_i64`, not the
    // library's 64-bit shift, on ARMv6-M).
    let shift = bits - 30;
    let s = |c: i64| {
        if shift >= 0 {
            shr_i64(c, shift as u32) as i32
        } else {
            ((c as u32) << -shift) as i32
        }
    };
    let (x, y, z) = (s(v[0]), s(v[1]), s(v[2]));
    let sq = mul_wide(x, x) + mul_wide(y, y) + mul_wide(z, z);
    Some((x, y, z, sq as u64))
}

/// Seeds of [`rsqrt_q61`]: `RSQRT_SEED[i] ≈ 2⁶¹ / √((i + 64.5)·2⁵⁴)` for the top eight
/// bits `i + 64` of an argument in [2⁶⁰, 2⁶²), computed at compile time with exact
/// integer square roots. 192 entries × 4 bytes = 768 bytes of flash; relative
/// error below 2⁻⁸.
const RSQRT_SEED: [u32; 192] = {
    let mut t = [0u32; 192];
    let mut i = 0;
    while i < 192 {
        // 2⁶¹/√((i + 64.5)·2⁵⁴) = √(2¹²²/((2i + 129)·2⁵³)) = √(2⁶⁹/(2i + 129)).
        let sq = (1u128 << 69) / (2 * i as u128 + 129);
        t[i] = isqrt_u128(sq) as u32;
        i += 1;
    }
    t
};

/// `2⁶¹/√s` to within 4 units, below 2³¹, for `s` in [2⁶⁰, 2⁶²): a table seed
/// (`RSQRT_SEED`, 8 bits) and two Newton steps `r ← r·(3 − s·r²)/2`, each three
/// 32×32→64-bit products ([`mul_wide_u`]; no division, no square root).
///
/// Bounds: `r` ∈ (2³⁰, 2³¹); `r²/2³²` < 2³⁰; times `s/2³⁰` < 2³² gives < 2⁶²;
/// `3·2³⁰ − y` ∈ (0, 2³²) for y within 2⁻⁷ of 2³⁰, and `r·(3·2³⁰ − y)` < 2⁶³.
///
/// ```
/// use fixshade::math::rsqrt_q61;
/// // 2^61 / √(2^60) = 2^31 (just above the range of the result).
/// assert!(rsqrt_q61(1 << 60).abs_diff(1 << 31) <= 4);
/// ```
#[inline]
pub fn rsqrt_q61(s: u64) -> u64 {
    // s >> 54 is in [64, 256); the index is below 192.
    let mut r = RSQRT_SEED[(((s >> 54) as usize).wrapping_sub(64)).min(191)];
    let sn = (s >> 30) as u32; // [2^30, 2^32)
    let mut k = 0;
    while k < 2 {
        // y = s·r²/2¹²² in Q30 ≈ 2³⁰.
        let r2 = (mul_wide_u(r, r) >> 32) as u32;
        let y = (mul_wide_u(r2, sn) >> 30) as u32;
        r = ((mul_wide_u(r, (3u32 << 30).wrapping_sub(y)) >> 31) as u32).min(i32::MAX as u32);
        k += 1;
    }
    r as u64
}

/// The Euclidean length of an `i64` vector, within 2⁻²⁷ of the exact value
/// (relatively; tested), without `i128`, a square root or a division: the
/// components are shifted so the largest lies in [2²⁹, 2³⁰) (as [`normalize_to_q30`]
/// does), `√sq = sq·rsqrt(sq)` from [`rsqrt_q61`] (the product of `sq >> 30` <
/// 3·2³⁰ and `r` < 2³¹ below 2⁶³), and shifted back.
///
/// ```
/// use fixshade::math::length;
/// assert_eq!(length([0, 0, 0]), 0);
/// assert!(length([3 << 20, 4 << 20, 0]).abs_diff(5 << 20) <= 1);
/// ```
pub fn length(v: [i64; 3]) -> u64 {
    let max = v[0].unsigned_abs() | v[1].unsigned_abs() | v[2].unsigned_abs();
    if max == 0 {
        return 0;
    }
    let hi = (max >> 32) as u32;
    let bits = if hi != 0 {
        64 - leading_zeros(hi)
    } else {
        32 - leading_zeros(max as u32)
    } as i32;
    let shift = bits - 30;
    let Some((_, _, _, sq)) = scale_for_length(v) else {
        return 0;
    };
    let j = if sq < 1 << 60 { 1 } else { 0 };
    let r = rsqrt_q61(sq << (2 * j)) as u32; // 2^61/(√sq·2^j)
    let root = (mul_wide_u((sq >> 30) as u32, r) >> (31 - j)) as u32; // √sq < 2^31
    if shift >= 0 {
        shl_u32(root, shift as u32)
    } else {
        (root >> (-shift).min(31)) as u64
    }
}

/// `v·2ˢ` as `u64` from 32-bit shifts (a variable 64-bit shift is a library call on
/// ARMv6-M); saturating.
#[inline]
fn shl_u32(v: u32, s: u32) -> u64 {
    match s {
        0 => v as u64,
        1..=31 => (((v >> (32 - s)) as u64) << 32) | (v << s) as u64,
        32 => (v as u64) << 32,
        _ if (v >> (64 - s.min(63))) != 0 => u64::MAX,
        _ => ((v << (s - 32)) as u64) << 32,
    }
}

/// `⌊v·s/2¹⁶⌋` for a `u64` and a Q16.16 factor `0 ≤ s < 2³¹` (saturating), from
/// two [`mul_wide_u`].
///
/// ```
/// use fixshade::math::mul_q16_u64;
/// assert_eq!(mul_q16_u64(3 << 40, 1 << 15), 3 << 39);
/// ```
pub fn mul_q16_u64(v: u64, s: i64) -> u64 {
    let s = s.clamp(0, i32::MAX as i64) as u32;
    let low = mul_wide_u(v as u32, s) >> 16;
    let high = mul_wide_u((v >> 32) as u32, s);
    if high >= 1 << 48 {
        return u64::MAX;
    }
    low + (high << 16)
}

/// Normalises an `i64` vector to Q2.30 unit length without a square root or a
/// division: the components are shifted so the largest lies in [2²⁹, 2³⁰), the sum
/// of their squares `n` (in [2⁵⁸, 3·2⁶⁰)) is brought into [2⁶⁰, 2⁶²) by an even
/// shift, and each component is multiplied by [`rsqrt_q61`] of it. Each component
/// is within 4 units (Q2.30) of the exact normalisation (tested). `None` for the
/// zero vector.
///
/// ```
/// use fixshade::math::{normalize_to_q30, ONE_Q30};
/// assert_eq!(normalize_to_q30([0, -7, 0]).map(|n| n[1].abs_diff(-ONE_Q30) <= 4), Some(true));
/// let n = normalize_to_q30([1, 1, 0]).unwrap();
/// assert!((n[0] - 759_250_125).abs() <= 4); // 2^30 / √2
/// ```
#[inline]
pub fn normalize_to_q30(v: [i64; 3]) -> Option<[i32; 3]> {
    let (x, y, z, sq) = scale_for_length(v)?;
    // Bring the sum into [2^60, 2^62) with an even shift 2j (j = 0 or 1):
    // √(sq·4^j) = len·2^j.
    let j = if sq < 1 << 60 { 1 } else { 0 };
    let r = rsqrt_q61(sq << (2 * j)) as i32; // 2^61/(len·2^j), in (2^30, 2^31)
                                             // c·2^30/len = c·r·2^j/2^31; |c| < 2^30, r < 2^31: the product is below 2^61.
    let sh = 31 - j;
    let d = |c: i32| ((mul_wide(c, r) + (1 << (sh - 1))) >> sh) as i32;
    Some([d(x), d(y), d(z)])
}

/// Dot product of Q2.30 vectors, Q2.30 (products < 2⁶¹, sum < 2⁶³).
///
/// ```
/// use fixshade::math::{dot_q30, ONE_Q30};
/// let h = ONE_Q30 / 2;
/// assert_eq!(dot_q30([h, h, 0], [ONE_Q30, ONE_Q30, 0]), ONE_Q30);
/// ```
#[inline]
pub fn dot_q30(a: [i32; 3], b: [i32; 3]) -> i32 {
    let s = mul_wide(a[0], b[0]) + mul_wide(a[1], b[1]) + mul_wide(a[2], b[2]);
    crate::fixed::sat_i64_to_i32((s + (1 << 29)) >> 30)
}

/// `2^(2^-i)` for i = 1..=30 in Q2.30, computed at compile time by repeated exact
/// integer square roots of 2.
const EXP2_TABLE: [u64; 30] = {
    let mut t = [0u64; 30];
    let mut v: u128 = 2u128 << 60; // 2 in Q.60
    let mut i = 0;
    while i < 30 {
        v = isqrt_u128(v << 60); // sqrt in Q.60
        t[i] = ((v + (1 << 29)) >> 30) as u64;
        i += 1;
    }
    t
};

/// log₂ of `c` in Q2.30 (0 < c ≤ 2³⁰, i.e. (0, 1]), result in Q.30 (≤ 0).
/// Bit-by-bit squaring: 30 exact iterations, error ≤ 2·2⁻³⁰.
/// Returned as `(k, y)` with log₂ c = −k + y·2⁻³⁰, `k` ≤ 30 and `y` < 2³⁰.
fn log2_q30(c: u32) -> (i32, i32) {
    debug_assert!(c > 0);
    let k = leading_zeros(c) as i32 - 1; // c << k in [2^30, 2^31)
    let mut m = c << k;
    let mut y = 0;
    for i in 1..=30 {
        let sq = mul_wide_u(m, m) >> 30; // m in [2^30, 2^32): m² < 2^64
        if sq >= 1 << 31 {
            m = (sq >> 1) as u32;
            y |= 1 << (30 - i);
        } else {
            m = sq as u32;
        }
    }
    (k, y)
}

/// 2^t for t ≤ 0 in Q.30, result Q2.30.
fn exp2_q30(t: i64) -> u32 {
    let ip = t >> 30; // floor, ≤ 0
    let f = (t - (ip << 30)) as u32; // [0, 2^30)
    if ip < -31 {
        return 0;
    }
    let mut r: u64 = 1 << 30;
    for (i, e) in EXP2_TABLE.iter().enumerate() {
        if f & (1 << (29 - i)) != 0 {
            // r < 2^31, e < 2^31: product < 2^62.
            r = (mul_wide_u(r as u32, *e as u32) + (1 << 29)) >> 30;
        }
    }
    // r in [2^30, 2^31); shift by -ip.
    let s = (-ip) as u32;
    ((r + ((1u64 << s) >> 1)) >> s) as u32
}

/// `c^n` for `c` in Q2.30 clamped to [0, 1] and `n` in Q16.16 (n ≥ 0), result Q2.30.
///
/// Integer `n` uses exponentiation by squaring (relative error below n·2⁻²⁹);
/// fractional `n` uses `2^(n·log₂ c)` with the bit-by-bit logarithm and a product
/// of `2^(2^-i)` constants. `c ≥ 1` gives 1; `c ≤ 0` gives 0 (for n > 0).
///
/// ```
/// use fixshade::math::pow_q30;
/// use fixshade::fixed::Q16_16;
/// let half = 1 << 29;
/// assert_eq!(pow_q30(half, Q16_16::from_int(2)), 1 << 28);
/// assert_eq!(pow_q30(1 << 30, Q16_16::from_int(1000)), 1 << 30);
/// ```
pub fn pow_q30(c: i32, n: Q16_16) -> i32 {
    let nb = n.to_bits();
    if nb <= 0 {
        return ONE_Q30;
    }
    if c <= 0 {
        return 0;
    }
    if c >= ONE_Q30 {
        return ONE_Q30;
    }
    if nb & 0xFFFF == 0 {
        // Factors ≤ 2^30: products ≤ 2^60, results ≤ 2^30.
        let mut e = (nb >> 16) as u32;
        let mut base = c as u32;
        let mut acc: u32 = 1 << 30;
        while e > 0 {
            if e & 1 == 1 {
                acc = ((mul_wide_u(acc, base) + (1 << 29)) >> 30) as u32;
            }
            e >>= 1;
            if e > 0 {
                base = ((mul_wide_u(base, base) + (1 << 29)) >> 30) as u32;
            }
        }
        return acc as i32;
    }
    // n·log₂ c = −k·n + y·n·2⁻³⁰ (Q.30 after the shift by 16): k·nb ≤ 31·2^26 fits i32,
    // y·nb < 2^56; |l·n| < 2^61 as before.
    let (k, y) = log2_q30(c as u32);
    let t = ((-((k * nb) as i64) << 30) + mul_wide(y, nb)) >> 16;
    exp2_q30(t) as i32
}

/// `c + x0·dc` modulo 2⁶⁴ for `x0 ≥ 0` (a packed value at pixel `x0` of a row whose
/// value at x = 0 is `c`, see `raster::pixel`): from 32-bit products (no 64×64
/// multiply).
#[inline(always)]
pub(crate) fn packed_at(c: u64, dc: u64, x0: i32) -> u64 {
    let x = x0 as u32;
    let step =
        mul_wide_u(x, dc as u32).wrapping_add((x.wrapping_mul((dc >> 32) as u32) as u64) << 32);
    c.wrapping_add(step)
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)] // f64 reference figures, host only
mod tests {
    extern crate std;
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn sin_cos_match_f64() {
        let mut worst = 0f64;
        for k in 0..4096u32 {
            let bits = k.wrapping_mul(1_048_573).wrapping_add(k * 7);
            let (s, c) = sin_cos_q32(Angle::from_turns_bits(bits));
            let a = bits as f64 / 4294967296.0 * 2.0 * PI;
            worst = worst
                .max((s as f64 / 4294967296.0 - a.sin()).abs())
                .max((c as f64 / 4294967296.0 - a.cos()).abs());
        }
        assert!(worst < 4.0 / 4294967296.0, "worst {worst}");
    }

    #[test]
    fn pow_matches_f64() {
        for n10 in [10i32, 15, 20, 80, 320, 1000, 2500, 10000] {
            let n = Q16_16::from_ratio(n10, 10);
            let nf = n.to_bits() as f64 / 65536.0;
            for k in 1..200 {
                let c = ((1i64 << 30) * k / 200) as i32;
                let cf = c as f64 / (1u64 << 30) as f64;
                let got = pow_q30(c, n) as f64 / (1u64 << 30) as f64;
                let want = cf.powf(nf);
                assert!(
                    (got - want).abs() < 2e-6,
                    "c={cf} n={nf} got {got} want {want}"
                );
            }
        }
    }

    /// xorshift64 for the randomised tests.
    fn xorshift(seed: &mut u64) -> u64 {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        *seed
    }

    /// Factors at the edges of the 16-bit halves and of `i32`.
    const EDGES: [i32; 10] = [
        0,
        1,
        -1,
        0xFFFF,
        0x10000,
        -0x10000,
        i32::MAX,
        i32::MIN,
        0x7FFF,
        -0x8000,
    ];

    #[test]
    fn split_products_equal_native() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        for &a in &EDGES {
            for &b in &EDGES {
                assert_eq!(mul_wide_split(a, b), a as i64 * b as i64, "{a} {b}");
                let (ua, ub) = (a as u32, b as u32);
                assert_eq!(mul_wide_u_split(ua, ub), ua as u64 * ub as u64);
                assert_eq!(mul_wide_16_split(a, b as i16), a as i64 * (b as i16) as i64);
            }
        }
        for _ in 0..1_000_000 {
            let r = xorshift(&mut seed);
            let (a, b) = (r as i32 >> (r >> 59), (r >> 32) as i32 >> ((r >> 54) & 31));
            assert_eq!(mul_wide_split(a, b), a as i64 * b as i64, "{a} {b}");
            let (ua, ub) = (r as u32, (r >> 32) as u32);
            assert_eq!(mul_wide_u_split(ua, ub), ua as u64 * ub as u64);
            assert_eq!(mul_wide_16_split(a, b as i16), a as i64 * (b as i16) as i64);
        }
    }

    #[test]
    fn split_wide_products_equal_native() {
        let edges = [
            0,
            1,
            -1,
            i64::MAX,
            i64::MIN,
            i64::MIN + 1,
            1 << 32,
            -(1 << 32),
            (1 << 32) - 1,
            i32::MIN as i64,
            u32::MAX as i64,
        ];
        for &a in &edges {
            for &b in &edges {
                assert_eq!(mul_i64_wide_split(a, b), a as i128 * b as i128, "{a} {b}");
            }
        }
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..300_000 {
            let r = xorshift(&mut seed);
            let (a, b) = (
                r as i64 >> (r >> 58),
                xorshift(&mut seed) as i64 >> (r & 63),
            );
            assert_eq!(mul_i64_wide_split(a, b), a as i128 * b as i128, "{a} {b}");
        }
    }

    #[test]
    fn split_shifts_and_divisions_equal_native() {
        let mut seed = 0x7777_1234_9999_abcdu64;
        for _ in 0..300_000 {
            let x = xorshift(&mut seed) as i64;
            let s = (xorshift(&mut seed) % 64) as u32;
            assert_eq!(shr_i64_split(x, s), x >> s, "{x} >> {s}");
            let n = xorshift(&mut seed) as u32 >> (seed % 32);
            let d = (xorshift(&mut seed) as u32 >> (seed % 32)).max(1);
            assert_eq!(div_rem_u32_shift(n, d), (n / d, n % d), "{n} / {d}");
        }
        for (n, d) in [
            (0, 1),
            (u32::MAX, 1),
            (u32::MAX, u32::MAX),
            (1 << 31, 3),
            (7, 1 << 31),
        ] {
            assert_eq!(div_rem_u32_shift(n, d), (n / d, n % d));
        }
    }

    /// The estimate lies within 2 below the exact high word, for the extremes and a
    /// million random factors.
    #[test]
    fn mul_hi_estimate_split_within_two_below() {
        let check = |a: i32, b: i32| {
            let exact = (a as i64 * b as i64) >> 32;
            let e = mul_hi_estimate_split(a, b) as i64;
            assert!((exact - 2..=exact).contains(&e), "{a} {b}: {e} vs {exact}");
        };
        for &a in &EDGES {
            for &b in &EDGES {
                check(a, b);
            }
        }
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..1_000_000 {
            let r = xorshift(&mut seed);
            check(r as i32 >> (r >> 59), (r >> 32) as i32 >> ((r >> 54) & 31));
        }
    }

    #[test]
    fn mul_hi_split_equals_native() {
        let mut seed = 0x7f4a_7c15_9e37_79b9u64;
        for &a in &EDGES {
            for &b in &EDGES {
                assert_eq!(
                    mul_hi_split(a, b),
                    ((a as i64 * b as i64) >> 32) as i32,
                    "{a} {b}"
                );
            }
        }
        for _ in 0..1_000_000 {
            let r = xorshift(&mut seed);
            let (a, b) = (r as i32 >> (r >> 59), (r >> 32) as i32 >> ((r >> 54) & 31));
            assert_eq!(
                mul_hi_split(a, b),
                ((a as i64 * b as i64) >> 32) as i32,
                "{a} {b}"
            );
        }
    }

    /// The seed's residual stays below 2^17 in magnitude over every bucket, and the
    /// refined reciprocal is within 2^-27 of `2^61/m`; the constant-times-reciprocal
    /// product's split form equals the native one.
    #[test]
    fn refined_reciprocal_is_within_bound() {
        let mut worst_e = 0;
        let mut worst = 0f64;
        let mut check = |m: u32| {
            let (r0, e) = recip_seed(m);
            assert!((1 << 15..=1 << 16).contains(&r0), "m {m}: r0 {r0}");
            worst_e = worst_e.max(e.unsigned_abs());
            let want = (1u64 << 61) as f64 / m as f64;
            let got = recip_refined(m) as f64;
            assert!(got > 0.0 && got < want, "m {m}: {got} vs {want}");
            worst = worst.max((got - want).abs() / want);
        };
        for i in 0..256u32 {
            let lo = (256 + i) << 22;
            for m in [lo, lo + 1, lo + (1 << 21), lo + (1 << 22) - 1] {
                check(m);
            }
        }
        let mut seed = 0x0123_4567_89ab_cdefu64;
        for _ in 0..2_000_000 {
            let r = xorshift(&mut seed);
            check((r as u32 >> 1) | (1 << 30));
            let (k, r2) = (((r >> 32) as i32 & 0x7FFF) << 16, (r as i32) & i32::MAX);
            assert_eq!(mul_hi_k_split(k, r2), mul_hi(k, r2), "{k} {r2}");
        }
        assert!(worst_e < 1 << 17, "residual {worst_e}");
        assert!(worst < 2f64.powi(-27), "relative error {worst:e}");
    }

    /// Both forms of the vertex transform's rows give the same bits, for random
    /// matrices at the largest scale the row bounds allow and positions over the
    /// whole range of each mesh bound.
    #[test]
    fn vertex_transform_rows_split_equal_wide() {
        let mut seed = 0x1357_9bdf_2468_ace0u64;
        let mut tested = 0;
        for k in 0..4000 {
            let bound = (xorshift(&mut seed) >> (34 + k % 30)) as i32 + 1; // up to 2^30
            let bound = bound.min((1 << 30) - 1);
            let mut m = Mat4 { m: [[0; 4]; 4] };
            for row in m.m.iter_mut() {
                for e in row.iter_mut() {
                    *e = (xorshift(&mut seed) as i64) >> (20 + xorshift(&mut seed) % 20);
                }
            }
            // The largest scale that fits every row.
            let t = (-40..60)
                .rev()
                .find_map(|sc| VertexTransform::new(&m, sc, bound, 30, None));
            let Some(t) = t else { continue };
            tested += 1;
            for _ in 0..200 {
                let q: Vec3 = core::array::from_fn(|_| {
                    let r = xorshift(&mut seed);
                    Q16_16::from_bits(((r % (2 * bound as u64 + 1)) as i64 - bound as i64) as i32)
                });
                let p = match t.shift {
                    PositionShift::None => t.input::<0>(&q),
                    PositionShift::Left => t.input::<1>(&q),
                    PositionShift::Right => t.input::<2>(&q),
                };
                for r in 0..4 {
                    let (split, wide) = if t.s == 13 {
                        (t.row_split::<13>(r, &p), t.row_wide::<13>(r, &p))
                    } else {
                        (t.row_split::<18>(r, &p), t.row_wide::<18>(r, &p))
                    };
                    assert_eq!(split, wide, "bound {bound} row {r}");
                    // And both are the exact floor.
                    let exact: i128 = (0..3).map(|i| t.m[r][i] as i128 * p[i] as i128).sum();
                    assert_eq!(wide as i128, (exact >> t.s) + t.t[r] as i128);
                    assert_eq!(by_form!(t, xyzw, &q)[r], wide);
                }
            }
        }
        assert!(tested > 3000, "{tested}");
    }

    /// The rows against the exact product of the Q32.32 matrix and the Q16.16
    /// position in clip units: within the bound the type states, 3·2^(P−1−s) + 1.5
    /// clip units (the entries' and `t`'s rounding, the floor), plus for a mesh
    /// rounded to 19 bits half a position step times the row's entries; and the
    /// bound is reached to within a factor of two for both position widths (it is
    /// not vacuous).
    #[test]
    fn vertex_transform_rows_within_the_stated_bound() {
        let mut seed = 0x0f1e_2d3c_4b5a_6978u64;
        let mut worst = [0f64; 2]; // P = 17, P = 19
        for k in 0..3000 {
            let bound = ((xorshift(&mut seed) >> (34 + k % 30)) as i32 + 1).min((1 << 30) - 1);
            let mut m = Mat4 { m: [[0; 4]; 4] };
            for row in m.m.iter_mut() {
                for e in row.iter_mut() {
                    *e = (xorshift(&mut seed) as i64) >> (20 + xorshift(&mut seed) % 20);
                }
            }
            let Some((t, scale)) = (-40..60)
                .rev()
                .find_map(|sc| VertexTransform::new(&m, sc, bound, 30, None).map(|t| (t, sc)))
            else {
                continue;
            };
            let p_bits = if t.s == 13 { 17 } else { 19 };
            for _ in 0..100 {
                let q: Vec3 = core::array::from_fn(|_| {
                    let r = xorshift(&mut seed);
                    Q16_16::from_bits(((r % (2 * bound as u64 + 1)) as i64 - bound as i64) as i32)
                });
                for (r, got) in by_form!(t, xyzw, &q).into_iter().enumerate() {
                    // Σ m·q·2^(scale − 48) + m₃·2^(scale − 32), in f64 from exact i128 sums.
                    let sum: i128 = (0..3)
                        .map(|i| m.m[r][i] as i128 * q[i].to_bits() as i128)
                        .sum::<i128>()
                        + ((m.m[r][3] as i128) << 16);
                    let exact = sum as f64 * 2f64.powi(scale - 48);
                    let rounding = if t.b > 0 {
                        (0..3).map(|i| t.m[r][i].unsigned_abs() as f64).sum::<f64>()
                            / 2f64.powi(t.s as i32 + 1)
                    } else {
                        0.0
                    };
                    let bound = 3.0 * 2f64.powi(p_bits - 1 - t.s as i32) + 1.5 + rounding;
                    let err = (got as f64 - exact).abs();
                    assert!(err <= bound, "row {r}: {err} > {bound}");
                    if t.b == 0 {
                        let w = &mut worst[(p_bits == 19) as usize];
                        *w = w.max(err / bound);
                    }
                }
            }
        }
        std::println!("worst error / bound, P = 17 and 19: {worst:?}");
        assert!(
            worst.iter().all(|w| *w > 0.5),
            "the bound is loose: {worst:?}"
        );
    }

    /// The length within 2^-27 of the exact one; zero for the zero vector.
    #[test]
    fn length_is_within_bound() {
        let mut seed = 0x2222_3333_4444_5555u64;
        let mut worst = 0f64;
        for k in 0..300_000 {
            let mag = (k % 60) as u32 + 1;
            let v: [i64; 3] = core::array::from_fn(|_| (xorshift(&mut seed) as i64) >> (64 - mag));
            let want = v.iter().map(|c| (*c as f64).powi(2)).sum::<f64>().sqrt();
            let got = length(v) as f64;
            if want == 0.0 {
                assert_eq!(got, 0.0);
                continue;
            }
            // Relative error beyond the last unit.
            worst = worst.max(((got - want).abs() - 1.0).max(0.0) / want);
        }
        assert!(worst < 2f64.powi(-27), "{worst:e}");
    }

    #[test]
    fn leading_zeros_search_equals_clz() {
        let mut seed = 0x5555_0123_aaaa_4567u64;
        for k in 0..=32 {
            let x = if k == 32 { 0 } else { 1u32 << k };
            assert_eq!(leading_zeros_search(x), x.leading_zeros());
            assert_eq!(
                leading_zeros_search(x.wrapping_sub(1)),
                x.wrapping_sub(1).leading_zeros()
            );
        }
        for _ in 0..100_000 {
            let x = (xorshift(&mut seed) as u32) >> (seed % 32);
            assert_eq!(leading_zeros_search(x), x.leading_zeros());
        }
    }

    /// The 16-bit-product reciprocal gives the same bits as the wide one: every
    /// seed bucket's ends and middle, a stride through the whole range and random
    /// arguments.
    #[test]
    fn recip_split_equals_wide() {
        let check = |m: u32| assert_eq!(recip_q61_split(m), recip_q61_wide(m), "m {m}");
        for i in 0..256u32 {
            let lo = (256 + i) << 22;
            for m in [lo, lo + 1, lo + (1 << 21), lo + (1 << 22) - 1] {
                check(m);
            }
        }
        let mut m = 1u32 << 30;
        while m < 1 << 31 {
            check(m);
            m += 997;
        }
        let mut seed = 0x3141_5926_5358_9793u64;
        for _ in 0..1_000_000 {
            check((xorshift(&mut seed) as u32 >> 1) | (1 << 30));
        }
    }

    /// The 16-bit reciprocal over its whole range: within 2⁻¹⁵ of 2³¹/m
    /// relatively (the bound the triangle setup's small path takes), below 2¹⁶.
    #[test]
    fn recip_q31_16_is_within_its_bound_everywhere() {
        let mut worst = 0f64;
        for m in 1u32 << 15..1 << 16 {
            let want = (1u64 << 31) as f64 / m as f64;
            let got = recip_q31_16(m);
            assert!(got < 1 << 16, "m {m}: {got}");
            let rel = (got as f64 - want).abs() / want;
            assert!(rel < 1.0 / 32768.0, "m {m}: {got} vs {want}");
            worst = worst.max(rel);
        }
        // The bound is not loose by orders of magnitude: the clamp at m = 2^15
        // alone costs 2^-16.
        assert!(worst > 1.0 / 131072.0, "{worst}");
    }

    #[test]
    fn recip_is_within_two_units() {
        let check = |m: u32| {
            let want = (1u64 << 61) as f64 / m as f64;
            let got = recip_q61(m);
            assert!((got as f64 - want).abs() <= 2.0, "m {m}: {got} vs {want}");
            assert!(got < 1 << 31);
        };
        // Every seed bucket's ends and middle, and random arguments.
        for i in 0..256u32 {
            let lo = (256 + i) << 22;
            for m in [lo, lo + 1, lo + (1 << 21), lo + (1 << 22) - 1] {
                check(m);
            }
        }
        let mut seed = 0x0123_4567_89ab_cdefu64;
        for _ in 0..2_000_000 {
            check((xorshift(&mut seed) as u32 >> 1) | (1 << 30));
        }
    }

    /// The exact normalisation in Q2.30, rounded to nearest: `c·2³⁰/|v|` with the
    /// length from an exact `u128` square root (`|v|` is irrational in general; the
    /// floor of `|v|·2⁴⁰` keeps the error far below one unit).
    fn exact_normalize(v: [i64; 3]) -> [i64; 3] {
        let sq: u128 = v.iter().map(|c| (*c as i128 * *c as i128) as u128).sum();
        // |v|·2^k with k chosen so the root has ~62 significant bits.
        let k = (60 - (128 - sq.leading_zeros() as i32) / 2).max(0) as u32;
        let len = isqrt_u128(sq << (2 * k)) as i128; // |v|·2^k
        v.map(|c| {
            let n = ((c as i128) << (30 + k)) * 2 + len;
            n.div_euclid(2 * len) as i64
        })
    }

    #[test]
    fn normalize_is_within_four_units_of_exact() {
        let mut worst = 0;
        let mut seed = 0x1234_5678_9abc_def0u64;
        for k in 0..400_000 {
            let mag = (k % 62) as u32 + 1;
            let v: [i64; 3] = core::array::from_fn(|_| (xorshift(&mut seed) as i64) >> (64 - mag));
            let Some(got) = normalize_to_q30(v) else {
                assert_eq!(v, [0; 3]);
                continue;
            };
            let want = exact_normalize(v);
            for i in 0..3 {
                worst = worst.max((got[i] as i64 - want[i]).abs());
            }
        }
        // Also the extremes of the seed table.
        for s in [1u64 << 60, (1u64 << 62) - 1, 3 << 59, (65 << 54) - 1] {
            let r = rsqrt_q61(s) as f64;
            let want = (1u64 << 61) as f64 / (s as f64).sqrt();
            assert!((r - want).abs() <= 4.0, "s={s} r={r} want={want}");
        }
        assert!(worst <= 4, "worst {worst}");
    }

    #[test]
    fn normalize_q30_is_unit() {
        for v in [[3i64, 4, 0], [1, 1, 1], [-7, 0, 1 << 40], [0, 0, -1]] {
            let n = normalize_to_q30(v).unwrap();
            let l: f64 = n
                .iter()
                .map(|c| (*c as f64 / (1 << 30) as f64).powi(2))
                .sum();
            assert!((l - 1.0).abs() < 1e-8);
        }
        assert_eq!(normalize_to_q30([0, 0, 0]), None);
    }

    #[test]
    fn isqrt_is_floor() {
        for n in [
            0u128,
            1,
            2,
            3,
            4,
            15,
            16,
            17,
            1 << 100,
            (1 << 100) - 1,
            u64::MAX as u128,
        ] {
            let r = isqrt_u128(n);
            assert!(r * r <= n && (r + 1) * (r + 1) > n);
        }
        for n in [0u64, 1, 5, 1 << 62, u64::MAX] {
            let r = isqrt_u64(n) as u128;
            assert!(r * r <= n as u128 && (r + 1) * (r + 1) > n as u128);
        }
    }
}
