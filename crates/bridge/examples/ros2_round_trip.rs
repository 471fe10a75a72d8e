//! The floor under `xhab bench --ros2`'s lock-step: the round trip of one `xhab/step` and its
//! `xhab/step_reply` between two ROS 2 nodes of this process (each on its own DDS participant,
//! as in `--compare-ros2`), with the lock-step QoS, and nothing else sent.
//!
//! `cargo run --release -p xhab-bridge --example ros2_round_trip [ROUND_TRIPS] [PAYLOADS]`: the
//! median and mean round trip (µs) of ROUND_TRIPS (default 3,000) exchanges after 200 warm-up
//! ones; with PAYLOADS > 0, that many more messages of the same type go out before each step
//! (as the simulator's state topics do), received by the agent side. Domain: `$ROS_DOMAIN_ID`.

use std::time::{Duration, Instant};
use xhab_bridge::ros::names::Names;
use xhab_bridge::ros2::lockstep::lockstep_qos;
use xhab_bridge::ros2::node::{Ros2Config, Ros2Node};
use xhab_bridge::ros2::xhab_msgs::{Step, StepReply};

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|s| s.parse().ok()).unwrap_or(3000);
    let payloads: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(0);
    let config = Ros2Config::from_env(|v| std::env::var(v).ok()).expect("ROS_DOMAIN_ID");
    let mut sim = Ros2Node::new(Names::plain("rt_sim"), config).expect("sim node");
    let mut agent = Ros2Node::new(Names::plain("rt_agent"), config).expect("agent node");
    let step = sim.publisher::<Step>("xhab_rt/step", lockstep_qos()).unwrap();
    let extra = sim.publisher::<Step>("xhab_rt/extra", lockstep_qos()).unwrap();
    let replies = sim.subscription::<StepReply>("xhab_rt/step_reply", lockstep_qos()).unwrap();
    let steps = agent.subscription::<Step>("xhab_rt/step", lockstep_qos()).unwrap();
    let extras = agent.subscription::<Step>("xhab_rt/extra", lockstep_qos()).unwrap();
    let reply = agent.publisher::<StepReply>("xhab_rt/step_reply", lockstep_qos()).unwrap();

    let total = n + 200;
    let echo = tokio::spawn(async move {
        loop {
            let (s, _) = steps.async_take().await.expect("step");
            if s.step > 0 {
                for _ in 0..payloads {
                    extras.async_take().await.expect("extra");
                }
            }
            reply.async_publish(StepReply { episode: s.episode, step: s.step, ..Default::default() }).await.expect("reply");
            if s.step as usize + 1 == total {
                break;
            }
        }
    });
    // Discovery: the first step is resent until it is answered.
    let mut rtts = Vec::with_capacity(n);
    for i in 0..total as u32 {
        let t0 = Instant::now();
        let msg = Step { episode: 0, step: i, ..Default::default() };
        'sent: loop {
            for _ in 0..if i > 0 { payloads } else { 0 } {
                extra.async_publish(msg).await.unwrap();
            }
            step.async_publish(msg).await.unwrap();
            // Answers to resent copies of step 0 are dropped; only step 0 is sent again.
            loop {
                match tokio::time::timeout(Duration::from_millis(if i == 0 { 50 } else { 5000 }), replies.async_take()).await {
                    Ok(Ok((r, _))) if r.step == i => break 'sent,
                    Ok(_) => {}
                    Err(_) if i == 0 => continue 'sent,
                    Err(_) => panic!("no reply to step {i}"),
                }
            }
        }
        if i == 0 {
            // Let discovery match the other topic too before anything more is sent.
            tokio::time::sleep(Duration::from_secs(1)).await;
        }
        if i >= 200 {
            rtts.push(t0.elapsed().as_secs_f64() * 1e6);
        }
    }
    echo.await.unwrap();
    rtts.sort_by(f64::total_cmp);
    let mean = rtts.iter().sum::<f64>() / rtts.len() as f64;
    println!("{{\"round_trips\":{n},\"payloads\":{payloads},\"median_us\":{:.1},\"mean_us\":{mean:.1},\"p90_us\":{:.1}}}", rtts[rtts.len() / 2], rtts[rtts.len() * 9 / 10]);
}
