//! Image comparison by normalized mean squared error (seed formula (3.1)).
//!
//! ```text
//!          Σ (ΔR² + ΔG² + ΔB²)
//! NMSE = -----------------------
//!          Σ (R₁² + G₁² + B₁²)
//! ```
//!
//! summed over all pixels, with image 1 the reference and the channels taken as 8-bit
//! integers. The sums are exact (integers); only the final quotient is a float. An
//! all-black reference has a zero denominator: NMSE is then 0 if the test image is
//! all black too, else infinite.
//!
//! The [`Verdict`] buckets NMSE into four grades; the comparison also reports the
//! largest per-channel difference and how many pixels differ in coverage.

use crate::image::Image;
use std::fmt;

/// How different two images look, graded by NMSE.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Verdict {
    /// NMSE <= 1e-4.
    Indistinguishable,
    /// 1e-4 < NMSE <= 2.5e-4.
    Minor,
    /// 2.5e-4 < NMSE <= 1e-3.
    Noticeable,
    /// NMSE > 1e-3 (also infinite or NaN NMSE).
    Significant,
}

impl Verdict {
    /// Upper NMSE bound (inclusive) of [`Verdict::Indistinguishable`].
    pub const INDISTINGUISHABLE_MAX: f64 = 1e-4;
    /// Upper NMSE bound (inclusive) of [`Verdict::Minor`].
    pub const MINOR_MAX: f64 = 2.5e-4;
    /// Upper NMSE bound (inclusive) of [`Verdict::Noticeable`].
    pub const NOTICEABLE_MAX: f64 = 1e-3;

    /// The verdict for an NMSE value: `<= 1e-4` indistinguishable, `<= 2.5e-4` minor,
    /// `<= 1e-3` noticeable, anything above (or NaN) significant.
    pub fn from_nmse(nmse: f64) -> Verdict {
        if nmse <= Self::INDISTINGUISHABLE_MAX {
            Verdict::Indistinguishable
        } else if nmse <= Self::MINOR_MAX {
            Verdict::Minor
        } else if nmse <= Self::NOTICEABLE_MAX {
            Verdict::Noticeable
        } else {
            Verdict::Significant
        }
    }

    /// Lower-case name: `indistinguishable`, `minor`, `noticeable`, `significant`.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Indistinguishable => "indistinguishable",
            Verdict::Minor => "minor",
            Verdict::Noticeable => "noticeable",
            Verdict::Significant => "significant",
        }
    }
}

impl fmt::Display for Verdict {
    /// Writes [`Verdict::as_str`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The result of comparing a test image with a reference image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// Normalized mean squared error; 0 for identical images, infinite when the
    /// reference is all black and the test image is not.
    pub nmse: f64,
    /// The grade of `nmse`.
    pub verdict: Verdict,
    /// Largest absolute difference of one 8-bit channel over all pixels.
    pub max_channel_error: u8,
    /// Number of pixels covered in one image and not in the other.
    pub coverage_mismatch: usize,
    /// Number of pixels compared (width x height).
    pub pixels: usize,
}

/// Compares `test` against `reference`. The images must have the same size, else
/// the error is `size mismatch: reference is 320x240, test is 640x480`; an image
/// whose pixel or coverage arrays do not match its size is an error too.
pub fn compare(reference: &Image, test: &Image) -> Result<Comparison, String> {
    if (reference.width, reference.height) != (test.width, test.height) {
        return Err(format!(
            "size mismatch: reference is {}x{}, test is {}x{}",
            reference.width, reference.height, test.width, test.height
        ));
    }
    let n = reference.width as usize * reference.height as usize;
    for (what, img) in [("reference", reference), ("test", test)] {
        if img.pixels.len() != n || img.covered.len() != n {
            return Err(format!(
                "{what} image is inconsistent: {}x{} but {} pixels and {} coverage flags",
                img.width,
                img.height,
                img.pixels.len(),
                img.covered.len()
            ));
        }
    }

    let mut num: u64 = 0;
    let mut den: u64 = 0;
    let mut max_err: u8 = 0;
    for (r, t) in reference.pixels.iter().zip(&test.pixels) {
        for (&a, &b) in r.iter().zip(t) {
            let d = a.abs_diff(b);
            max_err = max_err.max(d);
            num += u64::from(d) * u64::from(d);
            den += u64::from(a) * u64::from(a);
        }
    }
    let nmse = if den == 0 {
        if num == 0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        num as f64 / den as f64
    };
    let coverage_mismatch = reference
        .covered
        .iter()
        .zip(&test.covered)
        .filter(|(a, b)| a != b)
        .count();
    Ok(Comparison {
        nmse,
        verdict: Verdict::from_nmse(nmse),
        max_channel_error: max_err,
        coverage_mismatch,
        pixels: n,
    })
}

