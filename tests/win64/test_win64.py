"""The FMU's win64 binary on Windows (Wine), against its linux64 binary on the same machine.

`harness.c`, one FMI 2.0 master built twice (gcc for Linux, MinGW-w64 for Windows), runs the same plan of
calls against `binaries/linux64/WheelRailFriction.so` and, under Wine, `binaries/win64/WheelRailFriction.dll`,
both from the extracted FMU and each with a `file://` resource URI of its own platform (`file:///Z:/...` on
Windows), so the bundled table loads from the Windows path. The plan (built here, deterministic):

- Co-Simulation steps at more than 50 points: mode 1 (table) and 2 (exact), dry and wet, the contact
  geometry by gap curvatures and by prescribed semi-axes, spin, rolling backwards, lift-off, Kalker's exact
  theory; mode 0 (auto) across the table's coverage; `table_file` given as a Windows path;
- Model Exchange: time, inputs, outputs, directional derivatives, completed integrator steps;
- FMU states: serialized by one binary, deserialized by the other, stepped on, serialized again;
- bad inputs and illegal call sequences, then a short fuzz of random call sequences.

Checks: every call returns the same status on both platforms and logs the same number of messages of the same
statuses and categories (texts equal once each platform's paths are replaced); every integer and boolean is
equal; every Real within `EXACT_TOLERANCE` (the two C runtimes' `exp`, `log`, `pow`, `cbrt` differ in the last
bit for some arguments: a few per cent of the values by table differ by an ulp or two, at loads whose Hertz
semi-axes (a cube root) differ, and the exact solver's coupled solve carries such differences further); the
share of values equal bit for bit and the largest difference, by table and by the exact solver, are printed
and written to target/win64/comparison.json;
a state continues on the other platform as on its own and serializes back to the same bytes. The DLL's
import table names only DLLs that every Windows has, and it exports every FMI 2.0 function.

Needs: target/fmu/WheelRailFriction.fmu with both binaries (`make fmu`; override WHEELRAIL_FMU), gcc,
x86_64-w64-mingw32-gcc and x86_64-w64-mingw32-objdump, wine (`tools/win64-build.sh --install-only` installs
them). Wine starts slowly: the plan runs in three processes (Linux, Windows, Linux again for the state the
Windows binary serialized).
"""

import json
import os
import pathlib
import random
import re
import shutil
import struct
import subprocess
import time
import xml.etree.ElementTree as ET
import zipfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU = pathlib.Path(os.environ.get("WHEELRAIL_FMU", ROOT / "target" / "fmu" / "WheelRailFriction.fmu"))
REPORT = ROOT / "target" / "win64" / "comparison.json"
HERE = pathlib.Path(__file__).resolve().parent

# The largest relative difference allowed between the platforms' values of the exact solver, relative to the
# larger magnitude of the two values or, for values near zero, to the largest magnitude that output takes in
# the run: a few hundred ulps of float64, far below the solver's own tolerance (1e-6 relative), so that any
# real difference of the computation (a different code path, kernel or uninitialised value) fails.
EXACT_TOLERANCE = 1e-12

# The FMU's directional derivatives by the exact solver are forward differences with the relative step
# FD_STEP = 1e-4 (of max(|u|, nominal)): they divide the outputs' differences by it, so their platforms'
# difference is allowed to be EXACT_TOLERANCE / FD_STEP relative.
FD_STEP = 1e-4
DERIVATIVE_TOLERANCE = EXACT_TOLERANCE / FD_STEP
# the harnesses' commands that return derivatives (harness3.c's adjoint: the same differences, transposed)
DERIVATIVE_COMMANDS = ("dirder", "adjoint")

# The DLLs that every Windows (7 to 11) has; the FMU's DLL may import no other.
SYSTEM_DLLS = {"kernel32.dll", "advapi32.dll", "msvcrt.dll", "ntdll.dll", "userenv.dll", "ws2_32.dll"}

# The functions of the FMI 2.0 standard (fmi2Functions.h: common, Co-Simulation, Model Exchange).
FMI2_FUNCTIONS = """fmi2GetTypesPlatform fmi2GetVersion fmi2SetDebugLogging fmi2Instantiate fmi2FreeInstance
fmi2SetupExperiment fmi2EnterInitializationMode fmi2ExitInitializationMode fmi2Terminate fmi2Reset fmi2GetReal
fmi2GetInteger fmi2GetBoolean fmi2GetString fmi2SetReal fmi2SetInteger fmi2SetBoolean fmi2SetString
fmi2GetFMUstate fmi2SetFMUstate fmi2FreeFMUstate fmi2SerializedFMUstateSize fmi2SerializeFMUstate
fmi2DeSerializeFMUstate fmi2GetDirectionalDerivative fmi2SetRealInputDerivatives fmi2GetRealOutputDerivatives
fmi2DoStep fmi2CancelStep fmi2GetStatus fmi2GetRealStatus fmi2GetIntegerStatus fmi2GetBooleanStatus
fmi2GetStringStatus fmi2SetTime fmi2SetContinuousStates fmi2EnterEventMode fmi2NewDiscreteStates
fmi2EnterContinuousTimeMode fmi2CompletedIntegratorStep fmi2GetDerivatives fmi2GetEventIndicators
fmi2GetContinuousStates fmi2GetNominalsOfContinuousStates""".split()

