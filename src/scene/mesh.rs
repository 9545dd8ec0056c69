//! A body's `mesh` table: one of the generators, or a Gmsh file (optionally
//! one 2D physical group of it). Values the generators would reject are
//! checked here so the error names the key.

use super::raw::{self, GeneratorName, Pair};
use super::{Resolver, SceneError, SceneErrorKind};
use crate::mesh::{ElementKind, Mesh, generators, gmsh};
use crate::strip::StripPath;
use toml::Spanned;

const DIVISIONS: &str = "divisions must be at least 1";

/// `factor` times the product of two division counts; None on overflow.
fn product(d: [usize; 2], factor: usize) -> Option<usize> {
    d[0].checked_mul(d[1])?.checked_mul(factor)
}

impl Resolver<'_> {
    /// The body's reference mesh, and the path it is laid along (a
    /// `strip` mesh only).
    pub(super) fn body_mesh(
        &self,
        i: usize,
        body: &raw::Body,
    ) -> Result<(Mesh, Option<StripPath>), SceneError> {
        let index = i.to_string();
        let path_key = ["body", index.as_str(), "mesh"];
        let key = |k: &str| format!("body[{i}].mesh.{k}");
        let head: raw::MeshHead = self.table_at(&path_key)?;
        let kind = body
            .element
            .as_ref()
            .map_or(ElementKind::Q4, |e| *e.get_ref());
        let mut path = None;
        let generated = match (head.generator, head.file) {
            (Some(generator), _) => match generator.get_ref() {
                GeneratorName::Rectangle => {
                    let r: raw::Rectangle = self.table_at(&path_key)?;
                    let size = self.positive_pair(&r.size, key("size"), "size")?;
                    let divisions = self.divisions(&r.divisions, key("divisions"))?;
                    self.budget(product(divisions, 1), r.divisions.span(), key("divisions"))?;
                    let ratio = match &r.ratio {
                        Some(ratio) => self.positive_pair(ratio, key("ratio"), "ratio")?,
                        None => [1.0, 1.0],
                    };
                    generators::rectangle(kind, r.origin.0, size, divisions, ratio)
                }
                GeneratorName::Disk => {
                    let d: raw::Disk = self.table_at(&path_key)?;
                    let radius = self.positive(&d.radius, key("radius"), "radius")?;
                    let divisions = *d.divisions.get_ref();
                    if divisions == 0 {
                        return Err(self.invalid(d.divisions.span(), key("divisions"), DIVISIONS));
                    }
                    // The core and the shell: at most 2 n^2 elements.
                    let n2 = product([divisions, divisions], 2);
                    self.budget(n2, d.divisions.span(), key("divisions"))?;
                    let ratio = self.ratio(d.ratio.as_ref(), key("ratio"))?;
                    generators::disk(
                        kind,
                        d.center.0,
                        radius,
                        divisions,
                        ratio,
                        d.half.unwrap_or(false),
                    )
                }
                GeneratorName::Ring => {
                    let r: raw::Ring = self.table_at(&path_key)?;
                    let inner = self.positive(&r.r_inner, key("r_inner"), "r_inner")?;
                    let outer = self.exceeding(&r.r_outer, inner, key("r_outer"), "r_inner")?;
                    let angles = self.increasing_pair(&r.angles, key("angles"))?;
                    let divisions = self.divisions(&r.divisions, key("divisions"))?;
                    self.budget(product(divisions, 1), r.divisions.span(), key("divisions"))?;
                    let ratio = self.ratio(r.ratio.as_ref(), key("ratio"))?;
                    generators::ring(kind, r.center.0, inner, outer, angles, divisions, ratio)
                }
                GeneratorName::Strip => {
                    let r: raw::Strip = self.table_at(&path_key)?;
                    let planar =
                        !matches!(self.analysis, crate::problem::AnalysisKind::Axisymmetric);
                    if !planar || self.kinematics != crate::problem::Kinematics::TotalLagrangian {
                        return Err(self.invalid(
                            generator.span(),
                            key("generator"),
                            "a strip is bent onto its path from a straight reference: it needs \
                             a planar analysis with `kinematics = \"total_lagrangian\"`",
                        ));
                    }
                    let (p, divisions) = self.strip_path(&r, &key)?;
                    let along = divisions[1]
                        .checked_add(r.spans.get_ref().0[0])
                        .and_then(|n| n.checked_add(r.spans.get_ref().0[1]));
                    let count = along.and_then(|n| product([n, divisions[0]], 1));
                    self.budget(count, r.divisions.span(), key("divisions"))?;
                    let along = along.unwrap_or(usize::MAX);
                    let made = generators::strip(
                        kind,
                        p.length(),
                        p.thickness,
                        p.inner_y() > 0.0,
                        [along, divisions[0]],
                    );
                    path = Some(p);
                    made
                }
                GeneratorName::PlateWithHole => {
                    let p: raw::PlateWithHole = self.table_at(&path_key)?;
                    let hole = self.positive(&p.hole_radius, key("hole_radius"), "hole_radius")?;
                    let width = self.exceeding(&p.width, hole, key("width"), "hole_radius")?;
                    let y_range = self.increasing_pair(&p.y_range, key("y_range"))?;
                    let divisions = self.divisions(&p.divisions, key("divisions"))?;
                    // The O-grid round the hole; the strips that fill the
                    // plate are counted once the mesh is made.
                    self.budget(product(divisions, 1), p.divisions.span(), key("divisions"))?;
                    let ratio = self.ratio(p.ratio.as_ref(), key("ratio"))?;
                    generators::plate_with_hole(kind, hole, width, y_range, divisions, ratio)
                }
            },
            (None, Some(_)) => {
                if let Some(element) = &body.element {
                    return Err(self.invalid(
                        element.span(),
                        format!("body[{i}].element"),
                        "a mesh file brings its own element kind; remove `element`",
                    ));
                }
                let f: raw::MeshFile = self.table_at(&path_key)?;
                return Ok((self.mesh_file(&f, i)?, None));
            }
            (None, None) => {
                return Err(self.src.missing(
                    body.mesh.span(),
                    key("generator"),
                    "a mesh needs `generator` (rectangle, disk, ring, plate_with_hole, strip) or `file`",
                ));
            }
        };
        let mesh = generated.map_err(|e| {
            self.src.at(
                SceneErrorKind::Mesh,
                body.mesh.span(),
                format!("body[{i}].mesh"),
                e.to_string(),
            )
        })?;
        let made = Some(mesh.elements.len());
        self.budget(made, body.mesh.span(), format!("body[{i}].mesh"))?;
        Ok((mesh, path))
    }

    /// A `strip` mesh's path and divisions [across, along the wrap]: the
    /// elements are alike along the whole strip, each spanning 1 / n of
    /// the wrap's mid-line.
    fn strip_path(
        &self,
        r: &raw::Strip,
        key: &dyn Fn(&str) -> String,
    ) -> Result<(StripPath, [usize; 2]), SceneError> {
        let radius = self.positive(&r.radius, key("radius"), "radius")?;
        let thickness = self.positive(&r.thickness, key("thickness"), "thickness")?;
        let [a0, a1] = r.angles.get_ref().0;
        let wrap = a1 - a0;
        if wrap == 0.0 || wrap.abs() >= 360.0 {
            return Err(self.invalid(
                r.angles.span(),
                key("angles"),
                "the wrap a1 - a0 must be nonzero and less than 360 degrees in size",
            ));
        }
        let divisions = self.divisions(&r.divisions, key("divisions"))?;
        let spans = self.divisions(&r.spans, key("spans"))?;
        let strain = match &r.strain {
            Some(e) if !(*e.get_ref() > -0.5 && *e.get_ref() < 1.0) => {
                return Err(self.invalid(
                    e.span(),
                    key("strain"),
                    "the strain the strip is laid at must lie between -0.5 and 1",
                ));
            }
            Some(e) => *e.get_ref(),
            None => 0.0,
        };
        let mut p = StripPath {
            center: r.center.0,
            radius,
            thickness,
            start_angle: a0.to_radians(),
            wrap: wrap.to_radians(),
            spans: [0.0; 2],
            strain,
            element: 0.0,
        };
        // Along the path each element spans 1 / n of the wrap.
        let h = p.wrap_length() / divisions[1] as f64;
        p.spans = [spans[0] as f64 * h, spans[1] as f64 * h];
        p.element = h / (1.0 + strain);
        Ok((p, divisions))
    }

    /// Refuses a body of `elements` (None: beyond counting) when the scene's
    /// bodies would have more than `[solver] max_elements` with it; checked
    /// before a generator allocates.
    fn budget(
        &self,
        elements: Option<usize>,
        span: std::ops::Range<usize>,
        key: String,
    ) -> Result<(), SceneError> {
        let left = self.max_elements.saturating_sub(self.mesh.elements.len());
        match elements {
            Some(n) if n <= left => Ok(()),
            _ => {
                let count =
                    elements.map_or_else(|| "more than 2^64".to_string(), |n| n.to_string());
                let used = self.max_elements - left;
                let before = if used > 0 {
                    format!(", and the bodies before this one have {used}")
                } else {
                    String::new()
                };
                Err(self.invalid(
                    span,
                    key,
                    format!(
                        "{count} elements: more than the scene may have \
                         ([solver] max_elements = {}, which a scene may raise{before})",
                        self.max_elements
                    ),
                ))
            }
        }
    }

    /// A Gmsh file, relative to the scene file; `group` keeps the elements
    /// of one 2D physical group.
    fn mesh_file(&self, f: &raw::MeshFile, i: usize) -> Result<Mesh, SceneError> {
        let dir = self.src.file.parent().unwrap_or(std::path::Path::new(""));
        let mesh = gmsh::read(&dir.join(f.file.get_ref())).map_err(|e| {
            self.src.at(
                SceneErrorKind::Mesh,
                f.file.span(),
                format!("body[{i}].mesh.file"),
                e.to_string(),
            )
        })?;
        let within = Some(mesh.elements.len());
        self.budget(within, f.file.span(), format!("body[{i}].mesh.file"))?;
        let Some(group) = &f.group else {
            return Ok(mesh);
        };
        match mesh.element_sets.get(group.get_ref()) {
            Some(elements) => Ok(mesh.subset(elements)),
            None => {
                let names: Vec<&str> = mesh.element_sets.keys().map(String::as_str).collect();
                let names = if names.is_empty() {
                    "(none)".into()
                } else {
                    names.join(", ")
                };
                Err(self.src.at(
                    SceneErrorKind::UnknownReference,
                    group.span(),
                    format!("body[{i}].mesh.group"),
                    format!("the mesh file has no 2D physical group of that name; groups: {names}"),
                ))
            }
        }
    }

    fn positive_pair(
        &self,
        pair: &Spanned<Pair<f64>>,
        key: String,
        what: &str,
    ) -> Result<[f64; 2], SceneError> {
        let v = pair.get_ref().0;
        if v.iter().all(|&x| x > 0.0) {
            Ok(v)
        } else {
            Err(self.invalid(
                pair.span(),
                key,
                format!("both {what} components must be positive"),
            ))
        }
    }

    /// A value that must exceed `bound`, the value of key `bound_key`.
    fn exceeding(
        &self,
        value: &Spanned<f64>,
        bound: f64,
        key: String,
        bound_key: &str,
    ) -> Result<f64, SceneError> {
        let v = *value.get_ref();
        if v > bound {
            Ok(v)
        } else {
            let message = format!("must exceed {bound_key} = {bound:?}");
            Err(self.invalid(value.span(), key, message))
        }
    }

    fn increasing_pair(
        &self,
        pair: &Spanned<Pair<f64>>,
        key: String,
    ) -> Result<[f64; 2], SceneError> {
        let v = pair.get_ref().0;
        if v[1] > v[0] {
            Ok(v)
        } else {
            Err(self.invalid(pair.span(), key, "the second value must exceed the first"))
        }
    }

    fn divisions(&self, n: &Spanned<Pair<usize>>, key: String) -> Result<[usize; 2], SceneError> {
        let v = n.get_ref().0;
        if v.iter().all(|&d| d > 0) {
            Ok(v)
        } else {
            Err(self.invalid(n.span(), key, DIVISIONS))
        }
    }

    /// Grading ratio of a generator; 1 when not given.
    fn ratio(&self, ratio: Option<&Spanned<f64>>, key: String) -> Result<f64, SceneError> {
        ratio.map_or(Ok(1.0), |r| self.positive(r, key, "ratio"))
    }
}
