//! The LPCA driver (Kambhatla-Leen, §3.3.2): seed, then for each (dimension, iterations) of
//! the schedule alternate fitting subspaces and classifying points. With the SortCluster
//! algorithm the classification is Alg. 2; everything else is shared, so both produce the
//! same assignments.

use crate::classify::{self, ClassifyStats};
use crate::data::Dataset;
use crate::fit::fit;
use crate::init::{seed, Init, Seeding};
use crate::schedule::Schedule;
use crate::subspace::Subspace;
use crate::LpcaError;
use serde::Serialize;
use std::time::Instant;

/// How points are classified to subspaces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub enum Algorithm {
    /// Exhaustive classification (Lloyd's k-means when the schedule is "0:N").
    Lpca,
    /// SortCluster-LPCA (SortMeans when the schedule is "0:N"): the default.
    #[default]
    ScLpca,
}

impl std::fmt::Display for Algorithm {
    /// As [`str::parse`] reads it.
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            Algorithm::Lpca => "lpca",
            Algorithm::ScLpca => "sc-lpca",
        })
    }
}

impl std::str::FromStr for Algorithm {
    type Err = fenestra_core::UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "lpca" => Ok(Algorithm::Lpca),
            "sc-lpca" => Ok(Algorithm::ScLpca),
            _ => Err(fenestra_core::UnknownName::new(
                "algorithm",
                s,
                "lpca or sc-lpca",
            )),
        }
    }
}

/// A run of (SortCluster-)LPCA.
#[derive(Clone, Debug)]
pub struct Options {
    /// Number of clusters k.
    pub clusters: usize,
    /// Subspace dimensions and the iterations at each.
    pub schedule: Schedule,
    /// Exhaustive or SortCluster classification.
    pub algorithm: Algorithm,
    /// How the clusters start.
    pub init: Init,
    /// Seed of the initialisation.
    pub seed: u64,
}

/// One iteration: refit the subspaces, classify the points.
#[derive(Clone, Debug, Serialize)]
pub struct IterationStats {
    /// Subspace dimension.
    pub dim: usize,
    /// Iteration index, from 0.
    pub iteration: usize,
    /// Seconds spent fitting the subspaces.
    pub fit_seconds: f64,
    /// The classification.
    #[serde(flatten)]
    pub classify: ClassifyStats,
    /// Objective after this iteration: sum of point-subspace distances.
    pub phi: f64,
}

/// The result of a run: assignments, subspaces and statistics.
#[derive(Clone, Debug, Serialize)]
pub struct Outcome {
    /// Cluster of every point.
    #[serde(skip)]
    pub assignments: Vec<u32>,
    /// Distance of every point to its subspace.
    #[serde(skip)]
    pub distances: Vec<f64>,
    /// The subspaces.
    #[serde(skip)]
    pub models: Vec<Subspace>,
    /// The initialisation.
    pub init: Seeding,
    /// Exhaustive classification after seeds that give none (random, distance-sum).
    pub initial_classification: Option<ClassifyStats>,
    /// Every iteration.
    pub iterations: Vec<IterationStats>,
    /// Seed 003's objective: the sum over points of the distance to their subspace.
    pub phi: f64,
    /// Sum of squared distances over the sum of squared norms of the points.
    pub relative_squared_error: f64,
    /// Seconds spent classifying, over all iterations.
    pub classification_seconds: f64,
    /// Point-subspace distances evaluated, over all iterations.
    pub distance_evals: u64,
}

/// Runs LPCA or SortCluster-LPCA on `data`.
pub fn run(data: &Dataset, options: &Options) -> Result<Outcome, LpcaError> {
    let k = options.clusters;
    if k == 0 || k > data.n {
        return Err(LpcaError::Input(format!(
            "--clusters must be between 1 and the number of points ({}), got {k}",
            data.n
        )));
    }
    if options.schedule.max_dim() >= data.d {
        return Err(LpcaError::Input(format!(
            "subspace dimension {} must be below the data dimension {}",
            options.schedule.max_dim(),
            data.d
        )));
    }
    // Fits run in parallel over clusters; faer itself runs sequentially inside each, which
    // keeps every result independent of the thread count.
    faer::set_global_parallelism(faer::Par::Seq);
    let init = seed(data, k, options.init, options.seed);
    let mut models: Vec<Subspace> = init
        .centroids
        .iter()
        .map(|&i| Subspace::point(data.row(i).iter().map(|&v| v as f64).collect()))
        .collect();
    let (mut assign, mut dist, initial_classification) = match &init.assignment {
        Some((a, d)) => (a.clone(), d.clone(), None),
        None => {
            let (mut a, mut d) = (vec![0u32; data.n], vec![0.0; data.n]);
            let s = classify::full(data, &models, &mut a, &mut d);
            (a, d, Some(s))
        }
    };
    let mut iterations = Vec::new();
    for &(dim, iters) in &options.schedule.0 {
        for iteration in 0..iters {
            let t = Instant::now();
            models = fit(data, &assign, &models, dim);
            let fit_seconds = t.elapsed().as_secs_f64();
            let classify = match options.algorithm {
                Algorithm::Lpca => classify::full(data, &models, &mut assign, &mut dist),
                Algorithm::ScLpca => classify::sorted(data, &models, &mut assign, &mut dist),
            };
            iterations.push(IterationStats {
                dim,
                iteration,
                fit_seconds,
                classify,
                phi: dist.iter().sum(),
            });
        }
    }
    let energy = data.total_energy();
    Ok(Outcome {
        phi: dist.iter().sum(),
        relative_squared_error: dist.iter().map(|d| d * d).sum::<f64>()
            / energy.max(f64::MIN_POSITIVE),
        classification_seconds: iterations.iter().map(|i| i.classify.seconds).sum(),
        distance_evals: iterations.iter().map(|i| i.classify.distance_evals).sum(),
        assignments: assign,
        distances: dist,
        models,
        init,
        initial_classification,
        iterations,
    })
}
