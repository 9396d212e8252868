//! The volumetric part of a calibration report: the exact volumetric error over the mid-planes of
//! the work volume, at each of a set of rotary states spanning the rotary axes' travel
//! ([`rotary_states`](super::maps::rotary_states)), before compensation, and after: the machine
//! driven to the corrected set-points, corrected pose by pose on the exact chain or by the
//! compensation tables.

use super::super::html::Section;
use super::compensation::controller_name;
use super::compensation::CompensationPart;
use super::maps::{magnitudes_um, statistics, VolumeMap};
use super::quantity::{pose, quantity};
use super::CalibrationError;
use rayon::prelude::*;
use trueaxis::compensate::export::residual::{leaves_more_than_it_removes, Applied};
use trueaxis::compensate::{CorrectionWorkspace, Corrector};
use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::{rotation_log, Mat3, Pose, Vec3};
use trueaxis::machine::{Component, Machine, SetupSide};
use trueaxis::model::{actual_chain, nominal_chain, Frame, Predictor, Setup, VolumetricError};

/// The map before and after compensation.
pub struct VolumePart {
    pub map: VolumeMap,
    pub before: Vec<VolumetricError>,
    /// After compensation with the corrections of the compensating error model solved at each pose
    /// on the exact chain (what the real-time corrector and model-based controllers apply).
    pub after: Vec<VolumetricError>,
    /// `(largest, RMS)` of `|d|` (um) before compensation, after it, and after compensation with the
    /// sum of the own-axis and cross-axis tables instead (what table-based controllers apply).
    pub before_um: (f64, f64),
    pub after_um: (f64, f64),
    pub after_tables_um: (f64, f64),
    /// The controller format whose corrections the "after" map shows (`None`: the exact correction
    /// at each pose, as a model-based controller or the real-time corrector applies it).
    pub controller: Option<String>,
    /// The pose of the largest error before compensation (axis letter, mm or deg).
    pub max_pose: Vec<(char, f64)>,
    pub before_svg: String,
    pub after_svg: String,
    pub poses: usize,
    /// Paragraphs on what the two error models are.
    pub description: Vec<String>,
}

impl VolumePart {
    /// The machine with the errors `machine_errors`, before compensation and driven to the
    /// set-points corrected for `compensation_errors` (the same model, or an identified one): by the
    /// exact correction at each pose (Soons 1993 §2.3.5) and by the tables of `tables`. `None` for a
    /// machine without two linear axes with a travel. The set-up errors of the measurement (where
    /// the master ball or the probe sat) are left out of both models, as `trueaxis compensate`
    /// leaves them out of its tables and of the error it judges: they are not errors of the machine.
    pub fn compute(
        machine: &Machine,
        machine_errors: &ErrorModel,
        compensation_errors: &ErrorModel,
        tables: &CompensationPart,
        controller: Option<(&str, &dyn Applied)>,
    ) -> Result<Option<VolumePart>, CalibrationError> {
        let Some(map) = VolumeMap::over_rotary_states(machine) else { return Ok(None) };
        let (machine_errors, compensation_errors) = (&machine_errors.without_setup(), &compensation_errors.without_setup());
        let mut predictor = Predictor::new(machine, machine_errors);
        predictor.frame = Frame::Machine;
        let before = predictor.predict_batch(&map.poses_internal);
        let n = machine.axis_count();
        let setup = Setup::of_machine(machine);
        let at_setpoints = |q: &[f64], qc: &[f64]| {
            let mut params = vec![0.0; machine.parameter_count()];
            machine_errors.values_at(machine, qc, &mut params);
            error_at_setpoints(machine, q, qc, &params, &setup)
        };
        let corrector = Corrector::new(machine, compensation_errors);
        let after = match controller {
            // what the controller applies with the chosen format's files, at rest
            Some((_, applied)) => map
                .poses_user
                .par_chunks(n)
                .zip(map.poses_internal.par_chunks(n))
                .map(|(user, q)| {
                    let mut dq = vec![0.0; n];
                    applied.applied(user, &vec![None; n], &mut dq);
                    let qc: Vec<f64> =
                        machine.axes().iter().zip(user.iter().zip(&dq)).map(|(a, (u, d))| a.position_to_internal(u + d)).collect();
                    at_setpoints(q, &qc)
                })
                .collect(),
            None => map
                .poses_internal
                .par_chunks(n)
                .map_init(
                    || CorrectionWorkspace::new(machine),
                    |ws, q| {
                        let c = corrector.correct(q, ws);
                        let qc: Vec<f64> = q.iter().zip(&c.dq).map(|(a, b)| a + b).collect();
                        c.converged.then(|| at_setpoints(q, &qc))
                    },
                )
                .collect::<Option<Vec<VolumetricError>>>()
                .ok_or_else(|| CalibrationError::Computation("the correction did not converge at a pose of the volumetric map".into()))?,
        };
        let after_tables: Vec<VolumetricError> = map
            .poses_user
            .par_chunks(n)
            .zip(map.poses_internal.par_chunks(n))
            .map(|(user, q)| {
                let dq = tables.table_correction(user);
                let qc: Vec<f64> =
                    machine.axes().iter().zip(user.iter().zip(&dq)).map(|(a, (u, d))| a.position_to_internal(u + d)).collect();
                at_setpoints(q, &qc)
            })
            .collect();
        let (mb, ma, mt) = (magnitudes_um(&before), magnitudes_um(&after), magnitudes_um(&after_tables));
        if mb.iter().chain(&ma).chain(&mt).any(|v| !v.is_finite()) {
            return Err(CalibrationError::Computation("the volumetric error map is not finite".into()));
        }
        let (max_b, imax, rms_b) = statistics(&mb);
        let (max_a, _, rms_a) = statistics(&ma);
        let (max_t, _, rms_t) = statistics(&mt);
        let max_pose = machine.axes().iter().map(|a| a.letter).zip(map.poses_user[imax * n..(imax + 1) * n].iter().copied()).collect();
        // one colour scale for both maps, so that what compensation removes shows as darker colours
        let range = Some((0.0, max_b.max(max_a)));
        let before_svg = map.heatmap("Volumetric error |d| before compensation", &mb, range)?;
        let after_title = match controller {
            Some((name, _)) => format!("|d| after compensation with the {} tables", controller_name(name)),
            None => "|d| after compensation (exact correction at each pose)".to_string(),
        };
        let after_svg = map.heatmap(&after_title, &ma, range)?;
        let poses = map.len(machine);
        Ok(Some(VolumePart {
            map,
            before,
            after,
            before_um: (max_b, rms_b),
            after_um: (max_a, rms_a),
            after_tables_um: (max_t, rms_t),
            controller: controller.map(|(name, _)| name.to_string()),
            max_pose,
            before_svg,
            after_svg,
            poses,
            description: Vec::new(),
        }))
    }

