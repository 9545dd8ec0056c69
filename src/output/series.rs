//! The VTK series of a run: at t = 0 and after every converged increment,
//! the solid, the contactor surface of each contact pair with its nodal
//! contact values (state, tractions, slip, gap) and each rigid target where
//! it stands; and one `.pvd` that makes each time a multiblock data set of
//! them (part 0 the solid, then the pairs, then the rigid targets, in scene
//! order), so that ParaView opens the whole run at once.

use super::vtk::{DataArray, Piece, PvdEntry, Values, vectors, write_pvd, write_vtu};
use crate::problem::Problem;
use crate::results::PairResult;
use std::io;
use std::path::{Path, PathBuf};

/// What one time of the series shows: the converged state's displacements,
/// element stresses and plastic strains (None: no plasticity in the scene),
/// the contact pairs' results (scene order) and the rigid targets' poses
/// [ux, uy, theta] (scene order).
pub struct Frame<'a> {
    pub time: f64,
    pub u: &'a [f64],
    pub stress: &'a [[f64; 4]],
    pub plastic_strain: Option<&'a [f64]>,
    pub pairs: &'a [(String, PairResult)],
    pub rigid_poses: &'a [[f64; 3]],
}

/// The files of a series written so far, in `dir`, named after `stem`:
/// `<stem>_NNNN.vtu` (solid), `<stem>_contact_<pair>_NNNN.vtu`,
/// `<stem>_rigid_<rigid>_NNNN.vtu`, with NNNN the frame (0000 at t = 0).
pub struct VtkSeries {
    dir: PathBuf,
    stem: String,
    entries: Vec<PvdEntry>,
}

impl VtkSeries {
    pub fn new(dir: &Path, stem: &str) -> Self {
        VtkSeries {
            dir: dir.to_path_buf(),
            stem: stem.to_string(),
            entries: Vec::new(),
        }
    }

    /// The data sets written so far, as the `.pvd` lists them.
    pub fn entries(&self) -> &[PvdEntry] {
        &self.entries
    }

    /// Forgets the frames at `time` and later (a run taken back to an
    /// earlier state writes them again).
    pub fn forget_from(&mut self, time: f64) {
        self.entries.retain(|e| e.time < time);
    }

    /// The `.pvd` of the series: `<dir>/<stem>.pvd`.
    pub fn pvd_path(&self) -> PathBuf {
        self.dir.join(format!("{}.pvd", self.stem))
    }

    /// Writes frame `index` (its files, not the `.pvd`). On error the
    /// frame's files written before it stay out of the `.pvd`.
    pub fn write_frame(&mut self, index: usize, problem: &Problem, f: &Frame) -> io::Result<()> {
        let solid = format!("{}_{index:04}.vtu", self.stem);
        let path = self.dir.join(&solid);
        write_vtu(&path, &problem.mesh, f.u, f.stress, f.plastic_strain)
            .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
        let mut written = vec![PvdEntry {
            time: f.time,
            part: 0,
            name: "solid".into(),
            file: solid,
        }];

        let mut write = |part: usize, name: String, file: String, piece: Piece| {
            let path = self.dir.join(&file);
            (piece.write(&path))
                .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
            written.push(PvdEntry {
                time: f.time,
                part,
                name,
                file,
            });
            Ok::<(), io::Error>(())
        };

        for (i, pair) in problem.contacts.iter().enumerate() {
            let file = format!("{}_contact_{}_{index:04}.vtu", self.stem, pair.name);
            let Some((_, result)) = f.pairs.get(i) else {
                let msg = format!("no results for contact pair '{}'", pair.name);
                return Err(io::Error::new(io::ErrorKind::InvalidInput, msg));
            };
            let state: Vec<i32> = result.nodes.state.iter().map(|&s| i32::from(s)).collect();
            let nodes: Vec<i64> = pair.contactor.iter().map(|&n| n as i64).collect();
            let u: Vec<f64> = (pair.contactor.iter())
                .flat_map(|&n| [f.u[2 * n], f.u[2 * n + 1]])
                .collect();
            let displacement = vectors(&u);
            let reference = pair
                .contactor
                .iter()
                .map(|&n| problem.mesh.nodes[n])
                .collect();
            let piece = contactor_piece(
                reference,
                pair.closed,
                &displacement,
                &state,
                result,
                &nodes,
            );
            write(1 + i, format!("contact.{}", pair.name), file, piece)?;
        }

        for (r, rigid) in problem.rigids.iter().enumerate() {
            let file = format!("{}_rigid_{}_{index:04}.vtu", self.stem, rigid.name);
            let pose = f.rigid_poses.get(r).copied().unwrap_or_default();
            let (now, _) = rigid.points_at(pose);
            let moved: Vec<f64> = (rigid.points.iter().zip(&now))
                .flat_map(|(p0, p)| [p[0] - p0[0], p[1] - p0[1]])
                .collect();
            let displacement = vectors(&moved);
            let mut piece = Piece::polyline(rigid.points.clone(), false);
            (piece.point_data).push(DataArray::vector("displacement", &displacement));
            let part = 1 + problem.contacts.len() + r;
            write(part, format!("rigid.{}", rigid.name), file, piece)?;
        }
        self.entries.append(&mut written);
        Ok(())
    }

    /// Writes the `.pvd` of the frames written so far.
    pub fn write_pvd(&self) -> io::Result<PathBuf> {
        let path = self.pvd_path();
        write_pvd(&path, &self.entries)?;
        Ok(path)
    }
}

/// The contactor surface: its nodes (reference positions) joined segment by
/// segment, with per node the displacement, the state (0 open, 1 stick, 2
/// slip), `tn`, `tt`, `slip`, `gap` and the mesh node number.
fn contactor_piece<'a>(
    reference: Vec<[f64; 2]>,
    closed: bool,
    displacement: &'a [f64],
    state: &'a [i32],
    r: &'a PairResult,
    nodes: &'a [i64],
) -> Piece<'a> {
    let n = &r.nodes;
    let mut piece = Piece::polyline(reference, closed);
    piece.point_data = vec![
        DataArray::vector("displacement", displacement),
        DataArray::scalar("state", Values::I32(state)),
        DataArray::scalar("tn", Values::F64(&n.tn)),
        DataArray::scalar("tt", Values::F64(&n.tt)),
        DataArray::scalar("slip", Values::F64(&n.slip)),
        DataArray::scalar("gap", Values::F64(&n.gap)),
        DataArray::scalar("node", Values::I64(nodes)),
    ];
    piece
}
