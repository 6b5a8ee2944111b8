#!/usr/bin/env bash
# Which shared dependencies the demo's (tabula-cli) or the Python package's (tabula-py,
# as CI builds it: with `test-build-features`) own build resolves with other features
# than `cargo test --workspace` does: each such crate, and everything above it, is
# compiled twice. crates/tabula-unify turns those
# features on; no output means it is in step. Run after a dependency update.
set -euo pipefail
cd "$(dirname "$0")/.."
features_of() { cargo tree "$@" -f '{p} [{f}]' --prefix none --no-dedupe | sort -u; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
features_of --workspace >"$dir/workspace"
features_of -p tabula-cli -e normal,build >"$dir/tabula-cli"
features_of -p tabula-py --features test-build-features -e normal,build >"$dir/tabula-py"
python3 - "$dir" <<'PY'
import re, sys
def features(path):
    out = {}
    for line in open(path):
        m = re.match(r'(\S+ v\S+)(?: \([^)]*\))? \[(.*)\]', line.strip())
        if m:
            out.setdefault(m.group(1), set()).update(f for f in m.group(2).split(',') if f)
    return out
workspace = features(f"{sys.argv[1]}/workspace")
for build in ("tabula-cli", "tabula-py"):
    for crate, fs in sorted(features(f"{sys.argv[1]}/{build}").items()):
        if crate.startswith(build + " "):
            continue  # the package itself, built with its own feature selection
        if crate in workspace and fs != workspace[crate]:
            print(f"{build}: {crate} lacks {sorted(workspace[crate] - fs)}")
PY
