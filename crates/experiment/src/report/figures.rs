//! The report's charts as SVG (plotters' SVG backend: text stays `<text>` for the browser to
//! set, so no font files are needed). One colour per configuration throughout.

use super::summary::{Summary, CAUSES};
use super::ReportError;
use plotters::coord::ranged1d::SegmentedCoord;
use plotters::coord::types::RangedCoordusize;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::error::Error;
use std::path::Path;

/// Configuration colours, in the study's order (Tableau 10).
pub const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// Failure-cause colours, in [`CAUSES`] order.
pub const CAUSE_COLOURS: [[u8; 3]; 5] = [[128, 0, 38], [217, 95, 2], [117, 112, 179], [231, 41, 138], [102, 166, 30]];

/// The colour of the `i`th configuration.
pub fn colour(i: usize) -> [u8; 3] {
    PALETTE[i % PALETTE.len()]
}

/// `#rrggbb` of a colour.
pub fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The figures' files, relative to the report folder.
#[derive(Debug, Clone)]
pub struct Figures {
    /// SPL histogram, one panel per configuration.
    pub spl_histogram: String,
    /// Success and SPL with their intervals.
    pub intervals: String,
    /// Wall time per episode and real-time factor.
    pub timing: String,
    /// Failures by cause.
    pub failures: String,
}

/// Width of every figure (px).
const WIDTH: u32 = 960;
/// Bins of the SPL histogram over [0, 1].
pub const SPL_BINS: usize = 10;

type Drawn = Result<(), Box<dyn Error>>;
type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

fn rgb(c: [u8; 3]) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

/// Writes the SVG drawn by `draw` on a white canvas of `height` px to `out/name`.
fn svg(out: &Path, name: &str, height: u32, draw: impl FnOnce(&Area) -> Drawn) -> Result<String, ReportError> {
    let path = out.join(name);
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (WIDTH, height)).into_drawing_area();
        let drawn = root.fill(&WHITE).map_err(Box::from).and_then(|_| draw(&root)).and_then(|_| root.present().map_err(Box::from));
        drawn.map_err(|e| ReportError::Figure { path: path.clone(), message: e.to_string() })?;
    }
    std::fs::write(&path, text).map_err(|source| ReportError::Io { path, source })?;
    Ok(name.to_string())
}

/// Writes every figure of `s` into `out`.
pub fn write_all(out: &Path, s: &Summary) -> Result<Figures, ReportError> {
    Ok(Figures {
        spl_histogram: spl_histogram(out, s)?,
        intervals: intervals(out, s)?,
        timing: timing(out, s)?,
        failures: failures(out, s)?,
    })
}

/// Episodes per SPL bin (`SPL_BINS` bins over [0, 1], the last closed).
pub fn spl_bins(spl: &[f64]) -> [usize; SPL_BINS] {
    let mut bins = [0; SPL_BINS];
    for &x in spl.iter().filter(|x| x.is_finite()) {
        bins[((x.clamp(0.0, 1.0) * SPL_BINS as f64) as usize).min(SPL_BINS - 1)] += 1;
    }
    bins
}

/// `0..=n-1` as segments (at least two, so the axis has a width); `i`'s right edge.
fn categories(n: usize) -> (SegmentedCoord<RangedCoordusize>, impl Fn(usize) -> SegmentValue<usize>) {
    let hi = n.max(2) - 1;
    ((0..hi).into_segmented(), move |i: usize| if i + 1 > hi { SegmentValue::Last } else { SegmentValue::Exact(i + 1) })
}

/// The label of segment `v` among `names`.
fn category_label(names: &[String], v: &SegmentValue<usize>) -> String {
    match v {
        SegmentValue::CenterOf(i) => names.get(*i).cloned().unwrap_or_default(),
        _ => String::new(),
    }
}

/// Rounds `x` up to a tenth (at least `min`).
fn ceil_tenth(x: f64, min: f64) -> f64 {
    ((x * 10.0).ceil() / 10.0).max(min)
}

