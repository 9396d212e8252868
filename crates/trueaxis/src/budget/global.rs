//! The global stage of the allocation: a real-coded genetic algorithm on the logarithms of the
//! tolerances with a penalty for violated constraints, as the hybrid GA / SQP method of Zhu 2008
//! appendix B (Table B.1: population 10, crossover probability 0.9, mutation probability 0.1). Its
//! best point starts the local stage. Seeded (ChaCha8), so a seed gives the same result on every
//! machine and thread count.

use super::barrier::ConvexProblem;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Parameters of the genetic algorithm (defaults: Zhu 2008 Table B.1, with 500 generations).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeneticOptions {
    pub population: usize,
    pub generations: usize,
    pub crossover: f64,
    pub mutation: f64,
    pub seed: u64,
}

impl Default for GeneticOptions {
    fn default() -> Self {
        GeneticOptions { population: 10, generations: 500, crossover: 0.9, mutation: 0.1, seed: 1 }
    }
}

/// The fittest point found (`z`) and its objective; `upper[j]` bounds the search of `z_j`.
pub fn genetic(problem: &ConvexProblem, upper: &[f64], options: &GeneticOptions) -> (Vec<f64>, f64) {
    let n = upper.len();
    let lo: Vec<f64> = problem.lower.iter().zip(upper).map(|(l, u)| (l * (1.0 + 1e-6)).max(u * 1e-6).ln()).collect();
    let hi: Vec<f64> = upper.iter().map(|u| u.ln()).collect();
    let decode = |genes: &[f64]| -> Vec<f64> { genes.iter().map(|g| g.exp()).collect() };
    // penalty weight: the cost of the uniform point on the boundary, so that a violation of 1 (100 %)
    // costs ten times a feasible allocation
    let uniform: Vec<f64> = (0..n).map(|j| ((lo[j] + hi[j]) * 0.5).exp()).collect();
    let scale = problem.largest_row(&uniform).max(1e-300);
    let reference = problem.objective(&uniform.iter().map(|z| z / scale).collect::<Vec<_>>());
    let fitness = |genes: &[f64]| -> f64 {
        let z = decode(genes);
        let violation: f64 = problem.rows.iter().map(|c| (c.iter().zip(&z).map(|(c, z)| c * z).sum::<f64>() - 1.0).max(0.0)).sum();
        problem.objective(&z) + 10.0 * reference * violation
    };
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let size = options.population.max(2);
    let mut population: Vec<(Vec<f64>, f64)> = (0..size)
        .map(|_| {
            let genes: Vec<f64> = (0..n).map(|j| rng.gen_range(lo[j]..=hi[j])).collect();
            let f = fitness(&genes);
            (genes, f)
        })
        .collect();
    // rank order selection: weights size, size - 1, ..., 1 of the sorted population
    let total_weight = (size * (size + 1) / 2) as f64;
    let pick = |rng: &mut ChaCha8Rng| -> usize {
        let mut r = rng.gen::<f64>() * total_weight;
        for i in 0..size {
            r -= (size - i) as f64;
            if r <= 0.0 {
                return i;
            }
        }
        size - 1
    };
    for _ in 0..options.generations {
        population.sort_by(|a, b| a.1.total_cmp(&b.1));
        let mut next = vec![population[0].clone()]; // the best survives
        while next.len() < size {
            let (p, q) = (pick(&mut rng), pick(&mut rng));
            let mut child = population[p].0.clone();
            if rng.gen::<f64>() < options.crossover {
                for (j, gene) in child.iter_mut().enumerate() {
                    let w: f64 = rng.gen();
                    *gene = w * population[p].0[j] + (1.0 - w) * population[q].0[j];
                }
            }
            for (j, gene) in child.iter_mut().enumerate() {
                if rng.gen::<f64>() < options.mutation {
                    let step = (hi[j] - lo[j]) * 0.1 * (rng.gen::<f64>() * 2.0 - 1.0);
                    *gene = (*gene + step).clamp(lo[j], hi[j]);
                }
            }
            let f = fitness(&child);
            next.push((child, f));
        }
        population = next;
    }
    population.sort_by(|a, b| a.1.total_cmp(&b.1));
    let best = decode(&population[0].0);
    let value = problem.objective(&best);
    (best, value)
}
