//! LinuxCNC splines (`G5` cubic, `G5.1` quadratic, a `G5` continuing without I J, one in G91) run
//! as chords, checked three ways: rs274 runs the original, and the moves around the splines (which
//! start where each spline ends) are the ones trueaxis reads (1e-9 mm); every chord vertex lies on
//! the Bézier curve of the LinuxCNC manual, written here in Bernstein form (1e-9 mm), and the middle
//! of every chord within the 1 um chord tolerance of the curve; the corrected program, run by
//! rs274 and pushed through the erroneous machine, lands on the chords within 0.05 um.

use crate::common::oracle::Oracle;
use crate::common::rs274::rs274;
use trueaxis::compensate::nc::{correct_program, run_program, Dialect, NcOptions, Role};
use trueaxis::compensate::Corrector;
use trueaxis::errors::ErrorModel;

const PROGRAM: &str = "G21 G17 G90\nG0 X-20 Y-10 Z5\nG1 Z-1 F300\nG5.1 X0 Y-10 I10 J15\nG5 X25 Y5 I4 J6 P-6 Q-3\n\
                       G5 X40 Y-5 P-2 Q5\nG1 Z5\nG91\nG5 X10 Y10 I5 J0 P0 Q-5\nG90 G1 Z10\nM2\n";

/// The control points of the splines of `PROGRAM` (mm), from the manual's rules by hand.
fn controls() -> Vec<Vec<[f64; 2]>> {
    vec![
        vec![[-20.0, -10.0], [-10.0, 5.0], [0.0, -10.0]],
        vec![[0.0, -10.0], [4.0, -4.0], [19.0, 2.0], [25.0, 5.0]],
        // I J mirrored from the previous P Q: (6, 3)
        vec![[25.0, 5.0], [31.0, 8.0], [38.0, 0.0], [40.0, -5.0]],
        vec![[40.0, -5.0], [45.0, -5.0], [50.0, 0.0], [50.0, 5.0]],
    ]
}

/// The Bézier curve in Bernstein form.
fn curve(c: &[[f64; 2]], t: f64) -> [f64; 2] {
    let u = 1.0 - t;
    let w: Vec<f64> =
        if c.len() == 3 { vec![u * u, 2.0 * u * t, t * t] } else { vec![u * u * u, 3.0 * u * u * t, 3.0 * u * t * t, t * t * t] };
    [0, 1].map(|k| c.iter().zip(&w).map(|(p, w)| p[k] * w).sum())
}

#[test]
fn splines_become_chords_on_the_curve_and_are_corrected() {
    let Some(rs) = rs274() else { return };
    let machine = crate::linuxcnc_samples::mill();
    let errors = ErrorModel::load("../../examples/errors/vmc3.toml", &machine).unwrap();
    let mut options = NcOptions::new(&machine);
    options.dialect = Some(Dialect::LinuxCnc.into());
    options.setup.machine_inch = true;
    let (trace, _) = run_program(&machine, PROGRAM, "splines.ngc", &options).unwrap();
    // rs274: the moves that are not chords, in order
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("splines.ngc"), PROGRAM).unwrap();
    let theirs = rs.run(dir.path(), "splines.ngc", None).unwrap();
    let ours: Vec<_> = trace.moves.iter().filter(|m| m.role != Role::Generated).collect();
    assert_eq!(ours.len(), theirs.len());
    for (a, b) in ours.iter().zip(&theirs) {
        assert!((0..3).all(|k| (a.end[k] - b.end[k]).abs() < 1e-9), "{:?} vs {:?}", a.end, b.end);
    }
    // the chords of each spline
    let mut worst: f64 = 0.0;
    let mut count = 0;
    for (s, c) in controls().iter().enumerate() {
        let step = trace.moves.iter().filter(|m| m.role == Role::Generated).map(|m| m.step).collect::<std::collections::BTreeSet<_>>();
        let step = *step.iter().nth(s).unwrap();
        let chords: Vec<_> = trace.moves.iter().filter(|m| m.step == step).collect();
        let n = chords.len();
        count += n;
        let dense: Vec<f64> = (0..=20_000).map(|i| i as f64 / 20_000.0).collect();
        for (k, m) in chords.iter().enumerate() {
            let v = curve(c, (k + 1) as f64 / n as f64);
            assert!((m.end[0] - v[0]).abs() < 1e-9 && (m.end[1] - v[1]).abs() < 1e-9, "spline {s} vertex {k}: {:?} vs {v:?}", m.end);
            let mid = [(m.start[0] + m.end[0]) / 2.0, (m.start[1] + m.end[1]) / 2.0];
            let dist = |t: f64| {
                let p = curve(c, t);
                (p[0] - mid[0]).hypot(p[1] - mid[1])
            };
            // the nearest sample, then a ternary search around it
            let i = (0..dense.len()).min_by(|&a, &b| dist(a as f64 / 20_000.0).total_cmp(&dist(b as f64 / 20_000.0))).unwrap();
            let (mut lo, mut hi) = ((i as f64 - 1.0).max(0.0) / 20_000.0, (i as f64 + 1.0).min(20_000.0) / 20_000.0);
            for _ in 0..60 {
                let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                if dist(a) < dist(b) {
                    hi = b;
                } else {
                    lo = a;
                }
            }
            let d = dist(0.5 * (lo + hi));
            worst = worst.max(d);
        }
    }
    println!("{count} chords, the middle of a chord at most {:.3} um from the curve", worst * 1e3);
    assert!(worst <= 0.001 + 1e-6 && worst > 0.0003, "{worst}");
    // corrected, run by rs274, through the erroneous machine
    let corrector = Corrector::new(&machine, &errors);
    let r = correct_program(&corrector, PROGRAM, "splines.ngc", &options, &[]).unwrap();
    assert_eq!(r.expanded.len(), 4, "{:?}", r.expanded);
    assert!(r.expanded.iter().all(|e| e.contains("spline as lines within 1 um of the curve")), "{:?}", r.expanded);
    std::fs::write(dir.path().join("corrected.ngc"), &r.program).unwrap();
    let corrected = rs.run(dir.path(), "corrected.ngc", None).unwrap();
    let original = crate::fanuc::read(&machine, PROGRAM, &options);
    let oracle = Oracle { machine: &machine, errors: &errors, temperatures: vec![] };
    let report = oracle.compare(&original, &corrected, &vec![0.0; machine.axis_count()], 0.05, 1.05, &[]).unwrap();
    println!("corrected: {} moves, ends within {:.4} um, path within {:.4} um", report.moves, report.worst_end_um, report.worst_path_um);
}
