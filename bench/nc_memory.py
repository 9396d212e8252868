"""Peak memory and time of `trueaxis nc` against the number of lines of the program
(docs/nc.md, "Long programs": a program is read, run, corrected and written in parts).

The program is the raster of the criterion benchmark (`crates/trueaxis/benches/compensate.rs`,
`nc/vmc3`): G1 moves in 200 steps across the X travel of vmc3, one Y step per pass, three Z
levels, F3000, corrected for the vmc3 example errors, one process per run, `--out` a file beside it.
"whole" is the same program with an `o1 if [1]` ... `o1 endif` before its `M2`: control flow,
which the correction holds whole in memory (what every program took before the parts).
The peak resident memory is the child's `ru_maxrss` (`wait4`); its CPU time (user and system)
is given beside the wall time, which a loaded machine stretches.

    python3 bench/nc_memory.py [max_exponent] [max_whole_exponent]   # 10^3 .. 10^7 lines (7 6)
    TRUEAXIS_BIN=/path/to/trueaxis python3 bench/nc_memory.py 6

The programs are kept in target/nc-memory/ (about 36 bytes per line: 350 MiB for 10^7), made once.
"""

import sys
import tempfile
from pathlib import Path

from peak import BIN, ROOT, measure

MACHINE = ROOT / "examples" / "machines" / "vmc3.toml"
ERRORS = ROOT / "examples" / "errors" / "vmc3.toml"
# the travel of examples/machines/vmc3.toml (mm)
X, Y, Z = (-400, 400), (-250, 250), (-400, 0)


def triangle(t):
    """0 -> 1 -> 0 over each unit of t."""
    f = t - int(t)
    return 2 * f if f < 0.5 else 2 - 2 * f


def program(n, whole):
    """A program of n G1 lines (and 3 more), made once."""
    path = ROOT / "target" / "nc-memory" / f"raster_{n}{'_whole' if whole else ''}.ngc"
    if path.exists():
        return path
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    at = lambda r, u: r[0] + u * (r[1] - r[0])
    with open(tmp, "w") as f:
        f.write("(generated benchmark program)\nG21 G90 G17 G94\n")
        block = []
        for i in range(n):
            x, y, z = at(X, triangle(i / 200)), at(Y, (i // 200 % 100) / 99), at(Z, 0.3 + 0.2 * (i // 200 % 3))
            block.append(f"G1 X{x:.3f} Y{y:.3f} Z{z:.3f} F3000\n")
            if len(block) == 100_000:
                f.write("".join(block))
                block = []
        f.write("".join(block))
        if whole:
            f.write("o1 if [1]\no1 endif\n")
        f.write("M2\n")
    tmp.rename(path)
    return path


def main():
    top = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    top_whole = int(sys.argv[2]) if len(sys.argv) > 2 else 6
    print(f"binary {BIN}")
    print("| lines | program | path | wall / CPU | lines/s (CPU) | peak memory |")
    print("|---|---|---|---|---|---|")
    for e in range(3, top + 1):
        n = 10**e
        for whole in [False, True] if e <= top_whole else [False]:
            p = program(n, whole)
            with tempfile.TemporaryDirectory(prefix="nc-memory-", dir=p.parent) as out:
                wall, cpu, peak = measure(["nc", "--machine", MACHINE, "--errors", ERRORS, p, "--out", Path(out) / "corrected.ngc"])
            size = p.stat().st_size / 2**20
            path = "whole" if whole else "parts"
            print(f"| {n:,} | {size:,.1f} MiB | {path} | {wall:.2f} s / {cpu:.2f} s | {n / cpu:,.0f} | {peak:,.0f} MiB |", flush=True)


if __name__ == "__main__":
    main()
