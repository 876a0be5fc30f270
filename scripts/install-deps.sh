#!/usr/bin/env bash
# Installs the Debian 12 packages SyROF needs to build, test, cross-compile and
# emulate. Idempotent: packages already present are skipped, and apt is not
# touched at all when nothing is missing. Must run as root (or via sudo).
set -euo pipefail

packages=(
  # host build
  build-essential cmake ninja-build pkg-config
  # make package: dpkg-shlibdeps (dpkg-dev) for the .deb's Depends, and file, which CPack uses to find the ELF files
  dpkg-dev file
  # design dependencies
  libeigen3-dev libcgal-dev cyclonedds-dev cyclonedds-tools libgtest-dev libgmock-dev
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libfmt-dev libbenchmark-dev
  # the independent Fast DDS 2.9 reader of the swarm's beacons (tests/sim_dds/interop; fastddsgen runs on Java)
  libfastrtps-dev libfastcdr-dev fastddsgen
  # the app host's system call filter (grader/app_host)
  libseccomp-dev
  # the Gradescope bundle's zip (grader/report; found through pkg-config)
  libzip-dev
  # fuzzing and sanitizers with clang
  clang libclang-rt-14-dev
  # the viewer's browser tests (syrof view's page in headless Chromium; PNG screenshots)
  chromium libpng-dev
  # Teensy 3.2 cross toolchain and the emulated Cortex-M4
  gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib qemu-system-arm
)

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: run as root to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
