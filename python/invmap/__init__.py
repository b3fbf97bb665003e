"""invmap: closest points, cells and parameters of point clouds on parametric geometry.

    import numpy as np
    import invmap

    manifold = invmap.load("surface.json")          # a path, JSON text or a dict
    result = manifold.invert(np.random.rand(1000, 3), max_distance=0.1)
    result["status"], result["patch"], result["cell"], result["params"]

A Manifold is built once (cells and BVH) and is thread-safe; invert releases
the GIL. Manifolds pickle by value, so they travel to worker processes; for
point sets beyond one machine see invmap.dask. Errors raise InputError (a
ValueError) or FileError (an OSError) with the invmap command's messages.
"""

import json
import os

import numpy as np

from ._invmap import (DistanceTracker, FileError, InputError, Manifold, PointTracker, __version__, distance,
                      from_mesh, manifold, read_points)
from . import _invmap

__all__ = ["DistanceTracker", "FileError", "InputError", "Manifold", "PointTracker", "distance", "from_bspline",
           "from_mesh", "grid", "load", "manifold", "read_points"]

# Public names live in `invmap`, not in the private extension module: this
# is also where pickle looks classes up (manifolds and exceptions travel
# between Dask processes).
for _public in (DistanceTracker, FileError, InputError, Manifold, PointTracker):
    _public.__module__ = __name__
del _public


def _unpickle_manifold(state):
    """Rebuilds a pickled Manifold from its geometry bytes (what
    Manifold.__reduce__ names, for every pickle protocol)."""
    return _invmap._manifold_from_state(state)


def load(source):
    """Reads and builds a geometry.

    source: one of
      - a path (str or os.PathLike) to a geometry file, as `invmap invert
        --geometry` reads it: .json (invmap's geometry, docs/formats.md, or
        Coreform Cubit's Bezier extraction JSON), .obj, .stl, .off, .ply
        meshes, .msh gmsh meshes, .vtu VTK grids, .exo/.e Exodus II files,
        .bext/.bxt Cubit LS-DYNA Bezier extraction, CAD models (.step, .stp,
        .iges, .igs, .brep: one patch per face, docs/cad.md). Node fields of
        the file (gmsh $NodeData, VTU point data, Exodus nodal variables at
        the last time step) come with it: Manifold.fields, Manifold.probe;
      - JSON text of an invmap geometry (a str starting with "{");
      - a dict in the same schema (as json.load returns it); numpy arrays
        inside are accepted.

    Raises FileError when the file cannot be read, InputError when the
    geometry is invalid; messages name the file (or "<json>", "<dict>") and
    the line, as the command line prints them.
    """
    if isinstance(source, dict):
        return _invmap._load_json(json.dumps(source, default=_json_default), "<dict>")
    if isinstance(source, str) and source.lstrip().startswith("{"):
        return _invmap._load_json(source, "<json>")
    if isinstance(source, (str, os.PathLike)):
        return _invmap._load_file(os.fspath(source))
    raise TypeError(f"load: expected a path, JSON text or a dict, got {type(source).__name__}")


def _json_default(value):
    """Lets geometry dicts hold numpy arrays and scalars (json.dumps calls this for
    what it cannot encode); repr of a float64 round-trips, so nothing is lost."""
    if isinstance(value, (np.ndarray, np.generic)):
        return value.tolist()
    raise TypeError(f"load: {type(value).__name__} is not JSON serializable")


