//! The one PNG writer (and reader) of the simulator: 8-bit RGB images, still or
//! animated, with optional text chunks.

use std::io::BufWriter;
use std::path::Path;

/// An 8-bit RGB PNG read back: size, pixels (grey and alpha expanded or dropped) and
/// its Latin-1 text chunks.
pub struct Decoded {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major pixels.
    pub pixels: Vec<[u8; 3]>,
    /// `(keyword, text)` of each uncompressed text chunk.
    pub text: Vec<(String, String)>,
}

fn create(path: &Path) -> Result<BufWriter<std::fs::File>, String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    let file = std::fs::File::create(path)
        .map_err(|e| format!("cannot create {}: {e}", path.display()))?;
    Ok(BufWriter::new(file))
}

/// Writes `frames` (each `width · height · 3` bytes of RGB) as a PNG: one frame is a
/// still image, several an animation at `fps` frames per second looping forever.
/// `text` becomes uncompressed text chunks. Creates the parent directory.
pub fn write_rgb(
    path: &Path,
    width: u32,
    height: u32,
    frames: &[&[u8]],
    fps: u16,
    text: &[(&str, String)],
) -> Result<(), String> {
    let err = |e: png::EncodingError| format!("cannot write {}: {e}", path.display());
    let mut enc = png::Encoder::new(create(path)?, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    for (keyword, t) in text {
        enc.add_text_chunk(keyword.to_string(), t.clone())
            .map_err(err)?;
    }
    if frames.len() > 1 {
        enc.set_animated(frames.len() as u32, 0).map_err(err)?;
        enc.set_frame_delay(1, fps.max(1)).map_err(err)?;
    }
    let mut w = enc.write_header().map_err(err)?;
    for f in frames {
        w.write_image_data(f).map_err(err)?;
    }
    w.finish().map_err(err)
}

/// One 8-bit RGB frame (`width · height · 3` bytes) encoded as PNG bytes.
pub fn encode_rgb(width: u32, height: u32, rgb: &[u8]) -> Result<Vec<u8>, String> {
    let err = |e: png::EncodingError| format!("cannot encode a PNG: {e}");
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, width, height);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(err)?;
    w.write_image_data(rgb).map_err(err)?;
    w.finish().map_err(err)?;
    Ok(out)
}

/// Reads a PNG (8-bit RGB or RGBA, or grey; 16-bit samples are stripped to 8).
pub fn read_rgb(path: &Path) -> Result<Decoded, String> {
    let file =
        std::fs::File::open(path).map_err(|e| format!("cannot open {}: {e}", path.display()))?;
    let mut dec = png::Decoder::new(std::io::BufReader::new(file));
    dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = dec
        .read_info()
        .map_err(|e| format!("{} is not a readable PNG: {e}", path.display()))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| format!("{} is too large to read", path.display()))?;
    let mut buf = vec![0u8; size];
    let info = reader
        .next_frame(&mut buf)
        .map_err(|e| format!("{} is not a readable PNG: {e}", path.display()))?;
    let (w, h) = (info.width, info.height);
    let stride = info.line_size;
    let channels = info.color_type.samples();
    let mut pixels = Vec::with_capacity(w as usize * h as usize);
    for y in 0..h as usize {
        let row = &buf[y * stride..y * stride + w as usize * channels];
        for px in row.chunks_exact(channels) {
            pixels.push(match channels {
                1 | 2 => [px[0], px[0], px[0]],
                _ => [px[0], px[1], px[2]],
            });
        }
    }
    let text = reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect();
    Ok(Decoded {
        width: w,
        height: h,
        pixels,
        text,
    })
}
