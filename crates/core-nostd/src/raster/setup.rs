//! Triangle setup: sort the vertices, take one reciprocal of the determinant, and
//! derive the constant per-triangle increments of every attribute (seed 000 §2.1,
//! DESIGN.md method 1).
//!
//! With `dx1 = x1 − x0`, `dy1 = y1 − y0`, … (Q12.4) and `det = dx1·dy2 − dx2·dy1`,
//! an attribute `a` changes per pixel by
//! `Gx = 16·(Δa1·dy2 − Δa2·dy1) / det` along a row and `Gy = 16·(Δa2·dx1 − Δa1·dx2) / det`
//! down a column: the seed's `dI/dx`, the same on every scanline.
//!
//! Three ways compute the increments; [`setup`] takes the first whose error bound
//! holds, so every triangle gets the bound below:
//!
//! - **Small** (`small_increments`, every triangle within 128 pixels of its top
//!   vertex whose colours and depth change by less than 128 and 1024 steps across
//!   it): a 16-bit table-and-Newton reciprocal of the determinant
//!   ([`crate::math::recip_q31_16`]) and 32-bit products (`MULS` on ARMv6-M); extra
//!   error below 2¹¹ units (colours) and 2¹⁴ (depth), as the next path.
//! - **32-bit** (`setup_fast`, every other ordinary triangle): `|det|` cut to a 31-bit
//!   mantissa, one table-and-Newton reciprocal ([`crate::math::recip_q61`], no
//!   division), the four barycentric basis values `±16·d/det` from it, and each
//!   increment from two 32×32-bit products ([`crate::math::mul_wide`]). Its extra
//!   error, at most 2¹¹ units (colours) or 2¹⁴ units (depth) over any triangle it
//!   takes, is checked per triangle before it is used.
//! - **Exact** (`setup_with_det_div`: slivers, whose increments are huge and
//!   cannot afford it): |dx|, |dy| < 2¹⁷ (guard band), so `det` < 2³⁵; |Δa| ≤ 2³²
//!   (depth), so each numerator is below 2⁵⁴ and fits `i64`. The quotient uses one
//!   reciprocal `inv = ⌊2⁶² / |det|⌋` and an `i128` product; its error is at most
//!   `|num|/2⁶² + ½ ≤ 0.51` of the attribute's last bit.
//!
//! Every attribute value the rasterizer produces lies on the lattice
//! `V(x, y) = A + (x − xa)·Gx + (y − ya)·Gy` (wrapping `i32`) anchored at the pixel
//! `(xa, ya)` that holds the top vertex's first row. The anchor value `A` is the
//! exact plane value there to within one unit plus the rounding bias. Against the
//! exact plane the lattice is off by at most `0.51·(|x − xa| + |y − ya|) + 1` units
//! from the exact path and `0.5·(|x − xa| + |y − ya|) + 2¹¹ + 1` (colours) from the
//! 32-bit one, i.e. below 6300 units (0.1 of an output step) anywhere inside a
//! triangle of the 4095-pixel range: the interpolated colour is within
//! 0.5 + 0.1 < 1 output step of the exact value (the bound the accuracy tests
//! check). Depth: below 2¹⁴ + 4200 units, 0.32 of a u16 step, so the stored u16 is
//! within 1 of the exact one.

use super::edge::{first_row, is_small};
use super::vertex::ScreenVertex;
use crate::arrays;
use crate::divide::{wide_recip, Divide, Exact};
use crate::math::{leading_zeros, mul_i64_wide, mul_wide, recip_q31_16, recip_q61};

/// Number of interpolated attributes: three colour channels and depth.
pub const ATTRS: usize = 4;

/// Rounding bias added to the anchor so that `value >> 16` rounds to nearest.
pub const ROUND_BIAS: i32 = 1 << 15;

/// A triangle ready for the edge walker.
///
/// ```
/// use fixshade::raster::setup::{setup, ROUND_BIAS};
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32, r: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [r << 16, 0, 0] };
/// // Red 0 at the left, 160 at x = 16 pixels: 10 per pixel, constant over the triangle.
/// let s = setup([v(0, 16, 0), v(0, 0, 0), v(16, 0, 160)]).unwrap();
/// assert_eq!(s.v[0].y, 0); // sorted: top first
/// assert_eq!(s.gx[0], 10 << 16);
/// assert_eq!(s.gy[0], 0);
/// assert_eq!(s.at(3, 2)[0], (35 << 16) + ROUND_BIAS); // 10·3.5 at the pixel centre
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Setup {
    /// Vertices sorted by y (then x): top, middle, bottom.
    pub v: [ScreenVertex; 3],
    /// True if the middle vertex lies left of the long edge top→bottom.
    pub mid_left: bool,
    /// Per-pixel increments along x (colour channels in Q.16 output units, depth Q16.16).
    pub gx: [i32; ATTRS],
    /// Per-row increments along y.
    pub gy: [i32; ATTRS],
    /// Lattice anchor pixel.
    pub anchor: (i32, i32),
    /// Attribute values at the anchor pixel centre, rounding bias included.
    pub a: [i32; ATTRS],
    /// True when every increment is its true value; false when one was kept modulo
    /// 2³² (a sliver whose attribute changes by more than 2³¹ units per pixel).
    pub unwrapped: bool,
}

impl Setup {
    /// Attribute values at pixel `(x, y)` of the lattice (wrapping arithmetic: the
    /// result is exact modulo 2³², and the true value at a covered pixel fits `i32`,
    /// so it is exact there).
    #[inline]
    pub fn at(&self, x: i32, y: i32) -> [i32; ATTRS] {
        let dx = x.wrapping_sub(self.anchor.0);
        let dy = y.wrapping_sub(self.anchor.1);
        arrays::from_fn(|k| {
            self.a[k]
                .wrapping_add(dx.wrapping_mul(self.gx[k]))
                .wrapping_add(dy.wrapping_mul(self.gy[k]))
        })
    }
}

fn attrs(v: &ScreenVertex) -> [i64; ATTRS] {
    [v.c[0] as i64, v.c[1] as i64, v.c[2] as i64, v.z as i64]
}

/// The shared core of a triangle's setup: the edge deltas from the top vertex and the
/// one reciprocal of the determinant, signed. Used by [`setup`] and by the Phong
/// planes, so a Phong triangle divides once, like any other.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Det {
    dx1: i64,
    dy1: i64,
    dx2: i64,
    dy2: i64,
    /// `sign(det)·⌊2⁶²/|det|⌋`: |inv| ≤ 2⁶² fits `i64`, so each increment is one
    /// signed 64×64→128 multiply.
    inv: i64,
}

