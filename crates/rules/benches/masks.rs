//! Mask evaluation and curve refinement throughput.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use subdiv_rules::{catmull_clark, doo_sabin_weights, CurveScheme};

fn masks(c: &mut Criterion) {
    c.bench_function("doo_sabin_weights m=3..12", |b| {
        let mut buf = [0.0; 12];
        b.iter(|| {
            for m in 3..=12 {
                doo_sabin_weights(black_box(m), &mut buf[..m]);
            }
            black_box(buf[0])
        })
    });
    c.bench_function("cheng limit_stencil n=6", |b| {
        let sizes = [4, 3, 5, 4, 6, 4];
        let (mut e, mut f) = ([0.0; 6], [0.0; 6]);
        b.iter(|| catmull_clark::limit_stencil(black_box(&sizes), &mut e, &mut f))
    });
}

fn curves(c: &mut Criterion) {
    let polygon: Vec<[f64; 3]> = (0..64)
        .map(|i| {
            let t = i as f64 / 64.0 * std::f64::consts::TAU;
            [t.cos(), t.sin(), 0.1 * (3.0 * t).sin()]
        })
        .collect();
    for (name, scheme) in [
        ("chaikin", CurveScheme::Chaikin),
        ("cubic", CurveScheme::CubicBSpline),
        ("four_point", CurveScheme::default()),
    ] {
        c.bench_function(&format!("{name} 64 points x 6 levels"), |b| {
            b.iter(|| scheme.refine_levels(black_box(&polygon), true, 6))
        });
    }
}

criterion_group!(benches, masks, curves);
criterion_main!(benches);
