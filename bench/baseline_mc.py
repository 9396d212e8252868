#!/usr/bin/env python3
"""NumPy implementation of the Andolfatto et al. 2011 adaptive Monte Carlo (JCGM 101 §7.9.4 with several outputs)
as an expert writes it, for the side-by-side comparison of bench/compare.sh. Not part of trueaxis.
The model is linear, so the observation errors are never drawn one by one: the pseudo-inverse P
of the weighted design matrix once, the Gaussian sources (sensor noise, statistical drift) folded
into one 14-dimensional normal N(0, P diag(u^2) P^T) drawn as Z A^T, the cyclic drift of each
channel folded into two 14-vectors g, h (P e = sin(2 pi tau / T) g + cos(2 pi tau / T) h), the
interval endpoints of each sequence and of the whole run by np.partition (no sort: trueaxis keeps
the values in trial order and sorts only the tails of the shortest interval, which this baseline
does not compute). The same reduced form trueaxis evaluates (src/uncertainty/linear_map.rs).

BLAS on one thread (OPENBLAS_NUM_THREADS=1, set below unless given): on a loaded 2-core machine
OpenBLAS threads slow NumPy down, and trueaxis' figures are compared thread for thread.

  python3 bench/baseline_mc.py check    # u and 95 % intervals against `trueaxis uncertainty --json`
  python3 bench/baseline_mc.py time     # timings as JSON (seconds), keys = criterion benchmark ids

Model (docs/uncertainty.md, src/uncertainty): observation errors e = noise - D(t0 + (n-1) t_m + t_i)
per channel, parameters p = p0 + P e with P = (X^T W X)^-1 X^T W; cyclic drift
D(t) = E_VE/2 sin(2 pi t / T + phase), one uniform start time t0 per sequence (Andolfatto et al. 2011 eq. 12).
"""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import io
import json
import pathlib
import subprocess
import sys
import tomllib

import numpy as np

from baseline import best  # the same timing rule as the other baselines

ROOT = pathlib.Path(__file__).resolve().parent.parent
DESIGN = ROOT / "examples/uncertainty/kx8five_design.csv"
SOURCES = ROOT / "examples/uncertainty/kx8five_cyclic.toml"


def load_design(path):
    lines = [l for l in path.read_text().splitlines() if l.strip() and not l.lstrip().startswith("#")]
    header = lines[0].split(",")
    body = [l.split(",") for l in lines[1:]]
    col = {h: i for i, h in enumerate(header)}
    channel = np.array([r[col["channel"]] for r in body])
    t = np.array([float(r[col["t"]]) for r in body])
    y = np.array([float(r[col["y"]]) for r in body]) if "y" in col else np.zeros(len(body))
    w = np.array([float(r[col["weight"]]) for r in body]) if "weight" in col else np.ones(len(body))
    names = [h for h in header if h not in ("channel", "t", "y", "weight")]
    x = np.array([[float(r[col[h]]) for h in names] for r in body])
    return names, channel, t, y, w, x


def pseudo_inverse(x, w):
    sw = np.sqrt(w)
    return np.linalg.pinv(x * sw[:, None]) * sw[None, :]


def reduced_form(p_matrix, channel, t, sources):
    """The Gaussian factor A (p x p, A A^T = P diag(var) P^T) and the cyclic sources as
    (period, run duration, g, h) with P e = sin(2 pi tau / T) g + cos(2 pi tau / T) h."""
    n = len(t)
    var = np.zeros(n)
    cyclic = []
    for s in sources:
        if s["kind"] == "noise":
            for c, d in s["channels"].items():
                var[channel == c] += d["u"] ** 2
        elif s["kind"] == "drift_statistical":
            for c, d in s["channels"].items():
                var[channel == c] += (d["peak_to_valley"] / (2 * np.sqrt(3))) ** 2
        elif s["kind"] == "drift_cyclic":
            period = s["period_s"]
            run = s.get("run_duration_s", t.max())
            cos_part, sin_part = np.zeros(n), np.zeros(n)
            for c, d in s["channels"].items():
                rows = channel == c
                theta = 2 * np.pi * t[rows] / period + np.radians(d.get("phase_deg", 0.0))
                # -pv/2 sin(a + theta) = sin(a) (-pv/2 cos theta) + cos(a) (-pv/2 sin theta)
                cos_part[rows] = -0.5 * d["peak_to_valley"] * np.cos(theta)
                sin_part[rows] = -0.5 * d["peak_to_valley"] * np.sin(theta)
            cyclic.append((period, run, p_matrix @ cos_part, p_matrix @ sin_part))
        else:
            raise SystemExit(f"source kind {s['kind']} not in this baseline")
    covariance = (p_matrix * var[None, :]) @ p_matrix.T
    values, vectors = np.linalg.eigh(covariance)
    return vectors * np.sqrt(np.clip(values, 0.0, None))[None, :], cyclic


