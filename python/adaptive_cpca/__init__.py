"""adaptive-cpca from Python: relight transport and model files.

`import adaptive_cpca` gives the compiled module's API (Relighter, open,
Environment, Light, precompute, compress, import_transport, ...; the
compiled part is `adaptive_cpca._core`). `adaptive_cpca.torch` relights
model files in PyTorch on any device, in pure Python over torch and h5py,
without the compiled part.
"""

import importlib as _importlib
import importlib.util as _importlib_util

try:
    from . import _core
except ImportError as error:  # the pure-Python parts work without it
    _core = None
    _core_error = error
else:
    globals().update({name: value for name, value in vars(_core).items()
                      if not name.startswith("__") or name == "__version__"})
    __doc__ = _core.__doc__ or __doc__


def __getattr__(name):
    # A pure-Python submodule (torch, torch_lighting, ...) is imported, not refused.
    if not name.startswith("__") and _importlib_util.find_spec(f"{__name__}.{name}"):
        return _importlib.import_module(f"{__name__}.{name}")
    if _core is None and not name.startswith("__"):
        raise ImportError(f"adaptive_cpca.{name} needs the compiled module, which did not load "
                          f"({_core_error}); adaptive_cpca.torch works without it")
    raise AttributeError(f"module 'adaptive_cpca' has no attribute {name!r}")
