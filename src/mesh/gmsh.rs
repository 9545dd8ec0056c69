//! Gmsh MSH 4.1 ASCII reader: 4- and 8-node quadrilaterals, with the
//! physical groups as named sets (surfaces -> element sets, curves -> edge
//! and node sets, points -> node sets). Errors name the file and line.

use super::{Edge, Element, ElementKind, Mesh, MeshError, chain, edge_nodes, face_local_nodes};
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// Read a Gmsh MSH 4.1 ASCII file (see [`parse`]).
pub fn read(path: &Path) -> Result<Mesh, MeshError> {
    // Only a regular file: a FIFO or a device would block the read forever.
    if let Ok(meta) = std::fs::metadata(path)
        && !meta.is_file()
    {
        return Err(MeshError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a regular file (a FIFO, device or folder is not read)",
            ),
        });
    }
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse(&String::from_utf8_lossy(&bytes), path)
}

/// Parse MSH 4.1 ASCII text. Sections $MeshFormat, $PhysicalNames,
/// $Entities, $Nodes and $Elements are read, others skipped. Element types:
/// 3 (4-node quad), 16 (8-node quad), 1 (2-node line), 8 (3-node line),
/// 15 (point). Clockwise quadrilaterals are reordered counter-clockwise;
/// nodes no quadrilateral uses are dropped. Physical groups become sets by
/// name: dimension 2 element sets, dimension 1 edge sets (each line matched
/// to the quadrilateral face it lies on, body on the left, chained head to
/// tail) and node sets, dimension 0 node sets. Without a $PhysicalNames
/// section groups are named "group<tag>"; with one, every group used must be
/// named there.
pub fn parse(text: &str, path_for_messages: &Path) -> Result<Mesh, MeshError> {
    let mut r = Reader {
        size: text.len(),
        lines: text.lines().enumerate().peekable(),
        path: path_for_messages,
        line: 0,
        pending: Vec::new(),
    };
    let mut file = File::default();
    let mut seen_format = false;
    while let Some((line, header)) = r.next_line() {
        let header = header.trim();
        if header.is_empty() {
            continue;
        }
        let Some(section) = header.strip_prefix('$') else {
            return Err(r.error_at(
                line,
                format!("expected a section such as $Nodes, found {header:?}"),
            ));
        };
        if section.starts_with("End") {
            return Err(r.error_at(line, format!("{header} without a matching section start")));
        }
        if !seen_format && section != "MeshFormat" {
            return Err(r.error_at(
                line,
                "the file does not start with $MeshFormat; is it a Gmsh .msh file?",
            ));
        }
        match section {
            "MeshFormat" => {
                r.mesh_format()?;
                seen_format = true;
            }
            "PhysicalNames" => file.names = Some(r.physical_names()?),
            "Entities" => file.entities = r.entities()?,
            "Nodes" => r.nodes(&mut file)?,
            "Elements" => r.elements(&mut file)?,
            "PartitionedEntities" => {
                return Err(r.error_at(line, "partitioned meshes are not supported"));
            }
            _ => r.skip_section(line, section)?,
        }
        r.end_section(section)?;
    }
    if !seen_format {
        return Err(r.error_at(1, "empty file; expected a Gmsh MSH 4.1 ASCII mesh"));
    }
    build(file, &r)
}

/// (dimension, entity tag) -> (physical tags, line of the entity).
type Entities = HashMap<(usize, i64), (Vec<i64>, usize)>;

/// What the file holds, in its own numbering.
#[derive(Default)]
struct File {
    names: Option<HashMap<(usize, i64), String>>,
    entities: Entities,
    /// Node tag -> (index in file order, coordinates).
    nodes: HashMap<u64, (usize, [f64; 2])>,
    quads: Vec<Raw>,
    lines: Vec<Raw>,
    points: Vec<Raw>,
}

/// An element as read: tag, node tags, its entity, and the line it is on.
struct Raw {
    tag: u64,
    nodes: Vec<u64>,
    entity: (usize, i64),
    line: usize,
}

struct Reader<'a> {
    /// Bytes of the whole text: the bound on every count it states.
    size: usize,
    lines: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'a>>>,
    path: &'a Path,
    /// Line of the last token handed out (1-based).
    line: usize,
    /// Tokens left on the current line, reversed.
    pending: Vec<&'a str>,
}

