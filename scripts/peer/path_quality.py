"""Summary of scripts/peer_path_quality.sh: habitat-sim's find_path distances against xhab's exact
shortest paths on the same pairs, per scene and agent radius.

  path_quality.py DIR SCENE RADIUS...   reads DIR/SCENE.pairs.json, DIR/SCENE.xhab_R.json and
                                        DIR/SCENE.stray_R.json for each radius R

Only pairs whose xhab path bends are counted (straight pairs agree wherever both see through).
"""
import json
import math
import sys


def pct(xs, q):
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(q * (len(xs) - 1) + 0.5))]


def line(label, rel):
    if not rel:
        return f"  {label}: none"
    return (f"  {label}: n={len(rel)}; habitat/xhab - 1: median {pct(rel, 0.5):+.2%}, p90 {pct(rel, 0.9):+.2%}, "
            f"p99 {pct(rel, 0.99):+.2%}, max {max(rel):+.2%}, min {min(rel):+.2%}; "
            f"over +0.5%: {sum(r > 0.005 for r in rel) / len(rel):.1%}, under -0.5%: {sum(r < -0.005 for r in rel) / len(rel):.1%}")


def main(folder, scene, radii):
    with open(f"{folder}/{scene}.pairs.json") as f:
        rows = json.load(f)["rows"]
    for r in radii:
        with open(f"{folder}/{scene}.xhab_{r}.json") as f:
            paths = json.load(f)
        with open(f"{folder}/{scene}.stray_{r}.json") as f:
            strays = json.load(f)
        both = [(row, p, s) for row, p, s in zip(rows, paths, strays) if row["found"] and p]
        bent = [(row, p, s) for row, p, s in both if len(p) > 2]
        length = lambda p: sum(math.dist(a, b) for a, b in zip(p, p[1:]))
        rel = [row["distance"] / length(p) - 1 for row, p, _ in bent]
        inside = [row["distance"] / length(p) - 1 for row, p, s in bent if s <= 0.03]
        # Pushing a path that strays s from the navmesh back onto it lengthens it by at most about
        # 2 s at each bend and each place a leg strays: 2 s (bends + 1) bounds it generously.
        surely = [row for row, p, s in bent if row["distance"] > length(p) * 1.005 + 2 * s * (len(p) - 1)]
        st = [s for _, _, s in bent]
        print(f"{scene}, xhab radius {r} m: {len(rows)} pairs, {len(both)} joined by both, {len(bent)} bent in xhab's; "
              f"xhab's path strays from habitat's navmesh by median {pct(st, 0.5):.3f} m, p90 {pct(st, 0.9):.3f} m, max {max(st):.3f} m")
        print(line("all bent pairs", rel))
        print(line("bent pairs whose xhab path stays within 3 cm of the navmesh", inside))
        print(f"  find_path longer than xhab's path by over 0.5% plus 2 x stray x (bends + 1): {len(surely)} of {len(bent)} ({len(surely) / max(1, len(bent)):.1%})")


if __name__ == "__main__":
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