impl Det {
    /// `None` for a zero-area triangle. Vertices sorted, in the guard band.
    ///
    /// The reciprocal goes through `D`: [`Exact`] keeps the full `⌊2⁶²/|det|⌋`
    /// (bit-identical to the setup before the seam); any other variant rounds
    /// `|det|` up to its mantissa and takes [`wide_recip`]: relative error at most
    /// `η = 2^(1−b) + (2E + 2)·2^b/2³⁰` (see there), never an over-estimate. Every
    /// increment inherits it, so a covered pixel's value moves from the exact one
    /// towards the top vertex's by at most `η` of their difference: it stays in
    /// range, within `η` times the triangle's attribute range of the exact value.
    fn new<D: Divide>(p: [(i32, i32); 3]) -> Option<Det> {
        let (dx1, dy1) = ((p[1].0 - p[0].0) as i64, (p[1].1 - p[0].1) as i64);
        let (dx2, dy2) = ((p[2].0 - p[0].0) as i64, (p[2].1 - p[0].1) as i64);
        let det = dx1 * dy2 - dx2 * dy1;
        if det == 0 {
            return None;
        }
        // |det| ≥ 1 and < 2^35: a u64 division (one hardware divide on 64-bit hosts).
        // Both branches give 1 ≤ inv ≤ 2^62: fits i64, and so does its negation.
        let inv = if D::is_exact() {
            ((1u64 << 62) / det.unsigned_abs()) as i64
        } else {
            // ≤ 2^62 (the mantissa is at least 1), at least 1: the sign survives.
            wide_recip::<D>(det.unsigned_abs() as u128).scaled(62) as i64
        };
        Some(Det {
            dx1,
            dy1,
            dx2,
            dy2,
            inv: if det < 0 { -inv } else { inv },
        })
    }

    /// The per-pixel increments `(Gx, Gy)` of an attribute that changes by `d1` and
    /// `d2` from the top vertex to the others, with `extra` more fraction bits,
    /// rounded. |d| ≤ 2³², so each numerator is below 2⁵⁴ and, with |inv| ≤ 2⁶², the
    /// i128 product below 2¹¹⁶; the quotient is below 2^(55 + extra).
    #[inline]
    pub(crate) fn gradient(&self, d1: i64, d2: i64, extra: u32) -> (i128, i128) {
        let sh = 62 - extra;
        // |inv| ≤ 2^62 and |num| < 2^54 are both i64: one widening multiply (four
        // 32×32→64-bit products on ARMv6-M instead of six library calls).
        let inv = self.inv;
        let quot = |num: i64| (mul_i64_wide(num, inv) + (1 << (sh - 1))) >> sh;
        (
            quot(16 * (d1 * self.dy2 - d2 * self.dy1)),
            quot(16 * (d2 * self.dx1 - d1 * self.dx2)),
        )
    }
}

/// Sets up a triangle. Returns `None` for a zero-area triangle. Coordinates must lie
/// in the guard band (|x|, |y| < 2¹⁶); the clip stage guarantees it.
///
/// An increment is kept modulo 2³² (`i32` wrapping): a sliver may change an attribute
/// by more than 2³¹ units per pixel, but the lattice arithmetic is exact modulo 2³²
/// and the true value at every covered pixel fits, so the result there is still exact
/// to the bound above.
///
/// ```
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32| ScreenVertex { x, y, z: 0, c: [0; 3] };
/// assert!(setup([v(0, 0), v(32, 0), v(0, 32)]).is_some());
/// assert!(setup([v(0, 0), v(16, 16), v(32, 32)]).is_none()); // collinear: zero area
/// ```
pub fn setup(v: [ScreenVertex; 3]) -> Option<Setup> {
    setup_div::<Exact>(v)
}

/// [`setup`] with the determinant's reciprocal taken through the divider `D`
/// ([`setup`] is `setup_div::<Exact>`).
///
/// ```
/// use fixshade::divide::{Exact, ShiftAdd};
/// use fixshade::raster::setup::{setup, setup_div};
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32, r: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [r << 16, 0, 0] };
/// let t = [v(0, 0, 0), v(37, 5, 200), v(3, 29, 90)];
/// assert_eq!(setup_div::<Exact>(t), setup(t));
/// // An 8-term shift-and-add reciprocal never over-estimates: increments shrink a little.
/// let (e, a) = (setup(t).unwrap(), setup_div::<ShiftAdd<8>>(t).unwrap());
/// assert!(a.gx[0].abs() <= e.gx[0].abs() && a.gx[0].abs() * 10 > e.gx[0].abs() * 9);
/// ```
#[cfg_attr(not(target_os = "none"), inline(always))]
pub fn setup_div<D: Divide>(v: [ScreenVertex; 3]) -> Option<Setup> {
    if D::is_exact() {
        return setup_fast(v);
    }
    setup_with_det_div::<D>(v).map(|(s, _)| s)
}

/// The indices of three vertices sorted by `(y, x)`, from three compare-exchanges.
/// Two vertices with equal keys coincide, so the triangle has zero area and is
/// rejected whatever their order.
#[inline(always)]
fn order3(v: [&ScreenVertex; 3]) -> [usize; 3] {
    // (y, x) compared in order: two 32-bit comparisons, no 64-bit key.
    let k = [(v[0].y, v[0].x), (v[1].y, v[1].x), (v[2].y, v[2].x)];
    let mut o = [0, 1, 2];
    if k[o[1]] < k[o[0]] {
        o.swap(0, 1);
    }
    if k[o[2]] < k[o[1]] {
        o.swap(1, 2);
        if k[o[1]] < k[o[0]] {
            o.swap(0, 1);
        }
    }
    o
}

/// `v` sorted by `(y, x)` ([`order3`]).
#[inline(always)]
fn sort3(v: [ScreenVertex; 3]) -> [ScreenVertex; 3] {
    let [a, b, c] = order3([&v[0], &v[1], &v[2]]);
    [v[a], v[b], v[c]]
}

/// `2^k` for `k` < 63, from 32-bit shifts (a variable 64-bit shift is a helper call
/// on ARMv6-M).
#[inline(always)]
fn bit_i64(k: u32) -> i64 {
    if k < 32 {
        (1u32 << k) as i64
    } else {
        ((1u32 << (k - 32)) as i64) << 32
    }
}

/// Bit length of `v` (0 for 0).
#[inline(always)]
fn bit_len(v: u64) -> u32 {
    let hi = (v >> 32) as u32;
    if hi != 0 {
        64 - leading_zeros(hi)
    } else {
        32 - leading_zeros(v as u32)
    }
}

