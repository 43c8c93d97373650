//! The embedded-graphics adapter (`fixshade::present::eg::Model`) and the line-buffer
//! interface (`fixshade::present::linebuf`) give the same bytes as the native framebuffer
//! render (`fixshade_sim::render::render`, a `Framebuffer` of the whole frame).
//!
//! * Every pixel format, several span methods and all three shadings, on the
//!   figures, through a recording `DrawTarget` pre-filled with the background: the
//!   display, read back as the format's bytes, equals the framebuffer byte for byte.
//!   Scratch strips of 1, 7 and 240 rows.
//! * The adapter hands the display whole runs: only `fill_contiguous` calls, each one
//!   row tall, no pixel written twice, no `draw_iter` call; on the sphere (one convex
//!   silhouette) exactly one call per covered row.
//! * The line-buffer interface with bands of 1, 7, 16 and 240 rows: the bands
//!   concatenated equal the framebuffer, and every row is asked for exactly once.

use core::convert::Infallible;
use core::ops::Range;

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Point, Size};
use embedded_graphics_core::pixelcolor::{GrayColor, PixelColor, RgbColor};
use embedded_graphics_core::primitives::Rectangle;
use embedded_graphics_core::{Drawable, Pixel};
use fixshade::present::eg::{CoveredPixel, EgFormat, Model};
use fixshade::present::linebuf::{render_lines, LineBufferProvider};
use fixshade::raster::span::SpanMethod;
use fixshade::render::{BandMemory, Frame, XfVertex};
use fixshade::target::{Gray8, PixelFormat, Rgb565Be, Rgb565Le, Rgb888};
use fixshade_sim::render;
use fixshade_sim::scene::convert::background_channels;
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::desc::{FormatName, Named, ShadingName, SpanName};
use fixshade_sim::scene::load::{load_arg, LoadedScene};
use fixshade_sim::with_span_method;

/// A format whose display colour converts back to the stored pixel.
trait Back: EgFormat {
    fn from_color(c: Self::Color) -> Self::Raw;
}
impl Back for Rgb565Le {
    fn from_color(c: Self::Color) -> u16 {
        Self::pack(c.r() as u32, c.g() as u32, c.b() as u32)
    }
}
impl Back for Rgb565Be {
    fn from_color(c: Self::Color) -> u16 {
        Self::pack(c.r() as u32, c.g() as u32, c.b() as u32)
    }
}
impl Back for Rgb888 {
    fn from_color(c: Self::Color) -> [u8; 3] {
        [c.r(), c.g(), c.b()]
    }
}
impl Back for Gray8 {
    fn from_color(c: Self::Color) -> u8 {
        c.luma()
    }
}

/// A display that records what it is asked to do.
struct Recorder<C> {
    w: u32,
    h: u32,
    px: Vec<C>,
    /// Times each pixel was written.
    writes: Vec<u32>,
    /// Every `fill_contiguous` area.
    fills: Vec<Rectangle>,
    /// `draw_iter` calls (the per-pixel path).
    iter_calls: usize,
}

impl<C: PixelColor> Recorder<C> {
    fn new(w: u32, h: u32, bg: C) -> Self {
        let n = (w * h) as usize;
        Recorder {
            w,
            h,
            px: vec![bg; n],
            writes: vec![0; n],
            fills: Vec::new(),
            iter_calls: 0,
        }
    }
    fn put(&mut self, p: Point, c: C) {
        assert!(
            p.x >= 0 && p.y >= 0 && (p.x as u32) < self.w && (p.y as u32) < self.h,
            "pixel {p:?} outside the display"
        );
        let i = p.y as usize * self.w as usize + p.x as usize;
        self.px[i] = c;
        self.writes[i] += 1;
    }
}

impl<C: PixelColor> OriginDimensions for Recorder<C> {
    fn size(&self) -> Size {
        Size::new(self.w, self.h)
    }
}

impl<C: PixelColor> DrawTarget for Recorder<C> {
    type Color = C;
    type Error = Infallible;
    fn draw_iter<I: IntoIterator<Item = Pixel<C>>>(&mut self, pixels: I) -> Result<(), Infallible> {
        self.iter_calls += 1;
        for Pixel(p, c) in pixels {
            self.put(p, c);
        }
        Ok(())
    }
    fn fill_contiguous<I: IntoIterator<Item = C>>(
        &mut self,
        area: &Rectangle,
        colors: I,
    ) -> Result<(), Infallible> {
        self.fills.push(*area);
        let mut n = 0;
        let (x0, y0) = (area.top_left.x, area.top_left.y);
        let (w, h) = (area.size.width as i32, area.size.height as i32);
        let points = (y0..y0 + h).flat_map(|y| (x0..x0 + w).map(move |x| Point::new(x, y)));
        for (p, c) in points.zip(colors) {
            self.put(p, c);
            n += 1;
        }
        assert_eq!(
            n,
            area.size.width * area.size.height,
            "colours for {area:?}"
        );
        Ok(())
    }
}

