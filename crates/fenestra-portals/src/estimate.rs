//! The estimation pipeline of seed 000 ch. 4: photons (Alg. 1) -> DBSCAN clusters (Alg. 2)
//! -> RANSAC plane per cluster (Alg. 3) -> a covering shape of the inliers in that plane
//! (MVCE by Alg. 4, the PCA rectangle of §5.1, or the minimum-area rectangle) -> portals;
//! rectangles around openings in planar occluders are then snapped onto the openings' edges.

use crate::aim::{camera_surroundings, Surroundings};
use crate::carry::Carry;
use crate::cluster::{dbscan, DbscanParams};
use crate::error::PortalError;
use crate::fitted::{quad_portal, Estimated};
use crate::mvce::mvce;
use crate::photon::Deposit;
use crate::photon::{trace, PhotonParams, Photons};
use crate::portal::{EstimationRecord, Portal, PortalFile, Portals};
use crate::ransac::{ransac_plane, Plane, Ransac};
use crate::rectangle::{inner_rectangle, min_area_rectangle, pca_rectangle, Rectangle};
use crate::snap::{snap_to_opening, Opening, MIN_ENCLOSED};
use crate::window::{windows, within, WINDOW_GAP};
use fenestra_core::{UnknownName, Vec3};
use fenestra_render::options::ValueError;
use fenestra_render::{Progress, RenderScene};
use glam::{DVec2, DVec3};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The shape fitted to a cluster's inliers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Model {
    /// Minimum-volume covering ellipse (Alg. 4), the seed's choice.
    Ellipse,
    /// PCA rectangle (§5.1).
    Pca,
    /// Minimum-area enclosing rectangle; around an opening (photons by depth), shrunk to the
    /// photon ring's inner edges when the opening is rectangular.
    Rectangle,
    /// The smaller of the ellipse and the minimum-area rectangle (both cover every inlier).
    Smallest,
}

impl std::str::FromStr for Model {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, UnknownName> {
        match s {
            "ellipse" => Ok(Model::Ellipse),
            "pca" => Ok(Model::Pca),
            "rectangle" => Ok(Model::Rectangle),
            "smallest" => Ok(Model::Smallest),
            _ => Err(UnknownName::new(
                "portal model",
                s,
                "ellipse, pca, rectangle or smallest",
            )),
        }
    }
}

impl std::fmt::Display for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Model::Ellipse => "ellipse",
            Model::Pca => "pca",
            Model::Rectangle => "rectangle",
            Model::Smallest => "smallest",
        })
    }
}

impl fenestra_render::options::OptionValue for Model {
    const KIND: fenestra_render::options::Kind =
        fenestra_render::options::Kind::Choice(&["ellipse", "pca", "rectangle", "smallest"]);

    fn from_param(param: &serde_json::Value) -> Result<Self, ValueError> {
        match param {
            serde_json::Value::String(s) => s
                .parse()
                .map_err(|e: UnknownName| ValueError(e.to_string())),
            v => Err(ValueError(format!(
                "takes ellipse, pca, rectangle or smallest, got {v}"
            ))),
        }
    }
}

/// PT(theta, n, r), DBSCAN(eps, m), RANSAC(Plane, eps, tau, N), MVCE(eps) and the model.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct EstimateParams {
    /// Photon tracing PT(theta, n, r).
    pub photons: PhotonParams,
    /// Clustering DBSCAN(eps, m).
    pub dbscan: DbscanParams,
    /// Plane fitting RANSAC(eps, tau, N).
    pub ransac: Ransac,
    /// Khachiyan's stopping tolerance (seed §5.2: 0.001).
    pub mvce_eps: f64,
    /// The shape fitted to each cluster.
    pub model: Model,
    /// Stop tracing photons once the portals fitted to them settle: when the portals of
    /// 1.5 times as many photons lie within this fraction of their size of the previous ones
    /// (`None`, as in estimates made before it existed: trace to the target).
    #[serde(default)]
    pub settle: Option<f64>,
}

impl Default for EstimateParams {
    fn default() -> Self {
        EstimateParams {
            photons: PhotonParams::default(),
            dbscan: DbscanParams::default(),
            ransac: Ransac::default(),
            mvce_eps: 1e-3,
            model: Model::Smallest,
            settle: Some(0.01),
        }
    }
}

/// Seconds spent in each stage.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Timings {
    /// Photon tracing.
    pub photons: f64,
    /// DBSCAN.
    pub clustering: f64,
    /// Planes and covering shapes.
    pub fitting: f64,
}

impl Timings {
    /// All stages.
    pub fn total(&self) -> f64 {
        self.photons + self.clustering + self.fitting
    }
}

