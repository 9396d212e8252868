#!/usr/bin/env python3
"""Straightforward NumPy/SciPy implementations of trueaxis hot paths, written for the side-by-side
comparison of bench/compare.sh (issue 8). Not part of trueaxis; each function is what a careful
engineer would write in NumPy: vectorised over poses, no Python loop per pose.

  python3 bench/baseline.py check     # the NumPy chain against `trueaxis predict` (must agree)
  python3 bench/baseline.py time      # timings as JSON (seconds per call)

The model is the one of docs/design.md, Conventions: per axis, base outward, A_k = L_k S_k(q) J_k(q) with
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


# The chain as an expert writes it in NumPy: structure of arrays (each rotation entry and coordinate
# an array over the poses, shape (3, 3, m) and (3, m)), in chunks of CHUNK poses so that the
# temporaries stay in the cache, sine and cosine once per rotary axis, the constant (location)
# transforms composed once, the small rotations of the motion errors by their series (every
# machine error is far below 0.01 rad), tables by np.interp. Outputs: position (um), orientation
# (urad) and length (um) errors, as `trueaxis predict`.
CHUNK = 8192
IDENTITY = np.eye(3)[:, :, None]


def mat_mul(a, b):  # (3,3,m) x (3,3,m) -> (3,3,m); m = 1 broadcasts
    return a[:, 0, None, :] * b[None, 0, :, :] + a[:, 1, None, :] * b[None, 1, :, :] + a[:, 2, None, :] * b[None, 2, :, :]


def mat_vec(a, v):  # (3,3,m) x (3,m) -> (3,m)
    return a[:, 0] * v[0] + a[:, 1] * v[1] + a[:, 2] * v[2]


def mat_t_vec(a, v):  # a^T v
    return a[0] * v[0] + a[1] * v[1] + a[2] * v[2]


def skew_matrix(d):
    return np.array([[0.0, -d[2], d[1]], [d[2], 0.0, -d[0]], [-d[1], d[0], 0.0]])


def small_rotation(eps):
    """exp([eps]x) for (3,m) rotation vectors below 0.01 rad: d I + a [eps]x + b eps eps^T by series."""
    t2 = (eps * eps).sum(0)
    a = 1.0 - t2 * (1 / 6 - t2 * (1 / 120 - t2 / 5040))
    b = 0.5 - t2 * (1 / 24 - t2 * (1 / 720 - t2 / 40320))
    r = b * eps[:, None, :] * eps[None, :, :]
    r += (1.0 - b * t2) * IDENTITY
    x, y, z = a * eps
    r[0, 1] -= z
    r[0, 2] += y
    r[1, 0] += z
    r[1, 2] -= x
    r[2, 0] -= y
    r[2, 1] += x
    return r


def small_transform(eps, e, c):
    """Trans(c) [exp([eps]x), e] Trans(-c): rotation (3,3,m), translation (3,m)."""
    r = small_rotation(eps)
    return r, c + e - mat_vec(r, c)


class Chain:
    """Prepared once per machine and error model: per side, the steps base outward."""

    def __init__(self, machine, constants, tables):
        self.machine, self.tables = machine, tables
        self.steps = {}
        for side in ("tool", "work"):
            steps = []
            for letter in machine[side]:
                ax = machine["axes"][letter]
                loc = np.array([constants.get(f"E{c}0{letter}", 0.0) * scale(c) for c in COMPONENTS])
                if loc.any():  # a constant location error: its transform once
                    r, t = small_transform(loc[3:, None], loc[:3, None], (ax["p"] if ax["rotary"] else np.zeros(3))[:, None])
                    steps.append(("fixed", r, t))
                mot = [f"E{c}{letter}" for c in COMPONENTS]
                if any(n in constants or n in tables for n in mot):
                    steps.append(("motion", letter))
                if ax["rotary"]:
                    d = ax["d"]
                    steps.append(("rotate", letter, np.eye(3)[:, :, None], skew_matrix(d)[:, :, None], np.outer(d, d)[:, :, None], ax["p"][:, None]))
                else:
                    steps.append(("translate", letter, ax["d"][:, None]))
            self.steps[side] = steps
        self.constants = constants
        self.setup = {s: np.array([constants.get(f"{s}{c}", 0.0) * 1e-3 for c in "XYZ"])[:, None] for s in "TW"}

    def motion_values(self, letter, q_user):
        """(eps, e) of the motion errors of one axis at the chunk's positions (rad, mm)."""
        v = np.zeros((6, len(q_user)))
        for i, c in enumerate(COMPONENTS):
            name = f"E{c}{letter}"
            if name in self.constants:
                v[i] += self.constants[name] * scale(c)
            if name in self.tables:
                pos, val = self.tables[name]
                period = 360.0 if self.machine["axes"][letter]["rotary"] and pos[-1] - pos[0] == 360.0 else None
                v[i] += np.interp(q_user, pos, val, period=period) * scale(c)
        return v[3:], v[:3]

    def ends(self, side, q, q_user):
        """Nominal and actual pose of the end of one chain for the chunk's poses."""
        nominal = actual = None
        m = len(q_user[next(iter(q_user))])

        def then(pose, r, t):
            if pose is None:
                return np.broadcast_to(r, (3, 3, m)) if r.shape[2] == 1 else r, np.broadcast_to(t, (3, m)) if t.shape[1] == 1 else t
            return mat_mul(pose[0], r), pose[1] + mat_vec(pose[0], t)

        for step in self.steps[side]:
            kind, letter = step[0], step[1]
            if kind == "fixed":
                actual = then(actual, step[1], step[2])
            elif kind == "motion":
                ax = self.machine["axes"][letter]
                eps, e = self.motion_values(letter, q_user[letter])
                centre = ax["p"][:, None] + (0 if ax["rotary"] else ax["d"][:, None] * q[letter])
                actual = then(actual, *small_transform(eps, e, centre))
            elif kind == "rotate":
                _, _, eye, k, dd, p = step
                c, s_ = np.cos(q[letter]), np.sin(q[letter])
                r = eye * c + k * s_ + dd * (1.0 - c)
                t = p - mat_vec(r, p)
                nominal, actual = then(nominal, r, t), then(actual, r, t)
            else:
                t = step[2] * q[letter]
                for pose in ("nominal", "actual"):
                    cur = nominal if pose == "nominal" else actual
                    new = (np.broadcast_to(IDENTITY, (3, 3, m)), t) if cur is None else (cur[0], cur[1] + mat_vec(cur[0], t))
                    if pose == "nominal":
                        nominal = new
                    else:
                        actual = new
        return nominal, actual

    def volumetric_error(self, q_user, work_point=np.zeros(3)):
        """(m, 7): dx dy dz (um), drx dry drz (urad), dL (um) in the workpiece frame, chunk by chunk."""
        n = len(q_user[next(iter(q_user))])
        out = np.empty((n, 7))
        tp, wp = self.machine["tool_point"][:, None], work_point[:, None]
        for lo in range(0, n, CHUNK):
            qu = {k: v[lo:lo + CHUNK] for k, v in q_user.items()}
            q = {k: (np.radians(v) if self.machine["axes"][k]["rotary"] else v) for k, v in qu.items()}
            (tn, ta), (wn, wa) = self.ends("tool", q, qu), self.ends("work", q, qu)
            r_nominal = mat_t_vec(wn[0], mat_vec(tn[0], tp) + tn[1] - mat_vec(wn[0], wp) - wn[1])
            r_actual = mat_t_vec(wa[0], mat_vec(ta[0], tp + self.setup["T"]) + ta[1] - mat_vec(wa[0], wp + self.setup["W"]) - wa[1])
            position = r_actual - r_nominal
            # relative rotation actual x nominal^T; its rotation vector by the skew part (small angles)
            rel_a = np.einsum("kim,kjm->ijm", wa[0], ta[0])
            rel_n = np.einsum("kim,kjm->ijm", wn[0], tn[0])
            d = np.einsum("ikm,jkm->ijm", rel_a, rel_n)
            w = 0.5 * np.array([d[2, 1] - d[1, 2], d[0, 2] - d[2, 0], d[1, 0] - d[0, 1]])
            sin_t = np.sqrt((w * w).sum(0))
            cos_t = 0.5 * (d[0, 0] + d[1, 1] + d[2, 2] - 1.0)
            theta = np.arctan2(sin_t, cos_t)
            w *= np.where(sin_t > 0, theta / np.where(sin_t > 0, sin_t, 1.0), 1.0)
            norms = np.sqrt((r_actual ** 2).sum(0)) + np.sqrt((r_nominal ** 2).sum(0))
            length = (position * (r_actual + r_nominal)).sum(0) / np.where(norms > 0, norms, 1.0)
            out[lo:lo + CHUNK, :3] = position.T * 1e3
            out[lo:lo + CHUNK, 3:6] = w.T * 1e6
            out[lo:lo + CHUNK, 6] = length * 1e3
        return out


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
        mine = Chain(machine, constants, tables).volumetric_error(q)
        csv = "X,Y,Z,A,C\n" + "\n".join(",".join(f"{q[c][i]:.12g}" for c in "XYZAC") for i in range(200)) + "\n"
        pose_file = ROOT / "target/baseline_poses.csv"
        pose_file.write_text(csv)
        out = subprocess.run([str(ROOT / "target/release/trueaxis"), "predict", "--machine", "examples/machines/kx8five.toml",
                              "--errors", "bench/kx8five_tables.toml", "--poses", str(pose_file), "--json"],
                             cwd=ROOT, check=True, capture_output=True, text=True).stdout
        theirs = np.array([[p[k] for k in ("dx", "dy", "dz", "drx", "dry", "drz", "dL")] for p in json.loads(out)["poses"]])
        worst = np.abs(mine - theirs).max()
        print(f"NumPy chain vs trueaxis predict over 200 poses: largest difference {worst:.2e} um")
        sys.exit(0 if worst < 1e-4 else 1)  # predict prints 4 decimals

    rng = np.random.default_rng(1)
    results = {}
    prepared = Chain(machine, constants, tables)
    for n in (10_000, 1_000_000):
        q = poses(machine, n)
        results[f"volumetric_error/batch/{n}"] = best(lambda: prepared.volumetric_error(q), 3 if n < 10**6 else 1)
    q1 = poses(machine, 1)
    results["volumetric_error/one_pose"] = best(lambda: prepared.volumetric_error(q1), 200)
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
            cols.append((Chain(machine, plus, tables).volumetric_error(q807) - Chain(machine, minus, tables).volumetric_error(q807))[:, :3] / (2 * h))
        return np.stack(cols, -1)
    results["jacobian/batch_807"] = best(jacobian, 3)
    # the identification solves: bench/baseline_identify.py
    print(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
