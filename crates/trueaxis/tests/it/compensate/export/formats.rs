//! Tables, the volumetric grid and every export format, parsed back by independent readers written
//! here and checked against the library's corrections; the controllers' limits refuse bad tables.

use trueaxis::compensate::export::{self, linuxcnc::CompType, ExportInput, ExportedFile, Limits};
use trueaxis::compensate::{axis_tables, volumetric_grid, CompensateError, CorrectionWorkspace, Corrector, TableSet, TableSpec};
use trueaxis::error_model::{ErrorModel, MachineState};
use trueaxis::machine::Machine;

use crate::support::examples::load;

fn spec(points: usize) -> TableSpec {
    TableSpec { points, reference: None, temperatures: vec![] }
}

fn file<'a>(files: &'a [ExportedFile], name: &str) -> &'a str {
    &files.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("no {name}")).contents
}

/// Correction (user units) at a user-unit pose, at rest.
fn correction_at(corrector: &Corrector, user: &[f64]) -> Vec<f64> {
    let m = corrector.machine;
    let mut q = vec![0.0; m.axis_count()];
    m.pose_to_internal(user, &mut q);
    corrector.correct_state(&q, &MachineState::default(), &mut CorrectionWorkspace::new(m)).dq_user(m)
}

#[test]
fn tables_sum_to_the_correction_along_every_axis_line() {
    for (machine, errors) in [("vmc3", "vmc3_backlash"), ("c600u", "c600u"), ("head5", "head5")] {
        let (m, e) = load(machine, errors);
        let corrector = Corrector::new(&m, &e);
        // the reference at the first node of every table, so that the sums need no interpolation
        let reference: Vec<f64> = m.axes().iter().map(|a| a.range.map_or(0.0, |r| r[0])).collect();
        let tables = axis_tables(&corrector, &TableSpec { reference: Some(reference), ..spec(9) }).unwrap();
        assert_eq!(tables.tables.len(), m.axis_count() * m.axis_count());
        for driver in 0..m.axis_count() {
            let positions = &tables.table(driver, driver).unwrap().positions;
            for &x in positions.iter().skip(1).step_by(3) {
                let mut pose = tables.reference.clone();
                pose[driver] = x;
                let direct = correction_at(&corrector, &pose);
                for corrected in 0..m.axis_count() {
                    // own-axis table of `corrected` at its reference position (or at x) plus every
                    // cross-axis table into `corrected` at the pose
                    let own = tables.table(corrected, corrected).unwrap().mean_at(pose[corrected]);
                    let cross: f64 =
                        (0..m.axis_count()).filter(|&k| k != corrected).map(|k| tables.table(k, corrected).unwrap().mean_at(pose[k])).sum();
                    // additive up to second order in the errors (0.01 deg PIGEs: picometres)
                    assert!(
                        (own + cross - direct[corrected]).abs() < 1e-7,
                        "{machine}: {driver}->{corrected} at {x}: {} vs {}",
                        own + cross,
                        direct[corrected]
                    );
                }
            }
        }
    }
}

#[test]
fn grid_compensation_leaves_less_than_one_percent_of_the_volumetric_error() {
    // the corrections interpolated trilinearly from a 17 x 11 x 9 grid (50 mm pitch) applied to the
    // exact chain at poses between the nodes
    let (m, e) = load("vmc3", "vmc3");
    let corrector = Corrector::new(&m, &e);
    let grid = volumetric_grid(&corrector, [17, 11, 9], &spec(2)).unwrap();
    let mut ws = CorrectionWorkspace::new(&m);
    let (mut worst_error, mut worst_residual) = (0.0f64, 0.0f64);
    for i in 0..400 {
        let f = |k: u32| ((i as f64 + 0.5) * [0.618034, 0.754878, 0.569840][k as usize]).fract();
        let p = [-400.0 + 800.0 * f(0), -250.0 + 500.0 * f(1), -400.0 + 400.0 * f(2)];
        let dq: Vec<f64> = (0..3).map(|a| grid.interpolate(p, a)).collect();
        let exact = corrector.correct(&p, &mut ws);
        // first order, the residual after applying dq instead of the exact correction is the
        // difference of the two (the joint Jacobian of vmc3 is the identity)
        let residual = (0..3).map(|a| (dq[a] - exact.dq[a]).powi(2)).sum::<f64>().sqrt();
        worst_error = worst_error.max(exact.original_position.norm());
        worst_residual = worst_residual.max(residual);
    }
    assert!(worst_residual < 0.01 * worst_error, "residual {} um of {} um", worst_residual * 1e3, worst_error * 1e3);
    // nodes reproduce the sampled corrections exactly
    let node = grid.node_position(3, 4, 5);
    let direct = correction_at(&corrector, &node);
    for (a, d) in direct.iter().enumerate().take(3) {
        assert!((grid.interpolate(node, a) - d).abs() < 1e-12);
    }
}

