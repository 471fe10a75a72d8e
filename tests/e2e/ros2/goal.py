"""A goal for a discrete agent over ROS 2 (rclpy from PyPI): run while `xhab ros2 sim --lockstep`
and `xhab ros2 agent` run in the same ROS_DOMAIN_ID. Publishes `goal_pose` (argv[1..2]: x y in
map) and watches `ground_truth/pose` until the robot is within argv[3] m of the goal and stays
there for a second (the agent called stop). Exits non-zero on failure."""
import math, sys, time
import rclpy
from rclpy.qos import QoSProfile, QoSReliabilityPolicy
from geometry_msgs.msg import PoseStamped

gx, gy, tol = map(float, sys.argv[1:4])
T = 60.0


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


rclpy.init()
node = rclpy.create_node("xhab_goal_check")
state = {}
node.create_subscription(PoseStamped, "ground_truth/pose", lambda m: state.__setitem__("truth", m), QoSProfile(depth=10, reliability=QoSReliabilityPolicy.RELIABLE))
goal_pub = node.create_publisher(PoseStamped, "goal_pose", 10)
t0 = time.time()
while time.time() - t0 < 60 and (goal_pub.get_subscription_count() == 0 or "truth" not in state):
    rclpy.spin_once(node, timeout_sec=0.1)
if goal_pub.get_subscription_count() == 0:
    fail("no subscriber on goal_pose (is xhab ros2 agent running?)")
if "truth" not in state:
    fail("no ground truth from the simulator")
g = PoseStamped()
g.header.frame_id = "map"
g.pose.position.x, g.pose.position.y = gx, gy
g.pose.position.z = state["truth"].pose.position.z
g.pose.orientation.w = 1.0
# Discovery between Fast DDS and RustDDS endpoints completes in the background: the goal goes
# out once the agent's subscription is matched, and again until the robot moves.
start = state["truth"].pose.position
t0 = time.time()
while time.time() - t0 < 10:
    g.header.stamp = state["truth"].header.stamp
    goal_pub.publish(g)
    t1 = time.time()
    while time.time() - t1 < 0.5:
        rclpy.spin_once(node, timeout_sec=0.02)
    p = state["truth"].pose.position
    if math.hypot(p.x - start.x, p.y - start.y) > 0.1:
        break
print("goal_pose (%.2f, %.2f) sent" % (gx, gy), flush=True)
t0 = time.time()
best = float("inf")
near_since = None
while time.time() - t0 < T:
    rclpy.spin_once(node, timeout_sec=0.05)
    p = state["truth"].pose.position
    d = math.hypot(p.x - gx, p.y - gy)
    best = min(best, d)
    if d < tol:
        near_since = near_since or time.time()
        if time.time() - near_since > 1.0:
            print("reached: %.3f m from the goal after %.1f s" % (d, time.time() - t0), flush=True)
            node.destroy_node()
            rclpy.shutdown()
            print("PASS", flush=True)
            sys.exit(0)
    else:
        near_since = None
fail("the robot did not reach the goal within %.0f s: closest %.3f m, now (%.2f, %.2f)" % (T, best, p.x, p.y))
