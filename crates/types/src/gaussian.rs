//! Standard normal samples from a seeded stream (Box-Muller): the one sampler behind the
//! simulator's noise models and AMCL's motion model.

use rand::Rng;

/// One sample of N(0, 1), from two uniform draws of `rng`.
pub fn gaussian(rng: &mut impl Rng) -> f64 {
    let u1: f64 = rng.gen_range(f64::MIN_POSITIVE..1.0);
    let u2: f64 = rng.gen();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}
