//! Every input error gets a clear one-line message naming the file and what is wrong
//! (docs/design.md, Command line), never a panic.

use trueaxis::error_model::ErrorModel;
use trueaxis::machine::Machine;
use trueaxis::poses::read_poses_from;

const GOOD: &str = r#"
name = "m"
structure = "wCAbYXZt"
[axes]
X = { kind = "linear", direction = [1, 0, 0], range = [-300, 300] }
Y = { kind = "linear", direction = [0, 1, 0], range = [-250, 250] }
Z = { kind = "linear", direction = [0, 0, 1], range = [-400, 0] }
A = { kind = "rotary", direction = [1, 0, 0], point = [0, 0, 0], range = [-20, 70] }
C = { kind = "rotary", direction = [0, 0, 1], point = [0, 0, 0] }
[tool]
point = [0, 0, 0]
"#;

fn machine_error(text: &str) -> String {
    let e = Machine::from_toml_str(text, "bad.toml").expect_err("must be refused").to_string();
    assert!(e.starts_with("bad.toml: "), "message must name the file: {e}");
    assert!(!e.contains('\n'), "message must be one line: {e}");
    e
}

fn with(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "test setup: `{from}` not in the good file");
    GOOD.replacen(from, to, 1)
}

#[test]
fn the_good_file_loads() {
    Machine::from_toml_str(GOOD, "good.toml").unwrap();
}

#[test]
fn machine_file_errors_name_the_problem() {
    let cases: Vec<(String, &[&str])> = vec![
        (with("C = {", "Q = {"), &["unknown axis `Q`"]),
        (with("C = { kind = \"rotary\", direction = [0, 0, 1], point = [0, 0, 0] }\n", ""), &["names axis C", "not defined under [axes]"]),
        (with("structure = \"wCAbYXZt\"", "structure = \"wCbYXZt\""), &["axis A", "does not appear in structure"]),
        (with("direction = [1, 0, 0], range = [-300", "direction = [0, 0, 0], range = [-300"), &["axis X", "zero vector"]),
        (
            with("direction = [1, 0, 0], range = [-300", "direction = [1, 1, 0], range = [-300"),
            &["axis X", "not a unit vector", "1.414214"],
        ),
        (with("A = { kind = \"rotary\"", "A = { kind = \"linear\""), &["axis A", "rotary axis", "kind = \"linear\""]),
        (with("X = { kind = \"linear\", ", "X = { "), &["missing field `kind`"]),
        (with("X = { kind = \"linear\", direction", "X = { kind = \"linear\", directoin"), &["unknown field `directoin`"]),
        (with(", range = [-300, 300] }", " }"), &["axis X", "missing field `range`"]),
        (with("direction = [0, 0, 1], point = [0, 0, 0] }", "direction = [0, 0, 1] }"), &["axis C", "missing field `point`"]),
        (with("range = [-300, 300]", "range = [300, -300]"), &["axis X", "range [300, -300]", "smaller first"]),
        (with("structure = \"wCAbYXZt\"", "structure = \"wCAYXZt\""), &["exactly one `b`"]),
        (with("structure = \"wCAbYXZt\"", "structure = \"wCAbYXZXt\""), &["axis X appears twice"]),
        (with("structure = \"wCAbYXZt\"", "structure = \"CAbYXZ\""), &["must read workpiece to tool"]),
        (with("[tool]\npoint = [0, 0, 0]\n", ""), &["missing field `tool`"]),
        (with("[tool]\npoint = [0, 0, 0]", "[tool]\npoint = [0, nan, 0]"), &["[tool] point", "finite"]),
        (
            with("direction = [1, 0, 0], range = [-300", "direction = [1, nan, 0], range = [-300"),
            &["axis X", "direction must be finite numbers"],
        ),
        (
            with("direction = [0, 0, 1], point = [0, 0, 0] }", "direction = [0, 0, 1], point = [0, inf, 0] }"),
            &["axis C", "point must be finite numbers (mm)"],
        ),
        (
            with("structure = \"wCAbYXZt\"", "structure = \"WCAYXZT\""),
            &["structure `WCAYXZT` must contain exactly one `F` (frame) between `W` and `T`"],
        ),
        (with("structure = \"wCAbYXZt\"", "structure = \"WCAFYFXZT\""), &["exactly one `F`"]),
        (
            with("structure = \"wCAbYXZt\"", "structure = \"wCAbYXZQt\""),
            &["structure `wCAbYXZQt`: `Q` is not an axis letter (X Y Z U V W A B C)"],
        ),
        (with("kind = \"linear\", direction = [1, 0, 0]", "kind = \"prismatic\", direction = [1, 0, 0]"), &["prismatic"]),
        (with("name = \"m\"", "name = \"\""), &["`name` must not be empty"]),
        ("name = \"m\"\nstructure = \"wbt\"\n[axes]\n[tool]\npoint = [0, 0, 0]\n".to_string(), &["has no axes"]),
        ("this is not toml".to_string(), &["line 1"]),
    ];
    for (text, expected) in cases {
        let e = machine_error(&text);
        for fragment in expected {
            assert!(e.contains(fragment), "expected `{fragment}` in: {e}");
        }
    }
}

