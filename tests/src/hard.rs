//! The checks every hard case goes through (catalogue cases and property-test
//! triangles alike), with every span method and shading mode: no panic, no write
//! outside the target (a [`Guarded`] target), and, as the case asks, exact coverage,
//! watertightness, colour and depth within their bounds of the exact values.

use fixshade::raster::phong::{draw_phong, EvenOddPixels, PhongVertex, PixelLight, Rows};
use fixshade::raster::quadratic::{draw_quadratic, Fill};
use fixshade::raster::span::{DepthTest, NoDepth, SpanMethod};
use fixshade::raster::{draw_triangle, ScreenVertex, GUARD};
use fixshade::shade::{Flat, Gouraud};
use fixshade_sim::scene::desc::{Named, SpanName};
use fixshade_sim::with_span_method;

use crate::{area2, Count, Guarded, Rec, Winding, Window, P2};

/// What a case asks for besides "no panic, no write outside".
#[derive(Clone, Copy, Debug, Default)]
pub struct Holds {
    /// Exact top-left coverage of each triangle alone.
    pub coverage: bool,
    /// Colours within 1 step of the exact interpolation (flat: exactly the
    /// provoking colour).
    pub colour: bool,
    /// Depth within 1 of the exact interpolation.
    pub depth: bool,
    /// All triangles together cover their union exactly once.
    pub watertight: bool,
    /// Something is drawn.
    pub nonempty: bool,
    /// Nothing is drawn.
    pub empty: bool,
    /// With the depth test, a later triangle at equal depth leaves the earlier colour.
    pub first_wins: bool,
    /// A strip's rows equal the same rows of the whole frame.
    pub strip: bool,
}

impl Holds {
    /// From the catalogue's `holds` words.
    pub fn from_words(words: &[String]) -> Holds {
        let has = |w: &str| words.iter().any(|x| x == w);
        Holds {
            coverage: has("coverage"),
            colour: has("colour"),
            depth: has("depth"),
            watertight: has("watertight"),
            nonempty: has("nonempty"),
            empty: has("empty"),
            first_wins: has("first-wins"),
            strip: has("strip"),
        }
    }
}

/// Frame, strip and triangles of one case.
#[derive(Clone, Debug)]
pub struct Case {
    /// Frame width, height.
    pub frame: (u32, u32),
    /// Strip `(y0, rows)`.
    pub strip: (u32, u32),
    /// Triangles.
    pub tris: Vec<[ScreenVertex; 3]>,
    /// What must hold.
    pub holds: Holds,
}

/// Figures of one checked case.
#[derive(Clone, Copy, Debug, Default)]
pub struct Figures {
    /// Pixels whose coverage was compared with the model.
    pub coverage_checks: u64,
    /// Channel values compared with the exact value.
    pub colour_checks: u64,
    /// Largest |got − exact| of a colour channel (steps).
    pub max_colour_err: f64,
    /// Depth values compared.
    pub depth_checks: u64,
}

impl core::ops::AddAssign for Figures {
    fn add_assign(&mut self, o: Figures) {
        self.coverage_checks += o.coverage_checks;
        self.colour_checks += o.colour_checks;
        self.max_colour_err = self.max_colour_err.max(o.max_colour_err);
        self.depth_checks += o.depth_checks;
    }
}

/// Every span method.
pub fn span_methods() -> Vec<SpanName> {
    SpanName::ALL.iter().map(|(s, _)| *s).collect()
}

/// True for a method that moves vertices (its coverage and colours are those of a
/// snapped triangle, not of the input): `SpanMethod::SNAPS`.
pub fn snaps(s: SpanName) -> bool {
    with_span_method!(s, S => <S as fixshade::raster::span::SpanMethod>::SNAPS)
}

fn in_guard(v: &[ScreenVertex; 3]) -> bool {
    v.iter()
        .all(|p| p.x.unsigned_abs() < GUARD as u32 && p.y.unsigned_abs() < GUARD as u32)
}

fn p2(v: &ScreenVertex) -> P2 {
    (v.x, v.y)
}

/// The exact coverage of `tris` over `win`: `|Σ winding|` (triangles outside the
/// guard band contribute nothing: they are culled).
pub fn model(win: &Window, tris: &[[ScreenVertex; 3]]) -> Vec<u16> {
    let mut w = Winding::new(win.clone());
    for t in tris.iter().filter(|t| in_guard(t)) {
        w.triangle(t.map(|p| p2(&p)), 1);
    }
    w.finish().iter().map(|c| c.unsigned_abs() as u16).collect()
}

