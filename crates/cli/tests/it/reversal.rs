//! Reversal techniques (NISTIR 5236 NISTIR 5236 §3.4, eqs. 3.1-3.8) and scale thermal expansion
//! correction to 20 degC (Soons 1993 §3.2.4, §5.1.1): simulate readings from known machine and
//! artefact errors with the seed's sign conventions, reduce them, recover the known values; the
//! thermal worked examples are computed by hand in the comments.

use crate::support::{arg, json_of, trueaxis, ROOT};
use std::f64::consts::PI;
use trueaxis::instruments::{
    apparent_expansion_coefficient, best_fit_radius, correct_to_20c, flat_face_reversal, parallelism_urad, straightness_reversal,
    thermal_expansion_um, uniform_expansion_um, BestFitRadii, ExpandingBody, ReversalError, ReversalOptions, ScaleError, ScaleTemperature,
    ThermalCorrection, ThermalRun, REFERENCE_TEMPERATURE_DEGC,
};

fn assert_close(actual: f64, expected: f64, tol: f64, what: &str) {
    assert!((actual - expected).abs() <= tol, "{what}: got {actual}, expected {expected} (tolerance {tol})");
}

fn assert_all_close(actual: &[f64], expected: &[f64], tol: f64, what: &str) {
    assert_eq!(actual.len(), expected.len(), "{what}: lengths");
    for (i, (a, e)) in actual.iter().zip(expected).enumerate() {
        assert!((a - e).abs() <= tol, "{what}[{i}]: got {a}, expected {e} (tolerance {tol})");
    }
}

/// 0, step, ..., (n-1) step (mm).
fn grid(n: usize, step: f64) -> Vec<f64> {
    (0..n).map(|i| i as f64 * step).collect()
}

/// A curve orthogonal to 1 and z on a uniform grid: `c ((z - zm)^2 - mean((z - zm)^2))`. Its
/// least-squares line is exactly zero, so a known line added to it is the least-squares line.
fn orthogonal_bow(z: &[f64], c: f64) -> Vec<f64> {
    let zm = z.iter().sum::<f64>() / z.len() as f64;
    let mean_sq = z.iter().map(|v| (v - zm).powi(2)).sum::<f64>() / z.len() as f64;
    z.iter().map(|v| c * ((v - zm).powi(2) - mean_sq)).collect()
}

// ---------------------------------------------------------------------------------------------
// Straightness by arbor reversal, eqs. 3.1-3.3

#[test]
fn reversal_recovers_straightness_and_arbor_form() {
    // z = 0..300 mm; machine straightness s(z) and arbor profile a(z), um (cubic and quadratic polynomials)
    let z = grid(31, 10.0);
    let s: Vec<f64> = z.iter().map(|z| 1.5 + 0.02 * z - 1e-4 * z * z + 2e-7 * z * z * z).collect();
    let a: Vec<f64> = z.iter().map(|z| 0.8 - 0.01 * z + 3e-5 * z * z).collect();
    // eq. 3.1: m1 = a - s; eq. 3.2: m2 = a + s (arbor turned 180 deg, probe 2)
    let m1: Vec<f64> = a.iter().zip(&s).map(|(a, s)| a - s).collect();
    let m2: Vec<f64> = a.iter().zip(&s).map(|(a, s)| a + s).collect();

    let r = straightness_reversal(&z, &m1, &m2, ReversalOptions::default()).unwrap();
    assert_all_close(&r.straightness_um, &s, 1e-12, "s(z)");
    assert_all_close(&r.arbor_form_um, &a, 1e-12, "a(z)");
    assert!(r.line.is_none());

    // Swapping the probes flips the sign of s only (eq. 3.3 is m2 - m1).
    let swapped = straightness_reversal(&z, &m2, &m1, ReversalOptions::default()).unwrap();
    let minus_s: Vec<f64> = s.iter().map(|v| -v).collect();
    assert_all_close(&swapped.straightness_um, &minus_s, 1e-12, "-s(z)");
    assert_all_close(&swapped.arbor_form_um, &a, 1e-12, "a(z), swapped");
}

#[test]
fn reversal_best_fit_line_removed_and_reported() {
    // z = 0..300 mm, centre 150 mm, mean (z - 150)^2 = 8000 mm^2; the bow goes from -0.8 um (z = 150)
    // to +1.45 um (ends): 2.25 um peak to valley
    let z = grid(31, 10.0);
    let bow = orthogonal_bow(&z, 1e-4);
    // s = line (35 urad = 0.035 um/mm, 1.2 um at z = 0) + bow
    let s: Vec<f64> = z.iter().zip(&bow).map(|(z, b)| 1.2 + 0.035 * z + b).collect();
    let a: Vec<f64> = z.iter().map(|z| 0.3 + 4e-3 * z).collect();
    let m1: Vec<f64> = a.iter().zip(&s).map(|(a, s)| a - s).collect();
    let m2: Vec<f64> = a.iter().zip(&s).map(|(a, s)| a + s).collect();

    let r = straightness_reversal(&z, &m1, &m2, ReversalOptions { remove_line: true }).unwrap();
    let line = r.line.unwrap();
    assert_close(line.slope_urad, 35.0, 1e-9, "slope (urad)");
    assert_close(line.intercept_um, 1.2, 1e-12, "intercept (um)");
    assert_close(line.value_um(300.0), 1.2 + 10.5, 1e-12, "line at 300 mm");
    assert_all_close(&r.straightness_um, &bow, 1e-12, "best-fit straightness");
    assert_close(r.straightness_deviation_um(), 1e-4 * 22500.0, 1e-12, "straightness deviation (um)");
    assert_all_close(&r.arbor_form_um, &a, 1e-12, "a(z) untouched by the line removal");
}

