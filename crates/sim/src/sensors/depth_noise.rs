//! Optional depth-camera noise, seeded: Gaussian noise growing with the square of depth (as
//! structured-light sensors), and dropout of pixels on depth edges. Off by default.

use xhab_types::gaussian;
use rand::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};
use xhab_types::DepthImage;

/// Depth noise settings (all zero = no noise).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
pub struct DepthNoise {
    /// Standard deviation of the Gaussian noise at 1 m (m); it scales with depth squared.
    pub sigma_at_1m: f64,
    /// Depth jump between neighbouring pixels that makes an edge (m, 0 = no edge dropout).
    pub edge_threshold: f64,
    /// Probability that a pixel on an edge reads 0 (no return).
    pub edge_dropout: f64,
}

impl DepthNoise {
    /// Whether it changes anything.
    pub fn is_off(&self) -> bool {
        self.sigma_at_1m <= 0.0 && (self.edge_threshold <= 0.0 || self.edge_dropout <= 0.0)
    }

    /// Applies the noise to `img` with the stream of `seed` (same seed, same image).
    pub fn apply(&self, img: &mut DepthImage, seed: u64) {
        if self.is_off() {
            return;
        }
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let (w, h) = (img.width, img.height);
        let clean = img.data.clone();
        for v in 0..h {
            for u in 0..w {
                let i = v * w + u;
                let d = clean[i];
                if d <= 0.0 {
                    continue;
                }
                if self.edge_threshold > 0.0 && self.edge_dropout > 0.0 {
                    let jump = [(u > 0, i.wrapping_sub(1)), (u + 1 < w, i + 1), (v > 0, i.wrapping_sub(w)), (v + 1 < h, i + w)]
                        .iter()
                        .any(|&(ok, j)| ok && (clean[j] <= 0.0 || (clean[j] - d).abs() as f64 > self.edge_threshold));
                    if jump && rng.gen::<f64>() < self.edge_dropout {
                        img.data[i] = 0.0;
                        continue;
                    }
                }
                if self.sigma_at_1m > 0.0 {
                    let n = self.sigma_at_1m * (d as f64).powi(2) * gaussian(&mut rng);
                    img.data[i] = ((d as f64 + n).max(0.0)) as f32;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step_image() -> DepthImage {
        // Left half at 1 m, right half at 3 m: one vertical edge.
        let (w, h) = (20, 10);
        let data = (0..w * h).map(|i| if i % w < w / 2 { 1.0 } else { 3.0 }).collect();
        DepthImage { width: w, height: h, data }
    }

    #[test]
    fn off_by_default_and_seeded() {
        let mut a = step_image();
        DepthNoise::default().apply(&mut a, 1);
        assert_eq!(a, step_image());
        let n = DepthNoise { sigma_at_1m: 0.01, edge_threshold: 0.5, edge_dropout: 0.5 };
        let (mut b, mut c, mut d) = (step_image(), step_image(), step_image());
        n.apply(&mut b, 7);
        n.apply(&mut c, 7);
        n.apply(&mut d, 8);
        assert_eq!(b, c);
        assert_ne!(b, d);
    }

    #[test]
    fn noise_grows_with_depth_and_dropout_hits_only_edges() {
        let n = DepthNoise { sigma_at_1m: 0.01, edge_threshold: 0.5, edge_dropout: 1.0 };
        let mut img = step_image();
        n.apply(&mut img, 3);
        let w = img.width;
        let (mut near, mut far) = (Vec::new(), Vec::new());
        for (i, &v) in img.data.iter().enumerate() {
            let u = i % w;
            if u == w / 2 - 1 || u == w / 2 {
                assert_eq!(v, 0.0, "edge pixel {i} kept");
            } else if u < w / 2 {
                near.push((v - 1.0).abs());
            } else {
                far.push((v - 3.0).abs());
            }
        }
        let mean = |x: &[f32]| x.iter().sum::<f32>() / x.len() as f32;
        assert!(mean(&far) > 3.0 * mean(&near), "{} vs {}", mean(&far), mean(&near));
        assert!(mean(&near) < 0.03 && mean(&far) < 0.3);
    }
}