/// The JSON form of a [`Comparison`], fields in this order.
#[derive(serde::Serialize)]
struct JsonComparison {
    nmse: Option<f64>,
    verdict: &'static str,
    max_channel_error: u8,
    coverage_mismatch: usize,
}

/// serde_json formatter writing one line with a space after `:` and `,`.
struct SpacedFormatter;

impl serde_json::ser::Formatter for SpacedFormatter {
    fn begin_object_key<W: ?Sized + std::io::Write>(
        &mut self,
        writer: &mut W,
        first: bool,
    ) -> std::io::Result<()> {
        if first {
            Ok(())
        } else {
            writer.write_all(b", ")
        }
    }

    fn begin_object_value<W: ?Sized + std::io::Write>(
        &mut self,
        writer: &mut W,
    ) -> std::io::Result<()> {
        writer.write_all(b": ")
    }

    fn begin_array_value<W: ?Sized + std::io::Write>(
        &mut self,
        writer: &mut W,
        first: bool,
    ) -> std::io::Result<()> {
        if first {
            Ok(())
        } else {
            writer.write_all(b", ")
        }
    }
}

impl Comparison {
    /// Three lines of text (each ending in a newline):
    ///
    /// ```text
    /// NMSE 1.234e-6 indistinguishable
    /// max channel error 3
    /// coverage mismatch 0
    /// ```
    ///
    /// NMSE is written with `{:.3e}` (`0.000e0` for identical images, `inf` when
    /// the reference is black and the test image is not).
    pub fn to_text(&self) -> String {
        format!(
            "NMSE {:.3e} {}\nmax channel error {}\ncoverage mismatch {}\n",
            self.nmse, self.verdict, self.max_channel_error, self.coverage_mismatch
        )
    }

