use super::*;
use crate::curves::four_point;
use crate::doo_sabin_weights;
use crate::test_util::{combine, Rng};
use crate::vec3::lin2;

#[test]
fn moved_vertices_have_centroid_p() {
    // ERRATA D2: with "P +" the old vertex is the centroid of its moved
    // vertices, which is why the scheme keeps old vertices.
    let mut rng = Rng::new(41);
    for m in 3..=12 {
        for omega in [0.0, 0.3, 1.0, rng.range(0.0, 1.0)] {
            let p = rng.point(10.0);
            let images = rng.points(m, 10.0);
            let mut moved = vec![[f64::NAN; 3]; m];
            moved_images(p, &images, omega, &mut moved);
            assert!(dist(centroid(&moved), p) < 1e-14, "m = {m}, ω = {omega}");
        }
    }
}

#[test]
fn omega_zero_collapses_and_omega_one_translates() {
    let mut rng = Rng::new(42);
    let p = rng.point(1.0);
    let images = rng.points(5, 1.0);
    let g = centroid(&images);
    let mut moved = [[0.0; 3]; 5];
    moved_images(p, &images, 0.0, &mut moved);
    assert!(moved.iter().all(|&q| q == p));
    moved_images(p, &images, 1.0, &mut moved);
    for (q, img) in moved.iter().zip(&images) {
        assert!(dist(sub(*q, p), sub(*img, g)) < 1e-15);
    }
}

/// Grid positions P(i, j) = G_i + H_j (additive, otherwise random), i, j in
/// −3..=4.
struct Grid {
    g: Vec<Point3>,
    h: Vec<Point3>,
}

impl Grid {
    const OFFSET: i32 = 3;
    fn at(&self, i: i32, j: i32) -> Point3 {
        add(self.g[(i + Self::OFFSET) as usize], self.h[(j + Self::OFFSET) as usize])
    }
    /// Doo-Sabin image of corner (i, j) in the cell with lower-left (ci, cj).
    fn image(&self, (i, j): (i32, i32), (ci, cj): (i32, i32)) -> Point3 {
        let corners = [(ci, cj), (ci + 1, cj), (ci + 1, cj + 1), (ci, cj + 1)];
        let start = corners.iter().position(|&c| c == (i, j)).expect("corner of the cell");
        let mut w = [0.0; 4];
        doo_sabin_weights(4, &mut w);
        let pts: Vec<Point3> = (0..4)
            .map(|k| {
                let (a, b) = corners[(start + k) % 4];
                self.at(a, b)
            })
            .collect();
        combine(&w, &pts)
    }
    /// The four cells around vertex (i, j), in fan order.
    fn cells(i: i32, j: i32) -> [(i32, i32); 4] {
        [(i, j), (i - 1, j), (i - 1, j - 1), (i, j - 1)]
    }
    /// Moved vertex of (i, j) in `cell`, global ω.
    fn moved(&self, (i, j): (i32, i32), cell: (i32, i32), omega: f64) -> Point3 {
        let cells = Self::cells(i, j);
        let images: Vec<Point3> = cells.iter().map(|&c| self.image((i, j), c)).collect();
        let mut moved = [[0.0; 3]; 4];
        moved_images(self.at(i, j), &images, omega, &mut moved);
        moved[cells.iter().position(|&c| c == cell).unwrap()]
    }
}

#[test]
fn regular_grid_reproduces_four_point() {
    // ERRATA D4: ω_P = 1 is the 4-point scheme with ω = 1/16. On a regular
    // grid with additive data P(i, j) = G_i + H_j the new edge point of edge
    // (0,0)–(1,0) is the 4-point point of its row.
    let mut rng = Rng::new(43);
    for _ in 0..10 {
        let grid = Grid { g: rng.points(8, 1.0), h: rng.points(8, 1.0) };
        let four: Vec<Point3> = [(0, 0), (0, -1)]
            .iter()
            .flat_map(|&cell| [grid.moved((0, 0), cell, 1.0), grid.moved((1, 0), cell, 1.0)])
            .collect();
        let edge_point = centroid(&four);
        let row: Vec<Point3> = (-1..=2).map(|i| grid.at(i, 0)).collect();
        let expected = four_point(&row, false, 1.0 / 16.0)[3];
        assert!(dist(edge_point, expected) < 1e-14, "{:e}", dist(edge_point, expected));
        // Another tension breaks it: the check can fail.
        let half: Vec<Point3> = [(0, 0), (0, -1)]
            .iter()
            .flat_map(|&cell| [grid.moved((0, 0), cell, 0.5), grid.moved((1, 0), cell, 0.5)])
            .collect();
        assert!(dist(centroid(&half), expected) > 1e-6);
        // ω_P = 1/2 is the 4-point scheme with ω = 1/32.
        let expected_half = four_point(&row, false, 1.0 / 32.0)[3];
        assert!(dist(centroid(&half), expected_half) < 1e-14);
    }
}

