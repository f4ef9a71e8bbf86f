//! What each knob buys: for every volume x tree x radius kind and every query mode, the time per
//! frame (refit + query) and the accuracy against the exact pairs: recall (the share of exact
//! triangle pairs the reported pairs cover; 1 for every conservative mode, or the run fails),
//! precision (the share of the covered triangle pairs that intersect) and whether the
//! object-level answer (touching or not) is right.

use crate::method::label;
use crate::report::{Table, count, median, ms, sums};
use crate::scene::Scene;
use dvh::{
    BuildOptions, LeftoverPolicy, Mesh, Pair, PairKind, Pairs, QueryMode, QueryOptions, RadiusKind,
    TreeKind, VolumeKind, collide,
};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::HashMap;
use std::time::Instant;

/// Every volume x tree x radius kind (boxes have no radius kind), other options at defaults, and
/// the other leftover policy for the default options and the paper's DVH.
pub fn options() -> Vec<BuildOptions> {
    let mut all = Vec::new();
    for (volume, radius) in [
        (VolumeKind::Dvh, RadiusKind::Layered),
        (VolumeKind::Dvh, RadiusKind::Wrapped),
        (VolumeKind::Sbv, RadiusKind::Layered),
        (VolumeKind::Sbv, RadiusKind::Wrapped),
        (VolumeKind::Aabb, RadiusKind::Layered),
    ] {
        for tree in [TreeKind::Octree, TreeKind::Binary] {
            all.push(
                BuildOptions::default()
                    .with_volume(volume)
                    .with_tree(tree)
                    .with_radius(radius),
            );
        }
    }
    for volume in [VolumeKind::Dvh, VolumeKind::Aabb] {
        all.push(
            BuildOptions::default()
                .with_volume(volume)
                .with_leftovers(LeftoverPolicy::ExtraRings),
        );
    }
    all
}

/// One option and mode over a scene's frames.
pub struct Row {
    pub scene: &'static str,
    pub options: BuildOptions,
    pub mode: QueryMode,
    /// Per frame, milliseconds: the refit of every object, and every pair's query.
    pub refit_ms: Vec<f64>,
    pub query_ms: Vec<f64>,
    /// Volume tests per frame.
    pub bv_tests: Vec<f64>,
    /// Exact pairs, those of them the answer covers, and the triangle pairs it covers.
    pub exact: u64,
    pub covered: u64,
    pub expansion: u64,
    /// Object pairs and frames whose touching-or-not answer was right, out of `answers`.
    pub right: u64,
    pub answers: u64,
    /// Pair queries that stopped at a budget's frontier.
    pub frontier_queries: u64,
}

impl Row {
    /// Median refit + query per frame.
    pub fn time(&self) -> f64 {
        median(&sums(&self.refit_ms, &self.query_ms))
    }

    pub fn recall(&self) -> f64 {
        if self.exact == 0 {
            1.0
        } else {
            self.covered as f64 / self.exact as f64
        }
    }

    pub fn precision(&self) -> f64 {
        if self.expansion == 0 {
            1.0
        } else {
            self.covered as f64 / self.expansion as f64
        }
    }

    pub fn object_accuracy(&self) -> f64 {
        self.right as f64 / self.answers.max(1) as f64
    }

    /// Does the mode promise to cover every exact pair?
    pub fn conservative(&self) -> bool {
        !matches!(self.mode, QueryMode::FirstHit)
    }
}

/// A mode's name in tables.
pub fn mode_name(mode: QueryMode) -> String {
    match mode {
        QueryMode::Triangles => "triangles".into(),
        QueryMode::FirstHit => "first hit".into(),
        QueryMode::Leaves => "leaves".into(),
        QueryMode::Depth(d) => format!("depth {d}"),
        QueryMode::Budget(b) => format!("budget {b}"),
        // A mode newer than this runner.
        other => format!("{other:?}"),
    }
}

