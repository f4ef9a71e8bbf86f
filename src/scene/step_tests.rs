//! Scenes over a step: self-contact, motions, continuous collision and stencils, each held to the
//! pairwise and self queries on stand-alone meshes holding the same world positions.

use super::tests::exclude_ends;
use super::*;
use crate::fixtures::{MeshData, Morph, Rng, icosphere, torus};
use crate::{
    BuildOptions, CcdMode, CcdOptions, Impacts, NearPairs, Pairs, QueryOptions, SceneImpact,
    SceneImpacts, SceneNearPair, SceneNearPairs, VolumeKind, continuous_collide, nearest_features,
    self_collide, self_continuous_collide, self_nearest_features,
};
use nalgebra::{Isometry3, Vector3};

/// What the test knows of an object: its mesh (local positions for a rigid one), where its
/// vertices are in world coordinates at the start and the end of its step, and its filters.
#[derive(Clone)]
struct Model {
    mesh: Mesh,
    rigid: bool,
    start: Vec<f64>,
    end: Vec<f64>,
    moving: bool,
    group: u32,
    mask: u32,
    self_contact: bool,
}

impl Model {
    /// A stand-alone mesh holding the object's world positions and motion.
    fn standalone(&self) -> Mesh {
        let mut m = self.mesh.clone();
        if self.moving {
            m.refit_motion(&self.start, &self.end).unwrap();
        } else {
            m.refit(&self.end).unwrap();
        }
        m
    }
}

fn isometry(rng: &mut Rng, spread: f64, turn: f64) -> Isometry3<f64> {
    let t = Vector3::new(
        rng.range(-spread, spread),
        rng.range(-spread, spread),
        rng.range(-spread, spread),
    );
    let axis = Vector3::new(
        rng.range(-turn, turn),
        rng.range(-turn, turn),
        rng.range(-turn, turn),
    );
    Isometry3::new(t, axis)
}

fn pose(rng: &mut Rng, spread: f64, turn: f64) -> Pose {
    Pose::from_isometry(&isometry(rng, spread, turn)).unwrap()
}

/// `local` placed by `pose`, as the scene places a rigid object's vertices.
fn placed(local: &Mesh, pose: &Pose) -> Vec<f64> {
    local
        .positions()
        .iter()
        .flat_map(|p| pose.transform_point(p))
        .collect()
}

fn shifted(p: &[f64], by: [f64; 3]) -> Vec<f64> {
    p.iter().enumerate().map(|(k, x)| x + by[k % 3]).collect()
}

/// The object pairs the filters allow, `(i, j)` with `i < j`, and `(i, i)` for self-contact.
fn allowed_pairs(models: &[Option<Model>], excluded: &HashSet<(u32, u32)>) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (i, a) in models.iter().enumerate() {
        let Some(a) = a else { continue };
        if a.self_contact {
            out.push((i as u32, i as u32));
        }
        for (j, b) in models.iter().enumerate().skip(i + 1) {
            let Some(b) = b else { continue };
            let (i, j) = (i as u32, j as u32);
            if a.group & b.mask != 0 && b.group & a.mask != 0 && !excluded.contains(&(i, j)) {
                out.push((i, j));
            }
        }
    }
    out
}

/// Every impact of the scene's objects, pair by pair and object by object on stand-alone meshes.
fn pairwise_impacts(
    models: &[Option<Model>],
    excluded: &HashSet<(u32, u32)>,
    options: &CcdOptions,
) -> Vec<SceneImpact> {
    let meshes: Vec<Option<Mesh>> = models
        .iter()
        .map(|m| m.as_ref().map(Model::standalone))
        .collect();
    let mut impacts = Impacts::new();
    let mut out = Vec::new();
    for (i, j) in allowed_pairs(models, excluded) {
        let a = meshes[i as usize].as_ref().unwrap();
        if i == j {
            self_continuous_collide(a, options, &mut impacts).unwrap();
        } else {
            let b = meshes[j as usize].as_ref().unwrap();
            continuous_collide(a, b, options, &mut impacts).unwrap();
        }
        out.extend(impacts.iter().map(|&impact| SceneImpact {
            object_a: i,
            object_b: j,
            impact,
        }));
    }
    out
}

