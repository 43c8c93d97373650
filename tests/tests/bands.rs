//! Bands give the whole frame's bytes (issue: bands for free).
//!
//! * Every figure, the fill-bound bench sphere at 640×480 and every scene of the
//!   hard-case catalogue, Gouraud and flat, binned once ([`Frame::bin`]) and drawn
//!   band by band in bands of 1, 2, 16 and 240 rows: colour and depth byte for byte
//!   equal to one whole-frame draw, every triangle set up once (the binning counts
//!   the triangles once; no band re-walks). The same with no band memory (every band
//!   re-walks) and with too little (it falls back, reported); and with the edge
//!   walks carried from band to band ([`Binned::draw_band_resuming`]), the bands
//!   drawn top to bottom (from the records alone, [`Binned::into_bins`]), even then
//!   odd, and bottom to top.
//! * Two threads drawing alternate bands of one binned frame give the bytes one
//!   thread gives.
//! * Every triangle of the triangle catalogue, set up once into a record and drawn
//!   strip by strip, gives the whole framebuffer's bytes.

use fixshade::raster::setup::{setup, Record};
use fixshade::raster::span::{DepthTest, Gradient, NoDepth};
use fixshade::raster::{draw_record, ScreenVertex, Walk, GUARD};
use fixshade::render::{BandMemory, Binned, Frame, Stats, XfVertex};
use fixshade::scene::{Scene, ShadingMode};
use fixshade::shade::Gouraud;
use fixshade::target::{Framebuffer, PixelFormat, Rgb565Le, Rgb888, Strip};
use fixshade_sim::scene::convert::core_scene;
use fixshade_sim::scene::load::{load_arg, LoadedScene};
use fixshade_tests::catalogue::{scene_cases, triangle_cases};
use fixshade_tests::FIGURES;

const BANDS: [u32; 4] = [1, 2, 16, 240];

/// Colour and depth of a whole-frame draw, and its statistics.
fn whole<P: PixelFormat>(scene: &Scene<'_>, w: u32, h: u32) -> (Vec<P::Raw>, Vec<u16>, Stats) {
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let frame = Frame::<P>::prepare(scene, w, h, &mut cache).unwrap();
    let (mut c, mut d) = (
        vec![P::Raw::default(); (w * h) as usize],
        vec![0u16; (w * h) as usize],
    );
    let mut fb = Framebuffer::<P>::new(&mut c, Some(&mut d), w, h).unwrap();
    fb.clear(P::pack(1, 2, 3));
    let st = frame.draw::<Gradient, _>(&mut fb).unwrap();
    (c, d, st)
}

/// How the bands are drawn: each on its own ([`Binned::draw_band`], top to
/// bottom), or resuming the edge walks ([`Binned::draw_band_resuming`], with a walk
/// per record) in an order.
#[derive(Copy, Clone, Debug, PartialEq)]
enum Walks {
    None,
    TopToBottom,
    EvenThenOdd,
    BottomToTop,
}

impl Walks {
    fn order(self, bands: u32) -> Vec<u32> {
        match self {
            Walks::None | Walks::TopToBottom => (0..bands).collect(),
            Walks::EvenThenOdd => (0..bands).step_by(2).chain((1..bands).step_by(2)).collect(),
            Walks::BottomToTop => (0..bands).rev().collect(),
        }
    }
}

/// Colour and depth drawn band by band from one binning into `records` records
/// (and an index as large as it needs), with the statistics summed.
fn banded<P: PixelFormat>(
    scene: &Scene<'_>,
    (w, h): (u32, u32),
    rows: u32,
    records: usize,
    walks: Walks,
) -> (Vec<P::Raw>, Vec<u16>, Stats, bool) {
    let mut rec = vec![Record::EMPTY; records];
    let mut index = vec![0u16; BandMemory::index_len(records, h + 32, rows, h + 32)];
    let mut starts = vec![0u32; BandMemory::starts_len(h + 32, rows)];
    let mut walk = vec![Walk::EMPTY; if walks == Walks::None { 0 } else { records }];
    // With walks, the same memory first draws the frame 32 rows taller (other
    // triangles, other edges): binning the frame asked for must forget the walks
    // that drawing left there.
    if walks != Walks::None {
        let mem = BandMemory::new(&mut rec, &mut index, &mut starts).with_walks(&mut walk);
        draw_bands::<P>(scene, (w, h + 32), rows, mem, walks);
    }
    let mem = BandMemory::new(&mut rec, &mut index, &mut starts).with_walks(&mut walk);
    draw_bands::<P>(scene, (w, h), rows, mem, walks)
}

