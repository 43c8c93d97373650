//! Targets and pixel formats: where spans end up.
//!
//! A [`Target`] hands the rasterizer one row at a time: the colour row and, if it has
//! one, the depth row, whose cells are a [`DepthFormat`] (`u16` or `u32`). [`Framebuffer`] borrows a whole frame; [`Strip`] borrows
//! the rows `[y0, y0 + h)` of a taller frame so a display without a framebuffer can
//! be fed band by band. Rendering a frame as strips gives the same bytes as
//! rendering it whole (the rasterizer's integer state at any row does not depend on
//! where it started; see `raster`).
//!
//! Pixel formats are types ([`Rgb565Le`], [`Rgb565Be`], [`Rgb888`], [`Gray8`]); the
//! interpolated channels arrive already scaled to the format's channel range.
//!
//! ```
//! use fixshade::target::{Framebuffer, PixelFormat, Rgb565Be, Target};
//! let mut color = [0u16; 4 * 3];
//! let mut depth = [0xFFFFu16; 4 * 3];
//! let fb = Framebuffer::<Rgb565Be>::new(&mut color, Some(&mut depth), 4, 3).unwrap();
//! assert_eq!((fb.width(), fb.frame_height(), fb.rows()), (4, 3, 0..3));
//! // Big-endian bytes in memory whatever the CPU: red is F8 00.
//! assert_eq!(Rgb565Be::pack(31, 0, 0).to_ne_bytes(), [0xF8, 0x00]);
//! ```

use core::ops::Range;

/// A depth buffer cell: `u16` (16 bits, half the memory) or `u32` (32 bits).
///
/// The rasterizer interpolates depth in Q16.16 (`floor(d · 65534 · 2¹⁶)` for `d` in
/// [0, 1], near = 0); a `u16` cell keeps its integer part, a `u32` cell all 32 bits.
/// A pixel is drawn when its cell value is strictly below the stored one, and
/// [`DepthFormat::FAR`] is above every value a triangle can have.
///
/// How many bits a scene needs follows from its near/far ratio. With a perspective
/// camera the depth is `d = (1/n − 1/z)/(1/n − 1/f)`, so one step of a `b`-bit
/// buffer separates surfaces at eye distance `z` that lie
/// `Δz ≈ z² · (1/n − 1/f) / 2ᵇ ≈ z²/(n · 2ᵇ)` apart. At `z = f` a 16-bit buffer
/// resolves `f²/(n · 65536)`: for near 0.1 and far 10 that is 0.015 (1.5 ‰ of the
/// far distance), enough for most models; for near 10⁻⁴ it is 15 units and
/// surfaces fight. Sixteen bits suffice while `f/n ≲ 2¹⁶ · Δz/f` for the smallest gap
/// `Δz` the scene must resolve. A `u32` buffer keeps the interpolated depth's 16
/// fraction bits as well, at twice the memory. Those bits are as exact as the
/// pipeline makes them: the vertex stage's depth is within 2⁻¹⁰ of a 16-bit step,
/// and the triangle setup's increments keep a triangle's depth within 2¹⁴ units
/// (a quarter of a 16-bit step) at worst, far less on small triangles; so 32-bit
/// cells resolve at least 4 times and typically about 2¹⁰ times finer than 16-bit
/// ones (the sphere with culling off at near 10⁻⁴: NMSE against the f64 reference
/// 2.3·10⁻³ with 16 bits, 2.8·10⁻⁶ with 32; `accuracy::closed_model_at_a_tiny_near_plane_*`).
///
/// ```
/// use fixshade::target::DepthFormat;
/// // Depth 9.5 in Q16.16: a u16 cell keeps 9, a u32 cell the whole value.
/// let z = (9 << 16) | (1 << 15);
/// assert_eq!(u16::from_depth(z), 9);
/// assert_eq!(u32::from_depth(z), 9 << 16 | 1 << 15);
/// assert!(u16::from_depth(65534 << 16) < u16::FAR && u32::from_depth(-1) == u32::FAR);
/// ```
pub trait DepthFormat: Copy + Ord + core::fmt::Debug + 'static {
    /// The value a cleared buffer holds: farther than any drawn pixel.
    const FAR: Self;
    /// Bits per cell.
    const BITS: u32;
    /// The cell value of a Q16.16 depth (bias included; wrapping `i32`, read as
    /// `u32`).
    fn from_depth(z: i32) -> Self;
    /// The row as `u16` cells when `Self` is `u16` (the ARMv7E-M paired-pixel loops
    /// test two 16-bit depths per instruction); `None` otherwise.
    fn as_u16(row: &mut [Self]) -> Option<&mut [u16]>;
    /// The depth test of one pixel: stores the cell of `z` and returns true when it
    /// is strictly below the stored value (a tie keeps the first writer).
    ///
    /// ```
    /// use fixshade::target::DepthFormat;
    /// let mut d = u32::FAR;
    /// assert!(d.write_if_nearer(5 << 16) && d == 5 << 16);
    /// assert!(!d.write_if_nearer(5 << 16)); // a tie is not nearer
    /// ```
    #[inline(always)]
    fn write_if_nearer(&mut self, z: i32) -> bool {
        let n = Self::from_depth(z);
        if n < *self {
            *self = n;
            true
        } else {
            false
        }
    }
}

