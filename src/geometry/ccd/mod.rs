//! Continuous collision of linearly moving points, triangles and segments, decided exactly.

pub(crate) mod condition;
pub(crate) mod exact;
pub(crate) mod interval;
#[cfg(test)]
pub(crate) mod oracle;
pub(crate) mod poly;
pub(crate) mod scaled;