ME, CS = 0, 1
FUZZ_SEQUENCES = 120
FUZZ_SEED = 37


def bits(x):
    return "%016x" % struct.unpack("<Q", struct.pack("<d", x))[0]


def real(b):
    return struct.unpack("<d", struct.pack("<Q", int(b, 16)))[0]


def hexs(s):
    if s is None:
        return "-"
    data = s if isinstance(s, bytes) else s.encode()
    return data.hex() if data else "."


def windows_path(path):
    """A Unix path as Wine shows it to Windows programs (drive Z: is the Unix root)."""
    return "Z:" + str(path).replace("/", "\\")


# --------------------------------------------------------------------------------------------------------
# fixtures


def extract_fmu(fmu, libraries, out):
    """The FMU extracted into out, which must hold both libraries."""
    if not fmu.exists():
        pytest.fail(f"{fmu} is missing: build it with `make fmu`")
    with zipfile.ZipFile(fmu) as z:
        names = z.namelist()
        for lib in libraries:
            if lib not in names:
                pytest.fail(f"{fmu} has no {lib}: build it with `make fmu` (both binaries)")
        z.extractall(out)
    return out


@pytest.fixture(scope="session")
def fmu_dir(tmp_path_factory):
    libraries = ("binaries/linux64/WheelRailFriction.so", "binaries/win64/WheelRailFriction.dll")
    return extract_fmu(FMU, libraries, tmp_path_factory.mktemp("win64-fmu"))


def tool(name):
    path = shutil.which(name)
    if not path:
        pytest.fail(f"{name} is missing: run tools/win64-build.sh --install-only (as root)")
    return path


@pytest.fixture(scope="session")
def description(fmu_dir):
    """GUID and variables (name -> (value reference, type, causality)) of the FMU's modelDescription.xml."""
    root = ET.parse(fmu_dir / "modelDescription.xml").getroot()
    variables = {}
    for v in root.iter("ScalarVariable"):
        kind = next(c.tag for c in v if c.tag in ("Real", "Integer", "Boolean", "String"))
        start = next(c for c in v if c.tag == kind).get("start")
        variables[v.get("name")] = (int(v.get("valueReference")), kind, v.get("causality"), start)
    return root.get("guid"), variables


def compile_harness(source, out):
    """A master of tests/win64 built for Linux and for Windows: the two executables."""
    flags = ["-std=c11", "-O2", "-Wall", "-Wextra", "-Werror"]
    linux, windows = out / source.stem, out / (source.stem + ".exe")
    subprocess.run([tool(os.environ.get("CC", "gcc")), *flags, "-o", linux, source, "-ldl"], check=True)
    subprocess.run([tool("x86_64-w64-mingw32-gcc"), *flags, "-static", "-o", windows, source], check=True)
    return linux, windows


@pytest.fixture(scope="session")
def harnesses(tmp_path_factory):
    return compile_harness(HERE / "harness.c", tmp_path_factory.mktemp("win64-harness"))


@pytest.fixture(scope="session")
def wine_env(tmp_path_factory):
    tool("wine")
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    # one prefix for the session (tests/win64/test_win64_fmi3.py uses this fixture too): Wine creates it once
    prefix = tmp_path_factory.getbasetemp() / "wineprefix"
    prefix.mkdir(exist_ok=True)
    env.update(
        WINEPREFIX=str(prefix),
        WINEDEBUG="-all",
        # no Mono or Gecko installers (they would ask through a window) when Wine creates the prefix
        WINEDLLOVERRIDES="mscoree,mshtml=",
    )
    yield env
    # the Wine server outlives its last program by a few seconds: stop it with the session
    subprocess.run(["wineserver", "-k"], env=env, capture_output=True)


# --------------------------------------------------------------------------------------------------------
# the plan


