"""Speed-up of the Monte Carlo budget on a Dask LocalCluster with 1 and 2 workers (docs/python.md).

The KX8-Five cyclic-drift budget (3 stages) with a tighter numerical tolerance than the shipped
file, so that the run has enough sequences to time. Each worker is one process with one thread
(RAYON_NUM_THREADS=1), and the single-process reference is timed with one thread too.
Usage: RAYON_NUM_THREADS=1 .venv/bin/python examples/python/dask_speedup.py [tolerance] [blocks_per_chunk]
"""

import os
import sys
import time
from pathlib import Path

import trueaxis as ta
from dask.distributed import Client, LocalCluster
from trueaxis.distributed import run_uncertainty

EX = Path(__file__).resolve().parents[1]


def main() -> int:
    tolerance = float(sys.argv[1]) if len(sys.argv) > 1 else 0.01
    blocks = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    text = (EX / "uncertainty" / "kx8five_cyclic.toml").read_text().replace("tolerance = 0.05", f"tolerance = {tolerance}")
    plan = ta.UncertaintyPlan.from_design(EX / "uncertainty" / "kx8five_design.csv", ta.Sources.from_toml(text))
    t = time.perf_counter()
    single = plan.run()
    t1 = time.perf_counter() - t
    print(f"one process, RAYON_NUM_THREADS={os.environ.get('RAYON_NUM_THREADS', 'all')}: {t1:.2f} s, "
          f"{single['trials']} trials in the total stage ({single['sequences']} sequences), budget {single['budget_sequences']}")
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, dashboard_address=None,
                          env={"RAYON_NUM_THREADS": "1"}) as cluster, Client(cluster) as client:
            run_uncertainty(plan, client, blocks_per_chunk=blocks)  # warm-up: plan scattered, workers started
            t = time.perf_counter()
            result = run_uncertainty(plan, client, blocks_per_chunk=blocks, lookahead=2 * workers)
            tw = time.perf_counter() - t
        print(f"Dask, {workers} worker(s): {tw:.2f} s, speed-up over one process {t1 / tw:.2f}, identical: {result == single}")
    print(f"load average: {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
