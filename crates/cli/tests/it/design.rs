//! The units of the design criteria of `design optimal`: on the 2D CMM of Soons 1993 §4.4 (squareness
//! in urad, two scale errors in um/mm, 400 mm bars, sigma 1 um) the D-optimal six bars have
//! D = 2.5e-3 in (urad^2 (um/mm)^2 (um/mm)^2)^(1/3), which is 1e-2 times that, 2.5e-5, in Soons 1993's
//! units (rad, mm/mm, sigma = 1 mm): the value of its Table 4.1 design 3.

use crate::support::{json, trueaxis};

#[test]
fn criteria_state_their_units_and_seed_000_values() {
    let six_bars = [
        "design",
        "optimal",
        "--machine",
        "examples/machines/cmm2d.toml",
        "--campaign",
        "examples/campaigns/cmm2d/campaign.toml",
        "--count",
        "6",
    ];
    let doc = json(&trueaxis(&[&six_bars[..], &["--json"]].concat()));
    let d = doc["criteria"]["d"].as_f64().unwrap();
    assert!((d / 2.5e-3 - 1.0).abs() < 1e-6, "{d}");
    let units = &doc["units"];
    assert_eq!(units["d"], "(urad^2 (um/mm)^2 (um/mm)^2)^(1/3)");
    assert!(units["a"].is_null() && units["e"].is_null(), "A and E mix units here");
    assert_eq!(units["parameters"]["EC0Y"], "urad");
    assert_eq!(units["parameters"]["EXX[1]"], "um/mm");
    assert!((units["seed000"]["d_factor"].as_f64().unwrap() - 1e-2).abs() < 1e-15);
    assert!((units["seed000"]["d"].as_f64().unwrap() / 2.5e-5 - 1.0).abs() < 1e-6);
    // the readable output says the same
    let out = trueaxis(&six_bars);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("D in (urad^2 (um/mm)^2 (um/mm)^2)^(1/3)") && text.contains("D x 1.0000e-2 = 2.5000e-5"), "{text}");
}
