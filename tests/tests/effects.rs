//! Effects (`fixshade_sim::scene::effects`): every derivation rule has a scene that
//! triggers it and the derived frame keeps the pixels of the frame as written;
//! forced settings override the rules; adaptive shading stays within 1e-4 of full
//! Phong on the three figures and reports the triangles that paid; its per-triangle
//! bounds are never below the specular light and the Gouraud error actually found inside
//! a triangle.

use fixshade::effects::NoSpecular;
use fixshade::fixed::Q16_16;
use fixshade::light::{Light, LightKind, LightingSetup, Material};
use fixshade::math::{normalize_to_q30, Mat4};
use fixshade::specular::Specular;
use fixshade_sim::image::compare::compare;
use fixshade_sim::render;
use fixshade_sim::scene::desc::ShadingName;
use fixshade_sim::scene::desc::{Overrides, Source};
use fixshade_sim::scene::effects::{self, Effects, Lighting};
use fixshade_sim::scene::file::parse_scene;
use fixshade_sim::scene::load;
use fixshade_sim::scene::load::LoadedScene;

fn scene(text: &str) -> LoadedScene {
    let d = parse_scene(text, "test.toml").unwrap();
    load::load("test", &d, std::path::Path::new(".")).unwrap()
}

const CAMERA: &str = "[camera]\neye = [0, 0, 4]\n";
const SPHERE: &str = "[[object]]\nmesh = \"sphere\"\nlon = 24\nlat = 16\n";
const SPEC_LIGHT: &str =
    "[[light]]\ntype = \"directional\"\ndirection = [-0.5, 0.6, 0.8]\nspecular = [1, 1, 1]\n";
const SPEC_MATERIAL: &str = "[material]\nspecular = [0.6, 0.6, 0.6]\nshininess = 30\n";

fn derive(ls: &LoadedScene) -> Effects {
    effects::derive(ls).unwrap()
}

/// The derived frame's bytes equal the frame as written, run with every effect
/// on (the exact specular term forced, depth test on).
fn same_pixels_as_written(ls: &LoadedScene) {
    let e = derive(ls);
    let derived = render::render(&effects::apply(ls, &e), None).unwrap();
    let mut full = ls.clone();
    full.desc.effects = Overrides::parse("+specular", Source::CommandLine).unwrap();
    full.desc.depth_test = true;
    if full.desc.lights.is_empty() {
        full.desc.effects = Overrides::default();
    }
    let written = render::render(&full, None).unwrap();
    assert_eq!(derived.bytes, written.bytes, "{}", ls.name);
}

#[test]
fn no_lights_is_unlit_and_flat() {
    let ls = scene(&format!(
        "[render]\nshading = \"phong\"\n[material]\nemission = [0.3, 0.5, 0.1]\n{CAMERA}{SPHERE}"
    ));
    let e = derive(&ls);
    assert_eq!(e.lighting.value, Lighting::Unlit);
    assert!(e.lighting.why.contains("no lights"), "{}", e.lighting.why);
    assert_eq!(e.shading.value, ShadingName::FLAT);
    assert!(e.shading.why.contains("unlit"));
    same_pixels_as_written(&ls);
}

#[test]
fn zero_ks_means_no_specular() {
    let ls = scene(&format!("{CAMERA}{SPEC_LIGHT}{SPHERE}"));
    let e = derive(&ls);
    assert_eq!(e.lighting.value, Lighting::Diffuse);
    assert!(e.lighting.why.contains("k_s = 0"), "{}", e.lighting.why);
    assert!(!render::specular_pipeline(&effects::apply(&ls, &e).desc));
    same_pixels_as_written(&ls);
}

#[test]
fn no_specular_light_means_no_specular() {
    let ls = scene(&format!(
        "{CAMERA}[[light]]\ntype = \"point\"\nposition = [1, 2, 3]\nspecular = [0, 0, 0]\n{SPEC_MATERIAL}{SPHERE}"
    ));
    let e = derive(&ls);
    assert_eq!(e.lighting.value, Lighting::Diffuse);
    assert!(e.lighting.why.contains("no light has a specular"));
    assert_eq!(e.lights.value, (0, 1));
    same_pixels_as_written(&ls);
}

