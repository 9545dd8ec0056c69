//! VTK XML files in ASCII: an UnstructuredGrid per increment (reference
//! coordinates, displacement as point data, stress as cell data, so ParaView's
//! "Warp By Vector" shows the deformed shape) and a `.pvd` collection that
//! strings them into a time series. Numbers are written with Rust's shortest
//! round-trip form (`{:e}`), so reading them back gives the same f64.

use crate::mesh::{ElementKind, Mesh};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

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

/// Writes `mesh` in its reference configuration with the nodal displacements
/// `u` (two per node) and the element-average Cauchy stress of each element.
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    u: &[f64],
    element_stress: &[[f64; 4]],
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
    if let Some((e, _)) = mesh
        .elements
        .iter()
        .enumerate()
        .find(|(_, el)| el.nodes.iter().any(|&n| n >= mesh.nodes.len()))
    {
        return Err(invalid(format!("element {e} names a node beyond the mesh")));
    }
    let mut w = BufWriter::new(File::create(path)?);
    write_vtu_to(&mut w, mesh, u, element_stress)?;
    w.flush()
}

fn write_vtu_to<W: Write>(
    w: &mut W,
    mesh: &Mesh,
    u: &[f64],
    element_stress: &[[f64; 4]],
) -> io::Result<()> {
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">"#
    )?;
    writeln!(w, "<UnstructuredGrid>")?;
    writeln!(
        w,
        r#"<Piece NumberOfPoints="{}" NumberOfCells="{}">"#,
        mesh.nodes.len(),
        mesh.elements.len()
    )?;

    writeln!(w, "<Points>")?;
    writeln!(
        w,
        r#"<DataArray type="Float64" Name="Points" NumberOfComponents="3" format="ascii">"#
    )?;
    for p in &mesh.nodes {
        writeln!(w, "{:e} {:e} 0", p[0], p[1])?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</Points>")?;

    writeln!(w, "<Cells>")?;
    writeln!(
        w,
        r#"<DataArray type="Int64" Name="connectivity" format="ascii">"#
    )?;
    for el in &mesh.elements {
        for (i, n) in el.nodes.iter().enumerate() {
            if i > 0 {
                w.write_all(b" ")?;
            }
            write!(w, "{n}")?;
        }
        w.write_all(b"\n")?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(
        w,
        r#"<DataArray type="Int64" Name="offsets" format="ascii">"#
    )?;
    let mut offset = 0;
    for el in &mesh.elements {
        offset += el.nodes.len();
        writeln!(w, "{offset}")?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, r#"<DataArray type="UInt8" Name="types" format="ascii">"#)?;
    for el in &mesh.elements {
        writeln!(w, "{}", vtk_cell_type(el.kind))?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</Cells>")?;

    writeln!(w, r#"<PointData Vectors="displacement">"#)?;
    writeln!(
        w,
        r#"<DataArray type="Float64" Name="displacement" NumberOfComponents="3" format="ascii">"#
    )?;
    for d in u.chunks_exact(2) {
        writeln!(w, "{:e} {:e} 0", d[0], d[1])?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</PointData>")?;

    writeln!(w, r#"<CellData Scalars="von_mises">"#)?;
    writeln!(
        w,
        r#"<DataArray type="Float64" Name="stress" NumberOfComponents="4" ComponentName0="xx" ComponentName1="yy" ComponentName2="zz" ComponentName3="xy" format="ascii">"#
    )?;
    for s in element_stress {
        writeln!(w, "{:e} {:e} {:e} {:e}", s[0], s[1], s[2], s[3])?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(
        w,
        r#"<DataArray type="Float64" Name="von_mises" format="ascii">"#
    )?;
    for s in element_stress {
        writeln!(w, "{:e}", von_mises(s))?;
    }
    writeln!(w, "</DataArray>")?;
    writeln!(w, "</CellData>")?;

    writeln!(w, "</Piece>")?;
    writeln!(w, "</UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")?;
    Ok(())
}

/// Writes a ParaView collection: one data set per `(time, file)`, the file
/// named relative to the `.pvd` itself.
pub fn write_pvd(path: &Path, entries: &[(f64, String)]) -> io::Result<()> {
    let mut w = BufWriter::new(File::create(path)?);
    writeln!(w, r#"<?xml version="1.0"?>"#)?;
    writeln!(
        w,
        r#"<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">"#
    )?;
    writeln!(w, "<Collection>")?;
    for (time, file) in entries {
        write!(
            w,
            r#"<DataSet timestep="{time:e}" group="" part="0" file=""#
        )?;
        write_escaped(&mut w, file)?;
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
