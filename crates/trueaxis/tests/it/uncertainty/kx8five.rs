//! Andolfatto et al. 2011 §4-5: adaptive Monte Carlo uncertainty of the 14
//! link and setup errors of the Huron KX8-Five identified from 807 CapBall poses, with the sensor
//! noise of Table 3, the frame-transformation uncertainty of §4.3 and the drift of Table 4 by the
//! statistical and by the cyclic method.
//!
//! The design matrix is built from the first-order model (`support/kx8five_capball.rs`).

use crate::support::kx8five_capball;
use kx8five_capball::{capball_design, Trajectory};
use trueaxis::uncertainty::{
    run_adaptive, run_budget, CyclicDrift, DesignMatrix, Distribution, Evaluation, IdentificationMap, McSettings, PeriodicDrift, Source,
    SourceKind, StartPhase,
};

/// The 14 parameters of Andolfatto et al. 2011 eq. 1 with ISO names: the 8 link errors (tilts of A and the C
/// offset taken normal to the tilted A axis, see the last test) and the 6 setup errors.
const PARAMETERS: [&str; 14] = ["EC0Y", "EA0Z", "EB0Z", "EB0A", "EA0A", "EA0C", "EB0C", "EX0C", "TX", "TY", "TZ", "WX", "WY", "WZ"];
/// Time between two poses (s): 807 poses in about 10 minutes (Andolfatto et al. 2011 §3.4).
const T_I: f64 = 0.75;

/// The identification trajectory of Andolfatto et al. 2011 §3.2 in the spirit of its Fig. 2: the tool point held
/// on a master ball at (150, 0, 50) mm on the table while A tilts clockwise from 0 to 120 deg and
/// C turns three times clockwise; X, Y, Z follow. Rows x, y, z of each pose, pose k at k t_i.
fn kx8five_design() -> DesignMatrix {
    design_with(&PARAMETERS)
}

fn design_with(parameters: &[&str]) -> DesignMatrix {
    capball_design(&Trajectory::SEED_004, parameters, T_I)
}

fn normal(name: &str, u: [f64; 3]) -> Source {
    let channels = ["x", "y", "z"].iter().zip(u).map(|(c, u)| (c.to_string(), Distribution::Normal { mean: 0.0, u })).collect();
    Source { name: name.into(), kind: SourceKind::Noise { channels } }
}

/// Table 4 magnitudes of the drift (um).
const E_VE: [f64; 3] = [6.95, 3.42, 6.63];
/// Period of the spindle cooling cycle (s); Andolfatto et al. 2011 Fig. 9 shows cycles without stating the period.
const PERIOD: f64 = 1000.0;

fn sources(cyclic: bool) -> Vec<Source> {
    let drift = if cyclic {
        let channels =
            ["x", "y", "z"].iter().zip(E_VE).map(|(c, e)| (c.to_string(), PeriodicDrift::sine(PERIOD, e, 0.0).unwrap())).collect();
        SourceKind::CyclicDrift(CyclicDrift { channels, run_duration: None, start_phase: StartPhase::Sequence })
    } else {
        SourceKind::StatisticalDrift { channels: ["x", "y", "z"].iter().zip(E_VE).map(|(c, e)| (c.to_string(), e)).collect() }
    };
    vec![
        Source { name: "drift".into(), kind: drift },
        normal("sensors", [0.28, 0.28, 0.40]),        // Table 3
        normal("transformation", [0.56, 0.27, 0.69]), // §4.3, Fig. 7
    ]
}

fn settings() -> McSettings {
    // M = 10^4, 95 %, delta = 0.05 um or urad (Andolfatto et al. 2011 §4.1, Fig. 13)
    let mut s = McSettings::new(0.95, 0.05);
    s.seed = 4;
    s
}