/// What the pipeline found and what it took.
pub struct Estimate {
    /// The photons traced.
    pub photons: Photons,
    /// Photon indices of each cluster, largest first.
    pub clusters: Vec<Vec<usize>>,
    /// The fitted portals.
    pub portals: Vec<Estimated>,
    /// Seconds per stage.
    pub timings: Timings,
    /// What the camera sees around it, which photons were aimed at (lp_hf's pilot measures
    /// there too).
    pub surroundings: Surroundings,
}

impl Estimate {
    /// The fitted portals, sampled by the default strategy.
    pub fn portals(&self) -> Portals {
        Portals::new(self.portals.iter().map(|e| e.portal.clone()).collect())
    }

    /// The portals.json document of this estimate of `scene` made with `params`.
    pub fn file(&self, scene: &str, params: &EstimateParams) -> PortalFile {
        PortalFile {
            portals: self.portals.iter().map(Estimated::record).collect(),
            estimation: Some(EstimationRecord {
                scene: scene.to_string(),
                parameters: params.clone(),
                photons: self.photons.points.len(),
                beams: self.photons.beams,
                rays: self.photons.rays,
                deposit: self.photons.deposit,
                interrupted: self.photons.interrupted,
                settled: self.photons.settled,
                timed_out: self.photons.timed_out,
                clusters: self.clusters.len(),
                time_s: self.timings,
            }),
        }
    }

    /// A paragraph on the estimate: photons, clusters, time per stage, and a line per portal.
    pub fn summary(&self) -> String {
        let ph = &self.photons;
        let noise = ph.points.len() - self.clusters.iter().map(Vec::len).sum::<usize>();
        let mut s = format!(
            "{} photons ({:?} deposits) from {} beams, {} rays{}; {} clusters, {} noise photons; {} portals in {:.2} s (photons {:.2} s, DBSCAN {:.2} s, fitting {:.2} s)",
            ph.points.len(),
            ph.deposit,
            ph.beams,
            ph.rays,
            if ph.interrupted {
                ", interrupted".to_string()
            } else if ph.timed_out {
                format!(" (the time limit came before the {} aimed at)", ph.target)
            } else if ph.settled {
                format!(" (portals settled before the {} aimed at)", ph.target)
            } else if ph.points.len() < ph.target {
                format!(" (the beam limit came before the {} aimed at)", ph.target)
            } else {
                String::new()
            },
            self.clusters.len(),
            noise,
            self.portals.len(),
            self.timings.total(),
            self.timings.photons,
            self.timings.clustering,
            self.timings.fitting,
        );
        for (k, p) in self.portals.iter().enumerate() {
            let portal = &p.portal;
            let c = portal.center();
            let n = portal.normal();
            s.push_str(&format!(
                "\n  portal {k}: {} centre ({:.3}, {:.3}, {:.3}) normal ({:.3}, {:.3}, {:.3}) {}, area {:.5} m^2, {} photons ({} inliers)",
                portal.kind(),
                c.x,
                c.y,
                c.z,
                n.x,
                n.y,
                n.z,
                portal.size(),
                portal.area(),
                p.photons,
                p.inliers
            ));
        }
        s
    }
}

/// Runs the whole pipeline on `scene`. Ctrl-C (`cancel`) ends photon tracing early; the
/// portals are then fitted to the photons gathered so far.
pub fn estimate(
    scene: &RenderScene,
    params: &EstimateParams,
    cancel: &AtomicBool,
    progress: &dyn Progress,
) -> Result<Estimate, PortalError> {
    let t0 = Instant::now();
    params.validate()?;
    let surroundings = camera_surroundings(&scene.scene);
    let fitter = Fitter {
        scene,
        params,
        deposit: crate::photon::deposit_rule(scene, &params.photons),
        glass: crate::photon::glass_shapes(scene),
        surroundings: &surroundings,
    };
    let mut settling = Settling {
        fitter: &fitter,
        next_fit: FIRST_FIT,
        last: None,
    };
    let photons = trace(
        scene,
        &params.photons,
        surroundings.sphere,
        cancel,
        progress,
        &mut |points| settling.settled(points),
    )?;
    let t1 = Instant::now();
    let mut tracing = (t1 - t0).as_secs_f64();
    // Settled: the last test's fit, made while tracing, is that of all the photons.
    let (clusters, portals, fit_timings) = match settling.last.take() {
        Some(fit) if photons.settled => {
            tracing -= fit.2.clustering + fit.2.fitting;
            fit
        }
        _ => fitter.fit(&photons.points),
    };
    Ok(Estimate {
        photons,
        clusters,
        portals,
        timings: Timings {
            photons: tracing,
            ..fit_timings
        },
        surroundings,
    })
}

