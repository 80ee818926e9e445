//! Where a frame's reconstructed transfer is likely wrong, judged by the light of the
//! scene's own lights (beyond the seed). Reconstruction (eq. 4.5) and LPCA both fail on the
//! rare pixel whose transfer is unlike its neighbours' and its cluster's: the floor in a
//! contact shadow relit like the lit floor beside it, a ceiling strip beside a wall relit
//! dark. Such pixels are few (about half of a frame's relative squared error lies in 1% of
//! its pixels) and stand out in light: much darker or brighter than the average of the
//! explored samples they were made from. The precomputation evaluates the worst of them and
//! keeps their transfer uncompressed (`FrameTransfer::precompute`); the measurements, under
//! the scene's lights and under moved ones, are in docs/relight.md.

use crate::gather::Gather;
use crate::haar;
use crate::sparse::SparseVec;
use crate::transfer::radiosity;
use fenestra_lpca::Subspace;
use fenestra_render::RenderScene;

/// Light samples per gather sample for the radiosity the check is made with.
const RADIOSITY_SAMPLES: u32 = 64;

/// The luminance of one bounce under the scene's lights, for explored rows and cluster
/// subspaces, in the wavelet domain (<x, B> = <Wx, WB>).
pub struct LightCheck {
    /// Each explored row's light.
    rows: Vec<f64>,
    /// Each cluster's mean's light, then its directions'.
    clusters: Vec<Vec<f64>>,
    /// Lights are compared relative to theirs plus this: a hundredth of the rows' mean, so
    /// that nearly black pixels do not count as departing by their noise.
    floor: f64,
}

impl LightCheck {
    /// The check for `rows` (explored transfer, sparse wavelet images) and `models` (the
    /// clusters) over `gather` in `scene` under its own lights.
    pub fn new(
        scene: &RenderScene,
        gather: &Gather,
        rows: &[SparseVec],
        models: &[Subspace],
        seed: u64,
    ) -> Self {
        let n = haar::padded_len(gather.samples.len());
        let mut b: Vec<f64> = (radiosity(scene, gather, RADIOSITY_SAMPLES, seed).iter())
            .map(|c| c.luminance() as f64)
            .collect();
        b.resize(n, 0.0);
        haar::forward(&mut b, &mut vec![0.0; n]);
        Self::with_radiosity(b, rows, models)
    }

    /// The check with `radiosity` (wavelet domain, the padded length) given.
    fn with_radiosity(radiosity: Vec<f64>, rows: &[SparseVec], models: &[Subspace]) -> Self {
        let dot = |x: &[f64]| x.iter().zip(&radiosity).map(|(p, q)| p * q).sum::<f64>();
        let rows: Vec<f64> = rows.iter().map(|x| x.dot(&radiosity)).collect();
        let mean = rows.iter().map(|l| l.abs()).sum::<f64>() / rows.len().max(1) as f64;
        LightCheck {
            clusters: (models.iter())
                .map(|a| {
                    std::iter::once(&a.mean)
                        .chain(&a.basis)
                        .map(|v| dot(v))
                        .collect()
                })
                .collect(),
            rows,
            floor: (0.01 * mean).max(f64::MIN_POSITIVE),
        }
    }

    /// The light of the vector with `coordinates` in cluster `c`.
    fn compressed(&self, c: u32, coordinates: &[f32]) -> f64 {
        let l = &self.clusters[c as usize];
        l[0] + (l[1..].iter().zip(coordinates))
            .map(|(e, &w)| e * w as f64)
            .sum::<f64>()
    }

    /// How far the light of the reconstructed pixel with `coordinates` in cluster `c`
    /// departs from the mean of its explored neighbours' `rows`, relative to that mean.
    pub fn departure(
        &self,
        c: u32,
        coordinates: &[f32],
        rows: impl ExactSizeIterator<Item = u32>,
    ) -> f64 {
        let k = rows.len().max(1) as f64;
        let around = rows.map(|r| self.rows[r as usize]).sum::<f64>() / k;
        (self.compressed(c, coordinates) - around).abs() / (around.abs() + self.floor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sparse(dense: &[f64]) -> SparseVec {
        SparseVec::largest(dense, dense.len())
    }

    #[test]
    fn departures_are_relative_light_differences() {
        // Radiosity (1, 2, 0, 0); rows of light 1, 3 and 10 (their mean makes the floor);
        // one cluster: mean (1, 0, 0, 0), one direction (0, 1, 0, 0).
        let rows = [
            sparse(&[1.0, 0.0, 0.0, 0.0]),
            sparse(&[1.0, 1.0, 0.0, 0.0]),
            sparse(&[0.0, 5.0, 0.0, 0.0]),
        ];
        let model = Subspace {
            mean: vec![1.0, 0.0, 0.0, 0.0],
            basis: vec![vec![0.0, 1.0, 0.0, 0.0]],
        };
        let check = LightCheck::with_radiosity(vec![1.0, 2.0, 0.0, 0.0], &rows, &[model]);
        let floor = 0.01 * (1.0 + 3.0 + 10.0) / 3.0;
        // Coordinates 0.5: light 1 + 2 * 0.5 = 2, the mean of rows 0 and 1: no departure.
        assert!(check.departure(0, &[0.5], [0, 1].into_iter()).abs() < 1e-12);
        // Light 1 (coordinates 0) against rows 1 and 2's mean of 6.5.
        let d = check.departure(0, &[0.0], [1, 2].into_iter());
        assert!((d - 5.5 / (6.5 + floor)).abs() < 1e-12, "{d}");
        // Brighter by as much: the same departure.
        let d = check.departure(0, &[4.0], [1, 2].into_iter());
        assert!((d - 2.5 / (6.5 + floor)).abs() < 1e-12, "{d}");
    }
}
