#!/usr/bin/env python3
"""Writes the fuzz targets' seed inputs (tiny, hand-made, valid) beside this script:
seeds/TARGET/NAME. Run it again after changing it; the outputs are checked in.

Input layouts follow the targets (fuzz_targets/*.rs): a glTF file's external files and an OBJ's
material library come after a NUL byte; map images and ROS messages start with a selector byte.
"""

import base64
import gzip
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def put(target, name, data):
    d = os.path.join(HERE, target)
    os.makedirs(d, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def png(width, height, color_type, rows):
    """A PNG (8 bit) of `rows` (bytes per row, without filter bytes)."""
    raw = b"".join(b"\0" + r for r in rows)
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    ihdr = struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


# --- glTF ---------------------------------------------------------------------------------
POS = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 0, -1)
IDX = struct.pack("<3H", 0, 1, 2) + b"\0\0"
UV = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
TEX_PNG = png(2, 2, 2, [b"\xff\x00\x00\x00\xff\x00", b"\x00\x00\xff\xff\xff\xff"])


def gltf_doc(buffer_uri, buffer_len, textured=False, mode=None):
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"name": "floor", "children": [1], "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0, 0, 1]},
            {"mesh": 0, "translation": [0, 0.1, 0], "rotation": [0, 0, 0, 1], "scale": [2, 1, 1]},
        ],
        "buffers": [{"byteLength": buffer_len}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 6},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
        "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    }
    if buffer_uri is not None:
        doc["buffers"][0]["uri"] = buffer_uri
    if mode is not None:
        doc["meshes"][0]["primitives"][0]["mode"] = mode
    if textured:
        doc["bufferViews"].append({"buffer": 0, "byteOffset": 44, "byteLength": 24})
        doc["accessors"].append({"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"})
        doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = 2
        doc["meshes"][0]["primitives"][0]["material"] = 0
        doc["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "baseColorTexture": {"index": 0}}}]
        doc["textures"] = [{"source": 0, "sampler": 0}]
        doc["samplers"] = [{"wrapS": 33071, "wrapT": 33648}]
        doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(TEX_PNG).decode()}]
    return json.dumps(doc, separators=(",", ":"))


def glb(json_text, bin_data):
    j = json_text.encode()
    j += b" " * (-len(j) % 4)
    b = bin_data + b"\0" * (-len(bin_data) % 4)
    body = struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(b), b"BIN\0") + b
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


plain = POS + IDX
put("gltf", "tri.gltf", gltf_doc("data:application/octet-stream;base64," + base64.b64encode(plain).decode(), len(plain)))
put("gltf", "external.gltf", gltf_doc("tri%20data.bin", len(plain)).encode() + b"\0" + plain)
put("gltf", "strip.gltf", gltf_doc("data:application/octet-stream;base64," + base64.b64encode(plain).decode(), len(plain), mode=5))
textured = POS + IDX + UV
put("gltf", "textured.gltf", gltf_doc("data:application/octet-stream;base64," + base64.b64encode(textured).decode(), len(textured), textured=True))
put("gltf", "tri.glb", glb(gltf_doc(None, len(plain)), plain))

# --- OBJ (+ MTL after a NUL) ----------------------------------------------------------------
put("obj", "tri.obj", "# a triangle\nv 0 0 0\nv 1 0 0\nv 0 0 -1\nf 1 2 3\n")
put("obj", "quad_mtl.obj",
    "mtllib room.mtl\no floor\nv 0 0 0\nv 2 0 0\nv 2 0 -2\nv 0 0 -2\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 1 0\n"
    "usemtl wood\nf 1/1/1 2/2/1 3/3/1 4/4/1\ng wall\nusemtl red\nf -4 -3 -2\n"
    "\0newmtl wood\nKa 0.1 0.1 0.1\nKd 0.8 0.6 0.4\nKs 0 0 0\nNs 10\nd 1\nillum 2\nmap_Kd -clamp on wood.png\n"
    "newmtl red\nKd 1 0 0\n")
put("obj", "polygon.obj", "o ceiling\nv 0 2 0\nv 1 2 0\nv 1 2 1\nf 1 2 3\no room\nv 0 0 0\nv 1 0 0\nv 1 0.5 1\nv 0.5 0 1.5\nv 0 0 1\nf 4 5 6 7 8\nl 4 5\n")

# --- PLY ----------------------------------------------------------------------------------
HEAD = "ply\nformat {}\ncomment tiny\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
put("ply", "ascii.ply", HEAD.format("ascii 1.0") + "0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 9\n3 0 1 2\n4 0 1 2 3\n")
verts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
for fmt, e in [("binary_little_endian 1.0", "<"), ("binary_big_endian 1.0", ">")]:
    body = b"".join(struct.pack(e + "fffB", *v, 7) for v in verts)
    body += struct.pack(e + "B3i", 3, 0, 1, 2) + struct.pack(e + "B4i", 4, 0, 1, 2, 3)
    put("ply", ("le" if e == "<" else "be") + ".ply", HEAD.format(fmt).encode() + body)
put("ply", "double_index.ply",
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
    "element face 1\nproperty list uchar uint vertex_index\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")

