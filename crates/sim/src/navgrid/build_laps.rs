//! The time each step of a grid's build took, kept on the grid so that a benchmark can say
//! where a build's time goes (`examples/build_phases.rs`) without a profiler.

use std::time::Instant;

/// Wall time of each step of one build (s), in the order the steps ran.
#[derive(Debug, Clone, Default)]
pub struct BuildLaps {
    laps: Vec<(&'static str, f64)>,
    since: Option<Instant>,
}

impl BuildLaps {
    /// Starts the clock.
    pub(crate) fn start() -> BuildLaps {
        BuildLaps { laps: Vec::new(), since: Some(Instant::now()) }
    }

    /// Ends the step `name`: its time is that since the last step ended (or the start).
    pub(crate) fn lap(&mut self, name: &'static str) {
        let now = Instant::now();
        if let Some(t) = self.since.replace(now) {
            self.laps.push((name, (now - t).as_secs_f64()));
        }
    }

    /// Each step's name and wall time (s).
    pub fn laps(&self) -> &[(&'static str, f64)] {
        &self.laps
    }
}

#[cfg(test)]
mod tests {
    use super::BuildLaps;
    use std::time::{Duration, Instant};

    #[test]
    fn laps_come_in_order_and_add_up_to_the_time_taken() {
        let t = Instant::now();
        let mut laps = BuildLaps::start();
        std::thread::sleep(Duration::from_millis(3));
        laps.lap("first");
        laps.lap("second");
        let total = t.elapsed().as_secs_f64();
        let names: Vec<&str> = laps.laps().iter().map(|l| l.0).collect();
        assert_eq!(names, ["first", "second"]);
        assert!(laps.laps()[0].1 >= 0.003, "{:?}", laps.laps());
        assert!(laps.laps().iter().all(|l| l.1 >= 0.0));
        assert!(laps.laps().iter().map(|l| l.1).sum::<f64>() <= total);
        // A grid that was not built (no clock started) records nothing.
        let mut none = BuildLaps::default();
        none.lap("first");
        assert!(none.laps().is_empty());
    }
}
