//! The Python package `trueaxis` (module `trueaxis._native`, wrapped by `python/trueaxis`): the
//! library's machines, error models, prediction, identification, uncertainty (with the chunks of
//! a Monte Carlo run for distributed engines), optimal design, compensation, NC correction and
//! ISO 230 evaluations (positioning, circular tests, the rotary-axis ballbar test), fits of
//! parametric error functions to direct measurements, thermal error models and sensor placement,
//! the error budget for machine design, with numpy arrays in and out and the command line's JSON
//! documents as dictionaries. Units as everywhere in trueaxis: positions in mm and deg, errors in um and urad.

mod ballbar;
mod budget;
mod compensate;
mod convert;
mod evaluate;
mod exceptions;
mod fit;
mod identify;
mod machine;
mod progress;
mod thermal;
mod uncertainty;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("TrueaxisError", py.get_type::<exceptions::TrueaxisError>())?;
    m.add("InputError", py.get_type::<exceptions::InputError>())?;
    m.add("ComputationError", py.get_type::<exceptions::ComputationError>())?;
    m.add("ResourceError", py.get_type::<exceptions::ResourceError>())?;
    m.add("TrueaxisWarning", py.get_type::<exceptions::TrueaxisWarning>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // the columns of `Machine.predict`: 6 by default, 7 (dL last) with `with_dl=True`
    let columns: Vec<&str> = trueaxis::poses::PREDICTION_COLUMNS.iter().map(|(c, _)| *c).collect();
    let units: Vec<&str> = trueaxis::poses::PREDICTION_COLUMNS.iter().map(|(_, u)| *u).collect();
    m.add("PREDICTION_COLUMNS", columns[..6].to_vec())?;
    m.add("PREDICTION_COLUMNS_WITH_DL", columns)?;
    m.add("PREDICTION_UNITS", units[..6].to_vec())?;
    m.add("PREDICTION_UNITS_WITH_DL", units)?;
    m.add("BLOCK", trueaxis::uncertainty::BLOCK)?;
    m.add_class::<machine::Machine>()?;
    m.add_class::<machine::Errors>()?;
    m.add_class::<identify::Campaign>()?;
    m.add_class::<identify::Identification>()?;
    m.add_class::<identify::Candidates>()?;
    m.add_class::<uncertainty::Sources>()?;
    m.add_class::<uncertainty::UncertaintyPlan>()?;
    m.add_class::<uncertainty::BudgetRun>()?;
    m.add_class::<budget::BudgetProblem>()?;
    m.add_function(wrap_pyfunction!(identify::identify, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate::iso230_2, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate::iso230_4, m)?)?;
    m.add_function(wrap_pyfunction!(ballbar::ballbar_identify, m)?)?;
    m.add_function(wrap_pyfunction!(ballbar::ballbar_sensitivity, m)?)?;
    m.add_function(wrap_pyfunction!(ballbar::ballbar_simulate, m)?)?;
    m.add_function(wrap_pyfunction!(thermal::thermal_fit, m)?)?;
    m.add_function(wrap_pyfunction!(thermal::thermal_predict, m)?)?;
    m.add_function(wrap_pyfunction!(thermal::thermal_modes, m)?)?;
    m.add_function(wrap_pyfunction!(thermal::thermal_place, m)?)?;
    m.add_function(wrap_pyfunction!(budget::budget_configurations, m)?)?;
    m.add_function(wrap_pyfunction!(budget::budget_miniaturisation, m)?)?;
    m.add_function(wrap_pyfunction!(compensate::compensate, m)?)?;
    m.add_function(wrap_pyfunction!(compensate::correct_nc, m)?)?;
    Ok(())
}
