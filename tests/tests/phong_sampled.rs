//! The pixel-segment sampler applied to Phong shading (`--shading phong --segment L
//! --threshold K`, seed 002 §2.6): L = 1 is the per-pixel render bit for bit, strips
//! give the whole frame's bytes, and longer segments light fewer pixels at a
//! measured cost in accuracy.

use fixshade_sim::image::compare::compare;
use fixshade_sim::render;
use fixshade_sim::scene::desc::{FormatName, ShadingName};
use fixshade_sim::scene::load;
use fixshade_sim::scene::load::LoadedScene;

const FIGURES: [&str; 3] = ["sphere", "teapot", "robot"];

fn phong(fig: &str) -> LoadedScene {
    let mut ls = load::load_arg(fig).unwrap();
    ls.desc.shading = ShadingName::PHONG;
    ls
}

fn sampled(fig: &str, segment: u32, threshold: f64) -> LoadedScene {
    let mut ls = phong(fig);
    ls.desc.raycast.sampled = true;
    ls.desc.raycast.segment = segment;
    ls.desc.raycast.threshold = threshold;
    ls
}

#[test]
fn segment_one_is_the_per_pixel_render() {
    for fig in FIGURES {
        let full = render::render(&phong(fig), None).unwrap();
        for k in [0.0, 2.3, 64.0] {
            let s = render::render(&sampled(fig, 1, k), None).unwrap();
            assert_eq!(s.bytes, full.bytes, "{fig} K = {k}");
            // Every covered pixel was lit once (hidden ones too: the depth test
            // comes after the evaluation).
            assert_eq!(s.stats.evaluations, s.stats.pixels, "{fig}");
            assert_eq!(
                full.stats.evaluations, 0,
                "{fig}: the plain path counts nothing"
            );
        }
    }
}

#[test]
fn strips_give_the_whole_frame() {
    for fig in FIGURES {
        let ls = sampled(fig, 8, 2.3);
        let whole = render::render(&ls, None).unwrap();
        for rows in [1, 7, 16] {
            let s = render::render(&ls, Some(rows)).unwrap();
            assert_eq!(s.bytes, whole.bytes, "{fig}: strips of {rows} rows");
        }
    }
}

#[test]
fn longer_segments_light_fewer_pixels() {
    println!("figure  format    L   K     evals/px  NMSE vs per-pixel Phong  NMSE vs f64 Phong");
    for fig in FIGURES {
        for format in [FormatName::RGB888, FormatName::RGB565LE] {
            let mut base = phong(fig);
            base.desc.format = format;
            let full = render::render(&base, None).unwrap();
            let reference = render::matching_reference(&base);
            let mut first = None;
            for l in [2, 4, 8, 16] {
                let mut ls = sampled(fig, l, 2.3);
                ls.desc.format = format;
                let r = render::render(&ls, None).unwrap();
                let per_px = r.stats.evaluations as f64 / r.stats.pixels as f64;
                let vs_full = compare(&full.image, &r.image).unwrap();
                let vs_ref = compare(&reference, &r.image).unwrap();
                println!(
                    "{fig:7} {:9} {l:2}  2.3   {per_px:.3}     {:.3e}                {:.3e}",
                    format!("{format:?}"),
                    vs_full.nmse,
                    vs_ref.nmse
                );
                assert_eq!(vs_full.coverage_mismatch, 0, "{fig} L = {l}");
                // At the seed's K the sampled image stays indistinguishable from the
                // per-pixel one (the project's NMSE level for exact methods).
                assert!(vs_full.nmse <= 1e-5, "{fig} L = {l}: NMSE {}", vs_full.nmse);
                assert_eq!(r.stats.pixels, full.stats.pixels, "{fig} L = {l}");
                // Fewer evaluations than pixels, and fewer at L = 16 than at L = 2 (in
                // between the subdivision points move, so it need not fall at every step).
                assert!(per_px < 1.0, "{fig} L = {l}: {per_px}");
                let at_two = *first.get_or_insert(per_px);
                assert!(
                    l < 16 || per_px < at_two,
                    "{fig}: L = 16 {per_px} vs L = 2 {at_two}"
                );
            }
        }
    }
}
