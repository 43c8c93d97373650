//! A chart canvas: an RGB buffer that plotters draws into, labels in the built-in
//! pixel font ([`super::font`]) over it, written as a PNG ([`super::png`]).

use std::path::Path;

use plotters::style::RGBColor;

/// Text drawn over the chart; scale-1 labels get a white box behind them so the
/// markers they overlap do not hide them.
pub struct Label {
    /// Left edge, pixels.
    pub x: i32,
    /// Top edge, pixels.
    pub y: i32,
    /// The text.
    pub text: String,
    /// Font pixel size in image pixels.
    pub scale: i32,
    /// Colour.
    pub color: RGBColor,
}

/// A white RGB canvas of `width` x `height` pixels.
pub struct Canvas {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGB bytes (for `plotters::backend::BitMapBackend::with_buffer`).
    pub buf: Vec<u8>,
}

impl Canvas {
    /// A white canvas.
    pub fn new(width: u32, height: u32) -> Canvas {
        Canvas {
            width,
            height,
            buf: vec![255u8; (width * height * 3) as usize],
        }
    }

    /// Draws `labels` and writes the canvas to `path` as a PNG.
    pub fn finish(mut self, labels: &[Label], path: &Path) -> Result<(), String> {
        self.draw_labels(labels);
        super::png::write_rgb(path, self.width, self.height, &[&self.buf], 1, &[])
    }

    /// Draws `labels` and returns the canvas as PNG bytes.
    pub fn png_bytes(mut self, labels: &[Label]) -> Result<Vec<u8>, String> {
        self.draw_labels(labels);
        super::png::encode_rgb(self.width, self.height, &self.buf)
    }

    fn draw_labels(&mut self, labels: &[Label]) {
        let (w, h) = (self.width, self.height);
        for l in labels {
            if l.scale == 1 {
                let wpx = 6 * l.text.chars().count() as i32;
                for yy in (l.y - 1).max(0)..(l.y + 10).min(h as i32) {
                    for xx in (l.x - 1).max(0)..(l.x + wpx).min(w as i32) {
                        let i = (yy as usize * w as usize + xx as usize) * 3;
                        self.buf[i..i + 3].copy_from_slice(&[255, 255, 255]);
                    }
                }
            }
            super::font::draw_text(&mut self.buf, w, h, l.x, l.y, &l.text, l.scale, l.color);
        }
    }
}

/// A round axis step for a range of `span`: 1, 2 or 5 times a power of ten, about
/// an eighth of the range.
pub fn nice_step(span: f64) -> f64 {
    let raw = span / 8.0;
    let p = 10f64.powf(raw.log10().floor());
    let m = raw / p;
    p * if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    }
}
