//! Five-axis compensation as the controllers take it (docs/compensation.md, "Five-axis machines"):
//! the location errors in the controller's kinematic description, tables for what remains, and the
//! error the written files leave over the travel with the rotary axes moving (exact chain).
//!
//! - For the shipped five-axis machines and Heidenhain, Siemens and LinuxCNC, the files leave at
//!   most 10 % of the worst error before, and location errors alone less than 1 um.
//! - Files that leave more than they remove are refused for every controller format (and written
//!   with `force`, flagged).
//! - The Siemens swivel data read back by a reader of the public CYCLE800 / W1 documentation, the
//!   Heidenhain kinematics changes and the Fanuc tool-centre-point parameters read back, give the
//!   chain of the description trueaxis corrects with.
//! - The generated LinuxCNC kinematics module, built by halcompile and called the way motmod calls
//!   it under halrun, commands the set-points of the library's corrector (1e-6 mm) and its forward
//!   kinematics inverts them; motmod loads it.

use std::collections::HashMap;
use trueaxis::compensate::export::rigid_fit::RigidFit;
use trueaxis::compensate::export::{linuxcnc_kins, Limits};
use trueaxis::compensate::kinematic::{Carried, KinematicCorrection, RotaryLayout};
use trueaxis::compensate::{
    compensation, CompensateError, Compensation, CompensationRequest, CorrectionWorkspace, Corrector, ExportFormat, FormatOptions,
};
use trueaxis::error_model::ErrorModel;
use trueaxis::geometry::{rotation_about_axis, Vec3};
use trueaxis::machine::{AxisKind, Machine, ParameterId};

const FIVE_AXIS: [&str; 3] = ["c600u", "kx8five", "head5"];

use crate::support::examples::load;
use crate::support::tools;

fn request(m: &Machine, format: &str, force: bool) -> CompensationRequest {
    CompensationRequest {
        format: ExportFormat::parse(format, &FormatOptions::default()).unwrap(),
        points: 21,
        grid: [5, 5, 5],
        reference: None,
        limits: Limits::with_overrides(m, Some(10_000.0), None).unwrap(),
        temperatures: vec![],
        poses: None,
        force,
    }
}

fn job(m: &Machine, e: &ErrorModel, format: &str, force: bool) -> Result<Compensation, CompensateError> {
    compensation(&Corrector::new(m, e), &request(m, format, force))
}

/// The location errors of `e` alone (a model of constants).
fn location_only(m: &Machine, e: &ErrorModel) -> ErrorModel {
    let mut values = vec![0.0; m.parameter_count()];
    e.values_at(m, &vec![0.0; m.axis_count()], &mut values);
    for (i, v) in values.iter_mut().enumerate() {
        if !matches!(m.parameter_id(i), ParameterId::Location { .. }) {
            *v = 0.0;
        }
    }
    ErrorModel::from_parameter_vector(m, &values)
}

#[test]
fn the_files_of_each_controller_leave_at_most_a_tenth_of_the_error() {
    for name in FIVE_AXIS {
        let (m, e) = load(name, name);
        for format in ["heidenhain", "siemens", "linuxcnc"] {
            let r = job(&m, &e, format, false).unwrap().residual.unwrap();
            assert!(r.worst_um <= 0.1 * r.worst_error_um, "{name} {format}: {:.3} um left of {:.3} um", r.worst_um, r.worst_error_um);
            assert!(r.rms_um <= 0.1 * r.rms_error_um, "{name} {format}: RMS {:.3} of {:.3}", r.rms_um, r.rms_error_um);
            let location = location_only(&m, &e);
            let r = job(&m, &location, format, false).unwrap().residual.unwrap();
            assert!(r.worst_um < 1.0 && r.worst_error_um > 10.0, "{name} {format}, location errors alone: {r:?}");
        }
    }
}

