#!/usr/bin/env bash
# Sets everything up and runs every test: installs the Debian packages, checks that
# every C++ file is formatted (scripts/format.sh --check), builds the
# release preset (warnings as errors; configured as scripts/sulcus.sh does, so
# one build serves both), makes the LRS the xAPI tests talk to (Ralph, in a
# virtual environment), and runs ctest (window tests under Xvfb; the results
# store's tests start their own PostgreSQL server).
# Usage: scripts/test.sh [extra ctest arguments...]
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
scripts/format.sh --check
cmake --preset release >/dev/null
cmake --build --preset release
# A Learning Record Store for the xAPI tests: Ralph, from PyPI, in a virtual
# environment of the build (installed once; pinned).
lrs_venv=build/release/lrs-venv
if [[ ! -x $lrs_venv/bin/uvicorn || ! -x $lrs_venv/bin/ralph ]]; then
  python3 -m venv "$lrs_venv"
  "$lrs_venv/bin/pip" install -q "ralph-malph[cli,lrs]==5.1.0" "requests==2.32.3"
fi
ctest --preset release "$@"
