//! `wheelrail table`: build, merge, verify and describe lookup tables, write Slurm array jobs
//! of sharded builds, and the JSON of a point
//! evaluated by table (`wheelrail point --table DIR`, [`point_json`]).

use super::{StorageArg, TangentialArg};
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Instant;
use wheelrail::table::file::{ShardRecord, TableFiles};
use wheelrail::table::verify::{
    self, TARGET_MAX, TARGET_P99, TARGET_TEMPERATURE_P99, VerifyReport,
};
use wheelrail::table::{self, Axes, DIMENSIONS, Resolution, Storage, Table, TableOutput, coords};
use wheelrail::{OperatingPoint, Params};
use wheelrail_cli::slurm::{self, SlurmJob};

/// Arguments of `wheelrail table`.
#[derive(Debug, Args)]
pub struct TableArgs {
    #[command(subcommand)]
    command: TableCommand,
}

#[derive(Debug, Subcommand)]
enum TableCommand {
    /// Compute a table with the exact solver on all cores (progress and ETA on stderr).
    Build(BuildArgs),
    /// Join the shards 1..N of a build into one table (identical to a build in one piece).
    Merge(MergeArgs),
    /// Compare a table with the exact solver at random points and cell midpoints; exits with 1 if the
    /// target (p99 of |ΔF|/F_N ≤ 0.01, max ≤ 0.03) is missed.
    Verify(VerifyArgs),
    /// Describe a table or shard: format, model version, parameters, axes, build.
    Info(InfoArgs),
    /// Write a Slurm array job that builds the table in N shards (OUT/build.sbatch), the job that merges
    /// and verifies them (OUT/merge.sbatch) and OUT/submit.sh, which submits both.
    Slurm(SlurmArgs),
    /// Write the axes file of a table that covers the contacts of a CSV file (semi-axes a, b at a normal
    /// force, or gap curvatures A, B) and print its points, cost, bytes and the `table slurm` command.
    Plan(super::plan::PlanArgs),
}

#[derive(Debug, Args)]
struct BuildArgs {
    /// Parameter file (TOML) [default: the default parameter set].
    #[arg(long, value_name = "FILE.toml")]
    params: Option<PathBuf>,
    /// Tangential contact solver of every point [default: fastsim, or the parameter file's]; recorded
    /// in table.json's parameters.
    #[arg(long, value_enum)]
    tangential: Option<TangentialArg>,
    /// Axes file (TOML): per axis `points = [...]`, or `min`, `max`, `count`, `spacing` (linear, log,
    /// sinh) and `scale` (sinh) [default: the built-in axes].
    #[arg(long, value_name = "FILE.toml")]
    axes: Option<PathBuf>,
    /// Output directory.
    #[arg(long, value_name = "DIR", default_value = "table")]
    out: PathBuf,
    /// Build only part K of N (1 ≤ K ≤ N: the whole creepage cubes t with t mod N = K − 1), e.g. one task of a
    /// cluster array job; join the parts with `wheelrail table merge`.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// How the table stores its outputs: f32, u16 (16-bit codes, half the bytes: rounding about 1e-5 of
    /// F/F_N and 0.01 K of T_max), u16z (the same codes compressed: about a sixth of the f32 bytes) or u16x
    /// (compressed by xz: about a tenth of the f32 bytes). A
    /// shard stores f32 and records it for `wheelrail table merge`.
    #[arg(long, value_enum, default_value = "f32")]
    storage: StorageArg,
    /// With a u16 storage: the coarsest code steps F,T, F of the outputs per normal force (F/F_N, M_z/(F_N·c),
    /// the fluid load fraction, P_f/(F_N·V)) and T of T_max [K], e.g. 1e-4,0.1: each value within half a
    /// step of the computed one, about half the compressed bytes [default: range/65 535 per array].
    #[arg(long, value_name = "F,T", value_parser = Resolution::parse)]
    resolution: Option<Resolution>,
    /// Keep what --out holds if it is this build (the same parameters, axes, shard, storage, resolution and
    /// model version; every array's checksum verified) and compute nothing; build as without otherwise. A
    /// resubmitted array job or a rerun of an interrupted series of shards so recomputes only the
    /// shards that are missing or damaged.
    #[arg(long)]
    resume: bool,
}

