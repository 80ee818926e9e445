//! A portal fitted to one cluster of photons, with what it came from: what the estimator
//! and the window finder (which cuts glazed walls into panes) both make.

use crate::portal::{Portal, PortalRecord};
use crate::ransac::Plane;
use crate::rectangle::Rectangle;
use glam::DVec2;

/// One fitted portal and what it came from.
#[derive(Clone, Debug)]
pub struct Estimated {
    /// The portal.
    pub portal: Portal,
    /// Index of its cluster (clusters are ordered largest first).
    pub cluster: usize,
    /// Photons in the cluster and RANSAC inliers among them.
    pub photons: usize,
    /// RANSAC inliers among them.
    pub inliers: usize,
    /// Khachiyan iterations (0 when a rectangle was chosen without an ellipse).
    pub mvce_iterations: usize,
}

impl Estimated {
    /// Its portals.json record, with photons and cluster.
    pub fn record(&self) -> PortalRecord {
        let mut r = PortalRecord::new(&self.portal);
        r.photons = Some(self.photons);
        r.cluster = Some(self.cluster);
        r
    }
}

/// The quad of rectangle `r` in `plane`.
pub(crate) fn quad_portal(plane: &Plane, r: Rectangle) -> Portal {
    let to3 = |v: DVec2| (plane.from_plane(v) - plane.point).as_vec3();
    let (a, b) = (to3(r.half[0]), to3(r.half[1]));
    Portal::Quad {
        corner: plane.from_plane(r.center).as_vec3() - a - b,
        e1: a * 2.0,
        e2: b * 2.0,
    }
}
