//! Shared helpers of the cross-crate tests: a small PRNG, test pixel formats
//! (a write counter and a channel recorder), an independent exact coverage model
//! (the winding number of directed edges under the half-open rule), and mesh
//! projection with the f64 reference's matrices.
//!
//! The coverage model follows the normative convention and shares no code with the
//! core: pixel `(x, y)` is sampled at `(16x + 8, 16y + 8)` (Q12.4); a directed edge
//! `a → b` spans the rows whose centre `Yc` satisfies `min(a.y, b.y) <= Yc <
//! max(a.y, b.y)`, crosses such a row at the exact rational `X(Yc)`, and contributes
//! `+1` (edge going down the screen, `a.y < b.y`) or `−1` (going up) to every pixel
//! of that row whose centre satisfies `X(Yc) <= 16x + 8`. Summed over the three
//! edges of a triangle this is `+1` on exactly the pixels the triangle covers when it
//! is a front face (negative signed area with y down), `−1` when it is a back face,
//! and `0` elsewhere.

pub mod catalogue;
pub mod hard;
pub mod scenes;

use fixshade::raster::ScreenVertex;
use fixshade::target::{PixelFormat, Target};
use fixshade_sim::render::reference::{
    mat_mul, mat_vec, model_matrix, projection_matrix, view_matrix,
};
use fixshade_sim::scene::desc::{MeshData, SceneDesc};

/// True in unoptimised builds: tests scale their iteration counts with [`scaled`].
pub const DEBUG: bool = cfg!(debug_assertions);

/// `release` iterations in release builds, `debug` in debug builds.
pub fn scaled(release: usize, debug: usize) -> usize {
    if DEBUG {
        debug
    } else {
        release
    }
}

/// SplitMix64: small, fast, good enough to drive test cases; seeded explicitly so
/// every failure is reproducible.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: u64) -> u64 {
        assert!(n > 0);
        ((self.next_u64() as u128 * n as u128) >> 64) as u64
    }

    /// Uniform in `lo..=hi`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        assert!(lo <= hi, "empty range {lo}..={hi}");
        lo + self.below((hi - lo + 1) as u64) as i64
    }

    /// Uniform `i32` in `lo..=hi`.
    pub fn int(&mut self, lo: i32, hi: i32) -> i32 {
        self.range(lo as i64, hi as i64) as i32
    }

    /// True with probability `num / den`.
    pub fn chance(&mut self, num: u64, den: u64) -> bool {
        self.below(den) < num
    }

    /// A uniformly chosen element.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len() as u64) as usize]
    }
}

/// A pixel format that counts writes: every store adds 1 (saturating, so even a
/// badly broken rasterizer cannot make a test panic on overflow).
#[derive(Copy, Clone, Debug, Default)]
pub struct Count;

impl PixelFormat for Count {
    type Raw = u16;
    const MAX: [u32; 3] = [1, 1, 1];
    const GRAY: bool = true;
    const BYTES: usize = 2;
    const NAME: &'static str = "count";
    fn pack(_: u32, _: u32, _: u32) -> u16 {
        0
    }
    fn unpack(p: u16) -> [u32; 3] {
        [p as u32; 3]
    }
    const PLAIN_STORE: bool = false;
    fn store(dst: &mut u16, _: u16) {
        *dst = dst.saturating_add(1);
    }
    fn bytes(p: u16) -> [u8; 3] {
        let b = p.to_le_bytes();
        [b[0], b[1], 0]
    }
}

/// An RGB format with 8-bit channels (like `Rgb888`) that records the channel
/// integers the rasterizer hands to `pack`, unclipped and signed, so a value out of
/// `0..=255` is seen rather than wrapped. Unwritten pixels are `None`.
#[derive(Copy, Clone, Debug, Default)]
pub struct Rec;

impl PixelFormat for Rec {
    type Raw = Option<[i32; 3]>;
    const MAX: [u32; 3] = [255, 255, 255];
    const BYTES: usize = 3;
    const NAME: &'static str = "rec";
    fn pack(r: u32, g: u32, b: u32) -> Self::Raw {
        Some([r as i32, g as i32, b as i32])
    }
    fn unpack(p: Self::Raw) -> [u32; 3] {
        p.unwrap_or_default().map(|v| v as u32)
    }
    fn bytes(p: Self::Raw) -> [u8; 3] {
        p.unwrap_or_default().map(|v| v as u8)
    }
}

