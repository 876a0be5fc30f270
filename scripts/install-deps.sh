#!/usr/bin/env bash
# Installs the Debian 12 packages SyROF needs, by group:
#
#   install-deps.sh demo   what `make demo` needs: the host build's tools and
#                          every library CMake's configure step looks for and
#                          the `syrof` command links (docs/building.md)
#   install-deps.sh slurm  what `make test-slurm` adds: munge and Slurm's
#                          controller, node daemon and client commands
#   install-deps.sh [all]  everything: the demo group, then what the tests,
#                          the benchmarks, the Debian package, the cross
#                          build, the emulated Cortex-M4, fuzzing and the
#                          sanitizers add, and ccache (every other make target)
#
# Idempotent: packages already present are skipped, and apt is not touched at
# all when nothing is missing. Must run as root (or via sudo).
set -euo pipefail

demo_packages=(
  # host build; patch makes the assignments' broken variants from their
  # references (scripts/broken-variant.sh; build-essential brings it too,
  # through dpkg-dev, but the build needs it by name)
  build-essential cmake ninja-build pkg-config patch
  # design dependencies: configure locates each of them, and the syrof command
  # links them all (the lab, the DDS swarm, the grader and its app host)
  libeigen3-dev libcgal-dev cyclonedds-dev cyclonedds-tools
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  # the app host's system call filter (app_host/)
  libseccomp-dev
  # the Gradescope bundle's zip (grader/report; found through pkg-config)
  libzip-dev
  # the live page's HTTP server (lab/live, `syrof run --live`; found through
  # pkg-config, libcpp-httplib.so linked by syrof)
  libcpp-httplib-dev
  # HMAC-SHA256 of the per-student hidden seeds (grader/; Cyclone DDS links it too)
  libssl-dev
  # GoogleTest and Google Benchmark: configure finds them (a missing one fails
  # there, not in a later make test); a few MB, against Chromium's hundreds
  libgtest-dev libgmock-dev libbenchmark-dev
)

more_packages=(
  # make package: dpkg-shlibdeps (dpkg-dev) for the .deb's Depends, and file, which CPack uses to find the ELF files
  dpkg-dev file
  # make gradescope-prefix: run paths relative to each file in the Gradescope bundle's SyROF;
  # unzip opens bundles as Gradescope does (scripts/gradescope-limits.sh, test-gradescope-bundle.sh)
  patchelf unzip
  # the independent Fast DDS 2.9 reader of the swarm's beacons (tests/sim_dds/interop; fastddsgen runs on Java)
  libfastrtps-dev libfastcdr-dev fastddsgen
  # fuzzing and sanitizers with clang
  clang libclang-rt-14-dev
  # the viewer's browser tests (syrof view's page in headless Chromium; PNG screenshots)
  chromium libpng-dev
  # Teensy 3.2 cross toolchain and the emulated Cortex-M4; jq reads the
  # emulated swarm's JSON in scripts/bridge-hears-firmware-swarm.sh
  gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib qemu-system-arm jq
  # a compiler cache for developers and CI: the build uses it where installed (docs/building.md, "ccache")
  ccache
)

# make test-slurm only (scripts/test-slurm.sh): a one-machine Slurm cluster
slurm_packages=(munge slurmctld slurmd slurm-client)

group=${1:-all}
case "$group" in
  demo) packages=("${demo_packages[@]}") ;;
  all) packages=("${demo_packages[@]}" "${more_packages[@]}") ;;
  slurm) packages=("${slurm_packages[@]}") ;;
  *) echo "usage: install-deps.sh [demo|slurm|all]   (no argument: all)" >&2; exit 2 ;;
esac

missing=()
for package in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$package")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages of group $group present"
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
