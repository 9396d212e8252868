//! Structure-of-arrays arithmetic on blocks of [`LANES`] poses: every quantity of the exact chain
//! (a coordinate, a rotation-matrix entry) is an array holding that quantity for each pose of the
//! block, and every operation is a loop over the lanes, which the compiler turns into vector
//! instructions (two f64 per SSE2 register, four per AVX2, eight per AVX-512).
//!
//! The operations are those of [`crate::geometry`] (`Pose::then`, `transform_point`, Rodrigues'
//! formula, `rotation_exp`, `rotation_log`) with the same formulas and summation order, so a block
//! gives the results of the scalar path to rounding. Each operation is generic over [`MulAdd`]: the
//! kernels for CPUs with fused multiply-add form `a b + c` with one rounding ([`Fused`]), the
//! baseline kernel with two ([`Separate`], the scalar path's arithmetic).

use crate::geometry::{rotation_exp, rotation_log, Mat3, Pose, Vec3};

/// Poses evaluated together: 8 f64 fill one AVX-512 register or two AVX2 registers.
pub(crate) const LANES: usize = 8;

/// One scalar quantity for each pose of a block.
pub(crate) type Lanes = [f64; LANES];

/// A 3-vector per lane: `v[i][lane]`.
pub(crate) type LaneVec = [Lanes; 3];

/// A 3x3 matrix per lane, row-major: `m[row][column][lane]`.
pub(crate) type LaneMat = [[Lanes; 3]; 3];

/// How a block forms `a b + c` and the sums of products of the chain.
pub(crate) trait MulAdd {
    /// `a b + c`.
    fn mul_add(a: f64, b: f64, c: f64) -> f64;

    /// `a0 b0 + a1 b1 + a2 b2`.
    #[inline(always)]
    fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
        Self::mul_add(a[2], b[2], Self::mul_add(a[1], b[1], a[0] * b[0]))
    }

    /// `(a0 b0 + a1 b1 + a2 b2) + c`.
    fn dot3_add(a: [f64; 3], b: [f64; 3], c: f64) -> f64;
}

/// Fused multiply-add, one rounding (`vfmadd` where the kernel is compiled with FMA; every
/// AArch64 CPU has it).
pub(crate) struct Fused;

impl MulAdd for Fused {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }

    #[inline(always)]
    fn dot3_add(a: [f64; 3], b: [f64; 3], c: f64) -> f64 {
        a[2].mul_add(b[2], a[1].mul_add(b[1], a[0].mul_add(b[0], c)))
    }
}

/// A product, then a sum, each rounded: the scalar path's arithmetic, for CPUs without FMA
/// (there `f64::mul_add` would be a library call per operation).
pub(crate) struct Separate;

impl MulAdd for Separate {
    #[inline(always)]
    fn mul_add(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }

    #[inline(always)]
    fn dot3_add(a: [f64; 3], b: [f64; 3], c: f64) -> f64 {
        Self::dot3(a, b) + c
    }
}

/// `x` in every lane.
#[inline(always)]
pub(crate) fn splat(x: f64) -> Lanes {
    [x; LANES]
}

/// A constant vector in every lane.
#[inline(always)]
pub(crate) fn splat_vec(v: &Vec3) -> LaneVec {
    [splat(v.x), splat(v.y), splat(v.z)]
}

/// A rigid transform per lane (`x -> R x + t`, mm).
#[derive(Clone, Copy)]
pub(crate) struct LanePose {
    pub rotation: LaneMat,
    pub translation: LaneVec,
}

impl LanePose {
    pub(crate) const IDENTITY: LanePose = LanePose {
        rotation: [
            [[1.0; LANES], [0.0; LANES], [0.0; LANES]],
            [[0.0; LANES], [1.0; LANES], [0.0; LANES]],
            [[0.0; LANES], [0.0; LANES], [1.0; LANES]],
        ],
        translation: [[0.0; LANES]; 3],
    };

    /// A constant pose in every lane.
    pub(crate) fn splat(pose: &Pose) -> LanePose {
        let mut rotation = [[splat(0.0); 3]; 3];
        for (i, row) in rotation.iter_mut().enumerate() {
            for (j, entry) in row.iter_mut().enumerate() {
                *entry = splat(pose.rotation[(i, j)]);
            }
        }
        LanePose { rotation, translation: splat_vec(&pose.translation) }
    }

