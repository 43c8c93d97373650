//! The committed generated documents are current: `docs/accuracy-vs-time.*` and
//! `docs/specular.csv` match what `fixshade report` and `fixshade specular` compute
//! from this tree, host times and the provenance line excepted
//! (`fixshade_sim::tables::report::currency`).

use std::path::Path;

use fixshade_sim::tables::report::currency;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

#[test]
fn accuracy_vs_time_is_current() {
    if let Err(e) = currency::check_report(root()) {
        panic!("{e}");
    }
}

#[test]
fn specular_table_is_current() {
    if let Err(e) = currency::check_specular(root()) {
        panic!("{e}");
    }
}