#[derive(Debug, Args)]
struct SlurmArgs {
    /// Number of shards N (array tasks 1..N; at most the number of creepage cubes).
    #[arg(long, value_name = "N")]
    shards: usize,
    /// Job directory on a file system the compute nodes share: the scripts, logs/, shards/K and the merged
    /// table/.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Parameter file (TOML) of every shard [default: the default parameter set].
    #[arg(long, value_name = "FILE.toml")]
    params: Option<PathBuf>,
    /// Tangential contact solver of every shard [default: fastsim, or the parameter file's].
    #[arg(long, value_enum)]
    tangential: Option<TangentialArg>,
    /// Axes file (TOML) of every shard [default: the built-in axes].
    #[arg(long, value_name = "FILE.toml")]
    axes: Option<PathBuf>,
    /// Storage of the merged table (`table build --storage`).
    #[arg(long, value_enum, default_value = "f32")]
    storage: StorageArg,
    /// Coarsest code steps of the merged table's u16 storage (`table build --resolution`).
    #[arg(long, value_name = "F,T", value_parser = Resolution::parse)]
    resolution: Option<Resolution>,
    /// CPUs per array task, also each build's worker threads (RAYON_NUM_THREADS).
    #[arg(long, value_name = "C", default_value_t = 1)]
    cpus_per_task: usize,
    /// Time limit per task (sbatch --time) [default: the partition's].
    #[arg(long, value_name = "HH:MM:SS")]
    time: Option<String>,
    /// Partition (sbatch --partition) [default: the cluster's].
    #[arg(long, value_name = "P")]
    partition: Option<String>,
    /// The wheelrail executable the tasks run [default: this one].
    #[arg(long, value_name = "PATH")]
    wheelrail: Option<PathBuf>,
    /// Sample points of `table verify` after the merge (0: merge only).
    #[arg(long, value_name = "N", default_value_t = 2000)]
    verify_samples: usize,
}

#[derive(Debug, Args)]
struct MergeArgs {
    /// Output directory of the merged table.
    out: PathBuf,
    /// The shard directories (each of 1..N exactly once).
    #[arg(required = true)]
    shards: Vec<PathBuf>,
    /// Store the merged table so instead of as the shards record (`table build --storage`; the shards hold
    /// f32 values, so any storage is exact): e.g. to fit a size budget without computing again.
    #[arg(long, value_enum)]
    storage: Option<StorageArg>,
    /// With --storage or a recorded u16 storage: the resolution instead of the recorded one (`table build
    /// --resolution`; without it, with --storage: the finest codes).
    #[arg(long, value_name = "F,T", value_parser = Resolution::parse)]
    resolution: Option<Resolution>,
}

#[derive(Debug, Args)]
struct VerifyArgs {
    /// Table directory.
    dir: PathBuf,
    /// Number of sample points (half uniform random, half cell midpoints).
    #[arg(long, default_value_t = 2000)]
    samples: usize,
    /// Seed of the sample points.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Print the report as one JSON object.
    #[arg(long)]
    json: bool,
    /// Also write every compared sample (operating point, contact, table and exact outputs, errors) to
    /// this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct InfoArgs {
    /// Table (or shard) directory.
    dir: PathBuf,
}

/// Runs `wheelrail table`.
pub fn run(a: &TableArgs) -> Result<()> {
    match &a.command {
        TableCommand::Build(b) => build(b),
        TableCommand::Merge(m) => merge(m),
        TableCommand::Verify(v) => run_verify(v),
        TableCommand::Info(i) => info(&i.dir),
        TableCommand::Slurm(s) => slurm(s),
        TableCommand::Plan(p) => super::plan::run(p),
    }
}

fn parse_shard(text: &str) -> Result<ShardRecord> {
    let bad = || wheelrail::Error::OutOfRange {
        name: "shard".into(),
        value: text.into(),
        allowed: "K/N with whole numbers 1 <= K <= N".into(),
    };
    let (k, n) = text.split_once('/').ok_or_else(bad)?;
    let (index, count) = (
        k.trim().parse::<usize>().map_err(|_| bad())?,
        n.trim().parse::<usize>().map_err(|_| bad())?,
    );
    if index == 0 || index > count {
        bail!(bad());
    }
    Ok(ShardRecord { index, count })
}

fn progress(len: usize, what: &str) -> ProgressBar {
    let pb = ProgressBar::new(len as u64);
    pb.set_style(
        ProgressStyle::with_template(&format!(
            "{{elapsed_precise}} [{{wide_bar}}] {{pos}}/{{len}} {what}, ETA {{eta_precise}}"
        ))
        .expect("valid template"),
    );
    pb
}

