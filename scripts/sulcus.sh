#!/usr/bin/env bash
# Sets everything up and runs Sulcus: installs the Debian packages, builds the
# release preset, then runs the main program. Until the window lands, the main
# program is the headless CLI on a shipped mesh, which says what it does.
# Usage: scripts/sulcus.sh [sulcus-cli arguments...]
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release

cli=build/release/bin/sulcus-cli
if [[ $# -gt 0 ]]; then
  exec "$cli" "$@"
fi
mesh=resources/meshes/calibration_torus.obj
echo
echo "Sulcus is built. There is no window yet (it comes with issue 7), so this runs"
echo "the headless tools: checking the shipped calibration mesh the way every mesh"
echo "is checked before the engine builds a sphere-tree from it."
echo "  \$ $cli mesh info $mesh"
exec "$cli" mesh info "$mesh"
