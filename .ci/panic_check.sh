#!/usr/bin/env bash
# Panic-free images: fails when a release ELF's symbol table holds
# a function of `core::panicking` or `panic_bounds_check` (the targets of
# every panic call site; with LTO and gc-sections they only stay in the
# image when reachable code calls them). Builds the images first (skip with
# NO_BUILD=1) and prints one row per image.
#
#   bash .ci/panic_check.sh
#
# Reads symbols with `readelf -s` (binutils; any architecture) and matches
# both Rust manglings (legacy `_ZN4core9panicking…` and v0
# `…4core9panicking…`). Leftovers that cannot be removed are listed in
# .ci/panic_allow.txt as `image symbol-substring  # reason`; none are listed
# today.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=.ci/firmware_env.sh
source .ci/firmware_env.sh

if [ "${NO_BUILD:-0}" != 1 ]; then
  build_all_firmware >&2
fi

allowed() { # image symbol
  [ -f .ci/panic_allow.txt ] || return 1
  local image pattern _rest
  while read -r image pattern _rest; do
    case "$image" in '' | \#*) continue ;; esac
    if [ "$image" = "$1" ] && [[ "$2" == *"$pattern"* ]]; then return 0; fi
  done <.ci/panic_allow.txt
  return 1
}

status=0
printf '%-20s %8s %8s  %s\n' image found allowed verdict
check() { # image elf
  local image=$1 elf=$2 found=0 allowed_n=0 sym bad=()
  if [ ! -f "$elf" ]; then
    printf '%-20s missing ELF %s\n' "$image" "$elf"
    status=1
    return
  fi
  while read -r sym; do
    found=$((found + 1))
    if allowed "$image" "$sym"; then
      allowed_n=$((allowed_n + 1))
    else
      bad+=("$sym")
    fi
  done < <(readelf -s -W "$elf" | awk '{print $8}' | grep -E 'core9panicking|panic_bounds_check' | sort -u)
  if [ ${#bad[@]} -eq 0 ]; then
    printf '%-20s %8d %8d  %s\n' "$image" "$found" "$allowed_n" ok
  else
    printf '%-20s %8d %8d  %s\n' "$image" "$found" "$allowed_n" PANICS
    local s
    for s in "${bad[@]}"; do
      printf '    %s\n' "$(echo "$s" | c++filt 2>/dev/null || echo "$s")"
    done
    status=1
  fi
}

check avr_tracker "$ELF_AVR_UNO"
check avr_mega_tracker "$ELF_AVR_MEGA"
check qemu_tracker "$ELF_QEMU"
check blackpill_tracker "$ELF_BLACKPILL"

if [ "$status" -ne 0 ]; then
  echo "panic_check: FAILED (panic call sites in a release image, or an image missing)" >&2
else
  echo "panic_check: no panic call sites outside the list in .ci/panic_allow.txt"
fi
exit "$status"