    /// `self * other`, as [`Pose::then`].
    #[inline(always)]
    pub(crate) fn then<M: MulAdd>(&self, other: &LanePose) -> LanePose {
        LanePose { rotation: mat_mul::<M>(&self.rotation, &other.rotation), translation: self.transform_point::<M>(&other.translation) }
    }

    /// `self * Trans(t)`, as [`Pose::then_translation`].
    #[inline(always)]
    pub(crate) fn then_translation<M: MulAdd>(&self, t: &LaneVec) -> LanePose {
        LanePose { rotation: self.rotation, translation: self.transform_point::<M>(t) }
    }

    /// `R x + t`, as [`Pose::transform_point`].
    #[inline(always)]
    pub(crate) fn transform_point<M: MulAdd>(&self, x: &LaneVec) -> LaneVec {
        let (m, t) = (&self.rotation, &self.translation);
        let mut out = [splat(0.0); 3];
        for i in 0..3 {
            for l in 0..LANES {
                out[i][l] = M::dot3_add([m[i][0][l], m[i][1][l], m[i][2][l]], [x[0][l], x[1][l], x[2][l]], t[i][l]);
            }
        }
        out
    }

    /// The pose of one lane.
    #[cfg(test)]
    pub(crate) fn lane(&self, l: usize) -> Pose {
        Pose { rotation: mat_lane(&self.rotation, l), translation: vec_lane(&self.translation, l) }
    }
}

/// The vector of one lane.
#[inline(always)]
pub(crate) fn vec_lane(v: &LaneVec, l: usize) -> Vec3 {
    Vec3::new(v[0][l], v[1][l], v[2][l])
}

/// The matrix of one lane.
#[inline(always)]
pub(crate) fn mat_lane(m: &LaneMat, l: usize) -> Mat3 {
    Mat3::new(m[0][0][l], m[0][1][l], m[0][2][l], m[1][0][l], m[1][1][l], m[1][2][l], m[2][0][l], m[2][1][l], m[2][2][l])
}

/// Writes `m` into lane `l`.
#[inline(always)]
pub(crate) fn set_mat_lane(out: &mut LaneMat, l: usize, m: &Mat3) {
    for (i, row) in out.iter_mut().enumerate() {
        for (j, entry) in row.iter_mut().enumerate() {
            entry[l] = m[(i, j)];
        }
    }
}

#[inline(always)]
pub(crate) fn add(a: &LaneVec, b: &LaneVec) -> LaneVec {
    let mut out = [splat(0.0); 3];
    for i in 0..3 {
        for l in 0..LANES {
            out[i][l] = a[i][l] + b[i][l];
        }
    }
    out
}

#[inline(always)]
pub(crate) fn sub(a: &LaneVec, b: &LaneVec) -> LaneVec {
    let mut out = [splat(0.0); 3];
    for i in 0..3 {
        for l in 0..LANES {
            out[i][l] = a[i][l] - b[i][l];
        }
    }
    out
}

/// `a . b` per lane.
#[inline(always)]
pub(crate) fn dot<M: MulAdd>(a: &LaneVec, b: &LaneVec) -> Lanes {
    let mut out = splat(0.0);
    for l in 0..LANES {
        out[l] = M::dot3([a[0][l], a[1][l], a[2][l]], [b[0][l], b[1][l], b[2][l]]);
    }
    out
}

/// `|a|` per lane.
#[inline(always)]
pub(crate) fn norm<M: MulAdd>(a: &LaneVec) -> Lanes {
    let mut out = dot::<M>(a, a);
    for x in out.iter_mut() {
        *x = x.sqrt();
    }
    out
}

/// `m v`.
#[inline(always)]
pub(crate) fn mat_vec<M: MulAdd>(m: &LaneMat, v: &LaneVec) -> LaneVec {
    let mut out = [splat(0.0); 3];
    for i in 0..3 {
        for l in 0..LANES {
            out[i][l] = M::dot3([m[i][0][l], m[i][1][l], m[i][2][l]], [v[0][l], v[1][l], v[2][l]]);
        }
    }
    out
}

