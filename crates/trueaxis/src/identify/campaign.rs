//! The measurement campaign of docs/design.md, Files: the parameters to identify and the
//! measurements (instrument, data file, the points it relates, its frame and noise), turned into the
//! stacked linear problem of Andolfatto et al. 2011 eqs. 3-4 / Soons 1993 eq. 4.9:
//! `observations = design_matrix * unknowns + noise`.
//!
//! ```text
//! let campaign = Campaign::load("campaign.toml", &machine)?;
//! let nominal = campaign.nominal_errors(&machine)?;           // known errors (or all zero)
//! let design = campaign.design_matrix(&machine, &nominal)?;   // rows, weights, channels
//! ```
//!
//! Units: observations and residuals in um; each column in um of reading per user unit of its
//! unknown (um, urad, um/mm, ...).
//!
//! Large problems (10^5 readings, hundreds of basis coefficients): the rows are computed in
//! parallel over records (rayon, one workspace per thread, no allocation per record) in blocks of
//! about a megabyte, then copied into the column-major matrix.

use super::unknowns::{parameter_factors, BasisParameter, Unknown, UnknownKind};
use super::IdentifyError;
use crate::data::CsvTable;
use crate::error_model::{Basis, BasisSpec, ErrorModel};
use crate::geometry::Vec3;
use crate::instruments::{
    nominal_vector, plate_displacement, plate_rows, Ball3d, Instrument, Length, PointLength, Probe, SensorCalibration,
};
use crate::machine::{one_line, Machine};
use crate::model::{jacobian, Frame, JacobianWorkspace, Setup, JACOBIAN_ROWS};
use crate::poses::read_poses;
use nalgebra::{DMatrix, Matrix3};
use rayon::prelude::*;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CampaignFile {
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    source: Option<String>,
    #[serde(default)]
    parameters: Vec<String>,
    #[serde(default)]
    nominal_errors: Option<String>,
    /// `[basis.NAME]`: motion error NAME identified as a parametric function of its own axis (the
    /// fields of the error-values file's `[basis.NAME]` without `coefficients`).
    #[serde(default)]
    basis: BTreeMap<String, BasisSpec>,
    #[serde(default)]
    measurement: Vec<MeasurementFile>,
}

/// `calibration = { cube = "cube.csv" }` or `calibration = { matrix = [[..], [..], [..]], offset_um = [..] }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationFile {
    #[serde(default)]
    cube: Option<String>,
    #[serde(default)]
    matrix: Option<[[f64; 3]; 3]>,
    #[serde(default)]
    offset_um: Option<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum SigmaFile {
    One(f64),
    PerChannel(Vec<f64>),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MeasurementFile {
    instrument: String,
    data: String,
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    tool_point: Option<[f64; 3]>,
    #[serde(default)]
    work_point: Option<[f64; 3]>,
    #[serde(default)]
    frame: Option<String>,
    sigma_um: SigmaFile,
    #[serde(default)]
    length_offset: bool,
    #[serde(default)]
    plate: bool,
    #[serde(default)]
    calibration: Option<CalibrationFile>,
}

/// One measurement of a campaign with its data.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// `name` from the file, or the data file's stem.
    pub name: String,
    pub instrument: Instrument,
    /// The data file (resolved against the campaign file's folder).
    pub data: PathBuf,
    /// Standard deviation of the noise of each channel (um).
    pub sigma_um: Vec<f64>,
    /// Whether the gauge length is unknown (an offset unknown is added).
    pub length_offset: bool,
    /// For a probed plate: the centre of its misalignment rotations (mean of the nominal points,
    /// workpiece frame, mm).
    pub plate_centre: Option<Vec3>,
    /// Axis positions in user units: `axis_count * poses_per_record` per record.
    pub poses: Vec<f64>,
    /// File line of each record.
    pub lines: Vec<u64>,
    /// Readings (um), `channels` per record, after the sensor calibration if there is one; `None`
    /// when the data file has no reading columns yet (a planned measurement, see
    /// [`super::simulate_campaign`]).
    pub readings: Option<Vec<f64>>,
    /// The sensor-frame calibration of a 3D head (Andolfatto et al. 2011 eqs. 6-10) applied to the raw readings
    /// of the data file: `reading = M [raw; 1]`.
    pub calibration: Option<SensorCalibration>,
}

