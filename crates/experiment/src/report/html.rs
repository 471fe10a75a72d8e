//! The report page: one self-contained HTML file (inline CSS, no scripts) that links its
//! figures by relative paths, so it opens from the file system.

use super::figures::{colour, hex, Figures, CAUSE_COLOURS};
use super::stats::{Estimate, METHOD};
use super::summary::{Group, Summary, CAUSES};
use super::trajectories::{RunPictures, Why, GOAL, ROBOT, SHORTEST, START};
use crate::results::Results;
use crate::spec::TrajectorySpec;
use std::fmt::Write;

/// `s` with HTML's special characters escaped (text and attribute values).
pub fn escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            c => o.push(c),
        }
    }
    o
}

/// A relative path as a URL: bytes outside `[A-Za-z0-9._~/-]` percent-encoded.
pub fn href(path: &str) -> String {
    path.bytes().map(|b| if b.is_ascii_alphanumeric() || b"._~/-".contains(&b) { (b as char).to_string() } else { format!("%{b:02X}") }).collect()
}

/// What the page shows.
pub struct Page<'a> {
    /// The results.
    pub results: &'a Results,
    /// Their summary.
    pub summary: &'a Summary,
    /// The figures.
    pub figures: &'a Figures,
    /// The trajectory pictures, per run.
    pub runs: &'a [RunPictures],
    /// Which trajectories were asked for.
    pub trajectories: &'a TrajectorySpec,
    /// Remarks on what is missing (shown under the title).
    pub notes: &'a [String],
}

const STYLE: &str = "body{font-family:sans-serif;margin:24px auto;max-width:1000px;color:#222;line-height:1.4}\
h1{margin-bottom:4px}h2{border-bottom:1px solid #ccc;padding-bottom:4px;margin-top:36px}\
table{border-collapse:collapse;margin:12px 0}th,td{border:1px solid #ccc;padding:4px 8px;text-align:right}\
th{background:#f3f3f3}td.name,th.name{text-align:left}td.name{white-space:nowrap}.swatch{display:inline-block;width:12px;height:12px;margin-right:6px;vertical-align:middle}\
img.figure{width:100%;max-width:960px;border:1px solid #eee}.note{color:#555;font-size:90%}.warn{color:#a40}\
.maps{display:flex;flex-wrap:wrap;gap:12px}.maps figure{margin:0;width:310px}.maps img{width:310px;border:1px solid #ccc}\
figcaption{font-size:85%}nav a{margin-right:12px}";

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3}")
    } else {
        "–".into()
    }
}

fn estimate(e: &Estimate) -> String {
    match e.interval {
        Some((lo, hi)) => format!("{} <span class=\"note\">[{}, {}]</span>", num(e.mean), num(lo), num(hi)),
        None => num(e.mean),
    }
}

/// A configuration's name with its colour swatch.
fn configuration(s: &Summary, name: &str) -> String {
    match s.configurations.iter().position(|c| c == name) {
        Some(i) => format!("<span class=\"swatch\" style=\"background:{}\"></span>{}", hex(colour(i)), escape(name)),
        None => escape(name),
    }
}

fn group_rows(s: &Summary, groups: &[Group], with_agent: bool) -> String {
    let mut o = String::from("<table><tr><th class=\"name\">configuration</th>");
    if with_agent {
        o.push_str("<th class=\"name\">agent</th>");
    }
    o.push_str("<th>runs</th><th>episodes</th><th>invalid</th><th>success [95% CI]</th><th>SPL [95% CI]</th><th>soft SPL [95% CI]</th></tr>\n");
    for g in groups {
        let _ = write!(o, "<tr><td class=\"name\">{}</td>", configuration(s, &g.configuration));
        if with_agent {
            let _ = write!(o, "<td class=\"name\">{}</td>", escape(g.agent.as_deref().unwrap_or("")));
        }
        let _ = writeln!(
            o,
            "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            g.runs,
            g.success.n,
            g.invalid,
            estimate(&g.success),
            estimate(&g.spl),
            estimate(&g.soft_spl)
        );
    }
    o.push_str("</table>\n");
    o
}

fn figure(file: &str, alt: &str) -> String {
    format!("<p><a href=\"{0}\"><img class=\"figure\" src=\"{0}\" alt=\"{1}\"></a></p>\n", href(file), escape(alt))
}

