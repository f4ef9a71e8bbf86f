//! Scenes shared by the integration tests: random meshes, deformations and poses, and the checks
//! every query result must pass against the brute-force oracle.
#![allow(dead_code)]

use dvh::fixtures::{MeshData, Morph, Rng, grid, icosphere, soup, torus};
use dvh::{
    BuildOptions, Mesh, Pair, PairKind, Pairs, Pose, QueryMode, QueryOptions, brute_force, collide,
};
use nalgebra::{Isometry3, Vector3};
use std::collections::HashSet;

/// Every combination of build options.
pub fn all_build_options() -> Vec<BuildOptions> {
    BuildOptions::all().collect()
}

/// A random mesh of one of the kinds the tests cover, about unit size, centred at the origin.
pub fn random_shape(kind: u8, detail: u8, seed: u64) -> MeshData {
    let mut m = match kind % 5 {
        0 => {
            let mut m = icosphere(1 + u32::from(detail % 3));
            m.perturb(0.05, seed);
            m
        }
        1 => grid(3 + usize::from(detail % 12), 1.0),
        2 => torus(
            0.35,
            0.12 + 0.05 * f64::from(detail % 3),
            6 + usize::from(detail % 14),
            5 + usize::from(detail % 7),
        ),
        3 => soup(20 + 15 * usize::from(detail % 16), 1.0, 0.25, seed),
        _ => {
            // Two components with shared coordinates and duplicated triangles.
            let mut m = icosphere(1);
            let mut g = grid(4, 1.0);
            g.translate([-0.5, -0.5, 0.0]);
            m.append(&g);
            let extra = m.triangles[..9].to_vec();
            m.triangles.extend(extra);
            m
        }
    };
    m.normalize(1.0);
    m
}

/// A random rigid pose with rotation angle up to pi and translation up to `reach`.
pub fn random_pose(rng: &mut Rng, reach: f64) -> Pose {
    let axis = Vector3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    );
    let angle = rng.range(0.0, std::f64::consts::PI);
    let axis = if axis.norm() > 1e-6 {
        axis.normalize() * angle
    } else {
        Vector3::zeros()
    };
    let t = Vector3::new(
        rng.range(-reach, reach),
        rng.range(-reach, reach),
        rng.range(-reach, reach),
    );
    Pose::from_isometry(&Isometry3::new(t, axis)).expect("a rotation is rigid")
}

/// One side of a test scene.
pub struct Body {
    pub rest: MeshData,
    pub morph: Morph,
    pub pose: Option<Pose>,
    pub mesh: Mesh,
}

impl Body {
    pub fn new(
        rest: MeshData,
        morph_seed: u64,
        amplitude: f64,
        pose: Option<Pose>,
        options: &BuildOptions,
    ) -> Body {
        let morph = Morph::random(&rest, 3, amplitude, morph_seed);
        let mesh = Mesh::new(&rest.positions, &rest.triangles, options).expect("valid mesh");
        mesh.validate().expect("valid after build");
        Body {
            rest,
            morph,
            pose,
            mesh,
        }
    }

    /// Deforms to time `t` and refits.
    pub fn deform(&mut self, t: f64) {
        let p = self.morph.at(&self.rest.positions, t);
        self.mesh.refit(&p).expect("valid positions");
        self.mesh.validate().expect("valid after refit");
    }
}

fn swapped(p: &[Pair]) -> Vec<Pair> {
    let mut v: Vec<Pair> = p.iter().map(|q| Pair { a: q.b, b: q.a }).collect();
    v.sort_unstable();
    v
}

/// For node pairs reported by a coarse mode: is the triangle pair `(ta, tb)` below one of them?
struct Coverage {
    pairs: HashSet<(u32, u32)>,
    leaf_of_a: Vec<u32>,
    leaf_of_b: Vec<u32>,
    parent_a: Vec<u32>,
    parent_b: Vec<u32>,
}

