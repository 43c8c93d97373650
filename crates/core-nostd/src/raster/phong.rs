//! Phong shading: the eye-space normal and position are interpolated across the
//! triangle, the normal is renormalised at every pixel, and every pixel is lit
//! (seed 003; DESIGN.md method 5).
//!
//! Coverage and depth come from the same [`Setup`] and edge walk as every span
//! method, so a Phong triangle covers exactly the pixels a Gouraud one does. The six
//! per-pixel attributes — the normal in Q2.30 and the eye position in Q16.16 — each
//! get 16 more fraction bits and lie on the lattice `V = A + dx·Gx + dy·Gy` in
//! wrapping `i64` (exact modulo 2⁶⁴, see [`super::setup`]); the value at a covered
//! pixel is within `0.51·(|dx| + |dy|) + 1` units of 2⁻¹⁶ of the exact affine
//! interpolation, far below the normal's own LSB.
//!
//! Per pixel: the depth test first (a hidden pixel is not lit), then
//! [`crate::math::normalize_to_q30`] (a table-seeded reciprocal square root with two Newton
//! steps, no division), then the [`PixelLight`] — the frame's Blinn lighting with its
//! specular model — then pack and store. Normals that interpolate to zero length
//! (opposite vertex normals) are lit with the view direction's normal `(0, 0, 1)`.
//!
//! The even/odd fill ([`PhongFill::EVEN_ODD`]) keeps two accumulators per attribute,
//! one for the even and one for the odd pixels of a span, each stepping by `2·G`: the
//! seed 003 scheme for two lighting units. On the lattice both fills produce the same
//! values, so their images are bit-identical (tested).
//!
//! ```
//! use fixshade::raster::phong::{draw_phong, PhongVertex, PixelLight, Rows};
//! use fixshade::raster::span::NoDepth;
//! use fixshade::target::{Framebuffer, Gray8};
//!
//! /// Lights a pixel by the normal's z component: 1 facing the viewer.
//! struct Facing;
//! impl PixelLight for Facing {
//!     fn light(&self, _p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
//!         [n[2].max(0) >> 14; 3]
//!     }
//! }
//! let mut px = [0u8; 8 * 8];
//! let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 8, 8).unwrap();
//! let z = [0, 0, 1 << 30];
//! let v = |x: i32, y: i32| PhongVertex { x: x * 16, y: y * 16, z: 0, n: z, p: [0; 3] };
//! let n = draw_phong::<Gray8, _, NoDepth, Rows, _>(&mut fb, [v(0, 0), v(0, 8), v(8, 0)], &Facing);
//! assert_eq!(n, 28);
//! assert_eq!(px[0], 255);
//! ```

use super::edge::first_row;
use super::setup::{setup_with_det_div, Det, Setup, ROUND_BIAS};
use super::span::DepthMode;
use super::vertex::ScreenVertex;
use super::{row_range, scan};
use crate::arrays;
use crate::divide::{Divide, Exact};
use crate::math::{normalize_to_q30, ONE_Q30};
use crate::sampler::{fill_row, PixelFn, Threshold};
use crate::target::{to_channels, DepthFormat, PixelFormat, Target};

/// Lights one pixel: eye-space position (Q16.16) and unit normal (Q2.30) to a colour
/// (Q16.16 per channel, 0..=1). [`crate::light::LightingSetup`] implements it.
///
/// ```
/// use fixshade::light::{Light, LightingSetup, Material};
/// use fixshade::specular::BlinnExact;
/// use fixshade::math::{Mat4, ONE_Q30};
/// use fixshade::raster::phong::PixelLight;
/// use fixshade::fixed::Q16_16;
/// // The frame's lighting is a `PixelLight`; any other rule can be too.
/// let white = [Q16_16::ONE; 3];
/// let sun = Light::directional([Q16_16::ZERO, Q16_16::ZERO, Q16_16::ONE], white, white);
/// let l: LightingSetup<BlinnExact> =
///     LightingSetup::new(&[sun], &Mat4::IDENTITY, &Material::default(), [Q16_16::ZERO; 3], false);
/// assert_eq!(l.light([0; 3], [0, 0, ONE_Q30]), l.shade([0; 3], [0, 0, ONE_Q30]));
/// ```
pub trait PixelLight {
    /// The lit colour.
    fn light(&self, p: [i32; 3], n: [i32; 3]) -> [i32; 3];
}

