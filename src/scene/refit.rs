//! Refitting the deformable objects a scene query needs: those whose positions or motion
//! changed since their last refit, whole or (box volumes, discrete queries) only at the top of
//! their trees, the blocks below refit as the query reaches them.

use super::{Body, Object, Scene};
use crate::threads;
use std::sync::Arc;

/// One thread's part of the refits a query makes.
#[derive(Default)]
struct Share<'s> {
    /// The objects, each with whether it may be refit lazily.
    objects: Vec<(&'s mut Object, bool)>,
    vertices: usize,
    nodes: u64,
}

impl Scene {
    /// Refits the stale deformable objects for which `needed(id)` holds, on up to `threads`
    /// threads, each given a share of about equal vertex count (largest meshes first). Those
    /// for which `lazy(id)` holds, with box volumes and no step, get only their top refit (the
    /// query refits their blocks as it reaches them); the others are refit whole (with a step,
    /// their volumes hold it). Returns the nodes recomputed by whole refits.
    pub(super) fn refit_stale(
        &mut self,
        needed: impl Fn(usize) -> bool,
        threads: u32,
        lazy: impl Fn(usize) -> bool,
    ) -> u64 {
        // Whether object `id` is stale, and then whether it may be refit lazily.
        let stale = |id: usize, o: &Object| -> Option<bool> {
            if !needed(id) {
                return None;
            }
            let lazy = lazy(id) && !o.mesh.is_moving();
            match &o.body {
                Body::Deformable { fresh }
                    if !(fresh.is_current() || lazy && fresh.is_partial()) =>
                {
                    Some(lazy)
                }
                _ => None,
            }
        };
        let count = self
            .objects
            .iter()
            .enumerate()
            .filter(|(id, o)| o.as_ref().and_then(|o| stale(*id, o)).is_some())
            .count();
        let workers = threads::resolve(threads).min(count).max(1);
        if workers == 1 {
            // On one thread, in place: nothing to share out, nothing allocated.
            let mut nodes = 0;
            for (id, o) in self.objects.iter_mut().enumerate() {
                let Some(o) = o.as_mut() else { continue };
                if let Some(lazy) = stale(id, o) {
                    nodes += refit_object(o, lazy);
                }
            }
            return nodes;
        }
        let mut stale: Vec<(&mut Object, bool)> = self
            .objects
            .iter_mut()
            .enumerate()
            .filter_map(|(id, o)| {
                let o = o.as_mut()?;
                stale(id, o).map(|lazy| (o, lazy))
            })
            .collect();
        stale.sort_by_key(|(o, _)| std::cmp::Reverse(o.mesh.vertex_count()));
        let mut shares: Vec<Share> = (0..workers).map(|_| Share::default()).collect();
        for o in stale {
            let share = shares
                .iter_mut()
                .min_by_key(|s| s.vertices)
                .expect("at least one share");
            share.vertices += o.0.mesh.vertex_count();
            share.objects.push(o);
        }
        threads::on_each(
            threads::Step::SceneRefit,
            &mut shares,
            &|share: &mut Share, _| {
                for (o, lazy) in &mut share.objects {
                    share.nodes += refit_object(o, *lazy);
                }
            },
        );
        shares.iter().map(|s| s.nodes).sum()
    }
}

/// Refits deformable object `o`: only the top of its tree when `lazy` allows it (box volumes),
/// whole otherwise. Returns the nodes recomputed by a whole refit.
fn refit_object(o: &mut Object, lazy: bool) -> u64 {
    let Body::Deformable { fresh } = &mut o.body else {
        unreachable!("only deformable objects are refit");
    };
    let mesh = Arc::make_mut(&mut o.mesh);
    if lazy && mesh.refit_top(fresh) {
        return 0;
    }
    let s = mesh.refit_volumes();
    fresh.refit();
    s.nodes_refit
}
