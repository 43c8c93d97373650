//! Span filling and the pixel operations behind it.
//!
//! A [`Span`] is the plain data the edge walker hands over for one row: the pixel
//! range `[x0, x1)` (already clipped to the target), the attribute values at `x0`
//! from the triangle's lattice, and, for methods that want them, the exact edge
//! crossings with the attribute values interpolated along the edges.
//!
//! A [`SpanMethod`] turns that into pixel values; [`write_run`] is the pixel stage
//! shared by every method: depth test against the depth row (`u16` or `u32` cells,
//! [`DepthFormat`]; strictly nearer wins),
//! pack to the pixel format, store.

use super::edge::EdgeStepper;
use super::setup::{Setup, ATTRS};
use super::ScreenVertex;
use crate::divide::{wide_recip, Divide, Exact};
use crate::shade::Shading;
use crate::target::{DepthFormat, PixelFormat, Target};
use core::marker::PhantomData;

/// Edge crossings of a row, for methods that interpolate between the edges.
///
/// The crossings are exact rationals: an edge stepper at row `y` crosses the row at
/// `q − r/d` in pixel-centre coordinates (pixel x has its centre at x).
///
/// ```
/// use fixshade::raster::span::EdgeValues;
/// // Filled by the edge walker for methods with `EDGE_VALUES = true` (classic); the
/// // default is an empty placeholder with a valid stepper (d = 1).
/// let e = EdgeValues::default();
/// assert_eq!((e.left.d, e.il), (1, [0; 4]));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct EdgeValues {
    /// The left edge's stepper on this row.
    pub left: EdgeStepper,
    /// The right edge's stepper on this row.
    pub right: EdgeStepper,
    /// Attribute values at the left crossing (true values, bias included).
    pub il: [i64; ATTRS],
    /// Attribute values at the right crossing.
    pub ir: [i64; ATTRS],
}

impl Default for EdgeValues {
    fn default() -> Self {
        let e = EdgeStepper {
            q: 0,
            r: 0,
            d: 1,
            a: 0,
            b: 0,
        };
        EdgeValues {
            left: e,
            right: e,
            il: [0; ATTRS],
            ir: [0; ATTRS],
        }
    }
}

/// One row's worth of work for a span method.
///
/// ```
/// use fixshade::raster::span::{EdgeValues, Span};
/// // Row 7, pixels 10..14, red 0.5 in Q.16 channel units at x = 10, depth 0.
/// let s = Span { y: 7, x0: 10, x1: 14, v: [1 << 15, 0, 0, 0], edges: EdgeValues::default() };
/// assert_eq!(s.x1 - s.x0, 4);
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Span {
    /// Pixel row.
    pub y: i32,
    /// First pixel.
    pub x0: i32,
    /// One past the last pixel (`x0 < x1`).
    pub x1: i32,
    /// Lattice attribute values at `x0`.
    pub v: [i32; ATTRS],
    /// Edge crossings; filled only when the method's `EDGE_VALUES` is true.
    pub edges: EdgeValues,
}

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

