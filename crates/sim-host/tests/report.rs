//! `fixshade report --quick` in miniature: one figure, one timing run, MCU counts
//! from a fixture written here (distinct made-up numbers, so each cell can be traced
//! to its CSV row), into a temporary directory; checks the files it writes.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use fixshade_sim::image::Image;
use fixshade_sim::scene::desc::{Named, SpanName, SpecularName};
use fixshade_sim::tables::report::mcu::{key, BOARDS};
use fixshade_sim::tables::report::text::{CSV_HEADER, SUMMARY_WORDS};
use fixshade_sim::tables::report::{self, Config, ReportOptions};
use fixshade_sim::tables::specular::NS;

/// The made-up count of configuration `i` on core `k`.
fn count(k: usize, i: usize) -> f64 {
    1000.0 * (k + 1) as f64 + i as f64 + 0.25
}

/// An instruction table with a row for every configuration, `skip` excepted.
fn fixture(dir: &Path, configs: &[Config], skip: Option<usize>) -> (PathBuf, PathBuf) {
    let mut s = String::from(
        "board,figure,method,width,height,triangles,drawn,pixels,prepare,draw,total,per_pixel,\
         per_triangle,draw_per_pixel,divide,sweep,layout,helpers,shading,specular,shininess\n",
    );
    for (k, (board, _)) in BOARDS.iter().enumerate() {
        for (i, c) in configs.iter().enumerate() {
            if Some(i) == skip {
                continue;
            }
            let m = key(board, "sphere", c);
            let _ = writeln!(
                s,
                "{board},sphere,{},320,240,1,1,1,1,1,1,{:.2},1,{:.2},{},{},full,0,{},{},{}",
                m.method,
                count(k, i),
                count(k, i) / 2.0,
                m.divide,
                m.sweep,
                m.shading,
                m.specular,
                m.shininess
            );
        }
    }
    let mcu = dir.join("mcu.csv");
    std::fs::write(&mcu, s).unwrap();
    let mut sp = String::from("board,model,n,evals,instructions,per_eval\n");
    for (board, _) in BOARDS {
        for (mi, (_, model)) in SpecularName::ALL.iter().enumerate() {
            for n in NS {
                let _ = writeln!(sp, "{board},{model},{n},10,100,{}.00", 10 + mi);
            }
        }
    }
    let msp = dir.join("mcu-specular.csv");
    std::fs::write(&msp, sp).unwrap();
    (mcu, msp)
}

fn options(dir: &Path, mcu: PathBuf, msp: PathBuf) -> ReportOptions {
    ReportOptions {
        out_dir: dir.to_path_buf(),
        rounds: 1,
        runs_per_round: 1,
        progress: false,
        mcu_csv: mcu,
        mcu_specular_csv: msp,
        specular_csv: Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/specular.csv"),
        ..ReportOptions::quick()
    }
}

#[test]
fn quick_report_writes_table_csv_and_charts() {
    let dir = std::env::temp_dir().join(format!("fixshade-report-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let configs = report::configurations(true, report::specular_rows("sphere"));
    let (mcu, msp) = fixture(&dir, &configs, None);
    let opts = options(&dir, mcu, msp);
    let r = report::run_report(&opts).expect("report runs");
    assert_eq!(r.rows.len(), configs.len());

    let md = std::fs::read_to_string(dir.join("accuracy-vs-time.md")).expect("markdown");
    let csv = std::fs::read_to_string(dir.join("accuracy-vs-time.csv")).expect("csv");

    // CSV: one row per configuration, every MCU cell the fixture's number for it.
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, CSV_HEADER.split(',').collect::<Vec<_>>());
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), configs.len());
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), header.len(), "{row:?}");
        assert_eq!(row[col("configuration")], configs[i].name());
        for (k, c) in ["instr_per_px_armv6m", "instr_per_px_m4"]
            .iter()
            .enumerate()
        {
            assert_eq!(
                row[col(c)].parse::<f64>().ok(),
                Some(count(k, i)),
                "{row:?}"
            );
        }
        let nmse: f64 = row[col("nmse")].parse().expect("NMSE parses");
        assert!(nmse >= 0.0);
    }
    for kind in [
        "span",
        "shading",
        "divide",
        "setup",
        "specular",
        "perspective",
    ] {
        assert!(
            rows.iter().any(|r| r[col("kind")] == kind),
            "no {kind} rows"
        );
    }
    for (_, span) in SpanName::ALL {
        assert!(md.contains(&format!("`{span}`")), "span {span} missing");
    }

    // Markdown: the summary is short; then the recommendations, the charts, the
    // claims and every row; no placeholder anywhere; the commit is stated.
    let before_table: String = md
        .lines()
        .take_while(|l| !l.starts_with('|'))
        .collect::<Vec<_>>()
        .join("\n");
    let words = before_table.split_whitespace().count();
    assert!(
        words <= SUMMARY_WORDS,
        "{words} words before the first table"
    );
    assert!(before_table.contains("Made from ") && before_table.contains("commit"));
    assert!(md.contains("| you need | pick |"));
    assert!(md.contains("accuracy-vs-time-m4.png") && md.contains("accuracy-vs-time-m0.png"));
    assert!(md.contains("| counter-2x |"), "claims table");
    let all_rows = md.split("## All rows").nth(1).expect("full table");
    assert!(!all_rows.contains("not measured"), "a placeholder MCU cell");
    assert!(md.contains("report --quick"));
    let gradient = "| sphere | span | `gradient` |";
    let line = md
        .lines()
        .find(|l| l.starts_with(gradient))
        .expect("gradient row");
    let gi = configs
        .iter()
        .position(|c| c.kind == report::Kind::Span && c.span == SpanName::GRADIENT)
        .unwrap();
    assert!(
        line.contains(&format!("| {:.1} | {:.1} |", count(0, gi), count(1, gi))),
        "{line}"
    );

    for f in [
        "accuracy-vs-time-m4.png",
        "accuracy-vs-time-m0.png",
        "accuracy-vs-time.png",
    ] {
        let img = Image::read_png(&dir.join(f)).expect("PNG decodes");
        assert!(img.width >= 800 && img.height >= 500, "{f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_missing_mcu_row_fails_naming_board_figure_and_configuration() {
    let dir = std::env::temp_dir().join(format!("fixshade-report-missing-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let configs = report::configurations(true, report::specular_rows("sphere"));
    let i = configs
        .iter()
        .position(|c| c.kind == report::Kind::Shading)
        .unwrap();
    let (mcu, msp) = fixture(&dir, &configs, Some(i));
    let e = report::run_report(&options(&dir, mcu, msp)).unwrap_err();
    assert!(e.contains(&format!("board {}", BOARDS[0].0)), "{e}");
    assert!(e.contains("figure sphere"), "{e}");
    assert!(e.contains(&format!("`{}`", configs[i].name())), "{e}");
    assert!(!dir.join("accuracy-vs-time.md").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
