"""A second master: libcosim (DNV's co-simulation library, through libcosimpy, pinned in requirements.txt)
runs WheelRailFriction.fmu, two instances in one execution, and its outputs equal the library's
(`wheelrail point`) and fmpy's for the same inputs, and are physically sane."""

import math

import numpy as np
from fmpy import simulate_fmu
from libcosimpy.CosimEnums import CosimErrorCode
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

from conftest import CLI_OUTPUTS, GRID, cli_point

# a dry and a wet contact, both exact and cold (warm_start off), so that every step is the same solve as
# `wheelrail point`
CASES = {
    "dry": dict(creepage_longitudinal=0.004, creepage_lateral=-0.001, spin_creepage=0.0, normal_force=100e3,
                rolling_speed=30.0, wetness=0.0),
    "wet": dict(creepage_longitudinal=0.01, creepage_lateral=0.001, spin_creepage=0.0, normal_force=90e3,
                rolling_speed=20.0, wetness=0.8),
}
PARAMETERS = dict(grid_size=GRID, mode=2, warm_start=False)
STEP_NS = 1_000_000  # libcosim counts time in nanoseconds: 1 ms
STEPS = 5


def run_libcosim(fmu_path):
    """The outputs of each case after STEPS steps of a libcosim execution with both instances."""
    execution = CosimExecution.from_step_size(step_size=STEP_NS)
    slaves = {}
    for name in CASES:
        # libcosim keeps the slave object's pointer: keep the Python object alive until the end
        slaves[name] = CosimLocalSlave(fmu_path=fmu_path, instance_name=name)
    index = {name: execution.add_local_slave(local_slave=slave) for name, slave in slaves.items()}
    refs = {v.name.decode(): v.reference for v in execution.slave_variables(index["dry"])}
    for name, inputs in CASES.items():
        i = index[name]
        execution.integer_initial_value(i, refs["grid_size"], PARAMETERS["grid_size"])
        execution.integer_initial_value(i, refs["mode"], PARAMETERS["mode"])
        execution.boolean_initial_value(i, refs["warm_start"], PARAMETERS["warm_start"])
        for variable, value in inputs.items():
            execution.real_initial_value(i, refs[variable], value)
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    assert execution.simulate_until(target_time=STEPS * STEP_NS)
    status = execution.status()
    assert status.error_code == CosimErrorCode.SUCCESS.value and status.current_time == STEPS * STEP_NS
    results = {}
    for name, i in index.items():
        reals = observer.last_real_values(i, [refs[n] for n in CLI_OUTPUTS])
        results[name] = dict(zip(CLI_OUTPUTS, reals))
        results[name]["converged"] = observer.last_boolean_values(i, [refs["converged"]])[0]
        results[name]["evaluation_mode"] = observer.last_integer_values(i, [refs["evaluation_mode"]])[0]
    return results


def test_libcosim_runs_the_fmu_like_fmpy_and_the_library(fmu_path):
    results = run_libcosim(fmu_path)
    for name, inputs in CASES.items():
        got = results[name]
        reference = cli_point(**inputs)
        fmpy_row = simulate_fmu(
            fmu_path,
            stop_time=STEPS * 1e-3,
            output_interval=1e-3,
            start_values=dict(**PARAMETERS, **inputs),
            output=list(CLI_OUTPUTS),
        )[-1]
        for output, cli_name in CLI_OUTPUTS.items():
            assert math.isfinite(got[output]), f"{name}: {output}"
            np.testing.assert_allclose(got[output], reference[cli_name], rtol=1e-10, atol=1e-9,
                                       err_msg=f"{name}: {output} against wheelrail point")
            np.testing.assert_allclose(got[output], fmpy_row[output], rtol=1e-12, atol=1e-12,
                                       err_msg=f"{name}: {output} against fmpy")
        assert got["converged"] and got["evaluation_mode"] == 2
        # physics: creep forces oppose the creepages, the resultant is the traction coefficient times the
        # load and below it
        fx, fy, n = got["force_longitudinal"], got["force_lateral"], inputs["normal_force"]
        assert fx * inputs["creepage_longitudinal"] < 0 and fy * inputs["creepage_lateral"] < 0
        assert math.isclose(math.hypot(fx, fy), got["traction_coefficient"] * n, rel_tol=1e-9)
        assert 0 < got["traction_coefficient"] < 1
    # water carries part of the load in the wet contact only
    assert results["wet"]["fluid_load_fraction"] > 0 == results["dry"]["fluid_load_fraction"]
