//! The fair method gives the same bits whatever the thread count: its
//! parallel products, reductions and matrix builds work on fixed chunks
//! whose partial results are combined in order.

use crate::support::bumpy;
use subdiv_interp::fair::{self, FairAlgorithm, FairOptions};
use subdiv_mesh::{shapes, Mesh};

fn bits(m: &Mesh) -> Vec<[u64; 3]> {
    m.positions().iter().map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]).collect()
}

#[test]
fn one_thread_and_several_give_the_same_control_mesh() {
    // M¹ of 24 000 vertices: several chunks of every parallel loop.
    let mesh = bumpy(shapes::torus(100, 60), 0.01, 31);
    for algorithm in [FairAlgorithm::LimitPoints, FairAlgorithm::Elimination] {
        let opts = FairOptions::default().with_algorithm(algorithm);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| fair::interpolate(&mesh, &opts).unwrap())
        };
        let one = run(1);
        for threads in [2, 3] {
            let many = run(threads);
            assert!(bits(&one.control) == bits(&many.control), "{algorithm:?}: 1 vs {threads} threads differ");
            assert_eq!(one.parameters.energy.map(f64::to_bits), many.parameters.energy.map(f64::to_bits));
        }
    }
}
