//! Span methods: how a span's pixel values are computed ([`Gradient`], [`Classic`],
//! and, in the sibling modules, the parallel, segment and Sierpinski methods).
//!
//! A [`Span`] is the plain data the edge walker hands over for one row: the pixel
//! range `[x0, x1)` (already clipped to the target), the attribute values at `x0`
//! from the triangle's lattice, and, for methods that want them, the exact edge
//! crossings with the attribute values interpolated along the edges. A
//! [`SpanMethod`] turns that into pixel values; [`write_run`] is the pixel stage
//! shared by every method ([`super::pixel`]). The walker and the trait live in
//! [`super`], the pixel stage in [`super::pixel`]; both are re-exported here, where
//! a firmware names its span method.

pub use super::pixel::{pack_pixel, write_run, DepthMode, DepthTest, NoDepth};
pub use super::{EdgeValues, Span, SpanMethod};

use super::setup::{Setup, ATTRS};
use super::shading::Shading;
use super::vertex::ScreenVertex;
use crate::divide::{wide_recip, Divide, Exact};
use crate::target::{DepthFormat, PixelFormat, Target};
use core::marker::PhantomData;

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
        super::fill_gradient::<P, T, Z, Sh, (), _>(target, tri, ())
    }
    #[inline(always)]
    fn draw_vertices<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        v: [&ScreenVertex; 3],
    ) -> u32 {
        match &super::setup::lattice(v) {
            Some(r) => super::fill_gradient::<P, T, Z, Sh, (), _>(target, r, ()),
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
        let (t40, inv_w40) = if D::is_exact() {
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
        if D::is_exact() {
            return S::draw_vertices::<P, T, Z, Sh>(target, v);
        }
        match &Self::setup([*v[0], *v[1], *v[2]]) {
            Some(s) => Self::draw::<P, T, Z, Sh>(target, s),
            None => 0,
        }
    }
}
