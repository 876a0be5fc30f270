#!/usr/bin/env bash
# The size table of a Teensy 3.2 image (make firmware): flash and RAM used
# against the firmware's budgets and the chip, from the linker's symbols
# (firmware/boards/teensy32/teensy32.ld) and the image's sections.
#
#   scripts/firmware-size.sh build-teensy/bin/syrof-robot.elf
#
# The link itself fails when the image exceeds a budget or the chip, so this
# only reports. NM=<tool> and SIZE=<tool> override the programs.
set -euo pipefail

if [ $# -ne 1 ]; then
  echo "usage: $0 <image.elf>" >&2
  exit 2
fi
image=$1
nm_tool=${NM:-arm-none-eabi-nm}
size_tool=${SIZE:-arm-none-eabi-size}
[ -f "$image" ] || { echo "firmware-size: no image $image" >&2; exit 1; }

symbol() {
  local value
  value=$("$nm_tool" "$image" | awk -v name="$1" '$3 == name { print $1; exit }')
  [ -n "$value" ] || { echo "firmware-size: $image has no symbol $1 (not a teensy32 image?)" >&2; exit 1; }
  echo $((16#$value))
}
section() {
  "$size_tool" -A "$image" | awk -v name="$1" '$1 == name { print $2; found = 1 } END { if (!found) print 0 }'
}

flash_used=$(symbol __flash_end)
flash_budget=$(symbol __flash_budget)
ram_used=$(symbol __ram_used)
ram_budget=$(symbol __ram_budget)
stack=$(symbol __stack_size)
heap=$(symbol __heap_size)
data=$(section .data)
bss=$(section .bss)
code=$(( $(section .vectors) + $(section .text) + $(section .ARM.exidx) + $(section .init_array) ))

row() { printf '%-44s %9s %9s\n' "$@"; }
percent() { echo "$(( $1 * 100 / $2 ))%"; }
echo "syrof-robot for the Teensy 3.2 ($image)"
row "" bytes "of budget"
row "flash: vectors, code, constants" "$code" ""
row "flash: .data's initial values" "$data" ""
row "flash total (budget $((flash_budget / 1024)) KB, chip 256 KB)" "$flash_used" "$(percent "$flash_used" "$flash_budget")"
row "RAM: .data" "$data" ""
row "RAM: .bss" "$bss" ""
row "RAM: heap (fixed)" "$heap" ""
row "RAM: stack (one, every level)" "$stack" ""
row "RAM total (budget $((ram_budget / 1024)) KB, chip 64 KB)" "$ram_used" "$(percent "$ram_used" "$ram_budget")"