#[test]
fn a_missing_machine_file_is_named() {
    let e = Machine::load("/nonexistent/machine.toml").unwrap_err().to_string();
    assert!(e.contains("/nonexistent/machine.toml") && e.contains("cannot read"), "{e}");
}

#[test]
fn nearly_unit_directions_are_accepted_and_normalised() {
    let m = Machine::from_toml_str(&with("direction = [1, 0, 0], range = [-300", "direction = [1.00005, 0, 0], range = [-300"), "ok.toml")
        .unwrap();
    assert!((m.axes()[0].direction.norm() - 1.0).abs() < 1e-15);
}

fn errors_error(text: &str) -> String {
    let machine = Machine::from_toml_str(GOOD, "good.toml").unwrap();
    let e = ErrorModel::from_toml_str(text, "errors.toml", &machine).expect_err("must be refused").to_string();
    assert!(e.starts_with("errors.toml: "), "message must name the file: {e}");
    assert!(!e.contains('\n'), "one line: {e}");
    e
}

#[test]
fn error_values_file_errors_name_the_parameter() {
    let cases: Vec<(&str, &[&str])> = vec![
        ("[constant]\nEQQ = 1.0\n", &["EQQ", "not an ISO 230 parameter name"]),
        ("[constant]\nEX0B = 1.0\n", &["EX0B", "axis B", "does not have"]),
        ("[table.EX0C]\nposition = [0, 1]\nvalue = [0, 1]\n", &["EX0C", "constant", "not as a table"]),
        ("[polynomial.TX]\ncoefficients = [1.0]\n", &["TX", "constant"]),
        ("[table.EXX]\nposition = [0, 1, 2]\nvalue = [0, 1]\n", &["[table.EXX]", "3 entries", "2"]),
        ("[table.EXX]\nposition = [0, 2, 1]\nvalue = [0, 1, 2]\n", &["[table.EXX]", "increase strictly"]),
        ("[table.EXX]\nposition = [0]\nvalue = [0]\n", &["at least two points"]),
        ("[constant]\nEX0C = 1.0\nEXOC = 2.0\n", &["EX0C", "more than once"]),
        ("[constant]\nEXX = 1.0\n[polynomial.EXX]\ncoefficients = [0.0, 1.0]\n", &["EXX", "more than once"]),
        ("[polynomial.EXX]\ncoefficients = []\n", &["must not be empty"]),
        ("[constant]\nEXX = nan\n", &["EXX", "finite"]),
        ("[constants]\nEXX = 1.0\n", &["unknown field `constants`"]),
        ("[constant]\nEXX = \"five\"\n", &["line 2"]),
        (
            "[[term.\"EX0Y+\"]]\ncoefficient = 0.01\nfactors = { X = 1 }\n",
            &["[term.EX0Y+] EX0Y+", "one direction or position range needs a motion error"],
        ),
        ("[[term.EXX]]\ncoefficient = 0.01\nfactors = { X = 1 }\nrange = [10, -10]\n", &["[term.EXX] EXX", "lo < hi"]),
        ("[[term.EXX]]\ncoefficient = 0.01\nfactors = { \"Q:x\" = 1 }\n", &["input `Q:x`", "spindle speed `S:<name>` (rpm)"]),
        ("[load.EAX]\nreference_n = 4900\n", &["[load.EAX] EAX", "exactly one of them"]),
        (
            "[load.EA0Y]\nreference_n = 4900\nposition = [0, 1]\nvalue = [0, 1]\n",
            &["[load.EA0Y]", "give its change under the load as `constant`"],
        ),
        ("[load.EAX]\nreference_n = 0\nconstant = 1.0\n", &["[load.EAX]", "non-zero"]),
        ("[load.EAX]\nreference_n = 4900\nconstant = 1.0\nload = \"T:x\"\n", &["[load.EAX]", "force input `F:<name>`"]),
        ("[load.EAX]\nreference_n = 4900\nconstant = 1.0\nlever_mm = 375\n", &["[load.EAX]", "go together"]),
        (
            "[[drift.TZ]]\naxis = \"Z\"\nposition = 0\nsensors = [\"T:a\"]\ntime_constants_s = [60]\ngains_um_per_degc = [[1.0, 2.0]]\n",
            &["[drift.TZ] TZ", "one row per sensor (1) of one finite gain per time constant (1)"],
        ),
        (
            "[[drift.TZ]]\naxis = \"Q\"\nposition = 0\nsensors = [\"T:a\"]\ntime_constants_s = [60]\ngains_um_per_degc = [[1.0]]\n",
            &["[drift.TZ] TZ", "no axis Q"],
        ),
    ];
    for (text, expected) in cases {
        let e = errors_error(text);
        for fragment in expected {
            assert!(e.contains(fragment), "expected `{fragment}` in: {e}");
        }
    }
}

