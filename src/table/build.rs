//! Computing a table with the exact solver (in parallel, deterministic), in one piece or in shards, and
//! merging shards.
//!
//! The points are solved cube by cube: a **creepage cube** holds every (ξ̂, η̂, φ̂) node at one node of
//! (F_N, V, w, a/b, p_ref), i.e. one contact at one load, speed and wetness. Inside a cube the points are
//! solved along lines of ξ̂, each point starting from its predecessor's separations and film
//! ([`crate::solver::solve_from`], continuation) but from the bulk temperature, so that every node holds the
//! fixed point a cold start finds: where the coupled heat problem has two steady states (hot, fast contacts
//! in full slip near the onset of boundary lubrication) a predecessor's temperature could settle on the
//! other one — measured: T_max 898 against 579 K, F_x/F_N 0.117 against 0.093, at equivalent speed 65 m/s,
//! p0 1.2 GPa, ξ = −0.07 after −0.116 (a full warm start is 1.2× faster, a cold start 1.6× slower). The
//! cubes are independent, solved in parallel, each single-threaded and deterministic, and the results are
//! collected in index order, so the array bytes do not depend on the thread count or the scheduling. A
//! shard holds whole cubes.
//!
//! **Coverage windows.** Normalised creepage axes span the raw ranges of the softest contact of the table;
//! a stiff contact reaches its raw limit (|ξ| ≤ 0.1, …) long before the end of the axis, and beyond it the
//! raw creepage would leave what the solver accepts. So each cube solves only the nodes that an in-range
//! evaluation can touch: along each creepage axis, the nodes up to one beyond the first node at or past
//! the coordinate of the raw limit at k_max (raw limit × k_max, or its knee blend, which also grows with
//! k and k_r), where k_max (and k_r,max) is the largest creepage scale of the cube and its neighbours along
//! F_N, a/b and p_ref (every cell an evaluation interpolates in; the creepage scales are monotone in each
//! of them, a raw scale ∝ sqrt(a² + b²) is largest at a cell's ends), which
//! covers the four-node window of the cubic interpolation. With knee-blended axes every contact's raw
//! limit lies at nearly the same coordinate, and the windows cover nearly the whole axis. The nodes beyond hold the values
//! of the nearest covered node (flat continuation, which keeps the monotone interpolation's slopes finite)
//! and are never used by an in-range evaluation (`Table::in_range` checks the raw limits).
//!
//! A point whose coupled iteration does not converge is solved again from a cold start with four times the
//! iteration limits; if it still does not converge, its values are kept,
//! it is flagged 0 in `converged.npy` and listed in the sidecar's `unconverged`, and the build reports it. A
//! point whose solve fails outright fails the build (naming the point).

use super::TableOutput;
use super::axes::{Axes, DIMS, ETA, FORCE, PHI, PRESSURE, RATIO, XI};
use super::coords::{Coordinates, Ellipse, Scale};
use super::file::{
    ArrayRecord, BuildRecord, FORMAT, FORMAT_VERSION, FilmIntake, MODEL_VERSION, OUTPUTS,
    Resolution, ShardRecord, Sidecar, Storage, TableFiles, UnconvergedRecord, axis_records,
    corrupt, cube_count, cube_len, fingerprint, now_iso8601, shard_indices, symmetry_notes,
};
use crate::error::{Error, Result};
use crate::params::{FrictionLaw, OperatingPoint, Params};
use crate::solver::{Solution, Termination, WarmStart, solve, solve_from};
use rayon::prelude::*;
use std::path::Path;
use std::time::Instant;

/// Solves one point exactly (from `warm`, a neighbouring point's state, if given; if that fails, cold); if
/// the coupled iteration reached its limit without converging, once more from a cold start with four times
/// the iteration and fluid-sweep limits (and the same initial relaxation: the outer iteration damps its
/// oscillating cells itself once it stalls, docs/model.md §9; a halved start cleared none of 30 hot nodes
/// that the full one clears 12 of, nor 3 slow ones past the onset of the walls). A stalled iteration (the
/// film has no solution at the settled temperature, [`Termination::Stalled`]) is not retried: more
/// iterations solve the same film. The returned solution may still be unconverged (its report says so).
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
    if s.report.converged || matches!(s.report.termination, Termination::Stalled { .. }) {
        return Ok(s);
    }
    let mut retry = params.clone();
    retry.solver.max_iterations = (params.solver.max_iterations * 4).min(1_000_000);
    retry.solver.max_fluid_sweeps = (params.solver.max_fluid_sweeps * 4).min(10_000_000);
    solve(&retry, point)
}

