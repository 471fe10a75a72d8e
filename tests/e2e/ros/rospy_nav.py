#!/usr/bin/python3
"""A navigation node in plain rospy, the way a student would write one: a move_base action
server (actionlib SimpleActionServer for move_base_msgs/MoveBaseAction on `move_base`) that
reads the robot's pose from tf (map -> base_link), the laser on `scan`, and drives with
`cmd_vel`: turn toward the goal, go forward, turn away when the scan shows something close
ahead; SUCCEEDED within 0.15 m, ABORTED when it gives up, PREEMPTED when cancelled.

It runs on simulated time (use_sim_time, a rospy.Rate on /clock) and records what it saw:
every /odom and /ground_truth/pose message with its stamp, and the stamp of each goal. On
shutdown (and after each goal) it writes per-goal path lengths to the JSON file given as its
first argument: the positions of the messages stamped from one goal's stamp to the next's,
summed, by odometry and by ground truth, with the odometry's total turning.

    rospy_nav.py OUT.json [--give-up S] [--stall K] [--abort K]

--give-up S: ABORTED after S s of sim time on a goal (default 25); --stall K: stand still on
the K-th goal (1-based) until cancelled; --abort K: give up on the K-th goal after 2 s.
"""
import argparse, json, math, os, sys, threading
import rospy, actionlib, tf2_ros
from geometry_msgs.msg import Twist, PoseStamped
from move_base_msgs.msg import MoveBaseAction, MoveBaseResult
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan

REACHED = 0.15  # m
CLOSE = 0.35  # m: an obstacle this close ahead makes the robot turn away
RATE = 20.0  # Hz of sim time


