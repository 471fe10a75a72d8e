"""habitat-sim's side of scripts/peer_path_quality.sh; run with the peer's launcher
(/opt/habpeer/bin/hpython, see ../shared/peers/habitat/SETUP.md).

  hab_paths.py pairs ZUP_GLB OUT.json N     seeded random floor points (as the peer's timing
                                            script picks them), two pairs per point, and
                                            PathFinder.find_path's distance and path for each
  hab_paths.py stray ZUP_GLB PAIRS.json PATHS.json OUT.json
                                            for each pair, how far the other planner's path
                                            (PATHS.json, bend points) strays from habitat's
                                            navmesh: the largest horizontal distance (m) from a
                                            point on it, every 2 cm, to that point snapped to
                                            the navmesh

The navmesh is the one the timing script builds: recompute_navmesh with the defaults, agent
radius 0.1 m and height 1.5 m. Points and paths are in Habitat's frame (y up, m).
"""
import json
import math
import os
import sys

os.environ.setdefault("HABITAT_SIM_LOG", "quiet")
sys.path.insert(0, os.environ.get("HABITAT_PEER_DIR", os.path.join(os.path.dirname(__file__), "../../../shared/peers/habitat")))
import np2shim  # noqa: F401,E402  (must precede habitat_sim)
import numpy as np  # noqa: E402
import habitat_sim  # noqa: E402


def pathfinder(scene):
    s = habitat_sim.SimulatorConfiguration()
    s.scene_id = scene
    a = habitat_sim.agent.AgentConfiguration()
    a.height, a.radius = 1.5, 0.1
    # habitat loads no geometry without a renderer, and builds no navmesh without geometry.
    d = habitat_sim.CameraSensorSpec()
    d.uuid, d.sensor_type, d.resolution = "depth", habitat_sim.SensorType.DEPTH, [16, 16]
    a.sensor_specifications = [d]
    sim = habitat_sim.Simulator(habitat_sim.Configuration(s, [a]))
    ns = habitat_sim.NavMeshSettings()
    ns.set_defaults()
    ns.agent_radius, ns.agent_height = 0.1, 1.5
    if not sim.recompute_navmesh(sim.pathfinder, ns):
        sys.exit(f"hab_paths.py: {scene}: the navmesh build failed")
    return sim, sim.pathfinder


def pairs(scene, out, n):
    _sim, pf = pathfinder(scene)
    pf.seed(7)
    pts = [np.array(pf.get_random_navigable_point(), dtype=np.float32) for _ in range(3 * n)]
    pts = [p for p in pts if np.all(np.isfinite(p))]
    y0 = min(p[1] for p in pts)
    # The lowest floor, on islands of at least 1 m radius (no table tops), as the timing script.
    pts = [p for p in pts if p[1] - y0 < 0.2 and pf.island_radius(p) >= 1.0][:n]
    rows = []
    for i in range(len(pts)):
        for j in ((7 * i + 3) % len(pts), (13 * i + 5) % len(pts)):
            if i == j:
                continue
            sp = habitat_sim.ShortestPath()
            sp.requested_start, sp.requested_end = pts[i], pts[j]
            ok = bool(pf.find_path(sp))
            rows.append({"a": pts[i].tolist(), "b": pts[j].tolist(), "found": ok,
                         "distance": float(sp.geodesic_distance) if ok else None,
                         "path": [[float(v) for v in p] for p in sp.points] if ok else []})
    with open(out, "w") as f:
        json.dump({"scene": scene, "rows": rows}, f)
    print(f"{scene}: {len(rows)} pairs, find_path found {sum(r['found'] for r in rows)}")


def stray(scene, pairs_json, paths_json, out):
    _sim, pf = pathfinder(scene)
    with open(pairs_json) as f:
        rows = json.load(f)["rows"]
    with open(paths_json) as f:
        paths = json.load(f)
    if len(paths) != len(rows):
        sys.exit(f"hab_paths.py: {paths_json}: {len(paths)} paths for {len(rows)} pairs")
    res = []
    for path in paths:
        worst = 0.0
        for p, q in zip(path or [], (path or [])[1:]):
            p, q = np.array(p), np.array(q)
            for t in np.linspace(0.0, 1.0, max(1, int(math.dist(p, q) / 0.02)) + 1):
                x = p + t * (q - p)
                s = np.array(pf.snap_point(x.astype(np.float32)))
                worst = max(worst, math.hypot(s[0] - x[0], s[2] - x[2]) if np.all(np.isfinite(s)) else math.inf)
        res.append(worst if path else None)
    with open(out, "w") as f:
        json.dump(res, f)


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd == "pairs" and len(sys.argv) == 5:
        pairs(sys.argv[2], sys.argv[3], int(sys.argv[4]))
    elif cmd == "stray" and len(sys.argv) == 6:
        stray(*sys.argv[2:6])
    else:
        sys.exit(__doc__)