/// `m^T v`.
#[inline(always)]
pub(crate) fn mat_t_vec<M: MulAdd>(m: &LaneMat, v: &LaneVec) -> LaneVec {
    let mut out = [splat(0.0); 3];
    for i in 0..3 {
        for l in 0..LANES {
            out[i][l] = M::dot3([m[0][i][l], m[1][i][l], m[2][i][l]], [v[0][l], v[1][l], v[2][l]]);
        }
    }
    out
}

/// `a b`.
#[inline(always)]
pub(crate) fn mat_mul<M: MulAdd>(a: &LaneMat, b: &LaneMat) -> LaneMat {
    let mut out = [[splat(0.0); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for l in 0..LANES {
                out[i][j][l] = M::dot3([a[i][0][l], a[i][1][l], a[i][2][l]], [b[0][j][l], b[1][j][l], b[2][j][l]]);
            }
        }
    }
    out
}

/// `a^T b`.
#[inline(always)]
pub(crate) fn mat_t_mul<M: MulAdd>(a: &LaneMat, b: &LaneMat) -> LaneMat {
    let mut out = [[splat(0.0); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for l in 0..LANES {
                out[i][j][l] = M::dot3([a[0][i][l], a[1][i][l], a[2][i][l]], [b[0][j][l], b[1][j][l], b[2][j][l]]);
            }
        }
    }
    out
}

/// `a b^T`.
#[inline(always)]
pub(crate) fn mat_mul_t<M: MulAdd>(a: &LaneMat, b: &LaneMat) -> LaneMat {
    let mut out = [[splat(0.0); 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for l in 0..LANES {
                out[i][j][l] = M::dot3([a[i][0][l], a[i][1][l], a[i][2][l]], [b[j][0][l], b[j][1][l], b[j][2][l]]);
            }
        }
    }
    out
}

/// `d I + a [w]x + b w w^T` per lane, entry by entry as `geometry::so3::rodrigues`.
#[inline(always)]
pub(crate) fn rodrigues<M: MulAdd>(w: &LaneVec, d: &Lanes, a: &Lanes, b: &Lanes) -> LaneMat {
    let mut m = [[splat(0.0); 3]; 3];
    for l in 0..LANES {
        let (x, y, z) = (w[0][l], w[1][l], w[2][l]);
        let (d, a, b) = (d[l], a[l], b[l]);
        let (bx, by, bz) = (b * x, b * y, b * z);
        m[0][0][l] = M::mul_add(bx, x, d);
        m[0][1][l] = M::mul_add(bx, y, -(a * z));
        m[0][2][l] = M::mul_add(bx, z, a * y);
        m[1][0][l] = M::mul_add(by, x, a * z);
        m[1][1][l] = M::mul_add(by, y, d);
        m[1][2][l] = M::mul_add(by, z, -(a * x));
        m[2][0][l] = M::mul_add(bz, x, -(a * y));
        m[2][1][l] = M::mul_add(bz, y, a * x);
        m[2][2][l] = M::mul_add(bz, z, d);
    }
    m
}

/// Rotation by the angles `angle` (rad) about the constant unit vector `axis`, as
/// [`crate::geometry::rotation_about_axis`]: one sine and cosine per lane.
#[inline(always)]
pub(crate) fn rotation_about_axis<M: MulAdd>(axis: &LaneVec, angle: &Lanes) -> LaneMat {
    let (s, c) = sin_cos_lanes(angle);
    let one_minus_c: Lanes = std::array::from_fn(|l| 1.0 - c[l]);
    rodrigues::<M>(axis, &c, &s, &one_minus_c)
}

/// Largest angle (rad) whose sine and cosine [`sin_cos_lanes`] computes by its own reduction: the
/// multiples of pi/2 up to 2^20 are exact with the 33-bit leading part of pi/2 (about 9,000 turns
/// of a rotary table); a lane beyond, or not finite, takes the library's `sin_cos`.
const REDUCED_ANGLE_LIMIT: f64 = 1.0e6;

/// Whether [`sin_cos_lanes`] reduces `x` itself (finite and within [`REDUCED_ANGLE_LIMIT`]).
#[inline(always)]
fn is_reduced(x: f64) -> bool {
    x.is_finite() && x.abs() <= REDUCED_ANGLE_LIMIT
}

