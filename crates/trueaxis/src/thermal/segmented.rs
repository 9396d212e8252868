//! The geometric-thermal (G-T) model of NISTIR 5236 §3.6: per error component a regression on the axis
//! position and the selected temperatures (and "currently measured parameters during the operation,
//! such as spindle speed", §3.5), with the data "segmented depending on the direction of travel due
//! to hysteresis" and, if needed, "into regions of axis position"; "typically quadratic functions of
//! position", "first-order functions of one or two temperatures", "terms which are a product of
//! temperature and position".
//!
//! Each segment is a [`RegressionModel`] fitted to its rows: the direction of motion (`dir` column,
//! `+` / `-`) and a position range `[lo, hi)` (the outer ranges open: `-inf`, `inf`), with the
//! geometric/thermal split of degrees of [`super::regression::fit_split`]. As error terms of the
//! chain (`[[term."EXX+"]]` with `range`) the segments evaluate exactly as here.

use super::links::{model_terms, ErrorTerm};
use super::regression::{fit_split, RegressionModel};
use super::thermal_campaign::Campaign;
use crate::error::Error;
use serde::{Deserialize, Serialize};

/// One segment: a direction of motion and / or a position range, and its model's coefficients.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GtSegment {
    /// `+` or `-` (none: both directions).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<String>,
    /// `[lo, hi)` of the position (mm or deg; none: every position).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<[f64; 2]>,
    /// Row k: `[c_k0, c_k1, ..]` multiplying `P^k`, as [`RegressionModel::coefficients`].
    pub coefficients: Vec<Vec<f64>>,
}

/// A segmented G-T model of one error.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentedModel {
    pub error: String,
    /// The axis column P.
    pub position: String,
    /// Inputs (`T:<sensor>`, `S:<spindle>`, ...) in the order of the coefficients.
    pub sensors: Vec<String>,
    #[serde(rename = "segment")]
    pub segments: Vec<GtSegment>,
}

impl SegmentedModel {
    /// The regression model of segment `k`.
    pub fn segment_model(&self, k: usize) -> RegressionModel {
        RegressionModel {
            error: self.error.clone(),
            sensors: self.sensors.clone(),
            position: Some(self.position.clone()),
            intercept: true,
            coefficients: self.segments[k].coefficients.clone(),
        }
    }

    /// Checks every segment and that the segments do not overlap.
    pub fn validate(&self) -> Result<(), Error> {
        if self.segments.is_empty() {
            return Err(Error::input("a segmented model needs at least one [[segment]]"));
        }
        for (k, s) in self.segments.iter().enumerate() {
            self.segment_model(k).validate().map_err(|m| Error::input(format!("segment {}: {m}", k + 1)))?;
            if let Some(d) = &s.direction {
                if d != "+" && d != "-" {
                    return Err(Error::input(format!("segment {}: direction `{d}` is not + or -", k + 1)));
                }
            }
            if let Some([lo, hi]) = s.range {
                if lo.is_nan() || hi.is_nan() || lo >= hi {
                    return Err(Error::input(format!("segment {}: range [{lo}, {hi}] needs lo < hi", k + 1)));
                }
            }
        }
        Ok(())
    }

    /// The segment holding position `p` moving in `direction` (`None`: unknown).
    pub fn segment_of(&self, p: f64, direction: Option<&str>) -> Option<usize> {
        self.segments.iter().position(|s| {
            s.range.is_none_or(|[lo, hi]| lo <= p && p < hi) && (s.direction.is_none() || s.direction.as_deref() == direction)
        })
    }

    /// The prediction (um) at `rows` of a campaign: each row by its segment (columns `dir` when
    /// the segments are directional, the position column, the inputs).
    pub fn predict(&self, campaign: &Campaign, rows: &[usize]) -> Result<Vec<f64>, Error> {
        let inputs = campaign.select(&self.sensors, rows)?;
        let positions = campaign.select(std::slice::from_ref(&self.position), rows)?.remove(0);
        let directional = self.segments.iter().any(|s| s.direction.is_some());
        if directional && !campaign.has_directions() {
            return Err(Error::input(format!(
                "{}: the model has a segment per direction of motion: the data need the column `dir` (+ or -)",
                campaign.origin
            )));
        }
        let models: Vec<RegressionModel> = (0..self.segments.len()).map(|k| self.segment_model(k)).collect();
        let mut t = vec![0.0; self.sensors.len()];
        rows.iter()
            .enumerate()
            .map(|(i, &row)| {
                let direction = directional.then(|| campaign.dirs[row].as_str());
                let k = self.segment_of(positions[i], direction).ok_or_else(|| {
                    Error::input(format!(
                        "{}: row {}: no segment holds position {} moving `{}`",
                        campaign.origin,
                        row + 1,
                        positions[i],
                        direction.unwrap_or("")
                    ))
                })?;
                t.iter_mut().zip(&inputs).for_each(|(x, col)| *x = col[i]);
                Ok(models[k].evaluate(positions[i], &t))
            })
            .collect()
    }

