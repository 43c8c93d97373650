//! The `Divide` seam: how the pipeline divides by a small positive integer
//! (seed 002 §2.4, DESIGN.md method 7).
//!
//! The pipeline divides by span widths and edge lengths (`ΔI = (I_R − I_L)/(x_R −
//! x_L)` of the classic span method), all in the 12-bit range `1..=4096`. A variant
//! of [`Divide`] prepares a divisor once ([`Divide::recip`]) and then divides any
//! number of numerators by it ([`Divide::div`]): the three colour channels and the
//! depth of a span share one `recip`.
//!
//! Contract, the same for every variant:
//! - the divisor `k` is clamped into `1..=4096` ([`clamp_k`]: 0 becomes 1, larger
//!   values 4096), so nothing panics;
//! - the numerator is any `i32`; the quotient has the numerator's fixed-point
//!   format (a Q.16 difference gives a Q.16 increment);
//! - the quotient's magnitude is a floor: every variant computes
//!   `sign(n)·⌊|n|·r⌋` for its reciprocal `r`, so [`Exact`] and [`Table`] truncate
//!   toward zero exactly like Rust's `/`, and `div(−n) = −div(n)`;
//! - errors are stated against [`Exact`], in units of the numerator's last bit.
//!
//! ```
//! use fixshade::divide::{Divide, Exact, ShiftAdd, ShiftAddRounded, Table};
//! let n = 255 << 16; // a full-range colour difference, Q.16
//! assert_eq!(Exact::div(n, &Exact::recip(7)), 2_387_382); // 36.4286
//! assert_eq!(Table::div(n, &Table::recip(7)), 2_387_382); // always equal to Exact
//! assert_eq!(ShiftAdd::<6>::div(n, &ShiftAdd::<6>::recip(7)), 2_350_080); // 35.859375
//! assert_eq!(ShiftAddRounded::<8>::div(n, &ShiftAddRounded::<8>::recip(7)), 2_415_360); // 36.8555
//! ```
//!
//! # Variants, costs, and where they pay
//!
//! | variant | `recip` (once per divisor) | `div` (per numerator) | flash | error |
//! | --- | --- | --- | --- | --- |
//! | [`Exact`] | clamp | one unsigned division | – | 0 |
//! | [`Table`] | clamp, table load, count leading zeros | one 32×32→64 multiply, two shifts | 16 384 B | 0 |
//! | [`ShiftAdd<N>`] | one division of `2^N` | `N` conditional adds and `N` shifts | – | see below |
//! | [`ShiftAddRounded<N>`] | one division of `2^(N+1) + k − 1` | the same | – | about half |
//!
//! Instructions, from the release code rustc 1.95 generates for the inlined `div`
//! (sign handling included; the benchmarks and the report measure the real cost):
//! - Cortex-M3/M4/M7 (`thumbv7em`): `Exact` ≈ 7 instructions around one `udiv`,
//!   which takes 2–12 cycles (it stops early on small quotients); `Table` ≈ 9
//!   around one `umull` (1 cycle), `recip` ≈ 10 with `clz`; `ShiftAdd<N>` ≈ 4N + 5,
//!   branch-free (`IT` blocks). Here the hardware divider makes `Exact` about as fast
//!   as anything, `Table` is a little faster and exact, and shift-and-add never pays.
//! - Cortex-M0/M0+ (`thumbv6m`, ARMv6-M: no divide instruction, and `muls` keeps
//!   only the low 32 bits of a product): `Exact` calls `__aeabi_uidiv`, a
//!   shift-subtract loop of roughly 40–100 cycles; `Table` calls `__aeabi_lmul`
//!   (a software 64-bit product built from several `muls`) and `recip` calls
//!   `__clzsi2`; `ShiftAdd<N>` is ≈ 3N + 10 instructions with no call, plus a taken
//!   branch per set bit of the mask. This is where the seed's method pays: no
//!   divider, no wide multiplier. `ShiftAdd::recip` still divides once (a short
//!   `__aeabi_uidiv` of a constant below `2^(N+2)`) per span, shared by its 3–4 numerators,
//!   or it can shift the [`RECIP_TABLE`] entry instead (see [`shift_add_mask`]).
//!
//! # Errors
//!
//! [`Exact`] is the reference. [`Table`] is identical to it for every `i32`
//! numerator and every divisor (proof at [`Table`]).
//!
//! A shift-and-add divider with mask `a` (`1/k ≈ a/2^N`, see [`shift_add_mask`])
//! returns `⌊|n|·a/2^N⌋` exactly; with `c = 2^N − a·k` its error against `⌊|n|/k⌋` is
//! `E = ⌈(|n|·c − r·2^N)/(k·2^N)⌉`, `r = |n| mod k`. Hence:
//! - truncated (`c ≥ 0`): `0 ≤ E ≤ ⌈⌊|n|/k⌋·(2^N mod k)/2^N⌉`, never an
//!   overshoot; over all `k` at most `⌈|n|/2^N⌉`. For `k > 2^N` the mask is 0 and
//!   the whole quotient is lost, so for `N ≤ 11` the worst divisor is `k = 2^N + 1`
//!   and the maximum is `⌊n_max/(2^N + 1)⌋` (for `n_max ≥ 2^23`, checked by the
//!   tests; for small `n_max` another `k` can be one unit worse);
//! - rounded (`|c| ≤ k/2`): `|E| ≤ ⌈|n|/2^(N+1)⌉`, of either sign; for `N ≤ 10` the
//!   maximum is `⌊n_max/2^(N+1)⌋` (at the tie `k = 2^(N+1)`, same proviso).
//!
//! [`ShiftAdd::max_error`] and [`ShiftAddRounded::max_error`] return the exact
//! maximum over `|n| ≤ n_max` and `k ≤ k_max`; the tests check for every `k` in
//! `1..=4096`, with colour numerators `I·2^16` (`I` in `0..=255`) and a sweep of raw
//! numerators over all of `i32`, that no error exceeds it and that it is attained
//! (equal, not merely within one unit).
//!
//! For colour differences up to 255 steps in Q.16 (`n_max = 255·2^16`), in output
//! steps (`E/2^16`). "Max" and "mean" are the error of one increment `ΔI` (the mean
//! over `I` in `0..=255` and every `k ≤ 16`); "end" is the largest `k·E`, the drift of the last
//! pixel of a `k`-pixel span. T = [`ShiftAdd`], R = [`ShiftAddRounded`].
//!
//! | N | T max, k ≤ 16 | R max | T mean | R mean | T end | R end | T max, k ≤ 4096 | R max | T end | R end |
//! | --: | --: | --: | --: | --: | --: | --: | --: | --: | --: | --: |
//! | 4 | 12.3958 | 7.2443 | 2.0378 | 1.4955 | 111.56 | 79.69 | 15.0000 | 7.9688 | 255 | 255 |
//! | 5 | 7.2443 | 3.6779 | 1.2908 | 0.8578 | 79.69 | 47.81 | 7.7273 | 3.9844 | 255 | 255 |
//! | 6 | 3.6779 | 1.7076 | 0.6682 | 0.3496 | 47.81 | 23.91 | 3.9231 | 1.9922 | 255 | 255 |
//! | 7 | 1.6857 | 0.9297 | 0.3569 | 0.2014 | 21.91 | 13.95 | 1.9767 | 0.9961 | 255 | 255 |
//! | 8 | 0.6896 | 0.4427 | 0.1390 | 0.1060 | 8.96 | 3.98 | 0.9922 | 0.4980 | 255 | 255 |
//! | 9 | 0.4427 | 0.2264 | 0.0768 | 0.0507 | 3.98 | 2.99 | 0.4971 | 0.2490 | 255 | 255 |
//! | 10 | 0.1992 | 0.0996 | 0.0379 | 0.0221 | 2.49 | 1.00 | 0.2488 | 0.1245 | 255 | 255 |
//! | 11 | 0.0996 | 0.0581 | 0.0223 | 0.0151 | 1.00 | 0.87 | 0.1245 | 0.0623 | 255 | 255 |
//! | 12 | 0.0415 | 0.0267 | 0.0067 | 0.0054 | 0.50 | 0.37 | 0.0622 | 0.0311 | 127.44 | 84.97 |
//! | 13 | 0.0226 | 0.0125 | 0.0038 | 0.0027 | 0.25 | 0.12 | 0.0311 | 0.0155 | 84.97 | 50.95 |
//! | 14 | 0.0125 | 0.0071 | 0.0024 | 0.0018 | 0.08 | 0.08 | 0.0155 | 0.0078 | 50.95 | 28.28 |
//! | 15 | 0.0071 | 0.0036 | 0.0016 | 0.0008 | 0.08 | 0.05 | 0.0078 | 0.0039 | 28.28 | 15.00 |
//! | 16 | 0.0032 | 0.0016 | 0.0005 | 0.0003 | 0.03 | 0.02 | 0.0039 | 0.0020 | 14.89 | 7.70 |
//!
//! Which is better: the rounded expansion, at every `N`, for the same cost: its
//! maximum error per increment is 0.46–0.64 of the truncated one (0.64 at `N = 8`),
//! its mean 0.49–0.81 (0.76 at `N = 8`), and its span-end drift at most equal.
//! Its price is the sign: it can overshoot (`I_L + k·ΔI` past `I_R`), so a caller
//! that relies on staying inside `[I_L, I_R]` without clamping must use the
//! truncated [`ShiftAdd`]. Both lose everything on spans wider than `2^N` (`2^(N+1)`
//! rounded), and a `k`-pixel span needs roughly `2^N ≥ 255·k` for a drift below
//! one step: for the seed's typical `k ≤ 16` that is `N ≥ 11` truncated, `N ≥ 10`
//! rounded.
//!
//! # In the pipeline
//!
//! The pipeline divides in three places, each generic over `D`, chosen once per
//! draw: the `classic` span method's per-span division
//! ([`crate::raster::span::Classic`]`<D>`), the triangle setup's reciprocal of the
//! determinant ([`crate::raster::span::WithDivide`]`<S, D>` around any span method),
//! and Schlick's denominators ([`crate::specular::Schlick`]`<D>`,
//! [`crate::specular::SchlickModified`]`<D>`). Perspective division does not exist
//! yet. Their divisors are wide (a span width in units of `1/(d_L·d_R)` pixel, up
//! to 2⁵⁶; a determinant up to 2³⁵; a Q.30 denominator up to 2⁴¹), so they reach
//! the seam through [`wide_recip`]: a mantissa of `b` bits, one `recip`/`div` of
//! `2³⁰`, then multiplies.
//!
//! The default `D` is [`Exact`], and [`Divide::is_exact`] keeps each stage's own
//! full-precision division then (`classic`'s two Q.40 divisions of the rational
//! width, the setup's `⌊2⁶²/|det|⌋`, Schlick's rounded 64-bit quotient): the
//! default pipeline renders bit-identically to the pipeline before the seam. Every
//! other variant, [`Table`] included, pays the mantissa's rounding (`2^(1−b)`
//! relative, `2⁻¹¹` for `b = 12`) on top of its own error, so `table` in the
//! pipeline is not bit-identical to `exact` even though the two agree on every
//! `n / k` of the seam.
//!
//! # The seed's figures
//!
//! Seed 002 gives, for `k = 7` and `N = 6`, `255·(1/8 + 1/64) = 35.8594` against
//! `255/7 = 36.4286` (error 0.5692, 1.56 %); [`ShiftAdd<6>`] reproduces it exactly
//! (`2 350 080 = 35.859375·2^16`). For `N = 8` it states a maximum absolute error of
//! 0.4427 and a mean relative error of 0.81 %. The population that reproduces these
//! is the seed's own setting: numerator `I_b − I_a = 255` (its worst case in
//! TrueColor) and span lengths `k = 2..=16` (it says spans rarely exceed 16 pixels),
//! **but with the expansion rounded to nearest at bit 8** ([`ShiftAddRounded<8>`]):
//! 0.4427 at `k = 9` and 0.8073 %. The truncated expansion that its formula (2.18)
//! and its `k = 7` example use gives 0.6896 (at `k = 13`) and 1.0677 % instead. The
//! tests reproduce both in `f64` and through the integer dividers.

