//! The parallel span methods of seed 000 (§3.1–3.2) and seed 003: several pixel
//! intensities per step instead of one.
//!
//! In hardware these are separate computing units; in software they are independent
//! accumulators (instruction-level parallelism) and lanes the compiler can keep in
//! vector registers. Every method computes the same lattice values as
//! [`Gradient`](super::span::Gradient): pixel `x0 + i` of a span gets
//! `v + i·Gx` (wrapping `i32`), only the order and the grouping of the additions
//! differ. Modular integer addition is exact, so every method here produces the
//! same pixels as `Gradient`, bit for bit; no truncation error accumulates, and the
//! thesis' error formulas for truncated accumulators (δ = δ0 + z·2^−(V+1) for the
//! classic and δ0 + ⌊z/2⌋·2^−(V+2) for the even/odd scheme) have nothing to bound
//! here. The tests compare every method with `Gradient` byte for byte.
//!
//! Multiples of the increment (2·ΔI, 3·ΔI, 4·ΔI, …) are computed once per triangle,
//! with shifts and at most one addition, as the seed prescribes.

use super::setup::{Setup, ATTRS};
use super::shading::Shading;
use super::span::{pack_pixel, write_run, DepthMode, Span, SpanMethod};
use crate::arrays;
use crate::divide::Exact;
use crate::target::{DepthFormat, PixelFormat};

#[inline(always)]
fn add(a: &[i32; ATTRS], b: &[i32; ATTRS]) -> [i32; ATTRS] {
    [
        a[0].wrapping_add(b[0]),
        a[1].wrapping_add(b[1]),
        a[2].wrapping_add(b[2]),
        a[3].wrapping_add(b[3]),
    ]
}

#[inline(always)]
fn sub(a: &[i32; ATTRS], b: &[i32; ATTRS]) -> [i32; ATTRS] {
    [
        a[0].wrapping_sub(b[0]),
        a[1].wrapping_sub(b[1]),
        a[2].wrapping_sub(b[2]),
        a[3].wrapping_sub(b[3]),
    ]
}

/// `k·g` by shifts and adds (k ≤ 64), wrapping.
#[inline(always)]
fn times(g: &[i32; ATTRS], k: usize) -> [i32; ATTRS] {
    arrays::map(*g, |x| {
        let mut acc = 0i32;
        let mut bit = 0;
        while (k >> bit) != 0 {
            if (k >> bit) & 1 == 1 {
                acc = acc.wrapping_add(x.wrapping_shl(bit));
            }
            bit += 1;
        }
        acc
    })
}

/// Writes pixel `i` of the run with values `v` (depth test, pack, store).
#[inline(always)]
fn put<P: PixelFormat, Z: DepthMode>(
    color: &mut [P::Raw],
    depth: &mut [impl DepthFormat],
    i: usize,
    v: &[i32; ATTRS],
) {
    if Z::TEST {
        pack_pixel::<P, Z>(&mut color[i], &mut depth[i], v);
    } else {
        pack_pixel::<P, Z>(&mut color[i], &mut 0u16, v);
    }
}

/// The depth row for the ARMv7E-M paired loops, which test two 16-bit depths per
/// instruction: the row itself with `u16` cells, an empty one without a depth test,
/// `None` with `u32` cells.
#[cfg(fixshade_dsp)]
#[inline(always)]
fn u16_row<Z: DepthMode>(depth: &mut [impl DepthFormat]) -> Option<&mut [u16]> {
    if Z::TEST {
        DepthFormat::as_u16(depth)
    } else {
        Some(&mut [])
    }
}

/// `K` accumulators, the j-th starting at `v + j·ΔI`, each stepping by `K·ΔI`
/// (seed 000 §3.1). `K = 2` is the even/odd scheme: on an odd-length span the second
/// accumulator stops one step early.
///
/// ```
/// use fixshade::raster::span::{Gradient, NoDepth, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Rgb565Le};
/// use fixshade::raster::parallel::KWay;
/// // Draws one Gouraud triangle with method `S` into a 40×30 frame.
/// fn draw<S: SpanMethod>() -> [u16; 40 * 30] {
///     let mut px = [0u16; 40 * 30];
///     let mut fb = Framebuffer::<Rgb565Le>::new(&mut px, None, 40, 30).unwrap();
///     let v = |x: i32, y: i32, c: [i32; 3]| ScreenVertex { x, y, z: 0, c };
///     let tri = [v(13, 7, [31 << 16, 0, 0]), v(600, 200, [0, 63 << 16, 0]), v(90, 470, [0, 0, 31 << 16])];
///     draw_triangle::<Rgb565Le, _, S, NoDepth, Gouraud>(&mut fb, tri);
///     px
/// }
/// // Three accumulators stepping 3·ΔI: the same pixels as the constant gradient.
/// assert_eq!(draw::<KWay<3>>(), draw::<Gradient>());
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct KWay<const K: usize>;