/// How a span's pixel values are computed.
///
/// ```
/// use fixshade::raster::setup::Setup;
/// use fixshade::raster::span::{write_run, DepthMode, NoDepth, Span, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::{Gouraud, Shading};
/// use fixshade::target::{Framebuffer, Gray8, PixelFormat};
///
/// /// A custom method: every span in the colour of its first pixel.
/// struct PerSpan;
/// impl SpanMethod for PerSpan {
///     const NAME: &'static str = "per-span";
///     const EDGE_VALUES: bool = false;
///     type Divider = fixshade::divide::Exact;
///     type Tri = ();
///     fn prepare(_: &Setup) {}
///     fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
///         color: &mut [P::Raw],
///         depth: &mut [impl DepthFormat],
///         span: &Span,
///         _tri: &Setup,
///         _: &(),
///     ) {
///         write_run::<P, Z, Sh>(color, depth, span.v, &[0; 4]);
///     }
/// }
///
/// let mut px = [0u8; 16 * 16];
/// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 16, 16).unwrap();
/// let v = |x: i32, y: i32, g: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [g << 16, 0, 0] };
/// draw_triangle::<Gray8, _, PerSpan, NoDepth, Gouraud>(&mut fb, [v(0, 0, 0), v(0, 16, 0), v(16, 0, 240)]);
/// for row in px.chunks(16) {
///     let lit: Vec<u8> = row.iter().copied().filter(|&p| p > 0).collect();
///     assert!(lit.windows(2).all(|w| w[0] == w[1]));
/// }
/// ```
pub trait SpanMethod {
    /// Name used by the CLI and scene files.
    const NAME: &'static str;
    /// True if the method needs [`Span::edges`].
    const EDGE_VALUES: bool;
    /// True if the method moves vertices ([`SpanMethod::snap`] is not the identity).
    const SNAPS: bool = false;
    /// True if the method draws a triangle from its [`super::setup::Record`] alone
    /// (the constant gradient with the exact setup), so a frame drawn in bands can
    /// keep records instead of walking every triangle per band
    /// ([`crate::render::Binned`]).
    const RECORDS: bool = false;
    /// Where the method puts a screen vertex before culling and setup (the snapped
    /// Sierpinski variant moves vertices to even pixels). The identity by default.
    #[inline(always)]
    fn snap(v: ScreenVertex) -> ScreenVertex {
        v
    }
    /// The divider of the triangle setup's one reciprocal (the determinant's, for
    /// this method's setup and for the quadratic, Phong and adaptive fills a frame
    /// draws with it): [`Exact`] for every method but [`WithDivide`], which names
    /// its own.
    type Divider: Divide;
    /// Sets up a triangle for this method: [`super::setup::setup_div`] through
    /// [`SpanMethod::Divider`] by default.
    #[inline(always)]
    fn setup(v: [ScreenVertex; 3]) -> Option<Setup> {
        super::setup::setup_div::<Self::Divider>(v)
    }
    /// Per-triangle data of the method (lane offsets, multiples of the increment).
    type Tri;
    /// Computes the per-triangle data once, before the first span.
    fn prepare(tri: &Setup) -> Self::Tri;
    /// Fills `color` (exactly the span's pixels) and `depth` (the same pixels, or
    /// empty with [`NoDepth`]).
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        tri: &Setup,
        data: &Self::Tri,
    );
    /// Rasterizes a set-up triangle. The default walks its edges and hands each span
    /// to [`SpanMethod::fill`] ([`super::draw_setup`]); triangle-level methods such as
    /// the Sierpinski subdivision override it.
    fn draw<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        tri: &Setup,
    ) -> u32
    where
        Self: Sized,
    {
        super::draw_setup::<P, T, Self, Z, Sh>(target, tri)
    }
    /// Sets up and rasterizes a triangle of screen vertices inside the guard band:
    /// [`SpanMethod::setup`], then [`SpanMethod::draw`] (nothing for a zero-area
    /// triangle). A method may fuse the two (the constant gradient does, without
    /// copying the vertices into a [`Setup`]); the pixels are the same.
    #[inline(always)]
    fn draw_vertices<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        v: [&ScreenVertex; 3],
    ) -> u32
    where
        Self: Sized,
    {
        // Drawn from inside the Option: moving the set-up triangle out of it would
        // copy it (the setup is out of line on bare-metal targets).
        match &Self::setup([*v[0], *v[1], *v[2]]) {
            Some(s) => Self::draw::<P, T, Z, Sh>(target, s),
            None => 0,
        }
    }
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
    let mut p = 0u64;
    for (c, off) in v.iter().zip(Packed::<P>::OFF) {
        p = p.wrapping_add((*c as i64 as u64) << off);
    }
    Some(p)
}