/// Exact barycentric interpolation at the centre of pixel `(x, y)` of attribute
/// `get` (in units of 2⁻¹⁶), returned in whole units.
pub fn exact(v: &[ScreenVertex; 3], x: i32, y: i32, get: impl Fn(&ScreenVertex) -> i64) -> f64 {
    let p = (16 * x + 8, 16 * y + 8);
    let q = |i: usize| p2(&v[i]);
    let area = area2(q(0), q(1), q(2));
    let l = [
        area2(q(1), q(2), p),
        area2(q(2), q(0), p),
        area2(q(0), q(1), p),
    ];
    let num: i128 = (0..3).map(|i| l[i] as i128 * get(&v[i]) as i128).sum();
    num as f64 / (area as f64 * 65536.0)
}

fn guarded<P: fixshade::target::PixelFormat>(
    c: &Case,
    depth: bool,
    clear: P::Raw,
    sentinel: P::Raw,
) -> Guarded<P> {
    Guarded::<P>::new(
        c.frame.0, c.frame.1, c.strip.0, c.strip.1, depth, clear, sentinel,
    )
}

fn rec(c: &Case, depth: bool) -> Guarded<Rec> {
    guarded::<Rec>(c, depth, None, Some([i32::MIN; 3]))
}

fn intact<P: fixshade::target::PixelFormat>(g: &Guarded<P>, what: &str) -> Result<(), String> {
    if g.intact() {
        Ok(())
    } else {
        Err(format!(
            "{what}: write outside the target ({} stray rows)",
            g.bad_rows
        ))
    }
}

/// The rows of a case's frame its target holds.
fn window(c: &Case) -> Window {
    Window {
        width: c.frame.0 as usize,
        y0: c.strip.0 as i32,
        h: c.strip.1 as usize,
    }
}

/// The pixels the flat `gradient` draw of `t` covers in a case's target.
/// A fill without depth test wrote exactly the pixels `want` (those of the flat
/// `gradient` draw) and reported their number `n`.
fn same_coverage(
    want: &[bool],
    col: &[Option<[i32; 3]>],
    n: u32,
    what: &str,
    f: &mut Figures,
) -> Result<(), String> {
    let got: Vec<bool> = col.iter().map(|p| p.is_some()).collect();
    if got != want {
        return Err(format!("{what}: covers other pixels than gradient"));
    }
    let covered = got.iter().filter(|b| **b).count() as u32;
    if covered != n {
        return Err(format!("{what}: reported {n} pixels, wrote {covered}"));
    }
    f.coverage_checks += got.len() as u64;
    Ok(())
}

fn gradient_coverage(c: &Case, t: &[ScreenVertex; 3]) -> Vec<bool> {
    use fixshade::raster::span::Gradient;
    let mut g = guarded::<Count>(c, false, 0, 0);
    draw_triangle::<Count, _, Gradient, NoDepth, Flat>(&mut g, *t);
    g.pixels().iter().map(|p| *p > 0).collect()
}

fn pixel_xy(win: &Window, i: usize) -> (i32, i32) {
    ((i % win.width) as i32, win.y0 + (i / win.width) as i32)
}

/// Compares recorded colours of one triangle `t` with the exact values.
fn colour_errors(
    win: &Window,
    got: &[Option<[i32; 3]>],
    t: &[ScreenVertex; 3],
    what: &str,
    f: &mut Figures,
) -> Result<(), String> {
    for (i, p) in got.iter().enumerate() {
        let Some(p) = p else { continue };
        let (x, y) = pixel_xy(win, i);
        for (ch, got) in p.iter().enumerate() {
            let e = exact(t, x, y, |v| v.c[ch] as i64);
            let err = (*got as f64 - e).abs();
            f.colour_checks += 1;
            f.max_colour_err = f.max_colour_err.max(err);
            if !(err < 1.0 && (0..=255).contains(got)) {
                return Err(format!(
                    "{what}: pixel ({x},{y}) channel {ch}: got {got}, exact {e:.4}"
                ));
            }
        }
    }
    Ok(())
}