/// The largest divisor the seam supports: the 12-bit span/edge range of the seeds.
pub const K_MAX: u32 = 4096;

/// Clamps a divisor into `1..=K_MAX`, the range every [`Divide`] variant accepts.
///
/// `0` becomes `1` (a zero divisor never reaches the seam from the pipeline, which
/// divides only non-empty spans and non-zero determinants; clamping keeps a stray
/// one from panicking), and anything above [`K_MAX`] becomes `K_MAX`.
///
/// ```
/// use fixshade::divide::{clamp_k, K_MAX};
/// assert_eq!(clamp_k(0), 1);
/// assert_eq!(clamp_k(7), 7);
/// assert_eq!(clamp_k(100_000), K_MAX);
/// ```
pub const fn clamp_k(k: u32) -> u32 {
    if k == 0 {
        1
    } else if k > K_MAX {
        K_MAX
    } else {
        k
    }
}

/// Division of a signed numerator by a prepared small divisor.
///
/// Every variant computes `n / k` for a divisor `k` in `1..=K_MAX` (others are
/// clamped by [`clamp_k`]) and a numerator `n` anywhere in `i32` (`|n| ≤ 2³¹`). The
/// quotient has the same fixed-point format as `n` (a Q.16 difference gives a Q.16
/// increment). All variants are sign-symmetric, `div(−n) = −div(n)`, and never panic.
///
/// ```
/// use fixshade::divide::{Divide, Exact, ShiftAdd, Table};
/// fn increment<D: Divide>(i_l: i32, i_r: i32, width: u32) -> i32 {
///     let r = D::recip(width); // once per span
///     D::div(i_r - i_l, &r)
/// }
/// let (l, r) = (10 << 16, 255 << 16); // Q.16 channel values
/// assert_eq!(increment::<Exact>(l, r, 7), (245 << 16) / 7);
/// assert_eq!(increment::<Table>(l, r, 7), (245 << 16) / 7);
/// assert!(increment::<ShiftAdd<8>>(l, r, 7) <= (245 << 16) / 7);
/// ```
pub trait Divide {
    /// Name used by the CLI and scene files: `exact`, `table`, `shift-add-N`,
    /// `shift-add-rounded-N`.
    const NAME: &'static str;
    /// Per-divisor data, computed once when the divisor is known (a span width, a
    /// determinant).
    type Recip: Copy;
    /// Prepares division by `k`, clamped into `1..=K_MAX` by [`clamp_k`].
    fn recip(k: u32) -> Self::Recip;
    /// `n / k` for the prepared divisor, in the format of `n`; see the variant for
    /// its rounding and error.
    fn div(n: i32, r: &Self::Recip) -> i32;
    /// The largest `|div(n, recip(k)) − Exact::div(n, recip(k))|` over all `|n| ≤
    /// n_max` and `1 ≤ k ≤ k_max` (`k_max` clamped by [`clamp_k`]), in units of the
    /// last bit of `n`. This is the exact maximum, attained by some `(n, k)`.
    fn max_error(n_max: u32, k_max: u32) -> u32;
    /// True only for [`Exact`]: a pipeline stage with a full-precision division of
    /// its own (the classic span's rational width, the setup's `2⁶²/|det|`,
    /// Schlick's Q.30 denominator) keeps it, so the default renders bit-identically
    /// to the pipeline before the seam. Every other variant goes through
    /// [`wide_recip`]. The stages ask [`Divide::is_exact`], which is this constant
    /// for every divider of the core.
    const EXACT: bool = false;
    /// True if this divider divides as [`Exact`] does: [`Divide::EXACT`] for the
    /// core's variants (the compiler removes the test), and for a divider chosen
    /// at run time (the simulator's) whether the chosen one is `Exact`. Every stage
    /// that keeps its own full-precision division asks this, so a run-time divider
    /// set to `Exact` draws bit-identically to `Exact`.
    ///
    /// ```
    /// use fixshade::divide::{Divide, Exact, Table};
    /// assert!(Exact::is_exact() && !Table::is_exact());
    /// ```
    #[inline(always)]
    fn is_exact() -> bool {
        Self::EXACT
    }
    /// Mantissa bits `b` (clamped to `1..=12`) of a wide divisor in [`wide_recip`]: the divisor is
    /// rounded up to `b` significant bits before [`Divide::recip`] sees it. 12 (the
    /// seam's `1..=4096`) by default; the shift-and-add variants take
    /// `⌊(N + 1)/2⌋`, which balances the mantissa's rounding (`2^−b` relative)
    /// against the expansion's (`2^(b−N)`).
    fn mantissa_bits() -> u32 {
        12
    }
}

