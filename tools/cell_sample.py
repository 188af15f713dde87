#!/usr/bin/env python3
"""Estimates a table design's accuracy over its whole range without building the whole table.

A table interpolates inside one cell of its linear axes (normal force, speed, wetness, a/b, p_ref) from that
cell's corner nodes only, over the complete creepage axes (docs/model.md §12.3). So a table whose linear
axes are cut to the two nodes of one cell, its creepage axes unchanged, gives inside that cell exactly what
the whole table gives there: the same nodes, the same splines (also the one-sided slopes next to unresolved
cells along ξ̂ and η̂), the same unresolved and near-unconverged flags. This tool draws CELLS such cells at
random, the way `wheelrail table verify` draws its samples (even cells: the cell of a point uniform over the
ranges; odd cells: a cell uniform over the cell indices, like verify's cell midpoints), builds each one
(`table build --resume` into DIR/cell-K: an interrupted run resumes where it stopped), verifies it (`table
verify`, SAMPLES points inside the cell, seed K + 1, into DIR/cell-K.SAMPLES.json and .csv; a cell rebuilt for
other parameters or axes is verified anew) and pools the samples: |dF|/F_N and T_max errors as mode
auto serves them (unresolved cells and points next to unconverged nodes are solved exactly: error 0) and as
the table alone gives them, p99 and max, and a line per cell.

A cell of a table by similarity costs 16 creepage cubes (2 nodes on each of V, w, a/b, p_ref), e.g. 16 ×
3192 exact solves on the whole-range axes (tools/whole-range-axes.toml): ≈ 5 CPU-minutes for most cells,
≈ 40 at the hot, fast corner (V·s 65–158 m/s, p0 ≥ 1.7 GPa).

Usage: tools/cell_sample.py --axes FILE --cells N --out DIR [--samples S] [--seed K] [--params FILE]
                            [--wheelrail PATH]
Prints the pooled report (and writes it to DIR/report.json); exit status 0 whatever the errors.
"""

import argparse
import csv
import json
import math
import os
import random
import subprocess
import sys
import time
import tomllib

LINEAR = ["normal_force", "speed", "wetness", "semi_axis_ratio", "reference_pressure"]


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    raise ValueError(f"cannot write {v!r} to TOML")


def toml_text(axes):
    out = []
    for name, spec in axes.items():
        out.append(f"[{name}]")
        out += [f"{k} = {toml_value(v)}" for k, v in spec.items()]
    return "\n".join(out) + "\n"


def draw_cells(axes, n, seed):
    """n cells: per linear axis with more than one point, the index of the cell's lower node."""
    rng = random.Random(seed)
    cells = []
    for k in range(n):
        cell = {}
        for name in LINEAR:
            points = axes[name]["points"]
            if len(points) < 2:
                continue
            if k % 2 == 0:
                x = points[0] + (points[-1] - points[0]) * rng.random()
                i = max(j for j in range(len(points) - 1) if points[j] <= x)
            else:
                i = rng.randrange(len(points) - 1)
            cell[name] = i
        cells.append(cell)
    return cells


def cell_axes(axes, cell):
    sub = {name: dict(spec) for name, spec in axes.items()}
    for name, i in cell.items():
        spec = sub[name]
        lo, hi = spec["points"][i], spec["points"][i + 1]
        spec["points"] = [lo, hi]
        # the cell is linear in √x from sqrt_from on: then from its own lower node
        if "sqrt_from" in spec:
            if lo >= spec["sqrt_from"]:
                spec["sqrt_from"] = lo
            else:
                del spec["sqrt_from"]
    return sub


def run(cmd, **kw):
    return subprocess.run(cmd, check=False, text=True, capture_output=True, **kw)


def stats(values):
    if not values:
        return {"p99": None, "max": None, "n": 0}
    v = sorted(values)
    # nearest rank, as `table verify`
    rank = max(1, math.ceil(0.99 * len(v)))
    return {"p99": v[rank - 1], "max": v[-1], "n": len(v)}