fn build(a: &BuildArgs) -> Result<()> {
    let mut params = match &a.params {
        Some(p) => Params::from_toml_file(p)?,
        None => Params::default(),
    };
    if let Some(t) = a.tangential {
        params.tangential = t.into();
    }
    let axes = match &a.axes {
        Some(p) => Axes::from_toml_file(p)?,
        None => Axes::default(),
    };
    let shard = a.shard.as_deref().map(parse_shard).transpose()?;
    let storage = a.storage.into();
    needs_u16(storage, a.resolution)?;
    if a.resume && table::is_built(&a.out, &params, &axes, shard, storage, a.resolution) {
        eprintln!(
            "{} already holds this build (--resume): kept, nothing computed",
            a.out.display()
        );
        return Ok(());
    }
    let points = match shard {
        Some(s) => table::file::shard_len(&axes, s),
        None => axes.len(),
    };
    eprintln!(
        "building {points} points ({}) on {} threads into {}",
        shape_text(&axes),
        rayon::current_num_threads(),
        a.out.display()
    );
    let pb = progress(points, "points");
    let mut files = table::build(&params, &axes, shard, &|| pb.inc(1))?;
    files.sidecar.storage = storage;
    files.sidecar.resolution = a.resolution;
    pb.finish_and_clear();
    files.write(&a.out)?;
    report_written(&a.out, &files);
    Ok(())
}

/// A resolution is one of u16 codes: refused with f32 storage.
fn needs_u16(storage: Storage, resolution: Option<Resolution>) -> Result<()> {
    if storage.is_f32() && resolution.is_some() {
        bail!("--resolution sets the steps of u16 codes: it needs --storage u16, u16z or u16x");
    }
    Ok(())
}

fn shape_text(axes: &Axes) -> String {
    axes.shape()
        .iter()
        .zip(DIMENSIONS.iter())
        .map(|(n, d)| format!("{} {n}", d.symbol))
        .collect::<Vec<_>>()
        .join(" × ")
}

fn report_written(dir: &Path, files: &TableFiles) {
    let b = &files.sidecar.build;
    let n = files.converged.len();
    eprintln!(
        "wrote {}: {n} points in {:.1} s ({:.3} s per point and thread)",
        dir.display(),
        b.duration_seconds,
        b.duration_seconds * b.threads as f64 / n as f64,
    );
    let u = &files.sidecar.unconverged;
    if !u.is_empty() {
        eprintln!(
            "warning: {} point(s) did not converge even after a retry; they are flagged 0 in converged.npy \
             and listed in table.json (`unconverged`); evaluations near them report converged = false",
            u.len()
        );
        for r in u.iter().take(10) {
            eprintln!("  {:?} (residual {:.3e})", r.point, r.residual);
        }
    }
}

fn merge(a: &MergeArgs) -> Result<()> {
    // a storage given with the resolution is checked before the shards are read
    if let Some(storage) = a.storage {
        needs_u16(storage.into(), a.resolution)?;
    }
    let shards = a
        .shards
        .iter()
        .map(|p| Ok((TableFiles::read(p)?, p.as_path())))
        .collect::<Result<Vec<_>>>()?;
    let mut files = table::merge(shards)?;
    if a.storage.is_some() || a.resolution.is_some() {
        if let Some(storage) = a.storage {
            files.sidecar.storage = storage.into();
        }
        // (a resolution alone needs the storage the shards record)
        needs_u16(files.sidecar.storage, a.resolution)?;
        files.sidecar.resolution = a.resolution;
    }
    files.write(&a.out)?;
    report_written(&a.out, &files);
    Ok(())
}

/// The absolute path of an existing file or directory (the tasks of a cluster job run elsewhere).
fn canonical(what: &str, p: &Path) -> Result<PathBuf> {
    std::fs::canonicalize(p).with_context(|| format!("{what} {}", p.display()))
}

