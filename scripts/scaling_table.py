#!/usr/bin/env python3
"""How the cost of a profile grows (issue 24 point 5): the Markdown tables of
docs/PERFORMANCE.md from vts-bench's JSON output.

    build/bin/vts-bench --benchmark_filter='BM_(Columns|Triangles)/' \\
        --benchmark_repetitions=3 --benchmark_out=scaling.json --benchmark_out_format=json
    /usr/bin/python3 scripts/scaling_table.py [--cpu] scaling.json

--cpu: profiles per second of CPU time instead of wall time (one-thread
benchmarks on a shared machine, where wall time includes other work).

For each source, profiles/s at every size and the exponent b of the
least-squares line through (log size, log time per profile): the time per
profile grows as size^b, so a size k times larger costs about k^b times as
much. Where the growth is no power law (a fixed cost per profile beside one
that grows), the exponents between neighbouring sizes show where it bends.
The median of the repetitions is used when there are several.
"""

import json
import math
import re
import statistics
import sys
from collections import defaultdict

NAME = re.compile(r"^BM_(Columns|Triangles)/([^/]+)/([^/]+)")


def rates(benchmarks, cpu):
    """{(kind, source): {size: [profiles/s, ...]}}, sizes from the counters.
    With cpu, profiles per second of the benchmark thread's CPU time (what a
    one-thread run gets from an idle core; steadier on a shared machine)."""
    runs = defaultdict(lambda: defaultdict(list))
    for b in benchmarks:
        if b.get("run_type", "iteration") != "iteration" or "items_per_second" not in b:
            continue
        m = NAME.match(b["name"])
        if not m:
            continue
        kind, source, _ = m.groups()
        size = b["columns"] if kind == "Columns" else b["triangles"]
        rate = b["items_per_second"]
        if cpu:
            rate *= b["real_time"] / b["cpu_time"]
        runs[(kind, source)][int(round(size))].append(rate)
    return runs


def fit(points):
    """Least squares of log(time per profile) on log(size): (b, c), time = c * size^b."""
    xs = [math.log(s) for s, _ in points]
    ys = [math.log(1.0 / r) for _, r in points]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    return b, math.exp(my - b * mx)


def table(runs, kind, label):
    sources = sorted(s for k, s in runs if k == kind)
    if not sources:
        return ""
    sizes = sorted({size for (k, _), by in runs.items() if k == kind for size in by})
    lines = [f"| {label} | " + " | ".join(f"{s} (profiles/s)" for s in sources) + " |",
             "|---|" + "---|" * len(sources)]
    for size in sizes:
        cells = []
        for s in sources:
            r = runs[(kind, s)].get(size)
            cells.append(f"{statistics.median(r):,.0f}" if r else "")
        lines.append(f"| {size:,} | " + " | ".join(cells) + " |")
    exps, laws = [], []
    for s in sources:
        pts = [(size, statistics.median(r)) for size, r in sorted(runs[(kind, s)].items())]
        if len(pts) < 2:
            exps.append("")
            laws.append("")
            continue
        b, c = fit(pts)
        exps.append(f"**{b:.2f}**")
        laws.append(f"{c * 1e6:.3g} µs x {label.split()[0]}^{b:.2f}")
    lines.append("| exponent b (time per profile ~ size^b) | " + " | ".join(exps) + " |")
    local = []
    for s in sources:
        pts = [(size, statistics.median(r)) for size, r in sorted(runs[(kind, s)].items())]
        local.append(", ".join(f"{fit([a, b])[0]:.2f}" for a, b in zip(pts, pts[1:])))
    lines.append("| b between neighbouring sizes | " + " | ".join(local) + " |")
    lines.append("| fitted time per profile | " + " | ".join(laws) + " |")
    return "\n".join(lines) + "\n"


def main(argv):
    cpu = "--cpu" in argv
    argv = [a for a in argv if a != "--cpu"]
    if len(argv) != 2:
        sys.exit(__doc__)
    with open(argv[1]) as f:
        runs = rates(json.load(f)["benchmarks"], cpu)
    if not runs:
        sys.exit(f"{argv[1]}: no BM_Columns or BM_Triangles results")
    print(table(runs, "Columns", "columns"))
    print(table(runs, "Triangles", "triangles"))


if __name__ == "__main__":
    main(sys.argv)
