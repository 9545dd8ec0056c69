use super::*;

/// A sliding node on a symmetry plane (x prescribed) against a target
/// segment whose normal is tilted against the plane: the multiplier
/// takes up the free component, and a force it can carry leaves no
/// residual at the node or at the target.
#[test]
fn equilibrium_residual_on_a_symmetry_plane() {
    let (nx, ny) = (0.0654f64, 0.9979f64);
    let m = 300.0;
    let c = ContactSystem {
        rows: vec![contact::Row {
            dofs: contact::Entries::from_slice(&[(0, nx), (1, ny), (2, -nx), (3, -ny)]),
            rhs: 0.0,
            column: contact::Entries::default(),
        }],
        groups: vec![(0, 0..1)],
        ..Default::default()
    };
    let eq = [PRESCRIBED, 0, 1, 2];
    // The free entries of C^T m: node y, target x and y.
    let rhs = [ny * m, -nx * m, -ny * m];
    let out = equilibrium_residual(&c, &eq, &rhs);
    assert!(out.iter().all(|v| v.abs() <= 1e-12 * m), "{out:?}");
    // A force the row cannot carry (along the target, at the target
    // node) stays.
    let rhs = [ny * m, -nx * m + 5.0, -ny * m];
    let out = equilibrium_residual(&c, &eq, &rhs);
    assert!(
        (out[1] - 5.0).abs() <= 1e-9 && out[0].abs() <= 1e-9,
        "{out:?}"
    );
}

/// A node's multipliers in closed form (one row; two rows of a
/// sticking node) agree with the SVD's pseudo-inverse to round-off,
/// and singular cases (a zero column, two parallel rows, below the
/// cut-off or not) take the SVD's cut-off.
#[test]
fn node_multipliers_are_the_pseudo_inverse() {
    use nalgebra::{DMatrix, DVector};
    let cases: Vec<(DMatrix<f64>, DVector<f64>)> = vec![
        (
            DMatrix::from_row_slice(2, 1, &[0.3, -0.95]),
            DVector::from_row_slice(&[2.0, 7.0]),
        ),
        (
            DMatrix::from_row_slice(1, 1, &[-0.4]),
            DVector::from_row_slice(&[3.0]),
        ),
        (
            DMatrix::from_row_slice(2, 1, &[0.0, 0.0]),
            DVector::from_row_slice(&[1.0, 1.0]),
        ),
        (
            DMatrix::from_row_slice(2, 2, &[0.3, -0.95, 0.95, 0.3]),
            DVector::from_row_slice(&[2.0, -7.0]),
        ),
        (
            DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 2.0, 3.0]),
            DVector::from_row_slice(&[0.25, 4.0]),
        ),
        // Parallel rows: rank 1.
        (
            DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 0.5, 1.0]),
            DVector::from_row_slice(&[1.0, -3.0]),
        ),
        // Nearly parallel: the smaller singular value below the cut-off.
        (
            DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 0.5, 1.0 + 1e-14]),
            DVector::from_row_slice(&[1.0, -3.0]),
        ),
        // One component, two rows.
        (
            DMatrix::from_row_slice(1, 2, &[0.6, 0.8]),
            DVector::from_row_slice(&[5.0]),
        ),
    ];
    for (c, r) in cases {
        let eps = 1e-12 * c.abs().max();
        let svd = c.clone().svd(true, true).solve(&r, eps).unwrap();
        let mu = node_multipliers(&c, &r, eps).unwrap();
        let scale = svd.amax().max(1.0);
        assert!(
            (&mu - &svd).amax() <= 1e-14 * scale,
            "C {c} r {r}: {mu} against {svd}"
        );
    }
}
