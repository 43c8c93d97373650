//! The measurement commands: `fixshade report`, `specular`, `effects` and
//! `raycast-table`, each writing its document.

use std::path::{Path, PathBuf};

use super::{fail, CliError};
use crate::tables::{effects, raycast, report, specular};

/// `fixshade report`: accuracy against time, into `out` (default docs/, or
/// out/report-quick/ with `quick`), the MCU columns from `mcu_csv` (default
/// docs/mcu-instructions.csv).
pub fn report(
    quick: bool,
    out: Option<PathBuf>,
    mcu_csv: Option<PathBuf>,
) -> Result<String, CliError> {
    let mut opts = if quick {
        report::ReportOptions::quick()
    } else {
        report::ReportOptions::full()
    };
    if let Some(dir) = out {
        opts.out_dir = dir;
    }
    if let Some(csv) = mcu_csv {
        opts.mcu_csv = csv;
    }
    let r = report::run_report(&opts).map_err(fail)?;
    let files: Vec<String> = r.files.iter().map(|p| p.display().to_string()).collect();
    Ok(format!(
        "{}\n\n{}\nwrote {}",
        r.table,
        r.summary,
        files.join(", ")
    ))
}

/// `fixshade specular`: the specular models against cⁿ, into `out` (default docs/,
/// or out/specular-quick/ with `quick`), instructions per evaluation from `mcu_csv`
/// (default docs/mcu-specular.csv).
pub fn specular(
    quick: bool,
    out: Option<PathBuf>,
    mcu_csv: Option<PathBuf>,
) -> Result<String, CliError> {
    let mut opts = if quick {
        specular::TableOptions::quick()
    } else {
        specular::TableOptions::full()
    };
    if let Some(dir) = out {
        opts.out_dir = dir;
    }
    if let Some(csv) = mcu_csv {
        opts.mcu_csv = csv;
    }
    specular::summary(&opts, quick).map_err(fail)
}

/// `fixshade effects`: the effects table into `out` (default docs/effects.md, or
/// out/effects-quick.md with `quick`).
pub fn effects(quick: bool, out: Option<&Path>) -> Result<String, CliError> {
    effects::write_table(out, quick).map_err(fail)
}

/// `fixshade raycast-table`: pixel-segment ray casting measured into `out`, each
/// time the median of `runs` frames.
pub fn raycast_table(out: &Path, runs: usize) -> Result<String, CliError> {
    let md = raycast::write_table(out, runs, &raycast::TABLE_SCENES).map_err(fail)?;
    Ok(format!("{md}\nwrote {}", out.display()))
}