/// The SPL histogram: one panel per configuration in its colour, a shared y axis.
fn spl_histogram(out: &Path, s: &Summary) -> Result<String, ReportError> {
    let n = s.configurations.len().max(1);
    let bins: Vec<[usize; SPL_BINS]> = s.spl.iter().map(|x| spl_bins(x)).collect();
    let share = |b: &[usize; SPL_BINS], k: usize| b[k] as f64 / b.iter().sum::<usize>().max(1) as f64;
    let top = bins.iter().flat_map(|b| (0..SPL_BINS).map(move |k| share(b, k))).fold(0.0, f64::max);
    let top = ceil_tenth(top * 1.05, 0.1).min(1.0);
    svg(out, "spl_histogram.svg", 40 + 200 * n as u32, |root| {
        let (title, rest) = root.split_vertically(40);
        title.titled("SPL per episode, by configuration", ("sans-serif", 24))?;
        for (i, panel) in rest.split_evenly((n, 1)).iter().enumerate().take(s.configurations.len()) {
            let spl = &s.spl[i];
            let mean = spl.iter().sum::<f64>() / spl.len().max(1) as f64;
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{} (n = {}, mean SPL {:.3})", s.configurations[i], spl.len(), mean), ("sans-serif", 19))
                .margin(8)
                .x_label_area_size(34)
                .y_label_area_size(56)
                .build_cartesian_2d(0f64..1f64, 0f64..top)?;
            chart
                .configure_mesh()
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 15))
                .disable_x_mesh()
                .x_labels(SPL_BINS + 1)
                .y_labels(5)
                .x_desc("SPL")
                .y_desc("share of episodes")
                .x_label_formatter(&|x| format!("{x:.1}"))
                .y_label_formatter(&|y| format!("{:.0}%", y * 100.0))
                .draw()?;
            let c = rgb(colour(i));
            let b = bins[i];
            chart.draw_series((0..SPL_BINS).map(|k| {
                let (lo, hi) = (k as f64 / SPL_BINS as f64, (k + 1) as f64 / SPL_BINS as f64);
                let mut r = Rectangle::new([(lo, 0.0), (hi, share(&b, k))], c.filled());
                r.set_margin(0, 0, 2, 2);
                r
            }))?;
        }
        Ok(())
    })
}

/// Success rate and SPL per configuration with their 95% intervals.
fn intervals(out: &Path, s: &Summary) -> Result<String, ReportError> {
    svg(out, "intervals.svg", 380, |root| {
        let (title, rest) = root.split_vertically(40);
        title.titled("Success rate and SPL, 95% confidence intervals", ("sans-serif", 24))?;
        let panels = rest.split_evenly((1, 2));
        let metrics: [(&str, Vec<_>); 2] = [
            ("success rate", s.by_configuration.iter().map(|g| g.success).collect()),
            ("SPL", s.by_configuration.iter().map(|g| g.spl).collect()),
        ];
        for (panel, (name, est)) in panels.iter().zip(metrics) {
            let (x, right) = categories(s.configurations.len());
            let mut chart =
                ChartBuilder::on(panel).caption(name, ("sans-serif", 19)).margin(10).x_label_area_size(34).y_label_area_size(50).build_cartesian_2d(x, 0f64..1f64)?;
            chart.configure_mesh().label_style(("sans-serif", 15)).axis_desc_style(("sans-serif", 15)).disable_x_mesh().y_labels(6).x_label_formatter(&|v| category_label(&s.configurations, v)).draw()?;
            chart.draw_series(est.iter().enumerate().map(|(i, e)| {
                let mut r = Rectangle::new([(SegmentValue::Exact(i), 0.0), (right(i), if e.mean.is_finite() { e.mean } else { 0.0 })], rgb(colour(i)).filled());
                r.set_margin(0, 0, 18, 18);
                r
            }))?;
            chart.draw_series(
                est.iter().enumerate().filter_map(|(i, e)| e.interval.map(|(lo, hi)| ErrorBar::new_vertical(SegmentValue::CenterOf(i), lo, e.mean, hi, BLACK.stroke_width(2), 14))),
            )?;
        }
        Ok(())
    })
}

