//! Sparse wavelet images of transfer vectors and the classification distance of Wavelet-LPCA
//! (seed 003 §4.5.1.2, Alg. 4): for an affine subspace a = (mu, V),
//! d^2(x, a) = |x|^2 - 2 x . mu + |mu|^2 - |V^T x - V^T mu|^2 (eq. 4.3-4.4), where x enters
//! only through products with its few non-zero coefficients, and |mu|^2 and V^T mu are
//! computed once per subspace.

use fenestra_lpca::Subspace;

/// A vector of dimension `len` with `values` at `indices` (ascending) and zeros elsewhere.
#[derive(Clone, Debug, PartialEq)]
pub struct SparseVec {
    /// Dimension.
    pub len: usize,
    /// Where the non-zero coefficients are, ascending.
    pub indices: Vec<u32>,
    /// Their values.
    pub values: Vec<f64>,
    /// |x|^2 (kept: it does not change during LPCA).
    pub norm2: f64,
}

impl SparseVec {
    /// The `keep` coefficients of `dense` largest in magnitude (ties to the lower index).
    pub fn largest(dense: &[f64], keep: usize) -> Self {
        let mut order: Vec<u32> = (0..dense.len() as u32).collect();
        if keep < dense.len() {
            order.select_nth_unstable_by(keep, |&a, &b| {
                dense[b as usize]
                    .abs()
                    .total_cmp(&dense[a as usize].abs())
                    .then(a.cmp(&b))
            });
            order.truncate(keep);
        }
        order.sort_unstable();
        order.retain(|&i| dense[i as usize] != 0.0);
        let values: Vec<f64> = order.iter().map(|&i| dense[i as usize]).collect();
        SparseVec {
            len: dense.len(),
            norm2: values.iter().map(|v| v * v).sum(),
            indices: order,
            values,
        }
    }

    /// Its non-zero coefficients as (index, value).
    pub fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (self.indices.iter().map(|&i| i as usize)).zip(self.values.iter().copied())
    }

    /// x . y for a dense y.
    pub fn dot(&self, y: &[f64]) -> f64 {
        let mut out = [0.0];
        interleaved_products(y, self, &mut out);
        out[0]
    }

    /// The dense vector.
    pub fn to_dense(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.len];
        self.iter().for_each(|(i, v)| d[i] = v);
        d
    }
}

/// An affine subspace a = (mu, V) laid out for Alg. 4 over many sparse rows: coefficient i
/// of the mean and of every direction side by side ([mu_i, e1_i, ..., el_i]), so that a row's
/// products with all of them read one short run of memory per non-zero coefficient instead
/// of 1 + l scattered ones; with |mu|^2 and V^T mu, computed once.
#[derive(Clone, Debug)]
pub struct Packed {
    /// 1 + l.
    width: usize,
    /// The interleaved coefficients, d x (1 + l) row-major.
    data: Vec<f64>,
    /// |mu|^2.
    mean2: f64,
    /// V^T mu.
    basis_mean: Vec<f64>,
}

impl Packed {
    /// The layout and terms of `a`.
    pub fn new(a: &Subspace) -> Self {
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
        let width = 1 + a.basis.len();
        let mut data = Vec::with_capacity(a.mean.len() * width);
        for i in 0..a.mean.len() {
            data.push(a.mean[i]);
            data.extend(a.basis.iter().map(|e| e[i]));
        }
        Packed {
            width,
            data,
            mean2: dot(&a.mean, &a.mean),
            basis_mean: a.basis.iter().map(|e| dot(e, &a.mean)).collect(),
        }
    }

    /// x . mu and V^T x into `products` (resized to 1 + l).
    pub fn products(&self, x: &SparseVec, products: &mut Vec<f64>) {
        products.resize(self.width, 0.0);
        interleaved_products(&self.data, x, products);
    }

    /// Eq. 4.3-4.4: the squared distance of `x` to the subspace (`products`: scratch).
    pub fn distance2(&self, x: &SparseVec, products: &mut Vec<f64>) -> f64 {
        self.products(x, products);
        (x.norm2 + self.excess(products)).max(0.0)
    }

    /// d^2(x, a) - |x|^2 from x's [`Packed::products`]: what orders subspaces by their
    /// distance from x (linear in them but for the square of V^T x).
    pub fn excess(&self, products: &[f64]) -> f64 {
        let z: f64 = (products[1..].iter().zip(&self.basis_mean))
            .map(|(&p, &em)| (p - em) * (p - em))
            .sum();
        self.mean2 - 2.0 * products[0] - z
    }

    /// The coordinates V^T (x - mu) in the subspace of x with [`Packed::products`] `products`.
    pub fn coordinates(&self, products: &[f64]) -> Vec<f32> {
        (products[1..].iter().zip(&self.basis_mean))
            .map(|(&p, &em)| (p - em) as f32)
            .collect()
    }
}

