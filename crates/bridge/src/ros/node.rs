//! What every xhab ROS node shares: errors, the node with its resolved names, typed
//! subscriptions forwarded to channels, and taking a lock-step's messages by their stamp.

use super::names::Names;
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
    /// A name or remapping argument ROS would reject.
    #[error(transparent)]
    Name(#[from] super::names::NameError),
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

/// A registered node and the names it resolves topics and services with.
pub struct RosNode {
    /// roslibrust's handle (kept alive with the node).
    pub nh: NodeHandle,
    /// Namespace, node name and remappings.
    pub names: Names,
}

impl RosNode {
    /// Registers the node `names` with the master at `uri`.
    pub async fn new(uri: &str, names: Names) -> Result<RosNode, RosError> {
        let name = names.node_name();
        let nh = tokio::time::timeout(Duration::from_secs(10), NodeHandle::new(uri, &name))
            .await
            .map_err(|_| RosError::Timeout(format!("registering node {name} with the master at {uri}")))?
            .map_err(|e| RosError::Node(format!("cannot register node {name} with the master at {uri}: {e}")))?;
        Ok(RosNode { nh, names })
    }

    /// Advertises `topic` (resolved; latched or not).
    pub async fn advertise<T: RosMessageType>(&self, topic: &str, latched: bool) -> Result<Publisher<T>, RosError> {
        let g = self.names.resolve(topic);
        self.nh.advertise::<T>(&g, 16, latched).await.map_err(|e| RosError::Node(format!("advertising {g}: {e}")))
    }

    /// Subscribes to `topic` (resolved); messages arrive on the returned channel in order.
    /// Messages that fail to decode are logged and dropped (the connection and the node live on).
    pub async fn subscribe<T: RosMessageType>(&self, topic: &str) -> Result<mpsc::UnboundedReceiver<T>, RosError> {
        let g = self.names.resolve(topic);
        let mut sub = self.nh.subscribe::<T>(&g, 1000).await.map_err(|e| RosError::Node(format!("subscribing to {g}: {e}")))?;
        let (tx, rx) = mpsc::unbounded_channel();
        tokio::spawn(async move {
            while let Some(m) = sub.next().await {
                match m {
                    Ok(m) => {
                        if tx.send(m).is_err() {
                            break;
                        }
                    }
                    Err(e) => tracing::warn!("{g}: dropped a message: {e}"),
                }
            }
        });
        Ok(rx)
    }
}

/// Receives the next message from `rx` within `timeout`, naming `what` on failure.
pub async fn recv<T>(rx: &mut mpsc::UnboundedReceiver<T>, timeout: Duration, what: &str) -> Result<T, RosError> {
    match tokio::time::timeout(timeout, rx.recv()).await {
        Ok(Some(m)) => Ok(m),
        Ok(None) => Err(RosError::Protocol(format!("{what}: the subscription closed"))),
        Err(_) => Err(RosError::Timeout(format!("no {what} within {:.0} s", timeout.as_secs_f64()))),
    }
}

/// Messages with a header stamp.
pub trait Stamped {
    /// `header.stamp` as (secs, nsecs).
    fn stamp(&self) -> (i32, i32);
}

macro_rules! stamped {
    ($($t:ty),*) => {$(impl Stamped for $t { fn stamp(&self) -> (i32, i32) { (self.header.stamp.secs, self.header.stamp.nsecs) } })*};
}
use super::msgs::{geometry_msgs as gm, nav_msgs, sensor_msgs};
stamped!(gm::PoseStamped, gm::PoseWithCovarianceStamped, nav_msgs::Odometry, nav_msgs::OccupancyGrid, sensor_msgs::LaserScan);

/// A subscription whose messages are taken by their stamp: lock-step pairs a step's messages
/// on separate topics by `header.stamp` (which rospy and rosbag keep), never by arrival order
/// or `header.seq`.
pub struct StampInbox<T> {
    rx: mpsc::UnboundedReceiver<T>,
    pending: std::collections::VecDeque<T>,
}

impl<T: Stamped> StampInbox<T> {
    /// Wraps a subscription.
    pub fn new(rx: mpsc::UnboundedReceiver<T>) -> Self {
        Self { rx, pending: Default::default() }
    }

    /// The message stamped `stamp`, waiting up to `timeout`; messages stamped earlier are
    /// dropped (a step's messages come once, or again with the same stamp when resent), later
    /// ones kept for their own step. Another publisher on the topic (a bag played back, a
    /// second driver) may send any stamp, in any order: a later stamp is no sign that ours was
    /// lost, so only the timeout ends the wait.
    pub async fn take(&mut self, stamp: (i32, i32), timeout: Duration, what: &str) -> Result<T, RosError> {
        self.pending.retain(|m| m.stamp() >= stamp);
        if let Some(i) = self.pending.iter().position(|m| m.stamp() == stamp) {
            return Ok(self.pending.remove(i).expect("found at i"));
        }
        let deadline = tokio::time::Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(tokio::time::Instant::now());
            let m = recv(&mut self.rx, left, what).await.map_err(|e| match e {
                RosError::Timeout(t) => RosError::Timeout(format!("{t} stamped {}.{:09}", stamp.0, stamp.1)),
                e => e,
            })?;
            match m.stamp().cmp(&stamp) {
                std::cmp::Ordering::Less => {}
                std::cmp::Ordering::Equal => return Ok(m),
                std::cmp::Ordering::Greater => self.pending.push_back(m),
            }
        }
    }

    /// The newest message that has arrived, if any (older ones are dropped).
    pub fn latest(&mut self) -> Option<T> {
        while let Ok(m) = self.rx.try_recv() {
            self.pending.push_back(m);
        }
        let last = self.pending.pop_back();
        self.pending.clear();
        last
    }
}
