//! ROS 1 messages as they travel over TCPROS: a little-endian `u32` length, then the body.
//! [`decode`] is what roslibrust's subscribers do with every message they receive (a message
//! that fails is logged and dropped, see [`super::node::RosNode::subscribe`]); [`frame`] and
//! [`encode`] are its inverses, for tests and tools.

use roslibrust::RosMessageType;

/// A message that cannot be decoded as its type.
#[derive(Debug, thiserror::Error)]
#[error("{ros_type}: cannot decode a {len}-byte message: {reason}")]
pub struct DecodeError {
    /// The ROS type expected (e.g. `sensor_msgs/LaserScan`).
    pub ros_type: &'static str,
    /// Bytes received, length prefix included.
    pub len: usize,
    /// What is wrong, in words (the decoder's message).
    pub reason: String,
}

/// Decodes one message as received (the `u32` length prefix, then the body), as roslibrust's
/// ROS 1 subscriber does: the body must be exactly as long as the prefix says.
pub fn decode<T: RosMessageType>(bytes: &[u8]) -> Result<T, DecodeError> {
    roslibrust_serde_rosmsg::from_slice::<T>(bytes).map_err(|e| DecodeError { ros_type: T::DESCRIPTION.ros_type_name, len: bytes.len(), reason: e.to_string() })
}

/// A message body with its length prefix, as it is sent.
pub fn frame(body: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(body.len() + 4);
    out.extend_from_slice(&(body.len() as u32).to_le_bytes());
    out.extend_from_slice(body);
    out
}

/// Encodes a message as it is sent (length prefix included).
pub fn encode<T: RosMessageType>(msg: &T) -> Vec<u8> {
    // Serialising into memory cannot fail for the generated types (no maps, no enums).
    roslibrust_serde_rosmsg::to_vec(msg).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ros::msgs::{geometry_msgs as gm, sensor_msgs};

    #[test]
    fn messages_round_trip_and_bad_ones_are_errors() {
        let t = gm::Twist { linear: gm::Vector3 { x: 0.5, y: 0.0, z: 0.0 }, angular: gm::Vector3 { x: 0.0, y: 0.0, z: -1.0 } };
        let bytes = encode(&t);
        assert_eq!(bytes.len(), 4 + 48);
        assert_eq!(decode::<gm::Twist>(&bytes).unwrap(), t);
        assert_eq!(frame(&bytes[4..]), bytes);
        let e = decode::<gm::Twist>(&bytes[..20]).unwrap_err().to_string();
        assert!(e.starts_with("geometry_msgs/Twist: cannot decode a 20-byte message"), "{e}");
        // A scan whose ranges claim more elements than the message holds.
        let mut s = encode(&sensor_msgs::LaserScan { ranges: vec![1.0; 4], ..Default::default() });
        let n = s.len();
        s[n - 8 - 16..n - 4 - 16].copy_from_slice(&1_000_000u32.to_le_bytes());
        assert!(decode::<sensor_msgs::LaserScan>(&s).is_err());
    }
}