impl DepthFormat for u16 {
    const FAR: u16 = 0xFFFF;
    const BITS: u32 = 16;
    #[inline(always)]
    fn from_depth(z: i32) -> u16 {
        ((z as u32) >> 16) as u16
    }
    #[inline(always)]
    fn as_u16(row: &mut [u16]) -> Option<&mut [u16]> {
        Some(row)
    }
}

impl DepthFormat for u32 {
    // The largest depth is 65534·2¹⁶ + 65535 < u32::MAX.
    const FAR: u32 = u32::MAX;
    const BITS: u32 = 32;
    #[inline(always)]
    fn from_depth(z: i32) -> u32 {
        z as u32
    }
    #[inline(always)]
    fn as_u16(_: &mut [u32]) -> Option<&mut [u16]> {
        None
    }
}

/// A pixel format: how channel integers become stored pixels.
///
/// ```
/// use fixshade::target::{Gray8, PixelFormat, Rgb565Le, Rgb888};
/// // Channel integers in, stored pixel out, and back.
/// let p = Rgb565Le::pack(31, 63, 0);
/// assert_eq!(Rgb565Le::unpack(p), [31, 63, 0]);
/// assert_eq!((Rgb565Le::MAX, Rgb565Le::BYTES, Rgb565Le::NAME), ([31, 63, 31], 2, "rgb565le"));
/// assert_eq!(Rgb888::bytes(Rgb888::pack(1, 2, 3)), [1, 2, 3]);
/// assert!(Gray8::GRAY);
/// ```
pub trait PixelFormat {
    /// One stored pixel.
    type Raw: Copy + Default + PartialEq + core::fmt::Debug;
    /// Largest integer of each channel (R, G, B); grey formats use the first only.
    const MAX: [u32; 3];
    /// True for one-channel formats (only channel 0 is interpolated).
    const GRAY: bool = false;
    /// Bytes per stored pixel.
    const BYTES: usize;
    /// Name used by the CLI and scene files.
    const NAME: &'static str;
    /// Packs channel integers (each `0..=MAX[i]`) into a pixel.
    fn pack(r: u32, g: u32, b: u32) -> Self::Raw;
    /// Channel integers of a stored pixel (the inverse of `pack`).
    fn unpack(p: Self::Raw) -> [u32; 3];
    /// True if [`PixelFormat::store`] is a plain assignment, so pixel loops may write
    /// unconditionally with a select. Formats that override `store` set it to false.
    const PLAIN_STORE: bool = true;
    /// Stores `v` at `dst`. Formats that count writes (tests) override this, and set
    /// `PLAIN_STORE` to false.
    #[inline(always)]
    fn store(dst: &mut Self::Raw, v: Self::Raw) {
        *dst = v;
    }
    /// Appends the pixel's bytes, in memory order, to `out` (host output).
    fn bytes(p: Self::Raw) -> [u8; 3];
    /// The row as `u16` pixels when the stored pixel is a `u16` (the 5-6-5 formats:
    /// the Cortex-M span loops in assembly write them); `None` otherwise. A format
    /// that returns `Some` promises that `pack(r, g, b)` is `r << 11 | g << 5 | b`
    /// stored little-endian, or byte-swapped (told apart by the bytes of
    /// `pack(0, 0, 1)`): those loops write that value, not `pack`'s.
    ///
    /// ```
    /// use fixshade::target::{PixelFormat, Rgb565Be, Rgb888};
    /// assert!(Rgb565Be::as_u16(&mut [0u16; 4]).is_some());
    /// assert!(Rgb888::as_u16(&mut [[0u8; 3]; 4]).is_none());
    /// ```
    #[inline(always)]
    fn as_u16(row: &mut [Self::Raw]) -> Option<&mut [u16]> {
        let _ = row;
        None
    }
}

