//! Adaptive pixel-segment sampling (seed 002, §2.6): evaluate a costly per-pixel
//! function only at the ends of pixel segments, interpolate the inside, and halve a
//! segment wherever its ends differ by more than a threshold.
//!
//! The costly function is any [`PixelFn`] (a ray cast, per-pixel lighting); it
//! returns channel integers of the target format (`0..=P::MAX[i]`).
//!
//! # Row variant ([`fill_row`])
//!
//! The seed's loop over a row: the first pixel is evaluated; then, segment by
//! segment of `L` pixels, the left end is the previous right end, the right end
//! `x + L` (clamped to the last pixel) is evaluated, and if the two ends differ by
//! at most `K` in every channel the pixels in between are interpolated; otherwise
//! the centre pixel is evaluated and both halves are treated the same way, down to
//! segments of one pixel (which have no inside). With `L = 1` every pixel is
//! evaluated.
//!
//! # Block variant ([`fill_blocks`])
//!
//! The same in two dimensions: the corners of an `L × L` grid are evaluated; a block
//! whose four corners differ by at most `K` (per channel, largest minus smallest) is
//! filled bilinearly, otherwise its edge midpoints and centre are evaluated and its
//! four quarters are treated the same way.
//!
//! # Interpolation and rounding
//!
//! Pixel `i` of a segment of length `n` (ends `a` at `i = 0`, `b` at `i = n`) gets
//! `a + ⌊((b − a)·i·2 + n) / (2n)⌋` per channel: the exact value rounded to nearest,
//! halves rounded up (towards +∞). The block variant rounds its bilinear value
//! `Σ corner·weight / (w·h)` the same way. Results stay within the range of the
//! ends, so they are valid channel integers.
//!
//! # The threshold K
//!
//! The seed compares the ends with "K ≤ 2.3" but never says in which units. Here K
//! is a difference of one channel expressed in 8-bit levels (0..=255 for the full
//! channel range, whatever the format), given in Q8 ([`Threshold::from_q8`]: 256
//! means one 8-bit level; 589 ≈ 2.3 levels). A channel of maximum `M` with ends `a`,
//! `b` counts as different when `|a − b|·255/M > K`. In RGB565 one red step is 8.2
//! levels and one green step 4.05, so any K below 4.05 subdivides at every change
//! of the stored colour.
//!
//! ```
//! use fixshade::sampler::{fill_row, PixelFn, Threshold};
//! // A ramp: exactly linear, so every segment interpolates exactly. Segment ends
//! // are 8 levels apart, within K = 16 levels: nothing is subdivided.
//! struct Ramp(u32);
//! impl PixelFn for Ramp {
//!     fn eval(&mut self, x: u32, _y: u32) -> [u32; 3] {
//!         self.0 += 1;
//!         [x, 0, 0]
//!     }
//! }
//! let mut f = Ramp(0);
//! let mut row = [[0u32; 3]; 17];
//! let k = Threshold::from_q8(16 * 256, [255; 3]);
//! let evals = fill_row(&mut f, 0, 8, k, &mut row);
//! assert_eq!(evals, 3); // x = 0, 8, 16
//! assert!(row.iter().enumerate().all(|(x, c)| c[0] == x as u32));
//! // With K = 4 levels the 8-level steps are halved once: x = 4 and 12 too.
//! let mut f = Ramp(0);
//! assert_eq!(fill_row(&mut f, 0, 8, Threshold::from_q8(4 * 256, [255; 3]), &mut row), 5);
//! ```

/// A costly per-pixel function: the colour of pixel `(x, y)` in the target's
/// channel units.
///
/// ```
/// use fixshade::sampler::PixelFn;
/// // Any closure-like state works; here a disc of radius 4 around (4, 4).
/// struct Disc;
/// impl PixelFn for Disc {
///     fn eval(&mut self, x: u32, y: u32) -> [u32; 3] {
///         let (dx, dy) = (x as i32 - 4, y as i32 - 4);
///         if dx * dx + dy * dy <= 16 { [255, 255, 255] } else { [0; 3] }
///     }
/// }
/// assert_eq!(Disc.eval(4, 4), [255; 3]);
/// assert_eq!(Disc.eval(0, 0), [0; 3]);
/// ```
pub trait PixelFn {
    /// Evaluates pixel `(x, y)`.
    fn eval(&mut self, x: u32, y: u32) -> [u32; 3];
}

