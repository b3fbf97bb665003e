"""invmap.dask: chunked inversion on Dask's local scheduler and on a
dask.distributed cluster of 2 worker processes on loopback, including a
worker killed mid-run."""

import logging
import os

import dask
import dask.array as da
import distributed
import numpy as np
import pytest

import invmap
import invmap.dask
from conftest import WAVY_SURFACE, assert_results_equal, query_points

# distributed 2022.12 on tornado 6.2 warns about its own event-loop setup.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

CHUNK = 600
COUNT = 8 * CHUNK - 100  # 8 chunks, the last one shorter


@pytest.fixture(scope="module")
def surface():
    return invmap.load(WAVY_SURFACE)


@pytest.fixture(scope="module")
def points(surface):
    return query_points(surface, COUNT, seed=21, spread=0.1)


def per_chunk(manifold, points, **options):
    """Manifold.invert on each chunk in process, concatenated: what every
    chunk task computes (each chunk's rows are exactly invert on that chunk)."""
    parts = [manifold.invert(points[i:i + CHUNK], **options) for i in range(0, len(points), CHUNK)]
    return {key: np.concatenate([part[key] for part in parts]) for key in parts[0]}


def assert_close_to_whole_call(result, whole):
    """Against one invert call on all points: the engine's Newton iterations
    start from the other points of their spatial bucket, so values may differ
    in the last digits (and a point equidistant from two cells may report
    either); the found set and patches agree exactly."""
    for key in ("status", "patch"):
        np.testing.assert_array_equal(result[key], whole[key], err_msg=key)
    np.testing.assert_allclose(result["distance"], whole["distance"], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(result["closest"], whole["closest"], rtol=0, atol=1e-7)
    assert (result["cell"] == whole["cell"]).mean() > 0.98


def test_local_scheduler_inverts_each_chunk_once(surface, points, monkeypatch):
    calls = []
    original = invmap.dask._invert_block
    monkeypatch.setattr(invmap.dask, "_invert_block", lambda *args: calls.append(1) or original(*args))
    result = invmap.dask.invert(da.from_array(points, chunks=(CHUNK, 3)), surface, max_distance=0.05)
    in_process = surface.invert(points[:3])
    assert {key: (array.dtype, array.shape) for key, array in result.items()} == {
        key: (array.dtype, (COUNT,) + array.shape[1:]) for key, array in in_process.items()}
    (computed,) = dask.compute(result, scheduler="threads")
    assert len(calls) == 8
    assert_results_equal(computed, per_chunk(surface, points, max_distance=0.05))
    assert_close_to_whole_call(computed, surface.invert(points, max_distance=0.05))


def test_geometry_is_one_key_of_the_graph(surface, points):
    result = invmap.dask.invert(da.from_array(points, chunks=(CHUNK, 3)), surface)
    graph = dict(dask.base.collections_to_dsk(list(result.values()), optimize_graph=True))
    geometry_keys = [key for key in graph if isinstance(key, str) and key.startswith("invmap-geometry-")]
    assert len(geometry_keys) == 1
    assert len([key for key in graph if isinstance(key, tuple) and key[0].startswith("invmap-invert-")]) == 8


def test_numpy_input_and_column_chunks(surface, points):
    expected = surface.invert(points)
    (from_numpy,) = dask.compute(invmap.dask.invert(points, surface), scheduler="threads")
    assert_results_equal(from_numpy, expected)  # one chunk: exactly the whole call
    split_columns = da.from_array(points, chunks=(CHUNK, 1))
    (computed,) = dask.compute(invmap.dask.invert(split_columns, surface), scheduler="threads")
    assert_results_equal(computed, per_chunk(surface, points))


def test_pointwise_rows_do_not_depend_on_the_chunking(surface, points):
    # By default a row's last digits follow its chunk's other points (the
    # solves start from neighbours' answers); pointwise, they do not.
    for chunk in (CHUNK, 1000, len(points)):
        (computed,) = dask.compute(invmap.dask.invert(da.from_array(points, chunks=(chunk, 3)), surface,
                                                      pointwise=True), scheduler="threads")
        assert_results_equal(computed, surface.invert(points, pointwise=True))


def test_bad_arguments(surface, points):
    with pytest.raises(invmap.InputError, match=r"points: shape \(10, 2\), expected \(N, 3\)"):
        invmap.dask.invert(da.zeros((10, 2)), surface)
    with pytest.raises(TypeError, match="manifold must be an invmap.Manifold"):
        invmap.dask.invert(da.zeros((10, 3)), str(WAVY_SURFACE))


@pytest.fixture(scope="module")
def client():
    # A worker fetching a chunk from a dead peer retries the connection until
    # this timeout (default 30 s) before asking the scheduler for another copy.
    with dask.config.set({"distributed.comm.timeouts.connect": "3s"}):
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                           dashboard_address=None, silence_logs=logging.CRITICAL)
        with distributed.Client(cluster) as connected:
            yield connected
        cluster.close()