/// True for the formats the Cortex-M span loops draw (the paired loops of
/// [`crate::raster::dsp`] and Gradient's packed loop in assembly): three channels of 5, 6 and 5 bits
/// (the packed lanes of 21 + 22 + 21 bits, red at bit 43, green at 21, blue at 0),
/// a two-byte stored pixel (so `pack` is a bijection and `pack(unpack(p)) == p`) and
/// a plain store (so a kept pixel may be written back).
///
/// ```
/// use fixshade::target::is_565;
/// use fixshade::target::{Gray8, Rgb565Be, Rgb565Le, Rgb888};
/// assert!(is_565::<Rgb565Le>() && is_565::<Rgb565Be>());
/// assert!(!is_565::<Rgb888>() && !is_565::<Gray8>());
/// ```
pub const fn is_565<P: PixelFormat>() -> bool {
    !P::GRAY
        && P::MAX[0] == 31
        && P::MAX[1] == 63
        && P::MAX[2] == 31
        && P::BYTES == 2
        && core::mem::size_of::<P::Raw>() == 2
        && P::PLAIN_STORE
}

/// RGB 5-6-5 whose bytes in memory are little-endian on any CPU.
///
/// ```
/// use fixshade::target::{PixelFormat, Rgb565Le};
/// // Little-endian bytes in memory whatever the CPU: pure red is 00 F8.
/// assert_eq!(Rgb565Le::pack(31, 0, 0).to_ne_bytes(), [0x00, 0xF8]);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Rgb565Le;
/// RGB 5-6-5 whose bytes in memory are big-endian on any CPU (the order ST7789 and
/// ILI9341 controllers take over SPI).
///
/// ```
/// use fixshade::target::{PixelFormat, Rgb565Be};
/// // The bytes go to an SPI display in memory order: pure green is 07 E0.
/// assert_eq!(Rgb565Be::pack(0, 63, 0).to_ne_bytes(), [0x07, 0xE0]);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Rgb565Be;
/// RGB 8-8-8, three bytes R, G, B.
///
/// ```
/// use fixshade::target::{PixelFormat, Rgb888};
/// assert_eq!(Rgb888::pack(255, 128, 0), [255, 128, 0]);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Rgb888;
/// 8-bit grey: `(77 R + 150 G + 29 B) / 256` of the lit colour.
///
/// ```
/// use fixshade::target::{to_channels, Gray8, PixelFormat};
/// // White lit colour (1.0 in Q16.16 per channel) is grey 255 in Q.16 channel units.
/// assert_eq!(to_channels::<Gray8>([1 << 16; 3])[0] >> 16, 255);
/// assert_eq!(Gray8::unpack(Gray8::pack(200, 0, 0)), [200, 200, 200]);
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Gray8;

/// RGB 5-6-5 in a `u16` whose memory bytes are in the order `$to`/`$from` give.
macro_rules! rgb565_format {
    ($ty:ty, $name:literal, $to:ident, $from:ident) => {
        impl PixelFormat for $ty {
            type Raw = u16;
            const MAX: [u32; 3] = [31, 63, 31];
            const BYTES: usize = 2;
            const NAME: &'static str = $name;
            #[inline(always)]
            fn pack(r: u32, g: u32, b: u32) -> u16 {
                (((r << 11) | (g << 5) | b) as u16).$to()
            }
            fn unpack(p: u16) -> [u32; 3] {
                let v = u16::$from(p) as u32;
                [v >> 11, (v >> 5) & 63, v & 31]
            }
            fn bytes(p: u16) -> [u8; 3] {
                let b = p.to_ne_bytes();
                [b[0], b[1], 0]
            }
            #[inline(always)]
            fn as_u16(row: &mut [u16]) -> Option<&mut [u16]> {
                Some(row)
            }
        }
    };
}

rgb565_format!(Rgb565Le, "rgb565le", to_le, from_le);
rgb565_format!(Rgb565Be, "rgb565be", to_be, from_be);