impl Measurement {
    pub fn records(&self) -> usize {
        self.lines.len()
    }

    /// The internal-unit poses of record `r` (one or two).
    fn record_poses(&self, machine: &Machine, r: usize, buffer: &mut [f64]) {
        let n = machine.axis_count();
        let k = self.instrument.poses_per_record();
        for i in 0..k {
            machine.pose_to_internal(&self.poses[(r * k + i) * n..(r * k + i + 1) * n], &mut buffer[i * n..(i + 1) * n]);
        }
    }
}

/// A campaign: unknowns and measurements, bound to one machine.
#[derive(Clone, Debug)]
pub struct Campaign {
    /// The campaign file, for messages.
    pub origin: String,
    pub name: Option<String>,
    /// The error parameters named in `parameters` (in that order), then the coefficients of every
    /// `[basis.NAME]` (by name), then the nuisance unknowns of the measurements (gauge offsets,
    /// plate misalignments).
    pub unknowns: Vec<Unknown>,
    /// The motion errors identified as basis functions, with the position of their coefficients.
    pub bases: Vec<BasisParameter>,
    /// Known errors the identification starts from (`nominal_errors`), resolved path.
    pub nominal_errors: Option<PathBuf>,
    pub measurements: Vec<Measurement>,
}

/// The stacked linear problem of a campaign.
#[derive(Clone, Debug)]
pub struct DesignMatrix {
    /// Names and units of the columns (the campaign's unknowns).
    pub names: Vec<String>,
    pub units: Vec<String>,
    /// `rows x unknowns`, um of reading per user unit of each unknown (first order about zero
    /// errors, Soons 1993 eq. 2.24 / Andolfatto et al. 2011 eq. 2).
    pub matrix: DMatrix<f64>,
    /// Readings minus the exact prediction with the nominal errors (um): what the unknowns must
    /// explain.
    pub observations: Vec<f64>,
    /// Noise standard deviation of each row (um) and the weight `1 / sigma^2`.
    pub sigma_um: Vec<f64>,
    pub weights: Vec<f64>,
    /// Channel of each row (index into `channel_names`, e.g. `capball:dx`).
    pub channels: Vec<usize>,
    pub channel_names: Vec<String>,
    /// Measurement index and record index of each row.
    pub records: Vec<(usize, usize)>,
}

impl DesignMatrix {
    pub fn rows(&self) -> usize {
        self.matrix.nrows()
    }
}

fn input(origin: &str, message: impl std::fmt::Display) -> IdentifyError {
    IdentifyError::Input(format!("{origin}: {message}"))
}

impl Campaign {
    /// Reads a campaign TOML and its data files for `machine`. Every error names the file (and the
    /// line or key).
    pub fn load(path: impl AsRef<Path>, machine: &Machine) -> Result<Campaign, IdentifyError> {
        Self::load_with(path.as_ref(), machine, true)
    }

    /// As [`Campaign::load`], also without any unknown (an empty `parameters` list and no
    /// nuisance): a re-measurement to verify a model with (`evaluate::verification`).
    pub fn load_measurements(path: impl AsRef<Path>, machine: &Machine) -> Result<Campaign, IdentifyError> {
        Self::load_with(path.as_ref(), machine, false)
    }

    fn load_with(path: &Path, machine: &Machine, require_unknowns: bool) -> Result<Campaign, IdentifyError> {
        let origin = path.display().to_string();
        let text = crate::files::inputs::read_to_string(path).map_err(|e| input(&origin, format!("cannot read campaign file: {e}")))?;
        Campaign::parse_toml(&text, &origin, path.parent().unwrap_or(Path::new("")), machine, require_unknowns)
    }

    /// A campaign from its TOML text; `origin` names it in messages and the data files are read
    /// relative to `dir`.
    pub fn from_toml_str(text: &str, origin: &str, dir: &Path, machine: &Machine) -> Result<Campaign, IdentifyError> {
        Campaign::parse_toml(text, origin, dir, machine, true)
    }

