#!/usr/bin/env python3
"""Demo: WheelRailFriction.fmu in an fmpy co-simulation.

Scenario 1: the longitudinal creepage ramps from 0 to 3 % over 1 s at F_N = 100 kN, dry (w = 0) and wet
(w = 1), at 10 and 30 m/s, each evaluated by the FMU's bundled lookup table (mode 0, the MBS setting) and by
the exact coupled solver (mode 2). Writes target/demo/demo.csv (one row per communication point, case and
mode) and target/demo/traction_creepage.png (traction coefficient over creepage: table lines, exact dots).

Scenario 2: the MBS trace of tools/mbs_trace.py (one wheel 10 s at 1 kHz through a curve: tread → flange
root and back, braking, load transfer, a wet patch), every step in mode 0 (auto: the bundled table where it
covers the contact geometry, else the exact solver) and every --trace-every-th step in mode 2 (exact, the
reference). Writes target/demo/mbs_trace.csv (one row per step and run: the inputs of the step and its
outputs) and target/demo/mbs_trace.png (inputs a/b, F_N, creepages, wetness; outputs F_x, F_y, f, T_max by
auto and exact; how auto evaluated each step and its force error against exact).

usage: demo.py [--fmu PATH] [--out DIR] [--grid N] [--steps N] [--trace-every N]
"""

import argparse
import csv
import pathlib
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from fmpy import read_model_description, simulate_fmu  # noqa: E402

import mbs_trace  # noqa: E402  (tools/, the directory of this script)

ROOT = pathlib.Path(__file__).resolve().parents[1]
INPUTS = ["creepage_longitudinal", "creepage_lateral", "spin_creepage", "normal_force", "rolling_speed", "wetness"]
OUTPUTS = ["force_longitudinal", "force_lateral", "traction_coefficient", "max_temperature",
           "fluid_load_fraction", "converged", "evaluation_mode"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "WheelRailFriction.fmu"))
    ap.add_argument("--out", default=str(ROOT / "target" / "demo"))
    ap.add_argument("--grid", type=int, default=0,
                    help="grid_size parameter (cells per axis; 0: automatic, mode 0's fallback on a grid per contact)")
    ap.add_argument("--steps", type=int, default=30, help="communication steps per run")
    ap.add_argument("--trace-every", type=int, default=10,
                    help="the exact reference of the MBS trace at every N-th step")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)

    # the inputs the ramp does not drive (the contact geometry) as signals at their start values, so that every
    # input of the FMU has a signal
    held = {v.name: float(v.start) for v in read_model_description(a.fmu).modelVariables
            if v.causality == "input" and v.name not in INPUTS}
    rows = []
    colours = {(label, speed): None for label in ("dry", "wet") for speed in (10.0, 30.0)}
    fig, ax = plt.subplots(figsize=(9, 6))
    for speed in (10.0, 30.0):
        for label, wetness in (("dry", 0.0), ("wet", 1.0)):
            # every input as a signal: creepage ramp, the others constant
            ramp = np.array([(t, 0.03 * t, 0.0, 0.0, 100e3, speed, wetness, *held.values()) for t in (0.0, 1.0)],
                            dtype=[("time", np.double)] + [(n, np.double) for n in INPUTS + list(held)])
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
    trace_demo(a.fmu, out, a.grid, a.trace_every)


TRACE_OUTPUTS = ["force_longitudinal", "force_lateral", "traction_coefficient", "max_temperature",
                 "evaluation_mode", "contact_semi_axis_a", "contact_semi_axis_b", "peak_pressure"]


def run_trace(fmu, rows, mode, grid):
    """The outputs of each row's step (its inputs held from its time to the next row's) in `mode`."""
    step = rows[1][0] - rows[0][0]
    signals = np.array([tuple(r) for r in rows], dtype=[(n, np.double) for n in mbs_trace.COLUMNS])
    result = simulate_fmu(fmu, start_time=rows[0][0], stop_time=rows[-1][0] + step, output_interval=step,
                          input=signals, start_values=dict(grid_size=grid, mode=mode), output=TRACE_OUTPUTS)
    # quasi-static: the outputs at t belong to the inputs applied at the previous point t - step
    return np.array([result[np.argmin(np.abs(result["time"] - (r[0] + step)))] for r in rows])


