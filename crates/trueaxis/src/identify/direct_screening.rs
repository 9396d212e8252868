//! Screening of a direct fit (`trueaxis fit`: one error along its axis, e.g. the readings of an
//! ISO 230-2 laser test): readings the fitted function does not explain.
//!
//! For observation i of the least-squares fit (residual e_i, leverage h_i, p functions):
//! - the studentized residual with the robust scale s of the residuals (MAD scaled by 1.4826, so
//!   that the outlier does not hide behind the sigma it inflates): t_i = e_i / (s sqrt(1 - h_i));
//!   |t_i| over [`STUDENTIZED_LIMIT`] (5.5, as the identification's) is an outlier;
//! - Cook's distance of the fit as printed, D_i = e_i^2 h_i / (p sigma^2 (1 - h_i)^2) (Cook 1977,
//!   sigma the residual standard deviation): D_i over [`COOK_LIMIT`] (1, Cook and Weisberg 1982)
//!   is a reading that alone moves the fitted function by about the width of its confidence
//!   region.
//!
//! Each flagged reading is named by its file line, run (column `run`), position and direction
//! (`dir`), and the finding states the fit without the flagged readings: its residual standard
//! deviation and the largest change of the fitted function at the observed positions.

use super::campaign_screening::STUDENTIZED_LIMIT;
use crate::data::CsvTable;
use crate::identify::{fit_error_function, FitOptions, FittedFunction, IdentifyError};
use crate::screen::finding::{lines_text, Finding, Kind};
use crate::screen::robust::mad_sigma;

/// Cook's distance beyond this flags an influential reading (Cook and Weisberg 1982).
pub const COOK_LIMIT: f64 = 1.0;

/// What was fitted: the table rows of the observations, their positions and values, and how.
pub struct DirectObservations<'a> {
    pub table: &'a CsvTable,
    pub rows: &'a [usize],
    pub positions: &'a [f64],
    pub values: &'a [f64],
    pub options: &'a FitOptions,
    /// The column of positions, as named in messages.
    pub position_column: &'a str,
    /// The unit of the values (um or urad).
    pub unit: &'a str,
}

/// Studentized residuals (robust scale) and Cook's distances of `fitted`.
pub fn diagnostics(fitted: &FittedFunction) -> (Vec<f64>, Vec<f64>) {
    let fit = &fitted.fit;
    let s = mad_sigma(&fit.residuals).max(1e-12);
    let t = fit.residuals.iter().zip(&fit.leverage).map(|(e, h)| e / (s * (1.0 - h.min(0.999_999)).sqrt())).collect();
    (t, fit.cooks_distance())
}

/// The outliers and influential readings of `fitted`, one finding listing them; none when clean.
pub fn fit_outliers(obs: &DirectObservations, fitted: &FittedFunction) -> Result<Vec<Finding>, IdentifyError> {
    let (t, cook) = diagnostics(fitted);
    let flagged: Vec<usize> = (0..t.len()).filter(|&i| t[i].abs() > STUDENTIZED_LIMIT || cook[i] > COOK_LIMIT).collect();
    if flagged.is_empty() {
        return Ok(Vec::new());
    }
    let table = obs.table;
    let lines: Vec<u64> = flagged.iter().map(|&i| table.lines()[obs.rows[i]]).collect();
    let named: Vec<String> = flagged.iter().map(|&i| reading_text(obs, i, fitted.fit.residuals[i], t[i], cook[i])).collect();
    let message = format!(
        "{} reading(s) beyond the limits (studentized residual {STUDENTIZED_LIMIT} with the MAD-based scale, Cook's distance {COOK_LIMIT}): {}",
        flagged.len(),
        named.join("; ")
    );
    let keep: Vec<usize> = (0..t.len()).filter(|i| !flagged.contains(i)).collect();
    let consequence = without_text(obs, fitted, &keep)?;
    Ok(vec![Finding::flag(Kind::Outlier, table.origin(), format!("lines {}", lines_text(&lines)), message)
        .with_consequence(consequence)
        .with_lines(lines)])
}

/// "line 73 (run 4, target 300 mm, dir +): residual +45.1 um, studentized +38.2, Cook's distance 0.75".
fn reading_text(obs: &DirectObservations, i: usize, e: f64, t: f64, d: f64) -> String {
    let row = obs.rows[i];
    let cell = |name: &str| obs.table.cell(row, name).ok().map(|v| v.trim().to_string()).filter(|v| !v.is_empty());
    let mut place = Vec::new();
    if let Some(run) = cell("run") {
        place.push(format!("run {run}"));
    }
    place.push(format!("{} {}", obs.position_column, obs.positions[i]));
    if let Some(dir) = cell("dir") {
        place.push(format!("dir {dir}"));
    }
    format!(
        "line {} ({}): residual {e:+.2} {}, studentized {t:+.1}, Cook's distance {d:.2}",
        obs.table.lines()[row],
        place.join(", "),
        obs.unit
    )
}

/// The fit of the readings `keep`: its residual standard deviation and how far it moves.
fn without_text(obs: &DirectObservations, fitted: &FittedFunction, keep: &[usize]) -> Result<String, IdentifyError> {
    let positions: Vec<f64> = keep.iter().map(|&i| obs.positions[i]).collect();
    let values: Vec<f64> = keep.iter().map(|&i| obs.values[i]).collect();
    let Ok(without) = fit_error_function(&positions, &values, obs.options) else {
        return Ok("the remaining readings cannot be fitted with the same functions".into());
    };
    let moved = obs.positions.iter().map(|&x| (without.predict(x, 0.95).0 - fitted.predict(x, 0.95).0).abs()).fold(0.0, f64::max);
    Ok(format!(
        "without them the residual standard deviation would be {:.3} {u} (with them {:.3} {u}) and the fitted function moves by up to {moved:.3} {u}; \
         the fit is of every reading",
        without.fit.sigma,
        fitted.fit.sigma,
        u = obs.unit
    ))
}
