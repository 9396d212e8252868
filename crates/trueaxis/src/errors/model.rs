//! Error values bound to a machine: which function gives each parameter, and their evaluation at a
//! machine state (axis positions, directions of motion, temperatures) into the parameter vector of
//! [`crate::machine::Machine`] (internal units mm, rad).

use super::evaluator::{Evaluator, TableEvaluator};
use super::function::ErrorFunction;
use crate::machine::{AxisKind, Machine, ParameterId};

/// ISO 1 reference temperature (degC): temperature terms use `T - 20`.
pub const REFERENCE_TEMPERATURE: f64 = 20.0;

/// Direction of motion of an axis, for bidirectional (backlash, hysteresis) models
/// (seed 000 §3.2.5: separate models for positive and negative motion).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    Positive,
    Negative,
}

impl Direction {
    /// `+` or `-`.
    pub fn symbol(self) -> char {
        match self {
            Direction::Positive => '+',
            Direction::Negative => '-',
        }
    }
}

#[derive(Clone, Debug)]
struct Entry {
    index: usize,
    id: ParameterId,
    /// `None` for both directions, or the direction this function holds for.
    direction: Option<Direction>,
    function: ErrorFunction,
    /// `function` prepared for evaluation in internal units.
    evaluator: Evaluator,
    /// The axis whose position a motion error depends on.
    own_axis: Option<usize>,
}

/// A product term `coefficient * prod (axis position)^p * prod (T_s - 20 degC)^p` added to a
/// parameter: cross-coupling (seed 000 eq. 3.19, e.g. `e = b x y`) and position-temperature
/// products (seed 003 §3.6, e.g. scale expansion `alpha (T - 20) x`). Positions in mm or deg,
/// the value in um or urad.
#[derive(Clone, Debug, PartialEq)]
pub struct ProductTerm {
    pub id: ParameterId,
    pub coefficient: f64,
    /// `(axis index, power)`.
    pub axes: Vec<(usize, i32)>,
    /// `(sensor index into [`ErrorModel::sensors`], power)`.
    pub sensors: Vec<(usize, i32)>,
    index: usize,
}

/// The state of the machine an error model is evaluated at.
#[derive(Clone, Copy, Debug, Default)]
pub struct MachineState<'a> {
    /// Direction of motion per axis (canonical order), or `None` (at rest / unknown: the mean of the
    /// two directions is used).
    pub directions: Option<&'a [Option<Direction>]>,
    /// Temperatures (degC) of the sensors of [`ErrorModel::sensors`], in that order; empty means the
    /// reference temperature (20 degC) everywhere.
    pub temperatures: &'a [f64],
}

/// The error state of one machine: a function (or nothing, meaning zero) per parameter, plus
/// product terms.
#[derive(Clone, Debug)]
pub struct ErrorModel {
    entries: Vec<Entry>,
    terms: Vec<ProductTerm>,
    sensors: Vec<String>,
    parameter_count: usize,
    /// Evaluation plan, derived from `entries`: every constant for both directions summed into one
    /// parameter vector (internal units); the tables for both directions as `(parameter index, own
    /// axis, table)`; the indices of the other entries.
    constants: Vec<f64>,
    tables: Vec<(usize, usize, TableEvaluator)>,
    varying: Vec<usize>,
}

impl ErrorModel {
    /// All errors zero.
    pub fn zero(machine: &Machine) -> ErrorModel {
        let parameter_count = machine.parameter_count();
        ErrorModel {
            entries: Vec::new(),
            terms: Vec::new(),
            sensors: Vec::new(),
            parameter_count,
            constants: vec![0.0; parameter_count],
            tables: Vec::new(),
            varying: Vec::new(),
        }
    }

    /// Rebuilds the evaluation plan after a change of `entries`.
    fn plan(&mut self) {
        self.constants.fill(0.0);
        self.tables.clear();
        self.varying.clear();
        for (k, e) in self.entries.iter().enumerate() {
            match (&e.evaluator, e.direction, e.own_axis) {
                (Evaluator::Constant(v), None, _) => self.constants[e.index] += v,
                (Evaluator::Table(t), None, Some(axis)) => self.tables.push((e.index, axis, t.clone())),
                _ => self.varying.push(k),
            }
        }
    }

    /// Sets the function of one parameter for both directions. See [`ErrorModel::set_directional`].
    pub fn set(&mut self, machine: &Machine, id: ParameterId, function: ErrorFunction) -> Result<(), String> {
        self.set_directional(machine, id, None, function)
    }

