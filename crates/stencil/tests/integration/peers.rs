//! Differential tests against established libraries (OpenSubdiv, libigl, CGAL).
//!
//! The reference outputs live in `fixtures/peer/<mesh>/` (see its README); a
//! few large ones only in `../shared/peer-outputs/`, read when present. The
//! peers number vertices and faces their own way, so subdivided meshes are
//! compared as point sets (nearest neighbour both ways) plus vertex count,
//! face count and face-size histogram; limit points are compared row by row
//! in input order. Every deviation is relative to the input's bounding-box
//! diagonal d and must be ≤ 1e-9 (the peers agree with an independent
//! implementation to ~1e-16·d).
//!
//! The test prints the full table (scheme × mesh × level × max deviation/d)
//! with `--nocapture`.

use crate::common;

use glam::DVec3;
use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;
use subdiv_mesh::FaceList;
use subdiv_stencil::{apply, catmull_clark, loop_subdivision, LoopBeta, Scheme, SubdivisionPlan};

/// Largest accepted deviation, relative to d.
const TOL_REL: f64 = 1e-9;

/// A peer's subdivided mesh: one file per level.
struct PeerSurface {
    label: &'static str,
    file_prefix: &'static str,
    scheme: Scheme,
}

const SURFACES: [PeerSurface; 4] = [
    PeerSurface {
        label: "catmull-clark (OpenSubdiv)",
        file_prefix: "opensubdiv-catmull-clark",
        scheme: Scheme::CatmullClark,
    },
    PeerSurface {
        label: "loop orig-β (OpenSubdiv)",
        file_prefix: "opensubdiv-loop-origbeta",
        scheme: Scheme::Loop(LoopBeta::Loop),
    },
    PeerSurface {
        label: "loop Warren-β (libigl)",
        file_prefix: "libigl-loop-warren",
        scheme: Scheme::Loop(LoopBeta::Warren),
    },
    PeerSurface { label: "doo-sabin (CGAL)", file_prefix: "cgal-doo-sabin", scheme: Scheme::DooSabin },
];

#[derive(Clone, Copy, PartialEq)]
enum LimitKind {
    CatmullClark,
    LoopOrig,
}

const LIMITS: [(&str, &str, LimitKind); 2] = [
    ("catmull-clark limit (OpenSubdiv)", "opensubdiv-catmull-clark-limit.txt", LimitKind::CatmullClark),
    ("loop orig-β limit (OpenSubdiv)", "opensubdiv-loop-origbeta-limit.txt", LimitKind::LoopOrig),
];

fn peer_dirs() -> Vec<PathBuf> {
    vec![common::fixtures().join("peer"), common::shared().join("peer-outputs")]
}

/// Mesh folders: every folder of `fixtures/peer` and of the shared copy,
/// except `timing-meshes` (inputs of the timing table) and `creases`
/// (OpenSubdiv with crease/corner tags and face-varying data: one folder per
/// tagged case, with its own conventions; not untagged surfaces) and
/// `creases-interpolation` (OpenSubdiv's limits of our interpolating control
/// meshes, `subdiv-cli`'s `creases_opensubdiv` test).
fn peer_meshes() -> Vec<String> {
    let mut names = std::collections::BTreeSet::new();
    for dir in peer_dirs() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if e.path().is_dir() && !["timing-meshes", "creases", "creases-interpolation"].contains(&name.as_str()) {
                names.insert(name);
            }
        }
    }
    names.into_iter().collect()
}

/// A peer file, from the repository copy first, else from the shared copy.
fn peer_file(mesh: &str, file: &str) -> Option<PathBuf> {
    peer_dirs().into_iter().map(|d| d.join(mesh).join(file)).find(|p| p.is_file())
}

fn face_histogram(faces: &FaceList) -> BTreeMap<usize, usize> {
    let mut h = BTreeMap::new();
    for f in faces.iter() {
        *h.entry(f.len()).or_insert(0) += 1;
    }
    h
}

