//! The five-axis configurations of Zhu 2008 appendix C: the counts 720 / 360 / 432 / 288 (144 and 96
//! per category), the ideal form-shaping functions of Table C.1, the travel of Table C.2, the space
//! utility finding of Figure C.1, and the poses and budgets of the configuration study.

use std::f64::consts::PI;
use trueaxis::budget::configurations::{
    all_sequences, five_axis_configurations, ideal_pose, practical_configurations, three_linear_sequences, Configuration, Pattern,
};
use trueaxis::budget::form_shaping::form_shaping;
use trueaxis::budget::ranking::{study, study_poses, StudyOptions};
use trueaxis::budget::spec::KindValues;
use trueaxis::budget::travel::{linear_positions, required_travel, space_utility};
use trueaxis::geometry::Vec3;
use trueaxis::model::{nominal_chain, Setup};

#[test]
fn counts_of_the_appendix() {
    assert_eq!(all_sequences().len(), 720);
    assert_eq!(three_linear_sequences().len(), 360);
    let practical = practical_configurations();
    assert_eq!(practical.len(), 432);
    let five = five_axis_configurations();
    assert_eq!(five.len(), 288);
    for pattern in Pattern::PRACTICAL {
        assert_eq!(practical.iter().filter(|c| c.pattern() == pattern).count(), 144, "{pattern:?}");
        assert_eq!(five.iter().filter(|c| c.pattern() == pattern).count(), 96, "{pattern:?}");
    }
    // 5! orders of one set of five axes: the appendix's "120 per category"
    let one_set = three_linear_sequences().into_iter().filter(|s| s.contains(&'A') && s.contains(&'B')).count();
    assert_eq!(one_set, 120);
    // four degrees of freedom exactly when C turns about the tool axis (next to the tool) or turns
    // the linear axes in their XY plane (between the other rotary axis and the linear axes)
    for c in practical {
        let s = c.sequence;
        let four = s[4] == 'C' || (c.pattern() == Pattern::RotaryAtWorkpiece && s[1] == 'C');
        assert_eq!(c.degrees_of_freedom() == 4, four, "{}", c.axes());
        assert_eq!(c.degrees_of_freedom().max(4), c.degrees_of_freedom());
    }
}

/// Table C.1 as printed, `(l, m, n, u, v, w)` at `(x, y, z, a, b, c, p)`; the rows BCXYZ, BXYZA and
/// XYZBC carry the corrections of their printing errors (noted per row).
#[allow(clippy::too_many_arguments)] // the seven symbols of the table
fn table_c1(code: &str, x: f64, y: f64, z: f64, a: f64, b: f64, c: f64, p: f64) -> [f64; 6] {
    let (sa, ca, sb, cb, sc, cc) = (a.sin(), a.cos(), b.sin(), b.cos(), c.sin(), c.cos());
    match code {
        "ABXYZ" => [
            sb * p + sb * z + cb * x,
            -sa * cb * p - sa * cb * z + ca * y + sa * sb * x,
            ca * cb * p + ca * cb * z + sa * y - ca * sb * x,
            sb,
            -sa * cb,
            ca * cb,
        ],
        "ACXYZ" => {
            [-sc * y + cc * x, -sa * p - sa * z + ca * cc * y + ca * sc * x, ca * p + ca * z + sa * cc * y + sa * sc * x, 0.0, -sa, ca]
        }
        "BAXYZ" => [
            ca * sb * p + ca * sb * z + sa * sb * y + cb * x,
            -sa * p - sa * z + ca * y,
            ca * cb * p + ca * cb * z + sa * cb * y - sb * x,
            ca * sb,
            -sa,
            ca * cb,
        ],
        // printed n ends in "- sin(b) sin(c) x": the rotation gives - sin(b) cos(c) x
        "BCXYZ" => [sb * p + sb * z - cb * sc * y + cb * cc * x, cc * y + sc * x, cb * p + cb * z + sb * sc * y - sb * cc * x, sb, 0.0, cb],
        "CAXYZ" => [
            sc * sa * p + sa * sc * z - ca * sc * y + cc * x,
            -cc * sa * p - sa * cc * z + ca * cc * y + sc * x,
            ca * p + ca * z + sa * y,
            sa * sc,
            -sa * cc,
            ca,
        ],
        "CBXYZ" => [
            sb * cc * p + cc * sb * z - sc * y + cc * cb * x,
            sb * sc * p + sc * sb * z + cc * y + sc * cb * x,
            cb * p + cb * z - sb * x,
            cc * sb,
            sc * sb,
            cb,
        ],
        "AXYZB" => [sb * p + x, -sa * cb * p - sa * z + ca * y, ca * cb * p + ca * z + sa * y, sb, -sa * cb, ca * cb],
        "AXYZC" => [x, -sa * p - sa * z + ca * y, ca * p + ca * z + sa * y, 0.0, -sa, ca],
        // printed n ends in "+ sin(b) x": the rotation gives - sin(b) x
        "BXYZA" => [ca * sb * p + sb * z + cb * x, -sa * p + y, ca * cb * p + cb * z - sb * x, ca * sb, -sa, ca * cb],
        "BXYZC" => [sb * p + sb * z + cb * x, y, cb * p + cb * z - sb * x, sb, 0.0, cb],
        "CXYZA" => [sc * sa * p - sc * y + cc * x, -cc * sa * p + cc * y + sc * x, ca * p + z, sa * sc, -sa * cc, ca],
        "CXYZB" => [sb * cc * p - sc * y + cc * x, sb * sc * p + cc * y + sc * x, cb * p + z, cc * sb, sc * sb, cb],
        "XYZAB" => [sb * p + x, -sa * cb * p + y, ca * cb * p + z, sb, -sa * cb, ca * cb],
        "XYZAC" => [x, -sa * p + y, ca * p + z, 0.0, -sa, ca],
        "XYZBA" => [ca * sb * p + x, -sa * p + y, ca * cb * p + z, ca * sb, -sa, ca * cb],
        // printed position "l = x, m = -sin(a) p + y, n = z" uses a, which XYZBC does not have
        "XYZBC" => [sb * p + x, y, cb * p + z, sb, 0.0, cb],
        "XYZCA" => [sc * sa * p + x, -cc * sa * p + y, ca * p + z, sa * sc, -sa * cc, ca],
        "XYZCB" => [sb * cc * p + x, sb * sc * p + y, cb * p + z, cc * sb, sc * sb, cb],
        _ => unreachable!(),
    }
}

