//! Specular models: cheaper replacements for the Blinn term `cⁿ` (c = N·H), after
//! seed 002 (§2.1 Schlick and its modification, §2.2 the quadratic, §2.3 the
//! cosine-quadratic, §2.5 its energy-conserving form).
//!
//! Every model implements the [`Specular`] seam of [`crate::light`] (re-exported here
//! together with [`BlinnExact`], which stays in `light`): `prepare` runs once per
//! material and frame and does everything that depends on `n` alone (σ, √k, the
//! table lookup of `a`, the start of the zero region); `eval` runs per vertex or per
//! pixel and is a handful of integer operations.
//!
//! | `NAME` | type | formula | per `eval` |
//! | --- | --- | --- | --- |
//! | `exact` | [`BlinnExact`] | `cⁿ` | ≤ 20 multiplies (integer n), ~60 (fractional n) |
//! | `schlick` | [`Schlick`] | `c / (n − n·c + c)` | 1 multiply, 1 division |
//! | `schlick-mod` | [`SchlickModified`] | `c / (0.5·n·(1 − c²) + n − n·c + c)` | 2 multiplies (one 26×37-bit), 1 division |
//! | `quadratic` | [`Quadratic`] | `max(0, a·c² + (1 − a)·c)` | 2 multiplies |
//! | `cos-quad` | [`CosQuadratic`] | `max(0, σ·(c − 1) + 1)²`, σ = (n+1)/3 | 2 multiplies |
//! | `cos-quad-energy` | [`CosQuadraticEnergy`] | `(n + 6)/24.55 · max(0, σ·(c − 1) + 1)²` | 2 multiplies (one 38×30-bit) |
//!
//! (`BlinnExact` has no `NAME` constant because it lives in `light`; its name in the
//! scene file and CLI is `"exact"`, the first entry of [`NAMES`].) "Multiply" means an
//! unsigned 32×32→64-bit product (one `UMULL` on Cortex-M3/M4/M7, a short library
//! call on M0+); "division" a 64/64-bit unsigned division (a library call on every
//! Cortex-M). Besides those, each `eval` costs a few adds, shifts and compares.
//!
//! Numbers: `c` arrives in Q2.30 and is clamped to [0, 1] (the lighting stage only
//! calls with 0 < c ≤ 1); `n` is clamped to [1, 1000] by `prepare`. Results are Q2.30;
//! every model but the energy-conserving one stays in [0, 1] and gives exactly 1 at
//! c = 1; the energy-conserving one peaks at k = (n + 6)/24.55 (up to ≈ 41) and
//! saturates `eval` at 2 − 2⁻³⁰, the top of Q2.30; lighting calls
//! [`Specular::eval_wide`], which keeps the full value (see [`CosQuadraticEnergy`]). At c = 0 Schlick, modified Schlick and the quadratic give 0; the two
//! cosine-quadratic forms give 0 for n ≥ 2 and the formula's `(1 − σ)²` (times the
//! factor) for 1 ≤ n < 2, where their zero point (σ − 1)/σ is negative. Every model
//! is non-decreasing in `c`. Parameters that need more fraction bits than Q16.16 are
//! held in unsigned 32-bit fixed point: `a(n)` in Q10.22 (< 1024), σ in Q9.23 (< 512).
//!
//! Accuracy against each model's own formula evaluated in `f64` (with the exact σ,
//! k and a(n); tested for n ∈ {1, 2, 4, …, 512, 1000} over a dense sweep of `c`),
//! in Q2.30 LSBs (2⁻³⁰ ≈ 9.3e-10), absolute — each bound derived in the model's docs
//! and asserted with the measured maximum in brackets: Schlick ≤ 1 (0.5), modified
//! Schlick ≤ 16 (6.9), quadratic ≤ 40 (11.9), cosine-quadratic ≤ 40 (32.9),
//! energy-conserving ≤ 16 (5.6) wherever it does not saturate and ≤ 64 for its
//! unsaturated [`CosQuadraticEnergy::eval_wide`] (22 measured) — all below 4e-8,
//! five orders of magnitude under an 8-bit colour step.
//! How far each model is from `cⁿ` is a property of the model, not of this code; the
//! tests print it (`cargo test -p fixshade specular_error_vs_pow -- --nocapture`).
//!
//! ```
//! use fixshade::fixed::Q16_16;
//! use fixshade::specular::{CosQuadratic, Schlick, Specular};
//! let n = Q16_16::from_int(50);
//! let one = 1 << 30;
//! let p = <Schlick>::prepare(n);
//! assert_eq!(<Schlick>::eval(&p, one), one);
//! let q = CosQuadratic::prepare(n);
//! assert_eq!(CosQuadratic::eval(&q, one / 2), 0); // far outside the highlight
//! assert!(CosQuadratic::eval(&q, one - (one >> 8)) > one / 2);
//! ```
//!
//! The models plug into per-vertex lighting like the exact one:
//!
//! ```
//! use fixshade::fixed::Q16_16;
//! use fixshade::light::{Light, LightingSetup, Material};
//! use fixshade::math::Mat4;
//! use fixshade::specular::CosQuadratic;
//! let white = [Q16_16::ONE; 3];
//! let sun = Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], white, white);
//! let mat = Material { specular: white, shininess: Q16_16::from_int(64), ..Material::default() };
//! let setup = LightingSetup::<CosQuadratic>::new(&[sun], &Mat4::IDENTITY, &mat, [Q16_16::ZERO; 3], false);
//! let lit = setup.shade([0; 3], [0, 0, 1 << 30]);
//! assert_eq!(lit, [1 << 16; 3]); // N = L = H: full diffuse plus full highlight, clamped
//! ```

use crate::divide::{wide_recip, Divide, Exact};
use crate::fixed::Q16_16;
use crate::math::{isqrt_u128, pow_q30};
use core::marker::PhantomData;

