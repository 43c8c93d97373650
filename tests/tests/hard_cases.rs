//! The hard-case catalogue (`tests/catalogue/`), run with every span method and
//! shading mode into targets with a guard region: no panic (overflow checks are on
//! in the dev profile; the release run checks the wrapping build), no write outside
//! the target, and what each case lists under `holds` (exact coverage,
//! watertightness, colour and depth within their bounds of the exact values,
//! strip = frame, first-wins depth ties). See `fixshade_tests::hard`.

use fixshade_tests::catalogue::{self, TRI_HOLDS};
use fixshade_tests::hard::{check_all, Case, Figures, Holds};

#[test]
fn triangle_catalogue() {
    let cases = catalogue::triangle_cases();
    assert!(
        cases.len() >= 30,
        "the catalogue lost cases: {}",
        cases.len()
    );
    let mut names = std::collections::HashSet::new();
    let mut total = Figures::default();
    let mut failures = Vec::new();
    for tc in &cases {
        assert!(names.insert(tc.name.clone()), "duplicate case {}", tc.name);
        for w in &tc.holds {
            assert!(
                TRI_HOLDS.contains(&w.as_str()),
                "{}: unknown holds word `{w}`",
                tc.name
            );
        }
        let c = Case {
            frame: (tc.frame[0], tc.frame[1]),
            strip: tc.strip(),
            tris: tc.triangles(),
            holds: Holds::from_words(&tc.holds),
        };
        match check_all(&c) {
            Ok(f) => {
                println!(
                    "{:32} {:>9} coverage, {:>9} colour (max |err| {:.4}), {:>8} depth checks",
                    tc.name, f.coverage_checks, f.colour_checks, f.max_colour_err, f.depth_checks
                );
                total += f;
            }
            Err(e) => failures.push(format!("{}: {e}", tc.name)),
        }
    }
    println!("{} cases: {total:?}", cases.len());
    assert!(
        failures.is_empty(),
        "{} failing cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Renders a scene case with every span method and shading mode, whole frame and in
/// strips, and checks its `holds`.
#[test]
fn scene_catalogue() {
    use fixshade_sim::image::compare::compare;
    use fixshade_sim::render::{reference, render};
    use fixshade_sim::scene::desc::{Named, ShadingName};

    let cases = catalogue::scene_cases();
    assert!(
        cases.len() >= 12,
        "the catalogue lost cases: {}",
        cases.len()
    );
    let mut failures = Vec::new();
    for sc in &cases {
        for w in &sc.holds {
            assert!(
                catalogue::SCENE_HOLDS.contains(&w.as_str()),
                "{}: unknown holds word `{w}`",
                sc.name
            );
        }
        let mut ls = sc.load().unwrap_or_else(|e| panic!("{e}"));
        let mut check = || -> Result<String, String> {
            let mut covered = 0;
            for (shading, _) in ShadingName::ALL {
                for (span, sname) in fixshade_sim::scene::desc::SpanName::ALL {
                    ls.desc.shading = *shading;
                    ls.desc.span = *span;
                    let what = format!("{} {sname}", shading.name());
                    let whole = render(&ls, None);
                    let strips = render(&ls, Some(7));
                    let (whole, strips) = match (whole, strips) {
                        (Ok(a), Ok(b)) => (a, b),
                        (a, b) => {
                            if sc.holds("renders") {
                                return Err(format!(
                                    "{what}: render failed: {:?} / {:?}",
                                    a.err(),
                                    b.err()
                                ));
                            }
                            continue;
                        }
                    };
                    if sc.holds("strip") && whole.bytes != strips.bytes {
                        return Err(format!("{what}: strips differ from the whole frame"));
                    }
                    let n = whole.image.covered_count();
                    covered = covered.max(n);
                    if sc.holds("empty") && n != 0 {
                        return Err(format!("{what}: {n} pixels covered, expected none"));
                    }
                    // Sierpinski snaps vertices to even pixels: a tiny object may vanish.
                    let snaps = *span == fixshade_sim::scene::desc::SpanName::named("sierpinski");
                    // The ray caster skips mesh triangles with a vertex behind the
                    // eye, where the rasterizer clips them (a known limitation of
                    // `fixshade::raycast`): in this case every triangle crosses the
                    // eye plane, so its ray-cast image is empty.
                    let caster_skips = *shading == ShadingName::RAYCAST && sc.name == "w-near-zero";
                    if sc.holds("nonempty") && n == 0 && !snaps && !caster_skips {
                        return Err(format!("{what}: nothing covered"));
                    }
                    let gradient = *span == fixshade_sim::scene::desc::SpanName::GRADIENT;
                    if gradient && *shading == ShadingName::GOURAUD {
                        let r = reference(&ls, false);
                        let c = compare(&r, &whole.image)?;
                        if sc.holds("coverage") && c.coverage_mismatch != 0 {
                            return Err(format!(
                                "{what}: coverage differs from the reference at {} pixels",
                                c.coverage_mismatch
                            ));
                        }
                        if sc.holds("reference") {
                            let max = sc.nmse_max.expect("nmse_max");
                            if c.nmse > max {
                                return Err(format!("{what}: NMSE {:.3e} > {max:e}", c.nmse));
                            }
                        }
                    }
                }
            }
            Ok(format!("max covered {covered}"))
        };
        match check() {
            Ok(s) => println!("{:32} {s}", sc.name),
            Err(e) => failures.push(format!("{}: {e}", sc.name)),
        }
    }
    assert!(
        failures.is_empty(),
        "{} failing cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// Specular exponents n = 1 and n = 1000 with N·H at and within one LSB (Q2.30,
/// and the Q2.14 normal grid's 2⁻¹⁴) of 0 and of 1, every model: no panic, the
/// result in [0, 1] (energy-conserving: [0, 2)), non-decreasing in `c`, exactly 1 at
/// c = 1 (except the energy-conserving form, which peaks higher), and `exact`
/// within its stated relative error n·2⁻²⁹ of `cⁿ`.
#[test]
fn specular_extremes() {
    use fixshade::fixed::Q16_16;
    use fixshade::specular::*;
    const ONE: i32 = 1 << 30;
    let cs = [
        0,
        1,
        2,
        1 << 16,
        ONE / 2,
        ONE - (1 << 16),
        ONE - 2,
        ONE - 1,
        ONE,
    ];
    fn run<S: Specular>(name: &str, n: i32, cs: &[i32], top: i64, one_at_one: bool) -> Vec<i32> {
        let p = S::prepare(Q16_16::from_int(n));
        let v: Vec<i32> = cs.iter().map(|c| S::eval(&p, *c)).collect();
        for (c, r) in cs.iter().zip(&v) {
            assert!((0..top).contains(&(*r as i64)), "{name} n={n} c={c}: {r}");
        }
        assert!(
            v.windows(2).all(|w| w[0] <= w[1]),
            "{name} n={n}: not monotone {v:?}"
        );
        if one_at_one {
            assert_eq!(*v.last().unwrap(), ONE, "{name} n={n} at c = 1");
        }
        v
    }
    for n in [1, 1000] {
        let e = run::<BlinnExact>("exact", n, &cs, ONE as i64 + 1, true);
        for (c, got) in cs.iter().zip(&e) {
            let want = (*c as f64 / ONE as f64).powi(n) * ONE as f64;
            let tol = want * n as f64 * 2f64.powi(-29) + 2.0;
            assert!(
                (*got as f64 - want).abs() <= tol,
                "exact n={n} c={c}: {got}, want {want}"
            );
        }
        run::<Schlick>("schlick", n, &cs, ONE as i64 + 1, true);
        run::<SchlickModified>("schlick-mod", n, &cs, ONE as i64 + 1, true);
        run::<Quadratic>("quadratic", n, &cs, ONE as i64 + 1, true);
        run::<CosQuadratic>("cos-quad", n, &cs, ONE as i64 + 1, true);
        run::<CosQuadraticEnergy>("cos-quad-energy", n, &cs, 2 * ONE as i64, false);
    }
}

/// The fuzz seed corpora (`fuzz/seeds/<target>/`) are made from the catalogue.
/// They are regenerated with `FIXSHADE_WRITE_SEEDS=1`; otherwise this test fails
/// when they are missing or stale.
#[test]
fn fuzz_seeds_are_current() {
    use fixshade_tests::catalogue::raster_seed;
    let mut seeds: Vec<(String, Vec<u8>)> = Vec::new();
    for (i, tc) in catalogue::triangle_cases().iter().enumerate() {
        let (w, h) = (tc.frame[0].min(24), tc.frame[1].min(24));
        let (y0, rows) = tc.strip();
        let strip = (y0.min(h - 1), rows.min(h - y0.min(h - 1)));
        let tris = tc.triangles();
        // Raw coordinates, every shading and format, methods spread over the cases.
        for (j, flags) in [0b0000_0111u8, 0b0100_1000, 0b1000_0100, 0b1100_1101]
            .iter()
            .enumerate()
        {
            let method = ((i * 4 + j) % 15) as u8;
            seeds.push((
                format!("raster/{}-{j}", tc.name),
                raster_seed(method, *flags, w, h, strip, &tris),
            ));
        }
        // The Phong fills, affine and perspective-correct (without depth).
        seeds.push((
            format!("raster/{}-phong", tc.name),
            raster_seed(0x80, 0, w, h, strip, &tris),
        ));
    }
    for sc in catalogue::scene_cases() {
        let text = std::fs::read(catalogue::path(&sc.scene)).unwrap();
        seeds.push((format!("scene_file/{}", sc.name), text));
    }
    for name in fixshade_sim::scene::builtin::SCENES {
        let text = fixshade_sim::scene::builtin::text(name).unwrap();
        seeds.push((
            format!("scene_file/builtin-{name}"),
            text.as_bytes().to_vec(),
        ));
    }
    for p in obj_files() {
        let name = p.file_stem().unwrap().to_string_lossy().to_string();
        // The `obj` target's input: the OBJ text, then after a 0 byte the text of
        // the MTL file beside it, if there is one.
        let mut bytes = std::fs::read(&p).unwrap();
        if let Ok(mtl) = std::fs::read(p.with_extension("mtl")) {
            bytes.push(0);
            bytes.extend(mtl);
        }
        seeds.push((format!("obj/{name}"), bytes));
    }
    let cli: [&[&str]; 10] = [
        &[],
        &["help"],
        &["list"],
        &[
            "render", "sphere", "-o", "out.png", "--span", "kway4", "--strip", "7",
        ],
        &[
            "render",
            "x.toml",
            "--output",
            "o.png",
            "--shading",
            "quadratic",
            "--format",
            "gray8",
        ],
        &["reference", "teapot", "-o", "r.png", "--phong"],
        &["compare", "a.png", "b.png", "--json"],
        &["report", "--quick", "--out", "dir"],
        &["render", "sphere", "--strip", "0"],
        &["render", "--span"],
    ];
    for (i, args) in cli.iter().enumerate() {
        seeds.push((format!("cli_args/{i}"), args.join("\0").into_bytes()));
    }
    let root = fixshade_tests::package_path("../fuzz/seeds");
    let write = std::env::var_os("FIXSHADE_WRITE_SEEDS").is_some();
    let mut stale = Vec::new();
    for (rel, bytes) in &seeds {
        let p = root.join(rel);
        if write {
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(&p, bytes).unwrap();
        } else if std::fs::read(&p).ok().as_ref() != Some(bytes) {
            stale.push(rel.clone());
        }
    }
    assert!(
        stale.is_empty(),
        "fuzz seeds missing or stale (regenerate with FIXSHADE_WRITE_SEEDS=1): {stale:?}"
    );
}

/// Every OBJ file of the catalogue loads with a finite unit normal per vertex (the
/// `obj` fuzz target found NaN normals for huge finite coordinates) and the core
/// takes every part, except the files with coordinates beyond the core's range
/// ([`OUT_OF_RANGE`]), which the loader rejects naming the file, the line and the
/// range.
#[test]
fn obj_catalogue_normals_are_finite_units() {
    use fixshade_sim::scene::convert::{quantize_mesh, FixedMesh};
    let mut n = 0;
    for p in obj_files() {
        let file = p.file_name().unwrap().to_string_lossy().to_string();
        if let Some((_, line)) = OUT_OF_RANGE.iter().find(|(f, _)| *f == file) {
            let e = fixshade_sim::scene::mesh::load_obj(&p)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(&format!("{file}:{line}: vertex coordinate `"))
                    && e.contains("strictly between -16384 and 16384"),
                "{e}"
            );
            continue;
        }
        let parts = fixshade_sim::scene::mesh::load_obj(&p).unwrap_or_else(|e| panic!("{e}"));
        for part in &parts {
            for v in &part.mesh.normals {
                let len = v.iter().map(|c| c * c).sum::<f64>().sqrt();
                assert!((len - 1.0).abs() < 1e-9, "{}: normal {v:?}", p.display());
            }
            FixedMesh::from_mesh(&quantize_mesh(&part.mesh)).unwrap();
        }
        n += 1;
    }
    assert!(n >= 4);
}

/// Catalogue OBJ files with coordinates beyond the core's range, and the line the
/// loader's error names.
const OUT_OF_RANGE: [(&str, usize); 2] = [
    ("huge-coordinates.obj", 7),
    ("cancelling-infinite-normals.obj", 5),
];

/// The OBJ files of the catalogue (`meshes/*.obj`; their MTL files sit beside them).
fn obj_files() -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(catalogue::path("meshes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    files.sort();
    files
}
