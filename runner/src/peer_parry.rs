//! parry (`parry3d-f64`), measured beside dvh as its users would drive it for deforming meshes: a
//! `TriMesh` with the `DEFORMABLE` flag per object, `set_vertices` every frame (which refits its
//! BVH bottom-up, keeping the tree), then every pair of overlapping leaves (triangles) of the two
//! BVHs, from its tree-against-tree traversal `Bvh::leaf_pairs`, through parry's triangle test
//! (GJK on the triangles' support maps, in floating point).

use crate::method::{Counters, Method};
use crate::scene::Scene;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::details::intersection_test_support_map_support_map;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};
use std::cell::Cell;

#[derive(Default)]
pub struct Parry {
    meshes: Vec<TriMesh>,
    /// Each object's next positions as parry's vectors, converted outside the timed update (as
    /// FCL's are).
    staged: Vec<Vec<Vector>>,
}

fn vectors(world: &[f64], out: &mut Vec<Vector>) {
    out.clear();
    out.extend(world.chunks_exact(3).map(|p| Vector::new(p[0], p[1], p[2])));
}

impl Method for Parry {
    fn name(&self) -> String {
        "parry".into()
    }

    fn build(&mut self, scene: &Scene, world: &[Vec<f64>]) {
        self.meshes.clear();
        self.staged.clear();
        for (o, w) in scene.objects.iter().zip(world) {
            let mut v = Vec::new();
            vectors(w, &mut v);
            let indices = o
                .rest
                .triangles
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect();
            let mesh = TriMesh::with_flags(v.clone(), indices, TriMeshFlags::DEFORMABLE)
                .expect("parry accepts the scene's meshes");
            self.meshes.push(mesh);
            self.staged.push(v);
        }
    }

    fn stage(&mut self, object: usize, world: &[f64]) {
        vectors(world, &mut self.staged[object]);
    }

    fn update(&mut self, object: usize, _world: &[f64]) -> Option<u64> {
        self.meshes[object].set_vertices(&self.staged[object]);
        None
    }

    fn collide(&mut self, a: usize, b: usize, out: &mut Vec<u64>) -> Option<Counters> {
        out.clear();
        let (ma, mb) = (&self.meshes[a], &self.meshes[b]);
        let tests = Cell::new(0u64);
        let mut triangle_tests = 0;
        for (i, j) in ma.bvh().leaf_pairs(mb.bvh(), |n1, n2| {
            tests.set(tests.get() + 1);
            n1.intersects(n2)
        }) {
            triangle_tests += 1;
            let (ta, tb) = (ma.triangle(i), mb.triangle(j));
            if intersection_test_support_map_support_map(&Pose::IDENTITY, &ta, &tb) {
                out.push((u64::from(i) << 32) | u64::from(j));
            }
        }
        out.sort_unstable();
        out.dedup();
        Some(Counters {
            bv_tests: tests.get(),
            triangle_tests,
        })
    }
}
