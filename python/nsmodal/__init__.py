"""nsmodal: nonsmooth modal analysis of vibro-impact systems.

The computations are the C++ library's, compiled into the extension module
``nsmodal._nsmodal`` (pybind11); this package re-exports its classes and
functions under ``nsmodal`` and ships their type stubs (``__init__.pyi`` and the
``py.typed`` marker, PEP 561) for editors and type checkers.
"""
from . import _nsmodal
from ._nsmodal import *  # noqa: F401,F403  (the public API, listed in __all__)
from ._nsmodal import __version__

__all__ = sorted(name for name in dir(_nsmodal) if not name.startswith("_"))

# Shown, documented and pickled as nsmodal.X (pickle finds nsmodal.Model).
for _name in __all__:
    try:
        getattr(_nsmodal, _name).__module__ = __name__
    except (AttributeError, TypeError):  # not every object takes the attribute
        pass
del _name
