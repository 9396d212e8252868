//! LinuxCNC splines (`G5` cubic, `G5.1` quadratic, a `G5` continuing without I J, one in G91) run
//! as chords, checked three ways: rs274 runs the original, and the moves around the splines (which
//! start where each spline ends) are the ones trueaxis reads (1e-9 mm); every chord vertex lies on
//! the Bézier curve of the LinuxCNC manual, written here in Bernstein form (1e-9 mm), and the middle
//! of every chord within the 1 um chord tolerance of the curve; the corrected program, run by
//! rs274 and pushed through the erroneous machine, lands on the chords within 0.05 um.

use super::common::oracle::Oracle;
use super::common::rs274::rs274;
use trueaxis::compensate::nc::{correct_program, run_program, Dialect, Move, NcOptions, NcResult, Role, Trace};
use trueaxis::compensate::Corrector;
use trueaxis::error_model::ErrorModel;

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

/// The machine, errors and options of these tests, with rs274 and a directory for its files.
struct Bench {
    rs: &'static super::common::rs274::Rs274,
    machine: trueaxis::machine::Machine,
    errors: ErrorModel,
    options: NcOptions,
    dir: tempfile::TempDir,
}

impl Bench {
    fn new() -> Option<Bench> {
        let rs = rs274()?;
        let machine = super::linuxcnc_samples::mill();
        let errors = ErrorModel::load("../../examples/errors/vmc3.toml", &machine).unwrap();
        let mut options = NcOptions::new(&machine);
        options.dialect = Some(Dialect::LinuxCnc.into());
        options.setup.machine_inch = true;
        Some(Bench { rs, machine, errors, options, dir: tempfile::tempdir().unwrap() })
    }

    /// The trace trueaxis reads; rs274 runs a curve as NURBS_FEED without its points, so the moves
    /// that are not chords (which start where each curve ends) must be the ones rs274 prints.
    fn run(&self, program: &str, name: &str) -> Trace {
        let (trace, _) = run_program(&self.machine, program, name, &self.options).unwrap();
        std::fs::write(self.dir.path().join(name), program).unwrap();
        let theirs = self.rs.run(self.dir.path(), name, None).unwrap();
        let ours: Vec<_> = trace.moves.iter().filter(|m| m.role != Role::Generated).collect();
        assert_eq!(ours.len(), theirs.len());
        for (a, b) in ours.iter().zip(&theirs) {
            assert!((0..3).all(|k| (a.end[k] - b.end[k]).abs() < 1e-9), "{:?} vs {:?}", a.end, b.end);
        }
        trace
    }

    /// The program corrected; rs274 runs the corrected text, whose moves, pushed through the
    /// erroneous machine, land on the chords within 0.05 um.
    fn correct(&self, program: &str, name: &str) -> NcResult {
        let r = correct_program(&Corrector::new(&self.machine, &self.errors), program, name, &self.options, &[]).unwrap();
        std::fs::write(self.dir.path().join("corrected.ngc"), &r.program).unwrap();
        let corrected = self.rs.run(self.dir.path(), "corrected.ngc", None).unwrap();
        let original = super::fanuc::read(&self.machine, program, &self.options);
        let oracle = Oracle { machine: &self.machine, errors: &self.errors, temperatures: vec![] };
        let start = vec![0.0; self.machine.axis_count()];
        let report = oracle.compare(&original, &corrected, &start, 0.05, 1.05, &[]).unwrap();
        println!(
            "corrected: {} moves, ends within {:.4} um, path within {:.4} um",
            report.moves, report.worst_end_um, report.worst_path_um
        );
        r
    }
}

/// The chords (moves) of each curve of a trace, in order.
fn curves(trace: &Trace) -> Vec<Vec<&Move>> {
    let steps: std::collections::BTreeSet<u32> = trace.moves.iter().filter(|m| m.role == Role::Generated).map(|m| m.step).collect();
    steps.iter().map(|s| trace.moves.iter().filter(|m| m.step == *s).collect()).collect()
}