    fn parse_toml(text: &str, origin: &str, dir: &Path, machine: &Machine, require_unknowns: bool) -> Result<Campaign, IdentifyError> {
        let origin = origin.to_string();
        crate::io::toml_numbers::refuse_underflow(text).map_err(|m| input(&origin, m))?;
        let file: CampaignFile = toml::from_str(text).map_err(|e| input(&origin, one_line(&e.to_string())))?;
        let _ = &file.source;
        let dir = dir.to_path_buf();
        let mut unknowns = Vec::new();
        for name in &file.parameters {
            let u = Unknown::parse(machine, name).map_err(|m| input(&origin, format!("parameters: {m}")))?;
            if unknowns.iter().any(|v: &Unknown| v.name == u.name) {
                return Err(input(&origin, format!("parameters: {} is listed twice", u.name)));
            }
            unknowns.push(u);
        }
        let mut bases = Vec::new();
        for (name, spec) in &file.basis {
            let at = |m: String| input(&origin, format!("[basis.{name}]: {m}"));
            let basis = Basis::new(spec.clone()).map_err(at)?;
            let (coefficients, mut parameter) = Unknown::basis(machine, name, basis, bases.len()).map_err(at)?;
            if let Some(u) = unknowns.iter().find(|u| u.parameter().map(|(id, _)| id) == Some(parameter.id)) {
                return Err(at(format!("{} is also in `parameters` ({}); identify it one way", parameter.id, u.name)));
            }
            parameter.first = unknowns.len();
            unknowns.extend(coefficients);
            bases.push(parameter);
        }
        if file.measurement.is_empty() {
            return Err(input(&origin, "no [[measurement]]: a campaign needs at least one"));
        }
        let mut measurements = Vec::new();
        for (i, m) in file.measurement.iter().enumerate() {
            let measurement = load_measurement(m, i, &dir, &origin, machine)?;
            if measurements.iter().any(|o: &Measurement| o.name == measurement.name) {
                return Err(input(&origin, format!("measurement {}: the name `{}` is used twice; give `name`", i + 1, measurement.name)));
            }
            if measurement.length_offset {
                unknowns.push(Unknown::length_offset(i, &measurement.name));
            }
            if measurement.plate_centre.is_some() {
                unknowns.extend(Unknown::plate(i, &measurement.name));
            }
            measurements.push(measurement);
        }
        if require_unknowns && unknowns.is_empty() {
            return Err(input(&origin, "parameters: the list is empty and there is no [basis.NAME]; name the parameters to identify"));
        }
        Ok(Campaign { origin, name: file.name, unknowns, bases, nominal_errors: file.nominal_errors.map(|p| dir.join(p)), measurements })
    }

    /// The known errors (`nominal_errors`), or all zero.
    pub fn nominal_errors(&self, machine: &Machine) -> Result<ErrorModel, IdentifyError> {
        match &self.nominal_errors {
            Some(path) => ErrorModel::load(path, machine).map_err(|e| IdentifyError::Input(e.to_string())),
            None => Ok(ErrorModel::zero(machine)),
        }
    }

    /// Values (user units) of the unknowns in `nominal` (zero for nuisances).
    pub fn nominal_values(&self, nominal: &ErrorModel) -> Result<Vec<f64>, IdentifyError> {
        self.unknowns.iter().map(|u| u.nominal_value(nominal, &self.bases).map_err(|m| input(&self.origin, m))).collect()
    }

    /// Channel names `measurement:channel` and the row count.
    fn channel_layout(&self) -> (Vec<String>, usize) {
        let mut names = Vec::new();
        let mut rows = 0;
        for m in &self.measurements {
            names.extend(m.instrument.channels().iter().map(|c| format!("{}:{c}", m.name)));
            rows += m.records() * m.instrument.channels().len();
        }
        (names, rows)
    }

