#!/usr/bin/python3
"""Faulty ROS 1 peers against a running `xhab ros sim ... --physics` (ROS_MASTER_URI set).

Each fault is a hand-written TCPROS peer (Python's standard library: XML-RPC and sockets),
registered with the real master as a publisher of `cmd_vel` or speaking to our `odom`
publisher directly:
  md5        a cmd_vel publisher answering our subscriber's handshake with a wrong md5sum;
  sub_md5    a subscriber asking our odom publisher with a wrong md5sum;
  malformed  a cmd_vel publisher sending frames too short for a Twist, an empty frame, and a
             length prefix of almost 4 GiB before it closes;
  cut        a cmd_vel publisher that disconnects in the middle of a message.
After the faults a real rospy node must still read odom and drive the robot with cmd_vel.
Prints PASS, or FAIL with the reason (exit status 1)."""
import os, socket, struct, sys, threading, time
import xmlrpc.client
from xmlrpc.server import SimpleXMLRPCServer

MASTER = os.environ["ROS_MASTER_URI"]
TWIST_MD5 = "9f195f881246fdfa2798d1d3eebca84a"


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


def header(fields):
    body = b"".join(struct.pack("<I", len(f)) + f for f in (("%s=%s" % kv).encode() for kv in fields.items()))
    return struct.pack("<I", len(body)) + body


def read_header(conn):
    n = struct.unpack("<I", recv_exact(conn, 4))[0]
    body, out = recv_exact(conn, n), {}
    while body:
        m = struct.unpack("<I", body[:4])[0]
        k, _, v = body[4:4 + m].decode().partition("=")
        out[k], body = v, body[4 + m:]
    return out


def recv_exact(conn, n):
    b = b""
    while len(b) < n:
        chunk = conn.recv(n - len(b))
        if not chunk:
            raise EOFError("peer closed")
        b += chunk
    return b


class FakePublisher:
    """A publisher of cmd_vel registered with the master; `serve(conn)` runs the fault."""

    def __init__(self, name, serve):
        self.name, self.serve, self.connections = name, serve, 0
        self.tcp = socket.socket()
        self.tcp.bind(("127.0.0.1", 0))
        self.tcp.listen(4)
        self.rpc = SimpleXMLRPCServer(("127.0.0.1", 0), logRequests=False, allow_none=True)
        port = self.tcp.getsockname()[1]
        self.rpc.register_function(lambda caller, topic, protocols: [1, "", ["TCPROS", "127.0.0.1", port]], "requestTopic")
        self.rpc.register_function(lambda caller: [1, "", os.getpid()], "getPid")
        self.rpc.register_function(lambda caller, topic, pubs: [1, "", 0], "publisherUpdate")
        self.rpc.register_function(lambda caller, msg="": [1, "", 0], "shutdown")
        threading.Thread(target=self.rpc.serve_forever, daemon=True).start()
        threading.Thread(target=self.accept, daemon=True).start()
        api = "http://127.0.0.1:%d/" % self.rpc.server_address[1]
        code, msg, _ = xmlrpc.client.ServerProxy(MASTER).registerPublisher(name, "/cmd_vel", "geometry_msgs/Twist", api)
        if code != 1:
            fail("%s: registerPublisher: %s" % (name, msg))
        self.api = api

    def accept(self):
        while True:
            conn, _ = self.tcp.accept()
            self.connections += 1
            try:
                asked = read_header(conn)
                self.serve(conn, asked)
            except Exception as e:  # the fault itself may end the connection
                print("%s: %s" % (self.name, e), flush=True)
            finally:
                conn.close()

    def unregister(self):
        xmlrpc.client.ServerProxy(MASTER).unregisterPublisher(self.name, "/cmd_vel", self.api)


def reply(conn, name, md5):
    conn.sendall(header({"callerid": name, "md5sum": md5, "type": "geometry_msgs/Twist", "topic": "/cmd_vel", "latching": "0"}))


