//! Laser interferometer and electronic level readings on the exact chain (src/instruments/laser.rs,
//! level.rs, direct.rs): closed forms of the Abbe effect and of level readings, and round trips
//! simulate -> fit -> recover with the errors of examples/errors/vmc3.toml as the truth.

use trueaxis::data::CsvTable;
use trueaxis::error_model::{BasisSpec, ErrorFunction, ErrorModel};
use trueaxis::geometry::Vec3;
use trueaxis::identify::{run_direct_fit, DirectFitRequest, DirectModel, FitOptions};
use trueaxis::instruments::{DirectInstrument, DirectKind, DirectSetup, Laser, LaserOptics, Level, LevelBody};
use trueaxis::machine::{Machine, ParameterId, Side};
use trueaxis::model::Setup;

fn vmc3() -> Machine {
    Machine::from_toml_str(include_str!("../../../../../examples/machines/vmc3.toml"), "vmc3.toml").unwrap()
}

fn truth(m: &Machine) -> ErrorModel {
    ErrorModel::from_toml_str(include_str!("../../../../../examples/errors/vmc3.toml"), "vmc3 errors", m).unwrap()
}

fn only(m: &Machine, name: &str, f: ErrorFunction) -> ErrorModel {
    let mut e = ErrorModel::zero(m);
    e.set(m, ParameterId::parse(name).unwrap(), f).unwrap();
    e
}

fn id(name: &str) -> ParameterId {
    ParameterId::parse(name).unwrap()
}

/// Seeded normal noise of standard deviation `sigma`.
fn noise(n: usize, sigma: f64, seed: u64) -> Vec<f64> {
    use rand::SeedableRng;
    use rand_distr::Distribution;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let z: f64 = rand_distr::StandardNormal.sample(&mut rng);
            sigma * z
        })
        .collect()
}

/// X from -400 to 400 mm every 10 mm, Y = 0, Z = -200 (tool point 200 mm above the table).
fn x_poses() -> (Vec<f64>, Vec<f64>) {
    let xs: Vec<f64> = (0..=80).map(|i| -400.0 + 10.0 * i as f64).collect();
    let poses = xs.iter().flat_map(|x| [*x, 0.0, -200.0]).collect();
    (xs, poses)
}

/// The linear optics of EXX with the beam line 80 mm beside (y) and 150 mm above (z) the tool point.
fn exx_laser(m: &Machine) -> DirectInstrument {
    let i = DirectInstrument::for_parameter(m, &id("EXX"), Some(DirectKind::LaserLinear), &DirectSetup::of_machine(m)).unwrap();
    i.with_optics_offset(m, &[0.0, 0.0, -200.0], [80.0, 150.0]).unwrap()
}

#[test]
fn linear_optics_read_the_abbe_effect_of_pitch_and_yaw_in_closed_form() {
    // X carries the table: a pitch b (urad) about y through the X reference point (on the table
    // surface) moves the table point at the optics, 350 mm above it, by +b * 350e-3 um in x; the
    // reading (tool relative to the table) is -b * 0.35 um. A yaw c about z moves it by
    // -c * 80e-3 um (the optics at y = 80): reading +c * 0.08. Positioning EXX: reading -EXX.
    let m = vmc3();
    let laser = exx_laser(&m);
    let (xs, poses) = x_poses();
    for (name, f, per_unit) in [
        ("EBX", ErrorFunction::polynomial(vec![2.0, 0.02]).unwrap(), -0.35),
        ("ECX", ErrorFunction::polynomial(vec![1.0, -0.015]).unwrap(), 0.08),
        ("EXX", ErrorFunction::polynomial(vec![0.5, 0.01]).unwrap(), -1.0),
    ] {
        let readings = laser.simulate(&m, &only(&m, name, f.clone()), &poses, None);
        for (x, r) in xs.iter().zip(&readings) {
            let want = per_unit * f.evaluate(*x);
            // second order: (10 urad)^2 * 350 mm = 3.5e-5 um
            assert!((r - want).abs() < 1e-4, "{name} at x = {x}: reading {r} um, closed form {want}");
        }
    }
    // the interferometer on either body reads the same to first order
    let DirectInstrument::Laser(on_tool) = laser else { unreachable!() };
    assert_eq!(on_tool.optics, LaserOptics::Linear { beam: Vec3::x() });
    assert_eq!(on_tool.beam_on, Side::Tool, "X carries the workpiece: the interferometer stands on the tool side");
    let on_work = Laser { beam_on: Side::Workpiece, ..on_tool };
    let errors = truth(&m);
    let a = DirectInstrument::Laser(on_tool).simulate(&m, &errors, &poses, None);
    let b = DirectInstrument::Laser(on_work).simulate(&m, &errors, &poses, None);
    for (x, (a, b)) in xs.iter().zip(a.iter().zip(&b)) {
        assert!((a - b).abs() < 1e-3, "x = {x}: {a} vs {b}");
    }
}

