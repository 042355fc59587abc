#!/usr/bin/env python3
"""Checks a linked AVR image for two code patterns that LLVM's AVR backend
gets wrong, so that no image ships with either.

1. Incoming stack arguments on a 22-bit-PC device (ATmega2560; pass
   --pc-bytes 3). A call there pushes a 3-byte return address (AVR
   Instruction Set Manual, CALL: "STACK <- PC + 2, SP <- SP - 3" on devices
   with a 22-bit PC), but LLVM lays out a function's incoming stack
   arguments for a 2-byte one (its AVR frame lowering fixes the local area
   offset at -2 for every device), so such a function reads each stack
   argument one byte low. Arguments beyond the 18 bytes of r8-r25 (avr-gcc
   ABI, which LLVM follows) go on the stack. Found as: an access through Y
   (directly, through a copy of Y in Z or X, or with the temporary Y moves
   LLVM emits for offsets beyond 63) above the function's frame and saved
   registers. Known exception (allow-listed below, with the reason).

2. r0 overwritten between a multiplication and the read of its product.
   MUL/MULS/MULSU/FMUL* leave the product in r1:r0; to reach a stack slot
   beyond Y+63 LLVM brackets a Y adjustment with `in r0, SREG` ...
   `out SREG, r0`, and has been seen to put that bracket between the MUL and
   the `mov rX, r0` that takes the product, which then takes SREG. Found as:
   on a straight-line path (conditional skips over a jump followed), a write
   of r0 after a MUL and before r0 is read.

Method: `avr-objdump -d`, function by function. Both scans are linear and
conservative in what they report (an access pattern they do not follow is
not reported), which is why the firmware also avoids the conditions: no
function with more than 18 bytes of arguments on the firmware's paths, and
integer arithmetic kept out of the largest frames.

Usage: avr_codegen_check.py [--pc-bytes 2|3] ELF...   exit 1 on a finding.
"""
import re
import subprocess
import sys

# Functions whose stack-argument read is known and harmless.
ALLOWED_STACK_ARGS = {
    # libm's k_sin(x, y, iy): iy (i32) is the only stack argument and is
    # read one byte low: its test `iy == 0` sees the return address's low
    # byte instead of iy's top byte. iy is 0 or 1; with iy = 1 the low byte
    # still makes it non-zero (correct branch); with iy = 0 the other branch
    # computes x - ((z*(0.5*y - v*r) - y) - v*S1) with y = 0, which is
    # algebraically x + v*(S1 + z*r), the iy = 0 branch: the result is the
    # same either way. (libm 0.2, src/math/k_sin.rs.)
    "_RNvNtNtCsihf79mdDzM9_4libm4math5k_sin5k_sin",
}

MULS = {"mul", "muls", "mulsu", "fmul", "fmuls", "fmulsu"}
JUMPS = {"ret", "reti", "rjmp", "jmp", "ijmp", "eijmp"}


def s16(v):
    v &= 0xFFFF
    return v - 0x10000 if v & 0x8000 else v


def disassemble(elf):
    out = subprocess.run(
        ["avr-objdump", "-d", "--no-show-raw-insn", elf],
        capture_output=True, text=True, check=True,
    ).stdout
    funcs = {}
    cur = None
    for line in out.splitlines():
        m = re.match(r"^([0-9a-f]+) <(.*)>:", line)
        if m:
            cur = m.group(2)
            funcs[cur] = []
            continue
        m = re.match(r"^\s+([0-9a-f]+):\s+(\S+)\s*(.*?)\s*(;.*)?$", line)
        if cur is not None and m:
            args = [a.strip() for a in m.group(3).split(",")] if m.group(3) else []
            funcs[cur].append((int(m.group(1), 16), m.group(2), args))
    return funcs