/// A screen vertex at `(x, y)` (Q12.4) with depth 0 and colour `c`.
pub fn sv(x: i32, y: i32, c: [i32; 3]) -> ScreenVertex {
    ScreenVertex { x, y, z: 0, c }
}

/// A 2D point in Q12.4.
pub type P2 = (i32, i32);

/// Twice the signed area, y down: negative for a front face.
pub fn area2(a: P2, b: P2, c: P2) -> i64 {
    (b.0 - a.0) as i64 * (c.1 - a.1) as i64 - (c.0 - a.0) as i64 * (b.1 - a.1) as i64
}

/// `⌈n / d⌉` for `d > 0`.
pub fn ceil_div(n: i64, d: i64) -> i64 {
    assert!(d > 0);
    -((-n).div_euclid(d))
}

/// Per-pixel signed counts over a window of the frame: rows `[y0, y0 + h)`, columns
/// `[0, width)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Window {
    /// Width in pixels.
    pub width: usize,
    /// First frame row.
    pub y0: i32,
    /// Rows.
    pub h: usize,
}

impl Window {
    /// Pixels in the window.
    pub fn len(&self) -> usize {
        self.width * self.h
    }

    /// True for an empty window.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The exact winding-number coverage model described in the crate docs,
/// accumulated edge by edge over a [`Window`].
pub struct Winding {
    win: Window,
    /// Difference array: `diff[row * (width + 1) + x]`.
    diff: Vec<i32>,
}

impl Winding {
    /// An empty accumulator.
    pub fn new(win: Window) -> Winding {
        let n = (win.width + 1) * win.h;
        Winding {
            win,
            diff: vec![0; n],
        }
    }

    /// Adds the contribution of the directed edge `a → b`, times `weight`.
    pub fn edge(&mut self, a: P2, b: P2, weight: i32) {
        if a.1 == b.1 {
            return; // spans no row
        }
        let (sign, t, bt) = if a.1 < b.1 { (1, a, b) } else { (-1, b, a) };
        let (dx, dy) = ((bt.0 - t.0) as i64, (bt.1 - t.1) as i64);
        // Rows with t.y <= 16y + 8 < b.y.
        let first = ceil_div(t.1 as i64 - 8, 16);
        let last = ceil_div(bt.1 as i64 - 8, 16); // exclusive
        let lo = first.max(self.win.y0 as i64);
        let hi = last.min(self.win.y0 as i64 + self.win.h as i64);
        let w1 = self.win.width + 1;
        for y in lo..hi {
            let yc = 16 * y + 8;
            // X(yc) = t.x + dx·(yc − t.y)/dy; first x with 16x + 8 >= X(yc).
            let num = t.0 as i64 * dy + dx * (yc - t.1 as i64) - 8 * dy;
            let xs = ceil_div(num, 16 * dy).clamp(0, self.win.width as i64) as usize;
            let row = (y - self.win.y0 as i64) as usize;
            self.diff[row * w1 + xs] += sign * weight;
        }
    }

    /// Adds the three directed edges of a triangle.
    pub fn triangle(&mut self, v: [P2; 3], weight: i32) {
        for i in 0..3 {
            self.edge(v[i], v[(i + 1) % 3], weight);
        }
    }

    /// The per-pixel winding numbers, row-major over the window.
    pub fn finish(&self) -> Vec<i32> {
        let w1 = self.win.width + 1;
        let mut out = Vec::with_capacity(self.win.len());
        for row in 0..self.win.h {
            let mut acc = 0;
            for x in 0..self.win.width {
                acc += self.diff[row * w1 + x];
                out.push(acc);
            }
        }
        out
    }
}

/// Compares per-pixel values; `Err` names how many pixels differ and the first few
/// (frame coordinates).
pub fn diff_counts<A, B>(what: &str, win: &Window, got: &[A], want: &[B]) -> Result<usize, String>
where
    A: Copy + Into<i64>,
    B: Copy + Into<i64>,
{
    assert_eq!(got.len(), win.len());
    assert_eq!(want.len(), win.len());
    let mut bad = 0usize;
    let mut first = Vec::new();
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        let (g, w) = ((*g).into(), (*w).into());
        if g != w {
            bad += 1;
            if first.len() < 8 {
                let (x, y) = (i % win.width, win.y0 as usize + i / win.width);
                first.push(format!("({x},{y}): got {g}, want {w}"));
            }
        }
    }
    if bad == 0 {
        Ok(win.len())
    } else {
        Err(format!(
            "{what}: {bad} of {} pixels differ; first: {}",
            win.len(),
            first.join("; ")
        ))
    }
}

