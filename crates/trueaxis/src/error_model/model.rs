//! Error values bound to a machine: which function gives each parameter, and their evaluation at a
//! machine state (axis positions, directions of motion, temperatures) into the parameter vector of
//! [`crate::machine::Machine`] (internal units mm, rad).

use super::evaluator::{Evaluator, PositionFunction};
use super::function::ErrorFunction;
use super::inputs::InputKind;
use crate::error::{Error, Result};
use crate::machine::{AxisKind, Machine, ParameterId};

/// ISO 1 reference temperature (degC): temperature terms use `T - 20`.
pub const REFERENCE_TEMPERATURE: f64 = 20.0;

/// Direction of motion of an axis, for bidirectional (backlash, hysteresis) models
/// (Soons 1993 §3.2.5: separate models for positive and negative motion).
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

/// A product term `coefficient * prod (axis position)^p * prod (input - reference)^p` added to a
/// parameter: cross-coupling (Soons 1993 eq. 3.19, e.g. `e = b x y`), position-temperature products
/// (NISTIR 5236 §3.6, e.g. scale expansion `alpha (T - 20) x`), spindle-speed and load terms (inputs
/// of [`super::inputs`]). Positions in mm or deg, the value in um or urad.
///
/// A term of the geometric-thermal model of NISTIR 5236 §3.6 may hold for one segment only: one
/// direction of motion of the parameter's own axis (`direction`, NISTIR 5236: "segment the data
/// depending on the direction of travel due to hysteresis") and a range `[lo, hi)` of its position
/// (`range`, "regions of axis position"). A directional term counts half when the direction is
/// unknown (the mean of the two directions, as for bidirectional functions).
#[derive(Clone, Debug, PartialEq)]
pub struct ProductTerm {
    pub id: ParameterId,
    pub coefficient: f64,
    /// `(axis index, power)`.
    pub axes: Vec<(usize, i32)>,
    /// `(input index into [`ErrorModel::sensors`], power)`.
    pub sensors: Vec<(usize, i32)>,
    /// The direction of motion of the own axis the term holds for (`None`: both).
    pub direction: Option<Direction>,
    /// The range `[lo, hi)` of the own axis position (mm or deg) the term holds in (`None`: all).
    pub range: Option<(f64, f64)>,
    index: usize,
    own_axis: Option<usize>,
}

/// A workpiece-load error (Soons 1993 §3.3.3, eq. 3.20): the change of a parameter under a load,
/// measured as a function of its own axis position at a reference load placed at a reference
/// position, scaled linearly with the load and with its lever arm:
/// `e(q, F, p) = f(q) (F / F_ref) (L - p) / L`. Without a lever, `e = f(q) F / F_ref`.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadTerm {
    pub id: ParameterId,
    /// `f`: the change (um or urad) under the reference load, of the own axis position (mm, deg);
    /// a constant for a location error.
    pub function: ErrorFunction,
    /// `F_ref` (N).
    pub reference_n: f64,
    /// Input index of the load F (N, an `F:` input).
    pub load: usize,
    /// `(L, input index of p)`: the lever arm L (mm) at the reference position and the load
    /// position p (mm, a `P:` input) that shortens it.
    pub lever: Option<(f64, usize)>,
    index: usize,
    own_axis: Option<usize>,
}

