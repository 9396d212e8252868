#!/usr/bin/env python3
"""Straightforward NumPy/SciPy implementations of trueaxis hot paths, written for the side-by-side
comparison of bench/compare.sh (issue 8). Not part of trueaxis; each function is what a careful
engineer would write in NumPy: vectorised over poses, no Python loop per pose.

  python3 bench/baseline.py check     # the NumPy chain against `trueaxis predict` (must agree)
  python3 bench/baseline.py time      # timings as JSON (seconds per call)

The model is the one of DESIGN.md section 2: per axis, base outward, A_k = L_k S_k(q) J_k(q) with
exact small transforms Trans(c) [exp([eps]x), e] Trans(-c); the volumetric error is the tool point
relative to the workpiece point, actual minus nominal, in the workpiece frame.
"""
import json
import pathlib
import subprocess
import sys
import time
import tomllib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
COMPONENTS = "XYZABC"


def load_machine(path):
    m = tomllib.loads(pathlib.Path(path).read_text())
    code = m["structure"]
    upper = code.upper()
    w, f, t = upper.index("W"), upper.index("F") if "F" in upper else upper.index("B"), upper.index("T")
    work_side = list(code[w + 1:f].upper())[::-1]  # base outward
    tool_side = list(code[f + 1:t].upper())
    axes = {}
    for letter, a in m["axes"].items():
        d = np.array(a["direction"], float)
        axes[letter] = {"rotary": a["kind"] == "rotary", "d": d / np.linalg.norm(d),
                        "p": np.array(a.get("point", [0, 0, 0]), float), "range": a.get("range", [0.0, 360.0])}
    return {"axes": axes, "tool": tool_side, "work": work_side, "tool_point": np.array(m["tool"]["point"], float)}


def load_errors(path):
    e = tomllib.loads(pathlib.Path(path).read_text())
    return e.get("constant", {}), {k: (np.array(v["position"], float), np.array(v["value"], float)) for k, v in e.get("table", {}).items()}


def scale(component):
    return 1e-3 if component in "XYZ" else 1e-6  # um -> mm, urad -> rad


def skew(v):  # (N,3) -> (N,3,3)
    z = np.zeros(len(v))
    return np.stack([np.stack([z, -v[:, 2], v[:, 1]], -1), np.stack([v[:, 2], z, -v[:, 0]], -1),
                     np.stack([-v[:, 1], v[:, 0], z], -1)], -2)


def rodrigues(axis_times_angle):
    theta = np.linalg.norm(axis_times_angle, axis=1)
    k = skew(axis_times_angle)
    safe = np.where(theta > 0, theta, 1.0)
    a = np.where(theta > 0, np.sin(safe) / safe, 1.0)
    b = np.where(theta > 0, 2.0 * (np.sin(0.5 * safe) / safe) ** 2, 0.5)
    return np.eye(3) + a[:, None, None] * k + b[:, None, None] * (k @ k)


def compose(r1, t1, r2, t2):
    return r1 @ r2, np.einsum("nij,nj->ni", r1, t2) + t1


def chain(machine, side, q, params):
    """Nominal (params None) or actual pose of the end of one chain, for N poses."""
    n = len(next(iter(q.values())))
    r, t = np.broadcast_to(np.eye(3), (n, 3, 3)).copy(), np.zeros((n, 3))
    for letter in machine[side]:
        ax = machine["axes"][letter]
        qk = q[letter]
        if params is not None:
            for kind, centre in (("loc", ax["p"] if ax["rotary"] else np.zeros(3)),
                                 ("mot", ax["p"] if ax["rotary"] else ax["p"] + np.outer(qk, ax["d"]))):
                eps, e = params[(kind, letter)]
                rs = rodrigues(eps)
                c = np.broadcast_to(centre, (n, 3))
                r, t = compose(r, t, rs, c + e - np.einsum("nij,nj->ni", rs, c))
        if ax["rotary"]:
            rj = rodrigues(np.outer(qk, ax["d"]))
            tj = ax["p"] - np.einsum("nij,j->ni", rj, ax["p"])
        else:
            rj, tj = np.broadcast_to(np.eye(3), (n, 3, 3)), np.outer(qk, ax["d"])
        r, t = compose(r, t, rj, tj)
    return r, t


