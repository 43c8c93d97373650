//! Perspective-correct Gouraud colours (`fixshade::raster::perspective`, `--perspective
//! on`): against the perspective-correct f64 reference on the ground plane (two large
//! triangles, clipped at the near plane) and its tessellated twin; strips equal the
//! whole frame; every divider keeps the coverage; screen-space interpolation is what
//! an orthographic camera already gets. The same for Phong normals and eye positions
//! (`draw_phong_perspective`) on the Phong twins of the two scenes, and adaptive
//! shading.

use fixshade::divide::Divide;
use fixshade_sim::image::compare::compare;
use fixshade_sim::render;
use fixshade_sim::render::host::{with_selection, HostDivide, Selection};
use fixshade_sim::scene::desc::{DivideName, Named, ShadingName};
use fixshade_sim::scene::load;
use fixshade_sim::scene::load::LoadedScene;
use fixshade_sim::tables::effects::table_scene_path;

fn load(name: &str) -> LoadedScene {
    load::load_arg(&table_scene_path(name).display().to_string()).unwrap()
}

fn with(ls: &LoadedScene, on: bool, span: u32) -> LoadedScene {
    let mut out = ls.clone();
    out.desc.perspective_correct = on;
    out.desc.perspective_span = span;
    out
}

/// NMSE of a fixed-point render against the perspective-correct reference.
fn nmse(ls: &LoadedScene) -> f64 {
    let reference = render::matching_reference(&with(ls, true, 1));
    let r = render::render(ls, None).unwrap();
    let c = compare(&reference, &r.image).unwrap();
    assert_eq!(c.coverage_mismatch, 0);
    c.nmse
}

#[test]
fn large_triangles_need_the_correction() {
    let ls = load("ground-plane");
    let affine = nmse(&with(&ls, false, 1));
    let mut on = Vec::new();
    for span in [1, 8, 16, 64] {
        on.push(nmse(&with(&ls, true, span)));
    }
    println!("ground plane: affine {affine:.3e}, perspective 1/8/16/64 {on:?}");
    // Measured: affine 0.59, every pixel 2.1e-5.
    assert!(affine > 0.1, "{affine}");
    for n in &on {
        assert!(*n <= 1e-4, "{n}");
    }
}

#[test]
fn small_triangles_err_little_without_it() {
    let ls = load("ground-fine");
    let affine = nmse(&with(&ls, false, 1));
    let pixel = nmse(&with(&ls, true, 1));
    println!("tessellated ground plane: affine {affine:.3e}, every pixel {pixel:.3e}");
    // Measured: affine 2.92e-5, every pixel 1.2e-6. The per-pixel path must beat
    // screen space by 4× and stay near its figure before ce7d824 (1.2e-6): from
    // ce7d824 to the transform's 18-bit entries for 19-bit meshes it was 7.6e-6,
    // when the entries' rounding moved this 40-unit plane's positions by up to 0.1
    // subpixel at the far end and 0.47 near the eye (`math::VertexTransform`).
    assert!(affine <= 1e-4, "{affine}");
    assert!(pixel <= 1.5e-6, "{pixel}");
    assert!(4.0 * pixel < affine, "{pixel} {affine}");
}

#[test]
fn strips_equal_the_whole_frame() {
    for span in [1, 16] {
        let ls = with(&load("ground-plane"), true, span);
        let whole = render::render(&ls, None).unwrap();
        for rows in [1, 7, 16] {
            let strips = render::render(&ls, Some(rows)).unwrap();
            assert!(
                strips.bytes == whole.bytes,
                "span {span}, strips of {rows} rows"
            );
        }
    }
}