/// A vertex for Phong shading.
///
/// ```
/// use fixshade::math::ONE_Q30;
/// use fixshade::raster::phong::PhongVertex;
/// // Pixel (4, 2), depth 0, normal towards the viewer, eye position (0, 0, -3).
/// let v = PhongVertex { x: 4 * 16, y: 2 * 16, z: 0, n: [0, 0, ONE_Q30], p: [0, 0, -3 << 16] };
/// assert_eq!(v.n[2], 1 << 30);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct PhongVertex {
    /// x in Q12.4.
    pub x: i32,
    /// y in Q12.4, y down.
    pub y: i32,
    /// Depth, as [`ScreenVertex::z`].
    pub z: u32,
    /// Eye-space unit normal, Q2.30.
    pub n: [i32; 3],
    /// Eye-space position, Q16.16.
    pub p: [i32; 3],
}

/// How the spans of a Phong triangle are filled.
///
/// ```
/// use fixshade::raster::phong::{EvenOddPixels, PhongFill, Rows};
/// assert_eq!((Rows::NAME, Rows::EVEN_ODD), ("phong", false));
/// assert_eq!((EvenOddPixels::NAME, EvenOddPixels::EVEN_ODD), ("phong-even-odd", true));
/// ```
pub trait PhongFill {
    /// Name (`phong` or `phong-even-odd`).
    const NAME: &'static str;
    /// Two accumulators per attribute (even and odd pixels) instead of one.
    const EVEN_ODD: bool;
}

/// One accumulator per attribute, stepping pixel by pixel.
///
/// ```
/// use fixshade::raster::phong::{draw_phong, EvenOddPixels, PhongFill, PhongVertex, PixelLight, Rows};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::target::{Framebuffer, Gray8};
/// /// Grey from the normal's x component.
/// struct Side;
/// impl PixelLight for Side {
///     fn light(&self, _p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
///         [n[0].max(0) >> 14; 3]
///     }
/// }
/// fn draw<F: PhongFill>() -> [u8; 24 * 24] {
///     let mut px = [0u8; 24 * 24];
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 24, 24).unwrap();
///     let v = |x: i32, y: i32, nx: i32| PhongVertex { x, y, z: 0, n: [nx, 0, 1 << 29], p: [0; 3] };
///     draw_phong::<Gray8, _, NoDepth, F, _>(&mut fb, [v(5, 9, 0), v(20, 370, 1 << 30), v(380, 40, 1 << 29)], &Side);
///     px
/// }
/// // Both fills light the same lattice values: the same pixels.
/// assert_eq!(draw::<Rows>(), draw::<EvenOddPixels>());
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Rows;

/// Two accumulators per attribute stepping `2·G` over the even and odd pixels.
///
/// ```
/// use fixshade::raster::phong::{draw_phong, EvenOddPixels, PhongFill, PhongVertex, PixelLight, Rows};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::target::{Framebuffer, Gray8};
/// /// Grey from the normal's x component.
/// struct Side;
/// impl PixelLight for Side {
///     fn light(&self, _p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
///         [n[0].max(0) >> 14; 3]
///     }
/// }
/// fn draw<F: PhongFill>() -> [u8; 24 * 24] {
///     let mut px = [0u8; 24 * 24];
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 24, 24).unwrap();
///     let v = |x: i32, y: i32, nx: i32| PhongVertex { x, y, z: 0, n: [nx, 0, 1 << 29], p: [0; 3] };
///     draw_phong::<Gray8, _, NoDepth, F, _>(&mut fb, [v(5, 9, 0), v(20, 370, 1 << 30), v(380, 40, 1 << 29)], &Side);
///     px
/// }
/// // Both fills light the same lattice values: the same pixels.
/// assert_eq!(draw::<EvenOddPixels>(), draw::<Rows>());
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct EvenOddPixels;

impl PhongFill for Rows {
    const NAME: &'static str = "phong";
    const EVEN_ODD: bool = false;
}

impl PhongFill for EvenOddPixels {
    const NAME: &'static str = "phong-even-odd";
    const EVEN_ODD: bool = true;
}

