//! The least distance between two meshes.

mod entry;
#[cfg(test)]
mod tests;

pub use entry::{Distance, distance};
