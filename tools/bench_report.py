#!/usr/bin/env python3
"""Report of `make bench`: every criterion result with its ratio to the Polach formula, the scaling exponent
of the exact solver with the grid, the memory per FMU instance and the MBS trace through the FMU (time per
step, table and exact shares, force errors against the exact solver; standard library only).

Reads target/criterion/**/new/{benchmark,estimates}.json (a benchmark with a throughput of N elements per
iteration is shown per element), target/bench/memory.json and target/bench/mbs_trace.json; prints a table
and writes target/bench/report.md.
"""

import json
import math
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
CRITERION = ROOT / "target" / "criterion"
OUT = ROOT / "target" / "bench"
# Polach through `solve` (Hertz, Kalker's coefficients and the formula per call, as every other entry) and
# the bare formula with the contact precomputed
POLACH = "point/polach_1pct_30mps"
POLACH_FORMULA = "point/polach_formula_only_1pct_30mps"


def results():
    """{full_id: mean time [ns] per iteration, or per element where the benchmark has a throughput of N
    elements}, {full_id: N} of those with one, of every criterion benchmark that has run."""
    found, elements = {}, {}
    for bench in CRITERION.glob("**/new/benchmark.json"):
        meta = json.loads(bench.read_text())
        est = json.loads((bench.parent / "estimates.json").read_text())
        n = (meta.get("throughput") or {}).get("Elements")
        found[meta["full_id"]] = est["mean"]["point_estimate"] / (n or 1)
        if n:
            elements[meta["full_id"]] = n
    return found, elements


def human(ns):
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            return f"{ns / scale:.3g} {unit}"
    return f"{ns:.3g} ns"


def scaling(found):
    """Least-squares slope of log(time) against log(active cells) of the grid_scaling group."""
    pts = sorted(
        (int(k.rsplit("/", 1)[1]), v) for k, v in found.items() if k.startswith("grid_scaling/exact_dry_cells/")
    )
    if len(pts) < 2:
        return None, pts
    xs = [math.log(c) for c, _ in pts]
    ys = [math.log(t) for _, t in pts]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return slope, pts


def trace_section(t, found):
    """The MBS trace through the FMU (fmu/benches/trace.rs): per mode the table and exact shares, the time
    per step and the force errors against mode 2 (exact)."""
    tr = t["trace"]
    ran = {c["id"]: c["status"] for c in t["criterion"]}
    lines = [f"MBS trace through the FMU ({tr['steps']:,} steps of {tr['step_size'] * 1e3:g} ms from "
             f"{pathlib.Path(tr['path']).name}, one thread, bundled table; time per step = setting the inputs "
             f"and fmi2DoStep, timer overhead ≈ {t['timer_overhead_ns']:.0f} ns included; load average "
             f"{t['load_average_start']} at the start, {t['load_average_end']} at the end):", "",
             "| mode | evaluated | by table | by exact | refused | passes | time/step mean | p99 | max "
             "| dry mean / p99 | wet mean / p99 | mean, p99 / Polach's mean | CPU dry mean / p99 "
             "| CPU wet mean / p99 | CPU mean, p99 / Polach's | criterion mean/step |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    polach = t.get("polach")

    def split(s):
        return f"{human(s['mean'])} / {human(s['p99'])}" if s and s["count"] else "–"

    def ratios(m, key="ratio_to_polach"):
        r = m.get(key) or {}
        if r.get("mean") is None:
            return "n/a"
        return f"{r['mean']:,.0f}×, {r['p99']:,.0f}×" if r["mean"] >= 100 else f"{r['mean']:.3g}×, {r['p99']:.3g}×"
    for m in t["modes"]:
        s = m["time_per_step_ns"]
        key = f"mbs_trace/{m['name']}"
        crit = human(found[key]) if ran.get(key) == "run" and key in found else ran.get(key, "–")
        lines.append(f"| {m['mode']} {m['name']} | {m['evaluated']:,} | {m['by_table']:,} | {m['by_exact']:,} | "
                     f"{m['refused']:,} | {m['timing_passes']} | {human(s['mean'])} | {human(s['p99'])} | "
                     f"{human(s['max'])} | {split(m['time_per_step_ns_dry'])} | {split(m['time_per_step_ns_wet'])} | "
                     f"{ratios(m)} | {split(m.get('cpu_time_per_step_ns_dry'))} | "
                     f"{split(m.get('cpu_time_per_step_ns_wet'))} | {ratios(m, 'cpu_ratio_to_polach')} | {crit} |")
    if polach:
        p = polach["time_per_step_ns"]
        lines += ["", f"Polach on the same trace in the same run (the library's Polach law through the evaluation "
                      f"policy, exact mode, each row's geometry; the FMU does not offer the law): time/step mean "
                      f"{human(p['mean'])}, p99 {human(p['p99'])}; dry {split(polach['time_per_step_ns_dry'])}, "
                      f"wet {split(polach['time_per_step_ns_wet'])}; CPU time mean "
                      f"{split(polach.get('cpu_time_per_step_ns'))}. CPU time: the thread's (CLOCK_THREAD_CPUTIME_ID), "
                      f"without the waits of a loaded machine."]
    lines += ["", "Force error against mode 2 (exact) at every evaluated step, relative to F_N (mean / p99 / max):",
              "", "| mode | steps | count | abs(ΔF_x)/F_N | abs(ΔF_y)/F_N | abs(ΔF)/F_N |", "|---|---|---:|---|---|---|"]
    for m in t["modes"]:
        for which, e in m.get("error_vs_exact", {}).items():
            if e["force"]["count"] == 0:
                continue
            cells = " | ".join(f"{e[k]['mean']:.2e} / {e[k]['p99']:.2e} / {e[k]['max']:.2e}"
                               for k in ("force_x", "force_y", "force"))
            lines.append(f"| {m['mode']} {m['name']} | {which.replace('_', ' ')} | {e['force']['count']:,} | {cells} |")
    return lines


def main():
    found, elements = results()
    if not found:
        sys.exit("no criterion results under target/criterion: run `make bench` first")
    def ratio(key, ref):
        if ref not in found:
            return "n/a"
        r = found[key] / found[ref]
        return f"{r:,.0f}×" if r >= 100 else f"{r:.3g}×"

    lines = ["| benchmark | mean time | ratio to Polach via solve | ratio to the bare Polach formula |",
             "|---|---:|---:|---:|"]
    for key in sorted(found):
        label = f"{key} (per step, {elements[key]:,} per iteration)" if key in elements else key
        lines.append(f"| {label} | {human(found[key])} | {ratio(key, POLACH)} | {ratio(key, POLACH_FORMULA)} |")
    slope, pts = scaling(found)
    if slope is not None:
        lines += ["", f"Exact dry point against the grid: time ∝ cells^{slope:.2f} "
                      f"({', '.join(f'{c} cells {human(t)}' for c, t in pts)})."]
    memory = OUT / "memory.json"
    if memory.exists():
        m = json.loads(memory.read_text())
        lines += ["", "| FMU instance | bytes kept after a step | peak working bytes in a step |", "|---|---:|---:|"]
        for row in m["instances"]:
            lines.append(f"| {row['case']} | {row['kept_bytes']:,.0f} | {row['step_peak_bytes']:,} |")
    trace = OUT / "mbs_trace.json"
    if trace.exists():
        lines += [""] + trace_section(json.loads(trace.read_text()), found)
    text = "\n".join(lines) + "\n"
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "report.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
