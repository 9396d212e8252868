//! The general exact kinematic chain (and its first-order Jacobian) reproduces the closed-form error
//! model of the NIST two-axis turning centre: NISTIR 5236 section 2.3, Fig. 2.2,
//! eqs. 2.10-2.26, with the machine `examples/machines/lathe2.toml`.
//!
//! NIST computes `E = T_TOOL^-1 T_WORK` (eq. 2.9), whose position part `p_E` is the workpiece point
//! relative to the tool tip, in the tool frame. trueaxis reports the tool point relative to the
//! workpiece point, actual minus nominal, in the workpiece frame. At a cutting pose (the nominal tool
//! tip on the nominal workpiece point, so the nominal part of `p_E` vanishes) the two agree to first
//! order with opposite signs: `delta = -p_E`. The frames differ by a small rotation, which only
//! changes second-order terms.
//!
//! ERRATUM: eq. 2.24 as printed contains `+ delta_x(s)` and later `- delta_x(s)` again; the second
//! one is a typo for `- delta_x(x)` (the first-order expansion of eqs. 2.16-2.23 gives it, and
//! eqs. 2.25 and 2.26 have the analogous `- delta_y(x)` and `- delta_z(x)`). [`p_e`] implements the
//! corrected form.

use nalgebra::Vector3;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::model::{jacobian, volumetric_error, Frame, JacobianWorkspace, Predictor, Setup, JACOBIAN_ROWS};

const LATHE: &str = include_str!("../../../../../examples/machines/lathe2.toml");

/// NIST constant offset of the carriage frame (eq. 2.10), mm.
const X1: f64 = 120.0;
/// NIST tool dimensions (eq. 2.13), mm.
const X4: f64 = 30.0;
const Z4: f64 = 60.0;

/// urad times mm in um.
const URAD_MM: f64 = 1e-3;

fn lathe() -> Machine {
    Machine::from_toml_str(LATHE, "lathe2.toml").expect("lathe2.toml loads")
}

/// The NIST error symbols at one pose: translations in um, rotations in urad. `_z` carriage,
/// `_x` cross slide, `_t` turret, `_c` cutting tool, `_s` spindle, `_w` workpiece.
/// `dx_z` is the whole `delta_x(z) = delta'_x(z) + alpha_p z`, `dz_x` the whole
/// `delta_z(x) = delta'_z(x) + alpha_o x`. `eps_z(s)` is zero by assumption (eq. 2.20).
#[derive(Clone, Copy, Debug, Default)]
struct Nist {
    dx_z: f64,
    dy_z: f64,
    dz_z: f64,
    ex_z: f64,
    ey_z: f64,
    ez_z: f64,
    dx_x: f64,
    dy_x: f64,
    dz_x: f64,
    ex_x: f64,
    ey_x: f64,
    ez_x: f64,
    dx_t: f64,
    dy_t: f64,
    dz_t: f64,
    ex_t: f64,
    ey_t: f64,
    ez_t: f64,
    dx_c: f64,
    dy_c: f64,
    dz_c: f64,
    dx_s: f64,
    dy_s: f64,
    dz_s: f64,
    ex_s: f64,
    ey_s: f64,
    dx_w: f64,
    dy_w: f64,
    dz_w: f64,
}

type Field = fn(&mut Nist) -> &mut f64;

