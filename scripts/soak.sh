#!/usr/bin/env bash
# A soak run (not a CI test): the real haptic thread at the scene's rate for a
# long time with a scripted device, its memory (RSS) and open file handles
# sampled at a fixed interval. Prints one line a sample and the growth from the
# second sample to the end. Builds the release preset first.
#
#   scripts/soak.sh [SECONDS=3600] [INTERVAL=60] [SCENE=scenes/oral_inspection.yaml] [DEVICE=scripted:random]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-3600}
interval=${2:-60}
scene=${3:-scenes/oral_inspection.yaml}
device=${4:-scripted:random}
cmake --preset release >/dev/null
cmake --build --preset release >/dev/null
cli=build/release/bin/sulcus-cli
log=$(mktemp)
"$cli" run --scene "$scene" --device "$device" --seconds "$seconds" >"$log" 2>&1 &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT
# The scene is compiled (or read from the cache) before the thread starts: wait for the run to begin.
printf '%8s %10s %8s %8s\n' t_s rss_kib fds threads
first_rss="" first_fds=""
start=$(date +%s)
while kill -0 $pid 2>/dev/null; do
  now=$(( $(date +%s) - start ))
  rss=$(awk '/^VmRSS/ {print $2}' /proc/$pid/status 2>/dev/null || echo 0)
  thr=$(awk '/^Threads/ {print $2}' /proc/$pid/status 2>/dev/null || echo 0)
  fds=$(ls /proc/$pid/fd 2>/dev/null | wc -l)
  [ -z "$rss" ] && break
  printf '%8d %10s %8s %8s\n' "$now" "$rss" "$fds" "$thr"
  # The baseline: the second sample past the start (the first can catch the scene still loading).
  if [ -z "$first_rss" ] && [ "$now" -ge $(( 2 * interval )) ]; then first_rss=$rss first_fds=$fds; fi
  last_rss=$rss last_fds=$fds
  sleep "$interval"
done
wait $pid || { echo "soak: the run failed:"; cat "$log"; exit 1; }
trap - EXIT
tail -n 12 "$log"
if [ -n "$first_rss" ]; then
  echo "growth after the sample at $(( 2 * interval )) s: RSS $(( last_rss - first_rss )) KiB, file handles $(( last_fds - first_fds ))"
fi
