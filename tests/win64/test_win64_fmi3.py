"""The FMI 3.0 functions of the FMU's win64 binary on Windows (Wine), against its linux64 binary.

`harness3.c`, one FMI 3.0 master built twice (gcc for Linux, MinGW-w64 for Windows), runs the same plan of
calls against `binaries/x86_64-linux/WheelRailFriction.so` and, under Wine,
`binaries/x86_64-windows/WheelRailFriction.dll` of the FMI 3.0 FMU, each with the resource path of its own
platform. The plan (built here, deterministic):

- Co-Simulation instances of 4 contacts (`contacts` set in configuration mode), each contact its own inputs,
  12 steps by table (mode 1) and by the exact solver (mode 2, other geometries among the contacts), each on
  1, 2 and 0 (the cores) `threads`;
- two instances on 2 threads stepped in turn (they share the process's worker threads), freed; then a new
  instance on 2 threads (the workers started again), with the threads of the process counted in between;
- Model Exchange instances of 2 contacts: outputs after time and inputs, directional and adjoint derivatives;
- FMU states serialized by one binary, deserialized by the other, stepped on, serialized again;
- bad calls: `contacts` outside configuration mode, wrong numbers of values, NaN, calls in the wrong state,
  a corrupt FMU state, null instances.

Checks: as tests/win64/test_win64.py, by its `compare` (statuses, logs, values within EXACT_TOLERANCE: the
two C runtimes' `exp`, `cbrt`, `pow` … differ in the last bit for some arguments, so also values by table,
whose Hertz semi-axes take a `cbrt`, differ by an ulp at some points); on each platform, 2 and 0 threads
give the bits of 1 thread, and so do instances that share the worker threads, also on a host whose x87
precision is not the one the DLL computes with (the MinGW-built master: see fmu/src/fmi2/x87.rs); the
workers end with the last instance that used them; a state continues on the other platform as on its own
and serializes back to the same bytes; bad calls return the same errors on both platforms and change no
output; the DLL exports every function of fmi3Functions.h (the list of tests/fmu/fmi3.rs).

Needs: target/fmu/WheelRailFriction-fmi3.fmu with both binaries (`make fmu`; override WHEELRAIL_FMU3) and the
tools of test_win64.py. The plan runs in three processes (Linux, Windows, Linux again for the states the
Windows binary serialized).
"""

import os
import pathlib
import random
import re
import subprocess
import xml.etree.ElementTree as ET

import pytest
from test_win64 import (
    HERE,
    ROOT,
    Plan,
    bits,
    compare,
    compile_harness,
    extract_fmu,
    hexs,
    report,
    run_on_both,
    table_point,
    tool,
    wine_env,  # noqa: F401 (a fixture: the session's Wine prefix, shared with test_win64.py)
    windows_path,
)

FMU3 = pathlib.Path(os.environ.get("WHEELRAIL_FMU3", ROOT / "target" / "fmu" / "WheelRailFriction-fmi3.fmu"))
LINUX_LIBRARY = "binaries/x86_64-linux/WheelRailFriction.so"
WINDOWS_LIBRARY = "binaries/x86_64-windows/WheelRailFriction.dll"
# The functions of fmi3Functions.h, listed once, by the Rust test of the exports.
FMI3_LIST = ROOT / "tests" / "fmu" / "fmi3.rs"

CONTACTS = 4
STEPS = 12
# Steps of the instances that share the worker threads, and of a state's continuation.
POOL_STEPS = 6
CONTINUATION = 4
THREADS = (1, 2, 0)
# mode name: (parameters, how its values are compared, whether the contacts differ in geometry)
MODES = {
    "table": ({"mode": 1, "grid_size": 0}, "bits", False),
    "exact": ({"mode": 2, "grid_size": 12}, "close", True),
}
OK, ERROR = 0, 3
# the harness's status of an instantiate function that returned null
NULL_INSTANCE = 3
# The x87 control word of the Windows x64 calling convention (fmu/src/fmi2/x87.rs: STANDARD), with which the
# DLL computes: the Windows master (built with MinGW-w64) runs with another (64-bit precision), so that the
# tests of threads see whether the contacts a worker evaluates come out as those of the host's thread.
STANDARD_X87 = 0x027F
KINDS = {"Float64": "float64", "Int32": "int32", "Boolean": "boolean", "String": "string", "UInt64": "uint64"}


