//! Global residual and tangent. The sparsity pattern over the free degrees of
//! freedom and the element-to-pattern scatter map are built once; each
//! assembly only adds numbers into fixed slots.

use crate::element::{face_shape, gauss_1d};
use crate::kinematics::{
    ElementData, ElementError, ElementOutput, geometry_len, integrate, reference_geometry,
};
use crate::material::{self, MaterialLaw, Voigt};
use crate::mesh::{ElementKind, Mesh, face_local_nodes};
use crate::problem::{AnalysisKind, Distribution, Kinematics, Problem};
use std::f64::consts::PI;

/// Marks a prescribed degree of freedom in the equation map.
pub const PRESCRIBED: u32 = u32::MAX;

/// Compressed-column pattern of the free-dof matrix (both triangles).
#[derive(Clone, Debug)]
pub struct Pattern {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
}

/// The assembled model: laws, equation numbering, pattern and scatter map.
#[derive(Debug)]
pub struct Model {
    pub analysis: AnalysisKind,
    pub kinematics: Kinematics,
    laws: Vec<Box<dyn MaterialLaw>>,
    /// Law index of each element.
    element_law: Vec<usize>,
    /// Offset of each element's history in `State::history`.
    history_offset: Vec<usize>,
    pub history_len: usize,
    element_initial_stress: Vec<Voigt>,
    /// Body force entries (index into problem.body_forces) per element body.
    element_body: Vec<usize>,
    /// Equation of each dof (2 per node), or PRESCRIBED. The dofs of a
    /// rigid force set share one equation per component.
    pub eq: Vec<u32>,
    pub pattern: Pattern,
    /// Per element, nd*nd slots into the value array (row-major local).
    scatter: Vec<u32>,
    scatter_offset: Vec<usize>,
    /// True when the tangent is symmetric (no follower load in TL).
    pub symmetric: bool,
    /// True when the tangent never changes (linear kinematics and laws, no follower load).
    pub constant_tangent: bool,
    /// Each element's `kinematics::reference_geometry` from
    /// `geometry_offset[e]` (`usize::MAX`: not kept, beyond
    /// `GEOMETRY_LIMIT` or its reference Jacobian bad, which the
    /// integration then says).
    geometry: Vec<f64>,
    geometry_offset: Vec<usize>,
}

/// Work buffers of one assembly, sized once.
pub struct Workspace {
    /// sqrt of the sum of squares of every element force entry of the last
    /// assembly: the scale of the round-off in the residual.
    pub force_scale: f64,
    /// Edge pressures to apply instead of the scene's at t, by index into
    /// `problem.pressures` (the solver's, when an input overrides one);
    /// empty: the scene's.
    pub pressures: Vec<f64>,
    out: ElementOutput,
    x0: Vec<[f64; 2]>,
    u: Vec<[f64; 2]>,
}

impl Workspace {
    pub fn new() -> Self {
        Workspace {
            force_scale: 0.0,
            pressures: Vec::new(),
            out: ElementOutput::new(),
            x0: Vec::with_capacity(8),
            u: Vec::with_capacity(8),
        }
    }
}

impl Default for Workspace {
    fn default() -> Self {
        Self::new()
    }
}

/// Numbers of reference geometry the model keeps at most (512 MB): 14
/// per Gauss point of a 4-node element, 26 of an 8-node one, so Hertz q4
/// at 1e6 unknowns keeps its 28 million (224 MB beside the 2.6 GB of the
/// increment). A larger mesh computes the geometry at each assembly, as
/// the integration does without it.
const GEOMETRY_LIMIT: usize = 1 << 26;

