"""A small navigation node in rclpy (PyPI has no nav2_msgs, so no navigate_to_pose server):
takes its goal on `goal_pose` (map frame), drives with `cmd_vel` from `odom` (turn towards the
goal, then go, one command per odometry message), with map -> odom fixed by the last
`initialpose` and the odometry of the same instant, and reports each goal's fate on
`navigate_to_pose/_action/status` (action_msgs/GoalStatusArray) as Nav2's bt_navigator does:
EXECUTING once taken, SUCCEEDED within argv[1] m of it, ABORTED when a newer goal replaces it.
Runs until killed."""
import math, sys, uuid
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.qos import QoSProfile, QoSDurabilityPolicy, QoSReliabilityPolicy
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped, Twist
from nav_msgs.msg import Odometry
from action_msgs.msg import GoalStatus, GoalStatusArray

TOL = float(sys.argv[1]) if len(sys.argv) > 1 else 0.1


def yaw_of(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def compose(a, b):
    """Pose a (x, y, yaw) then b in a's frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], a[2] + b[2])


def inverse(a):
    c, s = math.cos(a[2]), math.sin(a[2])
    return (-c * a[0] - s * a[1], s * a[0] - c * a[1], -a[2])


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


rclpy.init()
node = rclpy.create_node("goto")
cmd = node.create_publisher(Twist, "cmd_vel", 10)
status_pub = node.create_publisher(GoalStatusArray, "navigate_to_pose/_action/status", QoSProfile(depth=1, reliability=QoSReliabilityPolicy.RELIABLE, durability=QoSDurabilityPolicy.TRANSIENT_LOCAL))
st = {"init": None, "map_odom": None, "goal": None, "goals": []}  # goals: [GoalStatus], the last the current


def publish_status():
    a = GoalStatusArray()
    a.status_list = list(st["goals"][-16:])
    status_pub.publish(a)


def set_current(status):
    st["goals"][-1].status = status
    publish_status()


def on_init(m):
    p = m.pose.pose
    st["init"] = ((p.position.x, p.position.y, yaw_of(p.orientation)), m.header.stamp.sec * 10**9 + m.header.stamp.nanosec)


def on_goal(m):
    if st["goal"] is not None:
        set_current(GoalStatus.STATUS_ABORTED)
    g = GoalStatus()
    g.goal_info.goal_id.uuid = list(uuid.uuid4().bytes)
    g.goal_info.stamp = m.header.stamp
    g.status = GoalStatus.STATUS_EXECUTING
    st["goals"].append(g)
    st["goal"] = (m.pose.position.x, m.pose.position.y)
    publish_status()


def on_odom(m):
    o = (m.pose.pose.position.x, m.pose.pose.position.y, yaw_of(m.pose.pose.orientation))
    t = m.header.stamp.sec * 10**9 + m.header.stamp.nanosec
    if st["init"] is not None and t >= st["init"][1]:
        st["map_odom"] = compose(st["init"][0], inverse(o))
        st["init"] = None
    tw = Twist()
    if st["goal"] is not None and st["map_odom"] is not None:
        x, y, yaw = compose(st["map_odom"], o)
        dx, dy = st["goal"][0] - x, st["goal"][1] - y
        d = math.hypot(dx, dy)
        if d < TOL:
            st["goal"] = None
            set_current(GoalStatus.STATUS_SUCCEEDED)
        else:
            e = wrap(math.atan2(dy, dx) - yaw)
            tw.angular.z = max(-1.0, min(1.0, 2.0 * e))
            if abs(e) < 0.2:
                tw.linear.x = min(0.22, 0.8 * d)
    cmd.publish(tw)


node.create_subscription(PoseWithCovarianceStamped, "initialpose", on_init, 10)
node.create_subscription(PoseStamped, "goal_pose", on_goal, 10)
node.create_subscription(Odometry, "odom", on_odom, 50)
print("goto: ready", flush=True)
try:
    rclpy.spin(node)
except (KeyboardInterrupt, ExternalShutdownException):
    pass
