//! Computing a table with the exact solver (in parallel, deterministic), in one piece or in shards, and
//! merging shards.
//!
//! The points are solved along lines of ξ (all other coordinates fixed), each point of a line starting from
//! its predecessor's state ([`crate::solver::solve_from`], continuation); the lines are independent, solved
//! in parallel, each single-threaded and deterministic, and the results are collected in index order, so the
//! array bytes do not depend on the thread count or the scheduling. A shard holds whole lines. A point
//! whose coupled iteration does not converge is solved again from a cold start with four times the
//! iteration limits and half the initial relaxation; if it still does not converge, its values are kept, it is flagged 0 in
//! `converged.npy` and listed in the sidecar's `unconverged`, and the build reports it. A point whose solve
//! fails outright fails the build (naming the point).

use super::TableOutput;
use super::axes::{Axes, DIMS, FORCE};
use super::file::{
    ArrayRecord, BuildRecord, FORMAT, FORMAT_VERSION, MODEL_VERSION, MomentScale, OUTPUTS,
    ShardRecord, Sidecar, TableFiles, UnconvergedRecord, axis_records, corrupt, fingerprint,
    line_stride, now_iso8601, shard_indices, symmetry_notes,
};
use crate::error::{Error, Result};
use crate::params::{FrictionLaw, OperatingPoint, Params};
use crate::solver::{Solution, WarmStart, solve, solve_from};
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

/// The operating point of table coordinates (ξ, η, φ, F_N, V, w).
pub fn operating_point(c: &[f64; DIMS]) -> OperatingPoint {
    OperatingPoint {
        creepage_x: c[0],
        creepage_y: c[1],
        spin: c[2],
        normal_force: c[3],
        speed: c[4],
        wetness: c[5],
    }
}

/// Solves one point exactly (from `warm`, a neighbouring point's state, if given; if that fails, cold); if
/// the coupled iteration does not converge, once more from a cold start with four times the iteration and fluid-sweep limits and
/// half the initial relaxation. The returned solution may still be unconverged (its report says so).
pub fn solve_with_retry(
    params: &Params,
    point: &OperatingPoint,
    warm: Option<&WarmStart>,
) -> Result<Solution> {
    // a warm start that fails outright is retried cold before anything else
    let s = match solve_from(params, point, warm) {
        Err(_) if warm.is_some() => solve(params, point)?,
        r => r?,
    };
    if s.report.converged {
        return Ok(s);
    }
    let mut retry = params.clone();
    retry.solver.max_iterations = (params.solver.max_iterations * 4).min(1_000_000);
    retry.solver.max_fluid_sweeps = (params.solver.max_fluid_sweeps * 4).min(10_000_000);
    retry.solver.relaxation = (params.solver.relaxation * 0.5).max(1e-3);
    solve(&retry, point)
}

/// What a table build keeps of one solved point.
struct PointResult {
    outputs: [f64; OUTPUTS],
    converged: bool,
    residual: f64,
}

/// The stored outputs of a solution: F_x/F_N, F_y/F_N, M_z/(F_N·c(F_N)), T_max [K], fluid load fraction
/// (an error if the solution lacks one, [`TableOutput::from_solution`]).
pub fn normalised(s: &Solution, normal_force: f64, scale: &MomentScale) -> Result<[f64; OUTPUTS]> {
    let o = TableOutput::from_solution(s)?;
    Ok([
        o.force_x / normal_force,
        o.force_y / normal_force,
        o.spin_moment / (normal_force * scale.radius(normal_force)),
        o.max_temperature,
        o.fluid_load_fraction,
    ])
}

/// Refuses a friction law that does not model every stored output: only the Tomberger law models the spin
/// moment, the temperature and the fluid load share (the closed-form Polach law costs microseconds and
/// needs no table).
fn check_law(params: &Params) -> Result<()> {
    if params.friction.law == FrictionLaw::Tomberger {
        return Ok(());
    }
    Err(Error::OutOfRange {
        name: "friction.law".into(),
        value: params.friction.law.to_string(),
        allowed:
            "tomberger (a table stores the spin moment, the maximum temperature and the fluid load \
                  fraction, which only its model gives)"
                .into(),
    })
}