/// The specular seam: how `cⁿ` (c = N·H) is evaluated.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{BlinnExact, Specular};
/// use fixshade::specular::Schlick;
/// let c = 0x3800_0000; // N·H = 0.875 in Q2.30
/// let n = Q16_16::from_int(8);
/// let exact = BlinnExact::eval(&BlinnExact::prepare(n), c); // 0.875⁸ ≈ 0.344
/// let approx = <Schlick>::eval(&<Schlick>::prepare(n), c); // c / (n − n·c + c) ≈ 0.467
/// assert!((exact - 368947264).abs() < 1 << 8);
/// assert!(approx > exact);
/// ```
pub trait Specular {
    /// False for a model that has no specular term at all
    /// ([`crate::effects::NoSpecular`]): lighting then compiles without the half
    /// vector, the power and the specular sums.
    const ENABLED: bool = true;
    /// True if frames lit with this type run the specular term:
    /// [`Specular::ENABLED`] for the core's types (the compiler removes the test),
    /// and for a model chosen at run time (the simulator's) whether the term is
    /// chosen. Every stage asks this.
    ///
    /// ```
    /// use fixshade::effects::NoSpecular;
    /// use fixshade::specular::{BlinnExact, Specular};
    /// assert!(BlinnExact::enabled() && !NoSpecular::enabled());
    /// ```
    #[inline(always)]
    fn enabled() -> bool {
        Self::ENABLED
    }
    /// True for two-sided lighting ([`crate::effects::TwoSided`]): the vertex stage
    /// also lights every vertex with its negated normal and the back material, and
    /// back faces draw with those colours. False for every plain model.
    const TWO_SIDED: bool = false;
    /// True if frames lit with this type light two-sided: [`Specular::TWO_SIDED`]
    /// for the core's types (the compiler removes the test), and for a model chosen
    /// at run time (the simulator's) whether two-sided lighting is chosen. Every
    /// stage asks this, so such a type draws one-sided and two-sided frames with
    /// one set of functions.
    ///
    /// ```
    /// use fixshade::effects::TwoSided;
    /// use fixshade::specular::{BlinnExact, Specular};
    /// assert!(TwoSided::<BlinnExact>::two_sided() && !BlinnExact::two_sided());
    /// ```
    #[inline(always)]
    fn two_sided() -> bool {
        Self::TWO_SIDED
    }
    /// Per-material data derived from n once per frame (a table lookup, a reciprocal).
    type Params: Copy;
    /// Prepares the parameters for exponent `n` (already clamped to 1..=1000).
    fn prepare(n: Q16_16) -> Self::Params;
    /// `cⁿ` or its approximation for `c` in Q2.30 (0 < c ≤ 1), result Q2.30 in [0, 1].
    fn eval(p: &Self::Params, c: i32) -> i32;
    /// The value lighting uses, in Q.30 as `u64`: [`Specular::eval`] for every model
    /// whose result stays in [0, 1]; a model that may exceed 1 (the energy-conserving
    /// form peaks near 41) overrides it with its unsaturated value, at most 2³⁶.
    #[inline]
    fn eval_wide(p: &Self::Params, c: i32) -> u64 {
        Self::eval(p, c).max(0) as u64
    }
}

/// Exact `cⁿ` (see [`crate::math::pow_q30`]).
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{BlinnExact, Specular};
/// let p = BlinnExact::prepare(Q16_16::from_int(2));
/// assert_eq!(BlinnExact::eval(&p, 1 << 29), 1 << 28); // 0.5² = 0.25
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct BlinnExact;

impl Specular for BlinnExact {
    type Params = Q16_16;
    fn prepare(n: Q16_16) -> Q16_16 {
        n
    }
    #[inline]
    fn eval(n: &Q16_16, c: i32) -> i32 {
        pow_q30(c, *n)
    }
}

/// The scene-file and CLI names of the six models, in the order of the seam table
/// in DESIGN.md: `exact` ([`BlinnExact`]), then the `NAME` of [`Schlick`],
/// [`SchlickModified`], [`Quadratic`], [`CosQuadratic`], [`CosQuadraticEnergy`].
///
/// ```
/// use fixshade::specular::{CosQuadraticEnergy, Schlick, NAMES};
/// assert_eq!(NAMES[0], "exact");
/// assert_eq!(NAMES[1], Schlick::NAME);
/// assert_eq!(NAMES[5], CosQuadraticEnergy::NAME);
/// ```
pub const NAMES: [&str; 6] = [
    "exact",
    Schlick::NAME,
    SchlickModified::NAME,
    Quadratic::NAME,
    CosQuadratic::NAME,
    CosQuadraticEnergy::NAME,
];

/// Fraction bits of the Q10.22 entries of [`QUADRATIC_A`] (`a(n)` < 1024).
///
/// ```
/// use fixshade::specular::{QUADRATIC_A, Q22_FRAC_BITS};
/// assert_eq!(QUADRATIC_A[1], 1 << Q22_FRAC_BITS); // a(2) = 1
/// ```
pub const Q22_FRAC_BITS: u32 = 22;

/// 1 in Q.30 as a `u64`.
const ONE: u64 = 1 << 30;

/// `c` clamped to [0, 1] in Q.30 and `d = 1 − c`; both ≤ 2³⁰.
#[inline]
fn split(c: i32) -> (u64, u64) {
    let c = c.clamp(0, 1 << 30) as u64;
    (c, ONE - c)
}

/// The raw bits of `n` clamped to [1, 1000] (so 2¹⁶ ≤ bits ≤ 1000·2¹⁶ < 2²⁶).
#[inline]
fn n_bits(n: Q16_16) -> u32 {
    n.to_bits().clamp(1 << 16, 1000 << 16) as u32
}

/// `ceil(2^(30 + frac) / p)` for a parameter `p` with `frac` fraction bits: the
/// smallest `d = 1 − c` (Q.30) with `p·d ≥ 1`, where the quadratic and
/// cosine-quadratic forms reach zero. At least `u32::MAX` means never (d ≤ 2³⁰).
#[inline]
fn zero_from(p: u32, frac: u32) -> u32 {
    if p == 0 {
        return u32::MAX;
    }
    let p = p as u64;
    // 2^(30 + frac) ≤ 2^53; the quotient saturates to u32::MAX for tiny p (an
    // interpolated a(n) for n just above 1).
    (1u64 << (30 + frac)).div_ceil(p).min(u32::MAX as u64) as u32
}

// ---------------------------------------------------------------------------------
// Schlick
// ---------------------------------------------------------------------------------

/// Parameters of [`Schlick`] and [`SchlickModified`]: just `n`, clamped to [1, 1000].
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{Schlick, Specular};
/// assert_eq!(<Schlick>::prepare(Q16_16::from_int(5000)).n(), Q16_16::from_int(1000));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct SchlickParams {
    /// Q16.16 bits of n, in [2¹⁶, 1000·2¹⁶].
    n: u32,
}

impl SchlickParams {
    /// The (clamped) exponent.
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::specular::{SchlickModified, Specular};
    /// assert_eq!(<SchlickModified>::prepare(Q16_16::ZERO).n(), Q16_16::ONE);
    /// ```
    pub const fn n(&self) -> Q16_16 {
        Q16_16::from_bits(self.n as i32)
    }
}

/// Schlick's rational approximation (seed 002, (2.1)): `c / (n − n·c + c)`.
///
/// Computed as `c / (n·(1 − c) + c)`: one 32×32→64 multiply (`n·d`), one 64/64
/// division, rounded to nearest. The denominator is at least `d + c = 1` (n ≥ 1), so
/// the result lies in [0, 1], is exactly 1 at c = 1 and exactly `c` for n = 1. Error
/// against the f64 formula ≤ 1 LSB (2⁻³⁰): the denominator's rounding is ≤ 2⁻³¹
/// relative, the quotient's ≤ ½ LSB. It decays slowly: the tail far from the
/// highlight stays well above `cⁿ`.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{Schlick, Specular};
/// let p = <Schlick>::prepare(Q16_16::from_int(3));
/// // c = 1/2: 0.5 / (3 − 1.5 + 0.5) = 1/4.
/// assert_eq!(<Schlick>::eval(&p, 1 << 29), 1 << 28);
/// assert_eq!(Schlick::NAME, "schlick");
/// ```
///
/// The denominator goes through a divider `D` ([`crate::divide`]): `Schlick` is
/// `Schlick<Exact>`, the rounded 64/64 division above, bit-identical to the model
/// before the seam. Any other `D` takes [`wide_recip`] of the denominator (one
/// division on the seam) and one multiply: `c·r / 2^shift`, rounded, capped at 1;
/// the result is at most the exact one, low by at most the reciprocal's relative
/// error `η = 2^(1−b) + (2E + 2)·2^b/2³⁰`.
///
/// ```
/// use fixshade::divide::Table;
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{Schlick, Specular};
/// let p = <Schlick<Table>>::prepare(Q16_16::from_int(3));
/// let v = <Schlick<Table>>::eval(&p, 1 << 29); // 1/4 with a 12-bit denominator
/// assert!(v <= 1 << 28 && (1 << 28) - v <= (1 << 28) >> 10);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Schlick<D: Divide = Exact>(PhantomData<D>);

