#!/usr/bin/env python3
"""Checks that AVR objects can be linked with `--relax` (.cargo/config.toml).

With `--relax`, GNU ld shortens a `call` or `jmp` whose target is within
reach into an `rcall` or `rjmp` and deletes the two bytes it saves. Code
after that point moves, so every instruction that reaches across it must be
adjusted: ld adjusts what it has a relocation for, and nothing else (GNU
binutils, bfd/elf32-avr.c, `elf32_avr_relax_delete_bytes`). ld relaxes only
objects whose ELF header has the link-relax flag (EF_AVR_LINKRELAX_PREPARED,
0x80: "the assembler emitted the relocations relaxation needs").

So an object passes when:
1. its header has the link-relax flag, and
2. every relative branch (`rjmp`, `rcall`, `br*`) without an R_AVR_7_PCREL
   or R_AVR_13_PCREL relocation spans no `call` or `jmp` (nothing between
   it and its target can shrink, so its offset stays right).

LLVM's AVR back end emits a relocation for each branch it generates; the
exceptions are branches inside inline assembly (the progmem copy loop's
`brne 1b`), which stay within a few instructions.

Usage: avr_relax_check.py OBJ...        exit 1 on a finding
       avr_relax_check.py --self-test   the check must flag doctored input
"""
import re
import subprocess
import sys

EF_AVR_LINKRELAX_PREPARED = 0x80
RELAXABLE = {"call", "jmp"}
PCREL = {"R_AVR_7_PCREL", "R_AVR_13_PCREL"}

SECTION = re.compile(r"^Disassembly of section (\S+):")
RELOC = re.compile(r"^\s+([0-9a-f]+):\s+(R_AVR_\w+)")
INSN = re.compile(r"^\s+([0-9a-f]+):\t(?:[0-9a-f]{2} )+\s*\t(\S+)\s*([^;]*)")
RELATIVE = re.compile(r"^\.([+-]\d+)")


def findings(dump):
    """Unrelocated branches of an `avr-objdump -dr` dump that span a
    relaxable instruction, as (section, offset, text) tuples."""
    sections = {}
    section = None
    for line in dump.splitlines():
        m = SECTION.match(line)
        if m:
            section = sections.setdefault(m.group(1), {"insns": [], "pcrel": set()})
            continue
        if section is None:
            continue
        m = RELOC.match(line)
        if m:
            if m.group(2) in PCREL:
                section["pcrel"].add(int(m.group(1), 16))
            continue
        m = INSN.match(line)
        if m:
            section["insns"].append((int(m.group(1), 16), m.group(2), m.group(3).strip()))
    found = []
    for name, sec in sections.items():
        for offset, op, operand in sec["insns"]:
            if not (op in ("rjmp", "rcall") or op.startswith("br")) or offset in sec["pcrel"]:
                continue
            rel = RELATIVE.match(operand.split(",")[-1].strip())
            if not rel:
                found.append((name, offset, f"{op} {operand}: target not understood"))
                continue
            # The offset counts from the next instruction (AVR ISA: PC + k + 1 words).
            target = offset + 2 + int(rel.group(1))
            lo, hi = min(offset, target), max(offset, target)
            shrinkable = [o for o, op2, _ in sec["insns"] if lo <= o < hi and op2 in RELAXABLE]
            if shrinkable:
                found.append((name, offset, f"{op} {operand} spans a {len(shrinkable)}-instruction relaxable range"))
    return found


def relax_flag(obj):
    out = subprocess.run(["avr-readelf", "-h", obj], capture_output=True, text=True, check=True).stdout
    m = re.search(r"Flags:\s+0x([0-9a-f]+)", out)
    return bool(m) and int(m.group(1), 16) & EF_AVR_LINKRELAX_PREPARED != 0


def check(obj):
    dump = subprocess.run(["avr-objdump", "-dr", obj], capture_output=True, text=True, check=True).stdout
    problems = [] if relax_flag(obj) else [("(header)", 0, "no link-relax flag")]
    problems += findings(dump)
    branches = sum(1 for line in dump.splitlines() if re.search(r"\t(rjmp|rcall|br[a-z]+)\s", line))
    for name, offset, text in problems:
        print(f"avr_relax_check: {obj}: {name}+0x{offset:x}: {text}", file=sys.stderr)
    print(f"avr_relax_check: {obj}: {branches} branches, {len(problems)} findings")
    return not problems


SELF_TEST_DUMP = """
Disassembly of section .text.f:

00000000 <f>:
   0:\t0e 94 00 00 \tcall\t0\t; 0x0 <f>
\t\t\t0: R_AVR_CALL\tg
   4:\t01 f4       \tbrne\t.+4      \t; 0xa <f+0xa>
   6:\t0c 94 00 00 \tjmp\t0\t; 0x0 <f>
\t\t\t6: R_AVR_CALL\th
   a:\tf9 f7       \tbrne\t.-2      \t; 0xa <f+0xa>
   c:\t01 f4       \tbrne\t.+2      \t; 0x10 <f+0x10>
\t\t\tc: R_AVR_7_PCREL\t.text.f+0x10
   e:\t08 95       \tret
  10:\t08 95       \tret
"""


def self_test():
    got = findings(SELF_TEST_DUMP)
    # Only the brne at 4: it has no relocation and jumps over the jmp at 6.
    # The brne at a spans nothing relaxable; the one at c has a relocation.
    ok = [(n, o) for n, o, _ in got] == [(".text.f", 4)]
    doctored = SELF_TEST_DUMP.replace("\t\t\tc: R_AVR_7_PCREL\t.text.f+0x10\n", "").replace(
        "   e:\t08 95       \tret", "   e:\t0c 94 00 00 \tjmp\t0")
    ok = ok and len(findings(doctored)) == 2
    print("avr_relax_check: self-test", "passed" if ok else "FAILED")
    return ok


def main(argv):
    if argv[1:] == ["--self-test"]:
        return 0 if self_test() else 1
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    results = [check(obj) for obj in argv[1:]]
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
