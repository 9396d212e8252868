//! The CapBall identification test of Andolfatto et al. 2011 on the Huron KX8-Five (`examples/machines/kx8five.toml`)
//! as a design matrix of the first-order model (`model::jacobian_batch`, machine frame, translation
//! rows): the tool point held on a master ball on the table while A and C sweep and X, Y, Z follow.
//! Used by `uncertainty/kx8five.rs` and `uncertainty/kx8five_table5.rs`.
#![allow(dead_code)]

use nalgebra::DMatrix;
use trueaxis::geometry::Vec3;
use trueaxis::machine::Machine;
use trueaxis::model::{jacobian_batch, nominal_chain, Frame, Setup, JACOBIAN_ROWS};
use trueaxis::uncertainty::DesignMatrix;

/// A 3D-ball trajectory: ball centre at home (mm, in M), A from 0 to `a_end_deg`, C from 0 to
/// `c_end_deg`, both linearly over `poses` poses.
#[derive(Clone, Copy, Debug)]
pub struct Trajectory {
    pub ball: [f64; 3],
    pub a_end_deg: f64,
    pub c_end_deg: f64,
    pub poses: usize,
}

impl Trajectory {
    /// The trajectory of the shipped design (`examples/uncertainty/kx8five_design.csv`): ball at
    /// (150, 0, 50) mm, A 0 -> 120 deg, C three turns clockwise, 807 poses (Andolfatto et al. 2011 §3.2, Fig. 2).
    pub const SEED_004: Trajectory = Trajectory { ball: [150.0, 0.0, 50.0], a_end_deg: 120.0, c_end_deg: -1080.0, poses: 807 };
}

/// The design matrix of `parameters` (ISO names) along `trajectory`: rows x, y, z of each pose,
/// pose k (from 1) at `k * point_time_s`; sensitivities in um per um or um per urad. `None` when a
/// pose leaves the travel of an axis.
pub fn try_capball_design(trajectory: &Trajectory, parameters: &[&str], point_time_s: f64) -> Option<DesignMatrix> {
    let machine = Machine::load("../../examples/machines/kx8five.toml").unwrap();
    let ball = Vec3::from(trajectory.ball);
    let n_poses = trajectory.poses;
    let n_axes = machine.axis_count();
    let index = |c: char| machine.axis_index(c).unwrap();
    let mut poses = vec![0.0; n_poses * n_axes];
    let mut user = vec![0.0; n_axes];
    for k in 0..n_poses {
        user.fill(0.0);
        let s = k as f64 / (n_poses - 1) as f64;
        user[index('A')] = trajectory.a_end_deg * s;
        user[index('C')] = trajectory.c_end_deg * s;
        let pose = &mut poses[k * n_axes..(k + 1) * n_axes];
        machine.pose_to_internal(&user, pose);
        // with X, Y, Z at 0 the ball is at p; the tool point follows it: (X, Y, Z) = p - tool point
        let p = nominal_chain(&machine, machine.work_chain(), pose, None).transform_point(&ball);
        let d = p - machine.tool_point;
        for (c, v) in ['X', 'Y', 'Z'].into_iter().zip(d.iter()) {
            user[index(c)] = *v;
        }
        machine.check_range(&user).ok()?;
        machine.pose_to_internal(&user, pose);
        let tool = nominal_chain(&machine, machine.tool_chain(), pose, None).transform_point(&machine.tool_point);
        let work = nominal_chain(&machine, machine.work_chain(), pose, None).transform_point(&ball);
        assert!((tool - work).norm() < 1e-9, "pose {k}: the tool point is on the ball");
    }
    let setup = Setup { tool_point: machine.tool_point, work_point: ball };
    let jac = jacobian_batch(&machine, &poses, &setup, Frame::Machine);
    let n_par = machine.parameter_count();
    let columns: Vec<(usize, f64)> = parameters
        .iter()
        .map(|name| {
            let (id, i) = machine.parse_parameter(name).unwrap();
            (i, 1e3 * id.component().to_internal()) // mm per internal unit -> um per um or urad
        })
        .collect();
    let mut x = DMatrix::zeros(3 * n_poses, parameters.len());
    let (mut channels, mut time) = (Vec::new(), Vec::new());
    for k in 0..n_poses {
        for (r, ch) in ["x", "y", "z"].iter().enumerate() {
            let row = &jac[(k * JACOBIAN_ROWS + r) * n_par..(k * JACOBIAN_ROWS + r + 1) * n_par];
            for (j, (i, factor)) in columns.iter().enumerate() {
                x[(3 * k + r, j)] = row[*i] * factor;
            }
            channels.push(ch.to_string());
            time.push(point_time_s * (k + 1) as f64);
        }
    }
    Some(DesignMatrix::new(parameters.iter().map(|p| p.to_string()).collect(), &channels, time, None, None, x).unwrap())
}

/// [`try_capball_design`] for a trajectory inside the travel.
pub fn capball_design(trajectory: &Trajectory, parameters: &[&str], point_time_s: f64) -> DesignMatrix {
    try_capball_design(trajectory, parameters, point_time_s).expect("the trajectory stays inside the travel")
}
