#!/usr/bin/env bash
# Sets everything up and runs every test: installs the Debian packages, checks that
# every C++ file is formatted (scripts/format.sh --check), builds the
# release preset (warnings as errors; configured as scripts/sulcus.sh does, so
# one build serves both), and runs ctest (window tests under Xvfb).
# Usage: scripts/test.sh [extra ctest arguments...]
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
scripts/format.sh --check
cmake --preset release >/dev/null
cmake --build --preset release
ctest --preset release "$@"