fn slurm(a: &SlurmArgs) -> Result<()> {
    needs_u16(a.storage.into(), a.resolution)?;
    // read the inputs now, so that a bad file fails here and not in every array task
    if let Some(p) = &a.params {
        Params::from_toml_file(p)?;
    }
    let axes = match &a.axes {
        Some(p) => Axes::from_toml_file(p)?,
        None => Axes::default(),
    };
    let cubes = table::file::cube_count(&axes);
    if a.shards == 0 || a.shards > cubes {
        bail!(wheelrail::Error::out_of_range(
            "shards",
            a.shards as f64,
            &format!(
                "1 ..= {cubes} (the number of creepage cubes of the axes, one per node of normal force, \
                 speed, wetness and contact geometry; a shard holds whole cubes)"
            ),
        ));
    }
    let wheelrail = match &a.wheelrail {
        Some(p) => canonical("wheelrail executable", p)?,
        None => std::env::current_exe().context("locating the wheelrail executable")?,
    };
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let job = SlurmJob {
        wheelrail,
        out: canonical("output directory", &a.out)?,
        params: a
            .params
            .as_deref()
            .map(|p| canonical("parameter file", p))
            .transpose()?,
        axes: a
            .axes
            .as_deref()
            .map(|p| canonical("axes file", p))
            .transpose()?,
        tangential: a.tangential.map(Into::into),
        storage: a.storage.into(),
        resolution: a.resolution,
        shards: a.shards,
        cpus_per_task: a.cpus_per_task,
        time: a.time.clone(),
        partition: a.partition.clone(),
        verify_samples: a.verify_samples,
    };
    let [build, merge, submit] = job.write()?;
    let largest = table::file::shard_len(
        &axes,
        ShardRecord {
            index: 1,
            count: a.shards,
        },
    );
    eprintln!(
        "{} points ({}) in {} shards of at most {largest} points, {} CPUs per task",
        axes.len(),
        shape_text(&axes),
        a.shards,
        a.cpus_per_task
    );
    println!(
        "wrote {}, {} and {}",
        build.display(),
        merge.display(),
        submit.display()
    );
    println!("submit both (the merge runs once every array task succeeded):");
    println!("  {}", submit.display());
    println!("or step by step:");
    println!(
        "  sbatch {}            # array job: shards/1 .. shards/{}",
        build.display(),
        a.shards
    );
    println!(
        "  sbatch --dependency=afterok:<array job id> {}",
        merge.display()
    );
    println!(
        "the merged table: {}",
        job.out.join(slurm::TABLE_DIR).display()
    );
    println!(
        "after failed or timed-out tasks submit again: the tasks keep the shards already built (--resume)"
    );
    Ok(())
}

fn run_verify(a: &VerifyArgs) -> Result<()> {
    if a.samples == 0 {
        bail!(wheelrail::Error::out_of_range(
            "samples",
            0.0,
            "whole number >= 1"
        ));
    }
    // without the probe check of `Table::load`: the comparison with the exact solver below is the thorough
    // form of it, and reports the errors of a stale table instead of refusing it
    let t = Table::from_files(TableFiles::read(&a.dir)?, Some(&a.dir))?;
    let points = verify::sample_points(&t, a.samples, a.seed);
    let pb = progress(points.len(), "exact points");
    let start = Instant::now();
    let compared = verify::compare(&t, &points, &|| pb.inc(1))?;
    pb.finish_and_clear();
    if let Some(path) = &a.csv {
        write_samples(path, &compared)?;
    }
    let r = verify::report(&t, &compared);
    if a.json {
        println!("{}", serde_json::to_string(&r).expect("report serialises"));
    } else {
        print_report(&r, start.elapsed().as_secs_f64());
    }
    if !r.meets_target() {
        bail!(
            "accuracy target missed: |ΔF|/F_N p99 {:.2e} (target {TARGET_P99}), max {:.2e} (target {TARGET_MAX}), \
             {} of {} points compared",
            r.force.p99,
            r.force.max,
            r.compared,
            points.len(),
        );
    }
    Ok(())
}