fn table_of(xs: &[f64], readings: &[f64]) -> CsvTable {
    let mut text = String::from("target,dev\n");
    for (x, r) in xs.iter().zip(readings) {
        text += &format!("{x},{r}\n");
    }
    CsvTable::from_reader(text.as_bytes(), "simulated.csv").unwrap()
}

fn piecewise(degree: usize, knots: Vec<f64>) -> BasisSpec {
    BasisSpec {
        family: "piecewise".into(),
        degree,
        knots,
        continuity: vec![0],
        constant: true,
        constraint: "none".into(),
        domain: [-400.0, 400.0],
        periodic: vec![],
    }
}

fn fit(
    m: &Machine,
    parameter: &str,
    instrument: DirectInstrument,
    known: ErrorModel,
    table: &CsvTable,
    spec: BasisSpec,
) -> trueaxis::identify::DirectFitReport {
    let request = DirectFitRequest {
        parameter: id(parameter),
        position_column: "target".into(),
        value_column: "dev".into(),
        direction: None,
        remove_drift: false,
        refine_wavelength: None,
        options: FitOptions { spec, stepwise_level: None, prediction_level: 0.95 },
        model: Some(DirectModel { machine: m.clone(), known, fixed_pose: vec![0.0, 0.0, -200.0], instrument }),
        corrections: vec![],
    };
    run_direct_fit(table, &request).unwrap()
}

#[test]
fn positioning_error_is_recovered_with_the_abbe_terms_from_the_chain() {
    // truth: all 21 errors of vmc3.toml; EXX is the table -5, -2, 0, 3, 6.5 um at -400..400 step 200
    let m = vmc3();
    let errors = truth(&m);
    let laser = exx_laser(&m);
    let (xs, poses) = x_poses();
    let e = noise(xs.len(), 0.05, 5);
    let readings: Vec<f64> = laser.simulate(&m, &errors, &poses, None).iter().zip(&e).map(|(r, n)| r + n).collect();
    let table = table_of(&xs, &readings);
    let spec = piecewise(1, vec![-200.0, 0.0, 200.0]);
    let exx = |x: f64| {
        [(-400.0, -5.0), (-200.0, -2.0), (0.0, 0.0), (200.0, 3.0), (400.0, 6.5)]
            .windows(2)
            .find(|w| x <= w[1].0)
            .map(|w| w[0].1 + (w[1].1 - w[0].1) * (x - w[0].0) / 200.0)
            .unwrap()
    };
    // the known errors (here: the truth; the fitted parameter's own entry is ignored) enter through the chain
    let with = fit(&m, "EXX", laser, errors.clone(), &table, spec.clone());
    // EXX is recovered up to its constant (a laser has an arbitrary zero): within 0.05 um
    // (about 4 standard deviations of the fitted function with 0.05 um noise on 81 readings)
    let f = &with.fitted.function;
    for x in [-400.0, -310.0, -200.0, -55.0, 0.0, 130.0, 200.0, 333.0, 400.0] {
        let got = f.evaluate(x) - f.evaluate(0.0);
        assert!((got - exx(x)).abs() < 0.05, "EXX({x}) = {got}, truth {}", exx(x));
    }
    assert!((with.fitted.fit.sigma - 0.05).abs() < 0.015, "residual {}", with.fitted.fit.sigma);
    // without the angular errors the fit carries their Abbe terms: EBX * 0.35 - ECX * 0.08 (um,
    // EBX = 2 + 0.02 x, ECX = -0.015 x urad), exactly in the basis, the same noise in both fits
    let without = fit(&m, "EXX", laser, ErrorModel::zero(&m), &table, spec);
    let g = &without.fitted.function;
    for x in [-400.0, -123.0, 0.0, 250.0, 400.0] {
        let difference = (g.evaluate(x) - f.evaluate(x)) - (g.evaluate(0.0) - f.evaluate(0.0));
        let abbe = 0.02 * x * 0.35 + 0.015 * x * 0.08;
        assert!((difference - abbe).abs() < 0.02, "Abbe term at {x}: {difference} um, closed form {abbe}");
    }
}

