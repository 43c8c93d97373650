//! Span filling and the pixel operations behind it.
//!
//! A [`Span`] is the plain data the edge walker hands over for one row: the pixel
//! range `[x0, x1)` (already clipped to the target), the attribute values at `x0`
//! from the triangle's lattice, and, for methods that want them, the exact edge
//! crossings with the attribute values interpolated along the edges.
//!
//! A [`SpanMethod`] turns that into pixel values; [`write_run`] is the pixel stage
//! shared by every method: depth test against the u16 buffer (strictly nearer wins),
//! pack to the pixel format, store.

use super::setup::{Setup, ATTRS};
use crate::shade::Shading;
use crate::target::{PixelFormat, Target};

/// Edge crossings of a row, for methods that interpolate between the edges.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct EdgeValues {
    /// Left crossing in pixel-centre coordinates (pixel x has its centre at x), Q.16.
    pub xl: i64,
    /// Right crossing, Q.16.
    pub xr: i64,
    /// Attribute values at the left crossing (true values, bias included).
    pub il: [i64; ATTRS],
    /// Attribute values at the right crossing.
    pub ir: [i64; ATTRS],
}

/// One row's worth of work for a span method.
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
pub trait DepthMode {
    /// True to test and write the u16 depth buffer.
    const TEST: bool;
}

/// Test and write depth: a pixel is drawn when its depth is strictly below the
/// stored one.
#[derive(Copy, Clone, Debug, Default)]
pub struct DepthTest;
/// Ignore depth; later triangles overwrite earlier ones.
#[derive(Copy, Clone, Debug, Default)]
pub struct NoDepth;

impl DepthMode for DepthTest {
    const TEST: bool = true;
}
impl DepthMode for NoDepth {
    const TEST: bool = false;
}

/// How a span's pixel values are computed.
pub trait SpanMethod {
    /// Name used by the CLI and scene files.
    const NAME: &'static str;
    /// True if the method needs [`Span::edges`].
    const EDGE_VALUES: bool;
    /// Per-triangle data of the method (lane offsets, multiples of the increment).
    type Tri;
    /// Computes the per-triangle data once, before the first span.
    fn prepare(tri: &Setup) -> Self::Tri;
    /// Fills `color` (exactly the span's pixels) and `depth` (the same pixels, or
    /// empty with [`NoDepth`]).
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [u16],
        span: &Span,
        tri: &Setup,
        data: &Self::Tri,
    );
    /// Rasterizes a set-up triangle. The default walks its edges and hands each span
    /// to [`SpanMethod::fill`] ([`super::draw_setup`]); triangle-level methods such as
    /// the Sierpinski subdivision override it.
    fn draw<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(target: &mut T, tri: &Setup) -> u32
    where
        Self: Sized,
    {
        super::draw_setup::<P, T, Self, Z, Sh>(target, tri)
    }
}

/// Packs the rounded channels `r >> 16`, `g >> 16`, `b >> 16`. Channel values are in
/// [0, MAX + 0.57) by the setup bound, so the shifts give 0..=MAX.
#[inline(always)]
fn pack<P: PixelFormat>(r: i32, g: i32, b: i32) -> P::Raw {
    P::pack((r >> 16) as u32, (g >> 16) as u32, (b >> 16) as u32)
}

/// The u16 depth of a Q16.16 depth value (bias included).
#[inline(always)]
fn depth_of(z: i32) -> u16 {
    ((z as u32) >> 16) as u16
}

/// The pixel stage for one pixel: depth test (strictly nearer wins), pack, store.
/// `d` is ignored without a depth test.
#[inline(always)]
pub fn pack_pixel<P: PixelFormat, Z: DepthMode>(c: &mut P::Raw, d: &mut u16, v: &[i32; ATTRS]) {
    if Z::TEST {
        let zz = depth_of(v[3]);
        if zz >= *d {
            return;
        }
        *d = zz;
    }
    P::store(c, pack::<P>(v[0], v[1], v[2]));
}

/// The pixel stage: writes `color.len()` pixels starting from values `v`, stepping
/// by `g` per pixel (wrapping adds: exact modulo 2³², see `setup`). The attributes are
/// held in separate scalars so the loop keeps them in registers.
#[inline(always)]
pub fn write_run<P: PixelFormat, Z: DepthMode, Sh: Shading>(
    color: &mut [P::Raw],
    depth: &mut [u16],
    v: [i32; ATTRS],
    g: &[i32; ATTRS],
) {
    let [mut r, mut gg, mut b, mut z] = v;
    let [dr, dg, db, dz] = *g;
    if Sh::INTERPOLATE {
        if Z::TEST {
            for (c, d) in color.iter_mut().zip(depth.iter_mut()) {
                let zz = depth_of(z);
                if zz < *d {
                    *d = zz;
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
                let zz = depth_of(z);
                if zz < *d {
                    *d = zz;
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
#[derive(Copy, Clone, Debug, Default)]
pub struct Gradient;

impl SpanMethod for Gradient {
    const NAME: &'static str = "gradient";
    const EDGE_VALUES: bool = false;
    type Tri = ();
    fn prepare(_: &Setup) {}
    #[inline(always)]
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [u16],
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
/// Error: the edge values are stepped with increments rounded to 2⁻¹⁶ of a unit
/// (≤ 4096 rows: below 0.001 output steps), and the per-span increment is truncated
/// to one unit (≤ 4096 pixels: below 0.07 output steps); the first pixel is an
/// interpolation with weight in [0, 1], so no error is amplified on narrow spans.
/// The total stays within the same 1-step bound as [`Gradient`]. An increment that
/// does not fit `i32` (a span narrower than 1/128 pixel, which holds one pixel) is
/// wrapped, which is harmless because it is never used.
#[derive(Copy, Clone, Debug, Default)]
pub struct Classic;

impl SpanMethod for Classic {
    const NAME: &'static str = "classic";
    const EDGE_VALUES: bool = true;
    type Tri = ();
    fn prepare(_: &Setup) {}
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [u16],
        span: &Span,
        _tri: &Setup,
        _: &(),
    ) {
        let e = &span.edges;
        let w = e.xr - e.xl; // > 0: the span is not empty
        if w <= 0 {
            return;
        }
        let t = ((span.x0 as i64) << 16) - e.xl; // in [0, w]
        let mut v = [0i32; ATTRS];
        let mut g = [0i32; ATTRS];
        for k in 0..ATTRS {
            let diff = e.ir[k] - e.il[k]; // |diff| < 2^33
                                          // diff·t < 2^33·2^29 = 2^62; diff << 16 < 2^49.
            v[k] = (e.il[k] + diff * t / w) as i32; // modulo 2^32 (depth is unsigned)
            g[k] = ((diff << 16) / w) as i32;
        }
        write_run::<P, Z, Sh>(color, depth, v, &g);
    }
}
