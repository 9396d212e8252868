//! Thermal FE and modal analysis against closed forms: the fin of Zhu 2008 Table 3.1 (analytic time
//! constants of a fin with insulated ends, and the exact discrete eigenvalues of 22 linear
//! elements), the sparse shift-invert Lanczos against the dense solver, 3D against 1D, modal
//! superposition against time stepping, and the mode weights.

use std::f64::consts::PI;
use std::path::Path;
use trueaxis::thermal::assembly::{assemble, Boundary, Material, Section, ThermalProblem, ThermalSystem};
use trueaxis::thermal::mesh::StructuredMesh;
use trueaxis::thermal::model_file::load_model;
use trueaxis::thermal::response::{modal_history, step_response, time_stepping, LoadHistory};
use trueaxis::thermal::{dominant_modes, modal_analysis, mode_weights, ModalOptions, SpectrumMethod};

// Zhu 2008 Table 3.1
const K: f64 = 60.5;
const RHO: f64 = 7800.0;
const CP: f64 = 434.0;
const L: f64 = 1.0;
const AREA: f64 = 0.0314;
const H: f64 = 20.0;

fn perimeter() -> f64 {
    2.0 * PI * 0.1
}

/// Continuum fin with insulated ends: tau_n = 1 / (a (n pi/L)^2 + h P / (rho c_p A)) (s).
fn analytic_tau(n: usize) -> f64 {
    let a = K / (RHO * CP);
    1.0 / (a * (n as f64 * PI / L).powi(2) + H * perimeter() / (RHO * CP * AREA))
}

fn fin(elements: usize) -> ThermalProblem {
    ThermalProblem {
        mesh: StructuredMesh::bar(L, elements).unwrap(),
        material: Material { conductivity_w_mk: K, density_kg_m3: RHO, specific_heat_j_kgk: CP },
        section: Section::Bar { area_m2: AREA, perimeter_m: perimeter() },
        lateral_convection_w_m2k: H,
        boundaries: vec![[Boundary::Insulated, Boundary::Insulated]],
        fluxes: vec![(0, 100.0)],
    }
}

