//! `render_chunked` (the Cortex-M0 firmware's strips and mesh chunks on the host)
//! draws with the scene's span method and divider.

use fixshade_sim::bake::render_chunked;
use fixshade_sim::desc::{DivideName, SpanName};
use fixshade_sim::pipeline;

#[test]
fn render_chunked_draws_with_the_scenes_divider() {
    let mut ls = pipeline::load_arg("sphere").unwrap();
    ls.desc.width = 160;
    ls.desc.height = 120;
    for span in [SpanName::Classic, SpanName::Gradient] {
        ls.desc.span = span;
        ls.desc.divide = DivideName::Exact;
        let exact = render_chunked(&ls, 64, 2).unwrap();
        assert_eq!(exact, pipeline::render(&ls, None).unwrap().bytes);
        for d in [DivideName::Table, DivideName::ShiftAdd(4)] {
            ls.desc.divide = d;
            let cut = render_chunked(&ls, 64, 2).unwrap();
            // The same pixels as the whole-frame render with that divider ...
            assert_eq!(cut, pipeline::render(&ls, None).unwrap().bytes, "{d:?}");
            // ... which are not `exact`'s (shift-add-4 is coarse; the table's wide
            // reciprocal rounds the divisor to 12 bits).
            assert_ne!(cut, exact, "{d:?}");
        }
    }
}
