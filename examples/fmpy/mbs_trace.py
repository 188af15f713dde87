#!/usr/bin/env python3
"""WheelRailFriction.fmu stepped as an MBS tool steps it: new inputs and a new contact geometry every step.

One wheel for 2 s at 1 kHz, in mode 0 (auto): braking at 0.1 % creepage with a 9 Hz oscillation, the normal
force 90 kN with a 23 Hz ripple, the contact moving from the tread towards the flange root and back between
0.6 and 1 s (the gap curvature B rising from 0.42 to 2 /m and falling again, with the spin it brings: the
exact solver, since the bundled table holds the tread's contact only) and a wet patch from 1.2 to 1.6 s. The FMU is driven through fmpy's FMU2Slave, call by call: set the inputs, fmi2DoStep, read the
outputs. Prints the time per step and how many steps were served by the table and by the exact solver, and
writes mbs_trace.csv.

    python examples/fmpy/mbs_trace.py [--fmu target/fmu/WheelRailFriction.fmu] [--out DIR]

Checks (exit 1 otherwise): every step succeeds, the braking force opposes the slip (F_x < 0), the traction
coefficient stays below 1, the contact ellipse follows the curvature input (b shrinks as B grows: Hertz), and
on the wet patch 1.1 % creepage transmits less than 0.1 % on the dry rail (the wet adhesion limit).
"""

import argparse
import csv
import math
import pathlib
import shutil
import sys
import time

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parents[2]
STEP = 1e-3
STEPS = 2000
OUTPUTS = ["force_longitudinal", "force_lateral", "traction_coefficient", "max_temperature",
           "contact_semi_axis_a", "contact_semi_axis_b"]


def inputs(t):
    """The inputs of the step starting at t (SI units)."""
    # contact position: 0 on the tread (the bundled table's contact), towards the flange root and back
    g = 0.5 - 0.5 * math.cos(2 * math.pi * (t - 0.6) / 0.4) if 0.6 <= t < 1.0 else 0.0
    wet = 1.0 if 1.2 <= t < 1.6 else 0.0
    return {
        "creepage_longitudinal": 0.001 + 0.0002 * math.sin(2 * math.pi * 9 * t) + 0.01 * wet,
        "creepage_lateral": 0.0005,
        "spin_creepage": 0.05 + 0.3 * g,
        "normal_force": 90e3 + 6e3 * math.sin(2 * math.pi * 23 * t),
        "rolling_speed": 25.0,
        "wetness": wet,
        "curvature_longitudinal": 1.015,
        "curvature_lateral": 0.4215 * (2.0 / 0.4215) ** g,
        "semi_axis_a": 0.0,
        "semi_axis_b": 0.0,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "WheelRailFriction.fmu"))
    ap.add_argument("--out", default=".")
    a = ap.parse_args()
    md = read_model_description(a.fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = extract(a.fmu)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="front-right-wheel")
    rows, failures = [], []
    try:
        fmu.instantiate()
        fmu.setInteger([vr["mode"]], [0])
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        names = list(inputs(0.0))
        refs = [vr[n] for n in names]
        out_refs, mode_ref = [vr[n] for n in OUTPUTS], vr["evaluation_mode"]
        started = time.perf_counter()
        for k in range(STEPS):
            t = k * STEP
            u = inputs(t)
            fmu.setReal(refs, [u[n] for n in names])
            fmu.doStep(currentCommunicationPoint=t, communicationStepSize=STEP)
            rows.append([t] + [u[n] for n in names] + fmu.getReal(out_refs) + fmu.getInteger([mode_ref]))
        seconds = time.perf_counter() - started
        fmu.terminate()
    finally:
        fmu.freeInstance()
        shutil.rmtree(unzipped, ignore_errors=True)
    columns = ["time"] + names + OUTPUTS + ["evaluation_mode"]
    col = {n: [r[i] for r in rows] for i, n in enumerate(columns)}
    by_table = sum(1 for m in col["evaluation_mode"] if m == 1)
    print(f"{STEPS} steps in {seconds:.2f} s ({1e6 * seconds / STEPS:.0f} µs per step including fmpy's calls): "
          f"{by_table} by table, {STEPS - by_table} by the exact solver")
    if not all(fx < 0 for fx in col["force_longitudinal"]):
        failures.append("the braking force does not oppose the slip everywhere")
    if not all(0 <= f < 1 for f in col["traction_coefficient"]):
        failures.append("a traction coefficient outside [0, 1)")
    b = col["contact_semi_axis_b"]
    if not b[800] < 0.7 * b[0]:
        failures.append(f"b does not shrink as B grows: {b[0]:.4f} m -> {b[800]:.4f} m")
    dry, wet = col["traction_coefficient"][1150], col["traction_coefficient"][1500]
    # on the wet patch ten times the creepage transmits less than the dry contact at 0.1 %: the adhesion limit
    if not wet < dry:
        failures.append(f"the wet patch does not lower the adhesion: f {dry:.3f} -> {wet:.3f}")
    out = pathlib.Path(a.out) / "mbs_trace.csv"
    with open(out, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(columns)
        w.writerows(rows)
    print(f"wrote {out}")
    for failure in failures:
        print("FAILED:", failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
