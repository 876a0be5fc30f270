#!/usr/bin/env bash
# A student's path against the installed Debian package alone (CI runs it
# after `apt-get install ./build/syrof_*.deb`): in a fresh folder outside
# the source tree, with a clean environment, `syrof new` (C and C++) ->
# cmake build -> `syrof run` with /usr/bin/syrof, and the Makefile way
# through pkg-config. Fails unless every run reached its end and wrote
# metrics.json without faults. Then a student grades the installed gather
# starter with `syrof grade` (the public tests, the hidden ones not being
# installed).
set -euo pipefail
syrof=${SYROF:-/usr/bin/syrof}
[ -x "$syrof" ] || { echo "try-installed-package: no $syrof; install the package first" >&2; exit 1; }
for file in /usr/libexec/syrof/syrof-app-host /usr/include/syrof/app.h /usr/include/syrof/queries/queries.h \
            /usr/lib/cmake/SyROF/SyROFConfig.cmake /usr/lib/pkgconfig/syrof-app.pc; do
  [ -e "$file" ] || { echo "try-installed-package: the package did not install $file" >&2; exit 1; }
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Nothing of a build tree may help: no CMAKE_PREFIX_PATH, PATH without it.
clean=(env -i "HOME=$work" "PATH=/usr/bin:/bin" "TMPDIR=${TMPDIR:-/tmp}")

# Reached the end (the scenario's 30 s) with metrics.json and no fault.
check_run() {
  local metrics=$1
  grep -q '"sim_seconds": 30' "$metrics" || { echo "try-installed-package: $metrics: the run did not reach 30 s" >&2; exit 1; }
  grep -q '"faults": \[\],' "$metrics" || { echo "try-installed-package: $metrics: faults" >&2; exit 1; }
}

for lang in c cpp; do
  name="installed_$lang"
  (
    cd "$work"
    "${clean[@]}" "$syrof" new "$name" --lang "$lang"
    cd "$name"
    grep -q 'HINTS "/usr/lib/cmake/SyROF"' CMakeLists.txt
    "${clean[@]}" cmake -S . -B build > build.log 2>&1 && "${clean[@]}" cmake --build build >> build.log 2>&1 ||
      { cat build.log >&2; exit 1; }
    "${clean[@]}" "$syrof" run scenario.yaml
  )
  check_run "$work/$name/out/$name/metrics.json"
  echo "try-installed-package: $lang: syrof new -> build -> run against the installed package: ok"
done

# The Makefile way: the C starter built by hand with pkg-config.
(
  cd "$work/installed_c"
  "${clean[@]}" sh -c 'gcc -shared -fPIC -o libby_hand.so app.c $(pkg-config --cflags --libs syrof-app) -lm'
  "${clean[@]}" "$syrof" run scenario.yaml --app ./libby_hand.so --out out/by_hand --quiet
)
check_run "$work/installed_c/out/by_hand/metrics.json"
echo "try-installed-package: gcc with pkg-config --cflags --libs syrof-app: ok"

# A student grading the installed gather starter: the package carries the
# assignment as students get it (no hidden sets), so the public tests only.
(
  cd "$work"
  cp -r /usr/share/syrof/assignments/gather/starter gather_starter
  "${clean[@]}" "$syrof" grade gather_starter --assignment gather --out graded > grade.txt 2>&1 ||
    { cat grade.txt >&2; exit 1; }
  grep -q 'Tests passed 0/5, Points 50.00/100.00' grade.txt || { cat grade.txt >&2; exit 1; }
  for file in grade.json results.json junit.xml report.html; do
    [ -s "graded/$file" ] || { echo "try-installed-package: syrof grade wrote no $file" >&2; exit 1; }
  done
)
echo "try-installed-package: syrof grade of the installed gather starter (public tests): ok"