/// [`setup`] in 32-bit products: the setup of the exact divider without a 64-bit
/// division or an `i128` product, falling back to [`setup_with_det_div`] for the
/// triangles where its error bound does not hold (slivers, values outside the
/// documented ranges).
///
/// With `|det|` cut to a 31-bit mantissa `m` (`|det| = m·2^(bits − 31)`, relative
/// error below 2⁻³⁰) and `R = recip_q61(m)` (relative error below 2⁻²⁹), the four
/// **barycentric basis values** `16·dy₂/det`, `−16·dy₁/det`, `−16·dx₂/det` and
/// `16·dx₁/det` are `16·d·R` (below 2⁵², one [`mul_wide`] each) scaled by a common
/// `2^−t` to `i32`s `B` with the largest in [2²⁹, 2³⁰], rounded: basis value =
/// `B/2^S`, `S = 30 + bits − t`. An attribute that changes by `d₁`, `d₂` from the
/// top vertex then has `Gx = round((d₁·B₁ + d₂·B₂)/2^S)` and `Gy` alike: two more
/// products per increment. Depth deltas (33 bits) are taken in quarters.
///
/// Error of an increment against the exact one: the common relative error `ρ` of
/// `R` and the mantissa (|ρ| < 2⁻²⁸) scales the whole sum, so it costs `|Gx|·2⁻²⁸`
/// however the two terms cancel; the rounding of each `B` (½ unit) costs
/// `(|d₁| + |d₂|)·2^−(S+1)`; the quarters of a depth delta at most
/// `3·(|B₁| + |B₂|)/2^S`; the final rounding ½ unit. With `D` a bound of the
/// deltas and `E` of the pixel steps from the lattice anchor to any pixel of the
/// triangle's bounding box, the first three add at most about
/// `E·(|G|·2⁻²⁸ + D·2^−(S+1))` (depth: `+ E·2^(34 − S)`) units, and `|G| ≤ 2D·2³⁰/2^S`.
/// The fast path is taken only when, on bit lengths (which over-estimate), that is
/// below 2¹¹ units for the colours and 2¹⁴ (a quarter of a u16 step) for the
/// depth, and every increment fits `i32`; everything else takes the exact path.
/// Within the fast path the lattice is off the exact plane by at most
/// `0.5·(|x − xa| + |y − ya|) + 2¹¹ + 1` units for colours (the module's bound plus
/// 2⁻⁵ of a step) and `… + 2¹⁴ + 1` for depth.
#[cfg_attr(not(target_os = "none"), inline(always))]
pub(crate) fn setup_fast(v: [ScreenVertex; 3]) -> Option<Setup> {
    lattice_into::<Setup>([&v[0], &v[1], &v[2]])
}

/// A triangle set up for the constant-gradient fill: its vertex positions sorted
/// top to bottom and the lattice of its attributes — everything
/// [`span::Gradient`](super::span::Gradient) draws from, 76 bytes, without the
/// vertices' colours and depths. Built once per triangle, it is what a
/// frame drawn in bands keeps per triangle ([`crate::render::bands`]).
///
/// ```
/// use fixshade::raster::setup::Record;
/// // Caller-owned memory for records can be a static array.
/// static mut RECORDS: [Record; 4] = [Record::EMPTY; 4];
/// assert_eq!(core::mem::size_of::<Record>(), 76);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Record {
    /// Q12.4 positions of the top, middle and bottom vertex.
    pub(crate) xy: [(i32, i32); 3],
    /// As [`Setup::gx`].
    pub(crate) gx: [i32; ATTRS],
    /// As [`Setup::gy`].
    pub(crate) gy: [i32; ATTRS],
    /// The lattice's values at pixel (0, 0), modulo 2³² ([`Setup::at`]`(0, 0)`):
    /// a row's values at x = 0 are these plus the row times `gy`, without the
    /// anchor.
    pub(crate) origin: [i32; ATTRS],
    /// As [`Setup::mid_left`].
    pub(crate) mid_left: bool,
    /// As [`Setup::unwrapped`].
    pub(crate) unwrapped: bool,
}

impl Record {
    /// A placeholder, for initialising record arrays.
    pub const EMPTY: Record = Record {
        xy: [(0, 0); 3],
        gx: [0; ATTRS],
        gy: [0; ATTRS],
        origin: [0; ATTRS],
        mid_left: false,
        unwrapped: false,
    };

    /// The record of a set-up triangle.
    #[inline(always)]
    pub fn of(s: &Setup) -> Record {
        Record {
            xy: arrays::map(s.v, |p| (p.x, p.y)),
            gx: s.gx,
            gy: s.gy,
            origin: s.at(0, 0),
            mid_left: s.mid_left,
            unwrapped: s.unwrapped,
        }
    }
}

/// What the constant-gradient fill (`super::fill_gradient`) draws from: a
/// [`Record`], or a [`Setup`] (a triangle set up with another divider, drawn
/// without building a record: the same values, from its anchor).
pub(crate) trait Lattice {
    /// Q12.4 positions of the top, middle and bottom vertex.
    fn xy(&self) -> [(i32, i32); 3];
    /// Increments along x.
    fn gx(&self) -> &[i32; ATTRS];
    /// Increments along y.
    fn gy(&self) -> &[i32; ATTRS];
    /// As [`Setup::mid_left`].
    fn mid_left(&self) -> bool;
    /// As [`Setup::unwrapped`].
    fn unwrapped(&self) -> bool;
    /// The lattice's values at x = 0 of row `y` (wrapping: exact modulo 2³², as
    /// [`Setup::at`]).
    fn row_start(&self, y: i32) -> [i32; ATTRS];
}

/// The accessors of [`Lattice`] that read a field of the same name.
macro_rules! lattice_fields {
    () => {
        #[inline(always)]
        fn gx(&self) -> &[i32; ATTRS] {
            &self.gx
        }
        #[inline(always)]
        fn gy(&self) -> &[i32; ATTRS] {
            &self.gy
        }
        #[inline(always)]
        fn mid_left(&self) -> bool {
            self.mid_left
        }
        #[inline(always)]
        fn unwrapped(&self) -> bool {
            self.unwrapped
        }
    };
}

impl Lattice for Record {
    #[inline(always)]
    fn xy(&self) -> [(i32, i32); 3] {
        self.xy
    }
    lattice_fields!();
    #[inline(always)]
    fn row_start(&self, y: i32) -> [i32; ATTRS] {
        arrays::from_fn(|k| self.origin[k].wrapping_add(y.wrapping_mul(self.gy[k])))
    }
}

impl Lattice for Setup {
    #[inline(always)]
    fn xy(&self) -> [(i32, i32); 3] {
        arrays::map(self.v, |p| (p.x, p.y))
    }
    lattice_fields!();
    #[inline(always)]
    fn row_start(&self, y: i32) -> [i32; ATTRS] {
        let dy = y.wrapping_sub(self.anchor.1);
        arrays::from_fn(|k| {
            self.a[k]
                .wrapping_sub(self.anchor.0.wrapping_mul(self.gx[k]))
                .wrapping_add(dy.wrapping_mul(self.gy[k]))
        })
    }
}

/// The lattice of [`setup`] as a [`Record`] (see [`setup_fast`] for how it is
/// computed); `None` for a zero-area triangle.
#[cfg_attr(not(target_os = "none"), inline(always))]
pub(crate) fn lattice(v: [&ScreenVertex; 3]) -> Option<Record> {
    lattice_into::<Record>(v)
}

/// What [`lattice_into`] builds: a [`Record`] (the values at pixel (0, 0)) or a
/// [`Setup`] (the values at the anchor, with the vertices).
trait LatticeOut: Sized {
    /// From the exact setup, for what the fast path does not take.
    fn exact(s: Setup) -> Self;
    /// From the sorted vertices `t`, `m`, `b`, the middle vertex's side and the
    /// increments.
    fn build(tmb: [&ScreenVertex; 3], mid_left: bool, gx: [i32; ATTRS], gy: [i32; ATTRS]) -> Self;
}

