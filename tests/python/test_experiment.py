"""xhab.experiment and xhab.merge: a study from Python equals the same study sharded and
merged, resumes, and reports errors naming the field."""

import json

import pytest

import xhab

SPEC = {
    "name": "python study",
    "scenes": [{"scene": "procedural:3", "generate": {"count": 3, "seed": 1}}],
    "agents": [{"agent": "oracle"}],
    "configurations": [{"physics": False, "ros": False}, {"physics": True, "ros": False}],
    "threads": 2,
}

TIMING = {"wall_s", "steps_per_s", "real_time_factor", "render_s", "render_frames_per_s", "ros_overhead", "stack_wait_s"}


def untimed(v):
    if isinstance(v, dict):
        return {k: untimed(x) for k, x in v.items() if k not in TIMING}
    if isinstance(v, list):
        return [untimed(x) for x in v]
    return v


def test_a_study_runs_resumes_and_merges_from_shards(tmp_path):
    whole = xhab.experiment(SPEC, tmp_path / "whole")
    assert [r["configuration"] for r in whole["runs"]] == ["-physics -ROS", "+physics -ROS"]
    assert len(whole["episodes"]) == 6
    assert all(r["aggregate"]["success"] == 1.0 for r in whole["runs"])
    assert (tmp_path / "whole" / "report" / "index.html").is_file()
    # The file on disk is what came back.
    assert untimed(json.loads((tmp_path / "whole" / "results.json").read_text())) == untimed(whole)
    # Again: nothing reruns, the same results.
    assert xhab.experiment(SPEC, tmp_path / "whole") == whole
    # Three shards in a folder each, merged into a fourth.
    for k in (1, 2, 3):
        assert xhab.experiment(SPEC, tmp_path / f"s{k}", shard=f"{k}/3", report=False) is None
    merged = xhab.merge([tmp_path / f"s{k}" for k in (1, 2, 3)], tmp_path / "merged", report=False)
    assert untimed(merged) == untimed(whole)


def test_a_yaml_file_and_its_errors(tmp_path):
    spec = tmp_path / "study.yaml"
    spec.write_text("name: y\nscenes: [{scene: 'procedural:3', generate: {count: 2}}]\nagents: [{agent: oracle}]\nconfigurations: [{physics: false, ros: false}]\n")
    r = xhab.experiment(spec, tmp_path / "out", report=False)
    assert r["experiment"] == "y" and len(r["episodes"]) == 2
    spec.write_text("name: y\nscenes: [{scene: 'procedural:3', generate: {count: 2}}]\nagents: [{agent: orcale}]\n")
    with pytest.raises(ValueError, match=r"study.yaml.*agents\[0\]\.agent.*orcale"):
        xhab.experiment(spec, tmp_path / "bad")
    with pytest.raises(ValueError, match="K/N"):
        xhab.experiment(SPEC, tmp_path / "bad2", shard="0/3")
    with pytest.raises(ValueError, match="incomplete"):
        xhab.experiment(SPEC, tmp_path / "part", shard="1/3", report=False)
        xhab.merge(tmp_path / "part")