def fmi3_functions():
    """The names of tests/fmu/fmi3.rs's FMI3_FUNCTIONS, checked against the length it declares."""
    text = FMI3_LIST.read_text()
    declared, body = re.search(r"const FMI3_FUNCTIONS: \[&str; (\d+)\] = \[(.*?)\];", text, re.S).groups()
    names = re.findall(r'"(fmi3\w+)"', body)
    assert len(names) == int(declared), f"{FMI3_LIST}: {len(names)} names, {declared} declared"
    return names


def encode(kind, value):
    if kind == "Float64":
        return bits(value)
    return hexs(value) if kind == "String" else int(value)


class Plan3(Plan):
    """A plan of harness3.c's calls: lines tagged by what the tests compare, and the statuses expected."""

    def __init__(self, description, paths):
        super().__init__(description, paths)
        self.tags = {}
        self.expected = {}

    def add(self, slot, *tokens, check="bits", vrs=None, expect=None, tag=None):
        if expect is not None:
            self.expected[len(self.lines)] = expect
        if tag is not None:
            self.tags.setdefault(tag, []).append(len(self.lines))
        super().add(slot, *tokens, check=check, vrs=vrs)

    def set(self, slot, values, expect=None, tag=None):
        """Sets variables by name (a value, or a list of values over the contacts), one call per type."""
        by_kind = {}
        for name, value in values.items():
            vr, kind = self.variables[name][:2]
            vrs, flat = by_kind.setdefault(kind, ([], []))
            vrs.append(vr)
            flat += [encode(kind, x) for x in (value if isinstance(value, list) else [value])]
        for kind, (vrs, flat) in by_kind.items():
            self.add(slot, "set_" + KINDS[kind], len(vrs), *vrs, len(flat), *flat, expect=expect, tag=tag)

    def outputs(self, slot, check, contacts, tag=None):
        reals = self.of("Float64", "output")
        per_value = [vr for vr in reals for _ in range(contacts)]
        self.add(slot, "get_float64", len(per_value), *reals, check=check, vrs=per_value, tag=tag)
        self.add(slot, "get_int32", contacts, self.vr("evaluation_mode"), tag=tag)
        self.add(slot, "get_boolean", contacts, self.vr("converged"), tag=tag)

    def instantiate(self, slot, name, contacts=None, parameters=(), model_exchange=False, initialize=True):
        """An instance of `contacts` (None: not configured), its parameters set, initialized."""
        resources = hexs(self.paths["resources"])
        if model_exchange:
            self.add(slot, "instantiate_me", hexs(name), hexs(self.guid), resources, 1)
        else:
            self.add(slot, "instantiate_cs", hexs(name), hexs(self.guid), resources, 1, 0)
        if contacts is not None:
            self.add(slot, "enter_config")
            self.set(slot, {"contacts": contacts})
            self.add(slot, "exit_config")
        self.set(slot, dict(parameters))
        if initialize:
            self.add(slot, "enter_init", bits(0.0))
            self.add(slot, "exit_init")

    def count_threads(self, tag):
        self.add(0, "process_threads", tag=tag)


def contact_points(plan, rng, contacts, geometry):
    """A point of each contact inside the bundled table's ranges; with `geometry`, the second contact of
    other gap curvatures and the third of prescribed semi-axes."""
    points = [plan.inputs(table_point(rng)) for _ in range(contacts)]
    if geometry:
        points[1].update(curvature_longitudinal=rng.uniform(1.0, 2.5), curvature_lateral=rng.uniform(0.3, 8.0))
        points[2].update(semi_axis_a=rng.uniform(4e-3, 9e-3), semi_axis_b=rng.uniform(3e-3, 1e-2))
    return points