#[test]
fn specular_pair_keeps_specular() {
    let ls = scene(&format!("{CAMERA}{SPEC_LIGHT}{SPEC_MATERIAL}{SPHERE}"));
    let e = derive(&ls);
    assert_eq!(e.lighting.value, Lighting::Specular);
    assert!(render::specular_pipeline(&effects::apply(&ls, &e).desc));
}

#[test]
fn one_convex_mesh_with_culling_needs_no_depth_buffer() {
    let ls = load::load_arg("sphere").unwrap();
    let e = derive(&ls);
    assert!(!e.depth.value);
    assert!(e.depth.why.contains("convex"), "{}", e.depth.why);
    same_pixels_as_written(&ls);
    // Phong too.
    let mut p = ls.clone();
    p.desc.shading = ShadingName::PHONG;
    same_pixels_as_written(&p);
}

#[test]
fn depth_stays_on_where_surfaces_can_overlap() {
    let teapot = derive(&load::load_arg("teapot").unwrap());
    assert!(teapot.depth.value);
    assert!(
        teapot.depth.why.contains("not convex"),
        "{}",
        teapot.depth.why
    );
    let two = scene(&format!("{CAMERA}{SPHERE}{SPHERE}"));
    assert!(derive(&two).depth.value);
    assert!(derive(&two).depth.why.contains("several objects"));
    let no_cull = scene(&format!("[render]\ncull = \"none\"\n{CAMERA}{SPHERE}"));
    let e = derive(&no_cull);
    assert!(e.depth.value && !e.cull.value);
    assert!(e.depth.why.contains("no culling"));
    let off = scene(&format!(
        "[render]\ndepth_test = false\n{CAMERA}{SPHERE}{SPHERE}"
    ));
    assert!(!derive(&off).depth.value);
}

#[test]
fn adaptive_without_specular_is_gouraud() {
    let ls = scene(&format!(
        "[render]\nshading = \"adaptive\"\n{CAMERA}{SPEC_LIGHT}{SPHERE}"
    ));
    let e = derive(&ls);
    assert_eq!(e.shading.value, ShadingName::GOURAUD);
    assert!(e.shading.why.contains("adaptive without"));
    // The derived frame is the Gouraud frame of the same scene. (Adaptive as written
    // still lights per pixel the triangles whose diffuse Gouraud error bound reaches
    // its limit; the rule trades that for the Gouraud cost.)
    let mut gouraud = ls.clone();
    gouraud.desc.shading = ShadingName::GOURAUD;
    let derived = render::render(&effects::apply(&ls, &e), None).unwrap();
    assert_eq!(derived.stats.per_pixel, 0);
    assert_eq!(derived.bytes, render::render(&gouraud, None).unwrap().bytes);
}

#[test]
fn local_viewer_without_specular_is_off() {
    let ls = scene(&format!(
        "[lighting]\nlocal_viewer = true\n{CAMERA}{SPEC_LIGHT}{SPHERE}"
    ));
    let e = derive(&ls);
    assert!(!e.local_viewer.value);
    assert!(e.local_viewer.why.contains("no specular"));
    same_pixels_as_written(&ls);
    let with = scene(&format!(
        "[lighting]\nlocal_viewer = true\n{CAMERA}{SPEC_LIGHT}{SPEC_MATERIAL}{SPHERE}"
    ));
    assert!(derive(&with).local_viewer.value);
}

