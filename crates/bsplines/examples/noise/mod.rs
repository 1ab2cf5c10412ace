//! Reproducible Gaussian noise for the examples (xorshift64* and Box–Muller), so that they
//! need no random-number crate and print the same figures on every machine.

/// Standard normal samples from a seed.
pub(crate) struct Gaussian(u64);

impl Gaussian {
    /// The stream of `seed` (any value but 0 gives a full period).
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }

    /// A uniform sample in (0, 1).
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        (bits as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// A standard normal sample.
    pub(crate) fn next(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}
