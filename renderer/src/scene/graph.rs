//! Groups as a scene graph (thesis Chapter III, "Transform Nodes in Scene Graph"): each object,
//! instance or group belongs to at most one group, and groups form a forest. A drawn object's
//! motion is the chain of its enclosing groups' layers, outermost first, then its own.

use super::file::GroupDesc;
use std::collections::HashMap;

/// Which group (index into the scene's groups) each named node belongs to.
#[derive(Clone, Debug, Default)]
pub struct Graph {
    parent: HashMap<String, usize>,
    group_names: Vec<String>,
}

/// What a name refers to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Node {
    Object { hidden: bool },
    Instance,
    Group,
}

impl Graph {
    /// Check the groups' children and link them; an error is `(field path, message)`.
    pub fn new(
        groups: &[GroupDesc],
        lookup: impl Fn(&str) -> Option<Node>,
    ) -> Result<Self, (String, String)> {
        let mut parent: HashMap<String, usize> = HashMap::new();
        for (g, group) in groups.iter().enumerate() {
            for (c, child) in group.children.iter().enumerate() {
                let field = format!("groups[{g}].children[{c}]");
                match lookup(child) {
                    None => {
                        return Err((
                            field,
                            format!(
                                "names `{child}`, but no object, instance or group has that name"
                            ),
                        ));
                    }
                    Some(Node::Object { hidden: true }) => {
                        return Err((
                            field,
                            format!(
                                "names object `{child}`, which is hidden (a template for \
                                 instances); place an instance of it instead"
                            ),
                        ));
                    }
                    Some(_) => {}
                }
                if let Some(&other) = parent.get(child) {
                    return Err((
                        field,
                        format!(
                            "names `{child}`, already a child of group `{}`; a node can belong \
                             to one group only",
                            groups[other].name
                        ),
                    ));
                }
                parent.insert(child.clone(), g);
            }
        }
        let graph = Self {
            parent,
            group_names: groups.iter().map(|g| g.name.clone()).collect(),
        };
        for (g, group) in groups.iter().enumerate() {
            if graph.ancestors(&group.name, groups.len()).contains(&g) {
                return Err((
                    format!("groups[{g}].children"),
                    format!("group `{}` ends up inside itself", group.name),
                ));
            }
        }
        Ok(graph)
    }

    /// Enclosing groups of `name`, innermost first; stops after `limit` steps (cycles).
    fn ancestors(&self, name: &str, limit: usize) -> Vec<usize> {
        let mut out = Vec::new();
        let mut at = name;
        while let Some(&g) = self.parent.get(at) {
            out.push(g);
            if out.len() > limit {
                break;
            }
            at = &self.group_names[g];
        }
        out
    }

    /// Enclosing groups of `name`, outermost first (after [`Graph::new`] succeeded).
    pub fn chain(&self, name: &str) -> Vec<usize> {
        let mut c = self.ancestors(name, usize::MAX);
        c.reverse();
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn group(name: &str, children: &[&str]) -> GroupDesc {
        GroupDesc {
            name: name.into(),
            children: children.iter().map(|c| c.to_string()).collect(),
            scale: None,
            location: [0.0; 3],
            velocity: [0.0; 3],
            rotation: [0.0; 3],
            angular_velocity: [0.0; 3],
        }
    }

    fn lookup(name: &str) -> Option<Node> {
        match name {
            "a" | "b" => Some(Node::Object { hidden: false }),
            "t" => Some(Node::Object { hidden: true }),
            "i" => Some(Node::Instance),
            "outer" | "inner" | "x" | "y" => Some(Node::Group),
            _ => None,
        }
    }

    #[test]
    fn chains_run_outermost_first() {
        let groups = [group("outer", &["inner", "b"]), group("inner", &["a", "i"])];
        let g = Graph::new(&groups, lookup).unwrap();
        assert_eq!(g.chain("a"), vec![0, 1]);
        assert_eq!(g.chain("i"), vec![0, 1]);
        assert_eq!(g.chain("b"), vec![0]);
        assert_eq!(g.chain("outer"), Vec::<usize>::new());
    }

    #[test]
    fn bad_groups_are_refused_naming_the_child() {
        let err = |groups: &[GroupDesc]| Graph::new(groups, lookup).unwrap_err();
        let (f, m) = err(&[group("x", &["a", "nope"])]);
        assert_eq!(f, "groups[0].children[1]");
        assert!(m.contains("nope"), "{m}");
        let (f, m) = err(&[group("x", &["a"]), group("y", &["a"])]);
        assert_eq!(f, "groups[1].children[0]");
        assert!(m.contains("already a child of group `x`"), "{m}");
        let (_, m) = err(&[group("x", &["y"]), group("y", &["x"])]);
        assert!(m.contains("inside itself"), "{m}");
        let (_, m) = err(&[group("x", &["x"])]);
        assert!(m.contains("inside itself"), "{m}");
        let (_, m) = err(&[group("x", &["t"])]);
        assert!(m.contains("hidden"), "{m}");
    }
}
