//! A LinuxCNC 2.9 kinematics module generated from the identified machine: forward and inverse
//! kinematics on the exact chain with the location errors (as lines of the axes in the frame of the
//! linear axes) and the motion errors (tables over each axis's travel), built by `halcompile
//! --install` like LinuxCNC's `userkins.comp` template and loaded before `motmod` (`[KINS]
//! KINEMATICS`). No table of the controller approximates the errors: every servo period the motion
//! module asks the module for the joints of the interpolated pose, and the module solves the exact
//! chain for them.
//!
//! World coordinates are those of LinuxCNC's tool-centre-point kinematics (`xyzac-trt-kins` in TCP
//! mode): X Y Z the tool point relative to the workpiece (mm, in the frame of the linear axes, the
//! workpiece frame of the machine file at home) and the rotary axes' programmed positions (deg),
//! which fix the tool axis the nominal machine would have there. The inverse kinematics puts the
//! actual tool point at X Y Z with that tool axis (Gauss-Newton on the exact chain, a few
//! iterations); the forward kinematics returns the actual tool point and the nominal rotary
//! positions of the actual tool axis. What a servo loop cannot know (the direction of motion,
//! temperatures, other inputs) is left out and listed.
//!
//! The C core (`core.c`, compiled into the module) is plain C99 on the math library; the generated
//! part holds the model's numbers. Units: mm and deg at the interface.

use super::ExportedFile;
use crate::compensate::kinematic::KinematicCorrection;
use crate::compensate::tables::table_range;
use crate::compensate::CompensateError;
use crate::error_model::{ErrorFunction, ErrorModel};
use crate::geometry::Pose;
use crate::machine::{AxisKind, Component, Machine, ParameterId, SetupSide};
use std::fmt::Write;

/// The C core of the module.
pub const CORE: &str = include_str!("core.c");

/// The module's name unless another is given.
pub const DEFAULT_NAME: &str = "trueaxis_kins";

/// Points of each motion-error table over an axis's travel.
pub const TABLE_POINTS: usize = 257;

/// The module's model: the numbers the C code holds, and the same model as an error model of the
/// machine (for the error the module leaves, computed by the library's corrector).
pub struct KinsModel {
    /// Location errors (mm, rad) and the tool setup (the tool point of the description).
    pub params: Vec<f64>,
    /// Per axis: the travel sampled (first, step, points) and the six motion errors (mm, rad) at
    /// each point, component-major.
    pub tables: Vec<(f64, f64, usize, bool, Vec<f64>)>,
    pub datum: Pose,
    /// The model as errors of the machine: location and setup constants and the motion errors as
    /// the sampled tables.
    pub errors: ErrorModel,
    pub left_out: Vec<String>,
}

