"""The FMI 3.0 FMU (target/fmu/WheelRailFriction-fmi3.fmu, override WHEELRAIL_FMU3): fmpy validates and
simulates it (Co-Simulation and Model Exchange); one instance of several contacts gives, bit for bit, what one
FMI 2.0 instance per contact gives at the same inputs, on one thread or two; instances stepped in turn share
the process's worker threads, which end with the last instance freed; `contacts` is refused outside
configuration mode; FMU states round-trip; derivatives are block-diagonal over the contacts, the adjoint the
transpose of the directional derivative; illegal call sequences, wrong array lengths and NaN inputs are
refused with fmi3Error and change nothing."""

import os
import random
import zipfile

import pytest
from conftest import ROOT
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave, fmi3LogMessageCallback

FMU3 = os.environ.get("WHEELRAIL_FMU3", str(ROOT / "target" / "fmu" / "WheelRailFriction-fmi3.fmu"))
INPUTS = ["creepage_longitudinal", "creepage_lateral", "spin_creepage", "normal_force", "rolling_speed", "wetness"]
OUTPUTS = ["force_longitudinal", "force_lateral", "spin_moment", "traction_coefficient", "max_temperature",
           "fluid_load_fraction", "contact_semi_axis_a", "contact_semi_axis_b", "peak_pressure",
           "frictional_power"]
GRID = 8
CONTACTS = 4


def contact_inputs(k, step):
    """Inputs of contact k at a step: different per contact and step, inside the bundled table's ranges."""
    return [0.001 * (k + 1) + 0.0005 * step, -0.0004 * k, 0.05 * k, 60e3 + 15e3 * k, 20.0 + 3 * k,
            [0.0, 0.3, 1.0, 0.6][k % 4]]


@pytest.fixture(scope="module")
def fmi3_files(tmp_path_factory):
    if not os.path.exists(FMU3):
        pytest.fail(f"{FMU3} is missing: build it with `make fmu`")
    md = read_model_description(FMU3)
    return md, {v.name: v.valueReference for v in md.modelVariables}, extract(
        FMU3, unzipdir=str(tmp_path_factory.mktemp("fmu3")))


@pytest.fixture(scope="module")
def fmi2_files(fmu_path, unzipped_fmu):
    md = read_model_description(fmu_path)
    return md, {v.name: v.valueReference for v in md.modelVariables}, unzipped_fmu


class Log:
    """The messages an instance logs."""

    def __init__(self):
        self.messages = []
        self.callback = fmi3LogMessageCallback(
            lambda env, status, category, message: self.messages.append((status, message.decode())))


def fmi3_instance(files, name, contacts=CONTACTS, threads=1, mode=2, cls=FMU3Slave, log=None, grid=GRID):
    md, vr, unzipped = files
    fmu = cls(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="WheelRailFriction", instanceName=name)
    if log is None:
        fmu.instantiate()
    else:
        fmu.instantiate(loggingOn=True, logMessage=log.callback)
    fmu.enterConfigurationMode()
    fmu.setUInt64([vr["contacts"]], [contacts])
    fmu.exitConfigurationMode()
    fmu.setUInt64([vr["threads"]], [threads])
    # the bundled table is for the default grid: mode 1 (table only) refuses others
    fmu.setInt32([vr["grid_size"], vr["mode"]], [0 if mode == 1 else grid, mode])
    fmu.enterInitializationMode(startTime=0.0)
    fmu.exitInitializationMode()
    return fmu


def fmi2_instance(files, name, mode=2):
    md, vr, unzipped = files
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="WheelRailFriction", instanceName=name)
    fmu.instantiate()
    fmu.setInteger([vr["grid_size"], vr["mode"]], [0 if mode == 1 else GRID, mode])
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    return fmu


def step3(fmu, vr, t, step, contacts=CONTACTS):
    """One vehicle step: every input as an array over the contacts; the outputs by contact."""
    per_contact = [contact_inputs(k, step) for k in range(contacts)]
    for j, name in enumerate(INPUTS):
        fmu.setFloat64([vr[name]], [per_contact[k][j] for k in range(contacts)])
    fmu.doStep(t, 1e-3)
    values = fmu.getFloat64([vr[n] for n in OUTPUTS], len(OUTPUTS) * contacts)
    modes = fmu.getInt32([vr["evaluation_mode"]], contacts)
    return [[values[i * contacts + k] for i in range(len(OUTPUTS))] + [modes[k]] for k in range(contacts)]