impl Coverage {
    fn new(a: &Mesh, b: &Mesh, nodes: &[Pair]) -> Coverage {
        let index = |m: &Mesh| {
            let mut leaf_of = vec![u32::MAX; m.triangle_count()];
            let mut parent = vec![u32::MAX; m.node_count()];
            for n in 0..m.node_count() as u32 {
                let view = m.node(n);
                for c in view.children.clone() {
                    parent[c as usize] = n;
                }
                if view.children.is_empty() {
                    for &t in m.node_triangles(n) {
                        leaf_of[t as usize] = n;
                    }
                }
            }
            (leaf_of, parent)
        };
        let (leaf_of_a, parent_a) = index(a);
        let (leaf_of_b, parent_b) = index(b);
        Coverage {
            pairs: nodes.iter().map(|p| (p.a, p.b)).collect(),
            leaf_of_a,
            leaf_of_b,
            parent_a,
            parent_b,
        }
    }

    fn covers(&self, p: &Pair) -> bool {
        let mut na = self.leaf_of_a[p.a as usize];
        while na != u32::MAX {
            let mut nb = self.leaf_of_b[p.b as usize];
            while nb != u32::MAX {
                if self.pairs.contains(&(na, nb)) {
                    return true;
                }
                nb = self.parent_b[nb as usize];
            }
            na = self.parent_a[na as usize];
        }
        false
    }
}

/// Runs every query mode on the two bodies and checks each against the brute force. Returns the
/// exact pairs.
pub fn check_all_modes(a: &Body, b: &Body, depth: u32, pairs: &mut Pairs) -> Vec<Pair> {
    let (pa, pb) = (a.pose.as_ref(), b.pose.as_ref());
    let expected = brute_force(&a.mesh, pa, &b.mesh, pb);

    let stats = collide(&a.mesh, pa, &b.mesh, pb, &QueryOptions::default(), pairs).expect("query");
    assert_eq!(pairs.kind(), PairKind::Triangles);
    assert_eq!(
        pairs.as_slice(),
        &expected[..],
        "exact mode differs from brute force"
    );
    assert_eq!(stats.pairs as usize, expected.len());
    assert!(
        stats.triangle_tests >= stats.pairs && stats.triangle_candidates >= stats.triangle_tests
    );

    collide(&b.mesh, pb, &a.mesh, pa, &QueryOptions::default(), pairs).expect("query");
    assert_eq!(
        pairs.as_slice(),
        &swapped(&expected)[..],
        "exact mode is not symmetric"
    );

    // A pair limit: some of the pairs, sorted, flagged; a limit above the count changes nothing.
    let k = expected.len().div_ceil(2);
    let limited = QueryOptions::default().with_max_pairs(Some(k));
    let stats = collide(&a.mesh, pa, &b.mesh, pb, &limited, pairs).expect("query");
    assert_eq!(pairs.len(), k);
    assert!(stats.truncated);
    assert!(pairs.as_slice().windows(2).all(|w| w[0] < w[1]));
    assert!(
        pairs.iter().all(|p| expected.binary_search(p).is_ok()),
        "a limited query reported a pair that does not intersect"
    );
    let roomy = QueryOptions::default().with_max_pairs(Some(expected.len() + 1));
    let stats = collide(&a.mesh, pa, &b.mesh, pb, &roomy, pairs).expect("query");
    assert_eq!(pairs.as_slice(), &expected[..]);
    assert!(!stats.truncated);

    collide(
        &a.mesh,
        pa,
        &b.mesh,
        pb,
        &QueryOptions::with_mode(QueryMode::FirstHit),
        pairs,
    )
    .expect("query");
    assert_eq!(
        pairs.is_empty(),
        expected.is_empty(),
        "first hit disagrees with exact"
    );
    assert!(pairs.len() <= 1);
    if let Some(p) = pairs.as_slice().first() {
        assert!(
            expected.binary_search(p).is_ok(),
            "first hit {p:?} is not an intersecting pair"
        );
    }

    check_budgets(a, b, &expected, pairs);

    for mode in [
        QueryMode::Leaves,
        QueryMode::Depth(depth),
        QueryMode::Depth(0),
    ] {
        collide(
            &a.mesh,
            pa,
            &b.mesh,
            pb,
            &QueryOptions::with_mode(mode),
            pairs,
        )
        .expect("query");
        assert_eq!(pairs.kind(), PairKind::Nodes);
        let nodes = pairs.as_slice().to_vec();
        if let QueryMode::Depth(d) = mode {
            for p in &nodes {
                let (na, nb) = (a.mesh.node(p.a), b.mesh.node(p.b));
                assert!(na.depth <= d && nb.depth <= d);
                assert!(na.depth == d || na.children.is_empty());
                assert!(nb.depth == d || nb.children.is_empty());
            }
        } else {
            for p in &nodes {
                assert!(
                    a.mesh.node(p.a).children.is_empty() && b.mesh.node(p.b).children.is_empty()
                );
            }
        }
        let cover = Coverage::new(&a.mesh, &b.mesh, &nodes);
        for p in &expected {
            assert!(
                cover.covers(p),
                "{mode:?} misses the intersecting pair {p:?}"
            );
        }
        collide(
            &b.mesh,
            pb,
            &a.mesh,
            pa,
            &QueryOptions::with_mode(mode),
            pairs,
        )
        .expect("query");
        assert_eq!(
            pairs.as_slice(),
            &swapped(&nodes)[..],
            "{mode:?} is not symmetric"
        );
    }
    expected
}