# --- map_server YAML ----------------------------------------------------------------------
put("map_yaml", "basic.yaml", "image: map.pgm\nresolution: 0.05\norigin: [-10.0, -10.0, 0.0]\n")
put("map_yaml", "full.yaml", "image: /maps/map.png\nresolution: 0.1\norigin: [1.5, -2.25, 0.3]\nnegate: 1\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmode: scale\n")
put("map_yaml", "bool.yaml", "{image: m.pgm, resolution: 1, origin: [0, 0, 0], negate: false, mode: raw}\n")

# --- map images (first byte: mode + 3 * negate) -------------------------------------------
put("map_image", "p5.pgm", b"\x00P5\n# CREATOR: xhab\n3 2\n255\n" + bytes([0, 254, 205, 100, 240, 10]))
put("map_image", "p5_16bit.pgm", b"\x01P5 2 2 65535\n" + struct.pack(">4H", 0, 65535, 30000, 52000))
put("map_image", "p2.pgm", b"\x06P2\n3 2\n15\n0 15 7\n3 12 1\n")
put("map_image", "gray.png", b"\x00" + png(2, 2, 0, [b"\x00\xff", b"\xcd\x80"]))
put("map_image", "rgba.png", b"\x01" + png(2, 1, 6, [b"\x00\x00\x00\xff\xff\xff\xff\x00"]))
put("map_image", "rgb.png", b"\x02" + png(1, 2, 2, [b"\x10\x20\x30", b"\xfe\xfe\xfe"]))

# --- episodes -----------------------------------------------------------------------------
ep = {"episodes": [
    {"episode_id": 0, "scene_id": "data/scene.glb", "start_position": [1.0, 0.05, -2.0],
     "start_rotation": [0, 0.7071, 0, 0.7071], "info": {"geodesic_distance": 3.2},
     "goals": [{"position": [3.0, 0.05, -4.0], "radius": None}], "shortest_paths": None, "start_room": None},
    {"episode_id": "e1", "scene_id": "s", "start_position": [0, 0, 0], "start_rotation": [0, 0, 0, 1],
     "goals": [{"position": [1, 0, 1], "radius": 0.36}, {"position": [2, 0, 2]}]},
]}
text = json.dumps(ep)
put("episodes", "two.json", text)
put("episodes", "two.json.gz", gzip.compress(text.encode(), mtime=0))
put("episodes", "empty.json", '{"episodes": []}')

# --- robot profiles -----------------------------------------------------------------------
put("robot_profile", "round.yaml", "name: r\nradius: 0.18\nheight: 0.4\nmass: 10\nwheel_base: 0.3\nmax_linear: 0.5\nmax_angular: 1.5\n"
    "max_linear_accel: 1.0\nmax_angular_accel: 3.0\ncamera_height: 0.3\n")
put("robot_profile", "footprint.yaml", "name: f\nradius: 0.2\nheight: 0.2\nmass: 1.5\nwheel_base: 0.16\nmax_linear: 0.22\nmax_angular: 2.84\n"
    "max_linear_accel: 2.5\nmax_angular_accel: 3.2\ncamera_height: 0.18\nfootprint: [[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]]\n"
    "laser: {frame: base_scan, x: -0.032, y: 0, z: 0.172}\n")

# --- nav params (files split at NUL; `@NS` first line: the namespace) ----------------------
put("nav_params", "move_base.yaml", "base_local_planner: dwa_local_planner/DWAPlannerROS\nshutdown_costmaps: false\ncontroller_frequency: 10.0\n"
    "planner_patience: 5.0\nrecovery_behavior_enabled: true\nrecovery_behaviors: [{name: rotate_recovery, type: rotate_recovery/RotateRecovery}]\n")
put("nav_params", "costmaps.yaml",
    "@global_costmap\nfootprint: [[-0.105, -0.105], [-0.105, 0.105], [0.041, 0.105], [0.041, -0.105]]\ninflation_radius: 1.0\n"
    "cost_scaling_factor: 3.0\nmap_type: costmap\nobservation_sources: scan\nscan: {sensor_frame: base_scan, data_type: LaserScan, topic: scan, marking: true, clearing: true}\n"
    "\0@local_costmap\nrolling_window: true\nwidth: 3\nheight: 3\nresolution: 0.05\nplugins: [{name: obstacle_layer, type: 'costmap_2d::ObstacleLayer'}, {name: inflation_layer, type: 'costmap_2d::InflationLayer'}]\n"
    "obstacle_layer: {obstacle_range: 3.0, raytrace_range: 3.5}\n")
put("nav_params", "dwa.yaml", "DWAPlannerROS:\n  max_vel_x: 0.22\n  min_vel_x: -0.22\n  max_vel_theta: 2.75\n  acc_lim_x: 2.5\n  vx_samples: 20\n"
    "  vth_samples: 40\n  sim_time: 1.5\n  xy_goal_tolerance: 0.05\n  yaw_goal_tolerance: 0.17\n  latch_xy_goal_tolerance: false\n"
    "  path_distance_bias: 32.0\n  goal_distance_bias: 20.0\n  occdist_scale: 0.02\n")
