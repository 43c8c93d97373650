//! The Sierpinski subdivision (seed 000 §3.3, DESIGN.md method 4): shade a quarter of
//! the triangle and replicate it.
//!
//! The midpoints `K = (A+B)/2`, `L = (B+C)/2`, `M = (A+C)/2` split triangle `ABC` into
//! four congruent triangles. The three corner triangles `AKM`, `KBL`, `MLC` are
//! translations of one another by the half-edge vectors `(B−A)/2` and `(C−A)/2`; the
//! central one `KLM` is their point reflection. Because the attributes are a plane,
//! a point `p + t` of a translated copy differs from `p` by the constant
//! `t·∇I` (for `t = (B−A)/2` that is the seed's `(I_B − I_A)/2`, its (3.4)–(3.6)).
//! So the spans of one corner triangle (the one at the top vertex `A`, where the
//! seed starts) are computed once — start pixel, end pixel, start value — and each
//! is written three times: at `p`, at `p + (B−A)/2` and at `p + (C−A)/2`, the values
//! plus the per-copy offset. The central triangle is walked normally (see below).
//!
//! # When replication is exact: [`SierpinskiExact`]
//!
//! Replication is exact when both half-edge vectors are whole pixels, i.e. when all
//! vertex deltas are multiples of 32 in Q12.4 (even pixels, the seed's condition
//! "БП and МП of every side even"); [`replicable`] tests it. Then:
//!
//! 1. *The midpoints are exact* Q12.4 points, so the four sub-triangles tile `ABC`:
//!    their interiors are disjoint and their closures cover it.
//! 2. *The coverage rule is the perturbed-centre rule.* The edge walker covers pixel
//!    `(x, y)` iff the point `c + (ε, ε²)`, `c` its centre, lies strictly inside the
//!    triangle for every small enough `ε > 0`: a row includes pixel `q` iff its centre
//!    is at or right of the left edge's crossing and left of the right edge's
//!    (`edge` module: `q = ⌈(X(yc) − 8)/16⌉`, and `16q + 8 ≥ X(yc)` ⇔
//!    `16q + 8 + ε > X(yc) + ε²·dx/dy`); the first row is the first centre at or below
//!    the top vertex, the last one the last centre strictly above the bottom vertex,
//!    and the middle row goes with the lower edge (all ⇔ `yc + ε²` compared with the
//!    vertex `y`). A perturbed point lies on no line for small `ε` (`a·ε + b·ε² = 0`
//!    for all small `ε` forces `a = b = 0`), so it lies in the interior of exactly one
//!    sub-triangle iff it lies in the interior of `ABC`: every pixel of `ABC` is
//!    covered by exactly one sub-triangle, and no other pixel — the internal edges
//!    are drawn once, and the result is watertight against `ABC`'s neighbours
//!    because `ABC`'s own pixel set is unchanged.
//! 3. *The rule is invariant under whole-pixel translations.* Moving a triangle by
//!    `(16·tx, 16·ty)` moves every centre onto a centre: `first_row(y + 16·ty) =
//!    first_row(y) + ty`, and the edge stepper's numerator on the shifted row becomes
//!    `N' = N + 16·tx·dy = N + tx·D`, so `q' = ⌈N'/D⌉ = q + tx`; the vertex sort by
//!    `(y, x)` and the orientation are unchanged. The spans of `AKM + t` are exactly
//!    the spans of `AKM` moved by `t`.
//! 4. *The values are the lattice values.* Every pixel `Gradient` writes gets the
//!    parent's lattice value `V(x, y) = A + (x − xa)·Gx + (y − ya)·Gy`, computed in
//!    wrapping `i32`, i.e. exactly in the ring ℤ/2³². Here the sub-triangles use the
//!    parent's [`Setup`] (its anchor, `A`, `Gx`, `Gy`, never a set-up of their own),
//!    and a copy's value `V(p) + tx·Gx + ty·Gy` equals `V(p + t)` in that ring.
//!    Within one triangle every pixel is written once, so the order of the writes
//!    does not matter, with or without the depth test.
//!
//! Hence [`SierpinskiExact`] writes the same bytes as [`Gradient`], colour and depth,
//! bit for bit. Triangles whose deltas are not even pixels (almost all of them for
//! subpixel vertices: all three vertices must be congruent modulo 2 pixels, a chance
//! of 1 in 2²⁰ for random Q12.4 vertices) are drawn by the default edge walker,
//! which is `Gradient` itself; so are flat triangles with differing vertex colours
//! (see the end).
//!
//! # The seed's variant: [`Sierpinski`]
//!
//! The seed makes every delta even by changing the mesh: its table 3.1 lists four
//! sufficient conditions (x even / odd for all points × y even / odd for all points)
//! and it enforces one "by writing 0 (alignment to even) or 1 (alignment to odd) into
//! the least significant bit of the X and Y coordinates of every point of the grid"
//! („записавши значення «0» – вирівнювання по парності, або «1» – вирівнювання по
//! непарності, в молодший розряд X та Y координат для всіх точок координатної
//! сітки“), accepting the distortion because the intensities do not move with the
//! points. The seed's points are whole pixels. [`snap_coord`] generalises its
//! "clear the least significant bit" to Q12.4: round to the nearest multiple of 32
//! (an even pixel), ties toward −∞. On whole-pixel input (`16·n`) that is exactly
//! `16·(n & !1)`, the seed's rule; on subpixel input it moves a coordinate by at most
//! one pixel (the seed's bound) instead of up to two. Then every triangle is
//! replicable and [`Sierpinski`] draws exactly what [`Gradient`] draws for the
//! snapped triangle, with the vertices' own colours and depths (a fresh
//! [`setup::setup`] of the snapped vertices): the only error is geometric.
//!
//! Watertightness: the snapping is a pure function of a vertex's own coordinates, so
//! two triangles sharing an edge share the snapped edge, and the snapped mesh is the
//! image of the mesh under one vertex map. For a mesh that tiles a region whose
//! boundary snapping keeps in place, the signed number of snapped triangles over any
//! perturbed centre is its winding number, 1: there are no holes, and if no triangle
//! changed its orientation every pixel is covered exactly once. A triangle that
//! snapping collapses to zero area is drawn as nothing, which is correct: it
//! contributes nothing to the winding number, and its neighbours' snapped triangles
//! cover its area. The exceptions: (a) a sliver narrower than about two pixels can be
//! flipped by snapping and then overlaps its neighbours (overdraw, never a hole);
//! (b) triangles the caller culls on their unsnapped coordinates before this method
//! sees them leave their snapped area uncovered: a zero-area input triangle that
//! snapping inflates, a back face whose snapped sliver faces the front (along
//! silhouettes), and a triangle whose unsnapped bounding box misses the frame or
//! strip but whose snapped one reaches its last column or first/last row (the edge
//! moves by up to one pixel). Snapping before culling removes (b).
//!
//! # The central triangle
//!
//! `KLM` is shaded normally, by walking its edges with the parent's lattice. It is
//! the point reflection of the corner triangles, and the top-left rule is not
//! invariant under a point reflection (a left edge becomes a right edge), so
//! reflected spans would disagree with the rule at centres exactly on an edge.
//!
//! In software the saving is per row (edge stepping and the span's start value are
//! computed once for three rows); the pixel writes are the same in number. Into a
//! strip, the shaded triangle is walked only over the rows from which some copy
//! lands in the strip (the union of three row intervals), not over all its rows.
//!
//! Flat shading: the renderer gives all three vertices the provoking colour, so the
//! colour gradients are zero and the span boundaries do not matter. (With differing
//! vertex colours `Gradient` would pack each span's colour at its first pixel;
//! [`SierpinskiExact`] then walks the triangle to stay identical, [`Sierpinski`]
//! packs at the sub-triangle spans' first pixels.)

