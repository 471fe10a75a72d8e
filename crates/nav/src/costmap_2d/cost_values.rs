//! Cell cost values, numerically those of ROS costmap_2d and nav2's `cost_values.hpp`, so a
//! costmap maps straight onto a ROS one.
//!
//! Costs 1..=252 are inflated costs that fall off with the distance to the nearest obstacle
//! (see [`InflationLayer`](super::InflationLayer)).

/// A cell with no obstacle near it (cost 0).
pub const FREE: u8 = 0;
/// The highest cost of a cell the robot's centre may occupy (252).
pub const MAX_NON_OBSTACLE: u8 = 252;
/// A cell within the robot's inscribed radius of an obstacle: the robot's centre there means a
/// collision for any heading (253).
pub const INSCRIBED: u8 = 253;
/// A cell holding an obstacle (254).
pub const LETHAL: u8 = 254;
/// A cell nothing is known about (255); only produced when unknown space is tracked.
pub const UNKNOWN: u8 = 255;

/// The nav_msgs/OccupancyGrid value ROS's costmap publisher gives cost `c`: 0 free, 99
/// inscribed, 100 lethal, -1 unknown, and 1..=98 for inflated costs scaled linearly.
pub fn cost_to_occupancy(c: u8) -> i8 {
    match c {
        FREE => 0,
        INSCRIBED => 99,
        LETHAL => 100,
        UNKNOWN => -1,
        c => (1 + (97 * (c as u32 - 1)) / 251) as i8,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn occupancy_translation_matches_ros() {
        for (c, o) in [
            (FREE, 0),
            (1, 1),
            (MAX_NON_OBSTACLE, 98),
            (INSCRIBED, 99),
            (LETHAL, 100),
            (UNKNOWN, -1),
        ] {
            assert_eq!(cost_to_occupancy(c), o, "cost {c}");
        }
    }
}