/// Every NIST symbol with the ISO 230 parameter that carries it in `lathe2.toml`. The turret is
/// locked and its frame is the cross-slide frame, so its errors fold into those of X.
const SYMBOLS: [(&str, &str, Field); 29] = [
    ("delta_x(z)", "EXZ", |n| &mut n.dx_z),
    ("delta_y(z)", "EYZ", |n| &mut n.dy_z),
    ("delta_z(z)", "EZZ", |n| &mut n.dz_z),
    ("eps_x(z)", "EAZ", |n| &mut n.ex_z),
    ("eps_y(z)", "EBZ", |n| &mut n.ey_z),
    ("eps_z(z)", "ECZ", |n| &mut n.ez_z),
    ("delta_x(x)", "EXX", |n| &mut n.dx_x),
    ("delta_y(x)", "EYX", |n| &mut n.dy_x),
    ("delta_z(x)", "EZX", |n| &mut n.dz_x),
    ("eps_x(x)", "EAX", |n| &mut n.ex_x),
    ("eps_y(x)", "EBX", |n| &mut n.ey_x),
    ("eps_z(x)", "ECX", |n| &mut n.ez_x),
    ("delta_x(t)", "EXX", |n| &mut n.dx_t),
    ("delta_y(t)", "EYX", |n| &mut n.dy_t),
    ("delta_z(t)", "EZX", |n| &mut n.dz_t),
    ("eps_x(t)", "EAX", |n| &mut n.ex_t),
    ("eps_y(t)", "EBX", |n| &mut n.ey_t),
    ("eps_z(t)", "ECX", |n| &mut n.ez_t),
    ("delta_x(c)", "TX", |n| &mut n.dx_c),
    ("delta_y(c)", "TY", |n| &mut n.dy_c),
    ("delta_z(c)", "TZ", |n| &mut n.dz_c),
    ("delta_x(s)", "EXC", |n| &mut n.dx_s),
    ("delta_y(s)", "EYC", |n| &mut n.dy_s),
    ("delta_z(s)", "EZC", |n| &mut n.dz_s),
    ("eps_x(s)", "EAC", |n| &mut n.ex_s),
    ("eps_y(s)", "EBC", |n| &mut n.ey_s),
    ("delta_x(w)", "WX", |n| &mut n.dx_w),
    ("delta_y(w)", "WY", |n| &mut n.dy_w),
    ("delta_z(w)", "WZ", |n| &mut n.dz_w),
];

/// Error part of `p_E` (um) at axis positions `x`, `z` (mm) and the cutting point
/// `x(w) = X1 + x + X4`, `z(w) = z + Z4`: NISTIR 5236 eqs. 2.24-2.26, with the eq. 2.24 erratum
/// corrected (`- delta_x(x)` where the print repeats `- delta_x(s)`). The nominal terms
/// `x(w) - X4 - x - X1` and `z(w) - Z4 - z` cancel at the cutting point.
fn p_e(n: &Nist, x: f64, z: f64) -> [f64; 3] {
    let (xw, zw) = (X1 + x + X4, z + Z4);
    let r = URAD_MM;
    let ey = n.ey_z + n.ey_x + n.ey_t;
    let ez = n.ez_z + n.ez_x + n.ez_t;
    let ex = n.ex_z + n.ex_x + n.ex_t;
    // eq. 2.24 (corrected)
    let pex = n.dx_w + n.ey_s * zw * r + n.dx_s - n.dx_c - ey * Z4 * r - n.dx_t - n.dx_x - n.dx_z;
    // eq. 2.25
    let pey = n.dy_w - n.ex_s * zw * r + n.dy_s - ez * X4 * r - n.dy_c + ex * Z4 * r - n.dy_t - n.ez_z * x * r - n.dy_x - n.dy_z;
    // eq. 2.26
    let pez = -n.ey_s * xw * r + n.dz_w + n.dz_s + ey * X4 * r - n.dz_c - n.dz_t + n.ey_z * x * r - n.dz_x - n.dz_z;
    [pex, pey, pez]
}

/// Orientation of the tool relative to the workpiece (urad), first order: the rotation parts of
/// eqs. 2.16-2.20 (not printed in NISTIR 5236, which gives only `p_E`).
fn tool_rotation(n: &Nist) -> [f64; 3] {
    [n.ex_z + n.ex_x + n.ex_t - n.ex_s, n.ey_z + n.ey_x + n.ey_t - n.ey_s, n.ez_z + n.ez_x + n.ez_t]
}

/// Constants (um, urad) of an error-values TOML giving the NIST symbols of `n` to the ISO
/// parameters of `lathe2.toml`, turret errors folded into the X errors.
fn constants_toml(n: &Nist) -> String {
    let mut iso: Vec<(&str, f64)> = Vec::new();
    for (_, name, field) in SYMBOLS {
        let v = *field(&mut n.clone());
        match iso.iter_mut().find(|(k, _)| *k == name) {
            Some((_, sum)) => *sum += v,
            None => iso.push((name, v)),
        }
    }
    let mut text = String::from("[constant]\n");
    for (name, v) in iso.into_iter().filter(|(_, v)| *v != 0.0) {
        text += &format!("{name} = {v:?}\n");
    }
    text
}

