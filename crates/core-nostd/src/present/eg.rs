//! embedded-graphics integration (feature `embedded-graphics`): a rendered model is
//! a [`Drawable`], so it draws into any [`DrawTarget`] with colour
//! [`Rgb565`](egc::pixelcolor::Rgb565), [`Rgb888`](egc::pixelcolor::Rgb888) or
//! [`Gray8`](egc::pixelcolor::Gray8) and composes with text and shapes.
//!
//! The model renders band by band into a small caller-owned scratch strip, exactly
//! as a [`crate::target::Strip`] does, in the [`Covered`] format: the pixel format
//! `P` plus one flag per pixel saying whether the frame wrote it. Each band is then
//! flushed row by row, one [`DrawTarget::fill_contiguous`] call per run of written
//! pixels, so the display receives whole spans (never single pixels) and pixels the
//! model does not cover are left alone. The colours are `P`'s own, channel for
//! channel: an Rgb565 display gets the same 5-6-5 values a
//! [`crate::target::Framebuffer`] of [`Rgb565Le`] or [`Rgb565Be`] would hold.
//!
//! `embedded_graphics::prelude` and [`crate::prelude`] both export an `Angle`; with
//! both glob-imported, name fixshade's explicitly (`use fixshade::fixed::Angle;`).
//!
//! ```
//! use embedded_graphics_core::pixelcolor::{Rgb565, RgbColor};
//! use embedded_graphics_core::prelude::*;
//! use fixshade::present::eg::{CoveredPixel, Model};
//! use fixshade::prelude::*;
//!
//! # struct Display([Rgb565; 64 * 48]);
//! # impl OriginDimensions for Display {
//! #     fn size(&self) -> Size { Size::new(64, 48) }
//! # }
//! # impl DrawTarget for Display {
//! #     type Color = Rgb565;
//! #     type Error = core::convert::Infallible;
//! #     fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, px: I) -> Result<(), Self::Error> {
//! #         for Pixel(p, c) in px {
//! #             if let (Ok(x @ 0..64), Ok(y @ 0..48)) = (usize::try_from(p.x), usize::try_from(p.y)) {
//! #                 self.0[y * 64 + x] = c;
//! #             }
//! #         }
//! #         Ok(())
//! #     }
//! # }
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
//! let mut display = Display([Rgb565::BLUE; 64 * 48]);
//! // Scratch for 8 rows of a 32 x 32 model: 8 x 32 x (4 + 2) bytes.
//! let mut cache = [XfVertex::default(); 3];
//! let mut color = [CoveredPixel::default(); 32 * 8];
//! let mut depth = [0u16; 32 * 8];
//! let model = Model::<Rgb565Le>::prepare(&scene, Size::new(32, 32), &mut cache, &mut color, Some(&mut depth))
//!     .unwrap()
//!     .at(Point::new(16, 8));
//! let stats = model.draw(&mut display).unwrap().unwrap();
//! assert!(stats.pixels > 100);
//! // Outside the model's 32 x 32 box the display is untouched.
//! assert_eq!(display.0[0], Rgb565::BLUE);
//! ```

use core::cell::Cell;
use core::marker::PhantomData;

use egc::draw_target::DrawTarget;
use egc::geometry::{Dimensions, Point, Size};
use egc::pixelcolor::PixelColor;
use egc::primitives::Rectangle;
use egc::Drawable;
use embedded_graphics_core as egc;

use crate::present::linebuf::{render_binned, LineBufferProvider};
use crate::present::DrawError;
use crate::raster::span::{Gradient, SpanMethod};
use crate::render::{BandMemory, Frame, Stats, XfVertex};
use crate::scene::Scene;
use crate::specular::{BlinnExact, Specular};
use crate::target::{Gray8, PixelFormat, Rgb565Be, Rgb565Le, Rgb888, TargetError};