class Plan:
    """Lines of the harness's plan, each with what its returned values are compared by."""

    def __init__(self, description, paths):
        self.guid, self.variables = description
        self.paths = paths
        self.lines = []
        # per line: ("bits" | "close", value references of the Reals it returns or None)
        self.checks = []
        self.marks = {}

    def add(self, slot, *tokens, check="bits", vrs=None):
        self.lines.append(" ".join([str(slot), *map(str, tokens)]))
        self.checks.append((check, vrs))

    def mark(self, name, start):
        self.marks[name] = (start, len(self.lines))

    def part(self, start, end):
        """Lines start..end of the plan (with their checks) as a plan of their own."""
        sub = Plan((self.guid, self.variables), self.paths)
        sub.lines, sub.checks = self.lines[start:end], self.checks[start:end]
        return sub

    def vr(self, name):
        return self.variables[name][0]

    def of(self, kind, causality):
        return [v[0] for v in self.variables.values() if v[1] == kind and v[2] == causality]

    def set(self, slot, values):
        """Sets variables by name (Reals, Integers, Booleans, Strings), one call per type."""
        by_kind = {}
        for name, value in values.items():
            vr, kind = self.variables[name][:2]
            if kind == "Real":
                value = bits(value)
            elif kind == "String":
                value = hexs(value)
            elif kind == "Boolean":
                value = int(bool(value))
            by_kind.setdefault(kind, []).extend([vr, value])
        for kind, args in by_kind.items():
            self.add(slot, "set_" + kind.lower(), *args)

    def outputs(self, slot, check):
        reals = self.of("Real", "output")
        self.add(slot, "get_real", *reals, check=check, vrs=reals)
        self.add(slot, "get_integer", *self.of("Integer", "output"))
        self.add(slot, "get_boolean", *self.of("Boolean", "output"))

    def instantiate(self, slot, name, fmu_type, parameters, uri=None, initialize=True):
        self.add(slot, "instantiate", hexs(name), fmu_type, hexs(self.guid), hexs(uri or self.paths["uri"]), 1)
        self.set(slot, parameters)
        if initialize:
            self.add(slot, "setup", bits(0.0))
            self.add(slot, "enter_init")
            self.add(slot, "exit_init")

    def inputs(self, point):
        """A point's inputs, the geometry by curvatures (the defaults unless given) or semi-axes."""
        start = {n: float(v[3]) for n, v in self.variables.items() if v[2] == "input"}
        values = dict(start, semi_axis_a=0.0, semi_axis_b=0.0)
        values.update(point)
        return values


def table_point(rng):
    """A point inside the bundled table's ranges (default contact): creepages, spin, load, speed, wetness."""
    return {
        "creepage_longitudinal": rng.uniform(-0.02, 0.02),
        "creepage_lateral": rng.uniform(-0.01, 0.01),
        "spin_creepage": rng.uniform(-0.8, 0.8),
        "normal_force": rng.uniform(2e4, 1.8e5),
        "rolling_speed": rng.choice([1, -1]) * rng.uniform(2.0, 60.0),
        "wetness": rng.choice([0.0, 0.0, rng.uniform(0.0, 1.0), 1.0]),
    }


def table_points(rng, n):
    """Points inside the bundled table's ranges (default contact): creepages, spin, load, speed, wetness."""
    points = [table_point(rng) for _ in range(n)]
    points[1]["normal_force"] = 0.0  # lifted wheel
    points[2]["rolling_speed"] = -25.0  # rolling backwards
    return points


def exact_points(rng, n):
    """Points for the exact solver: the table's ranges, other geometries (curvatures or semi-axes)."""
    points = table_points(rng, n)
    for k, p in enumerate(points):
        if k % 3 == 1:
            p.update(curvature_longitudinal=rng.uniform(1.0, 2.5), curvature_lateral=rng.uniform(0.3, 8.0))
        elif k % 3 == 2:
            p.update(semi_axis_a=rng.uniform(4e-3, 9e-3), semi_axis_b=rng.uniform(3e-3, 1e-2))
    return points


def cs_steps(plan, slot, points, check, t0=0.0, h=1e-3):
    for k, p in enumerate(points):
        plan.set(slot, plan.inputs(p))
        plan.add(slot, "do_step", bits(t0 + k * h), bits(h))
        plan.outputs(slot, check)


TABLE_MODE = {"mode": 1}
EXACT_MODE = {"mode": 2, "grid_size": 20}
CONTINUATION = 4


def continuation_points():
    return table_points(random.Random(99), CONTINUATION)


