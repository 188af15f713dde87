"""Co-simulation in fmpy with the contact geometry changing every step reproduces `wheelrail point` for the
same inputs: first gap curvatures A, B (Hertz), then prescribed semi-axes a, b (curvatures ignored)."""

import json
import math
import subprocess

import numpy as np
from fmpy import simulate_fmu

from conftest import CLI_OUTPUTS, GRID, cli

STEP = 1e-3
N_STEPS = 10
INPUTS = ["creepage_longitudinal", "creepage_lateral", "spin_creepage", "normal_force", "rolling_speed", "wetness",
          "curvature_longitudinal", "curvature_lateral", "semi_axis_a", "semi_axis_b"]
N_CURVATURE_STEPS = 5  # steps 0..4: Hertz from the curvatures; steps 5..9: prescribed semi-axes


def step_inputs(k):
    """The inputs held over step k, [k STEP, (k + 1) STEP): every one changes from step to step."""
    prescribed = k >= N_CURVATURE_STEPS
    j = k - N_CURVATURE_STEPS
    return dict(
        creepage_longitudinal=0.001 + 0.0008 * k,
        creepage_lateral=-0.001 + 0.0003 * k,
        spin_creepage=0.05 * (k % 3),
        normal_force=80e3 + 5e3 * k,
        rolling_speed=20.0 + k,
        wetness=0.5 if k == 8 else 0.0,
        curvature_longitudinal=1.0 + 0.6 * k / (N_STEPS - 1),  # 1.0 .. 1.6, ignored once semi-axes are given
        curvature_lateral=0.42 - 0.22 * k / (N_STEPS - 1),  # 0.42 .. 0.2
        semi_axis_a=4e-3 + 0.75e-3 * j if prescribed else 0.0,  # 4 .. 7 mm
        semi_axis_b=6e-3 + 1e-3 * j if prescribed else 0.0,  # 6 .. 10 mm
    )


def signals():
    """Piecewise-constant inputs: two rows at every interior communication point (value before, value after),
    so fmpy applies exactly step k's values at t = k STEP (it takes the value after a discontinuity) and the
    discontinuities add no communication points of their own."""
    rows = []
    for k in range(N_STEPS):
        values = [step_inputs(k)[n] for n in INPUTS]
        rows.append((k * STEP, *values))
        rows.append(((k + 1) * STEP, *values))
    return np.array(rows, dtype=[("time", np.double)] + [(n, np.double) for n in INPUTS])


def cli_geometry_point(inputs):
    """`wheelrail point --json` on the test grid, with the geometry flags (`cli_point` knows only the FMU
    names that the parameter specification maps to flags)."""
    args = [cli(), "point", "--json", "--grid", f"{GRID},{GRID}",
            "--creepage-x", repr(inputs["creepage_longitudinal"]),
            "--creepage-y", repr(inputs["creepage_lateral"]),
            "--spin", repr(inputs["spin_creepage"]),
            "--normal-force", repr(inputs["normal_force"]),
            "--speed", repr(inputs["rolling_speed"]),
            "--wetness", repr(inputs["wetness"])]
    if inputs["semi_axis_a"] > 0.0 and inputs["semi_axis_b"] > 0.0:
        args += ["--semi-axes", f"{inputs['semi_axis_a']!r},{inputs['semi_axis_b']!r}"]
    else:
        args += ["--curvatures", f"{inputs['curvature_longitudinal']!r},{inputs['curvature_lateral']!r}"]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


GEOMETRY_OUTPUTS = {
    "contact_semi_axis_a": "semi_axis_a",
    "contact_semi_axis_b": "semi_axis_b",
    "peak_pressure": "peak_pressure",
}


def test_changing_geometry_equals_the_cli_for_the_same_inputs(fmu_path):
    result = simulate_fmu(
        fmu_path,
        stop_time=N_STEPS * STEP,
        output_interval=STEP,
        input=signals(),
        start_values=dict(grid_size=GRID, mode=2, warm_start=False),
        output=list(CLI_OUTPUTS) + list(GEOMETRY_OUTPUTS) + ["converged", "evaluation_mode"],
    )

    def row_of_step(k):
        # quasi-static co-simulation: the row at (k + 1) STEP holds the outputs of the inputs of step k
        rows = result[np.isclose(result["time"], (k + 1) * STEP, rtol=0.0, atol=STEP * 1e-6)]
        assert len(rows) >= 1, f"no output row at t = {(k + 1) * STEP}"
        return rows[-1]

    # one step by curvatures, two by prescribed semi-axes (one of them wet)
    for k in (3, 6, 8):
        row = row_of_step(k)
        inputs = step_inputs(k)
        reference = cli_geometry_point(inputs)
        assert reference["evaluation"] == "exact"
        for fmu_name, cli_name in {**CLI_OUTPUTS, **GEOMETRY_OUTPUTS}.items():
            np.testing.assert_allclose(row[fmu_name], reference[cli_name], rtol=1e-12, atol=0.0,
                                       err_msg=f"{fmu_name} at step {k}")
        assert bool(row["converged"]) == reference["converged"]
        assert row["evaluation_mode"] == 2
        if k >= N_CURVATURE_STEPS:
            # prescribed: the ellipse is the input's, the curvatures are ignored
            assert row["contact_semi_axis_a"] == inputs["semi_axis_a"]
            assert row["contact_semi_axis_b"] == inputs["semi_axis_b"]
            np.testing.assert_allclose(row["peak_pressure"],
                                       3.0 * inputs["normal_force"] / (2.0 * math.pi * inputs["semi_axis_a"]
                                                                      * inputs["semi_axis_b"]), rtol=1e-12)

    # the geometry did change every step: each step's contact ellipse differs from the previous one
    axes = [(row_of_step(k)["contact_semi_axis_a"], row_of_step(k)["contact_semi_axis_b"]) for k in range(N_STEPS)]
    assert all(a > 0.0 and b > 0.0 for a, b in axes)
    assert all(axes[k] != axes[k + 1] for k in range(N_STEPS - 1))
    assert row_of_step(8)["fluid_load_fraction"] > 0.0 and row_of_step(6)["fluid_load_fraction"] == 0.0