/// A thermal drift model of one parameter interpolated over an axis position (Soons 1993 §3.4.4:
/// "models are estimated at several characteristic positions of the machine axes. The drift at an
/// arbitrary axis position is obtained by linear interpolation between the modelled drift at the
/// tested positions"). At each tested position the drift is the state-space model of
/// [`crate::thermal::drift_model`]: `sum_ij g_ij z_ij`, `z_ij` the rise of sensor i since the start of
/// its run through the lag j (lag inputs of [`super::inputs`]).
#[derive(Clone, Debug, PartialEq)]
pub struct DriftTerm {
    pub id: ParameterId,
    /// The axis (index) whose position the drift is interpolated over.
    pub axis: usize,
    /// Tested positions (mm or deg), increasing, each with `(lag input index, gain um/degC)`.
    pub points: Vec<(f64, Vec<(usize, f64)>)>,
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
    /// Standard uncertainties (k = 1) of constant values, in the parameters' units (um, urad), as an
    /// identification states them (`[uncertainty]` of an error-values file).
    uncertainties: Vec<(ParameterId, f64)>,
    terms: Vec<ProductTerm>,
    loads: Vec<LoadTerm>,
    drifts: Vec<DriftTerm>,
    /// Input names (`T:<sensor>`, `S:..`, `F:..`, `P:..`, lags) and the value each term refers to.
    sensors: Vec<String>,
    references: Vec<f64>,
    parameter_count: usize,
    /// Evaluation plan, derived from `entries`: every constant for both directions summed into one
    /// parameter vector (internal units); the other functions for both directions (tables,
    /// polynomials, bases) as `(parameter index, own axis, function)`; the indices of the
    /// directional entries.
    constants: Vec<f64>,
    positional: Vec<(usize, usize, PositionFunction)>,
    varying: Vec<usize>,
}

impl ErrorModel {
    /// All errors zero.
    pub fn zero(machine: &Machine) -> ErrorModel {
        let parameter_count = machine.parameter_count();
        ErrorModel {
            entries: Vec::new(),
            uncertainties: Vec::new(),
            terms: Vec::new(),
            loads: Vec::new(),
            drifts: Vec::new(),
            sensors: Vec::new(),
            references: Vec::new(),
            parameter_count,
            constants: vec![0.0; parameter_count],
            positional: Vec::new(),
            varying: Vec::new(),
        }
    }

    /// Rebuilds the evaluation plan after a change of `entries`.
    fn plan(&mut self) {
        self.constants.fill(0.0);
        self.positional.clear();
        self.varying.clear();
        for (k, e) in self.entries.iter().enumerate() {
            match (&e.evaluator, e.direction, e.own_axis) {
                (Evaluator::Constant(v), None, _) => self.constants[e.index] += v,
                (evaluator, None, Some(axis)) => match PositionFunction::of(evaluator, &e.function) {
                    Some(f) => self.positional.push((e.index, axis, f)),
                    None => self.varying.push(k),
                },
                _ => self.varying.push(k),
            }
        }
    }