/// [`banded`] into `mem`.
fn draw_bands<P: PixelFormat>(
    scene: &Scene<'_>,
    (w, h): (u32, u32),
    rows: u32,
    mem: BandMemory<'_>,
    walks: Walks,
) -> (Vec<P::Raw>, Vec<u16>, Stats, bool) {
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let frame = Frame::<P>::prepare(scene, w, h, &mut cache).unwrap();
    let binned: Binned<'_, '_, '_, '_, '_, P, _> = frame.bin(rows, mem).unwrap();
    let (mut c, mut d) = (
        vec![P::Raw::default(); (w * h) as usize],
        vec![0u16; (w * h) as usize],
    );
    let mut st = binned.stats();
    let complete = binned.complete();
    // Top to bottom, a complete binning draws from its records without the frame.
    let (mut binned, mut bins) = if walks == Walks::TopToBottom && complete {
        (None, Some(binned.into_bins().unwrap()))
    } else {
        (Some(binned), None)
    };
    for band in walks.order(BandMemory::bands(h, rows) as u32) {
        let r = (band * rows).min(h)..((band + 1) * rows).min(h);
        let span = (r.start * w) as usize..(r.end * w) as usize;
        let mut strip = Strip::<P>::new(
            &mut c[span.clone()],
            Some(&mut d[span]),
            w,
            h,
            r.start,
            r.len() as u32,
        )
        .unwrap();
        strip.clear(P::pack(1, 2, 3));
        st += if let Some(bins) = &mut bins {
            assert_eq!(bins.rows(band), r);
            bins.draw_band_resuming(band, &mut strip).unwrap()
        } else if let Some(binned) = &mut binned {
            assert_eq!(binned.rows(band), r);
            if walks == Walks::None {
                binned.draw_band::<Gradient, _>(band, &mut strip).unwrap()
            } else {
                binned
                    .draw_band_resuming::<Gradient, _>(band, &mut strip)
                    .unwrap()
            }
        } else {
            unreachable!("either the binned frame or its records")
        };
    }
    if let Some(binned) = binned {
        // The records without the frame exist exactly when the binning is complete.
        assert_eq!(binned.into_bins().is_some(), complete);
    }
    (c, d, st, complete)
}

/// The whole frame against bands of every height, with enough, no and too little
/// band memory.
fn check_scene<P: PixelFormat>(name: &str, ls: &LoadedScene) {
    let d = &ls.desc;
    let scene = core_scene(d, &ls.fixed).unwrap();
    let (w, h) = (d.width, d.height);
    let (wc, wd, ws) = whole::<P>(&scene, w, h);
    let binnable = matches!(scene.shading, ShadingMode::Gouraud | ShadingMode::Flat);
    // Drawn triangles after clipping: at most seven pieces each.
    let enough = ws.triangles as usize * 7 + 1;
    for rows in BANDS {
        for (records, what, walks) in [
            (enough, "records", Walks::None),
            (enough, "walks", Walks::TopToBottom),
            (enough, "walks, even then odd", Walks::EvenThenOdd),
            (enough, "walks, bottom to top", Walks::BottomToTop),
            (0, "no memory", Walks::None),
            (ws.drawn as usize / 2, "too few", Walks::None),
            (ws.drawn as usize / 2, "too few, walks", Walks::TopToBottom),
        ] {
            let (bc, bd, bs, complete) = banded::<P>(&scene, (w, h), rows, records, walks);
            assert!(
                bc == wc,
                "{name}: {rows}-row bands ({what}): colour differs"
            );
            assert!(bd == wd, "{name}: {rows}-row bands ({what}): depth differs");
            assert_eq!(bs.pixels, ws.pixels, "{name}: {rows}-row bands ({what})");
            let bands = h.div_ceil(rows);
            if binnable && records == enough {
                assert!(complete, "{name}: not binned with {records} records");
                assert_eq!(
                    (bs.triangles, bs.drawn, bs.culled, bs.rewalked),
                    (ws.triangles, ws.drawn, ws.culled, 0),
                    "{name}: {rows}-row bands: each triangle once"
                );
            } else if ws.drawn > 1 || !binnable {
                assert!(!complete, "{name} ({what})");
                assert_eq!(bs.rewalked, bands, "{name}: {rows}-row bands ({what})");
            }
        }
    }
}

#[test]
fn figures_in_bands_equal_whole_frame() {
    for name in FIGURES {
        let mut ls = load_arg(name).unwrap();
        check_scene::<Rgb565Le>(name, &ls);
        ls.desc.shading = fixshade_sim::scene::desc::ShadingName::FLAT;
        check_scene::<Rgb888>(&format!("{name} flat"), &ls);
    }
    let mut ls = load_arg("bench-sphere").unwrap();
    ls.desc.width = 640;
    ls.desc.height = 480;
    check_scene::<Rgb565Le>("bench-sphere 640x480", &ls);
}

#[test]
fn scene_catalogue_in_bands_equals_whole_frame() {
    for case in scene_cases() {
        let ls = case.load().unwrap();
        check_scene::<Rgb565Le>(&case.name, &ls);
    }
}

