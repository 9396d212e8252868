//! The five-axis configurations of Zhu 2008 appendix C (after Bohez 2002): which axes, in which
//! order from the workpiece to the tool, and where the bed is. Counting rules that give the
//! appendix's numbers:
//!
//! - 720: ordered choices of five different axes out of X Y Z A B C (`6 x 5!`), bed ignored;
//! - 360: those with the three linear axes (`3 x 5!`);
//! - 432: the three categories of the appendix, the two rotary axes both next to the workpiece
//!   (`RoRoTrTrTr`), one at each end (`RoTrTrTrRo`) or both next to the tool (`TrTrTrRoRo`): 36 axis
//!   assignments each (3 x 2 rotary, 3! linear), times the 4 places of the bed between two axes
//!   (144 per category). The appendix's "120 per category" is the number of orders of one set of
//!   five axes (5! = 360 / 3), not the size of these categories;
//! - 288: the configurations whose form-shaping function gives five degrees of freedom (96 per
//!   category): a C axis next to the tool turns about the tool axis, and one between the other rotary
//!   axis and the linear axes turns the linear axes in their own XY plane; either leaves four.

use crate::geometry::{Pose, Vec3};
use crate::machine::Machine;
use nalgebra::{Matrix6x5, Vector6};
use serde::Serialize;

/// The axis letters of the appendix.
pub const AXES: [char; 6] = ['X', 'Y', 'Z', 'A', 'B', 'C'];

/// Where the two rotary axes are in the chain from the workpiece to the tool.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Pattern {
    /// `RoRoTrTrTr`: both next to the workpiece (table-table machines).
    RotaryAtWorkpiece,
    /// `RoTrTrTrRo`: one at each end (table-head machines).
    Split,
    /// `TrTrTrRoRo`: both next to the tool (head-head machines).
    RotaryAtTool,
    /// A rotary axis between linear axes.
    Mixed,
}

impl Pattern {
    pub const PRACTICAL: [Pattern; 3] = [Pattern::RotaryAtWorkpiece, Pattern::Split, Pattern::RotaryAtTool];

    /// The appendix's notation.
    pub fn notation(self) -> &'static str {
        match self {
            Pattern::RotaryAtWorkpiece => "RoRoTrTrTr",
            Pattern::Split => "RoTrTrTrRo",
            Pattern::RotaryAtTool => "TrTrTrRoRo",
            Pattern::Mixed => "mixed",
        }
    }

    pub fn of(sequence: &[char]) -> Pattern {
        let rotary: String = sequence.iter().map(|c| if is_rotary(*c) { 'R' } else { 'T' }).collect();
        match rotary.as_str() {
            "RRTTT" => Pattern::RotaryAtWorkpiece,
            "RTTTR" => Pattern::Split,
            "TTTRR" => Pattern::RotaryAtTool,
            _ => Pattern::Mixed,
        }
    }
}

fn is_rotary(c: char) -> bool {
    matches!(c, 'A' | 'B' | 'C')
}

/// A five-axis configuration: the axes from the workpiece to the tool, and how many of them are
/// between the workpiece and the bed (carry the workpiece).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Configuration {
    pub sequence: [char; 5],
    pub bed: usize,
}

impl Configuration {
    pub fn pattern(&self) -> Pattern {
        Pattern::of(&self.sequence)
    }

    /// The axes as a string, workpiece to tool (`ABXYZ`).
    pub fn axes(&self) -> String {
        self.sequence.iter().collect()
    }

    /// The trueaxis structure code (`wBAbXYZt` for workpiece - A - B - bed - X - Y - Z - tool).
    pub fn structure(&self) -> String {
        let work: String = self.sequence[..self.bed].iter().collect();
        let tool: String = self.sequence[self.bed..].iter().collect();
        format!("w{work}b{tool}t")
    }

    /// The appendix's chain `P_T A B G_R X Y Z T_L`.
    pub fn chain(&self) -> String {
        let mut parts = vec!["P_T".to_string()];
        for (i, c) in self.sequence.iter().enumerate() {
            if i == self.bed {
                parts.push("G_R".into());
            }
            parts.push(c.to_string());
        }
        if self.bed == 5 {
            parts.push("G_R".into());
        }
        parts.push("T_L".into());
        parts.join(" ")
    }

    /// Degrees of freedom of the ideal form-shaping function: the rank of its Jacobian (tool
    /// position and direction) with respect to the five axes at a generic pose.
    pub fn degrees_of_freedom(&self) -> usize {
        degrees_of_freedom(&self.sequence)
    }

