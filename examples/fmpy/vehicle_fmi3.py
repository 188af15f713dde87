#!/usr/bin/env python3
"""WheelRailFriction-fmi3.fmu: one FMI 3.0 instance for all eight wheel-rail contacts of a vehicle.

A vehicle of two bogies with two wheelsets each runs 0.4 s on straight track and then 0.6 s into a curve,
at 1 kHz. Contact k is wheel k // 2 + 1 of the vehicle, on the left rail (even k) or the right (odd k). On
the straight the wheels of a wheelset roll with mirrored inputs (the lateral creepage and the spin change
sign from one side to the other: the wheelset's yaw and the conicity), both at the default tread contact;
in the curve the outer (left) wheels carry more load than the inner ones (cant deficiency), the leading
wheelset of each bogie runs at an angle of attack, and the contact of its outer wheel moves towards the
flange root (the gap curvature B rises from 0.42 to 2.5 /m: the exact solver takes over where the bundled
table holds the tread's contact only). The structural parameter `contacts` is set to 8 in configuration
mode; every input and output is an array of eight values. The run is made twice, on one thread and on all
cores (`threads` 0), and prints the time per vehicle step of each.

    python examples/fmpy/vehicle_fmi3.py [--fmu target/fmu/WheelRailFriction-fmi3.fmu]

Checks (exit 1 otherwise): every step succeeds; all cores give the bits of one thread; on the straight the
two wheels of a wheelset give the same longitudinal force and opposite lateral forces and spin moments (the
mirror symmetry of the contact: within 1e-9 of the normal force); braking creepage gives braking forces
(F_x < 0 for xi > 0: Kalker's convention) and the traction coefficient stays below 1; the flange-root
contact's ellipse narrows as B grows (Hertz: b falls); and the outer wheel, with more load and the same
creepage, transmits more longitudinal force than the inner one.
"""

import argparse
import math
import pathlib
import shutil
import sys
import time

from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

ROOT = pathlib.Path(__file__).resolve().parents[2]
CONTACTS = 8
STEP = 1e-3
STEPS = 1000
CURVE_START = 0.4
OUTPUTS = ["force_longitudinal", "force_lateral", "spin_moment", "traction_coefficient",
           "contact_semi_axis_b", "evaluation_mode"]
# how far into the curve the check of the outer and inner wheels looks [s]
IN_CURVE = 0.9


def inputs(t, k):
    """The inputs of contact k for the step starting at t (SI units)."""
    wheelset, right = k // 2, k % 2
    side = -1.0 if right else 1.0
    leading = wheelset % 2 == 0
    # 0 on the straight, rising smoothly to 1 over the first 0.3 s of the curve
    c = 0.0 if t < CURVE_START else 0.5 - 0.5 * math.cos(math.pi * min(1.0, (t - CURVE_START) / 0.3))
    outer = not right
    flange = c if (leading and outer) else 0.0
    return {
        "creepage_longitudinal": 0.0015,
        # the wheelset's yaw on the straight, plus the angle of attack of a leading wheelset in the curve
        "creepage_lateral": side * 0.0003 + (0.004 * c if leading else 0.0),
        "spin_creepage": side * 0.05 + 0.5 * flange,
        "normal_force": 80e3 * (1.0 + (0.25 if outer else -0.25) * c),
        "rolling_speed": 20.0,
        "wetness": 0.0,
        "curvature_longitudinal": 1.015,
        "curvature_lateral": 0.4215 * (2.5 / 0.4215) ** flange,
        "semi_axis_a": 0.0,
        "semi_axis_b": 0.0,
    }