/// Axis positions in canonical order (X Z C) for cross slide `x`, carriage `z` (mm), spindle `c` (rad).
fn pose(machine: &Machine, x: f64, z: f64, c: f64) -> Vec<f64> {
    let mut q = vec![0.0; machine.axis_count()];
    q[machine.axis_index('X').unwrap()] = x;
    q[machine.axis_index('Z').unwrap()] = z;
    q[machine.axis_index('C').unwrap()] = c;
    q
}

/// The cutting setup of pose `x`, `z`: the machine's tool point and the workpiece point
/// `(x(w), 0, z(w))` it nominally touches.
fn cutting_setup(machine: &Machine, x: f64, z: f64) -> Setup {
    Setup { tool_point: machine.tool_point, work_point: Vector3::new(X1 + x + X4, 0.0, z + Z4) }
}

// ---------------------------------------------------------------------------------------------
// A realistic error state, with position-dependent carriage and cross-slide errors.

/// NIST parallelism error alpha_p between z motion and the spindle axis (urad).
const ALPHA_P: f64 = 25.0;
/// NIST orthogonality error alpha_o between x motion and the spindle axis (urad).
const ALPHA_O: f64 = -30.0;
/// x straightness of the carriage delta'_x(z) (um, ascending powers of z in mm).
const STRAIGHT_XZ: [f64; 3] = [4.0, 0.0, 2e-5];
/// z straightness of the cross slide delta'_z(x) (um, ascending powers of x in mm).
const STRAIGHT_ZX: [f64; 3] = [2.5, 0.0, -1.5e-4];
/// Carriage displacement error delta_z(z) (um) as a table over z (mm).
const EZZ_TABLE: ([f64; 2], [f64; 2]) = ([0.0, 400.0], [0.0, 12.0]);
/// Carriage yaw eps_y(z) (urad) as a table over z (mm).
const EBZ_TABLE: ([f64; 3], [f64; 3]) = ([0.0, 200.0, 400.0], [10.0, 35.0, 20.0]);

fn polynomial(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, k| acc * t + k)
}

fn interpolate(p: &[f64], v: &[f64], t: f64) -> f64 {
    let i = p.windows(2).position(|w| t <= w[1]).unwrap_or(p.len() - 2);
    v[i] + (t - p[i]) / (p[i + 1] - p[i]) * (v[i + 1] - v[i])
}

/// The NIST symbols of the realistic error state at cross slide `x`, carriage `z` (mm). Turret errors
/// are zero (they fold into the X errors; see `each_nist_term_has_its_sign_and_abbe_arm`).
fn realistic_at(x: f64, z: f64) -> Nist {
    Nist {
        dx_z: polynomial(&STRAIGHT_XZ, z) + ALPHA_P * URAD_MM * z,
        dy_z: -6.0,
        dz_z: interpolate(&EZZ_TABLE.0, &EZZ_TABLE.1, z),
        ex_z: 15.0,
        ey_z: interpolate(&EBZ_TABLE.0, &EBZ_TABLE.1, z),
        ez_z: -22.0,
        dx_x: -7.0,
        dy_x: 3.5,
        dz_x: polynomial(&STRAIGHT_ZX, x) + ALPHA_O * URAD_MM * x,
        ex_x: -18.0,
        ey_x: 45.0,
        ez_x: 28.0,
        dx_c: 5.0,
        dy_c: -2.0,
        dz_c: -8.0,
        dx_s: 3.0,
        dy_s: -4.5,
        dz_s: 11.0,
        ex_s: 20.0,
        ey_s: -35.0,
        dx_w: -2.5,
        dy_w: 6.0,
        dz_w: 14.0,
        ..Nist::default()
    }
}

