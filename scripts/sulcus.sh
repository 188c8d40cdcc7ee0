#!/usr/bin/env bash
# Sets everything up and runs Sulcus: installs the Debian packages, builds the
# release preset, then runs the main program. Until the window lands, the main
# program is a short headless demo of the CLI, which says what it does.
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
echo
echo "Sulcus is built. There is no window yet (it comes with issue 7), so this runs a"
echo "short headless demo with sulcus-cli:"
mkdir -p build/release/demo
echo
echo "1. Generate the lower left first molar (FDI 36) from clinical dimensions:"
echo "  \$ $cli anatomy tooth 36 -o build/release/demo/36.stl"
"$cli" anatomy tooth 36 -o build/release/demo/36.stl
echo
echo "2. Check it the way every mesh is checked before the engine uses it:"
echo "  \$ $cli mesh info build/release/demo/36.stl"
"$cli" mesh info build/release/demo/36.stl
echo
echo "3. Validate the shipped scene of teeth 41 to 46 with their pocket depths:"
echo "  \$ $cli scene validate scenes/teeth_row.yaml"
exec "$cli" scene validate scenes/teeth_row.yaml