/// The difference threshold K, turned into one integer limit per channel.
///
/// ```
/// use fixshade::sampler::{Threshold, SEED_K_Q8};
/// let k = Threshold::from_q8(SEED_K_Q8, [255; 3]);
/// assert!(!k.differ([10, 10, 10], [12, 10, 10])); // 2 levels ≤ 2.3
/// assert!(k.differ([10, 10, 10], [13, 10, 10])); // 3 levels > 2.3
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Threshold {
    limit: [u32; 3],
}

/// 2.3 8-bit levels in Q8 (589/256 = 2.30): the seed's K.
pub const SEED_K_Q8: u32 = 589;

impl Threshold {
    /// K in Q8 8-bit levels (`k_q8 / 256` levels) for channels of maximum `max`.
    ///
    /// A channel difference `d` (channel units) exceeds K iff `d·255·256 > k_q8·M`;
    /// since `d` is an integer this is `d > ⌊k_q8·M / (255·256)⌋`, the stored limit.
    /// `k_q8·M` < 2³²·2¹⁶ is taken in u64.
    ///
    /// ```
    /// use fixshade::sampler::Threshold;
    /// // 2.3 levels: RGB565 limits are 0 (any change subdivides).
    /// assert_eq!(Threshold::from_q8(589, [31, 63, 31]).limits(), [0, 0, 0]);
    /// assert_eq!(Threshold::from_q8(589, [255; 3]).limits(), [2, 2, 2]);
    /// assert_eq!(Threshold::from_q8(16 * 256, [31, 63, 31]).limits(), [1, 3, 1]);
    /// ```
    pub const fn from_q8(k_q8: u32, max: [u32; 3]) -> Threshold {
        Threshold {
            limit: [
                limit_of(k_q8, max[0]),
                limit_of(k_q8, max[1]),
                limit_of(k_q8, max[2]),
            ],
        }
    }

    /// The largest per-channel difference (channel units) that still interpolates.
    pub const fn limits(&self) -> [u32; 3] {
        self.limit
    }

    /// True if `a` and `b` differ by more than K in some channel.
    #[inline]
    pub fn differ(&self, a: [u32; 3], b: [u32; 3]) -> bool {
        (0..3).any(|i| a[i].abs_diff(b[i]) > self.limit[i])
    }
}

/// `⌊k_q8·m / (255·256)⌋`; `k_q8·m` < 2⁶⁴ in u64.
const fn limit_of(k_q8: u32, m: u32) -> u32 {
    ((k_q8 as u64 * m as u64) / (255 * 256)) as u32
}

/// Largest supported segment length (and block side): keeps the recursion depth
/// at most 12 and the interpolation products within `u64` (see `lerp`).
pub const MAX_SEGMENT: u32 = 4096;

/// `a + ⌊((b − a)·i·2 + n) / (2n)⌋`, 0 ≤ i ≤ n ≤ 4096: |b − a|·i·2 < 2³²·2¹³ fits
/// i64. The result lies between `a` and `b`.
#[inline]
fn lerp(a: u32, b: u32, i: u32, n: u32) -> u32 {
    let d = b as i64 - a as i64;
    let num = d * i as i64 * 2 + n as i64;
    (a as i64 + num.div_euclid(2 * n as i64)) as u32
}

/// Fills row `y` (`out.len()` pixels) with segments of `segment` pixels (clamped to
/// 1..=[`MAX_SEGMENT`]) and threshold `k`; returns the number of evaluations.
/// An empty row costs nothing.
///
/// ```
/// use fixshade::sampler::{fill_row, PixelFn, Threshold};
/// // A step at x = 5: segments that straddle it are halved down to single pixels.
/// struct Step;
/// impl PixelFn for Step {
///     fn eval(&mut self, x: u32, _y: u32) -> [u32; 3] {
///         if x < 5 { [0; 3] } else { [255; 3] }
///     }
/// }
/// let mut row = [[0u32; 3]; 16];
/// let evals = fill_row(&mut Step, 0, 8, Threshold::from_q8(256, [255; 3]), &mut row);
/// assert!(row.iter().enumerate().all(|(x, c)| c[0] == if x < 5 { 0 } else { 255 }));
/// assert!(evals < 16); // fewer evaluations than pixels, yet the edge is exact
/// ```
pub fn fill_row<F: PixelFn>(
    f: &mut F,
    y: u32,
    segment: u32,
    k: Threshold,
    out: &mut [[u32; 3]],
) -> u32 {
    let w = out.len().min(u32::MAX as usize) as u32;
    if w == 0 {
        return 0;
    }
    let l = segment.clamp(1, MAX_SEGMENT);
    let mut evals = 1;
    out[0] = f.eval(0, y);
    let mut x0 = 0u32;
    while x0 + 1 < w {
        let x1 = (x0 + l).min(w - 1);
        out[x1 as usize] = f.eval(x1, y);
        evals += 1;
        evals += refine_row(f, y, x0, x1, k, out);
        x0 = x1;
    }
    evals
}