#[test]
fn splines_become_chords_on_the_curve_and_are_corrected() {
    let Some(bench) = Bench::new() else { return };
    let trace = bench.run(PROGRAM, "splines.ngc");
    let mut worst: f64 = 0.0;
    let mut count = 0;
    for (s, (c, chords)) in controls().iter().zip(curves(&trace)).enumerate() {
        let n = chords.len();
        count += n;
        for (k, m) in chords.iter().enumerate() {
            let v = curve(c, (k + 1) as f64 / n as f64);
            assert!((m.end[0] - v[0]).abs() < 1e-9 && (m.end[1] - v[1]).abs() < 1e-9, "spline {s} vertex {k}: {:?} vs {v:?}", m.end);
            let mid = [(m.start[0] + m.end[0]) / 2.0, (m.start[1] + m.end[1]) / 2.0];
            worst = worst.max(distance_to_curve(&|t| curve(c, t), 1.0, mid));
        }
    }
    println!("{count} chords, the middle of a chord at most {:.3} um from the curve", worst * 1e3);
    assert!(worst <= 0.001 + 1e-6 && worst > 0.0003, "{worst}");
    let r = bench.correct(PROGRAM, "splines.ngc");
    assert_eq!(r.expanded.len(), 4, "{:?}", r.expanded);
    assert!(r.expanded.iter().all(|e| e.contains("spline as lines within 1 um of the curve")), "{:?}", r.expanded);
}

/// NURBS blocks in the styles seen in published programs: the LinuxCNC manual's layout (control
/// points on continuation lines, `L3`, a heavier last point), a quarter circle as a rational
/// quadratic, a cubic Bézier written as an order-4 NURBS with expressions (as font tracers write
/// glyph outlines), and a cubic B-spline of six points with unequal weights in G91.
const NURBS: &str = "G21 G17 G90 G94\nG0 X-30 Y-20 Z5\nG1 Z-1 F400\n(quadratic, the default order)\n\
                     G5.2 X-30 Y-10 P1 L3\n     X-20 Y-5 P1\n     X-20 Y-15 P1\n     X-10 Y-20 P2\nG5.3\n\
                     (a quarter circle about X-10 Y0)\nG5.2 X10 Y-20 P[SQRT[2]/2]\nX10 Y0 P1\nG5.3\n\
                     #3 = 2\n#5 = 10\n#6 = 0\nG5.2 X[3*#3+#5] Y[4*#3+#6] L4 P1\nX[6*#3+#5] Y[2*#3+#6] P1\nX[8*#3+#5] Y[5*#3+#6] P1\nG5.3\n\
                     G91\nG5.2 X5 Y-10 P1 L4\nX10 Y5 P0.5\nX15 Y-5 P2\nX20 Y10 P1\nX25 Y0 P1\nG5.3\nG90 G1 Z10\nM2\n";

/// The control points (X, Y, weight) and order of each curve of `NURBS`, by hand from the
/// manual's rules: the current position first (weight 1), G91 points counted from the start.
fn nurbs_controls() -> Vec<(Vec<[f64; 3]>, usize)> {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    vec![
        (vec![[-30.0, -20.0, 1.0], [-30.0, -10.0, 1.0], [-20.0, -5.0, 1.0], [-20.0, -15.0, 1.0], [-10.0, -20.0, 2.0]], 3),
        (vec![[-10.0, -20.0, 1.0], [10.0, -20.0, h], [10.0, 0.0, 1.0]], 3),
        (vec![[10.0, 0.0, 1.0], [16.0, 8.0, 1.0], [22.0, 4.0, 1.0], [26.0, 10.0, 1.0]], 4),
        (vec![[26.0, 10.0, 1.0], [31.0, 0.0, 1.0], [36.0, 15.0, 0.5], [41.0, 5.0, 2.0], [46.0, 20.0, 1.0], [51.0, 10.0, 1.0]], 4),
    ]
}

/// The NURBS by its definition: Cox-de Boor basis functions on LinuxCNC's clamped uniform knots
/// (0 k times, then 1, 2, ..., then n - k + 2 k times), u in [0, n - k + 2].
fn nurbs_point(c: &[[f64; 3]], k: usize, u: f64) -> [f64; 2] {
    let n = c.len() - 1;
    let top = (n + 2 - k) as f64;
    let t: Vec<f64> = (0..=n + k)
        .map(|i| {
            if i < k {
                0.0
            } else if i <= n {
                (i + 1 - k) as f64
            } else {
                top
            }
        })
        .collect();
    fn basis(t: &[f64], i: usize, k: usize, u: f64, top: f64) -> f64 {
        if k == 1 {
            let inside = t[i] <= u && (u < t[i + 1] || (u == top && t[i + 1] == top && t[i] < top));
            return if inside { 1.0 } else { 0.0 };
        }
        let left = if t[i + k - 1] > t[i] { (u - t[i]) / (t[i + k - 1] - t[i]) * basis(t, i, k - 1, u, top) } else { 0.0 };
        let right = if t[i + k] > t[i + 1] { (t[i + k] - u) / (t[i + k] - t[i + 1]) * basis(t, i + 1, k - 1, u, top) } else { 0.0 };
        left + right
    }
    let (mut x, mut y, mut w) = (0.0, 0.0, 0.0);
    for (i, p) in c.iter().enumerate() {
        let b = basis(&t, i, k, u, top) * p[2];
        x += b * p[0];
        y += b * p[1];
        w += b;
    }
    [x / w, y / w]
}

