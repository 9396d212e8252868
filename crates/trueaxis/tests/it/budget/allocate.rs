//! Cost-optimal tolerance allocation (Zhu 2008 eqs. B.5-B.8) against the closed-form Lagrange
//! solutions of equal costs under one root-sum-square constraint (with and without an active lower
//! limit) and one worst-case constraint, the KKT conditions on whole work volumes, determinism for
//! a seed, and infeasible lower limits.

use trueaxis::budget::allocate::{allocate, AllocationOptions, Stack, Target};
use trueaxis::budget::cost::CostModel;
use trueaxis::budget::global::GeneticOptions;
use trueaxis::budget::poses::volume_grid;
use trueaxis::budget::sensitivity::{sensitivity, Sensitivity};
use trueaxis::budget::spec::{BudgetSpec, KindValues};
use trueaxis::budget::stackup::stack_up;
use trueaxis::machine::Machine;
use trueaxis::model::{Frame, Setup};

fn machine(name: &str) -> Machine {
    Machine::load(format!("{}/../../examples/machines/{name}.toml", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn one_pose(m: &Machine, user: &[f64]) -> (BudgetSpec, Sensitivity) {
    let spec = BudgetSpec::standard(m, KindValues::DEFAULT);
    let mut q = vec![0.0; m.axis_count()];
    m.pose_to_internal(user, &mut q);
    let s = sensitivity(m, &spec.components, &q, &Setup::of_machine(m), Frame::Workpiece);
    (spec, s)
}

/// The standard budget of a five-axis example machine and its sensitivity over a 3 x 3 x 3 grid of
/// the travel with the rotary axes at `rotary` (deg).
fn volume(name: &str, rotary: &[f64]) -> (BudgetSpec, Sensitivity) {
    let m = machine(name);
    let spec = BudgetSpec::standard(&m, KindValues::DEFAULT);
    let user = volume_grid(&m, 3, rotary).unwrap();
    let mut q = vec![0.0; user.len()];
    for (u, x) in user.chunks(m.axis_count()).zip(q.chunks_mut(m.axis_count())) {
        m.pose_to_internal(u, x);
    }
    let s = sensitivity(&m, &spec.components, &q, &Setup::of_machine(&m), Frame::Workpiece);
    (spec, s)
}

fn options(stack: Stack, target: Target) -> AllocationOptions {
    AllocationOptions { stack, target, genetic: GeneticOptions { generations: 200, ..GeneticOptions::default() } }
}

/// Homogenised gain `|SE_:j| x scale_j` (um per um/m or urad) of each component at pose 0.
fn gains(spec: &BudgetSpec, s: &Sensitivity) -> Vec<f64> {
    (0..spec.components.len()).map(|j| s.column(0, j).norm() * spec.components[j].scale()).collect()
}

#[test]
fn equal_costs_under_one_rss_constraint_give_the_lagrange_solution() {
    // minimise sum 1/e_j^k subject to sum g_j^2 e_j^2 <= V^2:
    // e_j = V g_j^(-2/(k+2)) / sqrt(sum_i g_i^(2k/(k+2)))
    let m = machine("c600u");
    let (mut spec, s) = one_pose(&m, &[120.0, -80.0, -150.0, 30.0, 45.0]);
    for k in [1.0, 2.0, 3.0] {
        spec.cost = CostModel::uniform(&spec.components, 1.0, k, [0.0; 3]);
        let v = 8.0;
        let a = allocate(&spec, &s, &options(Stack::Rss, Target::Total(v))).unwrap();
        let g = gains(&spec, &s);
        let sum: f64 = g.iter().filter(|x| **x > 1e-9).map(|x| x.powf(2.0 * k / (k + 2.0))).sum();
        for (j, &gain) in g.iter().enumerate() {
            if !a.allocated[j] {
                assert!(gain < 1e-9, "{} has an effect but was not allocated", spec.components[j].id);
                continue;
            }
            let expected = v * gain.powf(-2.0 / (k + 2.0)) / sum.sqrt() * spec.components[j].scale();
            assert!(
                (a.tolerances[j] - expected).abs() <= 1e-6 * expected,
                "k {k} {}: {} vs {expected}",
                spec.components[j].id,
                a.tolerances[j]
            );
        }
        let cost: f64 = g.iter().filter(|x| **x > 1e-9).map(|x| (v * x.powf(-2.0 / (k + 2.0)) / sum.sqrt()).powf(-k)).sum();
        assert!((a.cost - cost).abs() <= 1e-8 * cost);
        assert!(a.kkt_residual < 1e-6, "KKT residual {}", a.kkt_residual);
        assert_eq!(a.active.len(), 1);
        assert!(a.active[0].multiplier > 0.0 && a.active[0].marginal_cost_per_um < 0.0);
        assert!((a.achieved[0] - v).abs() < 1e-6 * v);
        assert!(a.global_cost >= a.cost);
    }
}

#[test]
fn an_active_lower_limit_takes_its_share_first() {
    let m = machine("vmc3");
    let (mut spec, s) = one_pose(&m, &[200.0, -100.0, -300.0]);
    let k = 2.0;
    let v = 5.0;
    let g = gains(&spec, &s);
    let sum: f64 = g.iter().filter(|x| **x > 1e-9).map(|x| x.powf(2.0 * k / (k + 2.0))).sum();
    let free = |j: usize| v * g[j].powf(-2.0 / (k + 2.0)) / sum.sqrt();
    // the component with the largest gain gets the tightest tolerance: give it a lower limit above it
    let tight = (0..g.len()).max_by(|a, b| g[*a].total_cmp(&g[*b])).unwrap();
    spec.cost = CostModel::uniform(&spec.components, 1.0, k, [0.0; 3]);
    let lower = 2.0 * free(tight);
    spec.cost.terms[tight].lower = lower * spec.components[tight].scale();
    let a = allocate(&spec, &s, &options(Stack::Rss, Target::Total(v))).unwrap();
    assert_eq!(a.at_lower, vec![tight]);
    let rest = (v * v - (g[tight] * lower).powi(2)).sqrt();
    let sum_rest: f64 = (0..g.len()).filter(|&j| j != tight && g[j] > 1e-9).map(|j| g[j].powf(2.0 * k / (k + 2.0))).sum();
    for j in (0..g.len()).filter(|&j| g[j] > 1e-9) {
        let expected = if j == tight { lower } else { rest * g[j].powf(-2.0 / (k + 2.0)) / sum_rest.sqrt() } * spec.components[j].scale();
        assert!((a.tolerances[j] - expected).abs() <= 1e-6 * expected, "{}: {} vs {expected}", spec.components[j].id, a.tolerances[j]);
    }
    assert!(a.kkt_residual < 1e-6);
}

#[test]
fn equal_costs_under_one_worst_case_constraint_give_the_lagrange_solution() {
    // one direction, worst case: minimise sum 1/e_j^k subject to sum g_j e_j <= V:
    // e_j = V g_j^(-1/(k+1)) / sum_i g_i^(k/(k+1)); the components of vmc3 that move the tool
    // point along x only, with the y and z targets out of reach.
    let m = machine("vmc3");
    let (mut spec, s) = one_pose(&m, &[150.0, 60.0, -200.0]);
    let k = 2.0;
    spec.cost = CostModel::uniform(&spec.components, 1.0, k, [0.0; 3]);
    // keep the components that act along x only
    let along_x: Vec<usize> = (0..spec.components.len())
        .filter(|&j| s.column(0, j).x.abs() > 1e-9 && s.column(0, j).y.abs() < 1e-12 && s.column(0, j).z.abs() < 1e-12)
        .collect();
    assert!(along_x.len() >= 4, "{along_x:?}");
    let spec = BudgetSpec {
        components: along_x.iter().map(|&j| spec.components[j].clone()).collect(),
        tolerances: along_x.iter().map(|&j| spec.tolerances[j]).collect(),
        cost: CostModel { terms: along_x.iter().map(|&j| spec.cost.terms[j]).collect() },
    };
    let s = sensitivity(&m, &spec.components, &[150.0, 60.0, -200.0], &Setup::of_machine(&m), Frame::Workpiece);
    let v = 6.0;
    let a = allocate(&spec, &s, &options(Stack::WorstCase, Target::PerDirection([v, 1e9, 1e9]))).unwrap();
    let g: Vec<f64> = (0..spec.components.len()).map(|j| s.column(0, j).x.abs() * spec.components[j].scale()).collect();
    let sum: f64 = g.iter().map(|x| x.powf(k / (k + 1.0))).sum();
    for (j, gain) in g.iter().enumerate() {
        let expected = v * gain.powf(-1.0 / (k + 1.0)) / sum * spec.components[j].scale();
        assert!((a.tolerances[j] - expected).abs() <= 1e-6 * expected, "{}: {} vs {expected}", spec.components[j].id, a.tolerances[j]);
    }
    assert!(a.kkt_residual < 1e-6);
}

#[test]
fn volume_allocations_satisfy_kkt_and_every_pose() {
    let (spec, s) = volume("c600u", &[30.0, 90.0]);
    for (stack, target) in [
        (Stack::Rss, Target::Total(10.0)),
        (Stack::Rss, Target::PerDirection([6.0, 8.0, 10.0])),
        (Stack::WorstCase, Target::PerDirection([20.0, 20.0, 15.0])),
        (Stack::WorstCase, Target::Total(25.0)),
    ] {
        let a = allocate(&spec, &s, &options(stack, target)).unwrap();
        assert!(a.kkt_residual < 1e-6, "{stack:?} {target:?}: KKT residual {}", a.kkt_residual);
        assert!(a.smallest_multiplier > -1e-9 * a.cost, "{stack:?}: negative multiplier {}", a.smallest_multiplier);
        assert!(!a.active.is_empty());
        assert!(a.cost <= a.global_cost);
        // every pose within the target, the binding ones on it (direct stack-up of the result)
        let mut largest = [0.0_f64; 3];
        for p in 0..s.poses() {
            let r = stack_up(s.pose(p), &a.tolerances);
            let values = match (stack, target) {
                (Stack::Rss, Target::Total(_)) => [r.rss_total; 3],
                (Stack::WorstCase, Target::Total(_)) => [r.worst_total; 3],
                (Stack::Rss, _) => r.rss,
                (Stack::WorstCase, _) => r.worst,
            };
            for d in 0..3 {
                largest[d] = largest[d].max(values[d]);
            }
        }
        let limits = match target {
            Target::Total(v) => [v; 3],
            Target::PerDirection(v) => v,
        };
        for d in 0..3 {
            assert!(largest[d] <= limits[d] * (1.0 + 1e-8), "{stack:?} {target:?} direction {d}: {} > {}", largest[d], limits[d]);
        }
        assert!((0..3).any(|d| (largest[d] - limits[d]).abs() <= 1e-6 * limits[d]), "{stack:?}: no constraint active {largest:?}");
    }
}

#[test]
fn deterministic_for_a_seed_and_the_same_optimum_for_any_seed() {
    let (spec, s) = volume("kx8five", &[45.0, 0.0]);
    let run = |seed: u64| {
        let mut o = options(Stack::Rss, Target::Total(12.0));
        o.genetic.seed = seed;
        allocate(&spec, &s, &o).unwrap()
    };
    let (a, b, c) = (run(1), run(1), run(77));
    assert_eq!(a.tolerances, b.tolerances);
    assert_eq!(a.global_cost, b.global_cost);
    for j in 0..a.tolerances.len() {
        assert!((a.tolerances[j] - c.tolerances[j]).abs() <= 1e-5 * a.tolerances[j], "{}", spec.components[j].id);
    }
    assert!((a.cost - c.cost).abs() <= 1e-9 * a.cost);
}

#[test]
fn lower_limits_above_the_target_are_refused() {
    let m = machine("vmc3");
    let (mut spec, s) = one_pose(&m, &[0.0, 0.0, -200.0]);
    spec.cost = CostModel::uniform(&spec.components, 1.0, 2.0, [5.0, 50.0, 50.0]);
    let e = allocate(&spec, &s, &options(Stack::Rss, Target::Total(1.0))).unwrap_err();
    assert_eq!(e.kind(), trueaxis::ErrorKind::Computation, "{e}");
    assert!(e.to_string().contains("lower limits alone") && e.to_string().contains("target 1 um"), "{e}");
}
