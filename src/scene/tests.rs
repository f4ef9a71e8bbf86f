use super::*;
use crate::fixtures::{Morph, Rng, icosphere, torus};
use crate::threads::{Step, shared_count, sharing};
use crate::{BuildOptions, Pairs, QueryMode, QueryOptions, VolumeKind, collide};
use nalgebra::{Isometry3, Vector3};
use std::sync::Arc;

/// What the test knows of an object, to query it pair by pair without the scene.
#[derive(Clone)]
struct Model {
    mesh: Mesh,
    pose: Option<Pose>,
    group: u32,
    mask: u32,
}

/// The ids of the live models.
pub(super) fn live<T>(models: &[Option<T>]) -> Vec<u32> {
    (0..models.len() as u32)
        .filter(|&i| models[i as usize].is_some())
        .collect()
}

/// Excludes the pair of the first and the last live model from `scene`, and records it.
pub(super) fn exclude_ends<T>(
    scene: &mut Scene,
    models: &[Option<T>],
    excluded: &mut HashSet<(u32, u32)>,
) {
    let live = live(models);
    let (x, y) = (live[0], live[live.len() - 1]);
    scene.exclude_pair(y, x).unwrap();
    excluded.insert((x, y));
}

/// The pose that moves by `t`, without turning.
fn translated(t: [f64; 3]) -> Pose {
    Pose::new(Pose::IDENTITY.rotation(), t).unwrap()
}

fn random_pose(rng: &mut Rng, spread: f64) -> Pose {
    let t = Vector3::new(
        rng.range(-spread, spread),
        rng.range(-spread, spread),
        rng.range(-spread, spread),
    );
    let axis = Vector3::new(
        rng.range(-2.0, 2.0),
        rng.range(-2.0, 2.0),
        rng.range(-2.0, 2.0),
    );
    Pose::from_isometry(&Isometry3::new(t, axis)).unwrap()
}

/// Every contact of the live models, pair by pair with [`collide`], in the scene's order.
fn pairwise(
    models: &[Option<Model>],
    excluded: &HashSet<(u32, u32)>,
    opts: &QueryOptions,
) -> Vec<Contact> {
    let mut pairs = Pairs::new();
    let mut out = Vec::new();
    for (i, a) in models.iter().enumerate() {
        let Some(a) = a else { continue };
        for (j, b) in models.iter().enumerate().skip(i + 1) {
            let Some(b) = b else { continue };
            let (i, j) = (i as u32, j as u32);
            if a.group & b.mask == 0 || b.group & a.mask == 0 || excluded.contains(&(i, j)) {
                continue;
            }
            collide(
                &a.mesh,
                a.pose.as_ref(),
                &b.mesh,
                b.pose.as_ref(),
                opts,
                &mut pairs,
            )
            .unwrap();
            out.extend(Contact::of_pairs(i, j, &pairs));
        }
    }
    out
}

