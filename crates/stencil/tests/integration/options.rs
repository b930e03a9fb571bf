//! The options and results of the crate seen from outside it, as a user sees
//! them. [`Options`] is `#[non_exhaustive]`: `Default` (or `Options::new`) and
//! the `with_*` setters are the only way to build one here (a struct literal
//! does not compile: the `compile_fail` doc-test on `Options`), so a new option
//! is not a breaking change. The results ([`LimitMatrix`], `LimitRows`,
//! `LevelSplit`, `Refinement`, `LevelSize`, `VertexStep`, `OutOfRange`)
//! are `#[non_exhaustive]` too: read through their fields, made by the crate
//! (a limit matrix also from its parts, [`LimitMatrix::new`]).

use subdiv_mesh::shapes;
use subdiv_stencil::{
    limit_matrix_catmull_clark, limit_matrix_doo_sabin, BoundaryInterpolation, CreaseMethod, FVarInterpolation,
    LimitMatrix, LoopBeta, Options, RowKind, Scheme, StencilError, SubdivisionPlan, Tension,
};

#[test]
fn options_are_built_from_default_and_setters_only() {
    let d = Options::default();
    assert_eq!(d, Options::new(Scheme::CatmullClark));
    assert_eq!(
        (d.boundary, d.crease_method, d.fvar),
        (BoundaryInterpolation::EdgeAndCorner, CreaseMethod::Uniform, FVarInterpolation::LinearAll)
    );

    let o = Options::default()
        .with_scheme(Scheme::Loop(LoopBeta::Loop))
        .with_boundary(BoundaryInterpolation::EdgeOnly)
        .with_crease_method(CreaseMethod::Chaikin)
        .with_fvar(FVarInterpolation::LinearBoundaries);
    assert_eq!(o.scheme, Scheme::Loop(LoopBeta::Loop));
    assert_eq!(
        (o.boundary, o.crease_method, o.fvar),
        (BoundaryInterpolation::EdgeOnly, CreaseMethod::Chaikin, FVarInterpolation::LinearBoundaries)
    );
    // Each setter changes its own field only.
    assert_eq!(o.with_scheme(Scheme::DooSabin).boundary, BoundaryInterpolation::EdgeOnly);
    assert_eq!(Options::from(Scheme::DooSabin).with_boundary(BoundaryInterpolation::None).scheme, Scheme::DooSabin);
    // Built options are used as before, and validated once.
    assert!(Options::default().with_scheme(Scheme::DengMa(Tension::Global(2.0))).validate().is_err());
    let plan = SubdivisionPlan::new(shapes::cube().topology(), Options::default().with_scheme(Scheme::DooSabin), 1);
    assert_eq!(plan.unwrap().topology().face_count(), 6 + 12 + 8);
}

#[test]
fn a_limit_matrix_is_rebuilt_from_its_parts() {
    let grid = shapes::quad_grid(4, 3);
    for m in [limit_matrix_catmull_clark(grid.topology()), limit_matrix_doo_sabin(grid.topology())] {
        let rebuilt = LimitMatrix::new(m.d.clone(), m.s.clone(), m.boundary_rows.clone(), m.row_kinds.clone()).unwrap();
        assert_eq!((&rebuilt.boundary_rows, &rebuilt.row_kinds), (&m.boundary_rows, &m.row_kinds));
        assert_eq!(rebuilt.to_csr(), m.to_csr());
    }
}

#[test]
fn limit_matrix_parts_are_checked() {
    let m = limit_matrix_catmull_clark(shapes::quad_grid(3, 3).topology());
    let n = m.size();
    let refused = |d: Vec<f64>, rows: Vec<u32>, kinds: Vec<RowKind>| match LimitMatrix::new(d, m.s.clone(), rows, kinds)
    {
        Err(StencilError::InvalidParameter(why)) => why,
        other => panic!("accepted: {other:?}"),
    };
    let (d, rows, kinds) = (m.d.clone(), m.boundary_rows.clone(), m.row_kinds.clone());
    assert!(refused(d[1..].to_vec(), rows.clone(), kinds.clone()).contains("D entries"));
    assert!(refused(d.clone(), rows.clone(), kinds[1..].to_vec()).contains("row kinds"));
    let mut negative = d.clone();
    negative[2] = -1.0;
    assert!(refused(negative, rows.clone(), kinds.clone()).contains("D[2]"));
    let reversed: Vec<u32> = rows.iter().rev().copied().collect();
    assert!(refused(d.clone(), reversed, kinds.clone()).contains("not ascending"));
    assert!(refused(d.clone(), vec![n as u32], kinds.clone()).contains("out of range"));
    // An interior (smooth) row cannot be in the sharp block.
    let smooth = m.rows_of(RowKind::Smooth)[0];
    let mut with_smooth = rows.clone();
    with_smooth.push(smooth);
    with_smooth.sort_unstable();
    assert!(refused(d.clone(), with_smooth, kinds.clone()).contains("of kind Smooth"));
    // A crease row alone: its columns (its neighbours on the crease) leave the block.
    let crease = m.rows_of(RowKind::Crease)[0];
    assert!(refused(d, vec![crease], kinds).contains("outside the boundary rows"));
}