// ---------------------------------------------------------------------------------------------
// Parallelism from best-fit circle radii, eqs. 3.4-3.5

#[test]
fn best_fit_radius_is_the_mean() {
    // (1 + 2 + 3 + 6) / 4 = 3 (eq. 3.4)
    assert_close(best_fit_radius(&[1.0, 2.0, 3.0, 6.0]).unwrap(), 3.0, 1e-15, "R");
}

#[test]
fn parallelism_from_hand_radii() {
    // R11 = 1.0, R21 = 11.5, R12 = 5.0, R22 = 0.5, dz = 300 mm:
    // [(11.5 - 1.0) - (0.5 - 5.0)] / (2 * 300) = 15 / 600 = 0.025 um/mm = 25 urad (eq. 3.5)
    let radii = BestFitRadii { probe1_location1_um: 1.0, probe1_location2_um: 11.5, probe2_location1_um: 5.0, probe2_location2_um: 0.5 };
    assert_close(parallelism_urad(&radii, 300.0).unwrap(), 25.0, 1e-12, "alpha_p");
    // measuring from location 2 to location 1 (dz negative) gives the same slope
    let reversed = BestFitRadii { probe1_location1_um: 11.5, probe1_location2_um: 1.0, probe2_location1_um: 0.5, probe2_location2_um: 5.0 };
    assert_close(parallelism_urad(&reversed, -300.0).unwrap(), 25.0, 1e-12, "alpha_p, reversed");
}

#[test]
fn parallelism_recovers_known_tilt_despite_taper_runout_and_roundness() {
    let n = 512; // readings per revolution, as in the seed
    let dz = 300.0; // mm between the two locations, as in the seed
    let alpha = 25.0; // urad: spindle axis moves towards probe 1 by 0.025 um per mm of z
    let shift = |z: f64| -3.0 + alpha * 1e-3 * z; // spindle axis towards probe 1, um
    let taper = |z: f64| 2.0 + 0.01 * z; // arbor radius deviation, um (common to both probes)
    let roundness = |t: f64| 0.4 * (3.0 * t + 0.3).cos() - 0.2 * (5.0 * t).sin(); // um, arbor form
                                                                                  // one revolution of "radius" readings (grow when the surface approaches the probe):
                                                                                  // probe 1 sees +shift, probe 2 (180 deg away) sees -shift; eccentric runout e cos(theta + phi)
    let revolution = |z: f64, probe: usize, ecc: f64, phase: f64, offset: f64| -> Vec<f64> {
        (0..n)
            .map(|i| {
                let theta = 2.0 * PI * i as f64 / n as f64 + if probe == 2 { PI } else { 0.0 };
                let sign = if probe == 1 { 1.0 } else { -1.0 };
                offset + taper(z) + sign * shift(z) + ecc * (theta + phase).cos() + roundness(theta)
            })
            .collect()
    };
    let (z1, z2) = (0.0, dz);
    let radii = BestFitRadii::from_readings(
        &revolution(z1, 1, 4.0, 0.2, 10.0),
        &revolution(z2, 1, 6.5, 0.25, 10.0),
        &revolution(z1, 2, 4.0, 0.2, -7.0),
        &revolution(z2, 2, 6.5, 0.25, -7.0),
    )
    .unwrap();
    // each radius: offset + taper +- shift (runout and roundness average out over the revolution)
    assert_close(radii.probe1_location1_um, 10.0 + 2.0 - 3.0, 1e-12, "R11");
    assert_close(radii.probe1_location2_um, 10.0 + 5.0 + 4.5, 1e-12, "R21");
    assert_close(radii.probe2_location1_um, -7.0 + 2.0 + 3.0, 1e-12, "R12");
    assert_close(radii.probe2_location2_um, -7.0 + 5.0 - 4.5, 1e-12, "R22");
    assert_close(parallelism_urad(&radii, dz).unwrap(), alpha, 1e-9, "alpha_p (urad)");
}

// ---------------------------------------------------------------------------------------------
// Flat-face disk, eqs. 3.6-3.8