use crate::arrays;
use core::ops::Range;

use super::draw_setup;
use super::edge::{first_row, EdgeStepper};
use super::setup::{self, Setup, ATTRS};
use super::shading::Shading;
use super::span::{write_run, DepthMode, Gradient, NoDepth, Span, SpanMethod};
use super::vertex::{ScreenVertex, GUARD};
use crate::divide::Exact;
use crate::target::{DepthFormat, PixelFormat, Target};

/// A point in Q12.4.
type Pt = (i32, i32);

/// Where the pixels of one triangle came from, inside the target.
///
/// ```
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::sierpinski::SierpinskiExact;
/// use fixshade::raster::span::NoDepth;
/// use fixshade::raster::ScreenVertex;
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Gray8};
/// let mut px = [0u8; 64 * 64];
/// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 64, 64).unwrap();
/// let v = |x: i32, y: i32, g: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [g << 16; 3] };
/// // Even deltas: the corner triangle is shaded once and copied to two others.
/// let s = setup([v(0, 0, 0), v(0, 48, 100), v(48, 0, 200)]).unwrap();
/// let st = SierpinskiExact::draw_stats::<Gray8, _, NoDepth, Gouraud>(&mut fb, &s);
/// assert!(st.replicated > 0 && st.walked == 0);
/// assert_eq!(st.total(), st.shaded + st.replicated + st.centre);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct SierpinskiStats {
    /// Pixels of the shaded corner triangle written at its own place.
    pub shaded: u32,
    /// Pixels written as translated copies of the shaded triangle's spans.
    pub replicated: u32,
    /// Pixels of the central triangle.
    pub centre: u32,
    /// Pixels drawn by the default edge walker (no replication).
    pub walked: u32,
}

impl SierpinskiStats {
    /// All pixels covered inside the target (what [`SpanMethod::draw`] returns).
    pub fn total(&self) -> u32 {
        self.shaded + self.replicated + self.centre + self.walked
    }
}

/// Snaps one Q12.4 coordinate to an even pixel: the nearest multiple of 32, ties
/// toward −∞, kept inside the guard band (`|c| ≤ GUARD − 32`). Idempotent and
/// monotone; `|snap_coord(c) − c| ≤ 16` for `|c| ≤ GUARD − 48` (the last pixels of
/// the guard band are clamped inwards).
///
/// ```
/// use fixshade::raster::sierpinski::snap_coord;
/// // On whole pixels (16·n) this is the seed's "write 0 into the LSB": 16·(n & !1).
/// assert_eq!([0, 16, 32, 48, -16].map(snap_coord), [0, 0, 32, 32, -32]);
/// assert_eq!([15, 17, 47, 49].map(snap_coord), [0, 32, 32, 64]);
/// ```
pub const fn snap_coord(c: i32) -> i32 {
    let s = (c.saturating_add(15) >> 5) << 5;
    let lim = GUARD - 32; // a multiple of 32: clamping keeps the result snapped
    if s > lim {
        lim
    } else if s < -lim {
        -lim
    } else {
        s
    }
}

/// Snaps a vertex's x and y with [`snap_coord`]; depth and colour stay.
///
/// ```
/// use fixshade::raster::sierpinski::snap;
/// use fixshade::raster::ScreenVertex;
/// let v = ScreenVertex { x: 3 * 16, y: 5 * 16 + 3, z: 7, c: [1, 2, 3] };
/// let s = snap(v);
/// assert_eq!((s.x, s.y, s.z, s.c), (32, 96, 7, [1, 2, 3])); // even pixels; the rest kept
/// ```
pub const fn snap(v: ScreenVertex) -> ScreenVertex {
    ScreenVertex {
        x: snap_coord(v.x),
        y: snap_coord(v.y),
        ..v
    }
}

/// True if all vertex deltas of `s` are multiples of 32 (even pixels) in x and y:
/// the midpoints are exact and the half-edge vectors are whole pixels.
///
/// ```
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::sierpinski::replicable;
/// use fixshade::raster::ScreenVertex;
/// let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [0; 3] };
/// assert!(replicable(&setup([v(0, 0), v(0, 6), v(8, 0)]).unwrap()));
/// assert!(!replicable(&setup([v(0, 0), v(0, 5), v(8, 0)]).unwrap()));
/// ```
pub fn replicable(s: &Setup) -> bool {
    let [a, b, c] = s.v;
    ((b.x - a.x) | (c.x - a.x) | (b.y - a.y) | (c.y - a.y)) & 31 == 0
}

