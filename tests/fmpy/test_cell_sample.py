"""tools/cell_sample.py: a table cut to one cell of its linear axes gives inside that cell exactly what the
whole table gives there, so verifying random cells estimates a design's accuracy without building it.

Small axes by similarity on a 6 x 6 grid, with more than two nodes on every linear axis (speed in sqrt(V)
from its middle node on, a/b and p_ref logarithmic): the tool draws cells, builds and verifies each; then the
whole table is built, and at every verified sample point of each cell (points the exact solver saw: carried
to other loads and speeds by similarity) `wheelrail point --mode table` by the cell's table and by the whole
table agree to the last bit.
"""

import csv
import json
import pathlib
import subprocess
import sys

from conftest import ROOT, cli

# the creepage axes of the small fixture table, linear axes of three nodes each (one F_N: by similarity)
CREEPAGES = (ROOT / "tests" / "fixtures" / "small-axes.toml").read_text().split("[normal_force]")[0]
AXES = CREEPAGES + """
[normal_force]
points = [100e3]
[speed]
similarity = true
sqrt_from = 20.0
points = [10.0, 20.0, 40.0]
[wetness]
points = [0.0, 0.1, 1.0]
[semi_axis_ratio]
interpolation = "log"
points = [0.45, 0.56, 0.7]
[reference_pressure]
interpolation = "log"
points = [0.6e9, 0.75e9, 0.9e9]
"""

OUTPUTS = ["force_x", "force_y", "spin_moment", "traction_coefficient", "max_temperature", "fluid_load_fraction"]


def point_by_table(table, params, row):
    flags = ["creepage_x", "creepage_y", "spin", "normal_force", "speed", "wetness"]
    args = [cli(), "point", "--json", "--params", str(params), "--table", str(table), "--mode", "table"]
    for f in flags:
        args += [f"--{f.replace('_', '-')}", row[f]]
    args += ["--semi-axes", f"{row['semi_axis_a']},{row['semi_axis_b']}"]
    return json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)


def test_a_table_cut_to_one_cell_evaluates_as_the_whole_table_inside_it(tmp_path):
    axes = tmp_path / "axes.toml"
    axes.write_text(AXES)
    params = tmp_path / "params.toml"
    params.write_text("[grid]\nnx = 6\nny = 6\n")
    out = tmp_path / "cells"
    tool = [sys.executable, str(ROOT / "tools" / "cell_sample.py"), "--axes", str(axes), "--cells", "4",
            "--samples", "6", "--out", str(out), "--params", str(params), "--wheelrail", cli()]
    subprocess.run(tool, check=True, capture_output=True, text=True)
    report = json.loads((out / "report.json").read_text())
    assert report["auto"]["force"]["n"] == 4 * 6 and len(report["lines"]) == 4
    whole = tmp_path / "whole"
    subprocess.run([cli(), "table", "build", "--params", str(params), "--axes", str(axes), "--out", str(whole)],
                   check=True, capture_output=True)
    cut = set()
    for k in range(4):
        cell = out / f"cell-{k}"
        sidecar = json.loads((cell / "table.json").read_text())
        # every linear axis with several nodes cut to two of them
        counts = {a["name"]: len(a["points"]) for a in sidecar["axes"]}
        assert all(counts[n] == 2 for n in ["speed", "wetness", "semi_axis_ratio", "reference_pressure"])
        cut.add(tuple(tuple(a["points"]) for a in sidecar["axes"]))
        with open(f"{cell}.6.csv") as f:
            rows = list(csv.DictReader(f))
        assert len(rows) == 6
        for row in rows:
            by_cell, by_whole = point_by_table(cell, params, row), point_by_table(whole, params, row)
            for o in OUTPUTS:
                assert by_cell[o] == by_whole[o], (k, row, o, by_cell[o], by_whole[o])
            # the tool's errors are those of this very evaluation against the exact solver's
            assert abs(by_cell["force_x"] - float(row["table_force_x"])) <= 1e-9 * abs(by_cell["force_x"]) + 1e-9
    # the draw reaches several cells (a fixed seed: deterministic)
    assert len(cut) >= 2
    # a second run builds nothing (the builds resume) and reports the same
    again = subprocess.run(tool, check=True, capture_output=True, text=True).stdout
    assert json.loads((out / "report.json").read_text()) == report, again
    # cells rebuilt for other parameters are verified anew, not reported from the first run's samples
    params.write_text("[grid]\nnx = 5\nny = 5\n")
    subprocess.run(tool, check=True, capture_output=True, text=True)
    assert json.loads((out / "report.json").read_text())["auto"] != report["auto"]
    assert json.loads((out / "cell-0" / "table.json").read_text())["params"]["grid"]["nx"] == 5
