//! `trueaxis design steady`: one 3D-ball reading per pose from a continuous recording.

use crate::output::text_or_file;
use crate::Failure;
use anyhow::anyhow;
use std::path::PathBuf;
use trueaxis::data::CsvTable;
use trueaxis::instruments::{steady_values, SteadySettings};
use trueaxis::io::units::Dimension;

/// Reduce a continuous 3D-ball recording (CapBall, R-test: dx, dy, dz sampled at a fixed rate while
/// the machine moves from pose to pose and dwells at each) to one reading per pose: the mean over
/// each dwell once the move has settled. Writes the campaign data file: the pose columns of --poses
/// and dx, dy, dz (um).
#[derive(clap::Args)]
#[command(after_help = "Example:\n  trueaxis design steady examples/campaigns/kx8five/stream_20.csv \
--poses examples/campaigns/kx8five/poses_20.csv --rate 200 --out readings_20.csv\n\n\
The recording has the columns dx, dy, dz (um; a unit in the header is honoured) and optionally t (s),\n\
from which the rate follows. A dwell is a stretch where every channel stays within --range um over\n\
--window s for at least --min-dwell s; --trim s are dropped at each end before averaging. The number\n\
of dwells must equal the number of poses, else the error says how many were found and what to change.")]
pub struct SteadyArgs {
    /// The recording (CSV): dx, dy, dz (um), optional t (s).
    stream: PathBuf,
    /// The poses in recording order (CSV, one column per axis): one dwell each.
    #[arg(long)]
    poses: PathBuf,
    /// Sample rate (Hz); default: from the t column.
    #[arg(long)]
    rate: Option<f64>,
    /// Standard deviation of the sensor noise (um): the default range is 8 times it.
    #[arg(long, default_value_t = 0.4)]
    noise: f64,
    /// Largest peak-to-peak range within a window on any channel (um); default 8 x --noise.
    #[arg(long)]
    range: Option<f64>,
    /// Window length (s).
    #[arg(long, default_value_t = 0.1)]
    window: f64,
    /// Shortest dwell (s).
    #[arg(long, default_value_t = 0.3)]
    min_dwell: f64,
    /// Dropped at each end of a dwell (s).
    #[arg(long, default_value_t = 0.02)]
    trim: f64,
    /// Write the readings here (atomically); stdout without.
    #[arg(long, value_parser = crate::output::file)]
    out: Option<crate::output::OutputPath>,
}

pub fn run(a: SteadyArgs) -> Result<(), Failure> {
    let stream = CsvTable::read(&a.stream).map_err(Failure::input)?;
    let name = a.stream.display().to_string();
    let channels = ["dx", "dy", "dz"]
        .map(|c| stream.numbers_as(c, Dimension::Length).map_err(Failure::input))
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
    let rate = match (a.rate, stream.has_column("t")) {
        (Some(r), _) => r,
        (None, true) => {
            let t = stream.numbers("t").map_err(Failure::input)?;
            let mut dt: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
            dt.sort_by(f64::total_cmp);
            let median = dt.get(dt.len() / 2).copied().unwrap_or(f64::NAN);
            1.0 / median
        }
        (None, false) => return Err(Failure::input(anyhow!("{name}: no t column: give the sample rate with --rate HZ"))),
    };
    if !(rate.is_finite() && (1.0..=1e6).contains(&rate)) {
        return Err(Failure::input(anyhow!(
            "{name}: sample rate {rate} Hz: give a rate from 1 Hz to 1 MHz (--rate, or increasing t in s)"
        )));
    }
    for (flag, v, lo, hi) in [
        ("--noise", a.noise, 1e-4, 100.0),
        ("--window", a.window, 0.0, 60.0),
        ("--min-dwell", a.min_dwell, 0.0, 600.0),
        ("--trim", a.trim, 0.0, 60.0),
    ] {
        if !(v.is_finite() && v > lo - 1e-300 && v <= hi) {
            return Err(Failure::input(anyhow!("{flag} {v}: give a value in ({lo}, {hi}]")));
        }
    }
    let samples = |s: f64| (s * rate).round() as usize;
    let settings = SteadySettings {
        window: samples(a.window).max(2),
        max_range_um: a.range.unwrap_or(8.0 * a.noise),
        min_samples: samples(a.min_dwell).max(samples(a.window).max(2)),
        trim: samples(a.trim),
    };
    let poses = CsvTable::read(&a.poses).map_err(Failure::input)?;
    let views: Vec<&[f64]> = channels.iter().map(|c| c.as_slice()).collect();
    let dwells = steady_values(&views, &settings, poses.len()).map_err(|e| Failure::input(anyhow!("{name}: {e}")))?;
    let columns: Vec<String> = poses.headers().iter().map(|h| h.name.clone()).collect();
    let values = columns.iter().map(|c| poses.numbers(c).map_err(Failure::input)).collect::<Result<Vec<_>, _>>()?;
    let mut out = format!(
        "# 3D-ball readings (um) reduced from {name} at {rate:.3} Hz: dwell means, window {} samples, range {} um\n{},dx,dy,dz\n",
        settings.window,
        settings.max_range_um,
        columns.join(",")
    );
    for (k, d) in dwells.iter().enumerate() {
        let pose: Vec<String> = values.iter().map(|v| format!("{}", v[k])).collect();
        out.push_str(&format!("{},{:.4},{:.4},{:.4}\n", pose.join(","), d.mean[0], d.mean[1], d.mean[2]));
    }
    let worst = dwells.iter().map(|d| d.std.iter().fold(0.0f64, |m, s| m.max(*s))).fold(0.0f64, f64::max);
    eprintln!("trueaxis: {} dwells for {} poses; largest standard deviation within a dwell {worst:.3} um", dwells.len(), poses.len());
    text_or_file(a.out.as_deref(), &out)
}
