//! Contacts: rigid contacts that constrain a frame's motion and add force variables.

mod contact6d;

pub use contact6d::{Contact6d, FORCE_ROWS, FORCE_VARS};