def inputs_of(plan, mode, steps, contacts=CONTACTS, seed=11):
    """The inputs of a mode's steps (the same for every run of the mode), as arrays over the contacts: each
    contact moves from one point to another on a straight line, as a vehicle's contacts change from step to
    step (its speed and wetness those of the first point)."""
    rng = random.Random(seed)
    first, last = (contact_points(plan, rng, contacts, MODES[mode][2]) for _ in range(2))
    for a, b in zip(first, last):
        b.update(rolling_speed=a["rolling_speed"], wetness=a["wetness"])
    return [
        {name: [a[name] + (b[name] - a[name]) * k / (steps - 1) for a, b in zip(first, last)] for name in first[0]}
        for k in range(steps)
    ]


def vehicle_steps(plan, slot, inputs, check, tag, contacts=CONTACTS, t0=0.0, h=1e-3):
    for k, values in enumerate(inputs):
        plan.set(slot, values, tag=tag)
        plan.add(slot, "do_step", bits(t0 + k * h), bits(h), tag=tag)
        plan.outputs(slot, check, contacts, tag=tag)


def main_plan(description, paths):
    """Everything but the continuation of the other platform's states."""
    plan = Plan3(description, paths)
    plan.add(0, "version")
    plan.add(0, "x87_control_word", tag="x87")
    steps = {mode: inputs_of(plan, mode, STEPS) for mode in MODES}

    # each mode on 1, 2 and 0 threads
    start = len(plan.lines)
    for mode, (parameters, check, _) in MODES.items():
        for threads in THREADS:
            plan.instantiate(0, f"{mode}-{threads}", CONTACTS, dict(parameters, threads=threads))
            vehicle_steps(plan, 0, steps[mode], check, f"{mode}-threads{threads}")
            plan.add(0, "free")
    plan.mark("threads", start)
    plan.add(0, "x87_control_word", tag="x87")

    # two instances on 2 threads stepped in turn, freed; a new one: the workers end and start again
    start = len(plan.lines)
    plan.count_threads("threads-before")
    for slot, mode in enumerate(MODES):
        plan.instantiate(slot, f"shared-{mode}", CONTACTS, dict(MODES[mode][0], threads=2))
    for k in range(POOL_STEPS):
        for slot, mode in enumerate(MODES):
            vehicle_steps(plan, slot, steps[mode][k : k + 1], MODES[mode][1], f"shared-{mode}", t0=k * 1e-3)
    plan.count_threads("threads-shared")
    plan.add(0, "free")
    plan.count_threads("threads-one-freed")
    plan.add(1, "free")
    plan.count_threads("threads-all-freed")
    plan.instantiate(2, "again", CONTACTS, dict(MODES["exact"][0], threads=2))
    vehicle_steps(plan, 2, steps["exact"][:POOL_STEPS], "close", "again-exact")
    plan.count_threads("threads-again")
    plan.add(2, "free")
    plan.count_threads("threads-end")
    plan.mark("shared-workers", start)

    # Model Exchange: outputs, directional and adjoint derivatives of 2 contacts
    start = len(plan.lines)
    unknowns = [plan.vr(n) for n in ("force_longitudinal", "force_lateral")]
    knowns = [plan.vr(n) for n in ("creepage_longitudinal", "normal_force")]
    for mode, (parameters, check, _) in MODES.items():
        plan.instantiate(0, f"me-{mode}", 2, parameters, model_exchange=True)
        plan.add(0, "update_discrete")
        plan.add(0, "enter_ct")
        for k, values in enumerate(inputs_of(plan, "table", 3, contacts=2, seed=5)):
            plan.add(0, "set_time", bits(k * 1e-3))
            plan.set(0, values)
            plan.outputs(0, check, 2)
            # seeds: creepage_longitudinal of contact 2 and normal_force of contact 1; a weight per output
            plan.add(0, "dirder", 2, *unknowns, 2, *knowns, 4, *map(bits, [0.0, 1.0, 1e3, 0.0]), 4, check=check,
                     vrs=[vr for vr in unknowns for _ in range(2)])
            plan.add(0, "adjoint", 2, *unknowns, 2, *knowns, 4, *map(bits, [0.5, -2.0, 1.5, 0.25]), 4,
                     check=check, vrs=[vr for vr in knowns for _ in range(2)])
            plan.add(0, "completed")
        plan.add(0, "terminate")
        plan.add(0, "free")
    plan.mark("model-exchange", start)

    # FMU states on 2 threads, serialized after 4 steps, then this platform's own continuation
    start = len(plan.lines)
    for mode, (parameters, check, _) in MODES.items():
        plan.instantiate(0, f"state-{mode}", CONTACTS, dict(parameters, threads=2))
        vehicle_steps(plan, 0, steps[mode][:CONTINUATION], check, None)
        plan.add(0, "get_state", 0)
        plan.add(0, "serialize", 0, paths["state_out"][mode])
        plan.add(0, "free_state", 0)
        vehicle_steps(plan, 0, steps[mode][CONTINUATION : 2 * CONTINUATION], check, f"continued-{mode}", t0=1.0)
        plan.add(0, "free")
    plan.mark("states", start)

    start = len(plan.lines)
    bad_calls(plan)
    plan.mark("bad", start)
    return plan


