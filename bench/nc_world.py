#!/usr/bin/env python3
"""`trueaxis nc` on real programs that other people wrote and published (issue 31's measure).

The programs are not in the repository (they are other people's files): this script fetches each
from its public repository at a pinned commit, runs `trueaxis nc` on it as a new user would (the
dialect detected, with a tool table and again without one, on a vmc3 whose travel and error tables
are widened to +-3 m so that no program is refused for its size), and classes what happens:

    python3 bench/nc_world.py fetch DIR        # git, network: the files below into DIR/owner/repo/path
    python3 bench/nc_world.py run DIR [--trueaxis target/release/trueaxis] [--dialect D]

Classes: corrected; refused by design (probing, cutter radius compensation, spindle-synchronised
motion: what no point-by-point corrector can do, docs/nc.md); the program stops itself (an alarm
it raises, `M99` restarting it, a wait loop on signals from outside); not for this machine (an axis
it lacks, a travel beyond +-3 m); refused as LinuxCNC refuses it (read as RS274/NGC, and LinuxCNC's
`rs274`, when installed, stops on the program too); failed (anything else: a reading trueaxis should
make). The result is in docs/nc.md, "Programs from other sources".
"""
import argparse, json, os, re, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
MANIFEST = json.load(open(os.path.join(HERE, "nc_world.json")))

CLASSES = [
    ("refused by design", r"\((probing|cutter radius compensation|spindle-synchronised motion)\)"),
    ("the program stops itself", r"stops with alarm|restarts it endlessly|endless loop|aborts here"),
    ("not for this machine", r"is not an axis of machine|leaves the machine's travel|covers .* but the program reaches"),
]
RS274 = "refused as LinuxCNC refuses it (rs274 stops on the program)"


def fetch(target):
    by_repo = {}
    for repo, commit, path in MANIFEST:
        by_repo.setdefault((repo, commit), []).append(path)
    for (repo, commit), paths in by_repo.items():
        with tempfile.TemporaryDirectory() as tmp:
            git = lambda *a: subprocess.run(["git", "-C", tmp, *a], check=True, capture_output=True)
            git("init", "-q")
            git("fetch", "-q", "--depth", "1", f"https://github.com/{repo}", commit)
            for p in paths:
                dest = os.path.join(target, repo, p)
                os.makedirs(os.path.dirname(dest), exist_ok=True)
                with open(dest, "wb") as f:
                    f.write(subprocess.run(["git", "-C", tmp, "show", f"{commit}:{p}"], check=True, capture_output=True).stdout)
        print(f"{repo}: {len(paths)} files")


def setup(tmp):
    """The widened vmc3, its errors and a tool table T1-T399 (LinuxCNC format, mm)."""
    machine = open(os.path.join(ROOT, "examples/machines/vmc3.toml")).read()
    for a in ("[-400, 400]", "[-250, 250]", "[-400, 0]"):
        machine = machine.replace(f"range = {a}", "range = [-3000, 3000]")
    errors = open(os.path.join(ROOT, "examples/errors/vmc3.toml")).read()
    errors = errors.replace("position = [-400, -200, 0, 200, 400]", "position = [-4000, -2000, 0, 2000, 4000]")
    files = {"machine.toml": machine, "errors.toml": errors,
             "tools.tbl": "".join(f"T{n} P{n} Z{50 + n * 0.5:.1f} D6 ;tool {n}\n" for n in range(1, 400))}
    for name, text in files.items():
        with open(os.path.join(tmp, name), "w") as f:
            f.write(text)


def classify(code, message, program, tools):
    if code == 0:
        return "corrected"
    for name, pattern in CLASSES:
        if re.search(pattern, message):
            return name
    # read as RS274/NGC and refused: does LinuxCNC's own interpreter run it?
    if "LinuxCNC" in message and rs274_refuses(program, tools):
        return RS274
    return "failed"


def rs274_refuses(program, tools):
    try:
        p = subprocess.run(["rs274", "-t", tools, "-g", os.path.basename(program)], cwd=os.path.dirname(program),
                           stdin=subprocess.DEVNULL, capture_output=True, timeout=300)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return p.returncode != 0


def run(target, trueaxis, dialect):
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        setup(tmp)
        for repo, _, path in MANIFEST:
            program = os.path.join(target, repo, path)
            outcome = []
            for tools in (True, False):
                cmd = [trueaxis, "nc", "--machine", f"{tmp}/machine.toml", "--errors", f"{tmp}/errors.toml", program,
                       "--out", f"{tmp}/out.nc", "--json"]
                if tools:
                    cmd += ["--tool-table", f"{tmp}/tools.tbl"]
                if dialect:
                    cmd += ["--dialect", dialect]
                p = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
                message = p.stderr.strip().splitlines()[-1] if p.returncode else json.loads(p.stdout).get("dialect", "")
                outcome.append((classify(p.returncode, message, program, f"{tmp}/tools.tbl"), message))
            rows.append((repo, path, outcome))
    for k, label in ((0, "with a tool table"), (1, "without a tool table")):
        counts = {}
        for _, _, o in rows:
            counts[o[k][0]] = counts.get(o[k][0], 0) + 1
        print(f"{label}: " + ", ".join(f"{n} {c}" for c, n in sorted(counts.items(), key=lambda x: -x[1])) + f" (of {len(rows)})")
    print()
    for repo, path, o in rows:
        if o[0][0] != "corrected" or o[1][0] != "corrected":
            print(f"- {repo} {path}: {o[0][0]}: {o[0][1][:240]}")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("what", choices=["fetch", "run"])
    ap.add_argument("dir")
    ap.add_argument("--trueaxis", default=os.path.join(ROOT, "target/release/trueaxis"))
    ap.add_argument("--dialect")
    a = ap.parse_args()
    fetch(a.dir) if a.what == "fetch" else run(a.dir, a.trueaxis, a.dialect)


if __name__ == "__main__":
    sys.exit(main())