#[test]
fn variable_omega_on_a_unit_grid() {
    // Regular planar unit grid around P = 0: Q_i − G = (±1, ±1)/4, every edge
    // has length 1, so ω_P = min(1, λ/4 · 1/(√2/4)) = λ/√2.
    let grid =
        Grid { g: (0..8).map(|i| [i as f64, 0.0, 0.0]).collect(), h: (0..8).map(|j| [0.0, j as f64, 0.0]).collect() };
    let p = grid.at(0, 0);
    let ring: Vec<Point3> = [(1, 0), (0, 1), (-1, 0), (0, -1)].iter().map(|&(i, j)| grid.at(i, j)).collect();
    let images: Vec<Point3> = Grid::cells(0, 0).iter().map(|&c| grid.image((0, 0), c)).collect();
    for lambda in [0.25, 0.5, 1.0] {
        let w = variable_omega(p, &ring, &images, lambda);
        assert!((w - lambda / 2f64.sqrt()).abs() < 1e-15, "λ = {lambda}: ω = {w}");
        assert_eq!(Tension::Variable { lambda }.omega(p, &ring, &images), w);
    }
    assert_eq!(Tension::default().omega(p, &ring, &images), 1.0);
    // Open fan: the first two cells, three neighbours. G = (0, ¼), Qᵢ − G =
    // (±¼, 0), edges 1, m = 2 → ω_P = min(1, ¼ · 4) = 1.
    assert_eq!(variable_omega(p, &ring[..3], &images[..2], 1.0), 1.0);
    assert_eq!(variable_omega(p, &ring[..3], &images[..2], 0.5), 0.5);
}

#[test]
fn variable_omega_is_displacement_safe_on_edges() {
    // Module docs: with the §3.4 ω_P every edge point satisfies
    // d_E ≤ (λ/4)‖P₁ − P₂‖, i.e. the edge condition with C = λ/4. Jittered
    // grid of quads, 9×9 vertices, random heights.
    let mut rng = Rng::new(44);
    let size = 9usize;
    for lambda in [0.2, 0.6, 1.0] {
        let pos: Vec<Vec<Point3>> = (0..size)
            .map(|i| {
                (0..size)
                    .map(|j| [i as f64 + rng.range(-0.4, 0.4), j as f64 + rng.range(-0.4, 0.4), rng.range(-1.5, 1.5)])
                    .collect()
            })
            .collect();
        let at = |i: i32, j: i32| pos[i as usize][j as usize];
        let image = |(i, j): (i32, i32), (ci, cj): (i32, i32)| {
            let corners = [(ci, cj), (ci + 1, cj), (ci + 1, cj + 1), (ci, cj + 1)];
            let start = corners.iter().position(|&c| c == (i, j)).unwrap();
            let mut w = [0.0; 4];
            doo_sabin_weights(4, &mut w);
            let pts: Vec<Point3> = (0..4)
                .map(|k| {
                    let (a, b) = corners[(start + k) % 4];
                    at(a, b)
                })
                .collect();
            combine(&w, &pts)
        };
        // Moved vertices of every interior vertex, keyed by (vertex, cell).
        let mut moved = std::collections::HashMap::new();
        let mut omegas = Vec::new();
        for i in 1..size as i32 - 1 {
            for j in 1..size as i32 - 1 {
                let cells = Grid::cells(i, j);
                let ring: Vec<Point3> =
                    [(i + 1, j), (i, j + 1), (i - 1, j), (i, j - 1)].iter().map(|&(a, b)| at(a, b)).collect();
                let images: Vec<Point3> = cells.iter().map(|&c| image((i, j), c)).collect();
                let omega = variable_omega(at(i, j), &ring, &images, lambda);
                omegas.push(omega);
                let mut out = [[0.0; 3]; 4];
                moved_images(at(i, j), &images, omega, &mut out);
                for (c, q) in cells.iter().zip(out) {
                    moved.insert(((i, j), *c), q);
                }
            }
        }
        assert!(omegas.iter().any(|&w| w < 1.0), "the bound is active somewhere");
        let bound = DisplacementBound { c: lambda / 4.0 + 1e-12 };
        let mut worst: f64 = 0.0;
        for i in 1..size as i32 - 2 {
            for j in 2..size as i32 - 2 {
                // Horizontal edge (i, j)–(i+1, j), cells (i, j) and (i, j−1).
                let four: Vec<Point3> =
                    [(i, j), (i, j - 1)].iter().flat_map(|&c| [moved[&((i, j), c)], moved[&((i + 1, j), c)]]).collect();
                let e = centroid(&four);
                worst = worst.max(edge_displacement_ratio(e, at(i, j), at(i + 1, j)));
                assert!(bound.edge_ok(e, at(i, j), at(i + 1, j)));
                // Face point of cell (i, j) when all four corners are interior.
                if i >= 1 && j >= 1 && i + 1 < size as i32 - 1 && j + 1 < size as i32 - 1 {
                    let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                    let f = centroid(&corners.map(|v| moved[&(v, (i, j))]));
                    let pts = corners.map(|(a, b)| at(a, b));
                    let longest = (0..4).map(|k| dist(pts[k], pts[(k + 1) % 4])).fold(0.0, f64::max);
                    let shortest = (0..4).map(|k| dist(pts[k], pts[(k + 1) % 4])).fold(f64::INFINITY, f64::min);
                    let d_f = face_displacement_ratio(f, &pts) * shortest;
                    assert!(d_f <= lambda / 4.0 * longest + 1e-12, "face bound");
                }
            }
        }
        assert!(worst > 0.0 && worst <= lambda / 4.0 + 1e-12, "λ = {lambda}: worst ratio {worst}");
    }
}

#[test]
fn displacement_ratios_by_hand() {
    let (p1, p2) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
    assert_eq!(edge_displacement_ratio([1.0, 0.5, 0.0], p1, p2), 0.25);
    let square = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    assert_eq!(face_displacement_ratio([0.5, 0.5, 0.3], &square), 0.3);
    let bound = DisplacementBound { c: 0.25 };
    assert!(bound.edge_ok([1.0, 0.5, 0.0], p1, p2));
    assert!(!bound.face_ok([0.5, 0.5, 0.3], &square));
    assert_eq!(lin2(0.5, p1, 0.5, p2), [1.0, 0.0, 0.0]);
}