/// The exact variant: replicates where the deltas are even pixels, otherwise draws
/// like [`Gradient`]. Output is identical to `Gradient`'s, bit for bit.
///
/// ```
/// use fixshade::raster::span::{Gradient, NoDepth, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Rgb565Le};
/// use fixshade::raster::sierpinski::SierpinskiExact;
/// // Draws one Gouraud triangle with method `S` into a 40×30 frame.
/// fn draw<S: SpanMethod>() -> [u16; 40 * 30] {
///     let mut px = [0u16; 40 * 30];
///     let mut fb = Framebuffer::<Rgb565Le>::new(&mut px, None, 40, 30).unwrap();
///     let v = |x: i32, y: i32, c: [i32; 3]| ScreenVertex { x, y, z: 0, c };
///     let tri = [v(13, 7, [31 << 16, 0, 0]), v(600, 200, [0, 63 << 16, 0]), v(90, 470, [0, 0, 31 << 16])];
///     draw_triangle::<Rgb565Le, _, S, NoDepth, Gouraud>(&mut fb, tri);
///     px
/// }
/// // Replicates only where the deltas allow it exactly: the same pixels.
/// assert_eq!(draw::<SierpinskiExact>(), draw::<Gradient>());
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct SierpinskiExact;

/// The seed's variant: snaps every vertex to even pixels ([`snap`]), then always
/// replicates. Draws exactly what [`Gradient`] draws for the snapped triangle.
///
/// ```
/// use fixshade::raster::sierpinski::Sierpinski;
/// use fixshade::raster::span::SpanMethod;
/// // The seed's variant moves vertices to even pixels before setup (coverage changes by
/// // at most one pixel per vertex; colours are replicated, NMSE reported in docs/).
/// assert!(Sierpinski::SNAPS);
/// assert_eq!(Sierpinski::NAME, "sierpinski");
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Sierpinski;

impl SierpinskiExact {
    /// Draws `tri` and says which path each pixel took. `draw` returns its total.
    pub fn draw_stats<P, T, Z, Sh>(target: &mut T, tri: &Setup) -> SierpinskiStats
    where
        P: PixelFormat,
        T: Target<P>,
        Z: DepthMode,
        Sh: Shading,
    {
        if Z::TEST && !target.has_depth() {
            return Self::draw_stats::<P, T, NoDepth, Sh>(target, tri);
        }
        let flat_ok = Sh::INTERPOLATE || (tri.gx[..3] == [0; 3] && tri.gy[..3] == [0; 3]);
        if replicable(tri) && flat_ok {
            replicate::<P, T, Z, Sh>(target, tri)
        } else {
            SierpinskiStats {
                walked: draw_setup::<P, T, Self, Z, Sh>(target, tri),
                ..SierpinskiStats::default()
            }
        }
    }
}

impl Sierpinski {
    /// Draws `tri` snapped to even pixels and says which path each pixel took.
    /// A triangle that snapping makes degenerate draws nothing.
    pub fn draw_stats<P, T, Z, Sh>(target: &mut T, tri: &Setup) -> SierpinskiStats
    where
        P: PixelFormat,
        T: Target<P>,
        Z: DepthMode,
        Sh: Shading,
    {
        if Z::TEST && !target.has_depth() {
            return Self::draw_stats::<P, T, NoDepth, Sh>(target, tri);
        }
        let v = arrays::map(tri.v, snap);
        if v == tri.v {
            return replicate::<P, T, Z, Sh>(target, tri);
        }
        // Snapped coordinates stay inside the guard band, as setup requires.
        match setup::setup(v) {
            Some(s) => replicate::<P, T, Z, Sh>(target, &s),
            None => SierpinskiStats::default(),
        }
    }
}

impl SpanMethod for SierpinskiExact {
    const NAME: &'static str = "sierpinski-exact";
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
        Gradient::fill::<P, Z, Sh>(color, depth, span, tri, &());
    }
    fn draw<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        tri: &Setup,
    ) -> u32 {
        Self::draw_stats::<P, T, Z, Sh>(target, tri).total()
    }
}

impl SpanMethod for Sierpinski {
    const NAME: &'static str = "sierpinski";
    const EDGE_VALUES: bool = false;
    const SNAPS: bool = true;
    type Divider = Exact;
    type Tri = ();
    fn prepare(_: &Setup) {}
    fn snap(v: ScreenVertex) -> ScreenVertex {
        snap(v)
    }
    #[inline(always)]
    fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading>(
        color: &mut [P::Raw],
        depth: &mut [impl DepthFormat],
        span: &Span,
        tri: &Setup,
        _: &(),
    ) {
        Gradient::fill::<P, Z, Sh>(color, depth, span, tri, &());
    }
    fn draw<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        tri: &Setup,
    ) -> u32 {
        Self::draw_stats::<P, T, Z, Sh>(target, tri).total()
    }
}

/// The midpoint of `a` and `b`, whose deltas are even: exact.
#[inline]
fn mid(a: Pt, b: Pt) -> Pt {
    (a.0 + (b.0 - a.0) / 2, a.1 + (b.1 - a.1) / 2)
}

