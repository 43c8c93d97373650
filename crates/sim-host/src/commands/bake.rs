//! `fixshade bake`: an OBJ, scene file or built-in scene as Rust source of static
//! arrays in the core's fixed-point formats (for flash).

use std::fmt::Write as _;
use std::path::Path;

use super::{fail, CliError};
use crate::render::bake::bake;

/// Bakes `input` (split into chunks of at most `chunk` vertices) into `output`;
/// returns the flash size and a line per object.
pub fn run(input: &str, output: &Path, chunk: Option<usize>) -> Result<String, CliError> {
    let mut command = format!("fixshade bake {input}");
    if let Some(n) = chunk {
        let _ = write!(command, " --chunk {n}");
    }
    let b = bake(input, chunk, &command).map_err(fail)?;
    if let Some(dir) = output.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| fail(format!("cannot create {}: {e}", dir.display())))?;
    }
    std::fs::write(output, &b.source)
        .map_err(|e| fail(format!("cannot write {}: {e}", output.display())))?;
    Ok(format!(
        "{input}: {} bytes of flash -> {}\n{}",
        b.flash_bytes,
        output.display(),
        b.summary.trim_end()
    ))
}
