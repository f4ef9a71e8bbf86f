//! The narrow phase of the queries on vertex-face and edge-edge pairs (continuous collision,
//! closest-point stencils): from the node pairs a traversal reports, the primitive pairs their
//! rings own, each enumerated once (the owners' rule of [`crate::mesh::Features`]) after box
//! filters, handed to a test generic over what it computes, on one thread or shared
//! out in chunks whose results are joined in order (so the answer does not depend on the thread
//! count).

mod boxes;
mod kind;
mod leaf_pairs;
mod node_pair;
mod subsets;
mod vocabulary;

pub use kind::ImpactKind;
pub(crate) use leaf_pairs::{Workspace, test_leaf_pairs};
pub(crate) use node_pair::Narrow;
pub(crate) use vocabulary::{Key, Owners, PrimitivePair, PrimitiveTest, Side, Worker};