/// DBSCAN clusters of photons (largest first), a portal fitted to each, and the seconds each
/// stage took (photon tracing's left zero).
type Fit = (Vec<Vec<usize>>, Vec<Estimated>, Timings);

/// What fitting portals to photons needs, gathered once per estimate.
struct Fitter<'a> {
    scene: &'a RenderScene,
    params: &'a EstimateParams,
    /// How the photons were deposited.
    deposit: Deposit,
    /// Which shapes are glass.
    glass: Vec<bool>,
    /// What the camera sees.
    surroundings: &'a Surroundings,
}

impl Fitter<'_> {
    /// The [`Fit`] of `points`: the seed's portals (a DBSCAN cluster each) and the windows
    /// found plane first ([`crate::window`]), combined by [`combine`].
    fn fit(&self, points: &[Vec3]) -> Fit {
        let (scene, params) = (self.scene, self.params);
        let t1 = Instant::now();
        let clusters = dbscan(points, params.dbscan);
        let t2 = Instant::now();
        let ring = self.deposit == Deposit::Depth;
        let seed: Vec<(Vec<usize>, Estimated)> = clusters
            .into_iter()
            .filter_map(|c| {
                let cluster: Vec<Vec3> = c.iter().map(|&i| points[i]).collect();
                let mut e = fit_cluster(&cluster, params, ring)?;
                if ring {
                    e.portal = snap_to_opening(&scene.scene, &e.portal);
                }
                Some((c, e))
            })
            .collect();
        let opening = Opening::new(&scene.scene, &self.glass);
        let gap = if ring { WINDOW_GAP } else { params.dbscan.eps };
        let windows = windows(&opening, points, &params.ransac, gap);
        let carry = Carry::new(scene, self.surroundings);
        let (clusters, portals) = combine(&opening, &carry, seed, windows);
        let t3 = Instant::now();
        let timings = Timings {
            photons: 0.0,
            clustering: (t2 - t1).as_secs_f64(),
            fitting: (t3 - t2).as_secs_f64(),
        };
        (clusters, portals, timings)
    }
}

/// A seed portal of this share of the area of the window around it stands for the window (the
/// seed's fit, snapped onto the opening's edges, is the more exact; a larger one was not
/// snapped, because mullions or slats stopped the probes).
const SEED_STANDS_FOR_WINDOW: std::ops::RangeInclusive<f32> = 0.8..=1.02;
/// How far (relative to a window's size) a portal may reach out of it and still lie within it.
const WITHIN: f32 = 0.05;

/// The portals of an estimate: each window (largest first) unless it lies within one already
/// kept, or the one seed portal within it when that covers most of it; then the seed portals
/// within no window; of these, those cut in an occluder (most of a ring around them closed,
/// [`MIN_ENCLOSED`]) that carry light ([`Carry::keep`]). Ordered by photons,
/// most first, with each portal's photons as its cluster.
fn combine(
    opening: &Opening,
    carry: &Carry,
    seed: Vec<(Vec<usize>, Estimated)>,
    mut windows: Vec<(Vec<usize>, Estimated)>,
) -> (Vec<Vec<usize>>, Vec<Estimated>) {
    windows.sort_by(|a, b| b.1.portal.area().total_cmp(&a.1.portal.area()));
    let mut used = vec![false; seed.len()];
    let mut kept: Vec<(Vec<usize>, Estimated)> = Vec::new();
    for w in windows {
        if kept
            .iter()
            .any(|k| within(&w.1.portal, &k.1.portal, WITHIN))
        {
            continue;
        }
        let inside: Vec<usize> = (0..seed.len())
            .filter(|&i| !used[i] && within(&seed[i].1.portal, &w.1.portal, WITHIN))
            .collect();
        for &i in &inside {
            used[i] = true;
        }
        match inside[..] {
            [i] if SEED_STANDS_FOR_WINDOW
                .contains(&(seed[i].1.portal.area() / w.1.portal.area())) =>
            {
                kept.push(seed[i].clone())
            }
            _ => kept.push(w),
        }
    }
    kept.extend(
        seed.into_iter()
            .zip(used)
            .filter(|(_, u)| !u)
            .map(|(s, _)| s),
    );
    kept.retain(|(_, e)| opening.enclosed_fraction(&e.portal) >= MIN_ENCLOSED);
    let mut kept = carry.keep(kept, |(_, e)| &e.portal);
    kept.sort_by_key(|(c, _)| std::cmp::Reverse(c.len()));
    kept.into_iter()
        .enumerate()
        .map(|(k, (c, mut e))| {
            e.cluster = k;
            (c, e)
        })
        .unzip()
}

/// Photons before the first fit of the settling test.
const FIRST_FIT: usize = 64;

