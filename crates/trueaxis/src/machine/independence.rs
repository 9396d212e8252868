//! The linear axes of a machine must move the tool in independent directions: two parallel axes
//! (a quill W beside a slide Z) or three in one plane leave a correction without a unique answer,
//! and the solver would fail late ("the correction did not converge") instead of the machine file
//! being refused where it is wrong.
//!
//! With the unit directions `d_1 .. d_k` of the `k` linear axes as columns of `D`, their
//! independence is the volume they span, `sqrt(det(D^T D))`: `sin` of the angle between two axes,
//! `|det D|` for three. A correction of a position error `e` moves the axes by up to `|e| / v`;
//! below [`MIN_INDEPENDENCE`] (two axes 0.57 deg from parallel) an error of 1 um would need more
//! than 100 um of axis motion, so the file is refused. More than three linear axes cannot be
//! independent in space.

use super::{Axis, AxisKind};
use crate::error::{Error, Result};
use nalgebra::DMatrix;

/// Smallest volume spanned by the unit directions of the linear axes (module documentation).
pub const MIN_INDEPENDENCE: f64 = 0.01;

/// Refuses linear axes that are parallel or dependent, naming them.
pub(super) fn refuse_dependent_linear_axes(axes: &[Axis]) -> Result<()> {
    let mut linear: Vec<&Axis> = axes.iter().filter(|a| a.kind == AxisKind::Linear).collect();
    linear.sort_by_key(|a| "XYZUVW".find(a.letter));
    let letters = |set: &[&Axis]| set.iter().map(|a| a.letter.to_string()).collect::<Vec<_>>();
    if linear.len() > 3 {
        return Err(Error::input(format!(
            "{} linear axes ({}): at most three can move in independent directions; trueaxis models machines whose linear axes are \
             independent",
            linear.len(),
            letters(&linear).join(" ")
        )));
    }
    // the smallest dependent set: a pair first, then all three
    for size in 2..=linear.len() {
        for set in subsets(&linear, size) {
            let v = volume(&set);
            if v < MIN_INDEPENDENCE {
                let names = letters(&set);
                let what = if size == 2 {
                    let angle = v.clamp(-1.0, 1.0).asin().to_degrees();
                    format!("linear axes {} and {} are parallel ({angle:.2} deg apart)", names[0], names[1])
                } else {
                    format!("linear axes {} lie in one plane (they span a volume of {v:.1e} of a cube)", names.join(", "))
                };
                return Err(Error::input(format!(
                    "{what}: a correction could not tell their motions apart; the linear axes of a machine must be independent \
                     (at least {MIN_INDEPENDENCE} apart as a sine or a volume)"
                )));
            }
        }
    }
    Ok(())
}

/// `sqrt(det(D^T D))` of the unit directions of `axes`.
fn volume(axes: &[&Axis]) -> f64 {
    let d = DMatrix::from_fn(3, axes.len(), |r, c| axes[c].direction[r]);
    (d.transpose() * &d).determinant().max(0.0).sqrt()
}

/// Every subset of `size` elements of `items` (at most three of them here).
fn subsets<T: Copy>(items: &[T], size: usize) -> Vec<Vec<T>> {
    if size == 0 {
        return vec![Vec::new()];
    }
    (0..items.len())
        .flat_map(|i| {
            subsets(&items[i + 1..], size - 1).into_iter().map(move |mut rest| {
                rest.insert(0, items[i]);
                rest
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::machine::Machine;

    fn machine(directions: &[(char, [f64; 3])]) -> Result<Machine, crate::machine::MachineError> {
        let structure: String = directions.iter().map(|(l, _)| *l).collect();
        let axes: String = directions
            .iter()
            .map(|(l, d)| format!("{l} = {{ kind = \"linear\", direction = [{}, {}, {}], range = [-100, 100] }}\n", d[0], d[1], d[2]))
            .collect();
        let text = format!("name = \"m\"\nstructure = \"wb{structure}t\"\n[axes]\n{axes}[tool]\npoint = [0, 0, 0]\n");
        Machine::from_toml_str(&text, "m.toml")
    }

    #[test]
    fn parallel_and_coplanar_linear_axes_are_refused_and_tilted_ones_kept() {
        let e = machine(&[('X', [1.0, 0.0, 0.0]), ('Y', [0.0, 1.0, 0.0]), ('Z', [0.0, 0.0, 1.0]), ('W', [0.0, 0.0, 1.0])])
            .unwrap_err()
            .to_string();
        assert!(e.contains("4 linear axes (X Y Z W)"), "{e}");
        let e = machine(&[('X', [1.0, 0.0, 0.0]), ('Y', [0.0, 1.0, 0.0]), ('U', [1.0, 0.0, 0.0])]).unwrap_err().to_string();
        assert!(e.contains("linear axes X and U are parallel (0.00 deg apart)"), "{e}");
        // 0.3 deg apart: within the bound
        let t = 0.3f64.to_radians();
        let e = machine(&[('X', [1.0, 0.0, 0.0]), ('U', [t.cos(), t.sin(), 0.0])]).unwrap_err().to_string();
        assert!(e.contains("0.30 deg apart"), "{e}");
        let s = 0.5f64.sqrt();
        let e = machine(&[('X', [1.0, 0.0, 0.0]), ('Y', [0.0, 1.0, 0.0]), ('U', [s, s, 0.0])]).unwrap_err().to_string();
        assert!(e.contains("linear axes X, Y, U lie in one plane"), "{e}");
        // a 45-degree slide and a few degrees of tilt are independent
        machine(&[('X', [1.0, 0.0, 0.0]), ('Y', [0.0, s, s]), ('Z', [0.0, 0.0, 1.0])]).unwrap();
        let t = 2f64.to_radians();
        machine(&[('X', [1.0, 0.0, 0.0]), ('U', [t.cos(), t.sin(), 0.0])]).unwrap();
    }
}