/// The realistic error state as an error-values TOML: `delta_x(z)` and `delta_z(x)` as polynomials
/// that include the parallelism and orthogonality slopes, `EZZ` and `EBZ` as tables, and the
/// constants of `n` (its position-dependent fields are ignored).
fn realistic_toml(n: &Nist) -> String {
    let list = |v: &[f64]| v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(", ");
    let mut exz = STRAIGHT_XZ;
    exz[1] += ALPHA_P * URAD_MM;
    let mut ezx = STRAIGHT_ZX;
    ezx[1] += ALPHA_O * URAD_MM;
    let constants = Nist { dx_z: 0.0, dz_z: 0.0, ey_z: 0.0, dz_x: 0.0, ..*n };
    format!(
        "name = \"NIST turning centre, realistic errors\"\n{}\n[polynomial.EXZ]\ncoefficients = [{}]\n[polynomial.EZX]\ncoefficients = [{}]\n\
         [table.EZZ]\nposition = [{}]\nvalue = [{}]\n[table.EBZ]\nposition = [{}]\nvalue = [{}]\n",
        constants_toml(&constants),
        list(&exz),
        list(&ezx),
        list(&EZZ_TABLE.0),
        list(&EZZ_TABLE.1),
        list(&EBZ_TABLE.0),
        list(&EBZ_TABLE.1)
    )
}

const POSES: [(f64, f64); 6] = [(-100.0, 50.0), (-100.0, 250.0), (0.0, 50.0), (0.0, 250.0), (40.0, 50.0), (40.0, 250.0)];

/// Crude bound (um) on the second-order remainder of the exact chain: `2 (E^2 L + E D)`, with `E` the
/// sum of the rotation magnitudes (rad), `D` the sum of the translation magnitudes (mm) and `L` the
/// longest lever arm (mm) from an error centre to the tool tip or workpiece point. It covers the
/// quadratic part of each `exp([eps]x)` (`eps^2 L / 2`), the products of two errors along the chains
/// (`eps_i eps_j L`, `eps_i d_j`) and the rotation of the first-order error vector (size
/// `<= E L + D`) into the workpiece frame instead of the tool frame (`eps(s) (E L + D)`); third-order
/// terms (`E^3 L`, about 1e-5 um here) are far inside the slack.
fn second_order_bound(n: &Nist, x: f64, z: f64) -> f64 {
    let rot = [n.ex_z, n.ey_z, n.ez_z, n.ex_x, n.ey_x, n.ez_x, n.ex_t, n.ey_t, n.ez_t, n.ex_s, n.ey_s];
    let tra = [
        n.dx_z, n.dy_z, n.dz_z, n.dx_x, n.dy_x, n.dz_x, n.dx_t, n.dy_t, n.dz_t, n.dx_c, n.dy_c, n.dz_c, n.dx_s, n.dy_s, n.dz_s, n.dx_w,
        n.dy_w, n.dz_w,
    ];
    let e: f64 = rot.iter().map(|v| v.abs() * 1e-6).sum();
    let d: f64 = tra.iter().map(|v| v.abs() * 1e-3).sum();
    // arms: carriage origin (X1, 0, z), cross slide origin (X1 + x, 0, z), spindle origin to the cutting point
    let tip = Vector3::new(X1 + x + X4, 0.0, z + Z4);
    let l = [Vector3::new(X1, 0.0, z), Vector3::new(X1 + x, 0.0, z), Vector3::zeros()].iter().map(|c| (tip - c).norm()).fold(0.0, f64::max);
    2.0 * (e * e * l + e * d) * 1e3
}

// ---------------------------------------------------------------------------------------------

#[test]
fn lathe2_toml_encodes_the_nist_turning_centre() {
    let m = lathe();
    assert_eq!(m.structure.to_string(), "wCbZXt");
    assert_eq!(m.axis_letters(), "XZC");
    assert_eq!(m.source.as_deref(), Some("NISTIR 5236 section 2.3, Fig. 2.2, eqs. 2.10-2.26"));
    assert!(!m.name.is_empty());
    let axis = |c: char| &m.axes()[m.axis_index(c).unwrap()];
    // eq. 2.10 / 2.11: carriage frame at (X1, 0, z), cross slide at (X1 + x, 0, z)
    assert_eq!(axis('Z').point, Vector3::new(X1, 0.0, 0.0));
    assert_eq!(axis('X').point, Vector3::new(X1, 0.0, 0.0));
    assert_eq!(axis('Z').direction, Vector3::z());
    assert_eq!(axis('X').direction, Vector3::x());
    assert_eq!(axis('X').range, Some([-150.0, 50.0]));
    assert_eq!(axis('Z').range, Some([0.0, 400.0]));
    // eq. 2.14: the spindle at the reference origin, about z, continuous
    assert_eq!(axis('C').point, Vector3::zeros());
    assert_eq!(axis('C').direction, Vector3::z());
    assert_eq!(axis('C').range, None);
    // eq. 2.13: tool tip at (X4, 0, Z4) in the turret (= cross slide) frame
    assert_eq!(m.tool_point, Vector3::new(X1 + X4, 0.0, Z4));
    let chain = |c: &[usize]| c.iter().map(|&k| m.axes()[k].letter).collect::<String>();
    assert_eq!(chain(m.tool_chain()), "ZX", "eq. 2.22: T_TOOL = 0T_z zT_x xT_t tT_c");
    assert_eq!(chain(m.work_chain()), "C", "eq. 2.23: T_WORK = 0T_s sT_w");
}

