//! A data set: n points of dimension d, stored row-major in f32.

use crate::LpcaError;

/// n points of dimension d, row-major in f32.
#[derive(Clone, Debug)]
pub struct Dataset {
    /// Number of points (rows).
    pub n: usize,
    /// Dimension (columns).
    pub d: usize,
    /// n x d values, row-major.
    pub values: Vec<f32>,
}

impl Dataset {
    /// Checks that `values` holds n rows of d finite values.
    pub fn new(n: usize, d: usize, values: Vec<f32>) -> Result<Self, LpcaError> {
        if n.checked_mul(d) != Some(values.len()) {
            return Err(LpcaError::Input(format!(
                "{} values do not make {n} rows of {d}",
                values.len()
            )));
        }
        if n == 0 || d == 0 {
            return Err(LpcaError::Input("the data set is empty".into()));
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(LpcaError::Input(format!(
                "row {}, column {}: value is not finite",
                i / d,
                i % d
            )));
        }
        Ok(Dataset { n, d, values })
    }

    /// Point `i`.
    pub fn row(&self, i: usize) -> &[f32] {
        &self.values[i * self.d..(i + 1) * self.d]
    }

    /// Sum of squared norms of all points.
    pub fn total_energy(&self) -> f64 {
        self.values.iter().map(|&v| v as f64 * v as f64).sum()
    }
}