/// Where each triangle and node of a mesh sits in leaf order: enough to tell, for a node pair,
/// which triangle pairs it covers.
struct Layout {
    /// Triangle -> its position in the leaf-ordered triangle list.
    position: Vec<u32>,
    /// Triangle -> the leaf holding it.
    leaf: Vec<u32>,
    /// Node -> parent (`u32::MAX` for the root).
    parent: Vec<u32>,
    /// Node -> its triangles as a range of the leaf-ordered list.
    span: Vec<(u32, u32)>,
}

impl Layout {
    fn new(mesh: &Mesh) -> Layout {
        let base = mesh.node_triangles(0).as_ptr() as usize;
        let nodes = mesh.node_count();
        let mut layout = Layout {
            position: vec![0; mesh.triangle_count()],
            leaf: vec![0; mesh.triangle_count()],
            parent: vec![u32::MAX; nodes],
            span: Vec::with_capacity(nodes),
        };
        for n in 0..nodes as u32 {
            let tris = mesh.node_triangles(n);
            // A node's triangles are a run of the root's: its offset in that run.
            let start = ((tris.as_ptr() as usize - base) / std::mem::size_of::<u32>()) as u32;
            layout.span.push((start, start + tris.len() as u32));
            let view = mesh.node(n);
            for c in view.children.clone() {
                layout.parent[c as usize] = n;
            }
            if view.children.is_empty() {
                for (k, &t) in tris.iter().enumerate() {
                    layout.position[t as usize] = start + k as u32;
                    layout.leaf[t as usize] = n;
                }
            }
        }
        layout
    }

    fn size(&self, n: u32) -> u64 {
        let (s, e) = self.span[n as usize];
        u64::from(e - s)
    }
}

/// How many of `exact` (triangle pairs) lie below one of `nodes` (node pairs, whose triangle
/// sets are disjoint): per exact pair, the ancestors of its leaf in `a`, each looked up among the
/// reported pairs' `b` ranges.
fn covered(la: &Layout, lb: &Layout, nodes: &[Pair], exact: &[Pair]) -> u64 {
    let mut by_a: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    for p in nodes {
        by_a.entry(p.a).or_default().push(lb.span[p.b as usize]);
    }
    for v in by_a.values_mut() {
        v.sort_unstable();
    }
    let mut n = 0;
    for e in exact {
        let y = lb.position[e.b as usize];
        let mut node = la.leaf[e.a as usize];
        loop {
            if let Some(ranges) = by_a.get(&node) {
                let k = ranges.partition_point(|&(s, _)| s <= y);
                if k > 0 && y < ranges[k - 1].1 {
                    n += 1;
                    break;
                }
            }
            node = la.parent[node as usize];
            if node == u32::MAX {
                break;
            }
        }
    }
    n
}

/// Budgets of 1, 2 and 5 times each power of ten from 10, up to `full` (the volume tests of the
/// costliest complete traversal), which ends the list.
fn budgets(full: u64) -> Vec<u64> {
    let mut out = Vec::new();
    let mut b = 10u64;
    loop {
        for m in [1, 2, 5] {
            let x = b * m;
            if x >= full {
                out.push(full.max(1));
                return out;
            }
            out.push(x);
        }
        b *= 10;
    }
}