#[test]
fn the_kinematic_description_carries_the_identified_axis_lines() {
    // c600u: the eight location errors of Jiang (2014) Table 3.1: the C line 10 um off in x and y
    // and tilted 174.533 urad about x and y; A tilted about y and z and shifted in y and z
    let (m, e) = load("c600u", "c600u");
    let k = KinematicCorrection::new(&m, &e, &[0.0; 5], &[], Carried::ROTARY_AXES);
    let c = m.axis_index('C').unwrap();
    let a = m.axis_index('A').unwrap();
    let tilt = |k2: usize| {
        trueaxis::geometry::rotation_log(&trueaxis::compensate::kinematic::smallest_rotation(
            &m.axes()[k2].direction,
            &k.written.axes[k2].direction,
        )) * 1e6
    };
    // with no linear-axis errors the frame of the linear axes is M: the lines are the PIGEs to first order
    let tc = tilt(c);
    assert!((tc.x - (174.533 + 0.0)).abs() < 0.5 && (tc.y - (174.533 + 174.533)).abs() < 1.0, "C tilt {tc:?} urad");
    let ta = tilt(a);
    assert!(ta.x.abs() < 1e-6 && (ta.y - 174.533).abs() < 0.1 && (ta.z - 174.533).abs() < 0.1, "A tilt {ta:?} urad");
    let shift_a = (k.written.axes[a].point - m.axes()[a].point) * 1e3;
    assert!((shift_a.y - 10.0).abs() < 1e-6 && (shift_a.z - 10.0).abs() < 1e-6, "A shift {shift_a:?} um");
}

#[test]
fn files_that_leave_more_than_they_remove_are_refused_for_every_controller() {
    let (c600u, c600u_errors) = load("c600u", "c600u");
    let (vmc3, vmc3_errors) = load("vmc3", "vmc3");
    // an X pitch of 0.5 urad/mm: an Abbe error that depends on X and Z at once, which tables leave
    let mut pitch = ErrorModel::zero(&vmc3);
    pitch
        .set(&vmc3, ParameterId::parse("EBX").unwrap(), trueaxis::error_model::ErrorFunction::polynomial(vec![0.0, 0.5]).unwrap())
        .unwrap();
    // a thermal growth of Z with a sensor at 40 degC: the ISG file carries no temperature
    let mut thermal = ErrorModel::zero(&vmc3);
    thermal.add_term(&vmc3, ParameterId::parse("EZZ").unwrap(), 0.05, &[('Z', 1)], &[("T:column", 1)]).unwrap();
    let cases: [(&str, &Machine, &ErrorModel, &[f64], &str); 8] = [
        ("linuxcnc", &vmc3, &vmc3_errors, &[], "--format linuxcnc-hal"),
        ("linuxcnc-hal", &c600u, &c600u_errors, &[], "--format linuxcnc"),
        ("lattice", &c600u, &c600u_errors, &[], "trueaxis nc"),
        ("fanuc", &c600u, &c600u_errors, &[], "trueaxis nc"),
        ("heidenhain", &vmc3, &pitch, &[], "trueaxis nc"),
        ("siemens", &vmc3, &pitch, &[], "trueaxis nc"),
        ("isg", &vmc3, &thermal, &[40.0], "trueaxis nc"),
        (
            "linuxcnc",
            &c600u,
            &{
                // a C axis that wobbles (EAC, EBC as functions of C) beyond what the module's
                // tables hold is still carried: the module is exact, so use a direction-dependent error
                let mut b = c600u_errors.clone();
                b.set_directional(
                    &c600u,
                    ParameterId::parse("ECC").unwrap(),
                    Some(trueaxis::error_model::Direction::Positive),
                    trueaxis::error_model::ErrorFunction::Constant(3000.0),
                )
                .unwrap();
                b.set_directional(
                    &c600u,
                    ParameterId::parse("ECC").unwrap(),
                    Some(trueaxis::error_model::Direction::Negative),
                    trueaxis::error_model::ErrorFunction::Constant(-3000.0),
                )
                .unwrap();
                b
            },
            &[],
            "trueaxis nc",
        ),
    ];
    for (format, m, e, temperatures, better) in cases {
        let mut r = request(m, format, false);
        r.temperatures = temperatures.iter().map(|t| Some(*t)).collect();
        let corrector = Corrector::new(m, e);
        match compensation(&corrector, &r) {
            Err(CompensateError::Limit(msg)) => {
                assert!(msg.contains("more than they remove") && msg.contains(better) && msg.contains("--force"), "{format}: {msg}")
            }
            other => panic!("{format} on {}: expected a refusal, got {:?}", m.name, other.map(|c| c.residual)),
        }
        r.force = true;
        let forced = compensation(&corrector, &r).unwrap();
        let residual = forced.residual.unwrap();
        assert!(residual.leaves_more_than_it_removes() && !forced.files.is_empty(), "{format}: {residual:?}");
    }
}