#[test]
fn flat_face_recovers_orthogonality_straightness_and_face_error() {
    let x = grid(31, 5.0); // 0..150 mm
    let bow = orthogonal_bow(&x, -2e-4);
    // delta_z(x) = 0.3 um + alpha_o x + bow, alpha_o = 20 urad = 0.02 um/mm
    let delta_z: Vec<f64> = x.iter().zip(&bow).map(|(x, b)| 0.3 + 0.02 * x + b).collect();
    // face squareness + misalignment (turns with the spindle): 0.05 um/mm, with a little form
    let e: Vec<f64> = x.iter().map(|x| -0.7 + 0.05 * x + 1e-5 * x * x).collect();
    // eq. 3.6: m1 = -delta_z + e; eq. 3.7: m2 = -delta_z - e
    let m1: Vec<f64> = delta_z.iter().zip(&e).map(|(d, e)| -d + e).collect();
    let m2: Vec<f64> = delta_z.iter().zip(&e).map(|(d, e)| -d - e).collect();

    let r = flat_face_reversal(&x, &m1, &m2).unwrap();
    assert_all_close(&r.delta_z_um, &delta_z, 1e-12, "delta_z");
    assert_all_close(&r.face_error_um, &e, 1e-12, "e");
    assert_close(r.orthogonality_urad(), 20.0, 1e-9, "alpha_o (urad)");
    assert_close(r.line.intercept_um, 0.3, 1e-12, "intercept");
    assert_all_close(&r.straightness_um, &bow, 1e-12, "delta'_z");
    // bow: -2e-4 ((x - 75)^2 - mean), range 2e-4 * 75^2 = 1.125 um
    assert_close(r.straightness_deviation_um(), 1.125, 1e-12, "straightness deviation");
}

// ---------------------------------------------------------------------------------------------
// Scale thermal expansion to 20 degC

#[test]
fn uniform_expansion_worked_example() {
    assert_eq!(REFERENCE_TEMPERATURE_DEGC, 20.0);
    // steel scale 11.5 um/m/K at 25.3 degC over 500 mm: 11.5 * 5.3 * 0.5 = 30.475 um
    assert_close(uniform_expansion_um(11.5, 25.3, 500.0), 30.475, 1e-9, "E");
    // Soons 1993 X scale, 9.75 um/m/K at 20.4 degC over 700 mm: 9.75 * 0.4 * 0.7 = 2.73 um
    assert_close(uniform_expansion_um(9.75, 20.4, 700.0), 2.73, 1e-9, "E");
    // below 20 degC the body is shorter: 11.5 * (-2) * 0.1 = -2.3 um
    assert_close(uniform_expansion_um(11.5, 18.0, 100.0), -2.3, 1e-12, "E");
}

#[test]
fn machine_scale_correction_worked_example() {
    // Warm steel scale (11.5 um/m/K, 25.3 degC, fixed point at 0): it reads short, the laser sees the
    // slide 15.2375 um long at 250 mm (11.5 * 5.3 * 0.25) and 30.475 um long at 500 mm; measured
    // deviations 0, 16.0, 32.0 um become 0, 16.0 - 15.2375 = 0.7625, 32.0 - 30.475 = 1.525 um.
    let x = [0.0, 250.0, 500.0];
    let c = ThermalCorrection {
        body: ExpandingBody::MachineScale,
        alpha_um_per_m_k: 11.5,
        temperature: ScaleTemperature::Uniform(25.3),
        datum_mm: 0.0,
    };
    let dev20 = correct_to_20c(&x, &[0.0, 16.0, 32.0], &c).unwrap();
    assert_all_close(&dev20, &[0.0, 0.7625, 1.525], 1e-9, "dev_20, machine scale");

    // fixed point at 100 mm: 500 mm is 400 mm away, 11.5 * 5.3 * 0.4 = 24.38 um; 0 mm is -100 mm
    // away, 11.5 * 5.3 * (-0.1) = -6.095 um
    let e = thermal_expansion_um(&[0.0, 100.0, 500.0], 11.5, &ScaleTemperature::Uniform(25.3), 100.0).unwrap();
    assert_all_close(&e, &[-6.095, 0.0, 24.38], 1e-9, "E about a datum at 100 mm");
}

#[test]
fn reference_artefact_correction_worked_example() {
    // Warm steel step gauge (11.5 um/m/K, 25.3 degC, zero face at 0) on a perfect machine at 20
    // degC: the 500 mm face is really at 500.030475 mm, the machine reads that, and the deviation
    // (gauge value minus machine reading) is -30.475 um; corrected: 0.
    let x = [0.0, 250.0, 500.0];
    let c = ThermalCorrection {
        body: ExpandingBody::Reference,
        alpha_um_per_m_k: 11.5,
        temperature: ScaleTemperature::Uniform(25.3),
        datum_mm: 0.0,
    };
    let dev20 = correct_to_20c(&x, &[0.0, -15.2375, -30.475], &c).unwrap();
    assert_all_close(&dev20, &[0.0, 0.0, 0.0], 1e-9, "dev_20, reference");
    // the same correction with the opposite sign of the machine-scale one
    let scale = ThermalCorrection { body: ExpandingBody::MachineScale, ..c };
    let a = correct_to_20c(&x, &[1.0, 2.0, 3.0], &c).unwrap();
    let b = correct_to_20c(&x, &[1.0, 2.0, 3.0], &scale).unwrap();
    assert_all_close(&a, &[1.0, 2.0 + 15.2375, 3.0 + 30.475], 1e-9, "reference");
    assert_all_close(&b, &[1.0, 2.0 - 15.2375, 3.0 - 30.475], 1e-9, "machine scale");
}

