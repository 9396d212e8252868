//! What a calibration report is made from: the files and the options of `trueaxis report`, one
//! field per option (named as the option; lengths in mm, times in s), as the command line, a
//! script or the Python package gives them. The per-circle options of the ballbar circles are
//! given once for all circles or once per circle, in order.

use super::super::{CalibrationError, CircleInput, POINTS};
use std::path::PathBuf;
use trueaxis::geometry::Vec3;
use trueaxis::identify::tmbb::TmbbSetup;
use trueaxis::instruments::ballbar::Plane;
use trueaxis::thermal::DEFAULT_SHARE;

/// Time per measured point of a campaign (s) when none is given.
pub const POINT_TIME_S: f64 = 0.75;
/// Normal and extended bar lengths R, L_e of the rotary-axis test (mm) when none are given.
pub const ROTARY_BARS_MM: [f64; 2] = [100.0, 150.0];
/// The setup RX, RZ, L1, L2 (mm) of the two-length test when none is given: Zhu 2008 Table 5.1.
pub const TMBB_SETUP_MM: [f64; 4] = {
    let s = TmbbSetup::ZHU_TABLE_5_1;
    [s.rx, s.rz, s.l1, s.l2]
};
/// Thermal modes computed when no number is given.
pub const THERMAL_MODES: usize = 6;

/// The report's inputs (the options of `trueaxis report`, docs/report.md).
#[derive(Clone, Debug)]
pub struct ReportRequest {
    /// Machine description (TOML); the machine itself is loaded by the caller.
    pub machine: PathBuf,
    /// Error values (TOML); default: the values identified from `campaign`.
    pub errors: Option<PathBuf>,
    pub campaign: Option<PathBuf>,
    pub allow_rank_deficient: bool,
    /// Uncertainty sources (TOML), with `campaign`.
    pub sources: Option<PathBuf>,
    /// Time per measured point of the campaign (s), for the drift sources.
    pub point_time: f64,
    /// ISO 230-4 circles and their planes, radii (mm) and centres (mm).
    pub ballbar: Vec<PathBuf>,
    pub ballbar_plane: Vec<Plane>,
    pub ballbar_radius: Vec<f64>,
    pub ballbar_centre: Vec<Vec3>,
    /// ISO 230-2 positioning tests.
    pub positioning: Vec<PathBuf>,
    /// The rotary-axis ballbar test: the steps A1, A2, C1, C2, the method (`extended-bar`,
    /// `two-pivot`, `four-setup`) and its geometry (mm).
    pub rotary_ballbar: Vec<PathBuf>,
    pub rotary_method: String,
    pub rotary_outer_offset: Option<f64>,
    pub rotary_outer_positions: Option<[f64; 2]>,
    pub rotary_inner_positions: Option<[f64; 2]>,
    pub rotary_pivot_offset_a: Option<[f64; 2]>,
    pub rotary_pivot_offset_c: Option<[f64; 2]>,
    /// Normal and extended bar lengths R, L_e (mm).
    pub rotary_bars: Vec<f64>,
    /// The two-length rotary-table test: the short and the long bar's files, the setup RX, RZ, L1, L2 (mm).
    pub tmbb: Vec<PathBuf>,
    pub tmbb_setup: Vec<f64>,
    /// Thermal conduction model, number of modes, cumulative weight share of the dominant ones.
    pub thermal_model: Option<PathBuf>,
    pub thermal_modes: usize,
    pub thermal_share: f64,
    /// Thermal error model and the campaign it predicts.
    pub thermal_error: Option<PathBuf>,
    pub thermal_data: Option<PathBuf>,
    /// Points per compensation table.
    pub points: usize,
    /// report.toml: certificate particulars, instruments, decision rule, tolerances, `[[fit]]` tables.
    pub certificate: Option<PathBuf>,
    /// The controller format of the after-compensation map.
    pub controller: Option<String>,
    pub title: Option<String>,
    /// The command that made the report, as the inputs section records it.
    pub command: Option<String>,
}

impl ReportRequest {
    /// The request of the machine alone, every option at its default.
    pub fn new(machine: PathBuf) -> ReportRequest {
        ReportRequest {
            machine,
            errors: None,
            campaign: None,
            allow_rank_deficient: false,
            sources: None,
            point_time: POINT_TIME_S,
            ballbar: Vec::new(),
            ballbar_plane: Vec::new(),
            ballbar_radius: Vec::new(),
            ballbar_centre: Vec::new(),
            positioning: Vec::new(),
            rotary_ballbar: Vec::new(),
            rotary_method: "extended-bar".into(),
            rotary_outer_offset: None,
            rotary_outer_positions: None,
            rotary_inner_positions: None,
            rotary_pivot_offset_a: None,
            rotary_pivot_offset_c: None,
            rotary_bars: ROTARY_BARS_MM.to_vec(),
            tmbb: Vec::new(),
            tmbb_setup: TMBB_SETUP_MM.to_vec(),
            thermal_model: None,
            thermal_modes: THERMAL_MODES,
            thermal_share: DEFAULT_SHARE,
            thermal_error: None,
            thermal_data: None,
            points: POINTS,
            certificate: None,
            controller: None,
            title: None,
            command: None,
        }
    }

    /// The circles with their plane, radius and centre.
    pub fn circles(&self) -> Result<Vec<CircleInput>, CalibrationError> {
        let n = self.ballbar.len();
        if n == 0 {
            if !(self.ballbar_plane.is_empty() && self.ballbar_radius.is_empty() && self.ballbar_centre.is_empty()) {
                return Err(bad("--ballbar-plane, --ballbar-radius and --ballbar-centre need a --ballbar circle"));
            }
            return Ok(Vec::new());
        }
        let planes = per_circle(&self.ballbar_plane, "--ballbar-plane", n, Some(Plane::Xy))?;
        let radii = per_circle(&self.ballbar_radius, "--ballbar-radius", n, None)?;
        let centres = per_circle(&self.ballbar_centre, "--ballbar-centre", n, Some(Vec3::zeros()))?;
        Ok((0..n).map(|i| CircleInput { path: self.ballbar[i].clone(), plane: planes[i], radius: radii[i], centre: centres[i] }).collect())
    }
}

/// A bad input.
pub(super) fn bad(message: impl Into<String>) -> CalibrationError {
    CalibrationError::Input(message.into())
}

/// The value of a per-circle option for circle `i` of `n`: given once for all or once per circle.
fn per_circle<T: Copy>(values: &[T], option: &str, n: usize, default: Option<T>) -> Result<Vec<T>, CalibrationError> {
    match values.len() {
        0 => default.map(|d| vec![d; n]).ok_or_else(|| bad(format!("--ballbar needs {option} (once for all circles or once per circle)"))),
        1 => Ok(vec![values[0]; n]),
        k if k == n => Ok(values.to_vec()),
        k => Err(bad(format!("{option} is given {k} times for {n} circles: give it once for all or once per --ballbar"))),
    }
}