/// Two threads draw the even and the odd bands of one binned frame into their own
/// strips: the bytes of one thread drawing them all.
#[test]
fn two_threads_draw_alternate_bands() {
    let mut ls = load_arg("teapot").unwrap();
    ls.desc.width = 320;
    ls.desc.height = 240;
    let scene = core_scene(&ls.desc, &ls.fixed).unwrap();
    let (w, h, rows) = (320u32, 240u32, 16u32);
    let (one, _, _, _) = banded::<Rgb565Le>(&scene, (w, h), rows, 20_000, Walks::None);
    let mut cache = vec![XfVertex::default(); scene.vertex_count()];
    let frame = Frame::<Rgb565Le>::prepare(&scene, w, h, &mut cache).unwrap();
    let mut rec = vec![Record::EMPTY; 20_000];
    let mut index = vec![0u16; BandMemory::index_len(20_000, h, rows, h)];
    let mut starts = vec![0u32; BandMemory::starts_len(h, rows)];
    let binned = frame
        .bin(rows, BandMemory::new(&mut rec, &mut index, &mut starts))
        .unwrap();
    assert!(binned.complete());
    let bands = binned.bands();
    let draw = |parity: u32| -> Vec<(u32, Vec<u16>)> {
        let mut out = Vec::new();
        let (mut c, mut d) = (
            vec![0u16; (w * rows) as usize],
            vec![0u16; (w * rows) as usize],
        );
        for band in (parity..bands).step_by(2) {
            let r = binned.rows(band);
            let n = (r.len() as u32 * w) as usize;
            let mut strip = Strip::<Rgb565Le>::new(
                &mut c[..n],
                Some(&mut d[..n]),
                w,
                h,
                r.start,
                r.len() as u32,
            )
            .unwrap();
            strip.clear(Rgb565Le::pack(1, 2, 3));
            binned.draw_band::<Gradient, _>(band, &mut strip).unwrap();
            out.push((band, c[..n].to_vec()));
        }
        out
    };
    let (even, odd) = std::thread::scope(|s| {
        let even = s.spawn(|| draw(0));
        let odd = s.spawn(|| draw(1));
        (even.join().unwrap(), odd.join().unwrap())
    });
    let mut two = vec![0u16; (w * h) as usize];
    for (band, c) in even.into_iter().chain(odd) {
        let y0 = (band * rows * w) as usize;
        two[y0..y0 + c.len()].copy_from_slice(&c);
    }
    assert!(two == one, "two threads differ from one");
}

/// The triangle catalogue: each triangle set up once into a record, drawn strip by
/// strip in strips of 1, 2, 16 and 240 rows (and the frame's height), equals the
/// triangles drawn into one framebuffer, with and without the depth test.
#[test]
fn triangle_catalogue_records_in_bands_equal_whole_frame() {
    for case in triangle_cases() {
        let [w, h] = case.frame;
        if (w as u64) * (h as u64) > 4096 * 256 {
            continue; // the 4095×4095 frame: covered by the strip tests
        }
        let tris: Vec<[ScreenVertex; 3]> = case.triangles();
        // As the rasterizer does: a triangle outside the guard band is not drawn.
        let inside = |t: &&[ScreenVertex; 3]| {
            t.iter()
                .all(|p| p.x.unsigned_abs() < GUARD as u32 && p.y.unsigned_abs() < GUARD as u32)
        };
        let records: Vec<Record> = tris
            .iter()
            .filter(inside)
            .filter_map(|t| setup(*t))
            .map(|s| Record::of(&s))
            .collect();
        for depth in [false, true] {
            let n = (w * h) as usize;
            let (mut c, mut d) = (vec![[0u8; 3]; n], vec![0xFFFFu16; n]);
            {
                let mut fb = Framebuffer::<Rgb888>::new(&mut c, Some(&mut d), w, h).unwrap();
                for r in &records {
                    if depth {
                        draw_record::<Rgb888, _, DepthTest, Gouraud>(&mut fb, r);
                    } else {
                        draw_record::<Rgb888, _, NoDepth, Gouraud>(&mut fb, r);
                    }
                }
            }
            for rows in BANDS.into_iter().chain([h]) {
                let rows = rows.min(h);
                let (mut bc, mut bd) = (vec![[0u8; 3]; n], vec![0xFFFFu16; n]);
                let mut y0 = 0;
                while y0 < h {
                    let r = rows.min(h - y0);
                    let span = (y0 * w) as usize..((y0 + r) * w) as usize;
                    let mut strip = Strip::<Rgb888>::new(
                        &mut bc[span.clone()],
                        Some(&mut bd[span]),
                        w,
                        h,
                        y0,
                        r,
                    )
                    .unwrap();
                    for rec in &records {
                        if depth {
                            draw_record::<Rgb888, _, DepthTest, Gouraud>(&mut strip, rec);
                        } else {
                            draw_record::<Rgb888, _, NoDepth, Gouraud>(&mut strip, rec);
                        }
                    }
                    y0 += r;
                }
                assert!(
                    bc == c && bd == d,
                    "{}: {rows}-row strips (depth {depth})",
                    case.name
                );
            }
        }
    }
}
