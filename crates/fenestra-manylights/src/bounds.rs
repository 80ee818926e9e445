//! What a cluster of lights can send towards a point: a box around them, their summed
//! emission, and the cones of their emitting normals and of the directions around those
//! normals they emit into (Conty Estevez and Kulla 2018, §4.1).

use fenestra_core::{Vec3, PI};

/// A cone of directions: axis `w` and the cosine of its half-angle (-1 for every direction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionCone {
    /// Unit axis.
    pub w: Vec3,
    /// Cosine of the half-angle.
    pub cos_theta: f32,
}

impl DirectionCone {
    /// Every direction.
    pub fn sphere() -> Self {
        DirectionCone {
            w: Vec3::Z,
            cos_theta: -1.0,
        }
    }

    /// The smallest cone holding both (exact when one holds the other, else the cone whose
    /// edge touches both: half-angle (theta_a + theta_d + theta_b) / 2).
    pub fn union(a: DirectionCone, b: DirectionCone) -> DirectionCone {
        let (ta, tb) = (
            a.cos_theta.clamp(-1.0, 1.0).acos(),
            b.cos_theta.clamp(-1.0, 1.0).acos(),
        );
        let td = a.w.dot(b.w).clamp(-1.0, 1.0).acos();
        if (td + tb).min(PI) <= ta {
            return a;
        }
        if (td + ta).min(PI) <= tb {
            return b;
        }
        let t = 0.5 * (ta + td + tb);
        if t >= PI {
            return DirectionCone::sphere();
        }
        let axis = a.w.cross(b.w);
        if axis.length_squared() < 1e-12 {
            return DirectionCone::sphere();
        }
        // a's axis turned towards b's by t - theta_a (Rodrigues' rotation about a x b).
        let k = axis.normalize();
        let (s, c) = (t - ta).sin_cos();
        let w = a.w * c + k.cross(a.w) * s + k * k.dot(a.w) * (1.0 - c);
        DirectionCone {
            w: w.normalize(),
            cos_theta: t.cos(),
        }
    }
}

/// Bounds on the light a set of emitters sends: where they are, how much, and which way.
#[derive(Clone, Copy, Debug)]
pub struct LightBounds {
    /// Box corner.
    pub lo: Vec3,
    /// Opposite corner.
    pub hi: Vec3,
    /// Emitted flux bound, in units where phi cos / d^2 is an irradiance: intensity (W/sr)
    /// for point and spot lights, radiance times area for flat emitters, radiance times
    /// pi r^2 for spheres.
    pub phi: f32,
    /// Cone of the emitters' normals (theta_o).
    pub normals: DirectionCone,
    /// Cosine of the angle around a normal within which an emitter sends light (theta_e:
    /// pi/2 for diffuse emitters).
    pub cos_theta_e: f32,
    /// Whether emitters send light on both sides of their normals.
    pub two_sided: bool,
}

impl LightBounds {
    /// The bounds of two sets together.
    pub fn union(a: &LightBounds, b: &LightBounds) -> LightBounds {
        if a.phi <= 0.0 {
            return *b;
        }
        if b.phi <= 0.0 {
            return *a;
        }
        LightBounds {
            lo: a.lo.min(b.lo),
            hi: a.hi.max(b.hi),
            phi: a.phi + b.phi,
            normals: DirectionCone::union(a.normals, b.normals),
            cos_theta_e: a.cos_theta_e.min(b.cos_theta_e),
            two_sided: a.two_sided || b.two_sided,
        }
    }

    /// The box's centre.
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.lo + self.hi)
    }

    /// An upper bound on what the set sends to the point `p` of normal `n` (zero normal: a
    /// point that receives from every side), up to a common scale: see
    /// [`ImportanceBounds::importance`].
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        ImportanceBounds::from(self).importance(p, n)
    }
}

/// [`LightBounds`] as importance reads them, with what does not depend on the point
/// computed once (the light BVH's descent asks two nodes a level).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ImportanceBounds {
    /// The box's centre.
    centre: Vec3,
    /// A quarter of the box's squared diagonal.
    half_diagonal2: f32,
    phi: f32,
    /// Axis of the normals' cone, and the cosine and sine of its half-angle.
    w: Vec3,
    cos_o: f32,
    sin_o: f32,
    cos_theta_e: f32,
    two_sided: bool,
}

impl From<&LightBounds> for ImportanceBounds {
    fn from(b: &LightBounds) -> Self {
        let cos_o = b.normals.cos_theta;
        ImportanceBounds {
            centre: b.centroid(),
            half_diagonal2: 0.25 * (b.hi - b.lo).length_squared(),
            phi: b.phi,
            w: b.normals.w,
            cos_o,
            sin_o: (1.0 - cos_o * cos_o).max(0.0).sqrt(),
            cos_theta_e: b.cos_theta_e,
            two_sided: b.two_sided,
        }
    }
}

