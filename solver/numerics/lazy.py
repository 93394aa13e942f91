"""A package's public names imported on first use (PEP 562 module ``__getattr__``).

``import solver`` then costs nothing until a name is used: reading and checking case tables
(``study validate``, ``study status``) does not load the solve's FFT and signal libraries.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
from collections.abc import Callable


def lazy_exports(package: str, public: dict[str, str]) -> tuple[Callable, Callable]:
    """The ``__getattr__`` and ``__dir__`` of ``package`` whose names ``public`` maps to modules.

    A name that is not public but a module or sub-package of the package is imported as such,
    a sub-package with all its modules, so that ``import solver`` still gives
    ``solver.bodies.heights`` as the eager import of every module did.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    public : dict
        Public name -> the module (relative to ``package``) that defines it.
    """

    def __getattr__(name: str):  # noqa: N807 - the module attribute hook
        if name in public:
            value = getattr(importlib.import_module(public[name], package), name)
        else:  # a sub-package, with its modules: ``solver.bodies.heights`` after ``import solver``
            try:
                value = importlib.import_module(f"{package}.{name}")
            except ModuleNotFoundError as error:
                if error.name != f"{package}.{name}":
                    raise
                raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
            for module in pkgutil.iter_modules(getattr(value, "__path__", [])):
                importlib.import_module(f"{value.__name__}.{module.name}")
        setattr(sys.modules[package], name, value)  # imported once
        return value

    def __dir__() -> list[str]:  # noqa: N807
        return sorted({*vars(sys.modules[package]), *public})

    return __getattr__, __dir__
