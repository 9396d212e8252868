//! The budget of every five-axis configuration for one part, with the same component tolerances, and
//! their ranking (Zhu 2008 appendices B and C together): each configuration's ideal machine
//! ([`Configuration::machine`]) is analysed at the poses that put the tool on a grid over the part
//! with the tool upright and tilted towards +-x and +-y.

use super::analysis::analyse;
use super::components::ErrorKind;
use super::configurations::{axis_direction, Configuration, Pattern};
use super::form_shaping::{form_shaping, FormShaping};
use super::poses::{linspace, to_internal};
use super::spec::{BudgetSpec, KindValues};
use super::travel::{linear_positions, required_travel, space_utility};
use crate::error::Error;
use crate::geometry::{rotation_about_axis, Vec3};
use crate::machine::Machine;
use crate::model::{Frame, Setup};
use rayon::prelude::*;
use std::collections::HashMap;

/// What the study varies: the part, the tool, the tolerances and the poses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyOptions {
    /// Part `l x m x n` (mm), a corner on the pivot of the rotary axes.
    pub part: [f64; 3],
    /// Tool length `p` (mm) from the pivot of the rotary axes next to the tool.
    pub tool_length: f64,
    pub tolerances: KindValues,
    /// Grid points per edge of the part.
    pub nodes: usize,
    /// Tilt of the tool from the workpiece's +Z in the four tilted directions (deg).
    pub tilt_deg: f64,
}

/// One configuration's place in the study.
#[derive(Clone, Debug)]
pub struct ConfigurationBudget {
    pub configuration: Configuration,
    pub form_shaping: FormShaping,
    /// Travel of X, Y, Z (mm, largest magnitude).
    pub travel: [f64; 3],
    pub space_utility: f64,
    /// Root mean square over the poses of the root-sum-square 3D error (um).
    pub rss_rms: f64,
    pub rss_max: f64,
    pub worst_max: f64,
    /// Shares (%) of the linear, angular and squareness errors.
    pub kind_shares: [f64; 3],
    pub poses: usize,
}