/// `$TC_CARR<n>[1]=<value>` of a swivel data init program.
fn read_carr(text: &str) -> HashMap<usize, String> {
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("$TC_CARR"))
        .filter_map(|l| {
            let (n, rest) = l.split_once('[')?;
            let (_, value) = rest.split_once("]=")?;
            Some((n.parse().ok()?, value.trim().trim_matches('"').to_string()))
        })
        .collect()
}

/// The Siemens toolholder model, from the public W1 / CYCLE800 documentation: offset vectors l1..l4
/// (basic + fine), rotary axis vectors v1, v2, axis offsets; table: x_machine = l2 + R1 (l3 +
/// R2 (l4 + x_table)); head: reference - tip = l1 + R1 (l2 + R2 (l3 + T)); R_i the rotation about
/// v_i by the axis position minus its offset.
struct Swivel {
    kind: String,
    l: [Vec3; 4],
    v: [Vec3; 2],
    offset: [f64; 2],
}

impl Swivel {
    fn read(text: &str) -> Swivel {
        let c = read_carr(text);
        let num = |n: usize| c.get(&n).map_or(0.0, |v| v.parse::<f64>().unwrap());
        let vec = |n: usize| Vec3::new(num(n), num(n + 1), num(n + 2));
        let l = [vec(1) + vec(41), vec(4) + vec(44), vec(15) + vec(55), vec(18) + vec(58)];
        Swivel { kind: c[&23].clone(), l, v: [vec(7), vec(10)], offset: [num(24) + num(64), num(25) + num(65)] }
    }

    fn rotation(&self, i: usize, position_deg: f64) -> trueaxis::geometry::Mat3 {
        if self.v[i].norm() == 0.0 {
            return trueaxis::geometry::Mat3::identity();
        }
        rotation_about_axis(&self.v[i].normalize(), (position_deg - self.offset[i]).to_radians())
    }
}

/// The tool point relative to the table (mm) in the Siemens model of `text` plus the machine's
/// nominal linear axes, at the pose `user` (mm, deg).
fn siemens_relative(m: &Machine, layout: &RotaryLayout, swivel: &Swivel, user: &[f64]) -> Vec3 {
    let linear = |chain: &[usize]| {
        chain.iter().filter(|&&k| m.axes()[k].kind == AxisKind::Linear).fold(Vec3::zeros(), |s, &k| s + m.axes()[k].direction * user[k])
    };
    let (tool_linear, work_linear) = (linear(m.tool_chain()), linear(m.work_chain()));
    let r1 = swivel.rotation(0, user[layout.first]);
    let r2 = layout.second.map_or(trueaxis::geometry::Mat3::identity(), |k| swivel.rotation(1, user[k]));
    let l = &swivel.l;
    match swivel.kind.as_str() {
        "P" => {
            // x_machine = work_linear + l2 + R1 (l3 + R2 (l4 + x_table)), tool point at tool_point + tool_linear
            let tip = m.tool_point + tool_linear;
            let inner = r1.transpose() * (tip - work_linear - l[1]) - l[2];
            r2.transpose() * inner - l[3]
        }
        "T" => {
            // tip = reference(q) - (l1 + R1 (l2 + R2 l3)), the reference at the machine file's tool point at home
            let reference = m.tool_point + tool_linear;
            reference - (l[0] + r1 * (l[1] + r2 * l[2])) - work_linear
        }
        other => panic!("kinematic type {other}"),
    }
}

/// Poses over the travel away from the singularities (|sin| of the tilt axis above 0.2).
fn poses(m: &Machine, count: usize) -> Vec<Vec<f64>> {
    (0..count)
        .map(|s| {
            m.axes()
                .iter()
                .enumerate()
                .map(|(k, a)| {
                    let [lo, hi] = a.range.unwrap_or([0.0, 360.0]);
                    let x = lo + (hi - lo) * (((s * 7 + k * 3) % 13) as f64 + 0.41) / 13.0;
                    if a.kind == AxisKind::Rotary && a.range.is_some() && x.to_radians().sin().abs() < 0.2 {
                        lo + 0.8 * (hi - lo)
                    } else {
                        x
                    }
                })
                .collect()
        })
        .collect()
}