def run(fmu_path, md, threads):
    """The vehicle along the track on `threads` threads: per step the outputs by name, each a list over
    the contacts; and the seconds per vehicle step."""
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = extract(fmu_path)
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="vehicle")
    steps = []
    try:
        fmu.instantiate()
        fmu.enterConfigurationMode()
        fmu.setUInt64([vr["contacts"]], [CONTACTS])
        fmu.exitConfigurationMode()
        fmu.setUInt64([vr["threads"]], [threads])
        fmu.setInt32([vr["mode"]], [0])
        fmu.enterInitializationMode(startTime=0.0)
        fmu.exitInitializationMode()
        names = list(inputs(0.0, 0))
        reals = [n for n in OUTPUTS if n != "evaluation_mode"]
        started = time.perf_counter()
        for i in range(STEPS):
            t = i * STEP
            u = [inputs(t, k) for k in range(CONTACTS)]
            # one call for all inputs: per variable its eight values, in the order of the value references
            fmu.setFloat64([vr[n] for n in names], [u[k][n] for n in names for k in range(CONTACTS)])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=STEP)
            values = fmu.getFloat64([vr[n] for n in reals], len(reals) * CONTACTS)
            out = {n: list(values[j * CONTACTS:(j + 1) * CONTACTS]) for j, n in enumerate(reals)}
            out["evaluation_mode"] = list(fmu.getInt32([vr["evaluation_mode"]], CONTACTS))
            out["inputs"] = u
            steps.append(out)
        seconds = (time.perf_counter() - started) / STEPS
        fmu.terminate()
    finally:
        fmu.freeInstance()
        shutil.rmtree(unzipped, ignore_errors=True)
    return steps, seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "WheelRailFriction-fmi3.fmu"))
    a = ap.parse_args()
    md = read_model_description(a.fmu)
    one, seconds_one = run(a.fmu, md, 1)
    cores, seconds_cores = run(a.fmu, md, 0)
    exact = sum(m == 2 for s in one for m in s["evaluation_mode"])
    print(f"{STEPS} vehicle steps of {CONTACTS} contacts: {1e3 * seconds_one:.2f} ms per step on one thread, "
          f"{1e3 * seconds_cores:.2f} ms on all cores (fmpy's calls included); {exact} of "
          f"{STEPS * CONTACTS} contact steps by the exact solver, the rest by table")
    failures = []
    if one != cores:
        failures.append("all cores do not give the bits of one thread")
    straight = [s for i, s in enumerate(one) if i * STEP < CURVE_START]
    for s in straight:
        for w in range(0, CONTACTS, 2):
            f_n = s["inputs"][w]["normal_force"]
            fx, fy, mz = (s[n] for n in ("force_longitudinal", "force_lateral", "spin_moment"))
            if max(abs(fx[w] - fx[w + 1]), abs(fy[w] + fy[w + 1]), abs(mz[w] + mz[w + 1])) > 1e-9 * f_n:
                failures.append(f"wheelset {w // 2 + 1} on the straight: left {fx[w]:.3f} {fy[w]:.3f} "
                                f"{mz[w]:.5f}, right {fx[w + 1]:.3f} {fy[w + 1]:.3f} {mz[w + 1]:.5f}: not mirrored")
                break
    if not all(fx < 0 for s in one for fx in s["force_longitudinal"]):
        failures.append("a braking creepage without a braking force")
    if not all(0 <= f < 1 for s in one for f in s["traction_coefficient"]):
        failures.append("a traction coefficient outside [0, 1)")
    b_tread = one[0]["contact_semi_axis_b"][0]
    b_flange = one[-1]["contact_semi_axis_b"][0]
    if not b_flange < 0.7 * b_tread:
        failures.append(f"the flange-root ellipse does not narrow: b {b_tread:.4f} m -> {b_flange:.4f} m")
    s = one[int(IN_CURVE / STEP)]
    # the trailing wheelset (contacts 2 and 3): the same creepages, the outer wheel 25 % more load
    outer, inner = s["force_longitudinal"][2], s["force_longitudinal"][3]
    if not abs(outer) > abs(inner):
        failures.append(f"the outer wheel transmits no more than the inner one: {outer:.0f} / {inner:.0f} N")
    print(f"in the curve, trailing wheelset: F_x outer {outer / 1e3:.2f} kN, inner {inner / 1e3:.2f} kN; leading "
          f"outer wheel at the flange root: b {1e3 * b_flange:.2f} mm (tread {1e3 * b_tread:.2f} mm)")
    for failure in failures:
        print("FAILED:", failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
