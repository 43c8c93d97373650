//! Drawing a prepared frame in horizontal bands without repeating work.
//!
//! A display without a whole framebuffer is fed band by band: a few rows rendered
//! into a small buffer, sent, the next band. [`Frame::bin`] does the per-triangle
//! work once per frame: every triangle is classified (culled, drawn or clipped) and
//! set up once, into a [`Record`] (its sorted positions and the lattice of its
//! attributes), and the records are sorted into bins, one list per band. Drawing a
//! band ([`Binned::draw_band`]) then walks only the records of that band, starting
//! each edge walk at the band's first row: the edge steppers are placed there
//! directly (one division at most), the lattice is not recomputed. With a
//! [`Walk`] per record ([`BandMemory::with_walks`]) and the bands drawn in order
//! ([`Binned::draw_band_resuming`], what [`crate::present::linebuf::render_binned`] does),
//! the steppers are not placed again either: each walk goes on from the row where
//! the band above left it. A band of 16 rows then costs about what the same rows of
//! a whole-frame draw cost.
//!
//! Memory is the caller's ([`BandMemory`]): records, the bins' index and the bins'
//! starts, all sized by `const fn`s so a firmware can put them in `static`s. When
//! the memory lent is too small for the frame, or the frame draws with a method or
//! shading that has no records (everything but the constant gradient of Gouraud or
//! flat shading with the exact setup), every band is drawn by walking all triangles
//! again ([`Frame::draw`] on the band): the same pixels, more work, counted in
//! [`Stats::rewalked`]. Never a panic, never a different pixel.
//!
//! A binned frame is shared, not mutated, by the band draws: two bands can be drawn
//! at the same time into different buffers (the RP2040's two cores; two threads on
//! the host).
//!
//! ```
//! use fixshade::prelude::*;
//! use fixshade::raster::setup::Record;
//! use fixshade::render::BandMemory;
//! # let scene = fixshade::doc_support::scene();
//! let (w, h, rows) = (64, 48, 16);
//! let mut cache = [XfVertex::default(); 3];
//! let frame = Frame::<Rgb565Le>::prepare(&scene, w, h, &mut cache).unwrap();
//! // Memory for up to 8 records of triangles at most 48 rows tall.
//! let mut records = [Record::EMPTY; 8];
//! let mut index = [0u16; BandMemory::index_len(8, 48, 16, 48)];
//! let mut starts = [0u32; BandMemory::starts_len(48, 16)];
//! let binned = frame.bin(rows, BandMemory::new(&mut records, &mut index, &mut starts)).unwrap();
//! assert!(binned.complete());
//! let (mut px, mut z) = ([0u16; 64 * 16], [0u16; 64 * 16]);
//! let mut covered = 0;
//! for band in 0..binned.bands() {
//!     let mut strip = Strip::new(&mut px, Some(&mut z), w, h, band * rows, rows).unwrap();
//!     strip.clear(0);
//!     covered += binned.draw_band::<Gradient, _>(band, &mut strip).unwrap().pixels;
//!     // ... send strip.color() to the display
//! }
//! // The same pixels as a whole-frame draw.
//! let (mut fpx, mut fz) = ([0u16; 64 * 48], [0u16; 64 * 48]);
//! let mut fb = Framebuffer::new(&mut fpx, Some(&mut fz), w, h).unwrap();
//! fb.clear(0);
//! assert_eq!(frame.draw::<Gradient, _>(&mut fb).unwrap().pixels, covered);
//! ```

use crate::arrays;
use core::marker::PhantomData;
use core::ops::Range;

use super::frame::{Frame, RenderError, Stats};
use super::walk::{Triangle, TriangleFill};
use crate::raster::edge::first_row_in_guard;
use crate::raster::outside_guard;
use crate::raster::setup::{lattice, Record};
use crate::raster::span::{DepthMode, DepthTest, NoDepth, SpanMethod};
use crate::raster::{fill_gradient, Walk};
use crate::scene::ShadingMode;
use crate::shade::{Flat, Gouraud, Shading};
use crate::specular::Specular;
use crate::target::{PixelFormat, Target};

