//! Small helpers to read typed attributes from XML elements with errors that name the element.

use crate::error::{ModelError, Result};
use crate::spatial::{rotation::rpy_to_matrix, Se3};
use nalgebra::Vector3;
use roxmltree::Node;

/// A description of an element for error messages, e.g. `joint 'knee'`.
pub fn describe(node: &Node) -> String {
    match node.attribute("name") {
        Some(n) => format!("{} '{}'", node.tag_name().name(), n),
        None => format!("<{}>", node.tag_name().name()),
    }
}

/// The first child element with this tag.
pub fn child<'a, 'i>(node: &Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    node.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
}

/// All child elements with this tag.
pub fn children<'a, 'i: 'a>(
    node: &Node<'a, 'i>,
    tag: &'a str,
) -> impl Iterator<Item = Node<'a, 'i>> + 'a {
    node.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == tag)
}

/// A required string attribute.
pub fn attr<'a>(node: &Node<'a, '_>, name: &str, ctx: &str) -> Result<&'a str> {
    node.attribute(name).ok_or_else(|| ModelError::Invalid {
        element: ctx.to_string(),
        reason: format!("<{}> lacks attribute '{}'", node.tag_name().name(), name),
    })
}

/// Parses a whitespace-separated list of finite numbers.
pub fn numbers(text: &str, ctx: &str, what: &str) -> Result<Vec<f64>> {
    text.split_whitespace()
        .map(|t| match t.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(ModelError::Invalid {
                element: ctx.to_string(),
                reason: format!("{what}: '{t}' is not a finite number"),
            }),
        })
        .collect()
}

/// A required attribute holding one finite number.
pub fn scalar(node: &Node, name: &str, ctx: &str) -> Result<f64> {
    let v = numbers(attr(node, name, ctx)?, ctx, name)?;
    match v.as_slice() {
        [x] => Ok(*x),
        _ => Err(ModelError::Invalid {
            element: ctx.to_string(),
            reason: format!("attribute '{name}' must hold one number"),
        }),
    }
}

/// An optional attribute holding one finite number.
pub fn scalar_or(node: &Node, name: &str, ctx: &str, default: f64) -> Result<f64> {
    if node.attribute(name).is_some() {
        scalar(node, name, ctx)
    } else {
        Ok(default)
    }
}

/// An optional attribute holding a 3-vector.
pub fn vec3_or(node: &Node, name: &str, ctx: &str, default: Vector3<f64>) -> Result<Vector3<f64>> {
    let Some(text) = node.attribute(name) else {
        return Ok(default);
    };
    let v = numbers(text, ctx, name)?;
    match v.as_slice() {
        [x, y, z] => Ok(Vector3::new(*x, *y, *z)),
        _ => Err(ModelError::Invalid {
            element: ctx.to_string(),
            reason: format!("attribute '{name}' must hold three numbers, got '{text}'"),
        }),
    }
}

/// The placement given by an optional `<origin xyz rpy>` child (identity if absent).
pub fn origin(node: &Node, ctx: &str) -> Result<Se3> {
    let Some(o) = child(node, "origin") else {
        return Ok(Se3::identity());
    };
    let xyz = vec3_or(&o, "xyz", ctx, Vector3::zeros())?;
    let rpy = vec3_or(&o, "rpy", ctx, Vector3::zeros())?;
    Ok(Se3::new(rpy_to_matrix(rpy.x, rpy.y, rpy.z), xyz))
}