/// A pixel format with an embedded-graphics colour.
///
/// ```
/// use embedded_graphics_core::pixelcolor::{Rgb565, RgbColor};
/// use fixshade::present::eg::EgFormat;
/// use fixshade::target::{PixelFormat, Rgb565Be};
/// assert_eq!(Rgb565Be::to_color(Rgb565Be::pack(31, 0, 0)), Rgb565::RED);
/// ```
pub trait EgFormat: PixelFormat {
    /// The embedded-graphics colour.
    type Color: PixelColor;
    /// The colour of a stored pixel (same channel values).
    fn to_color(p: Self::Raw) -> Self::Color;
}

impl EgFormat for Rgb565Le {
    type Color = egc::pixelcolor::Rgb565;
    #[inline]
    fn to_color(p: u16) -> Self::Color {
        let [r, g, b] = Self::unpack(p);
        // Channels are 0..=31, 0..=63, 0..=31.
        egc::pixelcolor::Rgb565::new(r as u8, g as u8, b as u8)
    }
}

impl EgFormat for Rgb565Be {
    type Color = egc::pixelcolor::Rgb565;
    #[inline]
    fn to_color(p: u16) -> Self::Color {
        let [r, g, b] = Self::unpack(p);
        egc::pixelcolor::Rgb565::new(r as u8, g as u8, b as u8)
    }
}

impl EgFormat for Rgb888 {
    type Color = egc::pixelcolor::Rgb888;
    #[inline]
    fn to_color(p: [u8; 3]) -> Self::Color {
        egc::pixelcolor::Rgb888::new(p[0], p[1], p[2])
    }
}

impl EgFormat for Gray8 {
    type Color = egc::pixelcolor::Gray8;
    #[inline]
    fn to_color(p: u8) -> Self::Color {
        egc::pixelcolor::Gray8::new(p)
    }
}

/// A stored pixel of `P` and whether the frame wrote it.
///
/// ```
/// use fixshade::present::eg::CoveredPixel;
/// let p = CoveredPixel::<u16>::default();
/// assert!(!p.written);
/// ```
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct CoveredPixel<R> {
    /// The pixel, as `P` stores it.
    pub raw: R,
    /// True once the frame has written the pixel.
    pub written: bool,
}

/// The pixel format `P` with a written flag per pixel ([`CoveredPixel`]). Channel
/// ranges are `P`'s, so a frame prepared for `Covered<P>` writes the same values as
/// one prepared for `P`.
///
/// ```
/// use fixshade::present::eg::Covered;
/// use fixshade::target::{PixelFormat, Rgb888};
/// let p = Covered::<Rgb888>::pack(1, 2, 3);
/// assert_eq!((p.raw, p.written), ([1, 2, 3], true));
/// ```
#[derive(Copy, Clone, Debug, Default)]
pub struct Covered<P>(PhantomData<P>);

impl<P: PixelFormat> PixelFormat for Covered<P> {
    type Raw = CoveredPixel<P::Raw>;
    const MAX: [u32; 3] = P::MAX;
    const GRAY: bool = P::GRAY;
    const BYTES: usize = P::BYTES;
    const NAME: &'static str = P::NAME;
    const PLAIN_STORE: bool = P::PLAIN_STORE;
    #[inline(always)]
    fn pack(r: u32, g: u32, b: u32) -> Self::Raw {
        CoveredPixel {
            raw: P::pack(r, g, b),
            written: true,
        }
    }
    fn unpack(p: Self::Raw) -> [u32; 3] {
        P::unpack(p.raw)
    }
    #[inline(always)]
    fn store(dst: &mut Self::Raw, v: Self::Raw) {
        P::store(&mut dst.raw, v.raw);
        dst.written = v.written;
    }
    fn bytes(p: Self::Raw) -> [u8; 3] {
        P::bytes(p.raw)
    }
}

/// The scratch strip, taken out of its cell while a draw runs.
struct Scratch<'a, R> {
    color: &'a mut [CoveredPixel<R>],
    depth: Option<&'a mut [u16]>,
}

