//! Thermal expansion of a machine scale or of a reference artefact: correction of linear
//! displacement deviations to the 20 degC reference temperature (ISO 1), and the apparent
//! expansion coefficient of a scale from two runs at two temperatures (Soons 1993 §3.2.4, §5.1.1).
//!
//! Units: positions in mm, deviations and expansions in um, temperatures in degC, expansion
//! coefficients in um/m/K (1 um/m/K = 1e-6 /K). An expansion `alpha (T - 20) L` is
//! `alpha [um/m/K] * (T - 20) [K] * L [mm] * 1e-3 [m/mm]` um.
//!
//! # Sign convention
//!
//! A deviation is actual minus nominal of the machine position (ISO 230-2; the `dev` column of
//! docs/design.md, Files): the position given by the reference (laser interferometer, step gauge, hole
//! plate) minus the position given by the machine's scale. A body at temperature `T` with coefficient
//! `alpha` is longer than at 20 degC: a feature nominally `L` from the body's fixed point (its thermal
//! datum) is at `L + E`, `E = alpha (T - 20) L` (for a uniform temperature; in general the integral of
//! `alpha (T(u) - 20)` from the datum to the feature).
//!
//! - [`ExpandingBody::MachineScale`]: the machine's own scale is warm and the reference is not (a
//!   laser interferometer corrected for the air but not for material temperature). When the scale
//!   reads `L` the slide is really at `L + E`: the warm scale *reads short*, the measured deviation
//!   is too large by `E`, and the deviation at 20 degC is `dev_20 = dev_measured - E`.
//!   Worked example: a steel scale, alpha 11.5 um/m/K, at 25.3 degC, 500 mm from its fixed point,
//!   `E = 11.5 * 5.3 * 500e-3 = 30.475` um; the slide travels 500.030475 mm when the scale says
//!   500 mm; a laser deviation of +32.000 um becomes `32.000 - 30.475 = +1.525` um at 20 degC.
//! - [`ExpandingBody::Reference`]: the reference artefact (a workpiece, a step gauge, a hole plate)
//!   is warm and the scale is not. A feature calibrated at `L` (20 degC) is really at `L + E`; a
//!   perfect machine reads `L + E` there, so the deviation (reference minus machine) is too small by
//!   `E`, and `dev_20 = dev_measured + E`. Same numbers: a steel step gauge at 25.3 degC measured by
//!   a perfect machine at 20 degC gives -30.475 um at 500 mm, corrected to 0.
//!
//! When both are away from 20 degC, correct for each body in turn. Do not correct laser readings
//! that the laser software has already normalised with a "material temperature": that is this same
//! `MachineScale` correction.

use super::least_squares_line;
use thiserror::Error;

/// The reference temperature for dimensional measurements, ISO 1, degC.
pub const REFERENCE_TEMPERATURE_DEGC: f64 = 20.0;