impl<'a> Reader<'a> {
    fn error_at(&self, line: usize, message: impl Into<String>) -> MeshError {
        MeshError::Gmsh {
            path: self.path.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    fn error(&self, message: impl Into<String>) -> MeshError {
        self.error_at(self.line, message)
    }

    /// The next whole line (1-based number); drops tokens left on the current one.
    fn next_line(&mut self) -> Option<(usize, &'a str)> {
        self.pending.clear();
        let (i, l) = self.lines.next()?;
        self.line = i + 1;
        Some((i + 1, l))
    }

    /// The next whitespace-separated token, across lines.
    fn token(&mut self, what: &str) -> Result<&'a str, MeshError> {
        loop {
            if let Some(t) = self.pending.pop() {
                return Ok(t);
            }
            match self.lines.next() {
                Some((i, l)) => {
                    self.line = i + 1;
                    if l.trim_start().starts_with('$') {
                        return Err(self.error(format!(
                            "expected {what}, found {:?}: the section ends early",
                            l.trim()
                        )));
                    }
                    self.pending = l.split_whitespace().rev().collect();
                }
                None => {
                    return Err(self.error(format!("expected {what}, found the end of the file")));
                }
            }
        }
    }

    fn number<T: std::str::FromStr>(&mut self, what: &str) -> Result<T, MeshError> {
        let t = self.token(what)?;
        t.parse()
            .map_err(|_| self.error(format!("expected {what}, found {t:?}")))
    }

    /// A count the file states: it cannot exceed what the file holds (each
    /// counted item takes at least a digit and a separator), so that a
    /// corrupt or hostile header is an error, not an allocation of its size.
    fn count(&mut self, what: &str) -> Result<usize, MeshError> {
        let n: usize = self.number(what)?;
        if n > self.size / 2 {
            return Err(self.error(format!(
                "{what} is {n}, more than a file of {} bytes can hold",
                self.size
            )));
        }
        Ok(n)
    }

    /// Expect `$End<section>` as the next non-blank line.
    fn end_section(&mut self, section: &str) -> Result<(), MeshError> {
        if let Some(t) = self.pending.last() {
            return Err(self.error(format!("unexpected {t:?} at the end of ${section}")));
        }
        while let Some((_, l)) = self.next_line() {
            let l = l.trim();
            if l.is_empty() {
                continue;
            }
            if l == format!("$End{section}") {
                return Ok(());
            }
            return Err(self.error(format!("expected $End{section}, found {l:?}")));
        }
        Err(self.error(format!("expected $End{section}, found the end of the file")))
    }

    fn skip_section(&mut self, start: usize, section: &str) -> Result<(), MeshError> {
        let end = format!("$End{section}");
        while let Some((_, l)) = self.lines.peek() {
            if l.trim() == end {
                return Ok(());
            }
            self.next_line();
        }
        Err(self.error_at(start, format!("${section} has no {end}")))
    }

    fn mesh_format(&mut self) -> Result<(), MeshError> {
        let version = self.token("the format version")?;
        let line = self.line;
        if version != "4.1" {
            return Err(self.error_at(
                line,
                format!(
                    "MSH version {version} is not supported; save the mesh as version 4.1 ASCII \
                     (gmsh -format msh41, or Mesh.MshFileVersion = 4.1)"
                ),
            ));
        }
        let file_type: u32 = self.number("the file type (0 for ASCII)")?;
        if file_type != 0 {
            return Err(self.error_at(
                line,
                "binary MSH files are not supported; save the mesh as ASCII (Mesh.Binary = 0)",
            ));
        }
        self.number::<usize>("the data size")?;
        Ok(())
    }

    fn physical_names(&mut self) -> Result<HashMap<(usize, i64), String>, MeshError> {
        let n = self.count("the number of physical names")?;
        let mut names = HashMap::new();
        for _ in 0..n {
            let Some((line, l)) = self.next_line() else {
                return Err(self.error("expected a physical name, found the end of the file"));
            };
            let bad = || {
                self.error_at(
                    line,
                    format!(
                        "expected `dimension tag \"name\"` in $PhysicalNames, found {:?}",
                        l.trim()
                    ),
                )
            };
            // The name is quoted and may hold spaces.
            let (numbers, quoted) = l.split_once('"').ok_or_else(bad)?;
            let mut numbers = numbers.split_whitespace().map(str::parse::<i64>);
            let (Some(Ok(dim)), Some(Ok(tag)), None) =
                (numbers.next(), numbers.next(), numbers.next())
            else {
                return Err(bad());
            };
            let dim = usize::try_from(dim).map_err(|_| bad())?;
            let name = quoted.trim_end().strip_suffix('"').ok_or_else(bad)?;
            if name.is_empty() {
                return Err(self.error_at(
                    line,
                    format!("physical group {tag} (dimension {dim}) has an empty name"),
                ));
            }
            names.insert((dim, tag), name.to_string());
        }
        Ok(names)
    }

    fn entities(&mut self) -> Result<Entities, MeshError> {
        let mut counts = [0usize; 4];
        for (d, c) in counts.iter_mut().enumerate() {
            *c = self.count(&format!("the number of entities of dimension {d}"))?;
        }
        let mut entities = HashMap::new();
        for (dim, &count) in counts.iter().enumerate() {
            for _ in 0..count {
                let tag: i64 = self.number("an entity tag")?;
                let line = self.line;
                // A point has its coordinates, the others a bounding box.
                let numbers = if dim == 0 { 3 } else { 6 };
                for _ in 0..numbers {
                    self.number::<f64>("a coordinate")?;
                }
                let n = self.count("the number of physical tags")?;
                let mut physical = Vec::with_capacity(n);
                for _ in 0..n {
                    physical.push(self.number::<i64>("a physical tag")?);
                }
                if dim > 0 {
                    let n = self.count("the number of bounding entities")?;
                    for _ in 0..n {
                        self.number::<i64>("a bounding entity tag")?;
                    }
                }
                entities.insert((dim, tag), (physical, line));
            }
        }
        Ok(entities)
    }

    fn nodes(&mut self, file: &mut File) -> Result<(), MeshError> {
        let blocks = self.count("the number of node blocks")?;
        let total = self.count("the number of nodes")?;
        self.number::<u64>("the smallest node tag")?;
        self.number::<u64>("the largest node tag")?;
        file.nodes.reserve(total);
        for _ in 0..blocks {
            let dim = self.count("the entity dimension")?;
            self.number::<i64>("the entity tag")?;
            let parametric: u32 = self.number("the parametric flag")?;
            let n = self.count("the number of nodes in the block")?;
            let mut tags = Vec::with_capacity(n);
            for _ in 0..n {
                tags.push(self.number::<u64>("a node tag")?);
            }
            for tag in tags {
                let x: f64 = self.number("a coordinate")?;
                let y: f64 = self.number("a coordinate")?;
                let z: f64 = self.number("a coordinate")?;
                if z.abs() > 1e-12 * (1.0 + x.abs().max(y.abs())) {
                    return Err(self.error(format!(
                        "node {tag} has z = {z}; only plane meshes in z = 0 are supported"
                    )));
                }
                if parametric != 0 {
                    for _ in 0..dim {
                        self.number::<f64>("a parametric coordinate")?;
                    }
                }
                let index = file.nodes.len();
                if file.nodes.insert(tag, (index, [x, y])).is_some() {
                    return Err(self.error(format!("node {tag} is defined twice")));
                }
            }
        }
        Ok(())
    }

    fn elements(&mut self, file: &mut File) -> Result<(), MeshError> {
        let blocks = self.count("the number of element blocks")?;
        self.count("the number of elements")?;
        self.number::<u64>("the smallest element tag")?;
        self.number::<u64>("the largest element tag")?;
        for _ in 0..blocks {
            let dim = self.count("the entity dimension")?;
            let entity: i64 = self.number("the entity tag")?;
            let kind: u32 = self.number("the element type")?;
            let header = self.line;
            let n = self.count("the number of elements in the block")?;
            let per = match kind {
                3 => 4,
                16 => 8,
                1 => 2,
                8 => 3,
                15 => 1,
                _ => {
                    return Err(self.error_at(
                        header,
                        format!(
                            "element type {kind}{} is not supported; use quadrilaterals (3 or 16)",
                            type_name(kind).map_or(String::new(), |n| format!(" ({n})"))
                        ),
                    ));
                }
            };
            for _ in 0..n {
                let tag: u64 = self.number("an element tag")?;
                let line = self.line;
                let mut nodes = Vec::with_capacity(per);
                for _ in 0..per {
                    nodes.push(self.number::<u64>("a node tag")?);
                }
                let raw = Raw {
                    tag,
                    nodes,
                    entity: (dim, entity),
                    line,
                };
                match kind {
                    3 | 16 => file.quads.push(raw),
                    1 | 8 => file.lines.push(raw),
                    _ => file.points.push(raw),
                }
            }
        }
        Ok(())
    }
}

fn type_name(kind: u32) -> Option<&'static str> {
    Some(match kind {
        2 => "3-node triangle",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        9 => "6-node triangle",
        10 => "9-node quadrilateral",
        11 => "10-node tetrahedron",
        12 => "27-node hexahedron",
        17 => "20-node hexahedron",
        20 => "9-node triangle",
        21 => "10-node triangle",
        26 => "4-node line",
        36 => "16-node quadrilateral",
        _ => return None,
    })
}