impl PixelFormat for Rgb888 {
    type Raw = [u8; 3];
    const MAX: [u32; 3] = [255, 255, 255];
    const BYTES: usize = 3;
    const NAME: &'static str = "rgb888";
    #[inline(always)]
    fn pack(r: u32, g: u32, b: u32) -> [u8; 3] {
        [r as u8, g as u8, b as u8]
    }
    fn unpack(p: [u8; 3]) -> [u32; 3] {
        [p[0] as u32, p[1] as u32, p[2] as u32]
    }
    fn bytes(p: [u8; 3]) -> [u8; 3] {
        p
    }
}

impl PixelFormat for Gray8 {
    type Raw = u8;
    const MAX: [u32; 3] = [255, 255, 255];
    const GRAY: bool = true;
    const BYTES: usize = 1;
    const NAME: &'static str = "gray8";
    #[inline(always)]
    fn pack(g: u32, _: u32, _: u32) -> u8 {
        g as u8
    }
    fn unpack(p: u8) -> [u32; 3] {
        [p as u32; 3]
    }
    fn bytes(p: u8) -> [u8; 3] {
        [p, 0, 0]
    }
}

/// Errors building a target.
///
/// ```
/// use fixshade::target::{Framebuffer, Rgb888, TargetError};
/// let mut color = [[0u8; 3]; 8];
/// let err = Framebuffer::<Rgb888>::new(&mut color, None, 4, 4).err();
/// assert_eq!(err, Some(TargetError::ColorBufferTooSmall));
/// let mut one = [[0u8; 3]; 1];
/// assert_eq!(Framebuffer::<Rgb888>::new(&mut one, None, 0, 1).err(), Some(TargetError::BadSize));
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum TargetError {
    /// Width or height is zero or above 4096.
    BadSize,
    /// The colour buffer holds fewer pixels than the declared size.
    ColorBufferTooSmall,
    /// The depth buffer holds fewer pixels than the colour buffer needs.
    DepthBufferTooSmall,
    /// The strip's rows do not lie inside the frame.
    StripOutsideFrame,
}

impl core::fmt::Display for TargetError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            TargetError::BadSize => "width and height must be 1..=4096",
            TargetError::ColorBufferTooSmall => "colour buffer is smaller than width x height",
            TargetError::DepthBufferTooSmall => "depth buffer is smaller than width x height",
            TargetError::StripOutsideFrame => "strip rows lie outside the frame",
        })
    }
}

/// Largest frame side in pixels (the 12-bit screen coordinate range).
pub const MAX_SIDE: u32 = 4096;

/// Where the rasterizer writes: rows of a frame of `width` × `frame_height` pixels,
/// of which the target holds `rows()`.
///
/// ```
/// use fixshade::target::{Framebuffer, Gray8, Target};
/// let mut color = [0u8; 6];
/// let mut fb = Framebuffer::<Gray8>::new(&mut color, None, 3, 2).unwrap();
/// assert!(!fb.has_depth());
/// let (row, depth) = fb.row(1);
/// row[2] = 9;
/// assert!(depth.is_empty());
/// assert_eq!(fb.color(), &[0, 0, 0, 0, 0, 9]);
/// ```
pub trait Target<P: PixelFormat> {
    /// Frame width in pixels.
    fn width(&self) -> u32;
    /// Height of the whole frame (for the projection's aspect and viewport).
    fn frame_height(&self) -> u32;
    /// The frame rows this target holds.
    fn rows(&self) -> Range<i32>;
    /// The depth buffer's cell.
    type Depth: DepthFormat;
    /// True if the target has a depth buffer.
    fn has_depth(&self) -> bool;
    /// Colour row `y` (frame coordinates, inside `rows()`) and its depth row (empty
    /// if there is no depth buffer).
    fn row(&mut self, y: i32) -> (&mut [P::Raw], &mut [Self::Depth]);
    /// All of `rows()` at once, if the target stores them one after another
    /// (`width()` cells a row, the first row first): the colour cells and the
    /// depth cells (empty if there is no depth buffer). The rasterizer's row loops
    /// on the Cortex-M cores then step from row to row instead of asking
    /// [`Target::row`] for each. The default is `None`: every row through
    /// [`Target::row`].
    ///
    /// ```
    /// use fixshade::target::{Rgb565Le, Strip, Target};
    /// let (mut c, mut d) = ([0u16; 12], [0u16; 12]);
    /// let mut s = Strip::<Rgb565Le>::new(&mut c, Some(&mut d), 3, 8, 4, 4).unwrap();
    /// let (color, depth) = s.rows_contiguous().unwrap();
    /// assert_eq!((color.len(), depth.len()), (12, 12)); // rows 4..8, 3 cells each
    /// ```
    #[allow(clippy::type_complexity)]
    fn rows_contiguous(&mut self) -> Option<(&mut [P::Raw], &mut [Self::Depth])> {
        None
    }
}

