#!/usr/bin/env python3
"""An MBS input trace for WheelRailFriction.fmu: one wheel, 10 s at 1 kHz, through a curve (benchmark and demo).

The outer (right-hand) front wheel of a braking vehicle runs on straight track, through an entry transition into
a curve, round it, out through an exit transition onto straight track again, and over a wet patch. Every value is
a closed-form function of time (no randomness): the trace is the same on every machine. Rows at t = k·1 ms,
k = 0 … 10 000 (10 001 rows); the row at t_k holds the inputs of the step [t_k, t_k + 1 ms]. Columns: `time` [s]
and the FMU inputs it drives, by their FMU names (SI units): `creepage_longitudinal` ξ, `creepage_lateral` η,
`spin_creepage` φ [1/m], `normal_force` F_N [N], `rolling_speed` V [m/s], `wetness` w, and the contact
geometry as the gap curvatures `curvature_longitudinal` A and `curvature_lateral` B [1/m] (Hertz in the FMU,
docs/model.md §2), with the prescribed semi-axes `semi_axis_a`, `semi_axis_b` 0 (not prescribed): every
input of the FMU.

Track (curve progress c: 0 straight, 1 full curve; raised-cosine transitions):
  0.0–1.5 s straight, 1.5–3.5 s entry transition, 3.5–6.0 s full curve, 6.0–8.0 s exit transition,
  8.0–10.0 s straight.

Contact position g ∈ [0, 1] (0 tread, 1 flange root): g = c·(0.93 + 0.07·cos(2π·1.3 Hz·t)), i.e. in the curve
the wheelset's lateral oscillation moves the contact by up to 14 % of the way back towards the tread, so the
geometry changes every step from the start of the entry transition to the end of the exit transition. On the
straight (g = 0) the geometry is exactly the FMU's default running-surface contact (A = 1.015 /m,
B = 0.4215 /m: a/b = 0.558, a = 5.9 mm, b = 10.5 mm at 100 kN).
  - Contact angle δ = δ_t + (δ_f − δ_t)·g, rolling radius r = r_t + 10 mm·g with the tread's δ_t = atan(1/40)
    (conicity 1/40) and r_t = 1/(2A_t) = 0.4926 m, the flange root's δ_f = 26°.
  - A = A_t + (A_f − A_t)·g from A_t = 1.015 /m to A_f = cos δ_f/(2 r_f) = 0.894 /m (wheel radius in the
    contact plane; the rail is straight along x).
  - B = B_t·(B_f/B_t)^g (log-linear) from B_t = 0.4215 /m to B_f = 7.0 /m (the rail's 13 mm gauge corner
    against the wheel's concave flange-root radius of −15.9 mm: (1/0.013 − 1/0.0159)/2 ≈ 7 /m).
  - Spin φ = sin δ/r (positive: the sign of this flange contact), 0.0507 /m on the tread.

Loads and motions:
  - F_N = 90 kN + 35 kN·c (quasi-static load transfer to the outer wheel from the cant deficiency)
          + 8 kN·sin(2π·1.1 Hz·t) (car-body bounce) + 6 kN·sin(2π·23 Hz·t) (track irregularities).
  - V = 25 m/s − 0.5 m/s²·t (service braking, 25 → 20 m/s).
  - w: a wet patch from 7.25 s to 8.75 s (raised-cosine rise and fall over 0.3 s each, w = 1 from 7.55 to
    8.45 s), on the end of the exit transition and the straight after it.
  - ξ = b·(0.0006 + 0.0144·w + 0.0001·sin(2π·9 Hz·t)), b rising from 0 to 1 between 0.3 and 1.0 s (brake
    application; ξ > 0 brakes: the force on the wheel opposes the slip): a braking creepage of 0.06 % (an
    adhesion demand of about 0.1) with a 9 Hz drivetrain oscillation; on the wet patch the demand exceeds
    the wet adhesion and the wheel creeps up to 1.5 % (wheel-slide protection holds it there).
  - η = −0.006·c + 0.0008·sin(2π·1.2 Hz·t): in the curve the angle of attack of the leading outer wheel
    (6 mrad), everywhere the wheelset's hunting (1.2 Hz: a kinematic wavelength of about 20 m).

Ranges over the trace (the inputs printed by this script; the contact from the FMU, checked by
tests/fmpy/test_mbs_trace.py):
  ξ 0 … 0.0151, η −0.0068 … 0.0008, φ 0.0507 … 0.872 /m (all inside the bundled table's ranges
  |ξ| ≤ 0.1, |η| ≤ 0.02, |φ| ≤ 1 /m), F_N 76.0 … 138.9 kN, V 20 … 25 m/s, w 0 … 1,
  A 0.894 … 1.015 /m, B 0.4215 … 7.0 /m. The contact (Hertz, the FMU's outputs `contact_semi_axis_a`,
  `contact_semi_axis_b`, `peak_pressure`): a/b 0.558 (tread) … 3.85 (flange root), √(ab) 5.0 … 8.0 mm, b down
  to 2.6 mm, p0 0.70 … 2.29 GPa; 3502 steps (35 %) on the default geometry (the straight track).

usage: mbs_trace.py [--out FILE.csv]   (default target/mbs_trace.csv; standard library only)
"""

