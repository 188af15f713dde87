"""Co-simulation in fmpy with input signals reproduces `wheelrail point` for the same inputs."""

import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import CLI_OUTPUTS, GRID, cli_point

INPUTS = ["creepage_longitudinal", "creepage_lateral", "spin_creepage", "normal_force", "rolling_speed", "wetness"]

# piecewise-constant inputs on [0, 1), [1, 2), [2, 3]: dry, dry with spin, wet
SEGMENTS = [
    dict(creepage_longitudinal=0.002, creepage_lateral=0.0, spin_creepage=0.0, normal_force=80e3,
         rolling_speed=20.0, wetness=0.0),
    dict(creepage_longitudinal=0.006, creepage_lateral=-0.002, spin_creepage=0.3, normal_force=100e3,
         rolling_speed=30.0, wetness=0.0),
    dict(creepage_longitudinal=0.01, creepage_lateral=0.001, spin_creepage=0.0, normal_force=120e3,
         rolling_speed=10.0, wetness=1.0),
]
PARAMETERS = dict(roughness=0.4, bulk_temperature=300.0)


def signals():
    rows = []
    for k, seg in enumerate(SEGMENTS):
        for t in (float(k), float(k + 1)):
            rows.append((t, *[seg[n] for n in INPUTS]))
    return np.array(rows, dtype=[("time", np.double)] + [(n, np.double) for n in INPUTS])


# warm_start off: every step is a cold solve, bit for bit the CLI's; on: each step starts from the previous
# one and agrees with the cold solve to within the solver tolerance (1e-6 relative change per iteration)
@pytest.mark.parametrize("warm_start, rtol", [(False, 1e-10), (True, 1e-6)])
def test_outputs_equal_the_cli_for_the_same_inputs(fmu_path, warm_start, rtol):
    result = simulate_fmu(
        fmu_path,
        stop_time=3.0,
        output_interval=0.5,
        input=signals(),
        start_values=dict(grid_size=GRID, mode=2, warm_start=warm_start, **PARAMETERS),
        output=list(CLI_OUTPUTS) + ["converged", "evaluation_mode"],
    )
    # quasi-static co-simulation: the row at t holds the outputs of the inputs applied at the previous
    # communication point (t - 0.5); at t = 0 those of the initial inputs
    expected_at = {0.0: 0, 1.0: 0, 2.0: 1, 3.0: 2}
    for t, k in expected_at.items():
        row = result[np.isclose(result["time"], t)][-1]
        reference = cli_point(**SEGMENTS[k], **PARAMETERS)
        for fmu_name, cli_name in CLI_OUTPUTS.items():
            np.testing.assert_allclose(row[fmu_name], reference[cli_name], rtol=rtol, atol=1e-9,
                                       err_msg=f"{fmu_name} at t = {t}")
        assert bool(row["converged"]) == reference["converged"]
        assert row["evaluation_mode"] == 2
    # the wet segment carries part of the load on the fluid, the dry ones none
    assert result["fluid_load_fraction"][-1] > 0.0 and result["fluid_load_fraction"][0] == 0.0


def test_auto_mode_evaluates_by_the_bundled_table(fmu_path):
    """Default parameters and mode: the FMU's bundled table evaluates, exactly as `wheelrail point --table`."""
    result = simulate_fmu(
        fmu_path,
        stop_time=3.0,
        output_interval=0.5,
        input=signals(),
        output=list(CLI_OUTPUTS) + ["converged", "evaluation_mode"],
    )
    expected_at = {0.0: 0, 1.0: 0, 2.0: 1, 3.0: 2}
    for t, k in expected_at.items():
        row = result[np.isclose(result["time"], t)][-1]
        reference = cli_point(table=True, **SEGMENTS[k])
        assert reference["evaluation"] == "table"
        for fmu_name, cli_name in CLI_OUTPUTS.items():
            np.testing.assert_allclose(row[fmu_name], reference[cli_name], rtol=1e-12, atol=1e-9,
                                       err_msg=f"{fmu_name} at t = {t}")
        assert row["evaluation_mode"] == 1 and bool(row["converged"])