impl ImportanceBounds {
    /// An upper bound on what the set sends to the point `p` of normal `n` (zero normal: a
    /// point that receives from every side), up to a common scale: phi cos(theta') / d^2 with
    /// the angles widened by the cone the box subtends from `p` (Conty Estevez and Kulla's
    /// importance, with the distance kept at least half the box's diagonal).
    #[inline]
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        let v = p - self.centre;
        let l2 = v.length_squared();
        let d2 = l2.max(self.half_diagonal2).max(1e-20);
        let wi = v.normalize_or(Vec3::Z);
        // The cone the bounding sphere subtends from p (everything when p is inside).
        let (sin_b, cos_b) = if l2 <= self.half_diagonal2 {
            (0.0, -1.0)
        } else {
            let sin2 = self.half_diagonal2 / l2;
            (sin2.sqrt(), (1.0 - sin2).max(0.0).sqrt())
        };
        let mut cos_w = self.w.dot(wi);
        if self.two_sided {
            cos_w = cos_w.abs();
        }
        let sin_w = (1.0 - cos_w * cos_w).max(0.0).sqrt();
        // theta_x = max(0, theta_w - theta_o), then theta' = max(0, theta_x - theta_b).
        let (cos_x, sin_x) = sub_clamped(cos_w, sin_w, self.cos_o, self.sin_o);
        let (cos_p, _) = sub_clamped(cos_x, sin_x, cos_b, sin_b);
        if cos_p <= self.cos_theta_e {
            return 0.0;
        }
        let mut importance = self.phi * cos_p / d2;
        if n != Vec3::ZERO {
            let cos_i = wi.dot(n).abs();
            let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
            importance *= sub_clamped(cos_i, sin_i, cos_b, sin_b).0;
        }
        importance.max(0.0)
    }
}

/// cos and sin of max(0, a - b) from those of a and b.
#[inline]
fn sub_clamped(cos_a: f32, sin_a: f32, cos_b: f32, sin_b: f32) -> (f32, f32) {
    if cos_a > cos_b {
        (1.0, 0.0)
    } else {
        (cos_a * cos_b + sin_a * sin_b, sin_a * cos_b - cos_a * sin_b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_core::{warp, Rng};

    #[test]
    fn a_cone_union_holds_both_cones() {
        let mut rng = Rng::new(4);
        for _ in 0..2000 {
            let cone = |rng: &mut Rng| DirectionCone {
                w: warp::square_to_uniform_sphere(rng.next_2d()),
                cos_theta: 2.0 * rng.next_f32() - 1.0,
            };
            let (a, b) = (cone(&mut rng), cone(&mut rng));
            let u = DirectionCone::union(a, b);
            // Every direction of a and of b (their edges in particular) lies in the union.
            for c in [a, b] {
                let edge = (1.0 - c.cos_theta * c.cos_theta).max(0.0).sqrt();
                let f = fenestra_core::Frame::from_normal(c.w);
                for k in 0..16 {
                    let phi = k as f32 / 16.0 * 2.0 * PI;
                    let d = f.to_world(Vec3::new(edge * phi.cos(), edge * phi.sin(), c.cos_theta));
                    assert!(
                        u.w.dot(d) >= u.cos_theta - 1e-4,
                        "{a:?} u {b:?} = {u:?} misses {d}"
                    );
                }
            }
        }
    }

    #[test]
    fn importance_bounds_what_a_single_flat_emitter_sends() {
        // One emitter (a small square of radiance 1 facing +z) at the origin: phi = L A, and
        // the importance at a point is at least its irradiance L A cos cos' / d^2 there.
        let bounds = LightBounds {
            lo: Vec3::new(-0.05, -0.05, 0.0),
            hi: Vec3::new(0.05, 0.05, 0.0),
            phi: 0.01,
            normals: DirectionCone {
                w: Vec3::Z,
                cos_theta: 1.0,
            },
            cos_theta_e: 0.0,
            two_sided: false,
        };
        let mut rng = Rng::new(9);
        for _ in 0..1000 {
            let p = warp::square_to_uniform_sphere(rng.next_2d()) * (0.5 + 3.0 * rng.next_f32());
            let n = warp::square_to_uniform_sphere(rng.next_2d());
            let wi = p.normalize();
            let irradiance = 0.01 * wi.z.max(0.0) * wi.dot(n).abs() / p.length_squared();
            let importance = bounds.importance(p, n);
            assert!(
                importance >= irradiance * 0.999,
                "{p} {n}: {importance} < {irradiance}"
            );
            if p.z < -0.08 {
                assert_eq!(importance, 0.0, "behind the emitter at {p}");
            }
        }
    }
}
