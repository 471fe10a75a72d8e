//! What every xhab ROS node shares: errors, the node handle, typed subscriptions forwarded to
//! channels, and waiting (without spinning) for peers to connect.

use roslibrust::ros1::{NodeHandle, Publisher};

use roslibrust::RosMessageType;
use std::time::Duration;
use tokio::sync::mpsc;

/// Errors of the ROS layer.
#[derive(Debug, thiserror::Error)]
pub enum RosError {
    /// The master could not be used.
    #[error(transparent)]
    Master(#[from] super::master::MasterError),
    /// roslibrust refused an operation (registering, advertising, subscribing).
    #[error("ROS: {0}")]
    Node(String),
    /// A peer did not do its part in time.
    #[error("ROS: {0}")]
    Timeout(String),
    /// A peer sent something the protocol does not allow.
    #[error("ROS: {0}")]
    Protocol(String),
}

/// Registers node `name` with the master at `uri`.
pub async fn node(uri: &str, name: &str) -> Result<NodeHandle, RosError> {
    tokio::time::timeout(Duration::from_secs(10), NodeHandle::new(uri, name))
        .await
        .map_err(|_| RosError::Timeout(format!("registering node {name} with the master at {uri}")))?
        .map_err(|e| RosError::Node(format!("cannot register node {name} with the master at {uri}: {e}")))
}

/// `topic` as a global name: roslibrust 0.26 matches the master's `publisherUpdate` (which
/// names topics globally) against the name as given, so a relative name would never connect
/// to publishers that appear after the subscription.
pub fn global(topic: &str) -> String {
    if topic.starts_with('/') { topic.to_string() } else { format!("/{topic}") }
}

/// Advertises `topic` (latched or not).
pub async fn advertise<T: RosMessageType>(nh: &NodeHandle, topic: &str, latched: bool) -> Result<Publisher<T>, RosError> {
    nh.advertise::<T>(&global(topic), 16, latched).await.map_err(|e| RosError::Node(format!("advertising {topic}: {e}")))
}

/// Subscribes to `topic`; messages arrive on the returned channel in order. Messages that fail
/// to decode are logged and dropped (the connection and the node live on).
pub async fn subscribe<T: RosMessageType>(nh: &NodeHandle, topic: &str) -> Result<mpsc::UnboundedReceiver<T>, RosError> {
    let mut sub = nh.subscribe::<T>(&global(topic), 1000).await.map_err(|e| RosError::Node(format!("subscribing to {topic}: {e}")))?;
    let (tx, rx) = mpsc::unbounded_channel();
    let topic = topic.to_string();
    tokio::spawn(async move {
        while let Some(m) = sub.next().await {
            match m {
                Ok(m) => {
                    if tx.send(m).is_err() {
                        break;
                    }
                }
                Err(e) => tracing::warn!("{topic}: dropped a message: {e}"),
            }
        }
    });
    Ok(rx)
}

/// Receives the next message from `rx` within `timeout`, naming `what` on failure.
pub async fn recv<T>(rx: &mut mpsc::UnboundedReceiver<T>, timeout: Duration, what: &str) -> Result<T, RosError> {
    match tokio::time::timeout(timeout, rx.recv()).await {
        Ok(Some(m)) => Ok(m),
        Ok(None) => Err(RosError::Protocol(format!("{what}: the subscription closed"))),
        Err(_) => Err(RosError::Timeout(format!("no {what} within {:.0} s", timeout.as_secs_f64()))),
    }
}

/// Messages with a header sequence number.
pub trait Sequenced {
    /// `header.seq`.
    fn seq(&self) -> u32;
}

macro_rules! sequenced {
    ($($t:ty),*) => {$(impl Sequenced for $t { fn seq(&self) -> u32 { self.header.seq } })*};
}
use super::msgs::{geometry_msgs as gm, nav_msgs, sensor_msgs};
sequenced!(gm::PoseStamped, gm::PoseWithCovarianceStamped, nav_msgs::Odometry, nav_msgs::OccupancyGrid, sensor_msgs::LaserScan);

/// A subscription's messages with handshake probes (`header.seq` = `PROBE_SEQ`) taken out:
/// it remembers that a probe came (the connection is up) and queues the real messages.
pub struct Inbox<T> {
    rx: mpsc::UnboundedReceiver<T>,
    pending: std::collections::VecDeque<T>,
    /// Whether a probe has arrived.
    pub probed: bool,
}

impl<T: Sequenced> Inbox<T> {
    /// Wraps a subscription.
    pub fn new(rx: mpsc::UnboundedReceiver<T>) -> Self {
        Self { rx, pending: Default::default(), probed: false }
    }

    /// Takes in whatever has arrived, without waiting.
    pub fn absorb(&mut self) {
        while let Ok(m) = self.rx.try_recv() {
            if m.seq() == super::sim_node::PROBE_SEQ {
                self.probed = true;
            } else {
                self.pending.push_back(m);
            }
        }
    }

    /// The next real message, waiting up to `timeout`.
    pub async fn next(&mut self, timeout: Duration, what: &str) -> Result<T, RosError> {
        loop {
            if let Some(m) = self.pending.pop_front() {
                return Ok(m);
            }
            let m = recv(&mut self.rx, timeout, what).await?;
            if m.seq() == super::sim_node::PROBE_SEQ {
                self.probed = true;
            } else {
                return Ok(m);
            }
        }
    }

    /// The newest real message that has arrived, if any (older ones are dropped).
    pub fn latest(&mut self) -> Option<T> {
        self.absorb();
        let last = self.pending.pop_back();
        self.pending.clear();
        last
    }
}
