//! 95% confidence intervals of the report's means: the Wilson score interval for success
//! rates, Student's t interval for SPL and soft SPL. Closed forms, so the report is the same
//! every time it is made from the same results.

/// The standard normal's 97.5% quantile: a two-sided 95% interval is `mean ± Z95 · se`.
pub const Z95: f64 = 1.959_963_984_540_054;

/// How the report's intervals are computed, in words (the page's methods note).
pub const METHOD: &str = "95% confidence intervals: Wilson score interval for the success rate; \
    Student's t interval (mean ± t(0.975, n−1) · s/√n, clipped to [0, 1]) for SPL and soft SPL. \
    Episodes are pooled over scenes, agents and seeds and treated as independent; with fewer \
    than two episodes no interval is given.";

/// A mean over `n` values and its 95% confidence interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// How many values.
    pub n: usize,
    /// Their mean (NaN without values).
    pub mean: f64,
    /// The interval `(low, high)`; `None` with fewer than two values (t) or none (Wilson).
    pub interval: Option<(f64, f64)>,
}

/// The Wilson score interval of a success rate: `successes` of `n` trials.
pub fn wilson(successes: f64, n: usize) -> Estimate {
    if n == 0 {
        return Estimate { n, mean: f64::NAN, interval: None };
    }
    let nf = n as f64;
    let p = successes / nf;
    let z2 = Z95 * Z95;
    let denom = 1.0 + z2 / nf;
    let centre = (p + z2 / (2.0 * nf)) / denom;
    let half = Z95 * (p * (1.0 - p) / nf + z2 / (4.0 * nf * nf)).max(0.0).sqrt() / denom;
    Estimate { n, mean: p, interval: Some(((centre - half).max(0.0), (centre + half).min(1.0))) }
}

/// The Wilson interval of values that are each 0 or 1 (success per episode).
pub fn success_rate(xs: &[f64]) -> Estimate {
    wilson(xs.iter().filter(|&&x| x >= 0.5).count() as f64, xs.len())
}

/// Student's t interval of the mean of `xs` (values in [0, 1]; the interval is clipped there).
pub fn t_interval(xs: &[f64]) -> Estimate {
    let n = xs.len();
    if n == 0 {
        return Estimate { n, mean: f64::NAN, interval: None };
    }
    let mean = xs.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return Estimate { n, mean, interval: None };
    }
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1) as f64;
    let half = t975(n - 1) * (var / n as f64).sqrt();
    Estimate { n, mean, interval: Some(((mean - half).max(0.0), (mean + half).min(1.0))) }
}

/// Student's t distribution's 97.5% quantile with `df` degrees of freedom (`df >= 1`): a
/// table to 30, then the Cornish–Fisher expansion around the normal (error below 1e-4).
pub fn t975(df: usize) -> f64 {
    const TABLE: [f64; 30] = [
        12.7062, 4.3027, 3.1824, 2.7764, 2.5706, 2.4469, 2.3646, 2.3060, 2.2622, 2.2281, 2.2010, 2.1788, 2.1604, 2.1448, 2.1314, 2.1199, 2.1098, 2.1009, 2.0930,
        2.0860, 2.0796, 2.0739, 2.0687, 2.0639, 2.0595, 2.0555, 2.0518, 2.0484, 2.0452, 2.0423,
    ];
    if df == 0 {
        return f64::INFINITY;
    }
    if df <= TABLE.len() {
        return TABLE[df - 1];
    }
    let (z, v) = (Z95, df as f64);
    let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
    z + (z3 + z) / (4.0 * v) + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * v * v) + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * v * v * v)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn wilson_matches_known_intervals() {
        // 8 of 10: (0.4902, 0.9433) in Newcombe (1998) and every calculator.
        let e = wilson(8.0, 10);
        let (lo, hi) = e.interval.unwrap();
        assert!(close(e.mean, 0.8, 1e-12) && close(lo, 0.4902, 1e-4) && close(hi, 0.9433, 1e-4), "{e:?}");
        // 0 of 10 keeps a non-empty interval: (0, 0.2775).
        let (lo, hi) = wilson(0.0, 10).interval.unwrap();
        assert!(close(lo, 0.0, 1e-12) && close(hi, 0.2775, 1e-4), "{lo} {hi}");
        // All of 20: (0.8389, 1).
        let (lo, hi) = success_rate(&[1.0; 20]).interval.unwrap();
        assert!(close(lo, 0.8389, 1e-4) && close(hi, 1.0, 1e-12), "{lo} {hi}");
        assert!(wilson(0.0, 0).interval.is_none());
    }

    #[test]
    fn t_interval_matches_hand_computation() {
        // mean 0.5, s = 0.2582, se = 0.1291, t(0.975, 3) = 3.1824: 0.5 ± 0.4108.
        let e = t_interval(&[0.2, 0.4, 0.6, 0.8]);
        let (lo, hi) = e.interval.unwrap();
        assert!(close(e.mean, 0.5, 1e-12) && close(lo, 0.0892, 1e-4) && close(hi, 0.9108, 1e-4), "{e:?}");
        // Clipped to [0, 1].
        let (lo, _) = t_interval(&[0.0, 0.0, 0.9]).interval.unwrap();
        assert_eq!(lo, 0.0);
        // One value: a mean, no interval.
        let one = t_interval(&[0.7]);
        assert!(one.mean == 0.7 && one.interval.is_none());
    }

    #[test]
    fn t_quantiles_join_the_normal() {
        assert!(close(t975(1), 12.7062, 1e-4) && close(t975(30), 2.0423, 1e-4));
        // Beyond the table: t(0.975, 40) = 2.0211, 60: 2.0003, 120: 1.9799.
        for (df, t) in [(31, 2.0395), (40, 2.0211), (60, 2.0003), (120, 1.9799), (100_000, 1.9600)] {
            assert!(close(t975(df), t, 1e-4), "df {df}: {} vs {t}", t975(df));
        }
    }
}
