//! The memory copy and clear routines the compiler calls, as byte loops.
//!
//! The ARM run-time ABI (*Run-time ABI for the Arm Architecture*, IHI 0043,
//! section 4.3.4) names `__aeabi_memcpy`, `__aeabi_memcpy4`,
//! `__aeabi_memcpy8` and `__aeabi_memclr*`; LLVM calls them (and C's
//! `memcpy`) for every copy or clear it does not inline, and `memcmp` for
//! comparisons of byte strings. `compiler_builtins` defines them as weak
//! symbols, unrolled for speed over aligned words: 1,176 bytes of this
//! image. These strong definitions replace them with three byte loops, 60
//! bytes in all (`.ci/budgets.sh`: 69,924 -> 68,800 B). The image copies
//! little: structures of at most a few hundred bytes (the configuration's
//! 160), none in an interrupt handler; at four or five cycles a byte at
//! 100 MHz that is a few microseconds.
//!
//! Each keeps its calling contract: `memcpy` returns its
//! destination (C11 7.24.2.1), the `__aeabi_` forms return nothing and may
//! clobber r0–r3 and r12 (IHI 0043, 4.3.4).

core::arch::global_asm!(
    ".section .text.suntracker_mem,\"ax\",%progbits",
    ".syntax unified",
    ".thumb",
    // memcpy(r0 = dst, r1 = src, r2 = n) -> dst
    ".global memcpy",
    ".type memcpy, %function",
    ".thumb_func",
    "memcpy:",
    "    mov   r3, r0",
    "    cbz   r2, 2f",
    "1:  ldrb  r12, [r1], #1",
    "    strb  r12, [r3], #1",
    "    subs  r2, r2, #1",
    "    bne   1b",
    "2:  bx    lr",
    ".size memcpy, . - memcpy",
    ".global __aeabi_memcpy",
    ".global __aeabi_memcpy4",
    ".global __aeabi_memcpy8",
    ".thumb_set __aeabi_memcpy, memcpy",
    ".thumb_set __aeabi_memcpy4, memcpy",
    ".thumb_set __aeabi_memcpy8, memcpy",
    // __aeabi_memclr(r0 = dst, r1 = n)
    ".global __aeabi_memclr",
    ".type __aeabi_memclr, %function",
    ".thumb_func",
    "__aeabi_memclr:",
    "    cbz   r1, 2f",
    "    movs  r2, #0",
    "1:  strb  r2, [r0], #1",
    "    subs  r1, r1, #1",
    "    bne   1b",
    "2:  bx    lr",
    ".size __aeabi_memclr, . - __aeabi_memclr",
    ".global __aeabi_memclr4",
    ".global __aeabi_memclr8",
    ".thumb_set __aeabi_memclr4, __aeabi_memclr",
    ".thumb_set __aeabi_memclr8, __aeabi_memclr",
    // memcmp(r0 = a, r1 = b, r2 = n) -> the difference of the first bytes
    // that differ, as unsigned chars (C11 7.24.4.1), or 0
    ".global memcmp",
    ".type memcmp, %function",
    ".thumb_func",
    "memcmp:",
    "    cbz   r2, 3f",
    "1:  ldrb  r3, [r0], #1",
    "    ldrb  r12, [r1], #1",
    "    subs  r3, r3, r12",
    "    bne   2f",
    "    subs  r2, r2, #1",
    "    bne   1b",
    "3:  movs  r0, #0",
    "    bx    lr",
    "2:  mov   r0, r3",
    "    bx    lr",
    ".size memcmp, . - memcmp",
);