/// Random scenes of rigid and deformable objects from two shared meshes, changed between frames
/// (poses, positions, objects added and removed, exclusions): the scene's contacts are exactly
/// those of the objects queried pair by pair, on one thread and on every core.
#[test]
fn scene_equals_pairwise_queries() {
    let sphere = icosphere(3);
    let ring = torus(0.6, 0.2, 24, 12);
    let options = [
        BuildOptions::default(),
        BuildOptions {
            volume: VolumeKind::Dvh,
            ..BuildOptions::default()
        },
    ];
    let sources: Vec<(Mesh, Morph, &[f64])> = [&sphere, &ring]
        .iter()
        .zip(&options)
        .enumerate()
        .map(|(k, (d, o))| {
            (
                Mesh::new(&d.positions, &d.triangles, o).unwrap(),
                Morph::random(d, 4, 0.1, k as u64),
                &d.positions[..],
            )
        })
        .collect();
    let mut shared_frames = 0;
    for seed in 0..4 {
        let mut rng = Rng::new(100 + seed);
        let mut scene = Scene::new();
        let mut models: Vec<Option<Model>> = Vec::new();
        let mut excluded = HashSet::new();
        let add = |scene: &mut Scene, models: &mut Vec<Option<Model>>, rng: &mut Rng| {
            let (mesh, morph, rest) = &sources[rng.below(2) as usize];
            let group = 1 << rng.below(3);
            let mask = if rng.below(4) == 0 { 0b011 } else { u32::MAX };
            let (id, model) = if rng.below(2) == 0 {
                let pose = random_pose(rng, 1.5);
                let id = scene.add_rigid(mesh, Some(&pose), group, mask).unwrap();
                let model = Model {
                    mesh: mesh.clone(),
                    pose: Some(pose),
                    group,
                    mask,
                };
                (id, model)
            } else {
                let mut positions = morph.at(rest, rng.unit());
                let shift = [0, 1, 2].map(|_| rng.range(-1.5, 1.5));
                for (k, x) in positions.iter_mut().enumerate() {
                    *x += shift[k % 3];
                }
                let mut m = mesh.clone();
                m.refit(&positions).unwrap();
                let id = scene.add_deformable(&m, group, mask).unwrap();
                let model = Model {
                    mesh: m,
                    pose: None,
                    group,
                    mask,
                };
                (id, model)
            };
            if models.len() <= id as usize {
                models.resize(id as usize + 1, None);
            }
            assert!(models[id as usize].is_none(), "id {id} given twice");
            models[id as usize] = Some(model);
        };
        for _ in 0..12 {
            add(&mut scene, &mut models, &mut rng);
        }
        let mut contacts = Contacts::new();
        for frame in 0..6 {
            // Move some objects.
            for id in 0..models.len() as u32 {
                let Some(model) = models[id as usize].as_mut() else {
                    continue;
                };
                if rng.below(3) != 0 {
                    continue;
                }
                if model.pose.is_some() {
                    let pose = random_pose(&mut rng, 1.5);
                    scene.set_pose(id, Some(&pose)).unwrap();
                    model.pose = Some(pose);
                } else {
                    let shift = [0, 1, 2].map(|_| rng.range(-0.2, 0.2));
                    let positions: Vec<f64> = model
                        .mesh
                        .positions()
                        .as_flattened()
                        .iter()
                        .enumerate()
                        .map(|(k, x)| x + shift[k % 3])
                        .collect();
                    scene.set_positions(id, &positions).unwrap();
                    model.mesh.refit(&positions).unwrap();
                }
            }
            // Remove one, add one (it may take the removed id), exclude a pair.
            if frame % 2 == 1 {
                let live = live(&models);
                let gone = live[rng.below(live.len() as u64) as usize];
                scene.remove(gone).unwrap();
                models[gone as usize] = None;
                excluded.retain(|&(i, j)| i != gone && j != gone);
                add(&mut scene, &mut models, &mut rng);
            }
            exclude_ends(&mut scene, &models, &mut excluded);
            let live = live(&models);
            for mode in [
                QueryMode::Triangles,
                QueryMode::FirstHit,
                QueryMode::Leaves,
                QueryMode::Depth(2),
                QueryMode::Budget(40),
            ] {
                let expected = pairwise(&models, &excluded, &QueryOptions::with_mode(mode));
                // All threads first: the objects moved since the last frame are refit by it.
                for threads in [0, 1] {
                    let opts = QueryOptions {
                        mode,
                        threads,
                        ..QueryOptions::default()
                    };
                    let before = shared_count(Step::ScenePairs);
                    let stats = scene.collide(&opts, &mut contacts).unwrap();
                    let what = format!("seed {seed} frame {frame} {mode:?} threads {threads}");
                    assert_eq!(contacts.as_slice(), &expected[..], "{what}");
                    // Several object pairs are shared among the threads.
                    if threads == 0 && stats.object_pairs_tested > 1 {
                        assert!(shared_count(Step::ScenePairs) > before, "{what}");
                        shared_frames += 1;
                    }
                    assert_eq!(stats.contacts, expected.len() as u64);
                    assert_eq!(stats.objects, live.len() as u64);
                    assert!(!stats.truncated);
                    let colliding: HashSet<(u32, u32)> =
                        expected.iter().map(|c| (c.object_a, c.object_b)).collect();
                    assert_eq!(stats.object_pairs_colliding, colliding.len() as u64);
                    assert!(stats.object_pairs_tested >= colliding.len() as u64);
                }
            }
            // Objects that share a mesh share its topology.
            for id in &live {
                let object = scene.object(*id).unwrap();
                assert!(sources.iter().any(|s| s.0.shares_shape_with(&object.mesh)));
            }
        }
    }
    assert!(shared_frames > 0, "no query shared its object pairs out");
}