def step2(fmu, vr, t, inputs):
    fmu.setReal([vr[n] for n in INPUTS], inputs)
    fmu.doStep(t, 1e-3)
    return fmu.getReal([vr[n] for n in OUTPUTS]) + fmu.getInteger([vr["evaluation_mode"]])


def free(*fmus):
    for fmu in fmus:
        fmu.terminate()
        fmu.freeInstance()


def test_fmpy_validates_the_fmu_and_its_layout():
    from fmpy.validation import validate_fmu

    assert validate_fmu(FMU3) == []
    with zipfile.ZipFile(FMU3) as z:
        names = set(z.namelist())
        xml = z.read("modelDescription.xml").decode()
    assert {"modelDescription.xml", "binaries/x86_64-linux/WheelRailFriction.so",
            "documentation/index.html"} <= names
    md = read_model_description(FMU3)
    assert md.fmiVersion == "3.0"
    # the schema's attribute names (fmpy 0.3.32 reads providesDirectionalDerivative, FMI 2.0's name)
    for capability in ["providesDirectionalDerivatives", "providesAdjointDerivatives", "canSerializeFMUState"]:
        assert xml.count(f'{capability}="true"') == 2, capability
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["contacts"].causality == "structuralParameter" and by_name["contacts"].type == "UInt64"
    for name in INPUTS + OUTPUTS + ["roughness", "semi_axis_a", "curvature_lateral", "converged"]:
        assert [d.variable.name for d in by_name[name].dimensions] == ["contacts"], name
    assert not by_name["mode"].dimensions and not by_name["bulk_temperature"].dimensions
    # the units and display units of FMI 2.0
    assert by_name["force_longitudinal"].unit == "N" and by_name["force_longitudinal"].displayUnit == "kN"


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_fmpy_simulates_it(fmi_type, fmu_path):
    """fmpy's own simulation of one contact equals that of the FMI 2.0 FMU at the same start values."""
    from fmpy import simulate_fmu

    start = dict(mode=1, creepage_longitudinal=0.004, normal_force=90e3, rolling_speed=25.0)
    kw = dict(fmi_type=fmi_type, stop_time=0.02, output_interval=0.01, output=["force_longitudinal"])
    got = simulate_fmu(FMU3, start_values={k: ([v] if k != "mode" else v) for k, v in start.items()}, **kw)
    want = simulate_fmu(fmu_path, start_values=start, **kw)
    assert [r[1][0] for r in got] == [r[1] for r in want]
    assert want[-1][1] < -1e3, "a creep force"


@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("mode", [1, 2])
def test_contacts_equal_one_fmi2_instance_each(fmi3_files, fmi2_files, mode, threads):
    """Exact (mode 2, warm starts carried from step to step) and by the table (mode 1)."""
    _, vr3, _ = fmi3_files
    _, vr2, _ = fmi2_files
    vehicle = fmi3_instance(fmi3_files, "vehicle", threads=threads, mode=mode)
    singles = [fmi2_instance(fmi2_files, f"contact{k}", mode) for k in range(CONTACTS)]
    for s in range(3):
        t = 1e-3 * s
        got = step3(vehicle, vr3, t, s)
        want = [step2(fmu, vr2, t, contact_inputs(k, s)) for k, fmu in enumerate(singles)]
        assert got == want, f"step {s}"
        assert {row[-1] for row in got} == {mode}
    free(vehicle, *singles)


