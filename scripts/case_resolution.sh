#!/usr/bin/env bash
# What a generated case's gingiva resolution buys and costs: one case of the
# probing assessment (seed 4242) built with its gingiva's sphere-trees at 512,
# 768, 1,024 (what a case uses, kCaseGingivaLeaves) and 3,072 leaves (the fixed
# probing scene's), then taken by three scripted students on each. Prints, per
# resolution, the trees' build time and each student's score line (readings
# within 1 mm, exact, bias). Numbers only: nothing here passes or fails.
# Takes about 5 minutes cold (each resolution's trees are built once, then cached).
# Usage: scripts/case_resolution.sh [sulcus-cli, default build/release/bin/sulcus-cli]
set -euo pipefail
cd "$(dirname "$0")/.."
cli=$(realpath "${1:-build/release/bin/sulcus-cli}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/scenes" "$tmp/lessons" "$tmp/results"
"$cli" lesson case lessons/periodontal_probing_case.yaml --seed 4242 \
  -o "$tmp/scenes/case.yaml"
for leaves in 512 768 1024 3072; do
  pattern="gingiva: {levels: 5, branch: 8, leaves:"
  sed "s/$pattern [0-9]*}/$pattern $leaves}/" "$tmp/scenes/case.yaml" \
    >"$tmp/scenes/case_$leaves.yaml"
  grep -q "leaves: $leaves}" "$tmp/scenes/case_$leaves.yaml" ||
    { echo "error: the saved case names no gingiva resolution" >&2; exit 1; }
  sed "s#^scene: .*#scene: ../scenes/case_$leaves.yaml#" \
    lessons/periodontal_probing.yaml >"$tmp/lessons/case_$leaves.yaml"
  echo "== gingiva at $leaves leaves"
  "$cli" scene build "$tmp/scenes/case_$leaves.yaml" 2>/dev/null | grep -E "built|ready"
  for student in careful human tremor; do
    printf '%-8s ' "$student"
    "$cli" lesson run "$tmp/lessons/case_$leaves.yaml" --device "student:$student" \
      --no-store --results "$tmp/results" -o "$tmp/results/$leaves-$student" 2>&1 |
      grep -E "^score"
  done
done
