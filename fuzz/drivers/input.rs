//! Values from the fuzzer's bytes: numbers, meshes through the C create entry points, poses,
//! collision filters.

use dvh::ffi::*;

/// Reads the input as a little stream of values; past its end, zeros.
pub struct Bytes<'a>(&'a [u8]);

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Self {
        Bytes(data)
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    pub fn u8(&mut self) -> u8 {
        let (&b, rest) = self.0.split_first().unwrap_or((&0, &[]));
        self.0 = rest;
        b
    }

    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }

    /// A double, mostly from a few interesting families, sometimes any bit pattern.
    pub fn f64(&mut self) -> f64 {
        match self.u8() % 8 {
            0 => f64::from_bits(u64::from(self.u32()) | u64::from(self.u32()) << 32),
            1 => f64::from(self.u8() as i8) * 2f64.powi(i32::from(self.u8() as i8) * 8),
            2 => f64::from(self.u8() % 5) - 2.0,
            _ => f64::from(self.u8() as i8) / 16.0,
        }
    }
}

/// A mesh made through one of the C create entry points, with the positions and triangles the
/// library read (floats and 16-bit indices widened as it widens them).
pub struct Made {
    pub mesh: *mut DvhMesh,
    pub positions: Vec<f64>,
    pub triangles: Vec<u32>,
}

/// Three floats per vertex at `stride` bytes, in a buffer that ends right after the last
/// vertex's coordinates (so that a read past them is caught by the sanitizer), filled with a
/// pattern in between.
pub fn strided(xyz: &[f64], stride: usize) -> Vec<u8> {
    let n = xyz.len() / 3;
    let mut buf = vec![0xa5u8; n.saturating_sub(1) * stride + 12 * usize::from(n > 0)];
    for (i, p) in xyz.chunks(3).enumerate() {
        for (k, &x) in p.iter().enumerate() {
            buf[i * stride + 4 * k..][..4].copy_from_slice(&(x as f32).to_le_bytes());
        }
    }
    buf
}

/// A mesh from the bytes: 1-24 vertices, 0-24 triangles, indices sometimes out of range, any
/// doubles, every option value in and out of range, through `dvh_mesh_create`, `_u16` or `_f32`
/// (strides of 12, 16 or 20 bytes). `None` when the create failed; a failed create must not
/// write its out-parameter nor report an internal panic.
pub fn make_mesh(bytes: &mut Bytes) -> Option<Made> {
    let vertex_count = 1 + usize::from(bytes.u8() % 24);
    let triangle_count = usize::from(bytes.u8() % 24);
    let mut positions: Vec<f64> = (0..3 * vertex_count).map(|_| bytes.f64()).collect();
    let mut triangles: Vec<u32> = (0..3 * triangle_count)
        .map(|_| {
            let i = bytes.u8();
            if i == 255 {
                bytes.u32()
            } else {
                u32::from(i) % vertex_count as u32
            }
        })
        .collect();
    let mut options = dvh_build_options_default();
    options.tree = u32::from(bytes.u8() % 3);
    options.volume = u32::from(bytes.u8() % 4);
    options.radius = u32::from(bytes.u8() % 3);
    options.leftovers = u32::from(bytes.u8() % 3);
    // One byte says the thread count, the entry point and the stride.
    let way = bytes.u8();
    options.refit_threads = u32::from(way % 3);
    let stride = 12 + 4 * usize::from(way / 9 % 3);
    let mut mesh = std::ptr::null_mut();
    // SAFETY: the arrays hold the counts given (the strided buffer exactly).
    let status = unsafe {
        match way / 3 % 3 {
            0 => dvh_mesh_create(
                positions.as_ptr(),
                vertex_count,
                triangles.as_ptr(),
                triangle_count,
                &options,
                &mut mesh,
            ),
            1 => {
                let short: Vec<u16> = triangles.iter().map(|&i| i as u16).collect();
                triangles = short.iter().map(|&i| u32::from(i)).collect();
                dvh_mesh_create_u16(
                    positions.as_ptr(),
                    vertex_count,
                    short.as_ptr(),
                    triangle_count,
                    &options,
                    &mut mesh,
                )
            }
            _ => {
                let buf = strided(&positions, stride);
                positions = positions.iter().map(|&x| f64::from(x as f32)).collect();
                dvh_mesh_create_f32(
                    buf.as_ptr().cast(),
                    stride,
                    vertex_count,
                    triangles.as_ptr(),
                    triangle_count,
                    &options,
                    &mut mesh,
                )
            }
        }
    };
    assert_ne!(status, DVH_STATUS_INTERNAL_PANIC);
    if status != DVH_STATUS_OK {
        assert!(mesh.is_null(), "a failed create wrote its out-parameter");
        return None;
    }
    Some(Made {
        mesh,
        positions,
        triangles,
    })
}