def yaw_of(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


class Nav:
    def __init__(self, out, give_up, stall, abort):
        self.out, self.give_up, self.stall, self.abort = out, give_up, stall, abort
        self.lock = threading.Lock()
        self.odoms, self.truths, self.goals = [], [], []  # (stamp, x, y, yaw); (stamp, id, result)
        self.scan = None
        self.tf = tf2_ros.Buffer(cache_time=rospy.Duration(30))
        self.listener = tf2_ros.TransformListener(self.tf)
        rospy.Subscriber("scan", LaserScan, self.on_scan, queue_size=1)
        rospy.Subscriber("odom", Odometry, self.on_odom, queue_size=10000)
        rospy.Subscriber("ground_truth/pose", PoseStamped, self.on_truth, queue_size=10000)
        self.cmd = rospy.Publisher("cmd_vel", Twist, queue_size=10)
        self.server = actionlib.SimpleActionServer("move_base", MoveBaseAction, execute_cb=self.execute, auto_start=False)
        self.server.start()

    def on_scan(self, m):
        self.scan = m

    def on_odom(self, m):
        p = m.pose.pose
        with self.lock:
            self.odoms.append((m.header.stamp.to_sec(), p.position.x, p.position.y, yaw_of(p.orientation)))

    def on_truth(self, m):
        p = m.pose
        with self.lock:
            self.truths.append((m.header.stamp.to_sec(), p.position.x, p.position.y, yaw_of(p.orientation)))

    def ahead(self):
        """The nearest return within 30 degrees of straight ahead, and which side is freer (+1 left)."""
        s = self.scan
        if s is None:
            return float("inf"), 1.0
        near, left, right = float("inf"), 0.0, 0.0
        for i, r in enumerate(s.ranges):
            a = wrap(s.angle_min + i * s.angle_increment)
            if math.isnan(r) or r < s.range_min:
                continue
            r = min(r, s.range_max)
            if abs(a) < math.radians(30):
                near = min(near, r)
            if 0 < a < math.radians(90):
                left += r
            elif -math.radians(90) < a < 0:
                right += r
        return near, (1.0 if left >= right else -1.0)

    def pose(self):
        t = self.tf.lookup_transform("map", "base_link", rospy.Time(0), rospy.Duration(1.0))
        return t.transform.translation.x, t.transform.translation.y, yaw_of(t.transform.rotation)

    def execute(self, goal):
        g = goal.target_pose
        with self.lock:
            self.goals.append([g.header.stamp.to_sec(), g.header.frame_id, None])
            k = len(self.goals)
        give_up = 2.0 if k == self.abort else self.give_up
        rate = rospy.Rate(RATE)
        t0 = rospy.get_time()
        mode, turn, until = "go", 1.0, 0.0
        result = "ABORTED"
        while not rospy.is_shutdown():
            if self.server.is_preempt_requested():
                self.cmd.publish(Twist())
                self.server.set_preempted()
                result = "PREEMPTED"
                break
            try:
                x, y, yaw = self.pose()
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException, tf2_ros.ExtrapolationException) as e:
                rospy.logwarn("no map -> base_link yet: %s", e)
                try:
                    rate.sleep()
                except rospy.ROSInterruptException:
                    break
                continue
            dx, dy = g.pose.position.x - x, g.pose.position.y - y
            d = math.hypot(dx, dy)
            if d < REACHED:
                self.cmd.publish(Twist())
                self.server.set_succeeded(MoveBaseResult(), "goal reached")
                result = "SUCCEEDED"
                break
            if k == self.stall:
                self.cmd.publish(Twist())
                try:
                    rate.sleep()
                except rospy.ROSInterruptException:
                    break
                continue
            if rospy.get_time() - t0 > give_up:
                self.cmd.publish(Twist())
                self.server.set_aborted(MoveBaseResult(), "gave up")
                break
            e = wrap(math.atan2(dy, dx) - yaw)
            near, side = self.ahead()
            now = rospy.get_time()
            cmd = Twist()
            if mode == "go" and near < CLOSE and near < d:
                mode, turn = "turn", side  # something close ahead: turn away from it
            if mode == "turn":
                cmd.angular.z = 0.8 * turn
                if near > CLOSE + 0.25:
                    mode, until = "pass", now + 2.0  # clear ahead: drive past the obstacle
            elif mode == "pass":
                if near < CLOSE:
                    mode, turn = "turn", side
                else:
                    cmd.linear.x = min(0.25, 0.5 * (near - 0.2))
                    if now > until:
                        mode = "go"
            elif abs(e) > 0.4:
                cmd.angular.z = math.copysign(min(1.0, 1.5 * abs(e)), e)
            else:
                cmd.linear.x = min(0.3, 0.6 * d, 0.5 * max(near - 0.2, 0.0))
                cmd.angular.z = 1.5 * e
            self.cmd.publish(cmd)
            try:
                rate.sleep()
            except rospy.ROSInterruptException:
                break
        with self.lock:
            self.goals[-1][2] = result
        self.dump()

    def dump(self):
        with self.lock:
            goals = list(self.goals)
            odoms, truths = list(self.odoms), list(self.truths)
        out = []
        for k, (stamp, frame, result) in enumerate(goals):
            end = goals[k + 1][0] if k + 1 < len(goals) else float("inf")

            def length(track):
                seg = [p for p in track if stamp - 1e-6 <= p[0] < end - 1e-6]
                L = sum(math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(seg, seg[1:]))
                turn = sum(abs(wrap(b[3] - a[3])) for a, b in zip(seg, seg[1:]))
                return L, turn, len(seg)

            lo, turn, n_odom = length(odoms)
            lt, _, n_truth = length(truths)
            out.append({"goal_stamp": stamp, "frame_id": frame, "result": result, "odom_path_length": lo, "odom_turn": turn, "odom_messages": n_odom, "truth_path_length": lt, "truth_messages": n_truth})
        tmp = self.out + ".tmp"
        with open(tmp, "w") as f:
            json.dump({"goals": out, "pid": os.getpid(), "use_sim_time": rospy.get_param("/use_sim_time", False)}, f, indent=1)
        os.replace(tmp, self.out)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--give-up", type=float, default=25.0)
    ap.add_argument("--stall", type=int, default=0)
    ap.add_argument("--abort", type=int, default=0)
    a = ap.parse_args(rospy.myargv(sys.argv)[1:])
    rospy.init_node("rospy_nav")
    if not rospy.get_param("/use_sim_time", False):
        rospy.logfatal("rospy_nav: /use_sim_time is not set: start it from `xhab bench --launch`")
        sys.exit(1)
    nav = Nav(a.out, a.give_up, a.stall, a.abort)
    rospy.on_shutdown(nav.dump)
    rospy.loginfo("rospy_nav: ready")
    rospy.spin()