    /// The stacked design matrix (first order about zero errors) and the observations (readings
    /// minus the exact prediction with `nominal`). Andolfatto et al. 2011 eqs. 3-4; Soons 1993 eqs. 4.1-4.9.
    pub fn design_matrix(&self, machine: &Machine, nominal: &ErrorModel) -> Result<DesignMatrix, IdentifyError> {
        let (channel_names, n_rows) = self.channel_layout();
        let p = self.unknowns.len();
        let mut readings = Vec::with_capacity(n_rows);
        for m in &self.measurements {
            readings.extend_from_slice(m.readings.as_ref().ok_or_else(|| {
                input(
                    &m.data.display().to_string(),
                    format!("no reading columns ({}): measure them or simulate them first", m.instrument.channels().join(", ")),
                )
            })?);
        }
        let mut matrix = DMatrix::zeros(n_rows, p);
        let mut sigma_um = Vec::with_capacity(n_rows);
        let mut channels = Vec::with_capacity(n_rows);
        let mut records = Vec::with_capacity(n_rows);
        let (mut row, mut channel_base) = (0, 0);
        for (mi, m) in self.measurements.iter().enumerate() {
            let nc = m.instrument.channels().len();
            // about 1 MB of rows per parallel block
            let block = (131_072 / (nc * p).max(1)).max(1);
            let mut buffer = vec![0.0; block.min(m.records()) * nc * p];
            for start in (0..m.records()).step_by(block) {
                let count = block.min(m.records() - start);
                let rows = &mut buffer[..count * nc * p];
                rows.par_chunks_mut(nc * p)
                    .enumerate()
                    .for_each_init(|| Workspace::new(machine, p), |ws, (i, out)| self.record_rows(machine, mi, start + i, ws, out));
                copy_rows(rows, p, &mut matrix, row);
                for r in start..start + count {
                    for c in 0..nc {
                        sigma_um.push(m.sigma_um[c]);
                        channels.push(channel_base + c);
                        records.push((mi, r));
                    }
                }
                row += count * nc;
            }
            channel_base += nc;
        }
        let predicted = self.predict(machine, nominal, &vec![0.0; p])?;
        let observations: Vec<f64> = readings.iter().zip(&predicted).map(|(a, b)| a - b).collect();
        let weights = sigma_um.iter().map(|s| 1.0 / (s * s)).collect();
        Ok(DesignMatrix {
            names: self.unknowns.iter().map(|u| u.name.clone()).collect(),
            units: self.unknowns.iter().map(|u| u.unit.clone()).collect(),
            matrix,
            observations,
            sigma_um,
            weights,
            channels,
            channel_names,
            records,
        })
    }

    /// The `channels x p` rows (row-major, um per user unit) of record `r` of measurement `mi`:
    /// the instrument's combination of the Jacobians of its poses, reduced to the unknowns, and the
    /// nuisance columns.
    fn record_rows(&self, machine: &Machine, mi: usize, r: usize, ws: &mut Workspace, out: &mut [f64]) {
        let m = &self.measurements[mi];
        let (n_axes, p) = (machine.axis_count(), self.unknowns.len());
        let (setup, frame) = (m.instrument.setup(), m.instrument.frame());
        let k = m.instrument.poses_per_record();
        m.record_poses(machine, r, &mut ws.q);
        let mut nominal_vectors = [Vec3::zeros(); 2];
        for (i, nominal) in nominal_vectors.iter_mut().enumerate().take(k) {
            let qi = &ws.q[i * n_axes..(i + 1) * n_axes];
            jacobian(machine, qi, &setup, frame, &mut ws.jacobian, &mut ws.full);
            *nominal = nominal_vector(machine, qi, &setup);
            parameter_factors(&self.unknowns, &self.bases, machine, qi, &mut ws.factors);
            let reduced = &mut ws.reduced[i * JACOBIAN_ROWS * p..(i + 1) * JACOBIAN_ROWS * p];
            self.reduce_columns(machine, &ws.full, &ws.factors, jacobian_rows_read(&m.instrument), reduced);
        }
        let (first, second) = ws.reduced.split_at(JACOBIAN_ROWS * p);
        let jacobians: [&[f64]; 2] = [first, second];
        m.instrument.linear_rows(&jacobians[..k], &nominal_vectors[..k], p, out);
        out.iter_mut().for_each(|v| *v *= 1e3);
        self.nuisance_columns(mi, &nominal_vectors[0], out);
    }