/// `c·2³⁰ / den` (Q.30, `c ≤ den`, `2³⁰ ≤ den < 2⁴¹`), rounded: exactly for
/// [`Exact`], through [`wide_recip`] otherwise, capped at 2³⁰.
#[inline]
fn schlick_div<D: Divide>(c: u64, den: u64) -> i32 {
    if D::is_exact() {
        // c·2^30 ≤ 2^60; c ≤ den, so the rounded quotient is ≤ 2^30.
        return (((c << 30) + den / 2) / den) as i32;
    }
    let w = wide_recip::<D>(den as u128);
    // den ≥ 2^30 and the mantissa has at most 12 bits, so shift ≥ 19; c·r ≤ 2^60.
    let q = (c * w.r as u64 + (1 << (w.shift - 1))) >> w.shift;
    q.min(ONE) as i32
}

impl Schlick {
    /// Name in scene files and on the command line.
    ///
    /// ```
    /// assert_eq!(fixshade::specular::Schlick::NAME, "schlick");
    /// ```
    pub const NAME: &'static str = "schlick";
}

impl<D: Divide> Specular for Schlick<D> {
    type Params = SchlickParams;

    /// Clamps `n` to [1, 1000].
    fn prepare(n: Q16_16) -> SchlickParams {
        SchlickParams { n: n_bits(n) }
    }

    #[inline]
    fn eval(p: &SchlickParams, c: i32) -> i32 {
        let (c, d) = split(c);
        // n < 2^26 (Q16.16), d ≤ 2^30: n·d < 2^56. The rounded Q.30 quotient is ≥ d
        // because n ≥ 2^16, so den ≥ d + c = 2^30 > 0, and den < 1001·2^30 < 2^40.
        let den = ((p.n as u64 * d + (1 << 15)) >> 16) + c;
        schlick_div::<D>(c, den)
    }
}

/// Seed 002's modified Schlick (2.2): `c / (0.5·n·(1 − c²) + n − n·c + c)`.
///
/// The extra `0.5·n·(1 − c²)` in the denominator (the seed's text says "numerator",
/// its formula and this code put it in the denominator) makes the tail decay faster.
/// Since `1 − c² = d·(1 + c)` with `d = 1 − c`, the denominator is
/// `n·d·(3 + c)/2 + c`: two multiplies (`d·(3 + c)`, 32×32→64, and `n·m`, 26×37-bit:
/// `UMULL` + `MLA` on Cortex-M4) and one 64/64 division per call. The denominator is
/// at least `1.5·d + c ≥ 1`, so the result lies in [0, 1], is exactly 1 at c = 1 and
/// 0 at c = 0. Error against the f64 formula ≤ 16 LSB (2⁻³⁰): `m = d·(3 + c)/2` is
/// rounded to 2⁻³⁷, which n ≤ 1000 turns into ≤ 8 LSB of the denominator (≥ 1).
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{SchlickModified, Specular};
/// let p = <SchlickModified>::prepare(Q16_16::from_int(2));
/// // c = 1/2: 0.5 / (0.5·2·0.75 + 2 − 1 + 0.5) = 0.5 / 2.25 = 2/9.
/// let v = <SchlickModified>::eval(&p, 1 << 29) as i64;
/// assert!((v - (2i64 << 30) / 9).abs() <= 1);
/// assert_eq!(<SchlickModified>::eval(&p, 1 << 30), 1 << 30);
/// ```
///
/// The denominator goes through a divider `D` exactly as in [`Schlick`];
/// `SchlickModified` is `SchlickModified<Exact>`.
#[derive(Copy, Clone, Debug, Default)]
pub struct SchlickModified<D: Divide = Exact>(PhantomData<D>);

impl SchlickModified {
    /// Name in scene files and on the command line.
    ///
    /// ```
    /// assert_eq!(fixshade::specular::SchlickModified::NAME, "schlick-mod");
    /// ```
    pub const NAME: &'static str = "schlick-mod";
}

impl<D: Divide> Specular for SchlickModified<D> {
    type Params = SchlickParams;

    /// Clamps `n` to [1, 1000].
    fn prepare(n: Q16_16) -> SchlickParams {
        SchlickParams { n: n_bits(n) }
    }

    #[inline]
    fn eval(p: &SchlickParams, c: i32) -> i32 {
        let (c, d) = split(c);
        // m = d·(3 + c)/2 = d·(4 − d)/2 in Q.36: d ≤ 2^30 and 3·2^30 + c ≤ 2^32, so the
        // Q.60 product d·(3 + c) is ≤ 2^62; m ≤ 1.5·2^36 < 2^37 (d ≤ 1), m ≥ 1.5·d·2^6.
        let m = (d * (3 * ONE + c) + (1 << 24)) >> 25;
        // n < 2^26, m < 2^37: n·m < 2^63 (Q.52). den ≥ d + c = 2^30 (n ≥ 1, m ≥ d·2^6)
        // and den < 1501·2^30 < 2^41.
        let den = ((p.n as u64 * m + (1 << 21)) >> 22) + c;
        schlick_div::<D>(c, den)
    }
}

// ---------------------------------------------------------------------------------
// Quadratic
// ---------------------------------------------------------------------------------

/// `a(n)` in Q10.22, rounded to nearest, for one integer `n` (≥ 1); integer
/// arithmetic only, so it runs in constant evaluation.
///
/// `t = √((n−1)/n)` (= cos γ at the inflection point γ = arctan(1/√(n−1)) of cosⁿ)
/// in Q.56, from an exact integer square root; `t^(n−1)` by squaring in Q.56
/// (`u128` products < 2¹¹²); `a = (1 − t^(n−1)) / (1 − t)`. Since `1 − t ≥ 1/(2n)`
/// ≥ 2⁻¹¹, the Q.56 rounding errors move `a` by less than 2⁻⁴⁰, far below the final
/// rounding to 2⁻²³.
const fn a_entry(n: u32) -> u32 {
    if n <= 1 {
        // t = 0 and t^0 = 1: a = (1 − 1)/(0 − 1) = 0, which is also the limit of
        // a(n) as n → 1⁺ (t^(n−1) = exp((n−1)·ln t) → 1 because x·ln x → 0).
        return 0;
    }
    const S: u32 = 56;
    let one: u128 = 1 << S;
    let nn = n as u128;
    // (n − 1)·2^112 < 2^10·2^112 = 2^122; t < 2^56 because (n−1)/n < 1.
    let t = isqrt_u128(((nn - 1) << (2 * S)) / nn);
    let mut e = n - 1;
    let mut base = t;
    let mut acc = one;
    while e > 0 {
        if e & 1 == 1 {
            acc = (acc * base + (one >> 1)) >> S; // both ≤ 2^56: product ≤ 2^112
        }
        e >>= 1;
        if e > 0 {
            base = (base * base + (one >> 1)) >> S;
        }
    }
    // (1 − t^(n−1))·2^22 < 2^78; 1 − t > 0.
    let num = (one - acc) << Q22_FRAC_BITS;
    let den = one - t;
    ((num + den / 2) / den) as u32
}

