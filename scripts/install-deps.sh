#!/usr/bin/env bash
# Installs tpcal's build and test dependencies from Debian 12 packages (about 1 GB, ~2 min).
# Run as root or with sudo. Used by README command 1 and by .ci/run.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
APT="$SUDO apt-get -o DPkg::Lock::Timeout=300 -y --no-install-recommends"
$SUDO apt-get -o DPkg::Lock::Timeout=300 update -qq
# Build: compiler, CMake, Ninja and the libraries behind each module.
$APT install g++ cmake ninja-build git pkg-config \
  libeigen3-dev libceres-dev libcgal-dev libgmp-dev libmpfr-dev libpcl-dev \
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev \
  libyaml-cpp-dev libcli11-dev libfmt-dev libfast-float-dev nlohmann-json3-dev libxxhash-dev libtbb-dev libxml2-dev \
  libgtest-dev libgmock-dev libbenchmark-dev
# scripts/test.sh's sanitizer stage: clang with its ASan/UBSan/libFuzzer runtimes (the unit tests and
# the fuzz smoke run share that build); about 38 MB of downloads, 230 MB installed.
$APT install clang libclang-rt-14-dev
# Tests: LinuxCNC's standalone interpreter (rs274) checks the NC programs; headless Chromium
# renders the HTML report. --no-install-recommends keeps LinuxCNC's real-time kernel out.
if [ "${TPCAL_SKIP_TEST_DEPS:-0}" != "1" ]; then
  $APT install linuxcnc-uspace chromium
fi
