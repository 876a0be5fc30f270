#!/usr/bin/env bash
# Prints text, data and bss per static library of a cross build, and a total.
#
#   scripts/size-table.sh build-cross/lib
#
# Sizes are the sums over each archive's object files as arm-none-eabi-size
# reports them (Berkeley format): what the library could add to a firmware
# image at most. The linker drops unused sections (-ffunction-sections,
# -fdata-sections, --gc-sections), so a real image holds less.
# SIZE=<tool> overrides the size program.
set -euo pipefail

if [ $# -ne 1 ]; then
  echo "usage: $0 <directory of .a files>" >&2
  exit 2
fi
lib_dir=$1
size_tool=${SIZE:-arm-none-eabi-size}

if [ ! -d "$lib_dir" ]; then
  echo "size-table: no directory $lib_dir" >&2
  exit 1
fi
command -v "$size_tool" >/dev/null || { echo "size-table: $size_tool not found" >&2; exit 1; }

shopt -s nullglob
archives=("$lib_dir"/*.a)
if [ ${#archives[@]} -eq 0 ]; then
  echo "size-table: no .a files in $lib_dir" >&2
  exit 1
fi

format='%-24s %10s %10s %10s\n'
printf "$format" library text data bss
total_text=0 total_data=0 total_bss=0
for archive in "${archives[@]}"; do
  name=$(basename "$archive" .a)
  name=${name#lib}
  # One line per member after a header: text data bss dec hex filename.
  read -r text data bss < <("$size_tool" --format=berkeley "$archive" |
    awk 'NR > 1 { text += $1; data += $2; bss += $3 } END { print text + 0, data + 0, bss + 0 }')
  printf "$format" "$name" "$text" "$data" "$bss"
  total_text=$((total_text + text))
  total_data=$((total_data + data))
  total_bss=$((total_bss + bss))
done
printf "$format" total "$total_text" "$total_data" "$total_bss"
