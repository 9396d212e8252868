//! The scaling curves of BENCHMARKS.md: reads the runs of `bench/scaling.py` (a CSV of workload,
//! work, wall_s, cpu_s, peak_bytes, threads) and draws two log-log panels, time per run and peak
//! resident memory against the work, one colour per workload (wall time solid, CPU time of all
//! threads dashed).
//!
//! Run: `cargo run --release -p trueaxis-report --example scaling_plot -- bench/scaling.csv docs/bench/scaling.svg`.

use plotters::prelude::*;
use std::collections::BTreeMap;
use trueaxis_report::style::{colour, font, legend, title, Swatch, LEGEND_HEIGHT, TICK, WIDTH};

/// One measured run.
struct Run {
    work: f64,
    wall_s: f64,
    cpu_s: f64,
    peak_mib: f64,
}

fn read(path: &str) -> Result<BTreeMap<String, Vec<Run>>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().ok_or(format!("{path}: empty"))?.split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).ok_or(format!("{path}: no column `{name}`"));
    let (w, n, wall, cpu, peak) = (column("workload")?, column("work")?, column("wall_s")?, column("cpu_s")?, column("peak_bytes")?);
    let mut runs: BTreeMap<String, Vec<Run>> = BTreeMap::new();
    for (i, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let cells: Vec<&str> = line.split(',').collect();
        let number = |k: usize| -> Result<f64, String> {
            cells.get(k).and_then(|c| c.trim().parse().ok()).filter(|v: &f64| v.is_finite() && *v > 0.0).ok_or(format!(
                "{path}, line {}: column {} is not a positive number",
                i + 2,
                header[k]
            ))
        };
        runs.entry(cells[w].to_string()).or_default().push(Run {
            work: number(n)?,
            wall_s: number(wall)?,
            cpu_s: number(cpu)?,
            peak_mib: number(peak)? / (1024.0 * 1024.0),
        });
    }
    Ok(runs)
}

/// A panel: its y label, its decades and the values of a run it draws (one line each).
type Panel<'a> = (&'a str, (f64, f64), &'a dyn Fn(&Run) -> Vec<f64>);

/// Decades `[10^a, 10^b]` enclosing `values`.
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    (10f64.powf(lo.log10().floor()), 10f64.powf(hi.log10().ceil()))
}

fn draw(runs: &BTreeMap<String, Vec<Run>>, out: &str) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let root = SVGBackend::new(out, (WIDTH, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    title(&root, "Scaling: time and peak memory against the work", 6).map_err(|e| err(&e))?;
    let (strip, plots) = root.split_vertically(40).1.split_vertically(LEGEND_HEIGHT);
    let entries: Vec<(String, Swatch)> = runs.keys().enumerate().map(|(k, name)| (name.clone(), Swatch::Line(colour(k), 3))).collect();
    legend(&strip, &entries).map_err(|e| err(&e))?;
    let panels = plots.split_evenly((1, 2));
    let (x0, x1) = decades(runs.values().flatten().map(|r| r.work));
    let all_times = runs.values().flatten().flat_map(|r| [r.wall_s, r.cpu_s]);
    let axes: [Panel; 2] = [
        ("time per run (s): wall solid, CPU dashed", decades(all_times), &|r| vec![r.wall_s, r.cpu_s]),
        ("peak resident memory (MiB)", decades(runs.values().flatten().map(|r| r.peak_mib)), &|r| vec![r.peak_mib]),
    ];
    for (area, (y_label, (y0, y1), values)) in panels.iter().zip(axes) {
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .margin_right(36)
            .x_label_area_size(64)
            .y_label_area_size(90)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc("work (poses, rows, trials, nodes)")
            .y_desc(y_label)
            .x_label_formatter(&|v| format!("1e{:.0}", v.log10()))
            .y_label_formatter(&|v| format!("1e{:.0}", v.log10()))
            .label_style(font(TICK))
            .axis_desc_style(font(TICK))
            .draw()
            .map_err(|e| err(&e))?;
        for (k, series) in runs.values().enumerate() {
            let c = colour(k);
            let count = values(&series[0]).len();
            for which in 0..count {
                let points: Vec<(f64, f64)> = series.iter().map(|r| (r.work, values(r)[which])).collect();
                if which == 0 {
                    chart.draw_series(LineSeries::new(points.clone(), c.stroke_width(3))).map_err(|e| err(&e))?;
                } else {
                    chart.draw_series(DashedLineSeries::new(points.clone(), 8, 6, c.stroke_width(2))).map_err(|e| err(&e))?;
                }
                chart.draw_series(points.iter().map(|p| Circle::new(*p, 4, c.filled()))).map_err(|e| err(&e))?;
            }
        }
    }
    root.present().map_err(|e| err(&e))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(input), Some(output)) = (args.get(1), args.get(2)) else {
        eprintln!("usage: scaling_plot <scaling.csv> <out.svg>");
        std::process::exit(2);
    };
    if let Err(e) = read(input).and_then(|runs| draw(&runs, output)) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