const fn a_table() -> [u32; 1000] {
    let mut t = [0u32; 1000];
    let mut i = 0;
    while i < t.len() {
        t[i] = a_entry(i as u32 + 1);
        i += 1;
    }
    t
}

/// The coefficient `a(n)` of the quadratic model for n = 1..=1000 (`QUADRATIC_A[n − 1]`),
/// unsigned Q10.22 (`a(1000)` ≈ 786.6 < 2¹⁰), rounded to nearest: 1000 × 4 bytes =
/// 4000 bytes of flash (`.rodata`).
///
/// Seed 002, (2.7)–(2.8): with `t = cos γ = √((n−1)/n)` at the inflection point
/// γ = arctan(1/√(n−1)) of cosⁿ, `a = (t^(n−1) − 1)/(t − 1)`, so that
/// `a·t² + (1 − a)·t = tⁿ`. For n = 1 the seed's (2.8) divides by √(n − 1) = 0; the
/// entry is the limit `a(1) = 0` (the model is then exactly `c`). Computed at compile
/// time by integer-only constant evaluation (no `build.rs`); a test checks all 1000
/// entries against f64 to within half an LSB.
///
/// ```
/// use fixshade::specular::QUADRATIC_A;
/// assert_eq!(QUADRATIC_A[0], 0); // a(1)
/// assert_eq!(QUADRATIC_A[1], 1 << 22); // a(2) = 1
/// assert_eq!(core::mem::size_of_val(&QUADRATIC_A), 4000);
/// let a1000 = QUADRATIC_A[999] >> 22;
/// assert_eq!(a1000, 786);
/// ```
pub static QUADRATIC_A: [u32; 1000] = a_table();

/// `a(n)` in Q10.22 for any `n` in [1, 1000] (clamped): the table entry for integer
/// `n`, and linear interpolation between the two neighbouring entries otherwise.
///
/// Why interpolate rather than round: a(n) is smooth and almost linear (≈ 0.787·n
/// for large n), so interpolation is accurate to 3.6e-6 relative for n ≥ 10 and
/// 2.9e-3 for 2 ≤ n < 10 (measured, `specular_a_interpolation_error`),
/// it keeps `a` continuous and increasing in `n` (a material animated through n does
/// not jump), and it costs one multiply once per frame. Rounding n instead would be
/// off by up to half a table step (≈ 0.39 in `a`, about 1/(2n) relative). Between 1 and
/// 2 a(n) rises with infinite slope from a(1) = 0, so there the chord underestimates
/// it (by up to 0.08 measured; a(1.5) ≈ 0.568 against 0.5).
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{quadratic_a, QUADRATIC_A};
/// assert_eq!(quadratic_a(Q16_16::from_int(10)), QUADRATIC_A[9]);
/// let mid = quadratic_a(Q16_16::from_ratio(21, 2)); // n = 10.5
/// assert!(mid > QUADRATIC_A[9] && mid < QUADRATIC_A[10]);
/// assert_eq!(quadratic_a(Q16_16::from_int(2000)), QUADRATIC_A[999]);
/// ```
pub fn quadratic_a(n: Q16_16) -> u32 {
    let nb = n_bits(n);
    let i = (nb >> 16) as usize; // 1..=1000
    let f = (nb & 0xFFFF) as u64;
    let a0 = QUADRATIC_A[i - 1];
    if f == 0 {
        return a0;
    }
    // f ≠ 0 implies n < 1000, so i ≤ 999 and entry i exists. The table increases,
    // so a1 ≥ a0; (a1 − a0) < 2^32, times f < 2^16: < 2^48.
    let a1 = QUADRATIC_A[i];
    a0 + (((a1 - a0) as u64 * f + (1 << 15)) >> 16) as u32
}

/// Parameters of [`Quadratic`]: `a(n)` and the start of its zero region.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{Quadratic, Specular, QUADRATIC_A};
/// assert_eq!(Quadratic::prepare(Q16_16::from_int(7)).a_q22(), QUADRATIC_A[6]);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct QuadraticParams {
    /// a(n), Q10.22.
    a: u32,
    /// Smallest d = 1 − c (Q.30) with a·d ≥ 1.
    d0: u32,
}

impl QuadraticParams {
    /// `a(n)` in Q10.22.
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::specular::{Quadratic, Specular};
    /// assert_eq!(Quadratic::prepare(Q16_16::ONE).a_q22(), 0);
    /// ```
    pub const fn a_q22(&self) -> u32 {
        self.a
    }
}

/// Seed 002's quadratic approximation (§2.2): `a·c² + (1 − a)·c`, negative values
/// clamped to 0, with `a = a(n)` from [`QUADRATIC_A`] (interpolated by
/// [`quadratic_a`] for fractional n).
///
/// The quadratic passes through (0, 0), (1, 1) and the inflection point of cosⁿ. It
/// is evaluated as `c·(1 − a·(1 − c))`, zero once `a·(1 − c) ≥ 1`, i.e. for
/// c ≤ 1 − 1/a: two 32×32→64 multiplies, no division, and inside the precomputed zero
/// region none at all. Result in [0, 1], exactly 1 at c = 1, 0 at c = 0, exactly `c`
/// for n = 1. Error against the f64 formula with the exact a(n) ≤ 40 LSB (2⁻³⁰): the
/// table's rounding (≤ 2⁻²³) is multiplied by `c·(1 − c)` ≤ min(¼, 1/a) — ≤ 32 LSB —
/// plus ≤ 1 LSB from each product's rounding.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{Quadratic, Specular};
/// let p = Quadratic::prepare(Q16_16::from_int(2)); // a = 1: the model is c²
/// assert_eq!(Quadratic::eval(&p, 1 << 29), 1 << 28);
/// assert_eq!(Quadratic::NAME, "quadratic");
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Quadratic;

impl Quadratic {
    /// Name in scene files and on the command line.
    ///
    /// ```
    /// assert_eq!(fixshade::specular::Quadratic::NAME, "quadratic");
    /// ```
    pub const NAME: &'static str = "quadratic";
}

impl Specular for Quadratic {
    type Params = QuadraticParams;

    /// Looks up (interpolates) `a(n)` and computes where the model reaches zero.
    fn prepare(n: Q16_16) -> QuadraticParams {
        let a = quadratic_a(n);
        QuadraticParams {
            a,
            d0: zero_from(a, Q22_FRAC_BITS),
        }
    }

    #[inline]
    fn eval(p: &QuadraticParams, c: i32) -> i32 {
        let (c, d) = split(c);
        if d >= p.d0 as u64 {
            return 0;
        }
        // d < d0 = ceil(2^52 / a), so a·d < 2^52 and s = a·d in Q.30 is ≤ 2^30.
        let s = (p.a as u64 * d + (1 << 21)) >> 22;
        let m = ONE.saturating_sub(s);
        // c, m ≤ 2^30: product ≤ 2^60; result ≤ 2^30.
        ((c * m + (1 << 29)) >> 30) as i32
    }
}

