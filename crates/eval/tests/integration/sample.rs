//! Sampling: points on the surface, unit normals, counts, determinism, and
//! the by-area distribution against the areas of a fine tessellation.

use crate::bspline_torus::BSplineTorus;
use subdiv_eval::{sample_by_area, sample_per_domain, PatchEvaluator, SurfaceParam};
use subdiv_mesh::shapes;

fn torus() -> BSplineTorus {
    // A torus of unequal faces: outer faces are larger than inner ones.
    let mesh = shapes::torus(9, 6);
    BSplineTorus::new(&mesh, 9, 6)
}

#[test]
fn per_domain_samples_are_on_the_surface_with_unit_normals() {
    let t = torus();
    let samples = sample_per_domain(&t, 3).unwrap();
    assert_eq!(samples.len(), 9 * 6 * 9);
    for s in &samples {
        assert!((s.normal.length() - 1.0).abs() < 1e-12);
        let e = t.evaluate(s.param).unwrap();
        assert_eq!(e.position, s.position);
        assert!(s.param.u > 0.0 && s.param.u < 1.0 && s.param.v > 0.0 && s.param.v < 1.0);
    }
    assert!(sample_per_domain(&t, 0).is_err());
}

/// Surface area of every domain from a 64 × 64 midpoint rule on |S_u × S_v|.
fn domain_areas(t: &BSplineTorus) -> Vec<f64> {
    let n = 64;
    t.domains()
        .iter()
        .map(|d| {
            let mut a = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let (u, v) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                    let s = t.evaluate(SurfaceParam { face: d.face, corner: 0, u, v }).unwrap();
                    a += s.du.cross(s.dv).length() / (n * n) as f64;
                }
            }
            a
        })
        .collect()
}

#[test]
fn area_samples_follow_the_area() {
    let t = torus();
    let count = 54_000;
    let samples = sample_by_area(&t, count, 42).unwrap();
    assert_eq!(samples.len(), count);
    assert_eq!(samples, sample_by_area(&t, count, 42).unwrap(), "deterministic");
    assert_ne!(samples, sample_by_area(&t, count, 43).unwrap());
    let areas = domain_areas(&t);
    let total: f64 = areas.iter().sum();
    let mut per_domain = vec![0usize; areas.len()];
    for s in &samples {
        per_domain[s.param.face as usize] += 1;
        let e = t.evaluate(s.param).unwrap();
        assert!((e.position - s.position).length() < 1e-12);
    }
    for (k, (&got, &a)) in per_domain.iter().zip(&areas).enumerate() {
        let expected = count as f64 * a / total;
        // Systematic sampling: ±1 per tessellation triangle (128 per domain),
        // plus the tessellation's area error (≪ 1 %).
        assert!((got as f64 - expected).abs() <= 0.01 * expected + 128.0, "domain {k}: {got} vs {expected}");
    }
    // Inner faces have less area than outer ones, and get fewer samples.
    let inner = per_domain[3];
    let outer = per_domain[0];
    assert!(inner < outer, "{inner} {outer}");
}

#[test]
fn doo_sabin_open_mesh_samples_are_on_the_surface() {
    // Strips (the domains between the face corners and the boundary curve) included.
    use subdiv_eval::{project::BoundLimitSurface, LimitSurface};
    use subdiv_stencil::{Options, Scheme};
    let mesh = shapes::polygon_mix(&shapes::quad_grid(4, 3), 2, 0.2, 0.2, 0.1);
    let surface = LimitSurface::new(&mesh, &Options::new(Scheme::DooSabin)).unwrap();
    assert!(surface
        .domains()
        .iter()
        .any(|d| d.corner >= mesh.topology().face_size(subdiv_mesh::FaceId(d.face)) as u32));
    let bound = BoundLimitSurface::new(&surface, mesh.positions()).unwrap();
    let samples = sample_per_domain(&bound, 3).unwrap();
    assert_eq!(samples.len(), surface.domains().len() * 9);
    let by_area = sample_by_area(&bound, 2000, 1).unwrap();
    for s in samples.iter().chain(&by_area) {
        assert!((s.normal.length() - 1.0).abs() < 1e-12);
        let e = surface.evaluate(mesh.positions(), s.param).unwrap();
        assert!((e.position - s.position).length() < 1e-12);
    }
}

/// Counts no memory can hold are typed errors, not a panic ("capacity overflow") or an abort
/// (issue #43); `per_domain_count` says how many samples a grid makes, `None` beyond `u64`.
#[test]
fn counts_beyond_memory_are_errors() {
    let t = torus();
    for count in [usize::MAX, usize::MAX / 2, 1 << 60] {
        let e = sample_by_area(&t, count, 0).unwrap_err();
        assert!(matches!(e, subdiv_eval::EvalError::InvalidInput { .. }), "{e}");
        assert!(e.to_string().contains("more samples than memory can hold"), "{e}");
    }
    // Passes the size check, fails the reservation (24 TB of picks): an error as well.
    assert!(sample_by_area(&t, 1_000_000_000_000, 0).is_err());
    for n in [usize::MAX, 1 << 32, 1 << 28] {
        assert!(sample_per_domain(&t, n).is_err(), "{n}");
    }
    assert_eq!(subdiv_eval::per_domain_count(54, 3), Some(486));
    assert_eq!(subdiv_eval::per_domain_count(6, 1 << 32), None);
    assert_eq!(subdiv_eval::per_domain_count(6, 65536), Some(6 << 32));
}

/// `sample_surface` and `LimitSurface::evaluate_all` run on normalised positions: at 1e-300
/// and 1e300 the normals are those at scale 1 (du × dv underflowed or overflowed to a zero
/// normal at ≤ 1e-150 and ≥ 1e150) and the positions are scaled.
#[test]
fn normals_do_not_depend_on_the_scale() {
    let mesh = shapes::torus(6, 4);
    let options = subdiv_stencil::Options::new(subdiv_stencil::Scheme::CatmullClark);
    let surface = subdiv_eval::LimitSurface::new(&mesh, &options).unwrap();
    let how = subdiv_eval::Sampling::ByArea { count: 64, seed: 7 };
    let unit = subdiv_eval::sample_surface(&surface, mesh.positions(), how).unwrap();
    let params: Vec<SurfaceParam> = unit.iter().map(|s| s.param).collect();
    let evaluated = surface.evaluate_all(mesh.positions(), &params).unwrap();
    for scale in [1e-300, 1e-200, 1e-150, 1e150, 1e200, 1e300] {
        let scaled: Vec<_> = mesh.positions().iter().map(|&p| p * scale).collect();
        let far = subdiv_eval::sample_surface(&surface, &scaled, how).unwrap();
        let far_evaluated = surface.evaluate_all(&scaled, &params).unwrap();
        for ((a, b), (c, d)) in unit.iter().zip(&far).zip(evaluated.iter().zip(&far_evaluated)) {
            assert_eq!(a.param, b.param, "{scale:e}");
            assert!((a.normal - b.normal).length() < 1e-12, "{scale:e}: {:?} vs {:?}", a.normal, b.normal);
            assert!((c.normal - d.normal).length() < 1e-12, "{scale:e}: {:?} vs {:?}", c.normal, d.normal);
            assert!((b.position / scale - a.position).length() < 1e-12 * a.position.length().max(1.0), "{scale:e}");
            assert!((d.du / scale - c.du).length() < 1e-12 * c.du.length().max(1.0), "{scale:e}");
        }
    }
}