impl Model {
    /// Build numbering and pattern. `prescribed[dof]` marks driven dofs.
    pub fn new(problem: &Problem, prescribed: &[bool]) -> Self {
        let mesh = &problem.mesh;
        let laws: Vec<Box<dyn MaterialLaw>> = problem
            .materials
            .iter()
            .map(|m| material::build(&m.spec, problem.analysis))
            .collect();
        let element_law = problem.element_material.clone();
        let mut history_offset = Vec::with_capacity(mesh.elements.len());
        let mut history_len = 0;
        for (e, el) in mesh.elements.iter().enumerate() {
            history_offset.push(history_len);
            history_len +=
                laws[element_law[e]].history_len() * crate::element::gauss_points(el.kind).len();
        }
        let mut element_body = vec![usize::MAX; mesh.elements.len()];
        for (b, body) in problem.bodies.iter().enumerate() {
            for e in body.elements.clone() {
                element_body[e] = b;
            }
        }
        let mut element_initial_stress = vec![[0.0; 4]; mesh.elements.len()];
        for is in &problem.initial_stresses {
            for e in problem.bodies[is.body].elements.clone() {
                for i in 0..4 {
                    element_initial_stress[e][i] += is.stress[i];
                }
            }
        }
        let (eq, n) = equations(problem, prescribed);
        let pattern = element_pattern(mesh, &eq, n);
        let (scatter, scatter_offset) = scatter_map(mesh, &eq, &pattern);
        let (geometry, geometry_offset) = kept_geometry(problem);
        let follower = problem.pressures.iter().any(|p| p.follower);
        let tl = problem.kinematics == Kinematics::TotalLagrangian;
        let linear_laws = laws.iter().all(|l| l.is_linear());
        Model {
            analysis: problem.analysis,
            kinematics: problem.kinematics,
            laws,
            element_law,
            history_offset,
            history_len,
            element_initial_stress,
            element_body,
            eq,
            pattern,
            scatter,
            scatter_offset,
            symmetric: !(tl && follower),
            constant_tangent: !tl && linear_laws,
            geometry,
            geometry_offset,
        }
    }

    /// Where element `e`'s material history lies in `State::history`.
    pub fn history_range(&self, e: usize) -> std::ops::Range<usize> {
        let end = self
            .history_offset
            .get(e + 1)
            .copied()
            .unwrap_or(self.history_len);
        self.history_offset[e]..end
    }

    /// Element `e`'s kept reference geometry (`kind` its kind).
    fn geometry_of(&self, e: usize, kind: ElementKind) -> Option<&[f64]> {
        let start = self.geometry_offset[e];
        (start != usize::MAX).then(|| &self.geometry[start..start + geometry_len(kind)])
    }

    pub fn free_dofs(&self) -> usize {
        self.pattern.n
    }

    /// The element-average equivalent plastic strain of each element in
    /// `history` (0 in an element whose law is not plastic); None when no
    /// law of the model is.
    pub fn element_plastic_strains(
        &self,
        mesh: &crate::mesh::Mesh,
        history: &[f64],
    ) -> Option<Vec<f64>> {
        let plastic = |law: &dyn MaterialLaw| {
            let probe = vec![0.0; law.history_len()];
            law.equivalent_plastic_strain(&probe).is_some()
        };
        if !self.laws.iter().any(|l| plastic(&**l)) {
            return None;
        }
        let strains = (mesh.elements.iter().enumerate())
            .map(|(e, el)| {
                let law = &*self.laws[self.element_law[e]];
                let per_point = law.history_len();
                let points = crate::element::gauss_points(el.kind).len();
                let h0 = self.history_offset[e];
                let values: Vec<f64> = (0..points)
                    .filter_map(|g| {
                        let at = h0 + g * per_point;
                        law.equivalent_plastic_strain(history.get(at..at + per_point)?)
                    })
                    .collect();
                values.iter().sum::<f64>() / values.len().max(1) as f64
            })
            .collect();
        Some(strains)
    }