/// A reading (um) as a function of the position (mm).
type ClosedForm = Box<dyn Fn(f64) -> f64>;

#[test]
fn straightness_with_yaw_and_roll_known_is_recovered() {
    // EYX (straightness in y, 1.5e-5 x^2 um) read by straightness optics on the beam line 150 mm above
    // the tool point (350 mm above the table): the roll EAX (0.01 x urad) adds +EAX * 0.35 um. The yaw
    // ECX acts about the table's moving reference point (x = 0 on the table): with the interferometer
    // (the reference line) on the stationary spindle side and the prism on the table, at that point,
    // it adds nothing; with the reference line on the table and the prism in the spindle, the line
    // turns about the reference point x mm away from the prism: -ECX * x / 1000 um.
    // With the errors known, both set-ups recover EYX.
    let m = vmc3();
    let errors = truth(&m);
    let (xs, poses) = x_poses();
    for beam_on in [Side::Tool, Side::Workpiece] {
        let setup = DirectSetup { beam_on: Some(beam_on), ..DirectSetup::of_machine(&m) };
        let optics = DirectInstrument::for_parameter(&m, &id("EYX"), None, &setup).unwrap();
        assert!(matches!(optics, DirectInstrument::Laser(Laser { optics: LaserOptics::Straightness { .. }, .. })));
        let optics = optics.with_optics_offset(&m, &[0.0, 0.0, -200.0], [0.0, 150.0]).unwrap();
        let yaw_lever = if beam_on == Side::Tool { 0.0 } else { 1.0 };
        let closed_forms: [(&str, ErrorFunction, ClosedForm); 3] = [
            ("EYX", ErrorFunction::polynomial(vec![0.0, 0.0, 1.5e-5]).unwrap(), Box::new(|x| -1.5e-5 * x * x)),
            ("EAX", ErrorFunction::polynomial(vec![0.0, 0.01]).unwrap(), Box::new(|x| 0.01 * x * 0.35)),
            ("ECX", ErrorFunction::polynomial(vec![0.0, -0.015]).unwrap(), Box::new(move |x| yaw_lever * 0.015 * x * x * 1e-3)),
        ];
        for (name, f, want) in &closed_forms {
            let r = optics.simulate(&m, &only(&m, name, f.clone()), &poses, None);
            for (x, r) in xs.iter().zip(&r) {
                assert!((r - want(*x)).abs() < 1e-4, "{beam_on:?}, {name} at {x}: {r} vs {}", want(*x));
            }
        }
        let e = noise(xs.len(), 0.05, 9);
        let readings: Vec<f64> = optics.simulate(&m, &errors, &poses, None).iter().zip(&e).map(|(r, n)| r + n).collect();
        let report = fit(&m, "EYX", optics, errors.clone(), &table_of(&xs, &readings), piecewise(2, vec![]));
        let f = &report.fitted.function;
        for x in [-400.0, -150.0, 0.0, 220.0, 400.0] {
            let got = f.evaluate(x) - f.evaluate(0.0);
            assert!((got - 1.5e-5 * x * x).abs() < 0.05, "{beam_on:?}: EYX({x}) = {got}, truth {}", 1.5e-5 * x * x);
        }
    }
}

#[test]
fn level_readings_are_the_closed_form_pitch_and_roll() {
    // a level on the table (carried by X) reads its rotation relative to gravity (the base): about y
    // EBX(x) + EBY(y), about x EAX(x) + EAY(y); a reference level on the saddle (carried by Y)
    // removes the Y part
    let m = vmc3();
    let errors = truth(&m); // EBX = 2 + 0.02 x, EAX = 0.01 x, EBY = -0.01 y, EAY = 0.03 y (urad)
    let poses: Vec<f64> = [[-400.0, 100.0, -50.0], [0.0, -250.0, -300.0], [250.0, 200.0, 0.0], [400.0, 0.0, -400.0]].concat();
    let level =
        |reference, axis: Vec3| DirectInstrument::Level(Level::new(&m, LevelBody::CarriedBy('X'), reference, axis, Vec3::z()).unwrap());
    let pitch = level(LevelBody::Base, Vec3::y()).simulate(&m, &errors, &poses, None);
    let roll = level(LevelBody::Base, Vec3::x()).simulate(&m, &errors, &poses, None);
    let differential = level(LevelBody::CarriedBy('Y'), Vec3::y()).simulate(&m, &errors, &poses, None);
    for (k, p) in poses.chunks(3).enumerate() {
        let (x, y) = (p[0], p[1]);
        // second order: (20 urad)^2 = 4e-10 rad = 4e-4 urad
        assert!((pitch[k] - (2.0 + 0.02 * x - 0.01 * y)).abs() < 1e-3, "pitch at {p:?}: {}", pitch[k]);
        assert!((roll[k] - (0.01 * x + 0.03 * y)).abs() < 1e-3, "roll at {p:?}: {}", roll[k]);
        assert!((differential[k] - (2.0 + 0.02 * x)).abs() < 1e-3, "differential at {p:?}: {}", differential[k]);
    }
    // a level never reads yaw
    let yaw =
        DirectInstrument::for_parameter(&m, &id("ECX"), Some(DirectKind::Level), &DirectSetup::of_machine(&m)).unwrap_err().to_string();
    assert!(yaw.contains("never yaw") && yaw.contains("ECX") && yaw.contains("laser-angular"), "{yaw}");
    let vertical = Level::new(&m, LevelBody::CarriedBy('X'), LevelBody::Base, Vec3::new(0.0, 1.0, 0.2), Vec3::z()).unwrap_err().to_string();
    assert!(vertical.contains("horizontal"), "{vertical}");
}