#[test]
fn per_point_temperatures() {
    // 9.75 um/m/K; points at 0, 250, 500 mm read at 20, 22, 24 degC:
    // 0; 9.75 * 2 * 0.25 = 4.875; 9.75 * 4 * 0.5 = 19.5 um
    let temps = [20.0, 22.0, 24.0];
    let e = thermal_expansion_um(&[0.0, 250.0, 500.0], 9.75, &ScaleTemperature::PerPoint(&temps), 0.0).unwrap();
    assert_all_close(&e, &[0.0, 4.875, 19.5], 1e-9, "E per point");
}

#[test]
fn sensors_along_the_scale_are_interpolated_and_integrated() {
    // Three Pt-100 (Soons 1993) at 0, 250, 500 mm reading 21, 24, 22 degC; 11.5 um/m/K = 0.0115 um/(mm K).
    // E(x) = 0.0115 * integral_0^x (T(u) - 20) du, T linear between sensors, constant outside:
    //   x = 125: T(125) = 22.5, 125 * ((21 + 22.5)/2 - 20) = 218.75 K mm -> 2.515625 um
    //   x = 250: 250 * ((21 + 24)/2 - 20) = 625                           -> 7.1875 um
    //   x = 375: T(375) = 23, 625 + 125 * ((24 + 23)/2 - 20) = 1062.5     -> 12.21875 um
    //   x = 500: 625 + 250 * ((24 + 22)/2 - 20) = 1375                    -> 15.8125 um
    //   x = 600: 1375 + 100 * (22 - 20) = 1575                            -> 18.1125 um
    //   x = -50: -50 * (21 - 20) = -50                                    -> -0.575 um
    let sx = [0.0, 250.0, 500.0];
    let st = [21.0, 24.0, 22.0];
    let t = ScaleTemperature::Sensors { positions_mm: &sx, temperatures_degc: &st };
    let x = [125.0, 250.0, 375.0, 500.0, 600.0, -50.0];
    let e = thermal_expansion_um(&x, 11.5, &t, 0.0).unwrap();
    assert_all_close(&e, &[2.515625, 7.1875, 12.21875, 15.8125, 18.1125, -0.575], 1e-9, "E from sensors");
    // datum at 250 mm: subtract E(250) = 7.1875
    let e = thermal_expansion_um(&[0.0, 500.0], 11.5, &t, 250.0).unwrap();
    assert_all_close(&e, &[-7.1875, 15.8125 - 7.1875], 1e-9, "E from sensors about 250 mm");

    // equal sensors, or a single sensor, are a uniform temperature
    let x = grid(15, 50.0);
    let uniform = thermal_expansion_um(&x, 11.5, &ScaleTemperature::Uniform(23.7), 120.0).unwrap();
    let flat = [23.7, 23.7, 23.7];
    let equal = thermal_expansion_um(&x, 11.5, &ScaleTemperature::Sensors { positions_mm: &sx, temperatures_degc: &flat }, 120.0).unwrap();
    let single =
        thermal_expansion_um(&x, 11.5, &ScaleTemperature::Sensors { positions_mm: &[300.0], temperatures_degc: &[23.7] }, 120.0).unwrap();
    assert_all_close(&equal, &uniform, 1e-12, "equal sensors");
    assert_all_close(&single, &uniform, 1e-12, "single sensor");
}

/// Scale error at 20 degC over the Soons 1993 X axis (0..700 mm): -15 um offset (the "suspicious"
/// value), a trend, a bow.
fn scale_error_20(x: f64) -> f64 {
    -15.0 + 0.012 * x - 1.5e-5 * x * x
}