/// `(sin x, cos x)` per lane, in vector instructions (the library's `sin_cos` is one call per
/// lane): `x = j pi/2 + r` with `j` the nearest integer and `|r| <= pi/4` (Cody-Waite reduction in
/// three parts of pi/2), the minimax polynomials of sine and cosine on `[-pi/4, pi/4]`, then the
/// quadrant `j mod 4` selects and signs them. Within 2 ulp of the correctly rounded values.
///
/// Source: the reduction constants and polynomial coefficients are those of fdlibm
/// (`e_rem_pio2.c`, `k_sin.c`, `k_cos.c`, Sun Microsystems 1993, used by most C libraries).
// the constants with the digits fdlibm publishes, so that they can be checked against it
#[allow(clippy::excessive_precision)]
#[inline(always)]
pub(crate) fn sin_cos_lanes(x: &Lanes) -> (Lanes, Lanes) {
    // pi/2 = PIO2_1 + PIO2_2 + PIO2_3 (+ below 1e-31), each part with at most 33 significant bits
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17e0;
    const PIO2_2: f64 = 6.077_100_506_303_965_976_6e-11;
    const PIO2_3: f64 = 2.022_266_248_711_166_455_8e-21;
    // 1.5 * 2^52: adding it rounds to the nearest integer, held in the low bits of the mantissa
    const ROUNDING: f64 = 6_755_399_441_055_744.0;
    const S: [f64; 6] = [
        -1.666_666_666_666_663_243_48e-1,
        8.333_333_333_322_489_461_24e-3,
        -1.984_126_982_985_794_931_34e-4,
        2.755_731_370_707_006_767_89e-6,
        -2.505_076_025_340_686_341_95e-8,
        1.589_690_995_211_550_102_21e-10,
    ];
    const C: [f64; 6] = [
        4.166_666_666_666_660_190_37e-2,
        -1.388_888_888_887_410_957_49e-3,
        2.480_158_728_947_672_941_78e-5,
        -2.755_731_435_139_066_330_35e-7,
        2.087_572_321_298_174_827_90e-9,
        -1.135_964_755_778_819_482_65e-11,
    ];
    let (mut sin, mut cos) = (splat(0.0), splat(0.0));
    let mut beyond = false;
    for l in 0..LANES {
        let shifted = x[l] * std::f64::consts::FRAC_2_PI + ROUNDING;
        let quadrant = shifted.to_bits();
        let j = shifted - ROUNDING;
        let r = ((x[l] - j * PIO2_1) - j * PIO2_2) - j * PIO2_3;
        let z = r * r;
        let s = r + r * z * (S[0] + z * (S[1] + z * (S[2] + z * (S[3] + z * (S[4] + z * S[5])))));
        let c = 1.0 - 0.5 * z + z * z * (C[0] + z * (C[1] + z * (C[2] + z * (C[3] + z * (C[4] + z * C[5])))));
        // quadrant j mod 4: (s, c), (c, -s), (-s, -c), (-c, s)
        let (sin_r, cos_r) = if quadrant & 1 == 0 { (s, c) } else { (c, s) };
        sin[l] = f64::from_bits(sin_r.to_bits() ^ ((quadrant & 2) << 62));
        cos[l] = f64::from_bits(cos_r.to_bits() ^ (((quadrant + 1) & 2) << 62));
        beyond |= !is_reduced(x[l]);
    }
    if beyond {
        for l in 0..LANES {
            if !is_reduced(x[l]) {
                (sin[l], cos[l]) = x[l].sin_cos();
            }
        }
    }
    (sin, cos)
}

