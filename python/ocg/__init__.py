"""OCG-SLAM from Python (docs/python.md).

- ObjectSlam: the whole system (SLAM, cuboid objects, OCG) fed frame by frame: track(image,
  timestamp, detections) -> T_cw or None; read_image gives the pixels ocg_slam run uses.
- ChangeDetector: the Object Covisibility Graph change detector, fed once per keyframe by
  any SLAM system (pose T_cw, camera, observed object ids, centroids).
- read_tum_trajectory, ate, object_metrics: the numbers of `ocg_eval`.

Errors from the library keep their message (file, line, key): ocg.FileError (an OSError),
ocg.ParseError, ocg.SettingsError and ocg.ReplayFormatError (ValueErrors), ValueError.
"""
from ._ocg import *  # noqa: F401,F403  (the native module defines __all__-free names)
from ._ocg import __doc__ as _native_doc  # noqa: F401

__version__ = "@PROJECT_VERSION@"