def wrong_md5(conn, asked):
    if asked.get("md5sum") != TWIST_MD5:
        fail("our cmd_vel subscriber asked for md5sum %r" % asked.get("md5sum"))
    reply(conn, "/fault_md5", "0123456789abcdef0123456789abcdef")
    time.sleep(1.0)


def malformed(conn, asked):
    reply(conn, "/fault_malformed", TWIST_MD5)
    conn.sendall(struct.pack("<I", 8) + b"\xff" * 8)  # 8 bytes where a Twist needs 48
    conn.sendall(struct.pack("<I", 0))  # an empty frame
    conn.sendall(struct.pack("<I", 0xFFFFFFF0) + b"\x00" * 64)  # almost 4 GiB announced
    time.sleep(0.5)


def cut(conn, asked):
    reply(conn, "/fault_cut", TWIST_MD5)
    conn.sendall(struct.pack("<I", 48) + struct.pack("<3d", 0.5, 0, 0)[:20])  # 20 of 48 bytes
    time.sleep(0.2)


def subscriber_with_wrong_md5():
    """Asks our odom publisher for a connection with a wrong md5sum: it must refuse (close)."""
    code, msg, pubs = xmlrpc.client.ServerProxy(MASTER).registerSubscriber("/fault_sub", "/odom", "nav_msgs/Odometry", "http://127.0.0.1:9/")
    if code != 1 or not pubs:
        fail("no odom publisher at the master: %s %r" % (msg, pubs))
    code, msg, proto = xmlrpc.client.ServerProxy(pubs[0]).requestTopic("/fault_sub", "/odom", [["TCPROS"]])
    if code != 1:
        fail("requestTopic odom: %s" % msg)
    s = socket.create_connection((proto[1], proto[2]), timeout=5)
    s.sendall(header({"callerid": "/fault_sub", "md5sum": "0123456789abcdef0123456789abcdef", "type": "nav_msgs/Odometry", "topic": "/odom", "tcp_nodelay": "1"}))
    try:
        data = s.recv(4096)
    except socket.timeout:
        fail("our odom publisher neither refused nor answered a wrong md5sum within 5 s")
    if data:
        fail("our odom publisher sent %d bytes to a subscriber with a wrong md5sum" % len(data))
    s.close()
    xmlrpc.client.ServerProxy(MASTER).unregisterSubscriber("/fault_sub", "/odom", "http://127.0.0.1:9/")
    print("sub_md5: refused", flush=True)


peers = [FakePublisher("/fault_md5", wrong_md5), FakePublisher("/fault_malformed", malformed), FakePublisher("/fault_cut", cut)]
deadline = time.time() + 20
while time.time() < deadline and not all(p.connections for p in peers):
    time.sleep(0.1)
for p in peers:
    if not p.connections:
        fail("our cmd_vel subscriber never connected to %s" % p.name)
print("faults served: %s" % ", ".join("%s %d connection(s)" % (p.name, p.connections) for p in peers), flush=True)
time.sleep(1.0)
for p in peers:
    p.unregister()
subscriber_with_wrong_md5()

# The node lives on: a real rospy node reads odom and drives the robot forward.
import rospy
from nav_msgs.msg import Odometry
from geometry_msgs.msg import Twist

rospy.init_node("xhab_fault_check", anonymous=True)
p0 = rospy.wait_for_message("/odom", Odometry, timeout=20).pose.pose.position
pub = rospy.Publisher("/cmd_vel", Twist, queue_size=1)
t0 = time.time()
while time.time() - t0 < 3.0:
    msg = Twist()
    msg.linear.x = 0.2
    pub.publish(msg)
    time.sleep(0.05)
p1 = rospy.wait_for_message("/odom", Odometry, timeout=20).pose.pose.position
moved = ((p1.x - p0.x) ** 2 + (p1.y - p0.y) ** 2) ** 0.5
if not moved > 0.1:
    fail("after the faults cmd_vel no longer moves the robot (odom moved %.3f m in 3 s at 0.2 m/s)" % moved)
print("after the faults: odom moved %.3f m" % moved, flush=True)
print("PASS", flush=True)