/// Every stencil within `d`, pair by pair and object by object on stand-alone meshes.
fn pairwise_stencils(
    models: &[Option<Model>],
    excluded: &HashSet<(u32, u32)>,
    d: f64,
    options: &QueryOptions,
) -> Vec<SceneNearPair> {
    let meshes: Vec<Option<Mesh>> = models
        .iter()
        .map(|m| m.as_ref().map(Model::standalone))
        .collect();
    let mut near = NearPairs::new();
    let mut out = Vec::new();
    for (i, j) in allowed_pairs(models, excluded) {
        let a = meshes[i as usize].as_ref().unwrap();
        if i == j {
            self_nearest_features(a, d, options, &mut near).unwrap();
        } else {
            let b = meshes[j as usize].as_ref().unwrap();
            nearest_features(a, None, b, None, d, options, &mut near).unwrap();
        }
        out.extend(near.iter().map(|&pair| SceneNearPair {
            object_a: i,
            object_b: j,
            pair,
        }));
    }
    out
}

/// Every triangle contact, pair by pair with `collide` and object by object with `self_collide`.
fn pairwise_contacts(
    models: &[Option<Model>],
    excluded: &HashSet<(u32, u32)>,
    options: &QueryOptions,
) -> Vec<Contact> {
    let meshes: Vec<Option<Mesh>> = models
        .iter()
        .map(|m| m.as_ref().map(Model::standalone))
        .collect();
    let mut pairs = Pairs::new();
    let mut out = Vec::new();
    for (i, j) in allowed_pairs(models, excluded) {
        let a = meshes[i as usize].as_ref().unwrap();
        if i == j {
            self_collide(a, options, &mut pairs).unwrap();
        } else {
            let b = meshes[j as usize].as_ref().unwrap();
            crate::collide(a, None, b, None, options, &mut pairs).unwrap();
        }
        out.extend(Contact::of_pairs(i, j, &pairs));
    }
    out
}

/// The earliest of `all` (the first in order among equal times).
fn earliest(all: &[SceneImpact]) -> Vec<SceneImpact> {
    let mut first: Option<SceneImpact> = None;
    for x in all {
        if first.is_none_or(|f| x.impact.toi < f.impact.toi) {
            first = Some(*x);
        }
    }
    first.into_iter().collect()
}

struct Source {
    mesh: Mesh,
    data: MeshData,
    morph: Morph,
}

/// A random scene of rigid and deformable objects from two shared meshes, some moving over the
/// step (poses, motions), some standing still, some with self-contact.
fn random_scene(sources: &[Source], rng: &mut Rng) -> (Scene, Vec<Option<Model>>) {
    let mut scene = Scene::new();
    let mut models: Vec<Option<Model>> = Vec::new();
    for _ in 0..7 {
        let s = &sources[rng.below(2) as usize];
        let group = 1 << rng.below(3);
        let mask = if rng.below(4) == 0 { 0b011 } else { u32::MAX };
        let (id, model) = if rng.below(3) == 0 {
            let i0 = isometry(rng, 1.0, 2.0);
            let p0 = Pose::from_isometry(&i0).unwrap();
            let id = scene.add_rigid(&s.mesh, Some(&p0), group, mask).unwrap();
            let (start, end, moving) = match rng.below(3) {
                0 => (placed(&s.mesh, &p0), placed(&s.mesh, &p0), false),
                1 => {
                    // A step that turns a little and moves.
                    let p1 = Pose::from_isometry(&(isometry(rng, 0.3, 0.2) * i0)).unwrap();
                    scene.set_pose_motion(id, Some(&p0), Some(&p1)).unwrap();
                    (placed(&s.mesh, &p0), placed(&s.mesh, &p1), true)
                }
                _ => {
                    // From the identity (a NULL pose) to a pose.
                    let p1 = pose(rng, 0.5, 0.3);
                    scene.set_pose_motion(id, None, Some(&p1)).unwrap();
                    (placed(&s.mesh, &Pose::IDENTITY), placed(&s.mesh, &p1), true)
                }
            };
            let model = Model {
                mesh: s.mesh.clone(),
                rigid: true,
                start,
                end,
                moving,
                group,
                mask,
                self_contact: false,
            };
            (id, model)
        } else {
            let shift = [0, 1, 2].map(|_| rng.range(-1.0, 1.0));
            let (t0, t1) = (rng.unit(), rng.unit());
            let start = shifted(&s.morph.at(&s.data.positions, t0), shift);
            let mut m = s.mesh.clone();
            m.refit(&start).unwrap();
            let id = scene.add_deformable(&m, group, mask).unwrap();
            let moving = rng.below(4) != 0;
            let end = if moving {
                let step = [0, 1, 2].map(|_| rng.range(-0.3, 0.3));
                let end = shifted(&s.morph.at(&s.data.positions, t1), shift);
                let end = shifted(&end, step);
                scene.set_motion(id, &start, &end).unwrap();
                end
            } else {
                start.clone()
            };
            let self_contact = rng.below(2) == 0;
            scene.set_self_contact(id, self_contact).unwrap();
            let model = Model {
                mesh: s.mesh.clone(),
                rigid: false,
                start,
                end,
                moving,
                group,
                mask,
                self_contact,
            };
            (id, model)
        };
        if models.len() <= id as usize {
            models.resize(id as usize + 1, None);
        }
        models[id as usize] = Some(model);
    }
    (scene, models)
}

