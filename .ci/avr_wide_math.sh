#!/usr/bin/env bash
# No software double precision and no 64-bit division in any AVR image.
#
# The 8-bit images compute in f32 and in integers of at most 32 bits where
# they divide: the soft-float f64 routines (compiler_builtins' __adddf3,
# __divdf3, __muldf3, conversions, comparisons) are 3-4 KB each, the 64-bit
# division routines (__udivdi3, __divdi3 and compiler_builtins' u64_div_rem)
# 3 KB together. A definition of any of them in an image means some caller
# uses it; the check fails naming the image, the routine and its callers (from
# the disassembly). 64-bit multiplication (__muldi3) and i64 -> f32
# (__floatdisf) are allowed.
#
#   bash .ci/avr_wide_math.sh              check every AVR image named in
#                                          .ci/firmware_env.sh (ELF_AVR_*; built
#                                          first: a missing image fails)
#   bash .ci/avr_wide_math.sh --self-test  exit 0 only if the check turns red on
#                                          real routines: AVR ELFs linked with
#                                          avr-gcc that divide two u64s (libgcc's
#                                          or compiler_builtins' __udivdi3) and
#                                          that add two doubles (compiler_builtins'
#                                          __adddf3, from the Uno build's
#                                          libcompiler_builtins rlib), stays green
#                                          on one that multiplies u64s and divides
#                                          u32s, and matches every routine of the
#                                          lists above by name
#
# Needs avr-nm, avr-objdump (binutils-avr), avr-gcc + avr-libc (self-test),
# c++filt (binutils) for readable callers.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=.ci/firmware_env.sh
source .ci/firmware_env.sh

# Software f64: libgcc's and compiler_builtins' names (the same names end
# compiler_builtins' mangled symbols, so the patterns are anchored at the
# end only).
F64_RE='__(add|sub|mul|div|neg)df3|__(extendsfdf2|truncdfsf2)|__(fix|fixuns)df[sdt]i|__float(un)?[sdt]idf|__(eq|ne|lt|le|gt|ge|unord|cmp)df2|__powidf2'
# 64-bit (and 128-bit) division: libgcc's entry points and AVR helpers,
# compiler_builtins' specialised u64/i64/u128/i128 division.
DIV64_RE='__u?(div|mod)(di|ti)3|__u?divmod(di|ti)4|__u?divmod64|__divdi3_moddi3|__udivdi3_umoddi3|[iu](64|128)_div_rem'
# compiler_builtins' overflow-checked products (`checked_mul`,
# `overflowing_mul` on i32/i64): on the ATmega2560 a `checked_mul` through
# __mulosi4 was seen to overwrite static RAM (the configuration's site
# read back as 0°, 0° and the stack ran into .bss); the firmware bounds its
# operands first and multiplies plainly instead.
MULO_RE='__mulo[sdt]i4'
WIDE_RE="(${F64_RE}|${DIV64_RE}|${MULO_RE})\$"

die() { echo "avr_wide_math: $*" >&2; exit 2; }

# Defined symbol names of an ELF, object or archive, one a line.
defined_symbols() {
  local out
  out=$(avr-nm --defined-only "$1" 2>&1) || { echo "avr-nm cannot read $1: ${out%%$'\n'*}" >&2; return 1; }
  awk 'NF >= 2 { print $NF }' <<<"$out"
}

# "caller -> routine" for each call or jump to a wide routine.
callers() { # elf
  avr-objdump -d "$1" | awk -v re="$WIDE_RE" '
    /^[0-9a-f]+ <.*>:$/ { fn = $0; sub(/^[0-9a-f]+ </, "", fn); sub(/>:$/, "", fn); next }
    /\t(r?call|r?jmp)\t/ && match($0, /<[^>+]+/) {
      target = substr($0, RSTART + 1, RLENGTH - 1)
      if (target ~ re && fn !~ re) print fn " -> " target
    }' | sort -u | { if command -v c++filt >/dev/null; then c++filt; else cat; fi; }
}

# Checks one image: 0 when it defines no wide routine.
check_elf() { # label elf
  local label=$1 elf=$2 syms hits
  if [ ! -f "$elf" ]; then
    echo "FAIL $label: missing ELF ${elf#"$PWD"/} (build it first)"
    return 1
  fi
  syms=$(defined_symbols "$elf") || { echo "FAIL $label: unreadable ELF"; return 1; }
  if ! grep -q . <<<"$syms"; then
    echo "FAIL $label: no symbols in ${elf#"$PWD"/} (stripped?): nothing to check"
    return 1
  fi
  hits=$(grep -E "$WIDE_RE" <<<"$syms" | sort -u || true)
  if [ -n "$hits" ]; then
    echo "FAIL $label: software f64, 64-bit division or an overflow-checked product in ${elf#"$PWD"/}:"
    sed 's/^/    defines  /' <<<"$hits"
    callers "$elf" | sed 's/^/    called   /'
    return 1
  fi
  echo "ok   $label: no software f64, no 64-bit division, no overflow-checked product ($(wc -l <<<"$syms") symbols)"
}