def main_plan(description, paths):
    """Everything but the continuation of another platform's states."""
    plan = Plan(description, paths)
    rng = random.Random(7)
    plan.add(0, "versions")

    # Co-Simulation: table, exact, Kalker's exact theory, auto, a table_file given as a native path
    start = len(plan.lines)
    plan.instantiate(0, "table", CS, TABLE_MODE)
    cs_steps(plan, 0, table_points(rng, 24), "bits")
    plan.mark("table", start)
    start = len(plan.lines)
    plan.instantiate(1, "exact", CS, EXACT_MODE)
    cs_steps(plan, 1, exact_points(rng, 18), "close")
    plan.mark("exact", start)
    start = len(plan.lines)
    plan.instantiate(2, "kalker", CS, {"mode": 2, "grid_size": 12, "tangential": 1})
    cs_steps(plan, 2, exact_points(rng, 4), "close")
    plan.add(2, "free")
    plan.instantiate(2, "auto", CS, {"mode": 0, "grid_size": 12})
    cs_steps(plan, 2, exact_points(rng, 6), "close")
    plan.add(2, "free")
    plan.instantiate(2, "native-table-path", CS, {"mode": 1, "table_file": paths["table"] + ";"})
    cs_steps(plan, 2, table_points(rng, 4), "bits")
    plan.add(2, "free")
    plan.mark("other-cs", start)

    # FMU states of the table and the exact instance, then their continuation on the same instance
    start = len(plan.lines)
    for slot, name, check in ((0, "table", "bits"), (1, "exact", "close")):
        plan.add(slot, "get_state", 0)
        plan.add(slot, "serialize", 0, paths["state_out"][name])
        plan.add(slot, "free_state", 0)
        begin = len(plan.lines)
        cs_steps(plan, slot, continuation_points(), check, t0=1.0)
        plan.mark("continued-" + name, begin)
        plan.add(slot, "free")
    plan.mark("states", start)

    # Model Exchange, by table and by the exact solver
    start = len(plan.lines)
    for slot, mode, check in ((0, TABLE_MODE, "bits"), (1, EXACT_MODE, "close")):
        plan.instantiate(slot, "me", ME, mode)
        plan.add(slot, "new_discrete")
        plan.add(slot, "enter_ct")
        plan.add(slot, "get_derivatives", 0)
        knowns = [plan.vr(n) for n in ("creepage_longitudinal", "creepage_lateral", "normal_force")]
        unknowns = [plan.vr(n) for n in ("force_longitudinal", "force_lateral", "spin_moment")]
        for k, p in enumerate(table_points(rng, 6)):
            plan.add(slot, "set_time", bits(k * 1e-3))
            plan.set(slot, plan.inputs(p))
            plan.outputs(slot, check)
            for seed in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]):
                plan.add(slot, "dirder", 3, *unknowns, 3, *knowns, *map(bits, seed), check=check, vrs=unknowns)
            plan.add(slot, "completed")
        plan.add(slot, "terminate")
        plan.add(slot, "free")
    plan.mark("model-exchange", start)

    start = len(plan.lines)
    bad_inputs_and_sequences(plan)
    plan.mark("bad", start)
    start = len(plan.lines)
    fuzz(plan, random.Random(FUZZ_SEED), FUZZ_SEQUENCES)
    plan.mark("fuzz", start)
    return plan


def resume_plan(description, paths):
    """The other platform's states restored in fresh instances, serialized again and stepped on."""
    plan = Plan(description, paths)
    for slot, name, check, parameters in ((0, "table", "bits", TABLE_MODE), (1, "exact", "close", EXACT_MODE)):
        plan.instantiate(slot, name, CS, parameters, initialize=False)
        plan.add(slot, "deserialize", 0, paths["state_in"][name])
        plan.add(slot, "set_state", 0)
        plan.add(slot, "get_state", 1)
        plan.add(slot, "serialize", 1, paths["reserialized"][name])
        begin = len(plan.lines)
        cs_steps(plan, slot, continuation_points(), check, t0=1.0)
        plan.mark("continued-" + name, begin)
        plan.add(slot, "free")
    # the exact instance's continuation without its state (a cold start at the same time): what the test
    # tells the restored warm start from
    plan.instantiate(2, "cold", CS, EXACT_MODE)
    begin = len(plan.lines)
    cs_steps(plan, 2, continuation_points(), "close", t0=1.0)
    plan.mark("cold-exact", begin)
    plan.add(2, "free")
    return plan


