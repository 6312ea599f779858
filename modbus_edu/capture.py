"""Captures: what a :class:`~modbus_edu.traffic.TrafficLog` recorded, as a pcap file Wireshark opens.

:func:`write_pcap` writes a log (a master's, a slave's, a loopback wire's monitor, a gateway master's)
or a list of frames as a classic pcap file; :func:`read_pcap` reads such a file, or a capture that
another tool (tshark, tcpdump, Wireshark) took of Modbus/TCP, back into a :class:`TrafficLog` whose
entries go straight into :func:`~modbus_edu.explain.explain`::

    master = mb.Master(mb.loopback_serial(meter))
    master.read_holding_registers(unit=1, address=0, count=2)
    mb.write_pcap(master.link.monitor, "meter.pcap")     # the wire, as Wireshark would show it
    frames = mb.read_pcap("meter.pcap")
    mb.explain(frames[0].data, frames[0].mode, frames[0].role)

**Modbus/TCP** is written as the packets a loopback interface would carry: Ethernet (all-zero
addresses, as Linux's ``lo`` has), IPv4 and TCP from the client ``127.0.0.1:49152`` to the server
``127.0.0.2:502``.  The connection opens with the three-way handshake and closes with FIN; every frame is
one segment whose sequence and acknowledgement numbers continue the stream, and the IP and TCP checksums
are right, so Wireshark follows the stream and dissects every frame as Modbus/TCP with no setting at all.
A frame sent as a *request* (``Traffic.role``, or a ``"tx"`` entry of a master's log) goes from the
client to the server, a *response* back.

**Serial frames** (RTU, ASCII) have no IP: each frame is one packet of a "user" link type, the one
a capture file gives to a protocol Wireshark cannot guess.  RTU frames use ``DLT_USER0`` (147), which
Wireshark's own "Modbus RTU" dissector (``mbrtu``) reads once the user link-type table says so::

    tshark -o 'uat:user_dlts:"User 0 (DLT=147)","mbrtu","0","","0",""' -r meter.pcap

(in Wireshark: Edit > Preferences > Protocols > DLT_USER > Encapsulations Table: Edit, then "+" and
DLT "User 0 (DLT=147)" with payload dissector ``mbrtu``; add ``-o mbrtu.crc_verification:TRUE`` to have
it check each CRC).  What tshark 4.0 then shows: every frame of 5 bytes or more as Modbus RTU, with its
unit and function; a serial line carries no direction, so it tells a request from a response by length
alone, which works for FC 1-4, 15, 16 and exception responses, and calls the others "unable to
classify"; the 4-byte requests of FC 7, 11, 12 and 17 are shorter than it accepts and stay plain bytes.
Wireshark has no Modbus ASCII dissector: ASCII frames use ``DLT_USER1`` (148), shown as lines of text
with the payload dissector ``data-text-lines``::

    tshark -o 'uat:user_dlts:"User 1 (DLT=148)","data-text-lines","0","","0",""' -r ascii.pcap

(:data:`TSHARK_RTU` and :data:`TSHARK_ASCII` hold these settings; :func:`tshark` runs tshark on a capture
with the setting its link type needs, and gives None where tshark is not installed.)

A frame's timestamp is the time its log gives it: on a loopback wire the virtual clock's, to the
nanosecond (the file stores nanoseconds), so the 3.5-character silences between frames show in
Wireshark's time column as they were on the wire.
A serial capture does not say who sent a frame: :func:`read_pcap` works it out (see there).

The packets and the file are made and read by **scapy** (imported only when a capture is written or
read: ``import modbus_edu`` stays fast).  Every problem with a file raises :class:`CaptureError`, a
:class:`~modbus_edu.errors.ModbusError`, saying what is wrong and where.
"""

from __future__ import annotations

import heapq
import ipaddress
import logging
import math
import os
import shutil
import subprocess
from collections.abc import Iterable
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .errors import CaptureError, MissingDependencyError, ModbusError, shown
from .framing import TcpSplitter, decode_frame
from .pcapfile import MAGICS, MAX_PACKET, bad_magic, check_blocks, cut_short
from .platform import BINDER, IN_BROWSER
from .traffic import Traffic, TrafficLog

__all__ = [
    "CLIENT",
    "LINKTYPE_ASCII",
    "LINKTYPE_RTU",
    "SERVER",
    "TSHARK_ASCII",
    "TSHARK_RTU",
    "read_pcap",
    "tshark",
    "write_pcap",
]