#[test]
fn apparent_coefficient_seed_000_example() {
    // True (apparent) coefficient 13.5 um/m/K, manufacturer's 9.75; average scale temperatures
    // 25.3 and 20.4 degC (Soons 1993 §5.1.1, Fig. 5.2). Fixed point at 0; run 2 homed 0.7 um off.
    let x = grid(71, 10.0);
    let alpha_true = 13.5;
    let run = |t: f64, shift: f64| -> Vec<f64> {
        x.iter().map(|&x| scale_error_20(x) + uniform_expansion_um(alpha_true, t, x) + shift).collect()
    };
    let warm = run(25.3, 0.0);
    let cold = run(20.4, 0.7);

    // raw runs (no correction applied)
    let r = apparent_expansion_coefficient(
        &x,
        &ThermalRun { deviations_um: &warm, temperature: ScaleTemperature::Uniform(25.3) },
        &ThermalRun { deviations_um: &cold, temperature: ScaleTemperature::Uniform(20.4) },
        0.0,
        0.0,
    )
    .unwrap();
    assert_close(r.alpha_um_per_m_k, 13.5, 1e-9, "apparent alpha from raw runs");
    assert_close(r.offset_um, -0.7, 1e-9, "offset");
    assert!(r.residual_rms_um < 1e-9, "residual {}", r.residual_rms_um);

    // runs corrected with the manufacturer's 9.75 um/m/K, as in Fig. 5.2: they still disagree by
    // (13.5 - 9.75) * (25.3 - 20.4) * 0.7 = 12.8625 um over 700 mm
    let corrected = |dev: &[f64], t: f64| {
        let c = ThermalCorrection {
            body: ExpandingBody::MachineScale,
            alpha_um_per_m_k: 9.75,
            temperature: ScaleTemperature::Uniform(t),
            datum_mm: 0.0,
        };
        correct_to_20c(&x, dev, &c).unwrap()
    };
    let warm20 = corrected(&warm, 25.3);
    let cold20 = corrected(&cold, 20.4);
    let spread = |i: usize| warm20[i] - cold20[i];
    assert_close(spread(70) - spread(0), 12.8625, 1e-9, "corrected runs' disagreement over 700 mm");
    let r = apparent_expansion_coefficient(
        &x,
        &ThermalRun { deviations_um: &warm20, temperature: ScaleTemperature::Uniform(25.3) },
        &ThermalRun { deviations_um: &cold20, temperature: ScaleTemperature::Uniform(20.4) },
        0.0,
        9.75,
    )
    .unwrap();
    assert_close(r.alpha_um_per_m_k, 13.5, 1e-9, "apparent alpha from corrected runs");
}

#[test]
fn apparent_coefficient_with_sensors_and_per_point_temperatures() {
    let x = grid(71, 10.0);
    let alpha_true = 11.2;
    // three sensors at the start, middle and end of the scale, datum (fixed point) at 350 mm
    let sx = [0.0, 350.0, 700.0];
    let warm_t = [25.0, 25.6, 25.3];
    let cold_t = [20.2, 20.6, 20.4];
    let warm_temp = ScaleTemperature::Sensors { positions_mm: &sx, temperatures_degc: &warm_t };
    let cold_temp = ScaleTemperature::Sensors { positions_mm: &sx, temperatures_degc: &cold_t };
    let simulate = |t: &ScaleTemperature| -> Vec<f64> {
        let e = thermal_expansion_um(&x, alpha_true, t, 350.0).unwrap();
        x.iter().zip(&e).map(|(&x, e)| scale_error_20(x) + e).collect()
    };
    let warm = simulate(&warm_temp);
    let cold = simulate(&cold_temp);
    let r = apparent_expansion_coefficient(
        &x,
        &ThermalRun { deviations_um: &warm, temperature: warm_temp },
        &ThermalRun { deviations_um: &cold, temperature: cold_temp },
        350.0,
        0.0,
    )
    .unwrap();
    assert_close(r.alpha_um_per_m_k, alpha_true, 1e-9, "apparent alpha, sensors");

    // per-point temperatures drifting during each run
    let warm_pp: Vec<f64> = (0..x.len()).map(|i| 24.8 + 0.01 * i as f64).collect();
    let cold_pp: Vec<f64> = (0..x.len()).map(|i| 20.9 - 0.004 * i as f64).collect();
    let warm = simulate(&ScaleTemperature::PerPoint(&warm_pp));
    let cold = simulate(&ScaleTemperature::PerPoint(&cold_pp));
    let r = apparent_expansion_coefficient(
        &x,
        &ThermalRun { deviations_um: &warm, temperature: ScaleTemperature::PerPoint(&warm_pp) },
        &ThermalRun { deviations_um: &cold, temperature: ScaleTemperature::PerPoint(&cold_pp) },
        350.0,
        0.0,
    )
    .unwrap();
    assert_close(r.alpha_um_per_m_k, alpha_true, 1e-9, "apparent alpha, per point");
}

// ---------------------------------------------------------------------------------------------
// Error messages

