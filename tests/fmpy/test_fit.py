"""`wheelrail fit` on the example measurements of docs/examples/fit: the FMU reproduces the report's fitted
curve, as `wheelrail point --params fitted.toml` does, with `parameter_file` = fitted.toml (a fitted key
without an FMU variable included) and, for a fit of FMU parameters only, with the report's FMU parameters
set by variable."""

import json
import subprocess

import numpy as np
from fmpy import simulate_fmu

from conftest import GRID, ROOT, cli

STEP = 1e-3
DATA = ROOT / "docs" / "examples" / "fit" / "roller-rig.csv"
INPUTS = ["creepage_longitudinal", "rolling_speed"]


def fit(tmp_path, free):
    subprocess.run([cli(), "fit", "--data", str(DATA), "--free", free, "--grid", f"{GRID},{GRID}",
                    "--out", str(tmp_path)], check=True, capture_output=True, text=True)
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["converged"]
    return report


def assert_reproduces(fmu_path, report, start_values):
    points = report["points"]
    # one step per data row, its inputs held over [k STEP, (k + 1) STEP)
    rows = []
    for k, p in enumerate(points):
        values = (p["creepage_x"], p["speed"])
        rows += [(k * STEP, *values), ((k + 1) * STEP, *values)]
    signals = np.array(rows, dtype=[("time", np.double)] + [(n, np.double) for n in INPUTS])
    result = simulate_fmu(
        fmu_path,
        stop_time=len(points) * STEP,
        output_interval=STEP,
        input=signals,
        start_values=dict(mode=2, warm_start=False, **start_values),
        output=["traction_coefficient", "evaluation_mode"],
    )
    for k, p in enumerate(points):
        # quasi-static co-simulation: the row at (k + 1) STEP holds the outputs of the inputs of step k
        row = result[np.isclose(result["time"], (k + 1) * STEP, rtol=0.0, atol=STEP * 1e-6)][-1]
        assert row["evaluation_mode"] == 2
        np.testing.assert_allclose(row["traction_coefficient"], p["traction_coefficient"]["model"], rtol=1e-12,
                                   err_msg=f"data line {p['line']}")


def test_the_fmu_reproduces_the_fitted_curve_from_the_fitted_parameter_file(fmu_path, tmp_path):
    report = fit(tmp_path, "roughness.k_r,material.yield_span")
    # the yield span has no FMU variable: only the parameter file carries it
    assert report["not_in_fmu"] == ["material.yield_span"]
    assert_reproduces(fmu_path, report, dict(parameter_file=str(tmp_path / "fitted.toml")))


def test_the_fmu_reproduces_the_fitted_curve_from_its_variables(fmu_path, tmp_path):
    report = fit(tmp_path, "roughness.k_r")
    assert report["not_in_fmu"] == []
    assert report["fmu_parameters"]["roughness"] == report["parameters"]["roughness.k_r"]["value"]
    assert_reproduces(fmu_path, report, report["fmu_parameters"])