fn depth_errors(
    win: &Window,
    col: &[Option<[i32; 3]>],
    dep: &[u16],
    t: &[ScreenVertex; 3],
    what: &str,
    f: &mut Figures,
) -> Result<(), String> {
    for (i, (c, d)) in col.iter().zip(dep).enumerate() {
        let (x, y) = pixel_xy(win, i);
        if c.is_none() {
            if *d != 0xFFFF {
                return Err(format!(
                    "{what}: pixel ({x},{y}): depth written without colour"
                ));
            }
            continue;
        }
        let e = exact(t, x, y, |v| v.z as i64);
        f.depth_checks += 1;
        if (*d as f64 - e).abs() >= 1.0 {
            return Err(format!("{what}: pixel ({x},{y}): depth {d}, exact {e:.4}"));
        }
    }
    Ok(())
}

/// Gouraud colours in range of a triangle given in-range vertex colours.
fn colours_valid(t: &[ScreenVertex; 3]) -> bool {
    t.iter()
        .all(|v| v.c.iter().all(|c| (0..=255 << 16).contains(c)))
}

/// Mid-edge colours of the quadratic surface that make it the Gouraud plane.
pub fn linear_mids(t: &[ScreenVertex; 3]) -> [[i32; 3]; 3] {
    core::array::from_fn(|k| {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        core::array::from_fn(|ch| ((a.c[ch] as i64 + b.c[ch] as i64) / 2) as i32)
    })
}

/// Checks one case with span method `S` (named `span`).
pub fn check_method<S: SpanMethod>(c: &Case, span: SpanName) -> Result<Figures, String> {
    let h = c.holds;
    let mut f = Figures::default();
    let name = span.name();
    let win = window(c);
    let mut total = 0u64;
    for (k, t) in c.tris.iter().enumerate() {
        let what = format!("[{name}] triangle {k}");
        // Coverage: a counting target, flat.
        let mut g = guarded::<Count>(c, false, 0, 0);
        let n = draw_triangle::<Count, _, S, NoDepth, Flat>(&mut g, *t);
        intact(&g, &what)?;
        let got = g.pixels();
        let sum: u64 = got.iter().map(|p| *p as u64).sum();
        if sum != n as u64 {
            return Err(format!("{what}: reported {n} pixels, wrote {sum}"));
        }
        total += sum;
        if got.iter().any(|p| *p > 1) {
            return Err(format!("{what}: a pixel written twice"));
        }
        if h.coverage && !snaps(span) {
            let want = model(&win, std::slice::from_ref(t));
            crate::diff_counts(&format!("{what} coverage"), &win, &got, &want)?;
            f.coverage_checks += got.len() as u64;
        }
        // Gouraud colours, without and with depth.
        for depth in [false, true] {
            let mut g = rec(c, depth);
            if depth {
                draw_triangle::<Rec, _, S, DepthTest, Gouraud>(&mut g, *t);
            } else {
                draw_triangle::<Rec, _, S, NoDepth, Gouraud>(&mut g, *t);
            }
            intact(&g, &what)?;
            let col = g.pixels();
            let covered = col.iter().filter(|p| p.is_some()).count() as u64;
            if covered != sum {
                return Err(format!(
                    "{what}: gouraud covered {covered} pixels, flat {sum}"
                ));
            }
            if h.colour && !snaps(span) && colours_valid(t) {
                colour_errors(&win, &col, t, &format!("{what} gouraud"), &mut f)?;
            } else if colours_valid(t) {
                for p in col.iter().flatten() {
                    if !p.iter().all(|ch| (0..=255).contains(ch)) {
                        return Err(format!("{what} gouraud: channel out of range: {p:?}"));
                    }
                }
            }
            if depth && h.depth && !snaps(span) {
                depth_errors(&win, &col, &g.depths(), t, &format!("{what} depth"), &mut f)?;
            }
        }
        // Flat: the renderer gives every vertex the provoking (last) colour.
        let pc = t[2].c;
        let flat = t.map(|v| ScreenVertex { c: pc, ..v });
        let mut g = rec(c, true);
        draw_triangle::<Rec, _, S, DepthTest, Flat>(&mut g, flat);
        intact(&g, &what)?;
        if colours_valid(t) {
            // Rounded to nearest, like every interpolated value.
            let want = pc.map(|v| (v + (1 << 15)) >> 16);
            if let Some(p) = g.pixels().into_iter().flatten().find(|p| *p != want) {
                return Err(format!(
                    "{what} flat: pixel {p:?}, provoking colour {want:?}"
                ));
            }
        }
    }
    if h.empty && total != 0 {
        return Err(format!("[{name}]: {total} pixels drawn, expected none"));
    }
    if h.nonempty && total == 0 && !snaps(span) {
        return Err(format!("[{name}]: nothing drawn"));
    }
    if h.watertight && !snaps(span) {
        let mut g = guarded::<Count>(c, false, 0, 0);
        for t in &c.tris {
            draw_triangle::<Count, _, S, NoDepth, Flat>(&mut g, *t);
        }
        intact(&g, &format!("[{name}] watertight"))?;
        let want = model(&win, &c.tris);
        if want.iter().any(|w| *w > 1) {
            return Err(format!("[{name}] watertight: the case's triangles overlap"));
        }
        crate::diff_counts(&format!("[{name}] watertight"), &win, &g.pixels(), &want)?;
    }
    if h.first_wins {
        let mut all = rec(c, true);
        let mut first = rec(c, true);
        for t in &c.tris {
            draw_triangle::<Rec, _, S, DepthTest, Gouraud>(&mut all, *t);
        }
        draw_triangle::<Rec, _, S, DepthTest, Gouraud>(&mut first, c.tris[0]);
        intact(&all, &format!("[{name}] first-wins"))?;
        for (i, (a, b)) in all.pixels().iter().zip(first.pixels()).enumerate() {
            if b.is_some() && *a != b {
                let (x, y) = pixel_xy(&win, i);
                return Err(format!(
                    "[{name}] first-wins: pixel ({x},{y}) is {a:?}, first triangle drew {b:?}"
                ));
            }
        }
    }
    if h.strip {
        let full_case = Case {
            strip: (0, c.frame.1),
            ..c.clone()
        };
        let mut full = rec(&full_case, true);
        let mut part = rec(c, true);
        for t in &c.tris {
            draw_triangle::<Rec, _, S, DepthTest, Gouraud>(&mut full, *t);
            draw_triangle::<Rec, _, S, DepthTest, Gouraud>(&mut part, *t);
        }
        let w = c.frame.0 as usize;
        let rows = &full.pixels()[c.strip.0 as usize * w..(c.strip.0 + c.strip.1) as usize * w];
        if rows != part.pixels().as_slice() {
            return Err(format!(
                "[{name}] strip: rows differ from the whole frame's"
            ));
        }
    }
    Ok(f)
}

