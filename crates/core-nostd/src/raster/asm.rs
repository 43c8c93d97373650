//! Gradient's packed span loop in assembly, for the 5-6-5 formats over 16-bit depth
//! cells on the Cortex-M cores ([`super::pixel`]'s `write_packed` calls it).
//!
//! The compiler unrolls the portable loop four times on M-profile cores and then
//! runs out of registers: the four depths and colour steps are spilled and reloaded
//! at every pixel. Measured on the bench sphere (`cargo xtask qemu`), a written
//! pixel took 20 instructions on the Cortex-M4 and 27 on ARMv6-M; these loops take
//! 16 and 23 (a hidden pixel 8 and 13), with the same pixels and depths: the QEMU
//! images compare every frame with the host's byte for byte, and the mps2 images
//! (Cortex-M4 and ARMv6-M) check that `Rgb565Be` (the byte-swapping store) draws
//! the `Rgb565Le` frame byte-swapped.
//!
//! What a step does, in both: the stored depth `d` of the pixel is read; where
//! `z >> 16 < d` (strictly nearer, as [`crate::target::DepthFormat::write_if_nearer`])
//! the new depth and the pixel are written. The pixel's fields are the integer bits
//! of the packed colour's lanes (red at bit 43, green at 21, blue at 0, each with 16
//! fraction bits): red is bits 59..64 (27..32 of the high word), green 37..43
//! (5..11 of the high word, already where 5-6-5 wants it), blue 16..21 (of the low
//! word). Then the colour steps by `dc` (add with carry across the two words) and
//! the depth by `dz`, wrapping, as the portable loop does.
//!
//! # Why there is `unsafe` here
//!
//! The crate denies `unsafe_code`; each `asm!` block is under its own
//! `#[allow(unsafe_code)]` with a SAFETY comment: it stores only into the cells of
//! the two rows it borrows mutably, reads only those and its inputs, pushes nothing.

/// The rows' first `n = min(color.len(), depth.len())` pixels as the packed loop
/// writes them; `swap`: store the pixel byte-swapped (`Rgb565Be`).
#[inline(always)]
pub(crate) fn packed_565_span(
    color: &mut [u16],
    depth: &mut [u16],
    c: u64,
    dc: u64,
    z: i32,
    dz: i32,
    swap: bool,
) {
    let n = color.len().min(depth.len());
    if n == 0 {
        return;
    }
    let (lo, hi) = (c as u32, (c >> 32) as u32);
    let (dlo, dhi) = (dc as u32, (dc >> 32) as u32);
    #[cfg(fixshade_dsp)]
    thumb2(color, depth, n, [lo, hi, dlo, dhi], z, dz, swap);
    #[cfg(fixshade_v6m)]
    v6m(color, depth, n, [lo, hi, dlo, dhi], z, dz, swap);
}

/// ARMv7-M and later (Thumb-2): both rows indexed from their ends by a negative
/// byte offset that steps up to zero, so one register and one flag-setting add
/// count the loop.
#[cfg(fixshade_dsp)]
#[inline(always)]
fn thumb2(
    color: &mut [u16],
    depth: &mut [u16],
    n: usize,
    [lo, hi, dlo, dhi]: [u32; 4],
    z: i32,
    dz: i32,
    swap: bool,
) {
    let (cp, dp) = (color[n..].as_mut_ptr(), depth[n..].as_mut_ptr());
    // 1 ≤ n ≤ 4096 (the guard band): −2n fits i32 and is below zero.
    let i = -2 * n as i32;
    macro_rules! run {
        ($($rev:literal)?) => {
            // SAFETY: the loads and stores are at `cp + i` and `dp + i` for
            // i = −2n, −2n + 2, …, −2: the n two-byte cells of `color[..n]` and
            // `depth[..n]`, borrowed mutably here; registers otherwise (flags
            // clobbered, stack untouched).
            #[allow(unsafe_code)]
            unsafe {
                core::arch::asm!(
                    "2:",
                    "ldrh {t}, [{dp}, {i}]",
                    // Stored ≤ new: the pixel stays.
                    "cmp {t}, {z}, lsr #16",
                    "bls 3f",
                    "lsrs {t}, {z}, #16",
                    "strh {t}, [{dp}, {i}]",
                    "and {t}, {hi}, #0x7e0",
                    "lsrs {u}, {hi}, #27",
                    "orr {t}, {t}, {u}, lsl #11",
                    "ubfx {u}, {lo}, #16, #5",
                    "orr {t}, {t}, {u}",
                    $($rev,)?
                    "strh {t}, [{cp}, {i}]",
                    "3:",
                    "adds {lo}, {lo}, {dlo}",
                    "adc {hi}, {hi}, {dhi}",
                    "add {z}, {z}, {dz}",
                    "adds {i}, {i}, #2",
                    "bne 2b",
                    cp = in(reg) cp,
                    dp = in(reg) dp,
                    i = inout(reg) i => _,
                    lo = inout(reg) lo => _,
                    hi = inout(reg) hi => _,
                    dlo = in(reg) dlo,
                    dhi = in(reg) dhi,
                    z = inout(reg) z => _,
                    dz = in(reg) dz,
                    t = out(reg) _,
                    u = out(reg) _,
                    options(nostack),
                );
            }
        };
    }
    if swap {
        run!("rev16 {t}, {t}");
    } else {
        run!();
    }
}

