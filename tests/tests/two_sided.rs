//! Two-sided lighting (`two_sided = true`, OpenGL's `GL_LIGHT_MODEL_TWO_SIDE`):
//! with the eye inside a closed sphere every face in view is a back face, lit with
//! its negated normal and the back material; against the f64 reference, which has
//! the same semantics. Without it the inside is lit from behind and stays dark.

use fixshade_sim::image::compare::compare;
use fixshade_sim::image::Image;
use fixshade_sim::render::{self, reference};
use fixshade_sim::scene::desc::Named;
use fixshade_sim::scene::load::{load, read_scene, LoadedScene};
use fixshade_sim::scene::names::{FormatName, ShadingName};
use fixshade_tests::catalogue;

/// The catalogue's two-sided inside-sphere scene in 8-bit channels, with
/// `two_sided` and the shading as given.
fn inside(two_sided: bool, shading: ShadingName) -> LoadedScene {
    let path = catalogue::path("scenes/inside-sphere-two-sided.toml");
    let (mut desc, dir) = read_scene(&path.display().to_string()).unwrap();
    desc.format = FormatName::RGB888;
    desc.two_sided = two_sided;
    desc.shading = shading;
    load("inside-sphere-two-sided", &desc, &dir).unwrap()
}

fn core(ls: &LoadedScene) -> Image {
    render::render(ls, None).unwrap().image
}

/// Mean of the channels over the image.
fn mean(img: &Image) -> f64 {
    let sum: u64 = img.pixels.iter().flatten().map(|&c| c as u64).sum();
    sum as f64 / (3 * img.pixels.len()) as f64
}

/// The inside of the sphere, two-sided, against the f64 reference of the same
/// shading (the Phong reference for Phong and quadratic shading): every pixel
/// covered as the reference covers it, NMSE within the catalogue's 1e-5
/// (measured: Gouraud and Phong 2.6e-7, flat 0, quadratic 9.2e-6).
#[test]
fn inside_of_a_sphere_is_lit_two_sided_as_the_reference() {
    for (shading, bound) in [
        (ShadingName::GOURAUD, 1e-5),
        (ShadingName::FLAT, 1e-5),
        (ShadingName::PHONG, 1e-5),
        (ShadingName::PHONG_EVEN_ODD, 1e-5),
        (ShadingName::QUADRATIC, 1e-5),
    ] {
        let ls = inside(true, shading);
        let img = core(&ls);
        let want = reference::matching_reference(&ls);
        let c = compare(&want, &img).unwrap();
        eprintln!("{}: NMSE {:.3e}", shading.name(), c.nmse);
        assert_eq!(c.coverage_mismatch, 0, "{}", shading.name());
        assert!(img.covered.iter().all(|&c| c), "{}", shading.name());
        assert!(c.nmse <= bound, "{}: NMSE {}", shading.name(), c.nmse);
    }
}

/// The same with perspective-correct colours (Gouraud) and normals and positions
/// (Phong), against the perspective-correct reference.
#[test]
fn inside_of_a_sphere_two_sided_perspective_correct() {
    for shading in [ShadingName::GOURAUD, ShadingName::PHONG] {
        let mut ls = inside(true, shading);
        ls.desc.perspective_correct = true;
        let img = core(&ls);
        let c = compare(&reference::matching_reference(&ls), &img).unwrap();
        eprintln!(
            "{} perspective-correct: NMSE {:.3e}",
            shading.name(),
            c.nmse
        );
        assert_eq!(c.coverage_mismatch, 0, "{}", shading.name());
        assert!(c.nmse <= 1e-5, "{}: NMSE {}", shading.name(), c.nmse);
    }
}

/// Without two-sided lighting the inside faces are lit with their outward
/// normals, away from the light inside: ambient only, far darker than two-sided,
/// and far from the two-sided reference.
#[test]
fn inside_of_a_sphere_is_dark_one_sided() {
    for shading in [ShadingName::GOURAUD, ShadingName::PHONG] {
        let lit = core(&inside(true, shading));
        let dark = core(&inside(false, shading));
        let want = reference::matching_reference(&inside(true, shading));
        let c = compare(&want, &dark).unwrap();
        eprintln!(
            "{}: one-sided NMSE {:.3e} against two-sided, mean {:.1} against {:.1}",
            shading.name(),
            c.nmse,
            mean(&dark),
            mean(&lit)
        );
        assert!(c.nmse > 0.5, "{}: {}", shading.name(), c.nmse);
        assert!(4.0 * mean(&dark) < mean(&lit), "{}", shading.name());
        // The one-sided reference agrees that it is dark.
        let one = reference::matching_reference(&inside(false, shading));
        assert!(compare(&one, &dark).unwrap().nmse <= 1e-5);
    }
}

/// With back faces culled no back face is drawn: two-sided lighting (forced on,
/// past the effect rule that would switch it off) draws the bytes of one-sided
/// lighting, in every shading that supports it.
#[test]
fn two_sided_with_culling_draws_the_one_sided_bytes() {
    for name in ["sphere", "teapot", "robot"] {
        for shading in [
            ShadingName::GOURAUD,
            ShadingName::FLAT,
            ShadingName::PHONG,
            ShadingName::QUADRATIC,
        ] {
            let (mut desc, dir) = read_scene(name).unwrap();
            desc.shading = shading;
            let one = render::render(&load(name, &desc, &dir).unwrap(), None).unwrap();
            desc.two_sided = true;
            let two = render::render(&load(name, &desc, &dir).unwrap(), None).unwrap();
            assert!(desc.cull_back);
            assert_eq!(one.bytes, two.bytes, "{name} {}", shading.name());
        }
    }
}

/// Adaptive shading does not support two-sided lighting: a clear error, no
/// pixels.
#[test]
fn adaptive_two_sided_is_a_clear_error() {
    let err = render::render(&inside(true, ShadingName::ADAPTIVE), None)
        .err()
        .unwrap();
    assert!(
        err.contains("two-sided lighting is not supported with adaptive shading"),
        "{err}"
    );
}