/// An input error of a scale thermal reduction; the message names the quantity at fault.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ScaleError {
    #[error("{what}: {first} has {first_len} values but {second} has {second_len}; they must match")]
    LengthMismatch { what: &'static str, first: &'static str, first_len: usize, second: &'static str, second_len: usize },
    #[error("{what}: no positions given")]
    NoPositions { what: &'static str },
    #[error("{what}: needs at least {needed} points, got {got}")]
    TooFewPoints { what: &'static str, needed: usize, got: usize },
    #[error("{what}: {name}[{index}] is not a finite number ({value})")]
    NonFinite { what: &'static str, name: &'static str, index: usize, value: f64 },
    #[error("{what}: {name} is not a finite number ({value})")]
    NonFiniteParameter { what: &'static str, name: &'static str, value: f64 },
    #[error("{what}: no temperature sensors given (at least one position and temperature are needed)")]
    NoSensors { what: &'static str },
    #[error(
        "{what}: sensor positions must be strictly increasing along the axis, \
         but sensor {index} at {position_mm} mm is not after sensor {previous_index} at {previous_mm} mm"
    )]
    SensorsOutOfOrder { what: &'static str, index: usize, position_mm: f64, previous_index: usize, previous_mm: f64 },
    #[error(
        "{what}: the two runs have the same thermal expansion at every position (equal temperatures, \
         or all positions equal), so the expansion coefficient cannot be estimated"
    )]
    NoTemperatureContrast { what: &'static str },
    /// A file's recorded material temperature that is no workshop temperature (kelvin, Fahrenheit),
    /// `io::plausibility::temperature_degc`; the message names the file.
    #[error("{message} (or give --no-file-temperature)")]
    ImplausibleFileTemperature { message: String },
}

crate::error::error_of_kind!(ScaleError, Input);

/// The temperature of the expanding body during a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ScaleTemperature<'a> {
    /// One temperature for the whole body and run, degC.
    Uniform(f64),
    /// One temperature per measured point, degC: the (uniform) body temperature when that point was
    /// read, as a laser's material-temperature sensor gives it. Point i expands by
    /// `alpha (T_i - 20) (x_i - datum)`.
    PerPoint(&'a [f64]),
    /// Sensors along the axis (Soons 1993: three Pt-100 at the start, middle and end of the X scale):
    /// their axis positions (mm, strictly increasing) and temperatures (degC). The temperature
    /// between sensors is interpolated linearly along the axis and held constant beyond the end
    /// sensors; the expansion at x is `alpha * integral from datum to x of (T(u) - 20) du`.
    Sensors { positions_mm: &'a [f64], temperatures_degc: &'a [f64] },
}

/// Which body's expansion is removed; see the module documentation for the derivation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExpandingBody {
    /// The machine's scale (measuring system); reference not expanding. `dev_20 = dev - E`.
    MachineScale,
    /// The reference artefact or workpiece; machine scale at 20 degC. `dev_20 = dev + E`.
    Reference,
}

/// A thermal correction of a run of deviations to 20 degC.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThermalCorrection<'a> {
    pub body: ExpandingBody,
    /// Expansion coefficient of the body, um/m/K (e.g. 9.75 for the Soons 1993 X scale, ~11.5 steel).
    pub alpha_um_per_m_k: f64,
    pub temperature: ScaleTemperature<'a>,
    /// Axis position (mm) of the body's fixed point, about which it expands (the fixed mounting point
    /// of a scale, the zero of a step gauge). If the deviations were zeroed at the first point, use
    /// that position to keep the zero there.
    pub datum_mm: f64,
}

/// One run of a scale calibration for [`apparent_expansion_coefficient`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThermalRun<'a> {
    /// Deviations (um), one per position.
    pub deviations_um: &'a [f64],
    /// The scale temperature during the run.
    pub temperature: ScaleTemperature<'a>,
}

/// Result of [`apparent_expansion_coefficient`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApparentExpansion {
    /// The apparent expansion coefficient of the scale, um/m/K.
    pub alpha_um_per_m_k: f64,
    /// Constant part of the difference between the runs (run 1 minus run 2), um: zero shift between
    /// the runs (homing, a different datum).
    pub offset_um: f64,
    /// RMS of the difference between the runs that the fit leaves, um.
    pub residual_rms_um: f64,
}

/// Expansion `alpha (T - 20) L` (um) of a uniform body of length `L` from its datum:
/// `alpha_um_per_m_k * (temperature_degc - 20) * length_mm * 1e-3` (ISO 1 reference 20 degC; seed
/// 000 §3.2.4). Example: 11.5 um/m/K, 25.3 degC, 500 mm: 30.475 um.
pub fn uniform_expansion_um(alpha_um_per_m_k: f64, temperature_degc: f64, length_mm: f64) -> f64 {
    alpha_um_per_m_k * (temperature_degc - REFERENCE_TEMPERATURE_DEGC) * length_mm * 1e-3
}

