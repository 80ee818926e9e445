//! Wavelet-LPCA (seed 003 §4.5): LPCA on sparse wavelet images of transfer vectors. Each
//! iteration fits every cluster's affine subspace (its mean, and its leading directions by
//! EM-PCA on the sparse rows, started from the previous iteration's directions, §4.5.2.2)
//! and assigns every vector to its nearest subspace by Alg. 4's sparse distance. With every
//! coefficient kept it is LPCA on the transfer vectors themselves, turned by W (the proofs
//! after Alg. 4); a test checks the assignments against fenestra-lpca's.

use crate::empca::em_pca;
use crate::sparse::{classify_sorted, Packed, SparseVec};
use fenestra_lpca::{Schedule, Subspace};
use rayon::prelude::*;

/// A Wavelet-LPCA run.
#[derive(Clone, Debug)]
pub struct WlpcaOptions {
    /// Subspace dimensions and iterations at each (as LPCA's schedule).
    pub schedule: Schedule,
    /// EM iterations per fit, at most.
    pub em_iterations: usize,
    /// EM stops when the span moves by less than this.
    pub em_tolerance: f64,
}

/// Its result.
#[derive(Clone, Debug)]
pub struct Wlpca {
    /// Cluster of every vector.
    pub assignments: Vec<u32>,
    /// Squared distance of every vector to its subspace.
    pub distances2: Vec<f64>,
    /// The subspaces (in the wavelet basis).
    pub models: Vec<Subspace>,
}

impl Wlpca {
    /// Sum of squared distances over the sum of squared norms.
    pub fn relative_squared_error(&self, rows: &[SparseVec]) -> f64 {
        let energy: f64 = rows.iter().map(|r| r.norm2).sum();
        self.distances2.iter().sum::<f64>() / energy.max(f64::MIN_POSITIVE)
    }
}

/// Wavelet-LPCA of `rows` from the clusters seeded at the rows `centroids`.
pub fn wlpca(rows: &[SparseVec], centroids: &[usize], options: &WlpcaOptions) -> Wlpca {
    let mut models: Vec<Subspace> = centroids
        .iter()
        .map(|&i| Subspace::point(rows[i].to_dense()))
        .collect();
    let packed = |models: &[Subspace]| models.iter().map(Packed::new).collect::<Vec<_>>();
    // Every row starts from the first cluster; the pruning finds the nearest all the same.
    let (mut assignments, mut distances2) =
        classify_sorted(rows, &models, &packed(&models), &vec![0; rows.len()]);
    for &(dim, iterations) in &options.schedule.0 {
        for _ in 0..iterations {
            models = (0..models.len())
                .into_par_iter()
                .map(|c| fit(rows, &assignments, c as u32, &models[c], dim, options))
                .collect();
            (assignments, distances2) =
                classify_sorted(rows, &models, &packed(&models), &assignments);
        }
    }
    Wlpca {
        assignments,
        distances2,
        models,
    }
}

/// Cluster `c`'s subspace of dimension up to `dim` (at most its members less one): the mean
/// of its members and EM-PCA's directions, started from `previous`'s and, for new ones, from
/// the first members' centred rows. A cluster without members keeps `previous`.
fn fit(
    rows: &[SparseVec],
    assignments: &[u32],
    c: u32,
    previous: &Subspace,
    dim: usize,
    options: &WlpcaOptions,
) -> Subspace {
    let members: Vec<&SparseVec> = (rows.iter().zip(assignments))
        .filter(|(_, &a)| a == c)
        .map(|(r, _)| r)
        .collect();
    if members.is_empty() {
        return previous.clone();
    }
    // The members' coefficients lie on the union of their indices (in the relight room a
    // few hundred of 4,096), and so do their mean and principal directions: the fit runs
    // there and is spread back.
    let support = Support::of(&members, previous.mean.len());
    let local: Vec<SparseVec> = members.iter().map(|r| support.restrict(r)).collect();
    let local: Vec<&SparseVec> = local.iter().collect();
    let mut mean = vec![0.0; support.indices.len()];
    for r in &local {
        r.iter().for_each(|(i, v)| mean[i] += v);
    }
    mean.iter_mut().for_each(|m| *m /= members.len() as f64);
    let dim = dim.min(members.len() - 1);
    if dim == 0 {
        return Subspace::point(support.spread(&mean));
    }
    let rows_start = |start: &mut Vec<Vec<f64>>| {
        for r in &local {
            if start.len() == dim {
                break;
            }
            let mut v = r.to_dense();
            v.iter_mut().zip(&mean).for_each(|(a, m)| *a -= m);
            start.push(v);
        }
    };
    let mut start: Vec<Vec<f64>> = (previous.basis.iter().take(dim))
        .map(|e| support.gather(e))
        .collect();
    rows_start(&mut start);
    let fit = |start| {
        let (iterations, tolerance) = (options.em_iterations, options.em_tolerance);
        em_pca(&local, &mean, start, iterations, tolerance)
    };
    // The previous directions cut to the support may have become dependent: the members'
    // rows then.
    let principal = fit(start).or_else(|| {
        let mut start = Vec::new();
        rows_start(&mut start);
        fit(start)
    });
    Subspace {
        mean: support.spread(&mean),
        basis: principal.map_or(Vec::new(), |p| {
            p.directions.iter().map(|e| support.spread(e)).collect()
        }),
    }
}

