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

/// Advertises `topic` (latched or not).
pub async fn advertise<T: RosMessageType>(nh: &NodeHandle, topic: &str, latched: bool) -> Result<Publisher<T>, RosError> {
    nh.advertise::<T>(topic, 16, latched).await.map_err(|e| RosError::Node(format!("advertising {topic}: {e}")))
}

/// Subscribes to `topic`; messages arrive on the returned channel in order. Messages that fail
/// to decode are logged and dropped (the connection and the node live on).
pub async fn subscribe<T: RosMessageType>(nh: &NodeHandle, topic: &str) -> Result<mpsc::UnboundedReceiver<T>, RosError> {
    let mut sub = nh.subscribe::<T>(topic, 1000).await.map_err(|e| RosError::Node(format!("subscribing to {topic}: {e}")))?;
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

/// Something with subscribers.
pub trait Connected: Sync {
    /// Whether at least one subscriber is connected.
    fn connected(&self) -> bool;
}

impl<T: RosMessageType> Connected for Publisher<T> {
    fn connected(&self) -> bool {
        self.has_connected_clients()
    }
}

/// Waits (sleeping 5 ms between looks, no busy wait) until each publisher has a subscriber;
/// an error naming the topics still alone after `timeout`.
pub async fn wait_for_subscribers(pubs: &[(&str, &dyn Connected)], timeout: Duration) -> Result<(), RosError> {
    let t0 = std::time::Instant::now();
    loop {
        let missing: Vec<&str> = pubs.iter().filter(|(_, p)| !p.connected()).map(|(n, _)| *n).collect();
        if missing.is_empty() {
            return Ok(());
        }
        if t0.elapsed() > timeout {
            return Err(RosError::Timeout(format!("nobody subscribed to {} within {:.0} s", missing.join(", "), timeout.as_secs_f64())));
        }
        tokio::time::sleep(Duration::from_millis(5)).await;
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