/// Caller-owned memory of a frame drawn in bands: the setup records, the bins'
/// index (record numbers, band after band) and the bins' starts.
///
/// RAM: `records · 76 + index · 2 + starts · 4` bytes ([`BandMemory::bytes`]), and
/// `records · 48` more for walks ([`BandMemory::with_walks`]).
/// `records` bounds the triangles drawn (after culling; a clipped triangle may give
/// up to seven pieces); `index` needs one entry per record and band it reaches
/// ([`BandMemory::index_len`]); `starts` one per band and one more
/// ([`BandMemory::starts_len`]). Too little of any of them is not an error: the
/// frame is then drawn band by band without records ([`Stats::rewalked`]).
///
/// ```
/// use fixshade::render::BandMemory;
/// // 400 records of triangles up to 24 rows tall, in 16-row bands of a 240-row frame.
/// const INDEX: usize = BandMemory::index_len(400, 240, 16, 24);
/// const STARTS: usize = BandMemory::starts_len(240, 16);
/// assert_eq!((INDEX, STARTS), (1200, 16));
/// assert_eq!(BandMemory::bytes(400, INDEX, STARTS), 400 * 76 + 1200 * 2 + 16 * 4);
/// ```
pub struct BandMemory<'m> {
    records: &'m mut [Record],
    index: &'m mut [u16],
    starts: &'m mut [u32],
    walks: &'m mut [Walk],
}

impl<'m> BandMemory<'m> {
    /// Lends the three arrays.
    pub fn new(
        records: &'m mut [Record],
        index: &'m mut [u16],
        starts: &'m mut [u32],
    ) -> BandMemory<'m> {
        BandMemory {
            records,
            index,
            starts,
            walks: &mut [],
        }
    }

    /// Lends, besides, one [`Walk`] per record (48 bytes each), for drawing the
    /// bands in order with [`Binned::draw_band_resuming`]: each record's edge walk
    /// then goes on from where the band above left it instead of being placed
    /// afresh at every band it reaches. Fewer walks than records are not an error:
    /// the walks are then not used.
    ///
    /// ```
    /// use fixshade::prelude::*;
    /// use fixshade::raster::{setup::Record, Walk};
    /// use fixshade::render::BandMemory;
    /// # let scene = fixshade::doc_support::scene();
    /// let mut cache = [XfVertex::default(); 3];
    /// let frame = Frame::<Rgb565Be>::prepare(&scene, 64, 48, &mut cache).unwrap();
    /// let (mut records, mut index, mut starts) = ([Record::EMPTY; 4], [0u16; 96], [0u32; 25]);
    /// let mut walks = [Walk::EMPTY; 4];
    /// let mem = BandMemory::new(&mut records, &mut index, &mut starts).with_walks(&mut walks);
    /// let mut binned = frame.bin(2, mem).unwrap();
    /// let (mut color, mut depth) = ([0u16; 64 * 2], [u16::MAX; 64 * 2]);
    /// let mut pixels = 0;
    /// for band in 0..binned.bands() {
    ///     let rows = binned.rows(band);
    ///     let mut strip = Strip::new(&mut color, Some(&mut depth), 64, 48, rows.start, 2).unwrap();
    ///     strip.clear(0);
    ///     pixels += binned.draw_band_resuming::<Gradient, _>(band, &mut strip).unwrap().pixels;
    /// }
    /// assert!(pixels > 0);
    /// ```
    pub fn with_walks(self, walks: &'m mut [Walk]) -> BandMemory<'m> {
        BandMemory { walks, ..self }
    }

    /// Bands of `band_rows` rows (at least 1) in a frame `height` rows tall.
    pub const fn bands(height: u32, band_rows: u32) -> usize {
        let r = if band_rows == 0 { 1 } else { band_rows };
        height.div_ceil(r) as usize
    }

    /// Length of the bins' starts: one per band and one more.
    pub const fn starts_len(height: u32, band_rows: u32) -> usize {
        Self::bands(height, band_rows) + 1
    }

    /// Length of the bins' index for `records` records of triangles at most
    /// `tallest` rows tall: each reaches at most `1 + ⌈(tallest − 1)/band_rows⌉`
    /// bands (and no more than the frame has).
    pub const fn index_len(records: usize, height: u32, band_rows: u32, tallest: u32) -> usize {
        let r = if band_rows == 0 { 1 } else { band_rows };
        let t = if tallest == 0 { 1 } else { tallest };
        let per = 1 + (t - 1).div_ceil(r) as usize;
        let bands = Self::bands(height, r);
        records * if per < bands { per } else { bands }
    }

    /// Bytes of RAM the three arrays take (and, with [`BandMemory::with_walks`],
    /// `records · size_of::<Walk>()` more: 48 bytes a record).
    pub const fn bytes(records: usize, index: usize, starts: usize) -> usize {
        records * core::mem::size_of::<Record>() + index * 2 + starts * 4
    }
}

