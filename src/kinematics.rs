//! The element integrator: strain-displacement relations of the three
//! analysis kinds under small strain and total Lagrangian kinematics, the
//! internal force vector and the consistent tangent (material + geometric).

use crate::element::{MAX_NODES, gauss_points, shape};
use crate::material::{MaterialLaw, Tangent, Voigt};
use crate::mesh::ElementKind;
use crate::problem::{AnalysisKind, Kinematics};
use std::f64::consts::PI;

/// Element degrees of freedom at most (Q8).
pub const MAX_DOFS: usize = 2 * MAX_NODES;

pub type ElementVector = [f64; MAX_DOFS];
pub type ElementMatrix = [[f64; MAX_DOFS]; MAX_DOFS];

/// Why an element could not be evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElementError {
    #[error(
        "element {element}: reference Jacobian {det:e} <= 0 at a Gauss point (distorted or clockwise element)"
    )]
    BadJacobian { element: usize, det: f64 },
    #[error("element {element}: deformation gradient determinant {det:e} <= 0 (element inverted)")]
    Inverted { element: usize, det: f64 },
    #[error("element {element}: non-finite stress from the material law")]
    NonFinite { element: usize },
}

/// What the integrator needs of one element.
pub struct ElementData<'a> {
    pub index: usize,
    pub kind: ElementKind,
    pub x0: &'a [[f64; 2]],
    pub u: &'a [[f64; 2]],
    pub law: &'a dyn MaterialLaw,
    /// Converged history of every Gauss point in; updated history out.
    pub history: &'a mut [f64],
    pub initial_stress: Voigt,
    /// Body force per unit reference volume.
    pub body_force: [f64; 2],
    /// The element's `reference_geometry`, when kept; computed otherwise.
    pub geometry: Option<&'a [f64]>,
}

/// Geometry of one Gauss point in the reference configuration.
struct Point {
    n: [f64; MAX_NODES],
    /// dN/dX
    g: [[f64; 2]; MAX_NODES],
    /// Reference radius (axisymmetric) or 0.
    r: f64,
    /// Reference volume weight: det J * w * (thickness or 2 pi r).
    dv: f64,
}

fn point(
    kind: ElementKind,
    index: usize,
    x0: &[[f64; 2]],
    xi: [f64; 2],
    w: f64,
    analysis: AnalysisKind,
) -> Result<Point, ElementError> {
    let nn = kind.node_count();
    let s = shape(kind, xi[0], xi[1]);
    // j[i][k] = dX_i / dxi_k, and the radius.
    let (j, r) = match kind {
        ElementKind::Q4 => gradient::<4>(x0, &s.dn, &s.n),
        ElementKind::Q8 => gradient::<8>(x0, &s.dn, &s.n),
    };
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    if det <= 0.0 || !det.is_finite() {
        return Err(ElementError::BadJacobian {
            element: index,
            det,
        });
    }
    // dN/dX = J^-T dN/dxi
    let inv = [
        [j[1][1] / det, -j[0][1] / det],
        [-j[1][0] / det, j[0][0] / det],
    ];
    let mut g = [[0.0; 2]; MAX_NODES];
    for a in 0..nn {
        g[a][0] = s.dn[a][0] * inv[0][0] + s.dn[a][1] * inv[1][0];
        g[a][1] = s.dn[a][0] * inv[0][1] + s.dn[a][1] * inv[1][1];
    }
    let factor = match analysis {
        AnalysisKind::PlaneStrain { thickness } | AnalysisKind::PlaneStress { thickness } => {
            thickness
        }
        AnalysisKind::Axisymmetric => {
            if r <= 0.0 {
                return Err(ElementError::BadJacobian {
                    element: index,
                    det: r,
                });
            }
            2.0 * PI * r
        }
    };
    Ok(Point {
        n: s.n,
        g,
        r,
        dv: det * w * factor,
    })
}

