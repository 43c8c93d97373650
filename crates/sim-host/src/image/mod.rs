//! Host images: 8-bit RGB pixels with a coverage mask, PNG in and out
//! ([`crate::chart::png`]), and their comparison ([`compare`]).

pub mod compare;

use crate::chart::png;
use std::path::Path;

/// An image as the host handles it: 8-bit RGB per pixel (formats with fewer bits are
/// expanded by `FormatName::expand`), plus which pixels some triangle covered.
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
        let bg = self.background;
        let data: Vec<u8> = self.pixels.iter().flat_map(|p| p.iter().copied()).collect();
        png::write_rgb(
            path,
            self.width,
            self.height,
            &[&data],
            1,
            &[
                (
                    "fixshade:background",
                    format!("{} {} {}", bg[0], bg[1], bg[2]),
                ),
                ("fixshade:coverage", encode_runs(&self.covered)),
            ],
        )
    }

    /// Reads a PNG (8-bit RGB or RGBA, or grey). Coverage comes from the
    /// `fixshade:coverage` chunk when present; otherwise every pixel that differs
    /// from the background (the `fixshade:background` chunk, or the top-left pixel)
    /// counts as covered.
    pub fn read_png(path: &Path) -> Result<Image, String> {
        let d = png::read_rgb(path)?;
        let n = d.pixels.len();
        let mut background = d.pixels.first().copied().unwrap_or([0; 3]);
        let mut covered = None;
        for (keyword, text) in &d.text {
            if keyword == "fixshade:background" {
                let v: Vec<u8> = text.split(' ').filter_map(|s| s.parse().ok()).collect();
                if v.len() == 3 {
                    background = [v[0], v[1], v[2]];
                }
            } else if keyword == "fixshade:coverage" {
                covered = decode_runs(text, n);
            }
        }
        let covered =
            covered.unwrap_or_else(|| d.pixels.iter().map(|p| *p != background).collect());
        Ok(Image {
            width: d.width,
            height: d.height,
            pixels: d.pixels,
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
