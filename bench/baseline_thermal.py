#!/usr/bin/env python3
"""SciPy baseline of trueaxis thermal modal analysis, as an expert writes it (issue 23), for the
side-by-side comparison of bench/compare.sh. Not part of trueaxis. BLAS on one thread
(OPENBLAS_NUM_THREADS=1, set below unless given).

  python3 bench/baseline_thermal.py check   # SciPy time constants against `trueaxis thermal modes`
  python3 bench/baseline_thermal.py time    # seconds per call as JSON, keyed by criterion id

The model is the one of benches/thermal.rs: a steel block 0.5 x 0.4 x 0.3 m (k = 50 W/m/K,
rho = 7850 kg/m^3, c_p = 460 J/kg/K) on a structured grid of trilinear hexahedra, convection
20 / 10 W/m^2/K on the faces x = 0 / x = 0.5 m, 5 on y = 0, 8 on z = 0.3 m, other faces insulated.
K and C are assembled here independently of trueaxis, as Kronecker products of the 1D linear-element
matrices (node i + nx (j + ny k)): C = rho c_p Mz (x) My (x) Mx, K = k (Kz (x) My (x) Mx + Mz (x) Ky (x) Mx
+ Mz (x) My (x) Kx) + sum over faces h (face mass). The first 20 modes: scipy.sparse.linalg.eigsh
(ARPACK) in shift-invert mode, with the factor of K - sigma C given as OPinv: SuperLU with a symmetric
fill-reducing ordering (permc_spec='MMD_AT_PLUS_A', SymmetricMode, no pivoting off the diagonal:
eigsh's default ordering COLAMD ignores the symmetry and fills 5x more, 483 s -> 86 s at 1e5 nodes),
and the shift trueaxis uses (half the smallest Rayleigh-quotient bound of lambda_1). For large
meshes an expert also tries scipy.sparse.linalg.lobpcg preconditioned by pyamg's smoothed-aggregation
multigrid (pip install pyamg), the method trueaxis takes above 5 x 10^4 nodes; `time` reports both
and, as thermal_modes/first_20, the faster.
"""
import importlib.util
import json
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import pathlib
import subprocess
import sys
import tempfile

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from baseline import best  # bench/baseline.py: the best of `repeat` timed calls

ROOT = pathlib.Path(__file__).resolve().parent.parent
SIZE_M = (0.5, 0.4, 0.3)
K_W_MK, RHO, CP = 50.0, 7850.0, 460.0
FACES = {"xmin": 20.0, "xmax": 10.0, "ymin": 5.0, "zmax": 8.0}
# cells per direction -> about 1e3, 1e4, 1e5 nodes (criterion parameter = node count)
CELLS = ((9, 9, 9), (21, 21, 21), (46, 46, 46))
MODES = 20


def line(cells, length):
    """1D linear elements: stiffness [[1,-1],[-1,1]]/h and consistent mass h [[2,1],[1,2]]/6."""
    h = length / cells
    n = cells + 1
    main = np.full(n, 2.0)
    main[[0, -1]] = 1.0
    k = sp.diags([main / h, -np.ones(n - 1) / h, -np.ones(n - 1) / h], [0, 1, -1], format="csr")
    m = sp.diags([main * h / 3.0, np.full(n - 1, h / 6.0), np.full(n - 1, h / 6.0)], [0, 1, -1], format="csr")
    return k, m


def end(n, side):
    """The 1 x 1 'mass' of a face at one end of a 1D line: e e^T."""
    e = np.zeros(n)
    e[0 if side == "min" else -1] = 1.0
    return sp.diags(e, format="csr")


def assemble(cells):
    (kx, mx), (ky, my), (kz, mz) = (line(c, s) for c, s in zip(cells, SIZE_M))
    kron3 = lambda z, y, x: sp.kron(z, sp.kron(y, x, format="csr"), format="csr")
    c = RHO * CP * kron3(mz, my, mx)
    k = K_W_MK * (kron3(kz, my, mx) + kron3(mz, ky, mx) + kron3(mz, my, kx))
    ones = [m.shape[0] for m in (mx, my, mz)]
    for face, h in FACES.items():
        axis, side = "xyz".index(face[0]), face[1:]
        factors = [mx, my, mz]
        factors[axis] = end(ones[axis], side)
        k = k + h * kron3(factors[2], factors[1], factors[0])
    return k.tocsc(), c.tocsc()


def shift(k, c):
    """As trueaxis (src/thermal/lanczos.rs): half the smaller of the Rayleigh quotients of the
    constant vector and of the unit vectors (both upper bounds of lambda_1), at least 1e-6 of the
    latter, below zero."""
    diagonal = (k.diagonal() / c.diagonal()).min()
    constant = k.sum() / c.sum()
    bound = min(constant, diagonal) if constant > 0 else diagonal
    return -max(0.5 * bound, 1e-6 * diagonal)