/// `exp([eps]x)` per lane, as [`crate::geometry::rotation_exp`]: the Taylor series of its
/// coefficients in every lane (the machine-error case, `|eps| < 0.01 rad`), the closed form for a
/// lane beyond.
#[inline(always)]
pub(crate) fn rotation_exp_lanes<M: MulAdd>(eps: &LaneVec) -> LaneMat {
    const A: [f64; 3] = [1.0 / 6.0, 1.0 / 120.0, 1.0 / 5040.0];
    const B: [f64; 3] = [1.0 / 24.0, 1.0 / 720.0, 1.0 / 40320.0];
    let (mut d, mut a, mut b) = (splat(0.0), splat(0.0), splat(0.0));
    let mut large = false;
    for l in 0..LANES {
        let e = [eps[0][l], eps[1][l], eps[2][l]];
        let t2 = M::dot3(e, e);
        large |= t2 >= 1e-4;
        a[l] = M::mul_add(-t2, M::mul_add(-t2, M::mul_add(-t2, A[2], A[1]), A[0]), 1.0);
        b[l] = M::mul_add(-t2, M::mul_add(-t2, M::mul_add(-t2, B[2], B[1]), B[0]), 0.5);
        d[l] = M::mul_add(-b[l], t2, 1.0);
    }
    let mut m = rodrigues::<M>(eps, &d, &a, &b);
    if large {
        for l in 0..LANES {
            let e = vec_lane(eps, l);
            if e.norm_squared() >= 1e-4 {
                set_mat_lane(&mut m, l, &rotation_exp(&e));
            }
        }
    }
    m
}

/// The exact small transform `Trans(c) [exp([eps]x), e; 0 1] Trans(-c)` per lane, as
/// [`Pose::small_transform`].
#[inline(always)]
pub(crate) fn small_transform<M: MulAdd>(eps: &LaneVec, e: &LaneVec, c: &LaneVec) -> LanePose {
    let rotation = rotation_exp_lanes::<M>(eps);
    LanePose { rotation, translation: sub(&add(c, e), &mat_vec::<M>(&rotation, c)) }
}