/// Number of interpolated Phong attributes: normal (3) and eye position (3).
pub(super) const PA: usize = 6;

/// The Phong attribute planes of a triangle, 16 extra fraction bits, wrapping `i64`.
struct Planes {
    gx: [i64; PA],
    gy: [i64; PA],
    anchor: (i32, i32),
    a: [i64; PA],
}

pub(super) fn attrs(v: &PhongVertex) -> [i64; PA] {
    [
        v.n[0] as i64,
        v.n[1] as i64,
        v.n[2] as i64,
        v.p[0] as i64,
        v.p[1] as i64,
        v.p[2] as i64,
    ]
}

impl Planes {
    /// The planes through the sorted vertices `v` (the order of [`Setup::v`]).
    ///
    /// The increments come from the triangle's [`Det`] (its one reciprocal) with 16
    /// extra fraction bits (bounds at [`Det::gradient`]). It may exceed 2⁶³ for a sliver; it is
    /// then kept modulo 2⁶⁴ like the colour lattice, and the anchor is computed
    /// from the untruncated i128 quotients (|q| < 2⁷², `16·q` < 2⁷⁶).
    fn new(v: &[PhongVertex; 3], det: &Det) -> Planes {
        let (a0, a1, a2) = (attrs(&v[0]), attrs(&v[1]), attrs(&v[2]));
        let anchor = (first_row(v[0].x), first_row(v[0].y));
        let ox = (16 * anchor.0 + 8 - v[0].x) as i128;
        let oy = (16 * anchor.1 + 8 - v[0].y) as i128;
        let mut p = Planes {
            gx: [0; PA],
            gy: [0; PA],
            anchor,
            a: [0; PA],
        };
        for k in 0..PA {
            let (d1, d2) = (a1[k] - a0[k], a2[k] - a0[k]);
            let (gx, gy) = if d1 != 0 || d2 != 0 {
                det.gradient(d1, d2, 16)
            } else {
                (0, 0)
            };
            p.gx[k] = gx as i64; // modulo 2^64 by design
            p.gy[k] = gy as i64;
            p.a[k] = (((a0[k] as i128) << 16) + ((ox * gx + oy * gy + 8) >> 4)) as i64;
        }
        p
    }

    /// Values at pixel `(x, y)` (wrapping: exact modulo 2⁶⁴).
    #[inline]
    fn at(&self, x: i32, y: i32) -> [i64; PA] {
        let dx = x.wrapping_sub(self.anchor.0) as i64;
        let dy = y.wrapping_sub(self.anchor.1) as i64;
        arrays::from_fn(|k| {
            self.a[k]
                .wrapping_add(dx.wrapping_mul(self.gx[k]))
                .wrapping_add(dy.wrapping_mul(self.gy[k]))
        })
    }
}

/// Lights one pixel from its lattice values and stores it (the depth test has passed).
#[inline(always)]
pub(super) fn shade_pixel<P: PixelFormat, L: PixelLight>(c: &mut P::Raw, a: &[i64; PA], light: &L) {
    let [r, g, b] = lit_channels::<P, L>(a, light);
    P::store(c, P::pack(r, g, b));
}

/// The lit colour of a pixel from its lattice values, as rounded channel integers.
#[inline(always)]
fn lit_channels<P: PixelFormat, L: PixelLight>(a: &[i64; PA], light: &L) -> [u32; 3] {
    let n = normalize_to_q30([a[0], a[1], a[2]]).unwrap_or([0, 0, ONE_Q30]);
    // Positions are Q16.16 with 16 extra bits; covered pixels lie between the
    // vertices, so the shifted value fits i32.
    let p = [
        (a[3] >> 16) as i32,
        (a[4] >> 16) as i32,
        (a[5] >> 16) as i32,
    ];
    let ch = to_channels::<P>(light.light(p, n));
    // Channels ≤ MAX·2^16 < 2^24: adding the rounding bias cannot overflow.
    let r = |v: i32| ((v + ROUND_BIAS) >> 16) as u32;
    [r(ch[0]), r(ch[1]), r(ch[2])]
}

/// Depth test for one pixel (strictly nearer wins); writes the depth when it passes.
#[inline(always)]
pub(super) fn depth_pass<Z: DepthMode>(d: Option<&mut impl DepthFormat>, z: i32) -> bool {
    match d {
        Some(d) if Z::TEST => d.write_if_nearer(z),
        _ => true,
    }
}

