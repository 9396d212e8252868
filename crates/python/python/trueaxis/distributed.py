"""Monte Carlo budgets and optimal designs on a distributed engine (docs/python.md).

Works with any executor whose ``submit(fn, *args)`` returns futures with ``.result()``:
``dask.distributed.Client`` (local or a cluster), ``concurrent.futures`` executors, or a Ray
wrapper. The plan travels to the workers once (``Client.scatter`` when the executor has it).

The result equals ``plan.run()`` in one process bit for bit for the same seed: each chunk draws
from its own counter-based random streams, and the driver feeds the sequences of each stage in
order to a ``BudgetRun``, which stops each stage at the sequence one process stops at. Sequences
computed beyond that point (``lookahead``) are discarded.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Tuple

from ._native import Candidates, UncertaintyPlan
from .results import OptimalDesign, UncertaintyBudget


def _run_chunk(plan: UncertaintyPlan, stage: int, chunk: Tuple[int, int, int]):
    return plan.run_chunk(stage, chunk)


def _exchange_starts(candidates: Candidates, count: int, start: int, stop: int, criterion: str, seed: int):
    return candidates.exchange_starts(count, start, stop, criterion=criterion, seed=seed)


def _submit(executor: Any, fn, *args):
    """``executor.submit``; on Dask with a fresh key per call (``pure=False``): two runs of the same
    plan submit the same arguments, and a key reused after a cancellation would wait forever."""
    if hasattr(executor, "scatter"):
        return executor.submit(fn, *args, pure=False)
    return executor.submit(fn, *args)


def _share(executor: Any, obj: Any) -> Any:
    """The object once on every worker when the executor can scatter (Dask), else itself."""
    scatter = getattr(executor, "scatter", None)
    return scatter(obj, broadcast=True, hash=False) if scatter is not None else obj


def run_uncertainty(
    plan: UncertaintyPlan,
    executor: Any,
    *,
    blocks_per_chunk: Optional[int] = None,
    lookahead: int = 4,
    poses=None,
    tool_point=None,
    work_point=None,
    frame: str = "workpiece",
) -> UncertaintyBudget:
    """The uncertainty budget of ``plan`` computed on ``executor``: the same ``UncertaintyBudget``
    as ``plan.run()``.

    Every stage (each source alone, then all together) runs at the same time; each keeps up to
    ``lookahead`` sequences in flight, each sequence cut into chunks of ``blocks_per_chunk`` blocks
    of ``trueaxis.BLOCK`` trials (default: one chunk per sequence). ``poses`` (N, axes) in mm and
    deg adds the uncertainty of the predicted dx dy dz there (a plan from a campaign).
    """
    if lookahead < 1:
        raise ValueError("lookahead must be at least 1")
    shared = _share(executor, plan)
    state = plan.start()
    stages = plan.stages
    # per stage: the next sequence to submit, and the futures of the submitted ones by sequence
    next_submit = [0] * stages
    in_flight: List[Dict[int, list]] = [dict() for _ in range(stages)]

    def submit(stage: int) -> None:
        first = state.next_sequence(stage)
        if first is None:
            return
        limit = min(first + lookahead, plan.max_sequences)
        while next_submit[stage] < limit:
            h = next_submit[stage]
            chunks = plan.chunks(h, blocks_per_chunk)
            in_flight[stage][h] = [(c, _submit(executor, _run_chunk, shared, stage, c)) for c in chunks]
            next_submit[stage] += 1

    for stage in range(stages):
        submit(stage)
    while not state.done:
        for stage in range(stages):
            h = state.next_sequence(stage)
            if h is None:
                continue
            pieces = in_flight[stage].pop(h)
            complete = state.push(stage, [(c, f.result()) for c, f in pieces])
            if complete:
                for rest in in_flight[stage].values():
                    for _, f in rest:
                        cancel = getattr(f, "cancel", None)
                        if cancel is not None:
                            cancel()
                in_flight[stage].clear()
            else:
                submit(stage)
    return state.finish(poses=poses, tool_point=tool_point, work_point=work_point, frame=frame)


def optimal_design(
    candidates: Candidates,
    executor: Any,
    count: int,
    *,
    criterion: str = "d",
    starts: int = 5,
    seed: int = 1,
    starts_per_chunk: int = 1,
) -> OptimalDesign:
    """The optimal design of ``count`` records from ``starts`` random starts of the exchange
    algorithm spread over ``executor`` in chunks of ``starts_per_chunk`` starts: the same
    ``OptimalDesign`` as ``candidates.exchange(count, criterion=..., starts=..., seed=...)``."""
    candidates.check(count, starts)
    shared = _share(executor, candidates)
    step = max(1, starts_per_chunk)
    futures = [
        _submit(executor, _exchange_starts, shared, count, a, min(a + step, starts), criterion, seed)
        for a in range(0, starts, step)
    ]
    outcomes = [o for f in futures for o in f.result()]
    return candidates.best_of(count, outcomes, criterion=criterion)