def sequence(estimate, factor, cyclic, trials, rng):
    """M trials of one sequence: (M, p) parameter values."""
    values = estimate[None, :] + rng.standard_normal((trials, len(estimate))) @ factor.T
    for period, run, g, h in cyclic:
        t0 = rng.uniform(0.0, period)
        a = 2 * np.pi * ((t0 + np.arange(trials) * run) % period) / period
        values += np.sin(a)[:, None] * g[None, :] + np.cos(a)[:, None] * h[None, :]
    return values


def statistics(values, coverage):
    """Per output: mean, u, symmetric interval endpoints (JCGM 101 §7.7.1) of one sequence, the
    endpoints by partial selection (np.partition)."""
    m = len(values)
    q = int((1 - coverage) / 2 * m + 0.5)
    lo, hi = max(q - 1, 0), min(m - q, m - 1)
    v = np.partition(values, (lo, hi), axis=0)
    return np.stack([values.mean(0), values.std(0, ddof=1), v[lo], v[hi]], -1)


def adaptive(design, sources_path, max_sequences=None, seed=4):
    names, channel, t, y, w, x = design
    cfg = tomllib.loads(sources_path.read_text())
    p_matrix = pseudo_inverse(x, w)
    estimate = p_matrix @ y
    factor, cyclic = reduced_form(p_matrix, channel, t, cfg["source"])
    trials, coverage, delta = cfg.get("trials_per_sequence", 10_000), cfg.get("coverage", 0.95), cfg["tolerance"]
    rng = np.random.default_rng(seed)
    per_sequence, samples, h = [], [], 0
    while True:
        values = sequence(estimate, factor, cyclic, trials, rng)
        samples.append(values)
        per_sequence.append(statistics(values, coverage))
        h += 1
        if max_sequences is not None and h >= max_sequences:
            break
        if max_sequences is None and h >= 2:
            s = np.stack(per_sequence).std(0, ddof=1) / np.sqrt(h)  # (p, 4)
            if (2 * s <= delta).all() or h >= cfg.get("max_sequences", 1000):
                break
    # the results over all trials by selection, no sort (trueaxis keeps the values in trial order)
    return names, h, statistics(np.concatenate(samples), coverage)


def main():
    design = load_design(DESIGN)
    if sys.argv[1:] == ["check"]:
        names, h, stats = adaptive(design, SOURCES)
        out = subprocess.run([str(pathlib.Path(__import__("os").environ.get("TRUEAXIS", ROOT / "target/release/trueaxis"))), "uncertainty", "--design", str(DESIGN), "--sources", str(SOURCES),
                              "--no-budget", "--json"], cwd=ROOT, check=True, capture_output=True, text=True).stdout
        theirs = json.loads(out)
        worst = 0.0
        for j, name in enumerate(names):
            u = theirs["parameters"][name]["std_uncertainty"]
            worst = max(worst, abs(stats[j, 1] / u - 1))
        print(f"NumPy Monte Carlo ({h} sequences) vs trueaxis uncertainty: largest relative difference of u {worst:.2%}")
        sys.exit(0 if worst < 0.02 else 1)
    results = {
        "uncertainty/seed004_cyclic/one_sequence": best(lambda: adaptive(design, SOURCES, max_sequences=1), 3),
        "uncertainty/seed004_cyclic/adaptive": best(lambda: adaptive(design, SOURCES), 1),
    }
    print(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