impl LatticeOut for Record {
    #[inline(always)]
    fn exact(s: Setup) -> Self {
        Record::of(&s)
    }
    #[inline(always)]
    fn build(
        [t, m, b]: [&ScreenVertex; 3],
        mid_left: bool,
        gx: [i32; ATTRS],
        gy: [i32; ATTRS],
    ) -> Self {
        // The centre of pixel (0, 0) from the top vertex, in subpixels: |o| ≤
        // 2^16 + 8 (guard band).
        let a = values_at(t, &gx, &gy, (8 - t.x, 8 - t.y));
        Record {
            xy: [(t.x, t.y), (m.x, m.y), (b.x, b.y)],
            mid_left,
            gx,
            gy,
            origin: a,
            unwrapped: true,
        }
    }
}

impl LatticeOut for Setup {
    #[inline(always)]
    fn exact(s: Setup) -> Self {
        s
    }
    #[inline(always)]
    fn build(
        [t, m, b]: [&ScreenVertex; 3],
        mid_left: bool,
        gx: [i32; ATTRS],
        gy: [i32; ATTRS],
    ) -> Self {
        let anchor = (first_row(t.x), first_row(t.y));
        // The anchor's centre from the top vertex, in [0, 16) subpixels.
        let o = (16 * anchor.0 + 8 - t.x, 16 * anchor.1 + 8 - t.y);
        Setup {
            v: [*t, *m, *b],
            mid_left,
            gx,
            gy,
            anchor,
            a: values_at(t, &gx, &gy, o),
            unwrapped: true,
        }
    }
}

/// The lattice's values at the pixel centre `o` subpixels from the top vertex
/// `t` (|o| < 2¹⁷), rounding bias included: modulo 2³² by design (the depth is
/// unsigned).
#[inline(always)]
fn values_at(
    t: &ScreenVertex,
    gx: &[i32; ATTRS],
    gy: &[i32; ATTRS],
    o: (i32, i32),
) -> [i32; ATTRS] {
    let a0 = [t.c[0], t.c[1], t.c[2], t.z as i32];
    arrays::from_fn(|k| {
        a0[k]
            .wrapping_add(origin_offset(gx[k], gy[k], o.0, o.1))
            .wrapping_add(ROUND_BIAS)
    })
}

/// The lattice of [`setup`] built into `L` (see [`setup_fast`] for how it is
/// computed); `None` for a zero-area triangle.
#[inline(always)]
fn lattice_into<L: LatticeOut>(v: [&ScreenVertex; 3]) -> Option<L> {
    let order = order3(v);
    let [i0, i1, i2] = order;
    let (t, m, b) = (v[i0], v[i1], v[i2]);
    match small_increments([t, m, b]) {
        Small::Zero => return None,
        Small::Set { neg, gx, gy } => return Some(L::build([t, m, b], neg, gx, gy)),
        Small::Other => {}
    }
    // The exact path, for what the fast one does not take.
    let exact = || setup_with_det_div::<Exact>([*t, *m, *b]).map(|(s, _)| L::exact(s));
    // Colour channels outside [0, 2^30) (never from the vertex stage) take the exact
    // path; inside, every delta fits i32 with a bit to spare.
    let cs = t.c[0] | t.c[1] | t.c[2] | m.c[0] | m.c[1] | m.c[2] | b.c[0] | b.c[1] | b.c[2];
    if cs >> 30 != 0 {
        return exact();
    }
    let (dx1, dy1) = (m.x - t.x, m.y - t.y);
    let (dx2, dy2) = (b.x - t.x, b.y - t.y);
    // |d| < 2^17 (guard band): products below 2^34, det below 2^35. On ARMv6-M,
    // where a 64-bit product is four 16×16-bit ones, edges under 2^15 subpixels
    // (the usual case) take two 32-bit products instead (`cross_small`, the same
    // value: |det| < 2^31).
    let wide = || mul_wide(dx1, dy2) - mul_wide(dx2, dy1);
    let det = if cfg!(fixshade_v6m) {
        match crate::math::cross_small(dx1, dy1, dx2, dy2) {
            Some(a) => a as i64,
            None => wide(),
        }
    } else {
        wide()
    };
    if det == 0 {
        return None;
    }
    let neg = det < 0;
    let mag = det.unsigned_abs();
    let bits = bit_len(mag); // 1..=35
                             // |det| < 2^35: above 31 bits it loses at most four (32-bit shifts only).
    let mant = if bits > 31 {
        let sh = bits - 31; // 1..=4
        ((mag as u32) >> sh) | (((mag >> 32) as u32) << (32 - sh))
    } else {
        (mag as u32) << (31 - bits)
    };
    // 2^61/m: 1/|det| = r·2^−(30 + bits).
    let r = recip_q61(mant) as i32;
    // 16·|d| < 2^21 and r < 2^31: each product below 2^52, the largest at least
    // 16·2^30 (some |d| ≥ 1). `hmax` bounds the high words' magnitudes (xor with
    // the sign: |v| ≤ (hmax + 1)·2^32), so with t = bits(hmax) + 2 every |v| >> t
    // is at most 2^30 and the largest at least 2^29; t is in [4, 22].
    // An image built for size calls the array builder here and copies its arrays
    // through memory, for every triangle: there `p` and `bb` are written out (the
    // other images compile the builder to the same code as before).
    #[cfg(feature = "small-flash")]
    let p = [
        mul_wide(16 * dy2, r),
        mul_wide(-16 * dy1, r),
        mul_wide(-16 * dx2, r),
        mul_wide(16 * dx1, r),
    ];
    #[cfg(not(feature = "small-flash"))]
    let p = arrays::map([16 * dy2, -16 * dy1, -16 * dx2, 16 * dx1], |d| {
        mul_wide(d, r)
    });
    let hmax = p.iter().fold(0u32, |acc, v| {
        acc | (((v >> 32) as i32) ^ ((v >> 63) as i32)) as u32
    });
    let sh_t = 34 - leading_zeros(hmax);
    let round_t = RoundShift::new(sh_t);
    #[cfg(feature = "small-flash")]
    let bb = {
        let signed = |v: i64| {
            let q = round_t.apply(v);
            if neg {
                -q
            } else {
                q
            }
        };
        [signed(p[0]), signed(p[1]), signed(p[2]), signed(p[3])]
    };
    #[cfg(not(feature = "small-flash"))]
    let bb = arrays::map(p, |v| {
        let q = round_t.apply(v);
        if neg {
            -q
        } else {
            q
        }
    });
    // S = 30 + bits − t: t ≤ 22 so S ≥ 9; bits ≤ 35 and t ≥ 4, so S ≤ 61.
    let sh = 30 + bits - sh_t;
    // The bound's inputs on bit lengths: E pixel steps, colour and depth deltas.
    let be = steps_bits([t, m, b]);
    let d1 = [m.c[0] - t.c[0], m.c[1] - t.c[1], m.c[2] - t.c[2]];
    let d2 = [b.c[0] - t.c[0], b.c[1] - t.c[1], b.c[2] - t.c[2]];
    let dor = d1
        .iter()
        .chain(d2.iter())
        .fold(0u32, |acc, d| acc | (d ^ (d >> 31)) as u32);
    let bd = 33 - leading_zeros(dor); // |d₁| + |d₂| < 2^bd
    let (z1, z2) = (
        (m.z >> 2) as i32 - (t.z >> 2) as i32,
        (b.z >> 2) as i32 - (t.z >> 2) as i32,
    );
    let bz = 33 - leading_zeros(((z1 ^ (z1 >> 31)) | (z2 ^ (z2 >> 31))) as u32);
    // Colours: |G| < 2^(bd + 31 − S) fits i32 and E·|G|·2^-28 < 2^10 when
    // bd ≤ S and be + bd ≤ S + 7; then E·D·2^−(S+1) < 2^6 too.
    // Depth (quarters, S − 2): |G| < 2^(bz + 33 − S), so bz + 2 ≤ S and
    // be + bz ≤ S + 5; the quarters and the basis rounding cost below 2^(34 − S) a
    // step, below 2^14 over E steps when be + 20 ≤ S.
    // (A depth that does not change at all has no error.)
    let zvar = t.z != m.z || t.z != b.z;
    if bd > sh || be + bd > sh + 7 || (zvar && (bz + 2 > sh || be + bz > sh + 5 || be + 20 > sh)) {
        return exact();
    }
    // |d| < 2^30 (colours; depth in quarters) and |B| ≤ 2^30: each product below
    // 2^60, the sum 2^61.
    let mut gx = [0i32; ATTRS];
    let mut gy = [0i32; ATTRS];
    let round = RoundShift::new(sh);
    for k in 0..3 {
        (gx[k], gy[k]) = increments(d1[k], d2[k], &bb, &round);
    }
    (gx[3], gy[3]) = increments(z1, z2, &bb, &RoundShift::new(sh - 2));
    // y points down: the middle vertex is left of top→bottom when det < 0.
    Some(L::build([t, m, b], neg, gx, gy))
}