    /// One JSON object on one line:
    /// `{"nmse": 1.234e-6, "verdict": "indistinguishable", "max_channel_error": 3,
    /// "coverage_mismatch": 0}`. NMSE is written in full precision; an infinite NMSE
    /// is `null` (its verdict is `significant`).
    pub fn to_json(&self) -> String {
        let value = JsonComparison {
            nmse: self.nmse.is_finite().then_some(self.nmse),
            verdict: self.verdict.as_str(),
            max_channel_error: self.max_channel_error,
            coverage_mismatch: self.coverage_mismatch,
        };
        let mut out = Vec::new();
        let mut ser = serde_json::Serializer::with_formatter(&mut out, SpacedFormatter);
        match serde::Serialize::serialize(&value, &mut ser) {
            Ok(()) => String::from_utf8(out).unwrap_or_default(),
            // Serializing this plain struct into memory cannot fail; keep a fallback
            // rather than a panic anyway.
            Err(e) => format!("{{\"error\": \"{e}\"}}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(pixels: &[[u8; 3]], covered: &[bool]) -> Image {
        Image {
            width: pixels.len() as u32,
            height: 1,
            pixels: pixels.to_vec(),
            covered: covered.to_vec(),
            background: [0; 3],
        }
    }

    #[test]
    fn compare_identical_images_are_indistinguishable() {
        let mut a = Image::new(8, 4, [16, 20, 32]);
        a.pixels[5] = [200, 100, 50];
        a.covered[5] = true;
        let c = compare(&a, &a.clone()).unwrap();
        assert_eq!(c.nmse, 0.0);
        assert_eq!(c.verdict, Verdict::Indistinguishable);
        assert_eq!(c.max_channel_error, 0);
        assert_eq!(c.coverage_mismatch, 0);
        assert_eq!(c.pixels, 32);
        assert_eq!(
            c.to_text(),
            "NMSE 0.000e0 indistinguishable\nmax channel error 0\ncoverage mismatch 0\n"
        );
        assert_eq!(
            c.to_json(),
            r#"{"nmse": 0.0, "verdict": "indistinguishable", "max_channel_error": 0, "coverage_mismatch": 0}"#
        );
    }

    #[test]
    fn compare_hand_computed_two_pixels() {
        // Δ² = 2² + 0 + 3² + 0 + 1² + 0 = 14; Σ ref² = 100 + 400 + 900 + 0 + 0 + 1600 = 3000.
        let r = image(&[[10, 20, 30], [0, 0, 40]], &[true, false]);
        let t = image(&[[12, 20, 27], [0, 1, 40]], &[true, true]);
        let c = compare(&r, &t).unwrap();
        assert_eq!(c.nmse, 14.0 / 3000.0);
        assert_eq!(c.verdict, Verdict::Significant);
        assert_eq!(c.max_channel_error, 3);
        assert_eq!(c.coverage_mismatch, 1);
        assert_eq!(c.pixels, 2);
        assert_eq!(
            c.to_text(),
            "NMSE 4.667e-3 significant\nmax channel error 3\ncoverage mismatch 1\n"
        );
        assert_eq!(
            c.to_json(),
            r#"{"nmse": 0.004666666666666667, "verdict": "significant", "max_channel_error": 3, "coverage_mismatch": 1}"#
        );
        let back: serde_json::Value = serde_json::from_str(&c.to_json()).unwrap();
        assert_eq!(back["nmse"].as_f64(), Some(14.0 / 3000.0));
    }

    #[test]
    fn compare_extreme_difference_and_max_error() {
        let r = image(&[[255, 255, 255]], &[true]);
        let t = image(&[[0, 255, 255]], &[true]);
        let c = compare(&r, &t).unwrap();
        assert_eq!(c.nmse, 1.0 / 3.0);
        assert_eq!(c.max_channel_error, 255);
    }

    #[test]
    fn compare_black_reference() {
        let black = image(&[[0, 0, 0], [0, 0, 0]], &[false, false]);
        let c = compare(&black, &black).unwrap();
        assert_eq!(c.nmse, 0.0);
        assert_eq!(c.verdict, Verdict::Indistinguishable);

        let t = image(&[[0, 0, 0], [0, 0, 1]], &[false, true]);
        let c = compare(&black, &t).unwrap();
        assert!(c.nmse.is_infinite());
        assert_eq!(c.verdict, Verdict::Significant);
        assert_eq!(c.to_text().lines().next(), Some("NMSE inf significant"));
        assert_eq!(
            c.to_json(),
            r#"{"nmse": null, "verdict": "significant", "max_channel_error": 1, "coverage_mismatch": 1}"#
        );
    }

    #[test]
    fn compare_verdict_thresholds() {
        assert_eq!(Verdict::from_nmse(0.0), Verdict::Indistinguishable);
        assert_eq!(Verdict::from_nmse(1e-4), Verdict::Indistinguishable);
        assert_eq!(Verdict::from_nmse(1.0000001e-4), Verdict::Minor);
        assert_eq!(Verdict::from_nmse(2.5e-4), Verdict::Minor);
        assert_eq!(Verdict::from_nmse(2.5000001e-4), Verdict::Noticeable);
        assert_eq!(Verdict::from_nmse(1e-3), Verdict::Noticeable);
        assert_eq!(Verdict::from_nmse(1.0000001e-3), Verdict::Significant);
        assert_eq!(Verdict::from_nmse(f64::INFINITY), Verdict::Significant);
        assert_eq!(Verdict::from_nmse(f64::NAN), Verdict::Significant);
        for (v, s) in [
            (Verdict::Indistinguishable, "indistinguishable"),
            (Verdict::Minor, "minor"),
            (Verdict::Noticeable, "noticeable"),
            (Verdict::Significant, "significant"),
        ] {
            assert_eq!(v.as_str(), s);
            assert_eq!(v.to_string(), s);
        }
    }

    #[test]
    fn compare_verdict_of_exact_boundary_images() {
        // Reference: 100 pixels of [100, 0, 0] → Σ ref² = 1_000_000. One channel off
        // by 10 gives 100 / 1e6 = 1e-4 exactly: still indistinguishable.
        let r = Image {
            width: 10,
            height: 10,
            pixels: vec![[100, 0, 0]; 100],
            covered: vec![true; 100],
            background: [0; 3],
        };
        let mut t = r.clone();
        t.pixels[0] = [110, 0, 0];
        let c = compare(&r, &t).unwrap();
        assert_eq!(c.nmse, 1e-4);
        assert_eq!(c.verdict, Verdict::Indistinguishable);
        t.pixels[1] = [100, 0, 1];
        let c = compare(&r, &t).unwrap();
        assert_eq!(c.nmse, 101.0 / 1e6);
        assert_eq!(c.verdict, Verdict::Minor);
        assert_eq!(c.max_channel_error, 10);
    }

    #[test]
    fn compare_size_mismatch() {
        let a = Image::new(320, 240, [0; 3]);
        let b = Image::new(640, 480, [0; 3]);
        assert_eq!(
            compare(&a, &b).unwrap_err(),
            "size mismatch: reference is 320x240, test is 640x480"
        );
        let mut bad = Image::new(2, 2, [0; 3]);
        bad.pixels.pop();
        assert!(compare(&bad, &Image::new(2, 2, [0; 3])).is_err());
    }
}