/// Thermal expansion (um) of the body at each axis position relative to its datum: how far the
/// feature or graduation nominally (at 20 degC) at `x` has moved, positive away from the datum in +x
/// direction; `alpha` in um/m/K (Soons 1993 §3.2.4, §5.1.1; ISO 1). See [`ScaleTemperature`] for the
/// three temperature inputs.
pub fn thermal_expansion_um(
    positions_mm: &[f64],
    alpha_um_per_m_k: f64,
    temperature: &ScaleTemperature,
    datum_mm: f64,
) -> Result<Vec<f64>, ScaleError> {
    expansion("scale thermal correction", positions_mm, alpha_um_per_m_k, temperature, datum_mm)
}

/// Deviations corrected to 20 degC (um): `dev_20 = dev - E` for the machine scale, `dev_20 = dev + E`
/// for a reference artefact, with `E` from [`thermal_expansion_um`] (Soons 1993 §3.2.4 / §5.1.1: the
/// laser data "compensated for the thermal expansion of the X-axis measurement scale"; the sign
/// derivation and worked examples are in the module documentation).
pub fn correct_to_20c(positions_mm: &[f64], deviations_um: &[f64], correction: &ThermalCorrection) -> Result<Vec<f64>, ScaleError> {
    const WHAT: &str = "scale thermal correction";
    check_len(WHAT, positions_mm, "deviations", deviations_um)?;
    check_finite(WHAT, "deviations", deviations_um)?;
    let e = expansion(WHAT, positions_mm, correction.alpha_um_per_m_k, &correction.temperature, correction.datum_mm)?;
    let sign = match correction.body {
        ExpandingBody::MachineScale => -1.0,
        ExpandingBody::Reference => 1.0,
    };
    Ok(deviations_um.iter().zip(&e).map(|(d, e)| d + sign * e).collect())
}

/// Apparent expansion coefficient of a machine scale from two runs at the same positions and
/// different scale temperatures (Soons 1993 §5.1.1: 9.75 um/m/K from the manufacturer, 13.5 um/m/K
/// apparent, scale temperatures 25.3 and 20.4 degC).
///
/// Both runs are deviations against a reference that does not expand (laser), either raw
/// (`alpha_applied_um_per_m_k = 0`) or already corrected with [`correct_to_20c`] and
/// `ExpandingBody::MachineScale` using `alpha_applied_um_per_m_k`. If the scale expands with the
/// coefficient `alpha`, the difference of the runs is
/// `dev_1(x) - dev_2(x) = (alpha - alpha_applied) (U_1(x) - U_2(x)) + c`, with `U_k` the expansion of
/// run k for 1 um/m/K ([`thermal_expansion_um`]) and `c` a constant (zero shift). The least-squares
/// fit of the difference against `U_1 - U_2` gives `alpha = alpha_applied + slope`. For uniform
/// temperatures this is `alpha_applied + 1000 * d(dev_1 - dev_2)/dx / (T_1 - T_2)` (x in mm): the
/// slope of the deviation difference against position over the temperature difference. At least 2
/// points.
pub fn apparent_expansion_coefficient(
    positions_mm: &[f64],
    run1: &ThermalRun,
    run2: &ThermalRun,
    datum_mm: f64,
    alpha_applied_um_per_m_k: f64,
) -> Result<ApparentExpansion, ScaleError> {
    const WHAT: &str = "apparent expansion coefficient";
    check_len(WHAT, positions_mm, "run 1 deviations", run1.deviations_um)?;
    check_len(WHAT, positions_mm, "run 2 deviations", run2.deviations_um)?;
    if positions_mm.len() < 2 {
        return Err(ScaleError::TooFewPoints { what: WHAT, needed: 2, got: positions_mm.len() });
    }
    check_finite(WHAT, "run 1 deviations", run1.deviations_um)?;
    check_finite(WHAT, "run 2 deviations", run2.deviations_um)?;
    check_parameter(WHAT, "applied expansion coefficient (um/m/K)", alpha_applied_um_per_m_k)?;
    let u1 = expansion(WHAT, positions_mm, 1.0, &run1.temperature, datum_mm)?;
    let u2 = expansion(WHAT, positions_mm, 1.0, &run2.temperature, datum_mm)?;
    let du: Vec<f64> = u1.iter().zip(&u2).map(|(a, b)| a - b).collect();
    let diff: Vec<f64> = run1.deviations_um.iter().zip(run2.deviations_um).map(|(a, b)| a - b).collect();
    // A contrast below 1e-12 um per um/m/K over the whole run is numerically nothing.
    let (min, max) = du.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    if max - min <= 1e-12 {
        return Err(ScaleError::NoTemperatureContrast { what: WHAT });
    }
    let (slope, offset) = least_squares_line(&du, &diff).ok_or(ScaleError::NoTemperatureContrast { what: WHAT })?;
    let sum_sq: f64 = du.iter().zip(&diff).map(|(u, d)| (d - offset - slope * u).powi(2)).sum();
    Ok(ApparentExpansion {
        alpha_um_per_m_k: alpha_applied_um_per_m_k + slope,
        offset_um: offset,
        residual_rms_um: (sum_sq / du.len() as f64).sqrt(),
    })
}

