"""The event bytes of Get Comm Event Log (FC 12), in words.

A serial device logs its last 64 communication events, newest first, one byte each (*Modbus Application
Protocol Specification* V1.1b3, section 6.10).  The byte's top bits say what kind of event it is:

* **receive event** (bit 7 = 1): a message came in; bit 1 communication error, bit 4 character overrun,
  bit 5 the device is in listen-only mode, bit 6 broadcast received (bits 0, 2 and 3 are not used);
* **send event** (bit 7 = 0, bit 6 = 1): the device answered; bit 0 read exception sent (exception
  codes 1-3), bit 1 server abort exception sent (code 4), bit 2 server busy exception sent (codes 5-6),
  bit 3 program NAK exception sent (code 7), bit 4 write timeout error, bit 5 in listen-only mode;
* **0x04**: the device entered listen-only mode;
* **0x00**: the device restarted its communications (FC 8, sub-function 01).

>>> describe_event(0x80)
'message received'
>>> describe_event(0x41)
'response sent: read exception sent (exception 01-03)'
"""

from __future__ import annotations

from .errors import ValueRangeError, shown

__all__ = ["describe_event"]

_RECEIVE_BITS = {1: "communication error", 4: "character overrun", 5: "in listen-only mode",
                 6: "broadcast received"}
_SEND_BITS = {0: "read exception sent (exception 01-03)",
              1: "server abort exception sent (exception 04)",
              2: "server busy exception sent (exception 05-06)",
              3: "program NAK exception sent (exception 07)",
              4: "write timeout error", 5: "in listen-only mode"}


def describe_event(event: int) -> str:
    """One FC 12 event byte in words (see the module's documentation)."""
    if isinstance(event, bool) or not isinstance(event, int) or not 0 <= event <= 0xFF:
        raise ValueRangeError(f"an event is one byte, 0 to 255, got {shown(event)}")
    if event & 0x80:
        kind, bits = "message received", _RECEIVE_BITS
    elif event & 0x40:
        kind, bits = "response sent", _SEND_BITS
    elif event == 0x04:
        return "entered listen-only mode"
    elif event == 0x00:
        return "communications restarted"
    else:
        return f"0x{event:02X}: not an event the specification defines"
    flags = [text for bit, text in bits.items() if event >> bit & 1]
    return kind + (": " + ", ".join(flags) if flags else "")
