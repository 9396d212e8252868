#!/usr/bin/env python3
"""Prints the table of bench/compare.sh: criterion means (target/criterion/*/new/estimates.json) next
to the NumPy baseline times (JSON argument), with the ratio baseline / trueaxis."""
import json
import pathlib
import sys

root = pathlib.Path(__file__).resolve().parent.parent / "target" / "criterion"
baseline = json.loads(pathlib.Path(sys.argv[1]).read_text())
rows = []
for est in sorted(root.glob("**/new/estimates.json")):
    bench = json.loads((est.parent / "benchmark.json").read_text())
    name = bench["full_id"]
    mean_s = json.loads(est.read_text())["mean"]["point_estimate"] * 1e-9
    rows.append((name, mean_s, baseline.get(name)))
print(f"{'benchmark':<40} {'trueaxis':>12} {'NumPy/SciPy':>12} {'ratio':>8}")
for name, t, b in rows:
    fmt = lambda s: f"{s * 1e6:10.2f} us" if s < 1e-3 else (f"{s * 1e3:10.2f} ms" if s < 1 else f"{s:10.3f} s ")
    print(f"{name:<40} {fmt(t)} {fmt(b) if b else '':>12} {f'{b / t:7.1f}x' if b else '':>8}")
