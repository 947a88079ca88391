//! URDF → [`Model`], following Pinocchio's parser so that state vectors exchange unchanged:
//! joints numbered depth-first from the root link, the children of a link taken in the order of
//! their joint names (urdfdom keeps joints in a name-sorted map, and Pinocchio walks that), fixed
//! joints merged into the parent body and kept as `FIXED_JOINT` frames, `<mimic>` loaded as an
//! independent joint.

use super::xml::{attr, child, children, describe, numbers, origin, scalar, scalar_or, vec3_or};
use crate::error::{ModelError, Result};
use crate::frame::{Frame, FrameKind};
use crate::geometry::{CollisionGeometry, Shape};
use crate::joint::{Joint, JointKind};
use crate::model::Model;
use crate::spatial::{Inertia, Se3};
use nalgebra::{DVector, Matrix3, SymmetricEigen, Vector3};
use std::collections::HashMap;
use std::path::Path;

/// How the root link is attached to the world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RootJoint {
    /// A 6-DoF free-flyer named `root_joint` (humanoids, Pinocchio's `JointModelFreeFlyer`).
    FreeFlyer,
    /// The root link is welded to the world.
    Fixed,
}

struct UrdfLink {
    inertia: Option<Inertia>,
    collisions: Vec<(Se3, Shape)>,
    visuals: Vec<(Se3, Shape)>,
}

struct UrdfJoint {
    name: String,
    kind: Option<JointKind>, // None = fixed
    parent: String,
    child: String,
    origin: Se3,
    lower: f64,
    upper: f64,
    velocity: f64,
    effort: f64,
}

/// Loads a URDF file.
pub fn build_model_from_urdf_file(path: impl AsRef<Path>, root: RootJoint) -> Result<Model> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| ModelError::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    build_model_from_urdf_str(&text, root)
}

/// Loads a URDF document held in a string.
pub fn build_model_from_urdf_str(xml: &str, root: RootJoint) -> Result<Model> {
    build_model_from_urdf_str_locked(xml, root, &[])
}

/// Loads a URDF document held in a string with the one-dof joints of `locked` (name, position)
/// made rigid at that position (Pinocchio's `buildReducedModel`): each becomes a fixed joint
/// whose origin includes its motion, so its child's inertia merges into the parent's body and
/// the model loses its dof. A name the URDF lacks, or a joint that is fixed or has more than
/// one dof, is an error.
pub fn build_model_from_urdf_str_locked(
    xml: &str,
    root: RootJoint,
    locked: &[(String, f64)],
) -> Result<Model> {
    let doc = roxmltree::Document::parse(xml).map_err(|e| ModelError::Xml(e.to_string()))?;
    let robot = doc.root_element();
    if robot.tag_name().name() != "robot" {
        return Err(ModelError::Invalid {
            element: describe(&robot),
            reason: "the document's root element must be <robot>".into(),
        });
    }
    let mut links: HashMap<String, UrdfLink> = HashMap::new();
    let mut link_order = Vec::new();
    for l in children(&robot, "link") {
        let name = attr(&l, "name", "<link>")?.to_string();
        let parsed = parse_link(&l, &name)?;
        if links.insert(name.clone(), parsed).is_some() {
            return Err(ModelError::Duplicate { kind: "link", name });
        }
        link_order.push(name);
    }
    let mut joints: Vec<UrdfJoint> = Vec::new();
    for j in children(&robot, "joint") {
        let parsed = parse_joint(&j)?;
        if joints.iter().any(|o| o.name == parsed.name) {
            return Err(ModelError::Duplicate {
                kind: "joint",
                name: parsed.name,
            });
        }
        for (role, link) in [("parent", &parsed.parent), ("child", &parsed.child)] {
            if !links.contains_key(link) {
                return Err(ModelError::MissingLink {
                    joint: parsed.name.clone(),
                    role,
                    link: link.clone(),
                });
            }
        }
        joints.push(parsed);
    }
    for (name, position) in locked {
        let invalid = |reason: String| ModelError::Invalid {
            element: format!("locked joint '{name}'"),
            reason,
        };
        let joint = (joints.iter_mut())
            .find(|j| &j.name == name)
            .ok_or_else(|| invalid("the URDF has no such joint".into()))?;
        let q = match joint.kind {
            Some(JointKind::Revolute { .. }) | Some(JointKind::Prismatic { .. }) => vec![*position],
            Some(JointKind::RevoluteUnbounded { .. }) => vec![position.cos(), position.sin()],
            _ => return Err(invalid("only a one-dof joint can be locked".into())),
        };
        if !position.is_finite() {
            return Err(invalid(format!("position {position}")));
        }
        let kind = joint
            .kind
            .take()
            .unwrap_or_else(|| unreachable!("matched above"));
        joint.origin = joint.origin * kind.transform(&q);
    }
    let name = robot.attribute("name").unwrap_or("robot").to_string();
    TreeBuilder::new(&links, &joints).build(name, &link_order, root)
}