/// A reciprocal of a wide divisor `d` taken through the seam:
/// `1/d ≈ r / 2^(30 + shift)`. See [`wide_recip`].
///
/// ```
/// use fixshade::divide::{wide_recip, Table};
/// // 1/1000 through the table: r/2^(30 + shift) with r = ⌊2^30/1000⌋, shift 0.
/// let w = wide_recip::<Table>(1000);
/// assert_eq!(w.shift, 0);
/// assert_eq!(w.scaled(40), (1u128 << 40) / 1000 / 1024 * 1024);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct WideRecip {
    /// `≈ 2³⁰/k` (never above) for the mantissa `k` of `d`, in `1..=2³⁰`.
    pub r: u32,
    /// `d ≤ k·2^shift`.
    pub shift: u32,
}

impl WideRecip {
    /// `≈ 2^p / d`, at least 1: `r·2^(p − 30 − shift)`, truncated when the shift is
    /// to the right. `r ≤ 2³⁰`, so the result is below `2^p` and fits `u128` for
    /// `p ≤ 127`.
    ///
    /// ```
    /// use fixshade::divide::{wide_recip, Table};
    /// assert_eq!(wide_recip::<Table>(1 << 20).scaled(62), 1 << 42);
    /// ```
    #[inline]
    pub fn scaled(&self, p: u32) -> u128 {
        let r = self.r as u128;
        let q = if p >= 30 + self.shift {
            r << (p - 30 - self.shift)
        } else {
            r >> (30 + self.shift - p)
        };
        q.max(1)
    }
}

/// The reciprocal of a wide divisor `d ≥ 1` (a span width in sub-pixel units, a
/// triangle's determinant, Schlick's denominator) through `D`: `d` is rounded up to
/// a mantissa `k` of [`Divide::mantissa_bits`] bits and a shift, `d ≤ k·2^shift`
/// (`d` itself when it is that short), and `r = D::div(2³⁰, D::recip(k))`, cut
/// back to at most `2³⁰/k` if `D` over-estimates (the rounded expansion does for
/// some `k`). Then `1/d ≈ r / 2^(30 + shift)`: one division on the seam per wide
/// divisor, and multiplies by `r` for every numerator.
///
/// The result **never over-estimates** `1/d`, so an interpolation `I_0 + ρ·(I_1 −
/// I_0)·x` with `x·(1/d) ≤ 1` stays between `I_0` and `I_1`: the pipeline needs
/// no clamping. Error, relative, at most `η = 2^(1−b) + (2E + 2)·2^b/2³⁰`: the
/// mantissa is off by less than one unit in its last bit against `k ≥ 2^(b−1)`,
/// and `r` by at most `2E + 2` units with `E = D::max_error(2³⁰, 2^b)` (the floor
/// of the exact quotient, and the cut-back). `d = 0` is treated as 1.
///
/// ```
/// use fixshade::divide::{wide_recip, ShiftAdd, Table};
/// let w = wide_recip::<Table>(3 << 20); // 3·2^20 = 3072·2^10
/// assert_eq!((w.r, w.shift), ((1 << 30) / 3072, 10));
/// let w = wide_recip::<Table>(7); // short: exact mantissa
/// assert_eq!((w.r, w.shift), ((1 << 30) / 7, 0));
/// let w = wide_recip::<ShiftAdd<8>>(1000); // 4-bit mantissa: 1000 ≤ 16·2^6
/// assert_eq!((w.r, w.shift), ((1 << 30) / 16, 6));
/// ```
#[inline]
pub fn wide_recip<D: Divide>(d: u128) -> WideRecip {
    let b = D::mantissa_bits().clamp(1, 12);
    let d = if d == 0 { 1 } else { d };
    let bits = 128 - d.leading_zeros();
    let (k, shift) = if bits <= b {
        (d as u32, 0)
    } else {
        let s = bits - b;
        // Rounded up: (d − 1) >> s < 2^b, so k ≤ 2^b ≤ 4096.
        ((((d - 1) >> s) + 1) as u32, s)
    };
    // 2^30 fits i32; every variant's quotient of a positive numerator is in
    // [0, 2^30].
    let mut r = D::div(1 << 30, &D::recip(k)).max(1) as u64;
    // k·r ≤ 2^12·2^30. An excess over 2^30 is removed with a shift by ⌊log₂ k⌋,
    // which removes at least excess/k (at most twice that, plus one).
    let excess = (k as u64 * r).saturating_sub(1 << 30);
    if excess > 0 {
        r = r
            .saturating_sub((excess >> (31 - k.leading_zeros())) + 1)
            .max(1);
    }
    WideRecip { r: r as u32, shift }
}

/// Applies the sign of `n` to the magnitude `q ≤ 2³¹` (`q = 2³¹` only for
/// `n = i32::MIN`, where the wrapping negation gives `i32::MIN` back).
#[inline(always)]
const fn with_sign(n: i32, q: u32) -> i32 {
    let s = n >> 31; // 0 or −1
    ((q as i32) ^ s).wrapping_sub(s)
}

/// Plain integer division, truncated toward zero: the reference every other
/// variant is measured against.
///
/// `Recip` is the clamped divisor itself. Cost: one `udiv` (Cortex-M3/M4/M7: 2–12
/// cycles, early-terminating on small quotients); on Cortex-M0/M0+ (ARMv6-M, no
/// divide instruction) a call to `__aeabi_uidiv`, a shift-subtract loop of roughly
/// 40–100 cycles.
///
/// ```
/// use fixshade::divide::{Divide, Exact};
/// let r = Exact::recip(7);
/// assert_eq!(Exact::div(255 << 16, &r), (255 << 16) / 7);
/// assert_eq!(Exact::div(-100, &r), -14); // toward zero, like `/`
/// assert_eq!(Exact::div(i32::MIN, &Exact::recip(1)), i32::MIN);
/// assert_eq!(Exact::recip(0), 1); // clamped
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Exact;

impl Exact {
    /// Always 0: this is the reference.
    ///
    /// ```
    /// # use fixshade::divide::Exact;
    /// assert_eq!(Exact::max_error(255 << 16, 4096), 0);
    /// ```
    pub const fn max_error(_n_max: u32, _k_max: u32) -> u32 {
        0
    }
}