fn summary_section(p: &Page) -> String {
    let s = p.summary;
    let mut o = String::from("<section id=\"summary\"><h2>Success and SPL by configuration</h2>\n");
    o += &group_rows(s, &s.by_configuration, false);
    if !s.by_agent.is_empty() {
        o += "<h3>By configuration and agent</h3>\n";
        o += &group_rows(s, &s.by_agent, true);
    }
    let _ = writeln!(o, "<p class=\"note\">{}</p>", escape(METHOD));
    o += &figure(&p.figures.intervals, "success rate and SPL per configuration with 95% confidence intervals");
    o += "</section>\n";
    o
}

fn scenes_section(s: &Summary) -> String {
    let mut o = String::from("<section id=\"scenes\"><h2>By scene</h2>\n<p class=\"note\">Each cell: success rate / SPL (episodes).</p>\n<table><tr><th class=\"name\">scene</th>");
    for c in &s.configurations {
        let _ = write!(o, "<th>{}</th>", configuration(s, c));
    }
    o += "</tr>\n";
    for (scene, cells) in s.scenes.iter().zip(&s.by_scene) {
        let _ = write!(o, "<tr><td class=\"name\">{}</td>", escape(scene));
        for cell in cells {
            match cell {
                Some(c) => {
                    let _ = write!(o, "<td>{} / {} <span class=\"note\">({})</span></td>", num(c.success), num(c.spl), c.episodes);
                }
                None => o += "<td class=\"note\">–</td>",
            }
        }
        o += "</tr>\n";
    }
    o += "</table></section>\n";
    o
}

fn timing_section(p: &Page) -> String {
    let s = p.summary;
    let mut o = String::from("<section id=\"timing\"><h2>Wall time and real-time factor</h2>\n");
    o += &figure(&p.figures.timing, "wall time per episode and real-time factor per configuration");
    o += "<table><tr><th class=\"name\">configuration</th><th>episodes</th><th>wall time (s)</th><th>per episode (s)</th><th>actions / s</th><th>real-time factor</th></tr>\n";
    for t in &s.timing {
        let per = if t.episodes > 0 { t.wall_s / t.episodes as f64 } else { f64::NAN };
        let rtf = t.real_time_factor.map_or_else(|| "<span class=\"note\">no sim time</span>".to_string(), num);
        let _ =
            writeln!(o, "<tr><td class=\"name\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.1}</td><td>{}</td></tr>", configuration(s, &t.configuration), t.episodes, num(t.wall_s), num(per), t.steps_per_s, rtf);
    }
    o += "</table>\n<p class=\"note\">Wall time: the runs' elapsed time summed (sharded runs: their parts'). Real-time factor: simulated seconds per wall-clock second, over runs under physics only.</p></section>\n";
    o
}

fn failures_section(p: &Page) -> String {
    let s = p.summary;
    let mut o = String::from("<section id=\"failures\"><h2>Failures by cause</h2>\n");
    o += &figure(&p.figures.failures, "failed episodes by cause per configuration");
    o += "<table><tr><th class=\"name\">configuration</th><th>episodes</th>";
    for ((_, name), c) in CAUSES.iter().zip(CAUSE_COLOURS) {
        let _ = write!(o, "<th><span class=\"swatch\" style=\"background:{}\"></span>{}</th>", hex(c), escape(name));
    }
    o += "<th>failed</th></tr>\n";
    for ((c, f), t) in s.configurations.iter().zip(&s.failures).zip(&s.timing) {
        let _ = write!(o, "<tr><td class=\"name\">{}</td><td>{}</td>", configuration(s, c), t.episodes);
        for n in f {
            let _ = write!(o, "<td>{n}</td>");
        }
        let _ = writeln!(o, "<td>{}</td></tr>", f.iter().sum::<usize>());
    }
    o += "</table></section>\n";
    o
}