/// Uniform grid hash over a point set, for nearest-neighbour queries.
struct PointGrid<'a> {
    points: &'a [DVec3],
    origin: DVec3,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl<'a> PointGrid<'a> {
    fn new(points: &'a [DVec3], scale: f64) -> Self {
        let origin = points.iter().fold(DVec3::splat(f64::INFINITY), |a, &p| a.min(p));
        // Points sample a surface: spacing ~ scale/√n.
        let cell = (2.0 * scale / (points.len() as f64).sqrt()).max(1e-300);
        let mut g = Self { points, origin, cell, cells: HashMap::new() };
        for (i, &p) in points.iter().enumerate() {
            let key = g.key(p);
            g.cells.entry(key).or_default().push(i as u32);
        }
        g
    }

    fn key(&self, p: DVec3) -> [i64; 3] {
        let q = ((p - self.origin) / self.cell).floor();
        [q.x as i64, q.y as i64, q.z as i64]
    }

    /// Distance from `q` to the nearest point of the set.
    fn nearest(&self, q: DVec3) -> f64 {
        let k = self.key(q);
        let mut best = f64::INFINITY;
        const RINGS: i64 = 2;
        for dx in -RINGS..=RINGS {
            for dy in -RINGS..=RINGS {
                for dz in -RINGS..=RINGS {
                    if let Some(ids) = self.cells.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) {
                        for &i in ids {
                            best = best.min(self.points[i as usize].distance(q));
                        }
                    }
                }
            }
        }
        // Anything outside the searched block is at least RINGS cells away.
        if best <= RINGS as f64 * self.cell {
            best
        } else {
            self.points.iter().map(|p| p.distance(q)).fold(f64::INFINITY, f64::min)
        }
    }
}

/// Symmetric nearest-neighbour (Hausdorff) distance between two point sets.
fn point_set_distance(a: &[DVec3], b: &[DVec3], scale: f64) -> f64 {
    let (ga, gb) = (PointGrid::new(a, scale), PointGrid::new(b, scale));
    let ab = a.iter().map(|&p| gb.nearest(p)).fold(0.0, f64::max);
    let ba = b.iter().map(|&p| ga.nearest(p)).fold(0.0, f64::max);
    ab.max(ba)
}

fn read_points(path: &PathBuf) -> Vec<DVec3> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().expect("a number")).collect();
            assert_eq!(v.len(), 3, "{}: `{l}` is not `x y z`", path.display());
            DVec3::new(v[0], v[1], v[2])
        })
        .collect()
}

struct Row {
    scheme: String,
    mesh: String,
    closed: bool,
    level: String,
    ours: String,
    peer: String,
    dev_rel: f64,
    ok: bool,
}

