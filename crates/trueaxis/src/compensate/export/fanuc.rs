//! Fanuc pitch-error compensation as a program for programmable parameter input (`G10 L50` ...
//! `G11`), the form a Fanuc control loads from a part program (Series 0i / 16i parameter manuals,
//! pitch-error compensation parameters 3620-3625; Fanuc technical report A-77810E; specs/anchors.md
//! §3).
//!
//! Per axis, a row of compensation points at a fixed interval (parameter 3624) through the
//! reference position (machine coordinate 0, point number 3620); 3621 / 3622 the most negative and
//! most positive point, 3623 the magnification, 3625 the travel per turn of a rotary axis. The value
//! of point p is the *increment* of the compensation over the section that ends at it, in detection
//! units times the magnification: moving up from the reference position the increments of the points
//! passed add up, moving down they are subtracted, so the compensation is zero at the reference
//! position and the value of the most negative point covers the first section inside the travel.
//! Each increment is output at its point (the compensation is not interpolated between points). For
//! a rotary axis over a full turn the most negative point is the reference point, its value equals
//! that of the last point, and the increments over one turn sum to zero. The parameters take effect
//! after a power cycle and a reference return (G28).
//!
//! Programmable parameter input: `G10 L50 ;` then `N<parameter> P<axis> R<value> ;` for axis
//! parameters and `N<10000 + point> R<value> ;` for the compensation data, `G11 ;` to end.
//!
//! Assumed (written in the head comment and checked): detection unit 0.001 mm / 0.001 deg (IS-B),
//! the interval a whole number of detection units, at most [`FanucLimits::max_points_per_axis`]
//! points per axis and point numbers 0 to [`FanucLimits::max_point_number`], values -128 to 127
//! (the magnification, 1 to 100, is the smallest that keeps them there). Values are the mean of both
//! directions (bidirectional compensation, 3605#0, is not written), own-axis only.

use super::residual::{Branch, Interpolation, TableSum};
use super::{check_user_limits, cross_axis_left_out, direction_left_out, micro_unit, to_micro, Export, ExportInput, ExportedFile};
use crate::compensate::tables::{line_tables, table_range, AxisTable};
use crate::compensate::{CompensateError, Corrector};
use crate::machine::{AxisKind, Machine};
use std::fmt::Write;

/// Detection unit (mm or deg): IS-B.
pub const DETECTION_UNIT: f64 = 1e-3;
/// Range of one compensation value (detection units times the magnification).
pub const MAX_VALUE: i64 = 127;
/// Largest magnification (parameter 3623).
pub const MAX_MAGNIFICATION: i64 = 100;

/// Limits of the control's pitch-error compensation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FanucLimits {
    /// Most compensation points of one axis (cnc.wiki: 128 between the extremes).
    pub max_points_per_axis: usize,
    /// Largest compensation point number (0i / 16i: 1023).
    pub max_point_number: usize,
}

impl Default for FanucLimits {
    fn default() -> Self {
        FanucLimits { max_points_per_axis: 128, max_point_number: 1023 }
    }
}

/// The pitch-error compensation of one axis as written.
#[derive(Clone, Debug, PartialEq)]
pub struct PitchAxis {
    pub axis: usize,
    /// Parameters 3620, 3621, 3622, 3623, 3624 (detection units), 3625 (detection units, 0: linear).
    pub reference_point: usize,
    pub most_negative: usize,
    pub most_positive: usize,
    pub magnification: i64,
    pub interval: i64,
    pub per_turn: i64,
    /// Value of each point from `most_negative` to `most_positive`.
    pub values: Vec<i64>,
}

impl PitchAxis {
    /// Interval (mm or deg).
    pub fn interval_user(&self) -> f64 {
        self.interval as f64 * DETECTION_UNIT
    }

    /// Compensation (mm or deg) at the end of the section of point `p`: the sum of the increments
    /// from the reference position.
    pub fn absolute_at_point(&self, p: usize) -> f64 {
        let unit = DETECTION_UNIT * self.magnification as f64;
        let r = self.reference_point;
        let value = |q: usize| self.values[q - self.most_negative] as f64 * unit;
        if p >= r {
            (r + 1..=p).map(value).sum()
        } else {
            -(p + 1..=r).map(value).sum::<f64>()
        }
    }
}