#[test]
fn seed_004_statistical_versus_cyclic_drift() {
    let map = IdentificationMap::new(kx8five_design()).unwrap();
    assert_eq!(map.design.observations(), 3 * 807);
    assert!(map.condition_number < 200.0, "condition number {}", map.condition_number);
    let s = settings();
    let stat = run_budget(&map, &sources(false), &s, Evaluation::Reduced, true, &mut |_, _, _| {}).unwrap();
    let cyc = run_budget(&map, &sources(true), &s, Evaluation::Reduced, true, &mut |_, _, _| {}).unwrap();
    let k = stat.gum_coverage_factor;
    for (j, name) in PARAMETERS.iter().enumerate() {
        let (st, cy) = (&stat.total.outputs[j], &cyc.total.outputs[j]);
        eprintln!(
            "{name}: statistical width {:.3} (u {:.3}, kurt {:.3}) cyclic width {:.3} (u {:.3}, kurt {:.3}, half/u {:.3}); budget drift {:.3} sensors {:.3} trans {:.3} rss {:.3} total {:.3}",
            st.symmetric.width(),
            st.std_uncertainty,
            st.excess_kurtosis,
            cy.symmetric.width(),
            cy.std_uncertainty,
            cy.excess_kurtosis,
            0.5 * cy.symmetric.width() / cy.std_uncertainty,
            cyc.rows[j].widths[0],
            cyc.rows[j].widths[1],
            cyc.rows[j].widths[2],
            cyc.rows[j].rss,
            cyc.rows[j].total
        );
        // 1. the statistical method gives narrower intervals than the cyclic method (Andolfatto et al. 2011 §5.1)
        assert!(st.symmetric.width() < cy.symmetric.width(), "{name}");
        // the statistical outputs are Gaussian: the GUM interval holds (half width / u = 1.96)
        assert!((0.5 * st.symmetric.width() / st.std_uncertainty - k).abs() < 0.03, "{name}");
        assert!((st.std_uncertainty - stat.rows[j].gum_total_u).abs() < 0.05, "{name}: MC and GUM");
        // 2. the cyclic method gives non-normal outputs (Andolfatto et al. 2011 §5.1, Fig. 10): arc-sine-like,
        // excess kurtosis near -1.5 and a 95 % half width near 1.44 u instead of 1.96 u
        if j < 8 {
            assert!(cy.excess_kurtosis < -1.0, "{name}: {}", cy.excess_kurtosis);
            let ratio = 0.5 * cy.symmetric.width() / cy.std_uncertainty;
            assert!(ratio > 1.35 && ratio < 1.6, "{name}: {ratio}");
        }
        assert!(st.excess_kurtosis.abs() < 0.1, "{name}");
        // 3. drift dominates the budget (Table 5), and the total is not below the root-sum-square
        let row = &cyc.rows[j];
        assert!(row.widths[0] > 4.0 * row.widths[1] && row.widths[0] > 4.0 * row.widths[2], "{name}");
        assert!(row.total > 0.995 * row.rss, "{name}: total {} rss {}", row.total, row.rss);
    }
    // as in Table 5, the total interval exceeds the RSS of the separate sources for most link errors
    let above = (0..8).filter(|&j| cyc.rows[j].total > cyc.rows[j].rss).count();
    assert!(above >= 6, "{above} of 8");
    assert_eq!(cyc.source_names, ["drift", "sensors", "transformation"]);
}

