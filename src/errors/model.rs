//! Error values bound to a machine: which function gives each parameter, and their evaluation at a
//! pose into the parameter vector of [`crate::machine::Machine`] (internal units mm, rad).

use super::function::ErrorFunction;
use crate::machine::{AxisKind, Machine, ParameterId};

/// The error state of one machine: a function (or nothing, meaning zero) per parameter.
#[derive(Clone, Debug)]
pub struct ErrorModel {
    /// `(parameter index, id, function)` for every non-zero parameter.
    entries: Vec<(usize, ParameterId, ErrorFunction)>,
    /// For each entry, the axis whose position a motion error depends on.
    own_axis: Vec<Option<usize>>,
    parameter_count: usize,
}

impl ErrorModel {
    /// All errors zero.
    pub fn zero(machine: &Machine) -> ErrorModel {
        ErrorModel { entries: Vec::new(), own_axis: Vec::new(), parameter_count: machine.parameter_count() }
    }

    /// Sets the function of one parameter. Functions of position are only allowed for motion errors;
    /// a table over a rotary axis that spans exactly 360 deg is made periodic.
    pub fn set(&mut self, machine: &Machine, id: ParameterId, function: ErrorFunction) -> Result<(), String> {
        let index = machine.parameter_index(&id)?;
        let function = match (id, function) {
            (ParameterId::Motion { axis, .. }, ErrorFunction::Table { positions, values, .. }) => {
                let rotary = machine.axes()[machine.axis_index(axis).expect("checked")].kind == AxisKind::Rotary;
                let span = positions[positions.len() - 1] - positions[0];
                let period = (rotary && (span - 360.0).abs() < 1e-9).then_some(360.0);
                ErrorFunction::Table { positions, values, period }
            }
            (ParameterId::Motion { .. }, f) | (_, f @ ErrorFunction::Constant(_)) => f,
            (id, _) => {
                return Err(format!("{id} is a constant (location or setup error); give it under [constant], not as a table or polynomial"))
            }
        };
        if self.entries.iter().any(|(i, ..)| *i == index) {
            return Err(format!("{id} is given more than once"));
        }
        self.entries.push((index, id, function));
        self.entries.sort_by_key(|(i, ..)| *i);
        self.own_axis = self
            .entries
            .iter()
            .map(|(_, id, _)| id.axis().filter(|_| matches!(id, ParameterId::Motion { .. })).and_then(|a| machine.axis_index(a)))
            .collect();
        Ok(())
    }

    /// Builds a model from a parameter vector in internal units (mm, rad), all constants.
    pub fn from_parameter_vector(machine: &Machine, values: &[f64]) -> ErrorModel {
        let mut model = ErrorModel::zero(machine);
        for (index, &v) in values.iter().enumerate() {
            if v != 0.0 {
                let id = machine.parameter_id(index);
                model.set(machine, id, ErrorFunction::Constant(v / id.component().to_internal())).expect("index from this machine");
            }
        }
        model
    }

    /// The parameters that have a function, with it.
    pub fn entries(&self) -> impl Iterator<Item = (&ParameterId, &ErrorFunction)> {
        self.entries.iter().map(|(_, id, f)| (id, f))
    }

    /// Evaluates every parameter at the pose `q` (internal units, canonical axis order) into
    /// `values` (mm for translations, rad for rotations). Motion errors are evaluated at their own
    /// axis position in user units (mm, deg).
    pub fn values_at(&self, machine: &Machine, q: &[f64], values: &mut [f64]) {
        debug_assert_eq!(values.len(), self.parameter_count);
        values.iter_mut().for_each(|v| *v = 0.0);
        for ((index, id, function), own_axis) in self.entries.iter().zip(&self.own_axis) {
            let position = own_axis.map_or(0.0, |axis| machine.axes()[axis].position_to_user(q[axis]));
            values[*index] = function.evaluate(position) * id.component().to_internal();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MACHINE: &str = r#"
name = "xc"
structure = "wCbXt"
[axes]
X = { kind = "linear", direction = [1, 0, 0], range = [-100, 100] }
C = { kind = "rotary", direction = [0, 0, 1], point = [0, 0, 0] }
[tool]
point = [0, 0, 0]
"#;

    #[test]
    fn parameter_vector_round_trips_through_constants() {
        let m = Machine::from_toml_str(MACHINE, "xc").unwrap();
        let values: Vec<f64> = (0..m.parameter_count()).map(|i| if i % 3 == 0 { 1e-3 * i as f64 } else { 0.0 }).collect();
        let model = ErrorModel::from_parameter_vector(&m, &values);
        let mut back = vec![0.0; m.parameter_count()];
        model.values_at(&m, &[50.0, 1.0], &mut back);
        for (a, b) in values.iter().zip(&back) {
            assert!((a - b).abs() < 1e-15);
        }
        assert_eq!(model.entries().count(), values.iter().filter(|v| **v != 0.0).count());
    }

    #[test]
    fn motion_errors_are_evaluated_at_their_own_axis_in_user_units() {
        let m = Machine::from_toml_str(MACHINE, "xc").unwrap();
        let mut model = ErrorModel::zero(&m);
        let exx = ParameterId::parse("EXX").unwrap();
        let ecc = ParameterId::parse("ECC").unwrap();
        model.set(&m, exx, ErrorFunction::polynomial(vec![0.0, 0.1]).unwrap()).unwrap(); // 0.1 um per mm
        model.set(&m, ecc, ErrorFunction::table(vec![0.0, 180.0, 360.0], vec![0.0, 18.0, 0.0], None).unwrap()).unwrap();
        let mut v = vec![0.0; m.parameter_count()];
        // X = 50 mm, C = 450 deg (a full turn plus 90 deg): the 360-deg table is periodic
        model.values_at(&m, &[50.0, 450f64.to_radians()], &mut v);
        assert!((v[m.parameter_index(&exx).unwrap()] - 5e-3).abs() < 1e-15, "5 um in mm");
        assert!((v[m.parameter_index(&ecc).unwrap()] - 9e-6).abs() < 1e-12, "9 urad in rad");
        assert!(model.set(&m, exx, ErrorFunction::Constant(1.0)).unwrap_err().contains("more than once"));
    }
}
