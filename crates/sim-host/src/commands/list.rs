//! `fixshade list`: the built-in scenes and every selectable name (from the core's
//! registry, [`crate::scene::names`]) with a line on what it does.

use fixshade::registry::{SPAN_METHOD_LINES, SPECULAR_LINES};

use crate::scene::builtin;
use crate::scene::desc::{DivideName, FormatName, ShadingName, SpanName, SpecularName};

/// One line on a shading mode.
fn describe_shading(name: &str) -> &'static str {
    match name {
        "flat" => "one colour per triangle (its last vertex's)",
        "gouraud" => "vertex colours interpolated",
        "quadratic" => "quadratic surface through vertex and edge-midpoint colours (seed 003)",
        "phong" => "normals interpolated, every pixel lit (with --segment/--threshold: lit at segment ends, interpolated inside)",
        "phong-even-odd" => "phong with two accumulators per normal component; same pixels",
        "adaptive" => {
            "phong where a highlight can reach a triangle (conservative bound), gouraud elsewhere"
        }
        "raycast" => "fixed-point ray casting sampled by pixel segments (--segment, --threshold)",
        _ => "",
    }
}

/// One line on a pixel format.
fn describe_format(name: &str) -> &'static str {
    match name {
        "rgb565le" => "RGB 5-6-5, little-endian bytes",
        "rgb565be" => "RGB 5-6-5, big-endian bytes (ST7789/ILI9341 over SPI)",
        "rgb888" => "RGB 8-8-8",
        "gray8" => "8-bit grey",
        _ => "",
    }
}

/// One line on a divider.
fn describe_divider(n: &str) -> &'static str {
    match n {
        "exact" => "full-precision integer division (the default)",
        "table" => "16 KiB reciprocal table of k = 1..4096, one multiply; exact on that range",
        _ if n.starts_with("shift-add-rounded-") => {
            "N shifts and adds, expansion of 1/k rounded at bit N (N = 4..16)"
        }
        _ => "N shifts and adds, truncated binary expansion of 1/k (N = 4..16)",
    }
}

/// `fixshade list`: every built-in scene and every name selectable on the command
/// line, with a line on each.
pub fn list() -> String {
    let mut out = format!(
        "built-in scenes: {}\nbuilt-in meshes (scene files): sphere, teapot, robot, obj (with path)\n",
        builtin::SCENES.join(", ")
    );
    let mut section = |title: &str, lines: Vec<(&'static str, &'static str)>| {
        out.push_str(&format!("\n{title}:\n"));
        for (n, d) in lines {
            out.push_str(&format!("  {n:18} {d}\n"));
        }
    };
    let names = |all: &[&'static str], f: &dyn Fn(usize, &str) -> &'static str| {
        all.iter().enumerate().map(|(i, n)| (*n, f(i, n))).collect()
    };
    section(
        "span methods (--span)",
        names(SpanName::NAMES, &|i, _| SPAN_METHOD_LINES[i]),
    );
    section(
        "shading modes (--shading)",
        names(ShadingName::NAMES, &|_, n| describe_shading(n)),
    );
    section(
        "specular models (--specular)",
        names(SpecularName::NAMES, &|i, _| SPECULAR_LINES[i]),
    );
    section(
        "dividers (--divide)",
        names(DivideName::NAMES, &|_, n| describe_divider(n)),
    );
    section(
        "pixel formats (--format)",
        names(FormatName::NAMES, &|_, n| describe_format(n)),
    );
    out.trim_end().to_string()
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_name_has_a_line() {
        for line in super::list().lines().filter(|l| l.starts_with("  ")) {
            assert!(
                line.split_whitespace().count() > 1,
                "no description: {line}"
            );
        }
    }
}
