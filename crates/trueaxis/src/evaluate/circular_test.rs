//! An ISO 230-4 circular test from its file, end to end: the ballbar file read forgivingly (a table
//! or a ballbar text export with a `Key: value` header), the radius and plane from the options or
//! the header, the evaluation with diagnostics on the machine's kinematic model, and the document
//! of `trueaxis ballbar iso230-4 --json`. The command line and the Python package both call
//! [`circular_test`].
//!
//! Units: radius and centre in mm, angles in deg, feed in mm/min, readings and results in um.

use super::ballbar_diagnostics::DiagnosticOptions;
use super::iso230_4::{evaluate, read_circular_table, CircularFile, Iso2304Result};
use super::EvaluateError;
use crate::data::CsvTable;
use crate::geometry::Vec3;
use crate::instruments::ballbar::{ballbar_header, Plane};
use crate::machine::Machine;
use serde_json::Value;

/// The machine of a circular test without a machine file: X, Y, Z all on the tool side, tool point
/// at the origin, travel +-5000 mm.
pub const CARTESIAN_MACHINE: &str = "name = \"Cartesian XYZ (all slides carry the tool)\"\nstructure = \"wbXYZt\"\n[axes]\n\
X = { kind = \"linear\", direction = [1, 0, 0], range = [-5000, 5000] }\n\
Y = { kind = \"linear\", direction = [0, 1, 0], range = [-5000, 5000] }\n\
Z = { kind = \"linear\", direction = [0, 0, 1], range = [-5000, 5000] }\n[tool]\npoint = [0, 0, 0]\n";

/// [`CARTESIAN_MACHINE`], built.
pub fn cartesian_machine() -> Machine {
    // a constant description, checked by the tests of this module
    Machine::from_toml_str(CARTESIAN_MACHINE, "built-in Cartesian machine").expect("the built-in Cartesian machine is valid")
}

/// The pose (mm, deg) of a programmed centre x, y, z (mm): the linear axes X, Y, Z at it, every
/// other axis at 0.
pub fn centre_pose(machine: &Machine, centre: Option<Vec3>) -> Vec<f64> {
    let c = centre.unwrap_or_else(Vec3::zeros);
    machine.axes().iter().map(|a| "XYZ".find(a.letter).map_or(0.0, |k| c[k])).collect()
}

/// The settings of a circular test (the options of `trueaxis ballbar iso230-4`).
#[derive(Clone, Debug, PartialEq)]
pub struct CircularTestOptions {
    /// Plane of the circle; none: the file's `Plane:`, else XY.
    pub plane: Option<Plane>,
    /// Nominal radius (mm), the bar length; none: the file's `Radius:`.
    pub radius_mm: Option<f64>,
    /// Programmed centre x, y, z (mm); none: the origin.
    pub centre_mm: Option<Vec3>,
    /// Feed rate (mm/min), to state the servo mismatch in ms.
    pub feed_mm_per_min: Option<f64>,
    /// Ball-screw pitch (mm), to fit cyclic errors.
    pub pitch_mm: Option<f64>,
    /// Decay angle of reversal spikes (deg).
    pub spike_width_deg: f64,
}

impl CircularTestOptions {
    /// A feed, pitch or spike width that is not a positive number is an input error naming its option.
    pub fn check(&self) -> Result<(), EvaluateError> {
        let checked = [("--feed", self.feed_mm_per_min), ("--pitch", self.pitch_mm), ("--spike-width", Some(self.spike_width_deg))];
        for (option, v) in checked {
            if let Some(v) = v.filter(|v| !(*v > 0.0 && v.is_finite())) {
                return Err(EvaluateError::Input(format!("{option} must be a positive number, got {v}")));
            }
        }
        Ok(())
    }
}

impl Default for CircularTestOptions {
    fn default() -> Self {
        CircularTestOptions { plane: None, radius_mm: None, centre_mm: None, feed_mm_per_min: None, pitch_mm: None, spike_width_deg: 3.0 }
    }
}

