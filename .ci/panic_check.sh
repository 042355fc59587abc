#!/usr/bin/env bash
# Panic call sites by caller. For every release image, finds each call of a
# panic entry (core::panicking::*, panic_bounds_check, slice index failures,
# unwrap_failed, expect_failed, str slice errors, the panic handler, …) in
# the disassembly, resolves it through inlining to the source line that
# panics and the crate that line is in (.ci/panic_sites.sh), and
#
#  - fails on every site in this project's code (src/, sun_algos/, drivers/),
#    naming file:line — these cannot be allowed;
#  - fails on every third-party or core site not allowed by crate and
#    function in .ci/panic_allow.txt;
#  - prints, per image, the remaining third-party sites by function.
#
#   bash .ci/panic_check.sh              build the images (skip: NO_BUILD=1), check
#   bash .ci/panic_check.sh --self-test  build the QEMU image with a deliberate
#                                        out-of-bounds index in src/controller/mod.rs
#                                        (--cfg suntracker_panic_canary, own
#                                        target dir) and exit 0 only if the
#                                        check fails naming src/controller/mod.rs
#
# Needs readelf (binutils), arm-none-eabi-objdump/-addr2line (Debian package
# binutils-arm-none-eabi) and avr-objdump/avr-addr2line (binutils-avr, comes
# with gcc-avr).
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=.ci/firmware_env.sh
source .ci/firmware_env.sh

ALLOW=.ci/panic_allow.txt