    /// The ideal machine of this configuration: every axis through the origin of M, the tool point
    /// `tool_length` mm along +Z, linear travels `[-t, t]` (mm, X Y Z), continuous rotary axes.
    /// Workpiece-side axes point the opposite way (ISO 841 primed axes), so the position of the tool
    /// relative to the workpiece is the form-shaping function of the appendix wherever the bed is.
    pub fn machine(&self, travel: [f64; 3], tool_length: f64) -> Machine {
        let mut text = format!(
            "name = \"{} ({})\"\nsource = \"Zhu (2008) appendix C\"\nstructure = \"{}\"\n[axes]\n",
            self.axes(),
            self.chain(),
            self.structure()
        );
        for (i, &c) in self.sequence.iter().enumerate() {
            let sign = if i < self.bed { -1.0 } else { 1.0 };
            let d = axis_direction(c) * sign;
            if is_rotary(c) {
                text += &format!("{c} = {{ kind = \"rotary\", direction = [{}, {}, {}], point = [0, 0, 0] }}\n", d.x, d.y, d.z);
            } else {
                let t = travel["XYZ".find(c).expect("linear letter")].max(1e-3);
                text += &format!("{c} = {{ kind = \"linear\", direction = [{}, {}, {}], range = [{}, {}] }}\n", d.x, d.y, d.z, -t, t);
            }
        }
        text += &format!("[tool]\npoint = [0, 0, {tool_length}]\n");
        Machine::from_toml_str(&text, &self.axes()).expect("a generated configuration is a valid machine")
    }
}

/// Unit direction of an axis letter of the appendix (A, B, C about X, Y, Z).
pub fn axis_direction(c: char) -> Vec3 {
    match c {
        'X' | 'A' => Vec3::x(),
        'Y' | 'B' => Vec3::y(),
        _ => Vec3::z(),
    }
}

/// The ideal relative pose of the tool in the workpiece frame for axis positions `q` (mm, rad) in
/// sequence order: `M_1(q_1) ... M_5(q_5) Trans(0, 0, p)`, the form-shaping function of the
/// appendix (Table C.1), all axes through the origin.
pub fn ideal_pose(sequence: &[char], q: &[f64], tool_length: f64) -> (Vec3, Vec3) {
    let mut t = Pose::IDENTITY;
    for (&c, &v) in sequence.iter().zip(q) {
        let motion = if is_rotary(c) {
            Pose::rotation_about_line(&axis_direction(c), &Vec3::zeros(), v)
        } else {
            Pose::translation(axis_direction(c) * v)
        };
        t = t.then(&motion);
    }
    (t.transform_point(&Vec3::new(0.0, 0.0, tool_length)), t.rotation * Vec3::z())
}

/// Rank of the Jacobian of the ideal form-shaping function (position, and tool direction times a
/// length) at a generic pose.
pub fn degrees_of_freedom(sequence: &[char]) -> usize {
    let q0 = [0.31, -0.47, 0.73, 0.59, -0.23];
    let p = 100.0;
    let f = |q: &[f64]| -> Vector6<f64> {
        let (x, d) = ideal_pose(sequence, q, p);
        Vector6::new(x.x, x.y, x.z, d.x * p, d.y * p, d.z * p)
    };
    let mut jac = Matrix6x5::zeros();
    for k in 0..5 {
        let h = 1e-6;
        let (mut plus, mut minus) = (q0, q0);
        plus[k] += h;
        minus[k] -= h;
        jac.set_column(k, &((f(&plus) - f(&minus)) / (2.0 * h)));
    }
    let sv = jac.svd(false, false).singular_values;
    let largest = sv.max();
    sv.iter().filter(|s| **s > 1e-6 * largest).count()
}

fn permutations(items: &[char], length: usize, out: &mut Vec<Vec<char>>, current: &mut Vec<char>) {
    if current.len() == length {
        out.push(current.clone());
        return;
    }
    for &c in items {
        if !current.contains(&c) {
            current.push(c);
            permutations(items, length, out, current);
            current.pop();
        }
    }
}

/// Every order of five different axes out of X Y Z A B C, workpiece to tool (720).
pub fn all_sequences() -> Vec<[char; 5]> {
    let mut out = Vec::new();
    permutations(&AXES, 5, &mut out, &mut Vec::new());
    out.into_iter().map(|v| [v[0], v[1], v[2], v[3], v[4]]).collect()
}

/// The sequences with the three linear axes (360).
pub fn three_linear_sequences() -> Vec<[char; 5]> {
    all_sequences().into_iter().filter(|s| ['X', 'Y', 'Z'].iter().all(|c| s.contains(c))).collect()
}

/// The configurations of the three categories with the bed between two axes (432).
pub fn practical_configurations() -> Vec<Configuration> {
    three_linear_sequences()
        .into_iter()
        .filter(|s| Pattern::of(s) != Pattern::Mixed)
        .flat_map(|sequence| (1..5).map(move |bed| Configuration { sequence, bed }))
        .collect()
}

/// The practical configurations with five degrees of freedom (288).
pub fn five_axis_configurations() -> Vec<Configuration> {
    practical_configurations().into_iter().filter(|c| c.degrees_of_freedom() == 5).collect()
}