/// `pitch_error.nc` (the `G10 L50` program).
pub fn export<'a>(input: &ExportInput<'a>, limits: FanucLimits) -> Result<Export<'a>, CompensateError> {
    check_user_limits(input)?;
    let m = input.machine;
    let corrector = Corrector::new(m, input.errors);
    let mut next_point = 0usize;
    let mut axes = Vec::new();
    let mut carried = Vec::new();
    let mut left_out = Vec::new();
    for k in 0..m.axis_count() {
        let own = input.tables.table(k, k).expect("own-axis table of every axis");
        let (pitch, table, at_reference) = pitch_axis(&corrector, input, k, own.positions.len(), next_point, limits)?;
        next_point = pitch.most_positive + 1;
        if to_micro(m, k, at_reference).abs() >= 5e-4 {
            left_out.push(format!(
                "the correction of {} at the reference position (zero there by definition): {:.3} {}",
                m.axes()[k].letter,
                to_micro(m, k, at_reference),
                micro_unit(m, k)
            ));
        }
        carried.push((table, Branch::Mean));
        axes.push(pitch);
    }
    left_out.extend(cross_axis_left_out(input));
    left_out.extend(direction_left_out(input, |t| t.is_own_axis()));
    let files = vec![ExportedFile { name: "pitch_error.nc".into(), contents: program(m, &axes, limits) }];
    Ok(Export { files, applied: Box::new(TableSum { machine: m, tables: carried, interpolation: Interpolation::Held }), left_out })
}

/// The compensation points of axis `k`: interval from the travel and `points`, the values from the
/// exact own-axis corrections at the section ends (mean of both directions, minus the value at the
/// reference position), the table of what the control applies (mm or deg at the section ends), and
/// the correction at the reference position that the control cannot apply (mm or deg).
fn pitch_axis(
    corrector: &Corrector,
    input: &ExportInput,
    k: usize,
    points: usize,
    first_number: usize,
    limits: FanucLimits,
) -> Result<(PitchAxis, AxisTable, f64), CompensateError> {
    let m = input.machine;
    let axis = &m.axes()[k];
    let [lo, hi] = table_range(m, k)?;
    let full_turn = axis.kind == AxisKind::Rotary && axis.range.is_none();
    // the interval: a whole number of detection units; over a full turn one that divides 360 deg
    let sections_wanted = points.saturating_sub(1).max(1) as f64;
    let interval = if full_turn {
        let per_turn = (360.0 / DETECTION_UNIT).round() as i64;
        (1..=per_turn).map(|d| per_turn / d).find(|i| per_turn % i == 0 && (per_turn / i) as f64 >= sections_wanted).unwrap_or(1)
    } else {
        ((hi - lo) / sections_wanted / DETECTION_UNIT).ceil().max(1.0) as i64
    };
    let step = interval as f64 * DETECTION_UNIT;
    let (n_neg, n_pos) = if full_turn {
        (0, (360.0 / step).round() as usize)
    } else {
        (((-lo) / step - 1e-9).ceil().max(0.0) as usize, (hi / step - 1e-9).ceil().max(0.0) as usize)
    };
    let reference_point = first_number + n_neg.saturating_sub(1);
    let most_negative = first_number;
    let most_positive = reference_point + n_pos;
    let count = most_positive - most_negative + 1;
    if count > limits.max_points_per_axis {
        return Err(CompensateError::Limit(format!(
            "Fanuc pitch-error compensation of {} needs {count} points at an interval of {step} {}; the control takes at most {} per axis \
             (use fewer --points); nothing was written",
            axis.letter,
            axis.position_unit(),
            limits.max_points_per_axis
        )));
    }
    if most_positive > limits.max_point_number {
        return Err(CompensateError::Limit(format!(
            "Fanuc pitch-error compensation needs point numbers up to {most_positive}; the control has 0 to {} (use fewer --points); \
             nothing was written",
            limits.max_point_number
        )));
    }
    // absolute corrections relative to the reference position at every section end, clamped into
    // the travel (sections beyond it are never traversed)
    let ends: Vec<f64> = (0..=(n_neg + n_pos)).map(|i| (i as f64 - n_neg as f64) * step).collect();
    let sampled: Vec<f64> = ends.iter().map(|x| x.clamp(lo, hi)).collect();
    let mut unique = sampled.clone();
    unique.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    if unique.len() < 2 {
        unique = vec![lo, hi];
    }
    let line = line_tables(corrector, &input.tables.reference, &input.tables.temperatures, k, &unique)?;
    let own = &line.tables[0];
    let mean_at = |x: f64| own.mean_at(x.clamp(lo, hi));
    let zero = mean_at(0.0f64.clamp(lo, hi));
    let relative: Vec<f64> = ends.iter().map(|&x| mean_at(x) - zero).collect();
    // the smallest magnification that keeps every increment within the value range, rounded on the
    // cumulative sum so that the errors do not add up
    let quantize = |unit: f64| -> Vec<i64> { relative.iter().map(|a| (a / unit).round() as i64).collect() };
    let increments = |s: &[i64]| -> Vec<i64> { (1..s.len()).map(|i| s[i] - s[i - 1]).collect() };
    let magnification = (1..=MAX_MAGNIFICATION)
        .find(|&mag| increments(&quantize(DETECTION_UNIT * mag as f64)).iter().all(|v| v.abs() <= MAX_VALUE))
        .ok_or_else(|| {
            CompensateError::Limit(format!(
                "Fanuc pitch-error compensation of {}: an increment exceeds {MAX_VALUE} detection units even at magnification \
                 {MAX_MAGNIFICATION} (use more --points); nothing was written",
                axis.letter
            ))
        })?;
    let unit = DETECTION_UNIT * magnification as f64;
    let sums = quantize(unit);
    let mut values = increments(&sums); // values[i] belongs to the section ends[i] -> ends[i + 1]
    if full_turn {
        // the reference point repeats the last point; the increments over the turn must close
        if sums[sums.len() - 1] != sums[0] {
            return Err(CompensateError::Limit(format!(
                "Fanuc pitch-error compensation of {} over one turn does not close ({} detection units): the error model is not periodic in {}",
                axis.letter,
                sums[sums.len() - 1] - sums[0],
                axis.letter
            )));
        }
        values.insert(0, *values.last().expect("a turn has points"));
    } else if n_neg == 0 {
        values.insert(0, 0); // the reference point's section lies below the travel
    }
    let pitch = PitchAxis {
        axis: k,
        reference_point,
        most_negative,
        most_positive,
        magnification,
        interval,
        per_turn: if full_turn { (360.0 / DETECTION_UNIT).round() as i64 } else { 0 },
        values,
    };
    debug_assert_eq!(pitch.values.len(), count);
    let applied: Vec<f64> = sums.iter().map(|s| *s as f64 * unit).collect();
    let table = AxisTable { driver: k, corrected: k, positions: ends, forward: applied.clone(), reverse: applied };
    Ok((pitch, table, zero))
}

