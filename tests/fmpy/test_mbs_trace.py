"""The MBS trace (tools/mbs_trace.py) through the FMU in fmpy: mode 0 (auto) against mode 2 (exact) at every
step of a part of the trace, with the contact geometry changing every step, to the table tolerance of
`wheelrail table verify` (|ΔF|/F_N p99 ≤ 0.01, max ≤ 0.03), and at auto's exact steps (the grid per contact)
to its accuracy against 30 × 30 (|ΔF|/F_N ≤ 0.01, T_max within 10 K). Whichever way auto evaluates a step (the
bundled table where it covers the geometry, the exact solver elsewhere) is recorded, the counts are
checked to add up and printed, and the steps on the table's own geometry must go by table."""

import math
import sys

import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import ROOT

sys.path.insert(0, str(ROOT / "tools"))
import mbs_trace  # noqa: E402

# every 5th row from 0.5 s to 9.5 s: straight track, both transitions, the curve and the wet patch; the steps
# follow each other 1 ms apart, so the geometry changes at every step from 1.5 s to 8.0 s of the trace
PART = range(500, 9501, 5)
STEP = 1e-3
INPUTS = mbs_trace.COLUMNS[1:]
OUTPUTS = ["force_longitudinal", "force_lateral", "max_temperature", "evaluation_mode", "contact_semi_axis_a",
           "contact_semi_axis_b", "peak_pressure"]
# |ΔF|/F_N accuracy targets of a table (those `wheelrail table verify` checks)
TARGET_P99, TARGET_MAX = 0.01, 0.03
# the accuracy of mode 0's grid per contact against 30 x 30: |ΔF|/F_N and |ΔT_max| [K] (docs/model.md §6.4)
FALLBACK_FORCE_ACCURACY, FALLBACK_TEMPERATURE_ACCURACY = 0.01, 10.0


@pytest.fixture(scope="module")
def rows():
    return mbs_trace.trace()


def column(rows, name):
    return np.array([r[mbs_trace.COLUMNS.index(name)] for r in rows])


def test_the_trace_is_deterministic_and_inside_the_documented_ranges(rows, tmp_path):
    assert rows == mbs_trace.trace()
    assert len(rows) == 10001
    np.testing.assert_allclose(np.diff(column(rows, "time")), STEP, rtol=1e-9)
    # the CSV reads back bit for bit
    mbs_trace.write_csv(tmp_path / "trace.csv", rows)
    lines = (tmp_path / "trace.csv").read_text().splitlines()
    assert lines[0].split(",") == mbs_trace.COLUMNS
    assert [[float(x) for x in line.split(",")] for line in lines[1:]] == rows
    # the tables' ranges, the stated input ranges
    xi, eta, phi = column(rows, "creepage_longitudinal"), column(rows, "creepage_lateral"), column(rows, "spin_creepage")
    assert np.all(np.abs(xi) <= 0.1) and np.all(np.abs(eta) <= 0.02) and np.all(np.abs(phi) <= 1.0)
    assert xi.min() == 0.0 and 0.0150 < xi.max() < 0.0152
    assert -0.0069 < eta.min() < -0.0067 and 0.0007 < eta.max() <= 0.0008
    assert 0.0507 < phi.min() < 0.0508 and 0.87 < phi.max() < 0.873
    fn, v, w = column(rows, "normal_force"), column(rows, "rolling_speed"), column(rows, "wetness")
    assert 75.9e3 < fn.min() < 76.1e3 and 138.8e3 < fn.max() < 139e3
    assert v.max() == 25.0 and v.min() == pytest.approx(20.0) and np.all(np.diff(v) < 0)
    wet = column(rows, "time")[w > 0.0]
    assert w.min() == 0.0 and w.max() == 1.0 and wet.max() - wet.min() == pytest.approx(1.5, abs=2e-3)
    # straight track on the default geometry exactly, curvatures changing every step in between
    a, b, t = column(rows, "curvature_longitudinal"), column(rows, "curvature_lateral"), column(rows, "time")
    straight = (t <= 1.5) | (t >= 8.0)
    assert np.all(a[straight] == 1.015) and np.all(b[straight] == 0.4215)
    inner = (t > 1.5) & (t < 8.0)
    assert np.all(np.diff(b[inner]) != 0.0) and np.all(np.diff(a[inner]) != 0.0)
    assert a.min() == pytest.approx(0.894, abs=5e-4) and b.max() == pytest.approx(7.0)
    assert np.all(column(rows, "semi_axis_a") == 0.0) and np.all(column(rows, "semi_axis_b") == 0.0)


def signals(rows):
    """Step j holds row PART[j] over [j STEP, (j + 1) STEP): two samples per step (value before and after each
    communication point), so fmpy applies the row's values exactly."""
    out = []
    for j, k in enumerate(PART):
        values = rows[k][1:]
        out.append((j * STEP, *values))
        out.append(((j + 1) * STEP, *values))
    return np.array(out, dtype=[("time", np.double)] + [(n, np.double) for n in INPUTS])