/// Two-sided lighting: off unless the scene asks; off when back faces are culled
/// (none is drawn to show it) and when unlit without a back material (both sides
/// alike): the derived frame keeps the pixels. On otherwise, and then it shows.
#[test]
fn two_sided_lighting_follows_the_scene_and_culling() {
    let off = derive(&scene(&format!("{CAMERA}{SPEC_LIGHT}{SPHERE}")));
    assert!(!off.two_sided.value && off.two_sided.why.contains("two_sided = false"));
    let culled = scene(&format!(
        "[lighting]\ntwo_sided = true\n{CAMERA}{SPEC_LIGHT}{SPHERE}"
    ));
    let e = derive(&culled);
    assert!(!e.two_sided.value && e.two_sided.why.contains("culled"));
    same_pixels_as_written(&culled);
    let unlit = scene(&format!(
        "[render]\ncull = \"none\"\n[lighting]\ntwo_sided = true\n{CAMERA}{SPHERE}"
    ));
    let e = derive(&unlit);
    assert!(!e.two_sided.value && e.two_sided.why.contains("unlit"));
    same_pixels_as_written(&unlit);
    // The eye inside the sphere: every face in view is a back face.
    let inside = "[render]\ncull = \"none\"\n[lighting]\ntwo_sided = true\n\
         [camera]\neye = [0, 0, 0]\ntarget = [0, 0, -1]\nnear = 0.05\n\
         [[light]]\ntype = \"point\"\nposition = [0, 0, 0]\n\
         [[object]]\nmesh = \"sphere\"\nscale = 3\n";
    let on = scene(inside);
    let e = derive(&on);
    assert!(e.two_sided.value, "{}", e.two_sided.why);
    same_pixels_as_written(&on);
    let mut one = effects::apply(&on, &e);
    one.desc.two_sided = false;
    let lit = render::render(&effects::apply(&on, &e), None).unwrap();
    let dark = render::render(&one, None).unwrap();
    assert_ne!(lit.bytes, dark.bytes);
}

#[test]
fn perspective_correction_follows_the_scene_and_the_shading() {
    let ortho = scene(&format!(
        "[camera]\neye = [0, 0, 4]\nprojection = \"orthographic\"\nheight = 3\n{SPHERE}"
    ));
    let e = derive(&ortho);
    assert!(!e.perspective.value && e.perspective.why.contains("orthographic"));
    let persp = derive(&scene(&format!("{CAMERA}{SPHERE}")));
    assert!(!persp.perspective.value && persp.perspective.why.contains("screen space"));
    let asked = scene(&format!(
        "[render]\nperspective_correct = true\n{CAMERA}{SPEC_LIGHT}{SPHERE}"
    ));
    let e = derive(&asked);
    assert!(e.perspective.value && e.perspective.why.contains("asked"));
    assert!(effects::apply(&asked, &e).desc.perspective_correct);
    // Forced on and off.
    let mut forced = scene(&format!("{CAMERA}{SPEC_LIGHT}{SPHERE}"));
    forced.desc.effects = Overrides::parse("+perspective", Source::CommandLine).unwrap();
    assert!(derive(&forced).perspective.value);
    let mut off = asked.clone();
    off.desc.effects = Overrides::parse("-perspective", Source::CommandLine).unwrap();
    let e = derive(&off);
    assert!(!e.perspective.value);
    assert!(!effects::apply(&off, &e).desc.perspective_correct);
    // Phong and adaptive shading are corrected too (normals and eye positions);
    // the explicit override still wins.
    for shading in [
        ShadingName::PHONG,
        ShadingName::PHONG_EVEN_ODD,
        ShadingName::ADAPTIVE,
    ] {
        let mut phong = asked.clone();
        phong.desc.shading = shading;
        let e = derive(&phong);
        assert!(
            e.perspective.value && e.perspective.why.contains("asked"),
            "{shading:?}"
        );
        assert!(effects::apply(&phong, &e).desc.perspective_correct);
        phong.desc.effects = Overrides::parse("-perspective", Source::CommandLine).unwrap();
        assert!(!derive(&phong).perspective.value, "{shading:?}");
    }
    // The quadratic surface, flat shading and sampled Phong are not corrected.
    let mut quad = asked.clone();
    quad.desc.shading = ShadingName::QUADRATIC;
    let e = derive(&quad);
    assert!(!e.perspective.value && e.perspective.why.contains("quadratic"));
    let mut sampled = asked.clone();
    sampled.desc.shading = ShadingName::PHONG;
    sampled.desc.raycast.sampled = true;
    let e = derive(&sampled);
    assert!(!e.perspective.value && e.perspective.why.contains("sampled"));
}