LINKTYPE_ETHERNET = 1
LINKTYPE_RTU = 147
"""``DLT_USER0``: one Modbus RTU frame per packet (Wireshark: payload dissector ``mbrtu``)."""
LINKTYPE_ASCII = 148
"""``DLT_USER1``: one Modbus ASCII frame per packet, ``:`` to CR LF (Wireshark: ``data-text-lines``)."""
TSHARK_RTU = 'uat:user_dlts:"User 0 (DLT=147)","mbrtu","0","","0",""'
"""tshark's ``-o`` setting that dissects :data:`LINKTYPE_RTU` packets as Modbus RTU."""
TSHARK_ASCII = 'uat:user_dlts:"User 1 (DLT=148)","data-text-lines","0","","0",""'
"""tshark's ``-o`` setting that shows :data:`LINKTYPE_ASCII` packets as text lines."""

CLIENT = ("127.0.0.1", 49152)
"""The client's (the master's) address and port in a written Modbus/TCP capture."""
SERVER = ("127.0.0.2", 502)
"""The server's address and port: 502, the port IANA registered for Modbus/TCP."""

_MODES = ("rtu", "ascii", "tcp")
_SERIAL_LINKTYPES = {LINKTYPE_RTU: "rtu", LINKTYPE_ASCII: "ascii"}
_MAX_FRAME = 65_000           # bytes of one frame in one written packet (IPv4 total length is 16 bits)
_MAX_SECONDS = 2**32 - 1      # the classic pcap header keeps the seconds in 32 bits
_CLIENT_ISN = 1_000           # the initial sequence numbers of the written connection
_SERVER_ISN = 500_000
_WINDOW = 65_483
_MAX_HELD = 256               # out-of-order segments held per direction while a gap waits to be filled
_MODBUS_PORTS = (502,)


# --- writing --------------------------------------------------------------------------------------------
def write_pcap(source: TrafficLog | Iterable[Any], path: str | os.PathLike[str], *,
               client: tuple[str, int] = CLIENT, server: tuple[str, int] = SERVER) -> Path:
    """Write ``source`` as a classic pcap file at ``path``; return the path.

    ``source`` is a :class:`~modbus_edu.traffic.TrafficLog` or a list of frames: :class:`Traffic`
    entries or tuples ``(time, direction, mode, data)`` (optionally followed by Traffic's other fields:
    source, dest, note, role).  All frames must be of one mode: a capture file has one link type, so a
    gateway's two sides (Modbus/TCP in front, RTU behind) go to two files.

    Modbus/TCP frames become one TCP connection from ``client`` to ``server`` (defaults :data:`CLIENT`
    and :data:`SERVER`), RTU and ASCII frames packets of link type :data:`LINKTYPE_RTU` or
    :data:`LINKTYPE_ASCII`; see the module's documentation for what Wireshark needs to read each.
    """
    entries = _entries(source)
    modes = sorted({entry.mode for entry in entries})
    if len(modes) > 1:
        raise CaptureError(
            f"the frames are of {len(modes)} modes ({', '.join(modes)}), and a capture file holds one link "
            f"type: write each mode to its own file, e.g. [t for t in log if t.mode == 'tcp']"
        )
    mode = modes[0]
    path = _path(path)
    scapy = _scapy()
    with _quiet_scapy():
        try:
            if mode == "tcp":
                client, server = _endpoint(client, "client"), _endpoint(server, "server")
                if client == server:
                    raise CaptureError(f"client and server are both {client}: a TCP connection has two ends")
                packets = _tcp_packets(entries, client, server)
                _write(scapy, path, LINKTYPE_ETHERNET, packets)
            else:
                linktype = LINKTYPE_RTU if mode == "rtu" else LINKTYPE_ASCII
                _write(scapy, path, linktype, [(entry.time, entry.data) for entry in entries])
        except OSError as exc:
            raise CaptureError(f"cannot write the capture {str(path)!r}: {exc.strerror or exc}") from None
    return path


def _entries(source: Any) -> list[Traffic]:
    """The frames of ``source`` as :class:`Traffic` entries, each checked."""
    if isinstance(source, (str, bytes, bytearray, os.PathLike)):
        raise CaptureError(
            f"write_pcap(source, path) takes the frames first (a TrafficLog or a list), got "
            f"{type(source).__name__} {str(source)[:40]!r}: is the order of the arguments swapped?"
        )
    try:
        items = list(source)
    except TypeError:
        raise CaptureError(
            f"write_pcap expects a TrafficLog or a list of frames, got {type(source).__name__}"
        ) from None
    if not items:
        raise CaptureError("there are no frames to write: the log is empty (has the master sent anything?)")
    entries = []
    for index, item in enumerate(items):
        if isinstance(item, Traffic):
            entry = item
        elif isinstance(item, (tuple, list)) and 4 <= len(item) <= 9:
            try:
                entry = Traffic(*item)
            except ModbusError as exc:
                raise CaptureError(f"frame {index}: {exc}") from None
            except (TypeError, ValueError) as exc:
                raise CaptureError(f"frame {index} is not (time, direction, mode, data, ...): {exc}") \
                    from None
        else:
            raise CaptureError(
                f"frame {index} is a {type(item).__name__}: expected a Traffic entry or a tuple "
                f"(time, direction, mode, data)"
            )
        _check_entry(index, entry)
        entries.append(entry)
    return entries