fn parse_link(l: &roxmltree::Node, name: &str) -> Result<UrdfLink> {
    let ctx = format!("link '{name}'");
    let inertia = match child(l, "inertial") {
        None => None,
        Some(i) => Some(parse_inertial(&i, name, &ctx)?),
    };
    let shapes = |tag: &str| -> Result<Vec<(Se3, Shape)>> {
        let mut out = Vec::new();
        for c in children(l, tag) {
            let placement = origin(&c, &ctx)?;
            let Some(g) = child(&c, "geometry") else {
                continue;
            };
            if let Some(shape) = parse_shape(&g, &ctx)? {
                out.push((placement, shape));
            }
        }
        Ok(out)
    };
    Ok(UrdfLink {
        inertia,
        collisions: shapes("collision")?,
        visuals: shapes("visual")?,
    })
}

fn parse_inertial(i: &roxmltree::Node, link: &str, ctx: &str) -> Result<Inertia> {
    let placement = origin(i, ctx)?;
    let mass = match child(i, "mass") {
        Some(m) => scalar(&m, "value", ctx)?,
        None => 0.0,
    };
    if mass < 0.0 {
        return Err(ModelError::BadInertia {
            link: link.to_string(),
            reason: format!("negative mass {mass}"),
        });
    }
    let t = match child(i, "inertia") {
        Some(t) => {
            let g = |k: &str| scalar_or(&t, k, ctx, 0.0);
            let (xx, xy, xz, yy, yz, zz) = (
                g("ixx")?,
                g("ixy")?,
                g("ixz")?,
                g("iyy")?,
                g("iyz")?,
                g("izz")?,
            );
            Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
        }
        None => Matrix3::zeros(),
    };
    let eig = SymmetricEigen::new(t).eigenvalues;
    // Relative tolerance for rounding in the file, absolute floor for all-zero tensors.
    let tol = (1e-9 * t.diagonal().abs().max()).max(1e-12);
    if eig.min() < -tol {
        return Err(ModelError::BadInertia {
            link: link.to_string(),
            reason: format!(
                "inertia tensor is not positive definite (eigenvalues {:.3e}, {:.3e}, {:.3e})",
                eig[0], eig[1], eig[2]
            ),
        });
    }
    let r = placement.rotation;
    Ok(Inertia::new(
        mass,
        placement.translation,
        r * t * r.transpose(),
    ))
}

fn parse_shape(g: &roxmltree::Node, ctx: &str) -> Result<Option<Shape>> {
    let Some(s) = g.children().find(|c| c.is_element()) else {
        return Ok(None);
    };
    let shape = match s.tag_name().name() {
        "box" => Shape::Box {
            size: vec3_or(&s, "size", ctx, Vector3::zeros())?,
        },
        "cylinder" => Shape::Cylinder {
            radius: scalar(&s, "radius", ctx)?,
            length: scalar(&s, "length", ctx)?,
        },
        "sphere" => Shape::Sphere {
            radius: scalar(&s, "radius", ctx)?,
        },
        "mesh" => Shape::Mesh {
            filename: attr(&s, "filename", ctx)?.to_string(),
            scale: vec3_or(&s, "scale", ctx, Vector3::new(1.0, 1.0, 1.0))?,
        },
        _ => return Ok(None),
    };
    Ok(Some(shape))
}

