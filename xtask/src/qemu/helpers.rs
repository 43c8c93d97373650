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
use std::sync::atomic::{AtomicBool, Ordering};

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
    // The log goes through a named pipe and is counted as QEMU writes it: a file
    // would hold gigabytes (a line per helper block run) and, on a full disk, end
    // in a cut line.
    let fifo = dir.join("helpers.fifo");
    let _ = std::fs::remove_file(&fifo);
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .map_err(|e| format!("cannot start mkfifo: {e}"))?;
    if !made.success() {
        return Err(format!("mkfifo {} failed ({made})", fifo.display()));
    }
    let mut qemu = Command::new("qemu-system-arm")
        .current_dir(dir)
        .args(["-cpu", cpu, "-machine", machine, "-nographic"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .args(["-icount", "shift=10"])
        .args(["-d", "exec,nochain,in_asm", "-dfilter", &filter, "-D"])
        .arg(&fifo)
        .arg("-kernel")
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("cannot start qemu-system-arm: {e}"))?;
    let opened = AtomicBool::new(false);
    let (frames, status) = std::thread::scope(|s| {
        let reader = s.spawn(|| {
            let file = std::fs::File::open(&fifo).map_err(|e| format!("{}: {e}", fifo.display()));
            opened.store(true, Ordering::SeqCst);
            let mut log = Counted(BufReader::with_capacity(1 << 20, file?), 0);
            let frames = count(&mut log, &marker)?;
            Ok::<_, String>((frames, log.1))
        });
        let status = qemu.wait();
        // A QEMU that ended before opening the pipe leaves the reader waiting
        // for a writer: open it once for writing, so that the reader sees the
        // end of the log.
        if !opened.load(Ordering::SeqCst) {
            let _ = std::fs::OpenOptions::new().write(true).open(&fifo);
        }
        let frames = reader
            .join()
            .unwrap_or_else(|_| Err("the log reader panicked".to_string()));
        (frames, status)
    });
    let _ = std::fs::remove_file(&fifo);
    let status = status.map_err(|e| format!("qemu-system-arm: {e}"))?;
    if !status.success() {
        let log = frames.err().map(|e| format!(", its log: {e}"));
        return Err(format!(
            "{}: the helper-count run failed ({status}{})",
            elf.display(),
            log.unwrap_or_default()
        ));
    }
    let (frames, bytes) = frames?;
    eprintln!(
        "xtask: {}: helper instructions counted from {} MB of execution log",
        elf.display(),
        bytes >> 20
    );
    Ok(frames)
}

/// A reader that counts the bytes read through it.
struct Counted<R>(R, u64);

impl<R: BufRead> std::io::Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.0.read(buf)?;
        self.1 += n as u64;
        Ok(n)
    }
}

impl<R: BufRead> BufRead for Counted<R> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        self.0.fill_buf()
    }
    fn consume(&mut self, n: usize) {
        self.1 += n as u64;
        self.0.consume(n);
    }
}

/// The helper instructions of each frame in an execution log (`-d
/// exec,nochain,in_asm`): blocks' sizes from their translations (`IN:` then one
/// `0x…:` line per instruction), executions from the `Trace` lines, the frames
/// from the markers at `marker`'s addresses.
///
/// A translation is followed by the first execution of its block, whose `Trace`
/// line names the block by `[cs_base/pc/flags/cflags]`: the size belongs to that
/// key, not to the address alone. Under `-icount` QEMU also translates shorter
/// blocks at an address already translated (the instruction budget left before
/// a timer event is in `cflags`, and an I/O instruction ends a block early);
/// keyed by address, such a short block's size would then be counted for every
/// later run of the full one.
///
/// A `Trace` line is written as a block is entered; a block that QEMU leaves
/// before its first instruction (an interrupt due, the instruction budget spent,
/// or the emulator's own timer asking the loop to look at its events, which
/// depends on the host's speed) is followed by a `Stopped execution of TB chain
/// before` line and traced again when it runs. Each trace is therefore counted
/// only once the next line shows that its block ran.
fn count(log: impl BufRead, marker: &HashMap<u32, Marker>) -> Result<Vec<u64>, String> {
    let mut size: HashMap<String, u64> = HashMap::new();
    // The size of the block translated last, until its first `Trace` line.
    let mut pending: Option<u64> = None;
    let mut frames = Frames::default();
    // The block traced last: a marker or a helper block's size.
    let mut entered: Option<Result<Marker, u64>> = None;
    for line in log.lines() {
        let line = line.map_err(|e| e.to_string())?;
        if line.starts_with("IN:") {
            pending = Some(0);
        } else if line.starts_with("0x") {
            if let Some(n) = &mut pending {
                *n += 1;
            }
        } else if line.starts_with("Stopped execution of TB chain") {
            entered = None;
        } else if line.starts_with("Trace ") {
            // `Trace cpu: host [cs_base/pc/flags/cflags] name`
            let key = line
                .split('[')
                .nth(1)
                .and_then(|f| f.split(']').next())
                .ok_or_else(|| format!("bad log line: {line}"))?;
            let pc = key
                .split('/')
                .nth(1)
                .and_then(|a| u32::from_str_radix(a, 16).ok())
                .ok_or_else(|| format!("bad log line: {line}"))?;
            if let Some(n) = pending.take() {
                size.insert(key.to_string(), n);
            }
            if let Some(b) = entered.take() {
                frames.ran(b);
            }
            // The filter logs nothing but helpers and the markers.
            entered = Some(match marker.get(&pc) {
                Some(&m) => Ok(m),
                None => Err(size.get(key).copied().unwrap_or(0)),
            });
        }
    }
    if let Some(b) = entered {
        frames.ran(b);
    }
    Ok(frames.done)
}