/// The seed's even/odd method: one accumulator for the even pixels `x0, x0+2, …`,
/// one for the odd ones, both stepping by 2·ΔI. The same computation as
/// [`KWay<2>`] under its own name.
///
/// ```
/// use fixshade::raster::span::{Gradient, NoDepth, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Rgb565Le};
/// use fixshade::raster::parallel::EvenOdd;
/// // Draws one Gouraud triangle with method `S` into a 40×30 frame.
/// fn draw<S: SpanMethod>() -> [u16; 40 * 30] {
///     let mut px = [0u16; 40 * 30];
///     let mut fb = Framebuffer::<Rgb565Le>::new(&mut px, None, 40, 30).unwrap();
///     let v = |x: i32, y: i32, c: [i32; 3]| ScreenVertex { x, y, z: 0, c };
///     let tri = [v(13, 7, [31 << 16, 0, 0]), v(600, 200, [0, 63 << 16, 0]), v(90, 470, [0, 0, 31 << 16])];
///     draw_triangle::<Rgb565Le, _, S, NoDepth, Gouraud>(&mut fb, tri);
///     px
/// }
/// // Two accumulators over the even and odd pixels: the same pixels.
/// assert_eq!(draw::<EvenOdd>(), draw::<Gradient>());
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct EvenOdd;

/// Lane starting offsets `j·ΔI` for j < K and the common step `K·ΔI`.
///
/// ```
/// use fixshade::raster::parallel::{KWay, Lanes};
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::span::SpanMethod;
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32, r: i32| ScreenVertex { x, y, z: 0, c: [r, 0, 0] };
/// let s = setup([v(0, 0, 0), v(160, 0, 10 << 16), v(0, 160, 0)]).unwrap();
/// // Computed once per triangle: K starting offsets j·ΔI and the step K·ΔI.
/// let lanes: Lanes<4> = KWay::<4>::prepare(&s);
/// assert!(format!("{lanes:?}").contains("step"));
/// ```
#[derive(Copy, Clone, Debug)]
pub struct Lanes<const K: usize> {
    start: [[i32; ATTRS]; K],
    step: [i32; ATTRS],
}

fn lanes<const K: usize>(s: &Setup) -> Lanes<K> {
    Lanes {
        start: arrays::from_fn(|j| times(&s.gx, j)),
        step: times(&s.gx, K),
    }
}

#[inline(always)]
fn fill_kway<const K: usize, P: PixelFormat, Z: DepthMode, Sh: Shading>(
    color: &mut [P::Raw],
    depth: &mut [impl DepthFormat],
    span: &Span,
    tri: &Setup,
    l: &Lanes<K>,
) {
    if !Sh::INTERPOLATE {
        return write_run::<P, Z, Sh>(color, depth, span.v, &tri.gx);
    }
    let n = color.len();
    // With the DSP extension: the same lanes, two pixels per step (5-6-5 formats,
    // spans whose channels stay in their packed lanes).
    #[cfg(fixshade_dsp)]
    if super::dsp::is_565::<P>() && n >= super::dsp::MIN_SPAN {
        if let Some(p) = super::dsp::span_start_565(&span.v, &tri.gx, n) {
            // The lanes j·ΔI and the step K·ΔI packed, from the packed increment (exact
            // modulo 2^64, like the lanes).
            let d = super::dsp::packed_565(&tri.gx);
            let mut c = [p; K];
            for j in 1..K {
                c[j] = c[j - 1].wrapping_add(d);
            }
            let z = arrays::from_fn(|j| span.v[3].wrapping_add(l.start[j][3]));
            let dc = c[K - 1].wrapping_add(d).wrapping_sub(p);
            // The paired loops test two 16-bit depths at once: with 32-bit cells the
            // portable loop below draws the span.
            if let Some(d16) = u16_row::<Z>(depth) {
                return super::dsp::kway::<K, P, Z>(color, d16, c, z, dc, l.step[3]);
            }
        }
    }
    let mut acc: [[i32; ATTRS]; K] = arrays::from_fn(|j| add(&span.v, &l.start[j]));
    let mut i = 0;
    while i + K <= n {
        for (j, a) in acc.iter_mut().enumerate() {
            put::<P, Z>(color, depth, i + j, a);
            *a = add(a, &l.step);
        }
        i += K;
    }
    for (j, a) in acc.iter().enumerate().take(n - i) {
        put::<P, Z>(color, depth, i + j, a);
    }
}

