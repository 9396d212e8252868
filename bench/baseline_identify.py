#!/usr/bin/env python3
"""NumPy/SciPy baseline of trueaxis's weighted least-squares identification (`identify::solve`),
written as an expert would for the same outputs (issue 23): unit-length column scaling, singular
values, solution, covariance and residuals from the p x p weighted Gram matrix (BLAS dsyrk,
n p^2 flops) and its symmetric eigendecomposition (LAPACK syevd), Cholesky for the solution; the
scaled matrix is never decomposed whole (no thin SVD, no n x p factor). As in trueaxis, a scaled
condition number above 1e4 (eps cond^2 > 2e-8) falls back to a QR of the scaled [A | b]
(scipy.linalg.qr, mode='r').

  python3 bench/baseline_identify.py check   # against trueaxis on two problems (must agree)
  python3 bench/baseline_identify.py time    # timings as JSON (seconds per call)

The BLAS thread count is OpenBLAS's: bench/compare.sh runs it with OPENBLAS_NUM_THREADS=1;
BENCHMARKS.md also states the figures with 2.
"""
import json
import pathlib
import subprocess
import sys

import numpy as np
import scipy.linalg as sl
from scipy.linalg.blas import dsyrk

from baseline import best  # bench/baseline.py: the fastest of `repeat` calls

ROOT = pathlib.Path(__file__).resolve().parent.parent
GRAM_CONDITION_LIMIT = 1e4
BLOCK_ROWS = 8192  # rows weighted at a time: the n x p weighted copy never exists whole


def weighted_gram(x, y, w):
    """Lower triangle of [X | y]^T W [X | y] (dsyrk on blocks of rows, Fortran order)."""
    n, p = x.shape
    g = np.zeros((p + 1, p + 1), order="F")
    sw = np.sqrt(w)
    for s in range(0, n, BLOCK_ROWS):
        block = np.empty((p + 1, min(BLOCK_ROWS, n - s)), order="F")  # the block transposed
        np.multiply(x[s:s + BLOCK_ROWS].T, sw[s:s + BLOCK_ROWS], out=block[:p])
        np.multiply(y[s:s + BLOCK_ROWS], sw[s:s + BLOCK_ROWS], out=block[p])
        g = dsyrk(1.0, block, beta=1.0, c=g, trans=0, lower=1, overwrite_c=1)
    return g


def solve(x, y, w):
    """What trueaxis `solve` returns: solution, standard uncertainties, sigma0, singular values."""
    n, p = x.shape
    g = weighted_gram(x, y, w)
    d = np.sqrt(np.diag(g)[:p])
    d[~(d > 0) | ~np.isfinite(d)] = 1.0
    a_ta = np.tril(g[:p, :p]) / np.outer(d, d)
    a_tb = g[p, :p] / d
    eigenvalues, v = sl.eigh(a_ta, lower=True, driver="evd", check_finite=False)
    s = np.sqrt(np.clip(eigenvalues[::-1], 0.0, None))
    v = v[:, ::-1]
    if s[-1] > 0 and s[0] <= GRAM_CONDITION_LIMIT * s[-1]:
        inverse = (v / s**2) @ v.T
        beta = sl.cho_solve(sl.cho_factor(a_ta, lower=True, check_finite=False), a_tb, check_finite=False)
    else:  # QR of the scaled [A | b], as trueaxis falls back
        sw = np.sqrt(w)
        r = sl.qr(np.column_stack([x * sw[:, None] / d, y * sw]), mode="r", check_finite=False)[0][: p + 1]
        _, s, vt = np.linalg.svd(r[:p, :p])
        inverse = (vt.T / s**2) @ vt
        beta = sl.solve_triangular(r[:p, :p], r[:p, p])
    solution = beta / d
    residuals = y - x @ solution
    sigma0 = np.sqrt(w @ residuals**2 / (n - p))
    covariance = inverse / np.outer(d, d) * sigma0**2
    return solution, np.sqrt(np.diag(covariance)), sigma0, s


def random_problem(rng, rows, cols, weighted):
    x = rng.standard_normal((rows, cols))
    truth = np.sin(0.7 * np.arange(cols))
    sigma = rng.uniform(0.5, 2.0, rows) if weighted else np.ones(rows)
    y = x @ truth + sigma * rng.standard_normal(rows)
    return x, y, 1.0 / sigma**2


def write_design(path, x, y, w):
    header = "channel,t,y,weight," + ",".join(f"c{j}" for j in range(x.shape[1]))
    table = np.column_stack([np.arange(len(y)), y, w, x])
    np.savetxt(path, table, delimiter=",", header=header, comments="", fmt="x,%d," + ",".join(["%.17g"] * (x.shape[1] + 2)))


def check():
    rng = np.random.default_rng(23)
    # the Andolfatto et al. 2011 design (807 poses x 3 channels, 14 parameters: the QR path) with simulated
    # readings, and a dense weighted 20000 x 210 problem (the Gram path: n (p + 1) >= 2^22)
    lines = [line for line in (ROOT / "examples/uncertainty/kx8five_design.csv").read_text().splitlines() if not line.startswith("#")]
    x4 = np.loadtxt(lines[1:], delimiter=",", usecols=range(2, len(lines[0].split(","))))
    sigma4 = rng.uniform(0.2, 1.0, x4.shape[0])
    y4 = x4 @ rng.uniform(-5, 5, x4.shape[1]) + sigma4 * rng.standard_normal(x4.shape[0])
    problems = {"Andolfatto et al. 2011 design 2421 x 14": (x4, y4, 1.0 / sigma4**2), "random weighted 20000 x 210": random_problem(rng, 20_000, 210, True)}
    worst = 0.0
    for name, (x, y, w) in problems.items():
        path = ROOT / "target/baseline_identify_design.csv"
        write_design(path, x, y, w)
        out = subprocess.run(["cargo", "run", "--release", "--quiet", "-p", "trueaxis", "--example", "identify_solve", "--", str(path)],
                             cwd=ROOT, check=True, capture_output=True, text=True).stdout
        theirs = json.loads(out)
        solution, u, sigma0, s = solve(x, y, w)
        errors = {
            "solution": np.abs(solution - theirs["solution"]).max() / np.abs(solution).max(),
            "std uncertainty": np.abs(u / np.array(theirs["std_uncertainty"]) - 1).max(),
            "sigma0": abs(sigma0 / theirs["sigma0"] - 1),
            "singular values": np.abs(s / np.array(theirs["singular_values"]) - 1).max(),
        }
        print(f"baseline vs trueaxis solve, {name}: largest relative differences "
              + ", ".join(f"{k} {v:.1e}" for k, v in errors.items()))
        worst = max(worst, *errors.values())
    sys.exit(0 if worst < 1e-9 else 1)


def main():
    if sys.argv[1:] == ["check"]:
        check()
    rng = np.random.default_rng(1)
    results = {}
    # the shapes of benches/identify.rs: the Andolfatto et al. 2011 size and the dense 10^5 x 500 (unit weights)
    for rows, cols in ((807 * 3, 14), (100_000, 500)):
        x, y, w = random_problem(rng, rows, cols, False)
        results[f"identify/solve_{rows}x{cols}"] = best(lambda: solve(x, y, w), 20 if rows < 10**5 else 3)
    print(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