/// What a table build keeps of one solved point.
#[derive(Clone)]
struct PointResult {
    outputs: [f32; OUTPUTS],
    converged: bool,
    residual: f64,
    film_intake: FilmIntake,
}

/// The stored outputs of a solution at normal force F_N [N], speed V [m/s] with contact radius c = sqrt(a·b)
/// [m]: F_x/F_N, F_y/F_N, M_z/(F_N·c), T_max [K], fluid load fraction, P_f/(F_N·V), rounded to the stored
/// f32 (an error if the solution lacks one, [`TableOutput::from_solution`]).
pub fn normalised(s: &Solution, point: &OperatingPoint, radius: f64) -> Result<[f32; OUTPUTS]> {
    let o = TableOutput::from_solution(s)?;
    let f = point.normal_force;
    Ok([
        o.force_x / f,
        o.force_y / f,
        o.spin_moment / (f * radius),
        o.max_temperature,
        o.fluid_load_fraction,
        s.global.frictional_power / (f * point.speed.abs()),
    ]
    .map(|v| v as f32))
}

/// Refuses a friction law that does not model every stored output: only the Tomberger law models the spin
/// moment, the temperature and the fluid load share (the closed-form Polach law costs microseconds and
/// needs no table).
fn check_law(params: &Params) -> Result<()> {
    match params.friction.law {
        FrictionLaw::Tomberger => return Ok(()),
        FrictionLaw::Constant | FrictionLaw::Polach => {}
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

/// The largest raw |creepage| the exact solver accepts along each creepage axis (ξ, η [-], φ [1/m]).
const SOLVER_RAW_LIMITS: [f64; 3] = [1.9, 1.9, 1e4];

/// The node indices of one creepage axis that a cube solves (inclusive), for in-range evaluations up to the
/// normalised coordinate `x` (see the module documentation).
fn window(points: &[f64], x: f64) -> (usize, usize) {
    let n = points.len();
    let hi = points
        .iter()
        .position(|p| *p >= x)
        .map_or(n - 1, |m| (m + 1).min(n - 1));
    let lo = points
        .iter()
        .rposition(|p| *p <= -x)
        .map_or(0, |m| m.saturating_sub(1));
    (lo, hi)
}

/// One creepage cube of a build: its node of (F_N, V, w, a/b, p_ref) as coordinates, contact, creepage
/// scales and coverage windows.
struct Cube {
    /// Cube index (flat index mod the number of cubes).
    index: usize,
    /// Coordinates of the cube's node (the creepage entries unused).
    node: [f64; DIMS],
    /// The parameters with the cube's contact as prescribed semi-axes.
    params: Params,
    /// The cube's contact ellipse.
    ellipse: Ellipse,
    /// k_x, k_y, k_φ of the cube's contact, with their raw scales.
    scales: [Scale; 3],
    /// Solved node range along ξ̂, η̂, φ̂.
    windows: [(usize, usize); 3],
}

impl Cube {
    /// Cube `index` of `axes`: its contact and its windows from the creepage scales of its neighbourhood.
    fn new(index: usize, axes: &Axes, params: &Params, coords: &Coordinates) -> Result<Cube> {
        let shape = axes.shape();
        // node indices of the cube along F_N … p_ref (C order, p_ref fastest)
        let mut rest = index;
        let mut at = [0usize; DIMS];
        for d in (FORCE..DIMS).rev() {
            at[d] = rest % shape[d];
            rest /= shape[d];
        }
        let coordinate = |d: usize, i: usize| axes.0[d].points[i];
        let node: [f64; DIMS] =
            std::array::from_fn(|d| if d < FORCE { 0.0 } else { coordinate(d, at[d]) });
        let contact = |f: usize, r: usize, p: usize| -> Result<(Ellipse, [Scale; 3])> {
            let force = coordinate(FORCE, f);
            let [a, b] =
                super::coords::semi_axes(coordinate(RATIO, r), coordinate(PRESSURE, p), force);
            let e = Ellipse {
                a,
                b,
                load_exponent: 0.0,
            };
            Ok((e, coords.scales(&e, force)?))
        };
        let (e, scales) = contact(at[FORCE], at[RATIO], at[PRESSURE])?;
        let span = |d: usize| at[d].saturating_sub(1)..=(at[d] + 1).min(shape[d] - 1);
        let mut k_max = scales;
        for f in span(FORCE) {
            for r in span(RATIO) {
                for p in span(PRESSURE) {
                    let (_, k) = contact(f, r, p)?;
                    for d in 0..3 {
                        k_max[d] = k_max[d].max(k[d]);
                    }
                }
            }
        }
        let mut windows = [(0, 0); 3];
        for (d, w) in windows.iter_mut().enumerate() {
            let axis = &axes.0[d];
            let limit = axis.raw_limit.unwrap_or(axis.max());
            // the coordinate of the raw limit grows with k and k_r (coords::map is increasing in both)
            *w = window(&axis.points, k_max[d].map(limit).q);
            let reach = scales[d].unmap(axis.points[w.0].abs().max(axis.points[w.1].abs()));
            if coords.normalised() && reach > SOLVER_RAW_LIMITS[d] {
                return Err(Error::Table {
                    path: "<build>".into(),
                    reason: format!(
                        "axis {}: the contact a = {:.3e} m, b = {:.3e} m at F_N = {} N needs raw {} up \
                         to {reach:.3} (beyond {}) to cover its neighbours' range: use closer points \
                         along normal_force, semi_axis_ratio and reference_pressure",
                        super::axes::DIMENSIONS[d].name,
                        e.a,
                        e.b,
                        node[FORCE],
                        super::axes::DIMENSIONS[d].name,
                        SOLVER_RAW_LIMITS[d]
                    ),
                });
            }
        }
        let mut p = params.clone();
        p.geometry.semi_axes = Some([e.a, e.b]);
        Ok(Cube {
            index,
            node,
            params: p,
            ellipse: e,
            scales,
            windows,
        })
    }

    /// The operating point of creepage node (i, j, l) of the cube.
    fn point(&self, axes: &Axes, [i, j, l]: [usize; 3]) -> OperatingPoint {
        OperatingPoint {
            creepage_x: self.scales[0].unmap(axes.0[XI].points[i]),
            creepage_y: self.scales[1].unmap(axes.0[ETA].points[j]),
            spin: self.scales[2].unmap(axes.0[PHI].points[l]),
            normal_force: self.node[FORCE],
            speed: self.node[FORCE + 1],
            wetness: self.node[FORCE + 2],
        }
    }

    /// Solves the cube's covered nodes (lines of ξ̂ by continuation) and fills the others with the nearest
    /// covered node's result: per creepage node in C order, the result (or the error's text) and whether
    /// it was solved (not a copy).
    fn solve(
        &self,
        axes: &Axes,
        on_point: &(dyn Fn() + Sync),
    ) -> Vec<(std::result::Result<PointResult, String>, bool)> {
        let [nx, ny, np] = [
            axes.0[XI].points.len(),
            axes.0[ETA].points.len(),
            axes.0[PHI].points.len(),
        ];
        let flat = |i: usize, j: usize, l: usize| (i * ny + j) * np + l;
        let mut out: Vec<Option<std::result::Result<PointResult, String>>> =
            vec![None; nx * ny * np];
        let [wx, wy, wp] = self.windows;
        let radius = self.ellipse.radius();
        for j in wy.0..=wy.1 {
            for l in wp.0..=wp.1 {
                let mut warm: Option<WarmStart> = None;
                for i in wx.0..=wx.1 {
                    let point = self.point(axes, [i, j, l]);
                    let r = solve_with_retry(&self.params, &point, warm.as_ref());
                    // the next node starts from this one's separations and film, but from the bulk
                    // temperature: where the heat has two steady states (hot, fast, wet contacts in full
                    // slip) a warm temperature can settle on the other one than a cold start — the
                    // solution `table verify`, `point` and a fresh FMU instance compute
                    warm = r.as_ref().ok().and_then(Solution::warm_start).map(|mut w| {
                        w.temperature.fill(self.params.material.bulk_temperature);
                        w
                    });
                    on_point();
                    out[flat(i, j, l)] = Some(
                        r.and_then(|sol| {
                            Ok(PointResult {
                                outputs: normalised(&sol, &point, radius)?,
                                converged: sol.report.converged,
                                residual: sol.report.residual,
                                film_intake: FilmIntake::of(
                                    point.wetness,
                                    sol.global.max_dry_area_fraction,
                                ),
                            })
                        })
                        .map_err(|e| {
                            format!(
                                "{point:?} at semi-axes [{:e}, {:e}] m: {e}",
                                self.ellipse.a, self.ellipse.b
                            )
                        }),
                    );
                }
            }
        }
        let clamp = |x: usize, w: (usize, usize)| x.clamp(w.0, w.1);
        let mut cube = Vec::with_capacity(nx * ny * np);
        for i in 0..nx {
            for j in 0..ny {
                for l in 0..np {
                    let (ci, cj, cl) = (clamp(i, wx), clamp(j, wy), clamp(l, wp));
                    let solved = (ci, cj, cl) == (i, j, l);
                    if !solved {
                        on_point();
                    }
                    let r = out[flat(ci, cj, cl)]
                        .clone()
                        .expect("every covered node is solved");
                    cube.push((r, solved));
                }
            }
        }
        cube
    }
}

/// Builds all points of a table (`shard` None) or one shard of it. `on_point` is called once per stored
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
    if !axes.normalised() {
        return Err(Error::Table {
            path: "<build>".into(),
            reason: "the creepage axes need raw limits (normalised creepages)".into(),
        });
    }
    let s = shard.unwrap_or(ShardRecord { index: 1, count: 1 });
    if s.count == 0 || s.index == 0 || s.index > s.count {
        return Err(Error::out_of_range(
            "shard",
            s.index as f64,
            &format!("K/N with 1 <= K <= N (got {}/{})", s.index, s.count),
        ));
    }
    let coords = Coordinates::new(params, axes);
    let start = Instant::now();
    let cubes = cube_count(axes);
    let mine: Vec<Cube> = (0..cubes)
        .filter(|t| t % s.count == s.index - 1)
        .map(|t| Cube::new(t, axes, params, &coords))
        .collect::<Result<_>>()?;
    let solved: Vec<Vec<(std::result::Result<PointResult, String>, bool)>> = mine
        .par_iter()
        .with_max_len(1)
        .map(|c| c.solve(axes, on_point))
        .collect();
    // the shard's points in flat index order: creepage node slowest, cube fastest
    let per_cube = cube_len(axes);
    let n = mine.len() * per_cube;
    let mut outputs: Vec<Vec<f32>> = (0..OUTPUTS).map(|_| Vec::with_capacity(n)).collect();
    let mut converged = Vec::with_capacity(n);
    let mut film_intake = Vec::with_capacity(n);
    let mut unconverged = Vec::new();
    let mut failures = Vec::new();
    for c in 0..per_cube {
        for (cube, results) in mine.iter().zip(&solved) {
            let index = c * cubes + cube.index;
            match &results[c].0 {
                Ok(p) => {
                    for (o, v) in outputs.iter_mut().zip(p.outputs) {
                        o.push(v);
                    }
                    converged.push(u8::from(p.converged));
                    film_intake.push(p.film_intake as u8);
                    if !p.converged && results[c].1 {
                        unconverged.push(UnconvergedRecord {
                            index,
                            point: cube.point(axes, creepage_node(axes, c)),
                            residual: p.residual,
                        });
                    }
                }
                Err(e) if results[c].1 => failures.push(e.clone()),
                Err(_) => {}
            }
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
    unconverged.sort_by_key(|u| u.index);
    debug_assert_eq!(shard_indices(axes, s).len(), converged.len());
    Ok(TableFiles {
        sidecar: sidecar(
            params,
            axes,
            shard,
            unconverged,
            start.elapsed().as_secs_f64(),
        ),
        axes: axes.clone(),
        outputs,
        converged,
        film_intake: Some(film_intake),
    })
}

/// A table of values given by a function of the table coordinates (ξ̂, η̂, φ̂, F_N, V, w, a/b, p_ref) instead
/// of the exact solver, every point marked converged: synthetic tables for tests and benchmarks.
pub(crate) fn tabulate(
    params: &Params,
    axes: &Axes,
    f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
) -> TableFiles {
    let n = axes.len();
    let mut outputs: Vec<Vec<f32>> = (0..OUTPUTS).map(|_| Vec::with_capacity(n)).collect();
    for i in 0..n {
        for (o, v) in outputs.iter_mut().zip(f(&axes.coordinates(i))) {
            o.push(v as f32);
        }
    }
    TableFiles {
        sidecar: sidecar(params, axes, None, Vec::new(), 0.0),
        axes: axes.clone(),
        outputs,
        converged: vec![1; n],
        film_intake: None,
    }
}

/// The files of a table on the nodes of `axes` for timing lookups and FMU steps on its layout without
/// building it (a lookup costs the same whatever the values): a smooth function shaped like the model's
/// outputs (forces saturating along ξ̂ and η̂, falling with speed and wetness; a spin moment along φ̂; T_max
/// rising with |ξ̂|; a fluid share growing with w; a frictional power), and at the probe nodes the exact
/// solutions, so that loading ([`super::Table::load`], the FMU) accepts the table.
pub fn timing_files(params: &Params, axes: &Axes) -> Result<TableFiles> {
    let mut files = tabulate(params, axes, &|q| {
        let saturated = |x: f64| (x / 0.4).tanh();
        let falling = 1.0 - 0.001 * q[4] - 0.3 * q[5];
        [
            -0.4 * falling * saturated(q[0]),
            -0.4 * falling * (saturated(q[1]) + 0.1 * saturated(q[2])),
            0.01 * saturated(q[2]),
            300.0 + 100.0 * q[0].abs().sqrt(),
            0.5 * q[5],
            0.01 * saturated(q[0]).abs(),
        ]
    });
    // the probe nodes as the loaded table finds them (every point converged), without laying out its rows
    let coordinates = Coordinates::new(params, axes);
    for n in super::probe_nodes(axes, |n| files.converged[n] == 1) {
        let (_, _, exact) = super::exact_at_node(params, &coordinates, axes, n)?;
        for (o, v) in exact.into_iter().enumerate() {
            files.outputs[o][n] = v;
        }
    }
    Ok(files)
}

/// The sidecar of a build (outputs and converged records are filled in when written).
fn sidecar(
    params: &Params,
    axes: &Axes,
    shard: Option<ShardRecord>,
    unconverged: Vec<UnconvergedRecord>,
    duration_seconds: f64,
) -> Sidecar {
    let empty = ArrayRecord {
        name: String::new(),
        unit: String::new(),
        description: String::new(),
        file: String::new(),
        sha256: String::new(),
        quantization: None,
    };
    Sidecar {
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
        film_intake: None,
        moment_scale: None,
        shard,
        storage: Storage::F32,
        resolution: None,
        build: BuildRecord {
            date: now_iso8601(),
            duration_seconds,
            threads: rayon::current_num_threads(),
            merged_shards: 0,
        },
    }
}

/// Whether two builds (tables or shards, by sidecar and axes) computed the same values: the same
/// parameters (and fingerprint), axes, model version, storage and resolution; their shard records aside.
fn same_build((s, axes): (&Sidecar, &Axes), (other, other_axes): (&Sidecar, &Axes)) -> bool {
    s.fingerprint == other.fingerprint
        && s.params == other.params
        && axes == other_axes
        && s.model_version == other.model_version
        && s.storage == other.storage
        && s.resolution == other.resolution
}

/// Whether `dir` already holds what [`build`] computes from `params`, `axes` and `shard`, recorded with
/// `storage` and `resolution`: a table (or shard) that reads and verifies (sidecar, every array's SHA-256)
/// and was built with the same parameters, axes, model version, storage, resolution and shard. An
/// interrupted or resubmitted sharded build so recomputes only what is missing (`wheelrail table build
/// --resume`); a directory the build was killed while writing fails the checksums (the sidecar is written
/// last) and is not built.
pub fn is_built(
    dir: &Path,
    params: &Params,
    axes: &Axes,
    shard: Option<ShardRecord>,
    storage: Storage,
    resolution: Option<Resolution>,
) -> bool {
    let Ok(t) = TableFiles::read(dir) else {
        return false;
    };
    let mut expected = sidecar(params, axes, shard, Vec::new(), 0.0);
    expected.storage = storage;
    expected.resolution = resolution;
    t.sidecar.shard == shard && same_build((&t.sidecar, &t.axes), (&expected, axes))
}

/// The (ξ̂, η̂, φ̂) node indices of creepage node `c` (C order within a cube).
fn creepage_node(axes: &Axes, c: usize) -> [usize; 3] {
    let (ny, np) = (axes.0[ETA].points.len(), axes.0[PHI].points.len());
    [c / (ny * np), (c / np) % ny, c % np]
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
        if !same_build((&t.sidecar, &t.axes), (&first.sidecar, &first.axes)) {
            return Err(corrupt(
                p,
                format!(
                    "was built with other parameters, axes, storage, resolution or model version than {}",
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
    let mut outputs = vec![vec![0.0f32; total]; OUTPUTS];
    let mut converged = vec![0u8; total];
    // recorded by every shard, or by none (shards of one build agree)
    let mut film_intake = shards
        .iter()
        .all(|(t, _)| t.film_intake.is_some())
        .then(|| vec![FilmIntake::Dry as u8; total]);
    let mut unconverged = Vec::new();
    let mut duration = 0.0;
    let mut threads = 0;
    for (t, path) in &shards {
        let k = t.sidecar.shard.map_or(1, |s| s.index);
        let indices = shard_indices(&axes, ShardRecord { index: k, count });
        if indices.len() != t.converged.len()
            || t.outputs.iter().any(|o| o.len() != indices.len())
            || t.film_intake
                .as_ref()
                .is_some_and(|f| f.len() != indices.len())
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
            if let (Some(all), Some(part)) = (film_intake.as_mut(), &t.film_intake) {
                all[i] = part[j];
            }
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
        film_intake,
    })
}
