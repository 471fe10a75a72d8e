"""Navigation over ROS 2 (rclpy from PyPI): run while `xhab ros2 sim` and `xhab ros2 nav` run
in the same ROS_DOMAIN_ID. Publishes `initialpose` (the start, argv[1..3]: x y yaw) and
`goal_pose` (argv[4..5]: x y in map), and watches `ground_truth/pose` until the robot is within
argv[6] m of the goal and stopped there. Exits non-zero on failure."""
import math, sys, time
import rclpy
from rclpy.qos import QoSProfile, QoSReliabilityPolicy
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

sx, sy, syaw, gx, gy, tol = map(float, sys.argv[1:7])
T = 120.0


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


rclpy.init()
node = rclpy.create_node("xhab_nav_check")
state = {}
node.create_subscription(PoseStamped, "ground_truth/pose", lambda m: state.__setitem__("truth", m), QoSProfile(depth=10, reliability=QoSReliabilityPolicy.RELIABLE))
node.create_subscription(Odometry, "odom", lambda m: state.__setitem__("odom", m), 10)
init_pub = node.create_publisher(PoseWithCovarianceStamped, "initialpose", 10)
goal_pub = node.create_publisher(PoseStamped, "goal_pose", 10)
# Wait for the nav node's subscriptions and the simulator's ground truth.
t0 = time.time()
while time.time() - t0 < 60 and (init_pub.get_subscription_count() == 0 or goal_pub.get_subscription_count() == 0 or "truth" not in state):
    rclpy.spin_once(node, timeout_sec=0.1)
if init_pub.get_subscription_count() == 0 or goal_pub.get_subscription_count() == 0:
    fail("no subscriber on initialpose/goal_pose (is xhab ros2 nav running?)")
if "truth" not in state:
    fail("no ground truth from the simulator")
ip = PoseWithCovarianceStamped()
ip.header.frame_id = "map"
ip.pose.pose.position.x, ip.pose.pose.position.y = sx, sy
ip.pose.pose.orientation.z, ip.pose.pose.orientation.w = math.sin(syaw / 2), math.cos(syaw / 2)
ip.pose.covariance[0] = ip.pose.covariance[7] = 0.05 ** 2
ip.pose.covariance[35] = 0.05 ** 2
g = PoseStamped()
g.header.frame_id = "map"
g.pose.position.x, g.pose.position.y = gx, gy
g.pose.orientation.w = 1.0
# Discovery between Fast DDS and RustDDS endpoints completes in the background: send the
# initial pose, then the goal, a few times over half a second each.
for msg, pub in ((ip, init_pub), (g, goal_pub)):
    for _ in range(5):
        msg.header.stamp = state["truth"].header.stamp
        pub.publish(msg)
        t1 = time.time()
        while time.time() - t1 < 0.1:
            rclpy.spin_once(node, timeout_sec=0.02)
print("initialpose (%.2f, %.2f, %.2f) and goal_pose (%.2f, %.2f) sent" % (sx, sy, syaw, gx, gy), flush=True)
t0 = time.time()
best = float("inf")
while time.time() - t0 < T:
    rclpy.spin_once(node, timeout_sec=0.05)
    p = state["truth"].pose.position
    d = math.hypot(p.x - gx, p.y - gy)
    best = min(best, d)
    o = state.get("odom")
    still = o is not None and abs(o.twist.twist.linear.x) < 1e-3 and abs(o.twist.twist.angular.z) < 1e-3
    if d < tol and still:
        print("reached: %.3f m from the goal after %.1f s, stopped" % (d, time.time() - t0), flush=True)
        node.destroy_node()
        rclpy.shutdown()
        print("PASS", flush=True)
        sys.exit(0)
fail("the robot did not reach the goal within %.0f s: closest %.3f m, now (%.2f, %.2f)" % (T, best, p.x, p.y))