def resume_plan(description, paths):
    """The other platform's states restored in instances that were not configured, serialized again and
    stepped on; an exact instance's continuation from a cold start."""
    plan = Plan3(description, paths)
    steps = {mode: inputs_of(plan, mode, STEPS)[CONTINUATION : 2 * CONTINUATION] for mode in MODES}
    for mode, (_, check, _) in MODES.items():
        plan.instantiate(0, f"resumed-{mode}", initialize=False)
        plan.add(0, "deserialize", 0, paths["state_in"][mode])
        plan.add(0, "set_state", 0)
        plan.add(0, "get_state", 1)
        plan.add(0, "serialize", 1, paths["reserialized"][mode])
        plan.add(0, "free_state", 0)
        plan.add(0, "free_state", 1)
        vehicle_steps(plan, 0, steps[mode], check, f"continued-{mode}", t0=1.0)
        plan.add(0, "free")
    plan.instantiate(1, "cold", CONTACTS, dict(MODES["exact"][0], threads=2))
    vehicle_steps(plan, 1, steps["exact"], "close", "cold-exact", t0=1.0)
    plan.add(1, "free")
    return plan


def bad_calls(plan):
    p = plan
    token, resources = hexs(p.guid), hexs(p.paths["resources"])
    contacts = p.vr("contacts")
    p.add(3, "instantiate_cs", hexs("x"), hexs("{00000000-0000-0000-0000-000000000000}"), resources, 1, 0,
          expect=NULL_INSTANCE)
    p.add(3, "instantiate_cs", "-", token, resources, 1, 0, expect=NULL_INSTANCE)
    p.add(3, "instantiate_cs", hexs("bad"), token, resources, 1, 0, expect=OK)
    p.set(3, {"contacts": 3}, expect=ERROR)  # outside configuration mode
    p.add(3, "do_step", bits(0.0), bits(1e-3), expect=ERROR)  # before initialization
    p.add(3, "enter_config", expect=OK)
    p.set(3, {"contacts": 0}, expect=ERROR)
    p.set(3, {"contacts": 10**9}, expect=ERROR)
    p.add(3, "set_uint64", 1, contacts, 2, 3, 3, expect=ERROR)  # two values for a scalar
    p.set(3, {"contacts": 3}, expect=OK)
    p.add(3, "exit_config", expect=OK)
    p.add(3, "exit_config", expect=ERROR)
    p.set(3, {"threads": 2, "mode": 1, "grid_size": 0}, expect=OK)
    p.add(3, "enter_init", bits(0.0), expect=OK)
    p.set(3, {"contacts": 4}, expect=ERROR)  # in initialization mode
    p.add(3, "exit_init", expect=OK)
    p.add(3, "enter_config", expect=ERROR)  # after initialization
    p.set(3, {"threads": 1}, expect=ERROR)  # fixed after initialization
    p.set(3, inputs_of(p, "table", 2, contacts=3, seed=3)[0], expect=OK)
    p.add(3, "do_step", bits(0.0), bits(1e-3), expect=OK)
    p.outputs(3, "bits", 3, tag="bad-before")
    wetness, normal_force = p.vr("wetness"), p.vr("normal_force")
    for tokens in (
        ("set_float64", 1, wetness, 2, bits(0.5), bits(0.5)),  # 2 values for 3 contacts
        ("set_float64", 1, wetness, 4, *[bits(0.5)] * 4),
        ("get_float64", 2, p.vr("force_lateral")),
        ("set_float64", 1, normal_force, 3, bits(1e5), bits(float("nan")), bits(1e5)),
        ("set_float64", 1, p.vr("rolling_speed"), 3, *[bits(float("inf"))] * 3),
        ("set_float64", 1, p.vr("force_longitudinal"), 3, *[bits(1.0)] * 3),  # an output
        ("get_float64", 1, 123456),
        ("set_int32", 1, p.vr("mode"), 1, 2),  # fixed after initialization
        ("enter_ct",),  # a Model Exchange function
        ("enter_event",),  # event mode not used
        ("exit_init",),
        ("dirder", 1, p.vr("force_lateral"), 1, wetness, 2, *[bits(1.0)] * 2, 3),  # 2 seeds for 3 contacts
        ("do_step", bits(1e-3), bits(-1e-3)),
        ("do_step", bits(1e-3), bits(float("nan"))),
    ):
        p.add(3, *tokens, expect=ERROR)
    p.outputs(3, "bits", 3, tag="bad-after")
    # a corrupt FMU state
    p.add(3, "get_state", 2, expect=OK)
    p.add(3, "serialize", 2, p.paths["scratch"], expect=OK)
    p.add(3, "flip", p.paths["scratch"], 40, expect=OK)
    p.add(3, "deserialize", 3, p.paths["scratch"], expect=ERROR)
    p.add(3, "free_state", 2, expect=OK)
    p.add(3, "terminate", expect=OK)
    p.add(3, "do_step", bits(1e-3), bits(1e-3), expect=ERROR)
    p.add(3, "reset", expect=OK)
    p.add(3, "free")
    for function in ("fmi3DoStep", "fmi3GetFloat64", "fmi3EnterInitializationMode", "fmi3Terminate",
                     "fmi3ExitConfigurationMode", "fmi3GetFMUState"):
        p.add(3, "null", function, expect=ERROR)
    p.add(3, "null", "fmi3FreeInstance", expect=OK)