/// Test 1, exact chain: with every NIST error present at realistic size (translations 2-15 um,
/// rotations 10-45 urad, alpha_p 25 urad, alpha_o -30 urad), the exact volumetric error at a cutting
/// pose equals `-p_E` of eqs. 2.24-2.26 up to the second-order remainder. Tolerance 0.005 um; the
/// remainder (observed 0.0009-0.0013 um) is also checked against the crude bound
/// `2 (E^2 L + E D)` of [`second_order_bound`] (0.04-0.07 um here, so 0.005 um is the tighter,
/// binding tolerance) and shown to be second order: scaling every error by 10 scales it by 100 (+-2).
#[test]
fn exact_chain_reproduces_eqs_2_24_to_2_26() {
    let machine = lathe();
    let errors = ErrorModel::from_toml_str(&realistic_toml(&realistic_at(0.0, 0.0)), "realistic", &machine).expect("error values load");
    let mut values = vec![0.0; machine.parameter_count()];
    for (x, z) in POSES {
        let q = pose(&machine, x, z, 0.0);
        let nist = realistic_at(x, z);
        let expected = p_e(&nist, x, z).map(|v| -v);
        let mut predictor = Predictor::new(&machine, &errors);
        predictor.setup = cutting_setup(&machine, x, z);
        let got = predictor.predict(&q).to_user_units();
        let residual = (0..3).map(|i| (got[i] - expected[i]).abs()).fold(0.0, f64::max);
        let bound = second_order_bound(&nist, x, z);
        println!(
            "x {x:6} z {z:5}: delta {:9.4} {:9.4} {:9.4} um, -p_E {:9.4} {:9.4} {:9.4} um, residual {residual:.2e} um, bound {bound:.2e} um",
            got[0], got[1], got[2], expected[0], expected[1], expected[2]
        );
        assert!(residual < 0.005, "x {x} z {z}: exact {:?} vs -p_E (eqs. 2.24-2.26) {expected:?} um", &got[..3]);
        assert!(residual <= bound, "x {x} z {z}: residual {residual} um exceeds the second-order bound {bound} um");
        // the error is not trivially small: a sign or arm mistake would show
        assert!(expected.iter().map(|v| v.abs()).fold(0.0, f64::max) > 10.0);

        // orientation, first order from the rotation parts of eqs. 2.16-2.20 (tolerance 0.05 urad,
        // the second-order size of products of the ~100 urad rotations)
        let rot = tool_rotation(&nist);
        for i in 0..3 {
            assert!((got[3 + i] - rot[i]).abs() < 0.05, "x {x} z {z}: orientation {i}: {} vs {} urad", got[3 + i], rot[i]);
        }

        // second order: the remainder scales with the square of the errors
        errors.values_at(&machine, &q, &mut values);
        let scaled: Vec<f64> = values.iter().map(|v| v * 10.0).collect();
        let big = volumetric_error(&machine, &q, &scaled, &predictor.setup, Frame::Workpiece).to_user_units();
        let residual10 = (0..3).map(|i| (big[i] - 10.0 * expected[i]).powi(2)).sum::<f64>().sqrt();
        let residual1 = (0..3).map(|i| (got[i] - expected[i]).powi(2)).sum::<f64>().sqrt();
        let ratio = residual10 / residual1;
        assert!((ratio - 100.0).abs() < 2.0, "x {x} z {z}: remainder ratio {ratio} for errors x10, expected 100 (second order)");
    }
}

