//! Regular patches: their basis functions (uniform bicubic B-spline for
//! Catmull-Clark, the quartic three-direction box spline for Loop, uniform
//! biquadratic B-spline for Doo-Sabin) and the gathering of their control
//! points from a local submesh, with the points beyond a boundary or an
//! infinitely sharp crease supplied by reflection ("phantom" points).
//!
//! Phantom points: the crease rules of Catmull-Clark and Loop (vertex
//! (E₋ + 6V + E₊)/8, edge midpoint; a corner stays) are exactly the smooth
//! rules applied to the lattice extended by point-wise reflection across the
//! crease line: a point x beyond the line is `a + b − m(x)`, `m(x)` its
//! mirror image and `a`, `b` the lattice points on the line nearest to the
//! midpoint of x and m(x) (`a = b` on the square lattice). Substituting the
//! reflected points into the smooth masks gives the crease masks (and, for
//! two perpendicular lines, the corner mask), and reflection commutes with
//! refinement, so the regular patch of the extended lattice is the limit
//! surface. OpenSubdiv's regular boundary patches rest on the same identity.
//! The tests compare every such patch with global subdivision.

use std::collections::HashMap;
use subdiv_mesh::{FaceId, HalfEdgeId, Topology, VertexId};
use subdiv_rules::crease::SHARPNESS_INFINITE;
use subdiv_rules::Rule;
use subdiv_stencil::LevelSharpness;

/// A corner's lattice directions toward the next and the previous corner.
pub(crate) type Frame = ((i32, i32), (i32, i32));

/// A linear combination of local vertices.
pub(crate) type Combo = Vec<(u32, f64)>;

/// The kind of a regular patch (its basis).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PatchKind {
    /// Uniform bicubic B-spline, 4×4 points, index `4j + i` (i along u).
    Bicubic,
    /// Quartic three-direction box spline, 12 points (`BOX_POINTS` order).
    BoxSpline,
    /// Uniform biquadratic B-spline, 3×3 points, index `3j + i`.
    Biquadratic,
}

impl PatchKind {
    /// Number of control points.
    pub fn len(self) -> usize {
        match self {
            PatchKind::Bicubic => 16,
            PatchKind::BoxSpline => 12,
            PatchKind::Biquadratic => 9,
        }
    }
}

/// Basis weights and their derivatives with respect to the patch's (s, t).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Basis {
    pub w: [f64; 16],
    pub ds: [f64; 16],
    pub dt: [f64; 16],
    pub dss: [f64; 16],
    pub dst: [f64; 16],
    pub dtt: [f64; 16],
}

/// Uniform cubic B-spline basis, first and second derivatives at `x`.
fn cubic(x: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let y = 1.0 - x;
    let b = [
        y * y * y / 6.0,
        (3.0 * x * x * x - 6.0 * x * x + 4.0) / 6.0,
        (-3.0 * x * x * x + 3.0 * x * x + 3.0 * x + 1.0) / 6.0,
        x * x * x / 6.0,
    ];
    let d = [-y * y / 2.0, (3.0 * x * x - 4.0 * x) / 2.0, (-3.0 * x * x + 2.0 * x + 1.0) / 2.0, x * x / 2.0];
    let dd = [y, 3.0 * x - 2.0, 1.0 - 3.0 * x, x];
    (b, d, dd)
}

/// Uniform quadratic B-spline basis, first and second derivatives at `x`.
fn quadratic(x: f64) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let y = 1.0 - x;
    ([y * y / 2.0, (-2.0 * x * x + 2.0 * x + 1.0) / 2.0, x * x / 2.0], [-y, 1.0 - 2.0 * x, x], [1.0, -2.0, 1.0])
}

/// Exponents (a, b) of the monomials sᵃtᵇ of degree ≤ 4, the columns of
/// [`BOX_COEFFICIENTS`].
const MONOMIALS: [(i32, i32); 15] = [
    (0, 0),
    (1, 0),
    (0, 1),
    (2, 0),
    (1, 1),
    (0, 2),
    (3, 0),
    (2, 1),
    (1, 2),
    (0, 3),
    (4, 0),
    (3, 1),
    (2, 2),
    (1, 3),
    (0, 4),
];