#[test]
fn fin_of_table_3_1_matches_the_analytic_time_constants() {
    let model = load_model(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/thermal/fin.toml")).unwrap();
    assert_eq!(model.system.node_count(), 23);
    let modes = modal_analysis(&model.system, &ModalOptions::default()).unwrap();
    // (1) the exact eigenvalues of 22 equal linear elements with consistent capacity: the discrete
    // modes are cos(n pi x_j / L), lambda_n = a (6/h^2)(1 - cos t)/(2 + cos t) + h P/(rho c A), t = n pi h/L
    let a = K / (RHO * CP);
    let he = L / 22.0;
    for n in 0..23 {
        let t = n as f64 * PI * he / L;
        let lambda = a * 6.0 / (he * he) * (1.0 - t.cos()) / (2.0 + t.cos()) + H * perimeter() / (RHO * CP * AREA);
        assert!((modes.lambda[n] - lambda).abs() < 1e-10 * lambda, "mode {n}: {} vs {lambda}", modes.lambda[n]);
    }
    // (2) the continuum time constants: tau_0 = 140.98 min, tau_1 = 56.57, tau_2 = 20.23, tau_3 = 9.77;
    // 22 elements are short of them by 0.0 %, 0.10 %, 0.58 % and 1.41 % (the discrete closed form above)
    let expected_min = [140.98, 56.57, 20.23, 9.77];
    for (n, (want_min, tol)) in expected_min.iter().zip([1e-9, 0.0011, 0.0060, 0.0145]).enumerate() {
        let tau = modes.tau_s(n);
        assert!((analytic_tau(n) / 60.0 - want_min).abs() < 0.01, "closed form {n}");
        assert!((tau - analytic_tau(n)).abs() < tol * analytic_tau(n), "tau_{n} = {} s vs {} s", tau, analytic_tau(n));
    }
    // (3) refinement: 440 elements agree with the continuum to 1e-4 on the first four
    let fine = modal_analysis(&assemble(&fin(440)).unwrap(), &ModalOptions { count: Some(4), ..Default::default() }).unwrap();
    for n in 0..4 {
        assert!((fine.tau_s(n) - analytic_tau(n)).abs() < 1e-4 * analytic_tau(n), "fine tau_{n}");
    }
}

#[test]
fn sparse_lanczos_agrees_with_dense_on_the_fin_and_modes_are_c_orthonormal() {
    let sys = assemble(&fin(600)).unwrap();
    let dense = modal_analysis(&sys, &ModalOptions { count: Some(8), method: SpectrumMethod::Dense, ..Default::default() }).unwrap();
    let sparse = modal_analysis(&sys, &ModalOptions { count: Some(8), method: SpectrumMethod::Lanczos, ..Default::default() }).unwrap();
    for i in 0..8 {
        assert!((dense.lambda[i] - sparse.lambda[i]).abs() < 1e-9 * dense.lambda[i]);
        // same shape (signs made deterministic)
        let diff: f64 = (0..601).map(|r| (dense.shape(r, i) - sparse.shape(r, i)).powi(2)).sum::<f64>().sqrt();
        let norm: f64 = (0..601).map(|r| dense.shape(r, i).powi(2)).sum::<f64>().sqrt();
        assert!(diff < 1e-6 * norm, "shape {i}");
    }
}

#[test]
fn a_block_insulated_on_its_sides_has_the_modes_of_a_bar_with_convective_ends() {
    // 3D block 0.1 x 0.08 x 0.5 m, convection 30 and 5 W/m^2/K at z = 0 and z = 0.5 m: modes uniform
    // in x, y are those of a 1D bar of area 0.008 m^2 with the same ends (same z discretisation)
    let material = Material { conductivity_w_mk: 45.0, density_kg_m3: 7850.0, specific_heat_j_kgk: 460.0 };
    let ends = [Boundary::Convection(30.0), Boundary::Convection(5.0)];
    let block = ThermalProblem {
        mesh: StructuredMesh::new(vec![3, 2, 10], vec![0.1, 0.08, 0.5]).unwrap(),
        material,
        section: Section::Solid,
        lateral_convection_w_m2k: 0.0,
        boundaries: vec![[Boundary::Insulated; 2], [Boundary::Insulated; 2], ends],
        fluxes: vec![],
    };
    let bar = ThermalProblem {
        mesh: StructuredMesh::bar(0.5, 10).unwrap(),
        material,
        section: Section::Bar { area_m2: 0.008, perimeter_m: 0.36 },
        lateral_convection_w_m2k: 0.0,
        boundaries: vec![ends],
        fluxes: vec![],
    };
    let m3 = modal_analysis(&assemble(&block).unwrap(), &ModalOptions::default()).unwrap();
    let m1 = modal_analysis(&assemble(&bar).unwrap(), &ModalOptions::default()).unwrap();
    // the first bar mode is the first block mode; every bar eigenvalue is a block eigenvalue
    assert!((m3.lambda[0] - m1.lambda[0]).abs() < 1e-10 * m1.lambda[0]);
    for l in &m1.lambda {
        assert!(m3.lambda.iter().any(|x| (x - l).abs() < 1e-9 * l), "bar eigenvalue {l} missing in 3D");
    }
    // first mode: slowest heat loss, tau > a single-lump estimate rho c V / (h A) with both ends
    let lump = 7850.0 * 460.0 * 0.1 * 0.08 * 0.5 / ((30.0 + 5.0) * 0.008);
    assert!(m3.tau_s(0) > lump && m3.tau_s(0) < 1.5 * lump);
}

#[test]
fn modal_superposition_equals_time_stepping_and_reaches_the_steady_state() {
    let sys = assemble(&fin(22)).unwrap();
    let modes = modal_analysis(&sys, &ModalOptions::default()).unwrap();
    let nodes = [0, 11, 22];
    // warm-up 2 h at the full flux, 1 h at half, 2 h off, sampled every 5 min
    let times: Vec<f64> = (0..=60).map(|k| 300.0 * k as f64).collect();
    let inputs: Vec<Vec<f64>> = times
        .iter()
        .map(|t| {
            vec![if *t < 7200.0 {
                1.0
            } else if *t < 10800.0 {
                0.5
            } else {
                0.0
            }]
        })
        .collect();
    let history = LoadHistory { loads: vec![sys.load.clone()], times_s: times.clone(), inputs };
    let modal = modal_history(&modes, &history, &nodes).unwrap();
    let stepped = time_stepping(&sys, &history, &nodes, 0.5, 20).unwrap();
    let peak = modal.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
    for (a, b) in modal.iter().flatten().zip(stepped.iter().flatten()) {
        assert!((a - b).abs() < 1e-4 * peak, "{a} vs {b}");
    }
    // the step response at t -> infinity is the steady state K^-1 Q: total heat balance
    // Q = h P L * mean rise (insulated ends), so the C-weighted mean rise is 100 W / (20 * P * 1 m)
    let long = step_response(&modes, &sys.load, &[1e7], &(0..23).collect::<Vec<_>>());
    let mean = (long[0][0] + long[0][22]) / 44.0 + long[0][1..22].iter().sum::<f64>() / 22.0;
    assert!((mean - 100.0 / (H * perimeter())).abs() < 1e-9 * mean, "{mean}");
    // first interval of the history equals the step response
    let step = step_response(&modes, &sys.load, &[300.0], &nodes);
    for (a, b) in step[0].iter().zip(&modal[1]) {
        assert!((a - b).abs() < 1e-12 * peak);
    }
}

#[test]
fn mode_weights_of_the_fin_follow_from_the_closed_form() {
    let sys = assemble(&fin(440)).unwrap();
    let modes = modal_analysis(&sys, &ModalOptions { count: Some(12), ..Default::default() }).unwrap();
    let w = mode_weights(&modes, &sys.load);
    // continuum: phi_0 = 1/sqrt(rho c A L), phi_n(0) = sqrt(2/(rho c A L)), so w_n = Q phi_n(0) tau_n
    let m = RHO * CP * AREA * L;
    for (n, mw) in w.iter().enumerate().take(5) {
        let phi0 = if n == 0 { 1.0 / m.sqrt() } else { (2.0 / m).sqrt() };
        let want = 100.0 * phi0 * analytic_tau(n);
        assert!((mw.weight - want).abs() < 2e-3 * want, "w_{n}: {} vs {want}", mw.weight);
    }
    // tau_0 : sqrt2 tau_1 : sqrt2 tau_2 ... -> the first modes reach 90 % of the weight of 12 modes
    let kept = dominant_modes(&w, 0.9);
    let share: f64 = kept.iter().map(|&i| w[i].share).sum();
    assert!(share >= 0.9 && share - w[*kept.last().unwrap()].share < 0.9);
    assert_eq!(kept[0], 0);
}

#[test]
fn lanczos_equals_dense_on_a_3d_block_of_2184_nodes() {
    // 12 x 11 x 13 cells of steel, four convective faces, the lowest 20 of 2184 modes; the sparse
    // factor ordered by nested dissection (mesh coordinates) and by minimum degree (none)
    let problem = ThermalProblem {
        mesh: StructuredMesh::new(vec![12, 11, 13], vec![0.36, 0.22, 0.52]).unwrap(),
        material: Material { conductivity_w_mk: 45.0, density_kg_m3: 7850.0, specific_heat_j_kgk: 460.0 },
        section: Section::Solid,
        lateral_convection_w_m2k: 0.0,
        boundaries: vec![
            [Boundary::Convection(25.0), Boundary::Insulated],
            [Boundary::Insulated, Boundary::Convection(8.0)],
            [Boundary::Convection(12.0), Boundary::Convection(40.0)],
        ],
        fluxes: vec![(0, 50.0)],
    };
    let sys = assemble(&problem).unwrap();
    assert_eq!(sys.node_count(), 2184);
    let dense = modal_analysis(&sys, &ModalOptions { count: None, method: SpectrumMethod::Dense, ..Default::default() }).unwrap();
    let nested = modal_analysis(&sys, &ModalOptions { count: Some(20), method: SpectrumMethod::Lanczos, ..Default::default() }).unwrap();
    let without = ThermalSystem { coordinates: None, ..sys.clone() };
    let minimum_degree =
        modal_analysis(&without, &ModalOptions { count: Some(20), method: SpectrumMethod::Lanczos, ..Default::default() }).unwrap();
    let n = sys.node_count();
    for sparse in [&nested, &minimum_degree] {
        for i in 0..20 {
            assert!((sparse.lambda[i] - dense.lambda[i]).abs() < 1e-9 * dense.lambda[i], "lambda_{i}");
            // C-orthonormal shapes with deterministic signs: the same vectors where the eigenvalue
            // is simple (relative gap to its neighbours above 1e-6)
            let gap = [i.checked_sub(1), Some(i + 1)]
                .iter()
                .flatten()
                .map(|&j| (dense.lambda[j] - dense.lambda[i]).abs() / dense.lambda[i])
                .fold(f64::INFINITY, f64::min);
            if gap > 1e-6 {
                let diff = (0..n).map(|r| (sparse.shape(r, i) - dense.shape(r, i)).powi(2)).sum::<f64>().sqrt();
                let norm = (0..n).map(|r| dense.shape(r, i).powi(2)).sum::<f64>().sqrt();
                assert!(diff < 1e-6 * norm, "shape {i}: {diff} vs {norm}");
            }
        }
    }
}