def _check_entry(index: int, entry: Traffic) -> None:
    if entry.mode not in _MODES:
        raise CaptureError(f"frame {index}: mode {shown(entry.mode)} is not one of 'rtu', 'ascii', 'tcp'")
    time = entry.time
    if not isinstance(time, (int, float)) or isinstance(time, bool) or not math.isfinite(time) \
            or not 0 <= time <= _MAX_SECONDS:
        raise CaptureError(
            f"frame {index}: time {shown(time)} cannot go in a pcap file, which counts seconds from 0 to "
            f"{_MAX_SECONDS} (a log's times are seconds on its link's clock)"
        )
    if len(entry.data) > _MAX_FRAME:
        raise CaptureError(f"frame {index} holds {len(entry.data)} bytes: at most {_MAX_FRAME} fit one "
                           f"packet (a Modbus frame has at most 260)")


def _endpoint(value: Any, name: str) -> tuple[str, int]:
    try:
        host, port = value
        host = str(ipaddress.IPv4Address(host))
    except (TypeError, ValueError):
        raise CaptureError(f"{name} must be (IPv4 address, port), e.g. {CLIENT}, got "
                           f"{shown(value)}") from None
    if not isinstance(port, int) or not 1 <= port <= 65535:
        raise CaptureError(f"{name} port must be 1..65535, got {shown(port)}")
    return host, port


def _path(path: Any) -> Path:
    if not isinstance(path, (str, os.PathLike)):
        raise CaptureError(f"a capture's path is a str or a Path, got {type(path).__name__}")
    return Path(path)


def _nanoseconds(time: float) -> tuple[int, int]:
    """(seconds, nanoseconds) of a time in seconds, rounded to the nanosecond."""
    return divmod(round(time * 1_000_000_000), 1_000_000_000)


def _write(scapy: Any, path: Path, linktype: int, packets: list[tuple[float, bytes]]) -> None:
    writer = scapy.RawPcapWriter(str(path), linktype=linktype, nano=True, snaplen=MAX_PACKET)
    try:
        writer.write_header(None)
        for time, data in packets:
            sec, nsec = _nanoseconds(time)
            writer.write_packet(data, sec=sec, usec=nsec)
    finally:
        writer.close()


def _tcp_packets(entries: list[Traffic], client: tuple[str, int],
                 server: tuple[str, int]) -> list[tuple[float, bytes]]:
    """The packets of one TCP connection carrying ``entries``: handshake, one segment a frame, FIN."""
    scapy = _scapy()
    ip_id = {client: 0, server: 0}
    packets: list[tuple[float, bytes]] = []
    # the Ethernet header of a loopback interface (all-zero addresses) is the same on every packet: made
    # once, it halves the time a long log takes
    ethernet = bytes(scapy.Ether(src="00:00:00:00:00:00", dst="00:00:00:00:00:00", type=0x0800))

    def segment(time: float, sender: tuple[str, int], seq: int, ack: int, flags: str, data: bytes = b"",
                options: list | None = None) -> None:
        receiver = server if sender == client else client
        ip_id[sender] += 1
        packet = (
            scapy.IP(src=sender[0], dst=receiver[0], id=ip_id[sender], flags="DF", ttl=64)
            / scapy.TCP(sport=sender[1], dport=receiver[1], seq=seq % 2**32, ack=ack % 2**32, flags=flags,
                        window=_WINDOW, options=options or [])
        )
        if data:
            packet = packet / scapy.Raw(data)
        packets.append((time, ethernet + bytes(packet)))

    start, end = entries[0].time, entries[-1].time
    seq = {client: _CLIENT_ISN, server: _SERVER_ISN}
    segment(start, client, seq[client], 0, "S", options=[("MSS", 65495)])
    seq[client] += 1
    segment(start, server, seq[server], seq[client], "SA", options=[("MSS", 65495)])
    seq[server] += 1
    segment(start, client, seq[client], seq[server], "A")
    for entry in entries:
        sender, receiver = (client, server) if entry.guessed_role == "request" else (server, client)
        segment(entry.time, sender, seq[sender], seq[receiver], "PA", entry.data)
        seq[sender] += len(entry.data)
        end = max(end, entry.time)
    segment(end, client, seq[client], seq[server], "FA")
    seq[client] += 1
    segment(end, server, seq[server], seq[client], "FA")
    seq[server] += 1
    segment(end, client, seq[client], seq[server], "A")
    return packets


