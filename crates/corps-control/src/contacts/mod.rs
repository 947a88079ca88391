//! Contacts: rigid contacts that constrain a frame's motion and add force variables.

mod contact;

pub use contact::{Contact, PYRAMID_ROWS};
