//! `fixshade specular --quick` into a temporary directory: the page has a row per
//! model and n, the claims section, the reflectance rows, and the CSV and PNG exist.

use fixshade_sim::image::Image;
use fixshade_sim::scene::desc::{Named, SpecularName};
use fixshade_sim::tables::specular::{CSV_HEADER, NS};

#[test]
fn quick_table_writes_a_row_per_model_and_n_and_the_claims() {
    let dir = std::env::temp_dir().join(format!("fixshade-specular-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // Made-up instruction counts, distinct per model, so the cells can be traced.
    let mut mcu = String::from("board,model,n,evals,instructions,per_eval\n");
    for board in ["mps2-an385-v6m", "mps2-an386"] {
        for (mi, (_, model)) in SpecularName::ALL.iter().enumerate() {
            for n in NS {
                mcu.push_str(&format!(
                    "{board},{model},{n},10,100,{}.{mi}0\n",
                    if board == "mps2-an386" { 20 } else { 70 }
                ));
            }
        }
    }
    let mcu_path = dir.join("mcu-specular.csv");
    std::fs::write(&mcu_path, mcu).unwrap();
    let args: Vec<String> = [
        "specular",
        "--quick",
        "--out",
        dir.to_str().unwrap(),
        "--mcu-csv",
        mcu_path.to_str().unwrap(),
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let printed = fixshade_sim::cli::run(&args).expect("specular --quick runs");
    assert!(printed.contains("wrote"), "{printed}");

    let md = std::fs::read_to_string(dir.join("specular.md")).expect("specular.md");
    let csv = std::fs::read_to_string(dir.join("specular.csv")).expect("specular.csv");
    let mut csv_lines = csv.lines();
    assert_eq!(csv_lines.next(), Some(CSV_HEADER));
    assert_eq!(csv_lines.count(), SpecularName::ALL.len() * NS.len());
    for (mi, (_, name)) in SpecularName::ALL.iter().enumerate() {
        for n in NS {
            let prefix = format!("| {name} | {n} |");
            let rows: Vec<&str> = md.lines().filter(|l| l.starts_with(&prefix)).collect();
            assert_eq!(rows.len(), 1, "row {prefix} in\n{md}");
            assert!(
                rows[0].ends_with(&format!("| 70.{mi}0 | 20.{mi}0 |")),
                "{}",
                rows[0]
            );
            // 12 columns: every cell filled.
            assert_eq!(rows[0].matches('|').count(), 13, "{}", rows[0]);
            assert!(
                !rows[0].contains("NaN") && !rows[0].contains("inf"),
                "{}",
                rows[0]
            );
            assert!(
                csv.lines().any(|l| l.starts_with(&format!("{name},{n},"))
                    && l.ends_with(&format!(",70.{mi}0,20.{mi}0"))),
                "csv row {name},{n}"
            );
        }
    }
    let claims = md
        .split("## The seed's claims, measured")
        .nth(1)
        .expect("claims section");
    let claims = claims.split("\n## ").next().unwrap();
    for key in [
        "Schlick:",
        "modified Schlick:",
        "quadratic: relative error",
        "quadratic: NMSE",
        "cosine-quadratic: NMSE",
        "1.7× faster",
        "20 % faster frames",
        "energy-conserving form",
    ] {
        let line = claims
            .lines()
            .find(|l| l.contains(key))
            .unwrap_or_else(|| panic!("claim `{key}` in\n{claims}"));
        assert!(
            line.contains("**holds**") || line.contains("**does not hold**"),
            "{line}"
        );
    }
    assert!(md.contains("Made from "), "commit line");
    assert!(!md.contains("not measured"));
    assert!(
        md.contains("| n | R(0) | max over θ_i |"),
        "reflectance rows"
    );
    let png = Image::read_png(&dir.join("specular-reflectance.png")).expect("png");
    assert!(png.width > 100 && png.height > 100);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arguments_are_usage_errors() {
    let args: Vec<String> = ["specular", "--fast"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let e = fixshade_sim::cli::run(&args).unwrap_err();
    assert_eq!(e.code, 2);
    let args: Vec<String> = ["specular", "--out"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(fixshade_sim::cli::run(&args).unwrap_err().code, 2);
}