# --- reading ---------------------------------------------------------------------------------------------
def read_pcap(path: str | os.PathLike[str], *, port: int | None = None) -> TrafficLog:
    """The Modbus frames in the capture at ``path``, oldest first, as a :class:`TrafficLog`.

    Reads classic pcap and pcapng files (what tcpdump and Wireshark write; a gzipped file must be
    unpacked first).  Each entry holds the frame's ``time`` (seconds, as the file stores them), its
    ``source`` and ``dest``, ``direction``, ``mode``, ``data`` (the frame's bytes) and ``role``:
    ``mb.explain(f.data, f.mode, f.role)`` dissects it, and ``log.explain(i)`` does the same.

    **Modbus/TCP** (in Ethernet, Linux "cooked", loopback or raw IP packets; IPv4 or IPv6): each TCP
    connection's bytes are put back in order per direction (retransmissions and overlaps counted once,
    segments that arrive early held until the gap before them fills) and cut into frames by
    :class:`~modbus_edu.framing.TcpSplitter`, the MBAP length rule the library's own links use.  A frame
    split over several segments is one entry, at the time of the segment that completes it (where
    Wireshark shows it too).  The server is the side on ``port`` if given, else the side that accepted
    the connection (the SYN's destination), else the side on port 502, else the lower port.  Frames to the
    server are requests (``direction "tx"``, as in a master's log), frames from it responses (``"rx"``).
    Without ``port``, a connection counts as Modbus/TCP when it is on port 502 or when all its bytes cut
    cleanly into MBAP frames; give ``port`` to read a server on another port whatever else it carries.
    Bytes that cannot start a frame are skipped, and the next frame's note says how many; so does a gap
    (bytes the capture missed).  Without the SYN, the first segment seen starts a direction until one
    from before it arrives (the first segments swapped): the direction is then read again from there,
    within its first 256 segments.  While a gap waits, at most 256 later segments are held; one more,
    and the reader goes on without the gap's bytes, and the next frame's note says so; should they come
    after all, they are not read, and a note says that too (on the direction's last frame if no frame
    follows).

    **Serial** packets (link types :data:`LINKTYPE_RTU` and :data:`LINKTYPE_ASCII`) are one frame each.
    The file does not say who sent them, so the role is worked out as a person reading the line would: a
    frame that decodes only as a request, or only as a response, is that; one that decodes as both (FC 5
    and FC 6 echo their requests) is the response when it answers the request just before it (same unit,
    same function), else a request.  A frame that decodes as neither (a CRC error) keeps ``role None``.

    A file that is not a capture, or is damaged (cut short at any byte but between two packets, a length
    field that runs past the end or past its block, a block that does not parse), raises
    :class:`CaptureError` saying where.  The work is linear in the
    size of the file.
    """
    if port is not None and (not isinstance(port, int) or isinstance(port, bool) or not 1 <= port <= 65535):
        raise CaptureError(f"port must be a TCP port 1..65535 (or None), got {shown(port)}")
    records = _records(_path(path))
    reader = _Reader(port)
    for index, (time, linktype, data) in enumerate(records):
        if linktype in _SERIAL_LINKTYPES:
            reader.serial(index, time, _SERIAL_LINKTYPES[linktype], data)
        else:
            reader.packet(index, time, linktype, data)
    return TrafficLog(reader.finish())


def _records(path: Path) -> list[tuple[float, int, bytes]]:
    """(time, link type, bytes) of every packet in the file, checked to be whole."""
    try:
        size = path.stat().st_size
        handle = path.open("rb")
    except OSError as exc:
        raise CaptureError(f"cannot open the capture {str(path)!r}: {exc.strerror or exc}") from None
    with handle:
        magic = handle.read(4)
        handle.seek(0)
        kind = MAGICS.get(magic)
        if kind is None:
            raise CaptureError(bad_magic(path, magic))
        if kind == "pcapng":
            check_blocks(path, handle, size)
            handle.seek(0)
        scapy = _scapy()
        records: list[tuple[float, int, bytes]] = []
        with _quiet_scapy():
            try:
                reader = scapy.RawPcapReader(handle)
            except Exception as exc:  # scapy's reasons for refusing a header vary: say it in our words
                raise CaptureError(f"{path.name}: the {kind} file header is damaged ({exc}); "
                                   f"nothing can be read from it") from None
            nano = getattr(reader, "nano", False)
            linktype = getattr(reader, "linktype", None)
            while True:
                where = handle.tell()
                try:
                    data, meta = reader._read_packet(MAX_PACKET + 1)
                except EOFError:
                    break
                except Exception as exc:  # a damaged block that scapy reports other than by EOFError
                    raise CaptureError(f"{path.name}: packet {len(records) + 1} (at byte {where}) is "
                                       f"damaged: {exc}") from None
                if kind == "pcap":
                    if meta.caplen != len(data):
                        raise CaptureError(cut_short(path, len(records), where, meta.caplen, len(data)))
                    time = meta.sec + meta.usec / (1e9 if nano else 1e6)
                    records.append((time, linktype, data))
                elif meta.tshigh is None or not meta.tsresol:
                    # a simple packet block has no timestamp: it keeps the time of the packet before it
                    records.append((records[-1][0] if records else 0.0, meta.linktype, data))
                else:
                    ticks = (meta.tshigh << 32) | meta.tslow
                    records.append((ticks / meta.tsresol, meta.linktype, data))
            stopped = handle.tell()
        if stopped < size:
            raise CaptureError(
                f"{path.name}: reading stopped at byte {stopped} of {size} after {len(records)} packets: "
                f"the {'record' if kind == 'pcap' else 'block'} there is damaged (its length field runs "
                f"past the end of the file, or its header does not parse); the file was cut short or "
                f"overwritten"
            )
    return records


