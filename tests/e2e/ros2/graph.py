"""ROS 2 graph check (rclpy from PyPI): run while `xhab ros2 sim ... --ros-args -r
__ns:=/robot1 -r __node:=simx -r scan:=base_scan` runs in the same ROS_DOMAIN_ID. Checks the
node's name and namespace, the remapped and namespaced topic names with their types, the QoS
each publisher offers (sensor data best effort; map and /tf_static transient local), and
that a late transient-local subscriber still gets the map. Exits non-zero on any failure."""
import sys, time
import rclpy
from rclpy.qos import QoSProfile, QoSDurabilityPolicy, QoSReliabilityPolicy, qos_profile_sensor_data
from sensor_msgs.msg import LaserScan
from nav_msgs.msg import OccupancyGrid


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


rclpy.init()
node = rclpy.create_node("xhab_graph_check")
want = {
    "/robot1/base_scan": ("sensor_msgs/msg/LaserScan", QoSReliabilityPolicy.BEST_EFFORT, QoSDurabilityPolicy.VOLATILE),
    "/robot1/odom": ("nav_msgs/msg/Odometry", QoSReliabilityPolicy.RELIABLE, QoSDurabilityPolicy.VOLATILE),
    "/robot1/map": ("nav_msgs/msg/OccupancyGrid", QoSReliabilityPolicy.RELIABLE, QoSDurabilityPolicy.TRANSIENT_LOCAL),
    "/robot1/camera/depth/image_raw": ("sensor_msgs/msg/Image", QoSReliabilityPolicy.BEST_EFFORT, QoSDurabilityPolicy.VOLATILE),
    "/tf": ("tf2_msgs/msg/TFMessage", QoSReliabilityPolicy.RELIABLE, QoSDurabilityPolicy.VOLATILE),
    "/tf_static": ("tf2_msgs/msg/TFMessage", QoSReliabilityPolicy.RELIABLE, QoSDurabilityPolicy.TRANSIENT_LOCAL),
    "/clock": ("rosgraph_msgs/msg/Clock", QoSReliabilityPolicy.RELIABLE, QoSDurabilityPolicy.VOLATILE),
}
t0 = time.time()
while time.time() - t0 < 30:
    rclpy.spin_once(node, timeout_sec=0.1)
    topics = dict(node.get_topic_names_and_types())
    if all(t in topics for t in want) and ("simx", "/robot1") in node.get_node_names_and_namespaces():
        break
else:
    fail("graph incomplete: topics %s, nodes %s" % (sorted(node.get_topic_names_and_types()), node.get_node_names_and_namespaces()))
topics = dict(node.get_topic_names_and_types())
for t in ["/scan", "/robot1/scan", "/odom", "/map"]:
    if t in topics:
        fail("%s should not exist (namespace and remapping)" % t)
for t, (ty, rel, dur) in want.items():
    if topics[t] != [ty]:
        fail("%s has types %s, want [%s]" % (t, topics[t], ty))
    pubs = node.get_publishers_info_by_topic(t)
    if len(pubs) != 1:
        fail("%s: %d publishers" % (t, len(pubs)))
    q = pubs[0].qos_profile
    if q.reliability != rel or q.durability != dur:
        fail("%s offers %s/%s, want %s/%s" % (t, q.reliability, q.durability, rel, dur))
    if (pubs[0].node_namespace, pubs[0].node_name) != ("/robot1", "simx"):
        fail("%s published by %s%s" % (t, pubs[0].node_namespace, pubs[0].node_name))
# Joining late: the latched map arrives; the remapped scan flows.
got = {}
latched = QoSProfile(depth=1, reliability=QoSReliabilityPolicy.RELIABLE, durability=QoSDurabilityPolicy.TRANSIENT_LOCAL)
node.create_subscription(OccupancyGrid, "/robot1/map", lambda m: got.setdefault("map", m), latched)
node.create_subscription(LaserScan, "/robot1/base_scan", lambda m: got.setdefault("scan", m), qos_profile_sensor_data)
t0 = time.time()
while time.time() - t0 < 20 and len(got) < 2:
    rclpy.spin_once(node, timeout_sec=0.1)
if "map" not in got or got["map"].info.width == 0:
    fail("no latched map for a late subscriber")
if "scan" not in got:
    fail("no scan on /robot1/base_scan")
print("graph ok: /robot1/simx, %d topics with their QoS, late map %dx%d" % (len(want), got["map"].info.width, got["map"].info.height), flush=True)
node.destroy_node()
rclpy.shutdown()
print("PASS", flush=True)
