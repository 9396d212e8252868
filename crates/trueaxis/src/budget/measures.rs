//! Measures of a sensitivity matrix (Zhu 2008 appendix B): its singular values and condition number
//! (the design sensitivity ellipsoid, eqs. B.12-B.13), the part measures `SP` (B.9-B.11), the machine
//! measures `SM` per axis and per kind (B.14-B.19), and the share of each component and group in the
//! root-sum-square volumetric error (B.20-B.21, with the exact lever arms in place of the part length).
//!
//! Over several poses each measure is the root mean square over the poses (the pose-averaged Gram
//! matrix `mean_p SE_p SE_p^T` for the singular values), which is the measure itself at one pose.
//! Sensitivities of homogenised tolerances are in mm: um of volumetric error per urad (angular and
//! squareness errors) or per um/m (linear errors).

use super::components::BudgetComponent;
use super::sensitivity::Sensitivity;
use nalgebra::Matrix3;

/// Homogenised sensitivity column factor (mm): `SE_:j * factor` is the gain per urad or um/m.
pub fn homogenising_factor(c: &BudgetComponent) -> f64 {
    if c.id.component().is_rotation() {
        1000.0
    } else {
        c.length_mm
    }
}

/// Singular values (mm, descending) of the homogenised matrices of the poses `selected`, as the
/// square roots of the eigenvalues of their mean Gram matrix.
pub fn singular_values(s: &Sensitivity, components: &[BudgetComponent], selected: impl IntoIterator<Item = usize>) -> [f64; 3] {
    let mut gram = Matrix3::zeros();
    let mut count = 0;
    let factors: Vec<f64> = components.iter().map(homogenising_factor).collect();
    for p in selected {
        for a in 0..3 {
            for b in a..3 {
                let value: f64 = s.row(p, a).iter().zip(s.row(p, b)).zip(&factors).map(|((x, y), f)| x * y * f * f).sum();
                gram[(a, b)] += value;
                if a != b {
                    gram[(b, a)] += value;
                }
            }
        }
        count += 1;
    }
    let gram = gram / count.max(1) as f64;
    let mut values: Vec<f64> = gram.symmetric_eigenvalues().iter().map(|l| l.max(0.0).sqrt()).collect();
    values.sort_by(|a, b| b.total_cmp(a));
    [values[0], values[1], values[2]]
}

/// Condition number `sigma_max / sigma_min`; `None` when the smallest is zero (a direction no
/// component error moves, e.g. a machine with fewer than three linear axes).
pub fn condition_number(sigma: &[f64; 3]) -> Option<f64> {
    (sigma[2] > 1e-12 * sigma[0]).then(|| sigma[0] / sigma[2])
}

/// The Euclidean norm of homogenised tolerances (um/m or urad) of the components `members`.
pub fn homogenised_norm(components: &[BudgetComponent], tolerances: &[f64], members: &[usize]) -> f64 {
    members.iter().map(|&j| (tolerances[j] / components[j].scale()).powi(2)).sum::<f64>().sqrt()
}

/// Per component: the mean over poses of `|SE_:j|^2` (um^2 per um^2 or per urad^2).
pub fn mean_square_gains(s: &Sensitivity) -> Vec<f64> {
    let n = s.components;
    let poses = s.poses();
    let mut out = vec![0.0; n];
    for p in 0..poses {
        for (j, o) in out.iter_mut().enumerate() {
            *o += s.column(p, j).norm_squared();
        }
    }
    out.iter_mut().for_each(|v| *v /= poses.max(1) as f64);
    out
}
