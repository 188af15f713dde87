#!/usr/bin/env python3
"""Demo: WheelRailFriction.fmu in an fmpy co-simulation.

Scenario: the longitudinal creepage ramps from 0 to 3 % over 1 s at F_N = 100 kN, dry (w = 0) and wet
(w = 1), at 10 and 30 m/s, each evaluated by the FMU's bundled lookup table (mode 0, the MBS setting) and by
the exact coupled solver (mode 2). Writes target/demo/demo.csv (one row per communication point, case and
mode) and target/demo/traction_creepage.png (traction coefficient over creepage: table lines, exact dots).

usage: demo.py [--fmu PATH] [--out DIR] [--grid N] [--steps N]
"""

import argparse
import csv
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from fmpy import simulate_fmu  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
INPUTS = ["creepage_longitudinal", "creepage_lateral", "spin_creepage", "normal_force", "rolling_speed", "wetness"]
OUTPUTS = ["force_longitudinal", "force_lateral", "traction_coefficient", "max_temperature",
           "fluid_load_fraction", "converged", "evaluation_mode"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "WheelRailFriction.fmu"))
    ap.add_argument("--out", default=str(ROOT / "target" / "demo"))
    ap.add_argument("--grid", type=int, default=30, help="grid_size parameter (cells per axis)")
    ap.add_argument("--steps", type=int, default=30, help="communication steps per run")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)

    rows = []
    colours = {(label, speed): None for label in ("dry", "wet") for speed in (10.0, 30.0)}
    fig, ax = plt.subplots(figsize=(9, 6))
    for speed in (10.0, 30.0):
        for label, wetness in (("dry", 0.0), ("wet", 1.0)):
            # every input as a signal: creepage ramp, the others constant
            ramp = np.array([(t, 0.03 * t, 0.0, 0.0, 100e3, speed, wetness) for t in (0.0, 1.0)],
                            dtype=[("time", np.double)] + [(n, np.double) for n in INPUTS])
            for mode, how in ((0, "table"), (2, "exact")):
                result = simulate_fmu(
                    a.fmu,
                    stop_time=1.0,
                    output_interval=1.0 / a.steps,
                    input=ramp,
                    start_values=dict(grid_size=a.grid, mode=mode),
                    output=OUTPUTS,
                )
                # quasi-static: the outputs at t belong to the input applied at the previous point t - dt
                creepage = np.interp(np.maximum(result["time"] - 1.0 / a.steps, 0.0), ramp["time"],
                                     ramp["creepage_longitudinal"])
                for r, xi in zip(result, creepage):
                    rows.append([label, how, speed, wetness, r["time"], xi] + [r[n] for n in OUTPUTS])
                style = dict(marker=".", linestyle="none") if how == "exact" else dict()
                line = ax.plot(100 * creepage, result["traction_coefficient"], label=f"{label}, V = {speed:g} m/s, {how}",
                               color=colours[(label, speed)], **style)
                colours[(label, speed)] = line[0].get_color()
                print(f"{label:>3}, V = {speed:4.0f} m/s, {how:>5} (evaluation_mode {result['evaluation_mode'][-1]}): "
                      f"f({100 * creepage[-1]:.1f} %) = {result['traction_coefficient'][-1]:.3f}, "
                      f"T_max = {result['max_temperature'][-1] - 273.15:.0f} degC")
    ax.set_xlabel("longitudinal creepage xi [%]")
    ax.set_ylabel("traction coefficient f = |F_T| / F_N [-]")
    ax.set_title("WheelRailFriction.fmu in fmpy: F_N = 100 kN, creepage ramp")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "traction_creepage.png", dpi=100)
    with open(out / "demo.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "evaluation", "rolling_speed", "wetness", "time", "creepage_longitudinal"] + OUTPUTS)
        w.writerows(rows)
    print(f"wrote {out / 'demo.csv'} and {out / 'traction_creepage.png'}")


if __name__ == "__main__":
    main()
