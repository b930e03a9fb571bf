//! File → Cheng and Zheng-Cai → measured error → two-level surface → PLY;
//! arrays → Deng-Wang → arrays. `cargo run -p subdiv --example pipeline -- MESH OUT_DIR`
use std::path::Path;
use subdiv::prelude::*;

/// Writes `OUT_DIR/{cheng,zheng-cai}.ply`; returns Deng-Wang's control points of a tetrahedron.
pub fn run(input: &Path, out_dir: &Path) -> Result<Vec<[f64; 3]>, Error> {
    let mesh = load_mesh(input)?;
    for method in [Method::Cheng, Method::ZhengCai] {
        let result = interpolate(&mesh, &MethodOptions::new(method))?;
        println!("{method}: {}", result.error_all(&mesh));
        let surface = result.surface(2)?;
        write_mesh(out_dir.join(format!("{method}.ply")), &surface, &WriteOptions::default().with_normals(true))?;
    }
    let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let tetrahedron = Mesh::from_arrays(&positions, &[[0u32, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])?;
    let result = interpolate(&tetrahedron, &MethodOptions::new(Method::DengWang))?;
    println!("deng-wang: {}", result.error_all(&tetrahedron));
    Ok(result.control.positions_to_arrays())
}

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().collect();
    let (input, out_dir) = match &args[..] {
        [_, input, out_dir] => (Path::new(input), Path::new(out_dir)),
        _ => (Path::new("fixtures/quad/spot_control_mesh.obj"), Path::new("target")),
    };
    println!("{} Deng-Wang control points", run(input, out_dir)?.len());
    Ok(())
}