/// Checks the quadratic surface fills (which take no span method): coverage as
/// `gradient`, no write outside, and with linear mid-edge colours the Gouraud bound.
pub fn check_quadratic(c: &Case) -> Result<Figures, String> {
    let h = c.holds;
    let mut f = Figures::default();
    let win = window(c);
    for (k, t) in c.tris.iter().enumerate() {
        let mid = linear_mids(t);
        for (fill, fname) in [(Fill::Blocks, "blocks"), (Fill::Rows, "rows")] {
            let what = format!("[quadratic {fname}] triangle {k}");
            let mut g = guarded::<Count>(c, false, 0, 0);
            let n = draw_quadratic::<Count, _, NoDepth>(&mut g, *t, mid, fill);
            intact(&g, &what)?;
            let got = g.pixels();
            let sum: u64 = got.iter().map(|p| *p as u64).sum();
            if sum != n as u64 {
                return Err(format!("{what}: reported {n} pixels, wrote {sum}"));
            }
            let want = model(&win, std::slice::from_ref(t));
            if h.coverage {
                crate::diff_counts(&format!("{what} coverage"), &win, &got, &want)?;
                f.coverage_checks += got.len() as u64;
            }
            for depth in [false, true] {
                let mut g = rec(c, depth);
                if depth {
                    draw_quadratic::<Rec, _, DepthTest>(&mut g, *t, mid, fill);
                } else {
                    draw_quadratic::<Rec, _, NoDepth>(&mut g, *t, mid, fill);
                }
                intact(&g, &what)?;
                let col = g.pixels();
                if h.colour && colours_valid(t) {
                    colour_errors(&win, &col, t, &what, &mut f)?;
                }
                if depth && h.depth {
                    depth_errors(&win, &col, &g.depths(), t, &format!("{what} depth"), &mut f)?;
                }
            }
        }
    }
    Ok(f)
}

