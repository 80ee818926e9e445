//! Transfer vectors at view samples the exploration did not evaluate (seed 003 §4.5.3,
//! eq. 4.5): a combination sum alpha_r x_r of the sparse wavelet images of nearby explored
//! samples, the weights alpha fitted by least squares to the new sample's transfer at a few
//! element indices I (|I| >= k), which are cheap to evaluate (eq. 4.1 for single gather
//! samples). The seed reads the neighbours' elements at I from their sparse images; here
//! their whole signals are inverse-transformed once and kept ([`Signals`]), since the next
//! pixels mostly have the same neighbours and need their elements too. The combination
//! itself is never formed: what a pixel keeps, its subspace coordinates, and what picks its
//! cluster are linear in it, so they are the same combination of the neighbours' products
//! with the subspace, which are kept with their signals.

use crate::haar;
use crate::sparse::{Packed, SparseVec};

/// The weights of eq. 4.5's combination of `signals` (the neighbours' transfer, inverse
/// transforms of their sparse wavelet images) that fits `values` at `indices` by least
/// squares, or their average where the elements at `indices` say nothing about the weights;
/// `None` when there are fewer indices than neighbours. `ridge` > 0 pulls the weights
/// towards the neighbours' average (1 / k each) with that weight relative to the system's
/// mean squared column norm: a few elements of spiky transfer vectors otherwise buy a fit
/// with large weights of opposite signs that is wrong everywhere else.
pub fn reconstruct(
    signals: &[&[f64]],
    indices: &[usize],
    values: &[f64],
    ridge: f64,
) -> Option<Vec<f64>> {
    let k = signals.len();
    if k == 0 || indices.len() < k || indices.len() != values.len() {
        return None;
    }
    // The |I| x k system, row-major: column r holds neighbour r's elements at I.
    let a: Vec<f64> = (0..indices.len() * k)
        .map(|e| signals[e % k][indices[e / k]])
        .collect();
    // (A^T A + lambda I) alpha = A^T b + lambda / k by Cholesky: k is a handful, and the
    // ridge (at least 1e-12 of the columns' scale, so that dependent neighbours share their
    // weight instead of failing) keeps the system positive definite.
    let norm2 = (0..k)
        .map(|r| {
            (0..indices.len())
                .map(|i| a[i * k + r].powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        / k as f64;
    let average = vec![1.0 / k as f64; k];
    let lambda = ridge.max(1e-12) * norm2;
    let mut m = vec![0.0; k * k];
    let mut rhs = vec![lambda / k as f64; k];
    for i in 0..indices.len() {
        let row = &a[i * k..(i + 1) * k];
        for r in 0..k {
            rhs[r] += row[r] * values[i];
            for c in 0..=r {
                m[r * k + c] += row[r] * row[c];
            }
        }
    }
    for r in 0..k {
        m[r * k + r] += lambda;
    }
    // Neighbours that are all zero at I (a pixel in shadow where they are lit) say nothing
    // about the weights: their average then.
    if norm2 > 0.0 {
        Some(non_negative(&m, &rhs, k).unwrap_or(average))
    } else {
        Some(average)
    }
}

/// The signals (inverse transforms) of explored samples' transfer, made on demand and kept
/// for the next pixels, the least recently used replaced; with each, the running sum of its
/// magnitude over the first `elements` entries (the gather samples), to draw elements where
/// the transfer is.
pub struct Signals {
    slots: Vec<Slot>,
    capacity: usize,
    elements: usize,
    clock: u64,
    scratch: Vec<f64>,
}

struct Slot {
    row: u32,
    signal: Vec<f64>,
    /// cumulative[j] = sum of |signal| over entries before j + 1.
    cumulative: Vec<f64>,
    /// The row's products with subspaces asked for ([`Packed::products`]), by cluster.
    products: Vec<(u32, Vec<f64>)>,
    used: u64,
}

impl Signals {
    /// Room for `capacity` signals (more than the neighbours a pixel asks for at once), of
    /// which the first `elements` entries can be drawn.
    pub fn new(capacity: usize, elements: usize) -> Self {
        Signals {
            slots: Vec::new(),
            capacity,
            elements,
            clock: 0,
            scratch: Vec::new(),
        }
    }

    /// The slot holding the signal of `rows[r]`, made if it is not kept; the slots of the
    /// last `capacity - 1` calls stay valid.
    pub fn load(&mut self, rows: &[SparseVec], r: u32) -> usize {
        self.clock += 1;
        if let Some(s) = self.slots.iter().position(|slot| slot.row == r) {
            self.slots[s].used = self.clock;
            return s;
        }
        let s = if self.slots.len() < self.capacity {
            self.slots.push(Slot {
                row: r,
                signal: Vec::new(),
                cumulative: Vec::new(),
                products: Vec::new(),
                used: 0,
            });
            self.slots.len() - 1
        } else {
            (0..self.slots.len())
                .min_by_key(|&s| self.slots[s].used)
                .expect("capacity above zero")
        };
        let x = &rows[r as usize];
        let (slot, scratch) = (&mut self.slots[s], &mut self.scratch);
        slot.signal.clear();
        slot.signal.resize(x.len, 0.0);
        x.iter().for_each(|(i, v)| slot.signal[i] = v);
        scratch.resize(x.len, 0.0);
        haar::inverse(&mut slot.signal, scratch);
        slot.cumulative.clear();
        let mut sum = 0.0;
        (slot.cumulative).extend(slot.signal[..self.elements].iter().map(|v| {
            sum += v.abs();
            sum
        }));
        slot.products.clear();
        (slot.row, slot.used) = (r, self.clock);
        s
    }

    /// Eq. 4.5's combination with `weights` of the rows in `slots`, as its products with
    /// cluster `c`'s subspace `a` ([`Packed::products`]) into `out`: the same combination of
    /// the rows' products, each made once and kept with its signal.
    pub fn products(
        &mut self,
        rows: &[SparseVec],
        slots: &[usize],
        weights: &[f64],
        c: u32,
        a: &Packed,
        out: &mut Vec<f64>,
    ) {
        out.clear();
        for (&s, &w) in slots.iter().zip(weights) {
            let slot = &mut self.slots[s];
            let kept = match slot.products.iter().position(|(k, _)| *k == c) {
                Some(k) => k,
                None => {
                    let mut p = Vec::new();
                    a.products(&rows[slot.row as usize], &mut p);
                    slot.products.push((c, p));
                    slot.products.len() - 1
                }
            };
            let p = &slot.products[kept].1;
            out.resize(p.len(), 0.0);
            out.iter_mut().zip(p).for_each(|(o, &v)| *o += w * v);
        }
    }

    /// The signal in slot `s`.
    pub fn signal(&self, s: usize) -> &[f64] {
        &self.slots[s].signal
    }

    /// An element drawn by `u` in [0, 1) with probability in proportion to the sum of the
    /// magnitudes of the signals in `slots` there (a slot by its total, then an element of
    /// it); uniform where they are all zero.
    pub fn pick(&self, slots: &[usize], u: f64) -> usize {
        let total = |s: usize| self.slots[s].cumulative.last().copied().unwrap_or(0.0);
        let sum: f64 = slots.iter().map(|&s| total(s)).sum();
        if !sum.is_finite() || sum <= 0.0 {
            return ((u * self.elements as f64) as usize).min(self.elements - 1);
        }
        let mut target = u * sum;
        for &s in slots {
            if target < total(s) {
                let c = &self.slots[s].cumulative;
                return c.partition_point(|&v| v <= target).min(c.len() - 1);
            }
            target -= total(s);
        }
        // Rounding left the target past the last total: its last element with weight.
        let c = &self.slots[*slots.last().expect("a slot")].cumulative;
        c.partition_point(|&v| v < c[c.len() - 1]).min(c.len() - 1)
    }
}

/// The normal equations `m` alpha = `rhs` (lower triangle of m, row-major) solved with the
/// weights kept non-negative: transfer vectors are, and so must be a combination standing
/// for one. A fit to a near-field spike at a few elements buys weights of opposite signs that
/// make negative light elsewhere; the most negative weight is dropped and the rest solved
/// again (Lawson and Hanson's active set, only ever dropping) until none is negative.
fn non_negative(m: &[f64], rhs: &[f64], k: usize) -> Option<Vec<f64>> {
    let mut free: Vec<usize> = (0..k).collect();
    while !free.is_empty() {
        let j = free.len();
        let mut sub = vec![0.0; j * j];
        for (a, &r) in free.iter().enumerate() {
            for (b, &c) in free.iter().enumerate().take(a + 1) {
                sub[a * j + b] = m[r * k + c];
            }
        }
        let x = cholesky_solve(&mut sub, free.iter().map(|&r| rhs[r]).collect(), j)?;
        match (0..j)
            .filter(|&a| x[a] < 0.0)
            .min_by(|&a, &b| x[a].total_cmp(&x[b]))
        {
            Some(a) => {
                free.remove(a);
            }
            None => {
                let mut alpha = vec![0.0; k];
                free.iter().zip(&x).for_each(|(&r, &w)| alpha[r] = w);
                return Some(alpha);
            }
        }
    }
    None
}

/// Solves m x = b for the symmetric positive definite k x k `m` (lower triangle, row-major,
/// overwritten by its Cholesky factor); `None` if it is not positive definite.
fn cholesky_solve(m: &mut [f64], mut b: Vec<f64>, k: usize) -> Option<Vec<f64>> {
    for j in 0..k {
        let d = m[j * k + j] - (0..j).map(|p| m[j * k + p].powi(2)).sum::<f64>();
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let d = d.sqrt();
        m[j * k + j] = d;
        for i in j + 1..k {
            let s = m[i * k + j] - (0..j).map(|p| m[i * k + p] * m[j * k + p]).sum::<f64>();
            m[i * k + j] = s / d;
        }
    }
    for i in 0..k {
        b[i] = (b[i] - (0..i).map(|p| m[i * k + p] * b[p]).sum::<f64>()) / m[i * k + i];
    }
    for i in (0..k).rev() {
        b[i] = (b[i] - (i + 1..k).map(|p| m[p * k + i] * b[p]).sum::<f64>()) / m[i * k + i];
    }
    Some(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::haar;
    use fenestra_core::Sampler;

    /// `count` rows of length `n` with entries `value(row, index, u)` (u uniform), the `keep`
    /// largest kept.
    fn rows(
        count: usize,
        n: usize,
        keep: usize,
        value: impl Fn(usize, usize, f64) -> f64,
    ) -> Vec<SparseVec> {
        let mut s = Sampler::new(5, 0, 0);
        (0..count)
            .map(|r| {
                let x: Vec<f64> = (0..n).map(|j| value(r, j, s.next_1d() as f64)).collect();
                SparseVec::largest(&x, keep)
            })
            .collect()
    }

    #[test]
    fn kept_signals_are_the_inverse_transforms() {
        let n = 32;
        let rows = rows(10, n, 12, |_, _, u| u - 0.5);
        let truth = |r: usize| {
            let mut d = rows[r].to_dense();
            haar::inverse(&mut d, &mut vec![0.0; n]);
            d
        };
        // Room for four: asking for rows in a pattern that evicts, the last three asked for
        // stay where they were given.
        let mut signals = Signals::new(4, n);
        let order = [0u32, 1, 2, 0, 3, 4, 5, 0, 9, 1, 1, 8, 2, 7];
        let mut given: Vec<(u32, usize)> = Vec::new();
        for &r in &order {
            let slot = signals.load(&rows, r);
            given.push((r, slot));
            for &(r, slot) in given.iter().rev().take(3) {
                assert_eq!(
                    signals.signal(slot),
                    truth(r as usize).as_slice(),
                    "row {r}"
                );
            }
        }
    }

    #[test]
    fn elements_are_drawn_by_the_signals_magnitude() {
        let n = 16;
        let rows = rows(
            3,
            n,
            n,
            |r, j, u| {
                if r == 2 || j % 5 == 0 {
                    0.0
                } else {
                    u - 0.2
                }
            },
        );
        // The first 12 entries can be drawn.
        let mut signals = Signals::new(4, 12);
        let slots: Vec<usize> = (0..2).map(|r| signals.load(&rows, r)).collect();
        let mut want = [0.0; 12];
        for &slot in &slots {
            (want.iter_mut().zip(signals.signal(slot))).for_each(|(w, v)| *w += v.abs());
        }
        let total: f64 = want.iter().sum();
        let draws = 100_000;
        let mut got = [0usize; 12];
        for i in 0..draws {
            got[signals.pick(&slots, (i as f64 + 0.5) / draws as f64)] += 1;
        }
        for j in 0..12 {
            let p = want[j] / total;
            let f = got[j] as f64 / draws as f64;
            assert!((f - p).abs() < 1e-3, "element {j}: drawn {f}, weight {p}");
        }
        // A zero signal: uniform over the entries that can be drawn.
        let zero = [signals.load(&rows, 2)];
        let mut got = [0usize; 12];
        for i in 0..1200 {
            got[signals.pick(&zero, (i as f64 + 0.5) / 1200.0)] += 1;
        }
        assert!(got.iter().all(|&c| c == 100), "{got:?}");
    }

    #[test]
    fn a_combination_of_the_neighbours_is_recovered_from_a_few_elements() {
        let n = 64;
        let mut s = Sampler::new(31, 0, 0);
        let mut scratch = vec![0.0; n];
        let images: Vec<SparseVec> = (0..3)
            .map(|_| {
                let mut x: Vec<f64> = (0..n).map(|_| s.next_1d() as f64).collect();
                haar::forward(&mut x, &mut scratch);
                SparseVec::largest(&x, 20)
            })
            .collect();
        // The new sample's transfer: 0.5 x0 + 2 x1 + 0.25 x2 (in the signal domain).
        let weights = [0.5, 2.0, 0.25];
        let mut truth = vec![0.0; n];
        for (img, w) in images.iter().zip(weights) {
            let mut x = img.to_dense();
            haar::inverse(&mut x, &mut scratch);
            truth.iter_mut().zip(&x).for_each(|(t, v)| *t += w * v);
        }
        let indices = [3, 17, 30, 41, 60];
        let values: Vec<f64> = indices.iter().map(|&j| truth[j]).collect();
        let refs: Vec<&SparseVec> = images.iter().collect();
        let dense = |images: &[&SparseVec]| -> Vec<Vec<f64>> {
            (images.iter())
                .map(|x| {
                    let mut d = x.to_dense();
                    haar::inverse(&mut d, &mut vec![0.0; n]);
                    d
                })
                .collect()
        };
        let signals = dense(&refs);
        let signals: Vec<&[f64]> = signals.iter().map(|s| s.as_slice()).collect();
        // Eq. 4.5's combination of the signals with the fitted weights.
        let combined = |signals: &[&[f64]], weights: &[f64]| -> Vec<f64> {
            let mut sum = vec![0.0; n];
            for (x, &w) in signals.iter().zip(weights) {
                sum.iter_mut().zip(x.iter()).for_each(|(s, v)| *s += w * v);
            }
            sum
        };
        let got = reconstruct(&signals, &indices, &values, 0.0).expect("fit");
        let back = combined(&signals, &got);
        for (j, (a, b)) in back.iter().zip(&truth).enumerate() {
            assert!((a - b).abs() < 1e-9, "element {j}: {a} vs {b}");
        }
        assert!(reconstruct(&signals, &indices[..2], &values[..2], 0.0).is_none());
        // Values no non-negative combination reaches (a spike at one element): the weights
        // stay non-negative, where least squares alone would subtract neighbours.
        // (Whole images: truncated ones may dip below zero themselves.)
        let whole: Vec<SparseVec> = (0..3)
            .map(|_| {
                let mut x: Vec<f64> = (0..n).map(|_| s.next_1d() as f64).collect();
                haar::forward(&mut x, &mut scratch);
                SparseVec::largest(&x, n)
            })
            .collect();
        let whole: Vec<&SparseVec> = whole.iter().collect();
        let mut spiky = values.clone();
        spiky[0] *= 50.0;
        let whole_signals = dense(&whole);
        let whole_signals: Vec<&[f64]> = whole_signals.iter().map(|s| s.as_slice()).collect();
        let got = reconstruct(&whole_signals, &indices, &spiky, 0.0).expect("fit");
        assert!(got.iter().all(|&w| w >= 0.0), "negative weights: {got:?}");
        let back = combined(&whole_signals, &got);
        assert!(back.iter().all(|&v| v >= -1e-9), "negative light: {back:?}");
        // A neighbour twice: the two copies share its weight, the fit is the same.
        let twice_signals = [signals[0], signals[0], signals[1], signals[2]];
        let got = reconstruct(&twice_signals, &indices, &values, 0.0).expect("fit");
        let back = combined(&twice_signals, &got);
        for (j, (a, b)) in back.iter().zip(&truth).enumerate() {
            assert!((a - b).abs() < 1e-6, "twice, element {j}: {a} vs {b}");
        }
    }

    #[test]
    fn subspace_products_of_a_combination_combine_the_rows_products() {
        let (n, l) = (64, 3);
        let rows = rows(
            5,
            n,
            20,
            |r, j, u| if (r + j) % 4 == 0 { 0.0 } else { u - 0.3 },
        );
        let mut s = Sampler::new(12, 0, 0);
        let mut r = || s.next_1d() as f64 - 0.5;
        let subspace = |r: &mut dyn FnMut() -> f64| fenestra_lpca::Subspace {
            mean: (0..n).map(|_| r()).collect(),
            basis: (0..l).map(|_| (0..n).map(|_| r()).collect()).collect(),
        };
        let a = [
            Packed::new(&subspace(&mut r)),
            Packed::new(&subspace(&mut r)),
        ];
        let mut signals = Signals::new(3, n);
        let weights = [0.5, 1.5, 0.25];
        // Rows 1, 3, 4; then 0, 3, 4 after row 1's slot went to row 0.
        for (pass, picked) in [[1u32, 3, 4], [0, 3, 4], [0, 3, 4]].iter().enumerate() {
            let slots: Vec<usize> = picked.iter().map(|&r| signals.load(&rows, r)).collect();
            let mut dense = vec![0.0; n];
            for (&r, w) in picked.iter().zip(weights) {
                rows[r as usize].iter().for_each(|(i, v)| dense[i] += w * v);
            }
            let x = SparseVec::largest(&dense, n);
            for (c, a) in a.iter().enumerate() {
                let (mut want, mut got) = (Vec::new(), Vec::new());
                a.products(&x, &mut want);
                signals.products(&rows, &slots, &weights, c as u32, a, &mut got);
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        (g - w).abs() < 1e-12,
                        "pass {pass}, cluster {c}: {got:?} vs {want:?}"
                    );
                }
            }
        }
    }
}