impl Point {
    /// Numbers per Gauss point in `reference_geometry`'s list: N, dN/dX,
    /// the radius and the volume weight.
    fn stride(nn: usize) -> usize {
        3 * nn + 2
    }

    fn write(&self, nn: usize, out: &mut Vec<f64>) {
        out.extend_from_slice(&self.n[..nn]);
        out.extend(self.g[..nn].iter().flatten());
        out.extend([self.r, self.dv]);
    }

    fn read(list: &[f64], nn: usize) -> Point {
        let mut p = Point {
            n: [0.0; MAX_NODES],
            g: [[0.0; 2]; MAX_NODES],
            r: list[3 * nn],
            dv: list[3 * nn + 1],
        };
        p.n[..nn].copy_from_slice(&list[..nn]);
        for a in 0..nn {
            p.g[a] = [list[nn + 2 * a], list[nn + 2 * a + 1]];
        }
        p
    }
}

/// The length of an element's `reference_geometry`.
pub fn geometry_len(kind: ElementKind) -> usize {
    gauss_points(kind).len() * Point::stride(kind.node_count())
}

/// The reference geometry of an element's Gauss points (N, dN/dX, the
/// radius, the volume weight), appended to `out`: the mesh fixes it, so
/// the assembly computes it once (`ElementData::geometry`) instead of at
/// every residual. Bit for bit what `integrate` computes without it.
pub fn reference_geometry(
    analysis: AnalysisKind,
    kind: ElementKind,
    index: usize,
    x0: &[[f64; 2]],
    out: &mut Vec<f64>,
) -> Result<(), ElementError> {
    let nn = kind.node_count();
    for (xi, w) in gauss_points(kind).iter() {
        point(kind, index, x0, xi, w, analysis)?.write(nn, out);
    }
    Ok(())
}

/// Result of integrating one element.
pub struct ElementOutput {
    /// Internal force minus body force.
    pub f: ElementVector,
    pub k: ElementMatrix,
    /// Volume-averaged Cauchy stress [xx, yy, zz, xy].
    pub cauchy: Voigt,
}

/// Internal force vector, tangent (when `tangent`) and average Cauchy stress
/// of one element at displacement `d.u`.
pub fn integrate(
    analysis: AnalysisKind,
    kinematics: Kinematics,
    d: &mut ElementData,
    tangent: bool,
    out: &mut ElementOutput,
) -> Result<(), ElementError> {
    // The node count a constant of each kind's copy, its loops unrolled:
    // the same operations in the same order (Hertz q4 at 1e4 unknowns, the
    // increment's three assemblies: 6.5-7.6 ms to 5.5-6.3 ms).
    match d.kind {
        ElementKind::Q4 => integrate_kind::<4>(analysis, kinematics, d, tangent, out),
        ElementKind::Q8 => integrate_kind::<8>(analysis, kinematics, d, tangent, out),
    }
}