def from_bspline(control_points, knots, degrees, weights=None):
    """A manifold of one B-spline (or NURBS) curve, surface or volume.

    control_points: array of shape (n_u, dim), (n_u, n_v, dim) or
      (n_u, n_v, n_w, dim), indexed [i_u, i_v, i_w, coordinate]; dim is the
      ambient dimension (2 or 3).
    knots: one non-decreasing knot vector per parametric direction, of
      length n + degree + 1 (a curve may pass the single vector directly).
    degrees: one degree per direction, or one int for all of them.
    weights: optional positive weights, shape control_points.shape[:-1]
      (a rational B-spline, NURBS).

    Reported parameters are knot values (u, v, w). Raises InputError, e.g.
    "from_bspline: patch 0: knots[1]: decreasing at index 4 (0.5 > 0.25)".
    """
    points = np.asarray(control_points, dtype=np.float64)
    directions = points.ndim - 1
    if directions not in (1, 2, 3):
        raise InputError(
            f"control_points: shape {points.shape}, expected (n_u, dim), (n_u, n_v, dim) or (n_u, n_v, n_w, dim)")
    if directions == 1 and np.ndim(knots) == 1:
        knots = [knots]
    if np.ndim(degrees) == 0:
        degrees = [degrees] * directions
    counts = list(points.shape[:-1])
    # docs/formats.md lists control points u fastest; reversing the parameter axes
    # makes numpy's C order run u fastest.
    axes = tuple(reversed(range(directions)))
    flat_points = np.ascontiguousarray(points.transpose(axes + (directions,))).reshape(-1, points.shape[-1])
    flat_weights = None
    if weights is not None:
        weights = np.asarray(weights, dtype=np.float64)
        if weights.shape != points.shape[:-1]:
            raise InputError(f"weights: shape {weights.shape}, expected {points.shape[:-1]} (one per control point)")
        flat_weights = np.ascontiguousarray(weights.transpose(axes)).reshape(-1)
    return _invmap._from_bspline(flat_points, counts, [int(d) for d in degrees],
                                 [np.asarray(k, dtype=np.float64).tolist() for k in knots], flat_weights)


def grid(functions, *, mode="arrangement", tree=None, epsilon=1e-4, box=None, resolution=1, initial_grid=None,
         max_cells=None, threads=0):
    """Refines a triangle (2D) or tetrahedron (3D) grid for the zero sets of
    implicit functions (as `invmap grid`; README "Implicit-complex grids").

    functions: a path to a JSON function list, its JSON text, or a list of
      dicts such as {"type": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.3}.
    mode: "arrangement", "material" or "csg" (then `tree`: a path, JSON text
      or a list of {"type": "Intersection"|"Union"|"Negation", "elements": [a, b]}).
    box: (x0, y0[, z0], x1, y1[, z1]) with `resolution` cubes (squares) per
      side, or initial_grid: a gmsh .msh path of linear tetrahedra (triangles).
    max_cells: stop refining there (None: no limit). threads: 0 = all cores.

    Returns a dict: "vertices" (V, 3), "cells" (C, dim + 1), "values" (V, k),
    "active" (C,) bool, "function_names", "stats" (cells, active_cells,
    vertices, min_radius_ratio, min_radius_ratio_active, seconds,
    reached_max_cells) and "zero_sets" ("vertices", "triangles",
    "triangle_labels", "segments", "segment_labels", "points",
    "point_labels"; labels are 4 function indices, -1 unused).
    Raises InputError (file and line in the message) or FileError.
    """
    functions_text, functions_name = _json_source(functions, "<functions>")
    tree_text, tree_name = (None, "<tree>") if tree is None else _json_source(tree, "<tree>")
    if (box is None) == (initial_grid is None):
        raise InputError("grid: give exactly one of box and initial_grid")
    return _invmap._grid(functions_text, functions_name, mode, tree_text, tree_name, float(epsilon),
                         None if box is None else [float(x) for x in box], int(resolution),
                         None if initial_grid is None else os.fspath(initial_grid),
                         2**63 - 1 if max_cells is None else int(max_cells), int(threads))


def _json_source(source, name):
    """(text, name for messages) of a JSON path, JSON text or a list."""
    if isinstance(source, (list, tuple)):
        return json.dumps(list(source), default=_json_default, indent=1), name
    if isinstance(source, str) and source.lstrip().startswith("["):
        return source, name
    if isinstance(source, (str, os.PathLike)):
        path = os.fspath(source)
        try:
            with open(path, encoding="utf-8") as f:
                return f.read(), path
        except OSError as e:
            raise FileError(f"{path}: {e.strerror}") from e
    raise TypeError(f"grid: expected a path, JSON text or a list, got {type(source).__name__}")
