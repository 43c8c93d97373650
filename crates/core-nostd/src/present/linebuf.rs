//! Streaming to displays without a framebuffer: the renderer asks a
//! [`LineBufferProvider`] for a buffer, band by band, fills it, and hands it back.
//!
//! This is the shape of Slint's software renderer (`process_line(line, range,
//! render_fn)`): the provider owns the memory (often a DMA buffer), calls the
//! render function with it, and then sends the filled rows to the display over SPI.
//! A band is `band_rows` frame rows (1 gives Slint's one line at a time); the
//! renderer keeps only a depth buffer of one band. Each band is a [`Strip`] drawn by
//! [`Binned::draw_band`], so the bytes are the same as rendering the whole frame
//! into a [`crate::target::Framebuffer`]. With [`BandMemory`] lent, every triangle is
//! set up once per frame and each band draws only the triangles that reach it;
//! without, each band walks the triangle list again.
//!
//! ```
//! use core::ops::Range;
//! use fixshade::prelude::*;
//! use fixshade::render::BandMemory;
//!
//! /// A display driver stand-in: counts the bytes it would send.
//! struct Spi {
//!     buf: [u16; 64 * 8],
//!     sent: usize,
//! }
//! impl LineBufferProvider for Spi {
//!     type Format = Rgb565Be;
//!     fn size(&self) -> (u32, u32) {
//!         (64, 48)
//!     }
//!     fn process_lines(&mut self, lines: Range<u32>, render: impl FnOnce(&mut [u16])) {
//!         let n = 64 * lines.len();
//!         render(&mut self.buf[..n]);
//!         // set the display window to `lines`, then send `self.buf[..n]`
//!         self.sent += 2 * n;
//!     }
//! }
//!
//! static POS: [[Q16_16; 3]; 3] = [
//!     [Q16_16::from_int(-1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::from_int(1), Q16_16::from_int(-1), Q16_16::ZERO],
//!     [Q16_16::ZERO, Q16_16::from_int(1), Q16_16::ZERO],
//! ];
//! static NRM: [[Q2_14; 3]; 3] = [[Q2_14::from_bits(0), Q2_14::from_bits(0), Q2_14::ONE]; 3];
//! let eye = [Q16_16::ZERO, Q16_16::ZERO, Q16_16::from_int(3)];
//! let scene = Scene::new(Camera::perspective(eye, [Q16_16::ZERO; 3], Angle::from_degrees(60)))
//!     .with_light(Light::directional(eye, rgb(255, 255, 255), rgb(0, 0, 0)))
//!     .unwrap()
//!     .with_object(Object::new(Mesh::new(&POS, &NRM, &[[0, 1, 2]]).unwrap()))
//!     .unwrap();
//!
//! let mut cache = [XfVertex::default(); 3];
//! let frame = Frame::<Rgb565Be>::prepare(&scene, 64, 48, &mut cache).unwrap();
//! let mut depth = [0u16; 64 * 8];
//! let mut spi = Spi { buf: [0; 64 * 8], sent: 0 };
//! let black = Rgb565Be::pack(0, 0, 0);
//! let none = BandMemory::new(&mut [], &mut [], &mut []); // no records: each band re-walks
//! let stats = render_lines::<Gradient, _, _, _>(&frame, 8, none, Some(&mut depth), black, &mut spi).unwrap();
//! assert_eq!(spi.sent, 64 * 48 * 2);
//! assert!(stats.pixels > 300);
//! ```

use core::ops::Range;

use crate::present::DrawError;
use crate::raster::span::SpanMethod;
use crate::render::{BandMemory, Binned, Frame, Stats};
use crate::specular::Specular;
use crate::target::{DepthFormat, PixelFormat, Strip, TargetError};

/// Receives a frame band by band; implemented by display drivers.
///
/// The renderer calls [`LineBufferProvider::process_lines`] for consecutive bands
/// from the top of the frame; every row of the frame is asked for exactly once.
///
/// ```
/// use core::ops::Range;
/// use fixshade::present::linebuf::LineBufferProvider;
/// use fixshade::target::Gray8;
///
/// /// Keeps the last band, one line at most, of a 16 × 16 display.
/// struct OneLine([u8; 16]);
/// impl LineBufferProvider for OneLine {
///     type Format = Gray8;
///     fn size(&self) -> (u32, u32) {
///         (16, 16)
///     }
///     fn process_lines(&mut self, lines: Range<u32>, render: impl FnOnce(&mut [u8])) {
///         assert_eq!(lines.len(), 1);
///         render(&mut self.0);
///     }
/// }
/// ```
pub trait LineBufferProvider {
    /// The display's pixel format.
    type Format: PixelFormat;