/// A prepared frame whose triangles are set up and sorted into bands
/// ([`Frame::bin`]); draw each band with [`Binned::draw_band`], in any order, from
/// any thread.
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::setup::Record;
/// use fixshade::render::BandMemory;
/// use fixshade::target::Strip;
/// # let scene = fixshade::doc_support::scene();
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Rgb565Be>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// let (mut records, mut index, mut starts) = ([Record::EMPTY; 4], [0u16; 12], [0u32; 4]);
/// let binned = frame.bin(16, BandMemory::new(&mut records, &mut index, &mut starts)).unwrap();
/// assert!(binned.complete());
/// let (mut color, mut depth) = ([0u16; 64 * 16], [u16::MAX; 64 * 16]);
/// for band in (0..binned.bands()).rev() {
///     let rows = binned.rows(band);
///     let mut strip = Strip::new(&mut color, Some(&mut depth), 64, 48, rows.start, rows.len() as u32).unwrap();
///     binned.draw_band::<Gradient, _>(band, &mut strip).unwrap();
/// }
/// ```
pub struct Binned<'f, 's, 'a, 'c, 'm, P: PixelFormat, Sp: Specular> {
    frame: &'f Frame<'s, 'a, 'c, P, Sp>,
    records: &'m [Record],
    index: &'m [u16],
    starts: &'m [u32],
    /// One per record ([`BandMemory::with_walks`]), or none.
    walks: &'m mut [Walk],
    band_rows: u32,
    complete: bool,
    stats: Stats,
}

/// The records and bins of a binned frame without the frame ([`Binned::into_bins`]):
/// what drawing the bands needs once every triangle is set up. It no longer
/// borrows the vertex cache, so the cache's memory can hold the band buffers
/// while the bands are drawn (the RAM of a small board: the larger of the two,
/// not their sum). Each band is drawn with the constant gradient from the records
/// ([`span::Gradient`](crate::raster::span::Gradient)'s pixels).
///
/// ```
/// use fixshade::prelude::*;
/// use fixshade::raster::setup::Record;
/// use fixshade::render::BandMemory;
/// # let scene = fixshade::doc_support::scene();
/// let (mut records, mut index, mut starts) = ([Record::EMPTY; 4], [0u16; 12], [0u32; 4]);
/// // One buffer, first the vertex cache, then the band's colour.
/// let mut cache = [XfVertex::default(); 3];
/// let bins = {
///     let frame = Frame::<Rgb565Be>::prepare(&scene, 64, 48, &mut cache).unwrap();
///     let binned = frame.bin(16, BandMemory::new(&mut records, &mut index, &mut starts)).unwrap();
///     binned.into_bins().expect("the memory holds every record")
/// };
/// // `bins` borrows no vertex cache: a board can reuse the cache's memory now.
/// cache[0] = XfVertex::default();
/// let (mut color, mut depth) = ([0u16; 64 * 16], [u16::MAX; 64 * 16]);
/// let mut pixels = 0;
/// for band in 0..bins.bands() {
///     let rows = bins.rows(band);
///     let mut strip = Strip::new(&mut color, Some(&mut depth), 64, 48, rows.start, 16).unwrap();
///     strip.clear(0);
///     pixels += bins.draw_band(band, &mut strip).unwrap().pixels;
/// }
/// assert!(pixels > 0);
/// ```
pub struct Bins<'m, P: PixelFormat> {
    records: &'m [Record],
    index: &'m [u16],
    starts: &'m [u32],
    /// One per record ([`BandMemory::with_walks`]), or none.
    walks: &'m mut [Walk],
    width: u32,
    height: u32,
    band_rows: u32,
    depth_test: bool,
    flat: bool,
    _format: PhantomData<fn() -> P>,
}