// ---------------------------------------------------------------------------------
// Cosine-quadratic
// ---------------------------------------------------------------------------------

/// σ = (n + 1)/3 in Q9.23 (rounded to nearest, error ≤ 2⁻²³/3) from the Q16.16
/// bits of n.
#[inline]
fn sigma_q23(nb: u32) -> u32 {
    // (nb + 2^16)·2^7 ≤ 1001·2^23; σ ≤ 333.7 < 2^9, so σ·2^23 < 2^32.
    let x = ((nb as u64) + (1 << 16)) << 7;
    ((x + 1) / 3) as u32
}

/// `max(0, 1 − σ·d)` in Q.30 for d = 1 − c (Q.30) below the zero region `d0`.
#[inline]
fn cos_quad_base(sigma: u32, d0: u32, d: u64) -> Option<u64> {
    if d >= d0 as u64 {
        return None;
    }
    // σ in Q9.23; d < d0 = ceil(2^53 / σ): σ·d < 2^53, so s ≤ 2^30.
    let s = (sigma as u64 * d + (1 << 22)) >> 23;
    Some(ONE.saturating_sub(s))
}

/// Parameters of [`CosQuadratic`]: σ and the start of the zero region.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{CosQuadratic, Specular};
/// // n = 2: σ = 1 exactly.
/// assert_eq!(CosQuadratic::prepare(Q16_16::from_int(2)).sigma_q23(), 1 << 23);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct CosQuadParams {
    /// σ = (n + 1)/3, Q9.23.
    sigma: u32,
    /// Smallest d = 1 − c (Q.30) with σ·d ≥ 1.
    d0: u32,
}

impl CosQuadParams {
    /// σ = (n + 1)/3 in Q9.23 (unsigned, rounded to nearest).
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::specular::{CosQuadratic, Specular};
    /// assert_eq!(CosQuadratic::prepare(Q16_16::from_int(1000)).sigma_q23(), 2_798_998_869); // 1001/3
    /// ```
    pub const fn sigma_q23(&self) -> u32 {
        self.sigma
    }
}

/// Seed 002's cosine-quadratic approximation (§2.3, (2.12)–(2.15)):
/// `(σ·(c − 1) + 1)²` with σ = (n + 1)/3 (chosen so that its integral against
/// sin γ over its support equals that of cosⁿ), and 0 for c < (σ − 1)/σ.
///
/// With d = 1 − c: `u = 1 − σ·d`, result `u²`. Two 32×32→64 multiplies, no division;
/// in the zero region (d ≥ 1/σ, precomputed) none. Result in [0, 1], exactly 1 at
/// c = 1; at c = 0 it is 0 for n ≥ 2 and `(1 − σ)²` for n < 2 (n = 1: 1/9). Error
/// against the f64 formula with the exact σ ≤ 40 LSB (2⁻³⁰): σ is rounded to Q9.23
/// (≤ 2⁻²³/3), and `∂u²/∂σ = −2u·d` with `2u·d ≤ 1/(2σ) ≤ ¾` gives ≤ 32 LSB, plus
/// the products' rounding.
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{CosQuadratic, Specular};
/// let p = CosQuadratic::prepare(Q16_16::from_int(5)); // σ = 2, zero below c = 1/2
/// assert_eq!(CosQuadratic::eval(&p, 3 << 28), 1 << 28); // (2·(−1/4) + 1)² = 1/4
/// assert_eq!(CosQuadratic::eval(&p, 1 << 29), 0);
/// assert_eq!(CosQuadratic::NAME, "cos-quad");
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct CosQuadratic;

impl CosQuadratic {
    /// Name in scene files and on the command line.
    ///
    /// ```
    /// assert_eq!(fixshade::specular::CosQuadratic::NAME, "cos-quad");
    /// ```
    pub const NAME: &'static str = "cos-quad";
}

impl Specular for CosQuadratic {
    type Params = CosQuadParams;

    /// σ = (n + 1)/3 and the start of the zero region, 1 − 1/σ.
    fn prepare(n: Q16_16) -> CosQuadParams {
        let sigma = sigma_q23(n_bits(n));
        CosQuadParams {
            sigma,
            d0: zero_from(sigma, 23),
        }
    }

    #[inline]
    fn eval(p: &CosQuadParams, c: i32) -> i32 {
        let (_, d) = split(c);
        match cos_quad_base(p.sigma, p.d0, d) {
            // u ≤ 2^30: u² ≤ 2^60; result ≤ 2^30.
            Some(u) => ((u * u + (1 << 29)) >> 30) as i32,
            None => 0,
        }
    }
}

/// Parameters of [`CosQuadraticEnergy`]: √k and √k·σ with k = (n + 6)/24.55, and the
/// zero region of [`CosQuadratic`].
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{CosQuadraticEnergy, Specular};
/// let p = CosQuadraticEnergy::prepare(Q16_16::from_int(1000));
/// // k = 1006/24.55 ≈ 40.98: far above the Q2.30 range.
/// assert_eq!(p.peak_q30() >> 30, 40);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct CosQuadEnergyParams {
    /// √k, Q.29 (≤ 6.41·2^29 < 2^32).
    r: u32,
    /// √k·σ, Q.26 (≤ 2137·2^26 < 2^38).
    w: u64,
    /// Smallest d = 1 − c (Q.30) with σ·d ≥ 1 (σ in Q9.23 as in [`CosQuadratic`]).
    d0: u32,
}

impl CosQuadEnergyParams {
    /// The peak value `k = (n + 6)/24.55` (the value at c = 1) in Q.30, unsaturated,
    /// as `√k` squared (within 2⁻²⁶ of the exact k).
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::specular::{CosQuadraticEnergy, Specular};
    /// let p = CosQuadraticEnergy::prepare(Q16_16::ONE);
    /// let k = p.peak_q30() as i64; // 7/24.55 ≈ 0.285
    /// assert!((k - (7i64 << 30) * 20 / 491).abs() < 64);
    /// ```
    pub const fn peak_q30(&self) -> u64 {
        let r = self.r as u64;
        // r < 6.41·2^29: r² < 41·2^58 < 2^63.4 (Q.58).
        (r * r + (1 << 27)) >> 28
    }
}