fn integrate_kind<const NN: usize>(
    analysis: AnalysisKind,
    kinematics: Kinematics,
    d: &mut ElementData,
    tangent: bool,
    out: &mut ElementOutput,
) -> Result<(), ElementError> {
    debug_assert_eq!(d.kind.node_count(), NN);
    let nn = NN;
    let nd = 2 * NN;
    let axi = matches!(analysis, AnalysisKind::Axisymmetric);
    let tl = kinematics == Kinematics::TotalLagrangian;
    let hl = d.law.history_len();
    out.f = [0.0; MAX_DOFS];
    if tangent {
        for row in out.k.iter_mut().take(nd) {
            row[..nd].fill(0.0);
        }
    }
    out.cauchy = [0.0; 4];
    let mut volume = 0.0;
    for (gp, (xi, w)) in gauss_points(d.kind).iter().enumerate() {
        let p = match d.geometry {
            Some(list) => {
                let stride = Point::stride(nn);
                Point::read(&list[gp * stride..(gp + 1) * stride], nn)
            }
            None => point(d.kind, d.index, d.x0, xi, w, analysis)?,
        };
        let Strain { f, f33, strain } = strain_at::<NN>(&p, d.u, axi, tl);
        let det_f = (f[0][0] * f[1][1] - f[0][1] * f[1][0]) * f33;
        if tl && det_f <= 0.0 {
            return Err(ElementError::Inverted {
                element: d.index,
                det: det_f,
            });
        }
        let mut s: Voigt = [0.0; 4];
        let mut c: Tangent = [[0.0; 4]; 4];
        d.law.evaluate(
            &strain,
            &mut d.history[gp * hl..(gp + 1) * hl],
            &mut s,
            &mut c,
        );
        for i in 0..4 {
            s[i] += d.initial_stress[i];
        }
        if s.iter().any(|v| !v.is_finite()) {
            return Err(ElementError::NonFinite { element: d.index });
        }
        let b = strain_variation::<NN>(&p, f, f33, axi);
        for q in 0..nd {
            let mut v = 0.0;
            for r in 0..4 {
                v += b[r][q] * s[r];
            }
            out.f[q] += v * p.dv;
        }
        for a in 0..nn {
            out.f[2 * a] -= p.n[a] * d.body_force[0] * p.dv;
            out.f[2 * a + 1] -= p.n[a] * d.body_force[1] * p.dv;
        }
        if tangent {
            add_material_tangent::<NN>(&b, &c, p.dv, &mut out.k);
            if tl {
                add_geometric_tangent::<NN>(&p, &s, axi, &mut out.k);
            }
        }
        // Cauchy stress sigma = F S F^T / det F; in plane stress det F takes the
        // law's thickness stretch where it defines one (1 otherwise).
        let det_f = match (analysis, tl) {
            (AnalysisKind::PlaneStress { .. }, true) => {
                det_f * d.law.thickness_stretch(&strain).unwrap_or(1.0)
            }
            _ => det_f,
        };
        let sigma = if tl { cauchy(f, f33, &s, det_f) } else { s };
        for i in 0..4 {
            out.cauchy[i] += sigma[i] * p.dv;
        }
        volume += p.dv;
    }
    for v in out.cauchy.iter_mut() {
        *v /= volume;
    }
    Ok(())
}

/// The gradient `d[i][k] = sum_a v[a][i] dn[a][k]` of a nodal field `v`
/// and its interpolated first component `sum_a n[a] v[a][0]`.
#[inline(always)]
fn gradient<const NN: usize>(v: &[[f64; 2]], dn: &[[f64; 2]], n: &[f64]) -> ([[f64; 2]; 2], f64) {
    let mut d = [[0.0; 2]; 2];
    let mut first = 0.0;
    for a in 0..NN {
        for i in 0..2 {
            for k in 0..2 {
                d[i][k] += v[a][i] * dn[a][k];
            }
        }
        first += n[a] * v[a][0];
    }
    (d, first)
}

/// The strain measures at a point: the deformation gradient `f` (the
/// identity under small strain) with `f33` (1 + u/r axisymmetric, 1 planar),
/// and the strain (Green-Lagrange under total Lagrangian kinematics, else
/// the small strain), Voigt [xx, yy, zz, 2 xy].
struct Strain {
    f: [[f64; 2]; 2],
    f33: f64,
    strain: Voigt,
}