import argparse
import csv
import math
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]
STEP = 1e-3  # [s]
ROWS = 10001  # t = 0 … 10 s
COLUMNS = ["time", "creepage_longitudinal", "creepage_lateral", "spin_creepage", "normal_force", "rolling_speed",
           "wetness", "curvature_longitudinal", "curvature_lateral", "semi_axis_a", "semi_axis_b"]

# the tread: the FMU's default gap curvatures (a rolling radius r = 1/(2A)) and a 1/40 cone
A_TREAD, B_TREAD = 1.015, 0.4215  # [1/m]
R_TREAD = 1.0 / (2.0 * A_TREAD)  # [m]
DELTA_TREAD = math.atan(1.0 / 40.0)  # [rad]
# the flange root: contact angle, rolling radius, curvatures
DELTA_FLANGE = math.radians(26.0)  # [rad]
R_FLANGE = R_TREAD + 0.010  # [m]
A_FLANGE = math.cos(DELTA_FLANGE) / (2.0 * R_FLANGE)  # [1/m]
B_FLANGE = 7.0  # [1/m]


def ramp(x):
    """Raised-cosine step: 0 for x ≤ 0, 1 for x ≥ 1, (1 − cos πx)/2 between."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    return 0.5 * (1.0 - math.cos(math.pi * x))


def curve_progress(t):
    """c: 0 on straight track, 1 in the full curve (entry transition 1.5–3.5 s, exit 6.0–8.0 s)."""
    return ramp((t - 1.5) / 2.0) - ramp((t - 6.0) / 2.0)


def wetness(t):
    """The wet patch: 0 → 1 from 7.25 s over 0.3 s, 1 → 0 from 8.45 s over 0.3 s."""
    return ramp((t - 7.25) / 0.3) - ramp((t - 8.45) / 0.3)


def sine(frequency, t):
    return math.sin(2.0 * math.pi * frequency * t)


def row(k):
    """The inputs of step k (at t = k·STEP), in the order of COLUMNS."""
    t = k * STEP
    c = curve_progress(t)
    g = c * (0.93 + 0.07 * math.cos(2.0 * math.pi * 1.3 * t))
    delta = DELTA_TREAD + (DELTA_FLANGE - DELTA_TREAD) * g
    radius = R_TREAD + (R_FLANGE - R_TREAD) * g
    w = wetness(t)
    brake = ramp((t - 0.3) / 0.7)
    return [
        t,
        brake * (0.0006 + 0.0144 * w + 0.0001 * sine(9.0, t)),
        -0.006 * c + 0.0008 * sine(1.2, t),
        math.sin(delta) / radius,
        90e3 + 35e3 * c + 8e3 * sine(1.1, t) + 6e3 * sine(23.0, t),
        25.0 - 0.5 * t,
        w,
        A_TREAD + (A_FLANGE - A_TREAD) * g,
        B_TREAD * (B_FLANGE / B_TREAD) ** g,
        0.0,
        0.0,
    ]


def trace():
    """Every row of the trace, in the order of COLUMNS."""
    return [row(k) for k in range(ROWS)]


def write_csv(path, rows):
    """Writes the trace as CSV with a header; floats as repr (read back bit for bit)."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        w.writerows([repr(x) for x in r] for r in rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(ROOT / "target" / "mbs_trace.csv"))
    a = ap.parse_args()
    rows = trace()
    write_csv(a.out, rows)
    print(f"wrote {a.out}: {len(rows)} rows")
    for j, name in enumerate(COLUMNS[1:], start=1):
        values = [r[j] for r in rows]
        print(f"  {name:<24} {min(values):.6g} … {max(values):.6g}")


if __name__ == "__main__":
    main()