/// Seed 002's energy-conserving form (§2.5, (2.26)):
/// `(n + 6)/24.55 · (σ·(c − 1) + 1)²`, zero in the same region as [`CosQuadratic`].
///
/// The factor k = (n + 6)/24.55 = 20·(n + 6)/491 makes the directional-hemispherical
/// reflectance of the lobe at most 1 (the seed's claim, to be measured on the host);
/// it exceeds 1 for n > 18.55 and reaches ≈ 40.98 at n = 1000, so the peak is **not**
/// clamped to 1 — that is the point of the normalisation. It does not fit Q2.30
/// either, whose largest value is just below 2: [`Specular::eval`] saturates at
/// `i32::MAX` (2 − 2⁻³⁰), so for n > 43.1 (k > 2) the top of the highlight is cut flat
/// where `k·u² ≥ 2`; [`CosQuadraticEnergy::eval_wide`] returns the full value in a
/// `u64` Q.30 (< 41·2³⁰ < 2³⁶) for callers that carry it. Output range of `eval`:
/// [0, 2 − 2⁻³⁰].
///
/// The factor is folded in by `prepare`: with `v = √k − (√k·σ)·d` (d = 1 − c) the
/// result is `v²`: two multiplies (`w·d`, 38×30-bit, `UMULL` + `MLA` on Cortex-M4,
/// and `v·v`, 32×32→64), no division, none in the zero region — the cost of
/// [`CosQuadratic`]. Error against the f64 formula ≤ 16 LSB (2⁻³⁰) below saturation
/// (`v` is within about 2⁻²⁹ and `2v ≤ 2√2` there) and ≤ 64 LSB for
/// [`CosQuadraticEnergy::eval_wide`] (`2v ≤ 2√41`).
///
/// ```
/// use fixshade::fixed::Q16_16;
/// use fixshade::specular::{CosQuadraticEnergy, Specular};
/// let p = CosQuadraticEnergy::prepare(Q16_16::from_int(2)); // k = 8/24.55, σ = 1
/// let v = CosQuadraticEnergy::eval(&p, 1 << 29) as i64; // k·(1/2)² ≈ 0.08147
/// assert!((v - (8i64 << 30) * 20 / 491 / 4).abs() < 64);
/// let big = CosQuadraticEnergy::prepare(Q16_16::from_int(1000));
/// assert_eq!(CosQuadraticEnergy::eval(&big, 1 << 30), i32::MAX); // saturated
/// assert!(CosQuadraticEnergy::eval_wide(&big, 1 << 30) > 40 << 30);
/// assert_eq!(CosQuadraticEnergy::NAME, "cos-quad-energy");
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct CosQuadraticEnergy;

impl CosQuadraticEnergy {
    /// Name in scene files and on the command line.
    ///
    /// ```
    /// assert_eq!(fixshade::specular::CosQuadraticEnergy::NAME, "cos-quad-energy");
    /// ```
    pub const NAME: &'static str = "cos-quad-energy";

    /// The unsaturated value `k·max(0, 1 − σ·(1 − c))²` in Q.30, at most
    /// `k ≤ 40.98` (< 2³⁶). [`Specular::eval`] is this value saturated to `i32::MAX`.
    ///
    /// ```
    /// use fixshade::fixed::Q16_16;
    /// use fixshade::specular::{CosQuadraticEnergy, Specular};
    /// let p = CosQuadraticEnergy::prepare(Q16_16::from_int(100));
    /// assert_eq!(CosQuadraticEnergy::eval_wide(&p, 1 << 30), p.peak_q30());
    /// assert_eq!(CosQuadraticEnergy::eval_wide(&p, 1 << 29), 0);
    /// ```
    #[inline]
    pub fn eval_wide(p: &CosQuadEnergyParams, c: i32) -> u64 {
        let (_, d) = split(c);
        if d >= p.d0 as u64 {
            return 0;
        }
        // d < d0 ≈ 2^30/σ, so w·d (Q.56) < √k·2^56·(1 + 2^-20) < 2^59; v (Q.29) ≤ r.
        let v = (p.r as u64).saturating_sub((p.w * d + (1 << 26)) >> 27);
        // v ≤ r < 6.41·2^29: v² < 41·2^58 < 2^63.4 (Q.58); result Q.30 ≤ k·2^30 < 2^36.
        (v * v + (1 << 27)) >> 28
    }
}

impl Specular for CosQuadraticEnergy {
    type Params = CosQuadEnergyParams;

    /// √k and √k·σ from exact integer square roots of the rationals
    /// k = 20·(n + 6)/491 and k·σ² = 20·(n + 6)·(n + 1)²/4419, and the zero region.
    fn prepare(n: Q16_16) -> CosQuadEnergyParams {
        let nb = n_bits(n) as u128;
        let n6 = nb + (6 << 16); // (n + 6)·2^16 < 2^26
        let n1 = nb + (1 << 16); // (n + 1)·2^16 < 2^26
                                 // √k in Q.29: k·2^58 = 20·(n + 6)·2^16·2^42/491 < 2^31·2^42 = 2^73.
        let k58 = ((20 * n6) << 42) / 491;
        // Round to nearest: isqrt(4x) = floor(2√x), then halve with rounding.
        let r = (isqrt_u128(k58 << 2) + 1) >> 1;
        // √k·σ in Q.26: k·σ²·2^52 = 20·(n+6)·(n+1)²·2^48 / (491·9·2^48) · 2^52
        //   = 20·n6·n1²·2^4 / 4419, numerator < 2^31·2^52·2^4 = 2^87.
        let ks2 = (20 * n6 * n1 * n1 * 16) / 4419;
        let w = (isqrt_u128(ks2 << 2) + 1) >> 1;
        let sigma = sigma_q23(n_bits(n));
        CosQuadEnergyParams {
            r: r as u32,
            w: w as u64,
            d0: zero_from(sigma, 23),
        }
    }

    #[inline]
    fn eval(p: &CosQuadEnergyParams, c: i32) -> i32 {
        Self::eval_wide(p, c).min(i32::MAX as u64) as i32
    }

    /// The unsaturated value (the inherent [`CosQuadraticEnergy::eval_wide`]): the
    /// lighting stage uses it, so highlights brighter than 1 reach the colour clamp.
    #[inline]
    fn eval_wide(p: &CosQuadEnergyParams, c: i32) -> u64 {
        CosQuadraticEnergy::eval_wide(p, c)
    }
}