    /// Residual r = f_int - f_ext over all dofs (prescribed ones give the
    /// reactions), and with `k` the tangent values over the pattern. With
    /// `stress`, the element-average Cauchy stresses too. With `kdu =
    /// (du, out)`, out += K du over all dofs (the full tangent, prescribed
    /// columns included: the predictor of a prescribed increment). `history`
    /// holds the converged history on entry and the trial one on return.
    #[allow(clippy::too_many_arguments)]
    pub fn assemble(
        &self,
        problem: &Problem,
        t: f64,
        u: &[f64],
        history: &mut [f64],
        r: &mut [f64],
        mut k: Option<&mut [f64]>,
        mut stress: Option<&mut [Voigt]>,
        mut kdu: Option<(&[f64], &mut [f64])>,
        ws: &mut Workspace,
    ) -> Result<(), ElementError> {
        let mesh = &problem.mesh;
        r.fill(0.0);
        let mut scale2 = 0.0;
        if let Some(k) = k.as_deref_mut() {
            k.fill(0.0);
        }
        let body_force: Vec<[f64; 2]> = problem
            .bodies
            .iter()
            .enumerate()
            .map(|(b, _)| {
                let mut f = [0.0; 2];
                for bf in problem.body_forces.iter().filter(|bf| bf.body == b) {
                    f[0] += bf.bx.at(t, &problem.functions);
                    f[1] += bf.by.at(t, &problem.functions);
                }
                f
            })
            .collect();
        for (e, el) in mesh.elements.iter().enumerate() {
            let nn = el.nodes.len();
            ws.x0.clear();
            ws.u.clear();
            for &nd in &el.nodes {
                ws.x0.push(mesh.nodes[nd]);
                ws.u.push([u[2 * nd], u[2 * nd + 1]]);
            }
            let law = &*self.laws[self.element_law[e]];
            let hl = law.history_len() * crate::element::gauss_points(el.kind).len();
            let h0 = self.history_offset[e];
            let b = self.element_body[e];
            let mut data = ElementData {
                index: e,
                kind: el.kind,
                x0: &ws.x0,
                u: &ws.u,
                law,
                history: &mut history[h0..h0 + hl],
                initial_stress: self.element_initial_stress[e],
                body_force: if b == usize::MAX {
                    [0.0; 2]
                } else {
                    body_force[b]
                },
                geometry: self.geometry_of(e, el.kind),
            };
            integrate(
                self.analysis,
                self.kinematics,
                &mut data,
                k.is_some() || kdu.is_some(),
                &mut ws.out,
            )?;
            if let Some((du, out)) = kdu.as_mut() {
                add_product(&el.nodes, &ws.out.k, du, out);
            }
            scale2 += ws.out.f[..2 * nn].iter().map(|v| v * v).sum::<f64>();
            for (a, &nd) in el.nodes.iter().enumerate() {
                r[2 * nd] += ws.out.f[2 * a];
                r[2 * nd + 1] += ws.out.f[2 * a + 1];
            }
            if let Some(k) = k.as_deref_mut() {
                self.scatter_matrix(e, 2 * nn, &ws.out.k, k);
            }
            if let Some(s) = stress.as_deref_mut() {
                s[e] = ws.out.cauchy;
            }
        }
        ws.force_scale = scale2.sqrt();
        self.add_pressures(problem, t, u, r, k, kdu, ws);
        for f in &problem.forces {
            let (fx, fy) = (
                f.fx.at(t, &problem.functions),
                f.fy.at(t, &problem.functions),
            );
            for &n in &f.nodes {
                r[2 * n] -= fx;
                r[2 * n + 1] -= fy;
            }
        }
        Ok(())
    }

    /// `out += dr/dp`: the load of edge pressure `i` at unit value, at
    /// displacements `u` (on the current edge for a follower pressure under
    /// total Lagrangian kinematics): the residual is linear in each
    /// pressure's value.
    pub fn pressure_load(
        &self,
        problem: &Problem,
        i: usize,
        u: &[f64],
        out: &mut [f64],
        ws: &mut Workspace,
    ) {
        let kept = std::mem::take(&mut ws.pressures);
        ws.pressures = (0..problem.pressures.len())
            .map(|j| if j == i { 1.0 } else { 0.0 })
            .collect();
        self.add_pressures(problem, 0.0, u, out, None, None, ws);
        ws.pressures = kept;
    }

    fn scatter_matrix(&self, e: usize, nd: usize, ke: &[[f64; 16]; 16], k: &mut [f64]) {
        let map = &self.scatter[self.scatter_offset[e]..self.scatter_offset[e] + nd * nd];
        for q1 in 0..nd {
            for q2 in 0..nd {
                let slot = map[q1 * nd + q2];
                if slot != PRESCRIBED {
                    k[slot as usize] += ke[q1][q2];
                }
            }
        }
    }

