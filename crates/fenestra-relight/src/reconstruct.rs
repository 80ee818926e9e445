//! Transfer vectors at view samples the exploration did not evaluate (seed 003 §4.5.3,
//! eq. 4.5): a combination sum alpha_r x_r of the sparse wavelet images of nearby explored
//! samples, the weights alpha fitted by least squares to the new sample's transfer at a few
//! element indices I (|I| >= k), which are cheap to evaluate (eq. 4.1 for single gather
//! samples). The seed reads the neighbours' elements at I from their sparse images; here
//! their whole signals are inverse-transformed once and kept ([`Signals`]), since the next
//! pixels mostly have the same neighbours and need their elements too.

use crate::haar;
use crate::sparse::SparseVec;

/// The sparse wavelet image of the vector whose elements at `indices` are `values`, as a
/// least-squares combination of `neighbours` (sparse wavelet images, all of length `n`, a
/// power of two, with `signals` their inverse transforms), or their average where the
/// elements at `indices` say nothing about the weights; `None` when there are fewer indices
/// than neighbours. `ridge` > 0 pulls the weights towards the neighbours' average (1 / k
/// each) with that weight relative to the system's mean squared column norm: a few elements
/// of spiky transfer vectors otherwise buy a fit with large weights of opposite signs that
/// is wrong everywhere else. `sums`: scratch, left as zeros.
pub fn reconstruct(
    neighbours: &[&SparseVec],
    signals: &[&[f64]],
    indices: &[usize],
    values: &[f64],
    ridge: f64,
    sums: &mut Vec<f64>,
) -> Option<SparseVec> {
    let k = neighbours.len();
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
    let alpha = if norm2 > 0.0 {
        non_negative(&m, &rhs, k).unwrap_or(average)
    } else {
        average
    };
    Some(combine(neighbours, &alpha, sums))
}

/// Eq. 4.5 on the sparse images: sum_r alpha_r x_r, summed per coefficient in neighbour
/// order in `sums` (zeros of length n, left as zeros) and read back in index order.
fn combine(neighbours: &[&SparseVec], alpha: &[f64], sums: &mut Vec<f64>) -> SparseVec {
    let n = neighbours[0].len;
    sums.resize(n, 0.0);
    let mut touched = vec![0u64; n.div_ceil(64)];
    for (x, &w) in neighbours.iter().zip(alpha) {
        for (i, v) in x.iter() {
            sums[i] += w * v;
            touched[i / 64] |= 1 << (i % 64);
        }
    }
    let (mut indices, mut values) = (Vec::new(), Vec::new());
    for (word, &bits) in touched.iter().enumerate() {
        let mut bits = bits;
        while bits != 0 {
            let i = word * 64 + bits.trailing_zeros() as usize;
            bits &= bits - 1;
            indices.push(i as u32);
            values.push(std::mem::take(&mut sums[i]));
        }
    }
    SparseVec {
        len: n,
        norm2: values.iter().map(|v| v * v).sum(),
        indices,
        values,
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
        (slot.row, slot.used) = (r, self.clock);
        s
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
        let mut sums = Vec::new();
        let got = reconstruct(&refs, &signals, &indices, &values, 0.0, &mut sums).expect("fit");
        let mut back = got.to_dense();
        haar::inverse(&mut back, &mut scratch);
        for (j, (a, b)) in back.iter().zip(&truth).enumerate() {
            assert!((a - b).abs() < 1e-9, "element {j}: {a} vs {b}");
        }
        assert!(
            sums.iter().all(|&v| v == 0.0),
            "the scratch is left as zeros"
        );
        assert!(
            reconstruct(&refs, &signals, &indices[..2], &values[..2], 0.0, &mut sums).is_none()
        );
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
        let got =
            reconstruct(&whole, &whole_signals, &indices, &spiky, 0.0, &mut sums).expect("fit");
        let mut back = got.to_dense();
        haar::inverse(&mut back, &mut scratch);
        assert!(back.iter().all(|&v| v >= -1e-9), "negative light: {back:?}");
        // A neighbour twice: the two copies share its weight, the fit is the same.
        let twice = [refs[0], refs[0], refs[1], refs[2]];
        let twice_signals = [signals[0], signals[0], signals[1], signals[2]];
        let got =
            reconstruct(&twice, &twice_signals, &indices, &values, 0.0, &mut sums).expect("fit");
        let mut back = got.to_dense();
        haar::inverse(&mut back, &mut scratch);
        for (j, (a, b)) in back.iter().zip(&truth).enumerate() {
            assert!((a - b).abs() < 1e-6, "twice, element {j}: {a} vs {b}");
        }
    }
}