/// Wall time per episode and real-time factor per configuration.
fn timing(out: &Path, s: &Summary) -> Result<String, ReportError> {
    svg(out, "timing.svg", 380, |root| {
        let (title, rest) = root.split_vertically(40);
        title.titled("Wall time and real-time factor", ("sans-serif", 24))?;
        let panels = rest.split_evenly((1, 2));
        let per_episode: Vec<Option<f64>> = s.timing.iter().map(|t| (t.episodes > 0).then(|| t.wall_s / t.episodes as f64)).collect();
        let rtf: Vec<Option<f64>> = s.timing.iter().map(|t| t.real_time_factor).collect();
        let panes = [("wall time per episode (s)", per_episode, "none"), ("real-time factor (simulated s / wall s)", rtf, "no sim time")];
        for (panel, (name, values, missing)) in panels.iter().zip(panes) {
            let top = values.iter().flatten().fold(0.0, |a: f64, &b| a.max(b));
            let top = if top > 0.0 { top * 1.15 } else { 1.0 };
            let (x, right) = categories(s.configurations.len());
            let mut chart =
                ChartBuilder::on(panel).caption(name, ("sans-serif", 19)).margin(10).x_label_area_size(34).y_label_area_size(60).build_cartesian_2d(x, 0f64..top)?;
            chart.configure_mesh().label_style(("sans-serif", 15)).axis_desc_style(("sans-serif", 15)).disable_x_mesh().y_labels(6).x_label_formatter(&|v| category_label(&s.configurations, v)).draw()?;
            chart.draw_series(values.iter().enumerate().filter_map(|(i, v)| {
                let mut r = Rectangle::new([(SegmentValue::Exact(i), 0.0), (right(i), (*v)?)], rgb(colour(i)).filled());
                r.set_margin(0, 0, 18, 18);
                Some(r)
            }))?;
            let label = ("sans-serif", 14).into_font().color(&BLACK).pos(Pos::new(HPos::Center, VPos::Bottom));
            chart.draw_series(values.iter().enumerate().map(|(i, v)| {
                let text = v.map_or_else(|| missing.to_string(), |v| if v >= 100.0 { format!("{v:.0}") } else { format!("{v:.3}") });
                Text::new(text, (SegmentValue::CenterOf(i), v.unwrap_or(0.0)), label.clone())
            }))?;
        }
        Ok(())
    })
}

/// Failures by cause: stacked shares of each configuration's episodes, a legend beside.
fn failures(out: &Path, s: &Summary) -> Result<String, ReportError> {
    svg(out, "failures.svg", 400, |root| {
        let (title, rest) = root.split_vertically(40);
        title.titled("Failed episodes by cause", ("sans-serif", 24))?;
        let (plot, legend) = rest.split_horizontally(WIDTH - 240);
        let episodes: Vec<usize> = s.timing.iter().map(|t| t.episodes).collect();
        let share = |i: usize, k: usize| s.failures[i][k] as f64 / episodes[i].max(1) as f64;
        let top = (0..s.failures.len()).map(|i| (0..CAUSES.len()).map(|k| share(i, k)).sum::<f64>()).fold(0.0, f64::max);
        let top = ceil_tenth(top * 1.1, 0.1).min(1.0);
        let (x, right) = categories(s.configurations.len());
        let mut chart = ChartBuilder::on(&plot).margin(10).x_label_area_size(34).y_label_area_size(60).build_cartesian_2d(x, 0f64..top)?;
        chart
            .configure_mesh()
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 15))
            .disable_x_mesh()
            .y_labels(6)
            .y_desc("share of episodes")
            .y_label_formatter(&|y| format!("{:.0}%", y * 100.0))
            .x_label_formatter(&|v| category_label(&s.configurations, v))
            .draw()?;
        for (k, c) in CAUSE_COLOURS.iter().enumerate() {
            chart.draw_series((0..s.failures.len()).filter(|&i| s.failures[i][k] > 0).map(|i| {
                let below: f64 = (0..k).map(|j| share(i, j)).sum();
                let mut r = Rectangle::new([(SegmentValue::Exact(i), below), (right(i), below + share(i, k))], rgb(*c).filled());
                r.set_margin(0, 0, 18, 18);
                r
            }))?;
        }
        for (k, ((_, name), c)) in CAUSES.iter().zip(CAUSE_COLOURS).enumerate() {
            let y = 30 + 28 * k as i32;
            legend.draw(&Rectangle::new([(10, y), (28, y + 18)], rgb(c).filled()))?;
            legend.draw(&Text::new(name.to_string(), (36, y + 2), ("sans-serif", 15).into_font()))?;
        }
        Ok(())
    })
}