fn to_bytes<P: PixelFormat>(px: &[P::Raw]) -> Vec<u8> {
    px.iter()
        .flat_map(|p| P::bytes(*p).into_iter().take(P::BYTES))
        .collect()
}

fn background<P: PixelFormat>(ls: &LoadedScene) -> P::Raw {
    let c = background_channels(ls.desc.format, ls.desc.background);
    P::pack(c[0], c[1], c[2])
}

/// Renders through the adapter with scratch strips of `rows` rows; the display's
/// pixels as the format's bytes, and the recorder.
fn through_adapter<P: Back, S: SpanMethod>(
    ls: &LoadedScene,
    rows: u32,
) -> (Vec<u8>, Recorder<P::Color>) {
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed).unwrap();
    let (w, h) = (d.width, d.height);
    let bg = background::<P>(ls);
    let mut display = Recorder::new(w, h, P::to_color(bg));
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let n = (w * rows) as usize;
    let mut color = vec![CoveredPixel::default(); n];
    let mut depth = vec![0u16; n];
    let model = Model::<P>::prepare(
        &scene,
        Size::new(w, h),
        &mut cache,
        &mut color,
        d.depth_test.then_some(&mut depth[..]),
    )
    .unwrap()
    .span::<S>();
    let stats = model.draw(&mut display).unwrap().unwrap();
    assert!(stats.pixels > 0);
    let raw: Vec<P::Raw> = display.px.iter().map(|c| P::from_color(*c)).collect();
    (to_bytes::<P>(&raw), display)
}

/// A line-buffer display: keeps the whole frame and checks the band order.
struct Lines<P: PixelFormat> {
    w: u32,
    h: u32,
    band: Vec<P::Raw>,
    frame: Vec<P::Raw>,
    next_row: u32,
}

impl<P: PixelFormat> LineBufferProvider for Lines<P> {
    type Format = P;
    fn size(&self) -> (u32, u32) {
        (self.w, self.h)
    }
    fn process_lines(&mut self, lines: Range<u32>, render: impl FnOnce(&mut [P::Raw])) {
        assert_eq!(lines.start, self.next_row, "bands out of order");
        assert!(lines.end > lines.start && lines.end <= self.h);
        self.next_row = lines.end;
        let n = (self.w * lines.len() as u32) as usize;
        // Poison the band: `render` must fill every pixel.
        self.band[..n].fill(P::pack(P::MAX[0], 0, P::MAX[2]));
        render(&mut self.band[..n]);
        let at = (lines.start * self.w) as usize;
        self.frame[at..at + n].copy_from_slice(&self.band[..n]);
    }
}

/// No band memory: every band walks the triangles again.
fn no_memory() -> BandMemory<'static> {
    BandMemory::new(&mut [], &mut [], &mut [])
}

fn through_lines<P: PixelFormat, S: SpanMethod>(ls: &LoadedScene, band_rows: u32) -> Vec<u8> {
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed).unwrap();
    let (w, h) = (d.width, d.height);
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let frame = Frame::<P>::prepare(&scene, w, h, &mut cache).unwrap();
    let n = (w * band_rows) as usize;
    let mut depth = vec![0u16; n];
    let mut lines = Lines::<P> {
        w,
        h,
        band: vec![P::Raw::default(); n],
        frame: vec![P::Raw::default(); (w * h) as usize],
        next_row: 0,
    };
    let bg = background::<P>(ls);
    let stats = render_lines::<S, P, _, _>(
        &frame,
        band_rows,
        no_memory(),
        Some(&mut depth),
        bg,
        &mut lines,
    )
    .unwrap();
    assert!(stats.pixels > 0);
    assert_eq!(lines.next_row, h, "every row asked for");
    to_bytes::<P>(&lines.frame)
}

fn check_format<P: Back>(ls: &LoadedScene, what: &str) {
    let native = render::render(ls, None).unwrap().bytes;
    let d = &ls.desc;
    for rows in [1, 7, 240] {
        let (bytes, rec) = with_span_method!(d.span, S => through_adapter::<P, S>(ls, rows));
        assert_eq!(bytes.len(), native.len());
        let differ = bytes.iter().zip(&native).filter(|(a, b)| a != b).count();
        assert_eq!(
            differ, 0,
            "{what}, adapter with {rows}-row scratch: {differ} bytes differ"
        );
        assert_eq!(rec.iter_calls, 0, "{what}: per-pixel draw_iter used");
        assert!(rec
            .fills
            .iter()
            .all(|r| r.size.height == 1 && r.size.width >= 1));
        assert!(
            rec.writes.iter().all(|n| *n <= 1),
            "{what}: a pixel was written twice"
        );
        let written: u32 = rec.writes.iter().sum();
        assert!(
            rec.fills.len() * 4 < written as usize,
            "{what}: {} fills for {written} pixels",
            rec.fills.len()
        );
    }
    for band in [1, 7, 16, 240] {
        let bytes = with_span_method!(d.span, S => through_lines::<P, S>(ls, band));
        let differ = bytes.iter().zip(&native).filter(|(a, b)| a != b).count();
        assert_eq!(bytes.len(), native.len());
        assert_eq!(
            differ, 0,
            "{what}, line buffer with {band}-row bands: {differ} bytes differ"
        );
    }
}