    /// Warnings for each compensation of the map that leaves more error than it removes (the
    /// rule of `trueaxis compensate`, which refuses to write such files).
    pub fn worse_than_before(&self) -> Vec<String> {
        let um = |v: f64| quantity(v, 2, "um");
        let before = self.before_um.0;
        let mut warnings = Vec::new();
        let mut warn = |what: String, left: f64, why: &str| {
            if leaves_more_than_it_removes(before, left) {
                warnings.push(format!(
                    "{what} leaves a largest error of {} against {} without compensation: more than it removes. {why}",
                    um(left),
                    um(before)
                ));
            }
        };
        let why_tables = "Axis-indexed tables cannot follow the errors of the rotary axes' locations as those axes turn; do not load them into this machine: correct its kinematic description instead (trueaxis compensate with --format heidenhain, siemens, fanuc or linuxcnc; docs/compensation.md, five-axis machines).";
        match &self.controller {
            Some(name) => warn(
                format!("Compensation with the {} files", controller_name(name)),
                self.after_um.0,
                "trueaxis compensate refuses to write them and names the better option.",
            ),
            None => warn(
                "The exact correction at each pose".into(),
                self.after_um.0,
                "The identified errors do not describe this machine: check the identification.",
            ),
        }
        warn("Compensation with the own-axis and cross-axis tables summed".into(), self.after_tables_um.0, why_tables);
        warnings
    }

    pub fn section(&self) -> Section {
        let at = pose(&self.max_pose);
        let um = |v: f64| quantity(v, 2, "um");
        let after_how = match &self.controller {
            Some(name) => format!(
                "with the corrections the {} tables apply (their interpolation and the terms the format can carry), on the exact chain",
                controller_name(name)
            ),
            None => "with the correction of every pose solved on the exact chain, as a controller that evaluates the error model or the real-time corrector applies it".to_string(),
        };
        let states = self.map.states_text();
        let where_ = if states.is_empty() {
            format!("{} poses, machine frame", self.poses)
        } else {
            format!(
                "at each rotary state {states}: {} poses, machine frame; each map shows at every node the largest |d| over the rotary states",
                self.poses
            )
        };
        let mut s = Section::new("volumetric", "Volumetric error before and after compensation")
            .paragraph(format!(
                "Exact volumetric error |d| of the tool point relative to the workpiece origin over the mid-planes of the linear-axis travel ({where_}). Before compensation: largest {} (at {}), RMS {}. After compensation, {}: largest {}, RMS {}.",
                um(self.before_um.0),
                at,
                um(self.before_um.1),
                after_how,
                um(self.after_um.0),
                um(self.after_um.1),
            ))
            .table(
                "Volumetric error |d| over the map",
                &["", "largest", "RMS"],
                vec![
                    vec!["before compensation".into(), um(self.before_um.0), um(self.before_um.1)],
                    vec![
                        match &self.controller {
                            Some(name) => format!("after, {} tables", controller_name(name)),
                            None => "after, exact correction".into(),
                        },
                        um(self.after_um.0),
                        um(self.after_um.1),
                    ],
                    vec!["after, own-axis and cross-axis tables summed".into(), um(self.after_tables_um.0), um(self.after_tables_um.1)],
                ],
            );
        for w in self.worse_than_before() {
            s = s.note(w);
        }
        for p in &self.description {
            s = s.paragraph(p.clone());
        }
        s.figure("Before compensation.", self.before_svg.clone())
            .figure("After compensation, on the same colour scale: what is left shows as dark colours.", self.after_svg.clone())
    }
}