/// The model of `kinematics` (every location error carried) and the motion errors of `errors`
/// (the machine's, at rest and at the reference temperatures).
pub fn model(machine: &Machine, errors: &ErrorModel, kinematics: &KinematicCorrection) -> Result<KinsModel, CompensateError> {
    for letter in ['X', 'Y', 'Z'] {
        if machine.axis_index(letter).is_none() {
            return Err(CompensateError::Input(format!(
                "a generated LinuxCNC kinematics module needs the linear axes X, Y and Z; machine `{}` has {}",
                machine.name,
                machine.axis_letters()
            )));
        }
    }
    let n = machine.axis_count();
    let params = kinematics.params.clone();
    let functions = errors.functions_only();
    let mut model = ErrorModel::from_parameter_vector(machine, &params);
    let mut tables = Vec::with_capacity(n);
    let mut values = vec![0.0; machine.parameter_count()];
    for k in 0..n {
        let axis = &machine.axes()[k];
        let [lo, hi] = table_range(machine, k)?;
        let step = (hi - lo) / (TABLE_POINTS - 1) as f64;
        let periodic = axis.kind == AxisKind::Rotary && axis.range.is_none();
        let positions: Vec<f64> = (0..TABLE_POINTS).map(|i| if i + 1 == TABLE_POINTS { hi } else { lo + step * i as f64 }).collect();
        let mut sampled = vec![0.0; 6 * TABLE_POINTS];
        let mut q = vec![0.0; n];
        for (i, &x) in positions.iter().enumerate() {
            q[k] = axis.position_to_internal(x);
            functions.values_at(machine, &q, &mut values);
            for c in Component::ALL {
                sampled[c.index() * TABLE_POINTS + i] = values[machine.motion_index(k, c)];
            }
        }
        for c in Component::ALL {
            let column = &sampled[c.index() * TABLE_POINTS..(c.index() + 1) * TABLE_POINTS];
            if column.iter().any(|v| *v != 0.0) {
                let user: Vec<f64> = column.iter().map(|v| v / c.to_internal()).collect();
                // a table of the program's own sampling that does not build is a failed computation
                let failed = |e: crate::Error| CompensateError::Computation(e.to_string());
                let function = ErrorFunction::table(positions.clone(), user, periodic.then_some(360.0)).map_err(failed)?;
                model.set(machine, ParameterId::Motion { axis: axis.letter, component: c }, function).map_err(failed)?;
            }
        }
        tables.push((lo, step, TABLE_POINTS, periodic, sampled));
    }
    let mut left_out = Vec::new();
    if errors.directional_entries().any(|(_, d, _)| d.is_some()) {
        left_out.push("the direction-dependent part (backlash) of the error model: a kinematics module does not know the direction of motion; the mean of both directions is used".to_string());
    }
    if !errors.terms().is_empty() || !errors.loads().is_empty() || !errors.drifts().is_empty() {
        left_out.push(
            "product, temperature, load and drift terms of the error model: the kinematics module holds the functions of the axis positions alone"
                .to_string(),
        );
    }
    Ok(KinsModel { params, tables, datum: kinematics.datum_written, errors: model, left_out })
}

fn number(v: f64) -> String {
    format!("{v:.17e}")
}

fn list(values: impl IntoIterator<Item = String>) -> String {
    let v: Vec<String> = values.into_iter().collect();
    if v.is_empty() {
        "0".into()
    } else {
        v.join(", ")
    }
}