/// The relative tool point of the controller's description (the corrector's model of it) at the
/// set-points `user`, in its datum.
fn description_relative(m: &Machine, k: &KinematicCorrection, user: &[f64]) -> Vec3 {
    let corrector = Corrector::new(m, &k.errors);
    let mut q = vec![0.0; m.axis_count()];
    m.pose_to_internal(user, &mut q);
    // the actual relative position at q is the nominal one plus the residual of a zero correction
    let (position, _) = corrector.residual_at(&q, &vec![0.0; m.axis_count()], &Default::default(), &mut CorrectionWorkspace::new(m));
    let nominal = corrector.nominal_relative_position(&q);
    let d = &k.datum_written;
    d.rotation * (nominal + position) + d.translation
}

#[test]
fn siemens_swivel_data_read_back_give_the_corrected_chain() {
    for name in FIVE_AXIS {
        let (m, e) = load(name, name);
        let c = job(&m, &e, "siemens", false).unwrap();
        let text = super::file(&c.files, "TC_CARR.INI");
        assert!(text.starts_with("%_N_TC_CARR_INI\n") && text.trim_end().ends_with("M17"), "{name}: {text}");
        let swivel = Swivel::read(text);
        let layout = RotaryLayout::of(&m).unwrap();
        let machine_errors = e.without_setup();
        let k = KinematicCorrection::new(&m, &machine_errors, &[0.0; 5], &[], Carried::ROTARY_AXES);
        let poses = poses(&m, 40);
        let read: Vec<Vec3> = poses.iter().map(|p| siemens_relative(&m, &layout, &swivel, p)).collect();
        let described: Vec<Vec3> = poses.iter().map(|p| description_relative(&m, &k, p)).collect();
        // the same up to a constant placement of the table frame (the datum)
        let fit = RigidFit::of(&read, &described);
        for (p, (r, d)) in poses.iter().zip(read.iter().zip(&described)) {
            let left = fit.left(r, d).norm();
            assert!(left < 2e-6, "{name} at {p:?}: {left} mm between the swivel data and the description");
        }
        // and they are not the nominal machine: the swivel data hold the identified lines
        let nominal: Vec<Vec3> = poses
            .iter()
            .map(|p| {
                let mut q = vec![0.0; m.axis_count()];
                m.pose_to_internal(p, &mut q);
                Corrector::new(&m, &ErrorModel::zero(&m)).nominal_relative_position(&q)
            })
            .collect();
        let nominal_fit = RigidFit::of(&nominal, &described);
        let worst = nominal.iter().zip(&described).map(|(n, d)| nominal_fit.left(n, d).norm()).fold(0.0, f64::max);
        assert!(worst > 5e-3, "{name}: the swivel data look nominal ({worst} mm)");
    }
}

#[test]
fn heidenhain_kinematics_changes_read_back_give_the_identified_lines() {
    for name in FIVE_AXIS {
        let (m, e) = load(name, name);
        let c = job(&m, &e, "heidenhain", false).unwrap();
        let text = super::file(&c.files, "KINEMATICS.TXT");
        let machine_errors = e.without_setup();
        let k = KinematicCorrection::new(&m, &machine_errors, &[0.0; 5], &[], Carried::ROTARY_AXES);
        for block in text.split("\nROTARY AXIS ").skip(1) {
            let letter = block.chars().next().unwrap();
            let axis = m.axis_index(letter).unwrap();
            let triple = |key: &str| {
                let line = block.lines().find(|l| l.trim_start().starts_with(key)).unwrap();
                let v: Vec<f64> = line.split_whitespace().filter_map(|w| w.parse().ok()).collect();
                Vec3::new(v[0], v[1], v[2])
            };
            let (point, direction) = (triple("identified position"), triple("identified direction"));
            let nominal = triple("nominal position");
            let shift = triple("position change");
            let tilt = triple("orientation change") * 1f64.to_radians();
            let zero: f64 = block
                .lines()
                .find(|l| l.trim_start().starts_with("zero offset"))
                .unwrap()
                .split_whitespace()
                .last()
                .unwrap()
                .parse()
                .unwrap();
            let w = &k.written.axes[axis];
            assert!((point - w.point).norm() < 1e-6 && (nominal + shift - w.point).norm() < 1e-6, "{name} {letter}");
            assert!((direction - w.direction).norm() < 1e-8, "{name} {letter}");
            let rebuilt = trueaxis::geometry::rotation_exp(&tilt) * m.axes()[axis].direction;
            assert!((rebuilt - w.direction).norm() < 1e-8, "{name} {letter}: {rebuilt} vs {}", w.direction);
            assert!((zero.to_radians() - w.zero_offset).abs() < 1e-8, "{name} {letter}");
        }
    }
}