/// Deformable objects moved since the last query are refit on several threads, and their pairs
/// queried on several, with the answer of one thread.
#[test]
fn threads_share_the_refits_and_the_pairs() {
    let s = icosphere(3);
    let mesh = Mesh::new(&s.positions, &s.triangles, &BuildOptions::default()).unwrap();
    let morph = Morph::random(&s, 3, 0.1, 9);
    let place = |i: usize, t: f64| -> Vec<f64> {
        let mut p = morph.at(&s.positions, t);
        for v in p.chunks_exact_mut(3) {
            v[0] += 1.8 * i as f64;
        }
        p
    };
    let (mut one, mut many) = (Scene::new(), Scene::new());
    for scene in [&mut one, &mut many] {
        // Eager refits: each moved object is refit whole before the query.
        scene.set_lazy_refit(false);
        for i in 0..6 {
            let id = scene.add_deformable(&mesh, 1, u32::MAX).unwrap();
            scene.set_positions(id, &place(i, 0.0)).unwrap();
        }
    }
    let (mut c1, mut c2) = (Contacts::new(), Contacts::new());
    for frame in 1..4 {
        let t = frame as f64 / 4.0;
        for scene in [&mut one, &mut many] {
            for i in 0..6 {
                scene.set_positions(i as u32, &place(i, t)).unwrap();
            }
        }
        let q = |threads| QueryOptions {
            threads,
            ..QueryOptions::default()
        };
        let s1 = one.collide(&q(1), &mut c1).unwrap();
        let what = format!("frame {frame}");
        let s2 = sharing(&[Step::SceneRefit, Step::ScenePairs], &what, || {
            many.collide(&q(0), &mut c2).unwrap()
        });
        assert!(
            s1.object_pairs_colliding >= 5,
            "{what}: the neighbours touch"
        );
        assert_eq!(c1.as_slice(), c2.as_slice(), "{what}");
        assert_eq!(s1, s2, "{what}");
    }
}

/// A handful of small spheres in a row, each touching its neighbours: pairs (0,1), (1,2), ...
fn chain(n: usize) -> (Mesh, Scene) {
    let d = icosphere(2);
    let mesh = Mesh::new(&d.positions, &d.triangles, &BuildOptions::default()).unwrap();
    let mut scene = Scene::new();
    for i in 0..n {
        let pose = translated([1.8 * i as f64, 0.0, 0.0]);
        assert_eq!(
            scene.add_rigid(&mesh, Some(&pose), 1, u32::MAX).unwrap(),
            i as u32
        );
    }
    (mesh, scene)
}