def stack_args(name, ins):
    """Offset above the saved registers reached, with its address, or None."""
    i, pushes = 0, 0
    while i < len(ins) and ins[i][1] == "push":
        pushes += 1
        i += 1
    if not (i + 1 < len(ins) and ins[i][1:] == ("in", ["r28", "0x3d"])
            and ins[i + 1][1:] == ("in", ["r29", "0x3e"])):
        return None
    i += 2
    frame = 0
    if i < len(ins) and ins[i][1] == "sbiw" and ins[i][2][0] == "r28":
        frame = int(ins[i][2][1], 0)
    elif (i + 1 < len(ins) and ins[i][1] == "subi" and ins[i][2][0] == "r28"
          and ins[i + 1][1] == "sbci"):
        frame = s16(int(ins[i][2][1], 0) + (int(ins[i + 1][2][1], 0) << 8))
    limit = frame + pushes
    ydisp = 0
    ptr = {"Z": None, "X": None}
    worst = None
    k = i
    while k < len(ins):
        addr, op, a = ins[k]
        nxt = ins[k + 1] if k + 1 < len(ins) else (0, "", [])
        if (op, a) in (("in", ["r0", "0x3f"]), ("out", ["0x3f", "r0"])):
            # LLVM brackets every temporary move of Y with a save and
            # restore of SREG (the restore may be tail-merged into another
            # block): Y is at the frame at both ends.
            ydisp = 0
        # A pointer moved: subi/sbci by a 16-bit immediate, or adiw/sbiw.
        moved = None
        if op == "subi" and a[0] in ("r28", "r30", "r26") and nxt[1] == "sbci":
            moved = (-s16(int(a[1], 0) + (int(nxt[2][1], 0) << 8)), 2)
        elif op in ("adiw", "sbiw") and a[0] in ("r28", "r30", "r26"):
            moved = (int(a[1], 0) * (1 if op == "adiw" else -1), 1)
        if moved:
            d, width = moved
            if a[0] == "r28":
                ydisp += d
            else:
                key = "Z" if a[0] == "r30" else "X"
                if ptr[key] is not None:
                    ptr[key] += d
            k += width
            continue
        if op == "movw" and len(a) == 2 and a[1] == "r28" and a[0] in ("r30", "r26"):
            ptr["Z" if a[0] == "r30" else "X"] = ydisp
            k += 1
            continue
        off = None
        for arg in a:
            m = re.fullmatch(r"([YZX])\+(\d+)", arg)
            if m:
                base, q = m.group(1), int(m.group(2))
                if base == "Y":
                    off = ydisp + q
                elif ptr[base] is not None:
                    off = ptr[base] + q
            elif arg in ("Z", "X", "Z+", "X+") and ptr[arg[0]] is not None:
                off = ptr[arg[0]]
                if arg.endswith("+"):
                    ptr[arg[0]] += 1
        if off is not None and op in ("ld", "ldd", "st", "std") and off > limit:
            if worst is None or off > worst[0]:
                worst = (off, addr, frame, pushes)
        # Any other write to Z or X ends following it.
        if a and op not in ("st", "std", "cp", "cpc", "cpi", "tst", "out", "push",
                            "sbrc", "sbrs"):
            for key, regs in (("Z", ("r30", "r31")), ("X", ("r26", "r27"))):
                if a[0] in regs:
                    ptr[key] = None
        k += 1
    return worst


def writes_r0(op, a):
    if op == "lpm" and not a:
        return True
    if op == "elpm" and not a:
        return True
    return bool(a) and a[0] == "r0" and op not in ("out", "st", "std", "push", "cp", "cpc",
                                                   "sbrc", "sbrs")


def reads_r0(op, a):
    if (op, a) == ("out", ["0x3f", "r0"]):
        # Restores SREG from the `in r0, SREG` of a bracket: reads that
        # value, not a product.
        return False
    if op in ("out", "st", "std", "sts") and a and a[-1] == "r0":
        return True
    if op == "push" and a == ["r0"]:
        return True
    return len(a) > 1 and a[1] == "r0" or (op in ("sbrc", "sbrs", "cp", "cpc", "tst")
                                          and a and a[0] == "r0")


def r0_clobbers(ins):
    """(mul address, clobber address, read address) per finding."""
    found = []
    mul = None
    clobber = None
    prev = ("", [])
    for addr, op, a in ins:
        skipped = prev[0].startswith("br") and prev[1] and prev[1][0].startswith(".+")
        prev = (op, a)
        if skipped and op in ("jmp", "rjmp"):
            continue  # a conditional skip over a jump: the path goes on
        if op in MULS:
            mul, clobber = addr, None
            continue
        if mul is None:
            continue
        if reads_r0(op, a):
            if clobber is not None:
                found.append((mul, clobber, addr))
            mul, clobber = None, None
            continue
        if op in JUMPS or op in ("call", "rcall", "icall", "eicall"):
            mul, clobber = None, None
            continue
        if writes_r0(op, a) and clobber is None:
            clobber = addr
    return found


def main(argv):
    pc_bytes = 2
    elfs = []
    it = iter(argv)
    for arg in it:
        if arg == "--pc-bytes":
            pc_bytes = int(next(it))
        else:
            elfs.append(arg)
    if not elfs or pc_bytes not in (2, 3):
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    bad = 0
    for elf in elfs:
        funcs = disassemble(elf)
        # Between the vectors and __ctors_end lie flash constants
        # (.progmem), which the disassembler shows as code: not code.
        code_start = funcs.get("__ctors_end", [(0, "", [])])[0][0] if funcs.get("__ctors_end") else 0
        n_args = n_r0 = 0
        for name, ins in funcs.items():
            if not ins or (name != "__vectors" and ins[0][0] < code_start):
                continue
            if pc_bytes == 3 and name not in ALLOWED_STACK_ARGS:
                w = stack_args(name, ins)
                if w:
                    off, addr, frame, pushes = w
                    print(f"{elf}: stack argument read at {addr:#x} (Y+{off}, frame {frame} B, "
                          f"{pushes} saved) in {name}")
                    n_args += 1
            for mul, clob, read in r0_clobbers(ins):
                print(f"{elf}: product of the MUL at {mul:#x} read from r0 at {read:#x} after "
                      f"r0 was overwritten at {clob:#x} in {name}")
                n_r0 += 1
        print(f"{elf}: {len(funcs)} functions; stack-argument reads: {n_args}; "
              f"r0 clobbered under a product: {n_r0}")
        bad += n_args + n_r0
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