/// Builds all points of a table (`shard` None) or one shard of it. `on_point` is called once per solved
/// point, from the worker threads (for a progress bar).
pub fn build(
    params: &Params,
    axes: &Axes,
    shard: Option<ShardRecord>,
    on_point: &(dyn Fn() + Sync),
) -> Result<TableFiles> {
    params.validate()?;
    check_law(params)?;
    axes.validate()?;
    let s = shard.unwrap_or(ShardRecord { index: 1, count: 1 });
    if s.count == 0 || s.index == 0 || s.index > s.count {
        return Err(Error::out_of_range(
            "shard",
            s.index as f64,
            &format!("K/N with 1 <= K <= N (got {}/{})", s.index, s.count),
        ));
    }
    let scale = MomentScale::of(params, axes.0[FORCE].points[0])?;
    let indices = shard_indices(axes, s);
    let start = Instant::now();
    // each ξ line is one continuation chain (every point starts from its predecessor along ξ); lines are
    // solved in parallel and their results put back in index order
    let stride = line_stride(axes);
    let lines: Vec<usize> = indices.iter().filter(|&&i| i < stride).copied().collect();
    // per point only what the table keeps (a full solution holds ~100 kB of fields): the normalised
    // outputs and the convergence report, or the error's text
    let mut solved: Vec<(usize, std::result::Result<PointResult, String>)> = lines
        .par_iter()
        .with_max_len(1)
        .flat_map_iter(|&line| {
            let mut warm: Option<WarmStart> = None;
            (line..axes.len())
                .step_by(stride)
                .map(|i| {
                    let point = operating_point(&axes.coordinates(i));
                    let r = solve_with_retry(params, &point, warm.as_ref());
                    warm = r.as_ref().ok().and_then(Solution::warm_start);
                    on_point();
                    let kept = r
                        .and_then(|sol| {
                            Ok(PointResult {
                                outputs: normalised(&sol, point.normal_force, &scale)?,
                                converged: sol.report.converged,
                                residual: sol.report.residual,
                            })
                        })
                        .map_err(|e| format!("{point:?}: {e}"));
                    (i, kept)
                })
                .collect::<Vec<_>>()
        })
        .collect();
    solved.sort_by_key(|(i, _)| *i);
    let mut outputs: Vec<Vec<f64>> = (0..OUTPUTS)
        .map(|_| Vec::with_capacity(indices.len()))
        .collect();
    let mut converged = Vec::with_capacity(indices.len());
    let mut unconverged = Vec::new();
    let mut failures = Vec::new();
    for (i, r) in solved {
        match r {
            Ok(p) => {
                for (o, v) in outputs.iter_mut().zip(p.outputs) {
                    o.push(v);
                }
                converged.push(u8::from(p.converged));
                if !p.converged {
                    unconverged.push(UnconvergedRecord {
                        index: i,
                        point: operating_point(&axes.coordinates(i)),
                        residual: p.residual,
                    });
                }
            }
            Err(e) => failures.push(e),
        }
    }
    if !failures.is_empty() {
        let n = failures.len();
        failures.truncate(5);
        return Err(Error::Table {
            path: "<build>".into(),
            reason: format!(
                "the exact solver failed at {n} point(s), e.g. {}",
                failures.join("; ")
            ),
        });
    }
    let empty = ArrayRecord {
        name: String::new(),
        unit: String::new(),
        description: String::new(),
        file: String::new(),
        sha256: String::new(),
    };
    Ok(TableFiles {
        sidecar: Sidecar {
            format: FORMAT.into(),
            format_version: FORMAT_VERSION,
            model_version: MODEL_VERSION.into(),
            fingerprint: fingerprint(params),
            params: params.clone(),
            axes: axis_records(axes),
            symmetry: symmetry_notes(axes),
            outputs: Vec::new(),
            converged: empty,
            unconverged,
            moment_scale: scale,
            shard,
            build: BuildRecord {
                date: now_iso8601(),
                duration_seconds: start.elapsed().as_secs_f64(),
                threads: rayon::current_num_threads(),
                merged_shards: 0,
            },
        },
        axes: axes.clone(),
        outputs,
        converged,
    })
}

