#!/usr/bin/env python3
"""Writes the malformed input files beside this script (one per failure kind per format).
README.md says what each breaks and what the CLI must say about it; the e2e test `malformed`
(tests/e2e/malformed.rs) feeds each to the command that reads it. The outputs are checked in:
run this again only after changing it.
"""

import base64
import gzip
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def put(name, data):
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


# --- glTF / GLB ---------------------------------------------------------------------------
POS = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 0, -1)
IDX = struct.pack("<3H", 0, 1, 2) + b"\0\0"
BIN = POS + IDX


def doc(**changes):
    d = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "floor", "mesh": 0}],
        "buffers": [{"byteLength": len(BIN), "uri": "data:application/octet-stream;base64," + base64.b64encode(BIN).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
        "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    }
    for path, value in changes.items():
        node = d
        keys = path.split("__")
        for k in keys[:-1]:
            node = node[int(k)] if k.isdigit() else node[k]
        last = keys[-1]
        if value is DELETE:
            del node[int(last) if last.isdigit() else last]
        elif last.isdigit():
            node[int(last)] = value
        else:
            node[last] = value
    return json.dumps(d, separators=(",", ":"))


DELETE = object()


def glb(json_text, bin_data=BIN, version=2, length=None, json_len=None, json_type=b"JSON", bin_len=None):
    j = json_text.encode()
    j += b" " * (-len(j) % 4)
    body = struct.pack("<I4s", len(j) if json_len is None else json_len, json_type) + j
    if bin_data is not None:
        body += struct.pack("<I4s", len(bin_data) if bin_len is None else bin_len, b"BIN\0") + bin_data
    total = 12 + len(body) if length is None else length
    return struct.pack("<4sII", b"glTF", version, total) + body


glb_doc = doc(buffers__0={"byteLength": len(BIN)})
put("glb_truncated_header.glb", b"glTF\x02\x00\x00")
put("glb_bad_magic.glb", b"GLTF" + glb(glb_doc)[4:])
put("glb_bad_version.glb", glb(glb_doc, version=1))
put("glb_length_too_long.glb", glb(glb_doc, length=4096))
put("glb_length_too_short.glb", glb(glb_doc, length=8))
put("glb_bad_chunk_length.glb", glb(glb_doc, json_len=0x7FFFFFF0))
put("glb_bad_chunk_type.glb", glb(glb_doc, json_type=b"BIN\0"))
put("glb_truncated_bin.glb", glb(glb_doc, bin_len=4000))
put("glb_missing_bin.glb", glb(glb_doc, bin_data=None))
put("glb_bad_json.glb", glb('{"asset": {"version": "2.0"}, "scenes": [}'))
put("gltf_accessor_out_of_range.gltf", doc(accessors__0__count=300))
put("gltf_accessor_count_overflow.gltf", doc(accessors__0__count=2**62, accessors__0__byteOffset=8))
put("gltf_accessor_bad_type.gltf", doc(accessors__0__type="SCALAR"))
put("gltf_indices_float.gltf", doc(accessors__1={"bufferView": 0, "componentType": 5126, "count": 3, "type": "SCALAR"}))
put("gltf_missing_buffer_file.gltf", doc(buffers__0={"byteLength": len(BIN), "uri": "missing.bin"}))
put("gltf_bad_base64.gltf", doc(buffers__0={"byteLength": len(BIN), "uri": "data:application/octet-stream;base64,@@not base64@@"}))
put("gltf_bad_percent_uri.gltf", doc(buffers__0={"byteLength": len(BIN), "uri": "%ff%fe.bin"}))
put("gltf_buffer_too_short.gltf", doc(buffers__0__byteLength=4096))
put("gltf_bad_reference.gltf", doc(meshes__0__primitives__0__attributes={"POSITION": 7}))
put("gltf_vertex_index_out_of_range.gltf", doc(buffers__0__uri="data:application/octet-stream;base64," + base64.b64encode(POS + struct.pack("<3H", 0, 1, 9) + b"\0\0").decode()))
put("gltf_nan_vertex.gltf", doc(buffers__0__uri="data:application/octet-stream;base64," + base64.b64encode(struct.pack("<9f", 0, 0, 0, float("nan"), 0, 0, 0, 0, -1) + IDX).decode()))
put("gltf_node_cycle.gltf", doc(nodes=[{"name": "a", "mesh": 0, "children": [1]}, {"name": "b", "children": [0]}]))
put("gltf_no_scene.gltf", doc(scenes=[], scene=DELETE, nodes=[]))

# --- OBJ (+MTL) -----------------------------------------------------------------------------
TRI = "v 0 0 0\nv 1 0 0\nv 0 0 -1\n"
put("obj_face_index_out_of_range.obj", TRI + "f 1 2 9\n")
put("obj_face_index_zero.obj", TRI + "f 0 1 2\n")
put("obj_face_non_numeric.obj", TRI + "f 1 2 three\n")
put("obj_face_index_overflow.obj", TRI + "vt 0 0\nf 1/1 2/4611686018427387904 3/1\n")
put("obj_bad_vertex.obj", "v 0 0 0\nv 1 0\nv 0 0 -1\nf 1 2 3\n")
put("obj_nan_vertex.obj", "v 0 0 0\nv nan 0 0\nv 0 0 -1\nf 1 2 3\n")
put("obj_no_faces.obj", TRI)
put("obj_not_utf8.obj", b"v 0 0 0\nv 1 0 0\n\xff\xfe 0 0 -1\nf 1 2 3\n")
put("obj_mtl_short_kd.obj", "mtllib obj_mtl_short_kd.mtl\nusemtl red\n" + TRI + "f 1 2 3\n")
put("obj_mtl_short_kd.mtl", "newmtl red\nKd 1 0\n")

# --- PLY ------------------------------------------------------------------------------------
HEAD = "ply\nformat {}\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n"
ASCII_BODY = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
put("ply_bad_magic.ply", "plx\n" + HEAD.format("ascii 1.0", 3, 1)[4:] + ASCII_BODY)
put("ply_bad_header.ply", HEAD.format("ascii 1.0", 3, 1).replace("property float y", "property flaot y") + ASCII_BODY)
put("ply_no_end_header.ply", HEAD.format("ascii 1.0", 3, 1).replace("end_header\n", ""))
put("ply_count_overflow.ply", HEAD.format("ascii 1.0", "99999999999999999999999", 1) + ASCII_BODY)
put("ply_wrong_element_count.ply", HEAD.format("ascii 1.0", 5, 1) + ASCII_BODY)
put("ply_non_numeric.ply", HEAD.format("ascii 1.0", 3, 1) + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n")
put("ply_face_index_out_of_range.ply", HEAD.format("ascii 1.0", 3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
put("ply_no_vertex_element.ply", "ply\nformat ascii 1.0\nelement point 1\nproperty float x\nend_header\n1\n")
put("ply_element_without_properties.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nend_header\n")
verts = b"".join(struct.pack("<3f", *v) for v in [(0, 0, 0), (1, 0, 0), (0, 1, 0)])
put("ply_truncated_binary.ply", HEAD.format("binary_little_endian 1.0", 3, 1).encode() + verts + struct.pack("<Bi", 3, 0))

# --- map_server maps (YAML + image) ---------------------------------------------------------
def yaml(image, extra=""):
    return f"image: {image}\nresolution: 0.05\norigin: [-1.0, -1.0, 0.0]\n{extra}"


put("map_missing_image_key.yaml", "resolution: 0.05\norigin: [0.0, 0.0, 0.0]\n")
put("map_typo_key.yaml", yaml("map_ok.pgm", "negat: 1\n"))
put("map_negative_resolution.yaml", yaml("map_ok.pgm").replace("0.05", "-0.05"))
put("map_resolution_text.yaml", yaml("map_ok.pgm").replace("0.05", "fine"))
put("map_bad_origin.yaml", yaml("map_ok.pgm").replace("[-1.0, -1.0, 0.0]", "[-1.0, -1.0]"))
put("map_bad_thresholds.yaml", yaml("map_ok.pgm", "occupied_thresh: 0.1\nfree_thresh: 0.5\n"))
put("map_bad_mode.yaml", yaml("map_ok.pgm", "mode: ternary\n"))
put("map_bad_negate.yaml", yaml("map_ok.pgm", "negate: 2\n"))
put("map_image_not_found.yaml", yaml("map_nowhere.pgm"))
put("map_ok.pgm", b"P5\n3 2\n255\n" + bytes([0, 254, 205, 254, 254, 0]))
put("map_pgm_truncated.yaml", yaml("map_pgm_truncated.pgm"))
put("map_pgm_truncated.pgm", b"P5\n# smaller than it says\n30 20\n255\n" + bytes([254] * 100))
put("map_pgm_bad_magic.yaml", yaml("map_pgm_bad_magic.pgm"))
put("map_pgm_bad_magic.pgm", b"P7\n3 2\n255\n" + bytes(6))
put("map_pgm_bad_header.yaml", yaml("map_pgm_bad_header.pgm"))
put("map_pgm_bad_header.pgm", b"P5\n3 x2\n255\n" + bytes(6))
put("map_pgm_bad_maxval.yaml", yaml("map_pgm_bad_maxval.pgm"))
put("map_pgm_bad_maxval.pgm", b"P2\n2 2\n70000\n0 1\n2 3\n")
put("map_pgm_ascii_bad_value.yaml", yaml("map_pgm_ascii_bad_value.pgm"))
put("map_pgm_ascii_bad_value.pgm", b"P2\n3 2\n255\n0 255 128\n7 x 9\n")


def png(width, height, rows):
    raw = b"".join(b"\0" + r for r in rows)
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


good_png = png(4, 4, [bytes([254] * 4)] * 4)
put("map_png_corrupt.yaml", yaml("map_png_corrupt.png"))
put("map_png_corrupt.png", good_png[:41] + b"\x00" * 8 + good_png[49:])

# --- episodes -------------------------------------------------------------------------------
EP = {"episode_id": 0, "scene_id": "procedural:1", "start_position": [1.0, 0.0, -1.0], "start_rotation": [0, 0, 0, 1],
      "info": {"geodesic_distance": 2.0}, "goals": [{"position": [2.0, 0.0, -2.0], "radius": 0.2}]}


def episodes(**changes):
    e = dict(EP)
    e.update(changes)
    return json.dumps({"episodes": [e]})


put("episodes_typo_field.json", episodes().replace("start_position", "start_postion"))
put("episodes_nan_position.json", episodes().replace("[1.0, 0.0, -1.0]", "[NaN, 0.0, -1.0]"))
put("episodes_huge_number.json", episodes().replace("[1.0, 0.0, -1.0]", "[1e999, 0.0, -1.0]"))
put("episodes_empty_goals.json", episodes(goals=[]))
put("episodes_goal_typo.json", episodes(goals=[{"position": [2.0, 0.0, -2.0], "raduis": 0.2}]))
put("episodes_negative_radius.json", episodes(goals=[{"position": [2.0, 0.0, -2.0], "radius": -0.2}]))
put("episodes_zero_rotation.json", episodes(start_rotation=[0, 0, 0, 0]))
put("episodes_wrong_type.json", episodes(start_position="kitchen"))
put("episodes_not_utf8.json", b'{"episodes": [\xff\xfe]}')
gz = gzip.compress(episodes().encode(), mtime=0)
put("episodes_truncated.json.gz", gz[: len(gz) // 2])
put("episodes_bad_crc.json.gz", gz[:-8] + b"\0\0\0\0" + gz[-4:])

# --- robot profiles -------------------------------------------------------------------------
ROBOT = ("name: r\nradius: 0.18\nheight: 0.4\nmass: 10\nwheel_base: 0.3\nmax_linear: 0.5\nmax_angular: 1.5\n"
         "max_linear_accel: 1.0\nmax_angular_accel: 3.0\ncamera_height: 0.3\n")
put("robot_out_of_range.yaml", ROBOT.replace("radius: 0.18", "radius: -0.18"))
put("robot_unknown_key.yaml", ROBOT.replace("height: 0.4", "heigth: 0.4"))
put("robot_missing_field.yaml", ROBOT.replace("mass: 10\n", ""))
put("robot_wrong_type.yaml", ROBOT.replace("mass: 10", "mass: heavy"))
put("robot_bad_footprint.yaml", ROBOT + "footprint: [[0.1, 0.1], [-0.1, 0.1]]\n")
put("robot_bad_laser_frame.yaml", ROBOT + "laser: {frame: 'base scan', z: 0.2}\n")
put("robot_laser_unknown_key.yaml", ROBOT + "laser: {frame: laser, height: 0.2}\n")

# --- ROS navigation parameters --------------------------------------------------------------
put("nav_wrong_type.yaml", "DWAPlannerROS:\n  max_vel_x: fast\n")
put("nav_out_of_range.yaml", "global_costmap:\n  inflation_radius: -0.5\n")
put("nav_int_for_real.yaml", "DWAPlannerROS:\n  vx_samples: 2.5\n")
put("nav_bad_yaml.yaml", "DWAPlannerROS:\n  max_vel_x: [0.2\n  min_vel_x: 0\n")
put("nav_not_a_map.yaml", "- max_vel_x\n- 0.2\n")
put("nav_bad_footprint.yaml", "local_costmap:\n  footprint: [[0.1, 0.1], [0.1]]\n")
