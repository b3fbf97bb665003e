"""Python gives exactly the invmap command's results on the same inputs."""

import csv

import numpy as np
import pytest

import invmap
from conftest import assert_results_equal, query_points

STATUS_CODES = {"found": 0, "none": 1, "invalid": 2}


def read_result_csv(path, dim):
    """An `invmap invert` CSV (docs/formats.md section 5) as invert()'s dict."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["index", "status", "patch", "cell", "u", "v", "w", "x", "y", "z", "distance"]
    rows = rows[1:]
    assert [int(r[0]) for r in rows] == list(range(len(rows)))

    def reals(column):
        return np.array([[float(r[c]) if r[c] else np.nan for c in column] for r in rows], dtype=np.float64)

    return {
        "status": np.array([STATUS_CODES[r[1]] for r in rows], dtype=np.uint8),
        "patch": np.array([int(r[2]) for r in rows], dtype=np.int32),
        "cell": np.array([int(r[3]) for r in rows], dtype=np.int64),
        "params": reals([4, 5, 6]),
        "closest": reals([7, 8, 9][:dim]),
        "distance": reals([10])[:, 0],
    }


def read_result_npy(path, dim):
    """An `invmap invert` .npy result: (N, 11) float64 in the CSV's columns."""
    table = np.load(path)
    assert table.shape[1] == 11
    return {
        "status": table[:, 1].astype(np.uint8),
        "patch": table[:, 2].astype(np.int32),
        "cell": table[:, 3].astype(np.int64),
        "params": table[:, 4:7],
        "closest": table[:, 7:7 + dim],
        "distance": table[:, 10],
    }


@pytest.mark.parametrize("name, output, gap", [
    ("surface", ".csv", None), ("surface", ".npy", 0.02), ("curve", ".csv", 0.1), ("torus", ".npy", None),
    ("tets", ".csv", 0.05), ("trimesh", ".npy", None), ("mesh2d", ".csv", 0.1),
])
def test_invert_matches_command_line(cli, geometry_files, tmp_path, name, output, gap):
    manifold = invmap.load(geometry_files[name])
    points = query_points(manifold, 2000, seed=11)
    np.save(tmp_path / "points.npy", points)
    args = ["invert", "--geometry", geometry_files[name], "--points", tmp_path / "points.npy",
            "--output", tmp_path / ("result" + output), "--quiet"]
    if gap is not None:
        args += ["--max-distance", repr(gap)]
    cli(*args)
    reader = read_result_csv if output == ".csv" else read_result_npy
    expected = reader(tmp_path / ("result" + output), manifold.dimension)
    result = manifold.invert(points, max_distance=gap)
    assert_results_equal(result, expected)
    if gap is not None:
        assert (result["status"] == 1).any()


@pytest.mark.parametrize("keep", ["near", "far"])
def test_trim_matches_command_line(cli, geometry_files, tmp_path, keep):
    manifold = invmap.load(geometry_files["surface"])
    points = query_points(manifold, 2000, seed=5)
    np.save(tmp_path / "points.npy", points)
    cli("trim", "--geometry", geometry_files["surface"], "--points", tmp_path / "points.npy",
        "--output", tmp_path / "kept.npy", "--max-distance", "0.03", "--keep", keep, "--quiet")
    kept = np.load(tmp_path / "kept.npy")
    np.testing.assert_array_equal(points[manifold.trim(points, 0.03, keep=keep)], kept)


def test_trim_of_more_points_than_a_chunk(cli, geometry_files, tmp_path):
    """Beyond the command's chunk of 2^18 points, trim still keeps exactly
    the points within the distance (the torus's closed form) and the same
    points as `invmap trim`, which reads the same chunks."""
    torus = invmap.load(geometry_files["torus"])
    rng = np.random.default_rng(11)
    points = rng.uniform([-3.0, -3.0, -1.0], [3.0, 3.0, 1.0], size=((1 << 18) + 5000, 3))
    mask = torus.trim(points, 0.1)
    distance = np.abs(np.hypot(np.hypot(points[:, 0], points[:, 1]) - 2.0, points[:, 2]) - 0.7)
    clear = np.abs(distance - 0.1) > 1e-9
    np.testing.assert_array_equal(mask[clear], distance[clear] <= 0.1)
    np.save(tmp_path / "points.npy", points)
    cli("trim", "--geometry", geometry_files["torus"], "--points", tmp_path / "points.npy",
        "--output", tmp_path / "kept.npy", "--max-distance", "0.1", "--quiet")
    np.testing.assert_array_equal(points[mask], np.load(tmp_path / "kept.npy"))


def test_info_matches_command_line(cli, geometry_files):
    for name, path in geometry_files.items():
        info = invmap.load(path).info()
        printed = cli("info", "--geometry", path).stdout
        assert f"dimension   {info['dimension']}\n" in printed, name
        assert f"cells       {info['cells']}\n" in printed, name
        for shape, count in info["cells_by_shape"].items():
            assert f"  {shape:<20} {count}\n" in printed, (name, shape)