/// The broad phase, the filters and the exclusions decide which pairs are queried.
#[test]
fn filters_and_broad_phase() {
    let (mesh, mut scene) = chain(6);
    let mut contacts = Contacts::new();
    let stats = scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert_eq!(
        stats.object_pairs_tested, 5,
        "only neighbours' boxes overlap"
    );
    assert_eq!(stats.object_pairs_colliding, 5);
    let touching: Vec<(u32, u32)> = dedup_pairs(&contacts);
    assert_eq!(touching, vec![(0, 1), (1, 2), (2, 3), (3, 4), (4, 5)]);
    // Object 6 in group 2 with a mask that ignores group 1, overlapping object 5.
    let pose = translated([9.9, 0.5, 0.0]);
    let id = scene.add_rigid(&mesh, Some(&pose), 2, 2).unwrap();
    scene.exclude_pair(2, 1).unwrap();
    scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert_eq!(dedup_pairs(&contacts), vec![(0, 1), (2, 3), (3, 4), (4, 5)]);
    // Its mask now takes group 1: it meets object 5.
    scene.remove(id).unwrap();
    let id2 = scene.add_rigid(&mesh, Some(&pose), 2, 3).unwrap();
    assert_eq!(id2, id, "a removed id is reused");
    scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert_eq!(
        dedup_pairs(&contacts),
        vec![(0, 1), (2, 3), (3, 4), (4, 5), (5, 6)]
    );
    // Removing object 1 forgets its exclusion; a new object taking id 1 is not excluded.
    scene.remove(1).unwrap();
    let pose1 = translated([1.8, 0.0, 0.0]);
    assert_eq!(
        scene.add_rigid(&mesh, Some(&pose1), 1, u32::MAX).unwrap(),
        1
    );
    scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert!(dedup_pairs(&contacts).contains(&(1, 2)));
}

fn dedup_pairs(contacts: &Contacts) -> Vec<(u32, u32)> {
    let mut v: Vec<(u32, u32)> = contacts.iter().map(|c| (c.object_a, c.object_b)).collect();
    v.dedup();
    v
}

/// `max_pairs` bounds the whole result: some of the contacts, sorted, and the flag.
#[test]
fn max_pairs_bounds_the_whole_result() {
    let (_, mut scene) = chain(5);
    let mut all = Contacts::new();
    scene.collide(&QueryOptions::default(), &mut all).unwrap();
    assert!(all.len() > 40);
    for max in [0, 1, 7, all.len() - 1, all.len(), all.len() + 5] {
        for threads in [1, 0] {
            let opts = QueryOptions {
                max_pairs: Some(max),
                threads,
                ..QueryOptions::default()
            };
            let mut some = Contacts::new();
            let stats = scene.collide(&opts, &mut some).unwrap();
            assert_eq!(some.len(), max.min(all.len()));
            assert_eq!(stats.truncated, max < all.len(), "max {max}");
            assert!(some.as_slice().windows(2).all(|w| w[0] < w[1]));
            assert!(some.iter().all(|c| all.as_slice().binary_search(c).is_ok()));
        }
    }
}

/// A failed call changes nothing, and says what was wrong.
#[test]
fn errors_change_nothing() {
    let (mesh, mut scene) = chain(3);
    let d = icosphere(2);
    let deformable = scene.add_deformable(&mesh, 1, u32::MAX).unwrap();
    let mut before = Contacts::new();
    scene
        .collide(&QueryOptions::default(), &mut before)
        .unwrap();
    let snapshot = format!("{scene:?}");
    let identity = Pose::default();
    assert_eq!(
        scene.set_pose(9, Some(&identity)),
        Err(Error::UnknownObject { object: 9 })
    );
    assert_eq!(
        scene.set_pose(deformable, Some(&identity)),
        Err(Error::WrongObjectKind {
            object: deformable,
            rigid: false
        })
    );
    assert_eq!(
        scene.set_positions(0, &d.positions),
        Err(Error::WrongObjectKind {
            object: 0,
            rigid: true
        })
    );
    let mut bad = d.positions.clone();
    bad[3 * 5 + 1] = f64::NAN;
    let e = scene.set_positions(deformable, &bad).unwrap_err();
    assert!(matches!(
        &e,
        Error::Object { object, error } if *object == deformable
            && matches!(**error, Error::NonFiniteCoordinate { vertex: 5, axis: 1, .. })
    ));
    assert!(
        e.to_string()
            .starts_with(&format!("object {deformable}: vertex 5"))
    );
    assert!(matches!(
        scene.set_positions(deformable, &d.positions[..30]),
        Err(Error::Object { .. })
    ));
    let far = translated([1e301, 0.0, 0.0]);
    assert!(matches!(
        scene.set_pose(0, Some(&far)),
        Err(Error::Object { object: 0, .. })
    ));
    assert!(matches!(
        scene.add_rigid(&mesh, Some(&far), 1, 1),
        Err(Error::ObjectPoseOutOfRange { .. })
    ));
    assert_eq!(scene.remove(7), Err(Error::UnknownObject { object: 7 }));
    assert_eq!(
        scene.exclude_pair(1, 1),
        Err(Error::SameObject { object: 1 })
    );
    assert_eq!(
        scene.exclude_pair(1, 8),
        Err(Error::UnknownObject { object: 8 })
    );
    let mut after = Contacts::new();
    assert_eq!(
        scene.collide(&QueryOptions::with_mode(QueryMode::Budget(0)), &mut after),
        Err(Error::ZeroBudget)
    );
    assert_eq!(format!("{scene:?}"), snapshot, "the scene changed");
    scene.collide(&QueryOptions::default(), &mut after).unwrap();
    assert_eq!(after.as_slice(), before.as_slice());
}

