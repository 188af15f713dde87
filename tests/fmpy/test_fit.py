"""`wheelrail fit` on the example measurements of docs/examples/fit: the FMU with the report's FMU parameters
(the fitted values by variable) reproduces the report's fitted curve, as `wheelrail point --params
fitted.toml` does."""

import json
import subprocess

import numpy as np
from fmpy import simulate_fmu

from conftest import GRID, ROOT, cli

STEP = 1e-3
DATA = ROOT / "docs" / "examples" / "fit" / "roller-rig.csv"
INPUTS = ["creepage_longitudinal", "rolling_speed"]


def test_the_fmu_reproduces_the_fitted_curve(fmu_path, tmp_path):
    subprocess.run([cli(), "fit", "--data", str(DATA), "--free", "roughness.k_r", "--grid", f"{GRID},{GRID}",
                    "--out", str(tmp_path)], check=True, capture_output=True, text=True)
    report = json.loads((tmp_path / "report.json").read_text())
    assert report["converged"] and report["not_in_fmu"] == []
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
        start_values=dict(mode=2, warm_start=False, **report["fmu_parameters"]),
        output=["traction_coefficient", "evaluation_mode"],
    )
    assert report["fmu_parameters"]["roughness"] == report["parameters"]["roughness.k_r"]["value"]
    for k, p in enumerate(points):
        # quasi-static co-simulation: the row at (k + 1) STEP holds the outputs of the inputs of step k
        row = result[np.isclose(result["time"], (k + 1) * STEP, rtol=0.0, atol=STEP * 1e-6)][-1]
        assert row["evaluation_mode"] == 2
        np.testing.assert_allclose(row["traction_coefficient"], p["traction_coefficient"]["model"], rtol=1e-12,
                                   err_msg=f"data line {p['line']}")