#[test]
fn form_shaping_functions_equal_table_c1() {
    let rows = [
        "ABXYZ", "ACXYZ", "BAXYZ", "BCXYZ", "CAXYZ", "CBXYZ", "AXYZB", "AXYZC", "BXYZA", "BXYZC", "CXYZA", "CXYZB", "XYZAB", "XYZAC",
        "XYZBA", "XYZBC", "XYZCA", "XYZCB",
    ];
    let values = [(12.0, -7.0, 31.0, 0.4, -1.1, 2.3, 150.0), (-40.0, 5.0, -3.0, -2.0, 0.7, -0.2, 80.0)];
    for code in rows {
        let sequence: Vec<char> = code.chars().collect();
        let f = form_shaping(&sequence);
        for &(x, y, z, a, b, c, p) in &values {
            let expected = table_c1(code, x, y, z, a, b, c, p);
            let angle = |k: char| match k {
                'a' => a,
                'b' => b,
                _ => c,
            };
            let var = |k: char| match k {
                'x' => x,
                'y' => y,
                'z' => z,
                _ => p,
            };
            let mut q = [0.0; 5];
            for (i, ch) in sequence.iter().enumerate() {
                q[i] = match ch {
                    'X' => x,
                    'Y' => y,
                    'Z' => z,
                    'A' => a,
                    'B' => b,
                    _ => c,
                };
            }
            let (position, direction) = ideal_pose(&sequence, &q, p);
            for k in 0..3 {
                let symbolic = f.position[k].evaluate(angle, var);
                assert!((symbolic - expected[k]).abs() < 1e-9, "{code} position {k}: {} = {symbolic} vs {}", f.position[k], expected[k]);
                assert!((position[k] - expected[k]).abs() < 1e-9, "{code} chain position {k}");
                let symbolic = f.orientation[k].evaluate(angle, var);
                assert!((symbolic - expected[3 + k]).abs() < 1e-12, "{code} orientation {k}: {}", f.orientation[k]);
                assert!((direction[k] - expected[3 + k]).abs() < 1e-12);
            }
        }
    }
    // printed like the appendix
    assert_eq!(form_shaping(&['A', 'B', 'X', 'Y', 'Z']).position[0].to_string(), "sin(b)*p + sin(b)*z + cos(b)*x");
    assert_eq!(form_shaping(&['X', 'Y', 'Z', 'A', 'B']).position[2].to_string(), "cos(a)*cos(b)*p + z");
    // four axes: XYZAC has no c
    assert!(!form_shaping(&['X', 'Y', 'Z', 'A', 'C']).position.iter().any(|e| e.letters().contains(&'c')));
}