/// A deformable object is refit by the query that needs it, and only then.
#[test]
fn refit_waits_for_a_query_that_needs_it() {
    let (mesh, mut scene) = chain(2);
    let d = icosphere(2);
    let id = scene.add_deformable(&mesh, 1, u32::MAX).unwrap();
    let far: Vec<f64> = d
        .positions
        .iter()
        .enumerate()
        .map(|(k, x)| x + if k % 3 == 1 { 50.0 } else { 0.0 })
        .collect();
    let mut contacts = Contacts::new();
    scene.set_positions(id, &far).unwrap();
    let stats = scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert_eq!(stats.nodes_refit, 0, "nothing reaches the moved object");
    assert_eq!(stats.object_pairs_tested, 1);
    // Back among the others: refit once, by the query that reaches it.
    scene.set_positions(id, &d.positions).unwrap();
    let stats = scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert_eq!(stats.nodes_refit, mesh.node_count() as u64);
    assert!(contacts.iter().any(|c| c.object_b == id));
    let stats = scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert_eq!(stats.nodes_refit, 0, "already fresh");
}

/// A rigid object's world box holds every vertex as the query computes it, for turned poses at
/// every scale and far from the origin.
#[test]
fn rigid_world_box_holds_every_posed_vertex() {
    let mut rng = Rng::new(3);
    for scale in [1e-9, 1.0, 1e7] {
        let mut d = icosphere(2);
        d.scale(scale);
        for _ in 0..50 {
            let points: Vec<[f64; 3]> = d
                .positions
                .chunks_exact(3)
                .map(|v| [v[0], v[1], v[2]])
                .collect();
            let local = LocalBounds::of(&points);
            let mut pose = random_pose(&mut rng, 1.0);
            let far = [0, 1, 2].map(|_| rng.range(-1e6, 1e6) * scale);
            pose = Pose::new(pose.rotation(), far).unwrap();
            let world = local.posed(&pose, scale * 2.0).unwrap();
            for v in d.positions.chunks_exact(3) {
                let p = pose.transform_point(&[v[0], v[1], v[2]]);
                assert!(world.contains(&p), "scale {scale}: {p:?} outside {world:?}");
            }
        }
    }
}

