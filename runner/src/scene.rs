//! The scenes: the paper's three experiments and the dense-contact stress scenes, the same as the
//! cross-check harness builds them (`cross_check/src/scenes.cpp`): the same meshes, seeds,
//! deformations and motions, so the same world coordinates frame by frame. One more, `far` (a
//! small mesh far from the origin), is the runner's alone.

use dvh::Pose;
use dvh::fixtures::{MeshData, Morph, Rng, cgal_mesh, grid, torus};
use std::f64::consts::{PI, TAU};

/// One object: its mesh at rest, its deformation, and its rigid motion over the run.
pub struct Object {
    /// Named in the FCL peer's errors (read nowhere else when it is not built).
    #[cfg_attr(not(fcl), allow(dead_code))]
    pub name: String,
    pub rest: MeshData,
    pub morph: Morph,
    pub motion: Box<dyn Fn(f64) -> Pose + Sync>,
}

/// A scene: objects, the object pairs tested every frame, and the number of frames.
pub struct Scene {
    pub name: &'static str,
    pub description: String,
    pub objects: Vec<Object>,
    pub pairs: Vec<(usize, usize)>,
    pub frames: usize,
    /// Did a mesh come from the built-in fallbacks rather than Debian's CGAL data?
    pub built_in: bool,
}

impl Scene {
    /// Every object's world coordinates at frame `f`: deformed at rest, then moved by its pose
    /// (as the harness computes them: `((R0 x + R1 y) + R2 z) + t`).
    pub fn world(&self, f: usize, out: &mut [Vec<f64>]) {
        let t = f as f64 / self.frames as f64;
        for (o, w) in self.objects.iter().zip(out.iter_mut()) {
            w.resize(o.rest.positions.len(), 0.0);
            o.morph.apply(&o.rest.positions, t, w);
            let pose = (o.motion)(t);
            for p in w.chunks_exact_mut(3) {
                let q = pose.transform_point(&[p[0], p[1], p[2]]);
                p.copy_from_slice(&q);
            }
        }
    }

    /// Triangles over all objects.
    pub fn triangles(&self) -> usize {
        self.objects.iter().map(|o| o.rest.triangle_count()).sum()
    }
}

/// Rotation by `angle` about `axis` (normalised here), then `translation`: the harness's
/// `Pose::from_axis_angle`, entry for entry.
pub fn axis_angle(axis: [f64; 3], angle: f64, translation: [f64; 3]) -> Pose {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let (x, y, z) = (axis[0] / n, axis[1] / n, axis[2] / n);
    let (c, s) = (angle.cos(), angle.sin());
    let k = 1.0 - c;
    let r = [
        [c + x * x * k, x * y * k - z * s, x * z * k + y * s],
        [y * x * k + z * s, c + y * y * k, y * z * k - x * s],
        [z * x * k - y * s, z * y * k + x * s, c + z * z * k],
    ];
    Pose::new(r, translation).expect("an axis-angle rotation is rigid")
}

/// Sizes and lengths of a run.
#[derive(Clone, Copy, Debug)]
pub struct Size {
    /// Paper sizes, or the short version's small meshes.
    pub full: bool,
    /// Frames; 0 for the default (200 full, 4 short).
    pub frames: usize,
}

/// A CGAL demo mesh subdivided to at least `triangles` and normalised to `size`, or a built-in
/// mesh of similar size when Debian's data is not installed.
pub fn mesh(name: &str, triangles: usize, size: f64, built_in: &mut bool) -> MeshData {
    let mut m = match cgal_mesh(name) {
        Ok(m) => m,
        Err(_) => {
            *built_in = true;
            // A knobbly torus: a closed, curved surface with concave parts, like the scans.
            let mut t = torus(0.5, 0.2, 48, 24);
            let morph = Morph::random(&t, 6, 0.08, name.len() as u64);
            t.positions = morph.at(&t.positions, 0.25);
            t
        }
    }
    .subdivided_to(triangles);
    m.normalize(size);
    m
}