/// Every comparison for one mesh folder. Returns table rows and failures.
fn compare_mesh(name: &str, rows: &mut Vec<Row>, failures: &mut Vec<String>, skips: &mut Vec<String>) {
    let Some(input_path) = common::find_mesh(name) else {
        skips.push(format!("{name}: input mesh not found in fixtures/ or ../shared/meshes/, skipped"));
        return;
    };
    let input = common::load(&input_path);
    let t = input.topology();
    let d = input.bbox_diagonal();
    let closed = t.is_closed();
    let triangles = t.faces().all_of_size(3);

    for s in &SURFACES {
        for level in 1..=2usize {
            let file = format!("{}-L{level}.obj", s.file_prefix);
            let Some(path) = peer_file(name, &file) else {
                let other = format!("{}-L{}.obj", s.file_prefix, 3 - level);
                if peer_file(name, &other).is_some() {
                    skips.push(format!("{name}/{file}: not in fixtures/peer nor ../shared/peer-outputs, skipped"));
                }
                continue;
            };
            if matches!(s.scheme, Scheme::Loop(_)) && !triangles {
                failures.push(format!("{name}: peer has {file} but the input is not a triangle mesh"));
                continue;
            }
            let peer = common::load(&path);
            let plan = SubdivisionPlan::new(t, s.scheme, level).expect("scheme applies to the fixture");
            let ours = plan.apply(input.positions());
            let ours_t = plan.topology();
            let dev = point_set_distance(&ours, peer.positions(), d) / d;
            let (oh, ph) = (face_histogram(ours_t.faces()), face_histogram(peer.topology().faces()));
            let counts_ok = ours.len() == peer.positions().len() && ours_t.face_count() == peer.topology().face_count();
            let ok = dev <= TOL_REL && counts_ok && oh == ph;
            if !ok {
                failures.push(format!(
                    "{name} {} L{level}: max deviation {dev:.3e}·d, ours V={} F={} {:?}, peer V={} F={} {:?}",
                    s.label,
                    ours.len(),
                    ours_t.face_count(),
                    oh,
                    peer.positions().len(),
                    peer.topology().face_count(),
                    ph
                ));
            }
            rows.push(Row {
                scheme: s.label.to_string(),
                mesh: name.to_string(),
                closed,
                level: format!("L{level}"),
                ours: format!("{}/{}", ours.len(), ours_t.face_count()),
                peer: format!("{}/{}", peer.positions().len(), peer.topology().face_count()),
                dev_rel: dev,
                ok,
            });
        }
    }

    for (label, file, kind) in LIMITS {
        let Some(path) = peer_file(name, file) else { continue };
        let peer = read_points(&path);
        let stencil = match kind {
            LimitKind::CatmullClark => catmull_clark::limit_stencil(t),
            LimitKind::LoopOrig => loop_subdivision::limit_stencil(t, LoopBeta::Loop).expect("a triangle mesh"),
        };
        let ours = apply(&stencil, input.positions());
        let ok_len = ours.len() == peer.len();
        // Row i against line i: input order is part of the contract.
        let dev = ours.iter().zip(&peer).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max) / d;
        let ok = ok_len && dev <= TOL_REL;
        if !ok {
            let worst = ours
                .iter()
                .zip(&peer)
                .enumerate()
                .max_by(|x, y| x.1 .0.distance(*x.1 .1).total_cmp(&y.1 .0.distance(*y.1 .1)))
                .map(|(i, (a, b))| format!("worst vertex {i}: ours {a}, peer {b}"))
                .unwrap_or_default();
            failures.push(format!(
                "{name} {label}: {} vs {} rows, max deviation {dev:.3e}·d; {worst}",
                ours.len(),
                peer.len()
            ));
        }
        rows.push(Row {
            scheme: label.to_string(),
            mesh: name.to_string(),
            closed,
            level: "limit".into(),
            ours: format!("{} pts", ours.len()),
            peer: format!("{} pts", peer.len()),
            dev_rel: dev,
            ok,
        });
    }
}