check_all() {
  local var status=0 n=0
  # Every AVR image firmware_env.sh names (a new one is checked too).
  for var in $(compgen -v ELF_AVR_); do
    n=$((n + 1))
    check_elf "$var" "${!var}" || status=1
  done
  [ "$n" -gt 0 ] || die "no ELF_AVR_* image in .ci/firmware_env.sh"
  if [ "$status" -ne 0 ]; then
    echo "avr_wide_math: software f64 or 64-bit division linked into an AVR image (or an image missing)" >&2
  fi
  return $status
}

self_test() {
  local dir rlib out fails=0 name
  dir=$(mktemp -d)
  # shellcheck disable=SC2064 # the directory is known now
  trap "rm -rf '$dir'" EXIT
  # compiler_builtins as the ATmega328P images link it (avr:5 objects).
  rlib=$(find "$FW_TARGET_DIR/avr-none" -name 'libcompiler_builtins-*.rlib' -print -quit 2>/dev/null || true)
  [ -n "$rlib" ] || die "self-test: no libcompiler_builtins rlib under $FW_TARGET_DIR/avr-none (build the Uno images first)"

  cat >"$dir/clean.c" <<'EOF'
volatile unsigned long long a = 1234567890123ULL, b = 97;
volatile unsigned long c = 4000000000UL, d = 7;
volatile float x = 1.5f;
int main(void) { a = a * b; c = c / d; x = x + x; return 0; }
EOF
  cat >"$dir/div64.c" <<'EOF'
volatile unsigned long long a = 1234567890123ULL, b = 97;
int main(void) { a = a / b; return 0; }
EOF
  # avr-gcc's double is 32 bits: compiler_builtins' f64 addition is called
  # by its name (the arguments are the two doubles' bits).
  cat >"$dir/f64.c" <<'EOF'
extern unsigned long long __adddf3(unsigned long long, unsigned long long);
volatile unsigned long long a = 0x3ff0000000000000ULL;
int main(void) { a = __adddf3(a, a); return 0; }
EOF
  for name in clean div64 f64; do
    avr-gcc -mmcu=atmega328p -Os -Wl,--gc-sections -o "$dir/$name.elf" "$dir/$name.c" "$rlib" \
      || die "self-test: avr-gcc could not link $name.c"
  done

  if out=$(check_elf clean "$dir/clean.elf"); then
    echo "self-test: green on u64 multiplication, u32 division and f32 addition"
  else
    echo "$out"; echo "self-test: FAILED: the clean ELF was refused" >&2; fails=1
  fi
  for name in div64:__udivdi3 f64:__adddf3; do
    if out=$(check_elf "${name%%:*}" "$dir/${name%%:*}.elf"); then
      echo "$out"; echo "self-test: FAILED: ${name%%:*}.elf passed" >&2; fails=1
    elif ! grep -q "defines  .*${name#*:}" <<<"$out"; then
      echo "$out"; echo "self-test: FAILED: ${name%%:*}.elf refused without naming ${name#*:}" >&2; fails=1
    else
      echo "self-test: red on ${name%%:*}.elf:"; echo "$out"
    fi
  done

  # The names: each routine to refuse is matched, each allowed one is not;
  # those compiler_builtins defines are taken from its own symbols.
  local syms cb
  syms=$(defined_symbols "$rlib") || die "self-test: cannot read $rlib"
  for name in __adddf3 __subdf3 __muldf3 __divdf3 __truncdfsf2 __extendsfdf2 __fixdfdi __floatdidf \
    __floatunsidf __floatsidf __eqdf2 __ltdf2 __unorddf2 __divdi3 __udivdi3 __moddi3 __umoddi3 \
    u64_div_rem u128_div_rem; do
    # The plain name or the tail of a mangled one (…8___adddf3, …11u64_div_rem).
    cb=$(grep -E "(^|[_0-9])${name}\$" <<<"$syms" | head -1 || true)
    [ -n "$cb" ] || { echo "self-test: FAILED: compiler_builtins defines no $name (renamed?)" >&2; fails=1; continue; }
    grep -qE "$WIDE_RE" <<<"$cb" || { echo "self-test: FAILED: $cb not matched" >&2; fails=1; }
  done
  for name in __udivmoddi4 __divmoddi4 __udivmod64 __divdi3_moddi3 i64_div_rem i128_div_rem __udivti3; do
    grep -qE "$WIDE_RE" <<<"$name" || { echo "self-test: FAILED: $name not matched" >&2; fails=1; }
  done
  for name in __muldi3 __floatdisf __floatundisf __udivmodsi4 __divmodsi4 __addsf3 __divsf3 \
    __fixsfdi _RNvNtNtCs4mWSxh7ZaAc_17compiler_builtins3int19specialized_div_rem11u32_div_rem; do
    if grep -qE "$WIDE_RE" <<<"$name"; then
      echo "self-test: FAILED: allowed routine $name matched" >&2; fails=1
    fi
  done
  [ "$fails" -eq 0 ] || exit 1
  echo "self-test: passed (red on real u64 division and f64 addition, green without; names matched)"
}

case "${1:-}" in
  --self-test) self_test ;;
  "") check_all ;;
  *) die "usage: bash .ci/avr_wide_math.sh [--self-test]" ;;
esac
