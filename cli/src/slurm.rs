//! Sharded table builds as a Slurm array job: the scripts that `wheelrail table slurm` writes.
//!
//! A job directory `OUT` holds `build.sbatch` (an `sbatch --array=1-N` job: task K runs
//! `wheelrail table build --shard K/N --out OUT/shards/K`), `merge.sbatch` (one task: `wheelrail table merge
//! OUT/table OUT/shards/1 … OUT/shards/N`, then `wheelrail table verify OUT/table`), `submit.sh` (submits the
//! array job and the merge job with `--dependency=afterok:<array job>`) and `logs/`. Every path in the scripts
//! is absolute (the tasks run on other nodes and in other directories) and shell-quoted; paths that `sbatch`
//! directives cannot carry are refused.

use anyhow::{Result, bail};
use std::path::{Path, PathBuf};
use wheelrail::Tangential;
use wheelrail::table::{Resolution, Storage};

/// Name of the array-job script in the job directory.
pub const BUILD_SCRIPT: &str = "build.sbatch";
/// Name of the merge-and-verify script in the job directory.
pub const MERGE_SCRIPT: &str = "merge.sbatch";
/// Name of the submission script in the job directory.
pub const SUBMIT_SCRIPT: &str = "submit.sh";
/// Sub-directory of the job directory with the shards (`shards/K`).
pub const SHARDS_DIR: &str = "shards";
/// Sub-directory of the job directory with the merged table.
pub const TABLE_DIR: &str = "table";
/// Sub-directory of the job directory with the Slurm logs.
pub const LOGS_DIR: &str = "logs";

/// A sharded table build as a Slurm array job. Paths must be absolute.
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmJob {
    /// The `wheelrail` executable the tasks run.
    pub wheelrail: PathBuf,
    /// Job directory (shards, merged table, logs, scripts).
    pub out: PathBuf,
    /// Parameter file passed to every build (None: the default parameter set).
    pub params: Option<PathBuf>,
    /// Axes file passed to every build (None: the built-in axes).
    pub axes: Option<PathBuf>,
    /// Tangential solver passed to every build (`--tangential`; None: the parameter file's).
    pub tangential: Option<Tangential>,
    /// Storage of the merged table, passed to every build (`--storage`; shards record it).
    pub storage: Storage,
    /// The coarsest code steps of the quantised storage, passed to every build (`--resolution`; shards
    /// record it).
    pub resolution: Option<Resolution>,
    /// Number of shards N = array tasks 1..=N.
    pub shards: usize,
    /// CPUs per task, also the worker threads of each build (`RAYON_NUM_THREADS`).
    pub cpus_per_task: usize,
    /// Time limit per task (`--time`, e.g. `02:00:00`; None: the partition's default).
    pub time: Option<String>,
    /// Partition (`--partition`; None: the cluster's default).
    pub partition: Option<String>,
    /// Sample points of `table verify` after the merge (0: merge only).
    pub verify_samples: usize,
}

/// The three scripts of a [`SlurmJob`].
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmScripts {
    /// `build.sbatch`: the array job.
    pub build: String,
    /// `merge.sbatch`: merge the shards, then verify.
    pub merge: String,
    /// `submit.sh`: submits both, the merge after the array job succeeded.
    pub submit: String,
}

/// Quotes `s` for a POSIX shell (single quotes; a single quote becomes `'\''`).
pub fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// The UTF-8 text of an absolute path, or an error naming `what`.
fn absolute(what: &str, p: &Path) -> Result<String> {
    if !p.is_absolute() {
        bail!("{what} {} must be an absolute path", p.display());
    }
    let Some(s) = p.to_str() else {
        bail!("{what} {} is not valid UTF-8", p.display());
    };
    if s.contains(['\n', '\r', '\0']) {
        bail!("{what} {s:?} contains a line break or NUL");
    }
    Ok(s.to_string())
}

/// Checks an `#SBATCH` option value: only the characters `allowed` accepts.
fn directive_value(what: &str, v: &str, allowed: fn(char) -> bool) -> Result<()> {
    if v.is_empty() || !v.chars().all(allowed) {
        bail!("{what} {v:?} has characters that an #SBATCH line cannot carry");
    }
    Ok(())
}

