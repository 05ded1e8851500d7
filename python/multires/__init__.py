"""multires: multiresolution editing of triangle meshes, from Python.

The compiled extension (``multires._multires``, Rust through PyO3) does the work; this
package re-exports it and adds :func:`batch`, corpus batches on Dask.

>>> import numpy as np, multires
>>> mesh = multires.Mesh.from_arrays(np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0]]),
...                                  np.array([[0, 1, 2]]))
>>> mesh.info()["faces"]
1

Everything the library refuses is a :class:`MeshError` (a ``ValueError``), with the
library's message; editing methods raise :class:`EditError` and recipes
:class:`RecipeError` (both ``MeshError`` subclasses); a missing file is a
``FileNotFoundError``. Long calls (reading, building, walking, editing, saving) release
the GIL, so threads run them in parallel.
"""

from ._multires import (  # noqa: F401
    EditError,
    Hierarchy,
    Mesh,
    MeshError,
    RecipeError,
    __version__,
    apply_recipe,
    barr_bend,
    barr_taper,
    barr_twist,
    blend,
    blend_image,
    blend_polyline,
    disk,
    ffd,
    grid,
    icosphere,
    lee_drag,
    read,
    submesh_pull,
    submesh_rotate,
    submesh_scale,
    submesh_taper,
    submesh_twist,
    surface_distance,
    taubin,
    torus,
    workflow,
)
from ._batch import batch  # noqa: F401

__all__ = [
    "EditError",
    "Hierarchy",
    "Mesh",
    "MeshError",
    "RecipeError",
    "__version__",
    "apply_recipe",
    "barr_bend",
    "barr_taper",
    "barr_twist",
    "batch",
    "blend",
    "blend_image",
    "blend_polyline",
    "disk",
    "ffd",
    "grid",
    "icosphere",
    "lee_drag",
    "read",
    "submesh_pull",
    "submesh_rotate",
    "submesh_scale",
    "submesh_taper",
    "submesh_twist",
    "surface_distance",
    "taubin",
    "torus",
    "workflow",
]