fn parse_joint(j: &roxmltree::Node) -> Result<UrdfJoint> {
    let name = attr(j, "name", "<joint>")?.to_string();
    let ctx = format!("joint '{name}'");
    let kind_str = attr(j, "type", &ctx)?;
    let link_of = |tag: &str| -> Result<String> {
        let e = child(j, tag).ok_or_else(|| ModelError::Invalid {
            element: ctx.clone(),
            reason: format!("missing <{tag}>"),
        })?;
        Ok(attr(&e, "link", &ctx)?.to_string())
    };
    let parent = link_of("parent")?;
    let child_link = link_of("child")?;
    let axis = match child(j, "axis") {
        Some(a) => vec3_or(&a, "xyz", &ctx, Vector3::x())?,
        None => Vector3::x(),
    };
    let moving = matches!(kind_str, "revolute" | "continuous" | "prismatic");
    let norm = axis.norm();
    if moving && norm < 1e-12 {
        return Err(ModelError::Invalid {
            element: ctx,
            reason: "axis has zero length".into(),
        });
    }
    let axis = axis / norm;
    let kind = match kind_str {
        "revolute" => Some(JointKind::Revolute { axis }),
        "continuous" => Some(JointKind::RevoluteUnbounded { axis }),
        "prismatic" => Some(JointKind::Prismatic { axis }),
        "fixed" => None,
        other => {
            return Err(ModelError::UnknownJointType {
                joint: name,
                kind: other.to_string(),
            })
        }
    };
    let (mut lower, mut upper, mut velocity, mut effort) = (
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::INFINITY,
        f64::INFINITY,
    );
    if let Some(l) = child(j, "limit") {
        if matches!(
            kind,
            Some(JointKind::Revolute { .. } | JointKind::Prismatic { .. })
        ) {
            lower = scalar_or(&l, "lower", &ctx, 0.0)?;
            upper = scalar_or(&l, "upper", &ctx, 0.0)?;
        }
        velocity = scalar_or(&l, "velocity", &ctx, f64::INFINITY)?;
        effort = scalar_or(&l, "effort", &ctx, f64::INFINITY)?;
    }
    if lower > upper {
        return Err(ModelError::Invalid {
            element: ctx,
            reason: format!("lower limit {lower} above upper limit {upper}"),
        });
    }
    if let Some(m) = child(j, "mimic") {
        // Tolerated and loaded as an independent joint, as Pinocchio does by default.
        numbers(
            m.attribute("multiplier").unwrap_or("1"),
            &ctx,
            "mimic multiplier",
        )?;
    }
    Ok(UrdfJoint {
        origin: origin(j, &ctx)?,
        name,
        kind,
        parent,
        child: child_link,
        lower,
        upper,
        velocity,
        effort,
    })
}

struct Limits {
    lower: Vec<f64>,
    upper: Vec<f64>,
    velocity: Vec<f64>,
    effort: Vec<f64>,
}

struct TreeBuilder<'a> {
    links: &'a HashMap<String, UrdfLink>,
    joints: &'a [UrdfJoint],
    out_joints: Vec<Joint>,
    inertias: Vec<Inertia>,
    frames: Vec<Frame>,
    collisions: Vec<CollisionGeometry>,
    visuals: Vec<CollisionGeometry>,
    limits: Limits,
    nq: usize,
    nv: usize,
}

impl<'a> TreeBuilder<'a> {
    fn new(links: &'a HashMap<String, UrdfLink>, joints: &'a [UrdfJoint]) -> Self {
        Self {
            links,
            joints,
            out_joints: Vec::new(),
            inertias: Vec::new(),
            frames: vec![Frame {
                name: "universe".into(),
                kind: FrameKind::Universe,
                parent_joint: None,
                placement: Se3::identity(),
            }],
            collisions: Vec::new(),
            visuals: Vec::new(),
            limits: Limits {
                lower: Vec::new(),
                upper: Vec::new(),
                velocity: Vec::new(),
                effort: Vec::new(),
            },
            nq: 0,
            nv: 0,
        }
    }

    fn add_joint(
        &mut self,
        name: &str,
        kind: JointKind,
        parent: Option<usize>,
        placement: Se3,
    ) -> usize {
        let id = self.out_joints.len();
        self.out_joints.push(Joint {
            name: name.to_string(),
            kind,
            parent,
            placement,
            idx_q: self.nq,
            idx_v: self.nv,
        });
        self.inertias.push(Inertia::zero());
        self.nq += kind.nq();
        self.nv += kind.nv();
        self.frames.push(Frame {
            name: name.to_string(),
            kind: FrameKind::Joint,
            parent_joint: Some(id),
            placement: Se3::identity(),
        });
        id
    }

