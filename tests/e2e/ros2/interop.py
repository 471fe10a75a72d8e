"""Interop check against real ROS 2 (rclpy from PyPI, Fast DDS): run with the ROS 2 virtual
environment's python while `xhab ros2 sim ... --physics --camera --rgb` runs in the same
ROS_DOMAIN_ID. Receives scan, odom, /tf, /tf_static, /clock, the camera's images and
camera_info, map and ground truth; drives the robot with cmd_vel; checks what needs no
simulator here and writes what it received as JSON (argv[1]) for the Rust test to compare
with the simulator. Exits non-zero with a message on any failure."""
import json, math, struct, sys, time
import rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile, QoSDurabilityPolicy, QoSReliabilityPolicy, QoSHistoryPolicy, qos_profile_sensor_data
from sensor_msgs.msg import LaserScan, Image, CameraInfo
from nav_msgs.msg import Odometry, OccupancyGrid
from rosgraph_msgs.msg import Clock
from geometry_msgs.msg import Twist, PoseStamped

T = 60.0


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


def sec(t):
    return t.sec + t.nanosec * 1e-9


def yaw_of(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


rclpy.init()
node = Node("xhab_ros2_check")
latched = QoSProfile(depth=1, reliability=QoSReliabilityPolicy.RELIABLE, durability=QoSDurabilityPolicy.TRANSIENT_LOCAL, history=QoSHistoryPolicy.KEEP_LAST)
reliable = QoSProfile(depth=10, reliability=QoSReliabilityPolicy.RELIABLE)
got = {}


def keep(name):
    def cb(msg):
        got.setdefault(name, []).append(msg)
        if len(got[name]) > 50:
            del got[name][0]
    return cb


subs = [
    node.create_subscription(LaserScan, "scan", keep("scan"), qos_profile_sensor_data),
    node.create_subscription(Odometry, "odom", keep("odom"), reliable),
    node.create_subscription(Clock, "/clock", keep("clock"), reliable),
    node.create_subscription(Image, "camera/depth/image_raw", keep("depth"), qos_profile_sensor_data),
    node.create_subscription(CameraInfo, "camera/depth/camera_info", keep("depth_info"), qos_profile_sensor_data),
    node.create_subscription(Image, "camera/rgb/image_raw", keep("rgb"), qos_profile_sensor_data),
    node.create_subscription(CameraInfo, "camera/rgb/camera_info", keep("rgb_info"), qos_profile_sensor_data),
    node.create_subscription(OccupancyGrid, "map", keep("map"), latched),
    node.create_subscription(PoseStamped, "ground_truth/pose", keep("truth"), reliable),
]


def spin_until(names, timeout=T):
    t0 = time.time()
    while time.time() - t0 < timeout:
        rclpy.spin_once(node, timeout_sec=0.05)
        if all(got.get(n) for n in names):
            return time.time() - t0
    fail("nothing received on %s within %.0f s (received: %s)" % ([n for n in names if not got.get(n)], timeout, sorted(got)))


wanted = ["scan", "odom", "clock", "depth", "depth_info", "rgb", "rgb_info", "map", "truth"]
took = spin_until(wanted)
print("all topics received after %.1f s" % took, flush=True)
# The clock advances while we listen.
c1 = got["clock"][-1].clock
frames0 = sec(got["depth"][-1].header.stamp)
t0 = time.time()
while time.time() - t0 < 2.0:
    rclpy.spin_once(node, timeout_sec=0.05)
c2 = got["clock"][-1].clock
# Camera frames keep coming (5 Hz of sim time at rate 1): large best-effort samples are not
# lost whole (they are when the subscriber's socket buffers are too small).
frames = len([m for m in got["depth"] if sec(m.header.stamp) > frames0])
if frames < 4:
    fail("only %d depth frames in 2 s (5 Hz expected)" % frames)
if not sec(c2) > sec(c1):
    fail("clock does not advance (%f, %f)" % (sec(c1), sec(c2)))

scan = got["scan"][-1]
truth0 = got["truth"][-1]
odom0 = got["odom"][-1]
depth = got["depth"][-1]
rgb = got["rgb"][-1]
dinfo = got["depth_info"][-1]
rinfo = got["rgb_info"][-1]
grid = got["map"][-1]
if len(depth.data) != depth.step * depth.height or depth.step != 4 * depth.width:
    fail("depth image: %d bytes, step %d, %dx%d" % (len(depth.data), depth.step, depth.width, depth.height))
depth_values = struct.unpack("<%df" % (depth.width * depth.height), bytes(depth.data))
if len(rgb.data) != rgb.step * rgb.height or rgb.step != 3 * rgb.width:
    fail("rgb image: %d bytes, step %d, %dx%d" % (len(rgb.data), rgb.step, rgb.width, rgb.height))



def truth_at(stamp):
    """The ground-truth pose published with the same stamp (the state of one instant). DDS
    orders samples within a topic only: the pose of the instant a scan was taken may still be
    on its way when the scan is in, so it is waited for (2 s at most)."""
    t0 = time.time()
    while True:
        m = min(got["truth"], key=lambda m: abs(sec(m.header.stamp) - sec(stamp)))
        if abs(sec(m.header.stamp) - sec(stamp)) <= 1e-6:
            return m.pose
        if time.time() - t0 > 2.0:
            fail("no ground truth stamped %.3f (nearest %.3f)" % (sec(stamp), sec(m.header.stamp)))
        rclpy.spin_once(node, timeout_sec=0.05)


scan_truth = truth_at(scan.header.stamp)
depth_truth = truth_at(depth.header.stamp)

# cmd_vel (default QoS: reliable) moves the robot: 0.2 m/s for 2.5 s of wall time at rate 1.
pub = node.create_publisher(Twist, "cmd_vel", 10)
cmd = Twist()
cmd.linear.x = 0.2
t0 = time.time()
while time.time() - t0 < 2.5:
    pub.publish(cmd)
    rclpy.spin_once(node, timeout_sec=0.05)
pub.publish(Twist())
t0 = time.time()
while time.time() - t0 < 1.0:
    pub.publish(Twist())
    rclpy.spin_once(node, timeout_sec=0.05)
odom1 = got["odom"][-1]
truth1 = got["truth"][-1]
moved_odom = math.hypot(odom1.pose.pose.position.x - odom0.pose.pose.position.x, odom1.pose.pose.position.y - odom0.pose.pose.position.y)
print("cmd_vel: odom moved %.3f m" % moved_odom, flush=True)


def pose_json(p):
    return {"x": p.position.x, "y": p.position.y, "z": p.position.z, "yaw": yaw_of(p.orientation)}


def info_json(i):
    return {"frame_id": i.header.frame_id, "width": i.width, "height": i.height, "distortion_model": i.distortion_model, "d": list(i.d), "k": list(i.k), "r": list(i.r), "p": list(i.p)}


def finite(v):
    return v if math.isfinite(v) else None


out = {
    "clock": [sec(c1), sec(c2)],
    "scan": {
        "frame_id": scan.header.frame_id, "stamp": sec(scan.header.stamp),
        "angle_min": scan.angle_min, "angle_max": scan.angle_max, "angle_increment": scan.angle_increment,
        "range_min": scan.range_min, "range_max": scan.range_max, "scan_time": scan.scan_time,
        "ranges": [finite(r) for r in scan.ranges],
    },
    "scan_truth": pose_json(scan_truth),
    "odom": {"frame_id": odom0.header.frame_id, "child_frame_id": odom0.child_frame_id, "pose": pose_json(odom0.pose.pose), "covariance": list(odom0.pose.covariance)},
    "odom_after": pose_json(odom1.pose.pose),
    "twist_after": {"linear": odom1.twist.twist.linear.x, "angular": odom1.twist.twist.angular.z},
    "truth": {"frame_id": truth0.header.frame_id, "pose": pose_json(truth0.pose)},
    "truth_after": pose_json(truth1.pose),
    "depth": {"frame_id": depth.header.frame_id, "encoding": depth.encoding, "width": depth.width, "height": depth.height, "is_bigendian": depth.is_bigendian,
              "stamp": sec(depth.header.stamp), "values": [finite(v) for v in depth_values]},
    "depth_truth": pose_json(depth_truth),
    "rgb": {"frame_id": rgb.header.frame_id, "encoding": rgb.encoding, "width": rgb.width, "height": rgb.height, "bytes": len(rgb.data), "distinct": len(set(bytes(rgb.data)))},
    "depth_info": info_json(dinfo),
    "rgb_info": info_json(rinfo),
    "map": {"frame_id": grid.header.frame_id, "width": grid.info.width, "height": grid.info.height, "resolution": grid.info.resolution,
            "origin": pose_json(grid.info.origin), "data": list(grid.data)},
}
with open(sys.argv[1], "w") as f:
    json.dump(out, f)
node.destroy_node()
rclpy.shutdown()
print("PASS", flush=True)
