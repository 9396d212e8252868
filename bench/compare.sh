#!/usr/bin/env bash
# Side-by-side: trueaxis (criterion) and straightforward NumPy/SciPy baselines (bench/baseline*.py),
# in one run on the same machine, printing the ratios. Usage: bash bench/compare.sh [criterion filter]
# Needs python3 with numpy, scipy and pyamg (installed with pip if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -c "import numpy, scipy, pyamg" 2>/dev/null || python3 -m pip install --quiet numpy scipy pyamg
# the baselines run their BLAS on one thread: on a shared 2-core machine OpenBLAS threads slow NumPy
# down 2-10x, and the ratios are stated thread for thread
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
cargo build --release --quiet
# each baseline first checks that it computes what trueaxis computes
for baseline in bench/baseline*.py; do
    python3 "$baseline" check
done
for b in $(sed -n '/^\[\[bench\]\]/{n;s/^name = "\(.*\)"$/\1/p}' crates/*/Cargo.toml); do
    cargo bench --quiet --bench "$b" -- --noplot "${1:-}" >/dev/null
done
for baseline in bench/baseline*.py; do
    python3 "$baseline" time
done | python3 -c "import json, sys; d = json.JSONDecoder(); text = sys.stdin.read(); out = {}
while text.strip():
    obj, end = d.raw_decode(text.lstrip()); out.update(obj); text = text.lstrip()[end:]
print(json.dumps(out, indent=1))" > target/baseline_times.json
python3 bench/report.py target/baseline_times.json