/// A pair found without contact is not queried again until one of its objects changes or the
/// options do; a pair with contacts always is.
#[test]
fn pairs_apart_are_not_queried_again() {
    let d = icosphere(2);
    let mesh = Mesh::new(&d.positions, &d.triangles, &BuildOptions::default()).unwrap();
    let mut scene = Scene::new();
    let at = |x: f64| translated([x, 1.9, 0.0]);
    // Boxes overlap (corners), spheres 2.68 apart: no contact. Object 2 touches object 0.
    scene.add_rigid(&mesh, Some(&at(0.0)), 1, u32::MAX).unwrap();
    scene
        .add_rigid(&mesh, Some(&translated([1.9, 0.0, 0.0])), 1, u32::MAX)
        .unwrap();
    scene.add_rigid(&mesh, Some(&at(1.5)), 1, u32::MAX).unwrap();
    let mut contacts = Contacts::new();
    let tested = |scene: &mut Scene, contacts: &mut Contacts, opts: &QueryOptions| {
        scene.collide(opts, contacts).unwrap().object_pairs_tested
    };
    let opts = QueryOptions::default();
    let first = tested(&mut scene, &mut contacts, &opts);
    let with_contacts = dedup_pairs(&contacts).len() as u64;
    assert!(first > with_contacts, "some pair is apart");
    let all = contacts.as_slice().to_vec();
    assert_eq!(tested(&mut scene, &mut contacts, &opts), with_contacts);
    assert_eq!(contacts.as_slice(), &all[..]);
    // Other options, or a moved object, query again.
    let first_hit = QueryOptions::with_mode(QueryMode::FirstHit);
    assert_eq!(tested(&mut scene, &mut contacts, &first_hit), first);
    scene
        .set_pose(1, Some(&translated([1.9, 0.0, 0.0])))
        .unwrap();
    assert!(tested(&mut scene, &mut contacts, &opts) > with_contacts);
    assert_eq!(contacts.as_slice(), &all[..]);
}

/// Rigid objects made from one state of one mesh share a single copy of it; a refit of the mesh
/// makes a new state, and deformable objects always have their own.
#[test]
fn rigid_objects_share_their_copy() {
    let d = icosphere(2);
    let mut mesh = Mesh::new(&d.positions, &d.triangles, &BuildOptions::rigid()).unwrap();
    let mut scene = Scene::new();
    let far = |x: f64| translated([x, 0.0, 0.0]);
    let ids: Vec<u32> = (0..100)
        .map(|i| {
            scene
                .add_rigid(&mesh, Some(&far(3.0 * i as f64)), 1, u32::MAX)
                .unwrap()
        })
        .collect();
    let one = scene.memory_bytes();
    let copy = |scene: &Scene, id: u32| Arc::clone(&scene.object(id).unwrap().mesh);
    assert!(
        ids.iter()
            .all(|&i| Arc::ptr_eq(&copy(&scene, i), &copy(&scene, ids[0])))
    );
    assert!(
        one < 2 * mesh.memory_bytes() + 100 * 1024,
        "{one} bytes for 100 shared objects"
    );
    let moved: Vec<f64> = d.positions.iter().map(|x| x * 2.0).collect();
    mesh.refit(&moved).unwrap();
    let bigger = scene
        .add_rigid(&mesh, Some(&far(-10.0)), 1, u32::MAX)
        .unwrap();
    assert!(!Arc::ptr_eq(&copy(&scene, bigger), &copy(&scene, ids[0])));
    let blob = scene.add_deformable(&mesh, 1, u32::MAX).unwrap();
    assert!(!Arc::ptr_eq(&copy(&scene, blob), &copy(&scene, bigger)));
    // The blob (radius 2) moved to x = 1.5 crosses the balls at 0 and 3 (radius 1).
    let shifted: Vec<f64> = moved
        .iter()
        .enumerate()
        .map(|(k, x)| x + if k % 3 == 0 { 1.5 } else { 0.0 })
        .collect();
    scene.set_positions(blob, &shifted).unwrap();
    let mut contacts = Contacts::new();
    scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    let pairs = dedup_pairs(&contacts);
    assert!(pairs.contains(&(ids[0], blob)) && pairs.contains(&(ids[1], blob)));
    assert!(Arc::ptr_eq(&copy(&scene, ids[1]), &copy(&scene, ids[0])));
    // Removing every object made from the first state lets its copy go.
    for &i in &ids {
        scene.remove(i).unwrap();
    }
    assert_eq!(scene.snapshots.len(), 1);
}