/// The pixel stage of a packed span ([`packed_channels`]): `color.len()` pixels from
/// the packed colour `c` and depth `z`, stepping by `dc` and `dz` per pixel. The
/// caller guarantees that every channel of every pixel lies in its lane (true at
/// covered pixels of a triangle whose increments are unwrapped, by the setup bound).
#[inline(always)]
pub(crate) fn write_packed<P: PixelFormat, Z: DepthMode>(
    color: &mut [P::Raw],
    depth: &mut [impl DepthFormat],
    mut c: u64,
    dc: u64,
    mut z: i32,
    dz: i32,
) {
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
/// write_run::<Gray8, NoDepth, Gouraud>(&mut row, &mut [], [10 << 16, 0, 0, 0], &[20 << 16, 0, 0, 0]);
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
            write_packed::<P, Z>(color, depth, c3, d3, z, dz);
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

/// The constant-gradient method (seed 000 §2.1): the per-pixel increment is the
/// triangle's `Gx`, computed once in setup; no division per span.
///
/// ```
/// use fixshade::raster::span::{Gradient, SpanMethod};
/// // The default method: one add per attribute per pixel, increments fixed per triangle.
/// assert_eq!(Gradient::NAME, "gradient");
/// assert!(!Gradient::EDGE_VALUES && !Gradient::SNAPS);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Gradient;

impl SpanMethod for Gradient {
    const NAME: &'static str = "gradient";
    const EDGE_VALUES: bool = false;
    const RECORDS: bool = true;
    type Divider = Exact;
    type Tri = ();
    fn prepare(_: &Setup) {}
    #[inline(always)]
    fn draw<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        tri: &Setup,
    ) -> u32 {
        super::fill_gradient::<P, T, Z, Sh>(target, &super::setup::Record::of(tri))
    }
    #[inline(always)]
    fn draw_vertices<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        v: [&ScreenVertex; 3],
    ) -> u32 {
        match &super::setup::lattice(v) {
            Some(r) => super::fill_gradient::<P, T, Z, Sh>(target, r),
            None => 0,
        }
    }
    #[inline(always)]
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        tri: &Setup,
        _: &(),
    ) {
        write_run::<P, Z, Sh>(color, depth, span.v, &tri.gx);
    }
}

/// The classic method (the idx3d baseline): attributes are interpolated along both
/// edges, and each span divides the difference of its end values by its width,
/// `ΔI = (I_R − I_L) / (x_R − x_L)`, then pre-steps to the first pixel centre.
///
/// The span's ends are the exact rational edge crossings `q − r/d`, so its width
/// `W = (x_R − x_L)` and the first pixel's weight `t = (x0 − x_L)/W ∈ [0, 1]` are
/// exact rationals; each span takes two divisions, `t` and `1/W` with 40 fraction
/// bits, shared by the attributes. Error: the edge values are stepped with
/// increments rounded to 2⁻¹⁶ of a unit (≤ 4096 rows: below 0.001 output steps);
/// `t` and `1/W` are within 2⁻⁴⁰ (relative), which costs below 2⁻⁶ of a unit at the
/// first pixel and below 2⁻⁷ per pixel after it (0.0005 output steps over 4096
/// pixels); the per-pixel increment is then truncated to one unit (below 0.07 output
/// steps over 4096 pixels). The total stays within the same 1-step bound as
/// [`Gradient`], however narrow the span: rounding the crossings to a fixed grid
/// instead would be amplified by `|ΔI|/W` on spans much narrower than a pixel.
///
/// The divider `D` ([`crate::divide`]) is chosen once per draw: `Classic` is
/// `Classic<Exact>`, which keeps the two full-precision divisions above and renders
/// bit-identically to the method before the seam ([`Divide::EXACT`]). Any other
/// divider takes one reciprocal of the width per span through the seam,
/// [`wide_recip`] (`1/W ≈ ρ ≤ 1/W`, relative error at most
/// `η = 2^(1−b) + (2E + 2)·2^b/2³⁰`), and derives `t = dist·ρ` and the increment
/// `ΔI = diff·ρ` by multiplies. The value at pixel `i` of the span is then
/// `I_L + diff·ρ·(x_i − x_L)`, between `I_L` and the exact value (`ρ` never
/// over-estimates and `x_i − x_L ≤ W`), so it stays in range with no clamping, off
/// by at most `η·|I_R − I_L|` plus the truncations above: `η·256` output steps for a
/// colour channel.
/// Coverage does not depend on `D`.
///
/// ```
/// use fixshade::raster::span::{Gradient, NoDepth, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Rgb565Le};
/// use fixshade::raster::span::Classic;
/// // Draws one Gouraud triangle with method `S` into a 40×30 frame.
/// fn draw<S: SpanMethod>() -> [u16; 40 * 30] {
///     let mut px = [0u16; 40 * 30];
///     let mut fb = Framebuffer::<Rgb565Le>::new(&mut px, None, 40, 30).unwrap();
///     let v = |x: i32, y: i32, c: [i32; 3]| ScreenVertex { x, y, z: 0, c };
///     let tri = [v(13, 7, [31 << 16, 0, 0]), v(600, 200, [0, 63 << 16, 0]), v(90, 470, [0, 0, 31 << 16])];
///     draw_triangle::<Rgb565Le, _, S, NoDepth, Gouraud>(&mut fb, tri);
///     px
/// }
/// // One division per span (the idx3d loop) from exact rational edge crossings: the
/// // same coverage, and every channel within one step of the constant gradient.
/// use fixshade::target::PixelFormat;
/// let (c, g) = (draw::<Classic>(), draw::<Gradient>());
/// for (a, b) in c.iter().zip(g.iter()) {
///     assert_eq!(*a == 0, *b == 0);
///     let (a, b) = (Rgb565Le::unpack(*a), Rgb565Le::unpack(*b));
///     assert!((0..3).all(|k| a[k].abs_diff(b[k]) <= 1));
/// }
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Classic<D: Divide = Exact>(PhantomData<D>);

