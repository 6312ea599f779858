"""The notebook tools, each imported by one loader when it is first needed.

``import modbus_edu`` loads none of them: nbformat, nbclient and IPython come with the ``course`` extra
and only the course tools (:mod:`modbus_edu.course`) use them; ``tqdm.auto`` loads ipywidgets when it
runs in a notebook.  The other heavy packages have their loader beside the one module that needs them:
scapy in :mod:`modbus_edu.capture`, cryptography in :mod:`modbus_edu.security`, matplotlib in
:mod:`modbus_edu.plotstyle`.
"""

from __future__ import annotations

from typing import Any

from .platform import IN_BROWSER


def load_nbformat() -> Any:
    """The ``nbformat`` module (reads and writes notebooks)."""
    import nbformat  # the course extra: only the course tools read notebooks

    return nbformat


def load_nbclient() -> Any:
    """The ``nbclient`` package with its ``exceptions`` and ``util`` (runs a notebook in a kernel)."""
    import nbclient  # the course extra: only the course tools run notebooks (it loads exceptions and util)

    return nbclient


def load_transformer_manager() -> Any:
    """IPython's ``TransformerManager``: a cell's source as the kernel runs it (magics made Python)."""
    from IPython.core.inputtransformer2 import TransformerManager  # the course extra: the grader only

    return TransformerManager


def load_tqdm() -> Any:
    """``tqdm.auto.tqdm``: a progress bar, a widget in a notebook and text elsewhere.

    In a browser (Pyodide), where no thread can start, tqdm's monitor thread (which only nudges bars that
    stall) is switched off beforehand instead of failing with a warning under the cell."""
    from tqdm.auto import tqdm  # tqdm.auto loads ipywidgets in a notebook: only when a bar is drawn

    if IN_BROWSER:
        tqdm.monitor_interval = 0
    return tqdm