fn export_input<'a>(
    m: &'a Machine,
    e: &'a ErrorModel,
    tables: &'a TableSet,
    grid: Option<&'a trueaxis::compensate::VolumetricGrid>,
    limits: Limits,
) -> ExportInput<'a> {
    ExportInput { machine: m, errors: e, tables, grid, limits }
}

#[test]
fn linuxcnc_files_read_back_as_linuxcnc_does() {
    let (m, e) = load("vmc3", "vmc3_backlash");
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(33)).unwrap();
    for comp_type in [CompType::Trims, CompType::Positions] {
        let files = export::linuxcnc::export(&export_input(&m, &e, &tables, None, Limits::default()), comp_type).unwrap().files;
        let ini = file(&files, "linuxcnc-comp.ini");
        for (joint, axis) in m.axes().iter().enumerate() {
            assert!(ini.contains(&format!("[JOINT_{joint}]\nCOMP_FILE = {}.comp\nCOMP_FILE_TYPE = {}", axis.letter, comp_type as i32)));
            let table = tables.table(joint, joint).unwrap();
            // usrmotLoadComp: sscanf "%lf %lf %lf"; type 0 trims are nominal - value, type 1 the values
            let rows: Vec<[f64; 3]> = file(&files, &format!("{}.comp", axis.letter))
                .lines()
                .map(|l| {
                    let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
                    [v[0], v[1], v[2]]
                })
                .collect();
            assert_eq!(rows.len(), 33);
            for (i, [nominal, fwd, rev]) in rows.iter().enumerate() {
                let (ft, rt) = match comp_type {
                    CompType::Positions => (nominal - fwd, nominal - rev),
                    CompType::Trims => (*fwd, *rev),
                };
                assert!((nominal - table.positions[i]).abs() < 1e-6);
                assert!((ft - table.forward[i]).abs() < 1.5e-6 && (rt - table.reverse[i]).abs() < 1.5e-6);
            }
            if axis.letter == 'X' {
                // the backlash of X (EXX+ - EXX- = 3 um) shows as forward - reverse trims of +3 um
                let [_, f, r] = rows[10];
                let gap = match comp_type {
                    CompType::Trims => f - r,
                    CompType::Positions => r - f,
                };
                assert!((gap - 3e-3).abs() < 2e-6, "{gap}");
            }
        }
    }
    // LinuxCNC takes at most 256 triplets per joint
    let long = axis_tables(&corrector, &spec(257)).unwrap();
    let err = export::linuxcnc::export(&export_input(&m, &e, &long, None, Limits::default()), CompType::Trims).unwrap_err();
    assert!(matches!(err, CompensateError::Limit(_)) && err.to_string().contains("at most 256"), "{err}");
    // the user's limit: the largest correction is above 10 um
    let limits = Limits::with_overrides(&m, Some(10.0), None).unwrap();
    let limited = export_input(&m, &e, &tables, None, limits);
    let err = export::linuxcnc::export(&limited, CompType::Trims).unwrap_err();
    assert!(err.to_string().contains("beyond the limit of 10 um (given for this run)"), "{err}");
    // the worst point is named: the largest |correction| of any table (the extent of the export)
    let worst = export::largest_corrections(&limited, export::Coverage::TABLES).max_um;
    assert!(err.to_string().contains(&format!("{worst:.3} um")) || err.to_string().contains(&format!("-{worst:.3} um")), "{worst} {err}");
    assert!(Limits::with_overrides(&m, Some(-1.0), None).is_err() && Limits::with_overrides(&m, None, Some(f64::NAN)).is_err());
}