impl<'s, 'a, 'c, P: PixelFormat, Sp: Specular> Frame<'s, 'a, 'c, P, Sp> {
    /// Classifies and sets up every triangle of the frame once and sorts the set-up
    /// triangles into bands of `band_rows` rows (at least 1), in `mem`. See the
    /// [module docs](self).
    ///
    /// The returned [`Binned::stats`] count the triangles (submitted, culled,
    /// clipped, drawn) once; the band draws add the pixels.
    pub fn bin<'f, 'm>(
        &'f self,
        band_rows: u32,
        mem: BandMemory<'m>,
    ) -> Result<Binned<'f, 's, 'a, 'c, 'm, P, Sp>, RenderError> {
        let band_rows = band_rows.max(1);
        let BandMemory {
            records,
            index,
            starts,
            walks,
        } = mem;
        if Sp::two_sided() {
            // No records of the back colours: bands re-walk.
            return Ok(self.unbinned(band_rows));
        }
        let flat = match self.scene.shading {
            ShadingMode::Gouraud => false,
            ShadingMode::Flat => true,
            // No records for the per-pixel and quadratic fills: bands re-walk.
            _ => return Ok(self.unbinned(band_rows)),
        };
        let height = self.vp.height;
        let bands = BandMemory::bands(height, band_rows);
        if starts.len() < bands + 1 {
            return Ok(self.unbinned(band_rows));
        }
        // 1. Every triangle classified and set up once, as a whole-frame draw does.
        let mut fill = Binner {
            records,
            n: 0,
            full: false,
            flat,
        };
        let st = self.walk(0..height as i32, &mut fill)?;
        let Binner {
            records, n, full, ..
        } = fill;
        if full || n > u16::MAX as usize + 1 {
            return Ok(Binned {
                stats: st,
                ..self.unbinned(band_rows)
            });
        }
        let records = &records[..n];
        // 2. Counting sort into the bins: starts[b + 1] counts band b's records, then
        //    the prefix sums make starts[b] band b's first entry.
        let starts = &mut starts[..bands + 1];
        starts.fill(0);
        for r in records {
            if let Some(bs) = band_span(r, height, band_rows) {
                for c in &mut starts[bs.start + 1..bs.end + 1] {
                    *c += 1;
                }
            }
        }
        for b in 0..bands {
            starts[b + 1] += starts[b];
        }
        let total = starts[bands] as usize;
        if total > index.len() {
            return Ok(Binned {
                stats: st,
                ..self.unbinned(band_rows)
            });
        }
        // Fill band by band with a cursor per band (starts[b] walks up to band b's
        // end, which is band b + 1's start), then shift the cursors back.
        for (i, r) in records.iter().enumerate() {
            if let Some(bs) = band_span(r, height, band_rows) {
                for c in &mut starts[bs] {
                    index[*c as usize] = i as u16;
                    *c += 1;
                }
            }
        }
        for b in (1..=bands).rev() {
            starts[b] = starts[b - 1];
        }
        starts[0] = 0;
        let walks = match walks.get_mut(..n) {
            Some(w) => {
                w.iter_mut().for_each(Walk::forget);
                w
            }
            None => &mut [],
        };
        Ok(Binned {
            frame: self,
            records,
            index: &index[..total],
            starts,
            walks,
            band_rows,
            complete: true,
            stats: st,
        })
    }

    /// A binned frame without records: every band re-walks the triangles.
    fn unbinned<'f, 'm>(&'f self, band_rows: u32) -> Binned<'f, 's, 'a, 'c, 'm, P, Sp> {
        Binned {
            frame: self,
            records: &[],
            index: &[],
            starts: &[],
            walks: &mut [],
            band_rows,
            complete: false,
            stats: Stats::default(),
        }
    }
}

