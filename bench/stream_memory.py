"""Peak memory and time of `trueaxis predict` and `trueaxis compensate --poses` against the number
of poses (docs/reliability.md: memory bounded by the run, not by its input).

Each command reads a pose file of the KX8-Five (five axes, uniformly spread over the travel) with
its 30 motion-error tables and location errors (`bench/kx8five_tables.toml`), one process per
run: `predict --out /dev/null` (the table is still formatted and written) and `compensate --format
csv --grid 3,3,3 --points 5 --poses P --out DIR` (corrections.csv streamed into the directory).
The peak resident memory is the child's `ru_maxrss` (`wait4`); its CPU time (user and system, all
threads) is given beside the wall time, which a loaded machine stretches.

    python3 bench/stream_memory.py [max_exponent]        # 10^3 .. 10^max_exponent poses (7)
    TRUEAXIS_BIN=/path/to/trueaxis python3 bench/stream_memory.py 6

The pose files are kept in target/stream-memory/ (40 bytes per pose: 385 MiB for 10^7), made once.
"""

import random
import shutil
import sys
import tempfile
from pathlib import Path

from peak import BIN, ROOT, measure

MACHINE = ROOT / "examples" / "machines" / "kx8five.toml"
ERRORS = ROOT / "bench" / "kx8five_tables.toml"
# the travel of examples/machines/kx8five.toml (mm, deg)
RANGES = [("X", -325, 325), ("Y", -350, 350), ("Z", -450, 0), ("A", 0, 180), ("C", -180, 180)]


def pose_file(n):
    """A pose file of n poses, made once (seeded)."""
    path = ROOT / "target" / "stream-memory" / f"kx8five_{n}.csv"
    if path.exists():
        return path
    path.parent.mkdir(parents=True, exist_ok=True)
    rng = random.Random(n)
    tmp = path.with_suffix(".tmp")
    with open(tmp, "w") as f:
        f.write(",".join(r[0] for r in RANGES) + "\n")
        block = []
        for _ in range(n):
            block.append(",".join(f"{rng.uniform(lo, hi):.3f}" for _, lo, hi in RANGES))
            if len(block) == 100_000:
                f.write("\n".join(block) + "\n")
                block = []
        if block:
            f.write("\n".join(block) + "\n")
    tmp.rename(path)
    return path


def main():
    top = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    print(f"binary {BIN}")
    print("| poses | file | predict wall / CPU | predict peak memory | compensate --poses wall / CPU | compensate --poses peak memory |")
    print("|---|---|---|---|---|---|")
    for e in range(3, top + 1):
        n = 10**e
        poses = pose_file(n)
        common = ["--machine", MACHINE, "--errors", ERRORS]
        pw, pc, pm = measure(["predict", *common, "--poses", poses, "--out", "/dev/null"])
        out = Path(tempfile.mkdtemp(prefix="stream-memory-"))
        try:
            cw, cc, cm = measure(["compensate", *common, "--format", "csv", "--grid", "3,3,3", "--points", "5", "--poses", poses, "--out", out / "comp"])
        finally:
            shutil.rmtree(out)
        size = poses.stat().st_size / 2**20
        print(f"| {n:,} | {size:,.0f} MiB | {pw:.2f} s / {pc:.2f} s | {pm:.0f} MiB | {cw:.2f} s / {cc:.2f} s | {cm:.0f} MiB |", flush=True)


if __name__ == "__main__":
    main()
