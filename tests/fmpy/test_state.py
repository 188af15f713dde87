"""FMU states restore an instance bit for bit: an instance set to another's state, or to its
serialized and deserialized copy in a fresh instance, continues exactly as the instance it was taken of."""

import pytest
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave

INPUTS = ["creepage_longitudinal", "creepage_lateral", "normal_force", "rolling_speed", "wetness"]
OUTPUTS = ["force_longitudinal", "force_lateral", "spin_moment", "traction_coefficient", "max_temperature",
           "fluid_load_fraction", "contact_semi_axis_a", "contact_semi_axis_b", "peak_pressure"]
BEFORE = [0.005, 0.0, 100e3, 30.0, 0.5]
# the step (dry), then a continuation with varying inputs
AFTER = [[0.02, 0.001, 80e3, 20.0, 0.0], [0.01, -0.002, 90e3, 25.0, 0.3], [0.003, 0.0, 110e3, 30.0, 1.0],
         [0.03, 0.004, 70e3, 15.0, 0.0]]


@pytest.fixture(scope="module")
def fmu_files(fmu_path, unzipped_fmu):
    md = read_model_description(fmu_path)
    return md, {v.name: v.valueReference for v in md.modelVariables}, unzipped_fmu


def instance(fmu_files, name, mode=None, roughness=None, warm_start=None):
    """An instance; initialized (with mode, roughness, warm_start) unless only instantiated (mode None)."""
    md, vr, unzipped = fmu_files
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName=name)
    fmu.instantiate()
    if mode is not None:
        fmu.setInteger([vr["mode"]], [mode])
        fmu.setBoolean([vr["warm_start"]], [warm_start])
        if roughness is not None:
            fmu.setReal([vr["roughness"]], [roughness])
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
    return fmu


def step(fmu, vr, t, inputs):
    fmu.setReal([vr[n] for n in INPUTS], inputs)
    fmu.doStep(t, 1e-3)
    return fmu.getReal([vr[n] for n in OUTPUTS]) + fmu.getInteger([vr["evaluation_mode"]])


@pytest.mark.parametrize("warm_start", [True, False])
@pytest.mark.parametrize("mode", [0, 1, 2])
def test_a_restored_state_continues_bit_for_bit(fmu_files, mode, warm_start):
    _, vr, _ = fmu_files
    # mode 1 evaluates by the bundled table, which is for the default parameters (roughness 0.5)
    a = instance(fmu_files, "a", mode, None if mode == 1 else 0.2, warm_start)
    b = instance(fmu_files, "b", 0 if mode == 1 else mode, 0.8, warm_start)
    assert step(a, vr, 0.0, BEFORE) != step(b, vr, 0.0, BEFORE)
    state = a.getFMUstate()
    blob = a.serializeFMUstate(state)
    a.freeFMUstate(state)
    c = instance(fmu_files, "c")
    for fmu in (b, c):
        restored = fmu.deSerializeFMUstate(blob)
        fmu.setFMUstate(restored)
        fmu.freeFMUstate(restored)
    for k, inputs in enumerate(AFTER):
        t = 1e-3 * (k + 1)
        want = step(a, vr, t, inputs)
        assert want[-1] == (1 if mode == 1 else 2)
        for other in (b, c):
            got = step(other, vr, t, inputs)
            # exactly equal: == on every float
            assert got == want, f"step {k}"
    for fmu in (a, b, c):
        fmu.terminate()
        fmu.freeInstance()