/// The bit length of `E`, the most pixel steps from the top vertex `t` to a pixel
/// centre of the triangle (sorted by y): `E` is at most the bounding box's width
/// and height in pixels, plus 2.
#[inline(always)]
fn steps_bits([t, m, b]: [&ScreenVertex; 3]) -> u32 {
    let (xl, xr) = (t.x.min(m.x).min(b.x), t.x.max(m.x).max(b.x));
    32 - leading_zeros((((xr - xl) + (b.y - t.y)) >> 4) as u32 + 2)
}

/// What [`small_increments`] made of a triangle.
enum Small {
    /// Zero area.
    Zero,
    /// The increments (and whether the middle vertex is left of the long edge).
    Set {
        neg: bool,
        gx: [i32; ATTRS],
        gy: [i32; ATTRS],
    },
    /// Not a triangle for the small path: the other paths decide.
    Other,
}

/// The increments of a small triangle in 32-bit arithmetic (`MULS` alone on
/// ARMv6-M, where the wide path's 64-bit products are library-class sequences):
/// the path of every triangle whose vertices lie within 128 pixels of the top
/// one (`d` = `[dx₁, dy₁, dx₂, dy₂]` from the top vertex, in [−2¹¹, 2¹¹)) and whose
/// attributes change by less than 2²³ units (colours: 128 steps of an 8-bit
/// channel, any 5- or 6-bit swing) and 2²⁶ (depth: 1024 steps of 16 bits) across
/// it; [`Small::Other`] for the rest.
///
/// - `|det|` ≤ 2²³ (`|det| < 2^k`), normalised to a 16-bit mantissa `m` (exact up
///   to 2¹⁶, else truncated: relative error below 2⁻¹⁵), gives `r = 2³¹/m`
///   ([`recip_q31_16`], within 2⁻¹⁵), so `r ≈ 2^(15 + k)/|det|`.
/// - The basis numerators `n = ±16·(dy₂, −dy₁, −dx₂, dx₁)` (the sign of `det`,
///   |n| ≤ 2¹⁵) times `r` are `P = n·2^(15 + k)/det` (|P| < 2³¹, exact products),
///   up to the common relative error `ρ < 2⁻¹⁴` of `r`.
/// - An attribute's deltas `d₁`, `d₂` from the top vertex are taken as
///   `δ = round(d/2^e)`, `e` such that δ lies in [−2¹⁴, 2¹⁴] (the channels share
///   one `e`, the depth has its own): `X = round((δ₁·P₀ + δ₂·P₁)/2¹⁶)`
///   ([`SplitBasis::x`]: from 16-bit halves of `P` on ARMv6-M, the same bits) is
///   `Gx·2^sh` with `sh = k − 1 − e`, and `Gx = round(X/2^sh)` (or `X·2^−sh`,
///   exactly, for `sh < 1`, if it fits `i32`); `Gy` alike.
///
/// Error of the lattice against the exact plane at a pixel centre inside the
/// triangle, `E` < 2⁹ pixel steps from the top vertex, for an attribute whose
/// deltas are below 2^b in magnitude: the deltas' rounding moves the middle and
/// bottom values by at most 2^(e − 1), which moves every value inside the
/// triangle by no more (barycentric weights); `ρ` scales every value's change from the
/// top vertex, below 2^b inside: 2^(b − 14); the rounding of `X` (½) and of the
/// increment (½) cost `0.75·E` for `sh ≥ 1` (below 384 units), `2^(−sh − 1)` a
/// step for `sh < 1`, taken only within 2⁹ (colours) and 2¹² (depth) over the
/// triangle's bounding box; the anchor one unit. Colours (b ≤ 23): below 3·2⁹ + 1
/// < 2¹¹ units, the wide path's bound; depth (b ≤ 26): below 3·2¹² + 1 < 2¹⁴ (a
/// quarter of a u16 step).
#[cfg_attr(not(feature = "small-flash"), inline(always))]
#[cfg_attr(feature = "small-flash", inline(never))]
fn small_increments([t, m, b]: [&ScreenVertex; 3]) -> Small {
    if !is_small([(t.x, t.y), (m.x, m.y), (b.x, b.y)]) {
        return Small::Other;
    }
    // Depth first (the cheaper test, and the one larger triangles fail): the
    // magnitude of the u32 difference; below 2^26 the i32 difference is exact.
    let zor = m.z.abs_diff(t.z) | b.z.abs_diff(t.z);
    if zor >> 26 != 0 {
        return Small::Other;
    }
    let (dx1, dy1) = (m.x - t.x, m.y - t.y);
    let (dx2, dy2) = (b.x - t.x, b.y - t.y);
    // The colour deltas, exact when every channel is in [0, 2^30) (always from
    // the vertex stage; else the other paths).
    let (mut cs, mut dor) = (0u32, 0u32);
    let (mut d1, mut d2) = ([0i32; 3], [0i32; 3]);
    for k in 0..3 {
        let (a, p, q) = (t.c[k], m.c[k], b.c[k]);
        cs |= (a | p | q) as u32;
        (d1[k], d2[k]) = (p.wrapping_sub(a), q.wrapping_sub(a));
        dor |= d1[k].unsigned_abs() | d2[k].unsigned_abs();
    }
    if cs >> 30 != 0 || dor >> 23 != 0 {
        return Small::Other;
    }
    // |d| ≤ 2^11: products at most 2^22, |det| ≤ 2^23.
    let det = dx1 * dy2 - dx2 * dy1;
    if det == 0 {
        return Small::Zero;
    }
    let neg = det < 0;
    let mag = det.unsigned_abs();
    let bd = 32 - leading_zeros(mag) as i32; // 1..=24
    let mant = if bd > 16 {
        mag >> (bd - 16)
    } else {
        mag << (16 - bd)
    };
    // r ≈ 2^31/mant = 2^(15 + bd)/|det|, in [2^15, 2^16); the sign of det on it.
    let r = recip_q31_16(mant) as i32;
    let r = if neg { -r } else { r };
    // |16·d| ≤ 2^15 and |r| < 2^16: each product below 2^31 in magnitude.
    let p = [16 * dy2 * r, -16 * dy1 * r, -16 * dx2 * r, 16 * dx1 * r];
    // e = max(bits − 14, 0): δ in [−2^14, 2^14]. The shift bd − 1 − e is at most 23.
    let e = |or: u32| (18 - leading_zeros(or) as i32).max(0);
    let (ec, ez) = (e(dor), e(zor));
    let (shc, shz) = (bd - 1 - ec, bd - 1 - ez);
    // A shift below 1 (a tiny or thin triangle whose attribute changes fast): X is
    // shifted left, exactly, and its rounding (½) costs 2^(−sh − 1) a step, below
    // 2^(be − sh − 1) over the triangle (E < 2^be): taken within 2^9 (colours) and
    // 2^12 (depth).
    if shc < 1 || shz < 1 {
        // Below 2^9 for a small triangle.
        let be = steps_bits([t, m, b]) as i32;
        if (shc < 1 && be - shc > 10) || (shz < 1 && be - shz > 13) {
            return Small::Other;
        }
    }
    let (z1, z2) = (
        (m.z as i32).wrapping_sub(t.z as i32),
        (b.z as i32).wrapping_sub(t.z as i32),
    );
    let split = SplitBasis::new(p);
    // `None` when a left shift would not fit i32.
    let inc = |d1: i32, d2: i32, e: i32, sh: i32| {
        // Rounded to nearest: δ in [−2^14, 2^14].
        let half_e = (1 << e) >> 1;
        let (a, c) = ((d1 + half_e) >> e, (d2 + half_e) >> e);
        let g = |h: usize, l: usize| {
            let x = split.x(a, c, h, l);
            if sh >= 1 {
                Some((x + (1 << (sh - 1))) >> sh)
            } else {
                // −sh ≤ 13 − be ≤ 12 (the check above): a valid shift.
                let g = x << -sh;
                (g >> -sh == x).then_some(g)
            }
        };
        Some((g(0, 1)?, g(2, 3)?))
    };
    let mut gx = [0i32; ATTRS];
    let mut gy = [0i32; ATTRS];
    for k in 0..3 {
        let Some(g) = inc(d1[k], d2[k], ec, shc) else {
            return Small::Other;
        };
        (gx[k], gy[k]) = g;
    }
    let Some(g) = inc(z1, z2, ez, shz) else {
        return Small::Other;
    };
    (gx[3], gy[3]) = g;
    // y points down: the middle vertex is left of top→bottom when det < 0.
    Small::Set { neg, gx, gy }
}

