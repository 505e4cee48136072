//! The scene's objects, instances and groups as instances to draw: each one's shape (a model
//! file loaded once however many objects name it), material and motion chain (its enclosing
//! groups' layers, outermost first, then its own: [`crate::scene::graph`]).

use super::check::{Check, Placement};
use crate::accel::Instance;
use crate::geometry::{Plane, Shape, Sphere, TriangleMesh};
use crate::motion::{Motion, MotionLayer};
use crate::scene::file::{InstanceDesc, ObjectDesc, ObjectKind, SceneFile};
use crate::scene::graph::{Graph, Node};
use anyhow::Result;
use glam::{Vec2, Vec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Every drawn object (hidden ones are templates for instances), then every instance, in the
/// file's order.
pub(super) fn instances(c: &Check, f: &SceneFile, dir: &Path) -> Result<Vec<Instance>> {
    let placer = Placer::new(c, f)?;
    let mut meshes = MeshCache::default();
    let mut shapes = Vec::new();
    let mut instances = Vec::new();
    for (i, o) in f.objects.iter().enumerate() {
        let at = format!("objects[{i}]");
        let shape = object_shape(c, &at, o, dir, &mut meshes)?;
        let scale = c.scale(format!("{at}.scale"), o.scale)?;
        let material = placer.material(format!("{at}.material"), &o.material)?;
        let own = c.layer(
            &at,
            Placement {
                location: o.location,
                velocity: o.velocity,
                rotation: o.rotation,
                angular_velocity: o.angular_velocity,
                scale,
            },
        )?;
        if !o.hidden {
            instances.push(Instance {
                shape: shape.clone(),
                motion: placer.motion(&o.name, own),
                material,
            });
        }
        shapes.push((shape, material, scale));
    }
    for (i, d) in f.instances.iter().enumerate() {
        instances.push(placer.instance(&format!("instances[{i}]"), d, &shapes)?);
    }
    Ok(instances)
}

/// An object's shape, material and own scale, which its instances start from.
type ObjectParts = (Shape, u32, Option<Vec3>);

/// What places an object or an instance: the materials by name and the groups' motion layers.
struct Placer<'a> {
    c: &'a Check<'a>,
    f: &'a SceneFile,
    material_index: HashMap<&'a str, u32>,
    graph: Graph,
    group_layers: Vec<MotionLayer>,
}

impl<'a> Placer<'a> {
    /// Checks the names and the groups (their children, then their placements).
    fn new(c: &'a Check<'a>, f: &'a SceneFile) -> Result<Self> {
        let material_index = f
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| (m.name.as_str(), i as u32))
            .collect();
        let nodes = node_names(c, f)?;
        let graph = Graph::new(&f.groups, |n| nodes.get(n).copied())
            .map_err(|(field, what)| c.err(field, what))?;
        let group_layers = f
            .groups
            .iter()
            .enumerate()
            .map(|(i, g)| {
                let at = format!("groups[{i}]");
                let scale = c.scale(format!("{at}.scale"), g.scale)?;
                c.layer(
                    &at,
                    Placement {
                        location: g.location,
                        velocity: g.velocity,
                        rotation: g.rotation,
                        angular_velocity: g.angular_velocity,
                        scale,
                    },
                )
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            c,
            f,
            material_index,
            graph,
            group_layers,
        })
    }

    /// The index of the material `name` (at `field`).
    fn material(&self, field: String, name: &str) -> Result<u32> {
        self.material_index.get(name).copied().ok_or_else(|| {
            self.c.err(
                field,
                format!(
                    "names material `{name}`, which is not defined (materials: {})",
                    Check::name_list(self.f.materials.iter().map(|m| m.name.as_str()))
                ),
            )
        })
    }

    /// The motion of node `name`: its groups' layers, outermost first, then `own`.
    fn motion(&self, name: &str, own: MotionLayer) -> Motion {
        Motion {
            layers: self
                .graph
                .chain(name)
                .into_iter()
                .map(|g| self.group_layers[g])
                .chain(std::iter::once(own))
                .collect(),
        }
    }

    /// Instance `d` (at `at`) of one of the `objects`: the object's shape, its material and
    /// scale unless the instance sets its own.
    fn instance(&self, at: &str, d: &InstanceDesc, objects: &[ObjectParts]) -> Result<Instance> {
        let (c, f) = (self.c, self.f);
        let Some(o) = f.objects.iter().position(|o| o.name == d.object) else {
            return Err(c.err(
                format!("{at}.object"),
                format!(
                    "names object `{}`, which is not defined (objects: {})",
                    d.object,
                    Check::name_list(f.objects.iter().map(|o| o.name.as_str()))
                ),
            ));
        };
        let (shape, object_material, object_scale) = &objects[o];
        let material = match &d.material {
            Some(m) => self.material(format!("{at}.material"), m)?,
            None => *object_material,
        };
        let scale = c.scale(format!("{at}.scale"), d.scale)?.or(*object_scale);
        let own = c.layer(
            at,
            Placement {
                location: d.location,
                velocity: d.velocity,
                rotation: d.rotation,
                angular_velocity: d.angular_velocity,
                scale,
            },
        )?;
        Ok(Instance {
            shape: shape.clone(),
            motion: self.motion(&d.name, own),
            material,
        })
    }
}