fn all_pairs(count: usize) -> Vec<(usize, usize)> {
    (0..count)
        .flat_map(|i| (i + 1..count).map(move |j| (i, j)))
        .collect()
}

/// Scene 1 of the paper: many small objects moving and deforming, every pair tested.
fn many(size: Size) -> Scene {
    let mut built_in = false;
    let count = if size.full { 40 } else { 6 };
    let base = if size.full {
        mesh("lion", 14_000, 1.0, &mut built_in)
    } else {
        mesh("elephant", 5_000, 1.0, &mut built_in)
    };
    let mut rng = Rng::new(1);
    let (nx, ny) = if size.full { (5, 4) } else { (3, 2) };
    let objects = (0..count)
        .map(|i| {
            let morph = Morph::random(&base, 3, 0.06, 100 + i as u64);
            let centre = [
                0.8 * (i % nx) as f64,
                0.8 * ((i / nx) % ny) as f64,
                0.8 * (i / (nx * ny)) as f64,
            ];
            let axis = [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ];
            let spin = rng.range(0.5, 1.5);
            let phase = rng.unit();
            let drift = rng.range(0.0, TAU);
            let dir = [drift.cos(), drift.sin(), rng.range(-0.5, 0.5)];
            Object {
                name: format!("object{i}"),
                rest: base.clone(),
                morph,
                motion: Box::new(move |t| {
                    let a = 0.16 * (TAU * (t + phase)).sin();
                    let tr = [0, 1, 2].map(|k| centre[k] + a * dir[k]);
                    axis_angle(axis, spin * TAU * t, tr)
                }),
            }
        })
        .collect();
    Scene {
        name: "many",
        description: format!(
            "{count} objects of {} triangles moving and deforming, every pair tested",
            base.triangle_count()
        ),
        objects,
        pairs: all_pairs(count),
        frames: 0,
        built_in,
    }
}

/// Scene 2: three medium meshes deforming into each other, more in their upper parts.
fn medium(size: Size) -> Scene {
    let mut built_in = false;
    let specs = [
        ("elephant", 84_000, 5_000, -0.32),
        ("elephant", 84_000, 5_000, 0.32),
        ("mannequin-devil", 100_000, 6_000, 0.0),
    ];
    let objects: Vec<Object> = specs
        .iter()
        .enumerate()
        .map(|(i, &(name, full, quick, x))| {
            let rest = mesh(
                name,
                if size.full { full } else { quick },
                1.0,
                &mut built_in,
            );
            let mut morph = Morph::random(&rest, 4, 0.08, 200 + i as u64);
            morph.upper_bias = 1.0;
            let z = if i == 2 { 0.25 } else { 0.0 };
            let phase = 0.3 * i as f64;
            Object {
                name: format!("{name}{i}"),
                rest,
                morph,
                motion: Box::new(move |t| {
                    let tr = [x + 0.06 * (TAU * (t + phase)).sin(), 0.0, z];
                    axis_angle([0.0, 1.0, 0.0], 0.3 * (TAU * t + phase).sin(), tr)
                }),
            }
        })
        .collect();
    Scene {
        name: "medium",
        description: format!(
            "3 meshes ({}, {}, {} triangles) deforming into each other, more at the top",
            objects[0].rest.triangle_count(),
            objects[1].rest.triangle_count(),
            objects[2].rest.triangle_count()
        ),
        objects,
        pairs: all_pairs(3),
        frames: 0,
        built_in,
    }
}

