#!/usr/bin/python3
"""move_base's clients in plain rospy against `xhab ros sim --physics` and `xhab ros nav`:
tf2 resolves map -> odom -> base_link -> the laser frame, an actionlib SimpleActionClient sends
a goal and waits for SUCCEEDED, a goal on move_base_simple/goal ends SUCCEEDED on
move_base/status under a new goal id, and move_base/clear_costmaps answers a ServiceProxy.

    move_base_clients.py GX1 GY1 GX2 GY2 LASER_FRAME LASER_X

Prints PASS on success; exits non-zero with FAIL: ... otherwise.
"""
import math, sys, time
import rospy, actionlib, tf2_ros
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from geometry_msgs.msg import PoseStamped, PoseWithCovarianceStamped
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from std_srvs.srv import Empty

T = 60.0  # wall s per goal (the simulator runs at 5x real time: 300 s of sim time)


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


def target(x, y):
    p = PoseStamped()
    p.header.frame_id = "map"
    p.header.stamp = rospy.Time.now()
    p.pose.position.x, p.pose.position.y = x, y
    p.pose.orientation.w = 1.0
    return p


def truth():
    return rospy.wait_for_message("ground_truth/pose", PoseStamped, timeout=10).pose.position


args = rospy.myargv(sys.argv)[1:]
gx1, gy1, gx2, gy2 = map(float, args[:4])
laser_frame, laser_x = args[4], float(args[5])
rospy.init_node("xhab_move_base_clients", anonymous=True)

# tf: the laser's static mount, and the whole chain map -> odom -> base_link -> laser.
buf = tf2_ros.Buffer()
listener = tf2_ros.TransformListener(buf)
try:
    m = buf.lookup_transform("base_link", laser_frame, rospy.Time(0), rospy.Duration(20)).transform.translation
except tf2_ros.TransformException as e:
    fail("no base_link -> %s: %s" % (laser_frame, e))
if abs(m.x - laser_x) > 1e-6 or abs(m.y) > 1e-6:
    fail("base_link -> %s at (%.4f, %.4f), expected x = %.4f" % (laser_frame, m.x, m.y, laser_x))
print("tf ok: base_link -> %s at x = %.4f, z = %.4f" % (laser_frame, m.x, m.z), flush=True)

# The stack localises from a pose estimate, as rviz's "2D Pose Estimate" gives it.
p0 = rospy.wait_for_message("ground_truth/pose", PoseStamped, timeout=20)
init = PoseWithCovarianceStamped()
init.header.frame_id = "map"
init.header.stamp = p0.header.stamp
init.pose.pose = p0.pose
init.pose.covariance[0] = init.pose.covariance[7] = 0.1 ** 2
init.pose.covariance[35] = 0.1 ** 2
ip = rospy.Publisher("initialpose", PoseWithCovarianceStamped, queue_size=1, latch=True)
ip.publish(init)

# 1. The move_base action through actionlib's own client.
client = actionlib.SimpleActionClient("move_base", MoveBaseAction)
if not client.wait_for_server(rospy.Duration(30)):
    fail("no move_base action server within 30 s")
t0 = time.time()
client.send_goal(MoveBaseGoal(target_pose=target(gx1, gy1)))
if not client.wait_for_result(rospy.Duration(T)):
    fail("move_base action: no result within %.0f s (state %s)" % (T, client.get_state()))
st = client.get_state()
p = truth()
if st != GoalStatus.SUCCEEDED:
    fail("move_base action ended %d (%s), robot at (%.2f, %.2f)" % (st, client.get_goal_status_text(), p.x, p.y))
d1 = math.hypot(p.x - gx1, p.y - gy1)
if d1 > 0.3:
    fail("move_base action SUCCEEDED with the robot %.2f m from the goal" % d1)
print("action ok: SUCCEEDED in %.1f s wall, %.2f m from the goal" % (time.time() - t0, d1), flush=True)

# Pose ok: map -> base_link through the stack's map -> odom agrees with the ground truth.
try:
    tb = buf.lookup_transform("map", "base_link", rospy.Time(0), rospy.Duration(5)).transform.translation
except tf2_ros.TransformException as e:
    fail("no map -> base_link (map -> odom from amcl, odom -> base_link from the simulator): %s" % e)
p = truth()
if math.hypot(tb.x - p.x, tb.y - p.y) > 0.3:
    fail("map -> base_link at (%.2f, %.2f), ground truth (%.2f, %.2f)" % (tb.x, tb.y, p.x, p.y))
try:
    buf.lookup_transform("map", laser_frame, rospy.Time(0), rospy.Duration(5))
except tf2_ros.TransformException as e:
    fail("no map -> %s: %s" % (laser_frame, e))
print("tf ok: map -> odom -> base_link -> %s resolves; map -> base_link within %.2f m of the truth" % (laser_frame, math.hypot(tb.x - p.x, tb.y - p.y)), flush=True)

# 2. move_base_simple/goal: the stack names the goal; its status ends SUCCEEDED.
statuses = []
rospy.Subscriber("move_base/status", GoalStatusArray, lambda m: statuses.append(m), queue_size=100)
rospy.sleep(1.0)
known = {s.goal_id.id for m in list(statuses) for s in m.status_list}
known.add(client.gh.comm_state_machine.action_goal.goal_id.id)  # the action's goal
simple = rospy.Publisher("move_base_simple/goal", PoseStamped, queue_size=1, latch=True)
rospy.sleep(0.5)
simple.publish(target(gx2, gy2))
t0 = time.time()
new_id, final = None, None
while time.time() - t0 < T and final is None:
    for m in list(statuses):
        for s in m.status_list:
            if s.goal_id.id in known:
                continue
            new_id = new_id or s.goal_id.id
            if s.goal_id.id == new_id and s.status in (GoalStatus.SUCCEEDED, GoalStatus.ABORTED, GoalStatus.PREEMPTED, GoalStatus.REJECTED):
                final = s.status
    time.sleep(0.1)
if new_id is None:
    fail("move_base_simple/goal: no new goal id on move_base/status within %.0f s (ids seen: %s)" % (T, sorted({s.goal_id.id for m in statuses for s in m.status_list})))
p = truth()
if final != GoalStatus.SUCCEEDED:
    fail("move_base_simple/goal: goal %r ended %s, robot at (%.2f, %.2f)" % (new_id, final, p.x, p.y))
d2 = math.hypot(p.x - gx2, p.y - gy2)
if d2 > 0.3:
    fail("move_base_simple/goal SUCCEEDED with the robot %.2f m from the goal" % d2)
print("simple goal ok: %r SUCCEEDED in %.1f s wall, %.2f m from the goal" % (new_id, time.time() - t0, d2), flush=True)

# 3. clear_costmaps as a service.
try:
    rospy.wait_for_service("move_base/clear_costmaps", timeout=10)
    rospy.ServiceProxy("move_base/clear_costmaps", Empty)()
except (rospy.ROSException, rospy.ServiceException) as e:
    fail("move_base/clear_costmaps: %s" % e)
print("clear_costmaps ok", flush=True)
print("PASS", flush=True)