/// Where the temperature of a body comes from in a data file.
#[derive(Clone, Debug, PartialEq)]
pub enum TemperatureSource {
    /// One temperature for the whole run, degC.
    Uniform(f64),
    /// A column of the data file (e.g. `T:scale`), one temperature per reading, degC
    /// ([`ScaleTemperature::PerPoint`]).
    Column(String),
}

/// A correction to 20 degC of the deviations in a data file (the owned form of
/// [`ThermalCorrection`], with the temperature from the file or given).
#[derive(Clone, Debug, PartialEq)]
pub struct TableCorrection {
    pub body: ExpandingBody,
    /// um/m/K.
    pub alpha_um_per_m_k: f64,
    pub temperature: TemperatureSource,
    /// The body's fixed point (mm).
    pub datum_mm: f64,
}

/// Why a data file cannot be corrected: a bad column, or bad values.
#[derive(Debug, Error)]
pub enum TableCorrectionError {
    #[error(transparent)]
    Data(#[from] crate::data::DataError),
    #[error(transparent)]
    Scale(#[from] ScaleError),
}

crate::error::error_of_kind!(TableCorrectionError, Input);

impl TableCorrection {
    /// The deviations (um) of `table`'s rows at `positions_mm` corrected to 20 degC by
    /// [`correct_to_20c`], each correction of `corrections` in turn (Soons 1993 §3.2.4; ISO 230-2
    /// asks for results at 20 degC).
    pub fn apply_all(
        corrections: &[TableCorrection],
        table: &crate::data::CsvTable,
        positions_mm: &[f64],
        deviations_um: &[f64],
    ) -> Result<Vec<f64>, TableCorrectionError> {
        let mut out = deviations_um.to_vec();
        for c in corrections {
            let column;
            let temperature = match &c.temperature {
                TemperatureSource::Uniform(t) => ScaleTemperature::Uniform(*t),
                TemperatureSource::Column(name) => {
                    column = table.numbers(name)?;
                    ScaleTemperature::PerPoint(&column)
                }
            };
            let correction = ThermalCorrection { body: c.body, alpha_um_per_m_k: c.alpha_um_per_m_k, temperature, datum_mm: c.datum_mm };
            out = correct_to_20c(positions_mm, &out, &correction)?;
        }
        Ok(out)
    }
}

fn expansion(
    what: &'static str,
    positions_mm: &[f64],
    alpha_um_per_m_k: f64,
    temperature: &ScaleTemperature,
    datum_mm: f64,
) -> Result<Vec<f64>, ScaleError> {
    if positions_mm.is_empty() {
        return Err(ScaleError::NoPositions { what });
    }
    check_finite(what, "positions", positions_mm)?;
    check_parameter(what, "expansion coefficient (um/m/K)", alpha_um_per_m_k)?;
    check_parameter(what, "datum position (mm)", datum_mm)?;
    let k = alpha_um_per_m_k * 1e-3; // um per (mm K)
    let t0 = REFERENCE_TEMPERATURE_DEGC;
    match *temperature {
        ScaleTemperature::Uniform(t) => {
            check_parameter(what, "temperature (degC)", t)?;
            Ok(positions_mm.iter().map(|&x| k * (t - t0) * (x - datum_mm)).collect())
        }
        ScaleTemperature::PerPoint(ts) => {
            check_len(what, positions_mm, "point temperatures", ts)?;
            check_finite(what, "point temperatures", ts)?;
            Ok(positions_mm.iter().zip(ts).map(|(&x, &t)| k * (t - t0) * (x - datum_mm)).collect())
        }
        ScaleTemperature::Sensors { positions_mm: sx, temperatures_degc: st } => {
            if sx.len() != st.len() {
                return Err(ScaleError::LengthMismatch {
                    what,
                    first: "sensor positions",
                    first_len: sx.len(),
                    second: "sensor temperatures",
                    second_len: st.len(),
                });
            }
            if sx.is_empty() {
                return Err(ScaleError::NoSensors { what });
            }
            check_finite(what, "sensor positions", sx)?;
            check_finite(what, "sensor temperatures", st)?;
            if let Some(i) = (1..sx.len()).find(|&i| sx[i] <= sx[i - 1]) {
                return Err(ScaleError::SensorsOutOfOrder {
                    what,
                    index: i,
                    position_mm: sx[i],
                    previous_index: i - 1,
                    previous_mm: sx[i - 1],
                });
            }
            let at_datum = profile_integral(sx, st, datum_mm);
            Ok(positions_mm.iter().map(|&x| k * (profile_integral(sx, st, x) - at_datum)).collect())
        }
    }
}

/// `integral from s_0 to x of (T(u) - 20) du` (K mm) for the piecewise-linear profile through the
/// sensors, constant beyond the end sensors. Sensors checked: non-empty, strictly increasing.
fn profile_integral(sx: &[f64], st: &[f64], x: f64) -> f64 {
    let t0 = REFERENCE_TEMPERATURE_DEGC;
    if x <= sx[0] {
        return (st[0] - t0) * (x - sx[0]);
    }
    let mut acc = 0.0;
    for i in 0..sx.len() - 1 {
        let width = sx[i + 1] - sx[i];
        if x <= sx[i + 1] {
            let w = x - sx[i];
            let t_x = st[i] + (st[i + 1] - st[i]) * w / width;
            return acc + w * (0.5 * (st[i] + t_x) - t0);
        }
        acc += width * (0.5 * (st[i] + st[i + 1]) - t0);
    }
    let last = sx.len() - 1;
    acc + (st[last] - t0) * (x - sx[last])
}

fn check_len(what: &'static str, positions_mm: &[f64], name: &'static str, values: &[f64]) -> Result<(), ScaleError> {
    if values.len() == positions_mm.len() {
        Ok(())
    } else {
        Err(ScaleError::LengthMismatch { what, first: "positions", first_len: positions_mm.len(), second: name, second_len: values.len() })
    }
}

fn check_finite(what: &'static str, name: &'static str, values: &[f64]) -> Result<(), ScaleError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(ScaleError::NonFinite { what, name, index, value: values[index] }),
        None => Ok(()),
    }
}

fn check_parameter(what: &'static str, name: &'static str, value: f64) -> Result<(), ScaleError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(ScaleError::NonFiniteParameter { what, name, value })
    }
}