/// The small path's basis `P` (|P| < 2³¹) as its products take it: whole on the
/// cores with a 32×32→64-bit multiply, in halves on ARMv6-M.
#[derive(Copy, Clone)]
struct SplitBasis {
    #[cfg(not(fixshade_v6m))]
    p: [i32; 4],
    /// High halves (signed) and low halves (in [0, 2¹⁶)): `P = Pₕ·2¹⁶ + Pₗ`.
    #[cfg(fixshade_v6m)]
    ph: [i32; 4],
    #[cfg(fixshade_v6m)]
    pl: [i32; 4],
}

impl SplitBasis {
    #[inline(always)]
    fn new(p: [i32; 4]) -> SplitBasis {
        #[cfg(not(fixshade_v6m))]
        {
            SplitBasis { p }
        }
        #[cfg(fixshade_v6m)]
        {
            SplitBasis {
                ph: p.map(|v| v >> 16),
                pl: p.map(|v| v & 0xFFFF),
            }
        }
    }

    /// `X = ⌊(a·P_h + c·P_l + 2¹⁵ − 1)/2¹⁶⌋` (rounded, halves down) for `a`, `c`
    /// in [−2¹⁴, 2¹⁴] (the sum below 2⁴⁶, X below 2³⁰ + 2¹⁵ in magnitude).
    #[inline(always)]
    fn x(&self, a: i32, c: i32, h: usize, l: usize) -> i32 {
        #[cfg(not(fixshade_v6m))]
        {
            ((mul_wide(a, self.p[h]) + mul_wide(c, self.p[l]) + 0x7FFF) >> 16) as i32
        }
        #[cfg(fixshade_v6m)]
        {
            split_x(a, c, [self.ph[h], self.ph[l]], [self.pl[h], self.pl[l]])
        }
    }
}

/// [`SplitBasis::x`] from 32-bit products: with `P = Pₕ·2¹⁶ + Pₗ`, the sum is
/// `(a·Pₕ₀ + c·Pₕ₁)·2¹⁶ + L`, `L = a·Pₗ₀ + c·Pₗ₁`, so `X = a·Pₕ₀ + c·Pₕ₁ + ⌊(L +
/// 2¹⁵ − 1)/2¹⁶⌋` exactly: with `a`, `c` in [−2¹⁴, 2¹⁴], |a·Pₕ| ≤ 2²⁹ and |a·Pₗ| ≤
/// 2³⁰ − 2¹⁴, so the high sum is at most 2³⁰ and `L + 2¹⁵ − 1` at most 2³¹ − 1
/// (the bias one short of a half is what keeps it inside `i32`).
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
fn split_x(a: i32, c: i32, ph: [i32; 2], pl: [i32; 2]) -> i32 {
    a * ph[0] + c * ph[1] + ((a * pl[0] + c * pl[1] + 0x7FFF) >> 16)
}

/// `⌊(gx·ox + gy·oy + 8)/16⌋` modulo 2³² for offsets |`ox`|, |`oy`| < 2¹⁷
/// subpixels: the change of an attribute from the top vertex to a pixel centre
/// (the anchor's, or that of pixel (0, 0): the two differ by whole steps `gx`,
/// `gy` times 16, which the floor passes through unchanged, so both are the
/// same lattice). The exact sum (|g| < 2³¹: products below 2⁴⁸) on the host and
/// ARMv7-M, where a 32×32→64 product is one instruction; on ARMv6-M
/// ([`origin_offset_split`]) from 32-bit products modulo 2³². Both give the same
/// bits (tested).
#[inline(always)]
fn origin_offset(gx: i32, gy: i32, ox: i32, oy: i32) -> i32 {
    debug_assert!(ox.unsigned_abs() < 1 << 17 && oy.unsigned_abs() < 1 << 17);
    #[cfg(fixshade_v6m)]
    {
        origin_offset_split(gx, gy, ox, oy)
    }
    #[cfg(not(fixshade_v6m))]
    {
        ((mul_wide(gx, ox) + mul_wide(gy, oy) + 8) >> 4) as i32
    }
}