#[test]
fn travel_equals_table_c2() {
    let (l, m, n, p): (f64, f64, f64, f64) = (100.0, 80.0, 60.0, 150.0);
    let r3 = (l * l + m * m + n * n).sqrt();
    let h = |a: f64, b: f64| a.hypot(b);
    // Table C.2; the four split entries the appendix prints as sqrt(p^2 + ...) are p + sqrt(...)
    let rows: [(&str, [f64; 3]); 12] = [
        ("ABXYZ", [r3, h(m, n), p + r3]),
        ("BAXYZ", [h(l, n), r3, p + r3]),
        ("CAXYZ", [h(l, m), r3, p + r3]),
        ("CBXYZ", [r3, h(l, m), p + r3]),
        ("AXYZB", [p + l, h(m, n), p + h(m, n)]),
        ("BXYZA", [h(l, n), p + m, p + h(l, n)]),
        ("CXYZA", [h(l, m), p + h(l, m), p + n]),
        ("CXYZB", [p + h(l, m), h(l, m), p + n]),
        ("XYZAB", [p + l, p + m, p + n]),
        ("XYZBA", [p + l, p + m, p + n]),
        ("XYZCA", [p + l, p + m, p + n]),
        ("XYZCB", [p + l, p + m, p + n]),
    ];
    for (code, expected) in rows {
        let s: Vec<char> = code.chars().collect();
        let sequence = [s[0], s[1], s[2], s[3], s[4]];
        let travel = required_travel(&sequence, [l, m, n], p).unwrap();
        for k in 0..3 {
            assert!((travel[k] - expected[k]).abs() <= 1e-9 * expected[k], "{code} axis {k}: {} vs {}", travel[k], expected[k]);
        }
    }
    // the corrected AXYZB Z entry is reached: b = 180 deg, a turning (m, n) onto +z
    let a = -(m / n).atan();
    let lin = linear_positions(&['A', 'X', 'Y', 'Z', 'B'], [a, PI], &Vec3::new(l, m, n), p).unwrap();
    assert!((lin.z - (p + h(m, n))).abs() < 1e-9, "{lin:?}");
    assert!(lin.z > (p * p + m * m + n * n).sqrt() + 10.0);
}

#[test]
fn space_utility_favours_table_tables_for_small_parts_and_heads_for_large_ones() {
    let utility = |code: [char; 5], ratio: f64| {
        let p = 100.0;
        let part = [ratio * p; 3];
        space_utility(part, required_travel(&code, part, p).unwrap())
    };
    let table = ['A', 'B', 'X', 'Y', 'Z'];
    let head = ['X', 'Y', 'Z', 'A', 'B'];
    assert!(utility(table, 0.2) > utility(head, 0.2));
    assert!(utility(table, 5.0) < utility(head, 5.0));
    // the large-part limit of the head-head category: every travel p + l, utility -> 1
    assert!(utility(head, 1000.0) > 0.99);
}

#[test]
fn study_poses_put_the_tool_on_the_part_and_budgets_rank() {
    let options = StudyOptions { part: [100.0, 80.0, 60.0], tool_length: 150.0, tolerances: KindValues::DEFAULT, nodes: 2, tilt_deg: 30.0 };
    let picked: Vec<Configuration> = five_axis_configurations()
        .into_iter()
        .filter(|c| ["CAXYZ", "ABXYZ", "CXYZA", "BXYZA", "XYZCA", "XYZAB"].contains(&c.axes().as_str()) && (c.bed == 2 || c.bed == 3))
        .collect();
    assert_eq!(picked.len(), 12);
    for c in &picked {
        let travel = required_travel(&c.sequence, options.part, options.tool_length).unwrap();
        let m = c.machine(travel.map(|t| t + 1e-6), options.tool_length);
        let poses = study_poses(c, &m, &options);
        assert_eq!(poses.len() / m.axis_count(), 5 * 8, "{}", c.axes());
        let setup = Setup::of_machine(&m);
        for (i, user) in poses.chunks(m.axis_count()).enumerate() {
            m.check_range(user).unwrap_or_else(|e| panic!("{}: {e}", c.axes()));
            let mut q = vec![0.0; m.axis_count()];
            m.pose_to_internal(user, &mut q);
            let tool = nominal_chain(&m, m.tool_chain(), &q, None);
            let work = nominal_chain(&m, m.work_chain(), &q, None);
            let relative = work.rotation.transpose() * (tool.transform_point(&setup.tool_point) - work.translation);
            let corner = i % 8;
            let expected = Vec3::new(100.0 * (corner & 1) as f64, 80.0 * (corner >> 1 & 1) as f64, 60.0 * (corner >> 2 & 1) as f64);
            assert!((relative - expected).norm() < 1e-9, "{} pose {i}: {relative:?} vs {expected:?}", c.axes());
            let direction = work.rotation.transpose() * tool.rotation * Vec3::z();
            let tilt = options.tilt_deg.to_radians();
            assert!((direction.z - if i < 8 { 1.0 } else { tilt.cos() }).abs() < 1e-9, "{} pose {i}", c.axes());
        }
    }
    let ranked = study(&picked, &options).unwrap();
    assert_eq!(ranked.len(), 12);
    for pair in ranked.windows(2) {
        assert!(pair[0].rss_rms <= pair[1].rss_rms);
    }
    for r in &ranked {
        assert!(r.rss_rms > 0.0 && r.rss_max >= r.rss_rms && r.worst_max >= r.rss_max, "{}", r.configuration.axes());
        assert!((r.kind_shares.iter().sum::<f64>() - 100.0).abs() < 1e-9);
    }
}