/// A prepared frame of a scene, drawable into an embedded-graphics [`DrawTarget`]
/// at an offset, with the span method `S` ([`Gradient`] by default).
///
/// The frame is `size` pixels; rows are rendered in bands as tall as the scratch
/// buffers allow (`color.len() / width`, and the same for `depth`), so 8 rows of
/// scratch for a 240-pixel-wide model cost 240·8·(size of a [`CoveredPixel`] + 2)
/// bytes. The vertex stage runs once, in [`Model::prepare`]; every
/// [`Drawable::draw`] rasterizes again (the same pixels each time).
///
/// [`Drawable::draw`] returns `Ok(Err(_))` when the frame cannot be drawn (a
/// depth-tested scene without a depth buffer) and `Err(_)` with the display's own
/// error.
///
/// See the [module docs](self) for an example.
pub struct Model<'a, P: EgFormat, S = Gradient, Sp: Specular = BlinnExact> {
    frame: Frame<'a, 'a, 'a, Covered<P>, Sp>,
    size: Size,
    origin: Point,
    scratch: Cell<Option<Scratch<'a, P::Raw>>>,
    _span: PhantomData<S>,
}

impl<'a, P: EgFormat> Model<'a, P> {
    /// Runs the vertex stage of `scene` for a `size` frame (exact Blinn specular)
    /// and keeps the scratch buffers. Fails if the frame cannot be prepared
    /// ([`DrawError::Render`]) or the buffers hold less than one row
    /// ([`DrawError::Buffer`]).
    pub fn prepare(
        scene: &'a Scene<'a>,
        size: Size,
        cache: &'a mut [XfVertex],
        color: &'a mut [CoveredPixel<P::Raw>],
        depth: Option<&'a mut [u16]>,
    ) -> Result<Self, DrawError> {
        Self::prepare_with::<BlinnExact>(scene, size, cache, color, depth)
    }

    /// [`Model::prepare`] with the specular model `Sp`.
    pub fn prepare_with<Sp: Specular>(
        scene: &'a Scene<'a>,
        size: Size,
        cache: &'a mut [XfVertex],
        color: &'a mut [CoveredPixel<P::Raw>],
        depth: Option<&'a mut [u16]>,
    ) -> Result<Model<'a, P, Gradient, Sp>, DrawError> {
        let frame = Frame::<Covered<P>>::prepare_with::<Sp>(scene, size.width, size.height, cache)?;
        // The frame checked 1..=4096.
        let w = size.width as usize;
        if color.len() < w {
            return Err(TargetError::ColorBufferTooSmall.into());
        }
        if depth.as_ref().is_some_and(|d| d.len() < w) {
            return Err(TargetError::DepthBufferTooSmall.into());
        }
        Ok(Model {
            frame,
            size,
            origin: Point::zero(),
            scratch: Cell::new(Some(Scratch { color, depth })),
            _span: PhantomData,
        })
    }
}

impl<'a, P: EgFormat, S: SpanMethod, Sp: Specular> Model<'a, P, S, Sp> {
    /// The same model with its top-left corner at `origin` on the display.
    pub fn at(mut self, origin: Point) -> Self {
        self.origin = origin;
        self
    }

    /// The same model drawn with the span method `S2`.
    pub fn span<S2: SpanMethod>(self) -> Model<'a, P, S2, Sp> {
        Model {
            frame: self.frame,
            size: self.size,
            origin: self.origin,
            scratch: self.scratch,
            _span: PhantomData,
        }
    }

    /// Renders every band (the core's band loop, [`render_binned`]; the frame is
    /// not binned, so each band walks the triangles) and flushes it to `target`.
    fn draw_bands<D: DrawTarget<Color = P::Color>>(
        &self,
        s: &mut Scratch<'a, P::Raw>,
        target: &mut D,
    ) -> Result<Result<Stats, DrawError>, D::Error> {
        let (w, h) = (self.size.width, self.size.height);
        let wu = w as usize;
        let mut band = s.color.len() / wu;
        if let Some(d) = s.depth.as_deref() {
            band = band.min(d.len() / wu);
        }
        // At least one row (checked in `prepare`), at most the frame.
        let band = (band as u32).clamp(1, h);
        let mut binned = match self
            .frame
            .bin(band, BandMemory::new(&mut [], &mut [], &mut []))
        {
            Ok(b) => b,
            Err(e) => return Ok(Err(e.into())),
        };
        let mut flush = Flush::<P, D> {
            color: &mut *s.color,
            size: (w, h),
            origin: self.origin,
            target,
            error: None,
        };
        let r = render_binned::<S, Covered<P>, _, Sp>(
            &mut binned,
            s.depth.as_deref_mut(),
            CoveredPixel::default(),
            &mut flush,
        );
        match flush.error {
            Some(e) => Err(e),
            None => Ok(r),
        }
    }
}

