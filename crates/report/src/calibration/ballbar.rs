//! The ballbar part of a calibration report: ISO 230-4 circles read from their CSV files and
//! evaluated as `trueaxis ballbar iso230-4` evaluates them (G, F, H and the diagnostics fitted on
//! the machine's Jacobian), with their polar plots.

use super::super::circular_runs_svg;
use super::super::html::Section;
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
    /// The polar plot and the lines of text beside it (`Iso2304Result::summary_lines`).
    pub svg: String,
    pub lines: Vec<String>,
    /// Paragraphs on how the test was done.
    pub description: Vec<String>,
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
        let title = format!("ISO 230-4 circular test, {} plane, R {} mm: {}", input.plane.name(), input.radius, input.path.display());
        let svg = circular_runs_svg(&title, (&format!("+{ia}"), &format!("+{ib}")), &runs, None, &lines)?;
        Ok(CirclePart { input, result, svg, lines, description: Vec::new() })
    }
}

/// One section with every circle: the ISO values, the polar plot, the diagnostics.
pub fn section(circles: &[CirclePart]) -> Section {
    let mut s = Section::new("ballbar", "Ballbar tests (ISO 230-4)").paragraph(
        "Circular deviation G, radial deviations F, hysteresis H (ISO 230-4), and diagnostics: a least-squares fit of the machine's own Jacobian in the circle plane (squareness, scale, straightness, backlash, servo mismatch).",
    );
    for c in circles {
        let rows = c
            .result
            .diagnostics
            .items
            .iter()
            .map(|d| {
                vec![
                    d.name.clone(),
                    d.parameter.clone(),
                    number(d.value, 3),
                    number(d.std_uncertainty, 3),
                    d.unit.to_string(),
                    number(d.effect_um, 3),
                    number(d.share_percent, 1),
                ]
            })
            .collect();
        let i = &c.input;
        s = s.paragraph(format!(
            "{}: {} plane, radius {} mm, centre ({}, {}, {}) mm.",
            i.path.display(),
            i.plane.name(),
            i.radius,
            i.centre.x,
            i.centre.y,
            i.centre.z
        ));
        for p in &c.description {
            s = s.paragraph(p.clone());
        }
        s = s.figure("Polar plot of the bar readings (deviation magnified, scale per division stated)", c.svg.clone());
        s = s.table(format!("Results of {}", i.path.display()), &["value"], c.lines.iter().map(|l| vec![l.clone()]).collect());
        s = s.table("Diagnostics", &["diagnostic", "ISO parameter", "value", "u", "unit", "effect (um)", "share (%)"], rows);
        for o in &c.result.diagnostics.omitted {
            s = s.note(format!("Not fitted: {o}"));
        }
    }
    s
}
