#!/usr/bin/env bash
# Panic call sites of one release ELF, by caller. Prints one line per call
# site, tab-separated:
#
#   address  kind  crate  site-function  site-file:line  outer-function
#   entry  caller
#
# outer-function is the function symbol the site is compiled into, entry the
# panic function called, caller the innermost frame outside the site's crate
# (and core/alloc) that the site is inlined into (empty if none: the site's
# crate is called through a function symbol of its own).
#
#   bash .ci/panic_sites.sh ELF
#
# How:
#  1. Panic entries are found by symbol in the disassembly: every function of
#     core/alloc named panic*, *_panic, *_fail, *_fail_rt, *_failed or do_panic
#     (core::panicking::*, panic_bounds_check, slice_index_fail and the other
#     slice index failures, option/result unwrap_failed, expect_failed,
#     str::slice_error_fail, cell borrow panics, …) and the panic handler
#     (rust_begin_unwind).
#     A core wrapper named otherwise that calls one of these shows up as a
#     site in core under its own name (not allowed unless listed): add its
#     name here so that its callers are found instead.
#  2. A call site is a direct branch to the start of an entry — `bl`, `b`,
#     `b.w`, conditional branches (tail calls), `cbz`/`cbnz` on ARM; `call`,
#     `rcall`, `jmp`, `rjmp` and `br*` on AVR — from a function that is not
#     itself an entry (panic -> panic_fmt -> rust_begin_unwind is one panic,
#     not three). Calls through a function pointer are not seen (rustc does
#     not emit them for panics).
#  3. `addr2line -f -i` resolves each site through inlining (the images have
#     `debug = true`). The frames are innermost first; the site of the panic
#     is the first frame, going outwards, that is not in core/alloc (those are
#     the unwrap/index/slice helpers that panic on behalf of their caller), or
#     the outermost frame when all of them are (core's own code, e.g. float
#     parsing). Its source path gives the crate:
#       <repo>/src, sun_algos/, drivers/   kind "project" (suntracker,
#                                          sun_algos, drivers)
#       ~/.cargo/registry/src/*/NAME-VER/  kind "third-party", crate NAME
#       .../library/NAME/src/ (rust-src)   kind "library", crate NAME
#     A path that is none of these (or `??`, no debug info) is third-party
#     crate "?". binutils-avr's addr2line (2.26) names the innermost frame
#     after the enclosing symbol; its file:line, and so the crate, are right.
#
# Tools: arm-none-eabi-objdump/-addr2line (Debian binutils-arm-none-eabi) for
# ARM images, avr-objdump/avr-addr2line (binutils-avr, installed with gcc-avr)
# for AVR images; c++filt (binutils) to demangle.
set -euo pipefail

if [ $# -ne 1 ] || [ ! -f "$1" ]; then
  echo "usage: $0 ELF (an existing release image)" >&2
  exit 2
fi
elf=$1
root=$(cd "$(dirname "$0")/.." && pwd)

machine=$(readelf -h "$elf" | sed -n 's/^ *Machine: *//p')
case "$machine" in
  ARM) prefix=arm-none-eabi- ;;
  *AVR*) prefix=avr- ;;
  *)
    echo "panic_sites: $elf: unsupported machine '$machine'" >&2
    exit 2
    ;;
esac
for tool in objdump addr2line; do
  if ! command -v "$prefix$tool" >/dev/null; then
    case "$prefix" in
      arm-*) pkg=binutils-arm-none-eabi ;;
      *) pkg=binutils-avr ;;
    esac
    echo "panic_sites: $prefix$tool not found (Debian package $pkg)" >&2
    exit 2
  fi
done

if ! command -v c++filt >/dev/null; then
  echo "panic_sites: c++filt not found (Debian package binutils)" >&2
  exit 2
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Names are demangled by the host's c++filt (binutils >= 2.36 knows both
# Rust manglings; binutils-avr's own demangler predates v0), without v0's
# crate disambiguators (`core[1a2b…]::`) and legacy hashes (`::h1a2b…`).
demangle() { c++filt | sed -E 's/\[[0-9a-f]{8,}\]//g; s/::h[0-9a-f]{16}//g'; }

"${prefix}objdump" -d --no-show-raw-insn "$elf" | demangle >"$tmp/dis"