#[test]
fn forced_settings_override_the_rules() {
    // Scene file forces the depth test on for the convex sphere.
    let ls = scene(&format!(
        "[render]\neffects = \"+depth, -specular\"\n{CAMERA}{SPEC_LIGHT}{SPEC_MATERIAL}{SPHERE}"
    ));
    let e = derive(&ls);
    assert!(e.depth.value && e.depth.why.contains("scene file"));
    assert_eq!(e.lighting.value, Lighting::Diffuse);
    // -specular changes the pixels: the highlight is gone.
    let forced = render::render(&effects::apply(&ls, &e), None).unwrap();
    let mut plain = ls.clone();
    plain.desc.effects = Overrides::default();
    let written = render::render(&plain, None).unwrap();
    assert_ne!(forced.bytes, written.bytes);
    // The command line comes after the scene file and wins.
    let mut cli = ls.clone();
    cli.desc
        .effects
        .extend(&Overrides::parse("-depth,+specular,-cull", Source::CommandLine).unwrap());
    let e = derive(&cli);
    assert!(!e.depth.value && e.depth.why.contains("--effects"));
    assert!(!e.cull.value);
    assert_eq!(e.lighting.value, Lighting::Specular);
    // -lighting draws unlit.
    let mut unlit = ls.clone();
    unlit.desc.effects = Overrides::parse("-lighting", Source::CommandLine).unwrap();
    assert_eq!(derive(&unlit).lighting.value, Lighting::Unlit);
    // Errors name the item.
    let err = Overrides::parse("-depht", Source::CommandLine).unwrap_err();
    assert!(
        err.contains("`-depht`") && err.contains("local-viewer"),
        "{err}"
    );
    let mut dark = scene(&format!("{CAMERA}{SPHERE}"));
    dark.desc.effects = Overrides::parse("+lighting", Source::CommandLine).unwrap();
    assert!(effects::derive(&dark).unwrap_err().contains("no lights"));
}

#[test]
fn adaptive_matches_phong_on_the_figures_and_counts_what_paid() {
    for fig in ["sphere", "teapot", "robot"] {
        let mut phong = load::load_arg(fig).unwrap();
        phong.desc.shading = ShadingName::PHONG;
        let mut adaptive = phong.clone();
        adaptive.desc.shading = ShadingName::ADAPTIVE;
        let p = render::render(&phong, None).unwrap();
        let a = render::render(&adaptive, None).unwrap();
        let c = compare(&p.image, &a.image).unwrap();
        let drawn = a.stats.triangles - a.stats.skipped();
        println!(
            "{fig}: NMSE vs Phong {:.3e}, {} of {} polygons per pixel",
            c.nmse, a.stats.per_pixel, drawn
        );
        assert_eq!(c.coverage_mismatch, 0);
        assert!(c.nmse <= 1e-4, "{fig}: {}", c.nmse);
        // Some triangles pay, not all.
        assert!(a.stats.per_pixel > 0, "{fig}");
        assert!(
            a.stats.per_pixel < drawn,
            "{fig}: {} of {drawn}",
            a.stats.per_pixel
        );
        // Phong's own stats report no adaptive count.
        assert_eq!(p.stats.per_pixel, 0);
    }
}

/// The specular part of `shade` at one point: with the specular term minus without.
fn specular_at<S: Specular>(
    with: &LightingSetup<S>,
    without: &LightingSetup<NoSpecular>,
    p: [i32; 3],
    n: [i32; 3],
) -> i64 {
    let a = with.shade(p, n);
    let b = without.shade(p, n);
    (0..3).map(|k| (a[k] - b[k]) as i64).max().unwrap()
}

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> i64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) as i64
    }
    /// Uniform in [-r, r] (Q16.16 raw).
    fn q(&mut self, r: i64) -> i64 {
        self.next() % (2 * r + 1) - r
    }
}

