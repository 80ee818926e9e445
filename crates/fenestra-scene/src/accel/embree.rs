//! Intel Embree 3 backend through the `embree` crate's raw bindings: native triangles, and
//! user geometry for spheres and disks that calls our exact intersection routines.

use super::{Hit, RayQuery};
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
    pub fn new(shapes: &[Shape]) -> Result<Self, String> {
        // SAFETY: plain FFI calls on handles we create and own; buffers are sized by Embree.
        unsafe {
            let device = rtcNewDevice(std::ptr::null());
            if device.is_null() {
                return Err("Embree could not create a device".into());
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
                return Err(format!("Embree failed to build the scene: {err:?}"));
            }
            Ok(EmbreeScene {
                device,
                scene,
                _analytic: analytic,
            })
        }
    }
}

fn device_error(device: RTCDevice) -> String {
    // SAFETY: valid device handle.
    format!("Embree error {:?}", unsafe { rtcGetDeviceError(device) })
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
}

/// Reads the single ray of a callback (we only trace with rtcIntersect1/rtcOccluded1, so N = 1
/// and the SOA layout of RTCRayN with N = 1 is that of RTCRay).
unsafe fn ray_of(r: *const RTCRay) -> Ray {
    let r = unsafe { &*r };
    Ray::new(
        Vec3::new(r.org_x, r.org_y, r.org_z),
        Vec3::new(r.dir_x, r.dir_y, r.dir_z),
    )
}

unsafe extern "C" fn bounds_fn(args: *const RTCBoundsFunctionArguments) {
    let args = unsafe { &*args };
    let a = unsafe { &*(args.geometryUserPtr as *const Analytic) };
    let (lo, hi) = a.shape.primitive_bounds(0);
    let b = unsafe { &mut *args.bounds_o };
    (b.lower_x, b.lower_y, b.lower_z) = (lo.x, lo.y, lo.z);
    (b.upper_x, b.upper_y, b.upper_z) = (hi.x, hi.y, hi.z);
}

unsafe extern "C" fn intersect_fn(args: *const RTCIntersectFunctionNArguments) {
    let args = unsafe { &*args };
    if args.N != 1 || unsafe { *args.valid } == 0 {
        return;
    }
    let a = unsafe { &*(args.geometryUserPtr as *const Analytic) };
    let rh = unsafe { &mut *(args.rayhit as *mut RTCRayHit) };
    let ray = unsafe { ray_of(&rh.ray) };
    if let Some((t, _, _)) = a.shape.intersect(0, &ray, rh.ray.tnear, rh.ray.tfar) {
        rh.ray.tfar = t;
        rh.hit.u = 0.0;
        rh.hit.v = 0.0;
        rh.hit.primID = args.primID;
        rh.hit.geomID = args.geomID;
        rh.hit.instID = [unsafe { (*args.context).instID[0] }];
    }
}

unsafe extern "C" fn occluded_fn(args: *const RTCOccludedFunctionNArguments) {
    let args = unsafe { &*args };
    if args.N != 1 || unsafe { *args.valid } == 0 {
        return;
    }
    let a = unsafe { &*(args.geometryUserPtr as *const Analytic) };
    let r = unsafe { &mut *(args.ray as *mut RTCRay) };
    let ray = unsafe { ray_of(r) };
    if a.shape.intersect(0, &ray, r.tnear, r.tfar).is_some() {
        r.tfar = f32::NEG_INFINITY;
    }
}