#[test]
fn reversal_errors() {
    let opts = ReversalOptions::default();
    let e = straightness_reversal(&[0.0, 1.0, 2.0], &[0.0, 1.0, 2.0], &[0.0, 1.0], opts).unwrap_err();
    assert!(matches!(e, ReversalError::LengthMismatch { .. }));
    assert_eq!(
        e.to_string(),
        "reversal straightness: positions has 3 values but m2 (probe 2 readings, arbor reversed) has 2; \
         they must be taken at the same positions"
    );
    let e = straightness_reversal(&[0.0], &[0.0], &[0.0], opts).unwrap_err();
    assert_eq!(e.to_string(), "reversal straightness: needs at least 2 points, got 1");
    let e = straightness_reversal(&[0.0, 1.0, 2.0], &[0.0, 1.0, f64::NAN], &[0.0, 1.0, 2.0], opts).unwrap_err();
    assert_eq!(e.to_string(), "reversal straightness: m1 (probe 1 readings)[2] is not a finite number (NaN)");
    let e = straightness_reversal(&[0.0, f64::INFINITY], &[0.0, 1.0], &[0.0, 1.0], opts).unwrap_err();
    assert_eq!(e.to_string(), "reversal straightness: positions[1] is not a finite number (inf)");
    let e = straightness_reversal(&[5.0, 5.0], &[0.0, 1.0], &[0.0, 1.0], ReversalOptions { remove_line: true }).unwrap_err();
    assert_eq!(e.to_string(), "reversal straightness: all positions are equal (5 mm), so no least-squares line can be fitted");
    // without line removal, equal positions are accepted (repeated readings)
    assert!(straightness_reversal(&[5.0, 5.0], &[0.0, 1.0], &[0.0, 1.0], opts).is_ok());

    let e = best_fit_radius(&[1.0, 2.0]).unwrap_err();
    assert_eq!(e.to_string(), "best-fit radius: needs at least 3 points, got 2");
    let e = best_fit_radius(&[1.0, f64::NAN, 2.0]).unwrap_err();
    assert_eq!(e.to_string(), "best-fit radius: readings[1] is not a finite number (NaN)");

    let radii = BestFitRadii { probe1_location1_um: 0.0, probe1_location2_um: 1.0, probe2_location1_um: 0.0, probe2_location2_um: 1.0 };
    let e = parallelism_urad(&radii, 0.0).unwrap_err();
    assert_eq!(e.to_string(), "parallelism: the distance dz between the two locations must be finite and non-zero, got 0 mm");
    assert!(matches!(parallelism_urad(&radii, f64::NAN), Err(ReversalError::InvalidDistance(_))));
    let bad = BestFitRadii { probe2_location2_um: f64::NAN, ..radii };
    let e = parallelism_urad(&bad, 300.0).unwrap_err();
    assert_eq!(e.to_string(), "parallelism: radii [R11, R21, R12, R22][3] is not a finite number (NaN)");

    let e = flat_face_reversal(&[0.0, 1.0], &[0.0, 1.0, 2.0], &[0.0, 1.0]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "flat-face reversal: positions has 2 values but m1 (first scan) has 3; they must be taken at the same positions"
    );
    let e = flat_face_reversal(&[3.0, 3.0, 3.0], &[0.0, 1.0, 2.0], &[0.0, 1.0, 2.0]).unwrap_err();
    assert_eq!(e.to_string(), "flat-face reversal: all positions are equal (3 mm), so no least-squares line can be fitted");
    let e = flat_face_reversal(&[0.0, 1.0], &[0.0, 1.0], &[f64::NEG_INFINITY, 1.0]).unwrap_err();
    assert_eq!(e.to_string(), "flat-face reversal: m2 (spindle turned 180 deg)[0] is not a finite number (-inf)");
}