/// The binning's fill for the triangle walk: each triangle set up into a record
/// of `records` (Gouraud colours, or the last vertex's with `flat`), clipped ones
/// piece by piece; `full` once a record did not fit. Covers no pixels.
struct Binner<'m> {
    records: &'m mut [Record],
    /// Records written.
    n: usize,
    full: bool,
    flat: bool,
}

impl Binner<'_> {
    /// Keeps the record of a set-up triangle (none for an empty one).
    #[inline(always)]
    fn push(&mut self, r: Option<Record>) {
        let Some(r) = r else { return };
        match self.records.get_mut(self.n) {
            Some(slot) => {
                // Field by field: each part is copied inline, where the 76-byte
                // record would go through a `memcpy` call on the chips.
                slot.xy = r.xy;
                slot.gx = r.gx;
                slot.gy = r.gy;
                slot.origin = r.origin;
                slot.mid_left = r.mid_left;
                slot.unwrapped = r.unwrapped;
                self.n += 1;
            }
            None => self.full = true,
        }
    }
}

impl<P: PixelFormat, Sp: Specular> TriangleFill<P, Sp> for Binner<'_> {
    type PerObject = ();

    #[inline(always)]
    fn inside(&mut self, _: &(), tri: &Triangle<'_, '_>, _: &mut Stats) -> u32 {
        if self.flat {
            let s = tri.coloured(false, false);
            self.push(lattice([&s[0], &s[1], &s[2]]));
        } else {
            self.push(lattice(tri.screen()));
        }
        0
    }

    #[inline(always)]
    fn clipped(&mut self, _: &(), tri: &Triangle<'_, '_>, st: &mut Stats) {
        tri.clip_coloured::<Sp>(!self.flat, st, |s, _| {
            if !outside_guard(arrays::map(s, |p| (p.x, p.y))) {
                self.push(lattice([&s[0], &s[1], &s[2]]));
            }
            0
        });
    }
}

/// The bands a record's rows reach: `[first, last + 1)`, or `None` if it covers
/// no row of the frame.
#[inline]
fn band_span(r: &Record, height: u32, band_rows: u32) -> Option<Range<usize>> {
    let top = first_row_in_guard(r.xy[0].1).max(0);
    let bottom = first_row_in_guard(r.xy[2].1).min(height as i32);
    (top < bottom).then(|| {
        let (t, b) = (
            band_of(top as u32, band_rows),
            band_of(bottom as u32 - 1, band_rows),
        );
        t as usize..b as usize + 1
    })
}

/// The band of row `y`: a shift for band heights that are powers of two (no
/// division, which ARMv6-M takes from a library routine), a division otherwise.
#[inline(always)]
fn band_of(y: u32, band_rows: u32) -> u32 {
    if band_rows.is_power_of_two() {
        y >> band_rows.trailing_zeros()
    } else {
        y / band_rows
    }
}

impl<'m, P: PixelFormat, Sp: Specular> Binned<'_, '_, '_, '_, 'm, P, Sp> {
    /// Rows per band.
    pub fn band_rows(&self) -> u32 {
        self.band_rows
    }

    /// Number of bands in the frame.
    pub fn bands(&self) -> u32 {
        bands_in(self.frame.vp.height, self.band_rows)
    }

    /// The frame rows of band `band`.
    pub fn rows(&self, band: u32) -> Range<u32> {
        rows_of(band, self.frame.vp.height, self.band_rows)
    }

    /// True if every triangle was set up and binned; false if the memory was too
    /// small or the frame's shading has no records (then each band re-walks).
    pub fn complete(&self) -> bool {
        self.complete
    }