/// Every object, instance and group name, checked to be unique and non-empty.
fn node_names<'f>(c: &Check, f: &'f SceneFile) -> Result<HashMap<&'f str, Node>> {
    let mut nodes: HashMap<&str, (Node, String)> = HashMap::new();
    let all = f
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| {
            (
                format!("objects[{i}]"),
                o.name.as_str(),
                Node::Object { hidden: o.hidden },
            )
        })
        .chain(
            f.instances
                .iter()
                .enumerate()
                .map(|(i, d)| (format!("instances[{i}]"), d.name.as_str(), Node::Instance)),
        )
        .chain(
            f.groups
                .iter()
                .enumerate()
                .map(|(i, g)| (format!("groups[{i}]"), g.name.as_str(), Node::Group)),
        );
    for (at, name, node) in all {
        if name.is_empty() {
            return Err(c.err(format!("{at}.name"), "is empty; expected a name"));
        }
        if let Some((_, other)) = nodes.get(name) {
            return Err(c.err(
                format!("{at}.name"),
                format!(
                    "repeats `{name}` (already {other}); objects, instances and groups share \
                     one set of names"
                ),
            ));
        }
        nodes.insert(name, (node, at));
    }
    Ok(nodes.into_iter().map(|(k, (n, _))| (k, n)).collect())
}

/// Meshes already loaded, by resolved path: objects naming the same file share one mesh.
#[derive(Default)]
struct MeshCache {
    loaded: HashMap<PathBuf, Arc<TriangleMesh>>,
}

fn object_shape(
    c: &Check,
    at: &str,
    o: &ObjectDesc,
    dir: &Path,
    meshes: &mut MeshCache,
) -> Result<Shape> {
    let kind = match o.kind {
        ObjectKind::Model => "model",
        ObjectKind::Sphere => "sphere",
        ObjectKind::Plane => "plane",
    };
    let f = |name: &str| format!("{at}.{name}");
    c.presence(f("file"), &o.file, o.kind == ObjectKind::Model, kind)?;
    c.presence(f("radius"), &o.radius, o.kind == ObjectKind::Sphere, kind)?;
    if o.kind != ObjectKind::Plane {
        c.presence(f("half_extent"), &o.half_extent, false, kind)?;
    }
    Ok(match o.kind {
        ObjectKind::Model => {
            let file = dir.join(o.file.as_deref().unwrap_or_default());
            let mesh = match meshes.loaded.get(&file) {
                Some(m) => m.clone(),
                None => {
                    let m = Arc::new(
                        TriangleMesh::from_obj(&file)
                            .map_err(|e| c.err(f("file"), e.to_string()))?,
                    );
                    meshes.loaded.insert(file, m.clone());
                    m
                }
            };
            Shape::Mesh(mesh)
        }
        ObjectKind::Sphere => Shape::Sphere(Sphere {
            radius: c.positive(f("radius"), o.radius.unwrap_or_default())?,
        }),
        ObjectKind::Plane => Shape::Plane(Plane {
            half_extent: match o.half_extent {
                None => None,
                Some([x, z]) => Some(Vec2::new(
                    c.positive(f("half_extent[0]"), x)?,
                    c.positive(f("half_extent[1]"), z)?,
                )),
            },
        }),
    })
}