/// The frames counted so far, and the one being counted.
#[derive(Default)]
struct Frames {
    /// Inside a measured window (between `mark_on` and `mark_off`).
    on: bool,
    /// The helper instructions of the frame being counted.
    acc: u64,
    done: Vec<u64>,
}

impl Frames {
    /// A marker, or a helper block of `n` instructions, has run.
    fn ran(&mut self, b: Result<Marker, u64>) {
        match b {
            Ok(Marker::On) => self.on = true,
            Ok(Marker::Off) => self.on = false,
            Ok(Marker::Frame) => self.done.push(std::mem::take(&mut self.acc)),
            Ok(Marker::Discard) => self.acc = 0,
            Err(n) if self.on => self.acc += n,
            Err(_) => {}
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Marker {
    On,
    Off,
    Frame,
    Discard,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The start of each test log: `mark_on` runs, then a helper block of three
    /// instructions (at 0x200) is translated and runs.
    const START: &str = "\
----------------
IN: mark_on
0x00000100:  4770       bx       lr

Trace 0: 0x1 [00000000/00000100/00000110/ff020200] mark_on
----------------
IN: __aeabi_lmul
0x00000200:  b510       push     {r4, lr}
0x00000202:  4343       muls     r3, r0, r3
0x00000204:  bd10       pop      {r4, pc}

Trace 0: 0x2 [00000000/00000200/00000110/ff020200] __aeabi_lmul
";

    /// The markers of the test logs: `mark_on` at 0x100, `mark_frame` at 0x300.
    fn markers() -> HashMap<u32, Marker> {
        HashMap::from([(0x100, Marker::On), (0x300, Marker::Frame)])
    }

    /// A helper block translated whole (3 instructions) and, at the same address,
    /// short (1 instruction, a smaller budget in `cflags`): each run counts its
    /// own block's size.
    #[test]
    fn sizes_belong_to_the_translated_block_not_its_address() {
        let log = START.to_string()
            + "\
----------------
IN: __aeabi_lmul
0x00000200:  b510       push     {r4, lr}

Trace 0: 0x3 [00000000/00000200/00000110/ff020001] __aeabi_lmul
Trace 0: 0x2 [00000000/00000200/00000110/ff020200] __aeabi_lmul
----------------
IN: mark_frame
0x00000300:  4770       bx       lr

Trace 0: 0x4 [00000000/00000300/00000110/ff020200] mark_frame
";
        assert_eq!(count(log.as_bytes(), &markers()), Ok(vec![3 + 1 + 3]));
    }

    /// A block QEMU left before its first instruction (`Stopped execution`) is
    /// counted when it is traced again and runs, not twice; a marker likewise.
    /// Two frames in a row with no helper between are two frames.
    #[test]
    fn a_block_stopped_before_it_ran_is_counted_once() {
        let log = START.to_string()
            + "\
Stopped execution of TB chain before 0x2 [00000200] __aeabi_lmul
Trace 0: 0x2 [00000000/00000200/00000110/ff020200] __aeabi_lmul
----------------
IN: mark_frame
0x00000300:  4770       bx       lr

Trace 0: 0x4 [00000000/00000300/00000110/ff020200] mark_frame
Stopped execution of TB chain before 0x4 [00000300] mark_frame
Trace 0: 0x4 [00000000/00000300/00000110/ff020200] mark_frame
Trace 0: 0x4 [00000000/00000300/00000110/ff020200] mark_frame
Trace 0: 0x2 [00000000/00000200/00000110/ff020200] __aeabi_lmul
Stopped execution of TB chain before 0x2 [00000200] __aeabi_lmul
";
        assert_eq!(count(log.as_bytes(), &markers()), Ok(vec![3, 0]));
    }
}