#[inline(always)]
fn strain_at<const NN: usize>(p: &Point, u: &[[f64; 2]], axi: bool, tl: bool) -> Strain {
    // Displacement gradient h[i][j] = du_i/dX_j and radial displacement.
    let (h, ur) = gradient::<NN>(u, &p.g, &p.n);
    let hoop = if axi { ur / p.r } else { 0.0 };
    let f = if tl {
        [[1.0 + h[0][0], h[0][1]], [h[1][0], 1.0 + h[1][1]]]
    } else {
        [[1.0, 0.0], [0.0, 1.0]]
    };
    let f33 = if tl { 1.0 + hoop } else { 1.0 };
    let strain: Voigt = if tl {
        [
            h[0][0] + 0.5 * (h[0][0] * h[0][0] + h[1][0] * h[1][0]),
            h[1][1] + 0.5 * (h[0][1] * h[0][1] + h[1][1] * h[1][1]),
            hoop + 0.5 * hoop * hoop,
            h[0][1] + h[1][0] + h[0][0] * h[0][1] + h[1][0] * h[1][1],
        ]
    } else {
        [h[0][0], h[1][1], hoop, h[0][1] + h[1][0]]
    };
    Strain { f, f33, strain }
}

/// B: row r of the strain's variation per dof (a, i).
#[inline(always)]
fn strain_variation<const NN: usize>(
    p: &Point,
    f: [[f64; 2]; 2],
    f33: f64,
    axi: bool,
) -> [[f64; MAX_DOFS]; 4] {
    let mut b = [[0.0; MAX_DOFS]; 4];
    for a in 0..NN {
        let (gx, gy) = (p.g[a][0], p.g[a][1]);
        b[0][2 * a] = f[0][0] * gx;
        b[0][2 * a + 1] = f[1][0] * gx;
        b[1][2 * a] = f[0][1] * gy;
        b[1][2 * a + 1] = f[1][1] * gy;
        if axi {
            b[2][2 * a] = f33 * p.n[a] / p.r;
        }
        b[3][2 * a] = f[0][0] * gy + f[0][1] * gx;
        b[3][2 * a + 1] = f[1][0] * gy + f[1][1] * gx;
    }
    b
}

/// The material part of the tangent, `B^T C B dv`, into `k`.
#[inline(always)]
fn add_material_tangent<const NN: usize>(
    b: &[[f64; MAX_DOFS]; 4],
    c: &Tangent,
    dv: f64,
    k: &mut ElementMatrix,
) {
    let nd = 2 * NN;
    let mut cb = [[0.0; MAX_DOFS]; 4];
    for r in 0..4 {
        for q in 0..nd {
            cb[r][q] = (0..4).map(|t| c[r][t] * b[t][q]).sum();
        }
    }
    for q1 in 0..nd {
        for q2 in 0..nd {
            let mut v = 0.0;
            for r in 0..4 {
                v += b[r][q1] * cb[r][q2];
            }
            k[q1][q2] += v * dv;
        }
    }
}

/// The geometric part of the total Lagrangian tangent, `(g_a . S g_b) I`,
/// and `S33 N_a N_b / r^2` radially, into `k`.
#[inline(always)]
fn add_geometric_tangent<const NN: usize>(p: &Point, s: &Voigt, axi: bool, k: &mut ElementMatrix) {
    for a in 0..NN {
        for bb in 0..NN {
            let (ga, gb) = (p.g[a], p.g[bb]);
            let mut v =
                ga[0] * (s[0] * gb[0] + s[3] * gb[1]) + ga[1] * (s[3] * gb[0] + s[1] * gb[1]);
            v *= p.dv;
            k[2 * a][2 * bb] += v;
            k[2 * a + 1][2 * bb + 1] += v;
            if axi {
                k[2 * a][2 * bb] += s[2] * p.n[a] * p.n[bb] / (p.r * p.r) * p.dv;
            }
        }
    }
}

/// The Cauchy stress `F S F^T / det F` (Voigt), `det_f` including the
/// thickness stretch in plane stress.
#[inline(always)]
fn cauchy(f: [[f64; 2]; 2], f33: f64, s: &Voigt, det_f: f64) -> Voigt {
    let sm = [[s[0], s[3]], [s[3], s[1]]];
    let mut fs = [[0.0; 2]; 2];
    for i in 0..2 {
        for k in 0..2 {
            fs[i][k] = f[i][0] * sm[0][k] + f[i][1] * sm[1][k];
        }
    }
    let mut sig = [[0.0; 2]; 2];
    for i in 0..2 {
        for k in 0..2 {
            sig[i][k] = (fs[i][0] * f[k][0] + fs[i][1] * f[k][1]) / det_f;
        }
    }
    [sig[0][0], sig[1][1], f33 * f33 * s[2] / det_f, sig[0][1]]
}

