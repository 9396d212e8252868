//! The miniaturisation case of Zhu 2008 appendix B.2 (three-axis machine P_T G_R X Y Z T_L, cubic
//! parts of 10 to 300 mm, 21 equal components) against the appendix's qualitative findings:
//! - large parts: the axis farthest from the tool (X) is the most sensitive and contributes most,
//!   X is the most sensitive direction of the part, both robustness indices rise, and angular and
//!   squareness errors dominate (Abbe effect);
//! - small parts: linear errors dominate and the axes contribute more equally;
//! - the allocation at constant relative accuracy shows the same trends: the share of linear errors
//!   falls and the share of X over that of Z rises with the part size.

use trueaxis::budget::analysis::BETWEEN_AXES;
use trueaxis::budget::global::GeneticOptions;
use trueaxis::budget::miniaturisation::{run, ARCSEC_URAD, SIZES};
use trueaxis::budget::spec::KindValues;

fn share(groups: &[trueaxis::budget::analysis::GroupShare], label: &str) -> f64 {
    groups.iter().find(|g| g.label == label).map_or(0.0, |g| g.share)
}

#[test]
fn findings_of_the_miniaturisation_case() {
    let cases =
        run(&SIZES, KindValues([1.0, ARCSEC_URAD, ARCSEC_URAD]), 1e-4, GeneticOptions { generations: 100, ..GeneticOptions::default() })
            .unwrap();
    let small = &cases[0].analysis;
    let large = &cases[5].analysis;
    // error kinds: linear errors dominate at 10 mm, angular + squareness at 300 mm
    assert!(share(&small.by_kind, "linear") > 90.0, "{}", share(&small.by_kind, "linear"));
    assert!(share(&large.by_kind, "angular") + share(&large.by_kind, "squareness") > 50.0);
    // the share of linear errors falls with every step in size
    for pair in cases.windows(2) {
        assert!(share(&pair[1].analysis.by_kind, "linear") < share(&pair[0].analysis.by_kind, "linear"));
    }
    // axes (motion errors; squareness errors are between axes): X, farthest from the tool, the most
    // sensitive at 300 mm; balanced at 10 mm
    let sm = |a: &trueaxis::budget::Analysis, axis: &str| a.by_axis.iter().find(|g| g.label == axis).unwrap().sensitivity_mm;
    assert!(sm(large, "X") > sm(large, "Y") && sm(large, "X") > sm(large, "Z"), "{:?}", large.by_axis);
    let spread = |a: &trueaxis::budget::Analysis| {
        let v: Vec<f64> = a.by_axis.iter().filter(|g| g.label != BETWEEN_AXES).map(|g| g.share).collect();
        v.iter().copied().fold(0.0, f64::max) / v.iter().copied().fold(f64::INFINITY, f64::min)
    };
    assert!(spread(small) < 1.05, "axes at 10 mm: {:?}", small.by_axis.iter().map(|g| g.share).collect::<Vec<_>>());
    assert!(spread(large) > 1.5, "axes at 300 mm: {:?}", large.by_axis.iter().map(|g| g.share).collect::<Vec<_>>());
    // part measures: X the most sensitive direction at 300 mm
    let sp = large.part_sensitivity;
    assert!(sp[0] > sp[1] && sp[0] > sp[2], "{sp:?}");
    // robustness indices RI_1 (condition) and RI_2 (largest singular value) rise with the part
    for pair in cases.windows(2) {
        assert!(pair[1].analysis.singular_values[0] > pair[0].analysis.singular_values[0]);
        assert!(pair[1].analysis.condition.unwrap() > pair[0].analysis.condition.unwrap());
    }
    // allocation at constant relative accuracy: the same trends in the shares of the allocated errors
    let alloc_small = &cases[0].allocated;
    let alloc_large = &cases[5].allocated;
    // ("with the decrease of the part sizes, the linear errors become more dominant"; "with the
    // increase of part size ... more error variations are allocated to" the axis away from the tool)
    for pair in cases.windows(2) {
        assert!(share(&pair[1].allocated.by_kind, "linear") < share(&pair[0].allocated.by_kind, "linear"));
        let ratio = |a: &trueaxis::budget::Analysis| share(&a.by_axis, "X") / share(&a.by_axis, "Z");
        assert!(ratio(&pair[1].allocated) > ratio(&pair[0].allocated), "{} mm", pair[1].size);
        assert!(ratio(&pair[1].analysis) > ratio(&pair[0].analysis), "{} mm", pair[1].size);
    }
    assert!(share(&alloc_small.by_kind, "linear") > 50.0);
    assert!(share(&alloc_large.by_axis, "X") > share(&alloc_large.by_axis, "Y"));
    assert!(share(&alloc_large.by_axis, "X") > share(&alloc_large.by_axis, "Z"));
    for case in &cases {
        assert!(case.allocation.kkt_residual < 1e-6, "{} mm: {}", case.size, case.allocation.kkt_residual);
        // constant relative accuracy: the binding direction is on its target
        let target = 1e-4 * case.size * 1000.0;
        assert!(case.allocation.achieved.iter().any(|v| (v - target).abs() < 1e-6 * target), "{:?}", case.allocation.achieved);
    }
}
