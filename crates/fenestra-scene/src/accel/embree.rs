//! Intel Embree 3 backend through the `embree` crate's raw bindings: native triangles, and
//! user geometry for spheres and disks that calls our exact intersection routines.

use super::{Hit, RayQuery, PACKET};
use crate::shape::{Shape, ShapeKind};
use embree::sys::*;
use fenestra_core::{Ray, Vec3};
use std::os::raw::c_void;

const INVALID_ID: u32 = u32::MAX;

/// A sphere or disk handed to Embree as user geometry.
struct Analytic {
    shape: Shape,
}

pub struct EmbreeScene {
    device: RTCDevice,
    scene: RTCScene,
    /// Owned by us, pointed to by Embree's user geometries: boxed so that the pointers stay
    /// valid while the vector grows.
    #[allow(clippy::vec_box)]
    _analytic: Vec<Box<Analytic>>,
}

// Embree scenes are safe to query from many threads once committed.
unsafe impl Send for EmbreeScene {}
unsafe impl Sync for EmbreeScene {}

impl EmbreeScene {
    pub fn new(shapes: &[Shape]) -> Result<Self, EmbreeError> {
        // SAFETY: plain FFI calls on handles we create and own; buffers are sized by Embree.
        unsafe {
            let device = rtcNewDevice(std::ptr::null());
            if device.is_null() {
                return Err(EmbreeError::Device);
            }
            let scene = rtcNewScene(device);
            rtcSetSceneBuildQuality(scene, RTCBuildQuality::HIGH);
            rtcSetSceneFlags(scene, RTCSceneFlags::ROBUST);
            let mut analytic = Vec::new();
            for (id, shape) in shapes.iter().enumerate() {
                if shape.primitive_count() == 0 {
                    // Nothing to hit (a PLY with no faces); Embree refuses empty buffers.
                    continue;
                }
                let geom = match &shape.kind {
                    ShapeKind::Mesh(mesh) => {
                        let g = rtcNewGeometry(device, RTCGeometryType::TRIANGLE);
                        let vb = rtcSetNewGeometryBuffer(
                            g,
                            RTCBufferType::VERTEX,
                            0,
                            RTCFormat::FLOAT3,
                            12,
                            mesh.positions.len(),
                        ) as *mut f32;
                        let ib = rtcSetNewGeometryBuffer(
                            g,
                            RTCBufferType::INDEX,
                            0,
                            RTCFormat::UINT3,
                            12,
                            mesh.indices.len(),
                        ) as *mut u32;
                        if vb.is_null() || ib.is_null() {
                            rtcReleaseGeometry(g);
                            return Err(device_error(device));
                        }
                        let verts = std::slice::from_raw_parts_mut(vb, mesh.positions.len() * 3);
                        for (dst, p) in verts.chunks_exact_mut(3).zip(&mesh.positions) {
                            dst.copy_from_slice(&p.to_array());
                        }
                        let idx = std::slice::from_raw_parts_mut(ib, mesh.indices.len() * 3);
                        for (dst, t) in idx.chunks_exact_mut(3).zip(&mesh.indices) {
                            dst.copy_from_slice(t);
                        }
                        g
                    }
                    ShapeKind::Sphere { .. } | ShapeKind::Disk { .. } => {
                        let g = rtcNewGeometry(device, RTCGeometryType::USER);
                        let boxed = Box::new(Analytic {
                            shape: shape.clone(),
                        });
                        let ptr = &*boxed as *const Analytic as *mut c_void;
                        analytic.push(boxed);
                        rtcSetGeometryUserPrimitiveCount(g, 1);
                        rtcSetGeometryUserData(g, ptr);
                        rtcSetGeometryBoundsFunction(g, Some(bounds_fn), ptr);
                        rtcSetGeometryIntersectFunction(g, Some(intersect_fn));
                        rtcSetGeometryOccludedFunction(g, Some(occluded_fn));
                        g
                    }
                };
                rtcCommitGeometry(geom);
                rtcAttachGeometryByID(scene, geom, id as u32);
                rtcReleaseGeometry(geom);
            }
            rtcCommitScene(scene);
            let err = rtcGetDeviceError(device);
            if err != RTCError::NONE {
                rtcReleaseScene(scene);
                rtcReleaseDevice(device);
                return Err(EmbreeError::Build(format!("{err:?}")));
            }
            Ok(EmbreeScene {
                device,
                scene,
                _analytic: analytic,
            })
        }
    }
}

fn device_error(device: RTCDevice) -> EmbreeError {
    // SAFETY: valid device handle.
    EmbreeError::Geometry(format!("{:?}", unsafe { rtcGetDeviceError(device) }))
}

