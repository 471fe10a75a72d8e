//! Every malformed input file of tests/malformed/, fed to the command that reads it: the CLI
//! must fail with exit status 2, an error (never a panic) that names the file and the field or
//! byte offset at fault. The files and what each must say are the table in
//! tests/malformed/README.md, which this test reads: a row is
//! `| FILE | `COMMAND FILE ...` | what it breaks | `text` `text` ... |`.

use crate::common::{repo_root, xhab};
use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant};

/// One row of the manifest.
struct Case {
    /// The file fed to the command.
    file: String,
    /// The command's arguments, `FILE` standing for the file's path.
    args: Vec<String>,
    /// What stderr must contain besides the file's name.
    expect: Vec<String>,
}

/// The backtick-quoted parts of a table cell.
fn quoted(cell: &str) -> Vec<String> {
    cell.split('`').skip(1).step_by(2).map(str::to_string).collect()
}

fn manifest(dir: &Path) -> Vec<Case> {
    let text = std::fs::read_to_string(dir.join("README.md")).expect("tests/malformed/README.md");
    let mut cases = Vec::new();
    for line in text.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| file ")) {
        let cells: Vec<&str> = line.trim_matches('|').split(" | ").map(str::trim).collect();
        assert_eq!(cells.len(), 4, "a manifest row has 4 cells: {line}");
        let file = cells[0].trim_matches('`').to_string();
        let args = quoted(cells[1]).first().unwrap_or_else(|| panic!("no command in {line}")).split_whitespace().map(str::to_string).collect();
        cases.push(Case { file, args, expect: quoted(cells[3]) });
    }
    cases
}

/// Runs the CLI, killing it after `limit` (a file that unexpectedly loads must not leave a
/// node waiting for a ROS master forever).
fn run(args: &[String], limit: Duration) -> (Option<i32>, String) {
    let mut child = xhab()
        .args(args)
        .env("ROS_MASTER_URI", "http://127.0.0.1:9")
        .env("XHAB_LOG", "error")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("xhab runs");
    // Read stderr while waiting, so a long message cannot fill the pipe and stall the CLI.
    let mut pipe = child.stderr.take().expect("stderr");
    let reader = std::thread::spawn(move || {
        let mut err = String::new();
        let _ = std::io::Read::read_to_string(&mut pipe, &mut err);
        err
    });
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("waiting for xhab") {
            break Some(s);
        }
        if t0.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (status.and_then(|s| s.code()), reader.join().expect("stderr reader"))
}

#[test]
fn malformed_inputs_are_errors_naming_the_file_and_the_fault() {
    let dir: PathBuf = repo_root().join("tests/malformed");
    let cases = manifest(&dir);
    assert!(cases.len() >= 40, "{} malformed files listed; the corpus has at least 40", cases.len());
    // Every file in the folder is fed to a command, or is what a fed file refers to.
    for e in std::fs::read_dir(&dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().to_string();
        if name == "README.md" || name == "make_corpus.py" {
            continue;
        }
        let used = cases.iter().any(|c| c.file == name || c.expect.iter().any(|x| x.contains(&name)));
        assert!(used || name == "map_ok.pgm" || name.ends_with(".mtl"), "{name} is in tests/malformed but not in its README's table");
    }
    let mut failures = Vec::new();
    for c in &cases {
        let path = dir.join(&c.file);
        assert!(path.is_file(), "{} is listed but missing", c.file);
        let args: Vec<String> = c.args.iter().map(|a| if a == "FILE" { path.display().to_string() } else { a.clone() }).collect();
        let (code, err) = run(&args, Duration::from_secs(120));
        let mut wrong = Vec::new();
        if code != Some(2) {
            wrong.push(format!("exit status {code:?}, not 2"));
        }
        if err.contains("panicked") {
            wrong.push("a panic".into());
        }
        if !err.contains(&c.file) {
            wrong.push(format!("no mention of {}", c.file));
        }
        for x in &c.expect {
            if !err.contains(x.as_str()) {
                wrong.push(format!("no `{x}`"));
            }
        }
        if !wrong.is_empty() {
            failures.push(format!("xhab {}: {}\n  stderr: {}", args.join(" "), wrong.join("; "), err.trim().replace('\n', "\n          ")));
        }
    }
    assert!(failures.is_empty(), "{} of {} malformed files:\n{}", failures.len(), cases.len(), failures.join("\n"));
}