/// Joins the shards 1..=N of one build into the full table. They must come from the same parameters, axes
/// and model version and cover every part exactly once. The arrays equal those of a build in one piece.
pub fn merge(mut shards: Vec<(TableFiles, &Path)>) -> Result<TableFiles> {
    let Some((first, first_path)) = shards.first() else {
        return Err(corrupt(Path::new("<merge>"), "no shards given"));
    };
    let first_path = first_path.to_path_buf();
    let count = match first.sidecar.shard {
        Some(s) => s.count,
        None => return Err(corrupt(&first_path, "is a complete table, not a shard")),
    };
    for (t, p) in &shards {
        let Some(s) = t.sidecar.shard else {
            return Err(corrupt(p, "is a complete table, not a shard"));
        };
        if s.count != count {
            return Err(corrupt(
                p,
                format!(
                    "is shard {}/{}, the others are of {count}",
                    s.index, s.count
                ),
            ));
        }
        let f = &first.sidecar;
        let same = t.sidecar.fingerprint == f.fingerprint
            && t.sidecar.params == f.params
            && t.axes == first.axes
            && t.sidecar.moment_scale == f.moment_scale
            && t.sidecar.model_version == f.model_version;
        if !same {
            return Err(corrupt(
                p,
                format!(
                    "was built with other parameters, axes or model version than {}",
                    first_path.display()
                ),
            ));
        }
    }
    shards.sort_by_key(|(t, _)| t.sidecar.shard.map(|s| s.index));
    let idx: Vec<usize> = shards
        .iter()
        .map(|(t, _)| t.sidecar.shard.map_or(0, |s| s.index))
        .collect();
    if idx != (1..=count).collect::<Vec<_>>() {
        return Err(corrupt(
            &first_path,
            format!("shards {idx:?} given; need each of 1..={count} exactly once"),
        ));
    }
    let axes = shards[0].0.axes.clone();
    let total = axes.len();
    let mut outputs = vec![vec![0.0; total]; OUTPUTS];
    let mut converged = vec![0u8; total];
    let mut unconverged = Vec::new();
    let mut duration = 0.0;
    let mut threads = 0;
    for (t, path) in &shards {
        let k = t.sidecar.shard.map_or(1, |s| s.index);
        let indices = shard_indices(&axes, ShardRecord { index: k, count });
        if indices.len() != t.converged.len() || t.outputs.iter().any(|o| o.len() != indices.len())
        {
            return Err(corrupt(
                path,
                format!("shard {k}/{count} does not hold the points of its part"),
            ));
        }
        for (j, &i) in indices.iter().enumerate() {
            for (o, src) in outputs.iter_mut().zip(&t.outputs) {
                o[i] = src[j];
            }
            converged[i] = t.converged[j];
        }
        unconverged.extend(t.sidecar.unconverged.iter().cloned());
        duration += t.sidecar.build.duration_seconds;
        threads = threads.max(t.sidecar.build.threads);
    }
    unconverged.sort_by_key(|u| u.index);
    let mut sidecar = shards[0].0.sidecar.clone();
    sidecar.shard = None;
    sidecar.unconverged = unconverged;
    sidecar.build = BuildRecord {
        date: now_iso8601(),
        duration_seconds: duration,
        threads,
        merged_shards: count,
    };
    Ok(TableFiles {
        sidecar,
        axes,
        outputs,
        converged,
    })
}
