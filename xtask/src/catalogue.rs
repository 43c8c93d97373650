//! The host side of the catalogue images: draws every case of the triangle catalogue
//! (tests/catalogue/triangles.toml, which `cargo xtask bake` bakes for the firmware)
//! with every span method and mode, as `fixshade_boards_common::catalogue` does on
//! the MCU, and compares the bytes.

use std::path::Path;

use fixshade::raster::span::{DepthTest, NoDepth};
use fixshade::raster::{draw_triangle, ScreenVertex};
use fixshade::shade::{Flat, Gouraud};
use fixshade::target::{PixelFormat, Rgb888, Strip};
use fixshade_sim::scene::desc::{Named, SpanName};
use fixshade_sim::with_span_method;
use fixshade_tests::catalogue::{triangle_cases, TriCase};

/// The modes in the firmware's order: (flat, depth).
const MODES: [(bool, bool); 4] = [(true, false), (true, true), (false, false), (false, true)];

/// The firmware's background, `catalogue::BACKGROUND`.
const BACKGROUND: [u32; 3] = [7, 77, 177];

/// Colour and depth streams of one case, as the firmware writes them.
pub fn host_case(case: &TriCase) -> Result<(Vec<u8>, Vec<u8>), String> {
    let (width, height) = (case.frame[0], case.frame[1]);
    let (y0, rows) = case.strip();
    let tris = case.triangles();
    let (mut col, mut dep) = (Vec::new(), Vec::new());
    let n = width as usize * rows as usize;
    for (span, _) in SpanName::ALL {
        for (flat, with_depth) in MODES {
            let mut c = vec![[0u8; 3]; n];
            let mut d = vec![0u16; n];
            let mut s = Strip::<Rgb888>::new(
                &mut c,
                with_depth.then_some(&mut d[..]),
                width,
                height,
                y0,
                rows,
            )
            .map_err(|e| format!("{}: {e}", case.name))?;
            s.clear(Rgb888::pack(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2]));
            for t in &tris {
                let t = if flat {
                    let pc = t[2].c;
                    t.map(|v| ScreenVertex { c: pc, ..v })
                } else {
                    *t
                };
                with_span_method!(*span, S => match (flat, with_depth) {
                    (true, false) => draw_triangle::<Rgb888, _, S, NoDepth, Flat>(&mut s, t),
                    (true, true) => draw_triangle::<Rgb888, _, S, DepthTest, Flat>(&mut s, t),
                    (false, false) => draw_triangle::<Rgb888, _, S, NoDepth, Gouraud>(&mut s, t),
                    (false, true) => draw_triangle::<Rgb888, _, S, DepthTest, Gouraud>(&mut s, t),
                });
            }
            col.extend(s.color().as_flattened());
            // `s` borrows `d` until here.
            let _ = s;
            if with_depth {
                dep.extend(d.iter().flat_map(|z| z.to_le_bytes()));
            }
        }
    }
    Ok((col, dep))
}

/// What [`check`] found.
pub struct Checked {
    /// Frames compared.
    pub frames: usize,
    /// Mismatches, one line each.
    pub bad: Vec<String>,
    /// Table rows `board case width y0 rows strip_rows pixels instructions`.
    pub rows: Vec<String>,
    /// Skipped cases `board case width`.
    pub skipped: Vec<String>,
}

/// Checks the firmware's method order, then every `TRICASE` of `log` against the
/// host, deleting each case's files once compared.
pub fn check(log: &str, out_dir: &Path) -> Result<Checked, String> {
    let want: Vec<&str> = SpanName::ALL.iter().map(|(_, n)| *n).collect();
    let have: Vec<&str> = log
        .lines()
        .find_map(|l| l.strip_prefix("TRIMETHODS "))
        .ok_or("no TRIMETHODS line")?
        .split_whitespace()
        .collect();
    if have != want {
        return Err(format!("firmware method order {have:?}, host {want:?}"));
    }
    let cases = triangle_cases();
    let (mut frames, mut bad, mut rows, mut skipped) = (0, Vec::new(), Vec::new(), Vec::new());
    for line in log.lines() {
        if let Some(rest) = line.strip_prefix("TRISKIP ") {
            skipped.push(rest.to_string());
            continue;
        }
        let Some(rest) = line.strip_prefix("TRICASE ") else {
            continue;
        };
        let f: Vec<&str> = rest.split_whitespace().collect();
        let [board, name, ..] = f.as_slice() else {
            return Err(format!("bad line: {line}"));
        };
        let case = cases
            .iter()
            .find(|c| c.name == *name)
            .ok_or_else(|| format!("unknown case {name}"))?;
        let (col, dep) = host_case(case)?;
        for (ext, host) in [("rgb", &col), ("z", &dep)] {
            let p = out_dir.join(format!("{name}.{ext}"));
            let mcu = std::fs::read(&p).map_err(|e| format!("{}: {e}", p.display()))?;
            if mcu != *host {
                bad.push(format!(
                    "{board} catalogue {name} ({ext}): {} bytes on the MCU, {} on the host, {}",
                    mcu.len(),
                    host.len(),
                    crate::qemu::first_difference(&mcu, host)
                ));
            }
            let _ = std::fs::remove_file(&p);
        }
        frames += SpanName::ALL.len() * MODES.len();
        rows.push(rest.to_string());
    }
    Ok(Checked {
        frames,
        bad,
        rows,
        skipped,
    })
}