/// Lights a pixel by its normal alone: channel `i` is `(nᵢ + 1) / 2` (Q16.16), so the
/// recorded colour shows the interpolated, renormalised normal.
#[derive(Clone, Copy, Debug, Default)]
pub struct NormalLight;

impl PixelLight for NormalLight {
    fn light(&self, _p: [i32; 3], n: [i32; 3]) -> [i32; 3] {
        // |n| < 2³¹: the sum < 2³², shifted to ≤ 2¹⁷, clamped to 0..=1.
        n.map(|c| ((c as i64 + (1 << 30)) >> 15).clamp(0, 1 << 16) as i32)
    }
}

/// The unit vector from the grey centre (127.5) to a vertex colour: opposite colours
/// give opposite normals, so the catalogue's 0 → 255 jumps interpolate through zero
/// length. A grey vertex faces the viewer.
pub fn colour_normal(c: [i32; 3]) -> [f64; 3] {
    let d = c.map(|v| v as f64 / 65536.0 - 127.5);
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if len > 0.0 {
        d.map(|x| x / len)
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// Phong vertices of a case's triangle: [`colour_normal`] in Q2.30, the eye position
/// from the screen position and depth.
pub fn phong_vertices(t: &[ScreenVertex; 3]) -> [PhongVertex; 3] {
    t.map(|v| PhongVertex {
        x: v.x,
        y: v.y,
        z: v.z,
        n: colour_normal(v.c).map(|x| (x * (1u32 << 30) as f64).round() as i32),
        p: [v.x >> 4, v.y >> 4, -((v.z >> 16) as i32)],
    })
}

/// Checks the Phong fills on a case: no write outside; without depth, exactly the
/// pixels the flat `gradient` draw covers; the even/odd fill bit-identical to the row
/// fill, with and without depth; depth within 1 of the exact value where the case
/// asks; and where the exact interpolated normal is at least half a unit long, every
/// channel within 1 step of `NormalLight` of the exact renormalised normal (`colour`
/// cases).
pub fn check_phong(c: &Case) -> Result<Figures, String> {
    let h = c.holds;
    let mut f = Figures::default();
    let win = window(c);
    for (k, t) in c.tris.iter().enumerate() {
        let what = format!("[phong] triangle {k}");
        let pv = phong_vertices(t);
        let want = gradient_coverage(c, t);
        for depth in [false, true] {
            let mut rows = rec(c, depth);
            let mut eo = rec(c, depth);
            let n = if depth {
                draw_phong::<Rec, _, DepthTest, Rows, _>(&mut rows, pv, &NormalLight);
                draw_phong::<Rec, _, DepthTest, EvenOddPixels, _>(&mut eo, pv, &NormalLight)
            } else {
                draw_phong::<Rec, _, NoDepth, Rows, _>(&mut rows, pv, &NormalLight);
                draw_phong::<Rec, _, NoDepth, EvenOddPixels, _>(&mut eo, pv, &NormalLight)
            };
            intact(&rows, &what)?;
            intact(&eo, &format!("{what} even-odd"))?;
            let col = rows.pixels();
            if col != eo.pixels() || (depth && rows.depths() != eo.depths()) {
                return Err(format!("{what}: even/odd fill differs from the row fill"));
            }
            if let Some(p) = col
                .iter()
                .flatten()
                .find(|p| !p.iter().all(|ch| (0..=255).contains(ch)))
            {
                return Err(format!("{what}: channel out of range: {p:?}"));
            }
            if !depth {
                same_coverage(&want, &col, n, &what, &mut f)?;
            }
            if depth && h.depth {
                depth_errors(
                    &win,
                    &col,
                    &rows.depths(),
                    t,
                    &format!("{what} depth"),
                    &mut f,
                )?;
            }
            if !depth && h.colour {
                let nv = t.map(|v| colour_normal(v.c));
                for (i, p) in col.iter().enumerate() {
                    let Some(p) = p else { continue };
                    let (x, y) = pixel_xy(&win, i);
                    let e: [f64; 3] = core::array::from_fn(|ch| {
                        let q = |v: &ScreenVertex| {
                            let j = t.iter().position(|u| u == v).unwrap_or(0);
                            (nv[j][ch] * 65536.0).round() as i64
                        };
                        exact(t, x, y, q)
                    });
                    let len = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
                    if len < 0.5 {
                        continue;
                    }
                    for ch in 0..3 {
                        let want = (e[ch] / len + 1.0) / 2.0 * 255.0;
                        let err = (p[ch] as f64 - want).abs();
                        f.colour_checks += 1;
                        f.max_colour_err = f.max_colour_err.max(err);
                        if err > 1.0 {
                            return Err(format!(
                                "{what}: pixel ({x},{y}) channel {ch}: got {}, exact {want:.4}",
                                p[ch]
                            ));
                        }
                    }
                }
            }
        }
    }
    Ok(f)
}

/// Checks the perspective-correct Gouraud fill (`raster::perspective`) on a case,
/// with vertex w equal, 1 : 2 : 4 and 1 : 2²⁰ : 3 (beyond its 2¹⁵ ratio, where the
/// far weight clamps), one division per pixel and per 16 pixels, through `exact`
/// (with and without depth) and `shift-add-4` (the coarsest divider): no write
/// outside; without depth, exactly the pixels the `gradient` draw covers, and the
/// count it reports; with in-range vertex colours, every channel inside the range of
/// the vertex colours (the fill clamps its weights; one step for the output
/// rounding); depth within 1 of the exact value where the case asks (depth is not
/// corrected: it is affine in screen space). The perspective-correct Phong fill
/// with the same w and spans (`exact`, with and without depth): no write outside,
/// the same coverage and count, channels in 0..=255, the same depth bound.
pub fn check_perspective(c: &Case) -> Result<Figures, String> {
    use fixshade::divide::{Exact, ShiftAdd};
    use fixshade::raster::perspective::{
        draw_phong_perspective, draw_triangle_perspective, Perspective,
    };
    let h = c.holds;
    let mut f = Figures::default();
    let win = window(c);
    for (k, t) in c.tris.iter().enumerate() {
        let want = gradient_coverage(c, t);
        let pv = phong_vertices(t);
        // Channel range of the vertex colours, in output steps (rounded).
        let range: [(i32, i32); 3] = core::array::from_fn(|ch| {
            let lo = t.iter().map(|v| v.c[ch]).min().unwrap_or(0);
            let hi = t.iter().map(|v| v.c[ch]).max().unwrap_or(0);
            ((lo >> 16) - 1, (hi >> 16) + 1)
        });
        for w in [[1, 1, 1], [1, 2, 4], [1, 1 << 20, 3]] {
            for (mode, mname) in [
                (Perspective::PER_PIXEL, "1px"),
                (Perspective::SUB16, "16px"),
            ] {
                for (run, rname) in [(0, "exact"), (1, "exact, depth"), (2, "shift-add-4")] {
                    let what = format!("[perspective {mname} {rname} w={w:?}] triangle {k}");
                    let depth = run == 1;
                    let mut g = rec(c, depth);
                    let n = match run {
                        0 => draw_triangle_perspective::<Rec, _, NoDepth, Gouraud, Exact>(
                            &mut g, *t, w, mode,
                        ),
                        1 => draw_triangle_perspective::<Rec, _, DepthTest, Gouraud, Exact>(
                            &mut g, *t, w, mode,
                        ),
                        _ => draw_triangle_perspective::<Rec, _, NoDepth, Gouraud, ShiftAdd<4>>(
                            &mut g, *t, w, mode,
                        ),
                    };
                    intact(&g, &what)?;
                    let col = g.pixels();
                    if !depth {
                        same_coverage(&want, &col, n, &what, &mut f)?;
                    }
                    if colours_valid(t) {
                        for (i, p) in col.iter().enumerate() {
                            let Some(p) = p else { continue };
                            for (ch, v) in p.iter().enumerate() {
                                f.colour_checks += 1;
                                if !(range[ch].0..=range[ch].1).contains(v) {
                                    let (x, y) = pixel_xy(&win, i);
                                    return Err(format!(
                                        "{what}: pixel ({x},{y}) channel {ch}: {v} outside the vertex colours' range {:?}",
                                        range[ch]
                                    ));
                                }
                            }
                        }
                    }
                    if depth && h.depth {
                        depth_errors(&win, &col, &g.depths(), t, &format!("{what} depth"), &mut f)?;
                    }
                }
                // Phong: the same coverage, channels in range, depth as exact.
                for depth in [false, true] {
                    let what =
                        format!("[perspective phong {mname} depth={depth} w={w:?}] triangle {k}");
                    let mut g = rec(c, depth);
                    let n = if depth {
                        draw_phong_perspective::<Rec, _, DepthTest, Exact, _>(
                            &mut g,
                            pv,
                            w,
                            mode,
                            &NormalLight,
                        )
                    } else {
                        draw_phong_perspective::<Rec, _, NoDepth, Exact, _>(
                            &mut g,
                            pv,
                            w,
                            mode,
                            &NormalLight,
                        )
                    };
                    intact(&g, &what)?;
                    let col = g.pixels();
                    if let Some(p) = col
                        .iter()
                        .flatten()
                        .find(|p| !p.iter().all(|ch| (0..=255).contains(ch)))
                    {
                        return Err(format!("{what}: channel out of range: {p:?}"));
                    }
                    if !depth {
                        same_coverage(&want, &col, n, &what, &mut f)?;
                    } else if h.depth {
                        depth_errors(&win, &col, &g.depths(), t, &format!("{what} depth"), &mut f)?;
                    }
                }
            }
        }
    }
    Ok(f)
}

/// Checks a case with every span method, the quadratic, Phong and perspective fills.
pub fn check_all(c: &Case) -> Result<Figures, String> {
    let mut f = check_quadratic(c)?;
    f += check_phong(c)?;
    f += check_perspective(c)?;
    for span in span_methods() {
        f += with_span_method!(span, S => check_method::<S>(c, span))?;
    }
    Ok(f)
}

/// Path of the baked triangle catalogue the QEMU firmware renders, under `boards/`
/// (written by `cargo xtask bake`).
pub const BAKED_TRIANGLES: &str = "baked/catalogue/triangles.rs";

/// The triangle catalogue as Rust source for the firmware (`boards/baked/catalogue/`):
/// every case's frame, drawn rows and triangles exactly as [`crate::catalogue::TriCase::triangles`]
/// gives them to the rasterizer. The file is self-contained (it declares its own
/// case type) so the firmware and `cargo xtask qemu` include the same bytes.
pub fn bake_triangles(cases: &[crate::catalogue::TriCase]) -> String {
    use std::fmt::Write as _;
    let mut s = String::from(
        "//! The hard-case triangle catalogue (tests/catalogue/triangles.toml) as data for\n\
         //! the QEMU firmware. Generated by `cargo xtask bake`: edit the catalogue and\n\
         //! bake again, not this file.\n\n\
         use fixshade::raster::ScreenVertex;\n\n\
         /// One case: a `width` × `height` frame of which rows `y0 .. y0 + rows` are drawn.\n\
         pub struct TriCase {\n    \
             /// The catalogue's name.\n    pub name: &'static str,\n    \
             /// Frame width.\n    pub width: u32,\n    \
             /// Frame height.\n    pub height: u32,\n    \
             /// First drawn row.\n    pub y0: u32,\n    \
             /// Drawn rows.\n    pub rows: u32,\n    \
             /// Triangles, in drawing order.\n    pub tris: &'static [[ScreenVertex; 3]],\n\
         }\n\n\
         const fn v(x: i32, y: i32, z: u32, c: [i32; 3]) -> ScreenVertex {\n    \
             ScreenVertex { x, y, z, c }\n\
         }\n\n\
         /// Every case, in the catalogue's order.\n\
         pub const CASES: &[TriCase] = &[\n",
    );
    for c in cases {
        let (y0, rows) = c.strip();
        let _ = writeln!(
            s,
            "    TriCase {{\n        name: {:?},\n        width: {},\n        height: {},\n        y0: {y0},\n        rows: {rows},\n        tris: &[",
            c.name, c.frame[0], c.frame[1]
        );
        for t in c.triangles() {
            s.push_str("            [\n");
            for p in t {
                let _ = writeln!(
                    s,
                    "                v({}, {}, {}, [{}, {}, {}]),",
                    p.x, p.y, p.z, p.c[0], p.c[1], p.c[2]
                );
            }
            s.push_str("            ],\n");
        }
        s.push_str("        ],\n    },\n");
    }
    s.push_str("];\n");
    s
}