/// `n / d` for `0 ≤ n`, `0 < d`, in u64 when both fit (one hardware division on
/// 64-bit hosts) and in u128 otherwise.
#[inline]
fn div_wide(n: u128, d: u128) -> u128 {
    match (u64::try_from(n), u64::try_from(d)) {
        (Ok(n), Ok(d)) => (n / d) as u128,
        _ => n / d,
    }
}

/// `(t, 1/W)` in Q.40 from one reciprocal of `width` through `D` (see [`Classic`]).
/// `0 ≤ dist ≤ width < 2⁵⁶` and `unit = dl·dr < 2⁴²` (one pixel in the units of
/// `width`).
#[inline]
fn seam_weights<D: Divide>(dist: i128, width: i128, unit: i128) -> (i128, i128) {
    let w = wide_recip::<D>(width as u128);
    let r = w.r as u128; // ≤ 2^30
                         // x·ρ in Q.40 = x·r·2^(10 − shift): x < 2^56, so x·r < 2^86 and x·r·2^10 < 2^96.
    let q40 = |x: i128, r: u128| {
        let p = x as u128 * r;
        (if w.shift <= 10 {
            p << (10 - w.shift)
        } else {
            p >> (w.shift - 10)
        }) as i128
    };
    (q40(dist, r), q40(unit, r))
}

impl<D: Divide> SpanMethod for Classic<D> {
    const NAME: &'static str = "classic";
    const EDGE_VALUES: bool = true;
    type Divider = Exact;
    type Tri = ();
    fn prepare(_: &Setup) {}
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        _tri: &Setup,
        _: &(),
    ) {
        let e = &span.edges;
        let (l, r) = (&e.left, &e.right);
        let (dl, dr) = (l.d as i128, r.d as i128);
        // In units of 1/(dl·dr) pixel (dl, dr < 2^21, |q| < 2^13): below 2^56.
        // x0 − x_L = (x0 − q_L) + r_L/d_L;  x_R − x_L = (q_R − q_L) + r_L/d_L − r_R/d_R.
        let dist = (((span.x0 - l.q) as i128) * dl + l.r as i128) * dr;
        let width = (((r.q - l.q) as i128) * dl + l.r as i128) * dr - r.r as i128 * dl;
        if width <= 0 || dist < 0 {
            return; // the span is empty: no pixel centre lies between the crossings
        }
        let (t40, inv_w40) = if D::EXACT {
            // t and 1/W in Q.40: dist ≤ width, so t40 ≤ 2^40; dist << 40 < 2^96.
            (
                div_wide((dist as u128) << 40, width as u128) as i128,
                div_wide(((dl * dr) as u128) << 40, width as u128) as i128,
            )
        } else {
            seam_weights::<D>(dist, width, dl * dr)
        };
        let mut v = [0i32; ATTRS];
        let mut g = [0i32; ATTRS];
        for k in 0..ATTRS {
            // |diff| < 2^33; diff·t40 < 2^74 and diff·inv_w40 < 2^33·2^82 fit i128.
            let diff = (e.ir[k] - e.il[k]) as i128;
            v[k] = (e.il[k] as i128 + ((diff * t40) >> 40)) as i32; // modulo 2^32 (depth is unsigned)
                                                                    // Wraps only when W < 1/128 pixel, where the span holds one pixel and g is unused.
            g[k] = ((diff * inv_w40) >> 40) as i32;
        }
        write_run::<P, Z, Sh>(color, depth, v, &g);
    }
}

