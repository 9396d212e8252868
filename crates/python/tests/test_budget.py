"""The error budget (Zhu 2008 appendices B and C) against the command line: `BudgetProblem.analyse`,
`BudgetProblem.allocate` and `budget_configurations` call the library entry points `trueaxis budget`
calls, so the documents and the files they write are the command's (exact); an allocation analysed
again meets its target; the configuration study reports its progress; bad input raises the
command's messages."""

import pickle

import numpy as np
import pytest

import trueaxis as ta
from conftest import ROOT, assert_same, cli_error, cli_json, pandas

EX = ROOT / "examples"
VMC3 = EX / "machines" / "vmc3.toml"
C600U = EX / "machines" / "c600u.toml"


def test_analyse_equals_the_cli_with_its_tables(tmp_path):
    c600u = ta.Machine.from_file(C600U)
    a, b = tmp_path / "cli", tmp_path / "py"
    expected = cli_json("budget", "analyse", "--machine", C600U, "--grid", "3", "--rotary", "A=45",
                        "--out", a.with_suffix(".csv"), "--sensitivity", a.with_suffix(".s.csv"))
    problem = ta.BudgetProblem(c600u, grid=3, rotary={"A": 45})
    assert problem.sets == ["work volume"] and problem.poses[0].shape == (27, 5) and np.all(problem.poses[0][:, 3] == 45)
    got = problem.analyse(out=b.with_suffix(".csv"), sensitivity=b.with_suffix(".s.csv"))
    assert isinstance(got, ta.BudgetAnalysis) and got.to_dict() == expected
    for suffix in (".csv", ".s.csv"):
        assert a.with_suffix(suffix).read_bytes() == b.with_suffix(suffix).read_bytes()
    assert got.rss_max.tolist() == [expected["sets"][0]["rss_um"]["max"]]
    # two part sizes, a budget's tolerances: the shares of the axes add up to 100 % in each set
    vmc3 = ta.Machine.from_file(VMC3)
    expected = cli_json("budget", "analyse", "--machine", VMC3, "--part", "100", "--part", "600x400x300", "--linear-um", "3")
    problem = ta.BudgetProblem(vmc3, parts=[100, (600, 400, 300)], linear_um=3)
    got = problem.analyse()
    assert got == expected and len(got.sets) == 2 and problem.sets == ["100x100x100", "600x400x300"]
    assert pickle.loads(pickle.dumps(problem)).analyse() == got
    pandas()
    shares = got.to_dataframe("by_axis").groupby("set")["share_percent"].sum()
    assert np.allclose(shares.to_numpy(), 100.0, atol=1e-9)
    components = got.to_dataframe()
    assert len(components) == 2 * len(expected["sets"][0]["components"]) and set(components["set"]) == {"100x100x100", "600x400x300"}
    # the Abbe effect: the larger part's error is larger
    assert got.rss_max[1] > got.rss_max[0]


def test_allocate_equals_the_cli_and_the_analysis_meets_the_target(tmp_path):
    vmc3 = ta.Machine.from_file(VMC3)
    a, b = tmp_path / "cli.toml", tmp_path / "py.toml"
    expected = cli_json("budget", "allocate", "--machine", VMC3, "--part", "300x200x150", "--part-nodes", "3",
                        "--target-um", "10", "--out", a)
    got = ta.BudgetProblem(vmc3, parts=[(300, 200, 150)], part_nodes=3).allocate(target_um=10, out=b)
    assert isinstance(got, ta.BudgetAllocation)
    assert_same(got.to_dict(), expected, rel=0)
    assert a.read_bytes() == b.read_bytes()
    assert got.tolerances.shape == (len(got.names),) and (got.tolerances > 0).all()
    # the allocated budget analysed again: its largest root-sum-square 3D error is the target
    check = ta.BudgetProblem(vmc3, budget=b, parts=[(300, 200, 150)], part_nodes=3).analyse()
    assert check.rss_max[0] == pytest.approx(10.0, rel=1e-6)
    # worst case, per direction
    expected = cli_json("budget", "allocate", "--machine", C600U, "--grid", "3", "--stack", "worst-case", "--target-xyz", "15,15,10")
    got = ta.BudgetProblem(ta.Machine.from_file(C600U), grid=3).allocate(stack="worst-case", target_xyz=(15, 15, 10))
    assert_same(got.to_dict(), expected, rel=0)
    assert all(v <= t * (1 + 1e-6) for v, t in zip(got.achieved_um, (15, 15, 10)))