impl Divide for Exact {
    const NAME: &'static str = "exact";
    const EXACT: bool = true;
    type Recip = u32;
    #[inline]
    fn recip(k: u32) -> u32 {
        clamp_k(k)
    }
    #[inline]
    fn div(n: i32, r: &u32) -> i32 {
        // `max(1)`: a hand-made zero divisor must not panic (and it lets the
        // compiler drop the zero check). Unsigned: no i32::MIN / −1 case.
        with_sign(n, n.unsigned_abs() / (*r).max(1))
    }
    fn max_error(n_max: u32, k_max: u32) -> u32 {
        Exact::max_error(n_max, k_max)
    }
}

/// `⌈log₂ k⌉` for `k ≥ 1` (0 for `k = 1`).
const fn ceil_log2(k: u32) -> u32 {
    32 - (k - 1).leading_zeros()
}

/// Builds [`RECIP_TABLE`]: entry `k − 1` is `⌈2^(31 + ⌈log₂ k⌉) / k⌉`.
const fn build_table() -> [u32; K_MAX as usize] {
    let mut t = [0u32; K_MAX as usize];
    let mut k = 1u32;
    while k <= K_MAX {
        let s = 31 + ceil_log2(k); // ≤ 43
        let num = 1u64 << s;
        let m = num.div_ceil(k as u64); // in [2^31, 2^32): see RECIP_TABLE
        t[(k - 1) as usize] = m as u32;
        k += 1;
    }
    t
}

/// The reciprocal table of [`Table`]: entry `k − 1` (for `k` in `1..=4096`) is
/// `m_k = ⌈2^s_k / k⌉` with `s_k = 31 + ⌈log₂ k⌉`, a normalised 32-bit reciprocal
/// (`2³¹ ≤ m_k < 2³²`, the top bit always set).
///
/// 4096 entries × 4 bytes = **16 384 bytes**, a `static` in flash (`.rodata`),
/// built by a `const fn` at compile time and linked only into programs that use
/// [`Table`]. The shift `s_k` is not stored; [`Table::recip`] derives it from `k`.
///
/// ```
/// use fixshade::divide::RECIP_TABLE;
/// assert_eq!(core::mem::size_of_val(&RECIP_TABLE), 16_384);
/// assert_eq!(RECIP_TABLE[0], 1 << 31); // k = 1: 2^31 / 1
/// assert_eq!(RECIP_TABLE[6], 0x9249_2493); // k = 7: ⌈2^34 / 7⌉
/// assert_eq!(RECIP_TABLE[4095], 1 << 31); // k = 4096: 2^43 / 2^12
/// ```
pub static RECIP_TABLE: [u32; K_MAX as usize] = build_table();

/// Prepared divisor of [`Table`]: the table entry and its shift.
///
/// ```
/// use fixshade::divide::{Divide, Table, TableRecip};
/// // Prepared once per divisor, used for every numerator of a span.
/// let r: TableRecip = Table::recip(7);
/// assert_eq!(Table::div(255, &r), 36);
/// assert_eq!(Table::div(-255, &r), -36);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct TableRecip {
    /// `m_k`, the table entry.
    m: u32,
    /// `⌈log₂ k⌉`, in `0..=12`; the full shift is `31 + c`.
    c: u32,
}

/// Division by one multiply with a reciprocal from [`RECIP_TABLE`]; the result is
/// **identical to [`Exact`]** (truncated toward zero) for every `i32` numerator
/// and every `k` in `1..=4096`.
///
/// `recip(k)` reads `m_k` and computes `c = ⌈log₂ k⌉`; `div` computes
/// `sign(n)·(((|n|·m_k) >> 31) >> c)`: one 32×32→64 multiply (`umull` on
/// Cortex-M3/M4/M7; on ARMv6-M the compiler's `__aeabi_lmul`, several `muls`) and
/// two shifts.
///
/// Proof of exactness. Let `s = 31 + c`, `m = ⌈2^s/k⌉` and `e = m·k − 2^s`, so
/// `0 ≤ e ≤ k − 1 < 2^c`. For `0 ≤ n ≤ 2³¹` write `n = q·k + r` with `0 ≤ r < k`:
/// `n·m / 2^s = q + (r + n·e/2^s) / k`, and `n·e ≤ 2³¹·(k − 1) < 2^(31 + c) = 2^s`,
/// so `r + n·e/2^s < r + 1 ≤ k` and the floor is exactly `q`. The product is below
/// `2³¹·2³² = 2⁶³`, and `(n·m) >> 31 < 2³²` fits a `u32`. The tests check every `k`
/// against the worst numerators (the top of the range, `r = k − 1`).
///
/// ```
/// use fixshade::divide::{Divide, Table};
/// let r = Table::recip(7);
/// assert_eq!(Table::div(255 << 16, &r), (255 << 16) / 7);
/// assert_eq!(Table::div(i32::MAX, &r), i32::MAX / 7);
/// assert_eq!(Table::div(i32::MIN, &r), i32::MIN / 7);
/// assert_eq!(Table::div(-100, &r), -14);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Table;

impl Table {
    /// Always 0: the table is exact for every `i32` numerator (proof above).
    ///
    /// ```
    /// # use fixshade::divide::Table;
    /// assert_eq!(Table::max_error(u32::MAX, 4096), 0);
    /// ```
    pub const fn max_error(_n_max: u32, _k_max: u32) -> u32 {
        0
    }
}

impl Divide for Table {
    const NAME: &'static str = "table";
    type Recip = TableRecip;
    #[inline]
    fn recip(k: u32) -> TableRecip {
        let k = clamp_k(k);
        TableRecip {
            // k − 1 is in 0..4096; the mask only spares the compiler a bounds check.
            m: RECIP_TABLE[((k - 1) & (K_MAX - 1)) as usize],
            c: ceil_log2(k),
        }
    }
    #[inline]
    fn div(n: i32, r: &TableRecip) -> i32 {
        // |n| ≤ 2^31, m < 2^32: the product is below 2^63; `>> 31` leaves < 2^32.
        let p = n.unsigned_abs() as u64 * r.m as u64;
        with_sign(n, ((p >> 31) as u32) >> r.c)
    }
    fn max_error(n_max: u32, k_max: u32) -> u32 {
        Table::max_error(n_max, k_max)
    }
}

/// The smallest number of terms [`ShiftAdd`] and [`ShiftAddRounded`] accept.
pub const SHIFT_ADD_MIN_N: u32 = 4;
/// The largest number of terms [`ShiftAdd`] and [`ShiftAddRounded`] accept.
pub const SHIFT_ADD_MAX_N: u32 = 16;

const SHIFT_ADD_NAMES: [&str; 17] = [
    "",
    "",
    "",
    "",
    "shift-add-4",
    "shift-add-5",
    "shift-add-6",
    "shift-add-7",
    "shift-add-8",
    "shift-add-9",
    "shift-add-10",
    "shift-add-11",
    "shift-add-12",
    "shift-add-13",
    "shift-add-14",
    "shift-add-15",
    "shift-add-16",
];

const SHIFT_ADD_ROUNDED_NAMES: [&str; 17] = [
    "",
    "",
    "",
    "",
    "shift-add-rounded-4",
    "shift-add-rounded-5",
    "shift-add-rounded-6",
    "shift-add-rounded-7",
    "shift-add-rounded-8",
    "shift-add-rounded-9",
    "shift-add-rounded-10",
    "shift-add-rounded-11",
    "shift-add-rounded-12",
    "shift-add-rounded-13",
    "shift-add-rounded-14",
    "shift-add-rounded-15",
    "shift-add-rounded-16",
];