fn sources() -> Vec<Source> {
    let sphere = icosphere(2);
    let ring = torus(0.6, 0.25, 16, 8);
    let options = [
        BuildOptions::default(),
        BuildOptions {
            volume: VolumeKind::Dvh,
            ..BuildOptions::default()
        },
    ];
    [sphere, ring]
        .into_iter()
        .zip(options)
        .enumerate()
        .map(|(k, (data, o))| Source {
            mesh: Mesh::new(&data.positions, &data.triangles, &o).unwrap(),
            morph: Morph::random(&data, 4, 0.35, 40 + k as u64),
            data,
        })
        .collect()
}

/// Random scenes over a step: the scene's impacts (every one, the earliest, a truncated list),
/// its stencils and its contacts equal the pairwise and self queries on stand-alone meshes
/// holding the same world positions and motions, on one thread and on every core.
#[test]
fn scene_queries_equal_pairwise_and_self_queries() {
    let sources = sources();
    let (mut self_impacts, mut pair_impacts, mut stencils, mut self_contacts) = (0, 0, 0, 0);
    for seed in 0..crate::fixtures::cases(3, 6) as u64 {
        let mut rng = Rng::new(700 + seed);
        let (mut scene, models) = random_scene(&sources, &mut rng);
        let mut excluded = HashSet::new();
        exclude_ends(&mut scene, &models, &mut excluded);
        let mut impacts = SceneImpacts::new();
        for mode in [CcdMode::Exact, CcdMode::Conservative] {
            let all = CcdOptions::default().with_mode(mode);
            let expected = pairwise_impacts(&models, &excluded, &all);
            self_impacts += expected.iter().filter(|x| x.object_a == x.object_b).count();
            pair_impacts += expected.iter().filter(|x| x.object_a != x.object_b).count();
            for threads in [0, 1] {
                let what = format!("seed {seed} {mode:?} threads {threads}");
                let opts = all.with_threads(threads);
                let stats = scene.continuous_collide(&opts, &mut impacts).unwrap();
                assert_eq!(impacts.as_slice(), &expected[..], "{what}");
                assert_eq!(stats.impacts, expected.len() as u64, "{what}");
                assert!(!stats.truncated, "{what}");
                let first = earliest(&expected);
                let stats = scene
                    .continuous_collide(&opts.with_earliest_only(true), &mut impacts)
                    .unwrap();
                assert_eq!(impacts.as_slice(), &first[..], "{what} earliest");
                let toi = first.first().map_or(f64::INFINITY, |x| x.impact.toi);
                assert_eq!(stats.earliest_toi, toi, "{what}");
                // A limit: each pair's own truncated answer, the first in order.
                let limit = expected.len() / 2;
                let per_pair =
                    pairwise_impacts(&models, &excluded, &all.with_max_impacts(Some(limit)));
                let stats = scene
                    .continuous_collide(&opts.with_max_impacts(Some(limit)), &mut impacts)
                    .unwrap();
                assert_eq!(
                    impacts.as_slice(),
                    &per_pair[..limit.min(per_pair.len())],
                    "{what} max {limit}"
                );
                assert_eq!(stats.truncated, expected.len() > limit, "{what}");
            }
        }
        let size = 2.0;
        let mut near = SceneNearPairs::new();
        for d in [0.0, 0.01 * size, 0.05 * size] {
            let expected = pairwise_stencils(&models, &excluded, d, &QueryOptions::default());
            stencils += expected.len();
            for threads in [0, 1] {
                let opts = QueryOptions::default().with_threads(threads);
                let stats = scene.nearest_features(d, &opts, &mut near).unwrap();
                assert_eq!(
                    near.as_slice(),
                    &expected[..],
                    "seed {seed} d {d} threads {threads}"
                );
                assert_eq!(stats.pairs, expected.len() as u64);
            }
        }
        let mut contacts = Contacts::new();
        let expected = pairwise_contacts(&models, &excluded, &QueryOptions::default());
        self_contacts += expected.iter().filter(|c| c.object_a == c.object_b).count();
        for threads in [0, 1] {
            let opts = QueryOptions::default().with_threads(threads);
            scene.collide(&opts, &mut contacts).unwrap();
            assert_eq!(
                contacts.as_slice(),
                &expected[..],
                "seed {seed} threads {threads}"
            );
        }
    }
    // Not vacuous: every kind of result came up.
    assert!(
        self_impacts > 0 && pair_impacts > 0,
        "{self_impacts} {pair_impacts}"
    );
    assert!(
        stencils > 0 && self_contacts > 0,
        "{stencils} {self_contacts}"
    );
}

