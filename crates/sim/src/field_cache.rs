//! The geodesic fields built lately on one grid: two users of the same episode in one process
//! (the simulator and an oracle agent node over ROS, say) build its field once.

use crate::goal_field::GoalField;
use crate::navgrid::NavGrid;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use xhab_types::Point2;

/// How many fields a grid keeps (the newest).
const CAPACITY: usize = 4;

/// A field and its goals' exact coordinates (the bits of x and y).
type Entry = (Vec<[u64; 2]>, Arc<GoalField>);

/// The last few fields built on a grid, keyed by their goals' exact coordinates.
#[derive(Debug, Default)]
pub struct FieldCache {
    recent: Mutex<VecDeque<Entry>>,
}

impl Clone for FieldCache {
    /// A copied grid starts with no fields of its own.
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl FieldCache {
    /// The field of `goals` on `grid`, built unless one of the last few built is it (the same
    /// field as [`GoalField::new`] gives, bit for bit).
    pub fn get(&self, grid: &NavGrid, goals: &[Point2]) -> Arc<GoalField> {
        let key: Vec<[u64; 2]> = goals.iter().map(|g| [g.x.to_bits(), g.y.to_bits()]).collect();
        if let Some((_, f)) = self.recent.lock().unwrap_or_else(|e| e.into_inner()).iter().find(|(k, _)| *k == key) {
            return f.clone();
        }
        // Built outside the lock: other episodes' lookups go on meanwhile.
        let f = Arc::new(GoalField::new(grid, goals));
        let mut r = self.recent.lock().unwrap_or_else(|e| e.into_inner());
        if r.len() == CAPACITY {
            r.pop_front();
        }
        r.push_back((key, f.clone()));
        f
    }
}
