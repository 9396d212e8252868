"""The KX8-Five (Andolfatto et al. 2011) from Python: predict the volumetric error over random poses, identify the
link errors from the shipped CapBall campaign, and compute their uncertainty by adaptive Monte Carlo
on a dask.distributed LocalCluster, checked against the same run in one process.

Run from the repository root after installing the package (README): .venv/bin/python examples/python/kx8five.py
"""

import sys
import time
from pathlib import Path

import numpy as np

import trueaxis as ta
from dask.distributed import Client, LocalCluster
from trueaxis.distributed import run_uncertainty

EX = Path(__file__).resolve().parents[1]


def main() -> int:

    machine = ta.Machine.from_file(EX / "machines" / "kx8five.toml")
    errors = ta.Errors.from_file(EX / "errors" / "kx8five.toml", machine)

    # 100 000 random poses inside the travel: X Y Z in mm, A C in deg
    rng = np.random.default_rng(1)
    low = np.array([-325.0, -350.0, -450.0, 0.0, -180.0])
    high = np.array([325.0, 350.0, 0.0, 180.0, 180.0])
    poses = low + (high - low) * rng.random((100_000, 5))
    t = time.perf_counter()
    e = machine.predict(errors, poses, frame="machine")  # (N, 6): dx dy dz um, drx dry drz urad
    t = time.perf_counter() - t
    position = np.linalg.norm(e[:, :3], axis=1)
    print(f"{len(poses)} poses in {t * 1e3:.1f} ms: |d| max {position.max():.2f} um, rms {np.sqrt(np.mean(position**2)):.2f} um")

    campaign = ta.Campaign.from_file(EX / "campaigns" / "kx8five" / "campaign.toml", machine)
    result = ta.identify(machine, campaign)
    doc = result.to_dict()
    print(f"identified {len(result.names)} parameters, residual rms {doc['residual_rms_um']:.3f} um:")
    for name, value, u, unit in zip(result.names, result.values, result.std_uncertainty, result.units):
        print(f"  {name:5} {value:9.3f} +- {u:.3f} {unit}")

    sources = ta.Sources.from_file(EX / "uncertainty" / "kx8five_cyclic.toml")
    plan = ta.UncertaintyPlan.from_campaign(machine, campaign, sources, budget=False)
    single = plan.run()

    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, Client(cluster) as client:
        distributed = run_uncertainty(plan, client)
    same = distributed == single
    print(f"Monte Carlo: {single['trials']} trials in {single['sequences']} sequences; on 2 Dask workers: "
          f"{'identical' if same else 'DIFFERENT'} results")
    for name in result.names[:3]:
        p = single["parameters"][name]
        print(f"  {name:5} u = {p['std_uncertainty']:.4f} {p['unit']}, 95 % interval [{p['interval'][0]:.3f}, {p['interval'][1]:.3f}]")
    return 0 if same else 1


# Dask starts its workers as new processes that import this file: run only as the main program.
if __name__ == "__main__":
    sys.exit(main())
