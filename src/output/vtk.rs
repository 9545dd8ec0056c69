//! VTK XML files for ParaView: UnstructuredGrid pieces (`.vtu`) with their
//! numbers in binary, zlib-compressed, after the XML (VTK's appended data,
//! `encoding="raw"`, `vtkZLibDataCompressor`, 64-bit headers), and the
//! `.pvd` collection that strings them into a time series. Every piece is in
//! its reference configuration with the `displacement` that carries it to the
//! current one, so one "Warp By Vector" shows the whole series deformed.

use crate::mesh::{ElementKind, Mesh};
use flate2::Compression;
use flate2::write::ZlibEncoder;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// VTK cell types used here.
const VTK_VERTEX: u8 = 1;
const VTK_LINE: u8 = 3;

/// Uncompressed bytes per compressed block (VTK's own default).
const BLOCK: usize = 32 * 1024;

/// VTK cell type of an element. Our Q8 node order (corners, then the
/// mid-sides of faces 0..3) is VTK's own for the quadratic quad.
pub fn vtk_cell_type(kind: ElementKind) -> u8 {
    match kind {
        ElementKind::Q4 => 9,  // VTK_QUAD
        ElementKind::Q8 => 23, // VTK_QUADRATIC_QUAD
    }
}

/// Von Mises equivalent stress of a Cauchy stress [xx, yy, zz, xy].
pub fn von_mises(s: &[f64; 4]) -> f64 {
    let [xx, yy, zz, xy] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2)) + 3.0 * xy * xy).sqrt()
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// The numbers of one DataArray, flat (components of a point together).
#[derive(Clone, Copy, Debug)]
pub enum Values<'a> {
    F64(&'a [f64]),
    I32(&'a [i32]),
    I64(&'a [i64]),
    U8(&'a [u8]),
}

impl Values<'_> {
    fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::I32(v) => v.len(),
            Values::I64(v) => v.len(),
            Values::U8(v) => v.len(),
        }
    }

    fn vtk_type(&self) -> &'static str {
        match self {
            Values::F64(_) => "Float64",
            Values::I32(_) => "Int32",
            Values::I64(_) => "Int64",
            Values::U8(_) => "UInt8",
        }
    }

    /// Little-endian bytes, as the file's `byte_order` says.
    fn bytes(&self) -> Vec<u8> {
        match self {
            Values::F64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::I32(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::I64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            Values::U8(v) => v.to_vec(),
        }
    }
}

/// A named array of point or cell data.
#[derive(Clone, Copy, Debug)]
pub struct DataArray<'a> {
    pub name: &'a str,
    /// Names of the components (their number is the array's number of
    /// components; empty: one component).
    pub components: &'a [&'a str],
    pub values: Values<'a>,
}

impl<'a> DataArray<'a> {
    pub fn scalar(name: &'a str, values: Values<'a>) -> Self {
        DataArray {
            name,
            components: &[],
            values,
        }
    }

    /// A vector of VTK's three components (x, y, z) per entry.
    pub fn vector(name: &'a str, xyz: &'a [f64]) -> Self {
        DataArray {
            name,
            components: &["x", "y", "z"],
            values: Values::F64(xyz),
        }
    }

    fn n_components(&self) -> usize {
        self.components.len().max(1)
    }
}

/// One UnstructuredGrid piece: reference points, cells, point and cell data.
#[derive(Debug, Default)]
pub struct Piece<'a> {
    /// Reference coordinates (z = 0).
    pub points: Vec<[f64; 2]>,
    /// Node indices of every cell, one after the other.
    pub connectivity: Vec<i64>,
    /// End of each cell in `connectivity`.
    pub offsets: Vec<i64>,
    pub types: Vec<u8>,
    pub point_data: Vec<DataArray<'a>>,
    pub cell_data: Vec<DataArray<'a>>,
}

