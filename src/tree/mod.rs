//! The hierarchy's shape: which nodes are the children of which, and which rings lie below each.
//! Bounding volumes live apart from it ([`crate::volume`]), so every volume kind shares one
//! shape, one builder and one traversal.

mod ring_table;
mod shape;
mod tree_build;

pub(crate) use ring_table::{RingTable, distinct_corners};
pub(crate) use shape::{Node, Subtree, Tree};
pub(crate) use tree_build::MAX_CHILDREN;
pub use tree_build::TreeKind;
