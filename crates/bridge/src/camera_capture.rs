//! A camera frame per step, timed, with noise seeded by the run, the episode and the step.

use std::time::Instant;
use xhab_sim::sensors::{CameraFrame, CameraRig};
use xhab_types::Pose2;

/// Frames rendered in an episode and the wall time spent on them.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct RenderStats {
    pub frames: u64,
    pub seconds: f64,
}

/// Renders the frame of step `step` of episode `index` from `base` (timed into `stats`); the
/// noise seed depends on the run's seed, the episode and the step only.
pub(crate) fn capture(rig: &CameraRig, base: Pose2, floor_z: f64, seed: u64, index: usize, step: u64, stats: &mut RenderStats) -> Result<CameraFrame, String> {
    let t = Instant::now();
    let s = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (index as u64).wrapping_mul(0xbf58_476d_1ce4_e5b9) ^ step;
    let f = rig.capture(base, floor_z, s).map_err(|e| format!("rendering the camera at step {step}: {e}"))?;
    stats.frames += 1;
    stats.seconds += t.elapsed().as_secs_f64();
    Ok(f)
}