impl File {
    /// The index (in file order) and position of node `tag`, which element
    /// `raw` refers to.
    fn node_of(&self, r: &Reader, tag: u64, raw: &Raw) -> Result<(usize, [f64; 2]), MeshError> {
        self.nodes.get(&tag).copied().ok_or_else(|| {
            r.error_at(
                raw.line,
                format!(
                    "element {} refers to node {tag}, which $Nodes does not define",
                    raw.tag
                ),
            )
        })
    }

    /// The physical group names of an element's entity.
    fn groups(&self, r: &Reader, raw: &Raw) -> Result<Vec<String>, MeshError> {
        let Some((physical, line)) = self.entities.get(&raw.entity) else {
            return Ok(Vec::new());
        };
        physical
            .iter()
            .map(|&tag| match &self.names {
                None => Ok(format!("group{tag}")),
                Some(names) => names.get(&(raw.entity.0, tag)).cloned().ok_or_else(|| {
                    r.error_at(
                        *line,
                        format!(
                            "physical group {tag} (dimension {}) of entity {} has no name in $PhysicalNames",
                            raw.entity.0, raw.entity.1
                        ),
                    )
                }),
            })
            .collect()
    }
}

/// The mesh's node numbering: per node of the file (in file order) its
/// number among the nodes quads use (`usize::MAX`: unused).
struct Numbering(Vec<usize>);