# --------------------------------------------------------------------------------------------------------
# fixtures


@pytest.fixture(scope="session")
def fmu3_dir(tmp_path_factory):
    return extract_fmu(FMU3, (LINUX_LIBRARY, WINDOWS_LIBRARY), tmp_path_factory.mktemp("win64-fmu3"))


@pytest.fixture(scope="session")
def description3(fmu3_dir):
    """The instantiation token and the variables (name -> (value reference, type, causality, start))."""
    root = ET.parse(fmu3_dir / "modelDescription.xml").getroot()
    variables = {
        v.get("name"): (int(v.get("valueReference")), v.tag, v.get("causality"), v.get("start"))
        for v in root.find("ModelVariables")
    }
    return root.get("instantiationToken"), variables


@pytest.fixture(scope="session")
def runs3(fmu3_dir, description3, wine_env, tmp_path_factory):  # noqa: F811 (wine_env: the fixture)
    work = tmp_path_factory.mktemp("win64-fmi3-run")

    def paths(tag, other, native, separator):
        """The files of one platform's run, as that platform names them."""
        return {
            "resources": native(fmu3_dir / "resources") + separator,
            "state_out": {m: native(work / f"{tag}-{m}.state") for m in MODES},
            "state_in": {m: native(work / f"{other}-{m}.state") for m in MODES},
            "reserialized": {m: native(work / f"{tag}-{m}-again.state") for m in MODES},
            "scratch": native(work / f"{tag}-scratch.state"),
        }

    linux_paths = paths("linux", "windows", str, "/")
    windows_paths = paths("windows", "linux", windows_path, "\\")
    so = str(fmu3_dir / LINUX_LIBRARY)
    dll = windows_path(fmu3_dir / WINDOWS_LIBRARY)

    plans = [(main_plan(description3, p), resume_plan(description3, p)) for p in (linux_paths, windows_paths)]
    harnesses = compile_harness(HERE / "harness3.c", work)
    return dict(run_on_both(harnesses, (so, dll), plans, work, wine_env), paths=(linux_paths, windows_paths))