def modes(k, c):
    """The 20 lowest eigenpairs of K phi = lambda C phi (with the mode shapes, as trueaxis):
    eigsh in shift-invert mode on a SuperLU factor of K - sigma C in a symmetric ordering."""
    sigma = shift(k, c)
    lu = sla.splu((k - sigma * c).tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                  options=dict(SymmetricMode=True))
    n = k.shape[0]
    op_inv = sla.LinearOperator((n, n), matvec=lu.solve, dtype=np.float64)
    return sla.eigsh(k, MODES, M=c, sigma=sigma, which="LM", OPinv=op_inv)


def have_pyamg():
    return importlib.util.find_spec("pyamg") is not None


def modes_lobpcg(k, c):
    """The same 20 modes by LOBPCG (block of 24, tolerance 1e-8) preconditioned by one V-cycle of
    pyamg's smoothed-aggregation multigrid of K (its defaults: symmetric Gauss-Seidel smoothing,
    the constant near-null-space vector), as an expert writes it for large meshes."""
    import pyamg

    n = k.shape[0]
    ml = pyamg.smoothed_aggregation_solver(k.tocsr(), B=np.ones((n, 1)), max_coarse=2000)
    x = np.random.default_rng(0).standard_normal((n, MODES + 4))
    lam, vecs = sla.lobpcg(k.tocsr(), x, B=c.tocsr(), M=ml.aspreconditioner(cycle="V"), tol=1e-8, maxiter=500, largest=False)
    order = np.argsort(lam)[:MODES]
    return lam[order], vecs[:, order]


def time_constants_s(cells, method="eigsh"):
    """The 20 longest time constants (s), decreasing."""
    lam, _ = (modes if method == "eigsh" else modes_lobpcg)(*assemble(cells))
    return np.sort(1.0 / lam)[::-1]


def model_toml(cells):
    faces = ", ".join(f"{f} = {h}" for f, h in FACES.items())
    return (f'kind = "grid3d"\nsize_m = {list(SIZE_M)}\ncells = {list(cells)}\nconductivity_w_mk = {K_W_MK}\n'
            f'density_kg_m3 = {RHO}\nspecific_heat_j_kgk = {CP}\nboundary = {{ {faces} }}\nflux_node = [0, 0, 0]\n')


def check():
    worst = 0.0
    with tempfile.TemporaryDirectory() as d:
        for cells in CELLS[:2]:
            path = pathlib.Path(d) / "block.toml"
            path.write_text(model_toml(cells))
            for method, scipy_method in (("lanczos", "eigsh"), ("lobpcg", "lobpcg")):
                out = subprocess.run([str(ROOT / "target/release/trueaxis"), "thermal", "modes", "--model", str(path), "--count",
                                      str(MODES), "--method", method, "--json"], check=True, capture_output=True, text=True).stdout
                theirs = np.array([m["tau_s"] for m in json.loads(out)["modes"]])
                if scipy_method == "lobpcg" and not have_pyamg():
                    print("pyamg not installed: the LOBPCG check is skipped")
                    continue
                mine = time_constants_s(cells, scipy_method)
                diff = np.abs(mine - theirs) / theirs
                worst = max(worst, diff.max())
                nodes = np.prod([c + 1 for c in cells])
                print(f"{nodes} nodes, trueaxis {method} vs SciPy {scipy_method}: tau_1 {mine[0] / 60:.4f} min, "
                      f"tau_20 {mine[-1] / 60:.4f} min; largest relative difference {diff.max():.1e}")
    sys.exit(0 if worst < 1e-8 else 1)


def main():
    if sys.argv[1:] == ["check"]:
        check()
    elif sys.argv[1:] == ["time"]:
        results = {}
        for cells in CELLS:
            nodes = int(np.prod([c + 1 for c in cells]))
            k, c = assemble(cells)
            repeat = 3 if nodes < 10**5 else 1
            eigsh = best(lambda: modes(k, c), repeat)
            # the expert's choice: the faster of shift-invert eigsh and multigrid LOBPCG
            lobpcg = best(lambda: modes_lobpcg(k, c), repeat) if have_pyamg() else None
            results[f"thermal_modes/first_20/{nodes}"] = min(eigsh, lobpcg or eigsh)
            results[f"thermal_modes/lanczos_first_20/{nodes}"] = eigsh
            if lobpcg is not None:
                results[f"thermal_modes/lobpcg_first_20/{nodes}"] = lobpcg
        print(json.dumps(results, indent=1))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
