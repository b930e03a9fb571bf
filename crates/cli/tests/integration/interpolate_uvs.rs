//! Texture coordinates through `subdiv interpolate`: the control mesh keeps
//! the input's UVs (refined by one level where it is a refined mesh) and
//! `--surface` writes them, with the seams where the input has them.

use crate::common::{fixtures, read, run_ok, Scratch};
use std::collections::{BTreeSet, HashMap};
use subdiv_mesh::PolygonSoup;

/// The seam edges of a soup, as vertex pairs (a < b): interior edges whose
/// two faces give different UV values at either end (compared by value).
fn seam_edges(soup: &PolygonSoup) -> BTreeSet<(u32, u32)> {
    let uvs = soup.uvs.as_ref().expect("the file has UVs");
    // (a, b) directed → (uv at a, uv at b) in that face.
    let mut sides: HashMap<(u32, u32), ([u64; 2], [u64; 2])> = HashMap::new();
    let mut corner = 0usize;
    for face in soup.faces.iter() {
        let m = face.len();
        for k in 0..m {
            let (a, b) = (face[k], face[(k + 1) % m]);
            let uv = |c: usize| {
                let v = uvs.values[uvs.indices[c] as usize];
                [v.x.to_bits(), v.y.to_bits()]
            };
            sides.insert((a, b), (uv(corner + k), uv(corner + (k + 1) % m)));
        }
        corner += m;
    }
    let mut seams = BTreeSet::new();
    for (&(a, b), &(ua, ub)) in &sides {
        if let Some(&(vb, va)) = sides.get(&(b, a)) {
            if a < b && (ua != va || ub != vb) {
                seams.insert((a, b));
            }
        }
    }
    seams
}

/// Per vertex, how many distinct UV values its corners use.
fn values_per_vertex(soup: &PolygonSoup) -> Vec<usize> {
    let uvs = soup.uvs.as_ref().expect("the file has UVs");
    let mut sets: Vec<BTreeSet<[u64; 2]>> = vec![BTreeSet::new(); soup.positions.len()];
    for (c, &v) in soup.faces.indices().iter().enumerate() {
        let uv = uvs.values[uvs.indices[c] as usize];
        sets[v as usize].insert([uv.x.to_bits(), uv.y.to_bits()]);
    }
    sets.iter().map(BTreeSet::len).collect()
}

/// Catmull-Clark methods (cheng, and deng-ma on the same split): the seams
/// of the surface are exactly the descendants of the input's: at level L
/// each input seam edge is 2^L surface seam edges and no other edge is one,
/// and every input vertex keeps as many UV values (siblings) as it had.
#[test]
fn surface_keeps_the_seams_of_a_uv_quad_mesh() {
    let scratch = Scratch::new("uvs");
    let input_path = fixtures().join("peer/creases/spot_uv/spot_uv.obj");
    let input = read(&input_path);
    let input_seams = seam_edges(&input);
    assert!(input_seams.len() > 10, "spot has seams");
    let input_values = values_per_vertex(&input);
    for method in ["cheng", "deng-ma"] {
        for (levels, fvar) in [(1usize, "linear-all"), (2, "linear-none"), (2, "linear-corners-only")] {
            let surface = scratch.path(&format!("spot-{method}-{levels}-{fvar}.obj"));
            let control = scratch.path(&format!("spot-{method}-control.obj"));
            run_ok(&[
                "interpolate",
                input_path.to_str().unwrap(),
                "--method",
                method,
                "--fvar",
                fvar,
                "--levels",
                &levels.to_string(),
                "--surface",
                surface.to_str().unwrap(),
                "-o",
                control.to_str().unwrap(),
            ]);
            let s = read(&surface);
            assert!(s.uvs.is_some(), "{method}: the surface has UVs");
            assert_eq!(
                seam_edges(&s).len(),
                input_seams.len() << levels,
                "{method}, {fvar}: seam edges at level {levels}"
            );
            let values = values_per_vertex(&s);
            assert_eq!(
                &values[..input_values.len()],
                &input_values[..],
                "{method}, {fvar}: siblings of input vertices"
            );
            if method == "cheng" {
                // The control mesh has the input's topology: its UVs are the input's, bit for bit.
                let c = read(&control);
                assert_eq!(seam_edges(&c), input_seams);
                assert_eq!(c.uvs, input.uvs);
            }
        }
    }
}

/// Doo-Sabin methods: the UVs of a seamless chart follow the control mesh
/// (M⁰ for nasri, M¹ refined by one Doo-Sabin step for zheng-cai and
/// fan-cheng-lai) and the surface; a chart with seams has no Doo-Sabin rule
/// (corner images of two charts would mix) — the positions are written and
/// a warning says the UVs are not.
#[test]
fn doo_sabin_methods_carry_seamless_uvs_and_warn_about_seams() {
    let scratch = Scratch::new("uvs");
    let grid = fixtures().join("peer/creases/uv_grid/uv_grid.obj");
    let spot = fixtures().join("peer/creases/spot_uv/spot_uv.obj");
    for method in ["nasri", "zheng-cai", "fan-cheng-lai"] {
        let control = scratch.path(&format!("grid-{method}-control.obj"));
        let surface = scratch.path(&format!("grid-{method}-surface.obj"));
        let stderr = run_ok(&[
            "interpolate",
            grid.to_str().unwrap(),
            "--method",
            method,
            "-o",
            control.to_str().unwrap(),
            "--surface",
            surface.to_str().unwrap(),
            "--levels",
            "2",
        ]);
        assert!(!stderr.contains("texture coordinates"), "{method}: {stderr}");
        let c = read(&control);
        let uvs = c.uvs.as_ref().unwrap_or_else(|| panic!("{method}: the control mesh has UVs"));
        assert_eq!(uvs.indices.len(), c.faces.indices().len());
        assert!(read(&surface).uvs.is_some(), "{method}: the surface has UVs");
        let stderr = run_ok(&[
            "interpolate",
            spot.to_str().unwrap(),
            "--method",
            method,
            "--surface",
            surface.to_str().unwrap(),
            "--levels",
            "1",
        ]);
        assert!(stderr.contains("texture coordinates"), "{method}: {stderr}");
        assert!(read(&surface).uvs.is_none());
    }
}