def trace_demo(fmu, out, grid, every):
    """The MBS trace in mode 0 at every step and in mode 2 at every `every`-th step: CSV and plot."""
    rows = mbs_trace.trace()
    started = time.perf_counter()
    auto = run_trace(fmu, rows, 0, grid)
    took = time.perf_counter() - started
    sampled = rows[::every]
    exact = run_trace(fmu, sampled, 2, grid)
    col = {n: np.array([r[i] for r in rows]) for i, n in enumerate(mbs_trace.COLUMNS)}
    t, fn = col["time"], col["normal_force"]
    by_table = int(np.sum(auto["evaluation_mode"] == 1))
    error = np.hypot(auto["force_longitudinal"][::every] - exact["force_longitudinal"],
                     auto["force_lateral"][::every] - exact["force_lateral"]) / np.abs(fn[::every])
    temperature = np.abs(auto["max_temperature"][::every] - exact["max_temperature"])
    simulated = rows[-1][0] - rows[0][0] + (rows[1][0] - rows[0][0])
    print(f"MBS trace, {len(rows)} steps: mode 0 evaluated {by_table} by table, {len(rows) - by_table} by the "
          f"exact solver in {took:.1f} s with fmpy for {simulated:.0f} s simulated; against mode 2 at {len(sampled)} "
          f"steps |dF|/F_N mean {error.mean():.2e}, max {error.max():.2e}; |dT_max| mean {temperature.mean():.1f} K, "
          f"max {temperature.max():.1f} K")
    with open(out / "mbs_trace.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["run"] + mbs_trace.COLUMNS + TRACE_OUTPUTS)
        for run, inputs, outputs in (("auto", rows, auto), ("exact", sampled, exact)):
            w.writerows([run] + list(r) + [o[n] for n in TRACE_OUTPUTS] for r, o in zip(inputs, outputs))

    te = t[::every]
    wet = col["wetness"] > 0.0
    fig, ax = plt.subplots(5, 1, figsize=(11, 14), sharex=True)
    ratio = auto["contact_semi_axis_a"] / auto["contact_semi_axis_b"]
    ax[0].plot(t, ratio, color="C0", label="a/b (contact ellipse)")
    ax[0].set_ylabel("a/b [-]")
    twin = ax[0].twinx()
    twin.plot(t, fn / 1e3, color="C1", lw=0.6, label="F_N")
    twin.set_ylabel("F_N [kN]")
    ax[0].legend(handles=ax[0].get_lines() + twin.get_lines(), loc="upper right")
    ax[0].set_title("MBS trace in fmpy: straight, curve (tread → flange root), straight; braking 25 → 20 m/s; "
                    "wet patch shaded")
    ax[1].plot(t, 100 * col["creepage_longitudinal"], label="xi [%]")
    ax[1].plot(t, 100 * col["creepage_lateral"], label="eta [%]")
    ax[1].plot(t, col["spin_creepage"], label="phi [1/m]")
    ax[1].plot(t, col["wetness"], color="C9", ls="--", label="wetness [-]")
    ax[1].set_ylabel("creepages, wetness")
    ax[1].legend(loc="upper left")
    for name, label, colour in (("force_longitudinal", "F_x", "C0"), ("force_lateral", "F_y", "C1")):
        ax[2].plot(t, auto[name] / 1e3, color=colour, label=f"{label}, mode 0 (auto)")
        ax[2].plot(te, exact[name] / 1e3, ".", color=colour, ms=3, label=f"{label}, mode 2 (exact)")
    ax[2].set_ylabel("force on the wheel [kN]")
    ax[2].legend(loc="lower left")
    ax[3].plot(t, auto["traction_coefficient"], color="C2", label="f, auto")
    ax[3].plot(te, exact["traction_coefficient"], ".", color="C2", ms=3, label="f, exact")
    ax[3].set_ylabel("traction coefficient f [-]")
    twin = ax[3].twinx()
    twin.plot(t, auto["max_temperature"] - 273.15, color="C3", label="T_max, auto")
    twin.plot(te, exact["max_temperature"] - 273.15, ".", color="C3", ms=3, label="T_max, exact")
    twin.set_ylabel("T_max [°C]")
    ax[3].legend(handles=ax[3].get_lines() + twin.get_lines(), loc="upper left")
    ax[4].semilogy(te, np.maximum(error, 1e-16), ".", color="C4", ms=3, label="|ΔF|/F_N, auto against exact")
    ax[4].axhline(0.01, color="C4", ls=":", label="table target p99 0.01")
    ax[4].set_ylabel("|ΔF|/F_N [-]")
    ax[4].set_xlabel("time [s]")
    twin = ax[4].twinx()
    twin.step(t, auto["evaluation_mode"], where="post", color="k", lw=0.8, label="mode 0 evaluated by")
    twin.set_yticks([1, 2], ["table", "exact"])
    twin.set_ylim(0.5, 2.5)
    ax[4].legend(handles=ax[4].get_lines() + twin.get_lines(), loc="center left")
    for a in ax:
        a.fill_between(t, 0, 1, where=wet, color="C9", alpha=0.15, transform=a.get_xaxis_transform())
        a.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "mbs_trace.png", dpi=90)
    print(f"wrote {out / 'mbs_trace.csv'} and {out / 'mbs_trace.png'}")


if __name__ == "__main__":
    main()
