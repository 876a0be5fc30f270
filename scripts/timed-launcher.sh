#!/bin/sh
# A compiler and linker launcher that measures: appends one line per call,
# "user_s sys_s wall_s output", to $TIMED_LOG (default /tmp/syrof-timed.log).
# CPU seconds stay meaningful when other builds load the machine. Used for
# the figures in docs/building.md ("CI"):
#   CCACHE_DISABLE=1 TIMED_LOG=$PWD/times.log cmake -G Ninja -S . -B build-timed \
#     -DCMAKE_CXX_COMPILER_LAUNCHER=$PWD/scripts/timed-launcher.sh \
#     -DCMAKE_C_COMPILER_LAUNCHER=$PWD/scripts/timed-launcher.sh \
#     -DCMAKE_CXX_LINKER_LAUNCHER=$PWD/scripts/timed-launcher.sh
#   TIMED_LOG=$PWD/times.log ninja -C build-timed
#   awk '{printf "%.1f %s\n", $1 + $2, $4}' times.log | sort -rn | head -30
output=unknown
previous=
for argument in "$@"; do
  if [ "$previous" = "-o" ]; then output=$argument; fi
  previous=$argument
done
exec /usr/bin/time -a -o "${TIMED_LOG:-/tmp/syrof-timed.log}" -f "%U %S %e $output" "$@"