#[test]
fn scale_errors() {
    let x = [0.0, 250.0, 500.0];
    let c = |t| ThermalCorrection { body: ExpandingBody::MachineScale, alpha_um_per_m_k: 11.5, temperature: t, datum_mm: 0.0 };

    let e = correct_to_20c(&x, &[0.0, 1.0], &c(ScaleTemperature::Uniform(25.0))).unwrap_err();
    assert!(matches!(e, ScaleError::LengthMismatch { .. }));
    assert_eq!(e.to_string(), "scale thermal correction: positions has 3 values but deviations has 2; they must match");
    let e = correct_to_20c(&x, &[0.0, 1.0, 2.0], &c(ScaleTemperature::PerPoint(&[20.0, 21.0]))).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: positions has 3 values but point temperatures has 2; they must match");
    let e = correct_to_20c(&x, &[0.0, f64::NAN, 2.0], &c(ScaleTemperature::Uniform(25.0))).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: deviations[1] is not a finite number (NaN)");
    let e = correct_to_20c(&x, &[0.0, 1.0, 2.0], &c(ScaleTemperature::Uniform(f64::NAN))).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: temperature (degC) is not a finite number (NaN)");
    let bad_alpha = ThermalCorrection { alpha_um_per_m_k: f64::INFINITY, ..c(ScaleTemperature::Uniform(25.0)) };
    let e = correct_to_20c(&x, &[0.0, 1.0, 2.0], &bad_alpha).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: expansion coefficient (um/m/K) is not a finite number (inf)");
    let e = thermal_expansion_um(&[], 11.5, &ScaleTemperature::Uniform(25.0), 0.0).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: no positions given");
    let e = thermal_expansion_um(&x, 11.5, &ScaleTemperature::PerPoint(&[20.0, 21.0, f64::NAN]), 0.0).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: point temperatures[2] is not a finite number (NaN)");

    // sensors
    let sensors = |p: &'static [f64], t: &'static [f64]| ScaleTemperature::Sensors { positions_mm: p, temperatures_degc: t };
    let e = thermal_expansion_um(&x, 11.5, &sensors(&[0.0, 500.0, 250.0], &[20.0, 21.0, 22.0]), 0.0).unwrap_err();
    assert!(matches!(e, ScaleError::SensorsOutOfOrder { index: 2, .. }));
    assert_eq!(
        e.to_string(),
        "scale thermal correction: sensor positions must be strictly increasing along the axis, \
         but sensor 2 at 250 mm is not after sensor 1 at 500 mm"
    );
    let e = thermal_expansion_um(&x, 11.5, &sensors(&[0.0, 0.0], &[20.0, 21.0]), 0.0).unwrap_err();
    assert!(matches!(e, ScaleError::SensorsOutOfOrder { index: 1, .. }));
    let e = thermal_expansion_um(&x, 11.5, &sensors(&[0.0, 500.0], &[20.0]), 0.0).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: sensor positions has 2 values but sensor temperatures has 1; they must match");
    let e = thermal_expansion_um(&x, 11.5, &sensors(&[], &[]), 0.0).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: no temperature sensors given (at least one position and temperature are needed)");
    let e = thermal_expansion_um(&x, 11.5, &sensors(&[0.0, 500.0], &[20.0, f64::NAN]), 0.0).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: sensor temperatures[1] is not a finite number (NaN)");
    let e = thermal_expansion_um(&x, 11.5, &ScaleTemperature::Uniform(25.0), f64::NAN).unwrap_err();
    assert_eq!(e.to_string(), "scale thermal correction: datum position (mm) is not a finite number (NaN)");

    // apparent coefficient
    let d = [0.0, 1.0, 2.0];
    fn run(dev: &[f64], t: f64) -> ThermalRun<'_> {
        ThermalRun { deviations_um: dev, temperature: ScaleTemperature::Uniform(t) }
    }
    let e = apparent_expansion_coefficient(&x, &run(&[0.0, 1.0], 25.0), &run(&d, 20.0), 0.0, 0.0).unwrap_err();
    assert_eq!(e.to_string(), "apparent expansion coefficient: positions has 3 values but run 1 deviations has 2; they must match");
    let e = apparent_expansion_coefficient(&x, &run(&d, 25.0), &run(&[0.0, 1.0, 2.0, 3.0], 20.0), 0.0, 0.0).unwrap_err();
    assert_eq!(e.to_string(), "apparent expansion coefficient: positions has 3 values but run 2 deviations has 4; they must match");
    let e = apparent_expansion_coefficient(&[0.0], &run(&[0.0], 25.0), &run(&[0.0], 20.0), 0.0, 0.0).unwrap_err();
    assert_eq!(e.to_string(), "apparent expansion coefficient: needs at least 2 points, got 1");
    let e = apparent_expansion_coefficient(&x, &run(&d, 22.0), &run(&d, 22.0), 0.0, 0.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "apparent expansion coefficient: the two runs have the same thermal expansion at every position \
         (equal temperatures, or all positions equal), so the expansion coefficient cannot be estimated"
    );
    let e = apparent_expansion_coefficient(&[7.0, 7.0, 7.0], &run(&d, 25.0), &run(&d, 20.0), 0.0, 0.0).unwrap_err();
    assert!(matches!(e, ScaleError::NoTemperatureContrast { .. }));
    let e = apparent_expansion_coefficient(&x, &run(&d, 25.0), &run(&d, 20.0), 0.0, f64::NAN).unwrap_err();
    assert_eq!(e.to_string(), "apparent expansion coefficient: applied expansion coefficient (um/m/K) is not a finite number (NaN)");
    let e = apparent_expansion_coefficient(&x, &run(&d, 25.0), &run(&[0.0, f64::NAN, 1.0], 20.0), 0.0, 0.0).unwrap_err();
    assert_eq!(e.to_string(), "apparent expansion coefficient: run 2 deviations[1] is not a finite number (NaN)");
}

// ---- the `trueaxis reversal` command on the shipped examples (examples/data/reversal_*.csv, whose
// comment lines give the simulated truth), against the closed forms and the library ----

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// The position, m1, m2 columns of a shipped example.
fn scans(path: &str) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let t = trueaxis::data::CsvTable::read(std::path::Path::new(ROOT).join(path)).unwrap();
    (t.numbers("position").unwrap(), t.numbers("m1").unwrap(), t.numbers("m2").unwrap())
}