/// The twelve basis functions of the regular Loop patch (the quartic box
/// spline, Stam 1998, "Evaluation of Loop subdivision surfaces", eliminated
/// w = 1 − s − t) as coefficients of [`MONOMIALS`], times 12. Row order:
/// [`BOX_POINTS`]. Checked in the tests against the Loop limit masks at the
/// level-2 points and the partition of unity.
#[rustfmt::skip]
const BOX_COEFFICIENTS: [[f64; 15]; 12] = [
    [1., -2., -4., 0., 6., 6., 2., 0., -6., -4., -1., -2., 0., 2., 1.],
    [1., 2., -2., 0., -6., 0., -4., 0., 6., 2., 2., 4., 0., -2., -1.],
    [0., 0., 0., 0., 0., 0., 2., 0., 0., 0., -1., -2., 0., 0., 0.],
    [1., -4., -2., 6., 6., 0., -4., -6., 0., 2., 1., 2., 0., -2., -1.],
    [6., 0., 0., -12., -12., -12., 8., 12., 12., 8., -1., -2., 0., -2., -1.],
    [1., 4., 2., 6., 6., 0., -4., -6., -12., -4., -1., -2., 0., 4., 2.],
    [0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 1., 2., 0., 0., 0.],
    [1., -2., 2., 0., -6., 0., 2., 6., 0., -4., -1., -2., 0., 4., 2.],
    [1., 2., 4., 0., 6., 6., -4., -12., -6., -4., 2., 4., 0., -2., -1.],
    [0., 0., 0., 0., 0., 0., 2., 6., 6., 2., -1., -2., 0., -2., -1.],
    [0., 0., 0., 0., 0., 0., 0., 0., 0., 2., 0., 0., 0., -2., -1.],
    [0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 0., 2., 1.],
];

/// Lattice coordinates (skew: the triangle's corners at (0,0), (1,0),
/// (0,1); the third lattice direction is (−1, 1)) of the twelve points of the
/// regular Loop patch.
pub(crate) const BOX_POINTS: [(i32, i32); 12] =
    [(0, -1), (1, -1), (2, -1), (-1, 0), (0, 0), (1, 0), (2, 0), (-1, 1), (0, 1), (1, 1), (-1, 2), (0, 2)];

/// One direction's values and first and second derivatives.
type Univariate<const N: usize> = ([f64; N], [f64; N], [f64; N]);

/// The N × N tensor-product basis (weight k = N·j + i) of one direction's
/// values and derivatives in s and the other's in t.
fn tensor_product<const N: usize>(b: &mut Basis, (bu, du, duu): Univariate<N>, (bv, dv, dvv): Univariate<N>) {
    for j in 0..N {
        for i in 0..N {
            let k = N * j + i;
            b.w[k] = bu[i] * bv[j];
            b.ds[k] = du[i] * bv[j];
            b.dt[k] = bu[i] * dv[j];
            b.dss[k] = duu[i] * bv[j];
            b.dst[k] = du[i] * dv[j];
            b.dtt[k] = bu[i] * dvv[j];
        }
    }
}