/// Rotary positions (rad, sequence order) that turn the tool along the unit vector `o` (workpiece
/// frame): `R1(t1) R2(t2) e_z = o`. The component of `R2(t2) e_z` along the first axis must equal
/// `o`'s (a rotation about an axis keeps it): `C + A cos t2 + B sin t2 = D`; then `t1` turns the
/// rest onto `o`. Of the two solutions, the one with the smaller `|t2|`.
pub fn orientation_angles(sequence: &[char; 5], o: &Vec3) -> Option<[f64; 2]> {
    let rotary: Vec<char> = sequence.iter().copied().filter(|c| "ABC".contains(*c)).collect();
    let (u1, u2) = (axis_direction(rotary[0]), axis_direction(rotary[1]));
    let w = Vec3::z();
    let parallel = u2 * u2.dot(&w);
    let perpendicular = w - parallel;
    let c = u1.dot(&parallel);
    let a = u1.dot(&perpendicular);
    let b = u1.dot(&u2.cross(&w));
    let radius = a.hypot(b);
    let d = u1.dot(o) - c;
    if radius < 1e-12 || d.abs() > radius * (1.0 + 1e-12) {
        return None;
    }
    let phase = b.atan2(a);
    let spread = (d / radius).clamp(-1.0, 1.0).acos();
    let wrap = |x: f64| (x + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI;
    let t2 = [wrap(phase + spread), wrap(phase - spread)].into_iter().min_by(|x, y| x.abs().total_cmp(&y.abs())).expect("two");
    let v = rotation_about_axis(&u2, t2) * w;
    let (vp, op) = (v - u1 * u1.dot(&v), o - u1 * u1.dot(o));
    let t1 = if vp.norm() < 1e-12 || op.norm() < 1e-12 { 0.0 } else { u1.dot(&vp.cross(&op)).atan2(vp.dot(&op)) };
    Some([t1, t2])
}

/// Poses (user units, the machine's canonical order) of the study for one configuration.
pub fn study_poses(configuration: &Configuration, machine: &Machine, options: &StudyOptions) -> Vec<f64> {
    let s = &configuration.sequence;
    let tilt = options.tilt_deg.to_radians();
    let directions = [
        Vec3::z(),
        Vec3::new(tilt.sin(), 0.0, tilt.cos()),
        Vec3::new(-tilt.sin(), 0.0, tilt.cos()),
        Vec3::new(0.0, tilt.sin(), tilt.cos()),
        Vec3::new(0.0, -tilt.sin(), tilt.cos()),
    ];
    let mut poses = Vec::new();
    for o in &directions {
        let Some(angles) = orientation_angles(s, o) else { continue };
        for z in linspace(0.0, options.part[2], options.nodes) {
            for y in linspace(0.0, options.part[1], options.nodes) {
                for x in linspace(0.0, options.part[0], options.nodes) {
                    let Some(lin) = linear_positions(s, angles, &Vec3::new(x, y, z), options.tool_length) else { continue };
                    let mut pose = vec![0.0; machine.axis_count()];
                    let mut r = 0;
                    for c in s {
                        let k = machine.axis_index(*c).expect("axis of the configuration");
                        pose[k] = match "XYZ".find(*c) {
                            Some(i) => lin[i],
                            None => {
                                r += 1;
                                angles[r - 1].to_degrees()
                            }
                        };
                    }
                    poses.extend(pose);
                }
            }
        }
    }
    poses
}

/// The budgets of `configurations`, ranked by the root mean square of the root-sum-square error
/// (smallest first; ties by axes and bed).
pub fn study(configurations: &[Configuration], options: &StudyOptions) -> Result<Vec<ConfigurationBudget>, Error> {
    study_with_progress(configurations, options, &|_, _| {})
}

/// [`study`], calling `progress(done, total)` after each configuration's budget (from the worker
/// threads, in the order they finish).
pub fn study_with_progress(
    configurations: &[Configuration],
    options: &StudyOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<ConfigurationBudget>, Error> {
    if options.part.iter().chain([&options.tool_length]).any(|v| !(v.is_finite() && *v > 0.0)) {
        return Err(Error::input(format!(
            "part {:?} mm and tool length {} mm must be positive lengths",
            options.part, options.tool_length
        )));
    }
    // travel depends only on the category and the rotary axes' order
    let key = |c: &Configuration| -> (Pattern, String) { (c.pattern(), c.sequence.iter().filter(|a| "ABC".contains(**a)).collect()) };
    let mut travels: HashMap<(Pattern, String), [f64; 3]> = HashMap::new();
    for c in configurations {
        if let std::collections::hash_map::Entry::Vacant(e) = travels.entry(key(c)) {
            e.insert(required_travel(&c.sequence, options.part, options.tool_length)?);
        }
    }
    let done = std::sync::atomic::AtomicUsize::new(0);
    let mut out: Vec<ConfigurationBudget> = configurations
        .par_iter()
        .map(|c| -> Result<ConfigurationBudget, Error> {
            let travel = travels[&key(c)];
            let margin = travel.map(|t| t * (1.0 + 1e-6) + 1e-6);
            let machine = c.machine(margin, options.tool_length);
            let spec = BudgetSpec::standard(&machine, options.tolerances);
            let user = study_poses(c, &machine, options);
            let internal = to_internal(&machine, &user);
            let analysis = analyse(&machine, &spec, &internal, &Setup::of_machine(&machine), Frame::Workpiece)?;
            let kind_shares = ErrorKind::ALL.map(|k| analysis.by_kind.iter().find(|g| g.label == k.name()).map_or(0.0, |g| g.share));
            progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1, configurations.len());
            Ok(ConfigurationBudget {
                configuration: *c,
                form_shaping: form_shaping(&c.sequence),
                travel,
                space_utility: space_utility(options.part, travel),
                rss_rms: analysis.rss_rms,
                rss_max: analysis.rss_max().1,
                worst_max: analysis.worst_max().1,
                kind_shares,
                poses: analysis.poses.len(),
            })
        })
        .collect::<Result<_, _>>()?;
    out.sort_by(|a, b| {
        a.rss_rms
            .total_cmp(&b.rss_rms)
            .then(a.configuration.axes().cmp(&b.configuration.axes()))
            .then(a.configuration.bed.cmp(&b.configuration.bed))
    });
    Ok(out)
}
