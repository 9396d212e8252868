"""What the memory benchmarks share (bench/stream_memory.py, bench/nc_memory.py): the binary under
test, and one run of it measured as the wall time, the CPU time of the child (user and system, all
threads) and its peak resident memory (`ru_maxrss` from `wait4`)."""

import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = os.environ.get("TRUEAXIS_BIN", str(ROOT / "target" / "release" / "trueaxis"))


def measure(args):
    """(wall s, CPU s, peak resident MiB) of one run of trueaxis with args."""
    start = time.perf_counter()
    p = subprocess.Popen([BIN, *map(str, args)], cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - start
    err = p.stderr.read().decode()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"trueaxis {' '.join(map(str, args))} failed: {err}")
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024
