//! The `helpers` column: instructions a frame spends inside compiler runtime helpers
//! (`__aeabi_*`, `__*di3`, `__*ti3`, `__*si3`, `__clz*`, `memcpy`/`memset`/`memmove`,
//! and the `compiler_builtins` routines behind them), measured from QEMU's execution
//! log.
//!
//! The image runs a second time with `-d exec,nochain,in_asm` and `-dfilter` limited
//! to the helpers' address ranges and to the four markers of `boards/common`
//! (`mark_on`, `mark_off`, `mark_frame`, `mark_discard`), all from the ELF's symbol
//! table: the log then holds only the blocks executed inside helpers (and their
//! translations, which give each block's instruction count) and the markers. The
//! counter's `measure` wraps what it measures in `mark_on`/`mark_off`, `FrameLog`
//! calls `mark_frame` when it writes a `FRAME` line: the helper instructions inside
//! the measured windows since the previous frame are that frame's. `-icount` makes
//! the run the same as the measuring one, block for block.

use std::collections::HashMap;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

/// A function of the ELF: start (Thumb bit cleared), size, name.
struct Func {
    start: u32,
    size: u32,
    name: String,
}

/// The functions (`STT_FUNC`) of a 32-bit little-endian ELF's symbol table.
fn functions(elf: &Path) -> Result<Vec<Func>, String> {
    let b = std::fs::read(elf).map_err(|e| format!("{}: {e}", elf.display()))?;
    let bad = || format!("{}: not a 32-bit little-endian ELF", elf.display());
    let u32_at = |o: usize| -> Result<u32, String> {
        b.get(o..o + 4)
            .map(|s| u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
            .ok_or_else(bad)
    };
    let u16_at = |o: usize| -> Result<u32, String> {
        b.get(o..o + 2)
            .map(|s| u16::from_le_bytes([s[0], s[1]]) as u32)
            .ok_or_else(bad)
    };
    if b.len() < 52 || &b[..4] != b"\x7fELF" || b[4] != 1 || b[5] != 1 {
        return Err(bad());
    }
    let shoff = u32_at(32)? as usize;
    let shentsize = u16_at(46)? as usize;
    let shnum = u16_at(48)? as usize;
    let mut out = Vec::new();
    for i in 0..shnum {
        let sh = shoff + i * shentsize;
        if u32_at(sh + 4)? != 2 {
            continue; // not SHT_SYMTAB
        }
        let (off, size, link, entsize) = (
            u32_at(sh + 16)? as usize,
            u32_at(sh + 20)? as usize,
            u32_at(sh + 24)? as usize,
            u32_at(sh + 36)? as usize,
        );
        let strtab = shoff + link * shentsize;
        let str_off = u32_at(strtab + 16)? as usize;
        for k in 0..size / entsize.max(1) {
            let s = off + k * entsize;
            let (name, value, sz) = (u32_at(s)? as usize, u32_at(s + 4)?, u32_at(s + 8)?);
            if b.get(s + 12).is_none_or(|info| info & 0xF != 2) {
                continue; // not STT_FUNC
            }
            let start = str_off + name;
            let end = b[start..].iter().position(|&c| c == 0).ok_or_else(bad)? + start;
            out.push(Func {
                start: value & !1,
                size: sz,
                name: String::from_utf8_lossy(&b[start..end]).into_owned(),
            });
        }
    }
    Ok(out)
}

/// True for a compiler runtime helper's symbol.
fn is_helper(name: &str) -> bool {
    let plain = name.starts_with("__aeabi_")
        || name.starts_with("__clz")
        || matches!(name, "memcpy" | "memset" | "memmove" | "memcmp");
    // __muldi3, __udivmoddi4, __multi3, __divsi3, …
    let arith = name.starts_with("__")
        && ["di3", "di4", "ti3", "ti4", "si3", "si4"]
            .iter()
            .any(|s| name.ends_with(s));
    plain || arith || name.contains("compiler_builtins")
}

/// The helper instructions of each frame the image logs, in `FRAME` order.
pub(super) fn per_frame(
    machine: &str,
    cpu: &str,
    elf: &Path,
    dir: &Path,
) -> Result<Vec<u64>, String> {
    let funcs = functions(elf)?;
    let mut ranges = Vec::new();
    let mut marker: HashMap<u32, Marker> = HashMap::new();
    for f in &funcs {
        let m = if f.name.contains("fixshade_boards_common7mark_on") {
            Some(Marker::On)
        } else if f.name.contains("fixshade_boards_common8mark_off") {
            Some(Marker::Off)
        } else if f.name.contains("fixshade_boards_common10mark_frame") {
            Some(Marker::Frame)
        } else if f.name.contains("fixshade_boards_common12mark_discard") {
            Some(Marker::Discard)
        } else {
            None
        };
        if let Some(m) = m {
            marker.insert(f.start, m);
        }
        if (m.is_some() || is_helper(&f.name)) && f.size > 0 {
            ranges.push((f.start, f.size));
        }
    }
    if marker.len() != 4 {
        return Err(format!(
            "{}: the image lacks the frame markers of boards/common",
            elf.display()
        ));
    }
    let filter = ranges
        .iter()
        .map(|(s, n)| format!("0x{s:x}+0x{n:x}"))
        .collect::<Vec<_>>()
        .join(",");
    let log = dir.join("helpers.log");
    let _ = std::fs::remove_file(&log);
    let status = Command::new("qemu-system-arm")
        .current_dir(dir)
        .args(["-cpu", cpu, "-machine", machine, "-nographic"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .args(["-icount", "shift=10"])
        .args(["-d", "exec,nochain,in_asm", "-dfilter", &filter, "-D"])
        .arg(&log)
        .arg("-kernel")
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .map_err(|e| format!("cannot start qemu-system-arm: {e}"))?;
    if !status.success() {
        return Err(format!(
            "{}: the helper-count run failed ({status})",
            elf.display()
        ));
    }
    let file = std::fs::File::open(&log).map_err(|e| format!("{}: {e}", log.display()))?;
    // Blocks' sizes from their translations (`IN:` then one `0x…:` line per
    // instruction), executions from the `Trace` lines.
    let mut size: HashMap<u32, u64> = HashMap::new();
    let mut block: Option<u32> = None;
    let (mut on, mut acc, mut frames) = (false, 0u64, Vec::new());
    let mut last: Option<u32> = None;
    for line in BufReader::new(file).lines() {
        let line = line.map_err(|e| e.to_string())?;
        if line.starts_with("IN:") {
            block = None;
        } else if let Some(addr) = line.strip_prefix("0x") {
            let pc = addr
                .split(':')
                .next()
                .and_then(|a| u32::from_str_radix(a, 16).ok())
                .ok_or_else(|| format!("bad log line: {line}"))?;
            let start = match block {
                Some(s) => s,
                None => {
                    // A (re)translation: its size counted afresh.
                    size.insert(pc, 0);
                    block = Some(pc);
                    pc
                }
            };
            *size.entry(start).or_insert(0) += 1;
        } else if line.starts_with("Trace ") {
            block = None;
            // `Trace cpu: host [cs_base/pc/flags/cflags] name`
            let pc = line
                .split('[')
                .nth(1)
                .and_then(|f| f.split('/').nth(1))
                .and_then(|a| u32::from_str_radix(a, 16).ok())
                .ok_or_else(|| format!("bad log line: {line}"))?;
            // A block whose run the instruction budget cuts off before its first
            // instruction (an interrupt due there) is traced again when it runs:
            // two traces of a marker in a row are one call (a frame has a measured
            // span between two of its markers).
            let again = last == Some(pc);
            last = Some(pc);
            match marker.get(&pc) {
                Some(_) if again => {}
                Some(Marker::On) => on = true,
                Some(Marker::Off) => on = false,
                Some(Marker::Frame) => frames.push(std::mem::take(&mut acc)),
                Some(Marker::Discard) => acc = 0,
                // The filter logs nothing but helpers and the markers.
                None if on => acc += size.get(&pc).copied().unwrap_or(0),
                None => {}
            }
        } else if line.trim().is_empty() {
            block = None;
        }
    }
    let _ = std::fs::remove_file(&log);
    Ok(frames)
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Marker {
    On,
    Off,
    Frame,
    Discard,
}
