//! Golden images: the fixed-point render of each figure, and of the catalogue
//! scenes of users' OBJ models and two-sided lighting ([`CATALOGUE_SCENES`]), must equal the committed
//! `tests/golden/NAME.png` exactly, pixels and coverage (the coverage mask travels
//! in the PNG's `fixshade:coverage` chunk).
//!
//! Regenerate after an intended change of the output with
//! `FIXSHADE_BLESS=1 cargo test -p fixshade-tests --release --test golden`, look at
//! the pictures, and commit them.

use fixshade_sim::image::Image;
use fixshade_sim::render;
use fixshade_sim::scene::load::{load_arg, LoadedScene};
use fixshade_tests::*;

/// Scenes of the hard-case catalogue (`tests/catalogue/scenes/NAME.toml`) with
/// golden images: OBJ `vn` normals (flat faces), recomputed normals (smooth), MTL
/// materials, two-sided lighting of the inside of a sphere, and a closed model in
/// 32-bit depth cells at near = 1e-4.
const CATALOGUE_SCENES: [&str; 5] = [
    "obj-cube-vn",
    "obj-cube-no-vn",
    "obj-mtl",
    "inside-sphere-two-sided",
    "tiny-near-depth32",
];

/// Every scene with a golden image: the figures, then [`CATALOGUE_SCENES`].
fn golden_scenes() -> Vec<(&'static str, LoadedScene)> {
    let figures = FIGURES.iter().map(|name| (*name, load_arg(name).unwrap()));
    let catalogue = CATALOGUE_SCENES.iter().map(|name| {
        let path = catalogue::path(&format!("scenes/{name}.toml"));
        (*name, load_arg(&path.display().to_string()).unwrap())
    });
    figures.chain(catalogue).collect()
}

const REGENERATE: &str =
    "if the change is intended, regenerate with `FIXSHADE_BLESS=1 cargo test -p fixshade-tests --release --test golden` and review the PNGs";

fn bless() -> bool {
    std::env::var("FIXSHADE_BLESS").is_ok_and(|v| v == "1")
}

/// Differences between a render and its golden image, as one message.
fn differences(name: &str, golden: &Image, got: &Image) -> Option<String> {
    if (golden.width, golden.height) != (got.width, got.height) {
        return Some(format!(
            "{name}: size {}x{}, golden image is {}x{}",
            got.width, got.height, golden.width, golden.height
        ));
    }
    let pixels = golden
        .pixels
        .iter()
        .zip(&got.pixels)
        .filter(|(a, b)| a != b)
        .count();
    let coverage = golden
        .covered
        .iter()
        .zip(&got.covered)
        .filter(|(a, b)| a != b)
        .count();
    let first = (0..golden.pixels.len())
        .find(|&i| golden.pixels[i] != got.pixels[i] || golden.covered[i] != got.covered[i]);
    first.map(|i| {
        let w = golden.width as usize;
        format!(
            "{name}: {pixels} pixels differ in colour and {coverage} in coverage from the golden image; \
             first at ({}, {}): golden {:?} covered {}, got {:?} covered {}",
            i % w,
            i / w,
            golden.pixels[i],
            golden.covered[i],
            got.pixels[i],
            got.covered[i]
        )
    })
}

#[test]
fn figures_match_golden_images() {
    let dir = package_path("golden");
    let mut failures = Vec::new();
    for (name, ls) in golden_scenes() {
        let got = render::render(&ls, None).unwrap().image;
        let path = dir.join(format!("{name}.png"));
        if bless() {
            std::fs::create_dir_all(&dir).unwrap();
            got.write_png(&path).unwrap();
            println!("wrote {}", path.display());
            continue;
        }
        let golden = Image::read_png(&path).unwrap_or_else(|e| {
            panic!("{e}; generate the golden images with FIXSHADE_BLESS=1 (see {REGENERATE})")
        });
        if let Some(msg) = differences(name, &golden, &got) {
            failures.push(msg);
        } else {
            println!("{name}: {} pixels identical", golden.pixels.len());
        }
    }
    assert!(failures.is_empty(), "{}\n{REGENERATE}", failures.join("\n"));
}

/// The comparison is not a tautology: one changed pixel, or one pixel's coverage,
/// is reported.
#[test]
fn golden_comparison_detects_one_pixel() {
    let ls = load_arg("sphere").unwrap();
    let img = render::render(&ls, None).unwrap().image;
    // A PNG round trip keeps everything.
    let dir = temp_dir("golden");
    let path = dir.join("sphere.png");
    img.write_png(&path).unwrap();
    let back = Image::read_png(&path).unwrap();
    assert_eq!(differences("sphere", &back, &img), None);
    let mut one = img.clone();
    let i = one.covered.iter().position(|c| *c).unwrap();
    one.pixels[i][1] ^= 1;
    let msg = differences("sphere", &back, &one).unwrap();
    assert!(
        msg.contains("1 pixels differ in colour and 0 in coverage"),
        "{msg}"
    );
    let mut cov = img.clone();
    cov.covered[0] = !cov.covered[0];
    let msg = differences("sphere", &back, &cov).unwrap();
    assert!(
        msg.contains("0 pixels differ in colour and 1 in coverage"),
        "{msg}"
    );
    let _ = std::fs::remove_dir_all(dir);
}
