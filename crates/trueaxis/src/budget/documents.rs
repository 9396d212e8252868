//! The documents of a budget problem, written once for the command line and the Python package: the
//! JSON of `trueaxis budget analyse --json` and `budget allocate --json`, the per-pose stack-up CSV
//! (`--out`: axis positions in mm and deg, root-sum-square and worst-case errors in um, the largest
//! homogenised singular value in mm, the condition number) and the sensitivity CSV
//! (`--sensitivity`: one row per pose and direction, um per um or per urad). Numbers that are not
//! finite are written as JSON `null`.

use super::allocate::{Allocation, AllocationOptions, Stack, Target};
use super::analysis::{Analysis, GroupShare};
use super::problem::{BudgetProblem, PoseSet};
use crate::model::Frame;
use serde_json::{json, Value};
use std::fmt::Write;

/// A number for JSON: `null` when not finite.
pub fn number(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

pub fn frame_name(frame: Frame) -> &'static str {
    match frame {
        Frame::Workpiece => "workpiece",
        Frame::Machine => "machine",
    }
}

pub fn stack_name(stack: Stack) -> &'static str {
    match stack {
        Stack::Rss => "root-sum-square",
        Stack::WorstCase => "worst case",
    }
}

/// The target as text (um) and as JSON.
pub fn target_text(target: Target) -> (String, Value) {
    match target {
        Target::Total(v) => (format!("{v} um (3D)"), json!({"total_um": v})),
        Target::PerDirection(v) => {
            (format!("{} / {} / {} um (x / y / z)", v[0], v[1], v[2]), json!({"x_um": v[0], "y_um": v[1], "z_um": v[2]}))
        }
    }
}

/// The name of a constraint's direction: x, y, z, or 3D.
pub fn direction_name(d: Option<usize>) -> &'static str {
    d.map_or("3D", |d| ["x", "y", "z"][d])
}

fn group_json(groups: &[GroupShare]) -> Value {
    Value::Array(
        groups.iter().map(|g| json!({"group": g.label, "share_percent": g.share, "rss_um": g.rss_um, "sm_mm": g.sensitivity_mm})).collect(),
    )
}

impl BudgetProblem {
    fn axis_names(&self) -> String {
        self.machine.axes().iter().map(|a| a.letter.to_string()).collect::<Vec<_>>().join(",")
    }

    fn positions(&self, pose: &[f64]) -> String {
        pose.iter().map(|v| format!("{v}")).collect::<Vec<_>>().join(",")
    }

    /// The document of `trueaxis budget analyse --json` for the analyses of every set.
    pub fn analysis_json(&self, analyses: &[Analysis]) -> Value {
        let sets: Vec<Value> = self.sets.iter().zip(analyses).map(|(set, a)| self.set_json(set, a)).collect();
        json!({
            "machine": self.machine.name,
            "frame": frame_name(self.frame),
            "units": {"tolerance": "um (linear) / urad (angular, squareness)", "volumetric_error": "um", "homogenised_sensitivity": "mm"},
            "sets": sets,
        })
    }

    fn set_json(&self, set: &PoseSet, a: &Analysis) -> Value {
        let spec = &self.spec;
        let (rss_pose, rss) = a.rss_max();
        let (worst_pose, worst) = a.worst_max();
        let components: Vec<Value> = spec
            .components
            .iter()
            .zip(&spec.tolerances)
            .zip(&a.components)
            .map(|((c, t), s)| {
                let rotation = c.id.component().is_rotation();
                json!({
                    "name": c.id.to_string(), "kind": c.kind.name(), "axis": c.axis.to_string(), "tolerance": t, "unit": c.kind.unit(),
                    "homogenisation_length_mm": c.length_mm, "gain": s.gain, "gain_unit": if rotation { "um/urad" } else { "um/um" },
                    "lever_mm": if rotation { number(s.gain * 1000.0) } else { Value::Null },
                    "rss_um": s.rss_um, "share_percent": s.share,
                })
            })
            .collect();
        let per_pose: Vec<Value> = set
            .user
            .chunks(self.machine.axis_count())
            .zip(&a.poses)
            .enumerate()
            .map(|(i, (pose, r))| {
                let positions: serde_json::Map<String, Value> =
                    self.machine.axes().iter().zip(pose).map(|(ax, v)| (ax.letter.to_string(), json!(v))).collect();
                json!({
                    "pose": i + 1, "position": positions,
                    "rss_um": {"x": r.stack.rss[0], "y": r.stack.rss[1], "z": r.stack.rss[2], "total": r.stack.rss_total},
                    "worst_case_um": {"x": r.stack.worst[0], "y": r.stack.worst[1], "z": r.stack.worst[2], "total": r.stack.worst_total},
                    "singular_values_mm": r.singular_values, "condition_number": r.condition.map_or(Value::Null, number),
                })
            })
            .collect();
        let dmax = |d: usize, worst: bool| a.direction_max(d, worst).1;
        json!({
            "label": set.label,
            "part_mm": set.part,
            "poses": a.poses.len(),
            "rss_um": {"max": rss, "max_pose": rss_pose + 1, "rms": a.rss_rms, "x_max": dmax(0, false), "y_max": dmax(1, false), "z_max": dmax(2, false)},
            "worst_case_um": {"max": worst, "max_pose": worst_pose + 1, "x_max": dmax(0, true), "y_max": dmax(1, true), "z_max": dmax(2, true)},
            "exact_check": {"pose": a.exact_check.pose + 1, "linear_um": a.exact_check.linear_um, "exact_um": a.exact_check.exact_um},
            "singular_values_mm": a.singular_values,
            "condition_number": a.condition.map_or(Value::Null, number),
            "part_sensitivity_mm": {"x": a.part_sensitivity[0], "y": a.part_sensitivity[1], "z": a.part_sensitivity[2]},
            "by_axis": group_json(&a.by_axis),
            "by_kind": group_json(&a.by_kind),
            "components": components,
            "no_effect": a.no_effect.iter().map(|&j| spec.components[j].id.to_string()).collect::<Vec<_>>(),
            "per_pose": per_pose,
        })
    }

