"""The catalogue of misconceptions, where it was first kept: it lives in :mod:`.diagnosis.misconceptions`
now; these names stay importable from here (the grader's verdicts and the course's tests read them)."""

from .diagnosis.misconceptions import (  # noqa: F401
    CATALOGUE,
    ORDER_WORDS,
    crc16_reflected,
    crc16_unreflected,
    detect,
    diagnose,
    name,
)
