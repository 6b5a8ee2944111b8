#!/usr/bin/env bash
# Runs every fuzz target for SECONDS each (default 600), one after another, seeded
# with the repository's own files and the hostile corpus (run `cargo test --release -p
# tabula-cli --test hostile` first to write it); prints one line per target.
# Needs a nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz`).
#   scripts/fuzz_all.sh [SECONDS] [TARGET…]
set -euo pipefail
cd "$(dirname "$0")/../fuzz"
secs=${1:-600}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(cloud mesh urdf srdf description xacro moveit scene params pddl ros)
H=../target/hostile-corpus  # written by the hostile-corpus test (cargo test --test hostile)
seed() { mkdir -p "corpus/$1"; shift; for f in "$@"; do [ -f "$f" ] && cp "$f" "corpus/${dir}/"; done; true; }
for t in "${targets[@]}"; do
  dir=$t
  case $t in
    cloud) seed cloud $H/cloud/* ;;
    mesh) seed mesh $H/mesh/* ;;
    urdf) seed urdf ../robots/*.urdf ../robots/*.toml $H/urdf/* ;;
    srdf) seed srdf $H/srdf/* ;;
    description) seed description ../robots/*.toml $H/description/* ;;
    xacro) seed xacro ../robots/*.xacro $H/xacro/* ;;
    moveit) seed moveit ../data/mbm/panda/problems/*/*.yaml $H/moveit/* ;;
    scene) seed scene ../scenes/*.toml $H/scene/* ;;
    params) seed params $H/params/* ;;
    pddl) seed pddl ../pddl/*.pddl $H/pddl/* ;;
  esac
  cargo +nightly fuzz build -O "$t" >/dev/null 2>&1
  log=artifacts/$t.log
  mkdir -p artifacts
  start=$(date +%s)
  # xacro's expression evaluator (pyisheval) keeps reference cycles between scopes: a
  # few kilobytes per expansion, freed at exit. Not what the fuzzer looks for.
  leaks=1; [ "$t" = xacro ] && leaks=0
  if cargo +nightly fuzz run -O "$t" -- -max_total_time="$secs" -rss_limit_mb=2048 \
      -timeout=20 -max_len=65536 -detect_leaks=$leaks >"$log" 2>&1; then
    status=ok
  else
    status="CRASH (see fuzz/$log and fuzz/artifacts/$t/)"
  fi
  runs=$(grep -o 'Done [0-9]* runs' "$log" | tail -1 || true)
  echo "$t: $status, $(( $(date +%s) - start )) s, ${runs:-no summary}"
done