impl<'a> Piece<'a> {
    /// A polyline through `points`, closed back to the first when asked; a
    /// single point is one vertex.
    pub fn polyline(points: Vec<[f64; 2]>, closed: bool) -> Self {
        let n = points.len();
        let mut piece = Piece {
            points,
            ..Piece::default()
        };
        if n == 1 {
            piece.add_cell(VTK_VERTEX, &[0]);
        }
        let segments = match (n, closed) {
            (0 | 1, _) => 0,
            (2, _) | (_, false) => n - 1,
            (_, true) => n,
        };
        for a in 0..segments {
            piece.add_cell(VTK_LINE, &[a as i64, ((a + 1) % n) as i64]);
        }
        piece
    }

    pub fn add_cell(&mut self, vtk_type: u8, nodes: &[i64]) {
        self.connectivity.extend_from_slice(nodes);
        self.offsets.push(self.connectivity.len() as i64);
        self.types.push(vtk_type);
    }

    /// Writes the piece as a `.vtu` file, after checking that every array
    /// has one entry per point (cell) and every cell names existing points.
    pub fn write(&self, path: &Path) -> io::Result<()> {
        self.check()?;
        let mut w = BufWriter::new(File::create(path)?);
        self.write_to(&mut w)?;
        w.flush()
    }

    fn check(&self) -> io::Result<()> {
        let (np, nc) = (self.points.len(), self.types.len());
        if self.offsets.len() != nc
            || self.offsets.last().map_or(0, |&o| o as usize) != self.connectivity.len()
        {
            return Err(invalid(format!(
                "{nc} cells, {} offsets ending at {:?} for {} connectivity entries",
                self.offsets.len(),
                self.offsets.last(),
                self.connectivity.len()
            )));
        }
        if let Some(n) = self
            .connectivity
            .iter()
            .find(|&&n| n < 0 || n as usize >= np)
        {
            return Err(invalid(format!("a cell names point {n} of {np}")));
        }
        for (data, count, what) in [
            (&self.point_data, np, "point"),
            (&self.cell_data, nc, "cell"),
        ] {
            for a in data {
                if a.values.len() != count * a.n_components() {
                    return Err(invalid(format!(
                        "{} values of {what} data {:?} for {count} {what}s ({} per {what} expected)",
                        a.values.len(),
                        a.name,
                        a.n_components()
                    )));
                }
            }
        }
        Ok(())
    }