impl SlurmJob {
    /// Checks the job and writes its scripts' text.
    pub fn scripts(&self) -> Result<SlurmScripts> {
        if self.shards == 0 {
            bail!("--shards must be at least 1");
        }
        if self.cpus_per_task == 0 {
            bail!("--cpus-per-task must be at least 1");
        }
        let wheelrail = absolute("wheelrail executable", &self.wheelrail)?;
        let out = absolute("output directory", &self.out)?;
        // the log path goes into an #SBATCH line in double quotes, where `%` is a filename pattern
        if out.contains(['"', '\\', '%']) {
            bail!(
                "output directory {out:?} contains \", \\ or %, which Slurm's --output cannot carry"
            );
        }
        let params = self
            .params
            .as_deref()
            .map(|p| absolute("parameter file", p))
            .transpose()?;
        let axes = self
            .axes
            .as_deref()
            .map(|p| absolute("axes file", p))
            .transpose()?;
        if let Some(t) = &self.time {
            directive_value("--time", t, |c| c.is_ascii_digit() || c == ':' || c == '-')?;
        }
        if let Some(p) = &self.partition {
            directive_value("--partition", p, |c| {
                c.is_ascii_alphanumeric() || "_-.,".contains(c)
            })?;
        }
        let n = self.shards;
        let c = self.cpus_per_task;
        let mut head = format!("#SBATCH --ntasks=1\n#SBATCH --cpus-per-task={c}\n");
        if let Some(t) = &self.time {
            head += &format!("#SBATCH --time={t}\n");
        }
        if let Some(p) = &self.partition {
            head += &format!("#SBATCH --partition={p}\n");
        }
        let mut vars = format!(
            "set -euo pipefail\nWHEELRAIL={}\nOUT={}\n",
            shell_quote(&wheelrail),
            shell_quote(&out)
        );
        let mut inputs = String::new();
        if let Some(p) = &params {
            vars += &format!("PARAMS={}\n", shell_quote(p));
            inputs += " --params \"$PARAMS\"";
        }
        if let Some(a) = &axes {
            vars += &format!("AXES={}\n", shell_quote(a));
            inputs += " --axes \"$AXES\"";
        }
        if let Some(t) = self.tangential {
            inputs += &format!(" --tangential {t}");
        }
        if !self.storage.is_f32() {
            inputs += &format!(" --storage {}", self.storage);
        }
        if let Some(r) = self.resolution {
            inputs += &format!(" --resolution {r}");
        }
        vars += &format!("export RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-{c}}}\"\n");
        let build = format!(
            "#!/bin/bash\n\
             # Sharded wheelrail table build, written by `wheelrail table slurm`: array task K of {n} builds shard\n\
             # K/{n} (whole creepage cubes) into $OUT/{SHARDS_DIR}/K. Submit with {SUBMIT_SCRIPT}, or `sbatch` this file and\n\
             # then {MERGE_SCRIPT}. sbatch options on the command line override the #SBATCH lines. A task whose\n\
             # shard is already built keeps it (--resume): submitting again after failed or timed-out tasks\n\
             # recomputes only the missing shards.\n\
             #SBATCH --job-name=wheelrail-table\n\
             #SBATCH --array=1-{n}\n\
             {head}\
             #SBATCH --output=\"{out}/{LOGS_DIR}/build-%A_%a.out\"\n\
             {vars}\
             \"$WHEELRAIL\" table build{inputs} --shard \"$SLURM_ARRAY_TASK_ID/{n}\" --resume \
             --out \"$OUT/{SHARDS_DIR}/$SLURM_ARRAY_TASK_ID\"\n"
        );
        let verify = if self.verify_samples > 0 {
            format!(
                "\"$WHEELRAIL\" table verify \"$OUT/{TABLE_DIR}\" --samples {}\n",
                self.verify_samples
            )
        } else {
            String::new()
        };
        let merge = format!(
            "#!/bin/bash\n\
             # Joins the {n} shards of {BUILD_SCRIPT} into $OUT/{TABLE_DIR}{}. Written by `wheelrail table slurm`;\n\
             # submit it after the array job succeeded (`sbatch --dependency=afterok:<array job>`, as {SUBMIT_SCRIPT} does).\n\
             #SBATCH --job-name=wheelrail-table-merge\n\
             {head}\
             #SBATCH --output=\"{out}/{LOGS_DIR}/merge-%j.out\"\n\
             {vars}\
             shards=()\n\
             for k in $(seq 1 {n}); do shards+=(\"$OUT/{SHARDS_DIR}/$k\"); done\n\
             \"$WHEELRAIL\" table merge \"$OUT/{TABLE_DIR}\" \"${{shards[@]}}\"\n\
             {verify}",
            if verify.is_empty() {
                ""
            } else {
                " and verifies it against the exact solver"
            }
        );
        let submit = format!(
            "#!/bin/bash\n\
             # Submits the array job {BUILD_SCRIPT} and, once all its tasks succeeded, {MERGE_SCRIPT}.\n\
             # Extra arguments go to both sbatch calls (e.g. --account=NAME).\n\
             set -euo pipefail\n\
             OUT={q}\n\
             array=$(sbatch --parsable \"$@\" \"$OUT/{BUILD_SCRIPT}\")\n\
             array=${{array%%;*}}\n\
             merge=$(sbatch --parsable \"$@\" --dependency=afterok:\"$array\" \"$OUT/{MERGE_SCRIPT}\")\n\
             echo \"submitted array job $array ({n} tasks) and merge job ${{merge%%;*}}; table: $OUT/{TABLE_DIR}, logs: $OUT/{LOGS_DIR}\"\n",
            q = shell_quote(&out)
        );
        Ok(SlurmScripts {
            build,
            merge,
            submit,
        })
    }