def number(x, spec):
    """x formatted by spec, or "-" where there is no sample."""
    return "-" if x is None else format(x, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--axes", required=True)
    ap.add_argument("--cells", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--params")
    ap.add_argument("--wheelrail", default="target/release/wheelrail")
    a = ap.parse_args()
    with open(a.axes, "rb") as f:
        axes = tomllib.load(f)
    # (an axis absent from the file would take its built-in points, which this tool does not know)
    missing = [n for n in LINEAR if "points" not in axes.get(n, {})]
    if missing:
        sys.exit(f"cell_sample: give the points of {', '.join(missing)} in the axes file")
    os.makedirs(a.out, exist_ok=True)
    pooled = {"auto": {"force": [], "max_temperature": []}, "table": {"force": [], "max_temperature": []}}
    lines = []
    for k, cell in enumerate(draw_cells(axes, a.cells, a.seed)):
        sub = cell_axes(axes, cell)
        where = ", ".join(f"{n} {sub[n]['points'][0]:.4g}–{sub[n]['points'][1]:.4g}" for n in cell)
        path = os.path.join(a.out, f"cell-{k}")
        with open(path + ".toml", "w") as f:
            f.write(toml_text(sub))
        build = [a.wheelrail, "table", "build", "--axes", path + ".toml", "--out", path, "--resume"]
        if a.params:
            build += ["--params", a.params]
        t0 = time.time()
        b = run(build)
        if b.returncode != 0:
            sys.exit(f"cell_sample: the build of cell {k} failed: {b.stderr}")
        built = time.time() - t0
        # the verification of this very build with this many samples (a rebuilt cell is verified anew)
        report, samples = f"{path}.{a.samples}.json", f"{path}.{a.samples}.csv"
        if "already holds this build" not in b.stderr:
            for f in (report, samples):
                if os.path.exists(f):
                    os.remove(f)
        if not os.path.exists(report):
            v = run([a.wheelrail, "table", "verify", path, "--samples", str(a.samples), "--seed", str(k + 1),
                     "--json", "--csv", samples])
            if v.returncode not in (0, 1):
                sys.exit(f"cell_sample: the verification of cell {k} failed: {v.stderr}")
            with open(report, "w") as f:
                f.write(v.stdout)
        cell_errors = {"force": [], "max_temperature": []}
        with open(samples) as f:
            for row in csv.DictReader(f):
                served = float(row["table_resolved"]) == 1.0 and float(row["table_converged"]) == 1.0
                for o in ("force", "max_temperature"):
                    e = float(row[o + "_error"])
                    pooled["table"][o].append(e)
                    pooled["auto"][o].append(e if served else 0.0)
                    cell_errors[o].append(e if served else 0.0)
        f_s, t_s = stats(cell_errors["force"]), stats(cell_errors["max_temperature"])
        line = (f"cell {k:3d} ({where}): {f_s['n']} samples, |dF|/F_N p99 {number(f_s['p99'], '.2e')} max "
                f"{number(f_s['max'], '.2e')}, T_max p99 {number(t_s['p99'], '.2f')} K max "
                f"{number(t_s['max'], '.2f')} K (as mode auto serves them)")
        lines.append(line)
        print(f"{line}; build {built:.0f} s", flush=True)
    result = {
        "cells": a.cells,
        "samples_per_cell": a.samples,
        "auto": {o: stats(v) for o, v in pooled["auto"].items()},
        "table": {o: stats(v) for o, v in pooled["table"].items()},
        "lines": lines,
    }
    with open(os.path.join(a.out, "report.json"), "w") as f:
        json.dump(result, f, indent=1)
    for mode in ("auto", "table"):
        f, t = result[mode]["force"], result[mode]["max_temperature"]
        print(f"pooled ({mode}): |dF|/F_N p99 {number(f['p99'], '.2e')} max {number(f['max'], '.2e')}; "
              f"T_max p99 {number(t['p99'], '.2f')} K max {number(t['max'], '.2f')} K "
              f"({f['n']} samples in {a.cells} cells)")


if __name__ == "__main__":
    main()