def bad_inputs_and_sequences(plan):
    p = plan
    guid, uri = p.guid, p.paths["uri"]
    # instantiation: wrong GUID, unknown type, null name, a resource location that does not exist
    p.add(3, "instantiate", hexs("x"), CS, hexs("{00000000-0000-0000-0000-000000000000}"), hexs(uri), 1)
    p.add(3, "instantiate", hexs("x"), 7, hexs(guid), hexs(uri), 1)
    p.add(3, "instantiate", "-", CS, hexs(guid), hexs(uri), 1)
    p.instantiate(3, "missing-resources", CS, {"mode": 1}, uri=uri + "/nowhere")
    p.add(3, "do_step", bits(0.0), bits(1e-3))
    p.add(3, "free")
    # a table directory that does not exist, and one with an illegal separator, in mode 1
    p.instantiate(3, "missing-table", CS, {"mode": 1, "table_file": p.paths["table"] + "-missing"})
    p.add(3, "free")
    # calls before initialization, values out of range, NaN and infinities, wrong references
    p.instantiate(3, "bad", CS, {"mode": 2, "grid_size": 8}, initialize=False)
    p.add(3, "do_step", bits(0.0), bits(1e-3))
    p.add(3, "set_integer", p.vr("grid_size"), -3)
    p.add(3, "set_integer", p.vr("mode"), 9)
    p.add(3, "set_real", p.vr("roughness"), bits(float("nan")))
    p.add(3, "set_real", p.vr("h_f_max"), bits(-1.0))
    p.add(3, "set_real", 9999, bits(1.0))
    p.add(3, "set_real", p.vr("force_longitudinal"), bits(1.0))
    p.add(3, "get_real", 9999)
    p.add(3, "set_string", p.vr("table_file"), "-")
    p.add(3, "set_time", bits(0.0))
    p.add(3, "enter_ct")
    p.add(3, "set_integer", p.vr("mode"), 2)
    p.add(3, "set_integer", p.vr("grid_size"), 8)
    p.add(3, "setup", bits(0.0))
    p.add(3, "enter_init")
    p.add(3, "enter_init")
    p.add(3, "exit_init")
    p.add(3, "set_integer", p.vr("grid_size"), 10)  # a fixed parameter after initialization
    for name, value in (
        ("creepage_longitudinal", float("nan")),
        ("normal_force", float("inf")),
        ("rolling_speed", float("-inf")),
        ("wetness", 3.0),
        ("semi_axis_a", 5e-3),
        ("curvature_lateral", -1.0),
    ):
        p.add(3, "set_real", p.vr(name), bits(value))
        p.add(3, "do_step", bits(0.0), bits(1e-3))
        p.outputs(3, "close")
        p.set(3, p.inputs({}))
    p.add(3, "do_step", bits(0.0), bits(-1e-3))
    p.add(3, "do_step", bits(5.0), bits(1e-3))
    p.add(3, "do_step", bits(0.0), bits(float("nan")))
    p.add(3, "get_derivatives", 1)
    p.add(3, "get_event_indicators", 1)
    p.add(3, "dirder", 1, p.vr("force_longitudinal"), 1, p.vr("roughness"), bits(1.0))
    p.add(3, "get_status", 0)
    p.add(3, "get_status", 2)
    p.add(3, "get_real_status", 2)
    # corrupt FMU states: a byte flipped, the plan itself as a blob
    p.add(3, "get_state", 2)
    p.add(3, "serialize", 2, p.paths["scratch"])
    p.add(3, "flip", p.paths["scratch"], 40)
    p.add(3, "deserialize", 3, p.paths["scratch"])
    p.add(3, "deserialize", 3, p.paths["plan"])
    p.add(3, "free_state", 2)
    p.add(3, "terminate")
    p.add(3, "do_step", bits(0.0), bits(1e-3))
    p.add(3, "reset")
    p.add(3, "enter_init")
    p.add(3, "exit_init")
    p.add(3, "do_step", bits(0.0), bits(1e-3))
    p.outputs(3, "close")
    p.add(3, "new_discrete")  # Model Exchange only
    p.add(3, "free")
    for function in ("fmi2DoStep", "fmi2GetReal", "fmi2EnterInitializationMode", "fmi2Terminate", "fmi2FreeInstance"):
        p.add(3, "null", function)


def fuzz(plan, rng, sequences):
    """Random call sequences on two instances: legal life cycles mostly, illegal orders and values often."""
    p = plan
    specials = [0.0, -0.0, 1e-3, -0.05, 2.0, 1e5, -1.0, 1e300, 5e-324, float("nan"), float("inf"), float("-inf")]
    real_inputs = [n for n, v in p.variables.items() if v[2] == "input"]
    outputs = p.of("Real", "output")
    for _ in range(sequences):
        # most sequences start from a legal life cycle up to the first communication point, on either slot
        if rng.random() < 0.7:
            slot = rng.randint(0, 1)
            kind = rng.choice([CS, CS, CS, ME])
            p.instantiate(slot, "fuzz", kind, {"mode": rng.choice([0, 1, 2]), "grid_size": rng.choice([6, 8])})
        for _ in range(rng.randint(3, 30)):
            slot = rng.randint(0, 1)
            r = rng.random()
            if r < 0.10:
                kind = rng.choice([CS, CS, CS, ME])
                uri = p.paths["uri"] if rng.random() < 0.9 else p.paths["uri"] + "/x"
                guid = p.guid if rng.random() < 0.95 else "{bad}"
                p.add(slot, "instantiate", hexs("fuzz"), kind, hexs(guid), hexs(uri), rng.randint(0, 1))
            elif r < 0.18:
                p.set(slot, {"mode": rng.choice([0, 1, 2, 2, 3, -1]), "grid_size": rng.choice([6, 8, 10, -2])})
            elif r < 0.21:
                # no native paths here: a path's length differs between the platforms and so would the size
                # of the serialized states that hold it (the native path is tested above)
                table = rng.choice(["", "no-such-table", "%s%n%d", ";", "no-such-table;"])
                p.add(slot, "set_string", p.vr("table_file"), hexs(table))
            elif r < 0.36:
                name = rng.choice(real_inputs)
                value = rng.choice(specials) if rng.random() < 0.15 else rng.uniform(-0.01, 0.01)
                p.add(slot, "set_real", p.vr(name), bits(value))
            elif r < 0.40:
                p.add(slot, rng.choice(["setup", "set_time"]), bits(rng.choice([0.0, 1.0, float("nan")])))
            elif r < 0.48:
                p.add(slot, rng.choice(["enter_init", "exit_init", "terminate", "reset", "enter_ct",
                                        "enter_event", "new_discrete", "completed", "cancel_step"]))
            elif r < 0.62:
                h = rng.choice([1e-3, 1e-3, 0.0, -1e-3, float("nan")])
                p.add(slot, "do_step", bits(rng.choice([0.0, 0.001, 1.0])), bits(h))
            elif r < 0.74:
                p.outputs(slot, "close")
            elif r < 0.80:
                p.add(slot, "dirder", 1, rng.choice(outputs), 1, p.vr(rng.choice(real_inputs)), bits(1.0),
                      check="close", vrs=[None])
            elif r < 0.90:
                k = rng.randint(0, 1)
                op = rng.choice(["get_state", "set_state", "free_state", "serialize", "deserialize"])
                if op in ("serialize", "deserialize"):
                    p.add(slot, op, k, p.paths["fuzz_state"])
                else:
                    p.add(slot, op, k)
            elif r < 0.93:
                p.add(slot, "get_status", rng.randint(0, 4))
            elif r < 0.96:
                p.add(slot, "debug_logging", rng.randint(0, 1), hexs(rng.choice(["logAll", "logStatusError", "nope"])))
            else:
                p.add(slot, "free")
        for slot in (0, 1):
            p.add(slot, "free")