/// Fills the inside of segment `[x0, x1]` whose ends are known; returns the
/// evaluations made. Recursion depth ≤ log₂ of the segment length ≤ 12.
fn refine_row<F: PixelFn>(
    f: &mut F,
    y: u32,
    x0: u32,
    x1: u32,
    k: Threshold,
    out: &mut [[u32; 3]],
) -> u32 {
    let n = x1 - x0;
    if n < 2 {
        return 0;
    }
    let (a, b) = (out[x0 as usize], out[x1 as usize]);
    if !k.differ(a, b) {
        for i in 1..n {
            out[(x0 + i) as usize] = core::array::from_fn(|c| lerp(a[c], b[c], i, n));
        }
        return 0;
    }
    let m = x0 + n / 2;
    out[m as usize] = f.eval(m, y);
    1 + refine_row(f, y, x0, m, k, out) + refine_row(f, y, m, x1, k, out)
}

/// Marks a pixel not yet known in [`fill_blocks`]' buffer.
const UNKNOWN: u32 = u32::MAX;

/// Fills a `width × height` image (`out`, row-major, at least `width·height`
/// entries; a shorter buffer fills nothing and returns 0) with blocks of
/// `segment × segment` pixels (clamped to 1..=[`MAX_SEGMENT`]) and threshold `k`;
/// returns the number of evaluations. Each pixel is evaluated at most once (shared
/// corners and edges are reused). A strip renderer calls it per band of rows; the
/// band's first row is then evaluated again.
///
/// ```
/// use fixshade::sampler::{fill_blocks, PixelFn, Threshold};
/// // A flat image costs only the corners of its 4×4 blocks: a 5×5 grid for 17×17 pixels.
/// struct Flat;
/// impl PixelFn for Flat {
///     fn eval(&mut self, _x: u32, _y: u32) -> [u32; 3] {
///         [100, 50, 25]
///     }
/// }
/// let mut img = [[0u32; 3]; 17 * 17];
/// let evals = fill_blocks(&mut Flat, 17, 17, 4, Threshold::from_q8(0, [255; 3]), &mut img);
/// assert_eq!(evals, 25);
/// assert!(img.iter().all(|c| *c == [100, 50, 25]));
/// ```
pub fn fill_blocks<F: PixelFn>(
    f: &mut F,
    width: u32,
    height: u32,
    segment: u32,
    k: Threshold,
    out: &mut [[u32; 3]],
) -> u32 {
    let n = width as usize * height as usize;
    if n == 0 || out.len() < n {
        return 0;
    }
    let l = segment.clamp(1, MAX_SEGMENT);
    let mut b = Blocks {
        f,
        w: width,
        out,
        k,
        evals: 0,
    };
    for p in b.out[..n].iter_mut() {
        p[0] = UNKNOWN;
    }
    let mut y0 = 0;
    loop {
        let y1 = (y0 + l).min(height - 1);
        let mut x0 = 0;
        loop {
            let x1 = (x0 + l).min(width - 1);
            b.refine(x0, y0, x1, y1);
            if x1 + 1 >= width {
                break;
            }
            x0 = x1;
        }
        if y1 + 1 >= height {
            break;
        }
        y0 = y1;
    }
    b.evals
}

struct Blocks<'f, 'o, F: PixelFn> {
    f: &'f mut F,
    w: u32,
    out: &'o mut [[u32; 3]],
    k: Threshold,
    evals: u32,
}