/// The object's boxes that its freshness calls current, each equal to the box an eager refit of
/// `eager` computes; returns how many there are.
fn check_current_boxes(scene: &Scene, id: u32, eager: &Mesh) -> usize {
    let o = scene.objects[id as usize].as_ref().unwrap();
    let Body::Deformable { fresh } = &o.body else {
        panic!("object {id} is rigid");
    };
    let (Volumes::Aabb { boxes }, Volumes::Aabb { boxes: want }) =
        (o.mesh.volumes(), eager.volumes())
    else {
        panic!("box volumes expected");
    };
    let mut current = 0;
    for n in 0..boxes.len() {
        let is_current = match o.mesh.blocks() {
            Some(blocks) => fresh.node_is_current(blocks, n),
            None => fresh.is_current(),
        };
        if is_current {
            assert_eq!(boxes[n], want[n], "object {id} node {n}");
            current += 1;
        }
    }
    current
}

/// A large deformable sphere touched at one spot by a small one: the query refits the blocks it
/// reaches and no others, and finds what the eagerly refit meshes give.
#[test]
fn lazy_refit_reaches_only_the_touched_blocks() {
    let big = icosphere(4);
    let mut small = icosphere(2);
    small.scale(0.1).translate([0.0, 0.0, 1.05]);
    let options = BuildOptions::default();
    let mut a = Mesh::new(&big.positions, &big.triangles, &options).unwrap();
    let b = Mesh::new(&small.positions, &small.triangles, &options).unwrap();
    let mut scene = Scene::new();
    let ia = scene.add_deformable(&a, 1, u32::MAX).unwrap();
    scene.add_deformable(&b, 1, u32::MAX).unwrap();
    let mut contacts = Contacts::new();
    let moved: Vec<f64> = big.positions.iter().map(|x| x * 1.001).collect();
    scene.set_positions(ia, &moved).unwrap();
    a.refit(&moved).unwrap();
    let stats = scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    let mut expected = Pairs::new();
    collide(&a, None, &b, None, &QueryOptions::default(), &mut expected).unwrap();
    assert!(!expected.is_empty());
    let got: Vec<(u32, u32)> = contacts.iter().map(|c| (c.a, c.b)).collect();
    let want: Vec<(u32, u32)> = expected.iter().map(|p| (p.a, p.b)).collect();
    assert_eq!(got, want);
    assert!(
        stats.nodes_refit > 0 && stats.nodes_refit * 4 < a.node_count() as u64,
        "{} of {} nodes refit",
        stats.nodes_refit,
        a.node_count()
    );
    let current = check_current_boxes(&scene, ia, &a);
    assert_eq!(current as u64, stats.nodes_refit);
    // The same query again refits nothing more.
    let again = scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert_eq!(again.nodes_refit, 0);
    // A coarse query needs every volume: the rest of the object is refit, once.
    let coarse = scene
        .collide(&QueryOptions::with_mode(QueryMode::Leaves), &mut contacts)
        .unwrap();
    assert_eq!(coarse.nodes_refit, a.node_count() as u64);
    assert_eq!(check_current_boxes(&scene, ia, &a), a.node_count());
    // Eager refit: the object whole, the same contacts.
    scene.set_lazy_refit(false);
    scene.set_positions(ia, &moved).unwrap();
    let eager = scene
        .collide(&QueryOptions::default(), &mut contacts)
        .unwrap();
    assert_eq!(eager.nodes_refit, a.node_count() as u64);
    let got: Vec<(u32, u32)> = contacts.iter().map(|c| (c.a, c.b)).collect();
    assert_eq!(got, want);
}

mod lazy_property {
    use super::*;
    use proptest::prelude::*;

    /// One frame: which objects move (a bit each), the morph's time, a shift of the moved
    /// objects, the query mode and whether the query runs on every core.
    type Frame = (u32, f64, [f64; 3], u8, bool);