/// The outcome of a circular test.
#[derive(Clone, Debug)]
pub struct CircularTest {
    pub plane: Plane,
    pub radius_mm: f64,
    /// The runs read, the file's metadata and header, warnings of reading it.
    pub file: CircularFile,
    pub result: Iso2304Result,
    /// What screening found suspect in the readings (`evaluate::ballbar_screening::spikes`), each with G of its
    /// run without it; the result above is of every reading.
    pub findings: Vec<crate::screen::Finding>,
}

impl CircularTest {
    /// The document of `trueaxis ballbar iso230-4 --json`: [`Iso2304Result::to_json`] with the
    /// file's `metadata`.
    pub fn to_json(&self) -> Value {
        let mut doc = self.result.to_json();
        doc["metadata"] = self.file.metadata.to_json();
        doc["data_quality"] = crate::screen::findings_json(&self.findings);
        doc
    }
}

/// Evaluates the circular test in `table` on `machine` (ISO 230-4 G, F, H and the diagnostics,
/// `evaluate::iso230_4`). A radius neither given nor in the file, or a feed, pitch or spike width
/// that is not a positive number, is an input error.
pub fn circular_test(table: &CsvTable, machine: &Machine, options: &CircularTestOptions) -> Result<CircularTest, EvaluateError> {
    options.check()?;
    let centre = centre_pose(machine, options.centre_mm);
    let name = table.origin();
    let header = ballbar_header(table)?;
    let radius = options.radius_mm.or(header.radius_mm).ok_or_else(|| {
        EvaluateError::Input(format!("{name}: give the nominal radius (--radius MM, the bar length); the file does not state it"))
    })?;
    let plane = match (options.plane, header.plane) {
        (Some(p), _) => p,
        (None, Some(p)) => Plane::parse(p).unwrap_or(Plane::Xy),
        (None, None) => Plane::Xy,
    };
    let file = read_circular_table(table, name, machine, plane, radius, &centre)?;
    let (ia, ib, _) = plane.letters();
    let ca = machine.axis_index(ia).map_or(0.0, |k| centre[k]);
    let cb = machine.axis_index(ib).map_or(0.0, |k| centre[k]);
    let diagnostic = DiagnosticOptions {
        plane,
        radius,
        centre: [ca, cb],
        pitch: options.pitch_mm,
        spike_width: options.spike_width_deg.to_radians(),
        feed: options.feed_mm_per_min,
    };
    let result = evaluate(machine, &file.runs, &diagnostic)?;
    let findings = crate::evaluate::ballbar_screening::spikes(name, &file.runs, radius);
    Ok(CircularTest { plane, radius_mm: radius, file, result, findings })
}

/// As [`circular_test`], reading the file at `path` (the options checked first).
pub fn circular_test_file(
    path: impl AsRef<std::path::Path>,
    machine: &Machine,
    options: &CircularTestOptions,
) -> Result<CircularTest, EvaluateError> {
    options.check()?;
    circular_test(&CsvTable::read(path)?, machine, options)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cartesian_machine_carries_the_tool_on_x_y_z() {
        let m = cartesian_machine();
        assert_eq!(m.axis_letters(), "XYZ");
        assert_eq!(centre_pose(&m, Some(Vec3::new(1.0, 2.0, -3.0))), vec![1.0, 2.0, -3.0]);
    }

    #[test]
    fn options_out_of_range_name_the_option() {
        let table = CsvTable::from_text("angle,dL\n0,1\n", "c.csv").unwrap();
        let m = cartesian_machine();
        let bad = CircularTestOptions { pitch_mm: Some(-5.0), radius_mm: Some(100.0), ..Default::default() };
        assert_eq!(circular_test(&table, &m, &bad).unwrap_err().to_string(), "--pitch must be a positive number, got -5");
        let no_radius = circular_test(&table, &m, &CircularTestOptions::default()).unwrap_err();
        assert!(no_radius.is_input() && no_radius.to_string().starts_with("c.csv: give the nominal radius"), "{no_radius}");
    }
}