#[test]
fn subdivided_meshes_and_limit_points_match_the_peers() {
    let meshes = peer_meshes();
    assert!(meshes.len() >= 15, "expected the peer fixtures, found {meshes:?}");
    let (mut rows, mut failures, mut skips) = (Vec::new(), Vec::new(), Vec::new());
    // Two workers: the meshes are independent and the machine has 2 cores.
    let results: Vec<_> = std::thread::scope(|s| {
        let chunks: Vec<Vec<String>> = (0..2).map(|k| meshes.iter().skip(k).step_by(2).cloned().collect()).collect();
        let handles: Vec<_> = chunks
            .into_iter()
            .map(|chunk| {
                s.spawn(move || {
                    let (mut r, mut f, mut sk) = (Vec::new(), Vec::new(), Vec::new());
                    for m in &chunk {
                        compare_mesh(m, &mut r, &mut f, &mut sk);
                    }
                    (r, f, sk)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().expect("worker panicked")).collect()
    });
    for (r, f, s) in results {
        rows.extend(r);
        failures.extend(f);
        skips.extend(s);
    }
    rows.sort_by(|a, b| (&a.scheme, &a.mesh, &a.level).cmp(&(&b.scheme, &b.mesh, &b.level)));

    eprintln!("\n| scheme | mesh | closed | level | ours V/F | peer V/F | max dev / d | ok |");
    eprintln!("|---|---|---|---|---|---|---|---|");
    for r in &rows {
        eprintln!(
            "| {} | {} | {} | {} | {} | {} | {:.2e} | {} |",
            r.scheme,
            r.mesh,
            if r.closed { "closed" } else { "open" },
            r.level,
            r.ours,
            r.peer,
            r.dev_rel,
            if r.ok { "yes" } else { "NO" }
        );
    }
    for s in &skips {
        eprintln!("SKIP {s}");
    }
    // Every folder has at least the Catmull-Clark level-1 output and limit.
    for m in &meshes {
        for needed in ["catmull-clark (OpenSubdiv)", "catmull-clark limit (OpenSubdiv)"] {
            assert!(rows.iter().any(|r| &r.mesh == m && r.scheme == needed), "{m}: no {needed} comparison ran");
        }
    }
    // Every peer and scheme is compared on several meshes of `fixtures/peer`
    // alone (a fresh clone, without `../shared`).
    let labels = SURFACES.iter().map(|s| s.label).chain(LIMITS.iter().map(|l| l.0));
    for label in labels {
        let from_fixtures = |r: &&Row| r.scheme == label && common::fixtures().join("peer").join(&r.mesh).is_dir();
        let n = rows.iter().filter(from_fixtures).count();
        assert!(n >= 3, "{label}: only {n} comparison(s) on the repository's fixtures");
    }
    assert!(failures.is_empty(), "{} peer comparison(s) failed:\n{}", failures.len(), failures.join("\n"));
}

/// The nearest-neighbour comparison itself must notice a moved point, a
/// missing point and a mismatch in the far corner of the grid.
#[test]
fn point_set_distance_detects_differences() {
    let grid: Vec<DVec3> = (0..400).map(|i| DVec3::new((i % 20) as f64, (i / 20) as f64, 0.0)).collect();
    let mut moved = grid.clone();
    moved.reverse();
    assert_eq!(point_set_distance(&grid, &moved, 28.0), 0.0);
    moved[7].z += 1e-6;
    assert!((point_set_distance(&grid, &moved, 28.0) - 1e-6).abs() < 1e-12);
    let mut far = grid.clone();
    far[0] = DVec3::new(100.0, 100.0, 100.0);
    let d = point_set_distance(&grid, &far, 28.0);
    let expect = DVec3::new(100.0, 100.0, 100.0).distance(DVec3::new(19.0, 19.0, 0.0));
    assert!((d - expect).abs() < 1e-9, "{d} vs {expect}");
}

/// Sensitivity check on real data: the two Loop β choices differ by far more
/// than the tolerance at valence 5, and the comparison sees it (so a zero
/// deviation in the table is agreement, not a blind comparison).
#[test]
fn comparison_tells_the_two_loop_betas_apart() {
    let input = common::fixture("icosphere_2");
    let d = input.bbox_diagonal();
    let orig = common::load(&peer_file("icosphere_2", "opensubdiv-loop-origbeta-L1.obj").expect("fixture"));
    let warren = common::load(&peer_file("icosphere_2", "libigl-loop-warren-L1.obj").expect("fixture"));
    let ours = |beta| SubdivisionPlan::new(input.topology(), Scheme::Loop(beta), 1).unwrap().apply(input.positions());
    let (w, o) = (ours(LoopBeta::Warren), ours(LoopBeta::Loop));
    assert!(point_set_distance(&w, warren.positions(), d) / d <= TOL_REL);
    assert!(point_set_distance(&o, orig.positions(), d) / d <= TOL_REL);
    let cross = point_set_distance(&w, orig.positions(), d) / d;
    assert!(cross > 1e-4, "Warren vs Loop β differ by only {cross:e}·d");
}