/// The shift-and-add mask of `1/k` with `N = n_bits` terms: the integer `a` with
/// `1/k ≈ a / 2^N`, bit `N − j` of `a` being the seed's `i_j`.
///
/// `rounded = false`: the truncated binary expansion, `a = ⌊2^N / k⌋`.
/// `rounded = true`: rounded to nearest at bit `N`, `a = ⌊2^N/k + ½⌋`, except that
/// the one exact tie (`k = 2^(N+1)`, `2^N/k = ½`) rounds down to 0.
///
/// `k` is clamped by [`clamp_k`] and `n_bits` to at most 30. For `k = 1` both give
/// `a = 2^N`: bit `N` is a `j = 0` term of weight 1 that the seed's sum (which
/// starts at `j = 1`) lacks, so division by 1 is exact instead of a multiplication
/// by `0.11…1₂ = 1 − 2^−N`. Every power of two `k ≤ 2^N` has the single bit `2^N/k`
/// and divides exactly. For `k > 2^N` the truncated expansion is all zeros (the
/// quotient is 0); the rounded one is `1` (`2^−N`) for `2^N < k < 2^(N+1)` and all
/// zeros from `k = 2^(N+1)` on.
///
/// Cost: one division of a constant of at most `N + 2` bits (`udiv` on M3/M4/M7,
/// a short `__aeabi_uidiv` on M0+), once per divisor. The same mask is a shift of
/// the table entry, `⌊2^N/k⌋ = RECIP_TABLE[k − 1] >> (31 + ⌈log₂ k⌉ − N)` (exact by
/// the [`Table`] theorem with `n = 2^N`), for a program that links the table anyway.
///
/// ```
/// use fixshade::divide::shift_add_mask;
/// assert_eq!(shift_add_mask(7, 6, false), 0b001001); // 1/7 ≈ 1/8 + 1/64
/// assert_eq!(shift_add_mask(6, 8, false), 42); // 0.0010_1010
/// assert_eq!(shift_add_mask(6, 8, true), 43); // 0.0010_1011
/// assert_eq!(shift_add_mask(1, 8, false), 256); // weight-1 bit: exact
/// assert_eq!(shift_add_mask(300, 8, false), 0);
/// assert_eq!(shift_add_mask(300, 8, true), 1);
/// assert_eq!(shift_add_mask(512, 8, true), 0); // the tie
/// ```
pub const fn shift_add_mask(k: u32, n_bits: u32, rounded: bool) -> u32 {
    let k = clamp_k(k); // ≤ 2^12
    let n_bits = if n_bits > 30 { 30 } else { n_bits };
    let one = 1u32 << n_bits; // ≤ 2^30
    if rounded {
        (2 * one + k - 1) / (2 * k) // 2^31 + 2^12 < 2^32
    } else {
        one / k
    }
}

/// `sign(n)·⌊|n|·mask / 2^N⌋` by `N` conditional adds and `N` one-bit shifts, plus
/// the weight-1 bit `N` (set only for `k = 1`).
///
/// The terms are taken lightest first (Horner's rule, shifting the accumulator):
/// `acc ← (acc + i_j·|n|) >> 1` for `j = N, N − 1, …, 1`. Nested floors of halvings
/// equal one floor (`⌊(⌊x/2⌋ + a)/2⌋ = ⌊(x + 2a)/4⌋` for integer `a`), so no bit is
/// lost before it can carry and the result is the exact floor of `|n|·mask/2^N`.
/// Shifting the numerator instead (the seed's device, Fig. 2.13) truncates every
/// term separately and loses up to one unit more per set bit.
#[inline(always)]
fn shift_add<const N: u32>(n: i32, mask: u32) -> i32 {
    let mag = n.unsigned_abs(); // ≤ 2^31
    let mut acc: u32 = 0;
    for j in 0..N {
        // Invariant acc ≤ mag − 1 (or acc = mag = 0), so acc + mag ≤ 2^32 − 1.
        if (mask >> j) & 1 != 0 {
            acc += mag;
        }
        acc >>= 1;
    }
    if (mask >> N) & 1 != 0 {
        // Only k = 1 (mask = 2^N, acc = 0 here). A hand-made mask with more bits
        // would wrap instead of panicking.
        acc = acc.wrapping_add(mag);
    }
    with_sign(n, acc)
}

/// The exact maximum of `|⌊n/k⌋ − ⌊n·a/2^N⌋|` over `0 ≤ n ≤ n_max`, for one `k`
/// and one mask `a`.
///
/// With `c = 2^N − a·k` and `n = q·k + r`, the error is `E = ⌈(n·c − r·2^N)/(k·2^N)⌉`.
/// For `c ≥ 0` (an under-estimate of `1/k`) `E ≥ 0` and it falls as `r` grows, so
/// its maximum is at `r = 0`, `n = ⌊n_max/k⌋·k`: `E = ⌈⌊n_max/k⌋·c / 2^N⌉`.
/// For `c < 0` (an over-estimate) `E ≤ 0` with `|E| = ⌊(n·|c| + r·2^N)/(k·2^N)⌋`,
/// growing with `r`: the maximum is at the end of a residue block, `n = n_max` or
/// `n = ⌊n_max/k⌋·k − 1`.
const fn mask_max_error(a: u32, k: u32, n_bits: u32, n_max: u32) -> u32 {
    let one = 1i64 << n_bits; // ≤ 2^16
    let k = k as i64; // ≤ 2^12
    let c = one - a as i64 * k; // |c| ≤ 2^16 · 2^12
    let n_max = n_max as i64; // < 2^32
    let q_max = n_max / k;
    if c >= 0 {
        // q_max·c < 2^32 · 2^16 = 2^48.
        ((q_max * c + one - 1) / one) as u32
    } else {
        let d = -c;
        let den = k * one; // ≤ 2^28
                           // n·d < 2^32 · 2^28 = 2^60; r·2^N < 2^28.
        let at_end = (n_max * d + (n_max % k) * one) / den;
        let at_block = if q_max >= 1 {
            let n = q_max * k - 1;
            (n * d + (k - 1) * one) / den
        } else {
            0
        };
        let e = if at_end > at_block { at_end } else { at_block };
        e as u32
    }
}

/// [`Divide::max_error`] of a shift-and-add divider: the maximum of
/// [`mask_max_error`] over `k` in `1..=k_max`.
const fn shift_add_max_error(n_bits: u32, rounded: bool, n_max: u32, k_max: u32) -> u32 {
    let k_max = clamp_k(k_max);
    let mut worst = 0;
    let mut k = 1;
    while k <= k_max {
        let e = mask_max_error(shift_add_mask(k, n_bits, rounded), k, n_bits, n_max);
        if e > worst {
            worst = e;
        }
        k += 1;
    }
    worst
}

/// Shift-and-add division with `N` terms of the **truncated** binary expansion of
/// `1/k` (seed 002 §2.4, formula (2.18)), `N` in `4..=16`.
///
/// `recip(k)` is the mask [`shift_add_mask`]`(k, N, false)` = `⌊2^N/k⌋`; `div`
/// returns `sign(n)·⌊|n|·mask / 2^N⌋` by `N` conditional adds and `N` one-bit
/// shifts. The terms are taken lightest first (Horner's rule on the accumulator,
/// `acc ← (acc + i_j·|n|) >> 1` for `j = N, …, 1`), so no bit is lost before it can
/// carry and the result is exactly that floor; the seed's device (Fig. 2.13), which
/// shifts the numerator and adds the shifted copies, truncates every term and can be
/// one unit worse per set bit, at the same cost.
///
/// The quotient never exceeds the exact one in magnitude:
/// `0 ≤ |Exact| − |ShiftAdd| ≤ ⌈⌊|n|/k⌋·(2^N mod k) / 2^N⌉` (for `k > 2^N` that is
/// `⌊|n|/k⌋`: everything is lost), which [`ShiftAdd::max_error`] maximises.
///
/// ```
/// use fixshade::divide::{Divide, ShiftAdd};
/// // The seed's example: 255 / 7 with N = 6 is 255·(1/8 + 1/64) = 35.859375.
/// let r = ShiftAdd::<6>::recip(7);
/// assert_eq!(r, 0b001001);
/// assert_eq!(ShiftAdd::<6>::div(255 << 16, &r), 2_350_080); // 35.859375 · 2^16
/// assert_eq!(ShiftAdd::<8>::div(-(255 << 16), &ShiftAdd::<8>::recip(4)), -(255 << 14));
/// assert_eq!(ShiftAdd::<8>::NAME, "shift-add-8");
/// ```
///
/// `N` outside `4..=16` is a compile-time error:
///
/// ```compile_fail
/// use fixshade::divide::{Divide, ShiftAdd};
/// let _ = ShiftAdd::<3>::recip(5);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct ShiftAdd<const N: u32>;