    /// The per-pose stack-up of every set (CSV; a `part` column when there are several sets).
    pub fn poses_csv(&self, analyses: &[Analysis]) -> String {
        let with_part = self.sets.len() > 1;
        let part = if with_part { "part," } else { "" };
        let mut out = format!(
            "{part}pose,{},rss_x,rss_y,rss_z,rss_total,worst_x,worst_y,worst_z,worst_total,sigma_max_mm,condition\n",
            self.axis_names()
        );
        for (set, a) in self.sets.iter().zip(analyses) {
            let label = if with_part { format!("{},", set.label) } else { String::new() };
            for (i, (pose, r)) in set.user.chunks(self.machine.axis_count()).zip(&a.poses).enumerate() {
                let s = &r.stack;
                let _ = writeln!(
                    out,
                    "{label}{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{}",
                    i + 1,
                    self.positions(pose),
                    s.rss[0],
                    s.rss[1],
                    s.rss[2],
                    s.rss_total,
                    s.worst[0],
                    s.worst[1],
                    s.worst[2],
                    s.worst_total,
                    r.singular_values[0],
                    r.condition.map_or(String::new(), |c| format!("{c:.4}"))
                );
            }
        }
        out
    }

    /// The sensitivity matrix of every set (CSV: one row per pose and direction x, y, z, one column
    /// per component, um per um or um per urad).
    pub fn sensitivity_csv(&self, analyses: &[Analysis]) -> String {
        let names: Vec<String> = self.spec.components.iter().map(|c| c.id.to_string()).collect();
        let mut out = format!("set,pose,{},direction,{}\n", self.axis_names(), names.join(","));
        for (set, a) in self.sets.iter().zip(analyses) {
            for (p, pose) in set.user.chunks(self.machine.axis_count()).enumerate() {
                for (d, name) in ["x", "y", "z"].iter().enumerate() {
                    let values: Vec<String> = a.sensitivity.row(p, d).iter().map(|v| format!("{v:.9e}")).collect();
                    let _ = writeln!(out, "{},{},{},{name},{}", set.label, p + 1, self.positions(pose), values.join(","));
                }
            }
        }
        out
    }

    /// The document of `trueaxis budget allocate --json` (`poses`: the number of poses allocated on).
    pub fn allocation_json(&self, a: &Allocation, options: &AllocationOptions, poses: usize) -> Value {
        let spec = &self.spec;
        let components: Vec<Value> = spec
            .components
            .iter()
            .enumerate()
            .map(|(j, c)| {
                let term = &spec.cost.terms[j];
                let homogenised = a.tolerances[j] / c.scale();
                json!({
                    "name": c.id.to_string(), "kind": c.kind.name(), "tolerance": a.tolerances[j], "unit": c.kind.unit(),
                    "homogenised": homogenised, "homogenised_unit": if c.kind.unit() == "um" { "um/m" } else { "urad" },
                    "lower": term.lower, "at_lower": a.at_lower.contains(&j), "allocated": a.allocated[j],
                    "cost": if a.allocated[j] { number(term.a / homogenised.powf(term.k)) } else { Value::Null },
                })
            })
            .collect();
        let active: Vec<Value> = a
            .active
            .iter()
            .map(|c| json!({"pose": c.pose + 1, "direction": direction_name(c.direction), "multiplier": c.multiplier, "marginal_cost_per_um": c.marginal_cost_per_um}))
            .collect();
        json!({
            "machine": self.machine.name, "poses": poses, "stack": stack_name(options.stack), "target": target_text(options.target).1,
            "cost": a.cost, "global_stage_cost": a.global_cost, "achieved_um": a.achieved,
            "kkt_residual": a.kkt_residual, "smallest_multiplier": a.smallest_multiplier, "duality_gap": a.duality_gap,
            "newton_steps": a.newton_steps, "cutting_rounds": a.cutting_rounds, "seed": options.genetic.seed,
            "active": active, "components": components,
        })
    }

    /// The budget file `trueaxis budget allocate --out` writes: the allocated tolerances with a
    /// header naming the target (`poses`: the number of poses allocated on).
    pub fn allocation_toml(&self, a: &Allocation, options: &AllocationOptions, poses: usize) -> String {
        let header = format!(
            "Cost-optimal tolerances for machine `{}` (trueaxis budget allocate)\n{} target {} at {} poses ({}); cost {:.6e}",
            self.machine.name,
            stack_name(options.stack),
            target_text(options.target).0,
            poses,
            self.sets[0].label,
            a.cost
        );
        self.spec.with_tolerances(a.tolerances.clone()).to_toml(&self.machine, &header)
    }
}