impl Numbering {
    /// Mesh node of node `tag`, which element `raw` refers to.
    fn node(&self, file: &File, r: &Reader, tag: u64, raw: &Raw) -> Result<usize, MeshError> {
        let (index, _) = file.node_of(r, tag, raw)?;
        match self.0[index] {
            usize::MAX => Err(r.error_at(
                raw.line,
                format!(
                    "element {}: node {tag} is not a node of any quadrilateral",
                    raw.tag
                ),
            )),
            n => Ok(n),
        }
    }
}

/// The mesh from what was read: quads reordered counter-clockwise, unused
/// nodes dropped, physical groups turned into sets.
fn build(file: File, r: &Reader) -> Result<Mesh, MeshError> {
    let Some(first) = file.quads.first() else {
        return Err(r.error_at(
            r.line,
            "the file has no quadrilateral elements (types 3 or 16)",
        ));
    };
    let kind = if first.nodes.len() == 4 {
        ElementKind::Q4
    } else {
        ElementKind::Q8
    };
    let quads = oriented_quads(&file, r, kind)?;
    let (nodes, numbering) = used_nodes(&file, &quads);
    let elements: Vec<Element> = quads
        .iter()
        .map(|q| Element {
            kind,
            nodes: q.iter().map(|&n| numbering.0[n]).collect(),
        })
        .collect();
    let mut mesh = Mesh {
        nodes,
        elements,
        ..Mesh::default()
    };
    for (e, q) in file.quads.iter().enumerate() {
        for name in file.groups(r, q)? {
            mesh.element_sets.entry(name).or_default().push(e);
        }
    }
    for (name, edges) in edge_sets(&file, r, &mesh, &numbering)? {
        let edges = chain(edges);
        let nodes = mesh.node_sets.entry(name.clone()).or_default();
        nodes.extend(edge_nodes(&edges));
        mesh.edge_sets.insert(name, edges);
    }
    for p in &file.points {
        for name in file.groups(r, p)? {
            let n = numbering.node(&file, r, p.nodes[0], p)?;
            mesh.node_sets.entry(name).or_default().push(n);
        }
    }
    for set in mesh.node_sets.values_mut() {
        set.sort_unstable();
        set.dedup();
    }
    Ok(mesh)
}