def run(fmu_path, rows, mode, **parameters):
    """The outputs of every step of PART in `mode` (the row at (j + 1) STEP holds step j's outputs)."""
    result = simulate_fmu(fmu_path, stop_time=len(PART) * STEP, output_interval=STEP, input=signals(rows),
                          start_values=dict(mode=mode, **parameters), output=OUTPUTS)
    out = []
    for j in range(len(PART)):
        at = result[np.isclose(result["time"], (j + 1) * STEP, rtol=0.0, atol=STEP * 1e-6)]
        assert len(at) >= 1, f"no output row at t = {(j + 1) * STEP}"
        out.append(at[-1])
    return np.array(out)


def test_auto_mode_along_the_trace_agrees_with_the_exact_solver(fmu_path, rows):
    auto, exact = run(fmu_path, rows, 0), run(fmu_path, rows, 2)
    assert np.all(exact["evaluation_mode"] == 2)
    by_table = int(np.sum(auto["evaluation_mode"] == 1))
    by_exact = int(np.sum(auto["evaluation_mode"] == 2))
    print(f"\nmode 0 along {len(PART)} steps of the MBS trace: {by_table} by table, {by_exact} by the exact solver")
    assert by_table + by_exact == len(PART), "evaluation_mode is neither 1 (table) nor 2 (exact) at some step"
    # the steps on the bundled table's own geometry (straight track) go by table, whatever else it covers
    part = [rows[k] for k in PART]
    default = (column(part, "curvature_longitudinal") == 1.015) & (column(part, "curvature_lateral") == 0.4215)
    assert np.all(auto["evaluation_mode"][default] == 1)
    assert by_table >= int(default.sum()) > 0

    fn = np.abs(column(part, "normal_force"))
    error = np.hypot(auto["force_longitudinal"] - exact["force_longitudinal"],
                     auto["force_lateral"] - exact["force_lateral"]) / fn
    p99 = np.sort(error)[math.ceil(0.99 * len(error)) - 1]  # nearest rank, as `wheelrail table verify`
    print(f"|dF|/F_N against mode 2: mean {error.mean():.2e}, p99 {p99:.2e}, max {error.max():.2e}")
    assert p99 <= TARGET_P99 and error.max() <= TARGET_MAX, (p99, error.max())
    # where auto solved exactly it did so on the grid per contact (grid_size 0): within the table's accuracy of
    # mode 2's 30 x 30
    solved = auto["evaluation_mode"] == 2
    temperature = np.abs(auto["max_temperature"] - exact["max_temperature"])
    print(f"at the {by_exact} exact steps: |dF|/F_N max {error[solved].max():.2e}, |dT_max| max "
          f"{temperature[solved].max():.1f} K")
    assert np.all(error[solved] <= FALLBACK_FORCE_ACCURACY)
    assert np.all(temperature[solved] <= FALLBACK_TEMPERATURE_ACCURACY)
    # with grid_size 30 set, auto's exact steps are the exact solver's results (warm starts from other states
    # aside)
    on_default = run(fmu_path, rows, 0, grid_size=30)
    same = np.hypot(on_default["force_longitudinal"] - exact["force_longitudinal"],
                    on_default["force_lateral"] - exact["force_lateral"]) / fn
    assert np.all(on_default["evaluation_mode"] == auto["evaluation_mode"])
    assert np.all(same[solved] <= 1e-6)
    # the contact both modes evaluated is the same and changed at every step of the curve part
    for name in ("contact_semi_axis_a", "contact_semi_axis_b", "peak_pressure"):
        np.testing.assert_allclose(auto[name], exact[name], rtol=1e-12, err_msg=name)
    a, b = exact["contact_semi_axis_a"], exact["contact_semi_axis_b"]
    t = column(part, "time")
    inner = (t > 1.5) & (t < 8.0)
    assert np.all(np.diff(a[inner]) != 0.0) and np.all(np.diff(b[inner]) != 0.0)
    # the contact ranges stated in tools/mbs_trace.py
    ratio, size, p0 = a / b, np.sqrt(a * b), exact["peak_pressure"]
    print(f"a/b {ratio.min():.3f} .. {ratio.max():.3f}, sqrt(ab) {1e3 * size.min():.2f} .. {1e3 * size.max():.2f} mm, "
          f"b >= {1e3 * b.min():.2f} mm, p0 {1e-9 * p0.min():.2f} .. {1e-9 * p0.max():.2f} GPa")
    assert ratio.min() == pytest.approx(0.558, abs=1e-3) and 3.75 < ratio.max() <= 3.86
    assert 4.9e-3 < size.min() and size.max() < 8.1e-3 and b.min() > 2.5e-3
    assert 0.69e9 < p0.min() and p0.max() < 2.3e9
