//! Continuous collision of linearly moving points, triangles and segments, decided exactly.

pub(crate) mod bernstein;
pub(crate) mod condition;
pub(crate) mod filtered;
#[cfg(test)]
mod grid_cases;
pub(crate) mod interval;
#[cfg(test)]
pub(crate) mod oracle;
pub(crate) mod poly;
pub(crate) mod rational;
pub(crate) mod scaled;

/// How a continuous test decides: exactly, or in floating point only.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum CcdMode {
    /// Exact for every finite input: a floating-point filter, then exact arithmetic where it
    /// cannot decide. The reported time is the earliest contact rounded down to a double.
    #[default]
    Exact,
    /// Floating point only, with the same filter: never misses a contact and never reports a
    /// time later than the exact one, but where rounding leaves it unsure (primitives coplanar
    /// and touching to within the rounding error of interval arithmetic on their coordinates,
    /// or a time span it cannot settle in a bounded search) it reports a contact at the start
    /// of that span. Bounded time per test: no big-number arithmetic.
    Conservative,
}

/// The earliest contact time of `kind` moving from `start` to `end`, decided as `mode` says,
/// when it is at most `until`; `None` otherwise. Times after `until` are not searched, so a
/// caller that wants only the earliest contact of many tests passes the earliest found so far.
pub(crate) fn time_of_impact(
    kind: crate::geometry::Primitive,
    start: &[crate::geometry::predicates::Point; 4],
    end: &[crate::geometry::predicates::Point; 4],
    mode: CcdMode,
    until: f64,
) -> Option<f64> {
    match mode {
        CcdMode::Exact => filtered::time_of_impact(kind, start, end, until),
        CcdMode::Conservative => filtered::conservative_time_of_impact(kind, start, end, until),
    }
}
