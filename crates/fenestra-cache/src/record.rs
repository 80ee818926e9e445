//! A cache record: where it is, where it may be reused (seed 003 eq. 2.1-2.2, the weight
//! of Ward et al. 1988 that radiance caching borrows), which directions it covers, and what it
//! holds ([`Payload`]: an L-tree of radiance samples, or irradiance with its gradients).

use crate::paraboloid;
use fenestra_core::{Frame, Vec2, Vec3};
use fenestra_scene::SurfaceInteraction;

/// Smallest error term a record is weighed with: a record exactly at the point weighs
/// 1/MIN_ERROR, not infinity.
const MIN_ERROR: f32 = 1e-3;

/// What a record holds, and what may be added to it after it is made.
pub trait Payload: Send + Sync {
    /// An addition (a new radiance sample of an L-tree).
    type Update: Copy + Send + Sync;

    /// Takes an addition in.
    fn absorb(&mut self, update: Self::Update);

    /// Bytes it takes.
    fn bytes(&self) -> usize;
}

/// A record of the spatial cache holding `P`.
#[derive(Clone, Debug)]
pub struct Record<P> {
    /// Where it is: rays that add samples leave from here.
    pub si: SurfaceInteraction,
    /// Its hemisphere: z is the shading normal on the side the record was seen from.
    pub frame: Frame,
    /// The geometric normal on that side.
    pub ng: Vec3,
    /// Harmonic mean distance to the surfaces its rays found, clamped (R_i of eq. 2.2).
    pub r: f32,
    /// What it holds.
    pub payload: P,
    /// The pixel whose sample created it (for the records picture).
    pub pixel: (u32, u32),
}

impl<P> Record<P> {
    /// The spatial weight w_i(p) of eq. 2.2 for a point `p` with normal `n` (on its viewer's
    /// side), if the record may serve it with maximum error `a` (eq. 2.1: w_i > 1/a) and does
    /// not lie in front of it (Ward et al. 1988's test, so that light does not leak into
    /// creases).
    pub fn weight(&self, p: Vec3, n: Vec3, a: f32) -> Option<f32> {
        let d = p - self.si.p;
        let (d2, reach) = (d.length_squared(), a * self.r);
        if d2 >= reach * reach {
            return None;
        }
        let error = d2.sqrt() / self.r + (1.0 - n.dot(self.frame.n)).max(0.0).sqrt();
        let in_front = d.dot(n + self.frame.n) < -0.1 * self.r;
        (error < a && !in_front).then(|| 1.0 / error.max(MIN_ERROR))
    }

    /// Where the world direction `w` lies in the record's disc D, if it points into the
    /// record's hemisphere (and off its geometric surface).
    pub fn disc(&self, w: Vec3) -> Option<Vec2> {
        let local = self.frame.to_local(w);
        (local.z > 0.0 && w.dot(self.ng) > 0.0).then(|| paraboloid::to_disc(local))
    }
}