/// The quads in file numbering, counter-clockwise, all of `kind`.
fn oriented_quads(
    file: &File,
    r: &Reader,
    kind: ElementKind,
) -> Result<Vec<Vec<usize>>, MeshError> {
    let mut quads: Vec<Vec<usize>> = Vec::with_capacity(file.quads.len());
    for q in &file.quads {
        if q.nodes.len() != kind.node_count() {
            return Err(r.error_at(
                q.line,
                format!(
                    "element {} is a {}-node quadrilateral in a mesh of {}-node ones; \
                     mixed Q4 and Q8 meshes are not supported",
                    q.tag,
                    q.nodes.len(),
                    kind.node_count()
                ),
            ));
        }
        let mut nodes = Vec::with_capacity(q.nodes.len());
        let mut corners = Vec::with_capacity(4);
        for &t in &q.nodes {
            let (index, x) = file.node_of(r, t, q)?;
            nodes.push(index);
            corners.push(x);
        }
        if super::twice_signed_area(&corners[..4]) < 0.0 {
            let order: &[usize] = match kind {
                ElementKind::Q4 => &[0, 3, 2, 1],
                ElementKind::Q8 => &[0, 3, 2, 1, 7, 6, 5, 4],
            };
            nodes = order.iter().map(|&l| nodes[l]).collect();
        }
        quads.push(nodes);
    }
    Ok(quads)
}

/// The nodes quads use, in file order, and the numbering that keeps them.
fn used_nodes(file: &File, quads: &[Vec<usize>]) -> (Vec<[f64; 2]>, Numbering) {
    let mut coordinates = vec![[0.0; 2]; file.nodes.len()];
    for &(index, x) in file.nodes.values() {
        coordinates[index] = x;
    }
    let mut map = vec![usize::MAX; coordinates.len()];
    for q in quads {
        for &n in q {
            map[n] = 0;
        }
    }
    let mut nodes = Vec::new();
    for (i, slot) in map.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = nodes.len();
            nodes.push(coordinates[i]);
        }
    }
    (nodes, Numbering(map))
}

/// The edge sets of the named line elements: each line on the face of the
/// quad it lies on (between two quads, the face running the line's way).
fn edge_sets(
    file: &File,
    r: &Reader,
    mesh: &Mesh,
    numbering: &Numbering,
) -> Result<BTreeMap<String, Vec<Edge>>, MeshError> {
    let kind = mesh.elements[0].kind;
    // Faces by their corner nodes.
    let mut faces: HashMap<(usize, usize), Vec<(usize, usize)>> = HashMap::new();
    for (e, el) in mesh.elements.iter().enumerate() {
        for f in 0..4 {
            let (a, b) = (el.nodes[f], el.nodes[(f + 1) % 4]);
            faces.entry((a.min(b), a.max(b))).or_default().push((e, f));
        }
    }
    let node = |tag: u64, raw: &Raw| numbering.node(file, r, tag, raw);
    let mut edge_sets: BTreeMap<String, Vec<Edge>> = BTreeMap::new();
    for l in &file.lines {
        let names = file.groups(r, l)?;
        if names.is_empty() {
            continue;
        }
        let wanted = match kind {
            ElementKind::Q4 => 2,
            ElementKind::Q8 => 3,
        };
        if l.nodes.len() != wanted {
            return Err(r.error_at(
                l.line,
                format!(
                    "line element {} has {} nodes but the quadrilaterals have {}; \
                     use {wanted}-node lines",
                    l.tag,
                    l.nodes.len(),
                    kind.node_count()
                ),
            ));
        }
        let ends = [node(l.nodes[0], l)?, node(l.nodes[1], l)?];
        let key = (ends[0].min(ends[1]), ends[0].max(ends[1]));
        let candidates = faces.get(&key).map(Vec::as_slice).unwrap_or(&[]);
        // On a boundary one face owns the line; between two quads take the
        // face running the line's way.
        let owner = match candidates {
            [one] => Some(*one),
            _ => candidates
                .iter()
                .copied()
                .find(|&(e, f)| mesh.elements[e].nodes[f] == ends[0]),
        };
        let Some((e, f)) = owner else {
            return Err(r.error_at(
                l.line,
                format!(
                    "line element {} (nodes {} {}) is not on the face of any quadrilateral",
                    l.tag, l.nodes[0], l.nodes[1]
                ),
            ));
        };
        let el = &mesh.elements[e];
        let edge_nodes: Vec<usize> = face_local_nodes(kind, f)
            .iter()
            .map(|&k| el.nodes[k])
            .collect();
        if kind == ElementKind::Q8 && node(l.nodes[2], l)? != edge_nodes[2] {
            return Err(r.error_at(
                l.line,
                format!(
                    "line element {}: mid-side node {} is not the mid-side node of the \
                     quadrilateral face it lies on",
                    l.tag, l.nodes[2]
                ),
            ));
        }
        for name in names {
            edge_sets.entry(name).or_default().push(Edge {
                element: e,
                face: f,
                nodes: edge_nodes.clone(),
            });
        }
    }
    Ok(edge_sets)
}