@dataclass
class _Direction:
    """One direction of a TCP connection: the bytes put back in order and cut into frames."""

    splitter: TcpSplitter = field(default_factory=TcpSplitter)
    next_seq: int | None = None
    position: int = 0        # bytes of this direction put in order so far (not wrapped, unlike next_seq)
    held: list[tuple[int, int, int, float, bytes]] = field(default_factory=list)
    """Segments that came early: (position, arrival order, packet index, time, bytes)."""
    origin: int | None = None
    """The sequence number of the direction's first byte, where no SYN said it: the first segment seen."""
    replay: list[tuple[int, float, int, bytes]] | None = None
    """Without a SYN, the first segments (packet index, time, seq, bytes), kept to read the direction
    again should bytes from before the first one seen arrive; None once there is a SYN or too many."""
    missed: int = 0          # bytes of gaps the capture did not hold, not yet reported
    skipped: int = 0         # bytes of gaps read past while too many segments waited, not yet reported
    skipped_spans: list[tuple[int, int]] = field(default_factory=list)
    """Positions (start, end) of the gaps read past, to know their bytes if they come after all."""
    late: int = 0            # bytes that came after the reader had read past them, not yet reported
    reported_junk: int = 0   # splitter.discarded already reported


@dataclass
class _Stream:
    server: tuple[str, int]
    client: tuple[str, int]
    directions: dict[tuple[str, int], _Direction] = field(default_factory=dict)
    frames: list[tuple[int, int, Traffic]] = field(default_factory=list)
    data_seen: bool = False


