#!/usr/bin/env python3
"""A Markdown table of `splinegpu bench --json` lines: per workload and path, the best of the
repetitions (min_seconds), and its useful bytes per second as a share of the same workload's
memset (host) and gpu-memset (device) measured in the same run.

    python3 scripts/bench_summary.py bench.jsonl
"""
import json
import sys


def main(path):
    rows = []
    with open(path) as lines:
        for line in lines:
            line = line.strip()
            if line.startswith("{"):
                rows.append(json.loads(line))
    if not rows:
        print("(no measurements)")
        return

    def rate(row):
        seconds = row["min_seconds"]
        return row["bytes"] / seconds if seconds > 0 else float("nan")

    reference = {}
    for row in rows:
        if row["path"] in ("memset", "gpu-memset"):
            reference[(row["workload"], row["path"])] = rate(row)
    print("| workload | path | float | min ms | median ms | samples | GB/s (min) | % memset | % gpu-memset |")
    print("|---|---|---|---:|---:|---:|---:|---:|---:|")
    for row in rows:
        share = []
        for ref in ("memset", "gpu-memset"):
            base = reference.get((row["workload"], ref))
            if base and row["bytes"] and row["path"] not in ("memset",):
                share.append(f"{100 * rate(row) / base:.1f}")
            else:
                share.append("")
        print(
            f"| {row['workload']} | {row['path']} | {row.get('float', '')} "
            f"| {1e3 * row['min_seconds']:.2f} | {1e3 * row['seconds']:.2f} | {row['samples']} "
            f"| {rate(row) / 1e9:.2f} | {share[0]} | {share[1]} |"
        )


if __name__ == "__main__":
    main(sys.argv[1])