#[test]
fn fanuc_tool_centre_point_parameters_hold_the_positions_and_name_the_tilts() {
    for name in FIVE_AXIS {
        let (m, e) = load(name, name);
        let c = job(&m, &e, "fanuc", true).unwrap();
        let text = super::file(&c.files, "tcp_parameters.nc");
        let params: HashMap<u32, f64> = text
            .lines()
            .filter_map(|l| l.strip_prefix('N')?.split_once(" R").map(|(n, v)| (n.parse().unwrap(), v.parse().unwrap())))
            .collect();
        let machine_errors = e.without_setup();
        let k = KinematicCorrection::new(&m, &machine_errors, &[0.0; 5], &[], Carried { rotary_directions: false, ..Carried::ROTARY_AXES });
        let layout = RotaryLayout::of(&m).unwrap();
        let vector = |n: u32| Vec3::new(params[&n], params[&(n + 1)], params[&(n + 2)]);
        if m.tool_chain().iter().all(|&a| m.axes()[a].kind == AxisKind::Linear) {
            assert!((vector(19700) - k.written.axes[layout.first].point).norm() < 1e-4, "{name}");
            let second = layout.second.unwrap();
            assert!((vector(19703) - (k.written.axes[second].point - k.written.axes[layout.first].point)).norm() < 1e-4, "{name}");
        } else {
            let tool_point = k.written.tool_end.transform_point(&m.tool_point);
            assert!((vector(19709) - (k.written.axes[layout.second.unwrap()].point - tool_point)).norm() < 1e-4, "{name}");
        }
        assert!(c.left_out.iter().any(|l| l.starts_with("tilt of rotary axis")), "{name}: {:?}", c.left_out);
        assert!(text.starts_with("%\n") && text.contains("G10 L52") && text.contains("G11\n"), "{name}");
    }
}

/// A HAL component that calls the loaded kinematics module as motmod does (kinematicsInverse, then
/// kinematicsForward of the joints it returned) and times 100 inverse calls.
const PROBE: &str = r#"component PROBE "calls the inverse and forward kinematics of the loaded kinematics module";
pin in float world#[9] "X Y Z A B C U V W";
pin out s32 joint#[9] "joints in millionths of a mm or deg";
pin out s32 back#[9] "forward kinematics of the joints, in millionths";
pin out s32 status;
pin out float echo#[9] "the world pose the joints are of";
pin out float ns "nanoseconds per inverse kinematics call, mean of 100";
option period no;
function probe;
license "GPL";
;;
#include <rtapi_math.h>
#include "kinematics.h"
FUNCTION(probe) {
    EmcPose p, f;
    double j[9];
    KINEMATICS_FORWARD_FLAGS ff = 0;
    KINEMATICS_INVERSE_FLAGS fi = 0;
    long long t0;
    int i, s = 0;
    (void)period;
    p.tran.x = world(0); p.tran.y = world(1); p.tran.z = world(2);
    p.a = world(3); p.b = world(4); p.c = world(5); p.u = world(6); p.v = world(7); p.w = world(8);
    for (i = 0; i < 9; i++) j[i] = 0.0;
    t0 = rtapi_get_time();
    for (i = 0; i < 100; i++) s |= kinematicsInverse(&p, j, &fi, &ff);
    ns = (double)(rtapi_get_time() - t0) / 100.0;
    for (i = 0; i < 9; i++) joint(i) = (int)floor(j[i] * 1e6 + 0.5);
    s |= kinematicsForward(j, &f, &ff, &fi);
    back(0) = (int)floor(f.tran.x * 1e6 + 0.5); back(1) = (int)floor(f.tran.y * 1e6 + 0.5); back(2) = (int)floor(f.tran.z * 1e6 + 0.5);
    back(3) = (int)floor(f.a * 1e6 + 0.5); back(4) = (int)floor(f.b * 1e6 + 0.5); back(5) = (int)floor(f.c * 1e6 + 0.5);
    for (i = 0; i < 9; i++) echo(i) = world(i);
    status = s;
}
"#;