    /// Attaches a link to joint `parent` at `placement` (in the joint frame): its BODY frame,
    /// inertia, collision and visual shapes.
    fn attach_link(&mut self, link: &str, parent: Option<usize>, placement: Se3) {
        self.frames.push(Frame {
            name: link.to_string(),
            kind: FrameKind::Body,
            parent_joint: parent,
            placement,
        });
        let data = &self.links[link];
        if let (Some(j), Some(i)) = (parent, data.inertia) {
            self.inertias[j] += i.transformed(&placement);
        }
        for (shapes, out) in [
            (&data.collisions, &mut self.collisions),
            (&data.visuals, &mut self.visuals),
        ] {
            for (o, shape) in shapes {
                out.push(CollisionGeometry {
                    link: link.to_string(),
                    parent_joint: parent,
                    placement: placement * *o,
                    shape: shape.clone(),
                });
            }
        }
    }

    fn build(mut self, name: String, link_order: &[String], root: RootJoint) -> Result<Model> {
        let mut parent_of: HashMap<&str, usize> = HashMap::new();
        let mut children_of: HashMap<&str, Vec<usize>> = HashMap::new();
        for (k, j) in self.joints.iter().enumerate() {
            if j.parent == j.child {
                return Err(ModelError::NotATree(format!(
                    "joint '{}' connects link '{}' to itself",
                    j.name, j.child
                )));
            }
            if let Some(other) = parent_of.insert(&j.child, k) {
                return Err(ModelError::NotATree(format!(
                    "link '{}' is the child of both joint '{}' and joint '{}'",
                    j.child, self.joints[other].name, j.name
                )));
            }
            children_of.entry(&j.parent).or_default().push(k);
        }
        for list in children_of.values_mut() {
            list.sort_by(|a, b| self.joints[*a].name.cmp(&self.joints[*b].name));
        }
        let roots: Vec<&String> = link_order
            .iter()
            .filter(|l| !parent_of.contains_key(l.as_str()))
            .collect();
        let root_link = match roots.as_slice() {
            [r] => (*r).clone(),
            [] if link_order.is_empty() => {
                return Err(ModelError::Invalid {
                    element: "<robot>".into(),
                    reason: "no <link>".into(),
                })
            }
            [] => {
                return Err(ModelError::NotATree(
                    "every link has a parent (a cycle)".into(),
                ))
            }
            many => {
                return Err(ModelError::NotATree(format!(
                    "several root links: {}",
                    many.iter()
                        .map(|s| s.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )))
            }
        };

        let root_parent = match root {
            RootJoint::FreeFlyer => {
                let id = self.add_joint("root_joint", JointKind::FreeFlyer, None, Se3::identity());
                for _ in 0..3 {
                    self.push_q_limits(f64::NEG_INFINITY, f64::INFINITY);
                }
                for _ in 0..4 {
                    self.push_q_limits(-1.0, 1.0);
                }
                for _ in 0..6 {
                    self.push_v_limits(f64::INFINITY, f64::INFINITY);
                }
                Some(id)
            }
            RootJoint::Fixed => None,
        };
        self.attach_link(&root_link, root_parent, Se3::identity());

        // Depth-first, pre-order: (urdf joint, parent model joint, parent link placement).
        let mut visited = 1usize;
        let mut stack: Vec<(usize, Option<usize>, Se3)> = Vec::new();
        let push_children = |stack: &mut Vec<_>, link: &str, parent: Option<usize>, at: Se3| {
            if let Some(list) = children_of.get(link) {
                for &k in list.iter().rev() {
                    stack.push((k, parent, at));
                }
            }
        };
        push_children(&mut stack, &root_link, root_parent, Se3::identity());
        while let Some((k, parent, at)) = stack.pop() {
            let j = &self.joints[k];
            visited += 1;
            let placement = at * j.origin;
            match j.kind {
                Some(kind) => {
                    let id = self.add_joint(&j.name, kind, parent, placement);
                    match kind {
                        JointKind::RevoluteUnbounded { .. } => {
                            self.push_q_limits(-1.0, 1.0);
                            self.push_q_limits(-1.0, 1.0);
                        }
                        _ => self.push_q_limits(j.lower, j.upper),
                    }
                    self.push_v_limits(j.velocity, j.effort);
                    self.attach_link(&j.child, Some(id), Se3::identity());
                    push_children(&mut stack, &j.child, Some(id), Se3::identity());
                }
                None => {
                    self.frames.push(Frame {
                        name: j.name.clone(),
                        kind: FrameKind::FixedJoint,
                        parent_joint: parent,
                        placement,
                    });
                    self.attach_link(&j.child, parent, placement);
                    push_children(&mut stack, &j.child, parent, placement);
                }
            }
        }
        if visited != link_order.len() {
            return Err(ModelError::NotATree(format!(
                "{} link(s) are not reachable from root link '{}' (a cycle?)",
                link_order.len() - visited,
                root_link
            )));
        }
        Ok(self.finish(name))
    }

    /// Appends the position limits of one configuration entry.
    fn push_q_limits(&mut self, lower: f64, upper: f64) {
        self.limits.lower.push(lower);
        self.limits.upper.push(upper);
    }

    /// Appends the velocity and effort limits of one velocity entry.
    fn push_v_limits(&mut self, velocity: f64, effort: f64) {
        self.limits.velocity.push(velocity);
        self.limits.effort.push(effort);
    }

    fn finish(self, name: String) -> Model {
        let n = self.out_joints.len();
        let mut subtree_nv: Vec<usize> = self.out_joints.iter().map(|j| j.nv()).collect();
        for i in (0..n).rev() {
            if let Some(p) = self.out_joints[i].parent {
                subtree_nv[p] += subtree_nv[i];
            }
        }
        let mut dof_parent = vec![None; self.nv];
        let mut dof_joint = vec![0; self.nv];
        for (i, j) in self.out_joints.iter().enumerate() {
            for k in 0..j.nv() {
                let d = j.idx_v + k;
                dof_joint[d] = i;
                dof_parent[d] = if k > 0 {
                    Some(d - 1)
                } else {
                    j.parent.map(|p| {
                        let pj = &self.out_joints[p];
                        pj.idx_v + pj.nv() - 1
                    })
                };
            }
        }
        let mut dof_ancestors = Vec::new();
        let mut dof_ancestors_start = vec![0];
        for k in 0..self.nv {
            let mut i = dof_parent[k];
            while let Some(ii) = i {
                dof_ancestors.push(ii);
                i = dof_parent[ii];
            }
            dof_ancestors_start.push(dof_ancestors.len());
        }
        let mut dof_ancestor_runs: Vec<(usize, usize)> = Vec::new();
        let mut dof_ancestor_runs_start = vec![0];
        for k in 0..self.nv {
            let chain = &dof_ancestors[dof_ancestors_start[k]..dof_ancestors_start[k + 1]];
            let first = dof_ancestor_runs.len();
            for &ii in chain {
                // Extend this dof's current run when ii is the next index down.
                match dof_ancestor_runs[first..].last_mut() {
                    Some((lo, _)) if *lo == ii + 1 => *lo = ii,
                    _ => dof_ancestor_runs.push((ii, ii)),
                }
            }
            dof_ancestor_runs_start.push(dof_ancestor_runs.len());
        }
        Model {
            name,
            joints: self.out_joints,
            inertias: self.inertias,
            frames: self.frames,
            nq: self.nq,
            nv: self.nv,
            lower_position_limit: DVector::from_vec(self.limits.lower),
            upper_position_limit: DVector::from_vec(self.limits.upper),
            velocity_limit: DVector::from_vec(self.limits.velocity),
            effort_limit: DVector::from_vec(self.limits.effort),
            gravity: Vector3::new(0.0, 0.0, -crate::STANDARD_GRAVITY),
            reference_configurations: Vec::new(),
            collisions: self.collisions,
            visuals: self.visuals,
            subtree_nv,
            dof_parent,
            dof_joint,
            dof_ancestors,
            dof_ancestors_start,
            dof_ancestor_runs,
            dof_ancestor_runs_start,
        }
    }
}
