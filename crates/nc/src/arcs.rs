//! Arc centres and their checks, as LinuxCNC 2.9 makes them (`interp_arc.cc`: `arc_data_r`,
//! `arc_data_ijk`; tolerances of `interp_internal.hh`): an R-format arc's centre on the side the
//! sign of R and the direction give, R too small by more than 0.00005 inch (0.00127 mm) refused; a
//! centre-format arc refused when its radius is zero or its start and end radii differ by more than
//! 0.0028 inch (0.028 mm, `CENTER_ARC_RADIUS_TOLERANCE`) and 0.1 %, or by 100 times that at all.
//! Coordinates are program coordinates of the plane's first and second axes, program units.

use std::f64::consts::{FRAC_PI_2, TAU};

/// LinuxCNC `RADIUS_TOLERANCE_INCH` and the millimetre value.
const RADIUS_TOLERANCE_INCH: f64 = 0.00005;
/// LinuxCNC `CENTER_ARC_RADIUS_TOLERANCE_INCH` (2 * 0.001 * sqrt 2) and `_MM` (2 * 0.01 * sqrt 2).
const SPIRAL_TOLERANCE_INCH: f64 = 2.0 * 0.001 * std::f64::consts::SQRT_2;
const SPIRAL_TOLERANCE_MM: f64 = 2.0 * 0.01 * std::f64::consts::SQRT_2;
/// LinuxCNC `SPIRAL_RELATIVE_TOLERANCE`.
const SPIRAL_RELATIVE: f64 = 0.001;

fn radius_tolerance(inch: bool) -> f64 {
    if inch {
        RADIUS_TOLERANCE_INCH
    } else {
        RADIUS_TOLERANCE_INCH * 25.4
    }
}

/// The centre of an R-format arc from `start` to `end` (program units).
pub(crate) fn centre_from_radius(clockwise: bool, start: [f64; 2], end: [f64; 2], r: f64, inch: bool) -> Result<[f64; 2], String> {
    if start == end {
        return Err("an R-format arc cannot end where it starts (a full circle needs centre words)".into());
    }
    let abs_r = r.abs();
    let mid = [(start[0] + end[0]) / 2.0, (start[1] + end[1]) / 2.0];
    let mut half = (mid[0] - end[0]).hypot(mid[1] - end[1]);
    if half - abs_r > radius_tolerance(inch) {
        return Err(format!("no arc of radius {abs_r} joins the start and end points, {} apart", 2.0 * half));
    }
    if half / abs_r > 1.0 - 1e-12 {
        half = abs_r;
    }
    let chord = (end[1] - start[1]).atan2(end[0] - start[0]);
    let theta = if clockwise == (r > 0.0) { chord - FRAC_PI_2 } else { chord + FRAC_PI_2 };
    let offset = abs_r * (half / abs_r).asin().cos();
    Ok([mid[0] + offset * theta.cos(), mid[1] + offset * theta.sin()])
}

/// Checks a centre-format arc: radius not zero, start and end radii equal within LinuxCNC's
/// tolerances.
pub(crate) fn check_centre(start: [f64; 2], end: [f64; 2], centre: [f64; 2], inch: bool) -> Result<(), String> {
    let r1 = (centre[0] - start[0]).hypot(centre[1] - start[1]);
    let r2 = (centre[0] - end[0]).hypot(centre[1] - end[1]);
    if r1 < radius_tolerance(inch) || r2 < radius_tolerance(inch) {
        return Err(format!("zero-radius arc (radius to start {r1:.4}, to end {r2:.4})"));
    }
    let spiral = if inch { SPIRAL_TOLERANCE_INCH } else { SPIRAL_TOLERANCE_MM };
    let abs_err = (r1 - r2).abs();
    let rel_err = abs_err / r1.max(r2);
    if abs_err > 100.0 * spiral || rel_err > SPIRAL_RELATIVE && abs_err > spiral {
        return Err(format!(
            "the radius to the end of the arc ({r2:.4}) differs from the radius to its start ({r1:.4}) by {abs_err:.4} ({:.3} %), more than LinuxCNC accepts ({spiral:.4} and 0.1 %)",
            rel_err * 100.0
        ));
    }
    Ok(())
}

/// The angle an arc turns through (rad, positive): less than a turn, a whole turn when start and
/// end coincide.
pub fn sweep(clockwise: bool, start: [f64; 2], end: [f64; 2], centre: [f64; 2]) -> f64 {
    if (start[0] - end[0]).abs() < 1e-12 && (start[1] - end[1]).abs() < 1e-12 {
        return TAU;
    }
    let a0 = (start[1] - centre[1]).atan2(start[0] - centre[0]);
    let a1 = (end[1] - centre[1]).atan2(end[0] - centre[0]);
    if clockwise {
        (a0 - a1).rem_euclid(TAU)
    } else {
        (a1 - a0).rem_euclid(TAU)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centres_and_checks_like_linuxcnc() {
        // G2 X10 Y0 R5 from 0,0: a half circle, centre at the middle
        let c = centre_from_radius(true, [0.0, 0.0], [10.0, 0.0], 5.0, false).unwrap();
        assert!((c[0] - 5.0).abs() < 1e-12 && c[1].abs() < 1e-12);
        // G2 with R > 0 from (0,0) to (10,10), R 10: the shorter arc, centre right of the chord
        let c = centre_from_radius(true, [0.0, 0.0], [10.0, 10.0], 10.0, false).unwrap();
        assert!((c[0] - 10.0).abs() < 1e-12 && c[1].abs() < 1e-12, "{c:?}");
        // negative R: the longer arc, centre on the other side
        let c = centre_from_radius(true, [0.0, 0.0], [10.0, 10.0], -10.0, false).unwrap();
        assert!(c[0].abs() < 1e-12 && (c[1] - 10.0).abs() < 1e-12, "{c:?}");
        assert!(centre_from_radius(true, [0.0, 0.0], [10.0, 0.0], 4.99, false).unwrap_err().contains("no arc of radius"));
        // within RADIUS_TOLERANCE: accepted as a half circle
        assert!(centre_from_radius(true, [0.0, 0.0], [10.0, 0.0], 4.9995, false).is_ok());
        // the mismatch of the sample in the LinuxCNC error message: 14.1421 vs 10
        assert!(check_centre([20.0, 10.0], [0.0, 0.0], [10.0, 0.0], false).unwrap_err().contains("differs"));
        assert!(check_centre([10.0, 0.0], [0.0, 10.0], [0.0, 0.0], false).is_ok());
        // 0.02 mm off on a 10 mm radius: 0.2 %, but under 0.028 mm: accepted
        assert!(check_centre([10.0, 0.0], [0.0, 10.02], [0.0, 0.0], false).is_ok());
        assert!(check_centre([10.0, 0.0], [0.0, 10.03], [0.0, 0.0], false).is_err());
        assert!((sweep(false, [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]) - FRAC_PI_2).abs() < 1e-12);
        assert!((sweep(true, [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]) - 3.0 * FRAC_PI_2).abs() < 1e-12);
        assert_eq!(sweep(true, [1.0, 0.0], [1.0, 0.0], [0.0, 0.0]), TAU);
    }
}
