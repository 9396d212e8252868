"""CPU time per pose of `Machine.predict` (the Python binding), for BENCHMARKS.md, side by side with
the batch kernel alone (`cargo run --release -p trueaxis --example kernel_cost`): the KX8-Five
(examples/machines/kx8five.toml) with the 30 benchmark tables (bench/kx8five_tables.toml), the
same poses as kernel_cost (axis k at the fractional part of i sqrt(p_k), p = 2 3 5 7 11, over its
travel; rotary axes in deg here, rad there), evaluated `repeats` times.

Each call returns a new array (its pages are faulted in and zeroed by the system, in the CPU
time), then each call writes one array passed as `out=` (kernel_cost also reuses its buffer).
Prints the process's CPU time per pose (every thread of the process, so rayon's workers are
counted; other processes waiting for the cores are not) and the wall time per pose.

Run: RAYON_NUM_THREADS=1 python crates/python/benches/predict_cost.py [poses] [repeats]
"""

import os
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

import trueaxis as ta

ROOT = Path(__file__).resolve().parents[3]


def poses_of(machine, n):
    """kernel_cost's low-discrepancy poses (mm, deg), shape (n, 5)."""
    i = np.arange(n, dtype=float)[:, None]
    u = np.mod(i * np.sqrt([2.0, 3.0, 5.0, 7.0, 11.0]), 1.0)
    axes = tomllib.loads(machine.toml)["axes"]
    ranges = [axes[letter].get("range", [0.0, 360.0]) for letter in machine.axes]
    lo, hi = np.array(ranges).T
    return lo + u * (hi - lo)


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 50
    machine = ta.Machine.from_file(ROOT / "examples/machines/kx8five.toml")
    errors = ta.Errors.from_file(ROOT / "bench/kx8five_tables.toml", machine)
    poses = poses_of(machine, n)
    machine.predict(errors, poses[:1000])  # the thread pool started
    threads = os.environ.get("RAYON_NUM_THREADS", str(os.cpu_count()))
    buffer = np.empty((n, 6))
    # a new array per call, then one array written by every call (out=, as kernel_cost's buffer)
    for label, kwargs in (("new array", {}), ("out=", {"out": buffer})):
        wall, cpu = time.perf_counter(), time.process_time()
        for _ in range(repeats):
            out = machine.predict(errors, poses, **kwargs)
        cpu = time.process_time() - cpu
        wall = time.perf_counter() - wall
        total = n * repeats
        print(
            f"Machine.predict ({label}), {threads} thread(s): {total} poses, {1e9 * cpu / total:.1f} ns CPU per pose "
            f"({total / cpu / 1e6:.2f} M poses/s per core), wall {1e9 * wall / total:.1f} ns per pose "
            f"({total / wall / 1e6:.2f} M poses/s); checksum {out[:, 0].sum() / 1e3:.6e} (mm, as kernel_cost's)"
        )


if __name__ == "__main__":
    main()
