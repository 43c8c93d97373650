//! The HUD example (`examples/hud_gauge.rs`, included here as a module) runs, its
//! PNG decodes, and the picture holds both the embedded-graphics text and the
//! shaded models: text pixels of the text colour inside the text boxes (and that
//! colour nowhere else), and the teapot's pixels equal to the teapot rendered alone
//! into a native framebuffer.

#[allow(dead_code)]
#[path = "../examples/hud_gauge.rs"]
mod hud_gauge;

use std::collections::HashSet;

use embedded_graphics::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics::prelude::*;
use fixshade::prelude::*;

fn decode(path: &std::path::Path) -> (u32, u32, Vec<[u8; 3]>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut rd = dec.read_info().unwrap();
    let mut buf = vec![0; rd.output_buffer_size().unwrap()];
    let info = rd.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let px = buf[..info.buffer_size()]
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width, info.height, px)
}

fn rgb8(c: Rgb565) -> [u8; 3] {
    let c = Rgb888::from(c);
    [c.r(), c.g(), c.b()]
}

#[test]
fn hud_gauge_png_has_text_and_shaded_models() {
    let dir = std::env::temp_dir().join(format!("fixshade-hud-{}", std::process::id()));
    let out = dir.join("hud_gauge.png");
    hud_gauge::run(&out).unwrap();
    let (w, h, px) = decode(&out);
    assert_eq!((w, h), (hud_gauge::SIZE.width, hud_gauge::SIZE.height));
    let at = |x: i32, y: i32| px[y as usize * w as usize + x as usize];

    // Text: the text colour inside the text boxes, and nowhere else.
    let text = rgb8(hud_gauge::TEXT);
    let (_, boxes) = hud_gauge::draw().unwrap();
    let mut in_text = 0;
    for y in 0..h as i32 {
        for x in 0..w as i32 {
            let inside = boxes.iter().any(|b| b.contains(Point::new(x, y)));
            if at(x, y) == text {
                assert!(inside, "text colour at {x},{y} outside the text");
                in_text += 1;
            }
        }
    }
    assert!(in_text > 500, "{in_text} text pixels");

    // The teapot: where the teapot alone, rendered natively, covers a pixel, the
    // picture has that pixel's colour; and it is shaded (many colours).
    let [_, _, _, pot] = hud_gauge::meshes().unwrap();
    let scene = hud_gauge::teapot_scene(&pot).unwrap();
    let area = hud_gauge::TEAPOT;
    let (tw, th) = (area.size.width, area.size.height);
    let n = (tw * th) as usize;
    let mut mask = vec![false; n];
    let mut colors = HashSet::new();
    let mut covered = 0;
    {
        let bg = Rgb565Le::pack(0, 0, 0);
        let mut color = vec![bg; n];
        let mut depth = vec![0xFFFFu16; n];
        let mut cache = vec![XfVertex::default(); scene.vertex_count()];
        let mut fb = Framebuffer::<Rgb565Le>::new(&mut color, Some(&mut depth), tw, th).unwrap();
        Renderer::new(&mut fb).draw(&scene, &mut cache).unwrap();
        for (i, d) in depth.iter().enumerate() {
            // A written pixel has a depth below the cleared 0xFFFF.
            mask[i] = *d != 0xFFFF;
        }
        for y in 0..th as i32 {
            for x in 0..tw as i32 {
                let i = (y as u32 * tw + x as u32) as usize;
                if !mask[i] {
                    continue;
                }
                covered += 1;
                let [r, g, b] = Rgb565Le::unpack(color[i]);
                let want = rgb8(Rgb565::new(r as u8, g as u8, b as u8));
                let got = at(area.top_left.x + x, area.top_left.y + y);
                assert_eq!(got, want, "teapot pixel {x},{y}");
                colors.insert(got);
            }
        }
    }
    assert!(covered > 4000, "{covered} teapot pixels");
    assert!(colors.len() > 100, "teapot has {} colours", colors.len());

    // The gauge: a shaded model inside its box (flat facets and the Gouraud hub:
    // more than a handful of colours that are neither background nor text).
    let g = hud_gauge::GAUGE;
    let bg = rgb8(hud_gauge::BACKGROUND);
    let gauge_colors: HashSet<[u8; 3]> = g
        .points()
        .map(|p| at(p.x, p.y))
        .filter(|c| *c != bg && *c != text)
        .collect();
    assert!(
        gauge_colors.len() > 30,
        "gauge has {} colours",
        gauge_colors.len()
    );
    std::fs::remove_dir_all(&dir).ok();
}
