//! The methods measured on the paper's scenes, behind one interface: dvh with each build option,
//! FCL in both configurations the cross-check uses, and parry.

use crate::scene::Scene;
use dvh::{BuildOptions, Mesh, Pairs, QueryOptions, collide};

/// What one query of a method counted (the paper's cost model), where the method says.
#[derive(Clone, Copy, Debug, Default)]
pub struct Counters {
    /// Bounding-volume pairs tested (`NV`).
    pub bv_tests: u64,
    /// Triangle pairs tested (`NP`).
    pub triangle_tests: u64,
}

/// A collision-detection method driven frame by frame on world coordinates.
pub trait Method {
    /// Its name in tables and plots.
    fn name(&self) -> String;
    /// Builds every object of `scene` from the world coordinates of frame 0.
    fn build(&mut self, scene: &Scene, world: &[Vec<f64>]);
    /// Prepares object `object`'s next coordinates; not timed (FCL's conversion of the input,
    /// as the cross-check stages it).
    fn stage(&mut self, _object: usize, _world: &[f64]) {}
    /// Timed: takes object `object`'s new coordinates and refits. Returns the nodes refit
    /// (`NU`), where the method counts them.
    fn update(&mut self, object: usize, world: &[f64]) -> Option<u64>;
    /// Timed: the intersecting triangle pairs of objects `a` and `b`, as sorted, distinct keys
    /// `(ta << 32) | tb`, written to `out`.
    fn collide(&mut self, a: usize, b: usize, out: &mut Vec<u64>) -> Option<Counters>;
}

/// dvh with one set of build options, every pair in exact mode, on some threads.
pub struct Dvh {
    pub options: BuildOptions,
    /// Threads of each refit and query (0: every core).
    pub threads: u32,
    meshes: Vec<Mesh>,
    pairs: Pairs,
}

impl Dvh {
    /// On the calling thread only.
    pub fn new(options: BuildOptions) -> Dvh {
        Dvh::threaded(options, 1)
    }

    /// On `threads` threads (0: every core) for refits and queries alike.
    pub fn threaded(options: BuildOptions, threads: u32) -> Dvh {
        Dvh {
            options: options.with_refit_threads(threads),
            threads,
            meshes: Vec::new(),
            pairs: Pairs::new(),
        }
    }
}

/// A short name for a set of build options: volume, tree, radius (spheres only), and the
/// leftover policy when it is not the default.
pub fn label(o: &BuildOptions) -> String {
    let volume = match o.volume {
        dvh::VolumeKind::Dvh => "DVH",
        dvh::VolumeKind::Sbv => "SBV",
        dvh::VolumeKind::Aabb => "AABB",
        // Kinds newer than this runner, here and below.
        _ => "?",
    };
    let tree = match o.tree {
        dvh::TreeKind::Octree => "octree",
        dvh::TreeKind::Binary => "binary",
        _ => "?",
    };
    let radius = match (o.volume, o.radius) {
        (dvh::VolumeKind::Aabb, _) => "",
        (_, dvh::RadiusKind::Layered) => " layered",
        (_, dvh::RadiusKind::Wrapped) => " wrapped",
        _ => " ?",
    };
    let leftovers = match o.leftovers {
        dvh::LeftoverPolicy::JoinAdjacent => "",
        dvh::LeftoverPolicy::ExtraRings => " extra rings",
        _ => " ?",
    };
    format!("{volume} {tree}{radius}{leftovers}")
}

impl Method for Dvh {
    fn name(&self) -> String {
        match self.threads {
            1 => format!("dvh {}", label(&self.options)),
            0 => format!(
                "dvh {}, {} threads",
                label(&self.options),
                rayon::current_num_threads()
            ),
            n => format!("dvh {}, {n} threads", label(&self.options)),
        }
    }

    fn build(&mut self, scene: &Scene, world: &[Vec<f64>]) {
        self.meshes = scene
            .objects
            .iter()
            .zip(world)
            .map(|(o, w)| {
                Mesh::new(w, &o.rest.triangles, &self.options).expect("scene meshes are valid")
            })
            .collect();
    }

    fn update(&mut self, object: usize, world: &[f64]) -> Option<u64> {
        let s = self.meshes[object]
            .refit(world)
            .expect("scene coordinates are finite");
        Some(s.nodes_refit)
    }

    fn collide(&mut self, a: usize, b: usize, out: &mut Vec<u64>) -> Option<Counters> {
        let s = collide(
            &self.meshes[a],
            None,
            &self.meshes[b],
            None,
            &QueryOptions::default().with_threads(self.threads),
            &mut self.pairs,
        )
        .expect("queries on valid meshes succeed");
        out.clear();
        out.extend(
            self.pairs
                .iter()
                .map(|p| (u64::from(p.a) << 32) | u64::from(p.b)),
        );
        Some(Counters {
            bv_tests: s.bv_tests,
            triangle_tests: s.triangle_tests,
        })
    }
}