/// A pose from the bytes: mostly rotations (identity, about an axis by any of 256 angles, so
/// orthonormal only within rounding, or from a normalised quaternion), sometimes any nine
/// doubles; a translation of any three doubles.
pub fn pose(bytes: &mut Bytes) -> DvhPose {
    let kind = bytes.u8();
    let rotation: [f64; 9] = match kind % 4 {
        0 => [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        1 => {
            let t = f64::from(bytes.u8()) * std::f64::consts::TAU / 256.0;
            let (s, c) = t.sin_cos();
            match kind / 4 % 3 {
                0 => [1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c],
                1 => [c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c],
                _ => [c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0],
            }
        }
        2 => {
            let q: [f64; 4] = std::array::from_fn(|_| f64::from(bytes.u8() as i8));
            let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            let [w, x, y, z] = if n > 0.0 {
                q.map(|v| v / n)
            } else {
                [1.0, 0.0, 0.0, 0.0]
            };
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ]
        }
        _ => std::array::from_fn(|_| bytes.f64()),
    };
    DvhPose {
        rotation,
        translation: [bytes.f64(), bytes.f64(), bytes.f64()],
    }
}

/// The library's reading of a C pose (`None` when it refuses it).
pub fn rust_pose(p: &DvhPose) -> Option<dvh::Pose> {
    let r = &p.rotation;
    dvh::Pose::new(
        [[r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]]],
        p.translation,
    )
    .ok()
}

/// A collision filter from the bytes: everything, one of two bits, or any word.
pub fn filter(bytes: &mut Bytes) -> u32 {
    match bytes.u8() % 4 {
        0 => u32::MAX,
        1 => 1,
        2 => 2,
        _ => bytes.u32(),
    }
}

/// A small sheet (`kind` even) or torus, chosen by `kind`: its coordinates rounded to
/// sixteenths, so that coplanar, collinear, parallel and touching primitives are common, and
/// its triangles.
pub fn small_shape(kind: u8) -> (Vec<f64>, Vec<u32>) {
    use dvh::fixtures::{grid, torus};
    let shape = if kind.is_multiple_of(2) {
        grid(1 + usize::from(kind / 2 % 4), 1.0)
    } else {
        torus(0.5, 0.25, 3 + usize::from(kind / 2 % 3), 3)
    };
    let p = shape
        .positions
        .iter()
        .map(|&x| (x * 16.0).round() / 16.0)
        .collect();
    (p, shape.triangles)
}

/// Moves up to seven vertices of `p` (x, y, z each) by sixteenths, as the bytes say.
pub fn nudge(bytes: &mut Bytes, p: &mut [f64]) {
    let n = p.len() / 3;
    for _ in 0..bytes.u8() % 8 {
        let v = usize::from(bytes.u8()) % n;
        for k in 0..3 {
            p[3 * v + k] += f64::from(bytes.u8() as i8 % 16) / 16.0;
        }
    }
}

/// A mesh of `p` and `triangles` through `dvh_mesh_create`, which must accept it.
pub fn c_mesh(p: &[f64], triangles: &[u32], options: &DvhBuildOptions) -> *mut DvhMesh {
    let mut mesh = std::ptr::null_mut();
    // SAFETY: the arrays hold the counts given.
    let status = unsafe {
        dvh_mesh_create(
            p.as_ptr(),
            p.len() / 3,
            triangles.as_ptr(),
            triangles.len() / 3,
            options,
            &mut mesh,
        )
    };
    assert_eq!(status, DVH_STATUS_OK);
    mesh
}

/// The primitives of `triangles`: the triangles, their edges (each once, lower vertex first,
/// sorted) and the vertices they use (sorted).
pub fn primitives(triangles: &[u32]) -> (Vec<[u32; 3]>, Vec<[u32; 2]>, Vec<u32>) {
    let tris: Vec<[u32; 3]> = triangles.chunks(3).map(|t| [t[0], t[1], t[2]]).collect();
    let mut edges: Vec<[u32; 2]> = tris
        .iter()
        .flat_map(|t| (0..3).map(move |k| [t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3])]))
        .filter(|e| e[0] != e[1])
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let mut used = triangles.to_vec();
    used.sort_unstable();
    used.dedup();
    (tris, edges, used)
}
