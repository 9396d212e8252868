//! The expanded uncertainties of ISO 230-2 results against the contributors written out by hand
//! (ISO 230-2:2014 Annex A; JCGM 100 Annex E.4.3), on a test built so that every estimator of the
//! standard uncertainty of positioning is known exactly.

use trueaxis::evaluate::iso230_2::{evaluate, read_runs_from_str};
use trueaxis::evaluate::positioning_uncertainty::{positioning_uncertainty, PositioningUncertaintyInputs};

/// 5 runs at 0, 250, ..., 1000 mm; run j reads the target's mean plus (j - 3) k, so that every
/// s = k sqrt(10 / 4); a 2 um reversal; a 3 um/m scale error.
fn test_text(k: f64) -> String {
    let mut text = String::from("target,dev,dir,run\n");
    for run in 1..=5 {
        for dir in ["+", "-"] {
            for i in 0..5 {
                let target = 250.0 * i as f64;
                let mean = 3e-3 * target + if dir == "+" { 1.0 } else { -1.0 };
                text += &format!("{target},{},{dir},{run}\n", mean + (run as f64 - 3.0) * k);
            }
        }
    }
    text
}

#[test]
fn each_result_combines_the_contributors_written_out() {
    let k = 0.1;
    let data = read_runs_from_str(&test_text(k), "test").unwrap();
    let result = evaluate(&data).unwrap();
    let s = k * (10.0f64 / 4.0).sqrt();
    assert!((result.r_plus - 4.0 * s).abs() < 1e-9, "s as built: R+ = {}", result.r_plus);
    let inputs = PositioningUncertaintyInputs {
        device_um: 0.5,
        device_um_per_m: 0.7,
        temperature_k: 0.1,
        expansion_um_per_m_k: 11.5,
        expansion_fraction: 0.1,
        temperature_offset_k: -1.5,
        misalignment_um: 1.0,
        eve_um: 0.4,
    };
    let u = positioning_uncertainty(&result, &inputs, false);
    assert_eq!(u.length, 1000.0);
    // standard uncertainties at L = 1 m, written out
    let device: f64 = (0.5 + 0.7) / 2.0; // 0.6
    let thermometer: f64 = 11.5 * 1.0 * 0.1 / 2.0; // 0.575
    let expansion = 1.0 * 1.5 * 1.15 / 3f64.sqrt(); // 0.99593
    let misalignment = 1.0 / (2.0 * 3f64.sqrt()); // 0.28868
    let eve = 0.4 / (2.0 * 3f64.sqrt()); // 0.11547
    let mean = s / 5f64.sqrt(); // 0.070711
    let of_s = s / 8f64.sqrt(); // 0.055902
    let e = 2.0 * (device.powi(2) + thermometer.powi(2) + expansion.powi(2) + misalignment.powi(2) + eve.powi(2) + mean.powi(2)).sqrt();
    assert!((e - 2.671454).abs() < 1e-5, "E written out: {e}");
    assert!((u.e - e).abs() < 1e-12 && (u.m - e).abs() < 1e-12, "U(E) {} U(M) {}", u.e, u.m);
    let r = 2.0 * ((4.0 * of_s).powi(2) + eve.powi(2)).sqrt();
    assert!((u.r - r).abs() < 1e-12, "U(R) {} vs {r}", u.r);
    let b = 2.0 * (2.0 * mean.powi(2) + eve.powi(2)).sqrt();
    assert!((u.b - b).abs() < 1e-12, "U(B) {} vs {b}", u.b);
    let a = 2.0 * ((e / 2.0).powi(2) + 2.0 * (2.0 * of_s).powi(2)).sqrt();
    assert!((u.a - a).abs() < 1e-12, "U(A) {} vs {a}", u.a);
    assert_eq!(u.of("A+"), Some(u.a));
    assert_eq!(u.of("B_mean"), Some(u.b));
    // the budget lists the same standard uncertainties
    let budget: Vec<f64> = u.budget.iter().map(|c| c.standard_uncertainty).collect();
    for (got, want) in budget.iter().zip([device, thermometer, expansion, misalignment, eve, mean, of_s]) {
        assert!((got - want).abs() < 1e-12, "budget {got} vs {want}");
    }
}

#[test]
fn a_rotary_axis_has_no_thermal_or_length_terms_and_a_perfect_test_only_the_device() {
    let data = read_runs_from_str(&test_text(0.0), "test").unwrap();
    let result = evaluate(&data).unwrap();
    let inputs = PositioningUncertaintyInputs {
        device_um: 0.5,
        device_um_per_m: 0.7,
        temperature_k: 0.1,
        expansion_um_per_m_k: 11.5,
        temperature_offset_k: 3.0,
        ..Default::default()
    };
    let rotary = positioning_uncertainty(&result, &inputs, true);
    // only the device's fixed part: U = 0.5 exactly; R and B (differences at one target) are 0
    assert!((rotary.e - 0.5).abs() < 1e-12, "rotary U(E) {}", rotary.e);
    assert_eq!((rotary.r, rotary.b), (0.0, 0.0));
    let linear = positioning_uncertainty(&result, &inputs, false);
    assert!(linear.e > rotary.e + 1.0, "the thermal terms count on a linear axis: {} vs {}", linear.e, rotary.e);
    assert!(linear.e.is_finite() && linear.a.is_finite());
}