    /// The display's width and height in pixels: the size the frame was prepared
    /// at (a different size fails with [`crate::render::RenderError::TargetSizeMismatch`]).
    fn size(&self) -> (u32, u32);

    /// Called once per band, top to bottom, with the band's frame rows `lines`. The
    /// provider calls `render` with a buffer of at least `width · lines.len()`
    /// pixels (row-major, width as prepared), which `render` fills completely (the
    /// background, then the triangles), and then sends the rows on. A provider that
    /// does not call `render` skips the band.
    fn process_lines(
        &mut self,
        lines: Range<u32>,
        render: impl FnOnce(&mut [<Self::Format as PixelFormat>::Raw]),
    );
}

/// Renders `frame` band by band into `provider`'s buffers with the span method `S`:
/// [`Frame::bin`] into `mem`, then [`render_binned`].
///
/// Bands are `band_rows` rows tall (the last one may be shorter; 0 counts as 1).
/// `depth` holds at least `width · band_rows` cells (`u16`, or `u32` where 16 bits
/// do not resolve the scene's near/far range: [`DepthFormat`]) and is required when
/// the scene uses the depth test. Each band is cleared to `background` before drawing.
/// `mem` lends the memory for setting each triangle up once per frame
/// ([`BandMemory`]; `BandMemory::new(&mut [], &mut [], &mut [])` lends none, and
/// every band then walks all triangles again). Errors: [`DrawError::Render`] from
/// the frame, or [`DrawError::Buffer`] if the provider's buffer or `depth` is too
/// small; the bands before the error have been sent.
///
/// ```
/// use core::ops::Range;
/// use fixshade::prelude::*;
/// use fixshade::raster::setup::Record;
/// use fixshade::render::BandMemory;
/// # let scene = fixshade::doc_support::scene();
/// struct Spi([u16; 64 * 16]);
/// impl LineBufferProvider for Spi {
///     type Format = Rgb565Be;
///     fn size(&self) -> (u32, u32) {
///         (64, 48)
///     }
///     fn process_lines(&mut self, lines: Range<u32>, render: impl FnOnce(&mut [u16])) {
///         render(&mut self.0[..64 * lines.len()]);
///     }
/// }
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Rgb565Be>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// let (mut records, mut index, mut starts) = ([Record::EMPTY; 4], [0u16; 12], [0u32; 4]);
/// let mem = BandMemory::new(&mut records, &mut index, &mut starts);
/// let mut depth = [0u16; 64 * 16];
/// let st = render_lines::<Gradient, _, _, _>(&frame, 16, mem, Some(&mut depth), 0, &mut Spi([0; 64 * 16])).unwrap();
/// // Each triangle set up once, no band walked all triangles again.
/// assert_eq!((st.triangles, st.rewalked), (1, 0));
/// ```
pub fn render_lines<S, P, L, Sp>(
    frame: &Frame<'_, '_, '_, P, Sp>,
    band_rows: u32,
    mem: BandMemory<'_>,
    depth: Option<&mut [impl DepthFormat]>,
    background: P::Raw,
    provider: &mut L,
) -> Result<Stats, DrawError>
where
    S: SpanMethod,
    P: PixelFormat,
    L: LineBufferProvider<Format = P>,
    Sp: Specular,
{
    let mut binned = frame.bin(band_rows, mem)?;
    render_binned::<S, P, L, Sp>(&mut binned, depth, background, provider)
}

