//! The demo run by `cargo run --release`: the three built-in figures rendered into
//! `out/`, each with its f64 reference, and a table of what they cost and how exact
//! they are.

use std::fmt::Write;
use std::path::Path;

use crate::image::compare::compare;
use crate::render;
use crate::scene::load::load_arg;

/// The demo figures.
pub const FIGURES: [&str; 3] = ["sphere", "teapot", "robot"];

/// Renders the figures into `out/` and returns the table.
pub fn run_demo() -> Result<String, String> {
    let dir = Path::new("out");
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create out/: {e}"))?;
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{:<8} {:>9} {:>8} {:>9} {:>10} {:>11}  verdict",
        "figure", "triangles", "drawn", "pixels", "ms/frame", "NMSE"
    );
    for name in FIGURES {
        let ls = load_arg(name)?;
        let r = render::render(&ls, None)?;
        let reference = render::reference(&ls, false);
        let c = compare(&reference, &r.image)?;
        let time = render::time_frame(&ls, 21)?;
        r.image.write_png(&dir.join(format!("{name}.png")))?;
        reference.write_png(&dir.join(format!("{name}-reference.png")))?;
        let _ = writeln!(
            t,
            "{:<8} {:>9} {:>8} {:>9} {:>10.3} {:>11.3e}  {}",
            name,
            r.stats.triangles,
            r.stats.drawn,
            r.image.covered_count(),
            time.as_secs_f64() * 1e3,
            c.nmse,
            c.verdict.as_str()
        );
    }
    let _ = write!(
        t,
        "{}x{} rgb565le, gouraud, gradient span; images in out/ (NAME.png, NAME-reference.png)",
        320, 240
    );
    Ok(t)
}
