//! Seeding the clusters (§3.5): uniform random, distance-sum, k-means++ and SortMeans++
//! (§3.5.1), which skips point-centroid distances with the triangle inequality and returns
//! exactly what k-means++ returns for the same random stream.

use crate::data::Dataset;
use crate::subspace::Subspace;
use fenestra_core::Rng;
use rayon::prelude::*;
use std::time::Instant;

/// How the initial clusters are chosen (seed 003 §3.5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum Init {
    /// k distinct random points.
    Random,
    /// The points of largest distance sum to the chosen ones.
    DistanceSum,
    /// k-means++ (Arthur and Vassilvitskii 2007).
    KmeansPlusPlus,
    /// k-means++ with SortMeans' pruning (seed 003 Alg. 3): the default.
    #[default]
    SortMeansPlusPlus,
}

impl std::fmt::Display for Init {
    /// As [`str::parse`] reads it.
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            Init::Random => "random",
            Init::DistanceSum => "distance-sum",
            Init::KmeansPlusPlus => "kmeans++",
            Init::SortMeansPlusPlus => "sortmeans++",
        })
    }
}

impl std::str::FromStr for Init {
    type Err = fenestra_core::UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "random" => Ok(Init::Random),
            "distance-sum" => Ok(Init::DistanceSum),
            "kmeans++" => Ok(Init::KmeansPlusPlus),
            "sortmeans++" => Ok(Init::SortMeansPlusPlus),
            _ => Err(fenestra_core::UnknownName::new(
                "initialisation",
                s,
                "random, distance-sum, kmeans++ or sortmeans++",
            )),
        }
    }
}

/// The initial centroids and what choosing them cost.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Seeding {
    /// Data indices of the initial centroids.
    pub centroids: Vec<usize>,
    /// Nearest centroid of every point and the distance to it (k-means++ and SortMeans++
    /// produce it as they go).
    #[serde(skip)]
    pub assignment: Option<(Vec<u32>, Vec<f64>)>,
    /// Point-centroid distances evaluated.
    pub distance_evals: u64,
    /// Seconds taken.
    pub seconds: f64,
}

fn centroid(data: &Dataset, i: usize) -> Subspace {
    Subspace::point(data.row(i).iter().map(|&v| v as f64).collect())
}

/// Chooses k distinct data points as initial centroids.
pub fn seed(data: &Dataset, k: usize, init: Init, seed: u64) -> Seeding {
    let start = Instant::now();
    let mut rng = Rng::new(seed);
    let mut s = match init {
        Init::Random => {
            let mut idx: Vec<usize> = (0..data.n).collect();
            for i in 0..k {
                let j = i + rng.below(data.n - i);
                idx.swap(i, j);
            }
            idx.truncate(k);
            Seeding {
                centroids: idx,
                assignment: None,
                distance_evals: 0,
                seconds: 0.0,
            }
        }
        Init::DistanceSum => {
            // alpha_i = sum_x |x - x_i|^2 = n |x_i|^2 - 2 <x_i, sum x> + sum |x|^2, in O(n d).
            let mut sum = vec![0.0f64; data.d];
            for i in 0..data.n {
                sum.iter_mut()
                    .zip(data.row(i))
                    .for_each(|(s, &v)| *s += v as f64);
            }
            let total = data.total_energy();
            let n = data.n as f64;
            let mut w: Vec<f64> = (0..data.n)
                .into_par_iter()
                .map(|i| {
                    let x = data.row(i);
                    let xx: f64 = x.iter().map(|&v| v as f64 * v as f64).sum();
                    (n * xx - 2.0 * crate::kernels::dot_f32_f64(x, &sum) + total).max(0.0)
                })
                .collect();
            let mut centroids = Vec::with_capacity(k);
            for _ in 0..k {
                let i = rng.weighted(&w);
                w[i] = 0.0;
                centroids.push(i);
            }
            Seeding {
                centroids,
                assignment: None,
                distance_evals: 0,
                seconds: 0.0,
            }
        }
        Init::KmeansPlusPlus | Init::SortMeansPlusPlus => {
            plus_plus(data, k, &mut rng, init == Init::SortMeansPlusPlus)
        }
    };
    s.seconds = start.elapsed().as_secs_f64();
    s
}

/// k-means++ (Arthur and Vassilvitskii: new centroids drawn with probability proportional to
/// the squared distance to the nearest chosen one) and, with `sorted`, SortMeans++.
fn plus_plus(data: &Dataset, k: usize, rng: &mut Rng, sorted: bool) -> Seeding {
    let first = rng.below(data.n);
    let mut centres = vec![centroid(data, first)];
    let mut centroids = vec![first];
    let mut near: Vec<(u32, f64)> = (0..data.n)
        .into_par_iter()
        .map_init(
            || vec![0.0; data.d],
            |s, i| (0, centres[0].distance(data.row(i), s)),
        )
        .collect();
    let mut evals = data.n as u64;
    while centroids.len() < k {
        let weights: Vec<f64> = near.iter().map(|(_, d)| d * d).collect();
        let new = rng.weighted(&weights);
        let c = centroid(data, new);
        let j = centres.len() as u32;
        // Step 2 of §3.5.1: distances from the new centroid to the existing ones.
        let d_new: Vec<f64> = if sorted {
            evals += centres.len() as u64;
            let mut s = vec![0.0; data.d];
            centres
                .iter()
                .map(|m| {
                    c.distance(
                        &m.mean.iter().map(|&v| v as f32).collect::<Vec<_>>(),
                        &mut s,
                    )
                })
                .collect()
        } else {
            Vec::new()
        };
        // Step 3: a point whose centroid is at least twice its distance from the new one
        // cannot move to it (triangle inequality); the margin covers rounding.
        let computed: u64 = near
            .par_iter_mut()
            .enumerate()
            .map_init(
                || vec![0.0; data.d],
                |s, (i, (a, d))| {
                    if sorted {
                        let dn = d_new[*a as usize];
                        if dn - 2.0 * *d > 1e-9 * (dn + *d) {
                            return 0;
                        }
                    }
                    let dist = c.distance(data.row(i), s);
                    if dist < *d {
                        *d = dist;
                        *a = j;
                    }
                    1
                },
            )
            .sum();
        evals += computed;
        centres.push(c);
        centroids.push(new);
    }
    let (a, d) = near.into_iter().unzip();
    Seeding {
        centroids,
        assignment: Some((a, d)),
        distance_evals: evals,
        seconds: 0.0,
    }
}