# The allow list: "image-glob crate function-glob # reason", one a line.
declare -a AL_IMAGE=() AL_CRATE=() AL_FUNC=() AL_LINE=() AL_USED=()
load_allow() {
  local n=0 line body reason image crate func
  [ -f "$ALLOW" ] || return 0
  while IFS= read -r line || [ -n "$line" ]; do
    n=$((n + 1))
    case "$line" in '' | \#*) continue ;; esac
    body=${line%%#*}
    reason=${line#"$body"}
    reason=${reason#\#}
    read -r image crate func <<<"$body"
    if [ -z "${func:-}" ] || [ -z "${reason// /}" ]; then
      echo "panic_check: $ALLOW:$n: expected 'image-glob crate function-glob  # reason': $line" >&2
      exit 2
    fi
    # Trailing blanks of the function pattern are not part of it.
    func=${func%"${func##*[![:space:]]}"}
    AL_IMAGE+=("$image")
    AL_CRATE+=("$crate")
    AL_FUNC+=("$func")
    AL_LINE+=("$n")
    AL_USED+=(0)
  done <"$ALLOW"
}

allowed() { # image crate function -> 0 if an entry allows it
  local i
  for i in "${!AL_IMAGE[@]}"; do
    # shellcheck disable=SC2053 # the list holds globs
    if [[ $1 == ${AL_IMAGE[$i]} && $2 == ${AL_CRATE[$i]} && $3 == ${AL_FUNC[$i]} ]]; then
      AL_USED[i]=1
      return 0
    fi
  done
  return 1
}

status=0
SUMMARY=()
check() { # image elf
  local image=$1 elf=$2 sites addr kind crate fun loc outer entry
  local n=0 n_prj=0 n_tp=0 n_lib=0 n_bad=0 key caller via
  local -A count=() reached=() verdict=()
  local -a keys=() project=()
  echo
  echo "== $image: ${elf#"$PWD"/}"
  if [ ! -f "$elf" ]; then
    echo "   missing ELF (build it first)"
    SUMMARY+=("$(printf '%-20s %6s %8s %16s %10s  %s' "$image" - - - - 'MISSING ELF')")
    status=1
    return
  fi
  sites=$(bash .ci/panic_sites.sh "$elf")
  while IFS=$'\t' read -r addr kind crate fun loc outer entry caller; do
    [ -n "$addr" ] || continue
    n=$((n + 1))
    if [ "$kind" = project ]; then
      n_prj=$((n_prj + 1))
      project+=("$loc: calls $entry in $fun (crate $crate; inlined into $outer, at $addr)")
      continue
    fi
    if [ "$kind" = library ]; then n_lib=$((n_lib + 1)); else n_tp=$((n_tp + 1)); fi
    key="$crate"$'\t'"$fun"
    if [ -z "${count[$key]:-}" ]; then
      keys+=("$key")
      count[$key]=0
      reached[$key]=""
      if allowed "$image" "$crate" "$fun"; then verdict[$key]=allowed; else verdict[$key]="NOT ALLOWED"; fi
    fi
    count[$key]=$((count[$key] + 1))
    # Where the crate is entered from, and the function symbol it is in.
    via=$outer
    if [ -n "$caller" ] && [ "$caller" != "$outer" ]; then via="$caller, in $outer"; fi
    if [ "$outer" != "$fun" ]; then
      case $'\n'"${reached[$key]}"$'\n' in
        *$'\n'"$via"$'\n'*) ;;
        *) reached[$key]+="${reached[$key]:+$'\n'}$via" ;;
      esac
    fi
    [ "${verdict[$key]}" = allowed ] || n_bad=$((n_bad + 1))
  done <<<"$sites"

  if [ ${#project[@]} -gt 0 ]; then
    echo "   PANIC SITES IN PROJECT CODE (remove the panicking operation; these cannot be allowed):"
    printf '     %s\n' "${project[@]}"
  fi
  if [ ${#keys[@]} -gt 0 ]; then
    echo "   third-party and core panic sites by function (sites, crate, function;"
    echo "   <- the function outside that crate it is inlined into, and the function symbol):"
    local k
    while IFS= read -r k; do
      crate=${k%%$'\t'*}
      fun=${k#*$'\t'}
      printf '   %3d  %-8s %s  [%s]\n' "${count[$k]}" "$crate" "$fun" "${verdict[$k]}"
      [ -z "${reached[$k]}" ] || printf '%s\n' "${reached[$k]}" | sed 's/^/           <- /'
    done < <(printf '%s\n' "${keys[@]}" | sort -t$'\t' -k1,1 -k2,2)
  elif [ "$n_prj" -eq 0 ]; then
    echo "   no panic call sites"
  fi
  if [ "$n_bad" -gt 0 ]; then
    echo "   $n_bad site(s) NOT ALLOWED: add 'image crate function  # reason' to $ALLOW, or remove them"
  fi

  local v=ok
  if [ "$n_prj" -gt 0 ] || [ "$n_bad" -gt 0 ]; then
    v=PANICS
    status=1
  fi
  SUMMARY+=("$(printf '%-20s %6d %8d %16d %10d  %s' "$image" "$n" "$n_prj" "$((n_tp + n_lib))" "$n_bad" "$v")")
}

summary() {
  echo
  printf '%-20s %6s %8s %16s %10s  %s\n' image sites project third-party/core unallowed verdict
  printf '%s\n' "${SUMMARY[@]}"
}

self_test() {
  local dir="$FW_TARGET_DIR/panic-canary" out rc=0
  echo "panic_check self-test: building qemu_tracker with --cfg suntracker_panic_canary in $dir" >&2
  # RUSTFLAGS replaces .cargo/config.toml's rustflags: keep its link script.
  RUSTFLAGS="-C link-arg=-Tlink.x --cfg suntracker_panic_canary" \
    cargo build --release --target thumbv7em-none-eabihf -p suntracker-mps2-an386 --bin qemu_tracker \
    --target-dir "$dir" >&2
  load_allow
  out=$(
    check qemu_tracker "$dir/thumbv7em-none-eabihf/release/qemu_tracker"
    echo "status=$status"
  ) || rc=$?
  grep -v '^status=' <<<"$out"
  if [ "$rc" -ne 0 ]; then
    echo "panic_check self-test: FAILED (the check itself broke, exit $rc)" >&2
    return 1
  fi
  if grep -q '^status=1$' <<<"$out" && grep -q 'src/controller/mod\.rs:[0-9]' <<<"$out"; then
    echo "panic_check self-test: ok (the canary index in src/controller/mod.rs turned the check red)"
    return 0
  fi
  echo "panic_check self-test: FAILED (the canary out-of-bounds index in src/controller/mod.rs was not reported)" >&2
  return 1
}

case "${1:-}" in
  --self-test)
    self_test
    exit
    ;;
  '') ;;
  *)
    echo "usage: $0 [--self-test]" >&2
    exit 2
    ;;
esac

if [ "${NO_BUILD:-0}" != 1 ]; then
  build_all_firmware >&2
fi
load_allow

check avr_tracker "$ELF_AVR_UNO"
check avr_settings "$ELF_AVR_SETTINGS"
check uno_library_firmware "$ELF_AVR_UNO_LIBRARY"
check avr_mega_tracker "$ELF_AVR_MEGA"
check avr_mega_tracker_dc "$ELF_AVR_MEGA_DC"
check qemu_tracker "$ELF_QEMU"
check blackpill_tracker "$ELF_BLACKPILL"
check blackpill_tracker_modbus "$ELF_BLACKPILL_MODBUS"
check blackpill_tracker_dc "$ELF_BLACKPILL_DC"
summary

for i in "${!AL_LINE[@]}"; do
  if [ "${AL_USED[$i]}" = 0 ]; then
    echo "panic_check: note: $ALLOW:${AL_LINE[$i]} allows no site of any image (stale?)"
  fi
done

if [ "$status" -ne 0 ]; then
  echo "panic_check: FAILED (panic call sites in project code or not allowed in $ALLOW, or an image missing)" >&2
else
  echo "panic_check: ok (no panic call site in project code; every other one allowed in $ALLOW)"
fi
exit "$status"