/// Volumetric error of the machine when the controller commands `qc` for the nominal pose `q` (mm,
/// rad): the tool point relative to the workpiece point on the actual chain at `qc` (parameters
/// `params` evaluated there) minus the same on the nominal chain at `q`, machine frame (docs/design.md
/// section 2; with `qc = q` it is `model::volumetric_error`).
pub fn error_at_setpoints(machine: &Machine, q: &[f64], qc: &[f64], params: &[f64], setup: &Setup) -> VolumetricError {
    let offset = |side| {
        let i = machine.setup_index(side, Component::X);
        Vec3::new(params[i], params[i + 1], params[i + 2])
    };
    // vector from the workpiece point to the tool point and the tool rotation, in the workpiece frame
    let relative = |tool: &Pose, work: &Pose, tool_point: Vec3, work_point: Vec3| -> (Vec3, Mat3) {
        let rt = work.rotation.transpose();
        (rt * (tool.transform_point(&tool_point) - work.transform_point(&work_point)), rt * tool.rotation)
    };
    let work_nominal = nominal_chain(machine, machine.work_chain(), q, None);
    let (r_nominal, rot_nominal) =
        relative(&nominal_chain(machine, machine.tool_chain(), q, None), &work_nominal, setup.tool_point, setup.work_point);
    let (r_actual, rot_actual) = relative(
        &actual_chain(machine, machine.tool_chain(), qc, params),
        &actual_chain(machine, machine.work_chain(), qc, params),
        setup.tool_point + offset(SetupSide::Tool),
        setup.work_point + offset(SetupSide::Workpiece),
    );
    let position = r_actual - r_nominal;
    let norms = r_actual.norm() + r_nominal.norm();
    let length = if norms > 0.0 { position.dot(&(r_actual + r_nominal)) / norms } else { 0.0 };
    let r = work_nominal.rotation;
    VolumetricError { position: r * position, orientation: r * rotation_log(&(rot_actual * rot_nominal.transpose())), length }
}

#[cfg(test)]
mod tests {
    use super::*;
    use trueaxis::model::volumetric_error;

    fn kx8five() -> (Machine, ErrorModel) {
        let machine = Machine::from_toml_str(include_str!("../../../../examples/machines/kx8five.toml"), "kx8five").unwrap();
        let errors =
            ErrorModel::from_toml_str(include_str!("../../../../examples/errors/kx8five.toml"), "kx8five errors", &machine).unwrap();
        (machine, errors)
    }

    #[test]
    fn at_the_nominal_set_points_it_is_the_volumetric_error() {
        let (machine, errors) = kx8five();
        let setup = Setup::of_machine(&machine);
        let mut params = vec![0.0; machine.parameter_count()];
        for user in [[100.0, -50.0, -200.0, 30.0, 45.0], [-300.0, 340.0, -10.0, 170.0, -120.0]] {
            let mut q = vec![0.0; 5];
            machine.pose_to_internal(&user, &mut q);
            errors.values_at(&machine, &q, &mut params);
            let a = error_at_setpoints(&machine, &q, &q, &params, &setup);
            let b = volumetric_error(&machine, &q, &params, &setup, Frame::Machine);
            assert!((a.position - b.position).norm() < 1e-12 && (a.orientation - b.orientation).norm() < 1e-15, "{a:?} vs {b:?}");
            assert!((a.length - b.length).abs() < 1e-12);
        }
    }

    #[test]
    fn at_the_corrected_set_points_the_position_error_is_the_correction_residual() {
        // a second formulation: the corrector's own residual at q + dq (Soons 1993 §2.3.5)
        let (machine, errors) = kx8five();
        let corrector = Corrector::new(&machine, &errors);
        let mut ws = CorrectionWorkspace::new(&machine);
        let setup = Setup::of_machine(&machine);
        let mut params = vec![0.0; machine.parameter_count()];
        let mut q = vec![0.0; 5];
        machine.pose_to_internal(&[120.0, 80.0, -150.0, 60.0, 200.0], &mut q);
        let c = corrector.correct(&q, &mut ws);
        assert!(c.converged);
        let qc: Vec<f64> = q.iter().zip(&c.dq).map(|(a, b)| a + b).collect();
        errors.values_at(&machine, &qc, &mut params);
        let after = error_at_setpoints(&machine, &q, &qc, &params, &setup);
        let before = volumetric_error(
            &machine,
            &q,
            &{
                let mut p = vec![0.0; machine.parameter_count()];
                errors.values_at(&machine, &q, &mut p);
                p
            },
            &setup,
            Frame::Machine,
        );
        assert!(before.position.norm() > 10e-3, "a visible error to correct: {} mm", before.position.norm());
        assert!(after.position.norm() < 1e-5, "residual {} mm after the exact correction", after.position.norm());
        assert!((after.position.norm() - c.residual_position.norm()).abs() < 1e-9);
    }
}