/// Rasterizes a Phong triangle, lighting every covered pixel with `light`. Returns
/// the number of pixels covered (before the depth test). Zero-area triangles and
/// vertices outside the guard band draw nothing.
///
/// See the [module docs](self) for an example.
pub fn draw_phong<P, T, Z, F, L>(target: &mut T, v: [PhongVertex; 3], light: &L) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    F: PhongFill,
    L: PixelLight,
{
    draw_phong_with::<P, T, Z, F, Exact, L>(target, v, light, None).0
}

/// [`draw_phong`] with the setup's one reciprocal (of the determinant: it scales
/// every increment, of depth, normal and position) taken through the divider `D`
/// ([`crate::raster::setup::setup_div`]; [`draw_phong`] is `draw_phong_div` with
/// [`Exact`]). An approximate `D` never over-estimates, so each interpolated
/// attribute moves from its exact value towards the top vertex's by at most the
/// reciprocal's relative error `η` ([`crate::divide::wide_recip`]) of its change
/// across the triangle; coverage does not change.
///
/// ```
/// use fixshade::divide::{Exact, ShiftAdd};
/// use fixshade::raster::phong::{draw_phong, draw_phong_div, PhongVertex, PixelLight, Rows};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::target::{Framebuffer, Gray8};
///
/// /// Grey from the normal's z: a lit pixel shows the interpolated normal.
/// struct Facing;
/// impl PixelLight for Facing {
///     fn light(&self, _p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
///         [n[2].max(0) >> 15; 3]
///     }
/// }
/// fn draw(div: bool, shift: bool) -> [u8; 32 * 32] {
///     let mut px = [0u8; 32 * 32];
///     let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 32, 32).unwrap();
///     let n = |z: i32| [0, 1 << 29, z];
///     let v = |x: i32, y: i32, z: i32| PhongVertex { x: x * 16, y: y * 16, z: 0, n: n(z), p: [0; 3] };
///     let t = [v(0, 0, 1 << 30), v(0, 32, 1 << 28), v(32, 0, 1 << 29)];
///     match (div, shift) {
///         (false, _) => draw_phong::<Gray8, _, NoDepth, Rows, _>(&mut fb, t, &Facing),
///         (true, false) => draw_phong_div::<Gray8, _, NoDepth, Rows, Exact, _>(&mut fb, t, &Facing),
///         (true, true) => draw_phong_div::<Gray8, _, NoDepth, Rows, ShiftAdd<12>, _>(&mut fb, t, &Facing),
///     };
///     px
/// }
/// assert_eq!(draw(true, false), draw(false, false)); // Exact: the same pixels
/// let (e, a) = (draw(false, false), draw(true, true));
/// assert!(e.iter().zip(&a).all(|(x, y)| x.abs_diff(*y) <= 4)); // 6-bit mantissa
/// ```
pub fn draw_phong_div<P, T, Z, F, D, L>(target: &mut T, v: [PhongVertex; 3], light: &L) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    F: PhongFill,
    D: Divide,
    L: PixelLight,
{
    draw_phong_with::<P, T, Z, F, D, L>(target, v, light, None).0
}

/// Sparse lighting of Phong spans: the pixel-segment sampler of seed 002 §2.6
/// ([`crate::sampler::fill_row`]) applied to the per-pixel lighting of each span.
///
/// A span is cut into pieces of at most [`SAMPLED_PIECE`] pixels from its first
/// pixel; in each piece the lighting is evaluated at the ends of segments of
/// `segment` pixels (clamped to 1..=[`SAMPLED_PIECE`]), the inside is interpolated
/// where the ends differ by at most `threshold` in every channel, and halved where
/// they differ more. Every pixel is then depth-tested as usual (a hidden pixel may
/// have been evaluated as a segment end). With `segment = 1` every pixel is lit, and
/// the image is bit-identical to [`draw_phong`] (tested).
///
/// ```
/// use fixshade::raster::phong::Sampling;
/// use fixshade::sampler::{Threshold, SEED_K_Q8};
/// let s = Sampling { segment: 8, threshold: Threshold::from_q8(SEED_K_Q8, [31, 63, 31]) };
/// assert_eq!(s.threshold.limits(), [0, 0, 0]); // RGB565: any change subdivides
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Sampling {
    /// Segment length L in pixels.
    pub segment: u32,
    /// Threshold K, in the target format's channel units.
    pub threshold: Threshold,
}