/// Shift-and-add division with `N` terms of the expansion of `1/k` **rounded to
/// nearest** at bit `N` (ties, only `k = 2^(N+1)`, down), `N` in `4..=16`.
///
/// The same `N` adds and shifts as [`ShiftAdd`], with the mask
/// [`shift_add_mask`]`(k, N, true)`. The reciprocal error is at most half as large
/// (`|1/k − a/2^N| ≤ 2^−(N+1)` against `< 2^−N`), but it has either sign: the
/// quotient can exceed the exact one, so an interpolation `I_L + i·ΔI` can overshoot
/// `I_R` at the end of a span and the caller must clamp. [`ShiftAdd`] never
/// overshoots.
///
/// ```
/// use fixshade::divide::{Divide, Exact, ShiftAddRounded};
/// let r = ShiftAddRounded::<8>::recip(6);
/// assert_eq!(r, 43); // 43/256 = 0.16797 > 1/6
/// let q = ShiftAddRounded::<8>::div(255 << 16, &r);
/// assert!(q > Exact::div(255 << 16, &6)); // an over-estimate
/// assert_eq!(ShiftAddRounded::<8>::NAME, "shift-add-rounded-8");
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct ShiftAddRounded<const N: u32>;

impl<const N: u32> ShiftAdd<N> {
    /// Compile-time check of `N`.
    const VALID_N: () = assert!(
        N >= SHIFT_ADD_MIN_N && N <= SHIFT_ADD_MAX_N,
        "ShiftAdd<N> needs N in 4..=16"
    );

    /// The exact maximum error against [`Exact`] over `|n| ≤ n_max`,
    /// `1 ≤ k ≤ k_max`, in units of the last bit of `n` (see the module docs for
    /// the table of values).
    ///
    /// ```
    /// # use fixshade::divide::ShiftAdd;
    /// // Q.16 colour differences up to 255, spans up to 16 pixels:
    /// assert_eq!(ShiftAdd::<8>::max_error(255 << 16, 16), 45_194); // 0.6896 steps
    /// ```
    pub const fn max_error(n_max: u32, k_max: u32) -> u32 {
        shift_add_max_error(N, false, n_max, k_max)
    }
}

impl<const N: u32> ShiftAddRounded<N> {
    /// Compile-time check of `N`.
    const VALID_N: () = assert!(
        N >= SHIFT_ADD_MIN_N && N <= SHIFT_ADD_MAX_N,
        "ShiftAddRounded<N> needs N in 4..=16"
    );

    /// The exact maximum error against [`Exact`] over `|n| ≤ n_max`,
    /// `1 ≤ k ≤ k_max`, in units of the last bit of `n`.
    ///
    /// ```
    /// # use fixshade::divide::ShiftAddRounded;
    /// assert_eq!(ShiftAddRounded::<8>::max_error(255 << 16, 16), 29_014); // 0.4427 steps
    /// ```
    pub const fn max_error(n_max: u32, k_max: u32) -> u32 {
        shift_add_max_error(N, true, n_max, k_max)
    }
}

impl<const N: u32> Divide for ShiftAdd<N> {
    const NAME: &'static str = {
        let () = Self::VALID_N;
        SHIFT_ADD_NAMES[N as usize]
    };
    fn mantissa_bits() -> u32 {
        N.div_ceil(2)
    }
    type Recip = u32;
    #[inline]
    fn recip(k: u32) -> u32 {
        let () = Self::VALID_N;
        shift_add_mask(k, N, false)
    }
    #[inline]
    fn div(n: i32, r: &u32) -> i32 {
        let () = Self::VALID_N;
        shift_add::<N>(n, *r)
    }
    fn max_error(n_max: u32, k_max: u32) -> u32 {
        ShiftAdd::<N>::max_error(n_max, k_max)
    }
}