/// The products of `x` with `out.len()` vectors stored interleaved in `data` (coefficient
/// i of vector j at `data[i * out.len() + j]`): `out[j]` = sum over x's coefficients (i, v)
/// of v * data[i * out.len() + j]. The sums are kept in registers, up to 16 at a time (summed
/// in memory, each coefficient waited for the store of the one before: half of Alg. 4's
/// time), and for a few vectors in several partial sums (coefficient k in sum k mod L, added
/// up in order at the end), so that one addition does not wait for the last.
pub fn interleaved_products(data: &[f64], x: &SparseVec, out: &mut [f64]) {
    let stride = out.len();
    for (block, out) in out.chunks_mut(16).enumerate() {
        let start = block * 16;
        macro_rules! widths {
            ($($w:literal / $l:literal)*) => {
                match out.len() {
                    $($w => register_sums::<$w, $l>(data, stride, start, x, out),)*
                    _ => unreachable!("chunks of at most 16"),
                }
            };
        }
        widths!(1/4 2/2 3/2 4/2 5/1 6/1 7/1 8/1 9/1 10/1 11/1 12/1 13/1 14/1 15/1 16/1);
    }
}

/// [`interleaved_products`] for the `W` vectors from `start` on, in `L` partial sums each.
#[inline]
fn register_sums<const W: usize, const L: usize>(
    data: &[f64],
    stride: usize,
    start: usize,
    x: &SparseVec,
    out: &mut [f64],
) {
    let column = |i: u32| -> &[f64; W] {
        (data[i as usize * stride + start..][..W])
            .try_into()
            .expect("W entries")
    };
    let mut sums = [[0.0f64; W]; L];
    let (indices, values) = (x.indices.chunks_exact(L), x.values.chunks_exact(L));
    let (rest_indices, rest_values) = (indices.remainder(), values.remainder());
    for (is, vs) in indices.zip(values) {
        for l in 0..L {
            for (s, &c) in sums[l].iter_mut().zip(column(is[l])) {
                *s += vs[l] * c;
            }
        }
    }
    for (&i, &v) in rest_indices.iter().zip(rest_values) {
        for (s, &c) in sums[0].iter_mut().zip(column(i)) {
            *s += v * c;
        }
    }
    for (j, o) in out.iter_mut().enumerate() {
        *o = sums.iter().map(|lane| lane[j]).sum();
    }
}

