//! Reference predictions for the Python package's test (crates/python/tests): random poses of the
//! shipped machines with their shipped error models, predicted by the library (exact chain) and
//! kept in crates/python/tests/data/predict_<machine>.csv with every digit (shortest round-trip
//! form). This test recomputes them and requires the file to match to 1e-12 um / urad, so the
//! reference of the Python test is always the library's current answer; with
//! TRUEAXIS_WRITE_PYTHON_REFERENCE=1 it rewrites the files.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::PathBuf;
use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::model::{Frame, Predictor, Setup};

const POSES: usize = 200;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `POSES` poses inside the travel (rotary axes without a range: -180..180 deg), user units,
/// and their predictions `dx dy dz drx dry drz dL` (um, urad), machine frame.
fn reference(name: &str) -> String {
    let root = root();
    let machine = Machine::load(root.join(format!("examples/machines/{name}.toml"))).unwrap();
    let errors = ErrorModel::load(root.join(format!("examples/errors/{name}.toml")), &machine).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut text = machine.axes().iter().map(|a| a.letter.to_string()).collect::<Vec<_>>().join(",");
    text += ",dx,dy,dz,drx,dry,drz,dL\n";
    let mut predictor = Predictor::new(&machine, &errors);
    predictor.setup = Setup::of_machine(&machine);
    predictor.frame = Frame::Machine;
    let mut q = vec![0.0; machine.axis_count()];
    for _ in 0..POSES {
        let user: Vec<f64> = machine
            .axes()
            .iter()
            .map(|a| {
                let [lo, hi] = a.range.unwrap_or([-180.0, 180.0]);
                lo + (hi - lo) * rng.gen::<f64>()
            })
            .collect();
        machine.pose_to_internal(&user, &mut q);
        let e = predictor.predict(&q).to_user_units();
        let fields: Vec<String> = user.iter().chain(e.iter()).map(|v| format!("{v:e}")).collect();
        text += &fields.join(",");
        text.push('\n');
    }
    text
}

fn numbers(text: &str) -> Vec<f64> {
    text.lines().skip(1).flat_map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap())).collect()
}

#[test]
fn python_reference_predictions_are_the_library_s() {
    for name in ["kx8five", "c600u", "vmc3"] {
        let path = root().join(format!("crates/python/tests/data/predict_{name}.csv"));
        let expected = reference(name);
        if std::env::var_os("TRUEAXIS_WRITE_PYTHON_REFERENCE").is_some() {
            std::fs::write(&path, &expected).unwrap();
        }
        let stored = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (a, b) = (numbers(&stored), numbers(&expected));
        assert_eq!(a.len(), b.len(), "{name}: {} numbers stored, {} computed", a.len(), b.len());
        assert_eq!(a.len(), POSES * (machine_axes(name) + 7));
        let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0f64, f64::max);
        assert!(worst <= 1e-12, "{name}: the stored reference differs from the library by {worst:e}");
    }
}

fn machine_axes(name: &str) -> usize {
    Machine::load(root().join(format!("examples/machines/{name}.toml"))).unwrap().axis_count()
}