def test_per_contact_roughness_and_shared_parameters(fmi3_files, fmi2_files):
    _, vr3, _ = fmi3_files
    _, vr2, _ = fmi2_files
    md, vr, unzipped = fmi3_files
    vehicle = FMU3Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="WheelRailFriction",
                        instanceName="rough")
    vehicle.instantiate()
    vehicle.enterConfigurationMode()
    vehicle.setUInt64([vr["contacts"]], [2])
    vehicle.exitConfigurationMode()
    vehicle.setInt32([vr["grid_size"], vr["mode"]], [GRID, 2])
    vehicle.setFloat64([vr["roughness"]], [0.2, 0.8])
    vehicle.enterInitializationMode()
    vehicle.exitInitializationMode()
    got = step3(vehicle, vr3, 0.0, 0, contacts=2)
    for k, roughness in enumerate([0.2, 0.8]):
        single = FMU2Slave(guid=fmi2_files[0].guid, unzipDirectory=fmi2_files[2],
                           modelIdentifier="WheelRailFriction", instanceName="single")
        single.instantiate()
        single.setInteger([vr2["grid_size"], vr2["mode"]], [GRID, 2])
        single.setReal([vr2["roughness"]], [roughness])
        single.setupExperiment(startTime=0.0)
        single.enterInitializationMode()
        single.exitInitializationMode()
        assert got[k] == step2(single, vr2, 0.0, contact_inputs(k, 0))
        free(single)
    assert got[0][0] != got[1][0]
    free(vehicle)


def test_contacts_is_refused_outside_configuration_mode(fmi3_files):
    _, vr, _ = fmi3_files
    log = Log()
    fmu = fmi3_instance(fmi3_files, "refuse", contacts=2, log=log)
    with pytest.raises(FMICallException):
        fmu.setUInt64([vr["contacts"]], [3])
    assert any("may be set only in configuration mode" in m for _, m in log.messages), log.messages
    assert fmu.getUInt64([vr["contacts"]]) == [2]
    with pytest.raises(FMICallException):
        fmu.enterConfigurationMode()
    free(fmu)
    md, _, unzipped = fmi3_files
    fresh = FMU3Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="WheelRailFriction",
                      instanceName="fresh")
    fresh.instantiate()
    with pytest.raises(FMICallException):
        fresh.setUInt64([vr["contacts"]], [3])
    fresh.enterConfigurationMode()
    for bad in [0, 10**9]:
        with pytest.raises(FMICallException):
            fresh.setUInt64([vr["contacts"]], [bad])
    fresh.setUInt64([vr["contacts"]], [3])
    fresh.exitConfigurationMode()
    assert fresh.getUInt64([vr["contacts"]]) == [3]
    assert len(fresh.getFloat64([vr["wetness"]], 3)) == 3
    fresh.freeInstance()