    /// From the full `7 x P` Jacobian at a pose and the factors of the unknowns there to the
    /// `7 x p` Jacobian of the unknowns (mm or rad per user unit), in the Jacobian rows `rows` only.
    /// Nuisance columns are left as they are (zero: nothing writes them).
    fn reduce_columns(&self, machine: &Machine, full: &[f64], factors: &[f64], rows: Range<usize>, out: &mut [f64]) {
        let (n_params, p) = (machine.parameter_count(), self.unknowns.len());
        for r in rows {
            let (source, target) = (&full[r * n_params..(r + 1) * n_params], &mut out[r * p..(r + 1) * p]);
            for ((t, u), f) in target.iter_mut().zip(&self.unknowns).zip(factors) {
                if let Some((_, index)) = u.parameter() {
                    *t = source[index] * f;
                }
            }
        }
    }

    /// Columns of the nuisance unknowns of measurement `mi` in the rows `out` (row-major,
    /// `channels x p`) of one record whose nominal vector is `nominal` (um per um or urad).
    fn nuisance_columns(&self, mi: usize, nominal: &Vec3, out: &mut [f64]) {
        let p = self.unknowns.len();
        // the nuisance unknowns are the last ones
        for (j, u) in self.unknowns.iter().enumerate().rev().take_while(|(_, u)| !u.is_model()) {
            match u.kind {
                UnknownKind::LengthOffset { measurement } if measurement == mi => out[j] = 1.0,
                UnknownKind::Plate { measurement, component } if measurement == mi => {
                    let centre = self.measurements[mi].plate_centre.expect("plate unknowns only with a centre");
                    let rows = plate_rows(nominal, &centre);
                    let to_internal = if component < 3 { 1e-3 } else { 1e-6 };
                    for c in 0..3 {
                        out[c * p + j] = rows[c * 6 + component] * to_internal * 1e3;
                    }
                }
                _ => {}
            }
        }
    }

    /// Exact readings (um) of every row, on the kinematic chain with the errors of `nominal` plus the
    /// unknowns `theta` (user units) added: the forward model of the Levenberg-Marquardt refinement
    /// and of simulation. Parallel over records.
    pub fn predict(&self, machine: &Machine, nominal: &ErrorModel, theta: &[f64]) -> Result<Vec<f64>, IdentifyError> {
        if theta.len() != self.unknowns.len() || theta.iter().any(|t| !t.is_finite()) {
            return Err(input(&self.origin, "the unknowns must be finite numbers, one per unknown"));
        }
        let (_, n_rows) = self.channel_layout();
        let mut out = vec![0.0; n_rows];
        let mut row = 0;
        let unknowns = theta.iter().any(|t| *t != 0.0).then_some(theta);
        for (mi, m) in self.measurements.iter().enumerate() {
            let nc = m.instrument.channels().len();
            out[row..row + m.records() * nc].par_chunks_mut(nc).enumerate().for_each_init(
                || Workspace::new(machine, self.unknowns.len()),
                |ws, (r, v)| self.record_exact(machine, nominal, unknowns, mi, r, ws, v),
            );
            row += m.records() * nc;
        }
        Ok(out)
    }

