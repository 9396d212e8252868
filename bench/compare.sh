#!/usr/bin/env bash
# Side-by-side: trueaxis (criterion) and straightforward NumPy/SciPy baselines (bench/baseline.py,
# bench/baseline_thermal.py), in one run on the same machine, printing the ratios.
# Usage: bash bench/compare.sh [criterion filter]
# Needs python3 with numpy and scipy (installed with pip if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -c "import numpy, scipy" 2>/dev/null || python3 -m pip install --quiet numpy scipy
cargo build --release --quiet
python3 bench/baseline.py check
python3 bench/baseline_thermal.py check
cargo bench --quiet --bench kinematics -- --noplot "${1:-}" >/dev/null
for b in $(sed -n 's/^name = "\(.*\)"$/\1/p' Cargo.toml | grep -v '^trueaxis$' | grep -v '^kinematics$'); do
    cargo bench --quiet --bench "$b" -- --noplot "${1:-}" >/dev/null
done
python3 bench/baseline.py time > target/baseline_kinematics_times.json
python3 bench/baseline_thermal.py time > target/baseline_thermal_times.json
python3 -c 'import json, sys; print(json.dumps({k: v for f in sys.argv[1:] for k, v in json.load(open(f)).items()}, indent=1))' \
    target/baseline_kinematics_times.json target/baseline_thermal_times.json > target/baseline_times.json
python3 bench/report.py target/baseline_times.json