/// Alg. 4 with SortCluster-LPCA's pruning (seed 003 Alg. 2, from fenestra-lpca): each row
/// starts at its `previous` cluster and visits the others in order of their distance from it
/// (D, a lower bound on subspace distances), stopping when the triangle inequality
/// d(x, a_j) >= D_ij - d(x, a_i) proves no farther one nearer. The same assignments and
/// distances as the exhaustive search (the first of equals), which a test checks.
pub fn classify_sorted(
    rows: &[SparseVec],
    models: &[Subspace],
    a: &[Packed],
    previous: &[u32],
) -> (Vec<u32>, Vec<f64>) {
    use rayon::prelude::*;
    let neighbours = fenestra_lpca::classify::sorted_neighbours(models);
    let mean_norm = a.iter().map(|p| p.mean2.sqrt()).fold(0.0, f64::max);
    (rows.par_iter().zip(previous))
        .map_init(Vec::new, |products, (x, &i)| {
            let d2 = a[i as usize].distance2(x, products);
            let d_i = d2.sqrt();
            // Distances come from an expanded square (eq. 4.4): each is accurate to about
            // 1e-7 of |x| + |mu|, so the pruning keeps a margin far above that.
            let margin = 1e-5 * (x.norm2.sqrt() + mean_norm);
            let mut best = (i, d2);
            for &(dij, j) in &neighbours[i as usize] {
                if dij - (d_i + best.1.sqrt()) > margin {
                    break;
                }
                let dj = a[j as usize].distance2(x, products);
                if dj < best.1 || (dj == best.1 && j < best.0) {
                    best = (j, dj);
                }
            }
            best
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::haar;
    use fenestra_core::Sampler;

    /// A random affine subspace of dimension `l` in `d` dimensions (orthonormal basis).
    fn subspace(d: usize, l: usize, seed: u64) -> Subspace {
        let mut s = Sampler::new(seed, 1, 0);
        let mut r = || s.next_1d() as f64 - 0.5;
        let mean: Vec<f64> = (0..d).map(|_| r()).collect();
        let mut basis: Vec<Vec<f64>> = Vec::new();
        while basis.len() < l {
            let mut v: Vec<f64> = (0..d).map(|_| r()).collect();
            for e in &basis {
                let c: f64 = v.iter().zip(e).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(e).for_each(|(a, b)| *a -= c * b);
            }
            let n = v.iter().map(|a| a * a).sum::<f64>().sqrt();
            basis.push(v.into_iter().map(|a| a / n).collect());
        }
        Subspace { mean, basis }
    }

    #[test]
    fn interleaved_products_are_the_dot_products_at_every_width() {
        let d = 64;
        let mut s = Sampler::new(8, 0, 0);
        let mut r = || s.next_1d() as f64 * 2.0 - 1.0;
        let dense: Vec<f64> = (0..d).map(|_| r()).collect();
        // 23 coefficients: partial sums of 2 and 4 leave some over.
        let x = SparseVec::largest(&dense, 23);
        // Widths with partial sums, within one block of sums, at its edge, spanning two.
        for width in [1, 2, 3, 5, 9, 16, 17, 25, 40] {
            let vectors: Vec<Vec<f64>> =
                (0..width).map(|_| (0..d).map(|_| r()).collect()).collect();
            let data: Vec<f64> = (0..d)
                .flat_map(|i| vectors.iter().map(move |v| v[i]))
                .collect();
            let mut out = vec![f64::NAN; width];
            interleaved_products(&data, &x, &mut out);
            for (j, v) in vectors.iter().enumerate() {
                let want: f64 = x.iter().map(|(i, c)| c * v[i]).sum();
                let close = (out[j] - want).abs() <= 1e-12 * want.abs().max(1.0);
                assert!(close, "width {width}, vector {j}: {} vs {want}", out[j]);
            }
        }
    }

    #[test]
    fn the_sparse_distance_equals_the_dense_one_and_survives_the_transform() {
        let (d, l) = (128, 4);
        let a = subspace(d, l, 5);
        let packed = Packed::new(&a);
        let mut products = Vec::new();
        let mut s = Sampler::new(6, 2, 0);
        let mut scratch = vec![0.0; d];
        let mut dense_scratch = vec![0.0f64; d];
        for keep in [1, 9, 40, 128] {
            let x: Vec<f64> = (0..d).map(|_| s.next_1d() as f64 * 2.0 - 1.0).collect();
            let sparse = SparseVec::largest(&x, keep);
            let dense: Vec<f32> = sparse.to_dense().iter().map(|&v| v as f32).collect();
            let want = a.distance(&dense, &mut dense_scratch).powi(2);
            let got = packed.distance2(&sparse, &mut products);
            assert!(
                (got - want).abs() < 1e-5 * want.max(1.0),
                "keep {keep}: {got} vs {want}"
            );
            // In wavelets: x and a transformed by W are as far apart (eq. 4.3's invariance).
            let mut wx = x.clone();
            haar::forward(&mut wx, &mut scratch);
            let mut wa = a.clone();
            haar::forward(&mut wa.mean, &mut scratch);
            wa.basis
                .iter_mut()
                .for_each(|e| haar::forward(e, &mut scratch));
            let full = SparseVec::largest(&wx, d);
            let plain: Vec<f32> = x.iter().map(|&v| v as f32).collect();
            let original = a.distance(&plain, &mut dense_scratch).powi(2);
            let transformed = Packed::new(&wa).distance2(&full, &mut products);
            assert!((original - transformed).abs() < 1e-5 * original.max(1.0));
        }
    }

    /// Alg. 4 by exhaustive search: each row's nearest subspace (the first of equals).
    fn classify(rows: &[SparseVec], a: &[Packed]) -> (Vec<u32>, Vec<f64>) {
        let mut products = Vec::new();
        (rows.iter())
            .map(|x| {
                let mut best = (0u32, f64::INFINITY);
                for (c, s) in a.iter().enumerate() {
                    let d = s.distance2(x, &mut products);
                    if d < best.1 {
                        best = (c as u32, d);
                    }
                }
                best
            })
            .unzip()
    }

    #[test]
    fn pruned_classification_equals_the_exhaustive_one() {
        // 16 subspaces of dimension 3 around four centres; rows near them, sparsified.
        let (d, k) = (64, 16);
        let mut models: Vec<Subspace> = (0..k).map(|c| subspace(d, 3, 40 + c as u64)).collect();
        for (c, m) in models.iter_mut().enumerate() {
            m.mean.iter_mut().for_each(|v| *v += 4.0 * (c % 4) as f64);
        }
        let packed: Vec<Packed> = models.iter().map(Packed::new).collect();
        let mut s = Sampler::new(9, 3, 0);
        let rows: Vec<SparseVec> = (0..500)
            .map(|r| {
                let m = &models[(r * 7) % k];
                let x: Vec<f64> = (0..d)
                    .map(|i| m.mean[i] + 2.0 * m.basis[0][i] + (s.next_1d() as f64 - 0.5))
                    .collect();
                SparseVec::largest(&x, 24 + r % 40)
            })
            .collect();
        let (full, full_d2) = classify(&rows, &packed);
        // Starting from any cluster (the right one, or a far one) finds the same.
        for shift in [0, 1, 5] {
            let previous: Vec<u32> = full.iter().map(|&c| (c + shift) % k as u32).collect();
            let (sorted, sorted_d2) = classify_sorted(&rows, &models, &packed, &previous);
            assert_eq!(sorted, full, "start shifted by {shift}");
            assert_eq!(sorted_d2, full_d2);
        }
    }

    #[test]
    fn the_largest_coefficients_are_kept() {
        let x = [0.5, -3.0, 0.0, 2.0, -0.1, 2.0];
        let s = SparseVec::largest(&x, 3);
        assert_eq!(s.indices, vec![1, 3, 5]);
        assert_eq!(s.values, vec![-3.0, 2.0, 2.0]);
        assert!((s.norm2 - 17.0).abs() < 1e-12);
        assert_eq!(SparseVec::largest(&x, 10).indices, vec![0, 1, 3, 4, 5]);
    }
}
