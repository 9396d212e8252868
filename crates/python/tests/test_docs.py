"""The Python examples of docs/python.md run: every ```python block without a cluster, in order and
in one namespace, in a fresh directory that sees the repository's examples/ (the calls of the Dask
block are tested by test_dask.py, on smaller problems)."""

import os
import re
import warnings

import trueaxis as ta
from conftest import ROOT


def python_blocks(text):
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


def test_the_tour_runs(tmp_path):
    blocks = [b for b in python_blocks((ROOT / "docs" / "python.md").read_text()) if "dask" not in b]
    assert len(blocks) >= 2
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    here = os.getcwd()
    namespace = {}
    try:
        os.chdir(tmp_path)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ta.TrueaxisWarning)
            for block in blocks:
                exec(compile(block, "docs/python.md", "exec"), namespace)
    finally:
        os.chdir(here)
    # what the tour's names hold
    assert namespace["e"].shape == (5, 6)
    assert abs((namespace["e"][0, 0] - namespace["e"][1, 0]) + 3.0) < 1e-3  # the X backlash, moving + vs -
    assert (tmp_path / "comp_poses" / "corrections.csv").exists() and (tmp_path / "dz_model.toml").exists()
    assert len(namespace["piges"]["parameters"]) == 8
    assert namespace["drift"]["error"] == "dz"
