//! Contacts: rigid contacts that constrain a frame's motion and add force variables.

mod contact;
mod wrench_limits;

pub use contact::{Contact, PYRAMID_ROWS};
pub use wrench_limits::{CopBox, WrenchLimits};