/// The `G10 L50` program with its head comment.
fn program(m: &Machine, axes: &[PitchAxis], limits: FanucLimits) -> String {
    let mut text = String::from("%\n");
    let _ = writeln!(text, "(TRUEAXIS PITCH ERROR COMPENSATION, MACHINE {})", m.name.to_uppercase());
    let _ = writeln!(text, "(PROGRAMMABLE PARAMETER INPUT, RUN IN MDI OR MEMORY WITH PARAMETER WRITE ENABLED)");
    let _ = writeln!(text, "(ASSUMED: DETECTION UNIT 0.001 MM / 0.001 DEG, IS-B; VALUES -{MAX_VALUE} TO {MAX_VALUE};)");
    let _ = writeln!(
        text,
        "(POINT NUMBERS 0 TO {}, AT MOST {} PER AXIS; AXIS NUMBERS P1, P2, ... IN THE ORDER {})",
        limits.max_point_number,
        limits.max_points_per_axis,
        m.axis_letters()
    );
    let _ = writeln!(text, "(REFERENCE POSITION = MACHINE COORDINATE 0; MEAN OF BOTH DIRECTIONS; POWER OFF/ON AND G28 AFTER INPUT)");
    for p in axes {
        let unit = if m.axes()[p.axis].kind == AxisKind::Rotary { "DEG" } else { "MM" };
        let _ = writeln!(
            text,
            "({} P{}: POINTS {} TO {}, REFERENCE POINT {}, INTERVAL {} {unit}, MAGNIFICATION {})",
            m.axes()[p.axis].letter,
            p.axis + 1,
            p.most_negative,
            p.most_positive,
            p.reference_point,
            p.interval_user(),
            p.magnification
        );
    }
    text.push_str("G10 L50 ;\n");
    for p in axes {
        let a = p.axis + 1;
        let _ = writeln!(text, "N3620 P{a} R{} ;", p.reference_point);
        let _ = writeln!(text, "N3621 P{a} R{} ;", p.most_negative);
        let _ = writeln!(text, "N3622 P{a} R{} ;", p.most_positive);
        let _ = writeln!(text, "N3623 P{a} R{} ;", p.magnification);
        let _ = writeln!(text, "N3624 P{a} R{} ;", p.interval);
        if p.per_turn > 0 {
            let _ = writeln!(text, "N3625 P{a} R{} ;", p.per_turn);
        }
    }
    for p in axes {
        for (i, v) in p.values.iter().enumerate() {
            let _ = writeln!(text, "N{} R{v} ;", 10000 + p.most_negative + i);
        }
    }
    text.push_str("G11 ;\nM30 ;\n%\n");
    text
}
