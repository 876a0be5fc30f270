#!/usr/bin/env bash
# setup.sh: Gradescope runs this once, as root, when it builds the
# autograder's image from the zip `syrof gradescope` wrote (docs/grading.md,
# "Publishing to Gradescope"). Two steps:
#   1. install SyROF from the Debian package in this bundle, with apt-get so
#      its dependencies (and the compiler a submission needs) come along;
#      SYROF_SKIP_INSTALL=1 skips it, for a machine that has SyROF already;
#   2. check that the installed `syrof` runs and the assignment is here.
# AUTOGRADER_ROOT (default /autograder) is where Gradescope lays things out.
set -euo pipefail

root="${AUTOGRADER_ROOT:-/autograder}"
source_dir="$root/source"

install_syrof() {
  local packages=("$source_dir"/syrof_*.deb)
  if [ ! -f "${packages[0]}" ]; then
    echo "setup.sh: no syrof_*.deb in $source_dir" >&2
    return 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q "${packages[@]}"
}

check_syrof() {
  if ! command -v syrof >/dev/null; then
    echo "setup.sh: the syrof command is not on PATH" >&2
    return 1
  fi
  if ! syrof --help >/dev/null; then
    echo "setup.sh: syrof does not run: $(command -v syrof)" >&2
    return 1
  fi
  if [ ! -f "$source_dir/assignment/assignment.yaml" ]; then
    echo "setup.sh: no assignment/assignment.yaml in $source_dir" >&2
    return 1
  fi
  echo "setup.sh: $(command -v syrof) is ready to grade $source_dir/assignment"
}

if [ "${SYROF_SKIP_INSTALL:-0}" != 1 ]; then
  install_syrof
fi
check_syrof