# --------------------------------------------------------------------------------------------------------
# tests


def values_of(results, lines):
    """The statuses and values of the given lines."""
    return [results[k][:2] for k in lines]


def without_thread_counts(plan, *runs):
    """The plan and its runs without the lines that count the process's threads (a count of its own on each
    platform: Wine's threads besides the program's)."""
    keep = [k for k, line in enumerate(plan.lines) if line.split()[1] != "process_threads"]
    sub = Plan(("", {}), plan.paths)
    sub.lines, sub.checks = [plan.lines[k] for k in keep], [plan.checks[k] for k in keep]
    return (sub, *([r[k] for k in keep] for r in runs))


def test_dll_exports_every_fmi3_function(fmu3_dir):
    dump = subprocess.run([tool("x86_64-w64-mingw32-objdump"), "-p", fmu3_dir / WINDOWS_LIBRARY], check=True,
                          capture_output=True, text=True).stdout
    exported = set(re.findall(r"\]\s+(fmi3\w+)", dump))
    missing = sorted(set(fmi3_functions()) - exported)
    assert not missing, f"not exported: {missing}"


def test_same_calls_same_results(runs3):
    plan, linux, windows = runs3["main"]
    problems, stats = compare(*without_thread_counts(plan, linux, windows), runs3["paths"])
    sections = {name: b - a for name, (a, b) in plan.marks.items()}
    report("fmi3 calls", {"lines": len(plan.lines), "sections": sections, "seconds": runs3["seconds"], **stats})
    assert not problems, f"{len(problems)} differences:\n" + "\n".join(problems[:40])
    assert linux[0][1] == windows[0][1] == [hexs("3.0")]
    # the plan exercises what it says: each mode's steps evaluated by that mode
    for mode, number in (("table", "1"), ("exact", "2")):
        lines = plan.tags[f"{mode}-threads1"]
        modes = [linux[k][1] for k in lines if plan.lines[k].split()[1] == "get_int32"]
        assert len(modes) == STEPS and all(m == [number] * CONTACTS for m in modes), (mode, modes)


@pytest.mark.parametrize("platform", [1, 2])
def test_threads_give_the_bits_of_one_thread(runs3, platform):
    """On each platform: 2 threads and 0 (the cores) as 1, also for instances that share the workers."""
    plan = runs3["main"][0]
    results = runs3["main"][platform]
    for mode in MODES:
        one = values_of(results, plan.tags[f"{mode}-threads1"])
        assert all(s == OK for s, _ in one)
        for threads in THREADS[1:]:
            assert values_of(results, plan.tags[f"{mode}-threads{threads}"]) == one, (mode, threads)
        shared = values_of(results, plan.tags[f"shared-{mode}"])
        assert shared == one[: len(shared)], f"{mode}: stepped in turn with another instance"
    again = values_of(results, plan.tags["again-exact"])
    assert again == values_of(results, plan.tags["exact-threads1"])[: len(again)], "the workers started again"


def test_the_windows_host_keeps_its_own_x87_control_word(runs3):
    """The master's thread runs with another x87 precision than the DLL computes with, before and after the
    calls: the DLL restores the host's control word."""
    plan, _, windows = runs3["main"]
    words = [int(windows[k][1][0], 16) for k in plan.tags["x87"]]
    assert len(set(words)) == 1 and words[0] != STANDARD_X87, [hex(w) for w in words]