    /// What the binning counted: triangles submitted, culled, clipped and drawn
    /// (once per frame, pixels 0). Zero if it did not bin.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The records and bins without the frame, when the frame is
    /// [`complete`](Binned::complete) (`None` otherwise: its bands need the frame
    /// to re-walk the triangles). See [`Bins`].
    pub fn into_bins(self) -> Option<Bins<'m, P>> {
        let f = self.frame;
        self.complete.then_some(Bins {
            records: self.records,
            index: self.index,
            starts: self.starts,
            walks: self.walks,
            width: f.vp.width,
            height: f.vp.height,
            band_rows: self.band_rows,
            depth_test: f.scene.depth_test,
            flat: f.scene.shading == ShadingMode::Flat,
            _format: PhantomData,
        })
    }

    /// Draws band `band` into `target`, whose rows must lie within the band (and
    /// whose size is the frame's). Records are drawn with the method `S` when it
    /// draws from records ([`SpanMethod::RECORDS`]: the constant gradient with the
    /// exact setup); otherwise, or when the frame was not binned, the band is drawn
    /// by [`Frame::draw`] walking every triangle ([`Stats::rewalked`] is then 1).
    /// The pixels are the same either way.
    pub fn draw_band<S: SpanMethod, T: Target<P>>(
        &self,
        band: u32,
        target: &mut T,
    ) -> Result<Stats, RenderError> {
        self.draw_band_with::<S, T>(band, target, &mut [])
    }

    /// [`Binned::draw_band`], resuming each record's edge walk where the band
    /// above left it, when the memory lent walks ([`BandMemory::with_walks`]): for
    /// bands drawn in order by one thread (a walk up to 64 rows above is stepped
    /// on, so every other band works too). The pixels are the same as
    /// [`Binned::draw_band`]'s, in any order of bands; a band far from where a walk
    /// stopped places it afresh.
    pub fn draw_band_resuming<S: SpanMethod, T: Target<P>>(
        &mut self,
        band: u32,
        target: &mut T,
    ) -> Result<Stats, RenderError> {
        let walks = core::mem::take(&mut self.walks);
        let r = self.draw_band_with::<S, T>(band, target, walks);
        self.walks = walks;
        r
    }

    /// [`Binned::draw_band`] with `walks`: one per record, or none.
    fn draw_band_with<S: SpanMethod, T: Target<P>>(
        &self,
        band: u32,
        target: &mut T,
        walks: &mut [Walk],
    ) -> Result<Stats, RenderError> {
        let f = self.frame;
        check_target(band, (f.vp.width, f.vp.height), self.band_rows, target)?;
        if !(S::RECORDS && self.complete) {
            let mut st = f.draw::<S, T>(target)?;
            st.rewalked = 1;
            return Ok(st);
        }
        let list = &self.index
            [self.starts[band as usize] as usize..self.starts[band as usize + 1] as usize];
        let flat = f.scene.shading == ShadingMode::Flat;
        draw_records::<P, T>(self.records, list, f.scene.depth_test, flat, target, walks)
    }
}