/// The basis of `kind` at (s, t).
pub(crate) fn basis(kind: PatchKind, s: f64, t: f64) -> Basis {
    let mut b = Basis { w: [0.0; 16], ds: [0.0; 16], dt: [0.0; 16], dss: [0.0; 16], dst: [0.0; 16], dtt: [0.0; 16] };
    match kind {
        PatchKind::Bicubic => tensor_product(&mut b, cubic(s), cubic(t)),
        PatchKind::Biquadratic => tensor_product(&mut b, quadratic(s), quadratic(t)),
        PatchKind::BoxSpline => {
            let mut m = [[0.0; 15]; 6]; // value, ∂s, ∂t, ∂ss, ∂st, ∂tt of each monomial
                                        // Powers x^(k-2) for k = 0..=6 (index k): 0 below the zeroth power.
            let powers = |x: f64| {
                let mut p = [0.0; 7];
                p[2] = 1.0;
                for k in 3..7 {
                    p[k] = p[k - 1] * x;
                }
                p
            };
            let (ps, pt) = (powers(s), powers(t));
            let pw = |p: &[f64; 7], k: i32| p[(k + 2) as usize];
            for (c, &(a, e)) in MONOMIALS.iter().enumerate() {
                let (af, ef) = (a as f64, e as f64);
                m[0][c] = pw(&ps, a) * pw(&pt, e);
                m[1][c] = af * pw(&ps, a - 1) * pw(&pt, e);
                m[2][c] = ef * pw(&ps, a) * pw(&pt, e - 1);
                m[3][c] = af * (af - 1.0) * pw(&ps, a - 2) * pw(&pt, e);
                m[4][c] = af * ef * pw(&ps, a - 1) * pw(&pt, e - 1);
                m[5][c] = ef * (ef - 1.0) * pw(&ps, a) * pw(&pt, e - 2);
            }
            for (k, row) in BOX_COEFFICIENTS.iter().enumerate() {
                let dot = |m: &[f64; 15]| row.iter().zip(m).map(|(a, b)| a * b).sum::<f64>() / 12.0;
                b.w[k] = dot(&m[0]);
                b.ds[k] = dot(&m[1]);
                b.dt[k] = dot(&m[2]);
                b.dss[k] = dot(&m[3]);
                b.dst[k] = dot(&m[4]);
                b.dtt[k] = dot(&m[5]);
            }
        }
    }
    b
}

/// The lattice a regular patch lives on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lattice {
    /// ℤ² (quads).
    Square,
    /// The triangular lattice in skew coordinates (triangles).
    Hex,
}

impl Lattice {
    fn cartesian(self, (s, t): (i32, i32)) -> (f64, f64) {
        match self {
            Lattice::Square => (s as f64, t as f64),
            Lattice::Hex => (s as f64 + 0.5 * t as f64, t as f64 * 0.75f64.sqrt()),
        }
    }

    fn to_lattice(self, (x, y): (f64, f64)) -> (i32, i32) {
        match self {
            Lattice::Square => (x.round() as i32, y.round() as i32),
            Lattice::Hex => {
                let t = (y / 0.75f64.sqrt()).round() as i32;
                ((x - 0.5 * t as f64).round() as i32, t)
            }
        }
    }
}

/// What a scheme's regular patch looks like.
pub(crate) struct RegularSpec {
    pub lattice: Lattice,
    /// Size of the patch's face and of every face around its corners.
    pub face_size: usize,
    /// Faces around a regular interior vertex.
    pub valence: usize,
    /// Faces in a regular crease (boundary) sector.
    pub crease_sector: usize,
    /// Faces in a regular corner sector, if corners can be regular.
    pub corner_sector: Option<usize>,
    /// Lattice position of each corner of the face.
    pub corners: &'static [(i32, i32)],
    /// Per corner: the lattice directions toward the next and the previous corner.
    pub frames: &'static [Frame],
    /// Lattice directions of the edges around a regular vertex in fan
    /// order, in a corner's frame (a, b) coordinates.
    pub dirs: &'static [(i32, i32)],
    /// The patch's points, in basis order.
    pub points: &'static [(i32, i32)],
    pub kind: PatchKind,
}

/// The faces around corner vertex `from(h0)` reachable from `h0`'s face
/// without crossing an infinitely sharp edge (or the boundary), with their
/// fan offsets (counter-clockwise positive): (offset, half-edge leaving the
/// vertex in that face); and whether the sector closes.
pub(crate) fn sector(t: &Topology, sharp: &LevelSharpness, h0: HalfEdgeId) -> (Vec<(i32, HalfEdgeId)>, bool) {
    let cut = |h: HalfEdgeId| sharp.edge(t, t.he_edge(h)) >= SHARPNESS_INFINITE;
    let limit = t.valence(t.he_from(h0)) as i32 + 1;
    let mut out = vec![(0, h0)];
    let (mut g, mut i, mut closed) = (h0, 0, false);
    loop {
        let p = t.he_prev(g);
        if cut(p) {
            break;
        }
        let Some(n) = t.he_twin(p) else { break };
        if n == h0 {
            closed = true;
            break;
        }
        i += 1;
        if i > limit {
            break;
        }
        out.push((i, n));
        g = n;
    }
    if !closed {
        let (mut g, mut i) = (h0, 0);
        while !cut(g) {
            let Some(tw) = t.he_twin(g) else { break };
            g = t.he_next(tw);
            i -= 1;
            if -i > limit {
                break;
            }
            out.push((i, g));
        }
    }
    (out, closed)
}

