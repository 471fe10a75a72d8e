#!/usr/bin/python3
"""Checks that a bag recorded (`rosbag record -a`) during a lock-step `xhab bench --ros` run
holds standard messages only on standard topics:

- xhab's lock-step protocol (xhab_msgs) on /xhab/* only, and nothing else there;
- per topic, header stamps never go back (odom, scan, ground truth, clock, amcl_pose; tf per
  parent -> child), and none is zero;
- no frame_id `probe` (nor an empty one) on any stamped message;
- nothing on initialpose or move_base_simple/goal (lock-step announces episodes on
  xhab/episode), and never a pose at (0, 0, 0) with an empty frame there;
- scans: ranges sized by their angles, each finite within [range_min, range_max] or +inf;
- odom: odom -> base_link, a unit quaternion, a covariance.

    check_bag.py BAG

Prints a summary and PASS; exits non-zero with FAIL: ... lines otherwise.
"""
import math, sys
import rosbag

failures = []


def fail(msg):
    if len(failures) < 30:
        print("FAIL: " + msg, flush=True)
    failures.append(msg)


def stamp(h):
    return (h.stamp.secs, h.stamp.nsecs)


counts, types = {}, {}
last = {}  # (topic, key) -> stamp
MONOTONIC = {"/odom", "/scan", "/ground_truth/pose", "/amcl_pose"}
REQUIRED = ["/clock", "/odom", "/scan", "/tf", "/tf_static", "/map", "/ground_truth/pose", "/cmd_vel", "/xhab/step", "/xhab/step_reply", "/xhab/episode"]


def headers(msg, path=""):
    """Every std_msgs/Header inside msg (recursively), with its path."""
    if getattr(msg, "_type", None) == "std_msgs/Header":
        yield path, msg
        return
    for name in getattr(msg, "__slots__", []):
        v = getattr(msg, name)
        if hasattr(v, "__slots__"):
            yield from headers(v, path + "." + name)
        elif isinstance(v, (list, tuple)) and v and hasattr(v[0], "__slots__"):
            for i, x in enumerate(v):
                yield from headers(x, "%s.%s[%d]" % (path, name, i))


with rosbag.Bag(sys.argv[1]) as bag:
    for topic, msg, t in bag.read_messages():
        counts[topic] = counts.get(topic, 0) + 1
        ty = msg._type
        types.setdefault(topic, set()).add(ty)
        n = counts[topic]
        if ty.startswith("xhab_msgs/") != topic.startswith("/xhab/"):
            if n == 1:
                fail("%s carries %s: xhab's protocol belongs on /xhab/* and only there" % (topic, ty))
        for path, h in headers(msg):
            if h.frame_id == "probe" or "probe" in h.frame_id:
                fail("%s #%d: frame_id %r at %s" % (topic, n, h.frame_id, path or "header"))
        if topic in MONOTONIC:
            s = stamp(msg.header)
            if s == (0, 0):
                fail("%s #%d: zero stamp" % (topic, n))
            if topic in last and s < last[topic]:
                fail("%s #%d: stamp %d.%09d after %d.%09d" % (topic, n, s[0], s[1], last[topic][0], last[topic][1]))
            last[topic] = s
            if not msg.header.frame_id:
                fail("%s #%d: empty frame_id" % (topic, n))
        if topic == "/clock":
            s = (msg.clock.secs, msg.clock.nsecs)
            if s == (0, 0) or ("/clock" in last and s < last["/clock"]):
                fail("/clock #%d: %d.%09d after %r" % (n, s[0], s[1], last.get("/clock")))
            last["/clock"] = s
        if topic == "/tf":
            for tr in msg.transforms:
                key = ("/tf", tr.header.frame_id, tr.child_frame_id)
                s = stamp(tr.header)
                if not tr.header.frame_id or not tr.child_frame_id:
                    fail("/tf #%d: empty frame (%r -> %r)" % (n, tr.header.frame_id, tr.child_frame_id))
                if s == (0, 0):
                    fail("/tf #%d: %s -> %s with a zero stamp" % (n, tr.header.frame_id, tr.child_frame_id))
                if key in last and s < last[key]:
                    fail("/tf #%d: %s -> %s at %d.%09d after %d.%09d" % (n, tr.header.frame_id, tr.child_frame_id, s[0], s[1], last[key][0], last[key][1]))
                last[key] = s
        if topic in ("/initialpose", "/move_base_simple/goal"):
            p = msg.pose.pose if hasattr(msg.pose, "pose") else msg.pose
            if not msg.header.frame_id and p.position.x == 0 and p.position.y == 0 and p.position.z == 0:
                fail("%s #%d: a pose at (0, 0, 0) with an empty frame" % (topic, n))
        if topic == "/scan":
            k = int(round((msg.angle_max - msg.angle_min) / msg.angle_increment)) + 1
            if len(msg.ranges) != k or (msg.intensities and len(msg.intensities) != k):
                fail("/scan #%d: %d ranges, %d intensities for %d angles" % (n, len(msg.ranges), len(msg.intensities), k))
            bad = [r for r in msg.ranges if math.isnan(r) or r == -math.inf or (math.isfinite(r) and not msg.range_min <= r <= msg.range_max)]
            if bad:
                fail("/scan #%d: %d ranges neither within [%.2f, %.2f] nor +inf, e.g. %r" % (n, len(bad), msg.range_min, msg.range_max, bad[:3]))
        if topic == "/odom":
            if msg.header.frame_id != "odom" or msg.child_frame_id != "base_link":
                fail("/odom #%d: %r -> %r" % (n, msg.header.frame_id, msg.child_frame_id))
            q = msg.pose.pose.orientation
            if abs(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w - 1) > 1e-6:
                fail("/odom #%d: quaternion not unit" % n)
            if not any(msg.pose.covariance):
                fail("/odom #%d: no covariance" % n)
        if topic == "/cmd_vel":
            if not all(math.isfinite(v) for v in (msg.linear.x, msg.linear.y, msg.angular.z)):
                fail("/cmd_vel #%d: non-finite" % n)

for t in REQUIRED:
    if counts.get(t, 0) == 0:
        fail("nothing recorded on %s" % t)
for t in ("/initialpose", "/move_base_simple/goal"):
    if counts.get(t, 0):
        fail("%d messages on %s during a lock-step run (episodes are announced on /xhab/episode)" % (counts[t], t))
print("recorded: " + ", ".join("%s %d (%s)" % (t, counts[t], "/".join(sorted(types[t]))) for t in sorted(counts)), flush=True)
if failures:
    print("FAIL: %d problems" % len(failures), flush=True)
    sys.exit(1)
print("PASS", flush=True)