/// The band loop: renders every band of `binned` into `provider`'s buffers, top to
/// bottom, with the span method `S` ([`Binned::draw_band_resuming`]: the edge walks
/// go on from band to band when the memory lent walks). The statistics count
/// each triangle once when the frame was binned, and once per band when the bands
/// re-walk (then [`Stats::rewalked`] counts the bands). See [`render_lines`].
///
/// A frame binned once can be sent twice (say, to two displays):
///
/// ```
/// use core::ops::Range;
/// use fixshade::present::linebuf::render_binned;
/// use fixshade::prelude::*;
/// use fixshade::raster::setup::Record;
/// use fixshade::render::BandMemory;
/// # let scene = fixshade::doc_support::scene();
/// struct Lines(u32);
/// impl LineBufferProvider for Lines {
///     type Format = Rgb565Be;
///     fn size(&self) -> (u32, u32) {
///         (64, 48)
///     }
///     fn process_lines(&mut self, lines: Range<u32>, render: impl FnOnce(&mut [u16])) {
///         let mut band = [0u16; 64 * 8];
///         render(&mut band[..64 * lines.len()]);
///         self.0 += 1;
///     }
/// }
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Rgb565Be>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// let (mut records, mut index, mut starts) = ([Record::EMPTY; 4], [0u16; 12], [0u32; 7]);
/// let mut binned = frame.bin(8, BandMemory::new(&mut records, &mut index, &mut starts)).unwrap();
/// let mut depth = [0u16; 64 * 8];
/// let (mut a, mut b) = (Lines(0), Lines(0));
/// render_binned::<Gradient, _, _, _>(&mut binned, Some(&mut depth), 0, &mut a).unwrap();
/// render_binned::<Gradient, _, _, _>(&mut binned, Some(&mut depth), 0, &mut b).unwrap();
/// assert_eq!((a.0, b.0), (6, 6)); // six bands of 8 rows each
/// ```
pub fn render_binned<S, P, L, Sp>(
    binned: &mut Binned<'_, '_, '_, '_, '_, P, Sp>,
    depth: Option<&mut [impl DepthFormat]>,
    background: P::Raw,
    provider: &mut L,
) -> Result<Stats, DrawError>
where
    S: SpanMethod,
    P: PixelFormat,
    L: LineBufferProvider<Format = P>,
    Sp: Specular,
{
    let mut total = binned.stats();
    total += render_bands(
        binned.band_rows(),
        depth,
        background,
        provider,
        |band, strip| {
            binned
                .draw_band_resuming::<S, _>(band, strip)
                .map_err(DrawError::from)
        },
    )?;
    Ok(total)
}

/// The band loop itself, for any way of drawing a band: for each band of
/// `band_rows` rows (0 counts as 1), top to bottom, asks `provider` for its buffer,
/// makes it a [`Strip`] of the band's rows (depth cells in `depth`, as
/// [`render_lines`] takes them), clears it to `background` and calls
/// `draw(band, strip)`; returns the statistics `draw` returned, summed, or the
/// first error (`draw`'s, or [`DrawError::Buffer`] for a buffer too small).
/// [`render_binned`] draws each band from a binned frame; a caller with its own
/// choice of draw (a run-time table of span methods, say) passes it here.
///
/// ```
/// use core::ops::Range;
/// use fixshade::present::linebuf::render_bands;
/// use fixshade::prelude::*;
/// # let scene = fixshade::doc_support::scene();
/// struct Lines([u16; 64 * 16]);
/// impl LineBufferProvider for Lines {
///     type Format = Rgb565Le;
///     fn size(&self) -> (u32, u32) {
///         (64, 48)
///     }
///     fn process_lines(&mut self, lines: Range<u32>, render: impl FnOnce(&mut [u16])) {
///         render(&mut self.0[..64 * lines.len()]);
///     }
/// }
/// let mut cache = [XfVertex::default(); 3];
/// let frame = Frame::<Rgb565Le>::prepare(&scene, 64, 48, &mut cache).unwrap();
/// let mut depth = [0u16; 64 * 16];
/// // Every band walks the triangle list again with `Classic`.
/// let st = render_bands(16, Some(&mut depth), 0, &mut Lines([0; 64 * 16]), |_, strip| {
///     frame.draw::<Classic, _>(strip).map_err(DrawError::from)
/// })
/// .unwrap();
/// assert_eq!(st.triangles, 3); // one triangle, walked by each of three bands
/// ```
pub fn render_bands<P, L, C, E>(
    band_rows: u32,
    mut depth: Option<&mut [C]>,
    background: P::Raw,
    provider: &mut L,
    mut draw: impl FnMut(u32, &mut Strip<'_, P, C>) -> Result<Stats, E>,
) -> Result<Stats, E>
where
    P: PixelFormat,
    L: LineBufferProvider<Format = P>,
    C: DepthFormat,
    E: From<DrawError>,
{
    let (w, h) = provider.size();
    if w == 0 || h == 0 {
        return Err(DrawError::Buffer(TargetError::BadSize).into());
    }
    let band_rows = band_rows.max(1);
    let mut total = Stats::default();
    for (band, y0) in (0..h).step_by(band_rows as usize).enumerate() {
        let rows = y0..(y0 + band_rows).min(h);
        let mut result = Ok(Stats::default());
        let depth = depth.as_deref_mut();
        provider.process_lines(rows.clone(), |buf| {
            result = Strip::with_depth_format(buf, depth, w, h, rows.start, rows.len() as u32)
                .map_err(|e| DrawError::from(e).into())
                .and_then(|mut strip| {
                    strip.clear(background);
                    draw(band as u32, &mut strip)
                });
        });
        total += result?;
    }
    Ok(total)
}