#[test]
fn specular_bound_is_never_below_the_light_found_inside() {
    let mut rng = Lcg(7);
    let white = [Q16_16::ONE; 3];
    let mut checked = 0;
    let mut tight = 0;
    for case in 0..400 {
        let local = case % 2 == 1;
        let point = case % 4 >= 2;
        let light = if point {
            Light {
                kind: LightKind::Point {
                    position: [0, 0, 0].map(|_| Q16_16::from_bits(rng.q(3 << 16) as i32)),
                    attenuation: [Q16_16::ONE, Q16_16::ZERO, Q16_16::from_ratio(1, 10)],
                },
                ambient: [Q16_16::ZERO; 3],
                diffuse: white,
                specular: white,
            }
        } else {
            let d = [0, 0, 0].map(|_| Q16_16::from_bits(rng.q(1 << 16) as i32));
            Light::directional(d, white, white)
        };
        let mat = Material {
            specular: [Q16_16::from_ratio(7, 10); 3],
            shininess: Q16_16::from_int(1 + (rng.next() % 200) as i32),
            ..Material::default()
        };
        let with = LightingSetup::<fixshade::specular::BlinnExact>::new(
            &[light],
            &Mat4::IDENTITY,
            &mat,
            [Q16_16::ZERO; 3],
            local,
        );
        let without = LightingSetup::<NoSpecular>::new(
            &[light],
            &Mat4::IDENTITY,
            &mat,
            [Q16_16::ZERO; 3],
            local,
        );
        // A small triangle in front of the eye (z < 0) with normals near a random
        // direction facing the eye.
        let centre = [rng.q(1 << 16), rng.q(1 << 16), -(4 << 16) + rng.q(1 << 16)];
        let base = [rng.q(1 << 16), rng.q(1 << 16), (1 << 16) + rng.q(1 << 15)];
        let spread = 1 + rng.next() % (1 << 14);
        let p: [[i32; 3]; 3] =
            core::array::from_fn(|_| core::array::from_fn(|k| (centre[k] + rng.q(1 << 14)) as i32));
        let n: [[i32; 3]; 3] = core::array::from_fn(|_| {
            let v: [i64; 3] = core::array::from_fn(|k| base[k] + rng.q(spread));
            normalize_to_q30(v).unwrap()
        });
        let bound = with.specular_bound(&n, &p);
        assert!(bound >= 0);
        // Sample the triangle: barycentric grid, normals interpolated and normalised.
        let mut found = 0;
        let steps = 12i64;
        for i in 0..=steps {
            for j in 0..=steps - i {
                let w = [i, j, steps - i - j];
                let pt: [i32; 3] = core::array::from_fn(|k| {
                    ((0..3).map(|v| w[v] * p[v][k] as i64).sum::<i64>() / steps) as i32
                });
                let nv: [i64; 3] =
                    core::array::from_fn(|k| (0..3).map(|v| w[v] * n[v][k] as i64).sum::<i64>());
                let Some(nn) = normalize_to_q30(nv) else {
                    continue;
                };
                found = found.max(specular_at(&with, &without, pt, nn));
            }
        }
        assert!(
            bound >= found,
            "case {case}: bound {bound} < specular {found} found inside (local {local}, point {point})"
        );
        checked += 1;
        if bound != i64::MAX && bound < 4 * found.max(1 << 10) {
            tight += 1;
        }
    }
    // The bound is useful, not just large: finite and within 4x (or 1/64) of
    // the light found in most cases.
    println!("{tight} of {checked} bounds within 4x of the sampled maximum");
    assert!(tight * 2 > checked, "{tight} of {checked}");
}

