//! scratch timing (will be rewritten)
use faer::linalg::matmul::triangular::{matmul as triangular_matmul, BlockStructure};
use faer::{Accum, Mat, Par};
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::time::Instant;

#[path = "../benches/common/cpu_clock.rs"]
mod cpu_clock;

fn cpu() -> f64 {
    1e-9 * cpu_clock::cpu_ns(cpu_clock::PROCESS).unwrap()
}

fn gram_blocked(x: &DMatrix<f64>, y: &[f64], sw: &[f64], rows: usize) -> Mat<f64> {
    let (n, p) = x.shape();
    let size = p + 1;
    let xs = x.as_slice();
    let starts: Vec<usize> = (0..n).step_by(rows).collect();
    starts
        .par_iter()
        .fold(
            || (Mat::<f64>::zeros(size, size), Mat::<f64>::zeros(rows, size)),
            |(mut g, mut buf), &s| {
                let m = rows.min(n - s);
                for j in 0..size {
                    let src = if j < p { &xs[j * n + s..j * n + s + m] } else { &y[s..s + m] };
                    let col = buf.col_mut(j).try_as_col_major_mut().unwrap().as_slice_mut();
                    for ((a, v), w) in col[..m].iter_mut().zip(src).zip(&sw[s..s + m]) {
                        *a = v * w;
                    }
                }
                let b = buf.as_ref().subrows(0, m);
                triangular_matmul(g.as_mut(), BlockStructure::TriangularLower, Accum::Add, b.transpose(), BlockStructure::Rectangular, b, BlockStructure::Rectangular, 1.0, Par::Seq);
                (g, buf)
            },
        )
        .map(|(g, _)| g)
        .reduce(|| Mat::<f64>::zeros(size, size), |a, b| a + b)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(100_000);
    let p: usize = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(500);
    let mut rng = ChaCha8Rng::seed_from_u64(500);
    let normal = rand_distr::StandardNormal;
    let x = DMatrix::from_fn(n, p, |_, _| rng.sample::<f64, _>(normal));
    let y: Vec<f64> = (0..n).map(|_| rng.sample::<f64, _>(normal)).collect();
    let sw = vec![1.0; n];
    let flops = n as f64 * (p + 1) as f64 * (p + 2) as f64 / 2.0 * 2.0 / 2.0; // one triangle: n p^2
    let g = gram_blocked(&x, &y, &sw, 256);
    let gs = Mat::from_fn(p, p, |i, j| if i >= j { g[(i, j)] } else { g[(j, i)] } / n as f64);
    for _ in 0..2 {
        let (t, c) = (Instant::now(), cpu());
        let l = gs.llt(faer::Side::Lower).unwrap();
        println!("llt: wall {:.3} cpu {:.3}", t.elapsed().as_secs_f64(), cpu() - c);
        let r = l.L().transpose().to_owned();
        let (t, c) = (Instant::now(), cpu());
        let s = r.svd().unwrap();
        println!("svd R: wall {:.3} cpu {:.3} {}", t.elapsed().as_secs_f64(), cpu() - c, s.S().column_vector()[0]);
        let (t, c) = (Instant::now(), cpu());
        let s = r.singular_values().unwrap();
        println!("sv only R: wall {:.3} cpu {:.3} {}", t.elapsed().as_secs_f64(), cpu() - c, s[0]);
        let (t, c) = (Instant::now(), cpu());
        let e = gs.self_adjoint_eigen(faer::Side::Lower).unwrap();
        println!("eigh G: wall {:.3} cpu {:.3} {}", t.elapsed().as_secs_f64(), cpu() - c, e.S().column_vector()[p - 1]);
    }
    for rows in [256usize] {
        for _ in 0..2 {
            let (t, c) = (Instant::now(), cpu());
            let g = gram_blocked(&x, &y, &sw, rows);
            let (w, cc) = (t.elapsed().as_secs_f64(), cpu() - c);
            println!("rows {rows}: wall {w:.3} s cpu {cc:.3} s  {:.1} GFLOP/s wall, {:.1} per cpu-s  g00 {}", flops / w * 1e-9, flops / cc * 1e-9, g[(0, 0)]);
        }
    }
    let weights = vec![1.0; n];
    for _ in 0..3 {
        let (t, c) = (Instant::now(), cpu());
        let svd = trueaxis::identify::ScaledSvd::with_observations(&x, &weights, &y, 1e-8);
        println!("ScaledSvd: wall {:.3} cpu {:.3} {:?}", t.elapsed().as_secs_f64(), cpu() - c, svd.reduction);
        let (t, c) = (Instant::now(), cpu());
        let names: Vec<String> = (0..p).map(|j| format!("c{j}")).collect();
        let _r = trueaxis::identify::IdentifiabilityReport::new(&x, &svd, &names, &names);
        println!("report: wall {:.3} cpu {:.3}", t.elapsed().as_secs_f64(), cpu() - c);
        let (t, c) = (Instant::now(), cpu());
        let _s = svd.solve_triangular().unwrap();
        println!("solve_triangular: wall {:.3} cpu {:.3}", t.elapsed().as_secs_f64(), cpu() - c);
        let (t, c) = (Instant::now(), cpu());
        let f = &x * nalgebra::DVector::from_element(p, 1.0);
        println!("fitted: wall {:.3} cpu {:.3} {}", t.elapsed().as_secs_f64(), cpu() - c, f[0]);
    }
}