    /// The exact reading (um) of record `r` of measurement `mi` into `v`, with the unknowns `theta`
    /// (`None`: all zero).
    #[allow(clippy::too_many_arguments)]
    fn record_exact(
        &self,
        machine: &Machine,
        nominal: &ErrorModel,
        theta: Option<&[f64]>,
        mi: usize,
        r: usize,
        ws: &mut Workspace,
        v: &mut [f64],
    ) {
        let m = &self.measurements[mi];
        let (n_axes, n_params) = (machine.axis_count(), machine.parameter_count());
        let k = m.instrument.poses_per_record();
        m.record_poses(machine, r, &mut ws.q);
        for i in 0..k {
            let qi = &ws.q[i * n_axes..(i + 1) * n_axes];
            let pi = &mut ws.params[i * n_params..(i + 1) * n_params];
            nominal.values_at(machine, qi, pi);
            if let Some(theta) = theta {
                parameter_factors(&self.unknowns, &self.bases, machine, qi, &mut ws.factors);
                for ((u, t), f) in self.unknowns.iter().zip(theta).zip(&ws.factors) {
                    if let Some((_, index)) = u.parameter() {
                        pi[index] += t * f;
                    }
                }
            }
        }
        let (q0, q1) = ws.q.split_at(n_axes);
        let (p0, p1) = ws.params.split_at(n_params);
        let (poses, params): ([&[f64]; 2], [&[f64]; 2]) = ([q0, q1], [p0, p1]);
        m.instrument.exact(machine, &poses[..k], &params[..k], v);
        v.iter_mut().for_each(|x| *x *= 1e3);
        if let Some(theta) = theta {
            self.add_nuisances(mi, m, machine, q0, theta, v);
        }
    }

    fn add_nuisances(&self, mi: usize, m: &Measurement, machine: &Machine, pose: &[f64], theta: &[f64], v: &mut [f64]) {
        let mut t = Vec3::zeros();
        let mut w = Vec3::zeros();
        let mut plate = false;
        for (u, value) in self.unknowns.iter().zip(theta) {
            match u.kind {
                UnknownKind::LengthOffset { measurement } if measurement == mi => v[0] += value,
                UnknownKind::Plate { measurement, component } if measurement == mi => {
                    plate = true;
                    if component < 3 {
                        t[component] = value * 1e-3;
                    } else {
                        w[component - 3] = value * 1e-6;
                    }
                }
                _ => {}
            }
        }
        if plate {
            let centre = m.plate_centre.expect("plate unknowns only with a centre");
            let point = nominal_vector(machine, pose, &m.instrument.setup());
            let d = plate_displacement(&point, &centre, &t, &w);
            for c in 0..3 {
                v[c] += d[c] * 1e3;
            }
        }
    }

    /// The `7 x p` first-order effect (mm or rad per user unit, rows `dx dy dz drx dry drz dL`) of
    /// the model unknowns on the volumetric error at pose `q` (mm, rad) between the points of
    /// `setup` in `frame`; nuisance columns are zero. For propagating the covariance of the
    /// identified parameters to predictions (Soons 1993 eq. 4.12, App. A eq. A.4).
    pub fn unknown_jacobian(&self, machine: &Machine, q: &[f64], setup: &Setup, frame: Frame) -> DMatrix<f64> {
        let p = self.unknowns.len();
        let mut ws = Workspace::new(machine, p);
        jacobian(machine, q, setup, frame, &mut ws.jacobian, &mut ws.full);
        parameter_factors(&self.unknowns, &self.bases, machine, q, &mut ws.factors);
        self.reduce_columns(machine, &ws.full, &ws.factors, 0..JACOBIAN_ROWS, &mut ws.reduced[..JACOBIAN_ROWS * p]);
        DMatrix::from_row_slice(JACOBIAN_ROWS, p, &ws.reduced[..JACOBIAN_ROWS * p])
    }
}

/// The rows of the Jacobian (`dx dy dz drx dry drz dL`) that [`Instrument::linear_rows`] reads:
/// the position rows for 3D balls, probes and probed lengths, the `dL` row for lengths.
fn jacobian_rows_read(instrument: &Instrument) -> Range<usize> {
    match instrument {
        Instrument::Length(_) => 6..7,
        Instrument::Ball3d(_) | Instrument::Probe(_) | Instrument::PointLength(_) => 0..3,
    }
}

/// Copies `rows` (row-major, `p` columns) into `matrix` from row `first` on, in tiles of 64 x 64
/// so that both the reads and the column-major writes stay in cache.
fn copy_rows(rows: &[f64], p: usize, matrix: &mut DMatrix<f64>, first: usize) {
    const TILE: usize = 64;
    let n = rows.len() / p.max(1);
    for i0 in (0..n).step_by(TILE) {
        for j0 in (0..p).step_by(TILE) {
            for j in j0..(j0 + TILE).min(p) {
                let mut column = matrix.column_mut(j);
                for i in i0..(i0 + TILE).min(n) {
                    column[first + i] = rows[i * p + j];
                }
            }
        }
    }
}

