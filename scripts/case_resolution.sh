#!/usr/bin/env bash
# What a generated case's gingiva resolution buys and costs: one case of the
# probing assessment (seed 4242) built with its gingiva's sphere-trees at 512,
# 768 and 1,024 leaves on the min-max cover tightened once (1,024 is what a
# case uses: kCaseGingivaLeaves, kCaseGingivaTightenPasses), at 1,024 traded
# for the mean (what a case used before) and at 3,072 traded (the fixed
# probing scene's), then taken by three scripted students on each. Prints, per
# resolution, the trees' build time and each student's score line (readings
# within 1 mm, exact, bias). Numbers only: nothing here passes or fails.
# Takes about 6 minutes cold (each resolution's trees are built once, then cached).
# Usage: scripts/case_resolution.sh [sulcus-cli, default build/release/bin/sulcus-cli]
set -euo pipefail
cd "$(dirname "$0")/.."
cli=$(realpath "${1:-build/release/bin/sulcus-cli}")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/scenes" "$tmp/lessons" "$tmp/results"
"$cli" lesson case lessons/periodontal_probing_case.yaml --seed 4242 \
  -o "$tmp/scenes/case.yaml"
for variant in "512 worst 1" "768 worst 1" "1024 worst 1" "1024 mean 3" "3072 mean 3"; do
  read -r leaves spend passes <<<"$variant"
  name="${leaves}_$spend"
  pattern="gingiva: {levels: 5, branch: 8,"
  trees="leaves: $leaves, spend: $spend, tighten_passes: $passes"
  sed "s/$pattern .*}/$pattern $trees}/" \
    "$tmp/scenes/case.yaml" >"$tmp/scenes/case_$name.yaml"
  grep -q "leaves: $leaves, spend: $spend" "$tmp/scenes/case_$name.yaml" ||
    { echo "error: the saved case names no gingiva resolution" >&2; exit 1; }
  sed "s#^scene: .*#scene: ../scenes/case_$name.yaml#" \
    lessons/periodontal_probing.yaml >"$tmp/lessons/case_$name.yaml"
  echo "== gingiva at $leaves leaves, spend $spend, tightened $passes times"
  "$cli" scene build "$tmp/scenes/case_$name.yaml" 2>/dev/null | grep -E "built|ready"
  for student in careful human tremor; do
    printf '%-8s ' "$student"
    "$cli" lesson run "$tmp/lessons/case_$name.yaml" --device "student:$student" \
      --no-store --results "$tmp/results" -o "$tmp/results/$name-$student" 2>&1 |
      grep -E "^score"
  done
done