# --------------------------------------------------------------------------------------------------------
# running and comparing


def parse(out):
    """The harness's output: per plan line, (status, returned values, log lines)."""
    results, logs = [], []
    for line in out.splitlines():
        kind, _, rest = line.partition(" ")
        if kind == "L":
            status, category, text = rest.split(" ")
            logs.append((int(status), bytes.fromhex(category) if category != "." else b"",
                         bytes.fromhex(text) if text != "." else b""))
        elif kind == "R":
            tokens = rest.split()
            results.append((int(tokens[1]), tokens[2:], logs))
            logs = []
        elif kind == "E":
            raise AssertionError(f"the harness stopped: {rest}")
    return results


def run(command, plan, plan_path, env=None):
    plan_path.write_text("\n".join(plan.lines) + "\n")
    started = time.monotonic()
    proc = subprocess.run(command, capture_output=True, env=env, timeout=1800)
    seconds = time.monotonic() - started
    results = parse(proc.stdout.decode())
    if proc.returncode != 0 or len(results) != len(plan.lines):
        last = plan.lines[len(results)] if len(results) < len(plan.lines) else "(none)"
        raise AssertionError(
            f"{command[0]} exited with {proc.returncode} after {len(results)} of {len(plan.lines)} calls; "
            f"next call: {last}\nstderr: {proc.stderr.decode()[-2000:]}"
        )
    return results, seconds


@pytest.fixture(scope="session")
def runs(fmu_dir, description, harnesses, wine_env, tmp_path_factory):
    work = tmp_path_factory.mktemp("win64-run")

    def paths(tag, other, native, uri):
        """The files of one platform's run, as that platform names them."""
        return {
            "uri": uri,
            "table": native(fmu_dir / "resources" / "table"),
            "state_out": {n: native(work / f"{tag}-{n}.state") for n in ("table", "exact")},
            "state_in": {n: native(work / f"{other}-{n}.state") for n in ("table", "exact")},
            "reserialized": {n: native(work / f"{tag}-{n}-again.state") for n in ("table", "exact")},
            "scratch": native(work / f"{tag}-scratch.state"),
            "fuzz_state": native(work / f"{tag}-fuzz.state"),
            "plan": native(work / f"{tag}-plan.txt"),
        }

    linux_paths = paths("linux", "windows", str, "file://" + str(fmu_dir / "resources"))
    windows_uri = "file:///" + windows_path(fmu_dir / "resources").replace("\\", "/")
    windows_paths = paths("windows", "linux", windows_path, windows_uri)

    so = str(fmu_dir / "binaries" / "linux64" / "WheelRailFriction.so")
    dll = windows_path(fmu_dir / "binaries" / "win64" / "WheelRailFriction.dll")

    plans = [(main_plan(description, p), resume_plan(description, p)) for p in (linux_paths, windows_paths)]
    return dict(run_on_both(harnesses, (so, dll), plans, work, wine_env), work=work,
                paths=(linux_paths, windows_paths))