/// [`origin_offset`] without a 64-bit product: with `g = 16·h + l` (`h = g >> 4`,
/// `l = g & 15`), `g·o = 16·h·o + l·o`, so the quotient is `h_x·o_x + h_y·o_y` (taken
/// modulo 2³²) plus `⌊(l_x·o_x + l_y·o_y + 8)/16⌋` (|l·o| < 2²¹, the sum below
/// 2²³): four `MULS` instead of two 64-bit products.
#[cfg(any(test, fixshade_v6m))]
#[inline(always)]
fn origin_offset_split(gx: i32, gy: i32, ox: i32, oy: i32) -> i32 {
    let high = (gx >> 4)
        .wrapping_mul(ox)
        .wrapping_add((gy >> 4).wrapping_mul(oy));
    high.wrapping_add(((gx & 15) * ox + (gy & 15) * oy + 8) >> 4)
}

/// One attribute's increments from its deltas `d₁`, `d₂` and the basis `b`:
/// `round((d₁·b₀ + d₂·b₁)/2^sh)` and `round((d₁·b₂ + d₂·b₃)/2^sh)` (see
/// [`setup_fast`] for the bounds). Kept out of line on ARMv6-M: one attribute at a
/// time keeps the 64-bit sums in registers, where the four inlined side by side
/// spill; inlined on the other cores, where each sum is two `SMLAL`.
#[cfg_attr(fixshade_v6m, inline(never))]
#[cfg_attr(not(fixshade_v6m), inline(always))]
fn increments(d1: i32, d2: i32, b: &[i32; 4], round: &RoundShift) -> (i32, i32) {
    if d1 == 0 && d2 == 0 {
        return (0, 0);
    }
    (
        round.apply(mul_wide(d1, b[0]) + mul_wide(d2, b[1])),
        round.apply(mul_wide(d1, b[2]) + mul_wide(d2, b[3])),
    )
}

/// `round(n / 2^sh)` (half up) for `1 ≤ sh < 63`, as `i32` (the caller knows it
/// fits). The bias `2^(sh−1)` is made once for the sums rounded by the same shift,
/// except on ARMv6-M, where it is made where it is added: there a 64-bit value
/// held across the products would take two of the eight low registers and spill
/// the sums (about 190 k more instructions on `bench-sphere-128x80`).
#[derive(Copy, Clone)]
struct RoundShift {
    sh: u32,
    #[cfg(not(fixshade_v6m))]
    bias: i64,
}

impl RoundShift {
    #[inline(always)]
    fn new(sh: u32) -> RoundShift {
        debug_assert!((1..63).contains(&sh));
        RoundShift {
            sh,
            #[cfg(not(fixshade_v6m))]
            bias: bit_i64(sh - 1),
        }
    }

    /// From 32-bit halves: with `sh ≥ 32` the high word of `n + 2^(sh−1)` shifted by
    /// `sh − 32` (nested floors), below 32 the low word of the shifted sum. No
    /// 64-bit shift by a variable amount (a helper call on ARMv6-M, a branchy
    /// sequence on ARMv7-M).
    #[inline(always)]
    fn apply(&self, n: i64) -> i32 {
        #[cfg(fixshade_v6m)]
        let n = n + bit_i64(self.sh - 1);
        #[cfg(not(fixshade_v6m))]
        let n = n + self.bias;
        let (hi, lo) = ((n >> 32) as i32, n as u32);
        if self.sh >= 32 {
            hi >> (self.sh - 32)
        } else {
            ((lo >> self.sh) | ((hi as u32) << (32 - self.sh))) as i32
        }
    }
}