impl<F: PixelFn> Blocks<'_, '_, F> {
    /// The pixel's colour, evaluating it if not yet known.
    fn get(&mut self, x: u32, y: u32) -> [u32; 3] {
        let i = y as usize * self.w as usize + x as usize;
        if self.out[i][0] == UNKNOWN {
            self.out[i] = self.f.eval(x, y);
            self.evals += 1;
        }
        self.out[i]
    }

    /// Fills the block with corners `(x0, y0)`–`(x1, y1)`, evaluating the corners
    /// not yet known. Recursion depth ≤
    /// log₂ of the side ≤ 12.
    fn refine(&mut self, x0: u32, y0: u32, x1: u32, y1: u32) {
        let (w, h) = (x1 - x0, y1 - y0);
        let c = [
            self.get(x0, y0),
            self.get(x1, y0),
            self.get(x0, y1),
            self.get(x1, y1),
        ];
        if w < 2 && h < 2 {
            return;
        }
        let differ = (0..3).any(|ch| {
            let lo = c.iter().map(|p| p[ch]).min().unwrap_or(0);
            let hi = c.iter().map(|p| p[ch]).max().unwrap_or(0);
            hi - lo > self.k.limit[ch]
        });
        if !differ {
            self.bilinear(x0, y0, x1, y1, c);
            return;
        }
        let mx = x0 + w / 2;
        let my = y0 + h / 2;
        match (w >= 2, h >= 2) {
            (true, true) => {
                self.refine(x0, y0, mx, my);
                self.refine(mx, y0, x1, my);
                self.refine(x0, my, mx, y1);
                self.refine(mx, my, x1, y1);
            }
            (true, false) => {
                self.refine(x0, y0, mx, y1);
                self.refine(mx, y0, x1, y1);
            }
            _ => {
                self.refine(x0, y0, x1, my);
                self.refine(x0, my, x1, y1);
            }
        }
    }