/// The indices where some of a cluster's rows are not zero, and each index's place among
/// them.
struct Support {
    indices: Vec<u32>,
    place: Vec<u32>,
}

impl Support {
    fn of(rows: &[&SparseVec], d: usize) -> Self {
        let mut place = vec![u32::MAX; d];
        rows.iter()
            .for_each(|r| r.indices.iter().for_each(|&i| place[i as usize] = 0));
        let mut indices = Vec::new();
        for (i, p) in place.iter_mut().enumerate() {
            if *p == 0 {
                *p = indices.len() as u32;
                indices.push(i as u32);
            }
        }
        Support { indices, place }
    }

    /// `x` (non-zero only on the support) on the support's indices.
    fn restrict(&self, x: &SparseVec) -> SparseVec {
        SparseVec {
            len: self.indices.len(),
            indices: x.indices.iter().map(|&i| self.place[i as usize]).collect(),
            values: x.values.clone(),
            norm2: x.norm2,
        }
    }

    /// A dense vector's entries on the support.
    fn gather(&self, x: &[f64]) -> Vec<f64> {
        self.indices.iter().map(|&i| x[i as usize]).collect()
    }

    /// A vector on the support as a dense vector of the full length.
    fn spread(&self, x: &[f64]) -> Vec<f64> {
        let mut full = vec![0.0; self.place.len()];
        (self.indices.iter().zip(x)).for_each(|(&i, &v)| full[i as usize] = v);
        full
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::haar;
    use fenestra_core::Sampler;
    use fenestra_lpca::{init::Init, Algorithm, Dataset, Options};

    /// Transfer-like vectors: 4 groups, each a smooth mean plus 2 smooth directions (low
    /// frequencies, which Haar images hold in few coefficients), a little noise.
    fn vectors(n: usize, d: usize) -> Vec<Vec<f64>> {
        let mut s = Sampler::new(21, 0, 0);
        let mut r = || s.next_1d() as f64 * 2.0 - 1.0;
        let mut smooth = |amplitude: f64| -> Vec<f64> {
            let (f, phase) = (1.0 + 2.0 * r().abs(), 3.0 * r());
            (0..d)
                .map(|j| {
                    amplitude * (f * j as f64 / d as f64 * std::f64::consts::TAU + phase).sin()
                })
                .collect()
        };
        let groups: Vec<(Vec<f64>, Vec<Vec<f64>>)> = (0..4)
            .map(|_| (smooth(3.0), vec![smooth(1.0), smooth(1.0)]))
            .collect();
        (0..n)
            .map(|i| {
                let (mean, dirs) = &groups[i % 4];
                let (a, b) = (2.0 * r(), r());
                (0..d)
                    .map(|j| mean[j] + a * dirs[0][j] + b * dirs[1][j] + 0.05 * r())
                    .collect()
            })
            .collect()
    }

    #[test]
    fn with_every_coefficient_kept_it_is_lpca() {
        let (n, d) = (400, 32);
        let x = vectors(n, d);
        let mut scratch = vec![0.0; d];
        let rows: Vec<SparseVec> = x
            .iter()
            .map(|v| {
                let mut w = v.clone();
                haar::forward(&mut w, &mut scratch);
                SparseVec::largest(&w, d)
            })
            .collect();
        let flat: Vec<f32> = x.iter().flatten().map(|&v| v as f32).collect();
        let data = Dataset::new(n, d, flat).expect("data");
        let schedule = Schedule::parse("0:3,1:3,2:4").expect("schedule");
        let options = Options {
            clusters: 4,
            schedule: schedule.clone(),
            algorithm: Algorithm::Lpca,
            init: Init::Random,
            seed: 3,
        };
        let lpca = fenestra_lpca::run(&data, &options).expect("lpca");
        let w = wlpca(
            &rows,
            &lpca.init.centroids,
            &WlpcaOptions {
                schedule,
                em_iterations: 500,
                em_tolerance: 1e-10,
            },
        );
        assert_eq!(w.assignments, lpca.assignments, "the same clusters");
        let dense = lpca.relative_squared_error;
        let sparse = w.relative_squared_error(&rows);
        assert!((sparse - dense).abs() < 1e-4 * dense, "{sparse} vs {dense}");
        // Keeping a quarter of the coefficients of these smooth vectors costs a little
        // accuracy, not the clustering.
        let quarter: Vec<SparseVec> = rows
            .iter()
            .map(|r| SparseVec::largest(&r.to_dense(), d / 4))
            .collect();
        let q = wlpca(
            &quarter,
            &lpca.init.centroids,
            &WlpcaOptions {
                schedule: Schedule::parse("0:3,1:3,2:4").expect("schedule"),
                em_iterations: 200,
                em_tolerance: 1e-8,
            },
        );
        let agree = q
            .assignments
            .iter()
            .zip(&lpca.assignments)
            .filter(|(a, b)| a == b)
            .count();
        assert!(agree as f64 > 0.95 * n as f64, "{agree} of {n} agree");
    }
}