impl<const K: usize> SpanMethod for KWay<K> {
    const NAME: &'static str = match K {
        2 => "kway2",
        3 => "kway3",
        4 => "kway4",
        _ => "kway",
    };
    const EDGE_VALUES: bool = false;
    type Divider = Exact;
    type Tri = Lanes<K>;
    fn prepare(s: &Setup) -> Lanes<K> {
        lanes::<K>(s)
    }
    #[inline(always)]
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        tri: &Setup,
        data: &Lanes<K>,
    ) {
        fill_kway::<K, P, Z, Sh>(color, depth, span, tri, data);
    }
}

impl SpanMethod for EvenOdd {
    const NAME: &'static str = "even-odd";
    const EDGE_VALUES: bool = false;
    type Divider = Exact;
    type Tri = Lanes<2>;
    fn prepare(s: &Setup) -> Lanes<2> {
        lanes::<2>(s)
    }
    #[inline(always)]
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        tri: &Setup,
        data: &Lanes<2>,
    ) {
        fill_kway::<2, P, Z, Sh>(color, depth, span, tri, data);
    }
}

/// Two interpolators, one from each end of the span towards its middle (seed 000
/// §3.2): the front one adds ΔI, the back one, starting at `v + (n−1)·ΔI`, subtracts it.
///
/// ```
/// use fixshade::raster::span::{Gradient, NoDepth, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Rgb565Le};
/// use fixshade::raster::parallel::Counter;
/// // Draws one Gouraud triangle with method `S` into a 40×30 frame.
/// fn draw<S: SpanMethod>() -> [u16; 40 * 30] {
///     let mut px = [0u16; 40 * 30];
///     let mut fb = Framebuffer::<Rgb565Le>::new(&mut px, None, 40, 30).unwrap();
///     let v = |x: i32, y: i32, c: [i32; 3]| ScreenVertex { x, y, z: 0, c };
///     let tri = [v(13, 7, [31 << 16, 0, 0]), v(600, 200, [0, 63 << 16, 0]), v(90, 470, [0, 0, 31 << 16])];
///     draw_triangle::<Rgb565Le, _, S, NoDepth, Gouraud>(&mut fb, tri);
///     px
/// }
/// // Two interpolators meeting in the middle of each span: the same pixels.
/// assert_eq!(draw::<Counter>(), draw::<Gradient>());
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Counter;

impl SpanMethod for Counter {
    const NAME: &'static str = "counter";
    const EDGE_VALUES: bool = false;
    type Divider = Exact;
    type Tri = ();
    fn prepare(_: &Setup) {}
    #[inline(always)]
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        tri: &Setup,
        _: &(),
    ) {
        if !Sh::INTERPOLATE {
            return write_run::<P, Z, Sh>(color, depth, span.v, &tri.gx);
        }
        let n = color.len();
        if n == 0 {
            return;
        }
        let g = &tri.gx;
        // (n − 1)·ΔI: n ≤ 4096, wrapping multiply is exact modulo 2^32.
        let last = (n - 1) as i32;
        let mut front = span.v;
        let mut back = add(&span.v, &arrays::map(*g, |x| x.wrapping_mul(last)));
        let (mut i, mut j) = (0, n - 1);
        while i < j {
            put::<P, Z>(color, depth, i, &front);
            put::<P, Z>(color, depth, j, &back);
            front = add(&front, g);
            back = sub(&back, g);
            i += 1;
            j -= 1;
        }
        if i == j {
            put::<P, Z>(color, depth, i, &front);
        }
    }
}

