//! `--shard K/N`: a deterministic slice of a study's runs × episodes, as contiguous parts of
//! runs, so that N shards together cover every episode exactly once.

use crate::plan::Plan;
use serde::{Deserialize, Serialize};
use std::str::FromStr;

/// Shard `index` (1-based) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which shard, 1..=count.
    pub index: usize,
    /// How many shards.
    pub count: usize,
}

impl FromStr for Shard {
    type Err = String;

    /// Parses `K/N` with 1 <= K <= N.
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("bad shard `{s}`: expected K/N with 1 <= K <= N (e.g. 2/4)");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (k.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Episodes `first..end` of run `run` (an index into the plan's runs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct PartRange {
    /// The run.
    pub run: usize,
    /// First episode (index into the run's episodes).
    pub first: usize,
    /// One past the last.
    pub end: usize,
}

/// The parts a shard runs (`None`: every run whole). The runs' episodes, laid end to end in
/// plan order, are cut into `count` slices of equal length (within one episode); shard K
/// takes the K-th, split where runs change.
pub fn parts(plan: &Plan, shard: Option<Shard>) -> Vec<PartRange> {
    let whole = |(run, r): (usize, &crate::plan::RunPlan)| PartRange { run, first: 0, end: r.episodes };
    let Some(s) = shard else {
        return plan.runs.iter().enumerate().map(whole).collect();
    };
    let total = plan.episodes();
    let (lo, hi) = ((s.index - 1) * total / s.count, s.index * total / s.count);
    let mut out = Vec::new();
    let mut start = 0;
    for (run, r) in plan.runs.iter().enumerate() {
        let (a, b) = (lo.max(start), hi.min(start + r.episodes));
        if a < b {
            out.push(PartRange { run, first: a - start, end: b - start });
        }
        start += r.episodes;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::RunPlan;

    fn plan(sizes: &[usize]) -> Plan {
        let runs = sizes
            .iter()
            .enumerate()
            .map(|(i, &n)| RunPlan { id: format!("r{i}"), scene: 0, agent: 0, configuration: 0, seed: 0, episodes_file: "e".into(), episodes_label: "e".into(), episodes: n })
            .collect();
        Plan { runs, skipped: Vec::new() }
    }

    #[test]
    fn shards_cover_every_episode_once() {
        for sizes in [vec![5usize, 3, 7], vec![1], vec![2, 2], vec![30, 30, 30, 30]] {
            let p = plan(&sizes);
            for n in 1..=9 {
                let mut seen: Vec<Vec<u32>> = sizes.iter().map(|&k| vec![0; k]).collect();
                for k in 1..=n {
                    for part in parts(&p, Some(Shard { index: k, count: n })) {
                        assert!(part.first < part.end && part.end <= sizes[part.run]);
                        for i in part.first..part.end {
                            seen[part.run][i] += 1;
                        }
                    }
                }
                assert!(seen.iter().flatten().all(|&c| c == 1), "{sizes:?} in {n} shards: {seen:?}");
            }
        }
        let p = plan(&[4, 4]);
        assert_eq!(parts(&p, None), vec![PartRange { run: 0, first: 0, end: 4 }, PartRange { run: 1, first: 0, end: 4 }]);
        assert_eq!(parts(&p, Some(Shard { index: 2, count: 4 })), vec![PartRange { run: 0, first: 2, end: 4 }]);
    }

    #[test]
    fn shard_arguments_are_checked() {
        assert_eq!("2/4".parse::<Shard>().unwrap(), Shard { index: 2, count: 4 });
        for bad in ["0/4", "5/4", "4", "a/b", "1/0", ""] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
