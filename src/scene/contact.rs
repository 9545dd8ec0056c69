//! `[[rigid]]` targets and `[[contact]]` pairs, oriented as the contact
//! kernel expects: a contactor surface is one ordered chain of nodes with its
//! body on the left from one node to the next; a target segment [A, B] has
//! the target body on the left of A -> B. Mesh edges already run with their
//! body on the left, so both come from edge sets as they are.

use super::raw::{self, DecisionsName, FormulationName, Pair, RecoveryName, RuleName, ValueSpec};
use super::{Resolver, SceneError, SceneErrorKind};
use crate::mesh::Edge;
use crate::problem::{
    ContactFormulation, ContactPair, Decisions, Driver, FrictionRule, Recovery, Rigid, Scaled,
    Target,
};
use std::collections::HashMap;
use toml::Spanned;

/// Pieces of a broken contactor set described in its error message.
const MAX_PIECES_SHOWN: usize = 4;

/// Chords a rigid arc may have.
const MAX_ARC_SEGMENTS: usize = 1_000_000;

impl Resolver<'_> {
    /// Rigid targets; their names are shared with the drivers, since both
    /// report reactions by name.
    pub(super) fn rigids(
        &self,
        list: &[Spanned<raw::Rigid>],
        drivers: &[Driver],
    ) -> Result<Vec<Rigid>, SceneError> {
        let mut rigids: Vec<Rigid> = Vec::new();
        for (i, r) in list.iter().enumerate() {
            let span = r.span();
            let r = r.get_ref();
            let key = |k: &str| format!("rigid[{i}].{k}");
            self.new_name(
                &r.name,
                key("name"),
                "rigid",
                rigids.iter().map(|r| r.name.as_str()),
                Some(" (a contact target with '.' is a body's edge set)"),
                true,
            )?;
            if let Some(d) = drivers.iter().position(|d| &d.name == r.name.get_ref()) {
                return Err(self.src.at(
                    SceneErrorKind::Duplicate,
                    r.name.span(),
                    key("name"),
                    format!(
                        "driver[{d}] has that name; rigids and drivers need distinct names \
                         (both report their reactions by name)"
                    ),
                ));
            }
            let (points, start) = match (&r.points, &r.arc) {
                (Some(points), None) => {
                    let points = self.polyline(points, &key("points"))?;
                    let first = points[0];
                    (points, first)
                }
                (None, Some(arc)) => (self.arc(arc, &key("arc"))?, arc.get_ref().center.0),
                (Some(_), Some(arc)) => {
                    return Err(self.invalid(
                        arc.span(),
                        key("arc"),
                        "give either `points` or `arc`, not both",
                    ));
                }
                (None, None) => {
                    return Err(self.src.missing(
                        span,
                        key("points"),
                        "a rigid gives exactly one of `points = [[x, y], ...]` or \
                         `arc = { center, radius, angles, segments }`",
                    ));
                }
            };
            let component = |spec: Option<&ValueSpec>, c: &str| {
                Ok::<_, SceneError>(
                    self.optional_scaled(spec, &key(c))?
                        .unwrap_or(Scaled::constant(0.0)),
                )
            };
            rigids.push(Rigid {
                name: r.name.get_ref().clone(),
                points,
                reference: r.reference.map_or(start, |p| p.0),
                ux: component(r.ux.as_ref(), "ux")?,
                uy: component(r.uy.as_ref(), "uy")?,
                theta: component(r.theta.as_ref(), "theta")?,
            });
        }
        Ok(rigids)
    }

    /// At least two points, no point equal to the one before it.
    fn polyline(
        &self,
        points: &Spanned<Vec<Spanned<Pair<f64>>>>,
        key: &str,
    ) -> Result<Vec<[f64; 2]>, SceneError> {
        let list = points.get_ref();
        if list.len() < 2 {
            return Err(self.invalid(
                points.span(),
                key,
                "a rigid polyline needs at least 2 points",
            ));
        }
        for (j, w) in list.windows(2).enumerate() {
            if w[0].get_ref().0 == w[1].get_ref().0 {
                return Err(self.invalid(
                    w[1].span(),
                    format!("{key}[{}]", j + 1),
                    "repeats the point before it; consecutive points must differ",
                ));
            }
        }
        Ok(list.iter().map(|p| p.get_ref().0).collect())
    }

    /// The points of an arc, from `angles[0]` to `angles[1]` (degrees) in
    /// `segments` equal steps.
    fn arc(&self, arc: &Spanned<raw::Arc>, key: &str) -> Result<Vec<[f64; 2]>, SceneError> {
        let a = arc.get_ref();
        let radius = self.positive(&a.radius, format!("{key}.radius"), "radius")?;
        let [a0, a1] = a.angles.get_ref().0;
        let sweep = a1 - a0;
        let angles_error =
            |message: &str| self.invalid(a.angles.span(), format!("{key}.angles"), message);
        if sweep == 0.0 {
            return Err(angles_error(
                "the two angles must differ (the arc runs from the first to the second)",
            ));
        }
        if sweep.abs() > 360.0 {
            return Err(angles_error("an arc spans at most 360 degrees"));
        }
        let n = *a.segments.get_ref();
        let segments_error =
            |message: &str| self.invalid(a.segments.span(), format!("{key}.segments"), message);
        if n == 0 {
            return Err(segments_error("segments must be at least 1"));
        }
        if n == 1 && sweep.abs() == 360.0 {
            return Err(segments_error("a full circle needs at least 2 segments"));
        }
        // The contact search runs over every segment of a rigid target:
        // more than a million is a mistake (the capstans use 5120), and
        // 1e8 of them took 15 GB and minutes before any step.
        if n > MAX_ARC_SEGMENTS {
            return Err(segments_error(&format!(
                "at most {MAX_ARC_SEGMENTS} segments (a polyline of that many chords is finer than any contactor needs)"
            )));
        }
        let [cx, cy] = a.center.0;
        let points: Vec<[f64; 2]> = (0..=n)
            .map(|i| {
                let angle = (a0 + sweep * i as f64 / n as f64).to_radians();
                [cx + radius * angle.cos(), cy + radius * angle.sin()]
            })
            .collect();
        if points.windows(2).any(|w| w[0] == w[1]) {
            return Err(self.invalid(
                a.radius.span(),
                format!("{key}.radius"),
                "the radius is too small for the center's coordinates: consecutive points \
                 of the arc coincide in floating point",
            ));
        }
        Ok(points)
    }

    /// Contact pairs: a contactor edge set against another body's edge set
    /// or a rigid.
    pub(super) fn contacts(
        &self,
        list: &[raw::Contact],
        rigids: &[Rigid],
    ) -> Result<Vec<ContactPair>, SceneError> {
        let mut pairs: Vec<ContactPair> = Vec::new();
        for (i, c) in list.iter().enumerate() {
            let key = |k: &str| format!("contact[{i}].{k}");
            self.new_name(
                &c.name,
                key("name"),
                "contact",
                pairs.iter().map(|p| p.name.as_str()),
                Some(""),
                true,
            )?;
            let contactor_key = key("contactor");
            let edges = self.edge_set(&c.contactor, &contactor_key)?;
            let body = self.set_body(&c.contactor, &contactor_key)?;
            let (contactor, closed) = self.contactor_chain(&edges, &c.contactor, &contactor_key)?;
            let mut target = self.target(&c.target, &key("target"), body, rigids)?;
            let coefficient = |value: &Spanned<f64>, k: &str| {
                let v = *value.get_ref();
                if v >= 0.0 {
                    Ok(v)
                } else {
                    Err(self.invalid(value.span(), key(k), format!("{k} must not be negative")))
                }
            };
            let mu_s = c
                .mu_s
                .as_ref()
                .map_or(Ok(0.0), |v| coefficient(v, "mu_s"))?;
            let mu_d = match &c.mu_d {
                None => mu_s,
                Some(value) => {
                    let v = coefficient(value, "mu_d")?;
                    if v > mu_s {
                        let default = if c.mu_s.is_none() {
                            " (mu_s defaults to 0)"
                        } else {
                            ""
                        };
                        return Err(self.invalid(
                            value.span(),
                            key("mu_d"),
                            format!("mu_d must not exceed mu_s = {mu_s:?}{default}"),
                        ));
                    }
                    v
                }
            };
            let formulation = self.formulation(c, &target, &key("formulation"))?;
            self.smooth_target(c, &mut target, formulation, &key("smooth_target"))?;
            pairs.push(ContactPair {
                name: c.name.get_ref().clone(),
                body,
                contactor,
                closed,
                target,
                mu_s,
                mu_d,
                rule: match c.rule {
                    None | Some(RuleName::MuDAfterSlip) => FrictionRule::MuDAfterSlip,
                    Some(RuleName::AlwaysMuS) => FrictionRule::AlwaysMuS,
                },
                recovery: match c.recovery {
                    None | Some(RecoveryName::Consistent) => Recovery::Consistent,
                    Some(RecoveryName::Lumped) => Recovery::Lumped,
                },
                decisions: match c.decisions {
                    None | Some(DecisionsName::Nodal) => Decisions::Nodal,
                    Some(DecisionsName::Paper) => Decisions::Paper,
                },
                formulation,
            });
        }
        Ok(pairs)
    }

    /// A pair's formulation: `formulation` when given; otherwise mortar
    /// against a body and node-to-segment against a rigid (mortar has no
    /// rigid targets) or when the pair names `decisions` (those are
    /// node-to-segment's). Mortar needs a body as target and no `decisions`.
    fn formulation(
        &self,
        c: &raw::Contact,
        target: &Target,
        key: &str,
    ) -> Result<ContactFormulation, SceneError> {
        let Some(f) = &c.formulation else {
            return Ok(match target {
                Target::Body { .. } if c.decisions.is_none() => ContactFormulation::Mortar,
                _ => ContactFormulation::NodeToSegment,
            });
        };
        if *f.get_ref() == FormulationName::NodeToSegment {
            return Ok(ContactFormulation::NodeToSegment);
        }
        let refuse = |why: &str| Err(self.invalid(f.span(), key, why.to_string()));
        if matches!(target, Target::Rigid(_)) {
            return refuse("mortar contact needs a body's edge set as target, not a rigid");
        }
        if c.decisions.is_some() {
            return refuse(
                "`decisions` chooses node-to-segment's state decisions; a mortar pair has none",
            );
        }
        Ok(ContactFormulation::Mortar)
    }

    /// `smooth_target = true`: the target's surface smoothed through its
    /// nodes (each segment a Catmull-Rom curve through its outer
    /// neighbours). Node-to-segment against a body's edge set under the
    /// nodal decisions only.
    fn smooth_target(
        &self,
        c: &raw::Contact,
        target: &mut Target,
        formulation: ContactFormulation,
        key: &str,
    ) -> Result<(), SceneError> {
        let Some(flag) = &c.smooth_target else {
            return Ok(());
        };
        if !*flag.get_ref() {
            return Ok(());
        }
        let refuse = |why: &str| Err(self.invalid(flag.span(), key, why.to_string()));
        if formulation != ContactFormulation::NodeToSegment {
            return refuse(
                "smooth_target smooths node-to-segment's target; mortar's normals are \
                 already continuous (set formulation = \"node_to_segment\")",
            );
        }
        if matches!(c.decisions, Some(DecisionsName::Paper)) {
            return refuse("smooth_target needs the nodal decisions (decisions = \"nodal\")");
        }
        let Target::Body {
            segments, smooth, ..
        } = target
        else {
            return refuse("smooth_target needs a body's edge set as target, not a rigid");
        };
        let mut before = HashMap::new();
        let mut after = HashMap::new();
        for &[a, b] in segments.iter() {
            before.insert(b, a);
            after.insert(a, b);
        }
        *smooth = Some(
            (segments.iter())
                .map(|[a, b]| [before.get(a).copied(), after.get(b).copied()])
                .collect(),
        );
        Ok(())
    }

    /// The index of the body a set reference `<body>.<set>` names.
    pub(super) fn set_body(&self, set: &Spanned<String>, key: &str) -> Result<usize, SceneError> {
        let (name, _) = self.set_ref(set, key)?;
        Ok(self
            .bodies
            .iter()
            .position(|b| b.name == name)
            .expect("set_ref returns a body's name"))
    }

    /// `<body>.<edge set>` of a body other than the contactor's, or a rigid's
    /// name.
    fn target(
        &self,
        target: &Spanned<String>,
        key: &str,
        contactor_body: usize,
        rigids: &[Rigid],
    ) -> Result<Target, SceneError> {
        let name = target.get_ref();
        if name.contains('.') {
            let edges = self.edge_set(target, key)?;
            let body = self.set_body(target, key)?;
            if body == contactor_body {
                return Err(self.invalid(
                    target.span(),
                    key,
                    format!(
                        "the target must belong to another body than the contactor (`{}`)",
                        self.bodies[body].name
                    ),
                ));
            }
            if self.bodies[body].running {
                return Err(self.invalid(
                    target.span(),
                    key,
                    format!(
                        "body `{}` runs: it can be a contactor, not a target",
                        self.bodies[body].name
                    ),
                ));
            }
            let segments = edges
                .iter()
                .flat_map(|e| {
                    let nodes = walk(e);
                    (1..nodes.len())
                        .map(|k| [nodes[k - 1], nodes[k]])
                        .collect::<Vec<_>>()
                })
                .collect();
            return Ok(Target::Body {
                body,
                segments,
                smooth: None,
            });
        }
        if let Some(r) = rigids.iter().position(|r| &r.name == name) {
            return Ok(Target::Rigid(r));
        }
        let names: Vec<&str> = rigids.iter().map(|r| r.name.as_str()).collect();
        let rigids = if names.is_empty() {
            "(none)".to_string()
        } else {
            names.join(", ")
        };
        let message = if self.bodies.iter().any(|b| &b.name == name) {
            format!(
                "`{name}` is a body, not a rigid; a body target is one of its edge sets, \
                 `{name}.<set>` (edge sets: {}); rigids: {rigids}",
                self.set_names(name, true)
            )
        } else {
            format!(
                "no rigid of that name (a body's edge set is written <body>.<set>); \
                 rigids: {rigids}"
            )
        };
        Err(self.src.at(
            SceneErrorKind::UnknownReference,
            target.span(),
            key,
            message,
        ))
    }

    /// The nodes of an edge set as one chain, each edge's last node the
    /// next one's first, and whether the chain closes on itself (its first
    /// node then is not repeated at the end). A closed loop starts with the
    /// set's first edge.
    fn contactor_chain(
        &self,
        edges: &[Edge],
        set: &Spanned<String>,
        key: &str,
    ) -> Result<(Vec<usize>, bool), SceneError> {
        let fail = |message: String| {
            self.invalid(
                set.span(),
                key,
                format!(
                    "edge set `{}` {message}; a contactor surface must be one chain or one \
                     closed loop",
                    set.get_ref()
                ),
            )
        };
        let at = |n: usize| {
            let [x, y] = self.mesh.nodes[n];
            format!("({x}, {y})")
        };
        if edges.is_empty() {
            return Err(fail("has no edges".into()));
        }
        // Edge starting, and edge ending, at each node.
        let mut from: HashMap<usize, usize> = HashMap::new();
        let mut to: HashMap<usize, usize> = HashMap::new();
        for (k, e) in edges.iter().enumerate() {
            let (a, b) = (e.nodes[0], e.nodes[1]);
            if from.insert(a, k).is_some() {
                return Err(fail(format!(
                    "branches at {}: two of its edges start there",
                    at(a)
                )));
            }
            if to.insert(b, k).is_some() {
                return Err(fail(format!(
                    "branches at {}: two of its edges end there",
                    at(b)
                )));
            }
        }
        // Open chains from the edges no other edge leads to, then loops.
        let heads: Vec<usize> = (0..edges.len())
            .filter(|&k| !to.contains_key(&edges[k].nodes[0]))
            .collect();
        let open = heads.len();
        let mut used = vec![false; edges.len()];
        let mut pieces: Vec<Vec<usize>> = Vec::new();
        for first in heads.into_iter().chain(0..edges.len()) {
            if used[first] {
                continue;
            }
            let mut piece = Vec::new();
            let mut k = first;
            loop {
                used[k] = true;
                piece.push(k);
                match from.get(&edges[k].nodes[1]) {
                    Some(&j) if !used[j] => k = j,
                    _ => break,
                }
            }
            pieces.push(piece);
        }
        if pieces.len() > 1 {
            let describe = |(p, piece): (usize, &Vec<usize>)| {
                let first = edges[piece[0]].nodes[0];
                if p < open {
                    let last = edges[piece[piece.len() - 1]].nodes[1];
                    format!("a chain from {} to {}", at(first), at(last))
                } else {
                    format!("a closed loop through {}", at(first))
                }
            };
            let mut shown: Vec<String> = pieces
                .iter()
                .enumerate()
                .take(MAX_PIECES_SHOWN)
                .map(describe)
                .collect();
            if pieces.len() > MAX_PIECES_SHOWN {
                shown.push("...".into());
            }
            return Err(fail(format!(
                "falls apart into {} separate pieces: {}",
                pieces.len(),
                shown.join("; ")
            )));
        }
        let mut nodes = vec![edges[pieces[0][0]].nodes[0]];
        for &k in &pieces[0] {
            nodes.extend_from_slice(&walk(&edges[k])[1..]);
        }
        let closed = open == 0;
        if closed {
            nodes.pop();
        }
        Ok((nodes, closed))
    }
}

/// An edge's nodes in walking order: start, (mid-side,) end. `Edge::nodes`
/// holds the mid-side node of a Q8 face last.
pub(super) fn walk(e: &Edge) -> Vec<usize> {
    match e.nodes[..] {
        [a, b, m] => vec![a, m, b],
        _ => e.nodes.clone(),
    }
}
