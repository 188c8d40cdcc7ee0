#!/usr/bin/env bash
# Sets everything up and runs Sulcus: installs the Debian packages, builds the
# release preset, then runs the main program: the window when there is a display,
# else a lesson taken headless by a scripted student, with its report.
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
  # The shipped lessons' scenes, prepared here (through the cache: seconds once
  # built) so that the window never makes a student wait for them.
  for s in scenes/periodontal_probing.yaml scenes/oral_inspection.yaml \
    scenes/periodontal_examination.yaml; do
    echo "Preparing $s (the first time only: one to two minutes)..."
    "$cli" scene build "$s" --drawn | tail -1
  done
  echo "Opening the window on its start page: say who you are and pick a lesson (the"
  echo "mouse and keyboard move the probe: W/S, A/D, Q/E as the screen shows it, N to"
  echo "the next site, R/F to press along the probe; F1 for help)."
  exec build/release/bin/sulcus
fi
echo
echo "No display (\$DISPLAY is not set), so the main program runs a lesson headless:"
echo "a scripted student takes the periodontal probing lesson (teeth 44 to 47), the"
echo "attempt is scored and stored, and its report is written (the first run builds"
echo "the scene's sphere-trees, about a minute)."
echo
echo "  \$ $cli lesson run lessons/periodontal_probing.yaml --student 'demo student' --device student:careful"
"$cli" lesson run lessons/periodontal_probing.yaml --student "demo student" --device student:careful
echo
echo "The same lesson by a student who presses 2 N at the pocket floor:"
echo "  \$ $cli lesson run lessons/periodontal_probing.yaml --student 'demo student' --device student:rough --quiet"
"$cli" lesson run lessons/periodontal_probing.yaml --student "demo student" --device student:rough --quiet
echo
echo "The oral inspection of the full mouth by a thorough scripted inspector (the first"
echo "run builds the full mouth's sphere-trees, about a minute):"
echo "  \$ $cli lesson run lessons/oral_inspection.yaml --student 'demo student' --device student:thorough --quiet"
"$cli" lesson run lessons/oral_inspection.yaml --student "demo student" --device student:thorough --quiet
echo
echo "The full periodontal examination of the whole mouth (156 sites, then stage,"
echo "extent and grade) by the careful student (the first run builds the scene's"
echo "26 gingiva shares, about a minute and a half):"
echo "  \$ $cli lesson run lessons/periodontal_examination.yaml \\"
echo "      --student 'demo student' --device student:careful --quiet"
"$cli" lesson run lessons/periodontal_examination.yaml --student "demo student" \
  --device student:careful --quiet
echo
echo "Every stored attempt (open a report.html in any browser):"
echo "  \$ $cli results list"
exec "$cli" results list
