#!/usr/bin/python3
"""Interop check against real ROS 1 (Debian's rospy): run with ROS_MASTER_URI set while
`xhab ros sim ... --physics --camera` runs. Exits non-zero with a message on any failure."""
import math, subprocess, sys, tempfile, os, time
import rospy, rosbag
from sensor_msgs.msg import LaserScan, Image, CameraInfo
from nav_msgs.msg import Odometry, OccupancyGrid
from tf2_msgs.msg import TFMessage
from rosgraph_msgs.msg import Clock
from geometry_msgs.msg import Twist, PoseStamped

def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)

rospy.init_node("xhab_interop_check", anonymous=True)
T = 30
scan = rospy.wait_for_message("/scan", LaserScan, timeout=T)
if scan.header.frame_id != "laser" or len(scan.ranges) < 10:
    fail("scan: frame %r, %d ranges" % (scan.header.frame_id, len(scan.ranges)))
finite = [r for r in scan.ranges if math.isfinite(r)]
if not finite or any(r < scan.range_min or r > scan.range_max for r in finite):
    fail("scan ranges outside [range_min, range_max]")
if abs(scan.angle_min + (len(scan.ranges) - 1) * scan.angle_increment - scan.angle_max) > 1e-3:
    fail("scan angles inconsistent")
odom = rospy.wait_for_message("/odom", Odometry, timeout=T)
if odom.header.frame_id != "odom" or odom.child_frame_id != "base_link":
    fail("odom frames %r -> %r" % (odom.header.frame_id, odom.child_frame_id))
q = odom.pose.pose.orientation
if abs(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w - 1) > 1e-9:
    fail("odom quaternion not unit")
tf = rospy.wait_for_message("/tf", TFMessage, timeout=T)
if not any(t.header.frame_id == "odom" and t.child_frame_id == "base_link" for t in tf.transforms):
    fail("tf without odom -> base_link")
c1 = rospy.wait_for_message("/clock", Clock, timeout=T).clock.to_sec()
time.sleep(0.5)
c2 = rospy.wait_for_message("/clock", Clock, timeout=T).clock.to_sec()
if not c2 > c1:
    fail("clock does not advance (%f, %f)" % (c1, c2))
depth = rospy.wait_for_message("/camera/depth/image_raw", Image, timeout=T)
if depth.encoding != "32FC1" or depth.width != 256 or depth.height != 256 or len(depth.data) != 4 * 256 * 256:
    fail("depth image %s %dx%d %d bytes" % (depth.encoding, depth.width, depth.height, len(depth.data)))
import struct
vals = struct.unpack("<%df" % (256 * 256), depth.data)
if not any(0 < v <= 10 for v in vals):
    fail("depth image has no valid depth")
info = rospy.wait_for_message("/camera/depth/camera_info", CameraInfo, timeout=T)
if abs(info.K[0] - 128.0) > 1e-6 or abs(info.K[2] - 127.5) > 1e-6:
    fail("camera_info K %r (hfov 90 at 256 px: fx = 128, cx = 127.5)" % (info.K,))
grid = rospy.wait_for_message("/map", OccupancyGrid, timeout=T)
if len(grid.data) != grid.info.width * grid.info.height or grid.info.width == 0:
    fail("map data size")
# The map to localise on: the scene cut at the lidar's height, on the same grid as /map.
amcl_map = rospy.wait_for_message("/amcl/map", OccupancyGrid, timeout=T)
if len(amcl_map.data) != amcl_map.info.width * amcl_map.info.height or amcl_map.info.width == 0:
    fail("amcl/map data size")
if not any(v == 100 for v in amcl_map.data) or not any(v == 0 for v in amcl_map.data):
    fail("amcl/map has no walls or no free space")
print("topics ok: scan %d beams, odom, tf, clock %.2f->%.2f, depth 256x256, camera_info, map %dx%d, amcl/map %dx%d" % (len(scan.ranges), c1, c2, grid.info.width, grid.info.height, amcl_map.info.width, amcl_map.info.height), flush=True)

# rosbag records our topics and reads back.
bag = os.path.join(tempfile.mkdtemp(), "xhab.bag")
subprocess.run(["rosbag", "record", "-O", bag, "--duration=3", "/scan", "/odom", "/tf", "/clock"], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
counts = {}
with rosbag.Bag(bag) as b:
    for topic, msg, t in b.read_messages():
        counts[topic] = counts.get(topic, 0) + 1
for t in ["/scan", "/odom", "/tf", "/clock"]:
    if counts.get(t, 0) == 0:
        fail("rosbag recorded no %s (%r)" % (t, counts))
print("rosbag ok: %r" % counts, flush=True)

# A small planner: drive to a point 0.6 m ahead of the start using odom, by cmd_vel alone.
pub = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
start = rospy.wait_for_message("/ground_truth/pose", PoseStamped, timeout=T).pose
yaw0 = 2 * math.atan2(start.orientation.z, start.orientation.w)
gx, gy = start.position.x + 0.6 * math.cos(yaw0), start.position.y + 0.6 * math.sin(yaw0)
t0 = time.time()
while time.time() - t0 < 40:
    o = rospy.wait_for_message("/ground_truth/pose", PoseStamped, timeout=T).pose
    dx, dy = gx - o.position.x, gy - o.position.y
    d = math.hypot(dx, dy)
    if d < 0.1:
        break
    yaw = 2 * math.atan2(o.orientation.z, o.orientation.w)
    e = math.atan2(dy, dx) - yaw
    e = math.atan2(math.sin(e), math.cos(e))
    cmd = Twist()
    cmd.angular.z = max(-1.0, min(1.0, 2.0 * e))
    cmd.linear.x = 0.2 if abs(e) < 0.5 else 0.0
    pub.publish(cmd)
    time.sleep(0.05)
pub.publish(Twist())
end = rospy.wait_for_message("/ground_truth/pose", PoseStamped, timeout=T).pose
moved = math.hypot(end.position.x - start.position.x, end.position.y - start.position.y)
left = math.hypot(gx - end.position.x, gy - end.position.y)
if left > 0.15:
    fail("the rospy planner did not bring the robot to its goal: moved %.3f m, %.3f m left" % (moved, left))
print("cmd_vel ok: a rospy planner drove the robot %.3f m to within %.3f m of its goal" % (moved, left), flush=True)
print("PASS", flush=True)