/// The C declarations of the model's numbers (before [`CORE`]).
pub fn model_c(machine: &Machine, model: &KinsModel) -> String {
    let m = machine;
    let n = m.axis_count();
    let mut c = String::new();
    let axes = m.axes();
    let _ = writeln!(c, "#define TA_N {n}");
    let _ = writeln!(
        c,
        "static const int ta_kind[TA_N] = {{ {} }};",
        list(axes.iter().map(|a| u8::from(a.kind == AxisKind::Rotary).to_string()))
    );
    let _ = writeln!(c, "static const double ta_scale[TA_N] = {{ {} }};", list(axes.iter().map(|a| number(a.position_to_internal(1.0)))));
    let vec3 = |v: &crate::geometry::Vec3| format!("{{ {}, {}, {} }}", number(v.x), number(v.y), number(v.z));
    let _ = writeln!(c, "static const double ta_dir[TA_N][3] = {{ {} }};", list(axes.iter().map(|a| vec3(&a.direction))));
    let _ = writeln!(c, "static const double ta_point[TA_N][3] = {{ {} }};", list(axes.iter().map(|a| vec3(&a.point))));
    let location = |k: usize| {
        let i = m.location_index(k, Component::X);
        format!("{{ {} }}", list(model.params[i..i + 6].iter().map(|v| number(*v))))
    };
    let _ = writeln!(c, "static const double ta_location[TA_N][6] = {{ {} }};", list((0..n).map(location)));
    let _ = writeln!(
        c,
        "static const double ta_location_centre[TA_N][3] = {{ {} }};",
        list(axes.iter().map(|a| vec3(&a.location_error_centre())))
    );
    let _ = writeln!(c, "static const int ta_points[TA_N] = {{ {} }};", list(model.tables.iter().map(|t| t.2.to_string())));
    let _ = writeln!(c, "static const double ta_first[TA_N] = {{ {} }};", list(model.tables.iter().map(|t| number(t.0))));
    let _ = writeln!(c, "static const double ta_step[TA_N] = {{ {} }};", list(model.tables.iter().map(|t| number(t.1))));
    let _ = writeln!(c, "static const int ta_period[TA_N] = {{ {} }};", list(model.tables.iter().map(|t| u8::from(t.3).to_string())));
    let mut start = 0;
    let starts: Vec<String> = model
        .tables
        .iter()
        .map(|t| {
            let s = start;
            start += t.4.len();
            s.to_string()
        })
        .collect();
    let _ = writeln!(c, "static const int ta_start[TA_N] = {{ {} }};", list(starts));
    let _ =
        writeln!(c, "static const double ta_values[] = {{ {} }};", list(model.tables.iter().flat_map(|t| t.4.iter().map(|v| number(*v)))));
    for (name, chain) in [("tool", m.tool_chain()), ("work", m.work_chain())] {
        let _ = writeln!(c, "static const int ta_{name}_chain[] = {{ {} }};", list(chain.iter().map(|k| k.to_string())));
        let _ = writeln!(c, "static const int ta_{name}_len = {};", chain.len());
    }
    let setup = m.setup_index(SetupSide::Tool, Component::X);
    let actual_tool = m.tool_point + crate::geometry::Vec3::new(model.params[setup], model.params[setup + 1], model.params[setup + 2]);
    let _ = writeln!(c, "static const double ta_tool_point[3] = {};", vec3(&m.tool_point));
    let _ = writeln!(c, "static const double ta_tool_point_actual[3] = {};", vec3(&actual_tool));
    let r = &model.datum.rotation;
    let _ = writeln!(
        c,
        "static const double ta_datum_r[3][3] = {{ {}, {}, {} }};",
        vec3(&r.row(0).transpose()),
        vec3(&r.row(1).transpose()),
        vec3(&r.row(2).transpose())
    );
    let _ = writeln!(c, "static const double ta_datum_t[3] = {};", vec3(&model.datum.translation));
    let _ = writeln!(c, "static const int ta_rotary_count = {};", axes.iter().filter(|a| a.kind == AxisKind::Rotary).count());
    c
}

/// The EmcPose member of each machine axis (`tran.x` ... `a` `b` `c` `u` `v` `w`).
fn member(letter: char) -> &'static str {
    match letter {
        'X' => "tran.x",
        'Y' => "tran.y",
        'Z' => "tran.z",
        'A' => "a",
        'B' => "b",
        'C' => "c",
        'U' => "u",
        'V' => "v",
        _ => "w",
    }
}

