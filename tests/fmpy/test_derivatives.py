"""fmi2GetDirectionalDerivative agrees with central differences of the outputs."""

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave

from conftest import GRID

OUTPUTS = ["force_longitudinal", "force_lateral", "spin_moment", "traction_coefficient"]
# input, absolute step of the reference central difference
KNOWNS = [("creepage_longitudinal", 1e-5), ("creepage_lateral", 1e-5), ("spin_creepage", 1e-3),
          ("normal_force", 50.0)]
POINT = dict(creepage_longitudinal=0.003, creepage_lateral=-0.001, spin_creepage=0.2, normal_force=90e3,
             rolling_speed=25.0, wetness=0.0)


@pytest.fixture()
def slave(fmu_path, unzipped_fmu):
    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = unzipped_fmu
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="jacobian")
    fmu.instantiate()
    fmu.setInteger([vr["grid_size"], vr["mode"]], [GRID, 2])
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.setReal([vr[n] for n in POINT], list(POINT.values()))
    fmu.exitInitializationMode()
    yield fmu, vr
    fmu.terminate()
    fmu.freeInstance()


def outputs(fmu, vr, **changes):
    point = {**POINT, **changes}
    fmu.setReal([vr[n] for n in point], list(point.values()))
    fmu.doStep(0.0, 1e-3)
    return np.array(fmu.getReal([vr[n] for n in OUTPUTS]))


def test_directional_derivatives_agree_with_central_differences(slave):
    fmu, vr = slave
    for name, h in KNOWNS:
        outputs(fmu, vr)
        d = np.array(fmu.getDirectionalDerivative([vr[n] for n in OUTPUTS], [vr[name]], [1.0]))
        up = outputs(fmu, vr, **{name: POINT[name] + h})
        down = outputs(fmu, vr, **{name: POINT[name] - h})
        central = (up - down) / (2 * h)
        scale = np.abs(central).max()
        np.testing.assert_allclose(d, central, rtol=0.02, atol=0.02 * scale, err_msg=name)


def test_a_combined_seed_is_the_sum_of_the_partials(slave):
    fmu, vr = slave
    outputs(fmu, vr)
    unknown = [vr[n] for n in OUTPUTS]
    d_x = np.array(fmu.getDirectionalDerivative(unknown, [vr["creepage_longitudinal"]], [1.0]))
    d_y = np.array(fmu.getDirectionalDerivative(unknown, [vr["creepage_lateral"]], [1.0]))
    d_xy = np.array(fmu.getDirectionalDerivative(unknown, [vr["creepage_longitudinal"], vr["creepage_lateral"]],
                                                 [2.0, -1.0]))
    np.testing.assert_allclose(d_xy, 2 * d_x - d_y, rtol=0.02, atol=0.02 * np.abs(d_xy).max())
