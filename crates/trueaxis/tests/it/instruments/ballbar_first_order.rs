//! The exact kinematic chain reproduces the first-order double-ballbar (DBB) relations of Jiang 2014
//! (X. Jiang, PhD thesis, Univ. of Birmingham, 2014) for the table-tilting C600U of
//! `examples/machines/c600u.toml`.
//!
//! Sources: digest `/work/shared/specs/jiang.md` section 1.3 (HTM chain, thesis Eqs. 3.2-3.8),
//! 2.3 (test paths, corrected D), 2.4 (ch. 5 setups), 2.5 (first-order relations), 2.8 (Fig. 3.7
//! diagnostics) and 4.1 (Table 3.1 simulation values).
//!
//! Setups (thesis ch. 5, Fig. 5.1 / 3.6; linear axes at 0; M = the thesis frame R):
//! - A1: pivot (0, R, 0), spindle ball O_R; C = 0; A swept -20 ... 70 deg.
//! - A2: pivot (0, R, 0), spindle ball (-D, 0, 0); C = 0; A swept -20 ... 70 deg.
//! - C1: pivot (R, 0, 0), spindle ball O_R; A = 0; C swept 0 ... 360 deg.
//! - C2: pivot (R, 0, 0), spindle ball (0, 0, +D); A = 0; C swept 0 ... 360 deg.
//!
//! R = 100 mm, L_e = 150 mm, D = sqrt(L_e^2 - R^2) = 111.803 mm. The thesis's Eq. 3.13 prints
//! D = 50 sqrt(2) = 70.71 mm, an arithmetic erratum (digest 2.3): with it the extended bar would be
//! 122.47 mm long, not 150 mm.
//!
//! PIGE names (digest 1.3, docs/design.md, Conventions): the thesis left-multiplies the PIGE matrix onto the
//! ideal axis matrix, as the library's `L_k S_k(q) J_k(q)`, so e_y0a = EY0A, e_z0a = EZ0A,
//! theta_y0a = EB0A, theta_z0a = EC0A, e_x0c = EX0C, e_y0c = EY0C, theta_x0c = EA0C,
//! theta_y0c = EB0C.

use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::Vec3;
use trueaxis::machine::Machine;
use trueaxis::model::{actual_chain, nominal_chain, volumetric_error, Frame, Setup};

/// Test radius R (mm), thesis Table 3.1.
const R: f64 = 100.0;
/// Extended bar length L_e (mm), thesis Table 3.1.
const L_E: f64 = 150.0;
/// Position PIGE of Table 3.1: 10 um.
const POSITION_UM: f64 = 10.0;
/// Orientation PIGE of Table 3.1: 0.01 deg in urad (174.533 urad).
const ORIENTATION_URAD: f64 = 0.01 * std::f64::consts::PI / 180.0 * 1e6;

/// Tolerance between the exact dL and the first-order relation (um). The neglected second-order
/// terms are of size theta^2 L (3.05e-8 * 150 mm = 0.0046 um), theta e (1.75e-4 * 10 um = 0.0017 um)
/// and |transverse displacement|^2 / (2 L) (at most (2 D theta)^2 / (2 * 100 mm) ~ 0.008 um with all
/// eight PIGEs); 0.02 um bounds their sum with margin.
const FIRST_ORDER_TOLERANCE_UM: f64 = 0.02;

/// Extended-bar offset of the spindle ball along the axis under test (mm), digest 2.3.
fn d() -> f64 {
    (L_E * L_E - R * R).sqrt()
}

