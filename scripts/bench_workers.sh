#!/usr/bin/env bash
# Trials per second of `tabula bench place` in one process and spread over 1 and 2
# `tabula worker` processes on this machine (BENCHMARKS.md, "Trials spread over
# workers"). Usage: scripts/bench_workers.sh [TRIALS] [SEED]
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -q
T=target/release/tabula
TRIALS=${1:-20}
SEED=${2:-1}
OUT=$(mktemp -d)
run() { # name, extra bench args…
    local name=$1; shift
    local t0 t1
    t0=$(date +%s.%N)
    $T bench place --suite simple --trials "$TRIALS" --seed "$SEED" --json "$@" >"$OUT/$name.json"
    t1=$(date +%s.%N)
    python3 -c "import sys; w=float(sys.argv[2])-float(sys.argv[1]); print(f'$name: {w:.1f} s, {$TRIALS/w:.2f} trials/s')" "$t0" "$t1"
}
run local
for n in 1 2; do
    port=$((7480 + n))
    pids=()
    for _ in $(seq "$n"); do
        $T worker --connect "tcp/127.0.0.1:$port" --duration 3600 2>/dev/null &
        pids+=($!)
    done
    run "workers-$n" --workers "$n" --listen "tcp/127.0.0.1:$port"
    kill "${pids[@]}"
done
python3 - "$OUT" <<'PY'
import json, sys
d = sys.argv[1]
key = lambda r: (r["seed"], r["success"], r["cause"], round(r["orientation_error_deg"], 6))
local = [key(r) for r in json.load(open(f"{d}/local.json"))]
for n in (1, 2):
    same = [key(r) for r in json.load(open(f"{d}/workers-{n}.json"))] == local
    print(f"workers-{n}: rows equal to one process: {same}")
PY
