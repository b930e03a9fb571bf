//! A bounding-volume hierarchy of axis-aligned boxes for nearest-item
//! queries: the patch bounds of [`crate::project`] and the triangles of a
//! fitting target ([`crate::fit`]).
//!
//! Built top-down by a median split of the box centres along the longest
//! axis of their extent (leaves of at most [`LEAF_SIZE`] items), stored as a
//! flat array (children of node `i` are contiguous). A query walks the tree
//! nearest child first and skips every subtree whose box is farther than the
//! best distance found so far (the box distance is a lower bound of any
//! item's distance inside it); the caller computes the exact distance of the
//! items it is offered.

use glam::DVec3;
use subdiv_mesh::Aabb;

/// Items per leaf.
pub const LEAF_SIZE: usize = 4;

/// Squared distance from `q` to the box (0 inside).
pub fn box_distance_squared(b: &Aabb, q: DVec3) -> f64 {
    let d = (b.min - q).max(q - b.max).max(DVec3::ZERO);
    d.length_squared()
}

/// The box covering two boxes.
pub fn union(a: &Aabb, b: &Aabb) -> Aabb {
    Aabb { min: a.min.min(b.min), max: a.max.max(b.max) }
}

#[derive(Clone, Debug)]
struct Node {
    bounds: Aabb,
    /// Inner node: index of the first of two children; leaf: first item in `order`.
    start: u32,
    /// 0 for an inner node, else the number of items in the leaf.
    count: u32,
}

/// A BVH over boxes, each naming one item (its index in the input).
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Item indices, leaf by leaf.
    order: Vec<u32>,
    /// Item boxes, by item index.
    boxes: Vec<Aabb>,
}

impl Bvh {
    /// Builds the hierarchy over `boxes` (item `i` is `boxes[i]`).
    pub fn new(boxes: Vec<Aabb>) -> Self {
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        let centres: Vec<DVec3> = boxes.iter().map(|b| 0.5 * (b.min + b.max)).collect();
        let mut nodes = Vec::with_capacity(2 * boxes.len() / LEAF_SIZE + 1);
        if !boxes.is_empty() {
            nodes.push(Node { bounds: boxes[0], start: 0, count: 0 });
            build(&mut nodes, 0, &mut order, 0, &boxes, &centres);
        }
        Self { nodes, order, boxes }
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    /// True when there are no items.
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// The box of item `i`.
    pub fn item_bounds(&self, i: usize) -> &Aabb {
        &self.boxes[i]
    }

    /// Offers the items to `visit` nearest box first, as `visit(item,
    /// box_distance²)`, skipping every item and subtree whose box distance² is
    /// larger than the current best; `visit` returns the new best squared
    /// distance (or the old one). `best` is the initial bound (∞ for none).
    pub fn nearest(&self, q: DVec3, mut best: f64, mut visit: impl FnMut(u32, f64) -> f64) -> f64 {
        if self.nodes.is_empty() {
            return best;
        }
        let mut stack: Vec<(u32, f64)> = Vec::with_capacity(64);
        stack.push((0, box_distance_squared(&self.nodes[0].bounds, q)));
        while let Some((i, lb)) = stack.pop() {
            if lb > best {
                continue;
            }
            let node = &self.nodes[i as usize];
            if node.count > 0 {
                let items = &self.order[node.start as usize..(node.start + node.count) as usize];
                // Nearest box first inside the leaf as well.
                let mut near: [(f64, u32); LEAF_SIZE] = [(f64::INFINITY, 0); LEAF_SIZE];
                for (k, &it) in items.iter().enumerate() {
                    near[k] = (box_distance_squared(&self.boxes[it as usize], q), it);
                }
                let near = &mut near[..items.len()];
                near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
                for &(d, it) in near.iter() {
                    if d <= best {
                        best = visit(it, d);
                    }
                }
                continue;
            }
            let (a, b) = (node.start, node.start + 1);
            let da = box_distance_squared(&self.nodes[a as usize].bounds, q);
            let db = box_distance_squared(&self.nodes[b as usize].bounds, q);
            // The nearer child is popped first.
            if da <= db {
                stack.push((b, db));
                stack.push((a, da));
            } else {
                stack.push((a, da));
                stack.push((b, db));
            }
        }
        best
    }
}

fn build(nodes: &mut Vec<Node>, at: usize, order: &mut [u32], offset: usize, boxes: &[Aabb], centres: &[DVec3]) {
    let bounds = order.iter().map(|&i| boxes[i as usize]).reduce(|a, b| union(&a, &b)).expect("non-empty");
    nodes[at].bounds = bounds;
    if order.len() <= LEAF_SIZE {
        nodes[at].start = offset as u32;
        nodes[at].count = order.len() as u32;
        return;
    }
    let (lo, hi) = order.iter().fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), &i| {
        (lo.min(centres[i as usize]), hi.max(centres[i as usize]))
    });
    let extent = hi - lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&a, &b| centres[a as usize][axis].total_cmp(&centres[b as usize][axis]));
    let first = nodes.len();
    nodes.push(Node { bounds, start: 0, count: 0 });
    nodes.push(Node { bounds, start: 0, count: 0 });
    nodes[at].start = first as u32;
    nodes[at].count = 0;
    let (left, right) = order.split_at_mut(mid);
    build(nodes, first, left, offset, boxes, centres);
    build(nodes, first + 1, right, offset + mid, boxes, centres);
}