/// Scene 3: two large meshes meeting at their extremities: the right one is the left one turned
/// half a turn about the vertical, placed so that their farthest-reaching vertices (along x)
/// meet, then pushed into each other by a varying depth.
fn large(size: Size) -> Scene {
    let mut built_in = false;
    let base = if size.full {
        mesh("refined_elephant", 350_000, 1.0, &mut built_in)
    } else {
        mesh("armadillo", 50_000, 1.0, &mut built_in)
    };
    let tip = (0..base.vertex_count()).fold(0, |best, v| {
        if base.positions[3 * v] > base.positions[3 * best] {
            v
        } else {
            best
        }
    });
    let (px, pz) = (base.positions[3 * tip], base.positions[3 * tip + 2]);
    let objects = (0..2)
        .map(|i| Object {
            name: if i == 0 { "left" } else { "right" }.to_string(),
            rest: base.clone(),
            morph: Morph::random(&base, 4, 0.05, 300 + i as u64),
            motion: Box::new(move |t| {
                let depth = 0.03 + 0.03 * (TAU * t).sin();
                let tr = if i == 0 {
                    [-px + 0.5 * depth, 0.0, 0.0]
                } else {
                    [px - 0.5 * depth, 0.0, 2.0 * pz]
                };
                axis_angle([0.0, 1.0, 0.0], if i == 0 { 0.0 } else { PI }, tr)
            }),
        })
        .collect();
    Scene {
        name: "large",
        description: format!(
            "2 meshes of {} triangles meeting at their extremities",
            base.triangle_count()
        ),
        objects,
        pairs: all_pairs(2),
        frames: 0,
        built_in,
    }
}

/// Dense contact: two sheets in one plane, one turning and sliding over the other.
fn coplanar(size: Size) -> Scene {
    let n = if size.full { 160 } else { 20 };
    let objects: Vec<Object> = (0..2)
        .map(|i| {
            let rest = grid(n, 1.0);
            let mut morph = Morph::random(&rest, 3, 0.03, 400 + i as u64);
            morph.planar = true;
            Object {
                name: if i == 0 { "sheet" } else { "turning sheet" }.to_string(),
                rest,
                morph,
                motion: Box::new(move |t| {
                    let tr = if i == 0 {
                        [0.0; 3]
                    } else {
                        [0.3 + 0.2 * (TAU * t).sin(), 0.25, 0.0]
                    };
                    axis_angle(
                        [0.0, 0.0, 1.0],
                        if i == 0 { 0.0 } else { 0.5 * TAU * t },
                        tr,
                    )
                }),
            }
        })
        .collect();
    Scene {
        name: "coplanar",
        description: format!(
            "2 coplanar sheets of {} triangles",
            objects[0].rest.triangle_count()
        ),
        objects,
        pairs: all_pairs(2),
        frames: 0,
        built_in: false,
    }
}

/// Dense contact: a mesh against an exact copy of itself (same deformation, same pose).
fn copy(size: Size) -> Scene {
    let mut built_in = false;
    let base = if size.full {
        mesh("bunny00", 70_000, 1.0, &mut built_in)
    } else {
        mesh("elephant", 5_000, 1.0, &mut built_in)
    };
    let morph = Morph::random(&base, 3, 0.05, 500);
    let objects = (0..2)
        .map(|i| Object {
            name: if i == 0 { "mesh" } else { "copy" }.to_string(),
            rest: base.clone(),
            morph: morph.clone(),
            motion: Box::new(|t| axis_angle([1.0, 1.0, 0.0], t, [0.1, 0.2, 0.3])),
        })
        .collect();
    Scene {
        name: "copy",
        description: format!(
            "a mesh of {} triangles against an exact copy",
            base.triangle_count()
        ),
        objects,
        pairs: all_pairs(2),
        frames: 0,
        built_in,
    }
}

/// A height field over `[0, size]²`, `n × n` cells: `z = amplitude · sin(2π fx x + px) ·
/// cos(2π fy y + py)` with seeded frequencies and phases (the harness's `terrain`).
fn terrain(n: usize, size: f64, amplitude: f64, seed: u64) -> MeshData {
    let mut m = grid(n, size);
    let mut rng = Rng::new(seed);
    let (fx, fy) = (rng.range(1.0, 3.0), rng.range(1.0, 3.0));
    // 6.28, not TAU: the harness's literal, which the scene must reproduce.
    #[allow(clippy::approx_constant)]
    let (px, py) = (rng.range(0.0, 6.28), rng.range(0.0, 6.28));
    for p in m.positions.chunks_exact_mut(3) {
        let (x, y) = (p[0] / size, p[1] / size);
        p[2] = amplitude * (TAU * fx * x + px).sin() * (TAU * fy * y + py).cos();
    }
    m
}

