//! The measurement behind the choice of Gauss-Seidel order (`gauss_seidel.rs`):
//! sweeps and time to tolerance for storage, symmetric and multicolour order
//! on the model problems (a)-(c). Prints a table with `--nocapture`; run
//! with `--release` for meaningful times. Asserts the sweep-count facts the
//! documentation relies on.

use std::time::Instant;

use subdiv_solve::{gauss_seidel, internals::model_problems, SolveOptions, SweepOrder};

#[test]
fn multicolour_order_needs_no_more_sweeps_than_storage_order() {
    let cases = [
        ("(a) random SPD 60k", model_problems::random_spd(60_000, 8, 3)),
        ("(b) bicubic torus 250x250", model_problems::bicubic_torus(250, 250)),
        ("(c) Loop grid 252x252", model_problems::loop_regular(252, 252)),
    ];
    println!("| matrix | order | iterations | sweeps | ms |");
    println!("|---|---|---|---|---|");
    for (name, a) in &cases {
        let p: Vec<[f64; 3]> = (0..a.n()).map(|i| [((i * 37) % 101) as f64 / 101.0, (i % 7) as f64, 1.0]).collect();
        let opts = SolveOptions::default().with_tol(1e-6);
        let mut sweeps = Vec::new();
        for order in [SweepOrder::Storage, SweepOrder::Symmetric, SweepOrder::Multicolor] {
            let t = Instant::now();
            let sol = gauss_seidel(a, &p, &opts, order).unwrap();
            let ms = t.elapsed().as_secs_f64() * 1e3;
            let sw = if order == SweepOrder::Symmetric { 2 * sol.iterations } else { sol.iterations };
            println!("| {name} | {order:?} | {} | {sw} | {ms:.1} |", sol.iterations);
            assert!(a.max_residual(&sol.x, &p) <= 1e-6);
            sweeps.push(sw);
        }
        let (storage, symmetric, multi) = (sweeps[0] as f64, sweeps[1] as f64, sweeps[2] as f64);
        assert!(multi <= 1.25 * storage, "{name}: multicolour {multi} vs storage {storage} sweeps");
        assert!(symmetric >= 0.75 * storage, "{name}: symmetric {symmetric} vs storage {storage} sweeps");
    }
}
