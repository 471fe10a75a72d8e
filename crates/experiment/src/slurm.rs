//! `xhab experiment FILE --slurm`: a study as a SLURM array job whose tasks run the shards
//! (`--shard K/N`, K = the array task id) and a dependent job that merges them and writes the
//! report. The scripts land in `DIR/slurm/` so that they can be read, edited and resubmitted.

use std::path::{Path, PathBuf};
use std::process::Command;

/// How to submit a study.
#[derive(Debug, Clone)]
pub struct SlurmOptions {
    /// The xhab binary the tasks run (an absolute path on the cluster's shared file system).
    pub xhab: PathBuf,
    /// The spec file.
    pub spec: PathBuf,
    /// The study's folder (shared by every task).
    pub out: PathBuf,
    /// The folder the spec's relative paths resolve against (the tasks start there).
    pub workdir: PathBuf,
    /// Array tasks, one shard each.
    pub shards: usize,
    /// CPUs per task (the spec's `threads`).
    pub cpus_per_task: usize,
    /// `--partition`, if any.
    pub partition: Option<String>,
    /// `--time` limit per task (SLURM's formats, e.g. `1:00:00`), if any.
    pub time: Option<String>,
    /// The job's name.
    pub name: String,
}

/// A submitted study.
#[derive(Debug, Clone)]
pub struct Submission {
    /// The array job's id.
    pub array_job: String,
    /// The merge job's id (runs after every task succeeded).
    pub merge_job: String,
    /// The array job's script.
    pub array_script: PathBuf,
    /// The merge job's script.
    pub merge_script: PathBuf,
}