/// What Embree refused.
#[derive(Debug, thiserror::Error)]
pub enum EmbreeError {
    /// No device could be made.
    #[error("Embree could not create a device")]
    Device,
    /// A geometry was refused, with Embree's error code.
    #[error("Embree error {0}")]
    Geometry(String),
    /// The scene did not build, with Embree's error code.
    #[error("Embree failed to build the scene: {0}")]
    Build(String),
}

impl Drop for EmbreeScene {
    fn drop(&mut self) {
        // SAFETY: we own one reference to each.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}

fn context() -> RTCIntersectContext {
    // rtcInitIntersectContext is an inline C function; this is what it does.
    RTCIntersectContext {
        flags: RTCIntersectContextFlags::INCOHERENT,
        filter: None,
        instID: [INVALID_ID],
    }
}

fn rtc_ray(ray: &Ray, tmax: f32) -> RTCRay {
    RTCRay {
        org_x: ray.o.x,
        org_y: ray.o.y,
        org_z: ray.o.z,
        tnear: 0.0,
        dir_x: ray.d.x,
        dir_y: ray.d.y,
        dir_z: ray.d.z,
        time: 0.0,
        tfar: tmax,
        mask: u32::MAX,
        id: 0,
        flags: 0,
    }
}

impl RayQuery for EmbreeScene {
    fn intersect(&self, ray: &Ray, tmax: f32) -> Option<Hit> {
        let mut rh = RTCRayHit {
            ray: rtc_ray(ray, tmax),
            hit: RTCHit {
                Ng_x: 0.0,
                Ng_y: 0.0,
                Ng_z: 0.0,
                u: 0.0,
                v: 0.0,
                primID: INVALID_ID,
                geomID: INVALID_ID,
                instID: [INVALID_ID],
            },
        };
        let mut ctx = context();
        // SAFETY: committed scene, valid ray and context.
        unsafe { rtcIntersect1(self.scene, &mut ctx, &mut rh) };
        (rh.hit.geomID != INVALID_ID).then_some(Hit {
            t: rh.ray.tfar,
            shape: rh.hit.geomID,
            prim: rh.hit.primID,
            u: rh.hit.u,
            v: rh.hit.v,
        })
    }

    fn occluded(&self, ray: &Ray, tmax: f32) -> bool {
        let mut r = rtc_ray(ray, tmax);
        let mut ctx = context();
        // SAFETY: as above.
        unsafe { rtcOccluded1(self.scene, &mut ctx, &mut r) };
        r.tfar == f32::NEG_INFINITY
    }

    fn intersect8(&self, rays: &[Ray; PACKET], tmax: [f32; PACKET]) -> [Option<Hit>; PACKET] {
        let mut rh = RTCRayHit8 {
            ray: rtc_ray8(rays, tmax),
            hit: RTCHit8 {
                Ng_x: [0.0; PACKET],
                Ng_y: [0.0; PACKET],
                Ng_z: [0.0; PACKET],
                u: [0.0; PACKET],
                v: [0.0; PACKET],
                primID: [INVALID_ID; PACKET],
                geomID: [INVALID_ID; PACKET],
                instID: [[INVALID_ID; PACKET]],
            },
        };
        let mut ctx = context();
        // SAFETY: committed scene, a 32-byte aligned packet (the bindings' type), all lanes
        // valid.
        unsafe { rtcIntersect8(VALID.0.as_ptr(), self.scene, &mut ctx, &mut rh) };
        std::array::from_fn(|i| {
            (rh.hit.geomID[i] != INVALID_ID).then_some(Hit {
                t: rh.ray.tfar[i],
                shape: rh.hit.geomID[i],
                prim: rh.hit.primID[i],
                u: rh.hit.u[i],
                v: rh.hit.v[i],
            })
        })
    }

    fn occluded8(&self, rays: &[Ray; PACKET], tmax: [f32; PACKET]) -> [bool; PACKET] {
        let mut r = rtc_ray8(rays, tmax);
        let mut ctx = context();
        // SAFETY: as above.
        unsafe { rtcOccluded8(VALID.0.as_ptr(), self.scene, &mut ctx, &mut r) };
        r.tfar.map(|t| t == f32::NEG_INFINITY)
    }
}

/// Every lane of a packet active; Embree reads the mask with aligned vector loads.
#[repr(C, align(32))]
struct Valid([i32; PACKET]);
static VALID: Valid = Valid([-1; PACKET]);

fn rtc_ray8(rays: &[Ray; PACKET], tmax: [f32; PACKET]) -> RTCRay8 {
    RTCRay8 {
        org_x: rays.each_ref().map(|r| r.o.x),
        org_y: rays.each_ref().map(|r| r.o.y),
        org_z: rays.each_ref().map(|r| r.o.z),
        tnear: [0.0; PACKET],
        dir_x: rays.each_ref().map(|r| r.d.x),
        dir_y: rays.each_ref().map(|r| r.d.y),
        dir_z: rays.each_ref().map(|r| r.d.z),
        time: [0.0; PACKET],
        tfar: tmax,
        mask: [u32::MAX; PACKET],
        id: [0; PACKET],
        flags: [0; PACKET],
    }
}

/// A callback's ray or ray-hit packet of N lanes: Embree's SOA layout (RTCRayN, RTCRayHitN),
/// every field an array of N 32-bit values in the order of RTCRay's and then RTCHit's fields.
/// N = 1 is the layout of RTCRay and RTCRayHit.
struct Lanes {
    base: *mut u32,
    n: usize,
}

/// Field positions within a ray(-hit) packet.
const ORG_X: usize = 0;
const TNEAR: usize = 3;
const DIR_X: usize = 4;
const TFAR: usize = 8;
const HIT_U: usize = 15;
const HIT_V: usize = 16;
const PRIM_ID: usize = 17;
const GEOM_ID: usize = 18;
const INST_ID: usize = 19;

impl Lanes {
    /// SAFETY: `i < n`, and `field` within the packet Embree handed over.
    unsafe fn at(&self, field: usize, i: usize) -> *mut u32 {
        unsafe { self.base.add(field * self.n + i) }
    }
    unsafe fn f32(&self, field: usize, i: usize) -> f32 {
        f32::from_bits(unsafe { *self.at(field, i) })
    }
    unsafe fn set_f32(&self, field: usize, i: usize, v: f32) {
        unsafe { *self.at(field, i) = v.to_bits() }
    }
    /// Lane `i`'s ray and its (tnear, tfar).
    unsafe fn ray(&self, i: usize) -> (Ray, f32, f32) {
        let v = |f: usize| unsafe { self.f32(f, i) };
        let ray = Ray::new(
            Vec3::new(v(ORG_X), v(ORG_X + 1), v(ORG_X + 2)),
            Vec3::new(v(DIR_X), v(DIR_X + 1), v(DIR_X + 2)),
        );
        (ray, v(TNEAR), v(TFAR))
    }
}

unsafe extern "C" fn bounds_fn(args: *const RTCBoundsFunctionArguments) {
    let args = unsafe { &*args };
    let a = unsafe { &*(args.geometryUserPtr as *const Analytic) };
    let (lo, hi) = a.shape.primitive_bounds(0);
    let b = unsafe { &mut *args.bounds_o };
    (b.lower_x, b.lower_y, b.lower_z) = (lo.x, lo.y, lo.z);
    (b.upper_x, b.upper_y, b.upper_z) = (hi.x, hi.y, hi.z);
}

/// Calls `on_hit(lanes, i, t)` for each valid lane `i` of a callback's packet whose ray hits
/// the analytic shape at distance `t` within its (tnear, tfar).
///
/// SAFETY: the arguments of one Embree callback: `user` an [`Analytic`], `valid` and `packet`
/// of `n` lanes.
unsafe fn analytic_hits(
    user: *mut c_void,
    valid: *const i32,
    n: u32,
    packet: *mut c_void,
    on_hit: impl Fn(&Lanes, usize, f32),
) {
    let a = unsafe { &*(user as *const Analytic) };
    let lanes = Lanes {
        base: packet as *mut u32,
        n: n as usize,
    };
    for i in 0..lanes.n {
        if unsafe { *valid.add(i) } == 0 {
            continue;
        }
        let (ray, tnear, tfar) = unsafe { lanes.ray(i) };
        if let Some((t, _, _)) = a.shape.intersect(0, &ray, tnear, tfar) {
            on_hit(&lanes, i, t);
        }
    }
}

unsafe extern "C" fn intersect_fn(args: *const RTCIntersectFunctionNArguments) {
    let args = unsafe { &*args };
    let (prim, geom) = (args.primID, args.geomID);
    let inst = unsafe { (*args.context).instID[0] };
    let user = args.geometryUserPtr;
    unsafe {
        analytic_hits(
            user,
            args.valid,
            args.N,
            args.rayhit as *mut c_void,
            |lanes, i, t| {
                // SAFETY: lane i of the packet Embree handed over.
                lanes.set_f32(TFAR, i, t);
                lanes.set_f32(HIT_U, i, 0.0);
                lanes.set_f32(HIT_V, i, 0.0);
                *lanes.at(PRIM_ID, i) = prim;
                *lanes.at(GEOM_ID, i) = geom;
                *lanes.at(INST_ID, i) = inst;
            },
        )
    }
}

unsafe extern "C" fn occluded_fn(args: *const RTCOccludedFunctionNArguments) {
    let args = unsafe { &*args };
    let user = args.geometryUserPtr;
    unsafe {
        analytic_hits(
            user,
            args.valid,
            args.N,
            args.ray as *mut c_void,
            |lanes, i, _| lanes.set_f32(TFAR, i, f32::NEG_INFINITY),
        )
    }
}
