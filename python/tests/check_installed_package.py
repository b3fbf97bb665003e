"""Imports invmap from an installed prefix (ctest python_installed_package).

    check_installed_package.py SITE_PACKAGES VERSION

The package must come from SITE_PACKAGES, where `cmake --install` put it,
not from the build tree, be version VERSION and answer queries whose
results are known exactly.
"""

import pathlib
import sys

site = pathlib.Path(sys.argv[1]).resolve()
version = sys.argv[2]
sys.path.insert(0, str(site))

import numpy as np  # noqa: E402

import invmap  # noqa: E402

location = pathlib.Path(invmap.__file__).resolve()
if site not in location.parents:
    sys.exit(f"invmap imported from {location}, not from {site}")
if invmap.__version__ != version:
    sys.exit(f"invmap version {invmap.__version__}, expected {version}")

# A segment from (0, 0) to (2, 0): (0.5, 1) is at distance 1 above (0.5, 0),
# a quarter along it; (3, 0) is at distance 1 beyond its end (2, 0).
manifold = invmap.load({"format": "invmap-geometry", "version": 1, "dimension": 2,
                        "patches": [{"kind": "mesh", "cell": "line", "vertices": [[0, 0], [2, 0]],
                                     "cells": [[0, 1]]}]})
result = manifold.invert(np.array([[0.5, 1.0], [3.0, 0.0]]))
np.testing.assert_array_equal(result["distance"], [1.0, 1.0])
np.testing.assert_array_equal(result["params"][:, 0], [0.25, 1.0])
np.testing.assert_array_equal(result["closest"][:, :2], [[0.5, 0.0], [2.0, 0.0]])
print(f"invmap {invmap.__version__} from {location.parent}: ok")
