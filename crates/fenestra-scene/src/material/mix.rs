//! pbrt-v4's mix of two materials.

/// pbrt-v4's mix: at each surface point one of two earlier materials, the second with
/// probability `amount`, chosen by a hash of the point (so a point always gets the same).
#[derive(Clone, Debug)]
pub struct Mix {
    /// Indices of the two materials; both below this material's own index.
    pub materials: [usize; 2],
    /// Probability of the second material, in [0, 1].
    pub amount: f32,
}

impl Mix {
    /// Why the parameters make no physical sense, if they do not.
    pub fn validate(&self) -> Option<String> {
        let amount = self.amount;
        (!(0.0..=1.0).contains(&amount)).then(|| format!("mix amount {amount} must lie in [0, 1]"))
    }
}