/// Longest piece of a span the sampled fill handles at once (the size of its stack
/// buffer of channel triples: 64 × 12 bytes).
pub const SAMPLED_PIECE: usize = 64;

/// [`draw_phong`] with the lighting sampled by pixel segments ([`Sampling`]).
/// Returns the pixels covered (before the depth test) and the lighting
/// evaluations made.
///
/// ```
/// use fixshade::raster::phong::{draw_phong_sampled, PhongVertex, PixelLight, Sampling};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::sampler::Threshold;
/// use fixshade::target::{Framebuffer, Gray8};
///
/// /// A constant light: every segment's ends agree.
/// struct Grey;
/// impl PixelLight for Grey {
///     fn light(&self, _p: [i32; 3], _n: [i32; 3]) -> [i32; 3] {
///         [1 << 15; 3]
///     }
/// }
/// let mut px = [0u8; 32 * 32];
/// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 32, 32).unwrap();
/// let z = [0, 0, 1 << 30];
/// let v = |x: i32, y: i32| PhongVertex { x: x * 16, y: y * 16, z: 0, n: z, p: [0; 3] };
/// let s = Sampling { segment: 8, threshold: Threshold::from_q8(0, [255; 3]) };
/// let (pixels, evals) =
///     draw_phong_sampled::<Gray8, _, NoDepth, _>(&mut fb, [v(0, 0), v(0, 32), v(32, 0)], &Grey, s);
/// assert_eq!(pixels, 496);
/// assert!(evals * 4 < pixels); // about one evaluation per 8 pixels, plus span ends
/// assert!(px.iter().filter(|&&p| p != 0).all(|&p| p == 128));
/// ```
pub fn draw_phong_sampled<P, T, Z, L>(
    target: &mut T,
    v: [PhongVertex; 3],
    light: &L,
    sampling: Sampling,
) -> (u32, u32)
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    L: PixelLight,
{
    draw_phong_with::<P, T, Z, Rows, Exact, L>(target, v, light, Some(sampling))
}

/// The common body of [`draw_phong`] and [`draw_phong_sampled`]: (pixels covered,
/// lighting evaluations; the latter only counted when sampling).
fn draw_phong_with<P, T, Z, F, D, L>(
    target: &mut T,
    v: [PhongVertex; 3],
    light: &L,
    sampling: Option<Sampling>,
) -> (u32, u32)
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    F: PhongFill,
    D: Divide,
    L: PixelLight,
{
    if super::vertex::outside_guard(arrays::map(v, |p| (p.x, p.y))) {
        return (0, 0);
    }
    if Z::TEST && !target.has_depth() {
        return draw_phong_with::<P, T, super::span::NoDepth, F, D, L>(target, v, light, sampling);
    }
    let sv = arrays::map(v, |p| ScreenVertex {
        x: p.x,
        y: p.y,
        z: p.z,
        c: [0; 3],
    });
    let Some((s, det)) = setup_with_det_div::<D>(sv) else {
        return (0, 0);
    };
    // The same order as `Setup::v` (equal keys only in zero-area triangles).
    let mut sorted = v;
    sorted.sort_unstable_by_key(|p| (p.y, p.x));
    let planes = Planes::new(&sorted, &det);
    let Some(rows) = row_range(&s, target.rows()) else {
        return (0, 0);
    };
    let mut evals = 0u32;
    let pixels = scan::<P, T, Z, _>(target, &s, rows, false, |color, depth, span| {
        let a = planes.at(span.x0, span.y);
        match sampling {
            None => fill::<P, Z, F, L>(color, depth, span.v[3], &s, a, &planes, light),
            Some(sm) => {
                let e = fill_sampled::<P, Z, L>(color, depth, span.v[3], &s, a, &planes, light, sm);
                evals = evals.saturating_add(e);
            }
        }
    });
    (pixels, evals)
}

