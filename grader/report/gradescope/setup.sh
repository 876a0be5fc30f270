#!/usr/bin/env bash
# setup.sh: Gradescope runs this once, as root, when it builds the
# autograder's image from the zip `syrof gradescope` wrote (docs/grading.md,
# "Publishing to Gradescope"). SyROF comes in the zip as a self-contained
# folder (source/syrof/: its programs, libsyrof_app, the app API's headers,
# its CMake package, and every library they need that is not glibc's or the
# C++ runtime's), so nothing of SyROF is installed. Two steps:
#   1. what a submission's build needs, a C and C++ compiler, CMake and
#      make, installed with apt-get from the image's own archive when the
#      image lacks them (Gradescope's default, Ubuntu 22.04, has none of
#      them); SYROF_SKIP_INSTALL=1 skips it;
#   2. the check that the bundled syrof runs here (its libraries found, the
#      image's glibc new enough: 2.35 and up) and the assignment is here.
# AUTOGRADER_ROOT (default /autograder) is where Gradescope lays things out.
set -euo pipefail

root="${AUTOGRADER_ROOT:-/autograder}"
source_dir="$root/source"
syrof="$source_dir/syrof/bin/syrof"

install_tools() {
  local missing=()
  command -v cc >/dev/null && command -v c++ >/dev/null || missing+=(build-essential)
  command -v cmake >/dev/null || missing+=(cmake)
  command -v make >/dev/null || missing+=(make)
  if [ ${#missing[@]} -eq 0 ]; then
    echo "setup.sh: a compiler, CMake and make are here already"
    return 0
  fi
  if ! command -v apt-get >/dev/null; then
    echo "setup.sh: this image lacks ${missing[*]} and has no apt-get to install them" >&2
    return 1
  fi
  echo "setup.sh: installing ${missing[*]} from the image's archive"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends "${missing[@]}"
}

check_syrof() {
  if [ ! -x "$syrof" ]; then
    echo "setup.sh: no syrof/bin/syrof in $source_dir: the zip was not written by syrof gradescope" >&2
    return 1
  fi
  local problem
  if ! problem=$("$syrof" --help 2>&1 >/dev/null); then
    echo "setup.sh: the bundled syrof does not run on this image: $problem" >&2
    echo "setup.sh: it needs glibc 2.35 or newer and libstdc++6 of GCC 12 or newer (Ubuntu 22.04 has both)" >&2
    return 1
  fi
  for tool in cc c++ cmake make; do
    command -v "$tool" >/dev/null || { echo "setup.sh: $tool is missing: a submission cannot be built" >&2; return 1; }
  done
  if [ ! -f "$source_dir/assignment/assignment.yaml" ]; then
    echo "setup.sh: no assignment/assignment.yaml in $source_dir" >&2
    return 1
  fi
  echo "setup.sh: $syrof is ready to grade $source_dir/assignment"
}

if [ "${SYROF_SKIP_INSTALL:-0}" != 1 ]; then
  install_tools
fi
check_syrof