/// The span method `S` with the triangle setup's reciprocal of the determinant
/// taken through the divider `D` ([`super::setup::setup_div`]; also in the
/// quadratic, Phong and adaptive fills a frame draws with it, see
/// [`SpanMethod::Divider`]); everything else is `S`'s own. `WithDivide<S, Exact>`
/// draws exactly what `S` draws.
///
/// With an approximate `D` every increment of the triangle is off by the
/// reciprocal's relative error `η` ([`wide_recip`]), so a pixel's value is off by
/// `η` times its change from the lattice anchor: small for ordinary triangles, but
/// slivers, whose increments are large, can leave the channel range. Coverage does
/// not depend on `D` (the edges never use the reciprocal; only the orientation,
/// whose sign the reciprocal keeps).
///
/// ```
/// use fixshade::raster::span::{Gradient, NoDepth, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Rgb565Le};
/// use fixshade::divide::Exact;
/// use fixshade::raster::span::WithDivide;
/// // Draws one Gouraud triangle with method `S` into a 40×30 frame.
/// fn draw<S: SpanMethod>() -> [u16; 40 * 30] {
///     let mut px = [0u16; 40 * 30];
///     let mut fb = Framebuffer::<Rgb565Le>::new(&mut px, None, 40, 30).unwrap();
///     let v = |x: i32, y: i32, c: [i32; 3]| ScreenVertex { x, y, z: 0, c };
///     let tri = [v(13, 7, [31 << 16, 0, 0]), v(600, 200, [0, 63 << 16, 0]), v(90, 470, [0, 0, 31 << 16])];
///     draw_triangle::<Rgb565Le, _, S, NoDepth, Gouraud>(&mut fb, tri);
///     px
/// }
/// // The exact divider keeps the setup's full-precision reciprocal: the same pixels.
/// assert_eq!(draw::<WithDivide<Gradient, Exact>>(), draw::<Gradient>());
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct WithDivide<S, D>(PhantomData<(S, D)>);

impl<S: SpanMethod, D: Divide> SpanMethod for WithDivide<S, D> {
    const NAME: &'static str = S::NAME;
    const EDGE_VALUES: bool = S::EDGE_VALUES;
    const SNAPS: bool = S::SNAPS;
    const RECORDS: bool = S::RECORDS && D::EXACT;
    #[inline(always)]
    fn snap(v: ScreenVertex) -> ScreenVertex {
        S::snap(v)
    }
    type Divider = D;
    type Tri = S::Tri;
    #[inline(always)]
    fn prepare(tri: &Setup) -> S::Tri {
        S::prepare(tri)
    }
    #[inline(always)]
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        tri: &Setup,
        data: &S::Tri,
    ) {
        S::fill::<P, Z, Sh>(color, depth, span, tri, data)
    }
    #[inline(always)]
    fn draw<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        tri: &Setup,
    ) -> u32 {
        S::draw::<P, T, Z, Sh>(target, tri)
    }
    #[inline(always)]
    fn draw_vertices<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        v: [&ScreenVertex; 3],
    ) -> u32 {
        // With the exact divider `S`'s own setup is this one's.
        if D::EXACT {
            return S::draw_vertices::<P, T, Z, Sh>(target, v);
        }
        match &Self::setup([*v[0], *v[1], *v[2]]) {
            Some(s) => Self::draw::<P, T, Z, Sh>(target, s),
            None => 0,
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

    #[test]
    fn write_run_blocks_equal_the_pixel_loop() {
        blocks_equal_reference::<Rgb565Le>();
        blocks_equal_reference::<Rgb565Be>();
        blocks_equal_reference::<Rgb888>();
    }
}