/// Self-contact is for deformable objects; motions and poses go to the right kind of object;
/// every failed call leaves the scene answering exactly as before.
#[test]
fn step_errors_change_nothing() {
    let sources = sources();
    let mut rng = Rng::new(5);
    let (mut scene, models) = random_scene(&sources, &mut rng);
    let rigid = (0..models.len() as u32)
        .find(|&i| models[i as usize].as_ref().is_some_and(|m| m.rigid))
        .unwrap();
    let deformable = (0..models.len() as u32)
        .find(|&i| models[i as usize].as_ref().is_some_and(|m| !m.rigid))
        .unwrap();
    let answers = |scene: &mut Scene| {
        let mut impacts = SceneImpacts::new();
        let mut near = SceneNearPairs::new();
        let mut contacts = Contacts::new();
        scene
            .continuous_collide(&CcdOptions::default(), &mut impacts)
            .unwrap();
        scene
            .nearest_features(0.05, &QueryOptions::default(), &mut near)
            .unwrap();
        scene
            .collide(&QueryOptions::default(), &mut contacts)
            .unwrap();
        (
            impacts.as_slice().to_vec(),
            near.as_slice().to_vec(),
            contacts.as_slice().to_vec(),
        )
    };
    let before = answers(&mut scene);
    let n = scene.vertex_count(deformable).unwrap();
    let good = models[deformable as usize].as_ref().unwrap().end.clone();
    let mut bad = good.clone();
    bad[7] = f64::NAN;
    let e = scene.set_self_contact(rigid, true).unwrap_err();
    assert_eq!(e, Error::RigidSelfContact { object: rigid });
    scene.set_self_contact(rigid, false).unwrap();
    let e = scene.set_motion(rigid, &good, &good).unwrap_err();
    assert!(
        matches!(e, Error::WrongObjectKind { rigid: true, .. }),
        "{e}"
    );
    let e = scene.set_pose_motion(deformable, None, None).unwrap_err();
    assert!(
        matches!(e, Error::WrongObjectKind { rigid: false, .. }),
        "{e}"
    );
    let e = scene.set_motion(deformable, &good, &bad).unwrap_err();
    let Error::Object { object, error } = &e else {
        panic!("{e}")
    };
    assert_eq!(*object, deformable);
    assert!(
        matches!(
            **error,
            Error::Motion {
                instant: crate::error::Instant::End,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("vertex 2"), "{e}");
    let e = scene.set_motion(deformable, &good[3..], &good).unwrap_err();
    assert!(e.to_string().contains("start"), "{e}");
    let e = scene
        .set_motion_with(deformable, n - 1, |_| [0.0; 3], |_| [0.0; 3])
        .unwrap_err();
    assert!(matches!(e, Error::Object { .. }), "{e}");
    let far = Pose::new(Pose::IDENTITY.rotation(), [1e301, 0.0, 0.0]).unwrap();
    let e = scene.set_pose_motion(rigid, None, Some(&far)).unwrap_err();
    assert!(e.to_string().contains(&format!("object {rigid}")), "{e}");
    let e = scene.set_self_contact(99, true).unwrap_err();
    assert_eq!(e, Error::UnknownObject { object: 99 });
    let e = scene
        .nearest_features(-1.0, &QueryOptions::default(), &mut SceneNearPairs::new())
        .unwrap_err();
    assert!(matches!(e, Error::InvalidDistance { .. }), "{e}");
    assert_eq!(answers(&mut scene), before);
}

/// A step lasts until positions or a pose are given: then the object stands still there, and
/// the discrete queries see the end of a step.
#[test]
fn a_step_ends_with_new_positions_or_pose() {
    let sources = sources();
    let s = &sources[0];
    let mut scene = Scene::new();
    let a = scene.add_deformable(&s.mesh, 1, 1).unwrap();
    let b = scene.add_rigid(&s.mesh, None, 1, 1).unwrap();
    let start = shifted(&s.data.positions, [3.0, 0.0, 0.0]);
    // `a` sweeps through `b` and ends beyond it.
    let end = shifted(&s.data.positions, [-3.0, 0.0, 0.0]);
    scene.set_motion(a, &start, &end).unwrap();
    let mut impacts = SceneImpacts::new();
    let mut contacts = Contacts::new();
    scene
        .continuous_collide(&CcdOptions::default(), &mut impacts)
        .unwrap();
    assert!(!impacts.is_empty(), "the sweep meets b");
    scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert!(contacts.is_empty(), "a ends beyond b");
    // New positions end the step: standing still at `end`, nothing meets.
    scene.set_positions(a, &end).unwrap();
    scene
        .continuous_collide(&CcdOptions::default(), &mut impacts)
        .unwrap();
    assert!(impacts.is_empty());
    // A rigid step through `a`, then a pose that ends it.
    let through = Pose::new(Pose::IDENTITY.rotation(), [-6.0, 0.0, 0.0]).unwrap();
    scene.set_pose_motion(b, None, Some(&through)).unwrap();
    scene
        .continuous_collide(&CcdOptions::default(), &mut impacts)
        .unwrap();
    assert!(!impacts.is_empty(), "b's sweep meets a");
    assert!(impacts.iter().all(|x| (x.object_a, x.object_b) == (a, b)));
    scene.set_pose(b, Some(&through)).unwrap();
    scene
        .continuous_collide(&CcdOptions::default(), &mut impacts)
        .unwrap();
    assert!(impacts.is_empty());
}

/// Two square plates facing each other across a gap: stencils within a distance a little larger
/// than the gap are found (their boxes are apart, but within the distance), none below it.
#[test]
fn stencils_reach_across_a_gap_between_boxes() {
    let plate = |x: f64| vec![x, 0.0, 0.0, x, 1.0, 0.0, x, 1.0, 1.0, x, 0.0, 1.0];
    let triangles = [0, 1, 2, 0, 2, 3];
    let mesh = Mesh::new(&plate(0.0), &triangles, &BuildOptions::default()).unwrap();
    let gap = 0.125;
    let mut scene = Scene::new();
    let a = scene.add_deformable(&mesh, 1, 1).unwrap();
    let moved = Pose::new(Pose::IDENTITY.rotation(), [gap, 0.0, 0.0]).unwrap();
    let b = scene.add_rigid(&mesh, Some(&moved), 1, 1).unwrap();
    let mut near = SceneNearPairs::new();
    scene
        .nearest_features(1.01 * gap, &QueryOptions::default(), &mut near)
        .unwrap();
    // Each corner of either plate faces the other plate: 8 vertex-face stencils at the gap,
    // among others.
    assert!(near.len() >= 8, "{}", near.len());
    assert!(near.iter().all(|s| (s.object_a, s.object_b) == (a, b)));
    assert!(near.iter().all(|s| s.pair.distance == gap));
    scene
        .nearest_features(0.99 * gap, &QueryOptions::default(), &mut near)
        .unwrap();
    assert!(near.is_empty());
}
