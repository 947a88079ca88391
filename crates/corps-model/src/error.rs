//! Typed errors of the model crate.

use thiserror::Error;

/// Everything that can go wrong when loading a model or calling an algorithm with bad input.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ModelError {
    /// The file could not be read.
    #[error("cannot read {path}: {reason}")]
    Io { path: String, reason: String },
    /// The XML is not well-formed.
    #[error("malformed XML: {0}")]
    Xml(String),
    /// A required element or attribute is missing or malformed.
    #[error("{element}: {reason}")]
    Invalid { element: String, reason: String },
    /// Two links or two joints share a name.
    #[error("duplicate {kind} name '{name}'")]
    Duplicate { kind: &'static str, name: String },
    /// A joint names a link that does not exist.
    #[error("joint '{joint}' refers to unknown {role} link '{link}'")]
    MissingLink {
        joint: String,
        role: &'static str,
        link: String,
    },
    /// The kinematic graph is not a tree.
    #[error("kinematic graph is not a tree: {0}")]
    NotATree(String),
    /// A joint type corps does not know.
    #[error("joint '{joint}' has unsupported type '{kind}'")]
    UnknownJointType { joint: String, kind: String },
    /// A link has physically impossible inertial parameters.
    #[error("link '{link}': {reason}")]
    BadInertia { link: String, reason: String },
    /// No frame of this name.
    #[error("unknown frame '{0}'")]
    UnknownFrame(String),
    /// No joint of this name.
    #[error("unknown joint '{0}'")]
    UnknownJoint(String),
    /// No reference configuration of this name.
    #[error("unknown reference configuration '{name}' (known: {known})")]
    UnknownConfiguration { name: String, known: String },
    /// A state vector has the wrong size.
    #[error("{what} has size {got}, expected {expected}")]
    Dimension {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    /// A state vector holds NaN or infinity.
    #[error("{what} has a non-finite entry at index {index}")]
    NonFinite { what: &'static str, index: usize },
    /// A matrix that had to be inverted is singular.
    #[error("singular: {0}")]
    Singular(String),
}

/// Result alias of the model crate.
pub type Result<T> = std::result::Result<T, ModelError>;
