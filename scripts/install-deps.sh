#!/usr/bin/env bash
# Installs every Debian 12 (bookworm) package Sulcus needs to build, test and run.
# Idempotent: packages already installed are skipped, and `apt-get update` runs
# only when something is missing (or the package lists are older than a day).
# Usage: scripts/install-deps.sh            (as root, or with sudo available)
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config ccache git
  # engine
  libeigen3-dev libopenmesh-dev libcgal-dev libgmp-dev libmpfr-dev libfcl-dev
  libyaml-cpp-dev libsqlite3-dev libusb-1.0-0-dev libcli11-dev libsodium-dev
  libzstd-dev libpq-dev libcurl4-openssl-dev libicu-dev
  clang-14 libclang-rt-14-dev clang-format-14
  # window (VTK 9.1 is built against Qt 5 on Debian 12)
  qtbase5-dev libvtk9-dev libvtk9-qt-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev xvfb xauth
  # a PostgreSQL server the results store's tests start in a temporary folder,
  # and openssl for the certificates of its TLS test
  postgresql-15 openssl
  # plots of the accuracy/cost figures; the virtual environment in which
  # scripts/bench.sh installs DAQP to compare the QP with
  gnuplot-nox python3-venv
  # public test meshes (CGAL's data set: elephant, fandisk, knot, ...), read by tests
  libcgal-demo
)

sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then sudo_cmd=(sudo); else
    echo "install-deps: not root and no sudo; install these packages by hand:" >&2
    echo "  ${packages[*]}" >&2
    exit 1
  fi
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install-deps: installing ${#missing[@]} missing package(s): ${missing[*]}"
lists=/var/lib/apt/lists
if [[ -z $(find "$lists" -maxdepth 1 -name '*Packages*' -mmin -1440 2>/dev/null | head -n 1) ]]; then
  "${sudo_cmd[@]}" apt-get update
fi
export DEBIAN_FRONTEND=noninteractive
if ! "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"; then
  # A stale list can name versions the mirror no longer has: refresh and retry once.
  "${sudo_cmd[@]}" apt-get update
  "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
fi
echo "install-deps: done"
