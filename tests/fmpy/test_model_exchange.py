"""FMI 2.0 Model Exchange of the same FMU: fmpy's ME simulation gives the outputs of Co-Simulation at the same
inputs, and the ME instance provides the integrator's Jacobian of the algebraic outputs."""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model, FMU2Slave

from conftest import GRID

INPUTS = ["creepage_longitudinal", "creepage_lateral", "spin_creepage", "normal_force", "rolling_speed", "wetness"]
OUTPUTS = ["force_longitudinal", "force_lateral", "spin_moment", "traction_coefficient", "max_temperature",
           "fluid_load_fraction", "contact_semi_axis_a", "contact_semi_axis_b", "peak_pressure"]
STEP = 0.05


def ramps():
    """Inputs varying continuously over [0, 1] through stick and slip, dry to wet, inside the bundled table."""
    t = np.linspace(0.0, 1.0, 11)
    rows = [(s, 0.001 + 0.01 * s, -0.002 * s, 0.2 * s, 80e3 + 40e3 * s, 20.0 + 10.0 * s, s) for s in t]
    return np.array(rows, dtype=[("time", np.double)] + [(n, np.double) for n in INPUTS])


def run(fmu_path, fmi_type, **start_values):
    return simulate_fmu(fmu_path, fmi_type=fmi_type, stop_time=1.0, output_interval=STEP, input=ramps(),
                        start_values=start_values, output=OUTPUTS + ["evaluation_mode", "converged"])


def test_model_description_offers_both_interfaces_from_one_binary(fmu_path):
    md = read_model_description(fmu_path, validate=True)
    assert md.modelExchange.modelIdentifier == md.coSimulation.modelIdentifier == "WheelRailFriction"
    assert md.modelExchange.providesDirectionalDerivative
    assert md.modelExchange.canGetAndSetFMUstate and md.modelExchange.canSerializeFMUstate
    assert not md.modelExchange.completedIntegratorStepNotNeeded
    assert md.numberOfContinuousStates == 0 and md.numberOfEventIndicators == 0
    # direct feedthrough: every output depends on every input, nothing else (no states)
    inputs = {v for v in md.modelVariables if v.causality == "input"}
    assert md.outputs and all(set(u.dependencies) == inputs for u in md.outputs)


# table: the same interpolation, so identical; exact cold: the same solve, identical; exact warm: the ME warm
# start advances at accepted points (here also twice at the start point: initialization, continuous-time
# mode), so the outputs agree within the solver tolerance (1e-6 relative change per iteration)
@pytest.mark.parametrize("mode, warm_start, rtol", [(1, True, 0.0), (2, False, 0.0), (2, True, 1e-6)])
def test_model_exchange_simulation_equals_co_simulation_at_the_same_inputs(fmu_path, mode, warm_start, rtol):
    start = dict(mode=mode, warm_start=warm_start) | ({} if mode == 1 else dict(grid_size=GRID))
    me = run(fmu_path, "ModelExchange", **start)
    cs = run(fmu_path, "CoSimulation", **start)
    assert np.all(me["evaluation_mode"] == (1 if mode == 1 else 2))
    # ME's row at t holds the outputs of the inputs at t; quasi-static CS's row at t + STEP those of the
    # inputs applied at t
    n = len(me) - 1
    assert n >= 19 and np.allclose(me["time"][:n] + STEP, cs["time"][1:n + 1])
    for name in OUTPUTS:
        np.testing.assert_allclose(me[name][:n], cs[name][1:n + 1], rtol=rtol, atol=0.0, err_msg=name)
    assert np.array_equal(me["converged"][:n], cs["converged"][1:n + 1])
    # the ramps move the outputs: the comparison is not between constants
    assert np.ptp(me["force_longitudinal"]) > 1e3 and np.ptp(me["fluid_load_fraction"]) > 0.0


@pytest.fixture()
def instances(fmu_path, unzipped_fmu):
    """An ME instance in continuous-time mode and a CS instance, both exact and cold on the test grid."""
    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = unzipped_fmu
    made = []
    for cls, name in [(FMU2Model, "me"), (FMU2Slave, "cs")]:
        fmu = cls(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="WheelRailFriction", instanceName=name)
        fmu.instantiate()
        fmu.setInteger([vr["grid_size"], vr["mode"]], [GRID, 2])
        fmu.setBoolean([vr["warm_start"]], [False])
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        made.append(fmu)
    me, cs = made
    needed, terminate, _, _, time_event, _ = me.newDiscreteStates()
    assert not needed and not terminate and not time_event
    me.enterContinuousTimeMode()
    yield me, cs, vr
    for fmu in made:
        fmu.terminate()
        fmu.freeInstance()


def test_the_integrators_jacobian_is_that_of_co_simulation(instances):
    me, cs, vr = instances
    point = dict(creepage_longitudinal=0.003, creepage_lateral=-0.001, spin_creepage=0.2, normal_force=90e3,
                 rolling_speed=25.0, wetness=0.3)
    me.setTime(0.01)
    for fmu in (me, cs):
        fmu.setReal([vr[n] for n in point], list(point.values()))
    cs.doStep(0.0, 0.01)
    unknown = [vr[n] for n in OUTPUTS[:3]]
    for known in ["creepage_longitudinal", "creepage_lateral", "normal_force"]:
        d_me = me.getDirectionalDerivative(unknown, [vr[known]], [1.0])
        d_cs = cs.getDirectionalDerivative(unknown, [vr[known]], [1.0])
        assert d_me == d_cs, known
    assert me.getReal(unknown) == cs.getReal(unknown)
    step_event, terminate = me.completedIntegratorStep()
    assert not step_event and not terminate
