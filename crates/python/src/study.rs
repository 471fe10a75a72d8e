//! `xhab.experiment` and `xhab.merge`: studies from Python through the library calls that
//! `xhab experiment` and `xhab merge` make.

use crate::{interruptible, py_err};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use xhab_experiment::{merge_and_report, run_experiment_until, ExperimentOptions, ExperimentSpec, Shard};

/// Runs the study `spec` (YAML or JSON text; `source` names it in errors) into `out`
/// (`results/NAME` when `None`): whole, or shard `K/N`; returns the results' JSON (whole runs)
/// or `None` (shards) and the folder.
#[pyfunction]
#[pyo3(signature = (spec, source, out, shard, report))]
pub fn experiment(py: Python<'_>, spec: &str, source: &str, out: Option<PathBuf>, shard: Option<&str>, report: bool) -> PyResult<(Option<String>, String)> {
    let spec = ExperimentSpec::parse(spec, Path::new(source)).map_err(|e| py_err(&e))?;
    let shard = shard.map(|s| s.parse::<Shard>()).transpose().map_err(PyValueError::new_err)?;
    let out = out.unwrap_or_else(|| Path::new("results").join(xhab_experiment::plan::slug(&spec.name)));
    let o = ExperimentOptions { out: out.clone(), shard, report };
    let cancel = AtomicBool::new(false);
    let run = interruptible(py, &cancel, || run_experiment_until(&spec, &o, &cancel, &|_| {}))?.map_err(|e| py_err(&e))?;
    let json = run.results.map(|r| serde_json::to_string(&r)).transpose().map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    Ok((json, out.display().to_string()))
}

/// Merges the shards in `dirs` into `out` (the first folder when `None`), then the report;
/// returns the results' JSON.
#[pyfunction]
#[pyo3(signature = (dirs, out, report))]
pub fn merge(py: Python<'_>, dirs: Vec<PathBuf>, out: Option<PathBuf>, report: bool) -> PyResult<String> {
    let Some(first) = dirs.first() else { return Err(PyValueError::new_err("merge: give at least one folder")) };
    let out = out.unwrap_or_else(|| first.clone());
    let (results, _) = py.detach(|| merge_and_report(&dirs, &out, report)).map_err(|e| py_err(&e))?;
    serde_json::to_string(&results).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}