/// Shades the corner triangle at the top vertex once and writes it three times,
/// then walks the central triangle. `s` must be [`replicable`].
fn replicate<P, T, Z, Sh>(target: &mut T, s: &Setup) -> SierpinskiStats
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    Sh: Shading,
{
    let [a, b, c] = arrays::map(s.v, |p| (p.x, p.y));
    let (k, l, m) = (mid(a, b), mid(b, c), mid(a, c));
    // Whole-pixel translations of the corner triangle AKM onto KBL and MLC.
    let t: [Pt; 3] = [
        (0, 0),
        ((b.0 - a.0) / 32, (b.1 - a.1) / 32),
        ((c.0 - a.0) / 32, (c.1 - a.1) / 32),
    ];
    // Value offsets t·∇V on the parent's lattice (wrapping: exact modulo 2^32).
    let off: [[i32; ATTRS]; 3] = arrays::map(t, |(tx, ty)| {
        arrays::from_fn(|i| {
            tx.wrapping_mul(s.gx[i])
                .wrapping_add(ty.wrapping_mul(s.gy[i]))
        })
    });
    let rows = target.rows();
    let width = target.width() as i32;
    let mut st = SierpinskiStats::default();
    let mut emit = |y: i32, ql: i32, qr: i32, v: &[i32; ATTRS]| {
        for (j, (&(tx, ty), o)) in t.iter().zip(off.iter()).enumerate() {
            let yy = y + ty;
            if !rows.contains(&yy) {
                continue;
            }
            let vj = arrays::from_fn(|i| v[i].wrapping_add(o[i]));
            let n = put_span::<P, T, Z, Sh>(target, width, yy, ql + tx, qr + tx, vj, &s.gx);
            if j == 0 {
                st.shaded += n;
            } else {
                st.replicated += n;
            }
        }
    };
    // Copy j lands in the target from the shaded rows `rows − ty_j`. Walk the union
    // of the three intervals (merged, in order), so that a strip costs only the rows
    // that reach it.
    let mut iv = arrays::map(t, |(_, ty)| (rows.start - ty, rows.end - ty));
    iv.sort_unstable();
    let mut cur = iv[0];
    for r in &iv[1..] {
        if r.0 <= cur.1 {
            cur.1 = cur.1.max(r.1);
        } else {
            walk_tri([a, k, m], s, cur.0..cur.1, &mut emit);
            cur = *r;
        }
    }
    walk_tri([a, k, m], s, cur.0..cur.1, &mut emit);
    walk_tri([k, l, m], s, rows, |y, ql, qr, v| {
        st.centre += put_span::<P, T, Z, Sh>(target, width, y, ql, qr, *v, &s.gx);
    });
    st
}

/// Writes the pixels `[xs, xe)` of target row `y` (inside `target.rows()`), clipped
/// to `[0, width)`, starting from values `v` at `xs` and stepping by `g`. Returns the
/// number of pixels written.
#[inline(always)]
fn put_span<P, T, Z, Sh>(
    target: &mut T,
    width: i32,
    y: i32,
    xs: i32,
    xe: i32,
    v: [i32; ATTRS],
    g: &[i32; ATTRS],
) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    Sh: Shading,
{
    let x0 = xs.max(0);
    let x1 = xe.min(width);
    if x0 >= x1 {
        return 0;
    }
    let skip = x0 - xs;
    let v = arrays::from_fn(|i| v[i].wrapping_add(skip.wrapping_mul(g[i])));
    let (crow, drow) = target.row(y);
    let (a, b) = (x0 as usize, x1 as usize);
    let depth = if Z::TEST {
        &mut drow[a..b]
    } else {
        &mut drow[..0]
    };
    write_run::<P, Z, Sh>(&mut crow[a..b], depth, v, g);
    (x1 - x0) as u32
}

/// Walks the rows in `rows` of the triangle with Q12.4 vertices `v` under the
/// top-left rule (the same stepping as the default walker) and calls
/// `emit(y, ql, qr, value)` for every non-empty row: pixels `[ql, qr)`, not clipped
/// in x, and the parent lattice value at `(ql, y)`.
#[inline(always)]
fn walk_tri<F>(mut v: [Pt; 3], s: &Setup, rows: Range<i32>, mut emit: F)
where
    F: FnMut(i32, i32, i32, &[i32; ATTRS]),
{
    v.sort_unstable_by_key(|p| (p.1, p.0));
    let [t, m, b] = v;
    // |deltas| < 2^17: the products fit i64.
    let det = (m.0 - t.0) as i64 * (b.1 - t.1) as i64 - (b.0 - t.0) as i64 * (m.1 - t.1) as i64;
    if det == 0 {
        return;
    }
    let mid_left = det < 0; // y points down, as in `setup`
    let y_top = first_row(t.1).max(rows.start);
    let y_mid = first_row(m.1);
    let y_bot = first_row(b.1).min(rows.end);
    if y_top >= y_bot {
        return;
    }
    half(
        s,
        (t, b),
        (t, m),
        mid_left,
        y_top..y_mid.min(y_bot),
        &mut emit,
    );
    half(
        s,
        (t, b),
        (m, b),
        mid_left,
        y_mid.max(y_top)..y_bot,
        &mut emit,
    );
}