#[test]
fn dividers_keep_coverage_and_stay_close() {
    let exact = with(&load("ground-plane"), true, 16);
    let base = render::render(&exact, None).unwrap();
    for &(d, name) in DivideName::ALL {
        let mut ls = exact.clone();
        ls.desc.divide = d;
        let r = render::render(&ls, None).unwrap();
        let c = compare(&base.image, &r.image).unwrap();
        assert_eq!(c.coverage_mismatch, 0, "{name}");
        // The reciprocal of the wide denominator never over-estimates and is within
        // η = 2^(1−b) + (2E + 2)·2^b/2³⁰ relative (`fixshade::divide::wide_recip`:
        // b the divider's mantissa bits, E its error on 2³⁰): both weights shrink
        // by at most η, so a colour moves towards the top vertex's by at most η of
        // the 255 range; the sub-span interpolates two such ends; one Rgb565 step.
        if d == DivideName::EXACT {
            continue;
        }
        let sel = Selection {
            divide: d,
            ..Selection::EXACT
        };
        let (b, e) = with_selection(sel, || {
            let b = HostDivide::mantissa_bits().clamp(1, 12);
            (b, HostDivide::max_error(1 << 30, 1 << b) as f64)
        });
        let eta = 2f64.powi(1 - b as i32) + (2.0 * e + 2.0) * 2f64.powi(b as i32 - 30);
        let bound = ((255.0 * eta.min(1.0)).ceil() + 8.0).min(255.0) as u8;
        println!(
            "{name}: NMSE {:.2e}, max error {} (bound {bound})",
            c.nmse, c.max_channel_error
        );
        assert!(
            c.max_channel_error <= bound,
            "{name}: {} > {bound}",
            c.max_channel_error
        );
    }
    assert_eq!(DivideName::parse("exact").unwrap(), DivideName::EXACT);
}

#[test]
fn an_orthographic_camera_gains_nothing() {
    let mut ls = load("hud-gauge");
    ls.desc.shading = ShadingName::GOURAUD;
    let off = render::render(&with(&ls, false, 1), None).unwrap();
    let on = render::render(&with(&ls, true, 1), None).unwrap();
    let c = compare(&off.image, &on.image).unwrap();
    assert_eq!(c.coverage_mismatch, 0);
    // Constant w: the weights are the screen ones, to rounding.
    assert!(c.max_channel_error <= 8, "{}", c.max_channel_error);
}

#[test]
fn phong_on_large_triangles_needs_the_correction() {
    let ls = load("ground-plane-phong");
    assert_eq!(ls.desc.shading, ShadingName::PHONG);
    let affine = nmse(&with(&ls, false, 1));
    let on: Vec<f64> = [1, 8, 16, 32]
        .iter()
        .map(|&span| nmse(&with(&ls, true, span)))
        .collect();
    println!("Phong ground plane: affine {affine:.3e}, perspective 1/8/16/32 {on:?}");
    // Measured (docs/effects.md): affine 0.61, every 1/8/16/32 pixels 3.8e-4.
    assert!(affine > 0.1, "{affine}");
    for n in &on {
        assert!(*n <= 1e-3, "{n}");
    }
}

#[test]
fn phong_on_small_triangles_errs_little_without_it() {
    let ls = load("ground-fine-phong");
    let affine = nmse(&with(&ls, false, 1));
    let pixel = nmse(&with(&ls, true, 1));
    println!("tessellated Phong ground plane: affine {affine:.3e}, every pixel {pixel:.3e}");
    // Measured (docs/effects.md): affine 2.5e-2, every pixel 8.5e-6.
    assert!(affine > 1e-3, "{affine}");
    assert!(pixel < 5e-5 && pixel < affine / 100.0, "{pixel} {affine}");
}

/// The even/odd Phong fill draws as the row fill under perspective correction;
/// adaptive shading (Phong where the highlight is, Gouraud elsewhere) is corrected
/// on both kinds of triangle; strips equal the whole frame.
#[test]
fn phong_fills_adaptive_and_strips() {
    let ls = with(&load("ground-plane-phong"), true, 16);
    let rows = render::render(&ls, None).unwrap();
    let mut eo = ls.clone();
    eo.desc.shading = ShadingName::PHONG_EVEN_ODD;
    assert!(render::render(&eo, None).unwrap().bytes == rows.bytes);
    for rows_n in [1, 7] {
        let strips = render::render(&ls, Some(rows_n)).unwrap();
        assert!(strips.bytes == rows.bytes, "strips of {rows_n} rows");
    }
    let fine = load("ground-fine-phong");
    let adaptive: Vec<f64> = [false, true]
        .iter()
        .map(|&on| {
            let mut ad = with(&fine, on, 1);
            ad.desc.shading = ShadingName::ADAPTIVE;
            nmse(&ad)
        })
        .collect();
    println!("adaptive, tessellated, affine / perspective: NMSE {adaptive:?}");
    assert!(adaptive[1] < adaptive[0], "{adaptive:?}");
}