    /// The model as error terms of `parameter` (a motion error of the position axis): each
    /// segment's terms with its direction and range.
    pub fn terms(&self, parameter: &str) -> Result<Vec<ErrorTerm>, Error> {
        let mut out = Vec::new();
        for (k, s) in self.segments.iter().enumerate() {
            for mut t in model_terms(parameter, &self.segment_model(k), 1.0)? {
                t.direction = s.direction.as_deref().and_then(|d| d.chars().next());
                t.range = s.range;
                out.push(t);
            }
        }
        Ok(out)
    }

    /// The model file text (`kind = "segmented"`).
    pub fn to_toml(&self) -> String {
        let body = toml::to_string(self).expect("a segmented model serialises");
        format!("# geometric-thermal model by segment (direction of motion, position range [lo, hi)): in each, E(P, T) = sum_k P^k (c_k0 + sum_i c_ki T_i), E in um\nkind = \"segmented\"\n{body}")
    }
}

/// How to segment a G-T fit, and the degrees of each segment's model.
#[derive(Clone, Debug, Default)]
pub struct Segmentation {
    /// One model per direction of motion (column `dir`).
    pub by_direction: bool,
    /// Breakpoints of the position (increasing): ranges `[-inf, b1)`, `[b1, b2)`, .., `[bn, inf)`.
    pub breakpoints: Vec<f64>,
    /// Degree of the geometric polynomial in the position.
    pub geometric_degree: usize,
    /// Degree of the position multiplying the temperatures (and other inputs).
    pub thermal_degree: usize,
}

/// Fits a G-T model of `error` on `rows` of `campaign` segment by segment, each with the degrees of
/// `segmentation` in the position of axis column `position`.
pub fn fit_segmented(
    campaign: &Campaign,
    rows: &[usize],
    error: &str,
    sensors: &[String],
    position: &str,
    segmentation: &Segmentation,
) -> Result<SegmentedModel, Error> {
    let (geometric_degree, thermal_degree) = (segmentation.geometric_degree, segmentation.thermal_degree);
    if segmentation.breakpoints.windows(2).any(|w| w[1] <= w[0]) || segmentation.breakpoints.iter().any(|b| !b.is_finite()) {
        return Err(Error::input("the position breakpoints of the ranges must be finite and increase strictly"));
    }
    if segmentation.by_direction && !campaign.has_directions() {
        return Err(Error::input(format!("{}: segments by direction of motion need the column `dir` (+ or -)", campaign.origin)));
    }
    let p = campaign.column(position)?;
    let mut bounds = vec![f64::NEG_INFINITY];
    bounds.extend(&segmentation.breakpoints);
    bounds.push(f64::INFINITY);
    let directions: Vec<Option<&str>> = if segmentation.by_direction { vec![Some("+"), Some("-")] } else { vec![None] };
    let mut segments = Vec::new();
    for d in &directions {
        for w in bounds.windows(2) {
            let seg_rows: Vec<usize> =
                rows.iter().copied().filter(|&r| w[0] <= p[r] && p[r] < w[1] && d.is_none_or(|d| campaign.dirs[r] == d)).collect();
            let name = format!("segment {}[{}, {})", d.map_or(String::new(), |d| format!("{d} ")), w[0], w[1]);
            let temps = campaign.select(sensors, &seg_rows)?;
            let positions: Vec<f64> = seg_rows.iter().map(|&r| p[r]).collect();
            let measured = campaign.select(&[error.to_string()], &seg_rows)?.remove(0);
            let needed = geometric_degree + 1 + sensors.len() * (thermal_degree + 1);
            if seg_rows.len() <= needed {
                return Err(Error::input(format!(
                    "{name}: {} rows cannot determine {needed} coefficients; use fewer segments or lower degrees",
                    seg_rows.len()
                )));
            }
            let (model, _) = fit_split(
                &format!("{error} {name}"),
                sensors,
                &temps,
                (position, &positions),
                geometric_degree,
                thermal_degree,
                &measured,
            )?;
            let range = (!segmentation.breakpoints.is_empty()).then_some([w[0], w[1]]);
            segments.push(GtSegment { direction: d.map(String::from), range, coefficients: model.coefficients });
        }
    }
    Ok(SegmentedModel { error: error.into(), position: position.into(), sensors: sensors.to_vec(), segments })
}
