#!/usr/bin/env python3
"""WheelRailFriction.fmu in Model Exchange: outputs and their directional derivatives, as an implicit
integrator asks for them.

The FMU has no continuous states: its outputs are algebraic functions of the inputs (direct feedthrough). An
integrator of the vehicle's equations of motion sets the inputs at each evaluation, reads the forces and, for
its Jacobian, the derivatives of the forces with respect to the creepages (fmi2GetDirectionalDerivative).
This example does that at a few creepages on the default contact, by the lookup table (mode 1: derivatives of
the interpolant) and by the exact solver (mode 2: forward differences), and compares each with a central
difference of the outputs it reads.

    python examples/fmpy/model_exchange.py [--fmu target/fmu/WheelRailFriction.fmu]

Checks (exit 1 otherwise): the derivative agrees with the central difference (within 2 %, or 1e-3 of the
largest), and at small creepage dF_x/dxi is the linear theory's creep stiffness -G c^2 C11 (Kalker) within
10 %: G = E/(2(1 + nu)) from the default E = 210 GPa and nu = 0.28 (docs/parameters.md), c^2 = a b from the
FMU's contact ellipse, C11 interpolated in Kalker's table between a/b = 0.5 and 0.6 at nu = 0.28 (3.740,
3.839; docs/model.md §13.3).
"""

import argparse
import pathlib
import shutil
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Model

ROOT = pathlib.Path(__file__).resolve().parents[2]
SHEAR_MODULUS = 210e9 / (2 * (1 + 0.28))  # G = E/(2(1 + nu)) [Pa]


def c11(ratio):
    """Kalker's C11 at nu = 0.28 for 0.5 <= a/b <= 0.6 (Kalker 1990, Table E.3, interpolated)."""
    return 3.740 + (ratio - 0.5) / 0.1 * (3.839 - 3.740)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "WheelRailFriction.fmu"))
    a = ap.parse_args()
    md = read_model_description(a.fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = extract(a.fmu)
    failures = []
    try:
        for mode, how, grid in ((1, "table", None), (2, "exact", 12)):
            fmu = FMU2Model(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.modelExchange.modelIdentifier,
                            instanceName=how)
            fmu.instantiate()
            fmu.setInteger([vr["mode"]], [mode])
            if grid:
                fmu.setInteger([vr["grid_size"]], [grid])
            fmu.setupExperiment(startTime=0.0)
            fmu.enterInitializationMode()
            fmu.exitInitializationMode()
            fmu.newDiscreteStates()
            fmu.enterContinuousTimeMode()
            fx, xi = vr["force_longitudinal"], vr["creepage_longitudinal"]
            for k, creepage in enumerate((2e-4, 1e-3, 4e-3)):
                fmu.setTime(k * 1e-3)
                fmu.setReal([xi], [creepage])
                force = fmu.getReal([fx])[0]
                (derivative,) = fmu.getDirectionalDerivative([fx], [xi], [1.0])
                h = 1e-6
                fmu.setReal([xi], [creepage + h])
                up = fmu.getReal([fx])[0]
                fmu.setReal([xi], [creepage - h])
                down = fmu.getReal([fx])[0]
                fmu.setReal([xi], [creepage])
                central = (up - down) / (2 * h)
                print(f"{how:>5}: xi = {100 * creepage:.2f} %  F_x = {force / 1e3:8.3f} kN  "
                      f"dF_x/dxi = {derivative / 1e6:8.2f} MN (central difference {central / 1e6:8.2f} MN)")
                if abs(derivative - central) > max(0.02 * abs(central), 1e-3 * abs(force) / creepage):
                    failures.append(f"{how}: directional derivative {derivative:.4g} vs {central:.4g} at {creepage}")
                if k == 0:
                    a_, b_ = fmu.getReal([vr["contact_semi_axis_a"], vr["contact_semi_axis_b"]])
                    linear = -SHEAR_MODULUS * a_ * b_ * c11(a_ / b_)
                    print(f"{how:>5}: linear theory -G c^2 C11 = {linear / 1e6:.2f} MN")
                    if not abs(derivative - linear) < 0.10 * abs(linear):
                        failures.append(f"{how}: creep stiffness {derivative:.4g} far from Kalker's {linear:.4g}")
                fmu.completedIntegratorStep()
            fmu.terminate()
            fmu.freeInstance()
    finally:
        shutil.rmtree(unzipped, ignore_errors=True)
    for failure in failures:
        print("FAILED:", failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
