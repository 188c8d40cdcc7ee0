#!/usr/bin/env bash
# Fuzzes every file reader with libFuzzer (clang, ASan + UBSan): builds the
# `fuzz` preset, then runs each target for SECONDS (default 20) from the seed
# corpus in tests/fuzz/corpus (copied, so the repository's corpus only grows by
# hand), with the format's dictionary. Prints, per target, the executions run
# and the coverage reached. An input that crashes, hangs (10 s), leaks or gets a
# library's error is kept under build/fuzz/artifacts/TARGET; copy it to
# tests/fuzz/regressions/TARGET/ with the fix, so that ctest replays it forever.
#
#   scripts/fuzz.sh [SECONDS] [TARGET...]     e.g. scripts/fuzz.sh 600 mesh_ply
#   FUZZ_RUNS=1000000 scripts/fuzz.sh 7200    each target until a million executions (or 2 h)
#   FUZZ_SEED=1 ...                           a fixed seed (CI)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(scene lesson answers mesh_stl mesh_obj mesh_ply mesh_off sph tree_cache recording recording_ticks trajectory_csv)
fi
if ! command -v clang++-14 >/dev/null; then
  echo "fuzz: clang-14 is missing: run scripts/install-deps.sh" >&2
  exit 1
fi
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
out=build/fuzz/runs
mkdir -p "$out"
status=0
printf '%-15s %12s %10s %8s %8s  %s\n' target executions exec/s cov ft result
for t in "${targets[@]}"; do
  work="$out/corpus/$t"
  artifacts="build/fuzz/artifacts/$t"
  mkdir -p "$work" "$artifacts"
  cp -n tests/fuzz/corpus/"$t"/* "$work"/ 2>/dev/null || true
  dict=()
  [ -f "tests/fuzz/dict/$t.dict" ] && dict=(-dict="tests/fuzz/dict/$t.dict")
  log="$out/$t.log"
  set +e
  build/fuzz/tests/fuzz/fuzz_"$t" "$work" "${dict[@]}" -seed="${FUZZ_SEED:-0}" -max_total_time="$seconds" -runs="${FUZZ_RUNS:--1}" -timeout=10 -rss_limit_mb=2560 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$artifacts/" >"$log" 2>&1
  rc=$?
  set -e
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  speed=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo 0)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || echo 0)
  if [ $rc -eq 0 ]; then result=clean; else result="FAILED (see $log, input in $artifacts)"; status=1; fi
  printf '%-15s %12s %10s %8s %8s  %s\n' "$t" "$runs" "$speed" "$cov" "$ft" "$result"
  if [ $rc -ne 0 ]; then grep -m3 -E 'DEFECT|ERROR: AddressSanitizer|runtime error|ERROR: libFuzzer|deadly signal|leak' "$log" || true; fi
done
exit $status
