//! Host images: 8-bit RGB pixels with a coverage mask, PNG in and out.

use crate::desc::FormatName;
use std::path::Path;

/// An image as the host handles it: 8-bit RGB per pixel (formats with fewer bits are
/// expanded by [`expand`]), plus which pixels some triangle covered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major pixels, top row first.
    pub pixels: Vec<[u8; 3]>,
    /// Row-major coverage: true where a triangle wrote the pixel.
    pub covered: Vec<bool>,
    /// The background colour of uncovered pixels.
    pub background: [u8; 3],
}

/// Channel maxima of a format: the largest integer each output channel holds.
pub fn channel_max(format: FormatName) -> [u32; 3] {
    match format {
        FormatName::Rgb565Le | FormatName::Rgb565Be => [31, 63, 31],
        FormatName::Rgb888 | FormatName::Gray8 => [255, 255, 255],
    }
}

/// Expands channel integers of `format` (each `0..=channel_max`) to 8 bits, rounding
/// to nearest: `v8 = (v * 255 + max / 2) / max`. Grey formats repeat their one channel.
pub fn expand(format: FormatName, c: [u32; 3]) -> [u8; 3] {
    let m = channel_max(format);
    let e = |v: u32, max: u32| ((v.min(max) * 255 + max / 2) / max) as u8;
    [e(c[0], m[0]), e(c[1], m[1]), e(c[2], m[2])]
}

impl Image {
    /// A `width` x `height` image filled with `background`, nothing covered.
    pub fn new(width: u32, height: u32, background: [u8; 3]) -> Image {
        let n = width as usize * height as usize;
        Image {
            width,
            height,
            pixels: vec![background; n],
            covered: vec![false; n],
            background,
        }
    }

    /// Number of covered pixels.
    pub fn covered_count(&self) -> usize {
        self.covered.iter().filter(|c| **c).count()
    }

    /// Writes the image as an 8-bit RGB PNG. The background colour is stored in a
    /// `fixshade:background` text chunk and the coverage mask in a
    /// `fixshade:coverage` chunk (run lengths), so `compare` can read both back.
    pub fn write_png(&self, path: &Path) -> Result<(), String> {
        let file = std::fs::File::create(path)
            .map_err(|e| format!("cannot create {}: {e}", path.display()))?;
        let w = std::io::BufWriter::new(file);
        let mut enc = png::Encoder::new(w, self.width, self.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let bg = self.background;
        let _ = enc.add_text_chunk(
            "fixshade:background".into(),
            format!("{} {} {}", bg[0], bg[1], bg[2]),
        );
        let _ = enc.add_text_chunk("fixshade:coverage".into(), encode_runs(&self.covered));
        let mut writer = enc
            .write_header()
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        let data: Vec<u8> = self.pixels.iter().flat_map(|p| p.iter().copied()).collect();
        writer
            .write_image_data(&data)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        writer
            .finish()
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    }

    /// Reads a PNG (8-bit RGB or RGBA, or grey). Coverage comes from the
    /// `fixshade:coverage` chunk when present; otherwise every pixel that differs
    /// from the background (the `fixshade:background` chunk, or the top-left pixel)
    /// counts as covered.
    pub fn read_png(path: &Path) -> Result<Image, String> {
        let file = std::fs::File::open(path)
            .map_err(|e| format!("cannot open {}: {e}", path.display()))?;
        let mut dec = png::Decoder::new(std::io::BufReader::new(file));
        dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = dec
            .read_info()
            .map_err(|e| format!("{} is not a readable PNG: {e}", path.display()))?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| format!("{} is too large to read", path.display()))?;
        let mut buf = vec![0u8; size];
        let info = reader
            .next_frame(&mut buf)
            .map_err(|e| format!("{} is not a readable PNG: {e}", path.display()))?;
        let (w, h) = (info.width, info.height);
        let n = w as usize * h as usize;
        let stride = info.line_size;
        let channels = info.color_type.samples();
        let mut pixels = Vec::with_capacity(n);
        for y in 0..h as usize {
            let row = &buf[y * stride..y * stride + w as usize * channels];
            for px in row.chunks_exact(channels) {
                pixels.push(match channels {
                    1 | 2 => [px[0], px[0], px[0]],
                    _ => [px[0], px[1], px[2]],
                });
            }
        }
        let mut background = pixels.first().copied().unwrap_or([0; 3]);
        let mut covered = None;
        for t in &reader.info().uncompressed_latin1_text {
            if t.keyword == "fixshade:background" {
                let v: Vec<u8> = t.text.split(' ').filter_map(|s| s.parse().ok()).collect();
                if v.len() == 3 {
                    background = [v[0], v[1], v[2]];
                }
            } else if t.keyword == "fixshade:coverage" {
                covered = decode_runs(&t.text, n);
            }
        }
        let covered = covered.unwrap_or_else(|| pixels.iter().map(|p| *p != background).collect());
        Ok(Image {
            width: w,
            height: h,
            pixels,
            covered,
            background,
        })
    }
}

/// Run-length text of a boolean mask: alternating run lengths, starting with a run
/// of `false`.
fn encode_runs(mask: &[bool]) -> String {
    let mut out = Vec::new();
    let mut cur = false;
    let mut run = 0usize;
    for &m in mask {
        if m == cur {
            run += 1;
        } else {
            out.push(run.to_string());
            cur = m;
            run = 1;
        }
    }
    out.push(run.to_string());
    out.join(" ")
}

fn decode_runs(text: &str, n: usize) -> Option<Vec<bool>> {
    let mut mask = Vec::with_capacity(n);
    let mut cur = false;
    for tok in text.split_ascii_whitespace() {
        let run: usize = tok.parse().ok()?;
        if mask.len() + run > n {
            return None;
        }
        mask.extend(std::iter::repeat_n(cur, run));
        cur = !cur;
    }
    (mask.len() == n).then_some(mask)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expand_rounds_to_nearest() {
        assert_eq!(expand(FormatName::Rgb565Le, [31, 63, 0]), [255, 255, 0]);
        assert_eq!(expand(FormatName::Rgb565Le, [16, 32, 1]), [132, 130, 8]);
        assert_eq!(expand(FormatName::Rgb888, [7, 8, 9]), [7, 8, 9]);
    }

    #[test]
    fn png_round_trip_keeps_pixels_coverage_and_background() {
        let mut img = Image::new(5, 3, [1, 2, 3]);
        img.pixels[7] = [200, 100, 50];
        img.covered[7] = true;
        img.covered[8] = true; // covered but background-coloured
        let dir = std::env::temp_dir().join(format!("fixshade-img-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("rt.png");
        img.write_png(&path).unwrap();
        let back = Image::read_png(&path).unwrap();
        assert_eq!(back, img);
    }

    #[test]
    fn runs_round_trip() {
        let m = vec![true, true, false, true, false, false];
        assert_eq!(decode_runs(&encode_runs(&m), 6), Some(m));
        assert_eq!(decode_runs("1 2", 6), None);
    }
}