    /// Sets the function of one parameter, for one direction of motion of its axis or for both.
    /// Functions of position and directions are only allowed for motion errors; a table over a
    /// rotary axis that spans exactly 360 deg is made periodic.
    pub fn set_directional(
        &mut self,
        machine: &Machine,
        id: ParameterId,
        direction: Option<Direction>,
        function: ErrorFunction,
    ) -> Result<(), String> {
        let index = machine.parameter_index(&id)?;
        let motion = matches!(id, ParameterId::Motion { .. });
        if direction.is_some() && !motion {
            return Err(format!("{id} is a constant (location or setup error); it has no direction of motion"));
        }
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
        for e in self.entries.iter().filter(|e| e.index == index) {
            if e.direction == direction {
                return Err(format!("{id}{} is given more than once", direction.map_or(String::new(), |d| d.symbol().to_string())));
            }
            if e.direction.is_none() || direction.is_none() {
                return Err(format!("{id} is given both for both directions and for one direction ({id}+ / {id}-)"));
            }
        }
        let own_axis = if motion { id.axis().and_then(|a| machine.axis_index(a)) } else { None };
        let position_scale = own_axis.map_or(1.0, |a| machine.axes()[a].position_to_user(1.0));
        let evaluator = Evaluator::new(&function, position_scale, id.component().to_internal());
        self.entries.push(Entry { index, id, direction, function, evaluator, own_axis });
        self.entries.sort_by_key(|e| (e.index, e.direction.map(|d| d.symbol())));
        self.plan();
        Ok(())
    }

    /// Adds a product term to parameter `id`: `coefficient` (um or urad per unit of the factors)
    /// times the axis positions (mm, deg) and sensor temperature deviations `T - 20` (K) raised to
    /// their powers.
    pub fn add_term(
        &mut self,
        machine: &Machine,
        id: ParameterId,
        coefficient: f64,
        axes: &[(char, i32)],
        sensors: &[(&str, i32)],
    ) -> Result<(), String> {
        let index = machine.parameter_index(&id)?;
        if !coefficient.is_finite() {
            return Err("`coefficient` must be a finite number".into());
        }
        let mut axis_powers = Vec::new();
        for (letter, power) in axes {
            let a = machine.axis_index(*letter).ok_or_else(|| {
                format!("factor {letter}: machine `{}` has no axis {letter} (axes: {})", machine.name, machine.axis_letters())
            })?;
            axis_powers.push((a, *power));
        }
        let mut sensor_powers = Vec::new();
        for (name, power) in sensors {
            let s = match self.sensors.iter().position(|n| n == name) {
                Some(s) => s,
                None => {
                    self.sensors.push(name.to_string());
                    self.sensors.len() - 1
                }
            };
            sensor_powers.push((s, *power));
        }
        if axis_powers.iter().chain(&sensor_powers).any(|(_, p)| *p < 0 || *p > 8) {
            return Err("factor powers must be integers from 0 to 8".into());
        }
        self.terms.push(ProductTerm { id, coefficient, axes: axis_powers, sensors: sensor_powers, index });
        Ok(())
    }