    fn write_to<W: Write>(&self, w: &mut W) -> io::Result<()> {
        let xyz: Vec<f64> = self.points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
        let points = [DataArray::vector("Points", &xyz)];
        let cells = [
            DataArray::scalar("connectivity", Values::I64(&self.connectivity)),
            DataArray::scalar("offsets", Values::I64(&self.offsets)),
            DataArray::scalar("types", Values::U8(&self.types)),
        ];
        let data = [
            ("PointData", &self.point_data[..]),
            ("CellData", &self.cell_data[..]),
        ];
        // The appended data holds the arrays in the reverse of their order
        // in the XML. Any order is valid VTK; this one is read right by
        // meshio 5.3, which maps each array's offset to its new place one
        // array at a time and looks the next one up by its offset: an
        // earlier array's new offset can equal a later one's, and in XML
        // order the earlier array is found first (a contact surface's `tn`
        // was read as its `slip`).
        let in_order = (points.iter().chain(&cells)).chain(data.iter().flat_map(|(_, d)| d.iter()));
        let encoded: Vec<Vec<u8>> = in_order
            .map(|a| encode(&a.values))
            .collect::<io::Result<_>>()?;
        let mut offsets = vec![0; encoded.len()];
        let mut at = 0;
        for (k, e) in encoded.iter().enumerate().rev() {
            offsets[k] = at;
            at += e.len();
        }
        let mut offsets = offsets.into_iter();
        let mut next = || offsets.next().unwrap_or_default();

        writeln!(w, r#"<?xml version="1.0"?>"#)?;
        writeln!(
            w,
            r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64" compressor="vtkZLibDataCompressor">"#
        )?;
        writeln!(w, "<UnstructuredGrid>")?;
        writeln!(
            w,
            r#"<Piece NumberOfPoints="{}" NumberOfCells="{}">"#,
            self.points.len(),
            self.types.len()
        )?;
        writeln!(w, "<Points>")?;
        write_array(w, &points[0], next())?;
        writeln!(w, "</Points>")?;
        writeln!(w, "<Cells>")?;
        for a in &cells {
            write_array(w, a, next())?;
        }
        writeln!(w, "</Cells>")?;
        for (tag, data) in data {
            if data.is_empty() {
                continue;
            }
            // The first vector (3 components) and the first scalar are the
            // ones ParaView shows by default.
            write!(w, "<{tag}")?;
            if let Some(v) = data.iter().find(|a| a.n_components() == 3) {
                write!(w, r#" Vectors="{}""#, v.name)?;
            }
            if let Some(s) = data.iter().find(|a| a.n_components() == 1) {
                write!(w, r#" Scalars="{}""#, s.name)?;
            }
            writeln!(w, ">")?;
            for a in data {
                write_array(w, a, next())?;
            }
            writeln!(w, "</{tag}>")?;
        }
        writeln!(w, "</Piece>")?;
        writeln!(w, "</UnstructuredGrid>")?;
        // Raw bytes after the underscore, up to the newline before the
        // closing tag.
        w.write_all(b"<AppendedData encoding=\"raw\">\n_")?;
        for e in encoded.iter().rev() {
            w.write_all(e)?;
        }
        writeln!(w, "\n</AppendedData>")?;
        writeln!(w, "</VTKFile>")?;
        Ok(())
    }
}

/// The XML of one DataArray, `format="appended"` at `offset` into the
/// appended data.
fn write_array<W: Write>(w: &mut W, a: &DataArray, offset: usize) -> io::Result<()> {
    write!(w, r#"<DataArray type="{}" Name=""#, a.values.vtk_type())?;
    write_escaped(w, a.name)?;
    w.write_all(b"\"")?;
    // One component is VTK's default (and readers then give a flat array).
    if a.components.len() > 1 {
        write!(w, r#" NumberOfComponents="{}""#, a.n_components())?;
        for (i, c) in a.components.iter().enumerate() {
            write!(w, r#" ComponentName{i}=""#)?;
            write_escaped(w, c)?;
            w.write_all(b"\"")?;
        }
    }
    writeln!(w, r#" format="appended" offset="{offset}"/>"#)
}

/// An array's appended data: the compression header (block count, block
/// size, size of a partial last block, each block's compressed size;
/// UInt64), then the zlib-compressed blocks.
fn encode(values: &Values) -> io::Result<Vec<u8>> {
    let raw = values.bytes();
    let mut header = vec![
        raw.len().div_ceil(BLOCK) as u64,
        BLOCK as u64,
        (raw.len() % BLOCK) as u64,
    ];
    let mut blocks = Vec::new();
    for chunk in raw.chunks(BLOCK) {
        let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
        z.write_all(chunk)?;
        let compressed = z.finish()?;
        header.push(compressed.len() as u64);
        blocks.extend_from_slice(&compressed);
    }
    let mut out: Vec<u8> = header.iter().flat_map(|x| x.to_le_bytes()).collect();
    out.extend_from_slice(&blocks);
    Ok(out)
}

/// Writes `mesh` in its reference configuration with the nodal displacements
/// `u` (two per node), the element-average Cauchy stress of each element and
/// its von Mises value, and, for a scene with plasticity, the element-average
/// equivalent plastic strain.
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    u: &[f64],
    element_stress: &[[f64; 4]],
    plastic_strain: Option<&[f64]>,
) -> io::Result<()> {
    if u.len() != 2 * mesh.nodes.len() {
        return Err(invalid(format!(
            "{} displacements for {} nodes (2 per node expected)",
            u.len(),
            mesh.nodes.len()
        )));
    }
    if element_stress.len() != mesh.elements.len() {
        return Err(invalid(format!(
            "{} element stresses for {} elements",
            element_stress.len(),
            mesh.elements.len()
        )));
    }
    let mut piece = Piece {
        points: mesh.nodes.clone(),
        ..Piece::default()
    };
    for el in &mesh.elements {
        let nodes: Vec<i64> = el.nodes.iter().map(|&n| n as i64).collect();
        piece.add_cell(vtk_cell_type(el.kind), &nodes);
    }
    let displacement = vectors(u);
    let stress: Vec<f64> = element_stress.iter().flatten().copied().collect();
    let vm: Vec<f64> = element_stress.iter().map(von_mises).collect();
    piece
        .point_data
        .push(DataArray::vector("displacement", &displacement));
    piece
        .cell_data
        .push(DataArray::scalar("von_mises", Values::F64(&vm)));
    piece.cell_data.push(DataArray {
        name: "stress",
        components: &["xx", "yy", "zz", "xy"],
        values: Values::F64(&stress),
    });
    if let Some(p) = plastic_strain {
        piece
            .cell_data
            .push(DataArray::scalar("plastic_strain", Values::F64(p)));
    }
    piece.write(path)
}

/// Two components per point as VTK's three (z = 0).
pub fn vectors(xy: &[f64]) -> Vec<f64> {
    xy.chunks_exact(2).flat_map(|d| [d[0], d[1], 0.0]).collect()
}

/// One data set of a `.pvd` collection.
#[derive(Clone, Debug, PartialEq)]
pub struct PvdEntry {
    pub time: f64,
    /// Block of the multiblock data set ParaView makes of each time (0, 1,
    /// ...); the same part is the same thing at every time.
    pub part: usize,
    /// The block's name (ParaView shows it in the block list).
    pub name: String,
    /// The file, relative to the `.pvd` itself.
    pub file: String,
}

/// Writes a ParaView collection of `entries`.
pub fn write_pvd(path: &Path, entries: &[PvdEntry]) -> io::Result<()> {
    let mut w = BufWriter::new(File::create(path)?);
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">"#
    )?;
    writeln!(w, "<Collection>")?;
    for e in entries {
        write!(
            w,
            r#"<DataSet timestep="{:e}" group="" part="{}" name=""#,
            e.time, e.part
        )?;
        write_escaped(&mut w, &e.name)?;
        w.write_all(br#"" file=""#)?;
        write_escaped(&mut w, &e.file)?;
        writeln!(w, r#""/>"#)?;
    }
    writeln!(w, "</Collection>")?;
    writeln!(w, "</VTKFile>")?;
    w.flush()
}

/// Writes `s` as XML attribute text.
fn write_escaped<W: Write>(w: &mut W, s: &str) -> io::Result<()> {
    let mut rest = s;
    while let Some(i) = rest.find(['&', '<', '>', '"', '\'']) {
        w.write_all(&rest.as_bytes()[..i])?;
        let entity: &[u8] = match rest.as_bytes()[i] {
            b'&' => b"&amp;",
            b'<' => b"&lt;",
            b'>' => b"&gt;",
            b'"' => b"&quot;",
            _ => b"&apos;",
        };
        w.write_all(entity)?;
        rest = &rest[i + 1..];
    }
    w.write_all(rest.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polylines_open_closed_and_single() {
        let p = |n: usize| (0..n).map(|i| [i as f64, 0.0]).collect::<Vec<_>>();
        let open = Piece::polyline(p(3), false);
        assert_eq!(open.connectivity, [0, 1, 1, 2]);
        assert_eq!(open.types, [VTK_LINE; 2]);
        let closed = Piece::polyline(p(3), true);
        assert_eq!(closed.connectivity, [0, 1, 1, 2, 2, 0]);
        assert_eq!(closed.offsets, [2, 4, 6]);
        // Two points closed are still one segment, not the same one twice.
        assert_eq!(Piece::polyline(p(2), true).types.len(), 1);
        let single = Piece::polyline(p(1), false);
        assert_eq!(
            (single.types, single.connectivity),
            (vec![VTK_VERTEX], vec![0])
        );
    }
}