/// Width of the segment that `p` units fill (seed 000 §3.2): with `k = log₂ p + 1`,
/// `w = k + (k − 2)·((k − 1) + (k − 3)) / 2`; p = 2, 4, 8, 16, 32, 64 gives
/// w = 2, 4, 8, 14, 22, 32.
///
/// ```
/// use fixshade::raster::parallel::segment_width;
/// assert_eq!([2, 4, 8, 16, 32, 64].map(segment_width), [2, 4, 8, 14, 22, 32]);
/// ```
pub const fn segment_width(p: usize) -> usize {
    let k = p.trailing_zeros() as usize + 1;
    if k < 3 {
        return k; // p = 1, 2: the (k − 2) factor is zero
    }
    k + (k - 2) * ((k - 1) + (k - 3)) / 2
}

/// Largest segment width.
pub const MAX_SEGMENT: usize = 32;

/// `P` units fill a segment of `w = segment_width(P)` pixels at once:
/// `I_i = I_0 + i·ΔI`, with the offsets `i·ΔI` computed once per triangle; the next
/// segment starts `w·ΔI` further on.
///
/// In software the units are vector lanes: a segment is computed as independent
/// lanes (structure of arrays, branch-free depth test as a select), which the
/// compiler turns into SIMD instructions on the host and into independent
/// instructions an in-order MCU pipeline can overlap.
///
/// ```
/// use fixshade::raster::span::{Gradient, NoDepth, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Rgb565Le};
/// use fixshade::raster::parallel::Segment;
/// // Draws one Gouraud triangle with method `S` into a 40×30 frame.
/// fn draw<S: SpanMethod>() -> [u16; 40 * 30] {
///     let mut px = [0u16; 40 * 30];
///     let mut fb = Framebuffer::<Rgb565Le>::new(&mut px, None, 40, 30).unwrap();
///     let v = |x: i32, y: i32, c: [i32; 3]| ScreenVertex { x, y, z: 0, c };
///     let tri = [v(13, 7, [31 << 16, 0, 0]), v(600, 200, [0, 63 << 16, 0]), v(90, 470, [0, 0, 31 << 16])];
///     draw_triangle::<Rgb565Le, _, S, NoDepth, Gouraud>(&mut fb, tri);
///     px
/// }
/// // Eight units filling segments of 8 pixels: the same pixels.
/// assert_eq!(draw::<Segment<8>>(), draw::<Gradient>());
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Segment<const P: usize>;

/// Per-triangle lane offsets `i·ΔI` for i < w, one array per attribute, and the
/// segment step `w·ΔI`.
///
/// ```
/// use fixshade::raster::parallel::{Segment, SegmentLanes};
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::span::SpanMethod;
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32, r: i32| ScreenVertex { x, y, z: 0, c: [r, 0, 0] };
/// let s = setup([v(0, 0, 0), v(160, 0, 10 << 16), v(0, 160, 0)]).unwrap();
/// // 16 units fill segments of 14 pixels; the offsets i·ΔI are computed once per triangle.
/// assert_eq!(Segment::<16>::W, 14);
/// let lanes: SegmentLanes = Segment::<16>::prepare(&s);
/// assert!(format!("{lanes:?}").contains("off"));
/// ```
#[derive(Copy, Clone, Debug)]
pub struct SegmentLanes {
    off: [[i32; MAX_SEGMENT]; ATTRS],
    step: [i32; ATTRS],
    /// The offsets by pairs of pixels, colours packed in the 5-6-5 lanes
    /// ([`super::dsp::segment`]).
    #[cfg(fixshade_dsp)]
    pairs: [super::dsp::PairOffsets; MAX_SEGMENT / 2],
    /// The packed increment.
    #[cfg(fixshade_dsp)]
    packed: u64,
}

impl<const P: usize> Segment<P> {
    /// Pixels per segment.
    pub const W: usize = segment_width(P);
}