    /// Edge pressure: r_a += p N_a (x'_y, -x'_x) * (thickness | 2 pi r) ds.
    /// Follower pressure in TL acts on the current edge and adds its load
    /// stiffness (unsymmetric).
    #[allow(clippy::too_many_arguments)]
    fn add_pressures(
        &self,
        problem: &Problem,
        t: f64,
        u: &[f64],
        r: &mut [f64],
        mut k: Option<&mut [f64]>,
        mut kdu: Option<(&[f64], &mut [f64])>,
        ws: &mut Workspace,
    ) {
        let mesh = &problem.mesh;
        let tl = self.kinematics == Kinematics::TotalLagrangian;
        for (i, pr) in problem.pressures.iter().enumerate() {
            let p = (ws.pressures.get(i).copied())
                .unwrap_or_else(|| pr.value.at(t, &problem.functions));
            let current = tl && pr.follower;
            for edge in &pr.edges {
                let el = &mesh.elements[edge.element];
                let local = face_local_nodes(el.kind, edge.face);
                let m = local.len();
                let mut x = [[0.0; 2]; 3];
                for (i, &a) in local.iter().enumerate() {
                    let nd = el.nodes[a];
                    x[i] = mesh.nodes[nd];
                    if current {
                        x[i][0] += u[2 * nd];
                        x[i][1] += u[2 * nd + 1];
                    }
                }
                ws.out.k = [[0.0; 16]; 16];
                let mut any_k = false;
                for &(s, w) in gauss_1d(3) {
                    let (n, dn) = face_shape(m, s);
                    let (mut dx, mut dy, mut rad) = (0.0, 0.0, 0.0);
                    for i in 0..m {
                        dx += dn[i] * x[i][0];
                        dy += dn[i] * x[i][1];
                        rad += n[i] * x[i][0];
                    }
                    let (factor, dfactor) = match self.analysis {
                        AnalysisKind::PlaneStrain { thickness }
                        | AnalysisKind::PlaneStress { thickness } => (thickness, 0.0),
                        AnalysisKind::Axisymmetric => (2.0 * PI * rad, 2.0 * PI),
                    };
                    for i in 0..m {
                        let nd = el.nodes[local[i]];
                        r[2 * nd] += p * n[i] * dy * factor * w;
                        r[2 * nd + 1] -= p * n[i] * dx * factor * w;
                    }
                    if current && (k.is_some() || kdu.is_some()) {
                        any_k = true;
                        for i in 0..m {
                            for j in 0..m {
                                let (ai, bj) = (local[i], local[j]);
                                let kk = &mut ws.out.k;
                                kk[2 * ai][2 * bj + 1] += p * n[i] * dn[j] * factor * w;
                                kk[2 * ai][2 * bj] += p * n[i] * dy * dfactor * n[j] * w;
                                kk[2 * ai + 1][2 * bj] -= p * n[i] * dn[j] * factor * w;
                                kk[2 * ai + 1][2 * bj] -= p * n[i] * dx * dfactor * n[j] * w;
                            }
                        }
                    }
                }
                if any_k {
                    let ke = ws.out.k;
                    if let Some(k) = k.as_deref_mut() {
                        self.scatter_matrix(edge.element, 2 * el.nodes.len(), &ke, k);
                    }
                    if let Some((du, out)) = kdu.as_mut() {
                        add_product(&el.nodes, &ke, du, out);
                    }
                }
            }
        }
    }
}

/// The equation of each dof (`PRESCRIBED` for a driven one) and their
/// count. A rigid force component's set is one unknown: each of its dofs is
/// numbered as the set's first (lowest) free dof.
fn equations(problem: &Problem, prescribed: &[bool]) -> (Vec<u32>, usize) {
    let mesh = &problem.mesh;
    let mut leader: Vec<usize> = (0..2 * mesh.nodes.len()).collect();
    for d in &problem.drivers {
        for c in (0..2).filter(|&c| d.force(c).is_some()) {
            if d.distribution != Distribution::Rigid {
                continue;
            }
            let dofs = d.nodes.iter().map(|&k| 2 * k + c);
            let dofs: Vec<usize> = dofs.filter(|&q| !prescribed[q]).collect();
            if let Some(&first) = dofs.iter().min() {
                for q in dofs {
                    leader[q] = first;
                }
            }
        }
    }
    let mut eq = vec![PRESCRIBED; 2 * mesh.nodes.len()];
    let mut n = 0u32;
    for dof in 0..eq.len() {
        if prescribed[dof] {
            continue;
        }
        if leader[dof] != dof {
            eq[dof] = eq[leader[dof]];
        } else {
            eq[dof] = n;
            n += 1;
        }
    }
    (eq, n as usize)
}

