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
if [[ -n "${DISPLAY:-}" && -x build/release/bin/sulcus ]]; then
  echo "Opening the window on scenes/periodontal_probing.yaml (the first run builds its"
  echo "sphere-trees, about 15 s; the mouse and keyboard move the probe: W/S, A/D, Q/E)."
  exec build/release/bin/sulcus "$(pwd)/scenes/periodontal_probing.yaml"
fi
echo
echo "No display (\$DISPLAY is not set), so this runs the headless demo instead:"
mkdir -p build/release/demo
echo
echo "1. Check the shipped probing scene and build its meshes and sphere-trees (cached):"
echo "  \$ $cli scene build scenes/periodontal_probing.yaml"
"$cli" scene build scenes/periodontal_probing.yaml
echo
echo "2. Run the real haptic thread on it for 3 s with a scripted probe poking tooth 44:"
echo "  \$ $cli run --scene scenes/periodontal_probing.yaml --device scripted:poke --seconds 3"
"$cli" run --scene scenes/periodontal_probing.yaml --device scripted:poke --seconds 3 \
  --record build/release/demo/poke.rec
echo
echo "3. Haptic devices plugged in:"
echo "  \$ $cli devices"
exec "$cli" devices