/// One segment: lane `k` gets `base + off[·][k]`. Branch-free when the format's
/// store is a plain store.
#[inline(always)]
fn segment_block<P: PixelFormat, Z: DepthMode, C: DepthFormat>(
    color: &mut [P::Raw],
    depth: &mut [C],
    base: &[i32; ATTRS],
    off: &[[i32; MAX_SEGMENT]; ATTRS],
) {
    let n = color.len().min(MAX_SEGMENT);
    let (or, og, ob, oz) = (&off[0][..n], &off[1][..n], &off[2][..n], &off[3][..n]);
    if Z::TEST {
        let depth = &mut depth[..n];
        for k in 0..n {
            let r = base[0].wrapping_add(or[k]);
            let g = base[1].wrapping_add(og[k]);
            let b = base[2].wrapping_add(ob[k]);
            let z = C::from_depth(base[3].wrapping_add(oz[k]));
            let px = P::pack((r >> 16) as u32, (g >> 16) as u32, (b >> 16) as u32);
            let keep = z < depth[k];
            if P::PLAIN_STORE {
                depth[k] = if keep { z } else { depth[k] };
                color[k] = if keep { px } else { color[k] };
            } else if keep {
                depth[k] = z;
                P::store(&mut color[k], px);
            }
        }
    } else {
        for k in 0..n {
            let r = base[0].wrapping_add(or[k]);
            let g = base[1].wrapping_add(og[k]);
            let b = base[2].wrapping_add(ob[k]);
            P::store(
                &mut color[k],
                P::pack((r >> 16) as u32, (g >> 16) as u32, (b >> 16) as u32),
            );
        }
    }
}

impl<const P: usize> SpanMethod for Segment<P> {
    const NAME: &'static str = match P {
        2 => "segment2",
        4 => "segment4",
        8 => "segment8",
        16 => "segment16",
        32 => "segment32",
        64 => "segment64",
        _ => "segment",
    };
    const EDGE_VALUES: bool = false;
    type Divider = Exact;
    type Tri = SegmentLanes;
    fn prepare(s: &Setup) -> SegmentLanes {
        let mut off = [[0i32; MAX_SEGMENT]; ATTRS];
        for (a, lane) in off.iter_mut().enumerate() {
            for i in 1..Self::W {
                lane[i] = lane[i - 1].wrapping_add(s.gx[a]);
            }
        }
        // k·ΔI packed, from the packed increment (exact modulo 2^64, like the lanes).
        #[cfg(fixshade_dsp)]
        let (pairs, packed) = {
            let d = super::dsp::packed_565(&s.gx);
            let mut pairs = [super::dsp::PairOffsets::default(); MAX_SEGMENT / 2];
            let mut k = 0u64;
            for (j, p) in pairs.iter_mut().enumerate().take(Self::W / 2) {
                *p = super::dsp::PairOffsets {
                    c: [k, k.wrapping_add(d)],
                    z: [off[3][2 * j], off[3][2 * j + 1]],
                };
                k = k.wrapping_add(d).wrapping_add(d);
            }
            (pairs, d)
        };
        SegmentLanes {
            off,
            step: times(&s.gx, Self::W),
            #[cfg(fixshade_dsp)]
            pairs,
            #[cfg(fixshade_dsp)]
            packed,
        }
    }
    #[inline(always)]
    fn fill<P2: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P2::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        tri: &Setup,
        data: &SegmentLanes,
    ) {
        if !Sh::INTERPOLATE {
            return write_run::<P2, Z, Sh>(color, depth, span.v, &tri.gx);
        }
        let w = Self::W;
        let n = color.len();
        // With the DSP extension: the same segments, two pixels per step (5-6-5
        // formats, whose packed lanes are `Rgb565Le`'s; spans whose channels stay in
        // their lanes).
        #[cfg(fixshade_dsp)]
        if super::dsp::is_565::<P2>() && n >= super::dsp::MIN_SPAN {
            if let Some(c) = super::dsp::span_start_565(&span.v, &tri.gx, n) {
                if let Some(d16) = u16_row::<Z>(depth) {
                    return super::dsp::segment::<P2, Z>(
                        color,
                        d16,
                        &data.pairs[..w / 2],
                        c,
                        span.v[3],
                        data.packed,
                        tri.gx[3],
                    );
                }
            }
        }
        let mut base = span.v;
        let mut i = 0;
        while i < n {
            let end = (i + w).min(n);
            let d = if Z::TEST {
                &mut depth[i..end]
            } else {
                &mut depth[..0]
            };
            segment_block::<P2, Z, _>(&mut color[i..end], d, &base, &data.off);
            base = add(&base, &data.step);
            i = end;
        }
    }
}