/// Screen triangles of a scene's objects projected with the f64 reference's
/// matrices and snapped to 1/16 pixel like the reference (`floor(16·s + 0.5)`).
/// Triangles with a vertex behind the eye or outside the guard band are counted in
/// `skipped` and left out (the scenes used here have none).
pub struct Projected {
    /// Snapped screen triangles (Q12.4), in mesh order.
    pub tris: Vec<[P2; 3]>,
    /// Triangles left out.
    pub skipped: usize,
}

/// Projects `meshes` (one per object of `desc`) to the screen of `desc`.
pub fn project(desc: &SceneDesc, meshes: &[MeshData]) -> Projected {
    let (w, h) = (desc.width as f64, desc.height as f64);
    let view = view_matrix(&desc.camera);
    let proj = projection_matrix(&desc.camera, w / h);
    let guard = fixshade::raster::GUARD as f64;
    let mut tris = Vec::new();
    let mut skipped = 0;
    for (obj, mesh) in desc.objects.iter().zip(meshes) {
        let m = mat_mul(&proj, &mat_mul(&view, &model_matrix(obj)));
        let pts: Vec<Option<P2>> = mesh
            .positions
            .iter()
            .map(|p| {
                let c = mat_vec(&m, [p[0], p[1], p[2], 1.0]);
                if c[3].is_nan() || c[3] <= 0.0 {
                    return None;
                }
                let sx = (c[0] / c[3] + 1.0) / 2.0 * w;
                let sy = (1.0 - c[1] / c[3]) / 2.0 * h;
                let snap = |s: f64| (s * 16.0 + 0.5).floor();
                let (x, y) = (snap(sx), snap(sy));
                (x.abs() < guard && y.abs() < guard).then_some((x as i32, y as i32))
            })
            .collect();
        for t in &mesh.triangles {
            match (pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize]) {
                (Some(a), Some(b), Some(c)) => tris.push([a, b, c]),
                _ => skipped += 1,
            }
        }
    }
    Projected { tris, skipped }
}

/// Sentinel pixels on every side of a [`Guarded`] target's buffer.
pub const GUARD_PX: usize = 3;

/// A target with a guard region: the rows `[y0, y0 + h)` of a `width` ×
/// `frame_height` frame, stored inside a buffer with [`GUARD_PX`] sentinel pixels on
/// every side. A request for a row outside `rows()` is counted in `bad_rows` and
/// served from the top guard row (instead of being clamped, as the core's targets
/// do), so a stray row shows up as a changed sentinel too; a column outside the row
/// cannot be reached without a slice-index panic. [`Guarded::intact`] checks that
/// every sentinel (colour and depth) is unchanged.
pub struct Guarded<P: PixelFormat> {
    buf: Vec<P::Raw>,
    depth: Option<Vec<u16>>,
    sentinel: P::Raw,
    width: usize,
    frame_height: u32,
    y0: i32,
    h: usize,
    /// Row requests outside `rows()`.
    pub bad_rows: usize,
}

/// Depth sentinel of a [`Guarded`] target (the interior starts at the far value).
pub const DEPTH_SENTINEL: u16 = 0x5A5A;

impl<P: PixelFormat> Guarded<P> {
    /// A target for rows `[y0, y0 + h)` of a `width` × `frame_height` frame; the
    /// interior starts as `clear`, the guard as `sentinel` (pick one the rasterizer
    /// never writes, e.g. `None` for [`Rec`]). Panics on sizes the core's own
    /// targets reject (the tests build only valid ones).
    pub fn new(
        width: u32,
        frame_height: u32,
        y0: u32,
        h: u32,
        depth: bool,
        clear: P::Raw,
        sentinel: P::Raw,
    ) -> Self {
        assert!(width >= 1 && h >= 1 && y0 + h <= frame_height);
        let (w, hh) = (width as usize, h as usize);
        let stride = w + 2 * GUARD_PX;
        let mut buf = vec![sentinel; stride * (hh + 2 * GUARD_PX)];
        let mut dbuf = vec![DEPTH_SENTINEL; stride * (hh + 2 * GUARD_PX)];
        for r in 0..hh {
            let at = (r + GUARD_PX) * stride + GUARD_PX;
            buf[at..at + w].fill(clear);
            dbuf[at..at + w].fill(0xFFFF);
        }
        Guarded {
            buf,
            depth: depth.then_some(dbuf),
            sentinel,
            width: w,
            frame_height,
            y0: y0 as i32,
            h: hh,
            bad_rows: 0,
        }
    }