fn poses_error(text: &str) -> String {
    let machine = Machine::from_toml_str(GOOD, "good.toml").unwrap();
    let e = read_poses_from(text.as_bytes(), "poses.csv", &machine).expect_err("must be refused").to_string();
    assert!(e.starts_with("poses.csv: "), "message must name the file: {e}");
    assert!(!e.contains('\n'), "one line: {e}");
    e
}

#[test]
fn pose_file_errors_name_line_and_column() {
    let cases: Vec<(&str, &[&str])> = vec![
        ("X,Y,Z,A\n0,0,0,0\n", &["missing column `C`", "axis C (deg)", "X,Y,Z,A"]),
        ("X,Y,Z,A,C\n0,0,zero,0,0\n", &["line 2", "column Z", "`zero` is not a number"]),
        ("X,Y,Z,A,C\n0,0,0,0,0\n0,0,0,90,0\n", &["line 3", "axis A at 90 deg", "outside its range [-20, 70] deg"]),
        ("X,Y,Z,A,C\n0,0,5,0,0\n", &["axis Z at 5 mm", "[-400, 0] mm"]),
        ("X,Y,Z,A,C\n", &["no poses"]),
        ("X,Y,Z,A,C\n0,0,0,0\n", &["line 2"]),
        ("X,Y,Z,A,C\n0,0,0,0,NaN\n", &["axis C", "not a finite number"]),
        ("X,Y,Z,A,C,T:spindle\n0,0,0,0,0,21.5\n0,0,0,0,0,warm\n", &["line 3", "column T:spindle", "`warm` is not a temperature"]),
    ];
    for (text, expected) in cases {
        let e = poses_error(text);
        for fragment in expected {
            assert!(e.contains(fragment), "expected `{fragment}` in: {e}");
        }
    }
}

#[test]
fn pose_files_accept_comments_spaces_and_extra_columns() {
    let machine = Machine::from_toml_str(GOOD, "good.toml").unwrap();
    let text = "# a comment\nt, X , Y, Z, A, C, T:spindle\n0.5, 10, 20, -30, 45, 370, 21.3\n";
    let poses = read_poses_from(text.as_bytes(), "p.csv", &machine).unwrap();
    assert_eq!(poses.user, vec![10.0, 20.0, -30.0, 45.0, 370.0]);
    let q = poses.internal(&machine);
    assert!((q[3] - 45f64.to_radians()).abs() < 1e-15);
}
