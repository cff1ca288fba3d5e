//! Graphviz output of a compiled plan: passes as boxes, resources as ellipses, culled passes
//! greyed out, and an edge labelled `next frame` from each kept resource to its history
//! resource (`LayerDesc::history`). Built with petgraph's `Dot` writer.

use super::compile::Plan;
use petgraph::dot::{Config, Dot};
use petgraph::graph::DiGraph;

/// Writes the plan's kept passes and resources as a Graphviz digraph.
pub fn to_dot(plan: &Plan) -> String {
    let mut g: DiGraph<String, &'static str> = DiGraph::new();
    let res: Vec<_> = plan
        .resources
        .iter()
        .map(|r| {
            let alloc = match r.slot {
                Some(s) => format!("slot {s}"),
                None => "unused".to_string(),
            };
            g.add_node(format!("{}\\n{}", r.name, alloc))
        })
        .collect();
    for p in &plan.passes {
        let v = g.add_node(format!("[{}] {}", p.kind.name(), p.name));
        for (_, r) in &p.reads {
            g.add_edge(res[*r], v, "read");
        }
        for (_, r) in &p.writes {
            g.add_edge(v, res[*r], "write");
        }
    }
    for (h, r) in plan.resources.iter().enumerate() {
        if let (Some(source), true) = (r.history_of, r.slot.is_some()) {
            g.add_edge(res[source], res[h], "next frame");
        }
    }
    for c in &plan.culled {
        g.add_node(format!("[culled] {c}"));
    }
    let body = format!(
        "{:?}",
        Dot::with_attr_getters(
            &g,
            &[Config::EdgeNoLabel],
            &|_, e| if *e.weight() == "next frame" { "style=dashed label=\"next frame\"".into() } else { String::new() },
            &|_, _| String::new()
        )
    );
    body.replace("\\\\n", "\\n")
}
