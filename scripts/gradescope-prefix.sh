#!/usr/bin/env bash
# SyROF as a self-contained folder for the Gradescope bundle (docs/grading.md,
# "Publishing to Gradescope"): what grading needs, and every shared library
# that needs which Gradescope's default image (Ubuntu 22.04, glibc 2.35) may
# lack, so that the bundle needs nothing from apt but a compiler, CMake and
# make.
#
#   scripts/gradescope-prefix.sh [BUILD_DIR [OUT_DIR]]   (defaults: build, BUILD_DIR/gradescope-prefix)
#   scripts/gradescope-prefix.sh --check DIR             (only the check below, on a folder made before)
#
# 1. `cmake --install BUILD_DIR --prefix OUT_DIR`, then only what grading
#    uses is kept: bin/syrof, libexec/syrof/syrof-app-host, libsyrof_app,
#    the app API's headers, the CMake package and syrof-app.pc.
# 2. Every library those ELF files need (ldd), but glibc's own and the C++
#    runtime (libstdc++, libgcc_s: the image's, see below), is copied into
#    OUT_DIR/lib/syrof-deps/; run paths are set relative to each file
#    ($ORIGIN) with patchelf, so nothing is looked up outside the folder but
#    glibc and the C++ runtime.
# 3. The check, which fails (exit 1) naming the file and what is wrong:
#    every ELF in the folder asks for no glibc symbol version above 2.35,
#    no libstdc++ version above GLIBCXX_3.4.30 / CXXABI_1.3.13 (what Ubuntu
#    22.04's libstdc++6 gives), and needs no library that is neither in the
#    folder nor glibc's nor the C++ runtime's.
# Debian 12's libstdc++ itself asks for glibc 2.36, so it cannot be bundled;
# Ubuntu 22.04's (GCC 12) carries every version SyROF's files ask for.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

readonly max_glibc_minor=35
readonly max_glibcxx_patch=30
readonly max_cxxabi_patch=13
# Libraries of glibc (and the kernel's vDSO), and of the C++ runtime: the image's own.
system_library() {
  case "$1" in
    linux-vdso.so.* | ld-linux-*.so.* | libc.so.6 | libm.so.6 | libpthread.so.0 | libdl.so.2 | librt.so.1 | \
      libresolv.so.2 | libutil.so.1 | libanl.so.1 | libstdc++.so.6 | libgcc_s.so.1) return 0 ;;
  esac
  return 1
}

is_elf() { [ -f "$1" ] && [ "$(head -c 4 "$1" | od -An -c | tr -d ' ')" = '177ELF' ]; }