#[test]
fn heidenhain_tables_have_equidistant_columns_per_axis() {
    let (m, e) = load("c600u", "c600u");
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(37)).unwrap();
    let files = export::heidenhain::export(&export_input(&m, &e, &tables, None, Limits::default())).unwrap().files;
    let cma: Vec<Vec<&str>> = file(&files, "COMP.CMA").lines().map(|l| l.split_whitespace().collect()).collect();
    assert_eq!(cma[1], ["NR", "X", "Y", "Z", "A", "C", "ACTIVE"]);
    assert_eq!(cma[2], ["0", "X.COM", "Y.COM", "Z.COM", "A.COM", "C.COM", "*"]);
    for (driver, axis) in m.axes().iter().enumerate() {
        let text = file(&files, &format!("{}.COM", axis.letter));
        let mut lines = text.lines();
        assert_eq!(lines.next().unwrap(), format!("BEGIN {}.COM MM", axis.letter));
        let header: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
        assert_eq!(header[..2], ["NR", "AXISPOS"]);
        assert_eq!(*header.last().unwrap(), "BACKLASH");
        let rows: Vec<Vec<f64>> =
            lines.take_while(|l| *l != "[END]").map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect()).collect();
        assert_eq!(rows.len(), 37);
        let step = (rows[36][1] - rows[0][1]) / 36.0;
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row[0], i as f64);
            assert!((row[1] - rows[0][1] - step * i as f64).abs() < 1e-6);
            for (col, name) in header.iter().enumerate().skip(2).take(header.len() - 3) {
                let corrected = m.axis_index(name.chars().next().unwrap()).unwrap();
                // own axis: forward (BACKLASH the reverse); cross-axis: the mean of both directions
                let t = tables.table(driver, corrected).unwrap();
                let expected = if corrected == driver { t.forward[i] } else { 0.5 * (t.forward[i] + t.reverse[i]) };
                assert!((row[col] - expected).abs() < 1e-6);
            }
        }
    }
    // a C table over one turn closes for a periodic model; a radial error of C that grows with the
    // angle (0.01 um/deg, not periodic) does not
    let mut broken = e.clone();
    broken.set(&m, "EXC".parse_id(), trueaxis::error_model::ErrorFunction::polynomial(vec![0.0, 0.01]).unwrap()).unwrap();
    let corrector = Corrector::new(&m, &broken);
    let tables = axis_tables(&corrector, &spec(37)).unwrap();
    let err = export::heidenhain::export(&export_input(&m, &broken, &tables, None, Limits::default())).unwrap_err();
    assert!(err.to_string().contains("does not close"), "{err}");
    // unequal spacing is refused
    let mut uneven = tables.clone();
    for t in uneven.tables.iter_mut().filter(|t| t.driver == 0) {
        t.positions[3] += 1.0;
    }
    let err = export::heidenhain::export(&export_input(&m, &e, &uneven, None, Limits::default())).unwrap_err();
    assert!(err.to_string().contains("equally spaced"), "{err}");
}

trait ParseId {
    fn parse_id(&self) -> trueaxis::machine::ParameterId;
}
impl ParseId for str {
    fn parse_id(&self) -> trueaxis::machine::ParameterId {
        trueaxis::machine::ParameterId::parse(self).unwrap()
    }
}

#[test]
fn isg_csv_holds_the_error_parameters_with_iso_names() {
    let (m, e) = load("c600u", "c600u");
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(5)).unwrap();
    let files = export::isg::export(&export_input(&m, &e, &tables, None, Limits::default())).unwrap().files;
    let text = file(&files, "volcomp.csv");
    // an independent ISG_CSV reader: `//` comments, `#` file breaks, a header then records
    let mut blocks: Vec<(Vec<String>, Vec<Vec<f64>>)> = Vec::new();
    for line in text.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with("//")) {
        if line == "#" {
            blocks.push((Vec::new(), Vec::new()));
        } else if blocks.last().is_some_and(|b| b.0.is_empty()) {
            blocks.last_mut().unwrap().0 = line.split_whitespace().map(String::from).collect();
        } else {
            blocks.last_mut().unwrap().1.push(line.split_whitespace().map(|v| v.parse().unwrap()).collect());
        }
    }
    assert_eq!(blocks.len(), m.axis_count() + 1);
    assert_eq!(blocks[3].0, ["A", "EXA", "EYA", "EZA", "EAA", "EBA", "ECA"]);
    let (names, rows) = blocks.last().unwrap();
    assert_eq!(names, &["Y0A", "Z0A", "B0A", "C0A", "X0C", "Y0C", "A0C", "B0C"]);
    // the file holds mm and rad: EY0A = 10 um, EB0A = 174.533 urad
    assert!((rows[0][0] - 0.010).abs() < 1e-12 && (rows[0][2] - 174.533e-6).abs() < 1e-12);
}