    /// Sets the function of one parameter for both directions. See [`ErrorModel::set_directional`].
    pub fn set(&mut self, machine: &Machine, id: ParameterId, function: ErrorFunction) -> Result<()> {
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
    ) -> Result<()> {
        let index = machine.parameter_index(&id)?;
        let motion = matches!(id, ParameterId::Motion { .. });
        if direction.is_some() && !motion {
            return Err(Error::input(format!("{id} is a constant (location or setup error); it has no direction of motion")));
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
                return Err(Error::input(format!(
                    "{id} is a constant (location or setup error); give it under [constant], not as a table or polynomial"
                )))
            }
        };
        for e in self.entries.iter().filter(|e| e.index == index) {
            if e.direction == direction {
                return Err(Error::input(format!(
                    "{id}{} is given more than once",
                    direction.map_or(String::new(), |d| d.symbol().to_string())
                )));
            }
            if e.direction.is_none() || direction.is_none() {
                return Err(Error::input(format!("{id} is given both for both directions and for one direction ({id}+ / {id}-)")));
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

    /// The index of input `name` (see [`super::inputs`]), registered on first use.
    fn input(&mut self, name: &str) -> Result<usize> {
        if let Some(i) = self.sensors.iter().position(|n| n == name) {
            return Ok(i);
        }
        let kind = InputKind::parse(name)?;
        self.sensors.push(name.to_string());
        self.references.push(kind.reference());
        Ok(self.sensors.len() - 1)
    }

    /// Adds a product term to parameter `id`: `coefficient` (um or urad per unit of the factors)
    /// times the axis positions (mm, deg) and the inputs' deviations from their references
    /// (`T - 20` in K, a spindle speed in rpm, a force in N, ...) raised to their powers.
    pub fn add_term(
        &mut self,
        machine: &Machine,
        id: ParameterId,
        coefficient: f64,
        axes: &[(char, i32)],
        sensors: &[(&str, i32)],
    ) -> Result<()> {
        self.add_segment_term(machine, id, None, None, coefficient, axes, sensors)
    }

    /// As [`ErrorModel::add_term`], for one segment of the own axis of a motion error: one direction
    /// of motion and / or a position range `[lo, hi)` (mm or deg; infinite ends allowed).
    #[allow(clippy::too_many_arguments)]
    pub fn add_segment_term(
        &mut self,
        machine: &Machine,
        id: ParameterId,
        direction: Option<Direction>,
        range: Option<(f64, f64)>,
        coefficient: f64,
        axes: &[(char, i32)],
        sensors: &[(&str, i32)],
    ) -> Result<()> {
        let index = machine.parameter_index(&id)?;
        if !coefficient.is_finite() {
            return Err(Error::input("`coefficient` must be a finite number"));
        }
        let own_axis = self.own_axis(machine, &id);
        if (direction.is_some() || range.is_some()) && own_axis.is_none() {
            return Err(Error::input(format!(
                "{id} is a constant (location or setup error): a term of one direction or position range needs a motion error"
            )));
        }
        if let Some((lo, hi)) = range {
            if lo.is_nan() || hi.is_nan() || lo >= hi {
                return Err(Error::input(format!("`range` [{lo}, {hi}] must be [lo, hi] with lo < hi (infinite ends allowed: -inf, inf)")));
            }
        }
        let mut axis_powers = Vec::new();
        for (letter, power) in axes {
            let a = machine.axis_index(*letter).ok_or_else(|| {
                Error::input(format!("factor {letter}: machine `{}` has no axis {letter} (axes: {})", machine.name, machine.axis_letters()))
            })?;
            axis_powers.push((a, *power));
        }
        let mut sensor_powers = Vec::new();
        for (name, power) in sensors {
            sensor_powers.push((self.input(name)?, *power));
        }
        if axis_powers.iter().chain(&sensor_powers).any(|(_, p)| *p < 0 || *p > 8) {
            return Err(Error::input("factor powers must be integers from 0 to 8"));
        }
        self.terms.push(ProductTerm { id, coefficient, axes: axis_powers, sensors: sensor_powers, direction, range, index, own_axis });
        Ok(())
    }

    /// The axis a motion error depends on (`None` for location and setup errors).
    fn own_axis(&self, machine: &Machine, id: &ParameterId) -> Option<usize> {
        matches!(id, ParameterId::Motion { .. }).then(|| id.axis().and_then(|a| machine.axis_index(a))).flatten()
    }

    /// Adds a workpiece-load error (see [`LoadTerm`]): `function` of the own axis position (a
    /// constant for a location error) under `reference_n` (N) of the load input `load` (`F:<name>`),
    /// with an optional lever `(L mm, position input P:<name>)`.
    pub fn add_load(
        &mut self,
        machine: &Machine,
        id: ParameterId,
        function: ErrorFunction,
        reference_n: f64,
        load: &str,
        lever: Option<(f64, &str)>,
    ) -> Result<()> {
        let index = machine.parameter_index(&id)?;
        let own_axis = self.own_axis(machine, &id);
        if own_axis.is_none() && !matches!(function, ErrorFunction::Constant(_)) {
            return Err(Error::input(format!(
                "{id} is a constant (location or setup error): give its change under the load as `constant`"
            )));
        }
        if !(reference_n.is_finite() && reference_n != 0.0) {
            return Err(Error::input("`reference_n` must be the (non-zero) load in N the change was measured under"));
        }
        if !matches!(InputKind::parse(load)?, InputKind::Force) {
            return Err(Error::input(format!("`load` = `{load}` must be a force input `F:<name>` (N)")));
        }
        let load = self.input(load)?;
        let lever = match lever {
            Some((l, p)) => {
                if !(l.is_finite() && l != 0.0) {
                    return Err(Error::input("`lever_mm` must be a non-zero length in mm"));
                }
                if !matches!(InputKind::parse(p)?, InputKind::Position) {
                    return Err(Error::input(format!("`lever_at` = `{p}` must be a position input `P:<name>` (mm)")));
                }
                Some((l, self.input(p)?))
            }
            None => None,
        };
        self.loads.push(LoadTerm { id, function, reference_n, load, lever, index, own_axis });
        Ok(())
    }

    /// Adds the drift model tested at `position` (mm or deg) of axis `axis` to the drift of `id`
    /// (see [`DriftTerm`]): sensors `T:<name>`, time constants (s) and `gains[i][j]` (um/degC).
    #[allow(clippy::too_many_arguments)]
    pub fn add_drift(
        &mut self,
        machine: &Machine,
        id: ParameterId,
        axis: char,
        position: f64,
        sensors: &[String],
        time_constants_s: &[f64],
        gains: &[Vec<f64>],
    ) -> Result<()> {
        let index = machine.parameter_index(&id)?;
        let axis = machine.axis_index(axis).ok_or_else(|| {
            Error::input(format!("`axis` {axis}: machine `{}` has no axis {axis} (axes: {})", machine.name, machine.axis_letters()))
        })?;
        if !position.is_finite() {
            return Err(Error::input("`position` must be a finite axis position"));
        }
        if time_constants_s.is_empty() || time_constants_s.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(Error::input("`time_constants_s` must be positive numbers of seconds"));
        }
        if sensors.is_empty()
            || gains.len() != sensors.len()
            || gains.iter().any(|g| g.len() != time_constants_s.len() || g.iter().any(|v| !v.is_finite()))
        {
            return Err(Error::input(format!(
                "`gains_um_per_degc` needs one row per sensor ({}) of one finite gain per time constant ({})",
                sensors.len(),
                time_constants_s.len()
            )));
        }
        let mut point = Vec::new();
        for (sensor, row) in sensors.iter().zip(gains) {
            if !matches!(InputKind::parse(sensor)?, InputKind::Temperature) {
                return Err(Error::input(format!("sensor `{sensor}` must be a temperature `T:<name>`")));
            }
            for (tau, g) in time_constants_s.iter().zip(row) {
                point.push((self.input(&super::inputs::lag_name(sensor, *tau))?, *g));
            }
        }
        let existing = match self.drifts.iter_mut().find(|d| d.index == index) {
            Some(d) => d,
            None => {
                self.drifts.push(DriftTerm { id, axis, points: Vec::new(), index });
                self.drifts.last_mut().expect("pushed")
            }
        };
        if existing.axis != axis {
            return Err(Error::input(format!(
                "the drift of {id} is interpolated over one axis; another entry names axis {}",
                machine.axes()[existing.axis].letter
            )));
        }
        if existing.points.iter().any(|(p, _)| *p == position) {
            return Err(Error::input(format!("the drift of {id} is given twice at position {position}")));
        }
        existing.points.push((position, point));
        existing.points.sort_by(|a, b| a.0.total_cmp(&b.0));
        Ok(())
    }

    /// Checks that every one-direction function has its counterpart.
    pub fn check_directions(&self) -> Result<()> {
        for e in &self.entries {
            if let Some(d) = e.direction {
                let other = if d == Direction::Positive { Direction::Negative } else { Direction::Positive };
                if !self.entries.iter().any(|f| f.index == e.index && f.direction == Some(other)) {
                    return Err(Error::input(format!("{}{} is given without {}{}", e.id, d.symbol(), e.id, other.symbol())));
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

    /// The model without the errors of parameters `drop` selects (their functions and every term,
    /// load and drift of them), e.g. the setup errors of a measurement (`TX .. WZ`), which belong to
    /// the instrument's set-up and not to the machine.
    pub fn without(&self, drop: impl Fn(&ParameterId) -> bool) -> ErrorModel {
        let mut model = self.clone();
        model.entries.retain(|e| !drop(&e.id));
        model.uncertainties.retain(|(id, _)| !drop(id));
        model.terms.retain(|t| !drop(&t.id));
        model.loads.retain(|l| !drop(&l.id));
        model.drifts.retain(|d| !drop(&d.id));
        model.plan();
        model
    }

    /// The model without the set-up errors of a measurement (`TX TY TZ WX WY WZ`: where a master
    /// ball or a probe head sits), which are not errors of the machine.
    pub fn without_setup(&self) -> ErrorModel {
        self.without(|id| matches!(id, ParameterId::Setup { .. }))
    }

    /// The model's functions alone: without its product, load and drift terms (what depends on
    /// several axes, on inputs, or on history).
    pub fn functions_only(&self) -> ErrorModel {
        let mut model = self.clone();
        model.terms.clear();
        model.loads.clear();
        model.drifts.clear();
        model.plan();
        model
    }

    /// Sets the standard uncertainty (k = 1, um or urad) of the constant value of `id`; an
    /// uncertainty that is negative or not finite is refused.
    pub fn set_uncertainty(&mut self, id: ParameterId, u: f64) -> Result<()> {
        if !(u.is_finite() && u >= 0.0) {
            return Err(Error::input(format!("the standard uncertainty of {id} must be a finite number >= 0, got {u}")));
        }
        self.uncertainties.retain(|(i, _)| *i != id);
        self.uncertainties.push((id, u));
        Ok(())
    }

    /// The standard uncertainties (k = 1, um or urad) of constant values the model states.
    pub fn uncertainties(&self) -> &[(ParameterId, f64)] {
        &self.uncertainties
    }

    /// Whether the model defines no error at all (no function, term, load or drift).
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty() && self.terms.is_empty() && self.loads.is_empty() && self.drifts.is_empty()
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

    /// Names of the inputs the model needs: temperature sensors (e.g. `T:spindle`), spindle speeds,
    /// forces, positions and lagged sensor rises ([`super::inputs`]), in the order
    /// [`MachineState::temperatures`] expects their values.
    pub fn sensors(&self) -> &[String] {
        &self.sensors
    }

    /// The value of each input at which its terms vanish (20 degC for a temperature, 0 else), in
    /// the order of [`ErrorModel::sensors`]: the value to use for an input that is not given.
    pub fn input_references(&self) -> &[f64] {
        &self.references
    }

    /// The workpiece-load errors.
    pub fn loads(&self) -> &[LoadTerm] {
        &self.loads
    }

    /// The drift models interpolated over an axis position.
    pub fn drifts(&self) -> &[DriftTerm] {
        &self.drifts
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
        for (index, axis, f) in &self.positional {
            values[*index] += f.value(q[*axis]);
        }
        self.add_state_dependent(machine, q, state, values);
    }

    /// The part of the evaluation plan that does not depend on the state beyond the axis positions:
    /// the constants summed (internal units, one per parameter) and the other functions for both
    /// directions as `(parameter index, own axis, function)`. [`ErrorModel::values_at_state`] is
    /// these plus [`ErrorModel::add_state_dependent`].
    pub(crate) fn position_plan(&self) -> (&[f64], &[(usize, usize, PositionFunction)]) {
        (&self.constants, &self.positional)
    }

    /// The parameters [`ErrorModel::add_state_dependent`] may change (sorted, each once): those of
    /// the directional functions, product, load and drift terms.
    pub(crate) fn state_dependent_parameters(&self) -> Vec<usize> {
        let mut indices: Vec<usize> = self
            .varying
            .iter()
            .map(|&k| self.entries[k].index)
            .chain(self.terms.iter().map(|t| t.index))
            .chain(self.loads.iter().map(|l| l.index))
            .chain(self.drifts.iter().map(|d| d.index))
            .collect();
        indices.sort_unstable();
        indices.dedup();
        indices
    }

    /// Adds to `values` (mm, rad) every contribution beyond [`ErrorModel::position_plan`]: the
    /// directional functions (weighted by the direction of motion), product, load and drift terms.
    pub(crate) fn add_state_dependent(&self, machine: &Machine, q: &[f64], state: &MachineState, values: &mut [f64]) {
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
        // an input not given is at its reference: its terms vanish
        let deviation = |i: usize| state.temperatures.get(i).map_or(0.0, |v| v - self.references[i]);
        for t in &self.terms {
            let mut v = t.coefficient;
            if let Some(a) = t.own_axis {
                let q = user(a);
                if t.range.is_some_and(|(lo, hi)| !(lo <= q && q < hi)) {
                    continue;
                }
                v *= match (t.direction, state.directions.and_then(|d| d[a])) {
                    (None, _) => 1.0,
                    (Some(d), Some(actual)) => f64::from(d == actual),
                    (Some(_), None) => 0.5,
                };
            }
            for (axis, power) in &t.axes {
                v *= user(*axis).powi(*power);
            }
            for (sensor, power) in &t.sensors {
                v *= deviation(*sensor).powi(*power);
            }
            values[t.index] += v * t.id.component().to_internal();
        }
        for l in &self.loads {
            let mut v = l.function.evaluate(l.own_axis.map_or(0.0, user)) * deviation(l.load) / l.reference_n;
            if let Some((lever, at)) = l.lever {
                v *= (lever - deviation(at)) / lever;
            }
            values[l.index] += v * l.id.component().to_internal();
        }
        for d in &self.drifts {
            let q = user(d.axis);
            let drift_at = |k: usize| d.points[k].1.iter().map(|(i, g)| g * deviation(*i)).sum::<f64>();
            let k = d.points.partition_point(|(p, _)| *p <= q);
            let v = match k {
                0 => drift_at(0),
                k if k == d.points.len() => drift_at(k - 1),
                k => {
                    let (p0, p1) = (d.points[k - 1].0, d.points[k].0);
                    let t = (q - p0) / (p1 - p0);
                    (1.0 - t) * drift_at(k - 1) + t * drift_at(k)
                }
            };
            values[d.index] += v * d.id.component().to_internal();
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
        assert!(model.set(&m, exx, ErrorFunction::Constant(1.0)).unwrap_err().to_string().contains("more than once"));
    }

    #[test]
    fn bidirectional_functions_follow_the_direction_of_motion() {
        // backlash: EXX+ = +0.4 um, EXX- = -0.4 um; the mean (direction unknown) is zero
        let m = Machine::from_toml_str(MACHINE, "xc").unwrap();
        let mut model = ErrorModel::zero(&m);
        let exx = ParameterId::parse("EXX").unwrap();
        model.set_directional(&m, exx, Some(Direction::Positive), ErrorFunction::Constant(0.4)).unwrap();
        assert!(model.check_directions().unwrap_err().to_string().contains("EXX+ is given without EXX-"));
        model.set_directional(&m, exx, Some(Direction::Negative), ErrorFunction::Constant(-0.4)).unwrap();
        model.check_directions().unwrap();
        assert!(model.set(&m, exx, ErrorFunction::Constant(1.0)).unwrap_err().to_string().contains("both directions"));
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
        assert!(model.add_term(&m, exx, 1.0, &[('Q', 1)], &[]).unwrap_err().to_string().contains("no axis Q"));
    }
}
