//! `[[tie]]`: the nodes of one body tied to an edge set of another by
//! constant constraint equations (normal only, or both directions).

use super::contact::walk;
use super::raw::{self, TieKindName};
use super::{Resolver, SceneError};
use crate::constraint::{Tie, TieKind, tie_rows};

impl Resolver<'_> {
    pub(super) fn ties(&self, list: &[raw::Tie]) -> Result<Vec<Tie>, SceneError> {
        let mut ties: Vec<Tie> = Vec::new();
        for (i, t) in list.iter().enumerate() {
            let key = |k: &str| format!("tie[{i}].{k}");
            self.new_name(
                &t.name,
                key("name"),
                "tie",
                ties.iter().map(|t| t.name.as_str()),
                Some(""),
                false,
            )?;
            let nodes = self.node_set(&t.nodes, &key("nodes"))?;
            let body = self.set_body(&t.nodes, &key("nodes"))?;
            let edges = self.edge_set(&t.to, &key("to"))?;
            if self.set_body(&t.to, &key("to"))? == body {
                return Err(self.invalid(
                    t.to.span(),
                    key("to"),
                    format!(
                        "the surface must belong to another body than the tied nodes (`{}`)",
                        self.bodies[body].name
                    ),
                ));
            }
            let segments: Vec<[usize; 2]> = edges
                .iter()
                .flat_map(|e| {
                    let w = walk(e);
                    (1..w.len()).map(move |k| [w[k - 1], w[k]])
                })
                .collect();
            let kind = match t.kind {
                TieKindName::Normal => TieKind::Normal,
                TieKindName::Full => TieKind::Full,
            };
            let (rows, normals) =
                tie_rows(&self.mesh.nodes, &nodes, &segments, kind).map_err(|m| {
                    self.invalid(
                        t.nodes.span(),
                        key("nodes"),
                        format!("{m} `{}`", t.to.get_ref()),
                    )
                })?;
            ties.push(Tie {
                name: t.name.get_ref().clone(),
                kind,
                nodes,
                normals,
                rows,
            });
        }
        Ok(ties)
    }
}
