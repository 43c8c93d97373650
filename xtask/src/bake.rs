//! `cargo xtask bake`: every file under `boards/baked/`, generated from its source
//! (the scenes, meshes and catalogues of the workspace) and never committed. The
//! firmware crates include them (`#[path = "../../baked/…"]`); `cargo xtask qemu`
//! bakes first, so the images always draw the current scenes.
//!
//! [`FILES`] is the list of what is baked: to give a board another scene, add a line
//! there and include the file in the board (see `boards/baked/README.md`).

use std::path::{Path, PathBuf};

use fixshade_sim::render::bake::{bake, bake_loaded};
use fixshade_sim::scene::load::load_arg;

/// How a scene's meshes are laid out for a board.
#[derive(Clone, Copy)]
pub enum Layout {
    /// Whole meshes (`boards/baked/full/`): the Cortex-M4 images and the real boards.
    Full,
    /// Runs of triangles using at most this many vertices each (`boards/baked/chunk/`):
    /// the Cortex-M0 images, whose RAM holds no whole-mesh vertex cache but a few chunk
    /// caches (boards/qemu-microbit: 128 vertices of them, 64 with the teapot's 32-bit
    /// depth rows). Fewer vertices a chunk mean more chunks in those caches at once, so
    /// fewer chunks prepared again for a later strip (a row of the bench sphere at
    /// 640×480 reaches up to four chunks of 64 vertices: two caches of 64 prepared 595
    /// chunks a frame, seven of 18 prepare 31 of its 76), and more vertices stored
    /// twice in flash. Each figure's limit is the best of several tried (by the
    /// instructions of a `gradient` frame on the micro:bit) that leaves the image its
    /// stack and flash room.
    Chunk(usize),
}

/// A baked scene: the file stem under `boards/baked/{full,chunk}/`, the input (a
/// built-in scene, or a scene file relative to the workspace root, as
/// `fixshade bake` takes it) and the layouts it is baked in.
pub struct Baked {
    /// File stem (`sphere` for `full/sphere.rs`).
    pub stem: &'static str,
    /// Built-in scene name or scene file path from the workspace root.
    pub input: &'static str,
    /// The layouts.
    pub layouts: &'static [Layout],
}

/// Every scene baked for the figure images and the real boards.
pub const FILES: &[Baked] = &[
    Baked {
        stem: "sphere",
        input: "sphere",
        layouts: &[Layout::Full, Layout::Chunk(42)],
    },
    Baked {
        stem: "teapot",
        input: "teapot",
        layouts: &[Layout::Full, Layout::Chunk(32)],
    },
    Baked {
        stem: "robot",
        input: "robot",
        layouts: &[Layout::Full, Layout::Chunk(25)],
    },
    Baked {
        stem: "bench_sphere",
        input: "bench-sphere",
        layouts: &[Layout::Full, Layout::Chunk(18)],
    },
    // The sphere benchmark's finer meshes (the Cortex-M4 and ARMv6-M full-frame images).
    Baked {
        stem: "bench_sphere_64x40",
        input: "crates/sim-host/scenes/bench-sphere-64x40.toml",
        layouts: &[Layout::Full],
    },
    Baked {
        stem: "bench_sphere_128x80",
        input: "crates/sim-host/scenes/bench-sphere-128x80.toml",
        layouts: &[Layout::Full],
    },
    // The perspective images' ground plane.
    Baked {
        stem: "ground_plane",
        input: "crates/sim-host/scenes/effects/ground-plane.toml",
        layouts: &[Layout::Full],
    },
];

/// Every file of `boards/baked/`: (path relative to it, source).
pub fn files(root: &Path) -> Result<Vec<(String, String)>, String> {
    let mut out = Vec::new();
    for b in FILES {
        for layout in b.layouts {
            let (dir, chunk) = match layout {
                Layout::Full => ("full", None),
                Layout::Chunk(n) => ("chunk", Some(*n)),
            };
            let mut command = format!("fixshade bake {}", b.input);
            if let Some(n) = chunk {
                command.push_str(&format!(" --chunk {n}"));
            }
            let source = if root.join(b.input).is_file() {
                let ls = load_arg(&root.join(b.input).display().to_string())?;
                bake_loaded(b.input, Some(&ls.desc), &ls.fixed, chunk, &command)?.source
            } else {
                bake(b.input, chunk, &command)?.source
            };
            out.push((format!("{dir}/{}.rs", b.stem), source));
        }
    }
    for (file, scene) in crate::raybake::RAY_SCENES {
        out.push((format!("ray/{file}"), crate::raybake::bake_ray(scene)?));
    }
    for (rel, source) in fixshade_tests::scenes::bake_all()? {
        out.push((format!("scenes/{rel}"), source));
    }
    out.push((
        fixshade_tests::hard::BAKED_TRIANGLES
            .trim_start_matches("baked/")
            .to_string(),
        fixshade_tests::hard::bake_triangles(&fixshade_tests::catalogue::triangle_cases()),
    ));
    Ok(out)
}

/// The directory of the baked files.
pub fn dir(root: &Path) -> PathBuf {
    root.join("boards/baked")
}

/// Name of the file listing what the last bake wrote (the boards' build scripts
/// check that it exists).
pub const STAMP: &str = "BAKED";

/// Files under `dir` (relative), but the README and the stamp.
fn existing(dir: &Path, rel: &Path, out: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir.join(rel)) else {
        return;
    };
    for e in entries.flatten() {
        let r = rel.join(e.file_name());
        if e.path().is_dir() {
            existing(dir, &r, out);
        } else if r != Path::new("README.md") && r != Path::new(STAMP) {
            out.push(r.display().to_string());
        }
    }
}

/// Writes every file of [`files`] that differs from what is there (an unchanged file
/// keeps its time, so the boards do not rebuild), removes files no longer baked,
/// and writes the stamp. Returns the number of files written, removed and baked.
pub fn write(root: &Path) -> Result<(usize, usize, usize), String> {
    let dir = dir(root);
    let files = files(root)?;
    let mut old = Vec::new();
    existing(&dir, Path::new(""), &mut old);
    let mut removed = 0;
    for rel in old {
        if !files.iter().any(|(r, _)| *r == rel) {
            std::fs::remove_file(dir.join(&rel)).map_err(|e| format!("{rel}: {e}"))?;
            removed += 1;
        }
    }
    let mut written = 0;
    for (rel, src) in &files {
        let p = dir.join(rel);
        if std::fs::read_to_string(&p).ok().as_deref() == Some(src.as_str()) {
            continue;
        }
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
        }
        std::fs::write(&p, src).map_err(|e| format!("{}: {e}", p.display()))?;
        written += 1;
    }
    let list: Vec<&str> = files.iter().map(|(r, _)| r.as_str()).collect();
    let stamp = format!(
        "Generated by `cargo xtask bake`: {} files.\n{}\n",
        files.len(),
        list.join("\n")
    );
    let stamp_path = dir.join(STAMP);
    if std::fs::read_to_string(&stamp_path).ok().as_deref() != Some(stamp.as_str()) {
        std::fs::write(&stamp_path, stamp).map_err(|e| format!("{}: {e}", stamp_path.display()))?;
    }
    Ok((written, removed, files.len()))
}

/// `cargo xtask bake`.
pub fn run(root: &Path) -> Result<(), String> {
    let (written, removed, total) = write(root)?;
    eprintln!(
        "xtask: boards/baked/: {written} files written, {removed} removed, {} up to date",
        total - written
    );
    Ok(())
}
