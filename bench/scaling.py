#!/usr/bin/env python3
"""Scaling curves for BENCHMARKS.md: runs `examples/scaling.rs` for every workload at sizes
10^3..10^7 (one process per run, so that each peak resident memory is its own), writes
bench/scaling.csv and draws docs/bench/scaling.svg.

  python3 bench/scaling.py            # every workload
  python3 bench/scaling.py thermal    # one workload (the others keep their rows in the CSV)

Sizes beyond what a workload can do on a 24 GB machine in minutes are left out (see SIZES).
"""
import csv
import json
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
# work units: poses; rows of a 500-column design; Monte Carlo trials (p = 0.9, sequences of at
# most 10^6); thermal nodes (10^7 nodes would need about 57 GB with LOBPCG, more than the 24 GB here)
SIZES = {
    "kinematics": [1e3, 1e4, 1e5, 1e6, 1e7],
    "identify": [1e3, 1e4, 1e5, 1e6],
    "montecarlo": [1e3, 1e4, 1e5, 1e6, 1e7],
    "thermal": [1e3, 1e4, 1e5, 1e6],
}
FIELDS = ["workload", "work", "wall_s", "cpu_s", "peak_bytes", "threads"]


def main():
    chosen = sys.argv[1:] or list(SIZES)
    unknown = [w for w in chosen if w not in SIZES]
    if unknown:
        sys.exit(f"unknown workload {unknown}; one of {list(SIZES)}")
    subprocess.run(["cargo", "build", "--release", "--quiet", "-p", "trueaxis", "--example", "scaling"], cwd=ROOT, check=True)
    table = ROOT / "bench/scaling.csv"
    rows = [r for r in csv.DictReader(table.open())] if table.exists() else []
    rows = [r for r in rows if r["workload"] not in chosen]
    for workload in chosen:
        for size in SIZES[workload]:
            out = subprocess.run([str(ROOT / "target/release/examples/scaling"), workload, f"{size:g}"], cwd=ROOT, check=True,
                                 capture_output=True, text=True).stdout
            run = json.loads(out)
            print(f"{workload:>10} {run['work']:>10} {run['wall_s']:10.4f} s wall {run['cpu_s']:10.4f} s CPU "
                  f"{run['peak_bytes'] / 2**20:9.1f} MiB", flush=True)
            rows.append({k: run[k] for k in FIELDS})
    rows.sort(key=lambda r: (r["workload"], float(r["work"])))
    with table.open("w", newline="") as f:
        writer = csv.DictWriter(f, FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    (ROOT / "docs/bench").mkdir(parents=True, exist_ok=True)
    subprocess.run(["cargo", "run", "--release", "--quiet", "-p", "trueaxis-report", "--example", "scaling_plot", "--",
                    str(table), str(ROOT / "docs/bench/scaling.svg")], cwd=ROOT, check=True)


if __name__ == "__main__":
    main()