def run_on_both(harnesses, libraries, plans, work, wine_env):
    """Each platform's (main plan, resume plan) in three processes (Wine starts slowly): the main plan on
    Linux, under Wine the main plan and the resume plan (the states Linux wrote), the resume plan on Linux
    (the states Windows wrote). Per plan, the Windows plan and both runs' results; the run times."""
    (linux_harness, windows_harness), (so, dll) = harnesses, libraries
    (linux_main, linux_resume), (windows_main, windows_resume) = plans
    windows_plan = Plan(("", {}), windows_main.paths)
    windows_plan.lines = windows_main.lines + windows_resume.lines
    plan_file = work / "linux-plan.txt"
    linux_out, linux_s = run([str(linux_harness), so, str(plan_file)], linux_main, plan_file)
    plan_file = work / "windows-plan.txt"
    windows_out, windows_s = run(["wine", str(windows_harness), dll, windows_path(plan_file)], windows_plan,
                                 plan_file, env=wine_env)
    plan_file = work / "linux-resume.txt"
    linux_resume_out, _ = run([str(linux_harness), so, str(plan_file)], linux_resume, plan_file)
    n = len(windows_main.lines)
    return {
        "main": (windows_main, linux_out, windows_out[:n]),
        "resume": (windows_resume, linux_resume_out, windows_out[n:]),
        "seconds": {"linux": linux_s, "windows (wine)": windows_s},
    }


def normalise(text, paths):
    """A log text with the platform's own paths replaced by their role."""
    # canonical Windows paths carry the verbatim prefix \\?\ (in Rust's debug format of a path, which
    # doubles each backslash, \\\\?\\)
    s = text.decode("utf-8", "replace").replace("\\\\\\\\?\\\\", "").replace("\\\\?\\", "")
    s = s.replace("\\\\", "\\")
    # Windows paths as Unix paths: Z:\tmp\x and Z:/tmp/x are /tmp/x
    s = re.sub(r"\bZ:/", "/", s.replace("\\", "/")).replace("//?/", "")
    names = []
    for role, value in paths.items():
        names += [(f"{role}.{k}", v) for k, v in value.items()] if isinstance(value, dict) else [(role, value)]
    for role, value in sorted(names, key=lambda x: -len(x[1])):
        s = s.replace(re.sub(r"\bZ:/", "/", value.replace("\\", "/")), f"<{role}>")
    # the operating system's own error texts differ ("No such file or directory" / "The system cannot find
    # the path specified."): keep the project's part of the message
    return re.sub(r":? ?[^:(]*\(os error \d+\)", " <os error>", s)


def compare(plan, linux, windows, paths):
    """Statuses, logs and values of two runs of the plan; returns the differences found and the statistics."""
    problems = []
    scale = {}
    for (check, vrs), (_, values, _) in zip(plan.checks, linux):
        if vrs:
            for vr, b in zip(vrs, values):
                scale[vr] = max(scale.get(vr, 0.0), abs(real(b)) if real(b) == real(b) else 0.0)
    stats = {
        how: {"values": 0, "bit_identical": 0, "largest_relative_difference": 0.0, "where": None}
        for how in ("table", "exact", "exact derivatives")
    }
    for k, ((check, vrs), (s_l, v_l, log_l), (s_w, v_w, log_w)) in enumerate(zip(plan.checks, linux, windows)):
        line = plan.lines[k]
        if s_l != s_w:
            problems.append(f"line {k + 1} `{line[:100]}`: status {s_l} on Linux, {s_w} on Windows")
            continue
        if [(s, c) for s, c, _ in log_l] != [(s, c) for s, c, _ in log_w]:
            problems.append(f"line {k + 1} `{line[:100]}`: logs differ: {log_l} / {log_w}")
            continue
        for (_, _, a), (_, _, b) in zip(log_l, log_w):
            if normalise(a, paths[0]) != normalise(b, paths[1]):
                problems.append(f"line {k + 1}: log texts differ:\n  {normalise(a, paths[0])}\n  {normalise(b, paths[1])}")
        if len(v_l) != len(v_w):
            problems.append(f"line {k + 1} `{line[:100]}`: {len(v_l)} values on Linux, {len(v_w)} on Windows")
            continue
        for j, (a, b) in enumerate(zip(v_l, v_w)):
            if vrs is None or len(a) != 16:
                if a != b:
                    problems.append(f"line {k + 1} `{line[:100]}`: value {j}: {a} / {b}")
                continue
            derivative = line.split()[1] in DERIVATIVE_COMMANDS
            how = "table" if check == "bits" else "exact derivatives" if derivative else "exact"
            st = stats[how]
            st["values"] += 1
            if a == b:
                st["bit_identical"] += 1
                continue
            x, y = real(a), real(b)
            floor = scale.get(vrs[j], 0.0) if vrs[j] is not None else 0.0
            rel = abs(x - y) / max(abs(x), abs(y), floor, 1e-300) if x == x and y == y else float("inf")
            if rel > st["largest_relative_difference"]:
                st["largest_relative_difference"], st["where"] = rel, f"line {k + 1} value {j}: {line[:70]}"
            if rel > (DERIVATIVE_TOLERANCE if derivative else EXACT_TOLERANCE):
                problems.append(f"line {k + 1} `{line[:100]}`: value {j}: {x!r} / {y!r}, relative {rel:.2e}")
    return problems, stats