// The f64 references are test-only (the brief allows f64 under `cfg(test)`); clippy
// exempts `#[test]` functions but not their helpers.
#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    extern crate std;
    use super::*;
    use crate::math::pow_q30;
    use std::println;
    use std::vec::Vec;

    const ONE_F: f64 = (1u64 << 30) as f64;
    const LSB: f64 = 1.0 / ONE_F;
    /// The largest Q2.30 value, where `eval` of the energy form saturates.
    const SAT: f64 = i32::MAX as f64 / ONE_F;
    const NS: [i32; 11] = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1000];

    fn q(v: i32) -> f64 {
        v as f64 / ONE_F
    }

    fn nf(n: Q16_16) -> f64 {
        n.to_bits() as f64 / 65536.0
    }

    fn a_f64(n: f64) -> f64 {
        if n <= 1.0 {
            return 0.0;
        }
        let t = ((n - 1.0) / n).sqrt();
        (t.powf(n - 1.0) - 1.0) / (t - 1.0)
    }

    fn schlick_f(n: f64, c: f64) -> f64 {
        c / (n - n * c + c)
    }
    fn schlick_mod_f(n: f64, c: f64) -> f64 {
        c / (0.5 * n * (1.0 - c * c) + n - n * c + c)
    }
    fn quadratic_f(n: f64, c: f64) -> f64 {
        let a = a_f64(n);
        (a * c * c + (1.0 - a) * c).max(0.0)
    }
    fn cos_quad_f(n: f64, c: f64) -> f64 {
        let s = (n + 1.0) / 3.0;
        if c < (s - 1.0) / s {
            0.0
        } else {
            (s * (c - 1.0) + 1.0).powi(2)
        }
    }
    fn energy_f(n: f64, c: f64) -> f64 {
        (n + 6.0) / 24.55 * cos_quad_f(n, c)
    }

    /// One model under test: its name, fixed-point evaluation (prepare + eval) and
    /// its own formula in f64 (as `eval` returns it, saturation included).
    struct Model {
        name: &'static str,
        fixed: fn(Q16_16, &[i32]) -> Vec<i32>,
        formula: fn(f64, f64) -> f64,
        /// Largest value `eval` may return for this n (Q2.30 bits).
        bound: fn(f64) -> i32,
        /// Tolerance against the f64 formula, in Q2.30 LSBs.
        tol_lsb: f64,
    }

    fn run<S: Specular>(n: Q16_16, cs: &[i32]) -> Vec<i32> {
        let p = S::prepare(n);
        cs.iter().map(|c| S::eval(&p, *c)).collect()
    }

    fn models() -> [Model; 5] {
        [
            Model {
                name: Schlick::NAME,
                fixed: run::<Schlick>,
                formula: schlick_f,
                bound: |_| 1 << 30,
                tol_lsb: 1.0,
            },
            Model {
                name: SchlickModified::NAME,
                fixed: run::<SchlickModified>,
                formula: schlick_mod_f,
                bound: |_| 1 << 30,
                tol_lsb: 16.0,
            },
            Model {
                name: Quadratic::NAME,
                fixed: run::<Quadratic>,
                formula: quadratic_f,
                bound: |_| 1 << 30,
                tol_lsb: 40.0,
            },
            Model {
                name: CosQuadratic::NAME,
                fixed: run::<CosQuadratic>,
                formula: cos_quad_f,
                bound: |_| 1 << 30,
                tol_lsb: 40.0,
            },
            Model {
                name: CosQuadraticEnergy::NAME,
                fixed: run::<CosQuadraticEnergy>,
                formula: |n, c| energy_f(n, c).min(SAT),
                bound: |_| i32::MAX,
                tol_lsb: 16.0,
            },
        ]
    }

    /// A dense sweep of c: uniform over [0, 1], uniform over the highlight
    /// (1 − c ≤ 40/n), and every value within 256 LSB of each end.
    fn sweep(n: f64) -> Vec<i32> {
        let mut cs = Vec::new();
        let one = 1i64 << 30;
        for k in 0..=(1 << 14) {
            cs.push(((one * k) >> 14) as i32);
        }
        let span = (40.0 / n).min(1.0);
        for k in 0..=(1 << 14) {
            cs.push(((1.0 - span * k as f64 / 16384.0) * ONE_F).round() as i32);
        }
        for k in 0..=256i32 {
            cs.push(k);
            cs.push((1 << 30) - k);
        }
        cs.sort_unstable();
        cs.dedup();
        cs
    }

    fn n_values() -> Vec<Q16_16> {
        let mut v: Vec<Q16_16> = NS.iter().map(|n| Q16_16::from_int(*n)).collect();
        // Fractional exponents too (interpolated a, non-dyadic σ).
        for (num, den) in [(3, 2), (7, 3), (101, 10), (1999, 2), (333_333, 1000)] {
            v.push(Q16_16::from_ratio(num, den));
        }
        v
    }

    #[test]
    fn specular_a_table_matches_f64_every_entry() {
        assert_eq!(core::mem::size_of_val(&QUADRATIC_A), 4000);
        let mut worst = 0f64;
        for n in 1..=1000u32 {
            let want = a_f64(n as f64) * (1u64 << 22) as f64;
            let got = QUADRATIC_A[n as usize - 1] as f64;
            let e = (got - want).abs();
            assert!(e <= 0.5 + 1e-3, "a({n}): {got} vs {want}");
            worst = worst.max(e);
        }
        println!("a(n) table: worst |entry − f64| = {worst:.4} LSB of Q10.22");
        assert_eq!(QUADRATIC_A[0], 0);
        assert_eq!(QUADRATIC_A[1], 1 << 22);
        assert!(QUADRATIC_A.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(QUADRATIC_A[999] >> 22, 786); // a(1000) ≈ 786.6 < 2^10
    }

    #[test]
    fn specular_a_interpolation_error() {
        // Relative error of the interpolated a(n) for fractional n, by range.
        let mut worst = [0f64; 3];
        let mut abs12 = 0f64;
        for nb in (1 << 16)..(1000 << 16) {
            if nb % 97 != 0 || nb & 0xFFFF == 0 {
                continue;
            }
            let n = Q16_16::from_bits(nb);
            let got = quadratic_a(n) as f64 / (1u64 << 22) as f64;
            let want = a_f64(nf(n));
            let r = if nf(n) < 2.0 {
                abs12 = abs12.max((got - want).abs());
                0
            } else if nf(n) < 10.0 {
                1
            } else {
                2
            };
            worst[r] = worst[r].max(((got - want) / want).abs());
        }
        println!(
            "a(n) interpolation: n in (1,2): max abs err {abs12:.4} (rel {:.3e}); \
             [2,10): rel {:.3e}; [10,1000): rel {:.3e}",
            worst[0], worst[1], worst[2]
        );
        assert!(abs12 < 0.1);
        assert!(worst[1] < 1e-2 && worst[2] < 1e-4);
    }

    #[test]
    fn specular_exact_points() {
        let one = 1 << 30;
        for n in n_values() {
            let n_f = nf(n);
            // c = 1 → 1 (the energy form: its factor k, saturated).
            assert_eq!(run::<Schlick>(n, &[one]), [one]);
            assert_eq!(run::<SchlickModified>(n, &[one]), [one]);
            assert_eq!(run::<Quadratic>(n, &[one]), [one]);
            assert_eq!(run::<CosQuadratic>(n, &[one]), [one]);
            let p = CosQuadraticEnergy::prepare(n);
            let k = (n_f + 6.0) / 24.55;
            assert!((p.peak_q30() as f64 / ONE_F - k).abs() < 4.0 * LSB * k);
            assert_eq!(CosQuadraticEnergy::eval_wide(&p, one), p.peak_q30());
            // c = 0 → 0 where the formula says so.
            assert_eq!(run::<Schlick>(n, &[0]), [0]);
            assert_eq!(run::<SchlickModified>(n, &[0]), [0]);
            assert_eq!(run::<Quadratic>(n, &[0]), [0]);
            if n_f >= 2.0 {
                assert_eq!(run::<CosQuadratic>(n, &[0]), [0]);
                assert_eq!(run::<CosQuadraticEnergy>(n, &[0]), [0]);
            } else {
                let s = (n_f + 1.0) / 3.0;
                let got = q(run::<CosQuadratic>(n, &[0])[0]);
                assert!((got - (1.0 - s).powi(2)).abs() < 40.0 * LSB);
            }
        }
        // n = 1: Schlick and the quadratic are exactly c; cos-quad at 0 is 1/9.
        let n1 = Q16_16::ONE;
        let cs: Vec<i32> = (0..=64).map(|k| k << 24).collect();
        assert_eq!(run::<Schlick>(n1, &cs), cs);
        assert_eq!(run::<Quadratic>(n1, &cs), cs);
        let ninth = run::<CosQuadratic>(n1, &[0])[0];
        assert!((ninth - (1 << 30) / 9).abs() <= 40); // σ = 2/3 rounded to Q9.23
                                                      // Out-of-range c is clamped to [0, 1].
        let p = <Schlick>::prepare(Q16_16::from_int(8));
        assert_eq!(<Schlick>::eval(&p, -5), 0);
        assert_eq!(<Schlick>::eval(&p, i32::MAX), one);
    }

    #[test]
    fn specular_monotone_nonnegative_bounded() {
        for n in n_values() {
            let cs = sweep(nf(n));
            for m in models() {
                let vs = (m.fixed)(n, &cs);
                let bound = (m.bound)(nf(n));
                for (i, v) in vs.iter().enumerate() {
                    assert!(*v >= 0, "{} n={} c={}: {v}", m.name, nf(n), cs[i]);
                    assert!(*v <= bound, "{} n={} c={}: {v}", m.name, nf(n), cs[i]);
                    if i > 0 {
                        assert!(
                            vs[i - 1] <= *v,
                            "{} n={} not monotone at c={}: {} > {v}",
                            m.name,
                            nf(n),
                            cs[i],
                            vs[i - 1]
                        );
                    }
                }
            }
            // The wide energy value is monotone too and bounded by its peak.
            let p = CosQuadraticEnergy::prepare(n);
            let w: Vec<u64> = cs
                .iter()
                .map(|c| CosQuadraticEnergy::eval_wide(&p, *c))
                .collect();
            assert!(w.windows(2).all(|x| x[0] <= x[1]));
            assert!(*w.last().unwrap() == p.peak_q30());
        }
    }

    #[test]
    fn specular_matches_own_f64_formula() {
        let mut failed = false;
        for m in models() {
            let mut worst = 0f64;
            let mut at = (0.0, 0.0);
            for n in NS {
                let n = Q16_16::from_int(n);
                let cs = sweep(nf(n));
                let vs = (m.fixed)(n, &cs);
                for (c, v) in cs.iter().zip(vs.iter()) {
                    let want = (m.formula)(nf(n), q(*c));
                    let e = (q(*v) - want).abs() / LSB;
                    if e > worst {
                        worst = e;
                        at = (nf(n), q(*c));
                    }
                }
            }
            println!(
                "{:>16}: max |fixed − own f64 formula| = {worst:.2} LSB = {:.2e} at n={} c={:.8} (tolerance {} LSB)",
                m.name,
                worst * LSB,
                at.0,
                at.1,
                m.tol_lsb
            );
            failed |= worst > m.tol_lsb;
        }
        assert!(!failed);
        // The unsaturated energy value, relative to its peak.
        let mut worst = 0f64;
        for n in NS {
            let n = Q16_16::from_int(n);
            let p = CosQuadraticEnergy::prepare(n);
            for c in sweep(nf(n)) {
                let got = CosQuadraticEnergy::eval_wide(&p, c) as f64 / ONE_F;
                let want = energy_f(nf(n), q(c));
                worst = worst.max((got - want).abs());
            }
        }
        println!("cos-quad-energy eval_wide: max abs err {worst:.2e}");
        assert!(worst < 64.0 * LSB);
    }

    #[test]
    fn specular_hard_cases() {
        let one = 1 << 30;
        for n in [Q16_16::ONE, Q16_16::from_int(1000)] {
            let n_f = nf(n);
            for c in [one - 1, one - 2, 1, 2] {
                for m in models() {
                    let v = q((m.fixed)(n, &[c])[0]);
                    let want = (m.formula)(n_f, q(c));
                    assert!(
                        (v - want).abs() <= m.tol_lsb * LSB,
                        "{} n={n_f} c={c}: {v} vs {want}",
                        m.name
                    );
                }
            }
        }
        // n = 1000, one LSB below 1: Schlick = c/(1000·2^-30 + c) ≈ 1 − 999·2^-30.
        let p = <Schlick>::prepare(Q16_16::from_int(1000));
        assert_eq!(<Schlick>::eval(&p, one - 1), one - 1000);
        // cos-quad: σ = 1001/3, (1 − σ·2^-30)² ≈ 1 − 2σ·2^-30.
        let p = CosQuadratic::prepare(Q16_16::from_int(1000));
        assert!((CosQuadratic::eval(&p, one - 1) - (one - 667)).abs() <= 1);
        // exact c^1000 one LSB below 1, for comparison: 1 − 1000·2^-30.
        assert!((pow_q30(one - 1, Q16_16::from_int(1000)) - (one - 1000)).abs() <= 1);
        // The energy form saturates at n = 1000 but not at n = 1.
        let p = CosQuadraticEnergy::prepare(Q16_16::from_int(1000));
        assert_eq!(CosQuadraticEnergy::eval(&p, one - 1), i32::MAX);
        let p = CosQuadraticEnergy::prepare(Q16_16::ONE);
        assert!(CosQuadraticEnergy::eval(&p, one) < one / 3);
    }

    /// Host-only report: each fixed-point model against the f64 cⁿ it approximates.
    /// No assertions on the seed's claims; run with `--nocapture` to see the table.
    #[test]
    fn specular_error_vs_pow() {
        type Eval = fn(Q16_16, &[i32]) -> Vec<i32>;
        let all: [(&str, Eval); 6] = [
            ("exact", run::<BlinnExact>),
            (Schlick::NAME, run::<Schlick>),
            (SchlickModified::NAME, run::<SchlickModified>),
            (Quadratic::NAME, run::<Quadratic>),
            (CosQuadratic::NAME, run::<CosQuadratic>),
            (CosQuadraticEnergy::NAME, run::<CosQuadraticEnergy>),
        ];
        println!(
            "model            n     max|f−cⁿ|   at c        maxrel(cⁿ≥0.6)  maxrel(0.1≤cⁿ<0.6)"
        );
        for (name, eval) in all {
            for n in NS {
                let n_f = n as f64;
                // Uniform in c, uniform over x = n(1 − c) ∈ [0, 30], and uniform over
                // the epicentre cⁿ ≥ 0.6 (c ≥ 0.6^(1/n)).
                let mut cs = Vec::new();
                for k in 0..=(1 << 16) {
                    cs.push((((1i64 << 30) * k) >> 16) as i32);
                }
                let span = (30.0 / n_f).min(1.0);
                let epi = 1.0 - 0.6f64.powf(1.0 / n_f);
                for k in 0..=(1 << 16) {
                    let t = k as f64 / 65536.0;
                    cs.push(((1.0 - span * t) * ONE_F).round() as i32);
                    cs.push(((1.0 - epi * t) * ONE_F).round() as i32);
                }
                let vs = eval(Q16_16::from_int(n), &cs);
                let (mut abs, mut at, mut rel_epi, mut rel_decay) = (0f64, 0f64, 0f64, 0f64);
                for (c, v) in cs.iter().zip(vs.iter()) {
                    let cf = q(*c);
                    let exact = cf.powi(n);
                    let e = (q(*v) - exact).abs();
                    if e > abs {
                        abs = e;
                        at = cf;
                    }
                    if exact >= 0.6 {
                        rel_epi = rel_epi.max(e / exact);
                    } else if exact >= 0.1 {
                        rel_decay = rel_decay.max(e / exact);
                    }
                }
                println!(
                    "{name:<16} {n:>4}  {abs:>10.3e}  {at:<10.6}  {:>12.4}%  {:>14.4}%",
                    rel_epi * 100.0,
                    rel_decay * 100.0
                );
            }
        }
    }
}