/// A whole frame in caller-owned buffers.
///
/// ```
/// use fixshade::target::{Framebuffer, PixelFormat, Rgb565Le, Target};
/// let (w, h) = (8, 4);
/// let mut color = [0u16; 8 * 4];
/// let mut depth = [0u16; 8 * 4];
/// let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), w, h).unwrap();
/// fb.clear(Rgb565Le::pack(0, 0, 31));
/// assert!(fb.color().iter().all(|&p| Rgb565Le::unpack(p) == [0, 0, 31]));
/// assert_eq!(fb.row(3).1[0], 0xFFFF); // cleared to the far value
/// ```
pub struct Framebuffer<'a, P: PixelFormat, D: DepthFormat = u16> {
    strip: Strip<'a, P, D>,
}

impl<'a, P: PixelFormat> Framebuffer<'a, P> {
    /// Borrows `color` (at least `width·height` pixels, row-major) and an optional
    /// `u16` depth buffer of the same size ([`Framebuffer::with_depth_format`] takes
    /// other cells).
    pub fn new(
        color: &'a mut [P::Raw],
        depth: Option<&'a mut [u16]>,
        width: u32,
        height: u32,
    ) -> Result<Self, TargetError> {
        Self::with_depth_format(color, depth, width, height)
    }
}

impl<'a, P: PixelFormat, D: DepthFormat> Framebuffer<'a, P, D> {
    /// [`Framebuffer::new`] with depth cells of any [`DepthFormat`] (`u16` or
    /// `u32`).
    ///
    /// ```
    /// use fixshade::target::{DepthFormat, Framebuffer, Gray8, Target};
    /// let (mut c, mut d) = ([0u8; 4], [0u32; 4]);
    /// let mut fb = Framebuffer::<Gray8, u32>::with_depth_format(&mut c, Some(&mut d), 2, 2).unwrap();
    /// fb.clear(0);
    /// assert_eq!(fb.row(1).1, &[u32::FAR; 2]);
    /// ```
    pub fn with_depth_format(
        color: &'a mut [P::Raw],
        depth: Option<&'a mut [D]>,
        width: u32,
        height: u32,
    ) -> Result<Self, TargetError> {
        Ok(Framebuffer {
            strip: Strip::with_depth_format(color, depth, width, height, 0, height)?,
        })
    }

    /// Fills colour with `c` and depth with the far value [`DepthFormat::FAR`].
    pub fn clear(&mut self, c: P::Raw) {
        self.strip.clear(c)
    }

    /// The colour and depth buffers (row-major, `width · height` pixels), mutably:
    /// for drawing the frame's rows through other targets, e.g. bands as
    /// [`Strip`]s over its rows.
    ///
    /// ```
    /// use fixshade::target::{Framebuffer, Gray8, Strip, Target};
    /// let (mut c, mut d) = ([0u8; 4 * 4], [0u16; 4 * 4]);
    /// let mut fb = Framebuffer::<Gray8>::new(&mut c, Some(&mut d), 4, 4).unwrap();
    /// let (color, depth) = fb.buffers();
    /// // Rows 2..4 of the frame as a strip of its own.
    /// let strip = Strip::<Gray8>::new(&mut color[8..], depth.map(|d| &mut d[8..]), 4, 4, 2, 2).unwrap();
    /// assert_eq!(strip.rows(), 2..4);
    /// ```
    pub fn buffers(&mut self) -> (&mut [P::Raw], Option<&mut [D]>) {
        let n = self.strip.width as usize * self.strip.h as usize;
        (
            &mut self.strip.color[..n],
            self.strip.depth.as_deref_mut().map(|d| &mut d[..n]),
        )
    }

    /// The colour buffer.
    pub fn color(&self) -> &[P::Raw] {
        self.strip.color()
    }
}