/// Measures every option and mode of `scene` on `frames` (frame numbers of the scene's run).
/// Panics if a conservative mode misses an exact pair.
pub fn run(scene: &Scene, frames: &[usize], options: &[BuildOptions]) -> Vec<Row> {
    let n = scene.objects.len();
    let mut world: Vec<Vec<Vec<f64>>> = vec![vec![Vec::new(); n]; frames.len()];
    for (f, w) in frames.iter().zip(world.iter_mut()) {
        scene.world(*f, w);
    }
    let bar = ProgressBar::new((frames.len() * (options.len() + 1)) as u64).with_style(
        ProgressStyle::with_template("{prefix:>9} [{bar:40}] {pos}/{len} {msg} ({eta})")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    bar.set_prefix(scene.name);
    // The exact pairs of every object pair and frame, once.
    bar.set_message("exact pairs");
    let build = |o: &BuildOptions| -> Vec<Mesh> {
        scene
            .objects
            .iter()
            .zip(&world[0])
            .map(|(ob, w)| Mesh::new(w, &ob.rest.triangles, o).expect("valid scene mesh"))
            .collect()
    };
    let mut pairs = Pairs::new();
    let mut exact: Vec<Vec<Vec<Pair>>> = Vec::new();
    {
        let mut meshes = build(&BuildOptions::default());
        for w in &world {
            for (m, p) in meshes.iter_mut().zip(w) {
                m.refit(p).expect("finite coordinates");
            }
            exact.push(
                scene
                    .pairs
                    .iter()
                    .map(|&(a, b)| {
                        collide(
                            &meshes[a],
                            None,
                            &meshes[b],
                            None,
                            &QueryOptions::default(),
                            &mut pairs,
                        )
                        .expect("query");
                        pairs.as_slice().to_vec()
                    })
                    .collect(),
            );
            bar.inc(1);
        }
    }

    let mut rows = Vec::new();
    for o in options {
        bar.set_message(label(o));
        // Every knob on one thread, as the peers run.
        let mut meshes = build(&o.with_refit_threads(1));
        let layouts: Vec<Layout> = meshes.iter().map(Layout::new).collect();
        let levels = meshes
            .iter()
            .map(|m| m.tree_stats().levels)
            .max()
            .unwrap_or(1) as u32;
        // The costliest complete traversal of a pair at the first frame sets the budgets.
        let full = scene
            .pairs
            .iter()
            .map(|&(a, b)| {
                collide(
                    &meshes[a],
                    None,
                    &meshes[b],
                    None,
                    &QueryOptions::with_mode(QueryMode::Leaves),
                    &mut pairs,
                )
                .expect("query")
                .bv_tests
            })
            .max()
            .unwrap_or(1);
        let mut modes = vec![QueryMode::Triangles, QueryMode::FirstHit, QueryMode::Leaves];
        modes.extend((0..levels.saturating_sub(1)).map(QueryMode::Depth));
        modes.extend(budgets(full).into_iter().map(QueryMode::Budget));
        let mut mine: Vec<Row> = modes
            .iter()
            .map(|&mode| Row {
                scene: scene.name,
                options: *o,
                mode,
                refit_ms: Vec::new(),
                query_ms: Vec::new(),
                bv_tests: Vec::new(),
                exact: 0,
                covered: 0,
                expansion: 0,
                right: 0,
                answers: 0,
                frontier_queries: 0,
            })
            .collect();
        for (f, w) in world.iter().enumerate() {
            let t = Instant::now();
            for (m, p) in meshes.iter_mut().zip(w) {
                m.refit(p).expect("finite coordinates");
            }
            let refit = t.elapsed().as_secs_f64() * 1e3;
            for row in mine.iter_mut() {
                let options = QueryOptions::with_mode(row.mode).with_threads(1);
                let (mut query, mut tests) = (0.0, 0u64);
                for (p, &(a, b)) in scene.pairs.iter().enumerate() {
                    let t = Instant::now();
                    let s = collide(&meshes[a], None, &meshes[b], None, &options, &mut pairs)
                        .expect("query");
                    query += t.elapsed().as_secs_f64() * 1e3;
                    tests += s.bv_tests;
                    row.frontier_queries += u64::from(s.frontier_pairs > 0);
                    let e = &exact[f][p];
                    let got = pairs.as_slice();
                    let (hit, expansion) = match pairs.kind() {
                        PairKind::Triangles => (
                            got.iter().filter(|q| e.binary_search(q).is_ok()).count() as u64,
                            got.len() as u64,
                        ),
                        PairKind::Nodes => (
                            covered(&layouts[a], &layouts[b], got, e),
                            got.iter()
                                .map(|q| layouts[a].size(q.a) * layouts[b].size(q.b))
                                .sum(),
                        ),
                    };
                    assert!(
                        !row.conservative() || hit == e.len() as u64,
                        "{} {} {}: frame {f}, pair {p}: {} of {} exact pairs covered",
                        scene.name,
                        label(o),
                        mode_name(row.mode),
                        hit,
                        e.len()
                    );
                    row.exact += e.len() as u64;
                    row.covered += hit;
                    row.expansion += expansion;
                    row.right += u64::from(got.is_empty() == e.is_empty());
                    row.answers += 1;
                }
                row.refit_ms.push(refit);
                row.query_ms.push(query);
                row.bv_tests.push(tests as f64);
            }
            bar.inc(1);
        }
        rows.extend(mine);
    }
    bar.finish_and_clear();
    rows
}

/// Every row, for the CSV file.
pub fn full_table(rows: &[Row]) -> Table {
    let mut t = Table::new(&[
        "scene",
        "options",
        "mode",
        "time_ms",
        "refit_ms",
        "query_ms",
        "bv_tests",
        "recall",
        "precision",
        "object_accuracy",
        "exact_pairs",
        "covered_pairs",
        "frontier_queries",
    ]);
    for r in rows {
        t.row(vec![
            r.scene.to_string(),
            label(&r.options),
            mode_name(r.mode),
            format!("{:.4}", r.time()),
            format!("{:.4}", median(&r.refit_ms)),
            format!("{:.4}", median(&r.query_ms)),
            format!("{:.0}", median(&r.bv_tests)),
            format!("{:.6}", r.recall()),
            format!("{:.6e}", r.precision()),
            format!("{:.4}", r.object_accuracy()),
            r.exact.to_string(),
            r.covered.to_string(),
            r.frontier_queries.to_string(),
        ]);
    }
    t
}

/// Per option, the exact modes and the leaves: what the volume, tree and radius buy.
pub fn options_table(rows: &[Row]) -> Table {
    let mut t = Table::new(&[
        "options",
        "refit",
        "triangles",
        "first hit",
        "leaves",
        "leaves precision",
        "leaves right",
    ]);
    let mut seen: Vec<BuildOptions> = Vec::new();
    for r in rows {
        if !seen.contains(&r.options) {
            seen.push(r.options);
        }
    }
    for o in seen {
        let of = |mode: QueryMode| rows.iter().find(|r| r.options == o && r.mode == mode);
        let (Some(tri), Some(first), Some(leaves)) = (
            of(QueryMode::Triangles),
            of(QueryMode::FirstHit),
            of(QueryMode::Leaves),
        ) else {
            continue;
        };
        t.row(vec![
            label(&o),
            ms(median(&tri.refit_ms)),
            ms(tri.time()),
            ms(first.time()),
            ms(leaves.time()),
            format!("{:.2e}", leaves.precision()),
            format!("{:.1}%", 100.0 * leaves.object_accuracy()),
        ]);
    }
    t
}

/// Every mode of one option: what the modes buy.
pub fn modes_table(rows: &[Row], o: &BuildOptions) -> Table {
    let mut t = Table::new(&[
        "mode",
        "time",
        "query",
        "volume tests",
        "recall",
        "precision",
        "object answer right",
    ]);
    for r in rows.iter().filter(|r| r.options == *o) {
        t.row(vec![
            mode_name(r.mode),
            ms(r.time()),
            ms(median(&r.query_ms)),
            count(median(&r.bv_tests) as u64),
            format!("{:.4}", r.recall()),
            format!("{:.2e}", r.precision()),
            format!("{:.1}%", 100.0 * r.object_accuracy()),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_grow_geometrically_to_the_full_cost() {
        assert_eq!(budgets(1), vec![1]);
        assert_eq!(budgets(120), vec![10, 20, 50, 100, 120]);
        assert_eq!(budgets(500), vec![10, 20, 50, 100, 200, 500]);
    }
}