/// The tangent's sparsity pattern: per column the sorted rows its
/// elements couple it to.
fn element_pattern(mesh: &Mesh, eq: &[u32], n: usize) -> Pattern {
    // Column sets, then sorted unique rows.
    let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut dofs = Vec::with_capacity(16);
    for el in &mesh.elements {
        dofs.clear();
        for &node in &el.nodes {
            for c in 0..2 {
                let q = eq[2 * node + c];
                if q != PRESCRIBED {
                    dofs.push(q as usize);
                }
            }
        }
        for &c in &dofs {
            cols[c].extend(dofs.iter().copied());
        }
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    col_ptr.push(0);
    for c in cols.iter_mut() {
        c.sort_unstable();
        c.dedup();
        row_idx.extend_from_slice(c);
        col_ptr.push(row_idx.len());
    }
    drop(cols);
    Pattern {
        n,
        col_ptr,
        row_idx,
    }
}

/// Per element, where each entry of its matrix goes in the pattern's
/// values (`PRESCRIBED` where its row or column is driven), and each
/// element's offset in that list.
fn scatter_map(mesh: &Mesh, eq: &[u32], pattern: &Pattern) -> (Vec<u32>, Vec<usize>) {
    let (col_ptr, row_idx) = (&pattern.col_ptr, &pattern.row_idx);
    let mut scatter = Vec::new();
    let mut scatter_offset = Vec::with_capacity(mesh.elements.len());
    for el in &mesh.elements {
        scatter_offset.push(scatter.len());
        let ld: Vec<u32> = el
            .nodes
            .iter()
            .flat_map(|&nd| [eq[2 * nd], eq[2 * nd + 1]])
            .collect();
        for &r in &ld {
            for &c in &ld {
                if r == PRESCRIBED || c == PRESCRIBED {
                    scatter.push(PRESCRIBED);
                } else {
                    let (c, r) = (c as usize, r as usize);
                    let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
                    let pos = rows
                        .binary_search(&r)
                        .expect("pattern holds every element pair");
                    scatter.push((col_ptr[c] + pos) as u32);
                }
            }
        }
    }
    (scatter, scatter_offset)
}

/// The reference geometry's numbers of every element and each one's offset
/// (`usize::MAX` where not kept): kept up to GEOMETRY_LIMIT.
fn kept_geometry(problem: &Problem) -> (Vec<f64>, Vec<usize>) {
    let mesh = &problem.mesh;
    let size: usize = mesh.elements.iter().map(|el| geometry_len(el.kind)).sum();
    let keep = size <= GEOMETRY_LIMIT;
    let mut geometry = Vec::with_capacity(if keep { size } else { 0 });
    let mut geometry_offset = Vec::with_capacity(mesh.elements.len());
    let mut x0 = Vec::with_capacity(8);
    for (e, el) in mesh.elements.iter().enumerate() {
        if !keep {
            geometry_offset.push(usize::MAX);
            continue;
        }
        let start = geometry.len();
        x0.clear();
        x0.extend(el.nodes.iter().map(|&nd| mesh.nodes[nd]));
        let kept = reference_geometry(problem.analysis, el.kind, e, &x0, &mut geometry);
        if kept.is_ok() {
            geometry_offset.push(start);
        } else {
            geometry.truncate(start);
            geometry_offset.push(usize::MAX);
        }
    }
    (geometry, geometry_offset)
}

/// out += K_e du_e for one element's nodes.
fn add_product(nodes: &[usize], ke: &[[f64; 16]; 16], du: &[f64], out: &mut [f64]) {
    let nd = 2 * nodes.len();
    let mut local = [0.0; 16];
    let mut any = false;
    for (a, &n) in nodes.iter().enumerate() {
        local[2 * a] = du[2 * n];
        local[2 * a + 1] = du[2 * n + 1];
        any |= local[2 * a] != 0.0 || local[2 * a + 1] != 0.0;
    }
    if !any {
        return;
    }
    for (a, &n) in nodes.iter().enumerate() {
        for c in 0..2 {
            let q = 2 * a + c;
            out[2 * n + c] += (0..nd).map(|j| ke[q][j] * local[j]).sum::<f64>();
        }
    }
}