def parameters(machine, constants, tables, q_user, vector=None):
    """Per axis and kind, (eps, e) arrays (N,3) in rad and mm, from the error values at the poses."""
    n = len(next(iter(q_user.values())))
    out = {}
    for letter in machine["axes"]:
        for kind in ("loc", "mot"):
            v = np.zeros((n, 6))
            for i, c in enumerate(COMPONENTS):
                name = f"E{c}0{letter}" if kind == "loc" else f"E{c}{letter}"
                if name in constants:
                    v[:, i] += constants[name] * scale(c)
                if kind == "mot" and name in tables:
                    pos, val = tables[name]
                    period = 360.0 if machine["axes"][letter]["rotary"] and pos[-1] - pos[0] == 360.0 else None
                    v[:, i] += np.interp(q_user[letter], pos, val, period=period) * scale(c)
            out[(kind, letter)] = (v[:, 3:], v[:, :3])
    setup = {s: np.array([constants.get(f"{s}{c}", 0.0) * 1e-3 for c in "XYZ"]) for s in "TW"}
    return out, setup


def volumetric_error(machine, constants, tables, q_user, work_point=np.zeros(3)):
    """dx dy dz (um) in the workpiece frame for N poses (q_user: letter -> array, mm or deg)."""
    q = {k: (np.radians(v) if machine["axes"][k]["rotary"] else v) for k, v in q_user.items()}
    params, setup = parameters(machine, constants, tables, q_user)
    tp = machine["tool_point"]
    rel = []
    for p, dt, dw in ((None, 0.0, 0.0), (params, setup["T"], setup["W"])):
        rt, tt = chain(machine, "tool", q, p)
        rw, tw = chain(machine, "work", q, p)
        tool = np.einsum("nij,j->ni", rt, tp + dt) + tt
        work = np.einsum("nij,j->ni", rw, work_point + dw) + tw
        rel.append(np.einsum("nji,nj->ni", rw, tool - work))
    return (rel[1] - rel[0]) * 1e3


def poses(machine, n):
    """The pose set of benches/common/mod.rs: u_k(i) = frac(i sqrt(p_k)), canonical axis order."""
    order = [c for c in "XYZUVWABC" if c in machine["axes"]]
    primes = [2, 3, 5, 7, 11, 13, 17, 19, 23]
    i = np.arange(n, dtype=float)
    out = {}
    for k, letter in enumerate(order):
        lo, hi = machine["axes"][letter]["range"]
        out[letter] = lo + np.modf(i * np.sqrt(primes[k]))[0] * (hi - lo)
    return out


def best(f, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def main():
    machine = load_machine(ROOT / "examples/machines/kx8five.toml")
    constants, tables = load_errors(ROOT / "bench/kx8five_tables.toml")
    if sys.argv[1:] == ["check"]:
        q = poses(machine, 200)
        mine = volumetric_error(machine, constants, tables, q)
        csv = "X,Y,Z,A,C\n" + "\n".join(",".join(f"{q[c][i]:.12g}" for c in "XYZAC") for i in range(200)) + "\n"
        pose_file = ROOT / "target/baseline_poses.csv"
        pose_file.write_text(csv)
        out = subprocess.run([str(ROOT / "target/release/trueaxis"), "predict", "--machine", "examples/machines/kx8five.toml",
                              "--errors", "bench/kx8five_tables.toml", "--poses", str(pose_file), "--json"],
                             cwd=ROOT, check=True, capture_output=True, text=True).stdout
        theirs = np.array([[p["dx"], p["dy"], p["dz"]] for p in json.loads(out)["poses"]])
        worst = np.abs(mine - theirs).max()
        print(f"NumPy chain vs trueaxis predict over 200 poses: largest difference {worst:.2e} um")
        sys.exit(0 if worst < 1e-4 else 1)  # predict prints 4 decimals

    rng = np.random.default_rng(1)
    results = {}
    for n in (10_000, 1_000_000):
        q = poses(machine, n)
        results[f"volumetric_error/batch/{n}"] = best(lambda: volumetric_error(machine, constants, tables, q), 3 if n < 10**6 else 1)
    q1 = poses(machine, 1)
    results["volumetric_error/one_pose"] = best(lambda: volumetric_error(machine, constants, tables, q1), 200)
    # first-order Jacobian of the 807-pose test by central differences of the vectorised chain
    # (84 parameters: what a NumPy user without an analytic adjoint Jacobian writes)
    q807 = poses(machine, 807)
    names = [f"E{c}{s}{a}" for a in machine["axes"] for s in ("", "0") for c in COMPONENTS] + [f"{s}{c}" for s in "TW" for c in "XYZ"]

    def jacobian():
        cols = []
        for name in names:
            h = 1.0
            plus, minus = dict(constants), dict(constants)
            plus[name] = constants.get(name, 0.0) + h
            minus[name] = constants.get(name, 0.0) - h
            cols.append((volumetric_error(machine, plus, tables, q807) - volumetric_error(machine, minus, tables, q807)) / (2 * h))
        return np.stack(cols, -1)
    results["jacobian/batch_807"] = best(jacobian, 3)
    # the identification solves: bench/baseline_identify.py
    print(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