class _Reader:
    """Turns packets into frames: TCP connections reassembled and cut, serial frames given their roles."""

    def __init__(self, port: int | None) -> None:
        self.port = port
        self.scapy = _scapy()
        self.streams: dict[frozenset, _Stream] = {}
        self.done: list[_Stream] = []
        self.serial_frames: list[tuple[int, int, Traffic]] = []
        self.order = 0
        self.previous: Traffic | None = None

    # -- serial --------------------------------------------------------------------------------------
    def serial(self, index: int, time: float, mode: str, data: bytes) -> None:
        role = _serial_role(data, mode, self.previous)
        previous = self.previous
        if role is None:  # undecodable: the turn of the line decides the direction
            answers = previous is not None and previous.role == "request" and previous.unit not in (0, None)
            direction = "rx" if answers else "tx"
        else:
            direction = "tx" if role == "request" else "rx"
        unit = Traffic(time, direction, mode, data).unit
        party = "broadcast" if unit == 0 else f"unit {unit}" if unit is not None else "?"
        source, dest = ("master", party) if direction == "tx" else (party, "master")
        entry = Traffic(time, direction, mode, data, source=source, dest=dest, role=role)
        self.previous = entry
        self.serial_frames.append((index, 0, entry))

    # -- TCP -----------------------------------------------------------------------------------------
    def packet(self, index: int, time: float, linktype: int, data: bytes) -> None:
        segment = self._tcp_segment(linktype, data)
        if segment is None:
            return
        src, dst, seq, flags, payload = segment
        key = frozenset((src, dst))
        stream = self.streams.get(key)
        syn, ack = bool(flags & 0x02), bool(flags & 0x10)
        if stream is not None and syn and not ack and stream.data_seen:
            self.done.append(stream)  # the same addresses and ports again: a new connection
            stream = None
        if stream is None:
            server = self._server(src, dst, syn, ack)
            client = dst if server == src else src
            stream = _Stream(server=server, client=client)
            stream.directions = {server: _Direction(), client: _Direction()}
            self.streams[key] = stream
        direction = stream.directions[src]
        if syn:
            direction.next_seq = (seq + 1) % 2**32
            direction.replay = None
            if not ack and stream.server != dst and self.port is None and not stream.data_seen:
                stream.server, stream.client = dst, src  # the SYN's destination accepts: it is the server
            return
        if not payload:
            return
        stream.data_seen = True
        if direction.next_seq is None:  # no SYN: the first bytes seen start the direction, until earlier come
            direction.next_seq = direction.origin = seq
            direction.replay = []
        self._segment(stream, src, direction, index, time, seq, payload)

    def _segment(self, stream: _Stream, src: tuple[str, int], direction: _Direction, index: int,
                 time: float, seq: int, payload: bytes) -> None:
        """Put one segment's bytes in their place: read now, held until a gap fills, or known already."""
        if direction.replay is not None:
            if _seq_offset(seq, direction.origin) < 0:  # type: ignore[arg-type]
                self._rewind(stream, src, direction, index, time, seq, payload)
                return
            direction.replay.append((index, time, seq, payload))
            if len(direction.replay) > _MAX_HELD:
                direction.replay = None  # the start is settled: later bytes from before it come too late
        offset = _seq_offset(seq, direction.next_seq)  # type: ignore[arg-type]
        if offset > 0:  # early: hold it until the gap before it fills
            heapq.heappush(direction.held, (direction.position + offset, self._next_order(), index, time,
                                            payload))
            if len(direction.held) > _MAX_HELD:
                self._skip_gap(stream, src, direction, missing=False)
            return
        if offset < 0:
            self._count_late(direction, direction.position + offset, min(-offset, len(payload)))
        self._take(stream, src, direction, index, time, -offset, payload)
        self._release(stream, src, direction, index, time)

    def _rewind(self, stream: _Stream, src: tuple[str, int], direction: _Direction, index: int,
                time: float, seq: int, payload: bytes) -> None:
        """Bytes from before the first segment seen (a capture without the SYN, the first segments
        swapped): read the direction again, from them."""
        mine = "tx" if src == stream.client else "rx"
        stream.frames = [item for item in stream.frames if item[2].direction != mine]
        fresh = _Direction(next_seq=seq, origin=seq, replay=[])
        stream.directions[src] = fresh
        for segment in [*direction.replay, (index, time, seq, payload)]:  # type: ignore[misc]
            self._segment(stream, src, fresh, *segment)

    @staticmethod
    def _count_late(direction: _Direction, start: int, size: int) -> None:
        """Bytes at positions start.. that the reader has passed: late if they are a gap's it read past
        (or from before a settled start), else a retransmission of bytes already read."""
        end = start + size
        late = max(0, min(end, 0) - start)  # before the first byte of a start without a SYN
        spans = []
        for low, high in direction.skipped_spans:
            inside = max(0, min(high, end) - max(low, start))
            late += inside
            if inside:  # what is left of the gap around these bytes
                pieces = ((low, max(low, min(high, start))), (max(low, end), high))
                spans += [(a, b) for a, b in pieces if a < b]
            else:
                spans.append((low, high))
        direction.skipped_spans = spans
        direction.late += late

    def _next_order(self) -> int:
        self.order += 1
        return self.order

    def _take(self, stream: _Stream, src: tuple[str, int], direction: _Direction, index: int, time: float,
              overlap: int, payload: bytes) -> None:
        """Feed the bytes of ``payload`` past the first ``overlap`` (already seen) to the splitter."""
        if overlap >= len(payload):
            return
        fresh = payload[overlap:]
        direction.next_seq = (direction.next_seq + len(fresh)) % 2**32  # type: ignore[operator]
        direction.position += len(fresh)
        to_server = src == stream.client
        for frame in direction.splitter.feed(fresh):
            notes = self._gap_notes(direction)
            junk = direction.splitter.discarded - direction.reported_junk
            if junk:
                notes.append(f"{junk} bytes before it skipped: they cannot start a Modbus/TCP frame")
                direction.reported_junk = direction.splitter.discarded
            sender, receiver = (stream.client, stream.server) if to_server else (stream.server, stream.client)
            entry = Traffic(time, "tx" if to_server else "rx", "tcp", frame, source=_label(sender),
                            dest=_label(receiver), note="; ".join(notes),
                            role="request" if to_server else "response")
            stream.frames.append((index, self._next_order(), entry))

    def _release(self, stream: _Stream, src: tuple[str, int], direction: _Direction, index: int,
                 time: float) -> None:
        """Feed the held segments that the stream has now reached."""
        held = direction.held
        while held:
            position, _, _, _, payload = held[0]
            start = position - direction.position
            if start > 0:
                return
            heapq.heappop(held)
            self._take(stream, src, direction, index, time, -start, payload)

    @staticmethod
    def _gap_notes(direction: _Direction) -> list[str]:
        """What the next frame's note says about the gaps and late bytes before it (then forgotten)."""
        notes = []
        if direction.missed:
            notes.append(f"after a gap: the capture lacks {direction.missed} bytes of this direction")
        if direction.skipped:
            notes.append(f"after a gap: {direction.skipped} bytes of this direction had not arrived while "
                         f"{_MAX_HELD} later segments waited for them; the reader went on without them")
        if direction.late:
            notes.append(f"{direction.late} bytes of this direction arrived after the reader had gone on "
                         f"without them: not read")
        direction.missed = direction.skipped = direction.late = 0
        return notes

    def _skip_gap(self, stream: _Stream, src: tuple[str, int], direction: _Direction, *,
                  missing: bool) -> None:
        """Segments wait for bytes the capture never had (``missing``: it ended) or has not had yet (too
        many wait): jump the gap."""
        first = direction.held[0]
        gap = max(first[0] - direction.position, 0)
        direction.splitter.flush()  # a frame cut by the gap cannot be completed
        direction.reported_junk = direction.splitter.discarded
        if missing:
            direction.missed += gap
        elif gap:
            direction.skipped += gap
            direction.skipped_spans = [*direction.skipped_spans[-(_MAX_HELD - 1):],
                                       (direction.position, direction.position + gap)]
        direction.next_seq = (direction.next_seq + gap) % 2**32  # type: ignore[operator]
        direction.position += gap
        self._release(stream, src, direction, first[2], first[3])

    def _server(self, src: tuple[str, int], dst: tuple[str, int], syn: bool, ack: bool) -> tuple[str, int]:
        if self.port is not None:
            if dst[1] == self.port:
                return dst
            if src[1] == self.port:
                return src
        if syn:
            return src if ack else dst
        for port in _MODBUS_PORTS:
            if dst[1] == port:
                return dst
            if src[1] == port:
                return src
        return dst if dst[1] <= src[1] else src

    def _tcp_segment(self, linktype: int, data: bytes) -> tuple | None:
        """(source, destination, seq, flags, payload) of a TCP packet; None for anything else."""
        scapy = self.scapy
        layer = scapy.conf.l2types.num2layer.get(linktype)
        if layer is None:
            return None
        try:
            packet = layer(data)
            tcp = packet.getlayer(scapy.TCP)
            if tcp is None:
                return None
            ip = tcp.underlayer
            if isinstance(ip, scapy.IP):
                if ip.frag or ip.flags.MF:
                    return None
                # the IP length ends the segment (Ethernet pads short frames); 0 where the capturing
                # host's network card was left to fill it in (segmentation offload)
                end = ip.len - ip.ihl * 4 if ip.len else None
            elif isinstance(ip, scapy.IPv6):
                end = ip.plen or None
            else:
                return None
            segment = bytes(tcp)
            header = tcp.dataofs * 4
            if header < 20 or header > len(segment):
                return None
            return ((ip.src, tcp.sport), (ip.dst, tcp.dport), tcp.seq, int(tcp.flags),
                    segment[header:end])
        except Exception:  # scapy could not dissect it: not a TCP packet this reader can use
            return None

    def finish(self) -> list[Traffic]:
        """Every frame, in the order of the packets that completed them."""
        frames = list(self.serial_frames)
        for stream in [*self.done, *self.streams.values()]:
            for src, direction in stream.directions.items():
                while direction.held:  # the capture ended with a gap before them: skip it
                    self._skip_gap(stream, src, direction, missing=True)
            modbus = self._is_modbus(stream)
            for src, direction in stream.directions.items():
                self._note_last(stream, src, direction)
            if modbus:
                frames.extend(stream.frames)
        frames.sort(key=lambda item: (item[0], item[1]))
        return [entry for _, _, entry in frames]

    def _note_last(self, stream: _Stream, src: tuple[str, int], direction: _Direction) -> None:
        """Late bytes or gaps after a direction's last frame: its note says so (never silently)."""
        if not (direction.late or direction.skipped or direction.missed):
            return
        mine = "tx" if src == stream.client else "rx"
        for at in range(len(stream.frames) - 1, -1, -1):
            index, order, entry = stream.frames[at]
            if entry.direction == mine:
                notes = [entry.note, *(f"after it: {note}" for note in self._gap_notes(direction))]
                stream.frames[at] = (index, order, Traffic(
                    entry.time, entry.direction, entry.mode, entry.data, source=entry.source,
                    dest=entry.dest, note="; ".join(n for n in notes if n), role=entry.role))
                return

    def _is_modbus(self, stream: _Stream) -> bool:
        if not stream.frames:
            return False
        if self.port is not None:
            return stream.server[1] == self.port
        if stream.server[1] in _MODBUS_PORTS:
            return True
        return all(not d.splitter.discarded and not d.splitter.pending and not d.missed
                   for d in stream.directions.values())