/// `table verify --csv`: one row per compared sample (SI units; a, b the contact's semi-axes [m], p_ref the
/// reference pressure [Pa]).
fn write_samples(path: &Path, compared: &[Option<verify::Compared>]) -> Result<()> {
    let outputs = TableOutput::values;
    let names = [
        "force_x",
        "force_y",
        "spin_moment",
        "traction_coefficient",
        "max_temperature",
        "fluid_load_fraction",
        "frictional_power",
    ];
    let mut out = String::from(
        "creepage_x,creepage_y,spin,normal_force,speed,wetness,semi_axis_a,semi_axis_b,semi_axis_ratio,reference_pressure",
    );
    for prefix in ["table", "exact"] {
        for n in names {
            out.push_str(&format!(",{prefix}_{n}"));
        }
    }
    for n in verify::ERROR_NAMES {
        out.push_str(&format!(",{n}"));
    }
    out.push_str(",table_resolved,table_converged\n");
    for c in compared.iter().flatten() {
        let (p, e) = (&c.sample.point, &c.sample.ellipse);
        let f = p.normal_force;
        let row = [
            p.creepage_x,
            p.creepage_y,
            p.spin,
            f,
            p.speed,
            p.wetness,
            e.a,
            e.b,
            e.a / e.b,
            coords::reference_pressure(e.a, e.b, f),
        ]
        .into_iter()
        .chain(outputs(&c.table))
        .chain(outputs(&c.exact))
        .chain(c.errors)
        .chain([c.table.resolved, c.table.converged].map(|b| f64::from(u8::from(b))));
        let cells: Vec<String> = row.map(|v| format!("{v:e}")).collect();
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    std::fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

fn print_report(r: &VerifyReport, seconds: f64) {
    println!(
        "{} points compared with the exact solver ({} skipped: exact solution not converged) in {seconds:.1} s",
        r.compared, r.skipped_unconverged
    );
    if r.unresolved > 0 {
        println!(
            "{} of them ({:.1} %) in cells across which the model jumps (a wet contact losing its film: \
             the T_max of a hot one, or where metal begins to cover the contact): mode auto solves such \
             points exactly, so they count with error 0 below (the CSV holds the table's values)",
            r.unresolved,
            100.0 * r.unresolved as f64 / r.compared as f64,
        );
    }
    if r.table_unconverged > 0 {
        println!(
            "{} of them ({:.1} %) interpolated from table points that did not converge when the table was \
             built: mode auto solves them exactly too, and they count with error 0 below",
            r.table_unconverged,
            100.0 * r.table_unconverged as f64 / r.compared as f64,
        );
    }
    println!(
        "{:>26}  {:>10}  {:>10}  {:>10}",
        "error", "max", "p99", "mean"
    );
    let power = r.frictional_power.map(|s| ("|dP_f|/(F_N V)", s));
    for (name, s) in [
        ("|dF|/F_N", r.force),
        ("|dM_z|/(F_N c)", r.spin_moment),
        ("|df| traction coeff.", r.traction_coefficient),
        ("|dT_max| [K]", r.max_temperature),
        ("|d fluid load fraction|", r.fluid_load_fraction),
    ]
    .into_iter()
    .chain(power)
    {
        println!(
            "{name:>26}  {:>10.3e}  {:>10.3e}  {:>10.3e}",
            s.max, s.p99, s.mean
        );
    }
    if let Some(w) = r.worst {
        println!(
            "worst |dF|/F_N {:.3e} at {:?}, semi-axes {:?} m",
            w.force_error, w.point, w.semi_axes
        );
    }
    if !r.cells.is_empty() {
        println!(
            "by cell of each axis (coordinates as stored; * p99 or max of |dF|/F_N above the target):"
        );
        println!(
            "{:>20}  {:>10}  {:>10}  {:>7}  {:>10}  {:>10}  {:>9}",
            "axis", "from", "to", "samples", "|dF| p99", "|dF| max", "dT p99 K"
        );
    }
    for c in &r.cells {
        let missed = c.force.p99 > TARGET_P99 || c.force.max > TARGET_MAX;
        println!(
            "{:>20}  {:>10.4e}  {:>10.4e}  {:>7}  {:>10.3e}  {:>10.3e}  {:>9.2}{}",
            c.axis,
            c.lower,
            c.upper,
            c.compared,
            c.force.p99,
            c.force.max,
            c.max_temperature.p99,
            if missed { " *" } else { "" }
        );
    }
    println!(
        "target (p99 <= {TARGET_P99}, max <= {TARGET_MAX}): {}",
        if r.meets_target() { "met" } else { "MISSED" }
    );
    println!(
        "T_max target (p99 <= {TARGET_TEMPERATURE_P99} K, reported only): {}",
        if r.meets_temperature_target() {
            "met"
        } else {
            "missed"
        }
    );
}

fn info(dir: &Path) -> Result<()> {
    let f = TableFiles::read(dir)?;
    let s = &f.sidecar;
    println!("table {}", dir.display());
    println!(
        "  format          {} version {}",
        s.format, s.format_version
    );
    println!("  model version   {}", s.model_version);
    println!("  fingerprint     {}", s.fingerprint);
    println!(
        "  parameters      {}",
        if s.params == Params::default() {
            "the default parameter set"
        } else {
            "custom (see params in table.json)"
        }
    );
    if let Some(sh) = s.shard {
        println!(
            "  shard           {}/{} ({} points; join with `wheelrail table merge`)",
            sh.index,
            sh.count,
            f.converged.len()
        );
    }
    println!(
        "  points          {} = {}",
        f.axes.len(),
        shape_text(&f.axes)
    );
    for (dim, (a, d)) in f.axes.0.iter().zip(DIMENSIONS.iter()).enumerate() {
        println!(
            "  {:<4} {:<13} {:>3} points, {:>10} .. {:<10} [{}] {:?}{}{}{}{}{}",
            d.symbol,
            d.name,
            a.points.len(),
            a.min(),
            a.max(),
            d.unit,
            a.interpolation(dim),
            a.sqrt_from.map_or(String::new(), |x| format!(
                " (in sqrt({}) from {x} on)",
                d.symbol
            )),
            if a.mirrored { ", mirrored" } else { "" },
            a.raw_limit
                .map_or(String::new(), |l| format!(", raw limit {l}")),
            a.raw_scale.map_or(String::new(), |k| match a.raw_length {
                Some(l) => format!(
                    ", knee-blended (raw scale {k} at contact size sqrt(a²+b²) = {l} m, in \
                     proportion to it)"
                ),
                None => format!(", knee-blended (raw scale {k})"),
            }),
            if a.similarity {
                ", similarity: equivalent speeds V·sqrt(F_N/100 kN) of every load, p_ref = p0 \
                 (docs/model.md §9.1)"
            } else {
                ""
            }
        );
    }
    let bytes: u64 = s
        .outputs
        .iter()
        .chain(std::iter::once(&s.converged))
        .chain(&s.film_intake)
        .filter_map(|r| std::fs::metadata(dir.join(&r.file)).ok())
        .map(|m| m.len())
        .sum();
    println!("  storage         {}", s.storage);
    if let Some(r) = s.resolution {
        println!(
            "  resolution      codes step by at least {} of the outputs per F_N, {} K of T_max",
            r.per_normal_force, r.temperature
        );
    }
    println!(
        "  outputs         {} ({:.2} MB of arrays)",
        s.outputs
            .iter()
            .map(|o| o.name.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        bytes as f64 / 1e6
    );
    println!(
        "  T_max           interpolated as {} (docs/model.md §12.3)",
        if wheelrail::table::rise::RiseVariable::new(&s.params.material).is_plain() {
            "T_max itself (G = (T - T0)/sqrt(sigma_y(T)/sigma_y(T0)) does not rise with T for this material)"
        } else {
            "G = (T - T0)/sqrt(sigma_y(T)/sigma_y(T0))"
        }
    );
    println!(
        "  heat            T_max's variable and P_f/(F_N V) interpolated {} (docs/model.md §12.3)",
        if wheelrail::table::heating::applies(&s.params) {
            "per unit of FASTSIM's direction factor L/L1"
        } else {
            "as they are (exact tangential solver)"
        }
    );
    println!(
        "  built           {} in {:.1} s on {} threads{}",
        s.build.date,
        s.build.duration_seconds,
        s.build.threads,
        if s.build.merged_shards > 0 {
            format!(" (merged from {} shards)", s.build.merged_shards)
        } else {
            String::new()
        }
    );
    println!("  unconverged     {} point(s)", s.unconverged.len());
    println!(
        "  film intake     {}",
        if s.film_intake.is_some() {
            "recorded (cells across the onset of the walls are unresolved)"
        } else {
            "not recorded (built by a version that did not record it)"
        }
    );
    Ok(())
}

/// The JSON object of a point evaluated by table (`wheelrail point --table DIR`): the keys of the exact
/// point that a table provides (with the Hertz contact of the parameters), plus `in_range`.
pub fn point_json(
    params: &Params,
    pt: &OperatingPoint,
    o: &TableOutput,
) -> Result<serde_json::Value> {
    let h = wheelrail::solver::normal_contact(params, pt.normal_force)?;
    let mut v = serde_json::json!({
        "force_x": o.force_x,
        "force_y": o.force_y,
        "spin_moment": o.spin_moment,
        "traction_coefficient": o.traction_coefficient,
        "normal_force": pt.normal_force,
        "semi_axis_a": h.a,
        "semi_axis_b": h.b,
        "peak_pressure": h.p0,
        "max_temperature": o.max_temperature,
        "fluid_load_fraction": o.fluid_load_fraction,
        "frictional_power": o.frictional_power,
        "converged": o.converged,
        "in_range": o.in_range,
    });
    v.as_object_mut()
        .expect("object")
        .extend(super::methods_json(params));
    Ok(v)
}