/// Why a submission failed.
#[derive(Debug, thiserror::Error)]
pub enum SlurmError {
    /// A script could not be written.
    #[error("writing {path}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// sbatch could not be started (not installed, not on PATH).
    #[error("running sbatch (is SLURM installed, and SLURM_CONF set where needed?)")]
    Spawn(#[source] std::io::Error),
    /// sbatch refused the job.
    #[error("sbatch {script} failed: {stderr}")]
    Refused {
        /// The script.
        script: PathBuf,
        /// What sbatch said.
        stderr: String,
    },
    /// Options out of range.
    #[error("{0}")]
    Options(String),
}

/// `s` quoted for `sh`.
fn sh(s: &Path) -> String {
    format!("'{}'", s.display().to_string().replace('\'', "'\\''"))
}

/// The array job's and merge job's scripts.
pub fn scripts(o: &SlurmOptions) -> Result<(String, String), SlurmError> {
    if o.shards == 0 {
        return Err(SlurmError::Options("--shards must be at least 1".into()));
    }
    let bad = |v: &str| v.is_empty() || !v.chars().all(|c| c.is_ascii_alphanumeric() || "-_:.,".contains(c));
    if o.partition.as_deref().is_some_and(bad) || o.time.as_deref().is_some_and(bad) {
        return Err(SlurmError::Options("--partition and --time take SLURM names and times (letters, digits, `-_:.,`)".into()));
    }
    let log = o.out.join("slurm");
    let mut head = format!("#!/bin/sh\n#SBATCH --job-name={}\n", crate::plan::slug(&o.name));
    if let Some(p) = &o.partition {
        head += &format!("#SBATCH --partition={p}\n");
    }
    if let Some(t) = &o.time {
        head += &format!("#SBATCH --time={t}\n");
    }
    let array = format!(
        "{head}#SBATCH --array=1-{n}\n#SBATCH --cpus-per-task={cpus}\n#SBATCH --output={log}/shard-%a.log\n\
         # One shard of the study per array task; finished parts are skipped when resubmitted.\n\
         cd {wd} || exit 1\nexec {xhab} --quiet experiment {spec} --out {out} --shard \"$SLURM_ARRAY_TASK_ID/{n}\"\n",
        n = o.shards,
        cpus = o.cpus_per_task.max(1),
        log = log.display(),
        wd = sh(&o.workdir),
        xhab = sh(&o.xhab),
        spec = sh(&o.spec),
        out = sh(&o.out),
    );
    let merge = format!(
        "{head}#SBATCH --cpus-per-task=1\n#SBATCH --output={log}/merge.log\n\
         # Runs after every shard succeeded: results.json/.csv and the report.\n\
         cd {wd} || exit 1\nexec {xhab} --quiet merge {out}\n",
        log = log.display(),
        wd = sh(&o.workdir),
        xhab = sh(&o.xhab),
        out = sh(&o.out),
    );
    Ok((array, merge))
}

/// Writes the scripts to `DIR/slurm/` and submits them: the array job, then the merge job
/// with `--dependency=afterok` on it.
pub fn submit(o: &SlurmOptions) -> Result<Submission, SlurmError> {
    let (array, merge) = scripts(o)?;
    let dir = o.out.join("slurm");
    std::fs::create_dir_all(&dir).map_err(|source| SlurmError::Write { path: dir.clone(), source })?;
    let (array_script, merge_script) = (dir.join("shards.sbatch"), dir.join("merge.sbatch"));
    for (p, text) in [(&array_script, array), (&merge_script, merge)] {
        std::fs::write(p, text).map_err(|source| SlurmError::Write { path: p.clone(), source })?;
    }
    let array_job = sbatch(&array_script, &[])?;
    let merge_job = sbatch(&merge_script, &[format!("--dependency=afterok:{array_job}")])?;
    Ok(Submission { array_job, merge_job, array_script, merge_script })
}

/// Plans `spec` into `o.out` (episode sets, `experiment.json`, so that every task agrees on
/// the runs) and submits it as [`submit`] does.
pub fn submit_experiment(spec: &crate::spec::ExperimentSpec, o: &SlurmOptions) -> Result<Submission, crate::execute::ExperimentError> {
    crate::execute::prepare(spec, &o.out)?;
    Ok(submit(o)?)
}

/// Submits `script`; the job's id.
fn sbatch(script: &Path, args: &[String]) -> Result<String, SlurmError> {
    let out = Command::new("sbatch").arg("--parsable").args(args).arg(script).output().map_err(SlurmError::Spawn)?;
    let stdout = String::from_utf8_lossy(&out.stdout).trim().to_string();
    if !out.status.success() || stdout.is_empty() {
        return Err(SlurmError::Refused { script: script.to_path_buf(), stderr: String::from_utf8_lossy(&out.stderr).trim().to_string() });
    }
    // `--parsable` prints `ID` or `ID;CLUSTER`.
    Ok(stdout.split(';').next().unwrap_or(&stdout).to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> SlurmOptions {
        SlurmOptions {
            xhab: "/opt/x hab/xhab".into(),
            spec: "/s/it's.yaml".into(),
            out: "/r/out".into(),
            workdir: "/w".into(),
            shards: 4,
            cpus_per_task: 2,
            partition: Some("gpu".into()),
            time: Some("1:00:00".into()),
            name: "four configurations".into(),
        }
    }

    #[test]
    fn scripts_run_one_shard_per_task_and_merge_after() {
        let (a, m) = scripts(&opts()).unwrap();
        assert!(a.contains("#SBATCH --array=1-4") && a.contains("--shard \"$SLURM_ARRAY_TASK_ID/4\""), "{a}");
        assert!(a.contains("#SBATCH --partition=gpu") && a.contains("#SBATCH --time=1:00:00") && a.contains("--cpus-per-task=2"));
        assert!(a.contains("'/opt/x hab/xhab'") && a.contains("'/s/it'\\''s.yaml'"), "{a}");
        assert!(a.contains("#SBATCH --job-name=four_configurations"));
        assert!(m.contains("merge '/r/out'") && !m.contains("--array"), "{m}");
        let mut bad = opts();
        bad.partition = Some("a b".into());
        assert!(scripts(&bad).is_err());
        bad = opts();
        bad.shards = 0;
        assert!(scripts(&bad).is_err());
    }
}
