//! `xhab experiment`, `merge` and SLURM: a study's runs equal the individual `xhab bench` runs
//! they stand for, a resumed study skips what it finished, shards merge into the whole run,
//! and a real single-node SLURM cluster runs the shards and the merge.

use crate::common::{repo_root, xhab};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const SPEC: &str = "name: e2e study
scenes:
  - scene: procedural:3
    generate: {count: 4, seed: 1}
agents:
  - agent: oracle
  - agent: nav
threads: 2
";

fn fresh(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("xhab-e2e-experiment-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn spec(dir: &Path, text: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join("study.yaml");
    std::fs::write(&p, text).unwrap();
    p
}

fn run_ok(c: &mut Command) -> String {
    let out = c.output().unwrap();
    assert!(out.status.success(), "{:?} failed:\n{}\n{}", c, String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr)
}

fn json(p: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))).unwrap()
}

/// `v` without timing figures (and, with `paths`, without the fields naming files and threads).
fn untimed(v: Value, paths: bool) -> Value {
    const TIMING: [&str; 7] = ["wall_s", "steps_per_s", "real_time_factor", "render_s", "render_frames_per_s", "ros_overhead", "stack_wait_s"];
    match v {
        Value::Object(m) => Value::Object(m.into_iter().filter(|(k, _)| !TIMING.contains(&k.as_str()) && !(paths && (k == "episodes_file" || k == "threads"))).map(|(k, v)| (k, untimed(v, paths))).collect()),
        Value::Array(a) => Value::Array(a.into_iter().map(|x| untimed(x, paths)).collect()),
        x => x,
    }
}

#[test]
fn a_study_equals_its_bench_runs_and_resumes() {
    let d = fresh("whole");
    let s = spec(&d, SPEC);
    let out = d.join("out");
    let log = run_ok(xhab().current_dir(&d).args(["-q", "experiment"]).arg(&s).arg("--out").arg(&out));
    assert!(log.contains("6 parts run, 0 already finished"), "{log}");
    // The report is written at the end (its contents: tests/e2e/report.rs).
    let page = std::fs::read_to_string(out.join("report/index.html")).unwrap();
    assert!(page.contains("e2e study") && page.contains("+physics +ROS"), "the report misses the study");
    let results = json(&out.join("results.json"));
    let runs = results["runs"].as_array().unwrap();
    // oracle under all four configurations, nav under the two with physics.
    assert_eq!(runs.len(), 6);
    assert_eq!(results["skipped"].as_array().unwrap().len(), 2);
    assert_eq!(results["episodes"].as_array().unwrap().len(), 24);
    let configs: Vec<&str> = runs.iter().map(|r| r["configuration"].as_str().unwrap()).collect();
    assert_eq!(configs[..4], ["-physics -ROS", "+physics -ROS", "-physics +ROS", "+physics +ROS"]);
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 25);
    assert!(csv.starts_with("run,scene,agent,configuration,physics,ros,seed,episode_index,episode_id,success,spl"));
    // Each run is the `xhab bench` run of the same agent, configuration and episodes.
    let episodes = out.join("episodes/procedural_3.json.gz");
    for r in runs {
        let id = r["id"].as_str().unwrap();
        let bench_out = d.join(format!("{id}.json"));
        let mut c = xhab();
        c.args(["-q", "bench", "--scene", "procedural:3", "--threads", "2", "--agent", r["agent"].as_str().unwrap()]).arg("--episodes").arg(&episodes).arg("--out").arg(&bench_out);
        if r["physics"] == true && r["agent"] == "oracle" {
            c.arg("--physics");
        }
        if r["ros"] == true {
            c.arg("--ros");
        }
        run_ok(&mut c);
        let mine = json(&out.join("runs").join(id).join("bench.json"));
        assert_eq!(untimed(mine, true), untimed(json(&bench_out), true), "run {id} differs from its xhab bench run");
    }
    // Again: every part is found finished, and the results are the same to the byte.
    let before = std::fs::read(out.join("results.json")).unwrap();
    let log = run_ok(xhab().current_dir(&d).args(["-q", "experiment"]).arg(&s).arg("--out").arg(&out).arg("--no-report"));
    assert!(log.contains("0 parts run, 6 already finished"), "{log}");
    assert_eq!(std::fs::read(out.join("results.json")).unwrap(), before);
    // Another study into the same folder is refused.
    let other = spec(&d.join("other"), &SPEC.replace("count: 4", "count: 3"));
    let e = xhab().current_dir(&d).args(["-q", "experiment"]).arg(&other).arg("--out").arg(&out).output().unwrap();
    assert!(!e.status.success());
    assert!(String::from_utf8_lossy(&e.stderr).contains("another experiment"), "{}", String::from_utf8_lossy(&e.stderr));
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn shards_merge_into_the_whole_study() {
    let d = fresh("shards");
    let s = spec(&d, SPEC);
    let whole = d.join("whole");
    run_ok(xhab().current_dir(&d).args(["-q", "experiment"]).arg(&s).arg("--out").arg(&whole).arg("--no-report"));
    // Four shards into one folder.
    let one = d.join("one");
    for k in 1..=4 {
        let log = run_ok(xhab().current_dir(&d).args(["-q", "experiment"]).arg(&s).arg("--out").arg(&one).args(["--shard", &format!("{k}/4"), "--no-report"]));
        assert!(log.contains(&format!("shard {k}/4 done")), "{log}");
    }
    assert!(!one.join("results.json").exists(), "a shard must not merge");
    // Merging before every shard ran names what is missing.
    let (a, b) = (d.join("a"), d.join("b"));
    for k in [1, 3] {
        run_ok(xhab().current_dir(&d).args(["-q", "experiment"]).arg(&s).arg("--out").arg(&a).args(["--shard", &format!("{k}/4")]));
    }
    let e = xhab().args(["merge", "--no-report"]).arg(&a).output().unwrap();
    let err = String::from_utf8_lossy(&e.stderr);
    assert!(!e.status.success() && err.contains("incomplete") && err.contains("have not run"), "{err}");
    for k in [2, 4] {
        run_ok(xhab().current_dir(&d).args(["-q", "experiment"]).arg(&s).arg("--out").arg(&b).args(["--shard", &format!("{k}/4")]));
    }
    run_ok(xhab().args(["merge", "--no-report"]).arg(&one));
    // Shards spread over two folders merge into a third.
    let c = d.join("c");
    run_ok(xhab().args(["merge", "--no-report"]).arg(&a).arg(&b).arg("--out").arg(&c));
    let w = untimed(json(&whole.join("results.json")), false);
    assert_eq!(untimed(json(&one.join("results.json")), false), w, "4 shards in one folder, merged");
    assert_eq!(untimed(json(&c.join("results.json")), false), w, "4 shards in two folders, merged");
    for run in w["runs"].as_array().unwrap() {
        let id = run["id"].as_str().unwrap();
        assert_eq!(untimed(json(&c.join("runs").join(id).join("bench.json")), false), untimed(json(&whole.join("runs").join(id).join("bench.json")), false), "{id}");
    }
    std::fs::remove_dir_all(&d).ok();
}