/// Fills one span: `z` is the lattice depth and `a` the attributes at its first pixel.
#[inline(always)]
fn fill<P: PixelFormat, Z: DepthMode, F: PhongFill, L: PixelLight>(
    color: &mut [P::Raw],
    depth: &mut [impl DepthFormat],
    z: i32,
    s: &Setup,
    a: [i64; PA],
    planes: &Planes,
    light: &L,
) {
    let gz = s.gx[3];
    let g = planes.gx;
    let mut depth = depth.iter_mut();
    if F::EVEN_ODD {
        // Even pixels from `a`, odd ones from `a + G`; both step by 2G.
        let g2: [i64; PA] = arrays::from_fn(|k| g[k].wrapping_mul(2));
        let mut even = a;
        let mut odd: [i64; PA] = arrays::from_fn(|k| a[k].wrapping_add(g[k]));
        let (mut ze, mut zo) = (z, z.wrapping_add(gz));
        let gz2 = gz.wrapping_mul(2);
        let mut pairs = color.chunks_mut(2);
        for pair in &mut pairs {
            if depth_pass::<Z>(depth.next(), ze) {
                shade_pixel::<P, L>(&mut pair[0], &even, light);
            }
            if let Some(c) = pair.get_mut(1) {
                if depth_pass::<Z>(depth.next(), zo) {
                    shade_pixel::<P, L>(c, &odd, light);
                }
            }
            for k in 0..PA {
                even[k] = even[k].wrapping_add(g2[k]);
                odd[k] = odd[k].wrapping_add(g2[k]);
            }
            ze = ze.wrapping_add(gz2);
            zo = zo.wrapping_add(gz2);
        }
    } else {
        let mut a = a;
        let mut z = z;
        for c in color.iter_mut() {
            if depth_pass::<Z>(depth.next(), z) {
                shade_pixel::<P, L>(c, &a, light);
            }
            for k in 0..PA {
                a[k] = a[k].wrapping_add(g[k]);
            }
            z = z.wrapping_add(gz);
        }
    }
}

/// The lighting of one span piece as a [`PixelFn`]: pixel `x` of the piece lies at
/// `a + x·G` on the lattice.
struct PieceLight<'l, P, L> {
    a: [i64; PA],
    g: [i64; PA],
    light: &'l L,
    _format: core::marker::PhantomData<P>,
}

impl<P: PixelFormat, L: PixelLight> PixelFn for PieceLight<'_, P, L> {
    #[inline]
    fn eval(&mut self, x: u32, _y: u32) -> [u32; 3] {
        // x < SAMPLED_PIECE; wrapping like every lattice step.
        let a = arrays::from_fn(|k| self.a[k].wrapping_add((x as i64).wrapping_mul(self.g[k])));
        lit_channels::<P, L>(&a, self.light)
    }
}

/// Fills one span with sampled lighting (see [`Sampling`]); returns the evaluations.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn fill_sampled<P: PixelFormat, Z: DepthMode, L: PixelLight>(
    color: &mut [P::Raw],
    depth: &mut [impl DepthFormat],
    z: i32,
    s: &Setup,
    a: [i64; PA],
    planes: &Planes,
    light: &L,
    sm: Sampling,
) -> u32 {
    let gz = s.gx[3];
    let g = planes.gx;
    let seg = sm.segment.clamp(1, SAMPLED_PIECE as u32);
    let mut buf = [[0u32; 3]; SAMPLED_PIECE];
    let mut depth = depth.iter_mut();
    let mut f = PieceLight::<P, L> {
        a,
        g,
        light,
        _format: core::marker::PhantomData,
    };
    let mut z = z;
    let mut evals = 0u32;
    for piece in color.chunks_mut(SAMPLED_PIECE) {
        let out = &mut buf[..piece.len()];
        evals = evals.saturating_add(fill_row(&mut f, 0, seg, sm.threshold, out));
        for (c, ch) in piece.iter_mut().zip(out.iter()) {
            if depth_pass::<Z>(depth.next(), z) {
                P::store(c, P::pack(ch[0], ch[1], ch[2]));
            }
            z = z.wrapping_add(gz);
        }
        // The next piece starts SAMPLED_PIECE pixels on (wrapping, like the lattice).
        for (a, g) in f.a.iter_mut().zip(g.iter()) {
            *a = a.wrapping_add(g.wrapping_mul(SAMPLED_PIECE as i64));
        }
    }
    evals
}
