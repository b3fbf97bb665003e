"""Inversion of Dask arrays of points, on one machine or a dask.distributed cluster.

    import dask.array as da
    import invmap, invmap.dask

    manifold = invmap.load("surface.json")
    points = da.from_array(big_numpy_array, chunks=(1_000_000, 3))   # or da.from_zarr, ...
    result = invmap.dask.invert(points, manifold, max_distance=0.01)
    status, distance = dask.compute(result["status"], result["distance"])

Each chunk of rows is inverted by Manifold.invert in a task (map_blocks).
The geometry enters the task graph once, as a single key every chunk task
depends on: the scheduler ships it to each worker once, and each worker
process builds the BVH once, caching the manifold by the geometry's content
hash (a later graph with the same geometry reuses it).
"""

import collections
import hashlib
import operator
import threading

import dask
import dask.array as da
import numpy as np

from . import InputError, Manifold

__all__ = ["cache_info", "clear_cache", "invert", "probe"]

# Worker-process cache of built manifolds, least recently used first. A few
# entries cover a pipeline that alternates geometries; each holds its BVH.
_CACHE_SIZE = 4
_cache = collections.OrderedDict()
_cache_stats = {"builds": 0, "hits": 0}
# One lock for lookups and builds: two tasks of a new geometry starting
# together must not both build it, and builds are rare enough to serialize.
_cache_lock = threading.Lock()


class _GeometryRef:
    """What the graph carries to the workers: the pickled geometry and its hash.

    In the process that made it, it also holds the manifold itself (never
    pickled), so a local scheduler uses the caller's manifold without a build.
    """

    __slots__ = ("key", "state", "local")

    def __init__(self, manifold):
        self.state = manifold.__getstate__()
        self.key = hashlib.sha256(self.state).hexdigest()
        self.local = manifold

    def __getstate__(self):
        return self.key, self.state

    def __setstate__(self, state):
        self.key, self.state = state
        self.local = None

    def manifold(self):
        """The built manifold: the local one, or this process's cached build."""
        if self.local is not None:
            return self.local
        with _cache_lock:
            built = _cache.get(self.key)
            if built is not None:
                _cache.move_to_end(self.key)
                _cache_stats["hits"] += 1
                return built
            built = Manifold.__new__(Manifold)
            built.__setstate__(self.state)
            _cache[self.key] = built
            _cache_stats["builds"] += 1
            while len(_cache) > _CACHE_SIZE:
                _cache.popitem(last=False)
            return built


def cache_info():
    """This process's manifold cache: {"builds", "hits", "size"}. On a cluster,
    client.run(invmap.dask.cache_info) returns it per worker."""
    with _cache_lock:
        return {"builds": _cache_stats["builds"], "hits": _cache_stats["hits"], "size": len(_cache)}


def clear_cache():
    """Drops this process's cached manifolds and zeroes the counters."""
    with _cache_lock:
        _cache.clear()
        _cache_stats.update(builds=0, hits=0)


def _task_threads(threads):
    """The threads a chunk task inverts with: `threads` when given, else the
    thread budget of the dask.distributed worker running the task (its
    nthreads), else None (all cores: Dask's local schedulers)."""
    if threads is not None:
        return threads
    try:
        from distributed import get_worker
        worker = get_worker()
    except (ImportError, ValueError):
        return None
    # distributed 2022.12 keeps nthreads on the worker's state (the worker's
    # own attribute is deprecated there); older releases have only the latter.
    return getattr(getattr(worker, "state", worker), "nthreads", None)


def _invert_block(points, ref, max_distance, threads, pointwise, signed=False):
    return ref.manifold().invert(points, max_distance=max_distance, threads=_task_threads(threads),
                                 pointwise=pointwise, signed=signed)


def _probe_block(points, ref, names, max_distance, threads):
    return ref.manifold().probe(points, names, max_distance=max_distance, threads=_task_threads(threads))


def _chunked_points(points, manifold, verb):
    """points as a 2-column-chunk-free dask array of the manifold's dimension."""
    if not isinstance(manifold, Manifold):
        raise TypeError(f"{verb}: manifold must be an invmap.Manifold, got {type(manifold).__name__}")
    if not isinstance(points, da.Array):
        points = da.from_array(np.asarray(points))
    dim = manifold.dimension
    if points.ndim != 2 or points.shape[1] != dim:
        raise InputError(f"points: shape {points.shape}, expected (N, {dim}) for a {dim}-D geometry")
    if len(points.chunks[1]) > 1:
        points = points.rechunk({1: -1})
    return points