/// Whether a local SLURM can be started; panics when `XHAB_REQUIRE_SLURM=1` demands it.
fn slurm_available(test: &str) -> bool {
    let has = |b: &str| Command::new("which").arg(b).stdout(Stdio::null()).status().is_ok_and(|s| s.success());
    // The daemons run as root: be root, or have sudo without a password.
    let root = Command::new("id").arg("-u").output().is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        || Command::new("sudo").args(["-n", "true"]).stderr(Stdio::null()).status().is_ok_and(|s| s.success());
    let ok = root && ["slurmctld", "slurmd", "sbatch", "munged"].iter().all(|b| has(b) || Path::new("/usr/sbin").join(b).exists());
    if !ok {
        if std::env::var("XHAB_REQUIRE_SLURM").as_deref() == Ok("1") {
            panic!("{test}: XHAB_REQUIRE_SLURM=1 but slurm-wlm/munge are missing, or neither root nor passwordless sudo (install slurm-wlm munge)");
        }
        crate::common::skipped(test, "slurm-wlm and munge not installed, or neither root nor passwordless sudo");
    }
    ok
}

/// Stops the test's cluster however the test ends.
struct Cluster(PathBuf);
impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(repo_root().join("scripts/slurm_local.sh")).arg("stop").arg(&self.0).status();
    }
}

#[test]
fn slurm_runs_the_shards_and_merges() {
    if !slurm_available("slurm_runs_the_shards_and_merges") {
        return;
    }
    let d = fresh("slurm");
    let s = spec(&d, &SPEC.replace("  - agent: nav\n", ""));
    let cluster = Cluster(d.join("cluster"));
    run_ok(Command::new(repo_root().join("scripts/slurm_local.sh")).arg("start").arg(&cluster.0));
    let conf = cluster.0.join("slurm.conf");
    let out = d.join("out");
    let log = run_ok(xhab().current_dir(&d).env("SLURM_CONF", &conf).args(["experiment"]).arg(&s).arg("--out").arg(&out).args(["--slurm", "--shards", "4", "--partition", "debug", "--time", "10:00"]));
    assert!(log.contains("array job") && log.contains("merge job"), "{log}");
    // The merge job writes results.json once every shard succeeded.
    let t = Instant::now();
    while !out.join("results.json").exists() {
        if t.elapsed() > Duration::from_secs(240) {
            let logs: String = std::fs::read_dir(out.join("slurm")).map(|r| r.flatten().map(|e| format!("{}:\n{}\n", e.path().display(), std::fs::read_to_string(e.path()).unwrap_or_default())).collect()).unwrap_or_default();
            let q = Command::new("squeue").env("SLURM_CONF", &conf).output().map(|o| String::from_utf8_lossy(&o.stdout).into_owned()).unwrap_or_default();
            panic!("no results after 240 s; queue:\n{q}\nlogs:\n{logs}");
        }
        std::thread::sleep(Duration::from_millis(500));
    }
    // Every shard ran as an array task, and their parts tile the study.
    for k in 1..=4 {
        assert!(out.join(format!("slurm/shard-{k}.log")).exists(), "no log of array task {k}");
    }
    let whole = d.join("whole");
    run_ok(xhab().current_dir(&d).args(["-q", "experiment"]).arg(&s).arg("--out").arg(&whole).arg("--no-report"));
    // Give the merge job a moment to finish writing its last file.
    std::thread::sleep(Duration::from_millis(500));
    assert_eq!(untimed(json(&out.join("results.json")), false), untimed(json(&whole.join("results.json")), false));
    // The merge job writes the report after the results.
    let t = Instant::now();
    while !out.join("report/index.html").exists() && t.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(200));
    }
    assert!(out.join("report/index.html").exists(), "the merge job wrote no report");
    drop(cluster);
    std::fs::remove_dir_all(&d).ok();
}