/// Test 1, first-order model: the Jacobian times the parameter vector is linear in the errors, so
/// it equals `-p_E` of eqs. 2.24-2.26 exactly, up to rounding (tolerance 1e-9 um), and the
/// orientation rows equal the first-order rotation sum (1e-9 urad).
#[test]
fn jacobian_reproduces_eqs_2_24_to_2_26_exactly() {
    let machine = lathe();
    let errors = ErrorModel::from_toml_str(&realistic_toml(&realistic_at(0.0, 0.0)), "realistic", &machine).expect("error values load");
    let n = machine.parameter_count();
    let mut values = vec![0.0; n];
    let mut ws = JacobianWorkspace::default();
    let mut jac = vec![0.0; JACOBIAN_ROWS * n];
    for (x, z) in POSES {
        let q = pose(&machine, x, z, 0.0);
        errors.values_at(&machine, &q, &mut values);
        // the error functions are evaluated at the own axis position (parallelism, orthogonality)
        let nist = realistic_at(x, z);
        let (_, exz) = machine.parse_parameter("EXZ").unwrap();
        let (_, ezx) = machine.parse_parameter("EZX").unwrap();
        assert!((values[exz] * 1e3 - nist.dx_z).abs() < 1e-12, "delta_x(z) = delta'_x(z) + alpha_p z");
        assert!((values[ezx] * 1e3 - nist.dz_x).abs() < 1e-12, "delta_z(x) = delta'_z(x) + alpha_o x");

        jacobian(&machine, &q, &cutting_setup(&machine, x, z), Frame::Workpiece, &mut ws, &mut jac);
        let row = |r: usize| (0..n).map(|j| jac[r * n + j] * values[j]).sum::<f64>();
        let expected = p_e(&nist, x, z);
        let rot = tool_rotation(&nist);
        for i in 0..3 {
            let first_order = row(i) * 1e3;
            assert!(
                (first_order + expected[i]).abs() < 1e-9,
                "x {x} z {z} component {i}: J p = {first_order} um, -p_E = {} um",
                -expected[i]
            );
            let rotation = row(3 + i) * 1e6;
            assert!((rotation - rot[i]).abs() < 1e-9, "x {x} z {z} rotation {i}: {rotation} vs {} urad", rot[i]);
        }
    }
}