/// Exactness stress: a bumpy sheet and its copy shifted sideways by 1e-12. The surfaces cross
/// along curves everywhere and nearly coincide elsewhere: nearly coplanar pairs by the thousand.
fn near(size: Size) -> Scene {
    let offset = 1e-12;
    let base = terrain(if size.full { 160 } else { 24 }, 1.0, 0.1, 7);
    let morph = Morph::random(&base, 3, 0.03, 600);
    let objects = (0..2)
        .map(|i| {
            let shift = if i == 0 { 0.0 } else { offset };
            Object {
                name: if i == 0 { "terrain" } else { "shifted" }.to_string(),
                rest: base.clone(),
                morph: morph.clone(),
                motion: Box::new(move |t| {
                    axis_angle([0.0, 0.0, 1.0], 0.2 * t, [shift, 0.5 * shift, 0.0])
                }),
            }
        })
        .collect();
    Scene {
        name: "near-1e-12",
        description: format!(
            "a terrain of {} triangles and its copy shifted sideways by 1e-12",
            base.triangle_count()
        ),
        objects,
        pairs: all_pairs(2),
        frames: 0,
        built_in: false,
    }
}

/// A small mesh far from the origin: two meshes 1e-3 across deforming into each other a
/// million units out on every axis, where coordinates keep about 7 significant digits of the
/// mesh's size. Not a cross-check scene: it measures what such placements cost.
fn far(size: Size) -> Scene {
    let mut built_in = false;
    let offset = 1e6;
    let triangles = if size.full { 20_000 } else { 3_000 };
    let objects: Vec<Object> = (0..2)
        .map(|i| {
            let rest = mesh("elephant", triangles, 1e-3, &mut built_in);
            let morph = Morph::random(&rest, 4, 0.08, 700 + i as u64);
            let x = if i == 0 { -0.3e-3 } else { 0.3e-3 };
            let phase = 0.5 * i as f64;
            Object {
                name: format!("far{i}"),
                rest,
                morph,
                motion: Box::new(move |t| {
                    let tr = [
                        offset + x + 0.06e-3 * (TAU * (t + phase)).sin(),
                        offset,
                        offset,
                    ];
                    axis_angle([0.0, 1.0, 0.0], 0.3 * (TAU * t + phase).sin(), tr)
                }),
            }
        })
        .collect();
    Scene {
        name: "far",
        description: format!(
            "2 meshes of {} triangles, 1e-3 across, deforming into each other 1e6 from the origin",
            objects[0].rest.triangle_count()
        ),
        objects,
        pairs: all_pairs(2),
        frames: 0,
        built_in,
    }
}

/// The paper's three scenes.
pub const PAPER: [&str; 3] = ["many", "medium", "large"];
/// The paper's three and the dense-contact ones.
pub const ALL: [&str; 5] = ["many", "medium", "large", "coplanar", "copy"];
/// Every scene, the exactness stress included.
pub const EVERY: [&str; 6] = ["many", "medium", "large", "coplanar", "copy", "near-1e-12"];
/// Scenes of the runner alone, run when named (`--scene far`).
pub const EXTRA: [&str; 1] = ["far"];

/// The scene called `name`, sized by `size`; `None` for an unknown name.
pub fn make(name: &str, size: Size) -> Option<Scene> {
    let mut scene = match name {
        "many" => many(size),
        "medium" => medium(size),
        "large" => large(size),
        "coplanar" => coplanar(size),
        "copy" => copy(size),
        "near-1e-12" => near(size),
        "far" => far(size),
        _ => return None,
    };
    scene.frames = if size.frames > 0 {
        size.frames
    } else if size.full {
        200
    } else {
        4
    };
    Some(scene)
}

/// FNV-1a over the bits of every coordinate of every object, in order: equal world coordinates
/// give equal checksums (the cross-check harness computes the same with `--checksums`).
pub fn checksum(world: &[Vec<f64>]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for w in world {
        for x in w {
            for byte in x.to_bits().to_le_bytes() {
                h = (h ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
            }
        }
    }
    h
}