fn trajectories_section(p: &Page) -> String {
    let s = p.summary;
    let key = |c: [u8; 3], what: &str| format!("<span class=\"swatch\" style=\"background:{}\"></span>{what} ", hex(c));
    let mut o = String::from("<section id=\"trajectories\"><h2>Trajectories</h2>\n");
    let named = if p.trajectories.episodes.is_empty() { String::new() } else { format!(" and the episodes {}", escape(&p.trajectories.episodes.join(", "))) };
    let _ = writeln!(o, "<p>Each run's {} lowest-SPL episodes (ties: lower episode index first){named}, top-down over the floor's map. {}{}{}{}</p>", p.trajectories.worst, key(SHORTEST, "shortest path"), key(ROBOT, "robot path"), key(START, "start"), key(GOAL, "goal"));
    for rp in p.runs {
        let r = &rp.run;
        let _ = writeln!(
            o,
            "<h3 id=\"run-{}\">{}</h3>\n<p class=\"note\">scene {}, agent {}, {}, seed {} · <a href=\"{}\">bench report</a></p>",
            escape(&r.id),
            escape(&r.id),
            escape(&r.scene),
            escape(&r.agent),
            configuration(s, &r.configuration),
            r.seed,
            href(&format!("../{}", r.report))
        );
        if let Some(n) = &rp.note {
            let _ = writeln!(o, "<p class=\"note\">{}</p>", escape(n));
        }
        o += "<div class=\"maps\">\n";
        for pic in &rp.pictures {
            let why = match pic.why {
                Why::Chosen => "named in the spec".to_string(),
                Why::Worst(k) => format!("lowest SPL #{k}"),
            };
            let metrics = pic.row.as_ref().map_or_else(String::new, |r| {
                let m = &r.metrics;
                let failure = m.failure.as_deref().map_or_else(String::new, |f| format!(", failed: {}", escape(f)));
                format!("<br>SPL {}, success {}{failure}, path {:.2} m, geodesic {:.2} m", num(m.spl), m.success, m.path_length, m.start_distance)
            });
            let _ = writeln!(
                o,
                "<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"trajectory of episode {1}\"></a><figcaption>episode {1} (#{2}), {3}{4}</figcaption></figure>",
                href(&pic.file),
                escape(&pic.episode_id),
                pic.index,
                why,
                metrics
            );
        }
        o += "</div>\n";
    }
    o += "</section>\n";
    o
}

fn skipped_section(r: &Results) -> String {
    let mut o = String::from("<section id=\"skipped\"><h2>Skipped combinations</h2>\n");
    if r.skipped.is_empty() {
        o += "<p>None: every scene × agent × configuration ran.</p>";
    } else {
        o += "<table><tr><th class=\"name\">scene</th><th class=\"name\">agent</th><th class=\"name\">configuration</th><th class=\"name\">reason</th></tr>\n";
        for s in &r.skipped {
            let _ = writeln!(o, "<tr><td class=\"name\">{}</td><td class=\"name\">{}</td><td class=\"name\">{}</td><td class=\"name\">{}</td></tr>", escape(&s.scene), escape(&s.agent), escape(&s.configuration), escape(&s.reason));
        }
        o += "</table>";
    }
    o += "</section>\n";
    o
}

/// The page's HTML.
pub fn page(p: &Page) -> String {
    let (r, s) = (p.results, p.summary);
    let list = |v: &[String]| v.iter().map(|x| escape(x)).collect::<Vec<_>>().join(", ");
    let mut o = String::new();
    let _ = writeln!(o, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{} · xhab report</title><style>{STYLE}</style></head><body>", escape(&r.experiment));
    let _ = writeln!(o, "<h1>{}</h1>", escape(&r.experiment));
    if !r.description.is_empty() {
        let _ = writeln!(o, "<p>{}</p>", escape(&r.description));
    }
    let invalid: usize = r.runs.iter().map(|x| x.invalid).sum();
    let seeds = s.seeds.iter().map(u64::to_string).collect::<Vec<_>>().join(", ");
    let _ = writeln!(
        o,
        "<p class=\"note\">{} runs, {} episodes ({invalid} invalid left out) · scenes: {} · agents: {} · configurations: {} · seeds: {seeds} · data: <a href=\"../results.json\">results.json</a>, <a href=\"../results.csv\">results.csv</a></p>",
        r.runs.len(),
        s.episodes(),
        list(&s.scenes),
        list(&s.agents),
        list(&s.configurations)
    );
    for n in p.notes {
        let _ = writeln!(o, "<p class=\"warn\">{}</p>", escape(n));
    }
    o += "<nav><a href=\"#summary\">summary</a><a href=\"#spl\">SPL histogram</a><a href=\"#scenes\">by scene</a><a href=\"#timing\">timing</a><a href=\"#failures\">failures</a><a href=\"#trajectories\">trajectories</a><a href=\"#skipped\">skipped</a></nav>\n";
    o += &summary_section(p);
    o += "<section id=\"spl\"><h2>SPL distribution</h2>\n";
    o += &figure(&p.figures.spl_histogram, "histogram of episode SPL per configuration");
    o += "<p class=\"note\">Ten bins over [0, 1] (the last includes 1); failed episodes have SPL 0.</p></section>\n";
    o += &scenes_section(s);
    o += &timing_section(p);
    o += &failures_section(p);
    o += &trajectories_section(p);
    o += &skipped_section(r);
    let _ = writeln!(o, "<footer class=\"note\"><p>Made by xhab from results.json (layout version {}).</p></footer>\n</body></html>", r.schema_version);
    o
}
