//! Synthetic data with known local-linear structure, for tests and for the BTF experiment of
//! §3.6.2 when no measured BTF is at hand.

use crate::data::Dataset;
use fenestra_core::Rng;

/// A standard normal number (Box-Muller).
fn normal(rng: &mut Rng) -> f64 {
    let u1 = rng.next_f64().max(1e-300);
    let u2 = rng.next_f64();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// `n` points near `clusters` random affine subspaces of dimension `dim` in R^`d`, with
/// isotropic noise of standard deviation `noise`; points of a cluster are contiguous.
pub fn subspace_mixture(
    n: usize,
    d: usize,
    clusters: usize,
    dim: usize,
    noise: f64,
    seed: u64,
) -> Dataset {
    let mut rng = Rng::new(seed);
    let models: Vec<(Vec<f64>, Vec<Vec<f64>>)> = (0..clusters)
        .map(|_| {
            let mean = (0..d).map(|_| normal(&mut rng) * 3.0).collect();
            let basis = (0..dim)
                .map(|_| (0..d).map(|_| normal(&mut rng)).collect())
                .collect();
            (mean, basis)
        })
        .collect();
    let mut values = Vec::with_capacity(n * d);
    for i in 0..n {
        let (mean, basis) = &models[i * clusters / n];
        let mut x = mean.clone();
        for e in basis {
            let c = normal(&mut rng);
            x.iter_mut().zip(e).for_each(|(xi, ei)| *xi += c * ei);
        }
        values.extend(x.iter().map(|&v| (v + noise * normal(&mut rng)) as f32));
    }
    Dataset { n, d, values }
}

/// A BTF in the apparent-BRDF arrangement (§3.6.2): one row per texel of a `size` x `size`
/// texture, holding its reflectance over `views` x `lights` direction pairs. The texture is a
/// patchwork of `materials` materials; each material's apparent BRDFs vary within a `dim`-
/// dimensional family of smooth lobes (mean lobe plus `dim` perturbations with decaying
/// weights), plus measurement noise.
pub fn btf_like(
    size: usize,
    views: usize,
    lights: usize,
    materials: usize,
    dim: usize,
    noise: f64,
    seed: u64,
) -> Dataset {
    let mut rng = Rng::new(seed);
    let d = views * lights;
    // A lobe over the (view, light) grid: a Gaussian around a random (view, light) centre,
    // as a specular highlight moves with both directions.
    let lobe = |rng: &mut Rng, width: f64| -> Vec<f64> {
        let (cv, cl) = (rng.next_f64(), rng.next_f64());
        let w = width * (0.5 + rng.next_f64());
        (0..d)
            .map(|i| {
                let (v, l) = (
                    (i / lights) as f64 / views as f64,
                    (i % lights) as f64 / lights as f64,
                );
                (-((v - cv).powi(2) + (l - cl).powi(2)) / (2.0 * w * w)).exp()
            })
            .collect()
    };
    let families: Vec<(Vec<f64>, Vec<Vec<f64>>)> = (0..materials)
        .map(|_| {
            let base = 0.1 + 0.4 * rng.next_f64();
            let mean: Vec<f64> = lobe(&mut rng, 0.15).iter().map(|v| base + v).collect();
            let basis = (0..dim).map(|_| lobe(&mut rng, 0.1)).collect();
            (mean, basis)
        })
        .collect();
    // Patchwork: each texel takes the material of the nearest of `materials` random sites.
    let sites: Vec<(f64, f64)> = (0..materials)
        .map(|_| (rng.next_f64(), rng.next_f64()))
        .collect();
    let mut values = Vec::with_capacity(size * size * d);
    for t in 0..size * size {
        let (x, y) = (
            (t % size) as f64 / size as f64,
            (t / size) as f64 / size as f64,
        );
        let m = (0..materials)
            .min_by(|&a, &b| {
                let da = (sites[a].0 - x).powi(2) + (sites[a].1 - y).powi(2);
                let db = (sites[b].0 - x).powi(2) + (sites[b].1 - y).powi(2);
                da.total_cmp(&db)
            })
            .unwrap_or(0);
        let (mean, basis) = &families[m];
        let mut row = mean.clone();
        for (j, e) in basis.iter().enumerate() {
            let c = normal(&mut rng) * 0.3 / (1.0 + j as f64);
            row.iter_mut().zip(e).for_each(|(r, ei)| *r += c * ei);
        }
        values.extend(row.iter().map(|&v| (v + noise * normal(&mut rng)) as f32));
    }
    Dataset {
        n: size * size,
        d,
        values,
    }
}