/// Budgeted queries: the frontier covers every exact pair at every budget, the volume tests stay
/// within the budget plus one opening, and a budget large enough to finish gives the leaves.
pub fn check_budgets(a: &Body, b: &Body, expected: &[Pair], pairs: &mut Pairs) {
    let (pa, pb) = (a.pose.as_ref(), b.pose.as_ref());
    let leaves = {
        let stats = collide(
            &a.mesh,
            pa,
            &b.mesh,
            pb,
            &QueryOptions::with_mode(QueryMode::Leaves),
            pairs,
        )
        .expect("query");
        (pairs.as_slice().to_vec(), stats.bv_tests)
    };
    let err = collide(
        &a.mesh,
        pa,
        &b.mesh,
        pb,
        &QueryOptions::with_mode(QueryMode::Budget(0)),
        pairs,
    )
    .unwrap_err();
    assert_eq!(err, dvh::Error::ZeroBudget);
    // Most child tests one opening can make: two octree nodes.
    const ONE_OPENING: u64 = 64;
    let full = leaves.1 + 1;
    for budget in [1, 2, 9, 40, full / 7 + 1, full / 2 + 1, full, u64::MAX] {
        let stats = collide(
            &a.mesh,
            pa,
            &b.mesh,
            pb,
            &QueryOptions::with_mode(QueryMode::Budget(budget)),
            pairs,
        )
        .expect("query");
        assert_eq!(pairs.kind(), PairKind::Nodes);
        assert!(
            stats.bv_tests <= budget.saturating_add(ONE_OPENING),
            "budget {budget}: {} volume tests",
            stats.bv_tests
        );
        let nodes = pairs.as_slice().to_vec();
        let cover = Coverage::new(&a.mesh, &b.mesh, &nodes);
        for p in expected {
            assert!(
                cover.covers(p),
                "budget {budget} misses the intersecting pair {p:?}"
            );
        }
        if budget >= full {
            assert_eq!(stats.frontier_pairs, 0, "budget {budget} ran out");
            assert_eq!(
                stats.bv_tests, leaves.1,
                "budget {budget}: not the leaves' tests"
            );
            assert_eq!(nodes, leaves.0, "budget {budget} differs from leaves mode");
        } else if stats.frontier_pairs == 0 {
            assert_eq!(
                nodes, leaves.0,
                "a finished budget differs from leaves mode"
            );
        }
    }
}