@pytest.mark.parametrize("cls", [FMU3Slave, FMU3Model])
def test_a_restored_state_continues_bit_for_bit(fmi3_files, cls):
    _, vr, _ = fmi3_files
    a = fmi3_instance(fmi3_files, "a", threads=2, cls=cls)
    b = fmi3_instance(fmi3_files, "b", contacts=1, cls=cls)

    def advance(fmu, s):
        per_contact = [contact_inputs(k, s) for k in range(CONTACTS)]
        for j, name in enumerate(INPUTS):
            fmu.setFloat64([vr[name]], [per_contact[k][j] for k in range(CONTACTS)])
        if cls is FMU3Slave:
            fmu.doStep(1e-3 * s, 1e-3)
        else:
            fmu.enterContinuousTimeMode() if s == 0 else None
            fmu.setTime(1e-3 * s)
            fmu.completedIntegratorStep()
        return fmu.getFloat64([vr[n] for n in OUTPUTS], len(OUTPUTS) * CONTACTS)

    if cls is FMU3Model:
        a.updateDiscreteStates()
    advance(a, 0)
    state = a.getFMUState()
    blob = a.serializeFMUState(state)
    a.freeFMUState(state)
    restored = b.deserializeFMUState(blob)
    b.setFMUState(restored)
    b.freeFMUState(restored)
    assert b.getUInt64([vr["contacts"]]) == [CONTACTS]
    for s in range(1, 3):
        want = advance(a, s)
        assert advance(b, s) == want, f"step {s}"
    corrupt = bytearray(blob)
    corrupt[len(corrupt) // 2] ^= 0x40
    with pytest.raises(FMICallException):
        b.deserializeFMUState(bytes(corrupt))
    free(a, b)


@pytest.mark.parametrize("mode", [1, 2])
def test_derivatives_are_those_of_each_contact_and_the_adjoint_is_the_transpose(fmi3_files, fmi2_files, mode):
    _, vr3, _ = fmi3_files
    _, vr2, _ = fmi2_files
    vehicle = fmi3_instance(fmi3_files, "d", contacts=2, mode=mode)
    step3(vehicle, vr3, 0.0, 0, contacts=2)
    unknowns = ["force_longitudinal", "force_lateral"]
    knowns = ["creepage_longitudinal", "normal_force"]
    # seed: creepage_longitudinal of contact 2 and normal_force of contact 1
    seed = [0.0, 1.0, 1e3, 0.0]
    got = vehicle.getDirectionalDerivative([vr3[n] for n in unknowns], [vr3[n] for n in knowns], seed, 4)
    for k in range(2):
        single = fmi2_instance(fmi2_files, "s", mode)
        step2(single, vr2, 0.0, contact_inputs(k, 0))
        want = single.getDirectionalDerivative([vr2[n] for n in unknowns], [vr2[n] for n in knowns],
                                               [seed[k], seed[2 + k]])
        assert [got[k], got[2 + k]] == want, f"contact {k + 1}"
        free(single)
    # <w, J v> = <J^T w, v> for the same w and v
    w = [0.5, -2.0, 1.5, 0.25]
    adjoint = vehicle.getAdjointDerivative([vr3[n] for n in unknowns], [vr3[n] for n in knowns], w, 4)
    lhs = sum(a * b for a, b in zip(w, got))
    rhs = sum(a * b for a, b in zip(adjoint, seed))
    assert lhs == pytest.approx(rhs, rel=1e-12, abs=1e-9)
    free(vehicle)


def test_illegal_calls_wrong_lengths_and_nan_are_refused_and_change_nothing(fmi3_files):
    """The FMI 2.0 fuzzer's ideas at a small budget: random calls, each either allowed or refused with
    fmi3Error; refused ones leave the outputs as they were."""
    _, vr, _ = fmi3_files
    log = Log()
    fmu = fmi3_instance(fmi3_files, "fuzz", contacts=3, mode=1, log=log)
    step3(fmu, vr, 0.0, 0, contacts=3)
    outputs = [vr[n] for n in OUTPUTS]
    before = fmu.getFloat64(outputs, len(OUTPUTS) * 3)
    refusals = [
        lambda: fmu.setFloat64([vr["wetness"]], [0.5, 0.5]),  # 2 values for 3 contacts
        lambda: fmu.getFloat64([vr["force_lateral"]], 2),
        lambda: fmu.setFloat64([vr["normal_force"]], [1e5, float("nan"), 1e5]),
        lambda: fmu.setFloat64([vr["rolling_speed"]], [float("inf")] * 3),
        lambda: fmu.setFloat64([vr["force_longitudinal"]], [1.0] * 3),  # an output
        lambda: fmu.setInt32([vr["mode"]], [2]),  # fixed after initialization
        lambda: fmu.setFloat64([vr["time"]], [1.0]),
        lambda: fmu.getFloat64([123456], 1),
        lambda: fmu.getFloat32([vr["wetness"]], 3),
        lambda: fmu.exitInitializationMode(),
        lambda: fmu.fmi3EnterContinuousTimeMode(fmu.component),  # a Model Exchange function
        lambda: fmu.enterEventMode(),  # event mode not used
        lambda: fmu.setUInt64([vr["threads"]], [2]),
        lambda: fmu.getDirectionalDerivative([vr["force_lateral"]], [vr["wetness"]], [1.0, 0.0, 0.0], 2),
        lambda: fmu.doStep(0.0, -1.0),
    ]
    rng = random.Random(16)
    for _ in range(60):
        call = rng.choice(refusals)
        with pytest.raises(FMICallException):
            call()
        assert fmu.getFloat64(outputs, len(OUTPUTS) * 3) == before
    assert any("nValues = 2, but the variables hold 3 values" in m for _, m in log.messages)
    assert any("normal_force[2] = NaN is not a finite number" in m for _, m in log.messages), log.messages
    assert any("Illegal call sequence" in m for _, m in log.messages)
    # still usable: the next step is that of a fresh instance
    got = step3(fmu, vr, 1e-3, 1, contacts=3)
    fresh = fmi3_instance(fmi3_files, "fresh", contacts=3, mode=1)
    assert got == step3(fresh, vr, 1e-3, 1, contacts=3)
    free(fmu, fresh)


# Two vehicles stepped in turn on two threads each (they share the process's worker threads), as Co-Simulation
# and as Model Exchange, by table and exact, their outputs against one vehicle on one thread; the number of the library's worker threads
# (/proc/self/task/*/comm, "wheelrail worke": Linux keeps 15 characters) while they exist and after each free.
WORKERS_SCRIPT = r"""
import glob, json, sys
sys.path.insert(0, sys.argv[1])
import test_fmi3 as t
from fmpy import read_model_description

md = read_model_description(t.FMU3)
files = (md, {v.name: v.valueReference for v in md.modelVariables}, sys.argv[2])
vr = files[1]

def workers():
    return sum(open(p).read().startswith("wheelrail worke") for p in glob.glob("/proc/self/task/*/comm"))

def outputs(cls, threads, vehicles, mode):
    fmus = [t.fmi3_instance(files, f"v{v}", threads=threads, cls=cls, mode=mode, grid=WORKERS_GRID)
            for v in range(vehicles)]
    got, counts = [], [workers()]
    for s in range(4):
        for fmu in fmus:
            if cls is t.FMU3Slave:
                got.append(t.step3(fmu, vr, 1e-3 * s, s))
            else:
                if s == 0:
                    fmu.enterContinuousTimeMode()
                fmu.setTime(1e-3 * s)
                for j, name in enumerate(t.INPUTS):
                    fmu.setFloat64([vr[name]], [t.contact_inputs(k, s)[j] for k in range(t.CONTACTS)])
                got.append(fmu.getFloat64([vr[n] for n in t.OUTPUTS], len(t.OUTPUTS) * t.CONTACTS))
                fmu.completedIntegratorStep()
        counts.append(workers())
    for fmu in fmus:
        t.free(fmu)
        counts.append(workers())
    return got, counts

# a grid on which a step of the contacts takes well over the least work that is shared between threads
WORKERS_GRID = 16
runs = {f"{cls.__name__} {mode} {threads} {vehicles}": outputs(cls, threads, vehicles, mode)
        for cls in (t.FMU3Slave, t.FMU3Model) for mode in (1, 2) for threads, vehicles in ((1, 1), (2, 2))}
print(json.dumps(runs))
"""


def test_instances_in_turn_share_the_workers_which_end_with_the_last_instance_and_small_steps_need_none(fmi3_files):
    import json
    import subprocess
    import sys

    script = subprocess.run([sys.executable, "-c", WORKERS_SCRIPT, os.path.dirname(__file__), fmi3_files[2]],
                            capture_output=True, text=True, check=True)
    runs = json.loads(script.stdout)
    for kind in ("FMU3Slave", "FMU3Model"):
        # by table (a few µs per contact step): too little work to share, the caller's thread evaluates it
        one, one_counts = runs[f"{kind} 1 1 1"]
        two, two_counts = runs[f"{kind} 1 2 2"]
        assert two[0::2] == one and two[1::2] == one, kind
        assert set(one_counts) == set(two_counts) == {0}, (kind, two_counts)
        one, one_counts = runs[f"{kind} 2 1 1"]
        two, two_counts = runs[f"{kind} 2 2 2"]
        # each vehicle of the two on two threads steps as the one vehicle on one thread, bit for bit
        assert two[0::2] == one and two[1::2] == one, kind
        assert set(one_counts) == {0}, "one thread: no worker"
        # none while the contacts' step times are unknown (the first evaluation, leaving initialization mode,
        # sets them up; the first two steps measure them: all on the caller's thread); one worker from the third
        # step on, shared by the two vehicles stepped in turn; it stays while a vehicle that used it lives and
        # ends with the last one freed
        assert two_counts == [0, 0, 0, 1, 1, 1, 0], (kind, two_counts)