def _select(blocks, rows, key, dtype, columns, name):
    """The array of one result key from the blocks of result dicts."""
    extra = dict(new_axis=1, chunks=(rows, columns)) if columns else dict(chunks=(rows,))
    return blocks.map_blocks(key, dtype=dtype, meta=np.empty((0,) * (1 + len(columns)), dtype=dtype),
                             name=name, **extra)


def _result_arrays(blocks, rows, dim, signed=False):
    """Manifold.invert's keys as dask arrays over the blocks."""
    fields = {
        "status": (np.uint8, ()),
        "patch": (np.int32, ()),
        "cell": (np.int64, ()),
        "params": (np.float64, (3,)),
        "closest": (np.float64, (dim,)),
        "distance": (np.float64, ()),
    }
    if signed:
        fields["signed_distance"] = (np.float64, ())
    return {key: _select(blocks, rows, operator.itemgetter(key), dtype, columns, f"invmap-{key}")
            for key, (dtype, columns) in fields.items()}


def invert(points, manifold, max_distance=None, threads=None, pointwise=False, signed=False):
    """Manifold.invert over a Dask array of points, chunk by chunk.

    points: (N, dim) dask array (a numpy array is wrapped with
      da.from_array), chunked by rows; column chunks are merged.
    manifold: an invmap.Manifold of dimension dim.
    max_distance: as Manifold.invert.
    threads: per task. Default: on a dask.distributed worker, the worker's
      own thread budget (its nthreads: a worker started with --nthreads 1
      inverts with one thread, so n such workers on n cores scale like n
      cores rather than each using every core); under Dask's local
      schedulers, all cores. Results do not depend on it.
    pointwise: as Manifold.invert: each row a function of its point alone,
      bit for bit whatever the chunking (by default the last digits of a
      row can depend on the other points of its chunk).
    signed: as Manifold.invert (CAD models of closed solids): adds
      "signed_distance"; a manifold that cannot sign raises InputError here.

    Returns a dict of dask arrays with Manifold.invert's keys (status, patch,
    cell, params, closest, distance[, signed_distance]) and the points' row
    chunks. One compute
    call inverts each chunk once, whichever of the arrays it asks for; a
    second call inverts again, so compute what you need together
    (dask.compute(result) or dask.compute(result["status"], result["cell"])).
    Each chunk's rows are exactly Manifold.invert's results on that chunk.
    """
    points = _chunked_points(points, manifold, "invert")
    if signed:  # the usage error now, not in a worker: no inside, or an open shell
        manifold.invert(np.empty((0, manifold.dimension)), signed=True)
    ref = _GeometryRef(manifold)
    geometry = dask.delayed(ref, name="invmap-geometry-" + ref.key, traverse=False)
    # Blocks of dicts (never computed as an array): one task per chunk, which
    # the per-key arrays below select from.
    blocks = da.map_blocks(_invert_block, points, geometry, max_distance, threads, pointwise, bool(signed),
                           drop_axis=1, dtype=object, meta=np.empty((0,), dtype=object), name="invmap-invert")
    return _result_arrays(blocks, points.chunks[0], manifold.dimension, bool(signed))


def probe(points, manifold, names=None, max_distance=None, threads=None):
    """Manifold.probe over a Dask array of points, chunk by chunk.

    points, max_distance, threads: as invert. names: the fields to give
    (default: every field of the manifold, Manifold.fields).

    Returns invert's dict of dask arrays plus "fields": {name: dask array},
    (N,) for a scalar and (N, components) otherwise. As with invert, one
    compute call probes each chunk once whichever arrays it asks for.
    """
    points = _chunked_points(points, manifold, "probe")
    available = manifold.fields
    if not available:
        raise InputError("probe: this manifold has no node fields (they come from gmsh $NodeData, VTU point data "
                         "and Exodus nodal variables)")
    names = list(available) if names is None else list(names)
    for name in names:
        if name not in available:
            raise InputError(f"probe: no field '{name}' (the fields: {', '.join(available)})")
    ref = _GeometryRef(manifold)
    geometry = dask.delayed(ref, name="invmap-geometry-" + ref.key, traverse=False)
    blocks = da.map_blocks(_probe_block, points, geometry, names, max_distance, threads,
                           drop_axis=1, dtype=object, meta=np.empty((0,), dtype=object), name="invmap-probe")
    rows = points.chunks[0]
    result = _result_arrays(blocks, rows, manifold.dimension)
    result["fields"] = {}
    for name in names:
        components = available[name]
        result["fields"][name] = _select(blocks, rows, lambda block, name=name: block["fields"][name], np.float64,
                                         () if components == 1 else (components,), f"invmap-field-{name}")
    return result
