//! The ballbar part of a calibration report: ISO 230-4 circles read from their CSV files and
//! evaluated as `trueaxis ballbar iso230-4` evaluates them (G, F, H and the diagnostics fitted on
//! the machine's Jacobian), with their polar plots.

use super::super::circle_svg;
use super::super::html::Section;
use super::conformity::{DecisionRule, Item};
use super::quantity::{quantity, with_uncertainty};
use super::{number, CalibrationError};
use std::path::PathBuf;
use trueaxis::evaluate::ballbar_diagnostics::DiagnosticOptions;
use trueaxis::evaluate::iso230_4::{evaluate, read_circular, Iso2304Result};
use trueaxis::geometry::Vec3;
use trueaxis::instruments::ballbar::Plane;
use trueaxis::machine::Machine;

/// Decay angle of reversal spikes (deg): the default of `trueaxis ballbar iso230-4 --spike-width`.
pub const SPIKE_WIDTH_DEG: f64 = 3.0;

/// One circular test as given: the file and the setup it was run with.
#[derive(Clone, Debug, PartialEq)]
pub struct CircleInput {
    pub path: PathBuf,
    pub plane: Plane,
    /// Nominal radius: the bar length (mm).
    pub radius: f64,
    /// Programmed centre x, y, z (mm); the other axes at 0.
    pub centre: Vec3,
}

impl CircleInput {
    /// The centre pose (mm, deg): the linear axes X, Y, Z at the centre, every other axis at 0 (as
    /// `ballbar iso230-4 --centre`).
    pub fn centre_pose(&self, machine: &Machine) -> Vec<f64> {
        machine.axes().iter().map(|a| "XYZ".find(a.letter).map_or(0.0, |k| self.centre[k])).collect()
    }

    /// The `trueaxis ballbar iso230-4` command that evaluates this circle the same way, with the
    /// circle and machine files named as given.
    pub fn command(&self, circle_file: &str, machine_file: &str) -> String {
        let c = self.centre;
        format!(
            "trueaxis ballbar iso230-4 {circle_file} --machine {machine_file} --plane {} --radius {} --centre {},{},{}",
            self.plane.name(),
            self.radius,
            c.x,
            c.y,
            c.z
        )
    }
}

/// An evaluated circle.
pub struct CirclePart {
    pub input: CircleInput,
    pub result: Iso2304Result,
    /// The polar plot, and the evaluation's summary (`Iso2304Result::summary_lines`, what
    /// `trueaxis ballbar iso230-4` prints).
    pub svg: String,
    pub lines: Vec<String>,
    /// Feed rate (mm/min) from the file's header, when it states one.
    pub feed_mm_per_min: Option<f64>,
    /// Expanded uncertainty (k = 2, um) of the bar readings, from the ballbar's calibration
    /// certificate (`report.toml`): the uncertainty quoted with G, F and H.
    pub reading_u_um: Option<f64>,
    /// What the file records (machine, serial number, date, operator ...).
    pub metadata: trueaxis::io::Metadata,
    /// Paragraphs on how the test was done.
    pub description: Vec<String>,
    /// Spikes away from the axis reversals (`trueaxis::evaluate::ballbar_screening::spikes`).
    pub findings: Vec<trueaxis::screen::Finding>,
}

impl CirclePart {
    pub fn evaluate(machine: &Machine, input: CircleInput) -> Result<CirclePart, CalibrationError> {
        let centre = input.centre_pose(machine);
        let file = read_circular(&input.path, machine, input.plane, input.radius, &centre)?;
        let runs = file.runs;
        let (ia, ib, _) = input.plane.letters();
        let at = |letter: char| machine.axis_index(letter).map_or(0.0, |k| centre[k]);
        let options = DiagnosticOptions {
            plane: input.plane,
            radius: input.radius,
            centre: [at(ia), at(ib)],
            pitch: None,
            spike_width: SPIKE_WIDTH_DEG.to_radians(),
            feed: None,
        };
        let result = evaluate(machine, &runs, &options)?;
        let lines = result.summary_lines();
        let feed = file.header.feed_mm_per_min;
        let directions: Vec<String> = runs.iter().map(|r| r.rotation.name().to_uppercase()).collect();
        let conditions = vec![
            format!(
                "{} plane, radius {} mm, centre ({}, {}, {}) mm",
                input.plane.name().to_uppercase(),
                input.radius,
                input.centre.x,
                input.centre.y,
                input.centre.z
            ),
            format!(
                "feed {}, {}",
                feed.map_or("not stated in the file".to_string(), |f| format!("{f} mm/min")),
                match directions.len() {
                    1 => format!("{} run", directions[0]),
                    _ => format!("runs {} in this order", directions.join(" then ")),
                }
            ),
        ];
        let title = format!("Circular test (ISO 230-4): {}", file_name(&input.path));
        let svg = circle_svg(&title, (&format!("+{ia}"), &format!("+{ib}")), &runs, None, &[], &conditions)?;
        let findings = trueaxis::evaluate::ballbar_screening::spikes(&input.path.display().to_string(), &runs, input.radius);
        Ok(CirclePart {
            input,
            result,
            svg,
            lines,
            feed_mm_per_min: feed,
            reading_u_um: None,
            metadata: file.metadata,
            description: Vec::new(),
            findings,
        })
    }