    /// Checks that every one-direction function has its counterpart.
    pub fn check_directions(&self) -> Result<(), String> {
        for e in &self.entries {
            if let Some(d) = e.direction {
                let other = if d == Direction::Positive { Direction::Negative } else { Direction::Positive };
                if !self.entries.iter().any(|f| f.index == e.index && f.direction == Some(other)) {
                    return Err(format!("{}{} is given without {}{}", e.id, d.symbol(), e.id, other.symbol()));
                }
            }
        }
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

    /// The parameters that have a function for both directions, with it.
    pub fn entries(&self) -> impl Iterator<Item = (&ParameterId, &ErrorFunction)> {
        self.entries.iter().filter(|e| e.direction.is_none()).map(|e| (&e.id, &e.function))
    }

    /// Every function with its direction (`None` = both).
    pub fn directional_entries(&self) -> impl Iterator<Item = (&ParameterId, Option<Direction>, &ErrorFunction)> {
        self.entries.iter().map(|e| (&e.id, e.direction, &e.function))
    }

    /// The product terms.
    pub fn terms(&self) -> &[ProductTerm] {
        &self.terms
    }

    /// Names of the temperature sensors the model needs (e.g. `T:spindle`), in the order
    /// [`MachineState::temperatures`] expects.
    pub fn sensors(&self) -> &[String] {
        &self.sensors
    }

    /// Evaluates every parameter at pose `q` (internal units, canonical axis order), at rest (mean
    /// of the two directions) and at the reference temperature, into `values` (mm, rad).
    pub fn values_at(&self, machine: &Machine, q: &[f64], values: &mut [f64]) {
        self.values_at_state(machine, q, &MachineState::default(), values)
    }

    /// Evaluates every parameter at pose `q` (internal units) and `state` into `values` (mm, rad).
    /// Motion errors are evaluated at their own axis position in user units (mm, deg); a
    /// bidirectional function uses the function of the axis's direction of motion, or the mean of the
    /// two when the direction is unknown.
    pub fn values_at_state(&self, machine: &Machine, q: &[f64], state: &MachineState, values: &mut [f64]) {
        debug_assert_eq!(values.len(), self.parameter_count);
        values.copy_from_slice(&self.constants);
        for (index, axis, table) in &self.tables {
            values[*index] += table.value(q[*axis]);
        }
        let user = |axis: usize| machine.axes()[axis].position_to_user(q[axis]);
        for e in self.varying.iter().map(|&k| &self.entries[k]) {
            let weight = match (e.direction, e.own_axis.and_then(|a| state.directions.and_then(|d| d[a]))) {
                (None, _) => 1.0,
                (Some(d), Some(actual)) => f64::from(d == actual),
                (Some(_), None) => 0.5,
            };
            if weight != 0.0 {
                values[e.index] += weight * e.evaluator.value(&e.function, e.own_axis.map_or(0.0, |a| q[a]));
            }
        }
        for t in &self.terms {
            let mut v = t.coefficient;
            for (axis, power) in &t.axes {
                v *= user(*axis).powi(*power);
            }
            for (sensor, power) in &t.sensors {
                let temperature = state.temperatures.get(*sensor).copied().unwrap_or(REFERENCE_TEMPERATURE);
                v *= (temperature - REFERENCE_TEMPERATURE).powi(*power);
            }
            values[t.index] += v * t.id.component().to_internal();
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

    #[test]
    fn bidirectional_functions_follow_the_direction_of_motion() {
        // backlash: EXX+ = +0.4 um, EXX- = -0.4 um; the mean (direction unknown) is zero
        let m = Machine::from_toml_str(MACHINE, "xc").unwrap();
        let mut model = ErrorModel::zero(&m);
        let exx = ParameterId::parse("EXX").unwrap();
        model.set_directional(&m, exx, Some(Direction::Positive), ErrorFunction::Constant(0.4)).unwrap();
        assert!(model.check_directions().unwrap_err().contains("EXX+ is given without EXX-"));
        model.set_directional(&m, exx, Some(Direction::Negative), ErrorFunction::Constant(-0.4)).unwrap();
        model.check_directions().unwrap();
        assert!(model.set(&m, exx, ErrorFunction::Constant(1.0)).unwrap_err().contains("both directions"));
        let i = m.parameter_index(&exx).unwrap();
        let mut v = vec![0.0; m.parameter_count()];
        for (dir, want) in [(Some(Direction::Positive), 0.4e-3), (Some(Direction::Negative), -0.4e-3), (None, 0.0)] {
            let directions = [dir, None];
            model.values_at_state(&m, &[10.0, 0.0], &MachineState { directions: Some(&directions), temperatures: &[] }, &mut v);
            assert!((v[i] - want).abs() < 1e-15, "{dir:?}");
        }
    }

    #[test]
    fn product_terms_couple_positions_and_temperatures() {
        // scale expansion 11.5 um/m/K: EXX += 0.0115 um/(mm K) * x * (T - 20); coupling EYX += 2e-4 x
        let m = Machine::from_toml_str(MACHINE, "xc").unwrap();
        let mut model = ErrorModel::zero(&m);
        let exx = ParameterId::parse("EXX").unwrap();
        let eyx = ParameterId::parse("EYX").unwrap();
        model.add_term(&m, exx, 0.0115, &[('X', 1)], &[("T:scale", 1)]).unwrap();
        model.add_term(&m, eyx, 2e-4, &[('X', 1)], &[]).unwrap();
        assert_eq!(model.sensors(), &["T:scale".to_string()]);
        let mut v = vec![0.0; m.parameter_count()];
        model.values_at_state(&m, &[100.0, 0.0], &MachineState { directions: None, temperatures: &[25.0] }, &mut v);
        // 0.0115 * 100 mm * 5 K = 5.75 um
        assert!((v[m.parameter_index(&exx).unwrap()] - 5.75e-3).abs() < 1e-15);
        assert!((v[m.parameter_index(&eyx).unwrap()] - 0.02e-3).abs() < 1e-15);
        // at the reference temperature the thermal term vanishes
        model.values_at(&m, &[100.0, 0.0], &mut v);
        assert_eq!(v[m.parameter_index(&exx).unwrap()], 0.0);
        assert!(model.add_term(&m, exx, 1.0, &[('Q', 1)], &[]).unwrap_err().contains("no axis Q"));
    }
}