/// The closest point to `p` on triangle `(a, b, c)` (Ericson, *Real-Time
/// Collision Detection*, 2005, §5.1.5: the Voronoi regions of the vertices,
/// edges and face).
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return a + v * ab;
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return a + w * ac;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + w * (c - b);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    a + ab * v + ac * w
}

/// Nearest-point queries on a point cloud or a triangle mesh (the fitting
/// target's side of the surface→target distance).
#[derive(Clone, Debug)]
pub struct TargetIndex {
    points: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    bvh: Bvh,
}

impl TargetIndex {
    /// An index over `triangles` (indices into `points`), or over the points
    /// themselves when `triangles` is empty.
    pub fn new(points: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Self {
        let boxes = if triangles.is_empty() {
            points.iter().map(|&p| Aabb { min: p, max: p }).collect()
        } else {
            triangles.iter().map(|t| Aabb::of(t.iter().map(|&i| points[i as usize])).expect("three corners")).collect()
        };
        Self { bvh: Bvh::new(boxes), points, triangles }
    }

    /// The nearest point of the target to `q` (on a triangle or a cloud point)
    /// and its distance; `None` for an empty target.
    pub fn nearest(&self, q: DVec3) -> Option<(DVec3, f64)> {
        let mut found = None;
        self.bvh.nearest(q, f64::INFINITY, |item, _| {
            let p = if self.triangles.is_empty() {
                self.points[item as usize]
            } else {
                let [a, b, c] = self.triangles[item as usize].map(|i| self.points[i as usize]);
                closest_point_on_triangle(q, a, b, c)
            };
            let d = (p - q).length_squared();
            match found {
                Some((_, old)) if old <= d => old,
                _ => {
                    found = Some((p, d));
                    d
                }
            }
        });
        found.map(|(p, d)| (p, d.sqrt()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::shapes::SplitMix64;

    fn random_point(rng: &mut SplitMix64) -> DVec3 {
        DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64()) * 2.0 - 1.0
    }

    #[test]
    fn nearest_matches_brute_force_on_points() {
        let mut rng = SplitMix64(7);
        let points: Vec<DVec3> = (0..500).map(|_| random_point(&mut rng)).collect();
        let index = TargetIndex::new(points.clone(), Vec::new());
        for _ in 0..200 {
            let q = random_point(&mut rng) * 1.5;
            let brute = points.iter().map(|p| (*p - q).length()).fold(f64::INFINITY, f64::min);
            let (_, d) = index.nearest(q).unwrap();
            assert_eq!(d, brute);
        }
    }

    #[test]
    fn closest_point_on_triangle_beats_dense_samples() {
        let mut rng = SplitMix64(3);
        for _ in 0..200 {
            let [a, b, c, p] = [0; 4].map(|_| random_point(&mut rng));
            let x = closest_point_on_triangle(p, a, b, c);
            let d = (x - p).length();
            let n = 60;
            for i in 0..=n {
                for j in 0..=n - i {
                    let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                    let y = a + s * (b - a) + t * (c - a);
                    assert!(d <= (y - p).length() + 1e-12);
                }
            }
        }
    }

    #[test]
    fn triangle_index_matches_brute_force() {
        let mut rng = SplitMix64(11);
        let points: Vec<DVec3> = (0..300).map(|_| random_point(&mut rng)).collect();
        let triangles: Vec<[u32; 3]> =
            (0..100).map(|_| [0; 3].map(|_| rng.below(points.len()) as u32)).filter(|t| t[0] != t[1]).collect();
        let index = TargetIndex::new(points.clone(), triangles.clone());
        for _ in 0..100 {
            let q = random_point(&mut rng);
            let brute = triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| points[i as usize]);
                    (closest_point_on_triangle(q, a, b, c) - q).length()
                })
                .fold(f64::INFINITY, f64::min);
            assert_eq!(index.nearest(q).unwrap().1, brute);
        }
    }
}