# The check of step 3 on every ELF file under $1; prints one line per problem.
check_folder() {
  local dir=$1 problems=0 file version needed
  local bundled
  bundled=$(find "$dir" \( -type f -o -type l \) -name '*.so*' -printf '%f\n' | sort -u)
  while IFS= read -r -d '' file; do
    is_elf "$file" || continue
    while read -r version; do
      local minor=${version#GLIBC_2.}; minor=${minor%%.*}
      if [ "$minor" -gt "$max_glibc_minor" ]; then
        echo "gradescope-prefix: ${file#"$dir"/} asks for $version (Ubuntu 22.04 has glibc 2.$max_glibc_minor)"
        problems=$((problems + 1))
      fi
    done < <(objdump -T "$file" | grep -o 'GLIBC_2\.[0-9][0-9.]*' | sort -u)
    while read -r version; do
      local patch=${version##*.} limit=$max_glibcxx_patch
      [[ $version == CXXABI_* ]] && limit=$max_cxxabi_patch
      if [ "$patch" -gt "$limit" ]; then
        echo "gradescope-prefix: ${file#"$dir"/} asks for $version (Ubuntu 22.04's libstdc++6 has GLIBCXX_3.4.$max_glibcxx_patch, CXXABI_1.3.$max_cxxabi_patch)"
        problems=$((problems + 1))
      fi
    done < <(objdump -T "$file" | grep -o 'GLIBCXX_3\.4\.[0-9]*\|CXXABI_1\.3\.[0-9]*' | sort -u)
    while read -r needed; do
      system_library "$needed" && continue
      grep -qxF "$needed" <<<"$bundled" && continue
      echo "gradescope-prefix: ${file#"$dir"/} needs $needed, which is neither in the folder nor glibc's nor the C++ runtime's"
      problems=$((problems + 1))
    done < <(objdump -p "$file" | awk '$1 == "NEEDED" {print $2}')
  done < <(find "$dir" -type f -print0)
  return $(( problems > 0 ))
}

if [ "${1:-}" = --check ]; then
  [ -d "${2:-}" ] || { echo "usage: gradescope-prefix.sh --check DIR" >&2; exit 2; }
  if check_folder "$(cd "$2" && pwd)"; then echo "gradescope-prefix: $2: every ELF file fits Ubuntu 22.04"; exit 0; fi
  exit 1
fi

build=$(cd "${1:-$root/build}" && pwd)
out=${2:-$build/gradescope-prefix}
for tool in patchelf objdump ldd; do
  command -v "$tool" >/dev/null || { echo "gradescope-prefix: $tool is missing (bash scripts/install-deps.sh)" >&2; exit 2; }
done
[ -x "$build/bin/syrof" ] || { echo "gradescope-prefix: no $build/bin/syrof: build first" >&2; exit 2; }

rm -rf "$out"
mkdir -p "$out"
out=$(cd "$out" && pwd)
cmake --install "$build" --prefix "$out" >/dev/null
# Only what grading uses: no robot, bridge, firmware config or installed assignments.
rm -rf "$out/share" "$out/bin/syrof-robot" "$out/bin/syrof-bridge" "$out/bin/syrof-firmware-config"
# A zip holds regular files only: each symbolic link becomes a copy.
find "$out" -type l | while read -r link; do
  target=$(readlink -f "$link")
  rm "$link"
  cp "$target" "$link"
done

deps="$out/lib/syrof-deps"
mkdir -p "$deps"
# The libraries each ELF file needs (transitively, as ldd resolves them here).
mapfile -t elves < <(find "$out/bin" "$out/libexec" "$out/lib" -maxdepth 2 -type f | while read -r f; do is_elf "$f" && echo "$f"; done)
for elf in "${elves[@]}"; do
  ldd "$elf" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}'
done | sort -u | while read -r name path; do
  system_library "$name" && continue
  [ -e "$out/lib/$name" ] && continue  # libsyrof_app, already in the folder
  cp -L "$path" "$deps/$name"
  chmod 0644 "$deps/$name"
done

# Run paths: each file finds the folder's libraries from where it lies.
for elf in "$out"/bin/*; do patchelf --set-rpath '$ORIGIN/../lib:$ORIGIN/../lib/syrof-deps' "$elf"; done
for elf in "$out"/libexec/syrof/*; do patchelf --set-rpath '$ORIGIN/../../lib:$ORIGIN/../../lib/syrof-deps' "$elf"; done
for elf in "$out"/lib/libsyrof_app.so*; do patchelf --set-rpath '$ORIGIN:$ORIGIN/syrof-deps' "$elf"; done
for elf in "$deps"/*; do patchelf --set-rpath '$ORIGIN' "$elf"; done

check_folder "$out"
version=$(sed -n 's/^project(syrof VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")
{
  echo "SyROF $version, self-contained for Gradescope's default image (Ubuntu 22.04): scripts/gradescope-prefix.sh"
  echo "checked: every ELF file asks for glibc 2.$max_glibc_minor at most, GLIBCXX_3.4.$max_glibcxx_patch and CXXABI_1.3.$max_cxxabi_patch at most,"
  echo "and needs no library outside this folder but glibc's and the C++ runtime's (libstdc++6, libgcc-s1)"
  echo "bundled libraries (lib/syrof-deps/): $(ls "$deps" | tr '\n' ' ')"
} > "$out/gradescope-prefix.txt"
echo "gradescope-prefix: $out: $(find "$out" -type f | wc -l) files, $(du -sh "$out" | cut -f1), $(ls "$deps" | wc -l) libraries bundled; every ELF file fits Ubuntu 22.04"
