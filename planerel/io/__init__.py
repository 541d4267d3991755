"""Stage 1, input and output: files and arrays in, :class:`~planerel.io.cloud.Cloud` out; labels,
clouds, facts and images back out to files.

In: depth images (PNG, TIFF, ABW), point clouds (PCD, PLY, NPY), label images, JSON side files.
Out: ``Cloud`` (organized ``(H, W, 3)`` points with intrinsics and up), and the writers' files.
Modules: :mod:`~planerel.io.cloud` (the ``Cloud`` type), :mod:`~planerel.io.readers` (every
reader; re-exported here, so ``planerel.io.read`` keeps working), :mod:`~planerel.io.writers`,
:mod:`~planerel.io.exports` (segmentation exports), :mod:`~planerel.io.naming` (scene names),
:mod:`~planerel.io.organize` (an image grid for an unorganized cloud, by z-buffer).
"""

from planerel.io.readers import *  # noqa: F401,F403  (the documented planerel.io.read & co.)
from planerel.io.readers import __all__  # noqa: F401