# Pass 1 collects the entries (function start addresses), pass 2 the
# branches to them: "address<TAB>enclosing function<TAB>entry".
awk -F'\t' '
function norm(a) { sub(/^0x/, "", a); sub(/^0+/, "", a); return a == "" ? "0" : a }
function is_entry(n) {
  if (n ~ /(^|::)rust_begin_unwind$/) return 1
  if (n !~ /^<?(core|alloc)::/) return 0
  return n ~ /::panicking::/ || n ~ /::panic[a-z0-9_]*(::|$)/ || n ~ /_panic(::|$)/ ||
         n ~ /_fail(_rt)?(::|$)/ || n ~ /_failed(::|$)/ || n ~ /::do_panic(::|$)/
}
function header_name(line) { line = substr(line, index(line, " <") + 2); sub(/>:$/, "", line); return line }
FNR == NR {
  if ($0 ~ /^[0-9a-f]+ <.*>:$/) {
    n = header_name($0)
    if (is_entry(n)) { split($0, h, " "); entry[norm(h[1])] = n }
  }
  next
}
/^[0-9a-f]+ <.*>:$/ { fn = header_name($0); in_entry = is_entry(fn); next }
/^ *[0-9a-f]+:\t/ {
  if (in_entry) next
  mn = $2; gsub(/ /, "", mn)
  if (mn !~ /^bl?(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?(\.[nw])?$/ && mn !~ /^cbn?z$/ &&
      mn !~ /^(call|rcall|jmp|rjmp|br[a-z][a-z])$/) next
  ops = $0
  if (!match(ops, /[0-9a-fx]+ </)) next
  t = norm(substr(ops, RSTART, RLENGTH - 2))
  if (!(t in entry)) next
  a = $1; gsub(/[ :]/, "", a)
  printf "0x%s\t%s\t%s\n", a, (fn == "" ? "?" : fn), entry[t]
}
' "$tmp/dis" "$tmp/dis" >"$tmp/sites"

[ -s "$tmp/sites" ] || exit 0

cut -f1 "$tmp/sites" | "${prefix}addr2line" -a -f -i -e "$elf" | demangle >"$tmp/a2l"

# Joins the sites with their inlining chains and classifies them.
awk -F'\t' -v root="$root" '
function crate_of(p,   s, c) {
  if (p ~ /^\?\?/ || p == "") return "?"
  if (match(p, /\/library\/[A-Za-z0-9_-]+\//)) {
    c = substr(p, RSTART + 9, RLENGTH - 10); gsub(/-/, "_", c); return "lib:" c
  }
  if (match(p, /\/\.cargo\/(registry\/src|git\/checkouts)\/[^\/]+\/[^\/]+\//)) {
    s = substr(p, RSTART, RLENGTH - 1); sub(/.*\//, "", s)
    sub(/-[0-9][^-]*(-[^-]*)?$/, "", s); gsub(/-/, "_", s); return s
  }
  if (index(p, root "/") == 1) p = substr(p, length(root) + 2)
  else if (p ~ /^\//) return "?"
  if (p ~ /^suntracker-time\//) return "prj:suntracker_time"
  if (p ~ /^sun_algos\//) return "prj:sun_algos"
  if (p ~ /^drivers\//) return "prj:drivers"
  if (p ~ /^src\//) return "prj:suntracker"
  return "?"
}
# Short paths: repo-relative, library/core/src/…, NAME-VER/src/….
function rel(p) {
  sub(/ \(discriminator [0-9]+\)$/, "", p)
  if (index(p, root "/") == 1) return substr(p, length(root) + 2)
  if (match(p, /\/library\//)) return substr(p, RSTART + 1)
  if (match(p, /\/\.cargo\/(registry\/src|git\/checkouts)\/[^\/]+\//)) return substr(p, RSTART + RLENGTH)
  return p
}
function flush(   i, s, c, cc, kind, caller) {
  if (addr == "") return
  if (nf == 0 || fun[nf] == "??") { nf++; fun[nf] = encl[addr]; loc[nf] = "??:0" }
  s = 0
  for (i = 1; i <= nf; i++) {
    c = crate_of(loc[i])
    if (c != "lib:core" && c != "lib:alloc") { s = i; break }
  }
  if (s == 0) { s = nf; c = crate_of(loc[nf]) }
  if (c ~ /^prj:/) kind = "project"
  else if (c ~ /^lib:/) kind = "library"
  else kind = "third-party"
  caller = ""
  for (i = s + 1; i <= nf; i++) {
    cc = crate_of(loc[i])
    if (cc != c && cc != "lib:core" && cc != "lib:alloc") { caller = fun[i]; break }
  }
  sub(/^(prj|lib):/, "", c)
  printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", addr, kind, c, fun[s], rel(loc[s]), fun[nf], entry[addr], caller
  addr = ""
}
FNR == NR { entry[$1] = $3; encl[$1] = $2; next }
/^0x[0-9a-f]+$/ {
  flush(); addr = $0; sub(/^0x0*/, "", addr); addr = "0x" addr; nf = 0; want = "fun"; next
}
want == "fun" { nf++; fun[nf] = $0; want = "loc"; next }
want == "loc" { loc[nf] = $0; want = "fun"; next }
END { flush() }
' "$tmp/sites" "$tmp/a2l"