impl<P: PixelFormat, D: DepthFormat> Target<P> for Framebuffer<'_, P, D> {
    type Depth = D;
    fn width(&self) -> u32 {
        self.strip.width()
    }
    fn frame_height(&self) -> u32 {
        self.strip.frame_height()
    }
    fn rows(&self) -> Range<i32> {
        self.strip.rows()
    }
    fn has_depth(&self) -> bool {
        self.strip.has_depth()
    }
    #[inline]
    fn row(&mut self, y: i32) -> (&mut [P::Raw], &mut [D]) {
        self.strip.row(y)
    }
    #[inline]
    #[allow(clippy::type_complexity)]
    fn rows_contiguous(&mut self) -> Option<(&mut [P::Raw], &mut [D])> {
        self.strip.rows_contiguous()
    }
}

/// Rows `[y0, y0 + h)` of a `width` × `frame_height` frame, in caller-owned buffers of
/// `width·h` pixels.
///
/// ```
/// use fixshade::target::{Rgb565Le, Strip, Target};
/// // A 320×240 frame fed to a display 16 rows at a time from one 10 KiB buffer.
/// let mut color = [0u16; 320 * 16];
/// let mut strip = Strip::<Rgb565Le>::new(&mut color, None, 320, 240, 0, 16).unwrap();
/// for band in 0..15 {
///     strip.set_y0(band * 16).unwrap();
///     strip.clear(0);
///     // ... draw the frame into `strip`, then send `strip.color()` to the display
///     assert_eq!(strip.rows(), band as i32 * 16..band as i32 * 16 + 16);
/// }
/// assert!(strip.set_y0(230).is_err()); // rows 230..246 are not all in the frame
/// ```
pub struct Strip<'a, P: PixelFormat, D: DepthFormat = u16> {
    color: &'a mut [P::Raw],
    depth: Option<&'a mut [D]>,
    width: u32,
    frame_height: u32,
    y0: u32,
    h: u32,
}

impl<'a, P: PixelFormat> Strip<'a, P> {
    /// Borrows buffers for rows `[y0, y0 + h)` of a frame `width` × `frame_height`:
    /// `color` and an optional `u16` depth buffer, each of at least `width·h`
    /// pixels ([`Strip::with_depth_format`] takes other depth cells).
    pub fn new(
        color: &'a mut [P::Raw],
        depth: Option<&'a mut [u16]>,
        width: u32,
        frame_height: u32,
        y0: u32,
        h: u32,
    ) -> Result<Self, TargetError> {
        Self::with_depth_format(color, depth, width, frame_height, y0, h)
    }
}

impl<'a, P: PixelFormat, D: DepthFormat> Strip<'a, P, D> {
    /// [`Strip::new`] with depth cells of any [`DepthFormat`] (`u16` or `u32`).
    ///
    /// ```
    /// use fixshade::target::{Gray8, Strip, Target};
    /// // Rows 4..6 of a 3 × 8 frame, with 32-bit depth.
    /// let (mut c, mut d) = ([0u8; 6], [0u32; 6]);
    /// let s = Strip::<Gray8, u32>::with_depth_format(&mut c, Some(&mut d), 3, 8, 4, 2).unwrap();
    /// assert_eq!(s.rows(), 4..6);
    /// ```
    pub fn with_depth_format(
        color: &'a mut [P::Raw],
        depth: Option<&'a mut [D]>,
        width: u32,
        frame_height: u32,
        y0: u32,
        h: u32,
    ) -> Result<Self, TargetError> {
        if width == 0 || width > MAX_SIDE || frame_height == 0 || frame_height > MAX_SIDE {
            return Err(TargetError::BadSize);
        }
        if h == 0 || y0.checked_add(h).is_none_or(|e| e > frame_height) {
            return Err(TargetError::StripOutsideFrame);
        }
        let n = width as usize * h as usize;
        if color.len() < n {
            return Err(TargetError::ColorBufferTooSmall);
        }
        if depth.as_ref().is_some_and(|d| d.len() < n) {
            return Err(TargetError::DepthBufferTooSmall);
        }
        Ok(Strip {
            color,
            depth,
            width,
            frame_height,
            y0,
            h,
        })
    }

    /// Moves the strip to start at frame row `y0` (same height, same buffers).
    pub fn set_y0(&mut self, y0: u32) -> Result<(), TargetError> {
        if y0.checked_add(self.h).is_none_or(|e| e > self.frame_height) {
            return Err(TargetError::StripOutsideFrame);
        }
        self.y0 = y0;
        Ok(())
    }