/// The band loop's provider for a model: renders each band into the scratch strip,
/// then hands its written pixels to the display ([`flush_row`]), keeping the
/// display's first error.
struct Flush<'b, 'd, P: EgFormat, D: DrawTarget<Color = P::Color>> {
    color: &'b mut [CoveredPixel<P::Raw>],
    size: (u32, u32),
    origin: Point,
    target: &'d mut D,
    error: Option<D::Error>,
}

impl<P: EgFormat, D: DrawTarget<Color = P::Color>> LineBufferProvider for Flush<'_, '_, P, D> {
    type Format = Covered<P>;

    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn process_lines(
        &mut self,
        lines: core::ops::Range<u32>,
        render: impl FnOnce(&mut [CoveredPixel<P::Raw>]),
    ) {
        if self.error.is_some() {
            return;
        }
        let wu = self.size.0 as usize;
        let buf = &mut self.color[..wu * lines.len()];
        render(buf);
        for (r, row) in buf.chunks_exact(wu).enumerate() {
            // lines.start + r < h ≤ 4096; the origin may be anywhere: saturate.
            let y = self
                .origin
                .y
                .saturating_add((lines.start as usize + r) as i32);
            if let Err(e) = flush_row::<P, D>(row, self.origin.x, y, self.target) {
                self.error = Some(e);
                return;
            }
        }
    }
}

/// Hands each run of written pixels of `row` to `fill_contiguous`, at display row
/// `y` with pixel 0 at `x0`.
fn flush_row<P: EgFormat, D: DrawTarget<Color = P::Color>>(
    row: &[CoveredPixel<P::Raw>],
    x0: i32,
    y: i32,
    target: &mut D,
) -> Result<(), D::Error> {
    let mut x = 0;
    while x < row.len() {
        if !row[x].written {
            x += 1;
            continue;
        }
        let start = x;
        while x < row.len() && row[x].written {
            x += 1;
        }
        // Row lengths are ≤ 4096.
        let area = Rectangle::new(
            Point::new(x0.saturating_add(start as i32), y),
            Size::new((x - start) as u32, 1),
        );
        target.fill_contiguous(&area, row[start..x].iter().map(|p| P::to_color(p.raw)))?;
    }
    Ok(())
}

impl<P: EgFormat, S: SpanMethod, Sp: Specular> Drawable for Model<'_, P, S, Sp> {
    type Color = P::Color;
    /// The frame's statistics, summed over the bands, or why it could not be drawn.
    type Output = Result<Stats, DrawError>;

    fn draw<D: DrawTarget<Color = P::Color>>(
        &self,
        target: &mut D,
    ) -> Result<Self::Output, D::Error> {
        // The scratch is always in its cell between draws; `draw` does not re-enter.
        let Some(mut s) = self.scratch.take() else {
            return Ok(Ok(Stats::default()));
        };
        let r = self.draw_bands(&mut s, target);
        self.scratch.set(Some(s));
        r
    }
}

impl<P: EgFormat, S, Sp: Specular> Dimensions for Model<'_, P, S, Sp> {
    /// The frame's rectangle on the display.
    fn bounding_box(&self) -> Rectangle {
        Rectangle::new(self.origin, self.size)
    }
}
