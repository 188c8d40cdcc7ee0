#!/usr/bin/env bash
# The shared results store's sync, measured: a PostgreSQL server in a folder of
# its own, N attempts taken by a scripted student while it is stopped (each kept
# on the station, waiting), then the server started and `sulcus-cli results sync`
# timed. Prints the seconds for the N and per attempt.
# Usage: scripts/results_scale.sh [N=10] [student=careful]   (after scripts/test.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-10}
student=${2:-careful}
cli=build/release/bin/sulcus-cli
bin=$(ls -d /usr/lib/postgresql/*/bin | sort -V | tail -n 1)
dir=$(mktemp -d /tmp/sulcus-scale-XXXXXX)
as=()
if [[ $(id -u) -eq 0 ]]; then
  chown postgres "$dir"
  as=(runuser -u postgres --)
fi
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
echo scale-secret > "$dir/pw"
"${as[@]}" "$bin/initdb" -D "$dir/data" -U sulcus --auth=scram-sha-256 --pwfile="$dir/pw" \
  --no-sync >/dev/null
pg() { "${as[@]}" "$bin/pg_ctl" -D "$dir/data" -l "$dir/log" -w "$@" >/dev/null; }
opts="-p $port -k $dir -c listen_addresses=127.0.0.1"
url="postgresql://sulcus:scale-secret@127.0.0.1:$port/postgres"
results="$dir/station"
trap 'pg stop -m immediate 2>/dev/null || true; rm -rf "$dir"' EXIT

pg -o "$opts" start
SULCUS_RESULTS_URL=$url "$cli" results list >/dev/null  # the tables
# Scripted students' attempts: demonstrations, allowed as the instructor would.
"$bin/psql" -q "$url" -c "INSERT INTO settings(key, value) VALUES ('demonstrations', \
  'allowed') ON CONFLICT (key) DO UPDATE SET value = 'allowed'"
pg stop
echo "taking $n attempts (student:$student) with the server stopped..."
for ((i = 0; i < n; ++i)); do
  SULCUS_RESULTS_DIR=$results SULCUS_RESULTS_URL=$url \
    "$cli" lesson run lessons/periodontal_probing.yaml --device "student:$student" \
    --student "s$i" --quiet >/dev/null 2>&1 || true
done
waiting=$(ls "$results"/attempts/*/not-in-database.txt 2>/dev/null | wc -l)
echo "$waiting attempts waiting"
pg -o "$opts" start
t0=$(date +%s.%N)
SULCUS_RESULTS_DIR=$results SULCUS_RESULTS_URL=$url "$cli" results sync | tail -n 1
t1=$(date +%s.%N)
python3 -c "print(f'sync of $waiting attempts: {$t1 - $t0:.1f} s, {($t1 - $t0) / max(1, $waiting):.2f} s an attempt')"
SULCUS_RESULTS_URL=$url "$cli" results list | tail -n 1