/// Rows `ys` between the long edge and one short edge (see `raster::walk`).
#[inline(always)]
fn half<F>(s: &Setup, long: (Pt, Pt), short: (Pt, Pt), mid_left: bool, ys: Range<i32>, emit: &mut F)
where
    F: FnMut(i32, i32, i32, &[i32; ATTRS]),
{
    if ys.is_empty() {
        return;
    }
    let el = EdgeStepper::new(long.0, long.1, ys.start);
    let es = EdgeStepper::new(short.0, short.1, ys.start);
    let (mut left, mut right) = if mid_left { (es, el) } else { (el, es) };
    let mut vl = s.at(left.q, ys.start);
    // A row step of the left edge: one row down and `a` (or `a + 1`) pixels across.
    let inc_a: [i32; ATTRS] =
        arrays::from_fn(|i| s.gy[i].wrapping_add(left.a.wrapping_mul(s.gx[i])));
    let inc_b: [i32; ATTRS] = arrays::from_fn(|i| inc_a[i].wrapping_add(s.gx[i]));
    for y in ys {
        if left.q < right.q {
            emit(y, left.q, right.q, &vl);
        }
        let inc = if left.step() { &inc_b } else { &inc_a };
        for (x, d) in vl.iter_mut().zip(inc.iter()) {
            *x = x.wrapping_add(*d);
        }
        right.step();
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use std::vec;
    use std::vec::Vec;

    use super::*;
    use crate::raster::draw_triangle;
    use crate::raster::span::DepthTest;
    use crate::shade::{Flat, Gouraud};
    use crate::target::{Framebuffer, Gray8, Rgb888, Strip};

    /// 64-bit LCG; the high bits are good enough for test geometry.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u32 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 33) as u32
        }
        /// Uniform in `[lo, hi]`.
        fn range(&mut self, lo: i32, hi: i32) -> i32 {
            lo + (self.next() % (hi - lo + 1) as u32) as i32
        }
    }

    /// Mock format: every store adds one, so overdraw shows.
    struct Mark;

    impl PixelFormat for Mark {
        type Raw = u8;
        const MAX: [u32; 3] = [1, 1, 1];
        const GRAY: bool = true;
        const BYTES: usize = 1;
        const NAME: &'static str = "mark";
        fn pack(_: u32, _: u32, _: u32) -> u8 {
            0
        }
        fn unpack(p: u8) -> [u32; 3] {
            [u32::from(p); 3]
        }
        fn store(dst: &mut u8, _: u8) {
            *dst = dst.saturating_add(1);
        }
        fn bytes(p: u8) -> [u8; 3] {
            [p, 0, 0]
        }
    }

    const W: u32 = 61;
    const H: u32 = 47;

    type Tri = [ScreenVertex; 3];

    fn vertex(rng: &mut Rng, x: i32, y: i32) -> ScreenVertex {
        ScreenVertex {
            x,
            y,
            z: (rng.next() % (65534 << 16)) & !0xF,
            c: [0; 3].map(|_: i32| (rng.range(0, 255) << 16) | rng.range(0, 0x7FFF)),
        }
    }

    /// A random triangle reaching up to 40 pixels past the frame. With `grid`, all
    /// three vertices are congruent modulo 32 (a shared random residue), so the deltas
    /// are even pixels. With `flat`, all vertices carry the provoking colour, as the
    /// renderer does for flat shading.
    fn random_tri(rng: &mut Rng, grid: bool, flat: bool) -> Tri {
        let (rx, ry) = (rng.range(0, 31), rng.range(0, 31));
        let big = rng.next() % 4 == 0;
        let spread = if big { 900 } else { 240 };
        let (cx, cy) = (
            rng.range(-640, 16 * W as i32 + 640),
            rng.range(-640, 16 * H as i32 + 640),
        );
        let mut v = [ScreenVertex::default(); 3];
        for p in v.iter_mut() {
            let (mut x, mut y) = (
                cx + rng.range(-spread, spread),
                cy + rng.range(-spread, spread),
            );
            if grid {
                x = (x & !31) + rx;
                y = (y & !31) + ry;
            }
            *p = vertex(rng, x, y);
        }
        if flat {
            let c = v[2].c;
            v[0].c = c;
            v[1].c = c;
        }
        v
    }

    fn random_tris(rng: &mut Rng, n: usize, grid: bool, flat: bool) -> Vec<Tri> {
        (0..n).map(|_| random_tri(rng, grid, flat)).collect()
    }

    /// Renders `tris` with `S` into a W × H frame, whole (`strip == 0`) or in strips of
    /// `strip` rows; returns colour, depth and the summed pixel counts.
    fn render<P: PixelFormat, S: SpanMethod, Z: DepthMode, Sh: Shading>(
        tris: &[Tri],
        strip: u32,
        with_depth: bool,
    ) -> (Vec<P::Raw>, Vec<u16>, u32) {
        let n = (W * H) as usize;
        let mut color = vec![P::Raw::default(); n];
        let mut depth = vec![0xFFFFu16; n];
        let mut count = 0;
        let h = if strip == 0 { H } else { strip };
        let mut y0 = 0;
        while y0 < H {
            let hh = h.min(H - y0);
            let r = (y0 * W) as usize..((y0 + hh) * W) as usize;
            let d = if with_depth {
                Some(&mut depth[r.clone()])
            } else {
                None
            };
            let mut t = Strip::<P>::new(&mut color[r], d, W, H, y0, hh).unwrap();
            for tri in tris {
                count += draw_triangle::<P, _, S, Z, Sh>(&mut t, *tri);
            }
            y0 += hh;
        }
        (color, depth, count)
    }

    /// `S` must give the same bytes and counts as `reference` drawing `ref_tris`.
    fn same<P: PixelFormat, S: SpanMethod, Z: DepthMode, Sh: Shading>(
        tris: &[Tri],
        ref_tris: &[Tri],
        what: &str,
    ) where
        P::Raw: PartialEq,
    {
        for strip in [0, 1, 5, 16] {
            for with_depth in [true, false] {
                let got = render::<P, S, Z, Sh>(tris, strip, with_depth);
                let want = render::<P, Gradient, Z, Sh>(ref_tris, strip, with_depth);
                assert!(got.0 == want.0, "{what}: colour differs, strip {strip}");
                assert_eq!(got.1, want.1, "{what}: depth differs, strip {strip}");
                assert_eq!(got.2, want.2, "{what}: pixel count differs, strip {strip}");
            }
        }
    }

    fn all_modes<S: SpanMethod>(tris: &[Tri], flat_tris: &[Tri], what: &str, snap_ref: bool) {
        let r = |t: &[Tri]| -> Vec<Tri> {
            if snap_ref {
                t.iter().map(|v| v.map(snap)).collect()
            } else {
                t.to_vec()
            }
        };
        let (rt, rf) = (r(tris), r(flat_tris));
        same::<Rgb888, S, DepthTest, Gouraud>(tris, &rt, what);
        same::<Rgb888, S, NoDepth, Gouraud>(tris, &rt, what);
        same::<Rgb888, S, DepthTest, Flat>(flat_tris, &rf, what);
        same::<Rgb888, S, NoDepth, Flat>(flat_tris, &rf, what);
        same::<Gray8, S, DepthTest, Gouraud>(tris, &rt, what);
        same::<Mark, S, NoDepth, Flat>(flat_tris, &rf, what);
    }

    #[test]
    fn exact_is_bit_identical_to_gradient_on_even_deltas() {
        let mut rng = Rng(1);
        for _ in 0..8 {
            let tris = random_tris(&mut rng, 40, true, false);
            let flat = random_tris(&mut rng, 40, true, true);
            assert!(tris
                .iter()
                .all(|t| { setup::setup(*t).is_none_or(|s| replicable(&s)) }));
            all_modes::<SierpinskiExact>(&tris, &flat, "even deltas", false);
        }
    }

    #[test]
    fn exact_is_bit_identical_to_gradient_on_arbitrary_triangles() {
        let mut rng = Rng(2);
        for _ in 0..8 {
            let mut tris = random_tris(&mut rng, 40, false, false);
            let mut flat = random_tris(&mut rng, 40, false, true);
            // A few replicable ones mixed in.
            tris.extend(random_tris(&mut rng, 10, true, false));
            flat.extend(random_tris(&mut rng, 10, true, true));
            all_modes::<SierpinskiExact>(&tris, &flat, "arbitrary", false);
        }
    }

    #[test]
    fn huge_triangles_across_the_guard_band() {
        // Vertices up to ±4000 pixels: copies land thousands of rows away, spans are
        // clipped on both sides, values wrap.
        let mut rng = Rng(9);
        let mut huge = |grid: bool| -> Vec<Tri> {
            (0..30)
                .map(|_| {
                    let (rx, ry) = (rng.range(0, 31), rng.range(0, 31));
                    core::array::from_fn(|_| {
                        let (x, y) = (rng.range(-64000, 64000), rng.range(-64000, 64000));
                        let (x, y) = if grid {
                            ((x & !31) + rx, (y & !31) + ry)
                        } else {
                            (x, y)
                        };
                        vertex(&mut rng, x, y)
                    })
                })
                .filter(|t| setup::setup(*t).is_some())
                .collect()
        };
        let (even, any) = (huge(true), huge(false));
        let flat: Vec<Tri> = even
            .iter()
            .map(|t| {
                let mut t = *t;
                t[0].c = t[2].c;
                t[1].c = t[2].c;
                t
            })
            .collect();
        all_modes::<SierpinskiExact>(&even, &flat, "huge, even", false);
        all_modes::<Sierpinski>(&any, &flat, "huge, snapped", true);
    }

    #[test]
    fn exact_falls_back_for_flat_triangles_with_varying_colour() {
        // Gradient packs a flat span's colour at its first pixel: only the walker
        // reproduces that when the vertex colours differ.
        let mut rng = Rng(3);
        let tris = random_tris(&mut rng, 60, true, false);
        same::<Rgb888, SierpinskiExact, NoDepth, Flat>(&tris, &tris, "flat, varying");
        same::<Rgb888, SierpinskiExact, DepthTest, Flat>(&tris, &tris, "flat, varying");
    }

    #[test]
    fn snapped_equals_gradient_on_the_snapped_triangles() {
        let mut rng = Rng(4);
        for _ in 0..6 {
            let keep = |t: &Tri| setup::setup(*t).is_some();
            let tris: Vec<Tri> = random_tris(&mut rng, 40, false, false)
                .into_iter()
                .filter(keep)
                .collect();
            let flat: Vec<Tri> = random_tris(&mut rng, 40, false, true)
                .into_iter()
                .filter(keep)
                .collect();
            all_modes::<Sierpinski>(&tris, &flat, "snapped", true);
        }
    }

    #[test]
    fn snapping_is_idempotent_deterministic_and_the_seeds_rule() {
        let mut rng = Rng(5);
        for _ in 0..100_000 {
            let c = rng.range(-GUARD + 1, GUARD - 1);
            let s = snap_coord(c);
            assert_eq!(s & 31, 0, "{c}");
            assert_eq!(snap_coord(s), s, "{c}");
            if c.abs() <= GUARD - 48 {
                assert!((s - c).abs() <= 16, "{c} -> {s}");
            }
            let d = rng.range(-GUARD + 1, GUARD - 1);
            if c <= d {
                assert!(snap_coord(c) <= snap_coord(d), "monotone: {c} {d}");
            }
        }
        // Ties go toward −∞; whole pixels follow the seed: clear the pixel's LSB.
        for n in -4093..=4093 {
            assert_eq!(snap_coord(16 * n), 16 * (n & !1), "pixel {n}");
            assert_eq!(snap_coord(32 * (n / 2) + 16), 32 * (n / 2));
        }
        // Only x and y take part: a vertex shared by two triangles (with different
        // colours or depths there) snaps to the same point.
        let a = vertex(&mut rng, 1234, -577);
        let b = ScreenVertex {
            z: 7,
            c: [1, 2, 3],
            ..a
        };
        assert_eq!((snap(a).x, snap(a).y), (snap(b).x, snap(b).y));
        assert_eq!((snap(a).x, snap(a).y), (1248, -576));
        assert_eq!(snap(snap(a)), snap(a));
        assert_eq!((snap(a).z, snap(a).c), (a.z, a.c));
        // The guard band is kept.
        assert_eq!(snap_coord(GUARD - 1), GUARD - 32);
        assert_eq!(snap_coord(-GUARD + 1), -GUARD + 32);
    }

    /// Counts per pixel of `tris` drawn with `S` (Mark format), whole or in strips.
    fn counts<S: SpanMethod>(tris: &[Tri], strip: u32) -> Vec<u8> {
        render::<Mark, S, NoDepth, Gouraud>(tris, strip, false).0
    }

    /// Asserts equal pixel counts, reporting the first few differences.
    #[track_caller]
    fn assert_counts(got: &[u8], want: &[u8], what: &str) {
        let bad: Vec<(u32, u32, u8, u8)> = got
            .iter()
            .zip(want.iter())
            .enumerate()
            .filter(|(_, (g, w))| g != w)
            .map(|(i, (g, w))| (i as u32 % W, i as u32 / W, *g, *w))
            .collect();
        assert!(
            bad.is_empty(),
            "{what}: {} pixels differ, (x, y, got, want): {:?}",
            bad.len(),
            &bad[..bad.len().min(8)]
        );
    }

    /// Pixels of the frame whose centres lie in `[x0, x1) × [y0, y1)` (Q12.4).
    fn rect_mask(x0: i32, y0: i32, x1: i32, y1: i32) -> Vec<u8> {
        let inside = |p: i32, lo: i32, hi: i32| lo <= 16 * p + 8 && 16 * p + 8 < hi;
        (0..H as i32)
            .flat_map(|y| (0..W as i32).map(move |x| (x, y)))
            .map(|(x, y)| u8::from(inside(x, x0, x1) && inside(y, y0, y1)))
            .collect()
    }

    fn area2(t: &[Pt; 3]) -> i64 {
        let [a, b, c] = *t;
        (b.0 - a.0) as i64 * (c.1 - a.1) as i64 - (c.0 - a.0) as i64 * (b.1 - a.1) as i64
    }

    /// `n + 1` grid lines `cell` apart from `start`.
    fn lines(start: i32, n: usize, cell: i32) -> Vec<i32> {
        (0..=n as i32).map(|i| start + i * cell).collect()
    }

    /// The grid on the lines `xs` × `ys` (Q12.4), interior vertices moved by
    /// `jitter()`, boundary vertices only along their side, each
    /// cell cut by a random diagonal, vertex order shuffled. Returns the triangles
    /// and, per triangle, its vertices in consistent (unjittered orientation)
    /// order, or `None` if the jitter folded the mesh.
    #[allow(clippy::type_complexity)]
    fn grid(
        rng: &mut Rng,
        xs: &[i32],
        ys: &[i32],
        mut jitter: impl FnMut(&mut Rng) -> i32,
    ) -> Option<(Vec<Tri>, Vec<[Pt; 3]>)> {
        let (nx, ny) = (xs.len() - 1, ys.len() - 1);
        let mut p = vec![vec![(0, 0); ny + 1]; nx + 1];
        for (i, col) in p.iter_mut().enumerate() {
            for (j, q) in col.iter_mut().enumerate() {
                let jx = if i == 0 || i == nx { 0 } else { jitter(rng) };
                let jy = if j == 0 || j == ny { 0 } else { jitter(rng) };
                *q = (xs[i] + jx, ys[j] + jy);
            }
        }
        let mut tris = Vec::new();
        let mut oriented = Vec::new();
        for i in 0..nx {
            for j in 0..ny {
                let (a, b, c, d) = (p[i][j], p[i + 1][j], p[i + 1][j + 1], p[i][j + 1]);
                let pair = if rng.next() % 2 == 0 {
                    [[a, d, c], [a, c, b]]
                } else {
                    [[a, d, b], [b, d, c]]
                };
                for t in pair {
                    // With y down, the unjittered triangles a-d-c, a-c-b, a-d-b and
                    // b-d-c all have the doubled area −cell² by this formula.
                    if area2(&t) >= 0 {
                        return None;
                    }
                    oriented.push(t);
                    let mut v = t.map(|(x, y)| vertex(rng, x, y));
                    v.rotate_left(rng.next() as usize % 3);
                    if rng.next() % 2 == 0 {
                        v.swap(0, 1);
                    }
                    tris.push(v);
                }
            }
        }
        Some((tris, oriented))
    }

    #[test]
    fn exact_coverage_is_watertight_on_grids() {
        let mut rng = Rng(6);
        let mut replicated = 0;
        for n in 0..40 {
            // Even: corners and jitter on the 2-pixel grid, so every triangle
            // replicates. Odd: arbitrary subpixel jitter, mostly walked. A jitter
            // below a quarter cell cannot fold the mesh.
            let on_grid = n % 2 == 0;
            let cell = 32 * rng.range(5, 8);
            let (x0, y0) = (rng.range(-200, 200), rng.range(-200, 200));
            let (x0, y0) = if on_grid {
                (x0 & !31, y0 & !31)
            } else {
                (x0, y0)
            };
            let (nx, ny) = (rng.range(1, 6) as usize, rng.range(1, 5) as usize);
            let jit = move |r: &mut Rng| {
                if on_grid {
                    32 * r.range(-1, 1)
                } else {
                    r.range(-cell / 4 + 1, cell / 4 - 1)
                }
            };
            let (xs, ys) = (lines(x0, nx, cell), lines(y0, ny, cell));
            let (tris, _) = grid(&mut rng, &xs, &ys, jit).expect("no fold");
            let want = rect_mask(x0, y0, x0 + nx as i32 * cell, y0 + ny as i32 * cell);
            for strip in [0, 3, 8] {
                assert_counts(&counts::<Gradient>(&tris, strip), &want, "gradient");
                let got = counts::<SierpinskiExact>(&tris, strip);
                assert_counts(&got, &want, &std::format!("grid {n}, strip {strip}"));
            }
            let mut c = vec![0u8; (W * H) as usize];
            let mut fb = Framebuffer::<Mark>::new(&mut c, None, W, H).unwrap();
            for t in &tris {
                let s = setup::setup(*t).unwrap();
                replicated += SierpinskiExact::draw_stats::<Mark, _, NoDepth, Gouraud>(&mut fb, &s)
                    .replicated;
            }
        }
        assert!(
            replicated > 1000,
            "replication happened: {replicated} pixels"
        );
    }

    #[test]
    fn snapped_coverage_is_watertight_on_grids() {
        let mut rng = Rng(7);
        let (mut collapsed, mut flipped) = (0, 0);
        for n in 0..120 {
            // 0, sparse: cells of 10 px, jitter below 1.5 px; with snapping (≤ 1 px
            // per axis) every vertex stays within a quarter cell of its grid point,
            // so no triangle collapses or flips. 1, dense: cells of 3 px, jitter
            // below a quarter cell: snapping collapses triangles. 2, slivers: cells of
            // 1–1.75 px, so that neighbouring vertices snap apart or
            // together: snapping collapses and flips
            // triangles. The corners of the rectangle are even pixels, so snapping
            // keeps its boundary. A jitter below a quarter cell never folds the mesh.
            let kind = n % 3;
            let (x0, y0) = (32 * rng.range(-6, 6), 32 * rng.range(-6, 6));
            let (xs, ys, jmax) = match kind {
                0 => {
                    let (nx, ny) = (rng.range(1, 7) as usize, rng.range(1, 5) as usize);
                    (lines(x0, nx, 160), lines(y0, ny, 160), 39 - 16)
                }
                1 => {
                    let (nx, ny) = (2 * rng.range(4, 11) as usize, 2 * rng.range(4, 9) as usize);
                    (lines(x0, nx, 48), lines(y0, ny, 48), 11)
                }
                _ => {
                    let nx = rng.range(8, 40) as usize;
                    let ny = rng.range(8, 30) as usize;
                    let mut narrow = |start: i32, n: usize| {
                        let mut v = vec![start];
                        for _ in 0..n {
                            v.push(v[v.len() - 1] + rng.range(16, 28));
                        }
                        let last = v[n];
                        v.push((last + 16 + 31) & !31); // an even pixel, 16..47 further
                        v
                    };
                    (narrow(x0, nx), narrow(y0, ny), 3)
                }
            };
            let jit = move |r: &mut Rng| r.range(-jmax, jmax);
            let (tris, oriented) = grid(&mut rng, &xs, &ys, jit).expect("no fold");
            let snapped: Vec<i64> = oriented
                .iter()
                .map(|t| area2(&t.map(|(x, y)| (snap_coord(x), snap_coord(y)))))
                .collect();
            let flips = snapped.iter().filter(|&&a| a > 0).count();
            let collapses = snapped.iter().filter(|&&a| a == 0).count();
            assert!(kind > 0 || flips + collapses == 0);
            collapsed += collapses;
            flipped += flips;
            let want = rect_mask(xs[0], ys[0], xs[xs.len() - 1], ys[ys.len() - 1]);
            for strip in [0, 4, 7] {
                let got = counts::<Sierpinski>(&tris, strip);
                if flips == 0 {
                    assert_counts(&got, &want, &std::format!("grid {n}, strip {strip}"));
                } else {
                    // No holes and nothing outside; flipped slivers overdraw.
                    for (g, w) in got.iter().zip(want.iter()) {
                        assert_eq!(*g == 0, *w == 0);
                    }
                }
            }
        }
        std::println!("snapping collapsed {collapsed} and flipped {flipped} triangles");
        assert!(
            collapsed > 0,
            "the dense grids exercise collapsed triangles"
        );
    }

    /// Pixels `Gradient` covers for the triangle `t` (Q12.4 points) in the target.
    fn gradient_count(t: [Pt; 3], strip: Option<(u32, u32)>) -> u32 {
        let v = t.map(|(x, y)| ScreenVertex {
            x,
            y,
            ..ScreenVertex::default()
        });
        let mut c = vec![0u8; (W * H) as usize];
        match strip {
            None => {
                let mut fb = Framebuffer::<Mark>::new(&mut c, None, W, H).unwrap();
                draw_triangle::<Mark, _, Gradient, NoDepth, Flat>(&mut fb, v)
            }
            Some((y0, h)) => {
                let mut s = Strip::<Mark>::new(&mut c, None, W, H, y0, h).unwrap();
                draw_triangle::<Mark, _, Gradient, NoDepth, Flat>(&mut s, v)
            }
        }
    }

    #[test]
    fn replication_writes_the_corner_triangles_pixels() {
        let mut rng = Rng(8);
        let (mut inside, mut total_rep) = (0, 0);
        for n in 0..400 {
            let tri = random_tri(&mut rng, true, false);
            let Some(s) = setup::setup(tri) else { continue };
            let strip = if n % 3 == 0 {
                let y0 = rng.range(0, H as i32 - 1) as u32;
                Some((y0, rng.range(1, (H - y0) as i32) as u32))
            } else {
                None
            };
            let mut c = vec![[0u8; 3]; (W * H) as usize];
            let st = match strip {
                None => {
                    let mut fb = Framebuffer::<Rgb888>::new(&mut c, None, W, H).unwrap();
                    SierpinskiExact::draw_stats::<Rgb888, _, NoDepth, Gouraud>(&mut fb, &s)
                }
                Some((y0, h)) => {
                    let mut t = Strip::<Rgb888>::new(&mut c, None, W, H, y0, h).unwrap();
                    SierpinskiExact::draw_stats::<Rgb888, _, NoDepth, Gouraud>(&mut t, &s)
                }
            };
            let [a, b, cc] = s.v.map(|p| (p.x, p.y));
            let (k, l, m) = (mid(a, b), mid(b, cc), mid(a, cc));
            assert_eq!(st.walked, 0);
            assert_eq!(st.shaded, gradient_count([a, k, m], strip));
            assert_eq!(
                st.replicated,
                gradient_count([k, b, l], strip) + gradient_count([m, l, cc], strip)
            );
            assert_eq!(st.centre, gradient_count([k, l, m], strip));
            assert_eq!(st.total(), gradient_count([a, b, cc], strip));
            let fits =
                |p: &Pt| p.0 >= 0 && p.1 >= 0 && p.0 <= 16 * W as i32 && p.1 <= 16 * H as i32;
            if strip.is_none() && [a, b, cc].iter().all(fits) {
                assert_eq!(st.replicated, 2 * st.shaded);
                inside += 1;
            }
            total_rep += st.replicated;
        }
        assert!(inside > 5 && total_rep > 2000, "{inside} {total_rep}");
        // A triangle with odd deltas is walked.
        let tri = [(0, 0), (16 * 20, 16), (48, 16 * 30)].map(|(x, y)| vertex(&mut rng, x, y));
        let s = setup::setup(tri).unwrap();
        let mut c = vec![[0u8; 3]; (W * H) as usize];
        let mut fb = Framebuffer::<Rgb888>::new(&mut c, None, W, H).unwrap();
        let st = SierpinskiExact::draw_stats::<Rgb888, _, NoDepth, Gouraud>(&mut fb, &s);
        assert!(!replicable(&s));
        assert_eq!((st.shaded, st.replicated, st.centre), (0, 0, 0));
        assert!(st.walked > 100);
        // The snapped variant replicates it.
        let st = Sierpinski::draw_stats::<Rgb888, _, NoDepth, Gouraud>(&mut fb, &s);
        assert_eq!(st.walked, 0);
        assert_eq!(st.replicated, 2 * st.shaded);
        assert!(st.shaded > 20);
    }

    #[test]
    fn names() {
        assert_eq!(SierpinskiExact::NAME, "sierpinski-exact");
        assert_eq!(Sierpinski::NAME, "sierpinski");
    }
}
