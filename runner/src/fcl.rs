//! FCL, through the cross-check harness's driver compiled into this binary (`fcl_shim.cpp`).

use crate::method::{Counters, Method};
use crate::scene::Scene;
use std::ffi::c_void;

unsafe extern "C" {
    fn runner_fcl_new(kind: i32) -> *mut c_void;
    fn runner_fcl_free(scene: *mut c_void);
    fn runner_fcl_add(
        scene: *mut c_void,
        pos: *const f64,
        vertices: usize,
        tris: *const u32,
        triangles: usize,
    ) -> i32;
    fn runner_fcl_stage(scene: *mut c_void, object: usize, pos: *const f64);
    fn runner_fcl_update(scene: *mut c_void, object: usize) -> i32;
    fn runner_fcl_collide(
        scene: *const c_void,
        a: usize,
        b: usize,
        sink: *mut c_void,
        push: extern "C" fn(*mut c_void, *const u64, usize),
    ) -> i32;
}

/// Which bounding volume FCL's `BVHModel` uses.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    Obbrss,
    Aabb,
}

/// One FCL configuration over a scene's objects.
pub struct Fcl {
    kind: Kind,
    scene: *mut c_void,
    vertices: Vec<usize>,
}

impl Fcl {
    pub fn new(kind: Kind) -> Fcl {
        Fcl {
            kind,
            scene: std::ptr::null_mut(),
            vertices: Vec::new(),
        }
    }
}

impl Drop for Fcl {
    fn drop(&mut self) {
        // SAFETY: NULL or created by runner_fcl_new and freed once, here.
        unsafe { runner_fcl_free(self.scene) }
    }
}

extern "C" fn push(sink: *mut c_void, keys: *const u64, len: usize) {
    // SAFETY: `sink` is the `Vec<u64>` passed to runner_fcl_collide below; `keys` points to
    // `len` keys owned by the driver for the duration of this call.
    unsafe {
        let out = &mut *sink.cast::<Vec<u64>>();
        if len > 0 {
            out.extend_from_slice(std::slice::from_raw_parts(keys, len));
        }
    }
}

impl Method for Fcl {
    fn name(&self) -> String {
        match self.kind {
            Kind::Obbrss => "FCL OBBRSS".into(),
            Kind::Aabb => "FCL AABB".into(),
        }
    }

    fn build(&mut self, scene: &Scene, world: &[Vec<f64>]) {
        // SAFETY: plain constructor call.
        self.scene = unsafe { runner_fcl_new(matches!(self.kind, Kind::Aabb) as i32) };
        assert!(!self.scene.is_null(), "FCL scene allocation failed");
        self.vertices.clear();
        for (o, w) in scene.objects.iter().zip(world) {
            let (nv, nt) = (w.len() / 3, o.rest.triangle_count());
            // SAFETY: `w` holds 3 * nv doubles, the triangles 3 * nt indices below nv.
            let status = unsafe {
                runner_fcl_add(self.scene, w.as_ptr(), nv, o.rest.triangles.as_ptr(), nt)
            };
            assert_eq!(status, 0, "FCL could not build {}", o.name);
            self.vertices.push(nv);
        }
    }

    fn stage(&mut self, object: usize, world: &[f64]) {
        assert_eq!(world.len(), 3 * self.vertices[object]);
        // SAFETY: `world` holds as many vertices as the object was built with.
        unsafe { runner_fcl_stage(self.scene, object, world.as_ptr()) }
    }

    fn update(&mut self, object: usize, _world: &[f64]) -> Option<u64> {
        // SAFETY: `object` was added to this scene; its positions were staged.
        let status = unsafe { runner_fcl_update(self.scene, object) };
        assert_eq!(status, 0, "FCL refit failed");
        None
    }

    fn collide(&mut self, a: usize, b: usize, out: &mut Vec<u64>) -> Option<Counters> {
        out.clear();
        // SAFETY: both objects exist; `push` appends to `out`, which outlives the call.
        let status =
            unsafe { runner_fcl_collide(self.scene, a, b, (out as *mut Vec<u64>).cast(), push) };
        assert_eq!(status, 0, "FCL collide failed");
        None
    }
}