def report(key, value):
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    data = json.loads(REPORT.read_text()) if REPORT.exists() else {}
    data[key] = value
    REPORT.write_text(json.dumps(data, indent=2) + "\n")
    print(f"win64 {key}: {json.dumps(value)}")


# --------------------------------------------------------------------------------------------------------
# tests


def test_dll_imports_only_system_dlls(fmu_dir):
    dll = fmu_dir / "binaries" / "win64" / "WheelRailFriction.dll"
    dump = subprocess.run([tool("x86_64-w64-mingw32-objdump"), "-p", dll], check=True, capture_output=True,
                          text=True).stdout
    imported = {m.lower() for m in re.findall(r"DLL Name: (\S+)", dump)}
    assert imported, "no import table found"
    assert imported <= SYSTEM_DLLS, f"the DLL imports {sorted(imported - SYSTEM_DLLS)} beyond the system DLLs"
    exported = set(re.findall(r"\]\s+(fmi2\w+)", dump))
    assert set(FMI2_FUNCTIONS) <= exported, f"not exported: {sorted(set(FMI2_FUNCTIONS) - exported)}"
    report("dll", {"bytes": dll.stat().st_size, "imports": sorted(imported)})


def test_same_calls_same_results(runs):
    plan, linux, windows = runs["main"]
    problems, stats = compare(plan, linux, windows, runs["paths"])
    sections = {name: b - a for name, (a, b) in plan.marks.items()}
    report("calls", {"lines": len(plan.lines), "sections": sections, "seconds": runs["seconds"], **stats})
    assert not problems, f"{len(problems)} differences:\n" + "\n".join(problems[:40])
    # the plan exercises what it says: points by table and by the exact solver, successful steps
    modes = [int(v[0]) for (s, v, _), line in zip(linux, plan.lines) if line.split()[1] == "get_integer" and s <= 1]
    assert modes.count(1) >= 30 and modes.count(2) >= 30, f"evaluation modes seen: {sorted(set(modes))}"


def test_bundled_table_loads_from_the_windows_path(runs):
    plan, _, windows = runs["main"]
    a, b = plan.marks["table"]
    statuses = [windows[k][0] for k in range(a, b)]
    assert all(s == 0 for s in statuses), "a table-mode call failed under Windows"
    modes = [windows[k][1] for k in range(a, b) if plan.lines[k].split()[1] == "get_integer"]
    assert modes and all(m == ["1"] for m in modes), f"not evaluated by table: {modes}"


def test_states_cross_platforms(runs):
    (linux_paths, windows_paths) = runs["paths"]
    main, linux_main, windows_main = runs["main"]
    resume, linux_resume, windows_resume = runs["resume"]
    assert all(s == 0 for s, _, _ in linux_resume) and all(s == 0 for s, _, _ in windows_resume)
    for name in ("table", "exact"):
        # serialized again after restoring: the same bytes as the other platform wrote
        for written, again in ((linux_paths["state_out"][name], windows_paths["reserialized"][name]),
                               (windows_paths["state_out"][name], linux_paths["reserialized"][name])):
            again = again.replace("Z:", "").replace("\\", "/")
            written = written.replace("Z:", "").replace("\\", "/")
            assert pathlib.Path(written).read_bytes() == pathlib.Path(again).read_bytes(), (written, again)
        # continued on the other platform as on the platform that wrote the state
        (a, b), (c, d) = main.marks["continued-" + name], resume.marks["continued-" + name]
        sub = main.part(a, b)
        assert [line.split()[1:] for line in resume.lines[c:d]] == [line.split()[1:] for line in sub.lines]
        for direction, own, restored, paths in (
            ("linux-to-windows", linux_main[a:b], windows_resume[c:d], (linux_paths, windows_paths)),
            ("windows-to-linux", windows_main[a:b], linux_resume[c:d], (windows_paths, linux_paths)),
        ):
            problems, stats = compare(sub, own, restored, paths)
            assert not problems, "\n".join(problems[:20])
            report(f"state-{name}-{direction}", stats["table" if name == "table" else "exact"])
    # the restored warm start matters: without it the exact solver's outputs differ by more than the tolerance
    (a, b), (c, d) = resume.marks["continued-exact"], resume.marks["cold-exact"]
    sub = resume.part(a, b)
    problems, _ = compare(sub, linux_resume[a:b], linux_resume[c:d], (linux_paths, linux_paths))
    assert problems, "a cold start continued as the restored state did: the test cannot tell them apart"
