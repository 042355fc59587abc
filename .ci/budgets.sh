#!/usr/bin/env bash
# Flash and static-RAM budgets of the firmware images. Builds the
# release images (skip with NO_BUILD=1), prints a size table and exits
# non-zero when any image is over its budget.
#
#   bash .ci/budgets.sh
#
# Sizes are read from the ELF section headers with `readelf` (binutils; any
# architecture), so no cross `size` tool is needed. Flash = every allocated
# section that is loaded from flash (.text, .rodata, .vector_table, .data's
# initial values, …); static RAM = .data + .bss (+ .uninit on Cortex-M).
# The Cortex-M stack is not static: cortex-m-rt places it at the top of RAM.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=.ci/firmware_env.sh
source .ci/firmware_env.sh

if [ "${NO_BUILD:-0}" != 1 ]; then
  build_all_firmware >&2
fi

# section sizes of an ELF: prints "flash ram"
elf_sizes() {
  local flash=0 ram=0 line name type size flags
  while read -r line; do
    # "[Nr] Name Type Address Off Size ES Flg Lk Inf Al", Nr may hold spaces
    line=${line#*]}
    read -r name type _ _ size _ flags _ <<<"$line"
    size=$((16#$size))
    case "$flags" in *A*) ;; *) continue ;; esac
    case "$name" in
      .data) flash=$((flash + size)); ram=$((ram + size)) ;;
      .bss | .uninit | .noinit) ram=$((ram + size)) ;;
      .stack | .heap | .eeprom | .fuse | .lock | .signature) ;;
      *) if [ "$type" = NOBITS ]; then ram=$((ram + size)); else flash=$((flash + size)); fi ;;
    esac
  done < <(readelf -S -W "$1" | grep -E '^ *\[ *[0-9]+\]')
  echo "$flash $ram"
}

status=0
printf '%-20s %-26s %10s %10s %10s %10s  %s\n' image part flash_B budget_B ram_B budget_B verdict
check() { # name part elf flash_budget ram_budget
  local name=$1 part=$2 elf=$3 flash_budget=$4 ram_budget=$5 flash ram verdict=ok
  if [ ! -f "$elf" ]; then
    printf '%-20s %-26s missing ELF %s\n' "$name" "$part" "$elf"
    status=1
    return
  fi
  read -r flash ram < <(elf_sizes "$elf")
  if [ "$flash" -gt "$flash_budget" ] || [ "$ram" -gt "$ram_budget" ]; then
    verdict=OVER
    status=1
  fi
  printf '%-20s %-26s %10d %10d %10d %10d  %s\n' "$name" "$part" "$flash" "$flash_budget" \
    "$ram" "$ram_budget" "$verdict"
}

# ATmega328P: 32 KiB flash less 512 B for a bootloader; 2 KiB RAM of which
# 1,536 B static, the rest for the stack.
check avr_tracker "ATmega328P (Uno)" "$ELF_AVR_UNO" 32256 1536
# ATmega2560: 128 KiB of its 256 KiB (half, leaving room to grow); RAM: the part's 8 KiB.
check avr_mega_tracker "ATmega2560 (Mega)" "$ELF_AVR_MEGA" 131072 8192
# Cortex-M images: 128 KiB flash and 32 KiB static RAM.
check qemu_tracker "Cortex-M4F (QEMU an386)" "$ELF_QEMU" 131072 32768
check blackpill_tracker "STM32F411 (Black Pill)" "$ELF_BLACKPILL" 131072 32768

if [ "$status" -ne 0 ]; then
  echo "budgets: FAILED (an image is over budget or missing)" >&2
else
  echo "budgets: all images within budget"
fi
exit "$status"