#[test]
fn generated_kinematics_module_run_by_linuxcnc_commands_the_corrected_set_points() {
    if !tools::linuxcnc_found() {
        return;
    }
    let pid = std::process::id();
    let dir = std::env::temp_dir().join(format!("trueaxis-kins-{pid}"));
    std::fs::create_dir_all(&dir).unwrap();
    tools::open_to_all(&dir);
    let install = |file: &str| tools::halcompile_install(&dir, file).flatten();
    let probe = format!("taprobe{pid}");
    std::fs::write(dir.join(format!("{probe}.comp")), PROBE.replace("PROBE", &probe)).unwrap();
    let Some(probe_so) = install(&format!("{probe}.comp")) else { return };
    let mut installed = vec![probe_so];
    for name in FIVE_AXIS {
        let (m, e) = load(name, name);
        let machine_errors = e.without_setup();
        let k = KinematicCorrection::new(&m, &machine_errors, &[0.0; 5], &[], Carried::ALL);
        let model = linuxcnc_kins::model(&m, &machine_errors, &k).unwrap();
        let module = format!("takins_{name}_{pid}");
        for f in linuxcnc_kins::export(&m, &model, &module).unwrap() {
            std::fs::write(dir.join(&f.name), &f.contents).unwrap();
        }
        let Some(so) = install(&format!("{module}.comp")) else { return };
        installed.push(so);
        // nominal poses: world = the nominal tool point relative to the workpiece and the rotary positions
        let poses = poses(&m, 8);
        let n = m.axis_count();
        let mut body = String::new();
        let mut expected = Vec::new();
        for p in &poses {
            let mut q = vec![0.0; n];
            m.pose_to_internal(p, &mut q);
            let world = Corrector::new(&m, &ErrorModel::zero(&m)).nominal_relative_position(&q);
            let mut values = [0.0; 9];
            values[..3].copy_from_slice(world.as_slice());
            for (k2, a) in m.axes().iter().enumerate() {
                if a.kind == AxisKind::Rotary {
                    values["XYZABCUVW".find(a.letter).unwrap()] = p[k2];
                }
            }
            for (i, v) in values.iter().enumerate() {
                body += &format!("setp {probe}.0.world{i} {v:.12}\n");
            }
            body += "loadusr -w sleep SLEEP\n";
            for i in 0..n {
                body += &format!("getp {probe}.0.joint{i}\n");
            }
            for i in 0..6 {
                body += &format!("getp {probe}.0.back{i}\n");
            }
            body += &format!("getp {probe}.0.status\ngetp {probe}.0.ns\n");
            for i in 0..6 {
                body += &format!("getp {probe}.0.echo{i}\n");
            }
            // the library's corrector on the module's model, converged far below the comparison
            let options =
                trueaxis::compensate::CorrectionOptions { tolerance_mm: 1e-10, rotary_tolerance_rad: 1e-13, ..Default::default() };
            let corrector = Corrector { options, datum: model.datum, ..Corrector::new(&m, &model.errors) };
            let c = corrector.correct(&q, &mut CorrectionWorkspace::new(&m));
            assert!(c.converged, "{name} {p:?}");
            expected.push((c.dq_user(&m).iter().zip(p).map(|(d, x)| d + x).collect::<Vec<f64>>(), values));
        }
        // each pose read once the servo thread has computed it (its echo of the world pose): on a
        // loaded machine the thread may run late, and then the script runs again with more time
        let width = n + 14;
        let mut numbers: Vec<f64> = Vec::new();
        for sleep in ["0.05", "0.3", "1"] {
            let script = format!(
                "loadrt {module}\nloadrt {probe}\nloadrt threads name1=t1 period1=1000000\naddf {probe}.0.probe t1\nstart\n{}stop\n",
                body.replace("SLEEP", sleep)
            );
            std::fs::write(dir.join("run.hal"), script).unwrap();
            let run = super::halrun(&dir.join("run.hal"), &dir);
            let stdout = String::from_utf8_lossy(&run.stdout);
            numbers = stdout.lines().filter_map(|l| l.trim().parse().ok()).collect();
            assert_eq!(numbers.len(), poses.len() * width, "{name}: {stdout}\n{}", String::from_utf8_lossy(&run.stderr));
            let current = expected
                .iter()
                .enumerate()
                .all(|(i, (_, world))| (0..6).all(|c| (numbers[i * width + n + 8 + c] - world[c]).abs() <= 1e-5 * world[c].abs().max(1.0)));
            if current {
                break;
            }
        }
        let mut cost = Vec::new();
        for (i, (set_points, world)) in expected.iter().enumerate() {
            let row = &numbers[i * width..(i + 1) * width];
            // joints read in millionths of a mm or deg: equal to 1e-6 (one count)
            for k2 in 0..n {
                let expected = (set_points[k2] * 1e6).round();
                assert!(
                    (row[k2] - expected).abs() <= 1.0,
                    "{name} pose {i} joint {k2}: LinuxCNC {} vs trueaxis {}",
                    row[k2] * 1e-6,
                    set_points[k2]
                );
            }
            for c2 in 0..6 {
                let expected = (world[c2] * 1e6).round();
                assert!(
                    (row[n + c2] - expected).abs() <= 1.0,
                    "{name} pose {i}: forward kinematics {c2} {} vs {}",
                    row[n + c2] * 1e-6,
                    world[c2]
                );
            }
            assert_eq!(row[n + 6], 0.0, "{name} pose {i}: status");
            cost.push(row[n + 7]);
        }
        eprintln!(
            "{name}: inverse kinematics {:.1} us per call under halrun (mean of 100 x {} poses, this machine's load)",
            cost.iter().sum::<f64>() / cost.len() as f64 / 1e3,
            cost.len()
        );
        // motmod takes it as its kinematics
        let wiring =
            format!("loadrt {module}\nloadrt tpmod\nloadrt homemod\nloadrt motmod servo_period_nsec=1000000 num_joints={n}\nshow comp\n");
        std::fs::write(dir.join("motmod.hal"), wiring).unwrap();
        let run = super::halrun(&dir.join("motmod.hal"), &dir);
        let text = String::from_utf8_lossy(&run.stdout).into_owned() + &String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success() && text.contains("motmod") && text.contains(&module), "{name}: motmod with {module}: {text}");
    }
    for so in installed {
        std::fs::remove_file(so).ok();
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_uncertainty_of_the_error_values_gives_that_of_the_error_left() {
    // vmc3 with EC0X known to 12 urad (k = 1): a squareness off by 12 urad is the shear of
    // residual_of_each_format_against_the_squareness_closed_form, whose best-fit rest is 2.544 um at
    // the corners of the XY travel; U = 2 u
    let m = Machine::load("../../examples/machines/vmc3.toml").unwrap();
    let text = "[constant]\nEC0X = 0.0\n[uncertainty]\nEC0X = 12.0\n";
    let e = ErrorModel::from_toml_str(text, "test.toml", &m).unwrap();
    assert_eq!(e.uncertainties(), &[(ParameterId::parse("EC0X").unwrap(), 12.0)]);
    let u = trueaxis::compensate::uncertainty_of_error_left(&Corrector::new(&m, &e), &[]).unwrap().unwrap();
    let theta = 12.0 * 250f64.powi(2) / (400f64.powi(2) + 250f64.powi(2));
    let corner = (((12.0 - theta) * 250.0).powi(2) + (theta * 400.0).powi(2)).sqrt() * 1e-3;
    assert!((u.expanded_um - 2.0 * corner).abs() < 1e-4 && u.parameters == 1, "{u:?} vs {}", 2.0 * corner);
    // the error-values text keeps it: set_uncertainty writes it back in place
    let written = trueaxis::error_model::set_uncertainty("[constant]\nEC0X = 1.5\n", &ParameterId::parse("EC0X").unwrap(), 0.75).unwrap();
    let back = ErrorModel::from_toml_str(&written, "written.toml", &m).unwrap();
    assert_eq!(back.uncertainties(), &[(ParameterId::parse("EC0X").unwrap(), 0.75)]);
    // a negative uncertainty is refused with the file and the name
    let err = ErrorModel::from_toml_str("[uncertainty]\nEC0X = -1.0\n", "bad.toml", &m).unwrap_err().to_string();
    assert!(err.contains("bad.toml") && err.contains("EC0X"), "{err}");
}