/// ARMv6-M (Thumb-1): most instructions reach only r0–r7, of which the compiler
/// lends six (and Thumb-1 code may name r8 and above only as clobbers). The depth
/// pointer, the colour row's offset from it, two temporaries and the colour's two
/// words take the six; the depth, the steps, the row's end and green's mask are
/// moved into r8–r12 and lr first (`MOV`, `ADD` and `CMP` reach those), read from a
/// block on the stack. Not inlined: one copy serves every span, as the micro:bit
/// images have only a few hundred bytes of flash to spare. The call and the saving
/// of r4–r11 cost about 40 instructions a span (on the bench sphere at 640×480,
/// 6.02 M instead of 5.61 M inlined, 6.77 M before the loop was in assembly).
#[cfg(fixshade_v6m)]
#[inline(never)]
fn v6m(
    color: &mut [u16],
    depth: &mut [u16],
    n: usize,
    [lo, hi, dlo, dhi]: [u32; 4],
    z: i32,
    dz: i32,
    swap: bool,
) {
    let dp = depth.as_mut_ptr();
    let end = depth[n..].as_mut_ptr();
    // The colour row's byte offset from the depth row (modulo 2³²).
    let k = (color.as_mut_ptr() as usize).wrapping_sub(dp as usize);
    let block: [u32; 5] = [z as u32, dz as u32, dlo, dhi, end as u32];
    macro_rules! run {
        ($($rev:literal)?) => {
            // SAFETY: the loads and stores are at `p` (depth) and `p + k` (colour)
            // for p = dp, dp + 2, …, end − 2: the n two-byte cells of
            // `depth[..n]` and `color[..n]`, borrowed mutably here, and the five
            // words of `block`, read; registers otherwise (flags clobbered, the
            // stack pointer untouched).
            #[allow(unsafe_code)]
            unsafe {
                core::arch::asm!(
                    "ldr r3, [r2]",
                    "mov r8, r3",
                    "ldr r3, [r2, #4]",
                    "mov r9, r3",
                    "ldr r3, [r2, #8]",
                    "mov r10, r3",
                    "ldr r3, [r2, #12]",
                    "mov r11, r3",
                    "ldr r3, [r2, #16]",
                    "mov r12, r3",
                    "movs r3, #0x7e",
                    "lsls r3, r3, #4",
                    "mov lr, r3",
                    "2:",
                    "ldrh r2, [r0]",
                    "mov r3, r8",
                    "lsrs r3, r3, #16",
                    // Stored ≤ new: the pixel stays.
                    "cmp r2, r3",
                    "bls 3f",
                    "strh r3, [r0]",
                    "mov r2, lr",
                    "ands r2, r5",
                    "lsrs r3, r5, #27",
                    "lsls r3, r3, #11",
                    "orrs r2, r3",
                    "lsls r3, r4, #11",
                    "lsrs r3, r3, #27",
                    "orrs r2, r3",
                    $($rev,)?
                    "strh r2, [r0, r1]",
                    "3:",
                    "mov r2, r10",
                    "adds r4, r4, r2",
                    "mov r2, r11",
                    "adcs r5, r2",
                    "add r8, r9",
                    "adds r0, #2",
                    "cmp r0, r12",
                    "bne 2b",
                    inout("r0") dp => _,
                    in("r1") k,
                    inout("r2") block.as_ptr() => _,
                    out("r3") _,
                    inout("r4") lo => _,
                    inout("r5") hi => _,
                    out("r8") _,
                    out("r9") _,
                    out("r10") _,
                    out("r11") _,
                    out("r12") _,
                    out("lr") _,
                    options(nostack),
                );
            }
        };
    }
    if swap {
        run!("rev16 r2, r2");
    } else {
        run!();
    }
}