/// Whether `v` and every edge at it carry no semi-sharp value.
fn no_semi_sharp(t: &Topology, sharp: &LevelSharpness, v: VertexId) -> bool {
    let semi = |s: f32| s > 0.0 && s < SHARPNESS_INFINITE;
    if semi(sharp.vertex(t, v)) {
        return false;
    }
    t.vertex_fan(v).iter().all(|&h| !semi(sharp.edge(t, t.he_edge(h))))
}

/// The control points of the regular patch of `face`, as combinations of
/// local vertices (phantom points included), or `None` when the face is not
/// regular: every corner smooth with the regular valence, or on a straight
/// crease with the regular sector, or (Catmull-Clark) a corner in one face,
/// all faces around the corners of the patch's size, no semi-sharp value at
/// the corners.
pub(crate) fn regular_points(
    spec: &RegularSpec,
    t: &Topology,
    sharp: &LevelSharpness,
    face: FaceId,
) -> Option<Vec<Combo>> {
    if t.face_size(face) != spec.face_size {
        return None;
    }
    let n = spec.dirs.len() as i32;
    let mut at: HashMap<(i32, i32), Combo> = HashMap::with_capacity(spec.points.len());
    let mut lines: Vec<((i32, i32), (i32, i32))> = Vec::new();
    let dir = |k: usize, i: i32| {
        let (a, b) = spec.frames[k];
        let (al, be) = spec.dirs[i.rem_euclid(n) as usize];
        (al * a.0 + be * b.0, al * a.1 + be * b.1)
    };
    let add = |p: (i32, i32), q: (i32, i32)| (p.0 + q.0, p.1 + q.1);
    let insert = |at: &mut HashMap<(i32, i32), Combo>, p: (i32, i32), v: u32| -> bool {
        match at.get(&p) {
            Some(c) => c.len() == 1 && c[0].0 == v,
            None => {
                at.insert(p, vec![(v, 1.0)]);
                true
            }
        }
    };
    for (k, h0) in t.face_half_edges(face).enumerate() {
        let c = t.he_from(h0);
        if !sharp.is_untagged() && !no_semi_sharp(t, sharp, c) {
            return None;
        }
        let (faces, closed) = sector(t, sharp, h0);
        let ok = match sharp.limit_rule(t, c).0 {
            Rule::Smooth => closed && faces.len() == spec.valence,
            Rule::Crease => !closed && faces.len() == spec.crease_sector,
            Rule::Corner => !closed && Some(faces.len()) == spec.corner_sector,
            Rule::Dart => false,
        };
        if !ok || t.valence(c) > 32 {
            return None;
        }
        let origin = spec.corners[k];
        if !insert(&mut at, origin, c.0) {
            return None;
        }
        let (mut lo, mut hi) = (0, 0);
        for &(i, h) in &faces {
            let g = t.he_face(h);
            if t.face_size(g) != spec.face_size {
                return None;
            }
            lo = lo.min(i);
            hi = hi.max(i);
            let corner = t.he_corner(h).index as usize;
            let ring = t.face(g);
            let m = ring.len();
            let vtx = |j: usize| ring[(corner + j) % m];
            // Corner 1 of the face (from the vertex) is along dir i, the
            // last one along dir i + 1, a quad's far corner at their sum.
            if !insert(&mut at, add(origin, dir(k, i)), vtx(1))
                || !insert(&mut at, add(origin, dir(k, i + 1)), vtx(m - 1))
            {
                return None;
            }
            if m == 4 && !insert(&mut at, add(origin, add(dir(k, i), dir(k, i + 1))), vtx(2)) {
                return None;
            }
        }
        if !closed {
            lines.push((origin, dir(k, lo)));
            lines.push((origin, dir(k, hi + 1)));
        }
    }
    // Phantom points by reflection across the crease lines (module docs),
    // repeated so a corner's diagonal point is reflected from a phantom.
    let lattice = spec.lattice;
    for _ in 0..3 {
        let mut progress = false;
        for &p in spec.points {
            if at.contains_key(&p) {
                continue;
            }
            for &(o, d) in &lines {
                let (px, py) = lattice.cartesian(p);
                let (ox, oy) = lattice.cartesian(o);
                let (dx, dy) = lattice.cartesian(d);
                let len2 = dx * dx + dy * dy;
                let (rx, ry) = (px - ox, py - oy);
                let along = (rx * dx + ry * dy) / len2;
                let (fx, fy) = (ox + along * dx, oy + along * dy); // foot on the line
                let mirror = lattice.to_lattice((2.0 * fx - px, 2.0 * fy - py));
                if mirror == p {
                    continue; // on the line itself
                }
                let Some(m) = at.get(&mirror).cloned() else { continue };
                // The lattice points on the line nearest to the foot.
                let a = lattice.to_lattice((fx - 0.5 * dx, fy - 0.5 * dy));
                let b = lattice.to_lattice((fx + 0.5 * dx, fy + 0.5 * dy));
                let on_lattice = lattice.to_lattice((fx, fy));
                let (ca, cb) = {
                    let (cx, cy) = lattice.cartesian(on_lattice);
                    if (cx - fx).abs() < 1e-9 && (cy - fy).abs() < 1e-9 {
                        (at.get(&on_lattice).cloned(), at.get(&on_lattice).cloned())
                    } else {
                        (at.get(&a).cloned(), at.get(&b).cloned())
                    }
                };
                let (Some(ca), Some(cb)) = (ca, cb) else { continue };
                let mut combo = ca;
                combo.extend(cb);
                combo.extend(m.iter().map(|&(v, w)| (v, -w)));
                at.insert(p, combo);
                progress = true;
                break;
            }
        }
        if !progress {
            break;
        }
    }
    spec.points.iter().map(|p| at.get(p).cloned()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_basis_is_a_partition_of_unity_with_derivatives_summing_to_zero() {
        for kind in [PatchKind::Bicubic, PatchKind::BoxSpline, PatchKind::Biquadratic] {
            for &(s, t) in &[(0.0, 0.0), (0.3, 0.2), (0.5, 0.5), (0.1, 0.7)] {
                let b = basis(kind, s, t);
                let n = kind.len();
                assert!((b.w[..n].iter().sum::<f64>() - 1.0).abs() < 1e-14);
                for d in [&b.ds, &b.dt, &b.dss, &b.dst, &b.dtt] {
                    assert!(d[..n].iter().sum::<f64>().abs() < 1e-13);
                }
            }
        }
    }

    #[test]
    fn basis_derivatives_match_central_differences() {
        let h = 1e-6;
        for kind in [PatchKind::Bicubic, PatchKind::BoxSpline, PatchKind::Biquadratic] {
            let (s, t) = (0.31, 0.27);
            let b = basis(kind, s, t);
            let (bs, bt) = (basis(kind, s + h, t), basis(kind, s, t + h));
            let (bs0, bt0) = (basis(kind, s - h, t), basis(kind, s, t - h));
            for k in 0..kind.len() {
                assert!(((bs.w[k] - bs0.w[k]) / (2.0 * h) - b.ds[k]).abs() < 1e-8);
                assert!(((bt.w[k] - bt0.w[k]) / (2.0 * h) - b.dt[k]).abs() < 1e-8);
                assert!(((bs.ds[k] - bs0.ds[k]) / (2.0 * h) - b.dss[k]).abs() < 1e-7);
                assert!(((bt.ds[k] - bt0.ds[k]) / (2.0 * h) - b.dst[k]).abs() < 1e-7);
                assert!(((bt.dt[k] - bt0.dt[k]) / (2.0 * h) - b.dtt[k]).abs() < 1e-7);
            }
        }
    }
}