    fn stride(&self) -> usize {
        self.width + 2 * GUARD_PX
    }

    /// True if no sentinel pixel changed and no row outside `rows()` was asked for.
    pub fn intact(&self) -> bool {
        let s = self.stride();
        let inside = |i: usize| {
            let (r, c) = (i / s, i % s);
            (GUARD_PX..GUARD_PX + self.h).contains(&r)
                && (GUARD_PX..GUARD_PX + self.width).contains(&c)
        };
        self.bad_rows == 0
            && self
                .buf
                .iter()
                .enumerate()
                .all(|(i, p)| inside(i) || *p == self.sentinel)
            && self.depth.as_ref().is_none_or(|d| {
                d.iter()
                    .enumerate()
                    .all(|(i, z)| inside(i) || *z == DEPTH_SENTINEL)
            })
    }

    /// The interior colour pixels, row-major.
    pub fn pixels(&self) -> Vec<P::Raw> {
        let s = self.stride();
        (0..self.h)
            .flat_map(|r| {
                let at = (r + GUARD_PX) * s + GUARD_PX;
                self.buf[at..at + self.width].iter().copied()
            })
            .collect()
    }

    /// The interior depth values, row-major (empty without depth).
    pub fn depths(&self) -> Vec<u16> {
        let s = self.stride();
        match &self.depth {
            None => Vec::new(),
            Some(d) => (0..self.h)
                .flat_map(|r| {
                    let at = (r + GUARD_PX) * s + GUARD_PX;
                    d[at..at + self.width].iter().copied()
                })
                .collect(),
        }
    }

    /// The window of the frame this target holds.
    pub fn window(&self) -> Window {
        Window {
            width: self.width,
            y0: self.y0,
            h: self.h,
        }
    }
}

impl<P: PixelFormat> Target<P> for Guarded<P> {
    type Depth = u16;
    fn width(&self) -> u32 {
        self.width as u32
    }
    fn frame_height(&self) -> u32 {
        self.frame_height
    }
    fn rows(&self) -> std::ops::Range<i32> {
        self.y0..self.y0 + self.h as i32
    }
    fn has_depth(&self) -> bool {
        self.depth.is_some()
    }
    fn row(&mut self, y: i32) -> (&mut [P::Raw], &mut [u16]) {
        let s = self.stride();
        let r = if self.rows().contains(&y) {
            (y - self.y0) as usize + GUARD_PX
        } else {
            self.bad_rows += 1;
            0
        };
        let at = r * s + GUARD_PX;
        let w = self.width;
        let color = &mut self.buf[at..at + w];
        let depth = match self.depth.as_deref_mut() {
            Some(d) => &mut d[at..at + w],
            None => &mut [],
        };
        (color, depth)
    }
}

/// Path of a file under the `tests/` package directory.
pub fn package_path(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// A fresh, empty temporary directory for one test.
pub fn temp_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("fixshade-tests-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create temp dir");
    d
}

/// The figures every end-to-end test runs over.
pub const FIGURES: [&str; 3] = ["sphere", "teapot", "robot"];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rng_is_uniformish_and_in_range() {
        let mut r = Rng::new(1);
        let mut hist = [0u32; 7];
        for _ in 0..7000 {
            let v = r.range(-3, 3);
            assert!((-3..=3).contains(&v));
            hist[(v + 3) as usize] += 1;
        }
        assert!(hist.iter().all(|h| (800..1200).contains(h)), "{hist:?}");
    }

    #[test]
    fn winding_of_one_triangle() {
        // Legs of 4 pixels from (0, 0): front face (negative area), covers the
        // pixels of the core's doc example.
        let v = [(0, 0), (0, 64), (64, 0)];
        assert!(area2(v[0], v[1], v[2]) < 0);
        let win = Window {
            width: 8,
            y0: 0,
            h: 4,
        };
        let mut w = Winding::new(win.clone());
        w.triangle(v, 1);
        let got = w.finish();
        let rows: Vec<String> = got
            .chunks(8)
            .map(|r| r.iter().map(|c| char::from(b'0' + *c as u8)).collect())
            .collect();
        assert_eq!(rows, ["11100000", "11000000", "10000000", "00000000"]);
        // Reversed orientation: −1 on the same pixels.
        let mut w = Winding::new(win);
        w.triangle([v[0], v[2], v[1]], 1);
        assert!(w.finish().iter().zip(&got).all(|(a, b)| *a == -*b));
    }
}