fn check(ls: &LoadedScene, what: &str) {
    // Every pixel format of the core's registry.
    macro_rules! by_format {
        ([] $($P:ty),* $(,)?) => {{
            let mut at = 0;
            $(
                if ls.desc.format.index() == at {
                    return check_format::<$P>(ls, what);
                }
                at += 1;
            )*
            unreachable!("format {at}")
        }};
    }
    fixshade::for_each_pixel_format!(by_format)
}

#[test]
fn adapter_and_line_buffer_equal_framebuffer_every_format() {
    let mut ls = load_arg("teapot").unwrap();
    // The teapot scene asks for 32-bit depth cells; the embedded-graphics adapter
    // (`eg::Model`) and this test's line buffer borrow 16-bit ones, so the frame they
    // must equal is the 16-bit one.
    ls.desc.depth_bits = 16;
    for &(format, _) in FormatName::ALL {
        ls.desc.format = format;
        check(&ls, &format!("teapot {format:?}"));
    }
}

#[test]
fn adapter_and_line_buffer_equal_framebuffer_methods_and_shadings() {
    for name in ["sphere", "robot"] {
        let mut ls = load_arg(name).unwrap();
        for span in [
            SpanName::CLASSIC,
            SpanName::named("kway3"),
            SpanName::named("segment8"),
            SpanName::named("sierpinski"),
        ] {
            ls.desc.span = span;
            check(&ls, &format!("{name} {span:?}"));
        }
        ls.desc.span = SpanName::GRADIENT;
        for shading in [ShadingName::FLAT, ShadingName::QUADRATIC] {
            ls.desc.shading = shading;
            check(&ls, &format!("{name} {shading:?}"));
        }
        ls.desc.shading = ShadingName::GOURAUD;
        // Without the depth test (and without a depth buffer): later triangles win.
        ls.desc.depth_test = false;
        ls.desc.cull_back = false;
        check(&ls, &format!("{name} no depth test"));
    }
}

#[test]
fn adapter_fills_one_run_per_row_of_a_convex_silhouette() {
    let ls = load_arg("sphere").unwrap();
    let native = render::render(&ls, None).unwrap();
    let w = ls.desc.width as usize;
    let covered_rows = native
        .image
        .covered
        .chunks(w)
        .filter(|r| r.iter().any(|c| *c))
        .count();
    assert!(covered_rows > 100);
    let (_, rec) = through_adapter::<Rgb565Le, fixshade::raster::span::Gradient>(&ls, 16);
    assert_eq!(rec.fills.len(), covered_rows);
    // And each fill is exactly that row's covered run.
    for r in &rec.fills {
        let y = r.top_left.y as usize;
        let row = &native.image.covered[y * w..(y + 1) * w];
        let first = row.iter().position(|c| *c).unwrap();
        let last = row.iter().rposition(|c| *c).unwrap();
        assert_eq!(
            (r.top_left.x as usize, r.size.width as usize),
            (first, last + 1 - first),
            "row {y}"
        );
    }
}

#[test]
fn adapter_draws_at_an_offset_and_leaves_the_rest() {
    let mut ls = load_arg("sphere").unwrap();
    ls.desc.format = FormatName::RGB888;
    let scene = core_scene(&ls.desc, &ls.fixed).unwrap();
    let (w, h) = (ls.desc.width, ls.desc.height);
    let marker = embedded_graphics_core::pixelcolor::Rgb888::new(1, 2, 3);
    let mut display = Recorder::new(w + 20, h + 10, marker);
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let mut color = vec![CoveredPixel::default(); w as usize * 8];
    let mut depth = vec![0u16; w as usize * 8];
    let model = Model::<Rgb888>::prepare(
        &scene,
        Size::new(w, h),
        &mut cache,
        &mut color,
        Some(&mut depth),
    )
    .unwrap()
    .at(Point::new(20, 10));
    model.draw(&mut display).unwrap().unwrap();
    let native = render::render(&ls, None).unwrap();
    let dw = (w + 20) as usize;
    for y in 0..(h + 10) as usize {
        for x in 0..dw {
            let got = display.px[y * dw + x];
            let inside = x >= 20 && y >= 10;
            let covered = inside && native.image.covered[(y - 10) * w as usize + (x - 20)];
            if covered {
                let want = native.image.pixels[(y - 10) * w as usize + (x - 20)];
                assert_eq!([got.r(), got.g(), got.b()], want, "pixel {x},{y}");
            } else {
                assert_eq!(got, marker, "pixel {x},{y} not covered but written");
            }
        }
    }
    // Drawing again gives the same pixels (the scratch is reused).
    let before = display.px.clone();
    model.draw(&mut display).unwrap().unwrap();
    assert_eq!(display.px, before);
}
