"""OCG-SLAM from Python (docs/python.md).

- ObjectSlam: the whole system (SLAM, cuboid objects, OCG) fed frame by frame: track(image,
  timestamp, detections) -> TrackResult (state, pose T_cw or None, keyframe, ...);
  read_image gives the pixels ocg_slam run uses.
- ChangeDetector: the Object Covisibility Graph change detector, fed once per keyframe by
  any SLAM system (pose T_cw, camera, observed object ids, centroids, ...: a dict or
  keywords of the fields observation_fields() lists; observation_to_json and
  observation_from_json give and read ocg_replay's lines).
- read_tum_trajectory, ate, object_metrics: the numbers of `ocg_eval`.

Errors from the library keep their message (file, line, key): ocg.FileError (an OSError),
ocg.ParseError, ocg.SettingsError and ocg.ReplayFormatError (ValueErrors), ValueError.
"""
import sys as _sys

# The native module is built for one interpreter (the one CMake found, named at configure
# time): another Python (pyenv, a venv, another version) cannot load it.
BUILT_FOR_PYTHON = "@Python3_EXECUTABLE@ (Python @Python3_VERSION_MAJOR@.@Python3_VERSION_MINOR@)"
# Every array it takes or gives is a NumPy array. Another Python of the same version loads
# the native module but may lack NumPy (pyenv's python3 before Debian's on PATH): say so
# here rather than at the first call.
try:
    import numpy as _numpy  # noqa: F401
except ImportError as _error:
    raise ImportError(
        "ocg needs NumPy, which " + _sys.executable + " cannot import; ocg was built for "
        + BUILT_FOR_PYTHON + ", which has it (python3-numpy): run that interpreter, or "
        "install NumPy for this one (docs/python.md). Cause: %s" % _error) from _error
try:
    from ._ocg import *  # noqa: F401,F403  (the native module defines __all__-free names)
    from ._ocg import __doc__ as _native_doc  # noqa: F401
except ImportError as _error:
    if getattr(_error, "name", None) == __name__ + "._ocg":
        # The package folder is written when CMake configures; the module is a build target.
        raise ImportError(
            "ocg's native module is not built in " + __path__[0] + ": build it with "
            "cmake --build BUILD --target ocg_python (tools/demo.sh builds it)") from _error
    raise ImportError(
        "ocg's native module was built for " + BUILT_FOR_PYTHON + ", but this is "
        + _sys.executable + " (Python %d.%d): run it with that interpreter, or rebuild with "
        "cmake -DPython3_EXECUTABLE=%s (docs/python.md). Cause: %s"
        % (_sys.version_info[0], _sys.version_info[1], _sys.executable, _error)) from _error

__version__ = "@PROJECT_VERSION@"