/// Buffers of one thread for the rows and exact readings of records (up to two poses each).
struct Workspace {
    jacobian: JacobianWorkspace,
    /// Axis positions of the record's poses (mm, rad).
    q: Vec<f64>,
    /// The full `7 x P` Jacobian of one pose.
    full: Vec<f64>,
    /// Parameter vectors of the record's poses (mm, rad).
    params: Vec<f64>,
    /// `d params / d theta` of every unknown at one pose.
    factors: Vec<f64>,
    /// The `7 x p` Jacobians of the unknowns at the record's poses.
    reduced: Vec<f64>,
}

impl Workspace {
    fn new(machine: &Machine, p: usize) -> Workspace {
        let n_params = machine.parameter_count();
        Workspace {
            jacobian: JacobianWorkspace::default(),
            q: vec![0.0; 2 * machine.axis_count()],
            full: vec![0.0; JACOBIAN_ROWS * n_params],
            params: vec![0.0; 2 * n_params],
            factors: vec![0.0; p],
            reduced: vec![0.0; 2 * JACOBIAN_ROWS * p],
        }
    }
}

fn load_measurement(m: &MeasurementFile, i: usize, dir: &Path, origin: &str, machine: &Machine) -> Result<Measurement, IdentifyError> {
    let at = |message: String| input(origin, format!("measurement {}: {message}", i + 1));
    let data = dir.join(&m.data);
    let data_name = data.display().to_string();
    let name = m.name.clone().unwrap_or_else(|| data.file_stem().map_or(format!("m{}", i + 1), |s| s.to_string_lossy().into_owned()));
    let point = |p: Option<[f64; 3]>, default: Vec3, key: &str| -> Result<Vec3, IdentifyError> {
        match p {
            Some(v) if v.iter().all(|x| x.is_finite()) => Ok(Vec3::new(v[0], v[1], v[2])),
            Some(_) => Err(at(format!("`{key}` must be three finite numbers (mm)"))),
            None => Ok(default),
        }
    };
    let setup = Setup {
        tool_point: point(m.tool_point, machine.tool_point, "tool_point")?,
        work_point: point(m.work_point, Vec3::zeros(), "work_point")?,
    };
    let frame = match m.frame.as_deref() {
        None | Some("workpiece") => Frame::Workpiece,
        Some("machine") => Frame::Machine,
        Some(other) => return Err(at(format!("frame `{other}`: expected \"workpiece\" or \"machine\""))),
    };
    let instrument = match m.instrument.as_str() {
        "ball3d" => Instrument::Ball3d(Ball3d { setup, frame }),
        "length" => Instrument::Length(Length { setup }),
        "point_length" => Instrument::PointLength(PointLength { setup }),
        "probe" => Instrument::Probe(Probe { setup }),
        other => return Err(at(format!("instrument `{other}`: expected ball3d, length, point_length or probe"))),
    };
    if m.frame.is_some() && !matches!(instrument, Instrument::Ball3d(_)) {
        return Err(at(format!(
            "`frame` applies to ball3d only ({} readings are frame-free or in the workpiece frame)",
            instrument.kind()
        )));
    }
    if m.length_offset && !matches!(instrument, Instrument::Length(_) | Instrument::PointLength(_)) {
        return Err(at("`length_offset` applies to length and point_length measurements only".into()));
    }
    if m.plate && !matches!(instrument, Instrument::Probe(_)) {
        return Err(at("`plate` applies to probe measurements only".into()));
    }
    let calibration = match &m.calibration {
        None => None,
        Some(_) if !matches!(instrument, Instrument::Ball3d(_)) => {
            return Err(at("`calibration` (a sensor-frame calibration) applies to ball3d measurements only".into()))
        }
        Some(c) => Some(calibration(c, dir).map_err(|e| at(format!("calibration: {e}")))?),
    };
    let nc = instrument.channels().len();
    let sigma_um = match &m.sigma_um {
        SigmaFile::One(s) => vec![*s; nc],
        SigmaFile::PerChannel(v) if v.len() == nc => v.clone(),
        SigmaFile::PerChannel(v) => {
            return Err(at(format!("`sigma_um` has {} values for {nc} channels ({})", v.len(), instrument.channels().join(", "))))
        }
    };
    if sigma_um.iter().any(|s| !s.is_finite() || *s <= 0.0) {
        return Err(at("`sigma_um` must be positive (um)".into()));
    }
    let table = CsvTable::read(&data).map_err(|e| at(e.to_string()))?;
    let first = read_poses(&data, machine).map_err(|e| at(e.to_string()))?;
    let n = machine.axis_count();
    let poses = if instrument.poses_per_record() == 2 {
        let mut second = Vec::with_capacity(first.user.len());
        for axis in machine.axes() {
            second.push(
                table
                    .numbers(&format!("{}2", axis.letter))
                    .map_err(|e| at(format!("{e} (the second end of a point_length has columns X2, Y2, ...)")))?,
            );
        }
        let mut both = Vec::with_capacity(2 * first.user.len());
        for r in 0..first.len() {
            both.extend_from_slice(&first.user[r * n..(r + 1) * n]);
            let pose: Vec<f64> = second.iter().map(|c| c[r]).collect();
            machine.check_range(&pose).map_err(|e| at(format!("{data_name}: line {}: second end: {e}", first.lines[r])))?;
            both.extend(pose);
        }
        both
    } else {
        first.user.clone()
    };
    let channels = instrument.channels();
    let readings = if channels.iter().all(|c| table.has_column(c)) {
        let columns: Vec<Vec<f64>> = channels.iter().map(|c| table.numbers(c)).collect::<Result<_, _>>().map_err(|e| at(e.to_string()))?;
        for (c, column) in channels.iter().zip(&columns) {
            crate::data::checks::physical_range(&table, c, column, &crate::io::ranges::READING_UM).map_err(|e| at(e.to_string()))?;
        }
        let mut readings: Vec<f64> = (0..table.len()).flat_map(|r| columns.iter().map(move |c| c[r])).collect();
        if let Some(cal) = &calibration {
            for record in readings.chunks_mut(3) {
                let v = cal.apply(&Vec3::new(record[0], record[1], record[2]));
                record.copy_from_slice(v.as_slice());
            }
        }
        Some(readings)
    } else if channels.iter().any(|c| table.has_column(c)) {
        return Err(at(format!("{data_name}: has some but not all of the reading columns {}", channels.join(", "))));
    } else {
        None
    };
    let mut measurement = Measurement {
        name,
        instrument,
        data,
        sigma_um,
        length_offset: m.length_offset,
        plate_centre: None,
        poses,
        lines: first.lines,
        readings,
        calibration,
    };
    if m.plate {
        let mut q = vec![0.0; n];
        let mut centre = Vec3::zeros();
        for r in 0..measurement.records() {
            measurement.record_poses(machine, r, &mut q);
            centre += nominal_vector(machine, &q, &setup);
        }
        measurement.plate_centre = Some(centre / measurement.records() as f64);
    }
    Ok(measurement)
}

/// The sensor-frame calibration of a ball3d measurement: a cube data file (relative to the campaign
/// file) or a given matrix and offset.
fn calibration(c: &CalibrationFile, dir: &Path) -> Result<SensorCalibration, String> {
    match (&c.cube, &c.matrix) {
        (Some(cube), None) if c.offset_um.is_none() => SensorCalibration::from_cube_file(&dir.join(cube)).map_err(|e| e.to_string()),
        (None, Some(rows)) => {
            let a = Matrix3::from_fn(|r, col| rows[r][col]);
            let d = Vec3::from(c.offset_um.unwrap_or([0.0; 3]));
            SensorCalibration::from_matrix(a, d).map_err(|e| e.to_string())
        }
        _ => Err(
            "give either `cube` (a data file with tx,ty,tz,sx,sy,sz in um) or `matrix` (rows of [e1 e2 e3]) with an optional `offset_um`"
                .into(),
        ),
    }
}
