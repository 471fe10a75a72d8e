#!/usr/bin/python3
"""Two `xhab ros sim` nodes side by side (__ns:=r1, and ROS_NAMESPACE=r2 with scan:=base_scan):
each robot's topics live in its own namespace. Exits non-zero with a message on failure."""
import sys
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


rospy.init_node("xhab_two_robots_check", anonymous=True)
T = 30
o1 = rospy.wait_for_message("/r1/odom", Odometry, timeout=T)
o2 = rospy.wait_for_message("/r2/odom", Odometry, timeout=T)
rospy.wait_for_message("/r1/scan", LaserScan, timeout=T)
rospy.wait_for_message("/r2/base_scan", LaserScan, timeout=T)
topics = dict(rospy.get_published_topics())
for t in ["/odom", "/scan", "/r2/scan"]:
    if t in topics:
        fail("%s is published: a namespace or remapping was not honoured (%s)" % (t, sorted(topics)))
# Different start seeds: the two robots are different robots.
p1, p2 = o1.pose.pose.position, o2.pose.pose.position
if abs(p1.x - p2.x) + abs(p1.y - p2.y) < 1e-6:
    fail("both namespaces carry the same robot")
master = rospy.get_master()
code, _, nodes = master.lookupNode("/r1/xhab_sim")
if code != 1:
    fail("node /r1/xhab_sim is not registered")
code, _, _ = master.lookupNode("/r2/sim2")
if code != 1:
    fail("node /r2/sim2 (__name:=sim2) is not registered")
print("PASS", flush=True)
