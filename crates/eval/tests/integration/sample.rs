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