impl<const N: u32> Divide for ShiftAddRounded<N> {
    const NAME: &'static str = {
        let () = Self::VALID_N;
        SHIFT_ADD_ROUNDED_NAMES[N as usize]
    };
    fn mantissa_bits() -> u32 {
        N.div_ceil(2)
    }
    type Recip = u32;
    #[inline]
    fn recip(k: u32) -> u32 {
        let () = Self::VALID_N;
        shift_add_mask(k, N, true)
    }
    #[inline]
    fn div(n: i32, r: &u32) -> i32 {
        let () = Self::VALID_N;
        shift_add::<N>(n, *r)
    }
    fn max_error(n_max: u32, k_max: u32) -> u32 {
        ShiftAddRounded::<N>::max_error(n_max, k_max)
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)] // f64 reference figures, host only
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    /// Q.16 full colour swing: 255 channel steps.
    const COLOUR_MAX: u32 = 255 << 16;

    /// `shift_add::<N>` for a run-time `N`.
    fn sa(n_bits: u32, n: i32, mask: u32) -> i32 {
        match n_bits {
            4 => shift_add::<4>(n, mask),
            5 => shift_add::<5>(n, mask),
            6 => shift_add::<6>(n, mask),
            7 => shift_add::<7>(n, mask),
            8 => shift_add::<8>(n, mask),
            9 => shift_add::<9>(n, mask),
            10 => shift_add::<10>(n, mask),
            11 => shift_add::<11>(n, mask),
            12 => shift_add::<12>(n, mask),
            13 => shift_add::<13>(n, mask),
            14 => shift_add::<14>(n, mask),
            15 => shift_add::<15>(n, mask),
            16 => shift_add::<16>(n, mask),
            _ => unreachable!(),
        }
    }

    fn exact(n: i32, k: u32) -> i32 {
        (n as i64 / k as i64) as i32
    }

    /// Colour numerators (`±I·2^16`) and a sweep of raw numerators over all of `i32`.
    fn numerators() -> Vec<i32> {
        let mut v: Vec<i32> = (0..=255).map(|i| i << 16).collect();
        v.extend((0..=255).map(|i: i32| -(i << 16)));
        let mut x: u32 = 1;
        for _ in 0..200 {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223); // LCG sweep
            v.push(x as i32);
        }
        v.extend([
            0,
            1,
            -1,
            2,
            255,
            -255,
            65_535,
            65_536,
            (1 << 24) - 1,
            1 << 24,
            (1 << 30) - 1,
            1 << 30,
            i32::MAX,
            i32::MAX - 1,
            i32::MIN,
            i32::MIN + 1,
        ]);
        v
    }

    /// The numerators at which [`mask_max_error`] says the maximum is attained.
    fn worst_numerators(k: u32, n_max: u32) -> [u32; 3] {
        let q = n_max / k;
        [q * k, n_max, (q * k).saturating_sub(1)]
    }

    /// `n` (a magnitude ≤ 2^31) with sign `neg`, as `i32`.
    fn signed(m: u32, neg: bool) -> Option<i32> {
        if neg {
            Some((m as i64).wrapping_neg() as i32).filter(|_| m <= 1 << 31)
        } else {
            i32::try_from(m).ok()
        }
    }

    #[test]
    fn clamping_and_names() {
        assert_eq!(Exact::recip(0), 1);
        assert_eq!(Exact::recip(5000), K_MAX);
        assert_eq!(Table::recip(0), Table::recip(1));
        assert_eq!(Table::recip(9999), Table::recip(4096));
        assert_eq!(ShiftAdd::<8>::recip(0), 256);
        assert_eq!(Exact::div(77, &0), 77); // a hand-made zero does not panic
        assert_eq!(Exact::NAME, "exact");
        assert_eq!(Table::NAME, "table");
        assert_eq!(ShiftAdd::<4>::NAME, "shift-add-4");
        assert_eq!(ShiftAdd::<16>::NAME, "shift-add-16");
        assert_eq!(ShiftAddRounded::<4>::NAME, "shift-add-rounded-4");
        assert_eq!(ShiftAddRounded::<16>::NAME, "shift-add-rounded-16");
    }

    #[test]
    fn table_entries_are_normalised_ceilings() {
        for k in 1..=K_MAX {
            let m = RECIP_TABLE[(k - 1) as usize] as u64;
            let s = 31 + ceil_log2(k);
            assert!(m >= 1 << 31, "k={k}");
            assert!(
                m * k as u64 >= 1 << s && (m - 1) * (k as u64) < 1 << s,
                "k={k}"
            );
            assert!(1u64 << (s - 31) >= k as u64 && (k == 1 || 1u64 << (s - 32) < k as u64));
        }
    }

    #[test]
    fn exact_and_table_equal_integer_division() {
        let ns = numerators();
        for k in 1..=K_MAX {
            let (re, rt) = (Exact::recip(k), Table::recip(k));
            let check = |n: i32| {
                let want = exact(n, k);
                assert_eq!(Exact::div(n, &re), want, "exact n={n} k={k}");
                assert_eq!(Table::div(n, &rt), want, "table n={n} k={k}");
            };
            ns.iter().copied().for_each(check);
            // The hardest numerators for the table: remainder k − 1 at the top of
            // the range, on both sides.
            let top = (i32::MAX / k as i32) * k as i32;
            for n in [top - 1, top - 1 - k as i32, top, i32::MAX] {
                check(n);
                check(-n);
            }
            let bottom = (i32::MIN / k as i32) * k as i32; // multiple of k ≥ i32::MIN
            for n in [bottom, bottom + 1, bottom.saturating_sub(1)] {
                check(n);
            }
        }
    }

    #[test]
    fn shift_add_is_the_floor_of_the_mask_product() {
        let ns = numerators();
        for n_bits in SHIFT_ADD_MIN_N..=SHIFT_ADD_MAX_N {
            for k in (1..=K_MAX).step_by(7).chain([1, 2, 3, 4, 5, 7, 4096]) {
                for rounded in [false, true] {
                    let a = shift_add_mask(k, n_bits, rounded);
                    for &n in &ns {
                        let m = (n.unsigned_abs() as u64 * a as u64) >> n_bits;
                        let want = if n < 0 { -(m as i64) } else { m as i64 };
                        assert_eq!(sa(n_bits, n, a) as i64, want, "N={n_bits} k={k} n={n}");
                    }
                }
            }
        }
    }

    #[test]
    fn masks_are_shifted_table_entries() {
        for n_bits in SHIFT_ADD_MIN_N..=SHIFT_ADD_MAX_N {
            for k in 1..=K_MAX {
                let m = RECIP_TABLE[(k - 1) as usize] as u64;
                let a = (m >> (31 + ceil_log2(k) - n_bits)) as u32;
                assert_eq!(a, shift_add_mask(k, n_bits, false), "N={n_bits} k={k}");
            }
        }
    }

    #[test]
    fn masks_at_the_ends() {
        for n_bits in SHIFT_ADD_MIN_N..=SHIFT_ADD_MAX_N {
            let one = 1u32 << n_bits;
            for rounded in [false, true] {
                // k = 1 and every power of two up to 2^N divide exactly.
                let mut k = 1;
                while k <= one.min(K_MAX) {
                    assert_eq!(shift_add_mask(k, n_bits, rounded), one / k);
                    for n in [i32::MAX, i32::MIN, 255 << 16, -12345] {
                        assert_eq!(sa(n_bits, n, one / k), exact(n, k), "k={k}");
                    }
                    k *= 2;
                }
            }
            if one < K_MAX {
                assert_eq!(shift_add_mask(one + 1, n_bits, false), 0);
                assert_eq!(shift_add_mask(2 * one - 1, n_bits, true), 1);
                assert_eq!(shift_add_mask(2 * one, n_bits, true), 0); // the tie
            }
        }
    }

    #[test]
    fn trait_impls_use_the_masks() {
        fn check<D: Divide<Recip = u32>>(n_bits: u32, rounded: bool) {
            for k in [1, 3, 7, 100, 4096] {
                assert_eq!(D::recip(k), shift_add_mask(k, n_bits, rounded));
                let n = -(200 << 16);
                assert_eq!(D::div(n, &D::recip(k)), sa(n_bits, n, D::recip(k)));
            }
        }
        check::<ShiftAdd<4>>(4, false);
        check::<ShiftAdd<11>>(11, false);
        check::<ShiftAdd<16>>(16, false);
        check::<ShiftAddRounded<5>>(5, true);
        check::<ShiftAddRounded<16>>(16, true);
        assert_eq!(
            <ShiftAdd<9> as Divide>::max_error(COLOUR_MAX, K_MAX),
            ShiftAdd::<9>::max_error(COLOUR_MAX, K_MAX)
        );
    }

    /// The closed-form per-k maximum against brute force over every numerator.
    #[test]
    fn max_error_formula_matches_brute_force() {
        for n_bits in [4, 5, 6, 8] {
            for rounded in [false, true] {
                for k in 1..=70 {
                    let a = shift_add_mask(k, n_bits, rounded);
                    for n_max in [0, 1, 5, 100, 1000, 3000] {
                        let brute = (0..=n_max)
                            .map(|n| (exact(n as i32, k) - sa(n_bits, n as i32, a)).unsigned_abs())
                            .max()
                            .unwrap();
                        assert_eq!(
                            mask_max_error(a, k, n_bits, n_max),
                            brute,
                            "N={n_bits} rounded={rounded} k={k} n_max={n_max}"
                        );
                    }
                }
            }
        }
    }

    /// Every k in 1..=4096, colour and raw numerators: the error never exceeds the
    /// stated bound, and the bound is attained exactly (it is tight, not within one).
    #[test]
    fn shift_add_errors_within_tight_bounds() {
        let ns = numerators();
        for n_bits in SHIFT_ADD_MIN_N..=SHIFT_ADD_MAX_N {
            for rounded in [false, true] {
                for n_max in [COLOUR_MAX, 1 << 31] {
                    let mut seen_max = 0;
                    for k in 1..=K_MAX {
                        let a = shift_add_mask(k, n_bits, rounded);
                        let bound = mask_max_error(a, k, n_bits, n_max);
                        let err = |n: i32| (exact(n, k) - sa(n_bits, n, a)).unsigned_abs();
                        for &n in ns.iter().filter(|n| n.unsigned_abs() <= n_max) {
                            let e = err(n);
                            assert!(
                                e <= bound,
                                "N={n_bits} r={rounded} k={k} n={n}: {e} > {bound}"
                            );
                            if !rounded {
                                // Truncation never overshoots.
                                assert!(
                                    sa(n_bits, n, a).unsigned_abs() <= exact(n, k).unsigned_abs()
                                );
                            }
                            assert_eq!(
                                sa(n_bits, n.saturating_neg(), a),
                                -sa(n_bits, n.max(-i32::MAX), a)
                            );
                        }
                        let attained = worst_numerators(k, n_max)
                            .into_iter()
                            .flat_map(|m| [signed(m, false), signed(m, true)])
                            .flatten()
                            .map(err)
                            .max()
                            .unwrap();
                        assert_eq!(attained, bound, "N={n_bits} r={rounded} k={k}");
                        seen_max = seen_max.max(attained);
                    }
                    assert_eq!(
                        seen_max,
                        shift_add_max_error(n_bits, rounded, n_max, K_MAX),
                        "N={n_bits} r={rounded}"
                    );
                }
            }
        }
    }

    /// The simple closed forms quoted in the module docs.
    #[test]
    fn closed_form_bounds() {
        for n_bits in SHIFT_ADD_MIN_N..=SHIFT_ADD_MAX_N {
            for n_max in [COLOUR_MAX, 1 << 31, 1000, 65_536, 12_345_678, 1 << 24] {
                let t = shift_add_max_error(n_bits, false, n_max, K_MAX);
                let r = shift_add_max_error(n_bits, true, n_max, K_MAX);
                let one = 1u64 << n_bits;
                // Loose bounds from |1/k − a/2^N| < 2^−N resp. ≤ 2^−(N+1), and the
                // all-zero expansion (k = 2^N + 1 resp. 2^(N+1)) as a lower bound.
                assert!(t as u64 <= (n_max as u64).div_ceil(one));
                assert!(r as u64 <= (n_max as u64).div_ceil(2 * one));
                if n_bits <= 11 {
                    assert!(t as u64 >= n_max as u64 / (one + 1), "N={n_bits}");
                }
                if n_bits <= 10 {
                    assert!(r as u64 >= n_max as u64 / (2 * one), "N={n_bits}");
                }
                // For large numerators the all-zero expansion is the worst case
                // exactly (for small ones another k can be one unit worse).
                if n_max >= 1 << 23 && n_bits <= 11 {
                    assert_eq!(t as u64, n_max as u64 / (one + 1), "N={n_bits}");
                }
                if n_max >= 1 << 23 && n_bits <= 10 {
                    assert_eq!(r as u64, n_max as u64 / (2 * one), "N={n_bits}");
                }
            }
        }
    }

    #[test]
    fn seed_example_k7_n6() {
        // 255·(1/8 + 1/64) = 35.859375 against 255/7 = 36.43; in Q.16 exactly.
        let r = ShiftAdd::<6>::recip(7);
        assert_eq!(r, 0b00_1001);
        let q = ShiftAdd::<6>::div(255 << 16, &r);
        assert_eq!(q, 2_350_080);
        assert_eq!(q as f64, 35.859375 * 65536.0);
        assert_eq!(
            ShiftAddRounded::<6>::div(255 << 16, &ShiftAddRounded::<6>::recip(7)),
            q
        );
        let exact = Exact::div(255 << 16, &7) as f64 / 65536.0;
        assert!((exact - 36.4286).abs() < 1e-4);
        assert!((exact - q as f64 / 65536.0 - 0.5692).abs() < 1e-4);
    }

    /// Max absolute and mean relative error of `255·a/2^N` against `255/k` over
    /// `k` in `2..=16`, in f64 (the seed's population), and through the integer
    /// divider in Q.16.
    fn seed_figures(n_bits: u32, rounded: bool) -> (f64, f64) {
        let (mut max_abs, mut sum_rel) = (0f64, 0f64);
        for k in 2..=16u32 {
            let a = shift_add_mask(k, n_bits, rounded) as f64 / (1u64 << n_bits) as f64;
            let want = 255.0 / k as f64;
            let got = 255.0 * a;
            // The integer path gives exactly the same value: 255·2^16·a/2^N has no
            // fraction below 2^−16 for N ≤ 16.
            let int = sa(n_bits, 255 << 16, shift_add_mask(k, n_bits, rounded)) as f64 / 65536.0;
            assert_eq!(int, got);
            max_abs = max_abs.max((want - got).abs());
            sum_rel += (want - got).abs() / want;
        }
        (max_abs, 100.0 * sum_rel / 15.0)
    }

    #[test]
    fn seed_figures_for_n8() {
        // The seed's figures (Δmax = 0.4427, δ = 0.81 %) are those of the expansion
        // rounded to nearest at bit 8, with I_b − I_a = 255 and k = 2..16.
        let (max_abs, mean_rel) = seed_figures(8, true);
        assert_eq!((max_abs * 1e4).round(), 4427.0);
        assert_eq!((mean_rel * 100.0).round(), 81.0);
        assert!((mean_rel - 0.8073).abs() < 1e-4, "{mean_rel}");
        // The truncated expansion the seed's formula (2.18) and k = 7 example use
        // gives larger figures.
        let (max_abs, mean_rel) = seed_figures(8, false);
        assert!((max_abs - 0.6896).abs() < 1e-4, "{max_abs}");
        assert!((mean_rel - 1.0677).abs() < 1e-4, "{mean_rel}");
        // The seed's own k = 7, N = 6 case: 0.5692 absolute, 1.56 % relative.
        let a = shift_add_mask(7, 6, false) as f64 / 64.0;
        let (want, got) = (255.0 / 7.0, 255.0 * a);
        assert!((want - got - 0.5692).abs() < 1e-4);
        assert_eq!((10000.0 * (want - got) / want).round(), 156.0);
    }

    /// Max and mean error per increment (channel steps) and at the end of the span
    /// (`k` increments), for `n = I·2^16`, `I` in `0..=255`, `k` in `1..=k_max`.
    fn measure(n_bits: u32, rounded: bool, k_max: u32) -> (f64, f64, f64) {
        let (mut max, mut sum, mut end, mut count) = (0u32, 0u64, 0u64, 0u64);
        for k in 1..=k_max {
            let a = shift_add_mask(k, n_bits, rounded);
            for i in 0..=255 {
                let n = i << 16;
                let e = (exact(n, k) - sa(n_bits, n, a)).unsigned_abs();
                max = max.max(e);
                end = end.max(e as u64 * k as u64);
                sum += e as u64;
                count += 1;
            }
        }
        (
            max as f64 / 65536.0,
            sum as f64 / count as f64 / 65536.0,
            end as f64 / 65536.0,
        )
    }

    #[test]
    fn truncated_against_rounded() {
        std::println!("N | k_max | trunc max  mean  span-end | rounded max  mean  span-end");
        for n_bits in SHIFT_ADD_MIN_N..=SHIFT_ADD_MAX_N {
            for k_max in [16, K_MAX] {
                let (tm, ta, te) = measure(n_bits, false, k_max);
                let (rm, ra, re) = measure(n_bits, true, k_max);
                std::println!(
                    "{n_bits:2} | {k_max:4} | {tm:.4} {ta:.5} {te:8.3} | {rm:.4} {ra:.5} {re:8.3}"
                );
                assert!(rm <= tm && ra < ta && re <= te, "N={n_bits} k_max={k_max}");
                // The measured maximum over colour numerators is the analytic one.
                let bound_t = shift_add_max_error(n_bits, false, COLOUR_MAX, k_max);
                let bound_r = shift_add_max_error(n_bits, true, COLOUR_MAX, k_max);
                assert!(tm * 65536.0 <= bound_t as f64 && rm * 65536.0 <= bound_r as f64);
            }
        }
        // The figures quoted in the module docs.
        let (tm, ta, _) = measure(8, false, 16);
        let (rm, ra, _) = measure(8, true, 16);
        assert_eq!(
            [tm, ta, rm, ra].map(|x| (x * 1e4).round()),
            [6896.0, 1390.0, 4427.0, 1060.0]
        );
    }
}