/// The distance of `p` from the curve `f` on [0, top]: the nearest of 20,000 samples, then a
/// ternary search around it.
fn distance_to_curve(f: &dyn Fn(f64) -> [f64; 2], top: f64, p: [f64; 2]) -> f64 {
    let dist = |u: f64| {
        let c = f(u);
        (c[0] - p[0]).hypot(c[1] - p[1])
    };
    let n = 20_000;
    let i = (0..=n).min_by(|&a, &b| dist(top * a as f64 / n as f64).total_cmp(&dist(top * b as f64 / n as f64))).unwrap();
    let (mut lo, mut hi) = (top * (i as f64 - 1.0).max(0.0) / n as f64, top * (i as f64 + 1.0).min(n as f64) / n as f64);
    for _ in 0..80 {
        let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if dist(a) < dist(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    dist(0.5 * (lo + hi))
}

#[test]
fn nurbs_become_chords_within_a_micrometre_of_the_curve_and_are_corrected() {
    let Some(bench) = Bench::new() else { return };
    let trace = bench.run(NURBS, "nurbs.ngc");
    let curves = curves(&trace);
    assert_eq!(curves.len(), 4);
    let (mut on, mut middle): (f64, f64) = (0.0, 0.0);
    for ((c, k), chords) in nurbs_controls().iter().zip(&curves) {
        let top = (c.len() + 1 - k) as f64;
        let f = |u: f64| nurbs_point(c, *k, u);
        let last = chords.last().unwrap().end;
        assert!((last[0] - c[c.len() - 1][0]).abs() < 1e-12 && (last[1] - c[c.len() - 1][1]).abs() < 1e-12);
        for m in chords.iter() {
            on = on.max(distance_to_curve(&f, top, [m.end[0], m.end[1]]));
            middle = middle.max(distance_to_curve(&f, top, [(m.start[0] + m.end[0]) / 2.0, (m.start[1] + m.end[1]) / 2.0]));
        }
        println!("order {k}, {} control points: {} chords", c.len(), chords.len());
    }
    println!("chord ends at most {on:.1e} mm from the curve, chord middles at most {:.3} um", middle * 1e3);
    assert!(on < 1e-9, "{on}");
    assert!(middle <= 0.001 + 1e-9 && middle > 0.0002, "{middle}");
    // second formulations: the rational quadratic is a circle, the order-4 curve of four points
    // is the cubic Bézier of its points (G5's curve)
    assert!(curves[1].iter().all(|m| ((m.end[0] + 10.0).hypot(m.end[1]) - 20.0).abs() < 1e-9));
    let cubic = [[10.0, 0.0], [16.0, 8.0], [22.0, 4.0], [26.0, 10.0]];
    for m in &curves[2] {
        assert!(distance_to_curve(&|t| curve(&cubic, t), 1.0, [m.end[0], m.end[1]]) < 1e-9);
    }
    // corrected: written as lines, run by rs274, through the erroneous machine onto the chords
    let r = bench.correct(NURBS, "nurbs.ngc");
    assert_eq!(
        r.expanded.iter().filter(|e| e.contains("NURBS (G5.2-G5.3) as lines within 1 um of the curve")).count(),
        4,
        "{:?}",
        r.expanded
    );
    let text = String::from_utf8_lossy(&r.program);
    assert!(text.lines().all(|l| !l.trim_start().starts_with("G5")), "{text}");
    assert_eq!(text.matches("(NURBS control point").count(), 14, "{text}");
    // read in parts, a NURBS that crosses from one part into the next sends the program whole; the
    // others go in parts: the same bytes either way
    let corrector = Corrector::new(&bench.machine, &bench.errors);
    let went = super::parts::compare(&corrector, NURBS.as_bytes(), "nurbs.ngc", &bench.options);
    assert!(matches!(&went[0], super::parts::Went::Whole(why) if why.contains("a NURBS across parts, at line 5")), "{went:?}");
    // nothing to correct: every NURBS stays as it was
    let zero = ErrorModel::zero(&bench.machine);
    let r = correct_program(&Corrector::new(&bench.machine, &zero), NURBS, "nurbs.ngc", &bench.options, &[]).unwrap();
    assert!(r.program == NURBS.as_bytes(), "{:?}", r.expanded);
    assert_eq!((r.changed_lines, r.inserted_lines), (0, 0));
}
