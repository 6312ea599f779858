"""The checkers of the course's exercises, one module per notebook (``nbNN.py``: the exercises of notebook
NN), each found and imported here, so that importing :mod:`modbus_edu.exercises` registers them all.

A checker judges from the exercise's own answer and asks the diagnosis (:mod:`..diagnosis`) to name a
wrong one: the concept's procedure with one step changed, and the catalogue of misconceptions that names it.
"""

from __future__ import annotations

import importlib
import pkgutil

NOTEBOOKS = {info.name: importlib.import_module(f"{__name__}.{info.name}")
             for info in sorted(pkgutil.iter_modules(__path__), key=lambda info: info.name)
             if info.name.startswith("nb")}
"""Each notebook's checker module by its name (``"nb03"``)."""
