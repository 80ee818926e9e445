//! The portal estimator's parameters as an options group, named as in seed 000 §5.2:
//! PT(theta, n, r), DBSCAN(eps, m), RANSAC(eps, tau, N), MVCE(eps); each default is the
//! pipeline's own. lp_hf reads it for `--portals auto` (`--estimate-theta`, Python's
//! `estimate_theta`); `fenestra portals`, which does nothing else, names the same options
//! without the prefix (`--theta`, Python's `fe.portals.estimate(theta=...)`).

use crate::estimate::{EstimateParams, Model};
use crate::photon::Deposit;
use fenestra_render::options::Validate;
use fenestra_render::registry::Group;

/// The pipeline's defaults, which the options start from.
fn defaults() -> EstimateParams {
    EstimateParams::default()
}

fenestra_render::options! {
    /// Portal estimation (seed 000 §5.2; with --portals auto).
    pub struct EstimateOptions in "estimate", flags "estimate" {
        /// PT: cone half-angle theta of a beam, degrees.
        pub theta: f32 = defaults().photons.theta_deg,
        /// PT: rays per beam n.
        pub rays: u32 = defaults().photons.rays_per_beam,
        /// PT: radius r of the rejection sphere, metres (depth discontinuities shorter than r
        /// deposit nothing).
        pub radius: f32 = defaults().photons.reject_radius,
        /// Where photons are deposited: depth (discontinuities, Alg. 1) or material (on glass,
        /// §5.3). Default: material when the scene has glass, depth otherwise.
        pub deposit: Option<Deposit> = defaults().photons.deposit,
        /// Photons to gather (default: 8192 by depth, 32768 by material).
        pub photons: Option<usize> = defaults().photons.target,
        /// Give up after this many beams if the photons are not gathered.
        pub max_beams: u64 = defaults().photons.max_beams,
        /// Give up tracing photons after this many seconds (0: no limit, so that the photons
        /// depend on nothing but the parameters); with --portals auto and a --time budget, at
        /// most 3% of the budget or 0.2 s, whichever is more (but no more than a quarter).
        pub time: f64 = defaults().photons.time_limit.unwrap_or(0.0),
        /// Stop tracing photons once portals fitted to 1.5 times as many photons lie within
        /// this fraction of their size of the previous fit's (0: trace to the photon target).
        pub settle: f64 = defaults().settle.unwrap_or(0.0),
        /// DBSCAN: neighbourhood radius eps, metres.
        pub eps: f32 = defaults().dbscan.eps,
        /// DBSCAN: minimum neighbours m of a core point.
        pub min_points: usize = defaults().dbscan.min_points,
        /// RANSAC: inlier distance to the plane, metres.
        pub ransac_eps: f64 = defaults().ransac.eps,
        /// RANSAC: inlier fraction that ends the search.
        pub ransac_tau: f64 = defaults().ransac.tau,
        /// RANSAC: maximum trials N.
        pub ransac_trials: usize = defaults().ransac.trials,
        /// MVCE: Khachiyan's stopping tolerance.
        pub mvce_eps: f64 = defaults().mvce_eps,
        /// Portal shape: ellipse (MVCE, the seed's), pca (PCA rectangle), rectangle (minimum
        /// area) or smallest (the smaller of ellipse and rectangle).
        pub model: Model = defaults().model,
        /// Seed of the photons' and RANSAC's random numbers.
        pub seed: u64 = defaults().photons.seed,
    }
}

/// The pipeline checks its parameters itself when it runs (`estimate`): one place for the rules.
impl Validate for EstimateOptions {}

impl EstimateOptions {
    /// The group as `fenestra portals` shows it: the same keys, flags without the prefix.
    pub fn unprefixed_group() -> Group {
        Group {
            flag_prefix: "",
            ..Group::of::<Self>()
        }
    }

    /// The parameters as the pipeline takes them.
    pub fn params(&self) -> EstimateParams {
        let mut p = EstimateParams::default();
        p.photons.theta_deg = self.theta;
        p.photons.rays_per_beam = self.rays;
        p.photons.reject_radius = self.radius;
        p.photons.deposit = self.deposit;
        p.photons.target = self.photons;
        p.photons.max_beams = self.max_beams;
        p.photons.time_limit = (self.time != 0.0).then_some(self.time);
        p.settle = (self.settle != 0.0).then_some(self.settle);
        p.photons.seed = self.seed;
        p.dbscan.eps = self.eps;
        p.dbscan.min_points = self.min_points;
        p.ransac.eps = self.ransac_eps;
        p.ransac.tau = self.ransac_tau;
        p.ransac.trials = self.ransac_trials;
        p.ransac.seed = self.seed;
        p.mvce_eps = self.mvce_eps;
        p.model = self.model;
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fenestra_render::options::{Options, Params};

    /// `render --portals auto` estimates with the pipeline's defaults: they must be these,
    /// or the two would find different portals in the same scene.
    #[test]
    fn the_options_defaults_are_the_pipelines() {
        let json = |p: &EstimateParams| serde_json::to_string(p).expect("json");
        assert_eq!(
            json(&EstimateOptions::default().params()),
            json(&EstimateParams::default())
        );
    }

    #[test]
    fn options_set_the_parameters_and_values_of_the_wrong_kind_are_refused() {
        let params = Params::new()
            .with("estimate.theta", "5")
            .with("estimate.deposit", "material")
            .with("estimate.photons", 1000);
        let p = EstimateOptions::from_params(&params)
            .expect("valid")
            .params();
        assert_eq!(p.photons.theta_deg, 5.0);
        assert_eq!(p.photons.deposit, Some(Deposit::Material));
        assert_eq!(p.photons.target, Some(1000));
        for (key, value, says) in [
            ("estimate.deposit", "glass", "unknown deposit rule 'glass'"),
            ("estimate.theta", "wide", "estimate.theta takes a number"),
        ] {
            let e = EstimateOptions::from_params(&Params::new().with(key, value))
                .expect_err(key)
                .to_string();
            assert!(e.contains(says), "{key}={value}: {e}");
        }
    }
}