def _seq_offset(seq: int, expected: int) -> int:
    """How far ``seq`` is past ``expected`` in 32-bit sequence space (negative: before it)."""
    return ((seq - expected + 2**31) % 2**32) - 2**31


def _serial_role(data: bytes, mode: str, previous: Traffic | None) -> str | None:
    roles = []
    for role in ("request", "response"):
        try:
            decode_frame(data, mode, role)
        except ModbusError:
            continue
        roles.append(role)
    if len(roles) == 1:
        return roles[0]
    if not roles:
        return None
    if previous is not None and previous.role == "request" and previous.unit not in (0, None):
        entry = Traffic(0.0, "rx", mode, data)
        if entry.unit == previous.unit and (entry.function or 0) & 0x7F == previous.function:
            return "response"
    return "request"


def _label(endpoint: tuple[str, int]) -> str:
    host, port = endpoint
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


# --- Wireshark's view -------------------------------------------------------------------------------------
def tshark(path: str | os.PathLike[str], *options: str, timeout: float = 60.0) -> str | None:
    """What Wireshark's command-line tshark prints for the capture at ``path``; None if tshark is missing.

    The setting that serial captures need (:data:`TSHARK_RTU` or :data:`TSHARK_ASCII`) is added from the
    file's link type; ``options`` go to tshark as they are (``"-V"`` for every field, ``"-Y", "modbus"`` to
    show only Modbus frames, ``"-T", "fields", "-e", "modbus.func_code"`` for one column).  tshark gets
    ``timeout`` seconds; a failure raises :class:`CaptureError` with what tshark said.
    """
    program = shutil.which("tshark")
    if program is None:
        return None
    path = _path(path)
    linktypes = {linktype for _, linktype, _ in _records(path)}
    settings = []
    if LINKTYPE_RTU in linktypes:
        settings += ["-o", TSHARK_RTU, "-o", "mbrtu.crc_verification:TRUE"]
    if LINKTYPE_ASCII in linktypes:
        settings += ["-o", TSHARK_ASCII]
    try:
        result = subprocess.run([program, *settings, "-r", str(path), *options], capture_output=True,
                                text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise CaptureError(f"tshark did not finish reading {path.name} within {timeout} s") from None
    if result.returncode != 0:
        said = " ".join(line for line in result.stderr.splitlines() if "dangerous" not in line)
        raise CaptureError(f"tshark could not read {path.name}: {said.strip()[:300]}")
    return result.stdout


# --- scapy, imported when needed ---------------------------------------------------------------------
class _Scapy:
    """The few scapy names this module uses, imported on first use (scapy takes most of a second)."""

    def __init__(self) -> None:
        with _quiet_scapy():  # scapy takes most of a second: only reading or writing a capture needs it
            from scapy.config import conf
            from scapy.layers.inet import IP, TCP
            if IN_BROWSER:  # scapy's IPv6 layer needs the socket module's IPv6, which Pyodide lacks:
                IPv6 = type("IPv6", (), {})  # a browser reads IPv4 captures only (ours are IPv4)
            else:
                from scapy.layers.inet6 import IPv6
            from scapy.layers.l2 import Ether
            from scapy.packet import Raw
            from scapy.utils import RawPcapReader, RawPcapWriter
        self.conf, self.IP, self.TCP, self.IPv6, self.Ether, self.Raw = conf, IP, TCP, IPv6, Ether, Raw
        self.RawPcapReader, self.RawPcapWriter = RawPcapReader, RawPcapWriter


_SCAPY: _Scapy | None = None


def _scapy() -> _Scapy:
    global _SCAPY
    if _SCAPY is None:
        try:
            _SCAPY = _Scapy()
        except ImportError:  # scapy is a dependency of the package, but a browser's copy carries none
            if IN_BROWSER:
                raise MissingDependencyError(
                    "captures are read and written with scapy, which this copy of the course does not "
                    f"carry (it runs in a web browser): they need a local Python or Binder ({BINDER})"
                ) from None
            raise CaptureError("captures need the scapy package: pip install 'scapy>=2.8,<2.9'") from None
    return _SCAPY


@contextmanager
def _quiet_scapy() -> Any:
    """Keep scapy's own warnings (printed to stderr) out of a notebook: our errors say what went wrong.

    In a browser (Pyodide) scapy also says, as a critical message, that it cannot do I/O there, which
    this module never asks of it (it builds packets and writes and reads files only): quieted too."""
    logger = logging.getLogger("scapy")
    level = logger.level
    logger.setLevel(logging.CRITICAL + 1 if IN_BROWSER else logging.ERROR)
    try:
        yield
    finally:
        logger.setLevel(level)
