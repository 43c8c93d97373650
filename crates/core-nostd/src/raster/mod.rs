//! Rasterization: triangle setup, edge walking, span filling.
//!
//! Contract: input is a triangle of [`ScreenVertex`]es inside the guard band
//! (|x|, |y| < [`GUARD`] in Q12.4) with colours in the target's channel units; output
//! is a sequence of [`span::Span`]s, each handed to the chosen [`span::SpanMethod`]
//! together with the target row it belongs to. Coverage follows the top-left rule
//! with pixel centres at +0.5 (see [`edge`]), so triangles that share an edge cover
//! each pixel along it exactly once.
//!
//! ```
//! use fixshade::raster::{draw_triangle, ScreenVertex};
//! use fixshade::raster::span::{Gradient, NoDepth};
//! use fixshade::shade::Gouraud;
//! use fixshade::target::{Framebuffer, Gray8};
//!
//! let mut px = [0u8; 8 * 4];
//! let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 8, 4).unwrap();
//! let white = [255 << 16; 3];
//! let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: white };
//! // A right triangle with legs of 4 pixels along the top-left corner.
//! draw_triangle::<Gray8, _, Gradient, NoDepth, Gouraud>(&mut fb, [v(0, 0), v(0, 4), v(4, 0)]);
//! let rows: Vec<String> = px
//!     .chunks(8)
//!     .map(|r| r.iter().map(|p| if *p > 0 { '#' } else { '.' }).collect())
//!     .collect();
//! // Centres exactly on the hypotenuse (a right edge) are not covered.
//! assert_eq!(rows, ["###.....", "##......", "#.......", "........"]);
//! ```

#[cfg(any(fixshade_dsp, fixshade_v6m))]
mod asm;
pub mod dsp;
pub mod edge;
pub mod parallel;
pub mod perspective;
pub mod phong;
pub mod pixel;
pub mod quadratic;
pub mod setup;
pub mod shading;
pub mod sierpinski;
pub mod span;
pub mod vertex;

use crate::arrays;
use edge::{first_row, first_row_in_guard, EdgeStepper};
use pixel::{DepthMode, NoDepth};
use setup::{Lattice, Setup, ATTRS};
use shading::Shading;
pub(crate) use vertex::outside_guard;
pub use vertex::{ScreenVertex, GUARD, SUBPIXEL_BITS};

use crate::divide::Divide;
use crate::target::{DepthFormat, PixelFormat, Target};
use core::ops::Range;

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