/// The settling test of [`EstimateParams::settle`]: portals fitted to the photons each time
/// their number has grown by half, compared with the previous fit.
struct Settling<'a> {
    fitter: &'a Fitter<'a>,
    next_fit: usize,
    /// The previous test's fit.
    last: Option<Fit>,
}

impl Settling<'_> {
    fn settled(&mut self, points: &[Vec3]) -> bool {
        let Some(tolerance) = self.fitter.params.settle else {
            return false;
        };
        if points.len() < self.next_fit {
            return false;
        }
        self.next_fit = points.len() + points.len() / 2;
        let fit = self.fitter.fit(points);
        let portals = &fit.1;
        let settled = !portals.is_empty()
            && self.last.as_ref().is_some_and(|(_, last, _)| {
                last.len() == portals.len()
                    && portals.iter().all(|p| {
                        last.iter()
                            .any(|q| same_portal(&p.portal, &q.portal, tolerance))
                    })
            });
        self.last = Some(fit);
        settled
    }
}

/// Whether two portals cover the same opening: parallel, centres and sizes within
/// `tolerance` times the portal's size (square root of its area).
fn same_portal(a: &Portal, b: &Portal, tolerance: f64) -> bool {
    let size = (a.area() as f64).sqrt();
    let parallel = (a.normal().dot(b.normal()) as f64).abs() >= 1.0 - tolerance * tolerance;
    let centres = (a.center() - b.center()).length() as f64 <= tolerance * size;
    let sizes = ((b.area() as f64).sqrt() - size).abs() <= tolerance * size;
    parallel && centres && sizes
}

impl EstimateParams {
    /// Checks the clustering and fitting parameters (photon tracing checks its own).
    fn validate(&self) -> Result<(), PortalError> {
        if !(self.dbscan.eps > 0.0) || self.dbscan.min_points == 0 {
            return Err(PortalError::Parameters(
                "DBSCAN needs eps > 0 and m >= 1".into(),
            ));
        }
        if self.settle.is_some_and(|t| !(t > 0.0 && t < 1.0)) {
            return Err(PortalError::Parameters(format!(
                "the settling tolerance must lie in (0, 1), not {}",
                self.settle.unwrap_or_default()
            )));
        }
        if !(self.ransac.eps > 0.0) || !(0.0..=1.0).contains(&self.ransac.tau) {
            return Err(PortalError::Parameters(
                "RANSAC needs eps > 0 and tau in [0, 1]".into(),
            ));
        }
        Ok(())
    }
}

/// Maximum Khachiyan iterations (the tolerance ends it long before on photon clusters).
const MVCE_MAX_ITERATIONS: usize = 100_000;

/// RANSAC plane, then the chosen covering shape of the inliers in that plane. With `ring`
/// (photons deposited by depth, which lie around an opening rather than on it) rectangles
/// shrink to the ring's inner edges when the opening is rectangular.
pub fn fit_cluster(points: &[Vec3], params: &EstimateParams, ring: bool) -> Option<Estimated> {
    let pts: Vec<DVec3> = points.iter().map(|p| p.as_dvec3()).collect();
    let fit = ransac_plane(&pts, &params.ransac)?;
    let plane = fit.plane;
    let flat: Vec<DVec2> = fit
        .inliers
        .iter()
        .map(|&i| plane.to_plane(pts[i]))
        .collect();
    let ellipse = || mvce(&flat, params.mvce_eps, MVCE_MAX_ITERATIONS);
    let quad = |r: Rectangle| quad_portal(&plane, r);
    let opening = |r: Rectangle| {
        if ring {
            inner_rectangle(&r, &flat).unwrap_or(r)
        } else {
            r
        }
    };
    let (portal, iterations) = match params.model {
        Model::Ellipse => {
            let e = ellipse()?;
            (ellipse_portal(&plane, &e), e.iterations)
        }
        Model::Pca => (quad(pca_rectangle(&flat)?), 0),
        Model::Rectangle => (quad(opening(min_area_rectangle(&flat)?)), 0),
        Model::Smallest => {
            let e = ellipse()?;
            match min_area_rectangle(&flat).map(opening) {
                Some(r) if r.area() < e.area() => (quad(r), e.iterations),
                _ => (ellipse_portal(&plane, &e), e.iterations),
            }
        }
    };
    Some(Estimated {
        portal,
        cluster: 0,
        photons: points.len(),
        inliers: fit.inliers.len(),
        mvce_iterations: iterations,
    })
}

fn ellipse_portal(plane: &Plane, e: &crate::mvce::Ellipse) -> Portal {
    let to3 = |v: DVec2| (plane.from_plane(v) - plane.point).as_vec3();
    Portal::Ellipse {
        center: plane.from_plane(e.center).as_vec3(),
        a: to3(e.axes[0]),
        b: to3(e.axes[1]),
    }
}
