use super::*;
use crate::curves::four_point;
use crate::doo_sabin_weights;
use crate::test_util::{combine, Rng};
use crate::vec3::lin2;

#[test]
fn moved_vertices_have_centroid_p() {
    // Correction D2 (docs/REFERENCES.md): with "P +" the old vertex is the centroid of its moved
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
    // Correction D4 (docs/REFERENCES.md): ω_P = 1 is the 4-point scheme with ω = 1/16. On a regular
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

// ---- open meshes (our construction, module docs "Open meshes") ----------------

/// P's two Chaikin images on the boundary polygon, ¾P + ¼P₋ and ¾P + ¼P₊.
fn chaikin_images(prev: Point3, p: Point3, next: Point3) -> [Point3; 2] {
    [lin2(0.75, p, 0.25, prev), lin2(0.75, p, 0.25, next)]
}

#[test]
fn boundary_centre_is_the_mean_of_the_chaikin_images() {
    let mut rng = Rng::new(45);
    for _ in 0..100 {
        let (prev, p, next) = (rng.point(3.0), rng.point(3.0), rng.point(3.0));
        let g = boundary_centre(p, Some((prev, next)));
        assert!(dist(g, centroid(&chaikin_images(prev, p, next))) < 1e-15);
        assert!(dist(g, combine(&crate::doo_sabin::BOUNDARY_CURVE_POINT, &[prev, p, next])) < 1e-15);
        // A corner ends both pieces: with the phantom 2P − P₊ the mean is P.
        let phantom = lin2(2.0, p, -1.0, next);
        assert!(dist(centroid(&chaikin_images(phantom, p, next)), p) < 1e-14);
        assert_eq!(boundary_centre(p, None), p);
    }
}

#[test]
fn curve_omega_is_section_3_4_on_the_boundary_polygon() {
    // The boundary polygon as a 1-D mesh: P's two "faces" are its two edges,
    // its Doo-Sabin images the Chaikin points; §3.4 (variable_omega) on that
    // fan is curve_omega. Scales vary so that the cap at 1 is both active and not.
    let mut rng = Rng::new(46);
    let mut capped = 0;
    for k in 0..400 {
        let (p, lambda) = (rng.point(1.0), rng.range(0.05, 1.0));
        let prev = add(p, scale(rng.point(1.0), rng.range(0.1, 3.0)));
        let next = add(p, scale(rng.point(1.0), if k % 2 == 0 { rng.range(0.1, 3.0) } else { 1e-3 }));
        let images = chaikin_images(prev, p, next);
        let expected = variable_omega(p, &[prev, next], &images, lambda);
        let got = curve_omega(p, Some((prev, next)), lambda);
        // (variable_omega measures the spread from rounded Chaikin points.)
        assert!((got - expected).abs() <= 1e-12 * expected, "{got} vs {expected}");
        capped += usize::from(got == 1.0);
        // At a corner the piece is extended by the phantom 2P − P₊.
        let phantom = lin2(2.0, p, -1.0, next);
        let at_end = variable_omega(p, &[phantom, next], &chaikin_images(phantom, p, next), lambda);
        // (The phantom loses digits when P₊ is close to P: 1e-3 apart here.)
        assert!((curve_omega(p, None, lambda) - at_end).abs() <= 1e-11 * lambda, "corner: {at_end} vs λ = {lambda}");
        // The 4-point tension is ω_P/16 (correction D4, docs/REFERENCES.md), global or variable.
        let variable = Tension::Variable { lambda };
        assert_eq!(variable.curve_tension(p, Some((prev, next))), got / 16.0);
        assert_eq!(Tension::Global(lambda).curve_tension(p, None), lambda / 16.0);
    }
    assert!(capped > 0 && capped < 400, "the cap at ω_P = 1 is active {capped} times of 400");
}

/// General (not additive) data on the quarter grid i, j ≥ 0, extended by one
/// ring of ghosts at i = −1 and j = −1 by linear extrapolation, the corner
/// ghost extrapolated in both directions (the tensor product).
struct GhostGrid {
    real: Vec<Vec<Point3>>,
}

impl GhostGrid {
    const SIZE: i32 = 5;
    fn at(&self, i: i32, j: i32) -> Point3 {
        match (i, j) {
            (-1, _) => lin2(2.0, self.at(0, j), -1.0, self.at(1, j)),
            (_, -1) => lin2(2.0, self.at(i, 0), -1.0, self.at(i, 1)),
            _ => self.real[i as usize][j as usize],
        }
    }
    fn real_cell((ci, cj): (i32, i32)) -> bool {
        ci >= 0 && cj >= 0
    }
    /// Doo-Sabin image of (i, j) in the cell with lower-left corner (ci, cj).
    fn image(&self, (i, j): (i32, i32), (ci, cj): (i32, i32)) -> Point3 {
        let corners = [(ci, cj), (ci + 1, cj), (ci + 1, cj + 1), (ci, cj + 1)];
        let start = corners.iter().position(|&c| c == (i, j)).expect("corner of the cell");
        let mut w = [0.0; 4];
        doo_sabin_weights(4, &mut w);
        let pts: Vec<Point3> =
            (0..4).map(|k| self.at(corners[(start + k) % 4].0, corners[(start + k) % 4].1)).collect();
        combine(&w, &pts)
    }
    /// The report's closed rule at (i, j) on the extended grid: moved image in `cell`.
    fn closed_moved(&self, v: (i32, i32), cell: (i32, i32), omega: f64) -> Point3 {
        let cells = Grid::cells(v.0, v.1);
        let images: Vec<Point3> = cells.iter().map(|&c| self.image(v, c)).collect();
        let mut moved = [[0.0; 3]; 4];
        moved_images(self.at(v.0, v.1), &images, omega, &mut moved);
        moved[cells.iter().position(|&c| c == cell).unwrap()]
    }
    /// The open rule at boundary vertex v (i = 0 or j = 0): its real cells and
    /// their moved images about the boundary centre.
    fn open_moved(&self, (i, j): (i32, i32), omega: f64) -> Vec<((i32, i32), Point3)> {
        let cells: Vec<(i32, i32)> = Grid::cells(i, j).into_iter().filter(|&c| Self::real_cell(c)).collect();
        let neighbours = match (i, j) {
            (0, 0) => None,
            (0, _) => Some((self.at(0, j - 1), self.at(0, j + 1))),
            _ => Some((self.at(i - 1, 0), self.at(i + 1, 0))),
        };
        let p = self.at(i, j);
        let g = boundary_centre(p, neighbours);
        let images: Vec<Point3> = cells.iter().map(|&c| self.image((i, j), c)).collect();
        let mut moved = vec![[0.0; 3]; cells.len()];
        moved_images_about(p, &images, g, omega, &mut moved);
        cells.into_iter().zip(moved).collect()
    }
}

#[test]
fn open_grid_is_the_closed_rule_on_a_ghost_extended_grid() {
    // Module docs, "Why this G" (b): on a regular quad grid the open rule is
    // the report's closed rule on the grid extended by linearly extrapolated
    // ghosts, for any data — the moved images of the boundary vertices in the
    // real cells (hence every face and interior edge point), and the boundary
    // edge points (the 4-point rule along the boundary, phantom at the corner).
    let mut rng = Rng::new(47);
    for _ in 0..10 {
        let n = GhostGrid::SIZE as usize;
        let grid = GhostGrid { real: (0..n).map(|_| rng.points(n, 1.0)).collect() };
        for omega in [1.0, 0.5, 0.2] {
            let mut worst: f64 = 0.0;
            let boundary: Vec<(i32, i32)> = (0..4).map(|i| (i, 0)).chain((1..4).map(|j| (0, j))).collect();
            for &v in &boundary {
                for (cell, open) in grid.open_moved(v, omega) {
                    worst = worst.max(dist(open, grid.closed_moved(v, cell, omega)));
                }
            }
            assert!(worst < 1e-14, "ω = {omega}: moved images differ by {worst:e}");
            // Boundary edge (i, 0)–(i + 1, 0): the ghost grid's E-face centroid
            // is the 4-point point of the boundary row (phantom before the corner).
            let row: Vec<Point3> = (0..n as i32).map(|i| grid.at(i, 0)).collect();
            let curve = four_point(&row, false, omega / 16.0);
            for i in 0..3 {
                let four: Vec<Point3> = [(i, 0), (i, -1)]
                    .iter()
                    .flat_map(|&c| [grid.closed_moved((i, 0), c, omega), grid.closed_moved((i + 1, 0), c, omega)])
                    .collect();
                let e = dist(centroid(&four), curve[2 * i as usize + 1]);
                assert!(e < 1e-14, "ω = {omega}, edge {i}: {e:e}");
            }
        }
    }
}

#[test]
fn a_centroid_centre_at_the_boundary_breaks_the_ghost_equivalence() {
    // The check above can fail: the report's G (the centroid of the images in
    // the real cells only) moves the images of boundary vertices off the ghost
    // grid's.
    let mut rng = Rng::new(48);
    let n = GhostGrid::SIZE as usize;
    let grid = GhostGrid { real: (0..n).map(|_| rng.points(n, 1.0)).collect() };
    let v = (2, 0);
    let cells = [(2, 0), (1, 0)];
    let images: Vec<Point3> = cells.iter().map(|&c| grid.image(v, c)).collect();
    let mut moved = [[0.0; 3]; 2];
    moved_images(grid.at(2, 0), &images, 1.0, &mut moved);
    let gap = dist(moved[0], grid.closed_moved(v, cells[0], 1.0));
    assert!(gap > 1e-3, "{gap}");
}

#[test]
fn variable_tension_is_displacement_safe_at_the_boundary() {
    // Module docs, "Variable tension" under "Open meshes": boundary edge
    // points (4-point rule with curve tensions, phantoms at the corners) and
    // interior edge points next to the boundary both keep d_E ≤ (λ/4)·length.
    // Jittered open grid of quads, 8×8 vertices, random heights, all four
    // corners.
    let mut rng = Rng::new(49);
    let size = 8i32;
    for lambda in [0.2, 0.6, 1.0] {
        let pos: Vec<Vec<Point3>> = (0..size)
            .map(|i| {
                (0..size)
                    .map(|j| [i as f64 + rng.range(-0.4, 0.4), j as f64 + rng.range(-0.4, 0.4), rng.range(-1.5, 1.5)])
                    .collect()
            })
            .collect();
        let at = |(i, j): (i32, i32)| pos[i as usize][j as usize];
        let on_boundary = |(i, j): (i32, i32)| i == 0 || j == 0 || i == size - 1 || j == size - 1;
        // The boundary loop, counter-clockwise from (0, 0).
        let mut walk: Vec<(i32, i32)> = (0..size - 1).map(|i| (i, 0)).collect();
        walk.extend((0..size - 1).map(|j| (size - 1, j)));
        walk.extend((0..size - 1).map(|i| (size - 1 - i, size - 1)));
        walk.extend((0..size - 1).map(|j| (0, size - 1 - j)));
        let n = walk.len();
        let is_corner = |v: (i32, i32)| (v.0 == 0 || v.0 == size - 1) && (v.1 == 0 || v.1 == size - 1);
        let neighbours = |k: usize| {
            let v = walk[k];
            (!is_corner(v)).then(|| (at(walk[(k + n - 1) % n]), at(walk[(k + 1) % n])))
        };
        let tension = Tension::Variable { lambda };
        let mut worst: f64 = 0.0;
        // Boundary edges: ½(Pᵢ + Pᵢ₊₁) + ωᵢ(Pᵢ₊₁ − Pᵢ₋₁) + ωᵢ₊₁(Pᵢ − Pᵢ₊₂).
        for k in 0..n {
            let (a, b) = (walk[k], walk[(k + 1) % n]);
            let before = if is_corner(a) { lin2(2.0, at(a), -1.0, at(b)) } else { at(walk[(k + n - 1) % n]) };
            let after = if is_corner(b) { lin2(2.0, at(b), -1.0, at(a)) } else { at(walk[(k + 2) % n]) };
            let (wa, wb) =
                (tension.curve_tension(at(a), neighbours(k)), tension.curve_tension(at(b), neighbours((k + 1) % n)));
            let e = add(lin2(0.5, at(a), 0.5, at(b)), lin2(wa, sub(at(b), before), wb, sub(at(a), after)));
            let ratio = edge_displacement_ratio(e, at(a), at(b));
            assert!(ratio <= lambda / 4.0 + 1e-12, "λ = {lambda}, boundary edge {k}: {ratio}");
            worst = worst.max(ratio);
        }
        // Moved images of every vertex, keyed by (vertex, cell).
        let mut moved = std::collections::HashMap::new();
        for i in 0..size {
            for j in 0..size {
                let v = (i, j);
                // Fan order: cell k lies between ring[k] and ring[k + 1]; an open
                // fan starts after its gap.
                let exists = |(ci, cj): (i32, i32)| ci >= 0 && cj >= 0 && ci < size - 1 && cj < size - 1;
                let all = Grid::cells(i, j);
                let around = [(i + 1, j), (i, j + 1), (i - 1, j), (i, j - 1)];
                let start = (0..4).find(|&k| exists(all[k]) && !exists(all[(k + 3) % 4])).unwrap_or(0);
                let cells: Vec<(i32, i32)> = (0..4).map(|k| all[(start + k) % 4]).take_while(|&c| exists(c)).collect();
                let ring_len = if cells.len() == 4 { 4 } else { cells.len() + 1 };
                let ring: Vec<Point3> = (0..ring_len).map(|k| at(around[(start + k) % 4])).collect();
                let images: Vec<Point3> = cells
                    .iter()
                    .map(|&c| {
                        let corners = [c, (c.0 + 1, c.1), (c.0 + 1, c.1 + 1), (c.0, c.1 + 1)];
                        let s = corners.iter().position(|&x| x == v).unwrap();
                        let mut w = [0.0; 4];
                        doo_sabin_weights(4, &mut w);
                        combine(&w, &(0..4).map(|k| at(corners[(s + k) % 4])).collect::<Vec<_>>())
                    })
                    .collect();
                let (g, omega) = if on_boundary(v) {
                    let k = walk.iter().position(|&x| x == v).unwrap();
                    let g = boundary_centre(at(v), neighbours(k));
                    (g, tension.boundary_omega(at(v), neighbours(k), &ring, &images, g))
                } else {
                    (centroid(&images), tension.omega(at(v), &ring, &images))
                };
                let mut out = vec![[0.0; 3]; cells.len()];
                moved_images_about(at(v), &images, g, omega, &mut out);
                for (c, q) in cells.iter().zip(out) {
                    moved.insert((v, *c), q);
                }
            }
        }
        // Interior edges with a boundary end: horizontal (i, j)–(i+1, j), j ≥ 1, and vertical ones.
        for i in 0..size - 1 {
            for j in 1..size - 1 {
                for (a, b, cells) in
                    [((i, j), (i + 1, j), [(i, j), (i, j - 1)]), ((j, i), (j, i + 1), [(j, i), (j - 1, i)])]
                {
                    if !(on_boundary(a) || on_boundary(b)) {
                        continue;
                    }
                    let four: Vec<Point3> = cells.iter().flat_map(|&c| [moved[&(a, c)], moved[&(b, c)]]).collect();
                    let ratio = edge_displacement_ratio(centroid(&four), at(a), at(b));
                    assert!(ratio <= lambda / 4.0 + 1e-12, "λ = {lambda}, edge {a:?}–{b:?}: {ratio}");
                    worst = worst.max(ratio);
                }
            }
        }
        assert!(worst > 0.5 * lambda / 4.0, "λ = {lambda}: the bound is nearly reached ({worst})");
    }
}
