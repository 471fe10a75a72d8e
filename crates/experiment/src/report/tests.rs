//! The report of the synthetic example study: page, figures, trajectory maps and errors.

use super::*;
use crate::results::Results;

/// A fresh folder holding the example study.
fn study(name: &str) -> (PathBuf, Results) {
    let dir = std::env::temp_dir().join(format!("xhab-report-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let r = example::write_example(&dir).unwrap();
    (dir, r)
}

/// Whether `s` is well-formed XML as far as an SVG needs: tags nest and close, attribute
/// values are quoted, text holds no raw `<` and only known entities after `&`.
fn well_formed(s: &str) -> Result<(), String> {
    let mut stack: Vec<&str> = Vec::new();
    let mut rest = s.trim_start();
    if let Some(after) = rest.strip_prefix("<?xml") {
        rest = &after[after.find("?>").ok_or("unclosed <?xml")? + 2..];
    }
    let entity = |t: &str| ["&amp;", "&lt;", "&gt;", "&quot;", "&apos;", "&#"].iter().any(|e| t.starts_with(e));
    while let Some(open) = rest.find('<') {
        let text = &rest[..open];
        if let Some(a) = text.find('&') {
            if !entity(&text[a..]) {
                return Err(format!("bare & in text {text:?}"));
            }
        }
        let close = rest[open..].find('>').ok_or("unclosed tag")? + open;
        let tag = &rest[open + 1..close];
        if tag.contains('<') {
            return Err(format!("< inside tag {tag:?}"));
        }
        if tag.matches('"').count() % 2 == 1 {
            return Err(format!("unbalanced quotes in {tag:?}"));
        }
        if let Some(name) = tag.strip_prefix('/') {
            let top = stack.pop().ok_or(format!("</{name}> closes nothing"))?;
            if top != name.trim() {
                return Err(format!("<{top}> closed by </{name}>"));
            }
        } else if !tag.ends_with('/') && !tag.starts_with('!') {
            stack.push(tag.split_whitespace().next().unwrap_or(""));
        }
        rest = &rest[close + 1..];
    }
    if !rest.trim().is_empty() {
        return Err(format!("text after the root: {rest:?}"));
    }
    if stack.is_empty() {
        Ok(())
    } else {
        Err(format!("unclosed {stack:?}"))
    }
}

#[test]
fn the_page_lists_every_configuration_agent_scene_and_skip_escaped() {
    let (dir, r) = study("page");
    let page = write_report(&dir).unwrap();
    assert_eq!(page, dir.join("report/index.html"));
    let html = std::fs::read_to_string(&page).unwrap();
    for c in ["-physics -ROS", "+physics -ROS", "-physics +ROS", "+physics +ROS"] {
        assert!(html.contains(&format!("</span>{c}</td>")), "{c} has no table row");
    }
    // Names are escaped: the study's and the agent's carry < > &.
    assert!(html.contains("<h1>Synthetic study &lt;oracle &amp; nav&gt;</h1>"));
    assert!(html.contains("nav &lt;stack&gt;") && !html.contains("nav <stack>"));
    assert!(html.contains("rooms-bottom-door &amp; co"));
    // The skipped combinations with their reason, the description, the interval method.
    assert_eq!(r.skipped.len(), 4);
    assert_eq!(html.matches("it runs under physics only").count(), 4);
    assert!(html.contains("Made-up episodes on two rooms"));
    assert!(html.contains("Wilson score interval") && html.contains("Student&#39;s t interval"));
    // Relative links only, no scripts.
    for needle in ["<script", "http://", "https://", "src=\"/", "href=\"/", "file:"] {
        assert!(!html.contains(needle), "the page holds {needle}");
    }
    for src in html.split("src=\"").skip(1).map(|s| &s[..s.find('"').unwrap()]) {
        assert!(dir.join("report").join(src).is_file(), "{src} is missing");
    }
    // Every run has its section; episodes: 12 runs x 12 but one invalid.
    assert_eq!(r.runs.len(), 12);
    for run in &r.runs {
        assert!(html.contains(&format!("id=\"run-{}\"", run.id)), "{}", run.id);
    }
    assert!(html.contains("143 episodes (1 invalid left out)"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn figures_are_svg_naming_the_configurations_in_their_colours() {
    let (dir, _) = study("figures");
    write_report(&dir).unwrap();
    for name in ["spl_histogram.svg", "intervals.svg", "timing.svg", "failures.svg"] {
        let svg = std::fs::read_to_string(dir.join("report").join(name)).unwrap();
        assert!(svg.trim_start().starts_with("<svg") && svg.trim_end().ends_with("</svg>"), "{name}");
        well_formed(&svg).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(svg.contains("<text"), "{name} has no text");
        for c in ["-physics -ROS", "+physics -ROS", "-physics +ROS", "+physics +ROS"] {
            assert!(svg.contains(&format!("\n{c}")), "{name} does not name {c}");
        }
    }
    let hist = std::fs::read_to_string(dir.join("report/spl_histogram.svg")).unwrap();
    for i in 0..4 {
        assert!(hist.contains(&format!("fill=\"{}\"", figures::hex(figures::colour(i)).to_uppercase())), "colour {i}");
    }
    let failures = std::fs::read_to_string(dir.join("report/failures.svg")).unwrap();
    for (_, cause) in summary::CAUSES {
        assert!(failures.contains(cause), "{cause}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn trajectory_maps_are_the_named_and_the_worst_episodes() {
    let (dir, r) = study("maps");
    write_report(&dir).unwrap();
    let html = std::fs::read_to_string(dir.join("report/index.html")).unwrap();
    for run in &r.runs {
        // ep-3 is named; then the two lowest SPL (ties by index) among the others.
        let mut rows: Vec<_> = r.episodes.iter().filter(|e| e.run == run.id && e.episode_index != 3).collect();
        rows.sort_by(|a, b| a.metrics.spl.total_cmp(&b.metrics.spl).then(a.episode_index.cmp(&b.episode_index)));
        for i in [3, rows[0].episode_index, rows[1].episode_index] {
            let file = format!("trajectories/{}-{i}.png", run.id);
            assert!(dir.join("report").join(&file).is_file(), "{file}");
            assert!(html.contains(&format!("src=\"{file}\"")), "{file} not on the page");
        }
        let drawn = std::fs::read_dir(dir.join("report/trajectories")).unwrap().filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with(&format!("{}-", run.id))).count();
        assert_eq!(drawn, 3, "{}", run.id);
    }
    // A picture shows the map, both paths, start and goal.
    let png = std::fs::read(dir.join("report/trajectories").join(format!("{}-3.png", r.runs[0].id))).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_report_is_the_same_every_time() {
    let (dir, _) = study("same");
    write_report(&dir).unwrap();
    let read = |n: &str| std::fs::read(dir.join("report").join(n)).unwrap();
    let first: Vec<Vec<u8>> = ["index.html", "spl_histogram.svg", "intervals.svg", "timing.svg", "failures.svg"].iter().map(|n| read(n)).collect();
    write_report(&dir).unwrap();
    let second: Vec<Vec<u8>> = ["index.html", "spl_histogram.svg", "intervals.svg", "timing.svg", "failures.svg"].iter().map(|n| read(n)).collect();
    assert!(first == second);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn summary_counts_agree_with_the_results() {
    let (dir, r) = study("summary");
    let s = summary::Summary::new(&r, &[]);
    assert_eq!(s.configurations, ["-physics -ROS", "+physics -ROS", "-physics +ROS", "+physics +ROS"]);
    assert_eq!(s.agents, ["oracle", "nav <stack>"]);
    // Oracle everywhere (2 scenes x 12, one invalid in the first run); nav under physics only.
    let n: Vec<usize> = s.by_configuration.iter().map(|g| g.success.n).collect();
    assert_eq!(n, [23, 48, 24, 48]);
    assert_eq!(s.by_agent.len(), 6);
    assert!(s.timing.iter().map(|t| t.real_time_factor.is_some()).eq([false, true, false, true]));
    for (f, t) in s.failures.iter().zip(&s.timing) {
        let failed = r.episodes.iter().filter(|e| e.configuration == t.configuration && e.metrics.success < 1.0).count();
        assert_eq!(f.iter().sum::<usize>(), failed);
    }
    assert_eq!(figures::spl_bins(&[0.0, 0.05, 0.1, 0.99, 1.0, f64::NAN]), [2, 1, 0, 0, 0, 0, 0, 0, 0, 2]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn errors_name_the_file() {
    let dir = std::env::temp_dir().join(format!("xhab-report-errors-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let e = write_report(&dir).unwrap_err();
    assert!(matches!(e, ReportError::Results(_)) && e.to_string().contains("results.json"), "{e}");
    example::write_example(&dir).unwrap();
    let run = crate::results::read_results(&dir).unwrap().runs[0].id.clone();
    let bad = dir.join("runs").join(&run).join("trajectories.json");
    std::fs::write(&bad, "{not json").unwrap();
    let e = write_report(&dir).unwrap_err();
    assert!(matches!(e, ReportError::Format { .. }) && e.to_string().contains(&bad.display().to_string()), "{e}");
    std::fs::remove_file(&bad).unwrap();
    std::fs::remove_file(dir.join("maps/floor0.yaml")).unwrap();
    let e = write_report(&dir).unwrap_err();
    assert!(matches!(e, ReportError::Map(_)) && e.to_string().contains("floor0.yaml"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_study_without_runs_still_has_a_page() {
    let dir = std::env::temp_dir().join(format!("xhab-report-empty-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    let empty = Results { schema_version: 1, experiment: "nothing ran".into(), description: String::new(), runs: vec![], skipped: vec![], episodes: vec![] };
    std::fs::write(dir.join("results.json"), serde_json::to_string(&empty).unwrap()).unwrap();
    let html = std::fs::read_to_string(write_report(&dir).unwrap()).unwrap();
    assert!(html.contains("The study has no runs.") && html.contains("experiment.json is missing"));
    for name in ["spl_histogram.svg", "intervals.svg", "timing.svg", "failures.svg"] {
        well_formed(&std::fs::read_to_string(dir.join("report").join(name)).unwrap()).unwrap();
    }
    std::fs::remove_dir_all(&dir).ok();
}