#[test]
fn pitch_from_a_level_and_from_angular_optics_is_recovered() {
    // EBX = 2 + 0.02 x urad: the level on the table reads +EBX (+ EBY(0) = 0); angular optics read the
    // tool relative to the table: -EBX plus the tool side's EBZ(-200) = 4 and EB0Z = 15 urad. With the
    // other errors known both fits recover EBX within 0.1 urad (0.2 urad noise on 81 readings).
    let m = vmc3();
    let errors = truth(&m);
    let (xs, poses) = x_poses();
    for (kind, sign, offset) in [(DirectKind::Level, 1.0, 0.0), (DirectKind::LaserAngular, -1.0, 19.0)] {
        let instrument = DirectInstrument::for_parameter(&m, &id("EBX"), Some(kind), &DirectSetup::of_machine(&m)).unwrap();
        assert_eq!(instrument.unit(), "urad");
        let clean = instrument.simulate(&m, &errors, &poses, None);
        for (x, r) in xs.iter().zip(&clean) {
            assert!((r - sign * (2.0 + 0.02 * x) - offset).abs() < 1e-3, "{kind:?} at {x}: {r}");
        }
        let e = noise(xs.len(), 0.2, 21);
        let readings: Vec<f64> = clean.iter().zip(&e).map(|(r, n)| r + n).collect();
        let report = fit(&m, "EBX", instrument, errors.clone(), &table_of(&xs, &readings), piecewise(1, vec![]));
        for x in [-400.0, 0.0, 400.0] {
            let got = report.fitted.function.evaluate(x);
            assert!((got - (2.0 + 0.02 * x)).abs() < 0.1, "{kind:?}: EBX({x}) = {got}");
        }
    }
}

#[test]
fn instruments_that_cannot_measure_the_parameter_are_refused() {
    let m = vmc3();
    let setup = DirectSetup::of_machine(&m);
    let refused = |name: &str, kind| DirectInstrument::for_parameter(&m, &id(name), kind, &setup).unwrap_err().to_string();
    assert!(refused("EC0Y", None).contains("EC0Y is not a motion error"));
    assert!(refused("TX", None).contains("TX is not a motion error"));
    assert!(refused("EXB", None).contains("axis B"));
    assert!(refused("EYX", Some(DirectKind::LaserLinear)).contains("use laser-straightness"));
    assert!(refused("EXX", Some(DirectKind::LaserStraightness)).contains("use laser-linear"));
    assert!(refused("EXX", Some(DirectKind::Level)).contains("not a displacement"));
    assert!(refused("EBX", Some(DirectKind::LaserLinear)).contains("read a displacement"));
    let angular = DirectInstrument::for_parameter(&m, &id("EBX"), None, &setup).unwrap();
    assert!(angular.with_optics_offset(&m, &[0.0; 3], [1.0, 2.0]).unwrap_err().to_string().contains("rotation"));
    // an explicit set-up reads the tool point
    let explicit = Laser { optics: LaserOptics::linear(Vec3::x()).unwrap(), setup: Setup::of_machine(&m), beam_on: Side::Workpiece };
    assert!(LaserOptics::straightness(Vec3::x(), Vec3::new(1.0, 1.0, 0.0)).is_err());
    let r = explicit.reading_user(&m, &[100.0, 0.0, -200.0], &vec![0.0; m.parameter_count()]);
    assert_eq!(r, 0.0);
}