    /// Toleranced items of this circle: `G`, `F`, `H` and diagnostics by name (`tolerances` in
    /// their units), decided under `rule`.
    pub fn conformity(&self, tolerances: &std::collections::BTreeMap<String, f64>, rule: DecisionRule) -> Vec<Item> {
        let name = file_name(&self.input.path);
        let mut items = Vec::new();
        for (key, &tol) in tolerances {
            match key.as_str() {
                "G" | "F" => {
                    for run in &self.result.runs {
                        let value = if key == "G" { run.g_um } else { run.f_max_um.abs().max(run.f_min_um.abs()) };
                        let what = if key == "G" { "circular deviation G" } else { "radial deviation F (largest magnitude)" };
                        items.push(Item::new(
                            format!("{name}, {} run: {what}", run.rotation.name().to_uppercase()),
                            "ballbar",
                            value,
                            self.reading_u_um,
                            tol,
                            "um",
                            rule,
                        ));
                    }
                }
                "H" => {
                    if let Some(h) = self.result.hysteresis_um {
                        items.push(Item::new(format!("{name}: circular hysteresis H"), "ballbar", h, self.reading_u_um, tol, "um", rule));
                    }
                }
                diagnostic => {
                    let wanted = diagnostic.replace('_', " ").to_lowercase();
                    for d in self.result.diagnostics.items.iter().filter(|d| d.name.to_lowercase() == wanted || d.parameter == diagnostic) {
                        items.push(Item::new(
                            format!("{name}: {}", d.name),
                            "ballbar",
                            d.value,
                            Some(2.0 * d.std_uncertainty),
                            tol,
                            d.unit,
                            rule,
                        ));
                    }
                }
            }
        }
        items
    }
}

/// The file's name without its directory (the path itself when it has none).
pub(super) fn file_name(path: &std::path::Path) -> String {
    path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
}

/// One section with every circle: the test conditions, the polar plot, the ISO 230-4 values and
/// the diagnostics, each with its expanded uncertainty.
pub fn section(circles: &[CirclePart]) -> Section {
    let mut s = Section::new("ballbar", "Ballbar tests (ISO 230-4)").paragraph(
        "Circular deviation G, radial deviations F and circular hysteresis H as ISO 230-4 defines them, and diagnostics: a least-squares fit of the machine's own error model in the plane of the circle (squareness, scale mismatch, straightness, backlash, lateral play, servo mismatch; docs/ballbar.md). The uncertainty of G, F and H is the expanded uncertainty of the bar readings from the ballbar's calibration certificate when report.toml gives it; that of a diagnostic is twice its least-squares standard uncertainty (the scatter of the readings about the fitted model).",
    );
    for c in circles {
        let i = &c.input;
        s = s.paragraph(format!(
            "{}: {} plane, radius {} mm, centre ({}, {}, {}) mm, feed {}.",
            i.path.display(),
            i.plane.name().to_uppercase(),
            i.radius,
            i.centre.x,
            i.centre.y,
            i.centre.z,
            c.feed_mm_per_min.map_or("not stated in the file".to_string(), |f| format!("{f} mm/min"))
        ));
        for p in &c.description {
            s = s.paragraph(p.clone());
        }
        s = s.figure(
            "Polar plot of the bar readings: the deviation from the nominal radius magnified about the black nominal circle (scale per division stated under the plot); the centre of the plot is the centre of the circle.",
            c.svg.clone(),
        );
        let u = c.reading_u_um;
        let value = |v: f64| with_uncertainty(v, u, "um", 2);
        let mut rows: Vec<Vec<String>> = c
            .result
            .runs
            .iter()
            .map(|r| {
                vec![
                    r.rotation.name().to_uppercase(),
                    value(r.g_um),
                    value(r.f_max_um),
                    value(r.f_min_um),
                    format!("({}, {}) um", number(r.centre_um[0], 2), number(r.centre_um[1], 2)),
                ]
            })
            .collect();
        if let Some(h) = c.result.hysteresis_um {
            rows.push(vec!["both".into(), format!("H = {}", value(h)), String::new(), String::new(), String::new()]);
        }
        s = s.table(
            format!("ISO 230-4 values of {}", file_name(&i.path)),
            &["run", "circular deviation G", "largest radial deviation F", "smallest radial deviation F", "centre of the fitted circle"],
            rows,
        );
        let diagnostics = c
            .result
            .diagnostics
            .items
            .iter()
            .map(|d| {
                vec![
                    d.name.clone(),
                    if d.parameter.is_empty() { "-".into() } else { d.parameter.clone() },
                    with_uncertainty(d.value, Some(2.0 * d.std_uncertainty), d.unit, 3),
                    quantity(d.effect_um, 2, "um"),
                    format!("{} %", number(d.share_percent, 0)),
                ]
            })
            .collect();
        s = s.table(
            format!("Diagnostics of {} (fit residual RMS {})", file_name(&i.path), quantity(c.result.diagnostics.residual_rms_um, 3, "um")),
            &["diagnostic", "ISO parameter", "value ± U (k = 2)", "effect on the reading", "share of the deviation"],
            diagnostics,
        );
        for o in &c.result.diagnostics.omitted {
            s = s.note(format!("Not fitted: {o}"));
        }
    }
    s
}