impl<P: PixelFormat> Bins<'_, P> {
    /// Rows per band.
    pub fn band_rows(&self) -> u32 {
        self.band_rows
    }

    /// Number of bands in the frame.
    pub fn bands(&self) -> u32 {
        bands_in(self.height, self.band_rows)
    }

    /// The frame rows of band `band`.
    pub fn rows(&self, band: u32) -> Range<u32> {
        rows_of(band, self.height, self.band_rows)
    }

    /// Draws band `band` into `target` from the records, as
    /// [`Binned::draw_band`] with [`Gradient`](crate::raster::span::Gradient).
    /// `target`'s rows must lie within the band and its frame size must be the
    /// frame's ([`RenderError::TargetSizeMismatch`] otherwise).
    pub fn draw_band<T: Target<P>>(&self, band: u32, target: &mut T) -> Result<Stats, RenderError> {
        self.check(band, target)?;
        self.draw_checked(band, target, &mut [])
    }

    /// [`Bins::draw_band`], resuming each record's edge walk where the band above
    /// left it, as [`Binned::draw_band_resuming`].
    pub fn draw_band_resuming<T: Target<P>>(
        &mut self,
        band: u32,
        target: &mut T,
    ) -> Result<Stats, RenderError> {
        self.check(band, target)?;
        let walks = core::mem::take(&mut self.walks);
        let r = self.draw_checked(band, target, walks);
        self.walks = walks;
        r
    }

    /// Whether `target` is of the frame's size and within band `band`.
    fn check<T: Target<P>>(&self, band: u32, target: &T) -> Result<(), RenderError> {
        check_target(band, (self.width, self.height), self.band_rows, target)
    }

    /// Band `band`'s records drawn into `target` (checked by [`Bins::check`]),
    /// resuming their walks from `walks` (one per record, or none).
    fn draw_checked<T: Target<P>>(
        &self,
        band: u32,
        target: &mut T,
        walks: &mut [Walk],
    ) -> Result<Stats, RenderError> {
        let list = &self.index
            [self.starts[band as usize] as usize..self.starts[band as usize + 1] as usize];
        draw_records::<P, T>(
            self.records,
            list,
            self.depth_test,
            self.flat,
            target,
            walks,
        )
    }
}

/// The number of bands of `band_rows` rows in a frame `height` rows tall.
#[inline(always)]
fn bands_in(height: u32, band_rows: u32) -> u32 {
    band_of(height + band_rows - 1, band_rows)
}

/// The frame rows of band `band`.
#[inline(always)]
fn rows_of(band: u32, height: u32, band_rows: u32) -> Range<u32> {
    let y0 = (band * band_rows).min(height);
    y0..(y0 + band_rows).min(height)
}

/// [`RenderError::TargetSizeMismatch`] unless `target` is of the frame's `size`
/// and its rows lie within band `band` of the frame's bands of `band_rows` rows.
#[inline(always)]
fn check_target<P: PixelFormat, T: Target<P>>(
    band: u32,
    (width, height): (u32, u32),
    band_rows: u32,
    target: &T,
) -> Result<(), RenderError> {
    if target.width() != width || target.frame_height() != height {
        return Err(RenderError::TargetSizeMismatch);
    }
    let rows = rows_of(band, height, band_rows);
    let tr = target.rows();
    if band >= bands_in(height, band_rows)
        || tr.start < rows.start as i32
        || tr.end > rows.end as i32
    {
        return Err(RenderError::TargetSizeMismatch);
    }
    Ok(())
}

/// The records `records[i]` of `list` drawn into `target` with the constant
/// gradient (with the depth test when `depth_test`, the last vertex's colour when
/// `flat`), resuming their walks from `walks` (one per record, or none).
#[inline(always)]
fn draw_records<P: PixelFormat, T: Target<P>>(
    records: &[Record],
    list: &[u16],
    depth_test: bool,
    flat: bool,
    target: &mut T,
    walks: &mut [Walk],
) -> Result<Stats, RenderError> {
    if depth_test && !target.has_depth() {
        return Err(RenderError::NoDepthBuffer);
    }
    let pixels = match (depth_test, flat) {
        (true, false) => fill::<P, DepthTest, Gouraud, T>(records, list, target, walks),
        (true, true) => fill::<P, DepthTest, Flat, T>(records, list, target, walks),
        (false, false) => fill::<P, NoDepth, Gouraud, T>(records, list, target, walks),
        (false, true) => fill::<P, NoDepth, Flat, T>(records, list, target, walks),
    };
    Ok(Stats {
        pixels,
        ..Stats::default()
    })
}

/// [`draw_records`] with its depth mode and shading.
#[inline(always)]
fn fill<P: PixelFormat, Z: DepthMode, Sh: Shading, T: Target<P>>(
    records: &[Record],
    list: &[u16],
    target: &mut T,
    walks: &mut [Walk],
) -> u32 {
    list.iter()
        .map(|&i| {
            let i = i as usize;
            fill_gradient::<P, T, Z, Sh, _, _>(target, &records[i], walks.get_mut(i))
        })
        .sum()
}