#[test]
fn adaptive_loop_converges_like_seed_004_fig_13() {
    // Andolfatto et al. 2011 §5.2: M = 10^4, delta = 0.05 um or urad, convergence after h = 17..24 sequences.
    //
    // Why the timing of eq. 12 converges at once here: point k of trial n is measured at
    // t0 + (n - 1) t_m + k t_i, so the drift phase of trial n is t0 + n t_m (mod T). With
    // t_m = 807 x 0.75 s = 605.25 s and T = 1000 s, t_m / T = 2421/4000: the 10^4 trials of a
    // sequence visit 4000 evenly spaced phases 2 or 3 times each, whatever t0 is, so the drift part
    // of every sequence is nearly the same sample (a quasi-random, low-discrepancy sweep of the cycle):
    // only the Gaussian sources vary between sequences and h = 2 or 3 (h >= 2 is the least the
    // procedure allows, JCGM 101 §7.9.4 e).
    //
    // The paper's 17..24 needs sequences that differ like independent samples: a random phase per
    // trial. Then the sequence mean of output j has the standard deviation u_j / sqrt(M); the
    // stopping rule 2 s_y <= delta with s_y^2 = var / h gives h* = 4 u_max^2 / (M delta^2), the
    // control variables of the standard uncertainty and the endpoints being smaller for these
    // arc-sine-like outputs (sd of a 2.5 % endpoint ~ 0.05 u / sqrt(M)). With this design the largest
    // u is 15.6 (the drift, about twice the paper's largest Table 5 values), so h* = 39; h scatters
    // about h* because s_y is estimated from h sequences (a chi distribution with h - 1 degrees of
    // freedom: +-2 of its standard deviations 1 / sqrt(2 (h - 1)) ~ +-23 % in s, +-37 % in h). The
    // paper's 17..24 with its endpoints limiting fits neither case exactly: its drift period is not
    // given, and a period that leaves a sequence's phases unevenly spread (t_m / T near a simple
    // fraction) gives sequences between the two cases. The adaptive procedure can also stop early by
    // chance (6 seeds: one stopped at h = 4, its s_y from 4 sequences being small): JCGM 101
    // §7.9.4 has no guard against it; the test allows one such stop in six.
    let map = IdentificationMap::new(kx8five_design()).unwrap();
    let s = settings();
    for phase in [StartPhase::Sequence, StartPhase::Trial] {
        let mut src = sources(true);
        if let SourceKind::CyclicDrift(c) = &mut src[0].kind {
            c.start_phase = phase;
        }
        let refs: Vec<&Source> = src.iter().collect();
        let model = map.model(&refs, Evaluation::Reduced).unwrap();
        let mut hs = Vec::new();
        let mut early = 0;
        for seed in 1..=6 {
            let mut s = s.clone();
            s.seed = seed;
            let mut seen = 0;
            let r = run_adaptive(&model, &s, &mut |h, _| seen = h).unwrap();
            let last = r.history.last().unwrap();
            assert!(r.converged && seen == r.sequences && r.history.len() == r.sequences - 1);
            assert!(last.max.iter().all(|v| 2.0 * v <= 0.05));
            let u_max = r.outputs.iter().map(|o| o.std_uncertainty).fold(0.0, f64::max);
            let h_star = 4.0 * u_max * u_max / (s.trials_per_sequence as f64 * 0.05 * 0.05);
            eprintln!("{phase:?} seed {seed}: h = {}, h* = {h_star:.1} (u_max {u_max:.3}), control variables {:?}", r.sequences, last.max);
            let endpoints = last.max[2].max(last.max[3]);
            match phase {
                StartPhase::Sequence => {
                    // the 4000-phase grid: done at once, the endpoints limiting (as in the paper's Fig. 13)
                    assert!((2..=4).contains(&r.sequences), "h = {}", r.sequences);
                    assert!(endpoints > last.max[0] && endpoints > last.max[1], "endpoints limit: {:?}", last.max);
                }
                StartPhase::Trial => {
                    assert!((15.0..17.0).contains(&u_max), "u_max = {u_max}");
                    let h = r.sequences as f64;
                    if h >= 0.63 * h_star {
                        assert!(h <= 1.37 * h_star + 1.0, "h = {h} vs h* = {h_star}");
                        assert!(last.max[0] > endpoints && last.max[0] > last.max[1], "the means limit: {:?}", last.max);
                    } else {
                        // a premature stop: s_y estimated from very few sequences came out small
                        early += 1;
                    }
                }
            }
            hs.push(r.sequences as f64);
        }
        hs.sort_by(f64::total_cmp);
        let median = 0.5 * (hs[2] + hs[3]);
        eprintln!("{phase:?}: h = {hs:?}, median {median}");
        if phase == StartPhase::Trial {
            assert!(early <= 1, "{early} premature stops in 6");
            assert!((median / 38.9 - 1.0).abs() < 0.15, "median h = {median}");
        }
    }
}

#[test]
fn iso_names_of_the_example_error_file_are_not_all_identifiable_from_one_ball() {
    // examples/errors/kx8five.toml maps Andolfatto et al. 2011's tilts of A to EB0A, EC0A and the offset of C to
    // EY0C. With A tilted 45 deg in the Y-Z plane, EB0A and EC0A together hold a zero offset of A,
    // which for one ball is a tilt of C plus a workpiece shift; and EY0C's part along A is a
    // translation (user guide). The test set uses EA0A and EX0C instead (both normal to A).
    let err = IdentificationMap::new(design_with(&[
        "EC0Y", "EA0Z", "EB0Z", "EB0A", "EC0A", "EA0C", "EB0C", "EX0C", "TX", "TY", "TZ", "WX", "WY", "WZ",
    ]))
    .unwrap_err();
    assert!(err.to_string().contains("cannot be separated") && err.to_string().contains("EB0A, EC0A, EB0C"), "{err}");
    let err = IdentificationMap::new(design_with(&[
        "EC0Y", "EA0Z", "EB0Z", "EB0A", "EA0A", "EA0C", "EB0C", "EY0C", "TX", "TY", "TZ", "WX", "WY", "WZ",
    ]))
    .unwrap_err();
    assert!(err.to_string().contains("WZ cannot be separated from EY0C, TY, TZ"), "{err}");
}

#[test]
fn shipped_example_design_is_this_design() {
    // examples/uncertainty/kx8five_design.csv holds this design rounded to 1e-6
    let shipped = DesignMatrix::read_csv("../../examples/uncertainty/kx8five_design.csv").unwrap();
    let built = kx8five_design();
    assert_eq!(shipped.parameters, built.parameters);
    assert_eq!(shipped.channel, built.channel);
    assert!(shipped.time.iter().zip(&built.time).all(|(a, b)| (a - b).abs() < 1e-12));
    assert!((&shipped.x - &built.x).abs().max() < 5.1e-7);
}