/// `<name>.comp`: the kinematics module for halcompile.
pub fn component(machine: &Machine, model: &KinsModel, name: &str) -> String {
    let mut c = format!(
        "component {name} \"Kinematics of {} with its identified errors, generated by trueaxis\";\n",
        machine.name.replace('"', "'")
    );
    c.push_str(
        "description \"\"\"\nForward and inverse kinematics on the exact chain of the machine with its identified location and motion\n\
         errors (trueaxis, docs/compensation.md). World coordinates: the tool point relative to the workpiece (mm) and the\n\
         programmed rotary axis positions (deg). Build with halcompile --install, then [KINS] KINEMATICS.\n\"\"\";\n",
    );
    c.push_str("pin out s32 last_iterations = 0 \"not used by the kinematics functions (halcompile needs a pin)\";\n");
    c.push_str("option period no;\nfunction nothing;\nlicense \"GPL\";\nauthor \"trueaxis\";\n;;\n\n#include <rtapi_math.h>\n#include \"kinematics.h\"\n\n");
    c.push_str(&model_c(machine, model));
    c.push('\n');
    c.push_str(CORE);
    c.push_str("\nFUNCTION(nothing) { (void)period; last_iterations = 0; }\n\nKINS_NOT_SWITCHABLE\n");
    c.push_str("EXPORT_SYMBOL(kinematicsType);\nEXPORT_SYMBOL(kinematicsInverse);\nEXPORT_SYMBOL(kinematicsForward);\n\n");
    c.push_str("KINEMATICS_TYPE kinematicsType() { return KINEMATICS_BOTH; }\n\n");
    let axes = machine.axes();
    let mut forward = String::from(
        "int kinematicsForward(const double *joints, EmcPose *pos, const KINEMATICS_FORWARD_FLAGS *fflags, KINEMATICS_INVERSE_FLAGS *iflags) {\n\
         \x20   double q[TA_N], world[3], rotary[TA_N];\n    int k;\n    (void)fflags; (void)iflags;\n\
         \x20   for (k = 0; k < TA_N; k++) q[k] = joints[k];\n    if (ta_forward(q, world, rotary) < 0) return -1;\n\
         \x20   pos->tran.x = world[0]; pos->tran.y = world[1]; pos->tran.z = world[2];\n",
    );
    let mut inverse = String::from(
        "int kinematicsInverse(const EmcPose *pos, double *joints, const KINEMATICS_INVERSE_FLAGS *iflags, KINEMATICS_FORWARD_FLAGS *fflags) {\n\
         \x20   double q[TA_N], world[3], rotary[TA_N];\n    int k;\n    (void)fflags; (void)iflags;\n\
         \x20   world[0] = pos->tran.x; world[1] = pos->tran.y; world[2] = pos->tran.z;\n    for (k = 0; k < TA_N; k++) rotary[k] = 0.0;\n",
    );
    for (k, a) in axes.iter().enumerate() {
        if a.kind == AxisKind::Rotary {
            let _ = writeln!(forward, "    pos->{} = rotary[{k}];", member(a.letter));
            let _ = writeln!(inverse, "    rotary[{k}] = pos->{};", member(a.letter));
        }
    }
    forward.push_str("    return 0;\n}\n\n");
    inverse.push_str(
        "    if (ta_inverse(world, rotary, q) < 0) return -1;\n    for (k = 0; k < TA_N; k++) joints[k] = q[k];\n    return 0;\n}\n",
    );
    c.push_str(&forward);
    c.push_str(&inverse);
    c
}

/// The lines for the machine's INI file.
pub fn ini_lines(machine: &Machine, name: &str) -> String {
    let letters = machine.axis_letters();
    format!(
        "# trueaxis: the generated kinematics module (build it first: halcompile --install {name}.comp)\n\
         [KINS]\nKINEMATICS = {name}\nJOINTS = {}\n\n# [TRAJ] COORDINATES = {letters}; joint n is the n-th axis of {letters}; units mm and deg\n",
        machine.axis_count()
    )
}

/// The module's files: `<name>.comp` and `<name>.ini`.
pub fn export(machine: &Machine, model: &KinsModel, name: &str) -> Result<Vec<ExportedFile>, CompensateError> {
    if name.is_empty()
        || !name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        || name.starts_with(|c: char| c.is_ascii_digit())
    {
        return Err(CompensateError::Input(format!(
            "the kinematics module name `{name}`: lower-case letters, digits and `_`, not starting with a digit"
        )));
    }
    let finite = model.params.iter().chain(model.tables.iter().flat_map(|t| t.4.iter())).all(|v| v.is_finite());
    if !finite {
        return Err(CompensateError::Computation("the kinematics module's numbers are not finite".into()));
    }
    let text = component(machine, model, name);
    Ok(vec![
        ExportedFile { name: format!("{name}.comp"), contents: text },
        ExportedFile { name: format!("{name}.ini"), contents: ini_lines(machine, name) },
    ])
}