@pytest.mark.parametrize("platform", [1, 2])
def test_worker_threads_end_with_the_last_instance(runs3, platform):
    plan = runs3["main"][0]
    results = runs3["main"][platform]
    count = {tag[len("threads-"):]: int(results[lines[0]][1][0]) for tag, lines in plan.tags.items()
             if tag.startswith("threads-")}
    before = count["before"]
    assert count["shared"] > before, count
    assert count["one-freed"] == count["shared"], f"the workers ended while an instance still used them: {count}"
    assert count["all-freed"] == before, f"the workers outlived the last instance: {count}"
    assert count["again"] > before and count["end"] == before, count
    report(f"fmi3 worker threads {['linux', 'windows (wine)'][platform - 1]}", count)


def test_states_cross_platforms(runs3):
    (linux_paths, windows_paths) = runs3["paths"]
    main, linux_main, windows_main = runs3["main"]
    resume, linux_resume, windows_resume = runs3["resume"]
    assert all(s == OK for s, _, _ in linux_resume) and all(s == OK for s, _, _ in windows_resume)
    for mode, (_, check, _) in MODES.items():
        # serialized again after restoring: the same bytes as the other platform wrote
        for written, again in ((linux_paths["state_out"][mode], windows_paths["reserialized"][mode]),
                               (windows_paths["state_out"][mode], linux_paths["reserialized"][mode])):
            again, written = (pathlib.Path(p.replace("Z:", "").replace("\\", "/")) for p in (again, written))
            assert written.read_bytes() == again.read_bytes(), (written, again)
        own, restored = main.tags[f"continued-{mode}"], resume.tags[f"continued-{mode}"]
        sub = main.part(0, 0)
        sub.lines, sub.checks = [main.lines[k] for k in own], [main.checks[k] for k in own]
        assert [resume.lines[k].split()[1:] for k in restored] == [line.split()[1:] for line in sub.lines]
        # continued on the other platform as on the platform that wrote the state, and as the other
        # platform continued its own state
        for direction, a, b, paths in (
            ("linux-to-windows", linux_main, windows_resume, (linux_paths, windows_paths)),
            ("windows-to-linux", windows_main, linux_resume, (windows_paths, linux_paths)),
            ("windows-own-and-restored", windows_main, windows_resume, (windows_paths, windows_paths)),
            ("linux-own-and-restored", linux_main, linux_resume, (linux_paths, linux_paths)),
        ):
            problems, stats = compare(sub, [a[k] for k in own], [b[k] for k in restored], paths)
            assert not problems, direction + ":\n" + "\n".join(problems[:20])
            report(f"fmi3 state-{mode}-{direction}", stats[mode])
    # the restored warm start matters: a cold start differs by more than the tolerance
    restored, cold = resume.tags["continued-exact"], resume.tags["cold-exact"]
    sub = main.part(0, 0)
    sub.lines, sub.checks = [resume.lines[k] for k in restored], [resume.checks[k] for k in restored]
    problems, _ = compare(sub, [linux_resume[k] for k in restored], [linux_resume[k] for k in cold],
                          (linux_paths, linux_paths))
    assert problems, "a cold start continued as the restored state did: the test cannot tell them apart"


def test_bad_calls_fail_alike_and_change_nothing(runs3):
    plan, linux, windows = runs3["main"]
    for name, results in (("linux", linux), ("windows", windows)):
        wrong = [f"line {k + 1} `{plan.lines[k][:80]}`: {results[k][0]}, expected {status}"
                 for k, status in plan.expected.items() if results[k][0] != status]
        assert not wrong, f"{name}:\n" + "\n".join(wrong)
        errors = [k for k, status in plan.expected.items() if status == ERROR]
        assert all(any(s == ERROR for s, _, _ in results[k][2]) for k in errors if plan.lines[k].split()[1] != "null"), \
            f"{name}: an error without its message"
        assert values_of(results, plan.tags["bad-after"]) == values_of(results, plan.tags["bad-before"])