fn machine() -> Machine {
    Machine::from_toml_str(include_str!("../../../../../examples/machines/c600u.toml"), "../../examples/machines/c600u.toml")
        .expect("c600u.toml loads")
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Step {
    A1,
    A2,
    C1,
    C2,
}

const STEPS: [Step; 4] = [Step::A1, Step::A2, Step::C1, Step::C2];

impl Step {
    /// Pivot ball (workpiece point) and spindle ball (tool point), in M at home (mm).
    fn setup(self) -> Setup {
        let (work_point, tool_point) = match self {
            Step::A1 => (Vec3::new(0.0, R, 0.0), Vec3::zeros()),
            Step::A2 => (Vec3::new(0.0, R, 0.0), Vec3::new(-d(), 0.0, 0.0)),
            Step::C1 => (Vec3::new(R, 0.0, 0.0), Vec3::zeros()),
            Step::C2 => (Vec3::new(R, 0.0, 0.0), Vec3::new(0.0, 0.0, d())),
        };
        Setup { tool_point, work_point }
    }

    /// Swept angles (deg), every 5 deg: A -20 ... 70, C 0 ... 360.
    fn sweep(self) -> Vec<f64> {
        let (lo, hi) = match self {
            Step::A1 | Step::A2 => (-20, 70),
            Step::C1 | Step::C2 => (0, 360),
        };
        (lo..=hi).step_by(5).map(f64::from).collect()
    }

    /// Pose (X Y Z A C, mm and rad) at the swept angle `deg`; the other rotary axis at 0.
    fn pose(self, deg: f64) -> Vec<f64> {
        let t = deg.to_radians();
        match self {
            Step::A1 | Step::A2 => vec![0.0, 0.0, 0.0, t, 0.0],
            Step::C1 | Step::C2 => vec![0.0, 0.0, 0.0, 0.0, t],
        }
    }

    /// Nominal bar length (mm): 100 mm without, 150 mm with the extension.
    fn nominal_length(self) -> f64 {
        match self {
            Step::A1 | Step::C1 => R,
            Step::A2 | Step::C2 => L_E,
        }
    }
}

/// The eight PIGEs of the thesis, internal units (mm, rad).
#[derive(Clone, Copy, Debug, Default)]
struct Piges {
    e_y0a: f64,
    e_z0a: f64,
    th_y0a: f64,
    th_z0a: f64,
    e_x0c: f64,
    e_y0c: f64,
    th_x0c: f64,
    th_y0c: f64,
}

/// (thesis symbol, ISO name, is a rotation) of the eight PIGEs.
const PIGE_NAMES: [(&str, &str, bool); 8] = [
    ("e_y0a", "EY0A", false),
    ("e_z0a", "EZ0A", false),
    ("theta_y0a", "EB0A", true),
    ("theta_z0a", "EC0A", true),
    ("e_x0c", "EX0C", false),
    ("e_y0c", "EY0C", false),
    ("theta_x0c", "EA0C", true),
    ("theta_y0c", "EB0C", true),
];

impl Piges {
    /// The Table 3.1 value of PIGE number `i` of [`PIGE_NAMES`] alone.
    fn table_3_1_single(i: usize) -> Piges {
        let mut values = [0.0; 8];
        values[i] = if PIGE_NAMES[i].2 { ORIENTATION_URAD * 1e-6 } else { POSITION_UM * 1e-3 };
        Piges::from_array(values)
    }

    /// All eight PIGEs at their Table 3.1 values.
    fn table_3_1_all() -> Piges {
        let mut values = [0.0; 8];
        for (i, v) in values.iter_mut().enumerate() {
            *v = if PIGE_NAMES[i].2 { ORIENTATION_URAD * 1e-6 } else { POSITION_UM * 1e-3 };
        }
        Piges::from_array(values)
    }

    fn from_array(v: [f64; 8]) -> Piges {
        Piges { e_y0a: v[0], e_z0a: v[1], th_y0a: v[2], th_z0a: v[3], e_x0c: v[4], e_y0c: v[5], th_x0c: v[6], th_y0c: v[7] }
    }

    fn to_array(self) -> [f64; 8] {
        [self.e_y0a, self.e_z0a, self.th_y0a, self.th_z0a, self.e_x0c, self.e_y0c, self.th_x0c, self.th_y0c]
    }

    /// The library's parameter vector (mm, rad) holding these PIGEs under their ISO names.
    fn parameters(self, machine: &Machine) -> Vec<f64> {
        let mut params = vec![0.0; machine.parameter_count()];
        for ((_, iso, _), value) in PIGE_NAMES.iter().zip(self.to_array()) {
            let (_, index) = machine.parse_parameter(iso).expect("ISO name of a c600u parameter");
            params[index] = value;
        }
        params
    }

    /// First-order dL (mm) of step `step` at swept angle `deg`: digest section 2.5 (derived from
    /// thesis Eqs. 3.2-3.8); A angle from +Y toward +Z, C angle from +X toward +Y, k = R / L_e.
    fn first_order_dl(&self, step: Step, deg: f64) -> f64 {
        let (s, c) = deg.to_radians().sin_cos();
        let d = d();
        let k = R / L_E;
        match step {
            // A1: dL = e_y0a cos(ta) + e_z0a sin(ta) + e_y0c
            Step::A1 => self.e_y0a * c + self.e_z0a * s + self.e_y0c,
            // A2: dL = k[(e_y0a - D th_z0a) cos(ta) + (e_z0a + D th_y0a) sin(ta)] + k e_y0c + (D/L_e) e_x0c
            Step::A2 => {
                k * ((self.e_y0a - d * self.th_z0a) * c + (self.e_z0a + d * self.th_y0a) * s) + k * self.e_y0c + d / L_E * self.e_x0c
            }
            // C1: dL = e_x0c cos(tc) + (e_y0c + e_y0a) sin(tc)
            Step::C1 => self.e_x0c * c + (self.e_y0c + self.e_y0a) * s,
            // C2: dL = k[(e_x0c + D(th_y0c + th_y0a)) cos(tc) + (e_y0c + e_y0a - D th_x0c) sin(tc)] - (D/L_e) e_z0a
            Step::C2 => {
                k * ((self.e_x0c + d * (self.th_y0c + self.th_y0a)) * c + (self.e_y0c + self.e_y0a - d * self.th_x0c) * s)
                    - d / L_E * self.e_z0a
            }
        }
    }
}

/// Exact dL (um) of the library chain at `deg` of `step`.
fn exact_dl_um(machine: &Machine, step: Step, deg: f64, params: &[f64]) -> f64 {
    volumetric_error(machine, &step.pose(deg), params, &step.setup(), Frame::Workpiece).length * 1e3
}

/// Nominal distance (mm) between the spindle ball and the pivot ball from the library's nominal chain.
fn nominal_distance_from_chain(machine: &Machine, step: Step, deg: f64) -> f64 {
    let q = step.pose(deg);
    let setup = step.setup();
    let tool = nominal_chain(machine, machine.tool_chain(), &q, None).transform_point(&setup.tool_point);
    let work = nominal_chain(machine, machine.work_chain(), &q, None).transform_point(&setup.work_point);
    (tool - work).norm()
}

/// Nominal distance (mm) by hand: the pivot turned about X (A, +Y toward +Z) or Z (C, +X toward +Y)
/// through O_R, thesis Eqs. 3.7-3.8 with all PIGEs zero.
fn nominal_distance_by_hand(step: Step, deg: f64) -> f64 {
    let (s, c) = deg.to_radians().sin_cos();
    let p = step.setup().work_point;
    let turned = match step {
        Step::A1 | Step::A2 => Vec3::new(p.x, c * p.y - s * p.z, s * p.y + c * p.z),
        Step::C1 | Step::C2 => Vec3::new(c * p.x - s * p.y, s * p.x + c * p.y, p.z),
    };
    (step.setup().tool_point - turned).norm()
}

#[test]
fn machine_file_is_the_design_example() {
    // docs/design.md, Files minimal example; source string as asked for the shipped example.
    let m = machine();
    assert_eq!(m.axis_letters(), "XYZAC");
    assert_eq!(m.structure.to_string(), "wCAbYXZt");
    assert_eq!(m.source.as_deref(), Some("Jiang 2014 ch. 3, Figs. 3.3-3.6, Table 3.1"));
    assert_eq!(m.tool_point, Vec3::zeros());
    let a = &m.axes()[m.axis_index('A').unwrap()];
    assert_eq!((a.direction, a.point, a.range), (Vec3::x(), Vec3::zeros(), Some([-20.0, 70.0])));
    let c = &m.axes()[m.axis_index('C').unwrap()];
    assert_eq!((c.direction, c.point, c.range), (Vec3::z(), Vec3::zeros(), None));
}

#[test]
fn nominal_bar_lengths_are_100_and_150_mm() {
    // Digest 2.3 / Table 3.1: nominal bar 100 mm (A1, C1), extended 150 mm (A2, C2). The 150 mm pins
    // D = sqrt(150^2 - 100^2) = 111.803 mm; the thesis's printed D = 50 sqrt(2) would give 122.47 mm.
    let m = machine();
    assert!((d() - 111.803_398_874_989_5).abs() < 1e-9);
    assert!(((50.0 * 2f64.sqrt()).hypot(R) - 122.474).abs() < 1e-3, "the erratum's bar length");
    for step in STEPS {
        for deg in step.sweep() {
            let chain = nominal_distance_from_chain(&m, step, deg);
            let hand = nominal_distance_by_hand(step, deg);
            assert!((chain - step.nominal_length()).abs() < 1e-9, "{step:?} at {deg} deg: nominal length {chain} mm");
            assert!((chain - hand).abs() < 1e-9, "{step:?} at {deg} deg: chain {chain} mm, by hand {hand} mm");
        }
    }
}

/// Largest |exact - first order| (um) over the sweep of `step`, and the largest |exact| and
/// |first order| (um).
fn compare(m: &Machine, step: Step, piges: &Piges) -> (f64, f64, f64) {
    let params = piges.parameters(m);
    let (mut deviation, mut exact_max, mut model_max) = (0.0f64, 0.0f64, 0.0f64);
    for deg in step.sweep() {
        let exact = exact_dl_um(m, step, deg, &params);
        let model = piges.first_order_dl(step, deg) * 1e3;
        deviation = deviation.max((exact - model).abs());
        exact_max = exact_max.max(exact.abs());
        model_max = model_max.max(model.abs());
    }
    (deviation, exact_max, model_max)
}

#[test]
fn each_table_3_1_pige_alone_follows_the_first_order_relations() {
    // Thesis section 3.3 / digest 2.8: one PIGE at its Table 3.1 value, the others zero, evaluated
    // every 5 deg along each step; relations of digest 2.5. Tolerance: FIRST_ORDER_TOLERANCE_UM.
    let m = machine();
    let mut worst = 0.0f64;
    for (i, (symbol, iso, _)) in PIGE_NAMES.iter().enumerate() {
        let piges = Piges::table_3_1_single(i);
        for step in STEPS {
            let (deviation, exact_max, model_max) = compare(&m, step, &piges);
            eprintln!("{step:?} {symbol:>9} ({iso}): max |dL| exact {exact_max:8.4} um, first order {model_max:8.4} um, max deviation {deviation:.2e} um");
            assert!(
                deviation < FIRST_ORDER_TOLERANCE_UM,
                "{step:?}, {symbol} = {iso} alone: exact dL departs from the first-order relation by {deviation} um"
            );
            // Not trivially zero: where the relation predicts a signal, the chain shows it.
            if model_max > 1.0 {
                assert!(exact_max > 1.0, "{step:?}, {symbol}: relation predicts {model_max} um, chain gives {exact_max} um");
            }
            worst = worst.max(deviation);
        }
    }
    eprintln!("worst deviation, single PIGEs: {worst:.2e} um");
}

#[test]
fn all_eight_table_3_1_piges_together_follow_the_first_order_relations() {
    // Table 3.1 with all eight PIGEs at once: the relations superpose to first order.
    let m = machine();
    let piges = Piges::table_3_1_all();
    for step in STEPS {
        let (deviation, exact_max, model_max) = compare(&m, step, &piges);
        eprintln!(
            "{step:?} all eight: max |dL| exact {exact_max:8.4} um, first order {model_max:8.4} um, max deviation {deviation:.2e} um"
        );
        assert!(deviation < FIRST_ORDER_TOLERANCE_UM, "{step:?}, all eight PIGEs: deviation {deviation} um");
        assert!(exact_max > 1.0 && model_max > 1.0, "{step:?}: no signal ({exact_max} um exact, {model_max} um first order)");
    }
}

#[test]
fn error_values_file_gives_the_same_traces() {
    // The same Table 3.1 state through the error-values TOML (docs/design.md, Files; um and urad).
    let m = machine();
    let text = format!(
        "[constant]\nEY0A = {p}\nEZ0A = {p}\nEB0A = {o}\nEC0A = {o}\nEX0C = {p}\nEY0C = {p}\nEA0C = {o}\nEB0C = {o}\n",
        p = POSITION_UM,
        o = ORIENTATION_URAD
    );
    let model = ErrorModel::from_toml_str(&text, "table_3_1.toml", &m).expect("Table 3.1 error values load");
    let direct = Piges::table_3_1_all().parameters(&m);
    let mut from_file = vec![0.0; m.parameter_count()];
    for step in STEPS {
        for deg in step.sweep() {
            let q = step.pose(deg);
            model.values_at(&m, &q, &mut from_file);
            let a = exact_dl_um(&m, step, deg, &from_file);
            let b = exact_dl_um(&m, step, deg, &direct);
            assert!((a - b).abs() < 1e-9, "{step:?} at {deg} deg: file {a} um, vector {b} um");
        }
    }
}

#[test]
fn exact_length_is_the_difference_of_actual_and_nominal_distances() {
    // dL = |actual| - |nominal| (docs/design.md, Conventions), checked against the library's own actual and
    // nominal chains evaluated directly, all eight Table 3.1 PIGEs.
    let m = machine();
    let params = Piges::table_3_1_all().parameters(&m);
    for step in STEPS {
        let setup = step.setup();
        for deg in step.sweep() {
            let q = step.pose(deg);
            let tool = actual_chain(&m, m.tool_chain(), &q, &params).transform_point(&setup.tool_point);
            let work = actual_chain(&m, m.work_chain(), &q, &params).transform_point(&setup.work_point);
            let direct = ((tool - work).norm() - nominal_distance_from_chain(&m, step, deg)) * 1e3;
            let exact = exact_dl_um(&m, step, deg, &params);
            // |L| ~ 150 mm: the direct difference loses ~1e-13 mm to cancellation
            assert!((direct - exact).abs() < 1e-6, "{step:?} at {deg} deg: direct {direct} um, library {exact} um");
        }
    }
}

#[test]
fn fig_3_7_diagnostics() {
    // Thesis section 3.3, Figs. 3.7-3.8 / digest 2.5, 2.8.
    let m = machine();
    let theta = ORIENTATION_URAD * 1e-6;
    for (name, piges) in
        [("theta_y0a", Piges { th_y0a: theta, ..Default::default() }), ("theta_z0a", Piges { th_z0a: theta, ..Default::default() })]
    {
        let params = piges.parameters(&m);
        // Fig. 3.7(c),(d): no visible change in A1 (spindle ball on the A axis at O_R).
        let a1 = Step::A1.sweep().into_iter().map(|deg| exact_dl_um(&m, Step::A1, deg, &params).abs()).fold(0.0, f64::max);
        assert!(a1 < 0.01, "{name} in A1: max |dL| = {a1} um, expected none");
        // Fig. 3.8: a clear eccentric arc in A2, about k D theta = 13.0 um.
        let a2 = Step::A2.sweep().into_iter().map(|deg| exact_dl_um(&m, Step::A2, deg, &params).abs()).fold(0.0, f64::max);
        assert!(a2 > 10.0, "{name} in A2: max |dL| = {a2} um, expected > 10 um");
        eprintln!("{name}: max |dL| A1 {a1:.2e} um, A2 {a2:.3} um");
    }
    // Digest 2.5: e_z0a is invisible in C1 (pivot in the plane z = 0, bar radial in that plane).
    let params = Piges { e_z0a: POSITION_UM * 1e-3, ..Default::default() }.parameters(&m);
    let c1 = Step::C1.sweep().into_iter().map(|deg| exact_dl_um(&m, Step::C1, deg, &params).abs()).fold(0.0, f64::max);
    assert!(c1 < 0.01, "e_z0a in C1: max |dL| = {c1} um, expected none");
    eprintln!("e_z0a: max |dL| C1 {c1:.2e} um");
}

#[test]
fn sign_conventions() {
    let m = machine();
    // A positive EY0A moves the A axis, and with it the pivot at (0, R, 0), toward +Y, away from the
    // spindle ball at O_R: the A1 bar lengthens by exactly 10 um at ta = 0.
    let params = Piges { e_y0a: POSITION_UM * 1e-3, ..Default::default() }.parameters(&m);
    let dl = exact_dl_um(&m, Step::A1, 0.0, &params);
    assert!((dl - 10.0).abs() < 1e-6, "EY0A = +10 um: dL(A1, 0 deg) = {dl} um, expected +10 um");
    // A positive EB0A (rotation about +Y at O_R) carries the pivot at (0, R cos ta, R sin ta) toward +X
    // by R sin(ta) theta, away from the spindle ball at (-D, 0, 0):
    // dL(A2, 70 deg) = k D theta sin(70 deg) = +12.2 um.
    let theta = ORIENTATION_URAD * 1e-6;
    let params = Piges { th_y0a: theta, ..Default::default() }.parameters(&m);
    let dl = exact_dl_um(&m, Step::A2, 70.0, &params);
    let expected = R / L_E * d() * theta * 70f64.to_radians().sin() * 1e3;
    assert!(expected > 12.0 && expected < 12.5);
    assert!((dl - expected).abs() < FIRST_ORDER_TOLERANCE_UM, "EB0A = +0.01 deg: dL(A2, 70 deg) = {dl} um, expected +{expected} um");
}