#[test]
#[allow(clippy::needless_range_loop)]
fn lattice_interpolates_as_the_library_grid() {
    let (m, e) = load("vmc3", "vmc3");
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(3)).unwrap();
    let grid = volumetric_grid(&corrector, [5, 4, 3], &spec(3)).unwrap();
    let files = export::lattice::export(&export_input(&m, &e, &tables, Some(&grid), Limits::default()), Some(60)).unwrap().files;
    let text = file(&files, "lattice3d.txt");
    let mut header = std::collections::HashMap::new();
    let mut points = std::collections::HashMap::new();
    for line in text.lines().filter(|l| !l.starts_with(';')) {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w[0] {
            "ORIGIN" | "PITCH" | "POINTS" => {
                header.insert(w[0], w[1..].iter().map(|v| v.parse::<f64>().unwrap()).collect::<Vec<_>>());
            }
            _ => {
                let v: Vec<f64> = w.iter().map(|v| v.parse().unwrap()).collect();
                points.insert((v[0] as usize, v[1] as usize, v[2] as usize), [v[3], v[4], v[5]]);
            }
        }
    }
    assert_eq!(header["POINTS"], [5.0, 4.0, 3.0]);
    assert_eq!(points.len(), 60);
    // independent trilinear interpolation of the parsed lattice (um) against the library (mm)
    let (o, h) = (&header["ORIGIN"], &header["PITCH"]);
    for p in [[-123.0, 77.0, -311.0], [399.0, -249.0, -1.0], [0.0, 0.0, -200.0]] {
        let u: Vec<f64> = (0..3).map(|d| (p[d] - o[d]) / h[d]).collect();
        let c: Vec<usize> = (0..3).map(|d| (u[d].floor() as usize).min(header["POINTS"][d] as usize - 2)).collect();
        let t: Vec<f64> = (0..3).map(|d| u[d] - c[d] as f64).collect();
        for a in 0..3 {
            let mut v = 0.0;
            for corner in 0..8usize {
                let o = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
                let w: f64 = (0..3).map(|d| if o[d] == 1 { t[d] } else { 1.0 - t[d] }).product();
                v += w * points[&(c[0] + o[0], c[1] + o[1], c[2] + o[2])][a];
            }
            assert!((v * 1e-3 - grid.interpolate(p, a)).abs() < 1e-6, "{p:?} axis {a}");
        }
    }
    let err = export::lattice::export(&export_input(&m, &e, &tables, Some(&grid), Limits::default()), Some(50)).unwrap_err();
    assert!(err.to_string().contains("at most 50"), "{err}");
}

#[test]
fn plain_csv_and_json_agree_with_the_tables() {
    let (m, e) = load("c600u", "c600u");
    let corrector = Corrector::new(&m, &e);
    let tables = axis_tables(&corrector, &spec(7)).unwrap();
    let grid = volumetric_grid(&corrector, [3, 3, 2], &spec(7)).unwrap();
    let input = export_input(&m, &e, &tables, Some(&grid), Limits::default());
    let files = export::plain::export_csv(&input).unwrap();
    let csv = file(&files, "tables.csv");
    assert_eq!(csv.lines().count(), 1 + 25 * 7);
    let row: Vec<&str> = csv.lines().find(|l| l.starts_with("C,") && l.split(',').nth(2) == Some("A")).unwrap().split(',').collect();
    let t = tables.table(4, 3).unwrap();
    assert!((row[3].parse::<f64>().unwrap() - t.forward[0].to_radians() * 1e6).abs() < 1e-4);
    assert_eq!(row[5], "urad");
    assert_eq!(file(&files, "grid.csv").lines().count(), 1 + 18);
    let doc = export::plain::to_json(&input).unwrap();
    let json_tables = doc["tables"].as_array().unwrap();
    assert_eq!(json_tables.len(), 25);
    let x = &json_tables[0];
    assert_eq!((x["driver"].as_str(), x["corrected"].as_str(), x["unit"].as_str()), (Some("X"), Some("X"), Some("um")));
    let first = tables.table(0, 0).unwrap().forward[0] * 1e3;
    assert!((x["forward"][0].as_f64().unwrap() - first).abs() < 1e-4);
    assert_eq!(doc["grid"]["counts"], serde_json::json!([3, 3, 2]));
    // the rotary limit in urad refuses the C corrections of the 0.01 deg PIGEs
    let limited = export_input(&m, &e, &tables, Some(&grid), Limits::with_overrides(&m, None, Some(1.0)).unwrap());
    assert!(export::plain::to_json(&limited).unwrap_err().to_string().contains("urad"));
}