    /// Bilinear fill of the unknown pixels of the block. A weight `(w−i)(h−j)` is at
    /// most 2²⁴ (sides ≤ 4096), times a channel < 2³² below 2⁵⁶; the sum of four
    /// such terms, doubled, is below 2⁵⁹ and fits u64.
    fn bilinear(&mut self, x0: u32, y0: u32, x1: u32, y1: u32, c: [[u32; 3]; 4]) {
        let (w, h) = ((x1 - x0).max(1) as u64, (y1 - y0).max(1) as u64);
        let den = w * h;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let idx = y as usize * self.w as usize + x as usize;
                if self.out[idx][0] != UNKNOWN {
                    continue;
                }
                let (i, j) = ((x - x0) as u64, (y - y0) as u64);
                let wt = [(w - i) * (h - j), i * (h - j), (w - i) * j, i * j];
                self.out[idx] = core::array::from_fn(|ch| {
                    let s: u64 = (0..4).map(|k| c[k][ch] as u64 * wt[k]).sum();
                    ((2 * s + den) / (2 * den)) as u32
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec;
    use std::vec::Vec;

    /// A function given by a closure, counting its calls.
    struct Counted<G: FnMut(u32, u32) -> [u32; 3]>(G, u32);
    impl<G: FnMut(u32, u32) -> [u32; 3]> PixelFn for Counted<G> {
        fn eval(&mut self, x: u32, y: u32) -> [u32; 3] {
            self.1 += 1;
            (self.0)(x, y)
        }
    }

    const K0: Threshold = Threshold::from_q8(0, [255; 3]);

    #[test]
    fn segment_one_evaluates_every_pixel() {
        let g = |x: u32, y: u32| [(x * 37 + y * 11) % 256, x % 7, 255 - x % 256];
        let mut f = Counted(g, 0);
        let mut row = vec![[0; 3]; 101];
        let n = fill_row(
            &mut f,
            3,
            1,
            Threshold::from_q8(1 << 20, [255; 3]),
            &mut row,
        );
        assert_eq!(n, 101);
        assert_eq!(f.1, 101);
        for (x, c) in row.iter().enumerate() {
            assert_eq!(*c, g(x as u32, 3));
        }
    }

    #[test]
    fn flat_row_costs_one_evaluation_per_segment() {
        for (w, l) in [(320u32, 8u32), (320, 16), (100, 7), (5, 16), (1, 4)] {
            let mut f = Counted(|_, _| [9, 200, 31], 0);
            let mut row = vec![[0; 3]; w as usize];
            let n = fill_row(&mut f, 0, l, K0, &mut row);
            assert_eq!(n, 1 + (w - 1).div_ceil(l), "w {w} l {l}");
            assert!(row.iter().all(|c| *c == [9, 200, 31]));
        }
    }

    #[test]
    fn an_edge_subdivides_to_single_pixels() {
        // Step at x = 37: the segment [32, 40] must be refined until the step lies
        // between two evaluated neighbours, so the row equals the function.
        let g = |x: u32, _| if x < 37 { [0; 3] } else { [255; 3] };
        let mut f = Counted(g, 0);
        let mut row = vec![[0; 3]; 64];
        let n = fill_row(&mut f, 0, 8, K0, &mut row);
        for (x, c) in row.iter().enumerate() {
            assert_eq!(*c, g(x as u32, 0), "x {x}");
        }
        // 9 segment ends + 3 halvings of [32, 40] (36, 38, 37).
        assert_eq!(n, 9 + 3);
    }

    #[test]
    fn interpolation_rounds_half_up() {
        // Ends 0 and 3 over 2 pixels: 1.5 → 2. Ends 3 and 0: 1.5 → 2 as well.
        assert_eq!(lerp(0, 3, 1, 2), 2);
        assert_eq!(lerp(3, 0, 1, 2), 2);
        assert_eq!(lerp(10, 0, 1, 4), 8); // 7.5 → 8
        assert_eq!(lerp(0, 10, 1, 4), 3); // 2.5 → 3
        for n in 1..40u32 {
            for i in 0..=n {
                for (a, b) in [(0u32, 255u32), (255, 0), (17, 18), (63, 0)] {
                    let exact = a as f64 + (b as f64 - a as f64) * i as f64 / n as f64;
                    assert_eq!(lerp(a, b, i, n), (exact + 0.5).floor() as u32);
                }
            }
        }
    }

    #[test]
    fn blocks_segment_one_and_flat_and_edges() {
        let (w, h) = (37u32, 23u32);
        let g = |x: u32, y: u32| [(x * 13 + y * 7) % 256, y, x];
        let mut f = Counted(g, 0);
        let mut out = vec![[0; 3]; (w * h) as usize];
        assert_eq!(fill_blocks(&mut f, w, h, 1, K0, &mut out), w * h);
        let want: Vec<[u32; 3]> = (0..h).flat_map(|y| (0..w).map(move |x| g(x, y))).collect();
        assert_eq!(out, want);

        // Flat: one evaluation per grid corner.
        let mut f = Counted(|_, _| [1, 2, 3], 0);
        let n = fill_blocks(&mut f, 33, 17, 8, K0, &mut out);
        assert_eq!(n, 5 * 3);
        assert!(out[..33 * 17].iter().all(|c| *c == [1, 2, 3]));

        // A disc edge: the blocks must reproduce it exactly with K = 0.
        let disc = |x: u32, y: u32| {
            let (dx, dy) = (x as i32 - 20, y as i32 - 11);
            if dx * dx + dy * dy < 64 {
                [200, 100, 50]
            } else {
                [0, 0, 0]
            }
        };
        let mut f = Counted(disc, 0);
        let n = fill_blocks(&mut f, w, h, 8, K0, &mut out);
        for y in 0..h {
            for x in 0..w {
                assert_eq!(out[(y * w + x) as usize], disc(x, y), "({x}, {y})");
            }
        }
        assert!(n < w * h, "{n}");
    }

    #[test]
    fn degenerate_sizes() {
        let mut f = Counted(|_, _| [0; 3], 0);
        assert_eq!(fill_row(&mut f, 0, 8, K0, &mut []), 0);
        assert_eq!(fill_row(&mut f, 0, 0, K0, &mut [[0; 3]; 3]), 3);
        assert_eq!(fill_row(&mut f, 0, u32::MAX, K0, &mut [[0; 3]; 3]), 2);
        assert_eq!(fill_blocks(&mut f, 0, 5, 8, K0, &mut []), 0);
        assert_eq!(fill_blocks(&mut f, 4, 4, 8, K0, &mut [[0; 3]; 3]), 0);
        let mut one = [[7; 3]; 1];
        assert_eq!(fill_blocks(&mut f, 1, 1, 8, K0, &mut one), 1);
        assert_eq!(one[0], [0; 3]);
    }
}
