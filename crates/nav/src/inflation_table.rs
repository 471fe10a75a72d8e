//! Inflation costs looked up by squared distance in cells, as costmap_2d's inflation layer
//! caches them: the cost formula runs once per distance, not once per cell.

use crate::costmap::{inflation_cost, CostmapParams, FREE};

/// Largest reach of a table (cells); farther inflation is cut there.
const MAX_REACH_CELLS: f64 = 1024.0;

/// [`inflation_cost`] for each squared cell distance up to the inflation's reach.
#[derive(Debug, Clone, PartialEq)]
pub struct InflationTable {
    costs: Vec<u8>,
    reach: usize,
}

impl InflationTable {
    /// The table of `p` on cells of `resolution` (m).
    pub fn new(p: &CostmapParams, resolution: f64) -> Self {
        // One cell beyond the larger of the inflation and inscribed radii every cost is FREE.
        let r = p.inflation_radius.max(p.inscribed_radius()) / resolution + 1.0;
        let r = if r.is_finite() { r.clamp(1.0, MAX_REACH_CELLS) } else { 1.0 };
        let reach = r.ceil() as usize;
        let costs = (0..=reach * reach).map(|d2| inflation_cost((d2 as f64).sqrt() * resolution, p)).collect();
        Self { costs, reach }
    }

    /// Cost of a cell whose nearest obstacle is `d2` cells^2 away (FREE beyond the reach).
    #[inline]
    pub fn cost(&self, d2: u32) -> u8 {
        self.costs.get(d2 as usize).copied().unwrap_or(FREE)
    }

    /// Distance (cells) beyond which every cost is FREE.
    pub fn reach(&self) -> usize {
        self.reach
    }

    /// Largest squared distance (cells^2) the table holds.
    pub fn cap(&self) -> u32 {
        (self.costs.len() - 1) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_equals_the_formula_at_every_distance() {
        for p in [
            CostmapParams::default(),
            CostmapParams { inflation_radius: 0.3, cost_scaling_factor: 3.0, ..Default::default() },
            CostmapParams { robot_radius: 0.4, inflation_radius: 0.2, ..Default::default() },
        ] {
            for res in [0.05, 0.1, 0.025] {
                let t = InflationTable::new(&p, res);
                for d2 in 0..(4 * t.cap() + 10) {
                    assert_eq!(t.cost(d2), inflation_cost((d2 as f64).sqrt() * res, &p), "{d2} at {res}");
                }
            }
        }
    }
}
