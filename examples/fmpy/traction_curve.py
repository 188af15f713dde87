#!/usr/bin/env python3
"""A traction-creepage curve from WheelRailFriction.fmu in fmpy, dry and wet, by the lookup table (mode 1).

Co-Simulation: the longitudinal creepage ramps from 0 to 3 % over 1 s at F_N = 100 kN, V = 30 m/s on the
default running-surface contact; every other input is held at its start value. The FMU is quasi-static, so
the outputs at t belong to the inputs applied at t - dt. Prints the curve's peak traction coefficient and
where it is reached, and writes traction_curve.csv.

    python examples/fmpy/traction_curve.py [--fmu target/fmu/WheelRailFriction.fmu] [--out DIR]

Checks what the physics requires (exit 1 otherwise): the force opposes the slip (F_x < 0 for xi > 0, Kalker's
sign convention), f = |F_x|/F_N, the dry curve lies above the wet one once the contact slips, and f stays
below 1.
"""

import argparse
import csv
import pathlib
import sys

import numpy as np
from fmpy import read_model_description, simulate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
STEPS = 60


def curve(fmu, wetness):
    md = read_model_description(fmu)
    inputs = {v.name: float(v.start) for v in md.modelVariables if v.causality == "input"}
    inputs.update(normal_force=100e3, rolling_speed=30.0, wetness=wetness)
    names = list(inputs)
    ramp = [(t, *[0.03 * t if n == "creepage_longitudinal" else inputs[n] for n in names]) for t in (0.0, 1.0)]
    signals = np.array(ramp, dtype=[("time", np.double)] + [(n, np.double) for n in names])
    result = simulate_fmu(fmu, stop_time=1.0, output_interval=1.0 / STEPS, input=signals,
                          start_values={"mode": 1},
                          output=["force_longitudinal", "traction_coefficient", "evaluation_mode"])
    creepage = 0.03 * np.maximum(result["time"] - 1.0 / STEPS, 0.0)
    return creepage[1:], result[1:]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "WheelRailFriction.fmu"))
    ap.add_argument("--out", default=".")
    a = ap.parse_args()
    rows, peaks, failures = [], {}, []
    for label, wetness in (("dry", 0.0), ("wet", 1.0)):
        xi, r = curve(a.fmu, wetness)
        f, fx = r["traction_coefficient"], r["force_longitudinal"]
        k = int(np.argmax(f))
        peaks[label] = f
        print(f"{label}: peak f = {f[k]:.3f} at xi = {100 * xi[k]:.2f} %, f(3 %) = {f[-1]:.3f} "
              f"(evaluated by {'table' if np.all(r['evaluation_mode'] == 1) else 'exact solver'})")
        if not np.all(fx[xi > 0] < 0):
            failures.append(f"{label}: F_x does not oppose the slip")
        if not np.allclose(f, np.abs(fx) / 100e3, rtol=1e-9):
            failures.append(f"{label}: f is not |F_x|/F_N")
        if not np.all(f < 1.0):
            failures.append(f"{label}: f reaches 1")
        rows += [[label, x, y, z] for x, y, z in zip(xi, fx, f)]
    slipping = slice(STEPS // 3, None)  # creepage above 1 %: the contact slips
    if not np.all(peaks["dry"][slipping] > peaks["wet"][slipping]):
        failures.append("the wet curve is not below the dry one where the contact slips")
    out = pathlib.Path(a.out) / "traction_curve.csv"
    with open(out, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case", "creepage_longitudinal", "force_longitudinal", "traction_coefficient"])
        w.writerows(rows)
    print(f"wrote {out}")
    for failure in failures:
        print("FAILED:", failure, file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