    /// Creates the job directory with `logs/` and writes the three scripts (executable); returns their paths
    /// (build, merge, submit).
    pub fn write(&self) -> Result<[PathBuf; 3]> {
        let s = self.scripts()?;
        std::fs::create_dir_all(self.out.join(LOGS_DIR))?;
        let paths = [BUILD_SCRIPT, MERGE_SCRIPT, SUBMIT_SCRIPT].map(|f| self.out.join(f));
        for (p, text) in paths.iter().zip([&s.build, &s.merge, &s.submit]) {
            std::fs::write(p, text)?;
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o755))?;
        }
        Ok(paths)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job() -> SlurmJob {
        SlurmJob {
            wheelrail: "/opt/wheel rail/bin/wheelrail".into(),
            out: "/scratch/my tables/run 1".into(),
            params: Some("/home/u/it's params.toml".into()),
            axes: Some("/home/u/axes.toml".into()),
            tangential: None,
            storage: Storage::F32,
            resolution: None,
            shards: 12,
            cpus_per_task: 8,
            time: Some("02:30:00".into()),
            partition: Some("compute".into()),
            verify_samples: 500,
        }
    }

    #[test]
    fn the_array_job_builds_shard_k_of_n_with_the_same_inputs_on_cpus_per_task_threads() {
        let b = job().scripts().unwrap().build;
        assert!(b.starts_with("#!/bin/bash\n"), "{b}");
        for line in [
            "#SBATCH --array=1-12\n",
            "#SBATCH --ntasks=1\n",
            "#SBATCH --cpus-per-task=8\n",
            "#SBATCH --time=02:30:00\n",
            "#SBATCH --partition=compute\n",
            "#SBATCH --output=\"/scratch/my tables/run 1/logs/build-%A_%a.out\"\n",
            "set -euo pipefail\n",
            "WHEELRAIL='/opt/wheel rail/bin/wheelrail'\n",
            "OUT='/scratch/my tables/run 1'\n",
            "PARAMS='/home/u/it'\\''s params.toml'\n",
            "AXES='/home/u/axes.toml'\n",
            "export RAYON_NUM_THREADS=\"${SLURM_CPUS_PER_TASK:-8}\"\n",
            "\"$WHEELRAIL\" table build --params \"$PARAMS\" --axes \"$AXES\" --shard \"$SLURM_ARRAY_TASK_ID/12\" --resume \
             --out \"$OUT/shards/$SLURM_ARRAY_TASK_ID\"\n",
        ] {
            assert!(b.contains(line), "missing {line:?} in\n{b}");
        }
        // every #SBATCH directive comes before the first command (sbatch stops reading them there)
        let first_command = b.find("set -euo").unwrap();
        assert!(b.rfind("#SBATCH").unwrap() < first_command, "{b}");
    }

    #[test]
    fn the_merge_job_joins_shards_1_to_n_then_verifies() {
        let m = job().scripts().unwrap().merge;
        assert!(!m.contains("--array"), "{m}");
        for line in [
            "#SBATCH --output=\"/scratch/my tables/run 1/logs/merge-%j.out\"\n",
            "OUT='/scratch/my tables/run 1'\n",
            "for k in $(seq 1 12); do shards+=(\"$OUT/shards/$k\"); done\n",
            "\"$WHEELRAIL\" table merge \"$OUT/table\" \"${shards[@]}\"\n",
            "\"$WHEELRAIL\" table verify \"$OUT/table\" --samples 500\n",
        ] {
            assert!(m.contains(line), "missing {line:?} in\n{m}");
        }
        let no_verify = SlurmJob {
            verify_samples: 0,
            ..job()
        };
        assert!(!no_verify.scripts().unwrap().merge.contains("verify"));
    }

    #[test]
    fn the_tangential_solver_is_passed_to_every_build() {
        let j = SlurmJob {
            tangential: Some(Tangential::Exact),
            ..job()
        };
        let b = j.scripts().unwrap().build;
        assert!(
            b.contains("\"$WHEELRAIL\" table build --params \"$PARAMS\" --axes \"$AXES\" --tangential exact --shard"),
            "{b}"
        );
        assert!(!job().scripts().unwrap().build.contains("--tangential"));
    }

    #[test]
    fn a_u16_storage_is_passed_to_every_build() {
        let j = SlurmJob {
            storage: Storage::U16,
            ..job()
        };
        let b = j.scripts().unwrap().build;
        assert!(
            b.contains("\"$WHEELRAIL\" table build --params \"$PARAMS\" --axes \"$AXES\" --storage u16 --shard"),
            "{b}"
        );
        assert!(!job().scripts().unwrap().build.contains("--storage"));
    }

    #[test]
    fn a_resolution_is_passed_to_every_build_as_it_reads_back() {
        let r = Resolution::parse("1e-4,0.1").unwrap();
        let j = SlurmJob {
            storage: Storage::U16x,
            resolution: Some(r),
            ..job()
        };
        let b = j.scripts().unwrap().build;
        let flag = "--storage u16x --resolution 0.0001,0.1 --shard";
        assert!(b.contains(flag), "{b}");
        assert_eq!(Resolution::parse("0.0001,0.1").unwrap(), r);
        assert!(!job().scripts().unwrap().build.contains("--resolution"));
    }

    #[test]
    fn submit_chains_the_merge_after_the_array_job() {
        let s = job().scripts().unwrap().submit;
        assert!(
            s.contains("array=$(sbatch --parsable \"$@\" \"$OUT/build.sbatch\")\n"),
            "{s}"
        );
        assert!(
            s.contains("--dependency=afterok:\"$array\" \"$OUT/merge.sbatch\""),
            "{s}"
        );
    }

    #[test]
    fn without_params_axes_time_or_partition_the_lines_are_left_out() {
        let j = SlurmJob {
            params: None,
            axes: None,
            time: None,
            partition: None,
            shards: 1,
            ..job()
        };
        let b = j.scripts().unwrap().build;
        for absent in [
            "--params",
            "--axes",
            "PARAMS=",
            "AXES=",
            "--time",
            "--partition",
        ] {
            assert!(!b.contains(absent), "{absent} in\n{b}");
        }
        assert!(b.contains("#SBATCH --array=1-1\n"), "{b}");
        assert!(
            b.contains("table build --shard \"$SLURM_ARRAY_TASK_ID/1\""),
            "{b}"
        );
    }

    #[test]
    fn the_quoted_paths_survive_a_real_shell() {
        let s = job().scripts().unwrap().build;
        let vars: String = s
            .lines()
            .filter(|l| l.starts_with("WHEELRAIL=") || l.starts_with("PARAMS="))
            .map(|l| format!("{l}\n"))
            .collect();
        let o = std::process::Command::new("bash")
            .arg("-c")
            .arg(format!("{vars}printf '%s|%s' \"$WHEELRAIL\" \"$PARAMS\""))
            .output()
            .unwrap();
        assert_eq!(
            String::from_utf8(o.stdout).unwrap(),
            "/opt/wheel rail/bin/wheelrail|/home/u/it's params.toml"
        );
    }

    #[test]
    fn bad_jobs_are_refused_with_a_reason() {
        let cases: [(SlurmJob, &str); 7] = [
            (SlurmJob { shards: 0, ..job() }, "--shards"),
            (
                SlurmJob {
                    cpus_per_task: 0,
                    ..job()
                },
                "--cpus-per-task",
            ),
            (
                SlurmJob {
                    out: "rel/dir".into(),
                    ..job()
                },
                "absolute",
            ),
            (
                SlurmJob {
                    params: Some("p.toml".into()),
                    ..job()
                },
                "parameter file",
            ),
            (
                SlurmJob {
                    out: "/scratch/100%".into(),
                    ..job()
                },
                "--output",
            ),
            (
                SlurmJob {
                    time: Some("2 h".into()),
                    ..job()
                },
                "--time",
            ),
            (
                SlurmJob {
                    partition: Some("a\"b".into()),
                    ..job()
                },
                "--partition",
            ),
        ];
        for (j, needle) in cases {
            let e = j.scripts().unwrap_err().to_string();
            assert!(e.contains(needle), "{needle}: {e}");
        }
    }
}