/// Rotation vector (rad) of `r` per lane, as [`crate::geometry::rotation_log`] for angles below
/// pi: `w theta / sin(theta)` with `w` the skew part. Near the identity (every machine error,
/// `tan(theta) <= 1e-3`) `theta / sin(theta) = atan(x) / (x cos(theta))`, `x = tan(theta)`, by the
/// series `atan(x)/x = 1 - x^2/3 + x^4/5 - x^6/7 + x^8/9` (remainder below 1e-31); `atan2` for a
/// lane beyond.
#[inline(always)]
pub(crate) fn rotation_log_lanes<M: MulAdd>(r: &LaneMat) -> LaneVec {
    let mut w = [splat(0.0); 3];
    let mut beyond = false;
    for l in 0..LANES {
        let wx = (r[2][1][l] - r[1][2][l]) * 0.5;
        let wy = (r[0][2][l] - r[2][0][l]) * 0.5;
        let wz = (r[1][0][l] - r[0][1][l]) * 0.5;
        let sin_theta = M::dot3([wx, wy, wz], [wx, wy, wz]).sqrt();
        let cos_theta = 0.5 * ((r[0][0][l] + r[1][1][l] + r[2][2][l]) - 1.0);
        let x = sin_theta / cos_theta;
        let x2 = x * x;
        beyond |= !(cos_theta > 0.0 && x2 <= 1e-6);
        let series = M::mul_add(-x2, M::mul_add(-x2, M::mul_add(-x2, M::mul_add(-x2, 1.0 / 9.0, 1.0 / 7.0), 1.0 / 5.0), 1.0 / 3.0), 1.0);
        let scale = series / cos_theta;
        w[0][l] = wx * scale;
        w[1][l] = wy * scale;
        w[2][l] = wz * scale;
    }
    if beyond {
        for l in 0..LANES {
            let log = rotation_log(&mat_lane(r, l));
            for (wi, v) in w.iter_mut().zip(log.iter()) {
                wi[l] = *v;
            }
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lanes_of(f: impl Fn(usize) -> f64) -> Lanes {
        std::array::from_fn(f)
    }

    #[test]
    fn exp_and_log_per_lane_equal_the_scalar_forms_on_both_sides_of_the_series() {
        exp_and_log_against_the_scalar_forms::<Separate>();
        exp_and_log_against_the_scalar_forms::<Fused>();
    }

    fn exp_and_log_against_the_scalar_forms<M: MulAdd>() {
        // lane l: a rotation vector of norm 10^(l - 9) rad, from 1e-9 to 0.1 (the last lanes
        // beyond both series thresholds), against geometry::rotation_exp / rotation_log
        let eps: LaneVec = [
            lanes_of(|l| 0.3 * 10f64.powi(l as i32 - 9)),
            lanes_of(|l| -0.8 * 10f64.powi(l as i32 - 9)),
            lanes_of(|l| 0.52 * 10f64.powi(l as i32 - 9)),
        ];
        let r = rotation_exp_lanes::<M>(&eps);
        let back = rotation_log_lanes::<M>(&r);
        for l in 0..LANES {
            let e = vec_lane(&eps, l);
            assert!((mat_lane(&r, l) - rotation_exp(&e)).norm() <= 2e-16, "lane {l}");
            let want = rotation_log(&rotation_exp(&e));
            assert!((vec_lane(&back, l) - want).norm() <= 1e-15 * e.norm().max(1e-300) + 1e-300, "lane {l}");
        }
    }

    #[test]
    fn sine_and_cosine_per_lane_are_within_two_ulp_of_the_library() {
        // angles over the quadrant boundaries, near multiples of pi/2, small, large and beyond the
        // reduction limit (library fallback), and a non-finite lane
        let mut angles = vec![0.0, -0.0, 1e-300, 1e-9, -3e-5, 0.5, 1.0, 100.0, -2500.0, 7.0e5, 3.0e7, f64::NAN];
        for k in -40..=40 {
            let near = k as f64 * std::f64::consts::FRAC_PI_2;
            angles.extend([near, near + 1e-7, near - 3e-12, (k as f64).to_radians() * 37.0]);
        }
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..20_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            angles.push((state >> 11) as f64 / (1u64 << 53) as f64 * 200.0 - 100.0);
        }
        let ulp = |v: f64| if v == 0.0 { f64::MIN_POSITIVE } else { f64::EPSILON * v.abs() };
        for chunk in angles.chunks(LANES) {
            let x = lanes_of(|l| chunk[l.min(chunk.len() - 1)]);
            let (s, c) = sin_cos_lanes(&x);
            for l in 0..LANES {
                let (want_s, want_c) = x[l].sin_cos();
                if x[l].is_nan() {
                    assert!(s[l].is_nan() && c[l].is_nan());
                    continue;
                }
                // absolute error within 2 ulp of 1 (the values' scale), relative within 2 ulp away from zero
                for (got, want) in [(s[l], want_s), (c[l], want_c)] {
                    assert!((got - want).abs() <= 2.0 * ulp(want).max(f64::EPSILON * 0.5), "x = {:e}: {got:e} vs {want:e}", x[l]);
                }
            }
        }
    }

    #[test]
    fn pose_products_per_lane_equal_the_scalar_products() {
        pose_products_against_the_scalar_products::<Separate>();
        pose_products_against_the_scalar_products::<Fused>();
    }

    /// With separate or fused roundings, within 1e-15 of the scalar products (rotations) and 1e-13
    /// mm (translations of up to 500 mm).
    fn pose_products_against_the_scalar_products<M: MulAdd>() {
        let pose = |l: usize| {
            Pose::rotation_about_line(&Vec3::new(1.0, 2.0, 2.0 + l as f64).normalize(), &Vec3::new(5.0, -3.0, l as f64), 0.3 * l as f64)
        };
        let other = |l: usize| {
            Pose::small_transform(&Vec3::new(1e-4, -2e-5, l as f64 * 1e-5), &Vec3::new(0.01, 0.0, -0.02), &Vec3::new(100.0, 0.0, 50.0))
        };
        let mut a = LanePose::IDENTITY;
        let mut b = LanePose::IDENTITY;
        for l in 0..LANES {
            set_mat_lane(&mut a.rotation, l, &pose(l).rotation);
            set_mat_lane(&mut b.rotation, l, &other(l).rotation);
            for i in 0..3 {
                a.translation[i][l] = pose(l).translation[i];
                b.translation[i][l] = other(l).translation[i];
            }
        }
        let ab = a.then::<M>(&b);
        let x = splat_vec(&Vec3::new(250.0, -125.0, 400.0));
        for l in 0..LANES {
            let want = pose(l).then(&other(l));
            let got = ab.lane(l);
            assert!((got.rotation - want.rotation).norm() <= 1e-15, "lane {l}");
            assert!((got.translation - want.translation).norm() <= 1e-13, "lane {l}");
            let p = vec_lane(&ab.transform_point::<M>(&x), l);
            assert!((p - want.transform_point(&Vec3::new(250.0, -125.0, 400.0))).norm() <= 1e-12, "lane {l}");
        }
    }
}