/// Test 2: one NIST error at a time (translations 8 um, rotations 50 urad, both signs), every
/// component of the exact chain equals the single term of eqs. 2.24-2.26 with its sign and Abbe arm
/// (tolerance 0.005 um; the remainder of a single error is below 0.001 um). Turret errors, given as
/// X errors, reproduce their own terms: they fold exactly into the cross-slide errors.
#[test]
fn each_nist_term_has_its_sign_and_abbe_arm() {
    let machine = lathe();
    for (symbol, iso, field) in SYMBOLS {
        let rotation = symbol.starts_with("eps");
        for magnitude in [1.0, -1.0] {
            let mut nist = Nist::default();
            *field(&mut nist) = magnitude * if rotation { 50.0 } else { 8.0 };
            let errors = ErrorModel::from_toml_str(&constants_toml(&nist), symbol, &machine).expect("constants load");
            let mut largest: f64 = 0.0;
            for (x, z) in POSES {
                let mut predictor = Predictor::new(&machine, &errors);
                predictor.setup = cutting_setup(&machine, x, z);
                let got = predictor.predict(&pose(&machine, x, z, 0.0)).to_user_units();
                let expected = p_e(&nist, x, z).map(|v| -v);
                for i in 0..3 {
                    assert!(
                        (got[i] - expected[i]).abs() < 0.005,
                        "{symbol} = {iso} = {magnitude:+}, x {x} z {z}, component {}: exact {} um, -p_E {} um",
                        ["x", "y", "z"][i],
                        got[i],
                        expected[i]
                    );
                    largest = largest.max(expected[i].abs());
                }
            }
            // every term moves the tool by at least 1 um somewhere, so a wrong sign cannot pass
            assert!(largest > 1.0, "{symbol}: closed form too small to test its sign ({largest} um)");
        }
    }

    // The Abbe example written out: carriage yaw eps_y(z) = +50 urad rotates the cross slide and tool
    // about the carriage origin (X1, 0, z); the tool tip is at the arm (x + X4, 0, Z4) from it, so it
    // moves by eps x arm = (eps Z4, 0, -eps (x + X4)) relative to the workpiece:
    // -p_Ex = +[eps_y(z)] Z4 (eq. 2.24), -p_Ez = -[eps_y(z)] X4 - eps_y(z) x (eq. 2.26).
    let errors = ErrorModel::from_toml_str("[constant]\nEBZ = 50.0\n", "EBZ", &machine).unwrap();
    for (x, z, dx, dz) in [(-100.0, 250.0, 3.0, 3.5), (40.0, 50.0, 3.0, -3.5), (0.0, 400.0, 3.0, -1.5)] {
        let mut predictor = Predictor::new(&machine, &errors);
        predictor.setup = cutting_setup(&machine, x, z);
        let got = predictor.predict(&pose(&machine, x, z, 0.0)).to_user_units();
        assert!(
            (got[0] - dx).abs() < 0.005 && got[1].abs() < 0.005 && (got[2] - dz).abs() < 0.005,
            "eps_y(z) at x {x} z {z}: {got:?}, expected ({dx}, 0, {dz}) um"
        );
    }
    // spindle tilt eps_y(s) = +50 urad tilts the workpiece about the spindle nose: the cutting point
    // (x(w), 0, z(w)) moves by (eps z(w), 0, -eps x(w)); the tool relative to it moves the opposite
    // way: -p_Ex = -eps_y(s) z(w) (eq. 2.24), -p_Ez = +eps_y(s) x(w) (eq. 2.26).
    let errors = ErrorModel::from_toml_str("[constant]\nEBC = 50.0\n", "EBC", &machine).unwrap();
    let (x, z) = (-100.0, 250.0); // x(w) = 50, z(w) = 310
    let mut predictor = Predictor::new(&machine, &errors);
    predictor.setup = cutting_setup(&machine, x, z);
    let got = predictor.predict(&pose(&machine, x, z, 0.0)).to_user_units();
    assert!(
        (got[0] + 15.5).abs() < 0.005 && got[1].abs() < 0.005 && (got[2] - 2.5).abs() < 0.005,
        "eps_y(s): {got:?}, expected (-15.5, 0, 2.5) um"
    );
}

/// NIST eq. 2.14 takes the spindle angle as zero "since there is no significance to the angular
/// position": with spindle drift constant in angle (and no workpiece offset, which turns with the
/// part), the error in the machine frame at any C angle, for the workpiece point that the rotation
/// brings to the same cutting point, equals the C = 0 result (tolerance 1e-8 um, rounding).
#[test]
fn spindle_angle_has_no_significance() {
    let machine = lathe();
    let no_workpiece_offset = Nist { dx_w: 0.0, dy_w: 0.0, dz_w: 0.0, ..realistic_at(0.0, 0.0) };
    let errors = ErrorModel::from_toml_str(&realistic_toml(&no_workpiece_offset), "no W", &machine).unwrap();
    for (x, z) in POSES {
        let mut predictor = Predictor::new(&machine, &errors);
        predictor.frame = Frame::Machine;
        predictor.setup = cutting_setup(&machine, x, z);
        let at_zero = predictor.predict(&pose(&machine, x, z, 0.0)).to_user_units();
        for c_deg in [30.0_f64, 137.0, -90.0, 250.0] {
            let c = c_deg.to_radians();
            let cutting = cutting_setup(&machine, x, z).work_point;
            // the part point that C = c brings to the cutting point
            let (s, co) = c.sin_cos();
            let at_home = Vector3::new(co * cutting.x + s * cutting.y, -s * cutting.x + co * cutting.y, cutting.z);
            predictor.setup.work_point = at_home;
            let got = predictor.predict(&pose(&machine, x, z, c)).to_user_units();
            for i in 0..6 {
                assert!((got[i] - at_zero[i]).abs() < 1e-8, "x {x} z {z} C {c_deg} deg, column {i}: {} vs {} at C = 0", got[i], at_zero[i]);
            }
        }
    }
}