    /// Fills colour with `c` and depth with [`DepthFormat::FAR`].
    pub fn clear(&mut self, c: P::Raw) {
        let n = self.width as usize * self.h as usize;
        self.color[..n].fill(c);
        if let Some(d) = self.depth.as_deref_mut() {
            d[..n].fill(D::FAR);
        }
    }

    /// The strip's colour pixels, row-major.
    pub fn color(&self) -> &[P::Raw] {
        &self.color[..self.width as usize * self.h as usize]
    }
}

impl<P: PixelFormat, D: DepthFormat> Target<P> for Strip<'_, P, D> {
    type Depth = D;
    fn width(&self) -> u32 {
        self.width
    }
    fn frame_height(&self) -> u32 {
        self.frame_height
    }
    fn rows(&self) -> Range<i32> {
        self.y0 as i32..(self.y0 + self.h) as i32
    }
    fn has_depth(&self) -> bool {
        self.depth.is_some()
    }
    #[inline]
    fn row(&mut self, y: i32) -> (&mut [P::Raw], &mut [D]) {
        let w = self.width as usize;
        // The rasterizer only asks for rows inside `rows()`; clamp anyway so a
        // wrong row can never index outside the buffers.
        let r = (y - self.y0 as i32).clamp(0, self.h as i32 - 1) as usize;
        let color = &mut self.color[r * w..(r + 1) * w];
        let depth = match self.depth.as_deref_mut() {
            Some(d) => &mut d[r * w..(r + 1) * w],
            None => &mut [],
        };
        (color, depth)
    }
    #[inline]
    #[allow(clippy::type_complexity)]
    fn rows_contiguous(&mut self) -> Option<(&mut [P::Raw], &mut [D])> {
        // The constructor checked that both buffers hold `width·h` cells.
        let n = self.width as usize * self.h as usize;
        let color = self.color.get_mut(..n)?;
        let depth = match self.depth.as_deref_mut() {
            Some(d) => d.get_mut(..n)?,
            None => &mut [],
        };
        Some((color, depth))
    }
}

/// Converts a lit Q16.16 colour (0..=1) to the format's channel units in Q.16.
/// `c·MAX` ≤ 2¹⁶·255 < 2²⁴; for grey, `(77r + 150g + 29b)·255` < 2³²·… is taken in i64.
///
/// ```
/// use fixshade::target::{to_channels, Rgb565Le};
/// // Half red (0.5 in Q16.16) in 5-6-5 units: 15.5 in Q.16.
/// assert_eq!(to_channels::<Rgb565Le>([1 << 15, 0, 0]), [31 << 15, 0, 0]);
/// ```
#[inline]
pub fn to_channels<P: PixelFormat>(c: [i32; 3]) -> [i32; 3] {
    if P::GRAY {
        let y = 77 * c[0] as i64 + 150 * c[1] as i64 + 29 * c[2] as i64;
        [((y * 255) >> 8) as i32, 0, 0]
    } else {
        [
            c[0] * P::MAX[0] as i32,
            c[1] * P::MAX[1] as i32,
            c[2] * P::MAX[2] as i32,
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_checked() {
        let mut c = [0u16; 10];
        assert_eq!(
            Framebuffer::<Rgb565Le>::new(&mut c, None, 4, 3).err(),
            Some(TargetError::ColorBufferTooSmall)
        );
        let mut c = [0u16; 12];
        let mut d = [0u16; 11];
        assert_eq!(
            Framebuffer::<Rgb565Le>::new(&mut c, Some(&mut d), 4, 3).err(),
            Some(TargetError::DepthBufferTooSmall)
        );
        assert_eq!(
            Framebuffer::<Rgb565Le>::new(&mut c, None, 0, 3).err(),
            Some(TargetError::BadSize)
        );
        assert_eq!(
            Strip::<Rgb565Le>::new(&mut c, None, 4, 3, 2, 2).err(),
            Some(TargetError::StripOutsideFrame)
        );
    }

    #[test]
    fn rgb565_byte_orders() {
        let p = Rgb565Le::pack(31, 0, 1);
        assert_eq!(p.to_ne_bytes(), [0x01, 0xF8]);
        assert_eq!(Rgb565Le::unpack(p), [31, 0, 1]);
        let p = Rgb565Be::pack(31, 0, 1);
        assert_eq!(p.to_ne_bytes(), [0xF8, 0x01]);
        assert_eq!(Rgb565Be::unpack(p), [31, 0, 1]);
    }
}