impl ElementOutput {
    pub fn new() -> Self {
        ElementOutput {
            f: [0.0; MAX_DOFS],
            k: [[0.0; MAX_DOFS]; MAX_DOFS],
            cauchy: [0.0; 4],
        }
    }
}

impl Default for ElementOutput {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::build;
    use crate::problem::MaterialSpec;

    /// A distorted element of `kind` (counter-clockwise, x > 0), its corner
    /// nodes first, then the midside ones (Q8).
    fn element(kind: ElementKind) -> Vec<[f64; 2]> {
        let corners = [[1.0, 0.1], [2.3, 0.0], [2.1, 1.2], [0.9, 1.0]];
        let mut x: Vec<[f64; 2]> = corners.to_vec();
        if kind == ElementKind::Q8 {
            for a in 0..4 {
                let (p, q) = (corners[a], corners[(a + 1) % 4]);
                // Off the chord, so the element's sides are curved.
                x.push([0.5 * (p[0] + q[0]) + 0.03, 0.5 * (p[1] + q[1]) - 0.02]);
            }
        }
        x
    }

    #[test]
    fn kept_reference_geometry_integrates_bit_for_bit() {
        let analyses = [
            AnalysisKind::PlaneStrain { thickness: 1.5 },
            AnalysisKind::Axisymmetric,
        ];
        let kinematics = [Kinematics::SmallStrain, Kinematics::TotalLagrangian];
        for kind in [ElementKind::Q4, ElementKind::Q8] {
            let x0 = element(kind);
            let u: Vec<[f64; 2]> = (0..x0.len())
                .map(|a| [0.01 * a as f64, -0.02 + 0.005 * (a * a) as f64])
                .collect();
            for analysis in analyses {
                let law = build(&MaterialSpec::LinearElastic { e: 200.0, nu: 0.3 }, analysis);
                let mut kept = Vec::new();
                reference_geometry(analysis, kind, 0, &x0, &mut kept).unwrap();
                assert_eq!(kept.len(), geometry_len(kind));
                assert_eq!(kept.len(), gauss_points(kind).len() * (3 * x0.len() + 2));
                for kin in kinematics {
                    let run = |geometry: Option<&[f64]>| {
                        let mut data = ElementData {
                            index: 0,
                            kind,
                            x0: &x0,
                            u: &u,
                            law: &*law,
                            history: &mut [],
                            initial_stress: [1.0, -2.0, 0.5, 0.25],
                            body_force: [0.3, -0.7],
                            geometry,
                        };
                        let mut out = ElementOutput::new();
                        integrate(analysis, kin, &mut data, true, &mut out).unwrap();
                        out
                    };
                    let (a, b) = (run(Some(&kept)), run(None));
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&a.f), bits(&b.f), "{kind:?} {analysis:?} {kin:?}");
                    assert_eq!(bits(a.k.as_flattened()), bits(b.k.as_flattened()));
                    assert_eq!(bits(&a.cauchy), bits(&b.cauchy));
                    assert!(a.f.iter().any(|&v| v != 0.0));
                }
            }
        }
    }

    #[test]
    fn a_bad_reference_jacobian_is_not_kept() {
        // Clockwise: the reference Jacobian is negative at every point.
        let mut x0 = element(ElementKind::Q4);
        x0.reverse();
        let mut kept = vec![7.0];
        let analysis = AnalysisKind::PlaneStrain { thickness: 1.0 };
        let err = reference_geometry(analysis, ElementKind::Q4, 3, &x0, &mut kept).unwrap_err();
        assert!(matches!(err, ElementError::BadJacobian { element: 3, .. }));
    }
}