/// How a span's pixel values are computed.
///
/// ```
/// use fixshade::raster::setup::Setup;
/// use fixshade::raster::span::{write_run, DepthMode, NoDepth, Span, SpanMethod};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::{Gouraud, Shading};
/// use fixshade::target::{DepthFormat, Framebuffer, Gray8, PixelFormat};
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
    /// True if the method draws a triangle from its [`setup::Record`] alone
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
    /// draws with it): [`Exact`](crate::divide::Exact) for every method but [`span::WithDivide`], which names
    /// its own.
    type Divider: Divide;
    /// Sets up a triangle for this method: [`setup::setup_div`] through
    /// [`SpanMethod::Divider`] by default.
    #[inline(always)]
    fn setup(v: [ScreenVertex; 3]) -> Option<Setup> {
        setup::setup_div::<Self::Divider>(v)
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
    /// to [`SpanMethod::fill`] ([`draw_setup`]); triangle-level methods such as
    /// the Sierpinski subdivision override it.
    fn draw<P: PixelFormat, T: Target<P>, Z: DepthMode, Sh: Shading>(
        target: &mut T,
        tri: &Setup,
    ) -> u32
    where
        Self: Sized,
    {
        draw_setup::<P, T, Self, Z, Sh>(target, tri)
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

/// Attribute values along an edge for methods that want edge values: stepped with
/// increments in Q.16 of an attribute unit (`i64`).
struct EdgeAttrs {
    val: [i64; ATTRS],
    inc: [i64; ATTRS],
}

fn vattrs(v: &ScreenVertex) -> [i64; ATTRS] {
    [v.c[0] as i64, v.c[1] as i64, v.c[2] as i64, v.z as i64]
}

/// `n / d` (truncating, as `i128` division) for `0 < d < 2⁶³`, with a 64-bit
/// division when `n` fits `i64` (the usual case: |Δa| < 2³³ times 2²⁰ is below 2⁵³;
/// only an edge read far from its top vertex needs the wide one). Both divisions
/// truncate toward zero, so the quotient is the same.
#[inline]
fn div_by_rows(n: i128, d: i128) -> i128 {
    match (i64::try_from(n), i64::try_from(d)) {
        (Ok(n), Ok(d)) => (n / d) as i128,
        _ => n / d,
    }
}

impl EdgeAttrs {
    /// Values at the edge crossing of row `y` for the edge `t → b`, 16 extra
    /// fraction bits: evaluated at row `anchor` (the first row of the triangle half
    /// being walked) and stepped `y − anchor` times, so a strip that starts inside
    /// the half gets exactly the values the whole frame steps to. |Δa| ≤ 2³², so
    /// `Δa·16 << 16` < 2⁵³ and `Δa·(yc − t.y) << 16` < 2⁶⁶ would not fit: the
    /// product is taken in i128; the stepping wraps like repeated adds would.
    fn new(t: &ScreenVertex, b: &ScreenVertex, y: i32, anchor: i32) -> EdgeAttrs {
        let dy = (b.y - t.y) as i128;
        let off = (16 * anchor + 8 - t.y) as i128;
        let steps = (y - anchor) as i64;
        let (at, ab) = (vattrs(t), vattrs(b));
        let mut val = [0i64; ATTRS];
        let mut inc = [0i64; ATTRS];
        for k in 0..ATTRS {
            let da = (ab[k] - at[k]) as i128;
            inc[k] = div_by_rows((da * 16) << 16, dy) as i64;
            val[k] = ((((at[k] as i128 + setup::ROUND_BIAS as i128) << 16)
                + div_by_rows((da * off) << 16, dy)) as i64)
                .wrapping_add(steps.wrapping_mul(inc[k]));
        }
        EdgeAttrs { val, inc }
    }

    #[inline]
    fn step(&mut self) {
        for k in 0..ATTRS {
            self.val[k] += self.inc[k];
        }
    }

    #[inline]
    fn get(&self) -> [i64; ATTRS] {
        arrays::map(self.val, |v| v >> 16)
    }
}

/// Rasterizes one triangle into `target`. Returns the number of pixels covered
/// (before the depth test) inside the target. Zero-area triangles draw nothing.
///
/// Vertices must lie inside the guard band; vertices outside are rejected (nothing is
/// drawn), never wrapped.
///
/// ```
/// use fixshade::raster::span::{DepthTest, Gradient};
/// use fixshade::raster::{draw_triangle, ScreenVertex};
/// use fixshade::shade::Flat;
/// use fixshade::target::{Framebuffer, Gray8};
/// let (mut px, mut z) = ([0u8; 8 * 8], [0xFFFFu16; 8 * 8]);
/// let mut fb = Framebuffer::<Gray8>::new(&mut px, Some(&mut z), 8, 8).unwrap();
/// let v = |x: i32, y: i32, depth: u32, g: i32| ScreenVertex { x: x * 16, y: y * 16, z: depth << 16, c: [g << 16; 3] };
/// // A near dark square's half drawn after a far bright one: the near one wins.
/// let far = draw_triangle::<Gray8, _, Gradient, DepthTest, Flat>(&mut fb, [v(0, 0, 900, 250), v(0, 8, 900, 250), v(8, 0, 900, 250)]);
/// let near = draw_triangle::<Gray8, _, Gradient, DepthTest, Flat>(&mut fb, [v(0, 0, 100, 50), v(0, 8, 100, 50), v(8, 0, 100, 50)]);
/// assert_eq!(far, near); // covered pixels are counted before the depth test
/// assert_eq!(px[0], 50);
/// ```
pub fn draw_triangle<P, T, S, Z, Sh>(target: &mut T, v: [ScreenVertex; 3]) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    S: SpanMethod,
    Z: DepthMode,
    Sh: Shading,
{
    if outside_guard(arrays::map(v, |p| (p.x, p.y))) {
        return 0;
    }
    draw_in_guard::<P, T, S, Z, Sh>(target, [&v[0], &v[1], &v[2]])
}

/// [`draw_triangle`] for a triangle already known to lie inside the guard band (the
/// frame's classification checked it): setup and fill. Inlined into the caller's
/// loop on hosted targets, so the set-up triangle is built in place; bare-metal
/// targets keep one copy (flash).
#[cfg_attr(not(target_os = "none"), inline(always))]
pub(crate) fn draw_in_guard<P, T, S, Z, Sh>(target: &mut T, v: [&ScreenVertex; 3]) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    S: SpanMethod,
    Z: DepthMode,
    Sh: Shading,
{
    S::draw_vertices::<P, T, Z, Sh>(target, v)
}

/// Rasterizes a triangle that has been set up: walks its edges and hands every span
/// to `S::fill`. This is the default of [`SpanMethod::draw`].
///
/// ```
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::span::{Gradient, NoDepth};
/// use fixshade::raster::{draw_setup, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Framebuffer, Gray8};
/// let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [100 << 16; 3] };
/// let s = setup([v(0, 0), v(0, 8), v(8, 0)]).unwrap();
/// // Set up once, draw into two strips of the same 8×8 frame.
/// let mut top = [0u8; 8 * 4];
/// let mut bottom = [0u8; 8 * 4];
/// let mut a = fixshade::target::Strip::<Gray8>::new(&mut top, None, 8, 8, 0, 4).unwrap();
/// let mut b = fixshade::target::Strip::<Gray8>::new(&mut bottom, None, 8, 8, 4, 4).unwrap();
/// let n = draw_setup::<Gray8, _, Gradient, NoDepth, Gouraud>(&mut a, &s)
///     + draw_setup::<Gray8, _, Gradient, NoDepth, Gouraud>(&mut b, &s);
/// let mut whole = [0u8; 64];
/// let mut fb = Framebuffer::<Gray8>::new(&mut whole, None, 8, 8).unwrap();
/// assert_eq!(n, draw_setup::<Gray8, _, Gradient, NoDepth, Gouraud>(&mut fb, &s));
/// assert_eq!([top, bottom].concat(), whole);
/// ```
pub fn draw_setup<P, T, S, Z, Sh>(target: &mut T, s: &Setup) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    S: SpanMethod,
    Z: DepthMode,
    Sh: Shading,
{
    if Z::TEST && !target.has_depth() {
        return draw_setup::<P, T, S, NoDepth, Sh>(target, s);
    }
    let Some(rows) = row_range(s, target.rows()) else {
        return 0;
    };
    let data = S::prepare(s);
    scan::<P, T, Z, _>(
        target,
        s,
        rows,
        S::EDGE_VALUES,
        #[inline(always)]
        |c, d, span| S::fill::<P, Z, Sh>(c, d, span, s, &data),
    )
}

/// Draws a set-up triangle from its [`setup::Record`] with the constant gradient
/// (what [`span::Gradient`] draws), into whatever rows `target` holds: a record set
/// up once can be drawn into any number of strips. Returns the pixels covered.
///
/// ```
/// use fixshade::raster::setup::{setup, Record};
/// use fixshade::raster::span::NoDepth;
/// use fixshade::raster::{draw_record, ScreenVertex};
/// use fixshade::shade::Gouraud;
/// use fixshade::target::{Gray8, Strip};
/// let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [200 << 16; 3] };
/// let rec = Record::of(&setup([v(0, 0), v(0, 8), v(8, 0)]).unwrap());
/// let (mut top, mut bottom) = ([0u8; 8 * 4], [0u8; 8 * 4]);
/// let n = draw_record::<Gray8, _, NoDepth, Gouraud>(&mut Strip::new(&mut top, None, 8, 8, 0, 4).unwrap(), &rec)
///     + draw_record::<Gray8, _, NoDepth, Gouraud>(&mut Strip::new(&mut bottom, None, 8, 8, 4, 4).unwrap(), &rec);
/// assert_eq!(n, 28); // 7 + 6 + … + 1 pixels (centres inside x + y < 8)
/// ```
pub fn draw_record<P, T, Z, Sh>(target: &mut T, r: &setup::Record) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    Sh: Shading,
{
    fill_gradient::<P, T, Z, Sh, (), _>(target, r, ())
}

/// The constant-gradient fill of a set-up triangle ([`span::Gradient`]'s draw): the
/// same rows, spans and values as [`draw_setup`] with [`span::Gradient`], from a walk
/// that keeps less state per row. Each row's attribute values start from the lattice
/// value at `x = 0` of that row, stepped down by `Gy` per row, plus `x0·Gx` at the
/// span's first pixel (wrapping arithmetic, exact modulo 2³² like
/// [`setup::Setup::at`]). Where the format's three channels fit one 64-bit register
/// and the increments are unwrapped, the row values are kept packed
/// ([`pixel::packed_channels`]: linear, so the packed lattice is the lattice packed,
/// and at covered pixels the lanes hold the channels); otherwise the spans go to
/// [`span::write_run`]. On the Cortex-M cores, a whole triangle at least
/// `asm::ROWS` rows tall in a 5-6-5 target over 16-bit depth whose rows lie one
/// after another takes the row loop of `asm::packed_565_rows` (the same pixels;
/// the test leaves the band draws and the smaller triangles as they were
/// compiled).
#[cfg_attr(not(target_os = "none"), inline(always))]
pub(crate) fn fill_gradient<P, T, Z, Sh, W, L>(target: &mut T, s: &L, walk: W) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    Sh: Shading,
    W: WalkSlot,
    L: Lattice,
{
    // On the Cortex-M cores a triangle at least `asm::ROWS` rows tall, drawn whole
    // (not in bands) into a target of at least as many rows, 5-6-5 over 16-bit
    // depth and storing its rows one after another, takes the row loop in
    // assembly (`fill_565_rows`). The height is the vertices' (16 subpixels a
    // row): the cheapest test, which the small triangles pay.
    #[cfg(all(any(fixshade_dsp, fixshade_v6m), not(feature = "small-flash")))]
    if !W::ACTIVE
        && Z::TEST
        && Sh::INTERPOLATE
        && pixel::asm_565::<P>()
        && s.xy()[2].1.wrapping_sub(s.xy()[0].1) >= 16 * asm::ROWS
        && s.unwrapped()
    {
        let r = target.rows();
        if r.end.wrapping_sub(r.start) >= asm::ROWS
            && target.has_depth()
            && asm::Rows565::of::<P, T>(target).is_some()
        {
            return fill_565_rows::<P, T, L>(target, s);
        }
    }
    fill_portable::<P, T, Z, Sh, W, L>(target, s, walk)
}

/// The rows of a set-up triangle in the target's rows `rows` (`(y_top, y_mid,
/// y_bot)`, as [`walk_rows`] takes them) and the lattice values at x = 0 of the
/// first; `None` if it has no row there.
#[inline(always)]
fn first_values(s: &impl Lattice, rows: Range<i32>) -> Option<((i32, i32, i32), [i32; ATTRS])> {
    let [t, m, b] = s.xy();
    let y_top = first_row_in_guard(t.1).max(rows.start);
    let y_bot = first_row_in_guard(b.1).min(rows.end);
    if y_top >= y_bot {
        return None;
    }
    let rows = (y_top, first_row_in_guard(m.1), y_bot);
    Some((rows, s.row_start(y_top)))
}

/// [`fill_gradient`] through [`Target::row`], for every target and format.
#[inline(always)]
fn fill_portable<P, T, Z, Sh, W, L>(target: &mut T, s: &L, walk: W) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    Sh: Shading,
    W: WalkSlot,
    L: Lattice,
{
    if Z::TEST && !target.has_depth() {
        return fill_portable::<P, T, NoDepth, Sh, W, L>(target, s, walk);
    }
    let Some((rows, base)) = first_values(s, target.rows()) else {
        return 0;
    };
    let (gx, gy) = (s.gx(), s.gy());
    let packed = (
        pixel::packed_channels::<P>(&base),
        pixel::packed_channels::<P>(gx),
        pixel::packed_channels::<P>(gy),
    );
    if let (Some(mut c_row), Some(pgx), Some(pgy), true, true) =
        (packed.0, packed.1, packed.2, s.unwrapped(), Sh::INTERPOLATE)
    {
        let (mut z_row, gzx, gzy) = (base[3], gx[3], gy[3]);
        return walk_rows::<P, T, Z, W>(
            target,
            s.xy(),
            s.mid_left(),
            rows,
            walk,
            no_half,
            |span| {
                if let Some((color, depth, x0)) = span {
                    let c = crate::math::packed_at(c_row, pgx, x0);
                    let z = z_row.wrapping_add(x0.wrapping_mul(gzx));
                    pixel::write_packed::<P, Z>(color, depth, c, pgx, z, gzx, W::ACTIVE);
                }
                c_row = c_row.wrapping_add(pgy);
                z_row = z_row.wrapping_add(gzy);
            },
        );
    }
    let mut row = base;
    walk_rows::<P, T, Z, W>(target, s.xy(), s.mid_left(), rows, walk, no_half, |span| {
        if let Some((color, depth, x0)) = span {
            let v = arrays::from_fn(|k| row[k].wrapping_add(x0.wrapping_mul(gx[k])));
            pixel::write_run::<P, Z, Sh>(color, depth, v, gx);
        }
        for k in 0..ATTRS {
            row[k] = row[k].wrapping_add(gy[k]);
        }
    })
}

/// [`fill_gradient`] of a whole triangle (no walk kept) with the packed values and
/// the row loop of `asm::packed_565_rows` for each half: a 5-6-5 target over
/// 16-bit depth cells that stores its rows one after another (the caller checked
/// that [`asm::Rows565::of`] finds them). Not inlined: one copy per target type.
#[cfg(all(any(fixshade_dsp, fixshade_v6m), not(feature = "small-flash")))]
#[inline(never)]
fn fill_565_rows<P: PixelFormat, T: Target<P>, L: Lattice>(target: &mut T, s: &L) -> u32 {
    let Some((rows, base)) = first_values(s, target.rows()) else {
        return 0;
    };
    // A 5-6-5 format's lanes fit: the packed values exist.
    let (Some(c_row), Some(pgx), Some(pgy)) = (
        pixel::packed_channels::<P>(&base),
        pixel::packed_channels::<P>(s.gx()),
        pixel::packed_channels::<P>(s.gy()),
    ) else {
        return 0;
    };
    let mut p = asm::PackedRows {
        c_row,
        pgx,
        pgy,
        z_row: base[3],
        gzx: s.gx()[3],
        gzy: s.gy()[3],
    };
    let half = |target: &mut T, l: &mut EdgeStepper, r: &mut EdgeStepper, ys| {
        let mut buf = asm::Rows565::of::<P, T>(target)?;
        Some(if pixel::swapped_565::<P>() {
            asm::packed_565_rows::<true>(&mut buf, &mut p, l, r, ys)
        } else {
            asm::packed_565_rows::<false>(&mut buf, &mut p, l, r, ys)
        })
    };
    // `half` finds the rows (the caller checked), so `row` is not called.
    walk_rows::<P, T, pixel::DepthTest, ()>(target, s.xy(), s.mid_left(), rows, (), half, |_| {})
}

/// No half drawn by [`walk_rows`]'s `half`: every row through `row`.
#[inline(always)]
fn no_half<T>(_: &mut T, _: &mut EdgeStepper, _: &mut EdgeStepper, _: Range<i32>) -> Option<u32> {
    None
}

/// The edge walk of [`fill_gradient`]: for each row of `rows` (from [`row_range`]),
/// `row(Some((colour, depth, x0)))` with the row's covered pixels `[x0, x1)` clipped
/// to the target (depth empty unless `Z::TEST`), or `row(None)` for a row with none:
/// `row` draws the span and moves its values on to the next row. A half of the
/// triangle (the rows `ys` between the edges `left` and `right`) goes first to
/// `half(target, left, right, ys)`, which may draw it instead (stepping both edges
/// past it and returning the pixels covered; `row` is then not called for those
/// rows) or return `None` ([`no_half`]). Returns the pixels covered. With `walk`,
/// the walk resumes where it stopped if that was at most `RESUME_ROWS` rows above
/// `y_top`, and stores where it stops.
#[inline(always)]
fn walk_rows<P, T, Z, W: WalkSlot>(
    target: &mut T,
    [t, m, b]: [(i32, i32); 3],
    mid_left: bool,
    (y_top, y_mid, y_bot): (i32, i32, i32),
    mut walk: W,
    mut half: impl FnMut(&mut T, &mut EdgeStepper, &mut EdgeStepper, Range<i32>) -> Option<u32>,
    mut row: impl FnMut(Option<(&mut [P::Raw], &mut [T::Depth], i32)>),
) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
{
    let width = target.width() as i32;
    // A walk that stopped at most `RESUME_ROWS` rows above: its steppers stepped on
    // to `y_top` (each step exact, so they equal steppers placed there directly).
    // Only a triangle that begins above the target's rows has one to resume.
    let mut resumed = None;
    if W::ACTIVE && y_top > first_row_in_guard(t.1) {
        if let Some(w) = walk.get() {
            let gap = y_top.wrapping_sub(w.row);
            if w.row != Walk::EMPTY.row && (0..=RESUME_ROWS).contains(&gap) {
                let (mut long, mut short) = (w.long, w.short);
                for _ in 0..gap {
                    long.step();
                    short.step();
                }
                resumed = Some((long, w.lower, short));
            }
        }
    }
    let mut long = match resumed {
        Some((l, _, _)) => l,
        None => EdgeStepper::new(t, b, y_top),
    };
    let mut covered = 0u32;
    // The upper half (top to middle vertex) covers rows `[y_top, y_mid)`, the lower
    // half `[y_mid, y_bot)`; the walk begins in the half of `y_top`.
    let mut lower = y_mid <= y_top;
    // The resumed short edge serves if it is that half's (it was stepped to `y_top`).
    let mut short = match resumed {
        Some((_, l, sh)) if l == lower => Some(sh),
        _ => None,
    };
    let mut ys = y_top;
    let short = loop {
        // One place that places a short edge, with the half's ends as arguments
        // (placed where the half begins, never ahead of it).
        let mut sh = match short {
            Some(sh) => sh,
            None => {
                let (top, bottom) = if lower { (m, b) } else { (t, m) };
                EdgeStepper::new(top, bottom, ys)
            }
        };
        let ye = if lower { y_bot } else { y_mid.min(y_bot) };
        let (left, right) = if mid_left {
            (&mut sh, &mut long)
        } else {
            (&mut long, &mut sh)
        };
        if let Some(n) = half(target, left, right, ys..ye) {
            covered += n;
        } else {
            for y in ys..ye {
                let x0 = left.q.max(0);
                let x1 = right.q.min(width);
                if x0 < x1 {
                    let (crow, drow) = target.row(y);
                    let (a, e) = (x0 as usize, x1 as usize);
                    let depth = if Z::TEST {
                        &mut drow[a..e]
                    } else {
                        &mut drow[..0]
                    };
                    row(Some((&mut crow[a..e], depth, x0)));
                    covered += (x1 - x0) as u32;
                } else {
                    row(None);
                }
                left.step();
                right.step();
            }
        }
        if lower || y_mid >= y_bot {
            break sh;
        }
        lower = true;
        ys = y_mid;
        short = None;
    };
    // Only a triangle that goes on below the target's rows is walked again.
    if W::ACTIVE && y_bot < first_row_in_guard(b.1) {
        walk.put(y_bot, lower, long, short);
    }
    covered
}

/// Where [`walk_rows`] keeps a [`Walk`]: nowhere (`()`, the whole-frame draws:
/// the code compiles as without walks), or a band's slot, if the memory lent one.
pub(crate) trait WalkSlot {
    /// False for `()`: nothing to keep.
    const ACTIVE: bool;
    /// The walk to resume, if any.
    fn get(&self) -> Option<&Walk>;
    /// Keeps where the walk stopped: the row and the steppers there.
    fn put(&mut self, row: i32, lower: bool, long: EdgeStepper, short: EdgeStepper);
}

impl WalkSlot for () {
    const ACTIVE: bool = false;
    #[inline(always)]
    fn get(&self) -> Option<&Walk> {
        None
    }
    #[inline(always)]
    fn put(&mut self, _: i32, _: bool, _: EdgeStepper, _: EdgeStepper) {}
}

impl WalkSlot for Option<&mut Walk> {
    const ACTIVE: bool = true;
    #[inline(always)]
    fn get(&self) -> Option<&Walk> {
        self.as_deref()
    }
    #[inline(always)]
    fn put(&mut self, row: i32, lower: bool, long: EdgeStepper, short: EdgeStepper) {
        if let Some(w) = self {
            (w.row, w.lower, w.long, w.short) = (row, lower, long, short);
        }
    }
}

/// The most rows a [`Walk`] is stepped on to resume (a band drawn by another
/// thread in between); further, the steppers are placed afresh.
const RESUME_ROWS: i32 = 64;

/// Where the edge walk of a set-up triangle stopped: the row it reached and its two
/// edge steppers there, so that drawing the next band resumes the walk instead of
/// placing the steppers afresh (a division each; see
/// [`crate::render::Binned::draw_band_resuming`]). The steppers at a row are a
/// function of the triangle and the row, so a resumed walk draws the same pixels.
///
/// A band memory lends one per record; the frame drawn band by band with walks is
/// the frame drawn without them:
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::{setup::Record, Walk};
/// use fixshade::render::BandMemory;
/// # let scene = fixshade::doc_support::scene();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Rgb565Be>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// let mut draw = |walks: &mut [Walk]| {
///     let (mut records, mut index, mut starts) = ([Record::EMPTY; 4], [0u16; 96], [0u32; 13]);
///     let mem = BandMemory::new(&mut records, &mut index, &mut starts).with_walks(walks);
///     let mut binned = frame.bin(4, mem).unwrap();
///     let mut color = [0u16; 64 * 48];
///     for band in 0..binned.bands() {
///         let rows = binned.rows(band);
///         let at = rows.start as usize * 64;
///         let (mut c, mut d) = ([0u16; 64 * 4], [u16::MAX; 64 * 4]);
///         let mut strip = Strip::new(&mut c, Some(&mut d), 64, 48, rows.start, 4).unwrap();
///         binned.draw_band_resuming::<Gradient, _>(band, &mut strip).unwrap();
///         color[at..at + c.len()].copy_from_slice(&c);
///     }
///     color
/// };
/// let with = draw(&mut [Walk::EMPTY; 4]);
/// assert_eq!(with, draw(&mut []));
/// assert!(with.iter().any(|&p| p != 0));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Walk {
    /// The row the steppers stand on; `i32::MIN`: none.
    row: i32,
    /// The short edge is the lower half's (middle to bottom vertex).
    lower: bool,
    long: EdgeStepper,
    short: EdgeStepper,
}

// The RAM figure of `BandMemory::with_walks` and the README.
const _: () = assert!(core::mem::size_of::<Walk>() == 48);

impl Walk {
    /// Marks the walk as none ([`Walk::EMPTY`]'s row): the next draw places the
    /// steppers afresh.
    #[inline(always)]
    pub(crate) fn forget(&mut self) {
        self.row = Walk::EMPTY.row;
    }

    /// No walk: the steppers are placed afresh.
    pub const EMPTY: Walk = {
        let e = EdgeStepper {
            q: 0,
            r: 0,
            d: 0,
            a: 0,
            b: 0,
        };
        Walk {
            row: i32::MIN,
            lower: false,
            long: e,
            short: e,
        }
    };
}

/// The rows a set-up triangle covers inside `rows`: `(top, middle, bottom)`, where
/// `[top, bottom)` is non-empty and `middle` is the first row of the lower half.
///
/// ```
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::{row_range, ScreenVertex};
/// let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [0; 3] };
/// let s = setup([v(0, 2), v(0, 10), v(8, 6)]).unwrap();
/// // Rows 2..10, the lower half from row 6; clipped to a strip of rows 4..8.
/// assert_eq!(row_range(&s, 0..100), Some((2, 6, 10)));
/// assert_eq!(row_range(&s, 4..8), Some((4, 6, 8)));
/// assert_eq!(row_range(&s, 20..30), None);
/// ```
#[inline]
pub fn row_range(s: &Setup, rows: Range<i32>) -> Option<(i32, i32, i32)> {
    let [t, m, b] = s.v;
    let y_top = first_row(t.y).max(rows.start);
    let y_bot = first_row(b.y).min(rows.end);
    (y_top < y_bot).then_some((y_top, first_row(m.y), y_bot))
}

/// Walks the edges of a set-up triangle over `rows` (from [`row_range`]) and calls
/// `fill(colour, depth, span)` for every non-empty span clipped to the target, with
/// the row's colour and depth slices for `[x0, x1)` (depth empty unless `Z::TEST`).
/// Returns the number of pixels covered. `edge_values` asks for [`Span::edges`].
///
/// ```
/// use fixshade::raster::setup::setup;
/// use fixshade::raster::span::NoDepth;
/// use fixshade::raster::{row_range, scan, ScreenVertex};
/// use fixshade::target::{Framebuffer, Gray8, Target};
/// let v = |x: i32, y: i32| ScreenVertex { x: x * 16, y: y * 16, z: 0, c: [0; 3] };
/// let s = setup([v(0, 0), v(0, 4), v(4, 0)]).unwrap();
/// let mut px = [0u8; 4 * 4];
/// let mut fb = Framebuffer::<Gray8>::new(&mut px, None, 4, 4).unwrap();
/// let rows = row_range(&s, fb.rows()).unwrap();
/// // A custom fill: mark each span with its length.
/// let n = scan::<Gray8, _, NoDepth, _>(&mut fb, &s, rows, false, |color, _depth, span| {
///     color.fill((span.x1 - span.x0) as u8);
/// });
/// assert_eq!(n, 6);
/// assert_eq!(px, [3, 3, 3, 0, 2, 2, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0]);
/// ```
#[inline(always)]
pub fn scan<P, T, Z, F>(
    target: &mut T,
    s: &Setup,
    (y_top, y_mid, y_bot): (i32, i32, i32),
    edge_values: bool,
    mut fill: F,
) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    F: FnMut(&mut [P::Raw], &mut [T::Depth], &Span),
{
    let [t, m, b] = s.v;
    // The long edge spans every row: one stepper serves both halves (the first walk
    // leaves it on the row where the second begins).
    let mut long = EdgeStepper::new((t.x, t.y), (b.x, b.y), y_top);
    let mut n = 0;
    n += walk::<P, T, Z, F>(
        target,
        s,
        &mut fill,
        edge_values,
        (&mut long, (&t, &b)),
        (&t, &m),
        (first_row(t.y), y_top),
        y_mid.min(y_bot),
    );
    n += walk::<P, T, Z, F>(
        target,
        s,
        &mut fill,
        edge_values,
        (&mut long, (&t, &b)),
        (&m, &b),
        (y_mid, y_mid.max(y_top)),
        y_bot,
    );
    n
}

/// Walks rows `[ys, ye)` between the long edge (its stepper positioned on row `ys`)
/// and one short edge; `anchor` is the half's own first row (`ys` unless the target
/// starts below it), where the edge values of [`SpanMethod::EDGE_VALUES`] methods
/// are anchored.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn walk<P, T, Z, F>(
    target: &mut T,
    s: &Setup,
    fill: &mut F,
    edge_values: bool,
    (el, long): (&mut EdgeStepper, (&ScreenVertex, &ScreenVertex)),
    short: (&ScreenVertex, &ScreenVertex),
    (anchor, ys): (i32, i32),
    ye: i32,
) -> u32
where
    P: PixelFormat,
    T: Target<P>,
    Z: DepthMode,
    F: FnMut(&mut [P::Raw], &mut [T::Depth], &Span),
{
    if ys >= ye {
        return 0;
    }
    // Non-empty rows imply dy > 0 on the short edge (rows lie between its end rows).
    let mut es = EdgeStepper::new((short.0.x, short.0.y), (short.1.x, short.1.y), ys);
    let ((left, lv), (right, rv)) = if s.mid_left {
        ((&mut es, short), (el, long))
    } else {
        ((el, long), (&mut es, short))
    };
    let (mut la, mut ra) = if edge_values {
        (
            Some(EdgeAttrs::new(lv.0, lv.1, ys, anchor)),
            Some(EdgeAttrs::new(rv.0, rv.1, ys, anchor)),
        )
    } else {
        (None, None)
    };
    let width = target.width() as i32;
    let mut vl = s.at(left.q, ys);
    // Lattice increments for a row step of the left edge: one row down plus `a`
    // (or `a + 1` on a diagonal step) pixels across. Wrapping: exact modulo 2^32.
    let inc_a: [i32; ATTRS] =
        arrays::from_fn(|k| s.gy[k].wrapping_add(left.a.wrapping_mul(s.gx[k])));
    let inc_b: [i32; ATTRS] = arrays::from_fn(|k| inc_a[k].wrapping_add(s.gx[k]));
    let mut covered = 0u32;
    for y in ys..ye {
        let x0 = left.q.max(0);
        let x1 = right.q.min(width);
        if x0 < x1 {
            // A span cut by the frame's left edge starts `skip` pixels into the row.
            let v = if x0 == left.q {
                vl
            } else {
                let skip = x0.wrapping_sub(left.q);
                arrays::from_fn(|k| vl[k].wrapping_add(skip.wrapping_mul(s.gx[k])))
            };
            let edges = match (&la, &ra) {
                (Some(l), Some(r)) => EdgeValues {
                    left: *left,
                    right: *right,
                    il: l.get(),
                    ir: r.get(),
                },
                _ => EdgeValues::default(),
            };
            let span = Span {
                y,
                x0,
                x1,
                v,
                edges,
            };
            let (crow, drow) = target.row(y);
            let (a, b) = (x0 as usize, x1 as usize);
            let depth = if Z::TEST {
                &mut drow[a..b]
            } else {
                &mut drow[..0]
            };
            fill(&mut crow[a..b], depth, &span);
            covered += (x1 - x0) as u32;
        }
        let inc = if left.step() { &inc_b } else { &inc_a };
        for k in 0..ATTRS {
            vl[k] = vl[k].wrapping_add(inc[k]);
        }
        right.step();
        if let (Some(l), Some(r)) = (&mut la, &mut ra) {
            l.step();
            r.step();
        }
    }
    covered
}

#[cfg(test)]
mod tests;