put("nav_params", "amcl.yaml", "@amcl\nmin_particles: 500\nmax_particles: 3000\nkld_err: 0.02\nupdate_min_d: 0.20\nupdate_min_a: !degrees 11.5\n"
    "laser_model_type: likelihood_field\nodom_model_type: diff\nodom_alpha1: 0.1\nuse_map_topic: yes\n")
# Nav2's layout (ros__parameters under node names, plugins by name), as nav2_bringup writes it.
put("nav_params", "nav2.yaml",
    "amcl:\n  ros__parameters:\n    alpha1: 0.2\n    max_particles: 2000\n    laser_model_type: \"likelihood_field\"\n"
    "controller_server:\n  ros__parameters:\n    controller_frequency: 20.0\n    controller_plugins: [\"FollowPath\"]\n"
    "    goal_checker_plugins: [\"general_goal_checker\"]\n    general_goal_checker:\n      plugin: \"nav2_controller::SimpleGoalChecker\"\n"
    "      xy_goal_tolerance: 0.25\n    FollowPath:\n      plugin: \"dwb_core::DWBLocalPlanner\"\n      max_vel_x: 0.26\n"
    "      vx_samples: 20\n      critics: [\"BaseObstacle\", \"PathAlign\", \"PathDist\", \"GoalDist\"]\n      PathDist.scale: 32.0\n"
    "local_costmap:\n  local_costmap:\n    ros__parameters:\n      rolling_window: true\n      width: 3\n      robot_radius: 0.22\n"
    "      plugins: [\"voxel_layer\", \"inflation_layer\"]\n      inflation_layer:\n        plugin: \"nav2_costmap_2d::InflationLayer\"\n"
    "        cost_scaling_factor: 3.0\n        inflation_radius: 0.55\n      voxel_layer:\n        plugin: \"nav2_costmap_2d::VoxelLayer\"\n"
    "        observation_sources: scan\n        scan:\n          topic: /scan\n          data_type: \"LaserScan\"\n          marking: True\n"
    "global_costmap:\n  global_costmap:\n    ros__parameters:\n      footprint: \"[[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]]\"\n"
    "planner_server:\n  ros__parameters:\n    planner_plugins: [\"GridBased\"]\n    GridBased:\n      plugin: \"nav2_navfn_planner::NavfnPlanner\"\n      tolerance: 0.5\n"
    "bt_navigator:\n  ros__parameters:\n    global_frame: map\n")

# --- ROS 1 messages (first byte: the type, as in fuzz_targets/ros_msgs.rs) ----------------
def s(text):
    b = text.encode()
    return struct.pack("<I", len(b)) + b


def header(frame):
    return struct.pack("<Iii", 7, 12, 500) + s(frame)


pose = struct.pack("<7d", 1.0, 2.0, 0.0, 0.0, 0.0, 0.3826834, 0.9238795)
twist = struct.pack("<6d", 0.2, 0, 0, 0, 0, -0.5)
cov = struct.pack("<36d", *([0.01] + [0] * 35))
goal_id = struct.pack("<ii", 3, 4) + s("goal-1")
msgs = {
    0: twist,
    1: header("odom") + s("base_link") + pose + cov + twist + cov,
    2: header("base_scan") + struct.pack("<7f", -3.14, 3.14, 1.57, 0, 0.2, 0.12, 3.5) + struct.pack("<I5f", 5, 1.0, 0.1, 9.0, float("inf"), float("nan")) + struct.pack("<I", 0),
    3: header("map") + pose + cov,
    4: header("") + goal_id + header("map") + pose,
    5: goal_id,
    6: header("") + struct.pack("<I", 2) + goal_id + b"\x01" + s("active") + goal_id + b"\x03" + s(""),
    7: header("") + goal_id + b"\x04" + s("aborted"),
    8: header("map") + pose,
    9: header("map") + struct.pack("<iifII", 1, 2, 0.05, 3, 2) + pose + struct.pack("<I", 6) + bytes([0, 100, 255, 0, 50, 0]),
    10: struct.pack("<I", 2) + header("odom") + s("base_link") + struct.pack("<7d", 1, 0, 0, 0, 0, 0, 1) + header("base_link") + s("laser") + struct.pack("<7d", -0.03, 0, 0.17, 0, 0, 0, 1),
    11: struct.pack("<h", 1),
    12: struct.pack("<I", 0) + s("ep-0") + struct.pack("<ii", 1, 0) + header("map") + pose + header("map") + pose + cov + struct.pack("<iiii", 1, 0, 0, 0),
    13: struct.pack("<IIii?", 0, 5, 2, 0, True),
    14: struct.pack("<IIB", 0, 5, 0) + twist + struct.pack("<h", -1),
}
names = ["twist", "odometry", "laser_scan", "pose_with_covariance_stamped", "move_base_action_goal", "goal_id",
         "goal_status_array", "move_base_action_result", "pose_stamped", "occupancy_grid", "tf_message", "int16",
         "xhab_episode", "xhab_step", "xhab_step_reply"]
for k, body in msgs.items():
    put("ros_msgs", f"{k:02}_{names[k]}", bytes([k]) + body)
