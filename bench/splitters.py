"""How fast the frame splitters cut junk, and how much they keep: ours against pymodbus 3.16's framers.

Usage (from the repository root)::

    .venv/bin/python bench/splitters.py            # 10 MB of junk per splitter, about a minute
    .venv/bin/python bench/splitters.py --quick    # 1 MB, for a smoke test

A splitter that reads a serial line, a TCP stream or a capture meets junk: noise, a wrong baud rate, a
hostile peer.  It must keep up with the line and keep bounded memory whatever comes.  Each row feeds
seeded random bytes (and, for ASCII, a run of ':' without CR LF, the worst case of that mode):

* ``1 MB chunks``: the junk in chunks of 1 MB, as a capture is read; MB/s;
* ``byte by byte``: one byte per call, as a slow serial port delivers it; KB/s;
* ``kept``: the most bytes the splitter held between calls (its look-behind), in bytes.

pymodbus's framers are no comparison here: they are not resynchronising splitters. Fed the same junk,
``FramerRTU.handleFrame`` gives up at the first byte it cannot use and leaves the rest to its caller,
and ``FramerAscii`` raises ``ValueError`` on the first non-hex digit (the bench shows that row), so the
figures below are measured against the targets of the "robust under abuse" work instead.
Targets: at least 1 MB/s in 1 MB chunks and 50 KB/s byte by byte, and bounded memory.
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from pymodbus.framer import FramerAscii  # noqa: E402
from pymodbus.pdu import DecodePDU  # noqa: E402

from modbus_edu.framing import AsciiSplitter, RtuSplitter, TcpSplitter  # noqa: E402


def ours_feed(make, data: bytes, step: int) -> tuple[float, int]:
    splitter = make()
    kept = 0
    start = time.perf_counter()
    for i in range(0, len(data), step):
        splitter.feed(data[i:i + step])
        kept = max(kept, len(splitter._buffer))
    return time.perf_counter() - start, kept


def pymodbus_ascii_on_junk(data: bytes) -> str:
    """What pymodbus's ASCII framer does with the same junk (the first 1000 bytes)."""
    try:
        FramerAscii(DecodePDU(is_server=True)).handleFrame(data[:1000], 0, 0)
    except Exception as exc:  # the finding: a framer that lets junk raise
        return f"{type(exc).__name__}: {exc}"
    return "no error"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="1 MB of junk instead of 10 MB")
    args = parser.parse_args()
    size = 1_000_000 if args.quick else 10_000_000
    slow = 100_000 if args.quick else 300_000  # bytes fed one at a time
    rng = random.Random(2026)
    junk = rng.randbytes(size)
    colons = b":" * (size // 4)
    rows = [
        ("RTU request", lambda: RtuSplitter("request"), junk),
        ("RTU response", lambda: RtuSplitter("response"), junk),
        ("ASCII", AsciiSplitter, junk),
        ("ASCII ':' run", AsciiSplitter, colons),
        ("TCP", TcpSplitter, junk),
    ]
    print(f"{'splitter':<14} {'bytes':>11} {'1 MB chunks':>13} {'target':>7}   {'byte by byte':>13} "
          f"{'target':>7}   {'kept (bytes)':>12}")
    for name, make, data in rows:
        elapsed, kept_chunks = ours_feed(make, data, 1_000_000)
        sample = data[:slow]
        elapsed_slow, kept_slow = ours_feed(make, sample, 1)
        mbs = len(data) / elapsed / 1e6
        kbs = len(sample) / elapsed_slow / 1e3
        print(f"{name:<14} {len(data):>11,} {mbs:>8.2f} MB/s {mbs / 1.0:>6.1f}x   {kbs:>8.1f} KB/s "
              f"{kbs / 50:>6.1f}x   {kept_slow:>12}")
    print(f"\npymodbus FramerAscii on the same junk: {pymodbus_ascii_on_junk(junk)}")


if __name__ == "__main__":
    main()
