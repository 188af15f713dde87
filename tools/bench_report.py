#!/usr/bin/env python3
"""Report of `make bench`: every criterion result with its ratio to the Polach formula, the scaling exponent
of the exact solver with the grid, and the memory per FMU instance (standard library only).

Reads target/criterion/**/new/{benchmark,estimates}.json and target/bench/memory.json; prints a table and
writes target/bench/report.md.
"""

import json
import math
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
CRITERION = ROOT / "target" / "criterion"
OUT = ROOT / "target" / "bench"
# Polach through `solve` (Hertz, Kalker's coefficients and the formula per call, as every other entry) and
# the bare formula with the contact precomputed
POLACH = "point/polach_1pct_30mps"
POLACH_FORMULA = "point/polach_formula_only_1pct_30mps"


def results():
    """{full_id: mean time [ns]} of every criterion benchmark that has run."""
    found = {}
    for bench in CRITERION.glob("**/new/benchmark.json"):
        meta = json.loads(bench.read_text())
        est = json.loads((bench.parent / "estimates.json").read_text())
        found[meta["full_id"]] = est["mean"]["point_estimate"]
    return found


def human(ns):
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


def scaling(found):
    """Least-squares slope of log(time) against log(active cells) of the grid_scaling group."""
    pts = sorted(
        (int(k.rsplit("/", 1)[1]), v) for k, v in found.items() if k.startswith("grid_scaling/exact_dry_cells/")
    )
    if len(pts) < 2:
        return None, pts
    xs = [math.log(c) for c, _ in pts]
    ys = [math.log(t) for _, t in pts]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return slope, pts


def main():
    found = results()
    if not found:
        sys.exit("no criterion results under target/criterion: run `make bench` first")
    def ratio(key, ref):
        if ref not in found:
            return "n/a"
        r = found[key] / found[ref]
        return f"{r:,.0f}×" if r >= 100 else f"{r:.3g}×"

    lines = ["| benchmark | mean time | ratio to Polach via solve | ratio to the bare Polach formula |",
             "|---|---:|---:|---:|"]
    for key in sorted(found):
        lines.append(f"| {key} | {human(found[key])} | {ratio(key, POLACH)} | {ratio(key, POLACH_FORMULA)} |")
    slope, pts = scaling(found)
    if slope is not None:
        lines += ["", f"Exact dry point against the grid: time ∝ cells^{slope:.2f} "
                      f"({', '.join(f'{c} cells {human(t)}' for c, t in pts)})."]
    memory = OUT / "memory.json"
    if memory.exists():
        m = json.loads(memory.read_text())
        lines += ["", "| FMU instance | bytes kept after a step | peak working bytes in a step |", "|---|---:|---:|"]
        for row in m["instances"]:
            lines.append(f"| {row['case']} | {row['kept_bytes']:,.0f} | {row['step_peak_bytes']:,} |")
    text = "\n".join(lines) + "\n"
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "report.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