#[test]
fn diffuse_bound_is_never_below_the_gouraud_error_found_inside() {
    // Gouraud's ambient and diffuse light (the vertex colours interpolated) against
    // the same light per pixel (interpolated normals renormalised), sampled over
    // small triangles, many of them crossing a light's terminator.
    let mut rng = Lcg(11);
    let white = [Q16_16::ONE; 3];
    let (mut checked, mut crossing, mut tight) = (0, 0, 0);
    for case in 0..600 {
        let point = case % 3 == 2;
        let centre = [rng.q(1 << 16), rng.q(1 << 16), -(4 << 16) + rng.q(1 << 16)];
        let base = [rng.q(1 << 16), rng.q(1 << 16), (1 << 16) + rng.q(1 << 15)];
        let spread = 1 + rng.next() % (1 << 14);
        let n: [[i32; 3]; 3] = core::array::from_fn(|_| {
            let v: [i64; 3] = core::array::from_fn(|k| base[k] + rng.q(spread));
            normalize_to_q30(v).unwrap()
        });
        let light = if point {
            Light {
                kind: LightKind::Point {
                    position: [0, 0, 0].map(|_| Q16_16::from_bits(rng.q(3 << 16) as i32)),
                    attenuation: [Q16_16::ONE, Q16_16::ZERO, Q16_16::from_ratio(1, 10)],
                },
                ambient: [Q16_16::from_ratio(1, 5); 3],
                diffuse: white,
                specular: white,
            }
        } else {
            // Most directions nearly perpendicular to the normals: the terminator
            // crosses the triangle.
            let side = [base[1], -base[0], rng.q(1 << 13)];
            let d: [i64; 3] = if case % 3 == 0 {
                core::array::from_fn(|_| rng.q(1 << 16))
            } else {
                side
            };
            Light::directional(
                d.map(|v| Q16_16::from_bits(v as i32)),
                white,
                [Q16_16::ZERO; 3],
            )
        };
        let setup = LightingSetup::<NoSpecular>::new(
            &[light],
            &Mat4::IDENTITY,
            &Material::default(),
            [Q16_16::ZERO; 3],
            false,
        );
        let p: [[i32; 3]; 3] =
            core::array::from_fn(|_| core::array::from_fn(|k| (centre[k] + rng.q(1 << 14)) as i32));
        let bound = setup.diffuse_bound(&n, &p);
        assert!(bound >= 0);
        let c: [[i32; 3]; 3] = core::array::from_fn(|v| setup.shade(p[v], n[v]));
        let mut found = 0;
        let steps = 12i64;
        for i in 0..=steps {
            for j in 0..=steps - i {
                let w = [i, j, steps - i - j];
                let pt: [i32; 3] = core::array::from_fn(|k| {
                    ((0..3).map(|v| w[v] * p[v][k] as i64).sum::<i64>() / steps) as i32
                });
                let nv: [i64; 3] =
                    core::array::from_fn(|k| (0..3).map(|v| w[v] * n[v][k] as i64).sum::<i64>());
                let Some(nn) = normalize_to_q30(nv) else {
                    continue;
                };
                let per_pixel = setup.shade(pt, nn);
                for ch in 0..3 {
                    let g: i64 = (0..3).map(|v| w[v] * c[v][ch] as i64).sum();
                    found = found.max((g - steps * per_pixel[ch] as i64).abs() / steps);
                }
            }
        }
        assert!(
            bound >= found,
            "case {case}: bound {bound} < Gouraud error {found} found inside (point {point})"
        );
        checked += 1;
        let lit: Vec<bool> = c.iter().map(|v| v[0] > 0).collect();
        if !point && lit.iter().any(|l| *l) && lit.iter().any(|l| !l) {
            crossing += 1;
            // Crossing the terminator: within 4x (or 1/256) of the error found.
            if bound < 4 * found.max(1 << 8) {
                tight += 1;
            }
        }
    }
    println!(
        "{checked} triangles, {crossing} crossing a terminator, {tight} of them bound within 4x"
    );
    assert!(crossing > 50, "{crossing}");
    assert!(tight * 2 > crossing, "{tight} of {crossing}");
}

#[test]
fn every_specular_model_is_non_decreasing() {
    // The adaptive bound evaluates the model at the bound of N·H.
    use fixshade_sim::scene::desc::{Named, SpecularName};
    for &(model, name) in SpecularName::ALL {
        for n in [1, 2, 8, 32, 128, 512, 1000] {
            let q = Q16_16::from_int(n);
            let ok = fixshade::select_specular!(model.name(), Sp => {
                let params = Sp::prepare(q);
                let mut last = 0u64;
                let mut ok = true;
                for c in (0..=(1 << 30)).step_by(1 << 14) {
                    let v = Sp::eval_wide(&params, c);
                    ok &= v >= last;
                    last = v;
                }
                ok
            })
            .expect("a model of the registry");
            assert!(ok, "{name} n = {n} is not non-decreasing");
        }
    }
}
