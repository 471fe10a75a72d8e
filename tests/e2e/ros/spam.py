#!/usr/bin/python3
"""A second publisher on /odom and /scan, as a misbehaving driver or a forgotten bag: random
content, stamped anywhere in [0, 2000) s with nanoseconds no lock-step step uses (odd ones,
while xhab's stamps are whole ticks), earlier and later than the run's own, at ~200 Hz until
killed. A lock-step run pairs messages by stamp: these must change nothing."""
import math, random
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan

rospy.init_node("xhab_spam", anonymous=True)
odom = rospy.Publisher("odom", Odometry, queue_size=100)
scan = rospy.Publisher("scan", LaserScan, queue_size=100)
rng = random.Random(7)
n = 0


def when():
    return rospy.Time(rng.randrange(0, 2000), 2 * rng.randrange(0, 500_000_000) + 1)


while not rospy.is_shutdown():
    o = Odometry()
    o.header.stamp = when()
    o.header.frame_id, o.child_frame_id = "odom", "base_link"
    o.pose.pose.position.x, o.pose.pose.position.y = rng.uniform(-5, 5), rng.uniform(-5, 5)
    yaw = rng.uniform(-math.pi, math.pi)
    o.pose.pose.orientation.z, o.pose.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    o.twist.twist.linear.x = rng.uniform(-1, 1)
    odom.publish(o)
    s = LaserScan()
    s.header.stamp = when()
    s.header.frame_id = "laser"
    s.angle_min, s.angle_max, s.angle_increment = -math.pi, math.pi, 2 * math.pi / 359
    s.range_min, s.range_max = 0.1, 3.5
    s.ranges = [rng.uniform(0.1, 3.5) for _ in range(360)]
    scan.publish(s)
    n += 1
    if n % 200 == 0:
        print("spam: %d pairs" % n, flush=True)
    rospy.sleep(0.005)
