//! `render_chunked` (the Cortex-M0 firmware's strips and mesh chunks on the host)
//! draws with the scene's span method, divider and perspective correction.

use fixshade_sim::render;
use fixshade_sim::render::render_chunked;
use fixshade_sim::scene::desc::{DivideName, SpanName};
use fixshade_sim::scene::load;

#[test]
fn render_chunked_draws_with_the_scenes_divider() {
    let mut ls = load::load_arg("sphere").unwrap();
    ls.desc.width = 160;
    ls.desc.height = 120;
    for span in [SpanName::CLASSIC, SpanName::GRADIENT] {
        ls.desc.span = span;
        ls.desc.divide = DivideName::EXACT;
        let exact = render_chunked(&ls, 64, 2).unwrap();
        assert_eq!(exact, render::render(&ls, None).unwrap().bytes);
        for d in [DivideName::named("table"), DivideName::named("shift-add-4")] {
            ls.desc.divide = d;
            let cut = render_chunked(&ls, 64, 2).unwrap();
            // The same pixels as the whole-frame render with that divider ...
            assert_eq!(cut, render::render(&ls, None).unwrap().bytes, "{d:?}");
            // ... which are not `exact`'s (shift-add-4 is coarse; the table's wide
            // reciprocal rounds the divisor to 12 bits).
            assert_ne!(cut, exact, "{d:?}");
        }
    }
}

#[test]
fn render_chunked_draws_perspective_correct_colours() {
    let mut ls = load::load_arg("sphere").unwrap();
    ls.desc.width = 160;
    ls.desc.height = 120;
    ls.desc.span = SpanName::GRADIENT;
    ls.desc.perspective_correct = false;
    let affine = render_chunked(&ls, 64, 2).unwrap();
    ls.desc.perspective_correct = true;
    for d in [DivideName::EXACT, DivideName::named("shift-add-8")] {
        ls.desc.divide = d;
        let mut seen = Vec::new();
        for span in [1, 16] {
            ls.desc.perspective_span = span;
            let cut = render_chunked(&ls, 64, 2).unwrap();
            // The whole-frame render's pixels, strips of 2 rows and 64-vertex chunks
            // notwithstanding ...
            assert_eq!(
                cut,
                render::render(&ls, None).unwrap().bytes,
                "{d:?} {span}"
            );
            // ... which are not the affine fill's, and depend on the sub-span.
            assert_ne!(cut, affine, "{d:?} {span}");
            seen.push(cut);
        }
        assert_ne!(seen[0], seen[1], "{d:?}");
    }
}
