"""invmap.distance and invmap.DistanceTracker: analytic answers, the pose
forms, errors, and the same fields and values as `invmap distance`."""

import json
import math
import threading

import numpy as np
import pytest

import invmap


def segment(p, q):
    """A straight cubic Bezier curve from p to q (3D), as a manifold."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    points = [list(p + (q - p) * t) for t in (0, 1 / 3, 2 / 3, 1)]
    return invmap.load({"format": "invmap-geometry", "version": 1, "dimension": 3,
                        "patches": [{"kind": "bezier", "cell": "line", "degrees": [3], "control_points": points}]})


def translation(x, y, z):
    return [1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z]


def torus_distance(p):
    """Distance from p to the sample torus (R = 2, r = 0.7 around z)."""
    x, y, z = p
    return abs(math.hypot(math.hypot(x, y) - 2.0, z) - 0.7)


def test_skew_segments():
    a = segment([0, 0, 0], [1, 0, 0])
    b = segment([0.5, -1, 1], [0.5, 1, 1])
    r = invmap.distance(a, b)
    assert r["distance"] == pytest.approx(1.0, abs=1e-12)
    assert r["a"]["point"] == pytest.approx([0.5, 0, 0], abs=1e-12)
    assert r["b"]["point"] == pytest.approx([0.5, 0, 1], abs=1e-12)
    assert r["a"]["params"] == pytest.approx([0.5], abs=1e-9)
    assert (r["a"]["patch"], r["a"]["cell"]) == (0, 0)
    assert r["certified"] is True
    assert r["seconds"] >= 0
    # Moved down by 1, B crosses A: distance 0 at a common point.
    r = invmap.distance(a, b, pose_b=translation(0, 0, -1))
    assert r["distance"] == 0.0
    assert r["a"]["point"] == pytest.approx(r["b"]["point"], abs=1e-12)


def test_pose_forms_agree(geometry_files):
    torus = invmap.load(geometry_files["torus"])
    stick = segment([0, 0, 3], [0, 0, 4])
    angle = 0.4
    c, s = math.cos(angle), math.sin(angle)
    rows = [c, -s, 0, 1.5, s, c, 0, 0.5, 0, 0, 1, 0.2]
    expected = invmap.distance(torus, stick, pose_b=rows)
    # B's low end, turned about z (it is on the axis) and moved, is nearest.
    assert expected["distance"] == pytest.approx(torus_distance([1.5, 0.5, 3.2]), abs=1e-9)
    matrix34 = np.array(rows).reshape(3, 4)
    matrix44 = np.vstack([matrix34, [0, 0, 0, 1]])
    for pose in (tuple(rows), matrix34, matrix44, matrix34.tolist()):
        got = invmap.distance(torus, stick, pose_b=pose)
        assert got["distance"] == pytest.approx(expected["distance"], abs=1e-12)
    # Moving both models alike changes no distance.
    both = invmap.distance(torus, stick, pose_a=matrix44, pose_b=np.array(rows + [0, 0, 0, 1]).reshape(4, 4)
                           @ np.eye(4))
    assert both["distance"] == pytest.approx(invmap.distance(torus, stick)["distance"], abs=1e-9)


def test_max_distance_and_errors(geometry_files):
    torus = invmap.load(geometry_files["torus"])
    stick = segment([0, 0, 3], [0, 0, 4])
    far = invmap.distance(torus, stick, max_distance=1.0)
    assert far["distance"] is None and far["a"] is None and far["b"] is None
    with pytest.raises(invmap.InputError, match="pose_b"):
        invmap.distance(torus, stick, pose_b=[1, 0, 0])
    with pytest.raises(invmap.InputError, match="rotation"):
        invmap.distance(torus, stick, pose_b=translation(0, 0, 0)[:0] + [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0])
    with pytest.raises(invmap.InputError, match="last row"):
        invmap.distance(torus, stick, pose_b=np.eye(4) * 2)
    with pytest.raises(invmap.InputError, match="max_distance"):
        invmap.distance(torus, stick, max_distance=-1.0)
    curve2d = invmap.load(geometry_files["curve"])
    with pytest.raises(invmap.InputError, match="dimensions"):
        invmap.distance(torus, curve2d)


def test_tracker_matches_fresh_queries(geometry_files):
    torus = invmap.load(geometry_files["torus"])
    stick = segment([0, 0, 3], [0, 0, 4])
    tracker = invmap.DistanceTracker(torus, stick)
    rng = np.random.default_rng(3)
    pose = np.array(translation(2.0, 0.0, -1.5), float)
    for step in range(12):
        pose[3] += rng.uniform(-0.1, 0.1)
        pose[11] += rng.uniform(-0.1, 0.1)
        tracked = tracker.update(pose)
        fresh = invmap.distance(torus, stick, pose_b=pose)
        assert tracked["distance"] == pytest.approx(fresh["distance"], abs=1e-10), step


def test_same_fields_as_the_command(cli, geometry_files, tmp_path):
    (tmp_path / "stick.json").write_text(json.dumps({
        "format": "invmap-geometry", "version": 1, "dimension": 3,
        "patches": [{"kind": "bezier", "cell": "line", "degrees": [1], "control_points": [[0, 0, 3], [0, 0, 4]]}]}))
    pose = "1,0,0,1.2,0,1,0,0.3,0,0,1,0.1"
    done = cli("distance", "--a", geometry_files["torus"], "--b", tmp_path / "stick.json", "--pose-b", pose)
    command = json.loads(done.stdout)
    python = invmap.distance(invmap.load(geometry_files["torus"]), invmap.load(tmp_path / "stick.json"),
                             pose_b=[float(x) for x in pose.split(",")])
    assert set(python) == set(command)
    assert python["distance"] == command["distance"]
    assert python["a"] == command["a"] and python["b"] == command["b"]
    assert python["certified"] == command["certified"]


def test_local_minima_of_points(geometry_files):
    torus = invmap.load(geometry_files["torus"])
    r = torus.local_minima(np.array([[2.0, 0, 3], [np.nan, 0, 0], [2.0, 0, -3]]))
    assert list(r["offsets"]) == [0, 1, 2, 3]
    assert list(r["status"]) == [0, 2, 0]
    assert r["distance"][0] == pytest.approx(2.3, abs=1e-9)
    assert r["closest"][2] == pytest.approx([2, 0, -0.7], abs=1e-9)
    assert r["certified"].all()
    # Every minimum is a point invert also reaches from the same query when
    # it is the nearest: the first row of each point is invert's answer.
    points = np.array([[0.5, 3.1, 0.2], [3.0, 1.0, 1.5]])
    rows = torus.local_minima(points)
    nearest = torus.invert(points)
    for i in range(2):
        first = rows["offsets"][i]
        assert rows["distance"][first] == pytest.approx(nearest["distance"][i], abs=1e-9)
        assert list(rows["distance"][first:rows["offsets"][i + 1]]) == sorted(rows["distance"][first:rows["offsets"][i + 1]])
    none = torus.local_minima(np.array([[2.0, 0, 3]]), max_distance=1.0)
    assert list(none["status"]) == [1]


def test_all_minima_between_models(geometry_files):
    torus = invmap.load(geometry_files["torus"])
    stick = segment([0, 0, 3], [0, 0, 4])
    r = invmap.distance(torus, stick, pose_b=translation(2.5, 0, -2), all_minima=True)
    assert r["minima"], r
    assert r["minima"][0]["distance"] == pytest.approx(r["distance"], abs=1e-12)
    distances = [m["distance"] for m in r["minima"]]
    assert distances == sorted(distances)
    assert "minima" not in invmap.distance(torus, stick)


def test_point_tracker_matches_invert(geometry_files):
    surface = invmap.load(geometry_files["surface"])
    tracker = invmap.PointTracker(surface)
    rng = np.random.default_rng(5)
    point = np.array([0.4, 0.5, 0.1])
    info = surface.info()
    for step in range(60):
        point = point + rng.uniform(-0.005, 0.005, 3)
        if step == 30:
            point = np.array(info["bounds_hi"]) + 0.1
        got = tracker.update(point)
        expected = surface.invert(point[None, :])
        assert got["status"] == expected["status"][0]
        assert got["distance"] == pytest.approx(expected["distance"][0], abs=1e-11)
        assert np.allclose(got["closest"], expected["closest"][0], atol=1e-8)
    assert tracker.update([np.nan, 0, 0])["status"] == 2
    with pytest.raises(invmap.InputError, match="coordinates"):
        tracker.update([1.0, 2.0])
    far = invmap.PointTracker(surface, max_distance=1e-3).update([0.5, 0.5, 5.0])
    assert far["status"] == 1 and far["patch"] == -1


def test_trackers_shared_between_threads(geometry_files):
    """A tracker used from several Python threads at once: updates take
    turns, each answering its own query (no crash, no answer of another)."""
    surface = invmap.load(geometry_files["surface"])
    torus = invmap.load(geometry_files["torus"])
    point_tracker = invmap.PointTracker(surface)
    pair_tracker = invmap.DistanceTracker(surface, torus, threads=1)
    failures = []

    def run(seed):
        rng = np.random.default_rng(seed)
        for _ in range(40):
            point = rng.random(3)
            got = point_tracker.update(point)["distance"]
            fresh = surface.invert(point[None], threads=1)["distance"][0]
            if abs(got - fresh) > 1e-12:
                failures.append(("point", point.tolist(), got, fresh))
            pose = [1, 0, 0, 0.5, 0, 1, 0, 0.5, 0, 0, 1, 0.6 + rng.uniform(0, 0.5)]
            distance = pair_tracker.update(pose)["distance"]
            fresh = invmap.distance(surface, torus, pose_b=pose, threads=1)["distance"]
            if abs(distance - fresh) > 1e-12:
                failures.append(("pair", pose[11], distance, fresh))

    threads = [threading.Thread(target=run, args=(seed,)) for seed in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not failures, failures[:5]
