"""What every bench module shares: the fastest of timed runs, the ratio in words, and the list
of rows that tells each row on standard error as it is measured."""

from __future__ import annotations

import sys
import time

REPEATS = 5


def best(run, repeats=REPEATS, calls=1):
    """The fastest of `repeats` timed runs (after one warm-up) of `calls` calls, per call."""
    run()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            run()
        times.append((time.perf_counter() - start) / calls)
    return min(times)


def faster(ours, theirs, goal=None):
    ratio = f"{theirs / ours:.2f}x faster" if theirs >= ours else f"{ours / theirs:.2f}x slower"
    return ratio + (f" (goal {goal})" if goal else "")


class Rows(list):
    """The rows, each also told on standard error as it is measured (the run takes minutes)."""

    def append(self, row) -> None:
        super().append(row)
        print(f"  {row[0]}: {row[1]:.3g} against {row[3]:.3g}", file=sys.stderr, flush=True)