#[test]
fn reversal_arbor_command_gives_the_simulated_straightness() {
    let doc = json_of(&["reversal", "arbor", "examples/data/reversal_arbor.csv", "--remove-line", "--json"]);
    let (z, m1, m2) = scans("examples/data/reversal_arbor.csv");
    // s = (m2 - m1) / 2 (eq. 3.3) minus its line: the simulated bow 6e-5 (z - 150)^2 minus its mean
    // (its line has zero slope on the symmetric grid); the readings are rounded to 1e-4 um
    let s = numbers(&doc["straightness_um"]);
    let mean_bow = z.iter().map(|z| 6e-5 * (z - 150.0).powi(2)).sum::<f64>() / z.len() as f64;
    for (i, z) in z.iter().enumerate() {
        assert_close(s[i], 6e-5 * (z - 150.0).powi(2) - mean_bow, 1e-4, "straightness");
        assert_close(numbers(&doc["arbor_form_um"])[i], 0.5 * (m1[i] + m2[i]), 1e-12, "arbor form = (m1 + m2) / 2");
    }
    assert_close(doc["line"]["slope_urad"].as_f64().unwrap(), 4.0, 1e-3, "slope (urad)");
    assert_close(doc["straightness_deviation_um"].as_f64().unwrap(), 6e-5 * (150f64.powi(2) - 10f64.powi(2)), 2e-4, "deviation");
    // the same as the library
    let lib = straightness_reversal(&z, &m1, &m2, ReversalOptions { remove_line: true }).unwrap();
    assert_all_close(&s, &lib.straightness_um, 1e-12, "command = library");
    // without --remove-line: s = (m2 - m1) / 2 itself, and no line
    let raw = json_of(&["reversal", "arbor", "examples/data/reversal_arbor.csv", "--json"]);
    let expected: Vec<f64> = m1.iter().zip(&m2).map(|(a, b)| 0.5 * (b - a)).collect();
    assert_all_close(&numbers(&raw["straightness_um"]), &expected, 1e-12, "s = (m2 - m1) / 2");
    assert!(raw["line"].is_null());
}

#[test]
fn reversal_parallelism_and_disk_commands_give_the_simulated_values() {
    let doc = json_of(&["reversal", "parallelism", "examples/data/reversal_parallelism.csv", "--dz", "200", "--json"]);
    // runout and out-of-roundness average out over the 512 readings of a revolution (to 1e-6 um rounding)
    for (key, want) in [("R11", 20.0), ("R21", 22.5), ("R12", 18.0), ("R22", 15.5)] {
        assert_close(doc["radii_um"][key].as_f64().unwrap(), want, 1e-6, key);
    }
    // alpha_p = [(22.5 - 20) - (15.5 - 18)] / (2 * 200) um/mm = 12.5 urad (eq. 3.5)
    assert_close(doc["parallelism_urad"].as_f64().unwrap(), 12.5, 1e-5, "alpha_p");
    let reversed = json_of(&["reversal", "parallelism", "examples/data/reversal_parallelism.csv", "--dz", "-200", "--json"]);
    assert_close(reversed["parallelism_urad"].as_f64().unwrap(), -12.5, 1e-5, "alpha_p with dz reversed");

    let disk = json_of(&["reversal", "disk", "examples/data/reversal_disk.csv", "--json"]);
    let (x, m1, m2) = scans("examples/data/reversal_disk.csv");
    assert_close(disk["orthogonality_urad"].as_f64().unwrap(), 8.0, 1e-3, "orthogonality (eq. 3.8 line)");
    assert_close(disk["straightness_deviation_um"].as_f64().unwrap(), 0.675, 2e-4, "straightness deviation");
    let dz = numbers(&disk["delta_z_um"]);
    let e = numbers(&disk["face_error_um"]);
    for i in 0..x.len() {
        assert_close(dz[i], -0.5 * (m1[i] + m2[i]), 1e-12, "delta_z = -(m1 + m2) / 2");
        assert_close(e[i], 0.5 + 0.02 * x[i], 1e-4, "face error");
    }
}

#[test]
fn reversal_command_text_plot_and_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let plot = dir.path().join("arbor.svg");
    let out = trueaxis(&["reversal", "arbor", "examples/data/reversal_arbor.csv", "--remove-line", "--plot", arg(&plot)]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("slope 4.000 urad") && text.contains("straightness deviation"), "{text}");
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("straightness s"));

    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "position,m1\n0,1\n10,2\n").unwrap();
    let huge = dir.path().join("huge.csv");
    std::fs::write(&huge, "position,m1,m2\n0,1e308,-1e308\n10,-1e308,1e308\n").unwrap();
    let cases: Vec<(Vec<&str>, i32, &str)> = vec![
        (vec!["reversal", "arbor", arg(&bad)], 2, "missing column `m2`"),
        (vec!["reversal", "disk", "examples/data/reversal_arbor.csv", "--position", "x"], 2, "missing column `x`"),
        (vec!["reversal", "parallelism", "examples/data/reversal_parallelism.csv", "--dz", "0"], 2, "distance dz"),
        (vec!["reversal", "parallelism", "examples/data/reversal_arbor.csv", "--dz", "10"], 2, "missing column `probe1_location1`"),
        (vec!["reversal", "arbor", arg(&huge), "--json"], 1, "overflowed"),
        (vec!["reversal", "disk", "missing.csv"], 2, "missing.csv"),
    ];
    for (args, code, fragment) in cases {
        let out = trueaxis(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {err}");
        assert!(err.contains(fragment), "{args:?}: expected `{fragment}` in {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
        assert!(out.stdout.is_empty(), "nothing printed on failure");
    }
}