    fn frame() -> impl Strategy<Value = Frame> {
        (
            0u32..64,
            0.0..1.0f64,
            [-0.2..0.2f64, -0.2..0.2f64, -0.2..0.2f64],
            0u8..4,
            any::<bool>(),
        )
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

        /// Over random frame sequences of six deforming objects (two shared meshes, boxes
        /// refit lazily), the scene's contacts equal those of the eagerly refit meshes pair
        /// by pair, every box the scene calls current equals the eager one, and no query
        /// recomputes more nodes than the objects it moved hold.
        #[test]
        fn lazy_refit_equals_eager(frames in prop::collection::vec(frame(), 1..6)) {
            let sources = [icosphere(4), torus(0.6, 0.25, 48, 24)];
            let morphs: Vec<Morph> =
                sources.iter().enumerate().map(|(k, d)| Morph::random(d, 3, 0.15, k as u64)).collect();
            let meshes: Vec<Mesh> = sources
                .iter()
                .map(|d| Mesh::new(&d.positions, &d.triangles, &BuildOptions::default()).unwrap())
                .collect();
            let place = |k: usize, t: f64, shift: [f64; 3]| -> Vec<f64> {
                let at = [(k % 3) as f64 * 1.5, (k / 3) as f64 * 1.5, 0.0];
                morphs[k % 2]
                    .at(&sources[k % 2].positions, t)
                    .iter()
                    .enumerate()
                    .map(|(c, x)| x + at[c % 3] + shift[c % 3])
                    .collect()
            };
            let mut scene = Scene::new();
            let mut models: Vec<Option<Model>> = Vec::new();
            for k in 0..6 {
                let mut m = meshes[k % 2].clone();
                m.refit(&place(k, 0.0, [0.0; 3])).unwrap();
                let id = scene.add_deformable(&m, 1, u32::MAX).unwrap();
                prop_assert_eq!(id as usize, k);
                models.push(Some(Model { mesh: m, pose: None, group: 1, mask: u32::MAX }));
            }
            let mut contacts = Contacts::new();
            for (f, &(moving, t, shift, mode, every_core)) in frames.iter().enumerate() {
                for (k, model) in models.iter_mut().enumerate() {
                    if moving & (1 << k) == 0 {
                        continue;
                    }
                    let positions = place(k, t, shift);
                    scene.set_positions(k as u32, &positions).unwrap();
                    model.as_mut().unwrap().mesh.refit(&positions).unwrap();
                }
                let mesh = |k: usize| &models[k].as_ref().unwrap().mesh;
                let before: Vec<usize> =
                    (0..6).map(|k| check_current_boxes(&scene, k as u32, mesh(k))).collect();
                let mode = [
                    QueryMode::Triangles,
                    QueryMode::FirstHit,
                    QueryMode::Triangles,
                    QueryMode::Leaves,
                ][mode as usize];
                let opts = QueryOptions {
                    mode,
                    threads: if every_core { 0 } else { 1 },
                    ..QueryOptions::default()
                };
                let expected = pairwise(&models, &HashSet::new(), &QueryOptions::with_mode(mode));
                let stats = scene.collide(&opts, &mut contacts).unwrap();
                prop_assert_eq!(contacts.as_slice(), &expected[..], "frame {} {:?}", f, mode);
                // Every node refit is current after, and none is refit unless its object was
                // not wholly current before.
                let after: Vec<usize> =
                    (0..6).map(|k| check_current_boxes(&scene, k as u32, mesh(k))).collect();
                let newly: usize = (0..6).map(|k| after[k] - before[k]).sum();
                let stale: usize = (0..6)
                    .filter(|&k| before[k] < mesh(k).node_count())
                    .map(|k| mesh(k).node_count())
                    .sum();
                prop_assert!(
                    newly as u64 <= stats.nodes_refit && stats.nodes_refit <= stale as u64,
                    "frame {}: {} newly current, {} refit, {} in stale objects",
                    f, newly, stats.nodes_refit, stale
                );
            }
        }
    }
}