/// [`setup_div`], also returning its [`Det`] for further attribute planes.
/// Always inlined on hosted targets, so the set-up triangle is built where it is
/// used instead of being returned through memory; bare-metal targets keep one copy
/// (flash; see [`super::edge::EdgeStepper::new`]).
#[cfg_attr(not(target_os = "none"), inline(always))]
pub(crate) fn setup_with_det_div<D: Divide>(v: [ScreenVertex; 3]) -> Option<(Setup, Det)> {
    let v = sort3(v);
    let det = Det::new::<D>(arrays::map(v, |p| (p.x, p.y)))?;
    let (a0, a1, a2) = (attrs(&v[0]), attrs(&v[1]), attrs(&v[2]));
    let mut gx = [0i64; ATTRS];
    let mut gy = [0i64; ATTRS];
    for k in 0..ATTRS {
        let (d1, d2) = (a1[k] - a0[k], a2[k] - a0[k]);
        if d1 != 0 || d2 != 0 {
            // The quotient is below 2^55 and fits i64.
            let (x, y) = det.gradient(d1, d2, 0);
            (gx[k], gy[k]) = (x as i64, y as i64);
        }
    }
    let anchor = (first_row(v[0].x), first_row(v[0].y));
    // Offsets of the anchor centre from the top vertex, in [0, 16) subpixels.
    let ox = (16 * anchor.0 + 8 - v[0].x) as i64;
    let oy = (16 * anchor.1 + 8 - v[0].y) as i64;
    // ox, oy < 16 and |g| < 2^55: the sum is below 2^60.
    let a = arrays::from_fn(|k| {
        let off = (ox * gx[k] + oy * gy[k] + 8) >> 4;
        (a0[k] + off + ROUND_BIAS as i64) as i32 // modulo 2^32 by design
    });
    let s = Setup {
        // y points down: the middle vertex is left of top→bottom when det < 0.
        mid_left: det.inv < 0,
        v,
        gx: arrays::map(gx, |g| g as i32), // modulo 2^32 by design
        gy: arrays::map(gy, |g| g as i32),
        anchor,
        a,
        unwrapped: gx
            .iter()
            .chain(gy.iter())
            .all(|g| i32::try_from(*g).is_ok()),
    };
    Some((s, det))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::GUARD;

    /// The split form of the small path's products equals the 64-bit one at the
    /// extremes and on a million random arguments.
    #[test]
    fn small_path_split_products_equal_wide() {
        let wide = |a: i32, c: i32, p0: i32, p1: i32| {
            ((a as i64 * p0 as i64 + c as i64 * p1 as i64 + 0x7FFF) >> 16) as i32
        };
        let split = |a: i32, c: i32, p0: i32, p1: i32| {
            split_x(a, c, [p0 >> 16, p1 >> 16], [p0 & 0xFFFF, p1 & 0xFFFF])
        };
        let lim = (1 << 15) * ((1 << 16) - 1);
        let ds = [0, 1, -1, 1 << 14, -(1 << 14), 12345, -777];
        let ps = [0, 1, -1, lim, -lim, 0xFFFF, -0x10000, 0x8000, 987_654_321];
        for &a in &ds {
            for &c in &ds {
                for &p0 in &ps {
                    for &p1 in &ps {
                        assert_eq!(split(a, c, p0, p1), wide(a, c, p0, p1), "{a} {c} {p0} {p1}");
                    }
                }
            }
        }
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..1_000_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let d = |sh: u32| ((seed >> sh) as i32 % (1 << 14)) >> ((seed >> (sh + 40)) & 15);
            // In (−2^14, 2^14), inside the deltas' range [−2^14, 2^14].
            let p = |sh: u32| ((seed >> sh) as i32 % lim) >> ((seed >> (sh + 3)) & 31);
            let (a, c, p0, p1) = (d(0), d(14), p(28), p(33));
            assert_eq!(split(a, c, p0, p1), wide(a, c, p0, p1), "{a} {c} {p0} {p1}");
        }
    }

    /// The small path's lattice against the exact plane at every pixel centre
    /// inside random small triangles (ordinary, thin and slivers, colours over the
    /// 8-bit range, depths over the whole range): below 2¹¹ units (colours) and
    /// 2¹⁴ (depth), the bounds its docs derive; most ordinary triangles take it.
    #[test]
    fn small_path_stays_within_its_bound() {
        extern crate std;
        const DEPTH_MAX: u64 = crate::geometry::DEPTH_SCALE as u64 + 1;
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        let (mut taken, mut tried, mut worst_c, mut worst_z) = (0, 0, 0f64, 0f64);
        for i in 0..40_000 {
            // Sizes from a pixel to 127 pixels; every fourth a sliver.
            let size = (16 + next(2016) as i32) >> (next(8) as i32);
            let (x0, y0) = (next(4000) as i32 - 2000, next(4000) as i32 - 2000);
            let mut v = [(x0, y0); 3];
            for p in v.iter_mut().skip(1) {
                *p = (
                    x0 + next(2 * size as u64 + 1) as i32 - size,
                    y0 + next(2 * size as u64 + 1) as i32 - size,
                );
            }
            if i % 4 == 0 {
                // Nearly collinear: the third vertex close to the first edge.
                let (dx, dy) = (v[1].0 - x0, v[1].1 - y0);
                let f = next(1000) as i32;
                v[2] = (
                    x0 + dx * f / 1000 + next(3) as i32 - 1,
                    y0 + dy * f / 1000 + next(3) as i32 - 1,
                );
            }
            // Values around a base, spread from 2^8 units to the whole range.
            let (zs, cs) = (1u64 << (8 + next(25)), 1u64 << (8 + next(17)));
            let (z0, c0) = (next(DEPTH_MAX), [0; 3].map(|_| next(256 << 16)));
            let sv = v.map(|(x, y)| ScreenVertex {
                x,
                y,
                z: (z0 + next(zs)).min(DEPTH_MAX - 1) as u32,
                c: c0.map(|c| (c + next(cs)).min((256 << 16) - 1) as i32),
            });
            let [i0, i1, i2] = order3([&sv[0], &sv[1], &sv[2]]);
            let (t, m, b) = (&sv[i0], &sv[i1], &sv[i2]);
            let d = [m.x - t.x, m.y - t.y, b.x - t.x, b.y - t.y];
            tried += 1;
            let Small::Set { neg, gx, gy } = small_increments([t, m, b]) else {
                continue;
            };
            taken += 1;
            let s = <Setup as LatticeOut>::build([t, m, b], neg, gx, gy);
            let det = (d[0] as i64 * d[3] as i64 - d[2] as i64 * d[1] as i64) as f64;
            let (xl, xr) = (t.x.min(m.x).min(b.x), t.x.max(m.x).max(b.x));
            for py in first_row(t.y)..first_row(b.y) {
                for px in first_row(xl)..first_row(xr) + 1 {
                    let (u, w) = ((16 * px + 8 - t.x) as f64, (16 * py + 8 - t.y) as f64);
                    let l1 = (u * d[3] as f64 - w * d[2] as f64) / det;
                    let l2 = (w * d[0] as f64 - u * d[1] as f64) / det;
                    if l1 < 0.0 || l2 < 0.0 || l1 + l2 > 1.0 {
                        continue;
                    }
                    let got = s.at(px, py);
                    let at = |a: [f64; 3]| a[0] + l1 * (a[1] - a[0]) + l2 * (a[2] - a[0]);
                    for (k, g) in got.iter().take(3).enumerate() {
                        let want = at([t.c[k], m.c[k], b.c[k]].map(f64::from));
                        let e = ((g - ROUND_BIAS) as f64 - want).abs();
                        worst_c = worst_c.max(e);
                        assert!(e < 2048.0, "colour {k}: {e} {sv:?}");
                    }
                    let want = at([t.z, m.z, b.z].map(f64::from));
                    // Modulo 2^32, as the lattice is (a value a hair below 0).
                    let z = got[3].wrapping_sub(ROUND_BIAS) as u32 as f64;
                    let e = (z - want).rem_euclid(4294967296.0);
                    let e = e.min(4294967296.0 - e);
                    worst_z = worst_z.max(e);
                    assert!(e < 16384.0, "depth: {e} {sv:?}");
                }
            }
        }
        assert!(taken * 2 > tried, "{taken} of {tried}");
        std::println!(
            "small path: {taken} of {tried}; worst {worst_c} (colour), {worst_z} (depth)"
        );
    }

    /// The split origin offset against the exact 64-bit sum: the extreme
    /// gradients at the extreme and small offsets, and a million random ones.
    #[test]
    fn origin_offset_split_equals_wide() {
        let wide = |gx: i32, gy: i32, ox: i32, oy: i32| {
            ((gx as i64 * ox as i64 + gy as i64 * oy as i64 + 8) >> 4) as i32
        };
        let edges = [0, 1, -1, 15, -16, 0xFFFF, -0x10000, i32::MAX, i32::MIN];
        let lim = (1 << 17) - 1;
        let offsets = (-20..20).chain([lim, -lim, lim - 15, 8 - GUARD, 8 + GUARD - 1]);
        for &gx in &edges {
            for &gy in &edges {
                for ox in offsets.clone() {
                    for oy in offsets.clone() {
                        assert_eq!(
                            origin_offset_split(gx, gy, ox, oy),
                            wide(gx, gy, ox, oy),
                            "{gx} {gy} {ox} {oy}"
                        );
                    }
                }
            }
        }
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..1_000_000 {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let (gx, gy) = (seed as i32 >> (seed >> 59), (seed >> 32) as i32);
            // Offsets over the whole range, some of them small.
            let o = |sh: u64| ((seed >> sh) as i32 % (1 << 17)) >> ((seed >> (sh + 20)) & 15);
            let (ox, oy) = (o(20), o(38));
            assert_eq!(origin_offset_split(gx, gy, ox, oy), wide(gx, gy, ox, oy));
            assert_eq!(origin_offset(gx, gy, ox, oy), wide(gx, gy, ox, oy));
        }
    }
}