def test_configurations_equal_the_cli_with_progress():
    expected = cli_json("budget", "configurations", "--part", "200x150x100", "--tool-length", "150")
    calls = []
    got = ta.budget_configurations(part=(200, 150, 100), tool_length=150, progress=lambda done, total: calls.append((done, total)))
    assert isinstance(got, ta.BudgetConfigurations) and got.to_dict() == expected
    assert len(calls) == 288 and sorted(d for d, _ in calls) == list(range(1, 289)) and {t for _, t in calls} == {288}
    assert got.counts.five_degrees_of_freedom == 288 and len(got["ranking"]) == 288
    rms = got.column("ranking", "rss_rms_um")
    assert np.all(np.diff(rms) >= 0)  # ranked, smallest first

    def stop(done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        ta.budget_configurations(part=50, progress=stop)


def test_budget_refusals_carry_the_cli_messages():
    vmc3 = ta.Machine.from_file(VMC3)
    for kwargs, args in [
        (dict(rotary={"Q": 1}), ["--rotary", "Q=1"]),
        (dict(linear_um=0), ["--linear-um", "0"]),
        (dict(grid=1), ["--grid", "1"]),
        (dict(parts=[100], part_nodes=1), ["--part", "100", "--part-nodes", "1"]),
    ]:
        code, message = cli_error("budget", "analyse", "--machine", VMC3, *args)
        with pytest.raises(ta.InputError) as e:
            ta.BudgetProblem(vmc3, **kwargs)
        assert code == 2 and str(e.value) == message, (kwargs, message)
    with pytest.raises(ta.InputError, match="give one of target_um"):
        ta.BudgetProblem(vmc3).allocate()
    with pytest.raises(ta.InputError, match="allocate takes one pose set"):
        ta.BudgetProblem(vmc3, parts=[100, 200]).allocate(target_um=10)
    with pytest.raises(ta.InputError, match="poses, parts and grid: give one of them"):
        ta.BudgetProblem(vmc3, parts=[100], grid=3)
    code, message = cli_error("budget", "configurations", "--tool-length", "0")
    with pytest.raises(ta.InputError) as e:
        ta.budget_configurations(tool_length=0)
    assert code == 2 and str(e.value) == message


def test_poses_as_an_array_equal_the_pose_file():
    vmc3 = ta.Machine.from_file(VMC3)
    path = EX / "poses" / "vmc3.csv"
    expected = cli_json("budget", "analyse", "--machine", VMC3, "--poses", path)
    from_file = ta.BudgetProblem(vmc3, poses=path).analyse()
    assert from_file == expected
    poses = vmc3.read_poses(path)
    got = ta.BudgetProblem(vmc3, poses=poses).analyse()
    doc, ref = got.to_dict(), expected
    assert doc["sets"][0].pop("label") == "poses" and ref["sets"][0].pop("label") == str(path)
    assert doc == ref
    far = poses.copy()
    far[1, 0] = 1e4
    with pytest.raises(ta.InputError, match=r"poses: pose 2: axis X at 10000 mm is outside its range"):
        ta.BudgetProblem(vmc3, poses=far)
    with pytest.raises(ta.InputError, match="poses: expected a 2-dimensional array"):
        ta.BudgetProblem(vmc3, poses=[1.0, 2.0, 3.0])


def test_miniaturisation_equals_the_cli():
    expected = cli_json("budget", "miniaturisation", "--sizes", "10,300")
    got = ta.budget_miniaturisation(sizes=[10, 300])
    assert isinstance(got, ta.BudgetMiniaturisation) and got == expected
    assert got.size_mm.tolist() == [10.0, 300.0]
    # the target of the allocation is the relative accuracy (1e-4) times the part size, in um
    assert [s["allocation"]["target_um"] for s in got["sizes"]] == pytest.approx([1.0, 30.0], rel=1e-12)
    code, message = cli_error("budget", "miniaturisation", "--linear-um", "0")
    with pytest.raises(ta.InputError) as e:
        ta.budget_miniaturisation(linear_um=0)
    assert code == 2 and str(e.value) == message


def test_rss_at_equals_the_analysis_with_the_rotary_axes_of_the_set():
    # at the poses of the set itself, the stack-up of the analysis
    vmc3 = ta.BudgetProblem(ta.Machine.from_file(VMC3), grid=3)
    per_pose = vmc3.analyse()["sets"][0]["per_pose"]
    assert vmc3.rss_at(vmc3.poses[0]) == pytest.approx([p["rss_um"]["total"] for p in per_pose], rel=1e-12)
    # poses given with A at 0 are evaluated with A where the set has it (45 deg)
    c600u = ta.BudgetProblem(ta.Machine.from_file(C600U), grid=3, rotary={"A": 45})
    poses = c600u.poses[0].copy()
    poses[:, 3] = 0.0
    expected = [p["rss_um"]["total"] for p in c600u.analyse()["sets"][0]["per_pose"]]
    assert c600u.rss_at(poses) == pytest.approx(expected, rel=1e-12)
    with pytest.raises(ta.InputError, match="columns"):
        c600u.rss_at(np.zeros((2, 3)))
