//! Random motions on a grid with the degenerate shapes the continuous tests must decide, for
//! the unit tests of the filters.

use crate::fixtures::Rng;

/// Four corners' start or end positions.
pub(crate) type Prim = [[f64; 3]; 4];

/// Corners on a grid of step `1 / grid` in [-1, 1]³ (the end equal to the start when `still`),
/// then given `shape`: 1 coplanar throughout, 2 a corner shared at the start, 3 a corner
/// repeated throughout (a degenerate triangle or edge), 4 parallel edges moving together, any
/// other value left as drawn.
pub(crate) fn grid_case(rng: &mut Rng, grid: u64, still: bool, shape: usize) -> (Prim, Prim) {
    let mut coord = || (rng.next_u64() % (2 * grid + 1)) as f64 / grid as f64 - 1.0;
    let mut s: Prim = [[0.0; 3]; 4];
    let mut e: Prim = [[0.0; 3]; 4];
    for i in 0..4 {
        for k in 0..3 {
            s[i][k] = coord();
            e[i][k] = if still { s[i][k] } else { coord() };
        }
    }
    match shape {
        1 => (0..4).for_each(|i| {
            s[i][2] = 0.0;
            e[i][2] = 0.0;
        }),
        2 => s[0] = s[1],
        3 => {
            s[2] = s[3];
            e[2] = e[3];
        }
        4 => {
            let d = [0, 1, 2].map(|k| s[1][k] - s[0][k]);
            s[3] = [0, 1, 2].map(|k| s[2][k] + d[k]);
            e[3] = [0, 1, 2].map(|k| e[2][k] + (e[1][k] - e[0][k]));
        }
        _ => {}
    }
    (s, e)
}