def compute_on(client, result, timeout=90):
    """Computes the dict of arrays on the cluster, failing after `timeout` s."""
    futures = client.compute(result)
    distributed.wait(futures, timeout=timeout)
    return futures.result()


def test_cluster_matches_in_process_and_builds_once_per_worker(client, surface, points):
    client.run(invmap.dask.clear_cache)
    array = da.from_array(points, chunks=(CHUNK, 3))
    computed = compute_on(client, invmap.dask.invert(array, surface, max_distance=0.05))
    assert_results_equal(computed, per_chunk(surface, points, max_distance=0.05))
    assert_close_to_whole_call(computed, surface.invert(points, max_distance=0.05))
    # A second graph with the same geometry reuses each worker's build.
    compute_on(client, invmap.dask.invert(array[::2], surface))
    caches = client.run(invmap.dask.cache_info)
    assert all(cache["builds"] <= 1 for cache in caches.values()), caches
    assert sum(cache["builds"] for cache in caches.values()) >= 1
    assert sum(cache["hits"] for cache in caches.values()) >= 8 + 8 - 2


def test_a_task_uses_its_workers_thread_budget(client):
    # Each worker of the cluster has 1 thread: a chunk task inverts with 1
    # (with all cores, 2 single-thread workers ran 4 threads on 2 cores).
    workers = list(client.scheduler_info()["workers"])
    budgets = client.gather([client.submit(invmap.dask._task_threads, None, workers=[w], pure=False) for w in workers])
    assert budgets == [1] * len(workers)
    assert client.submit(invmap.dask._task_threads, 3, pure=False).result() == 3
    # Outside a worker (the local schedulers): all cores.
    assert invmap.dask._task_threads(None) is None


def die_once(block, marker, block_id=None):
    """Kills its worker process, as a crash would, the first time it runs on
    block 3 (the marker file makes "first" hold across processes)."""
    if block_id[0] == 3:
        try:
            os.close(os.open(marker, os.O_CREAT | os.O_EXCL))
        except FileExistsError:
            return block
        os._exit(1)
    return block


def test_worker_killed_mid_run_is_recovered(client, surface, points, tmp_path):
    marker = str(tmp_path / "killed")
    workers_before = set(client.scheduler_info()["workers"])
    result = invmap.dask.invert(da.from_array(points, chunks=(CHUNK, 3)), surface)
    # The kill comes after block 3's inversion, so the dead worker takes
    # inverted chunks (and its copy of the geometry) with it; Dask must
    # recompute them from the graph.
    result["distance"] = result["distance"].map_blocks(die_once, marker, dtype=np.float64)
    computed = compute_on(client, result)
    assert os.path.exists(marker)
    assert workers_before - set(client.scheduler_info()["workers"]), "no worker died"
    assert_results_equal(computed, per_chunk(surface, points))
