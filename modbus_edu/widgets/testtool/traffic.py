"""The TestTool's counters, TX/RX lamps, buttons' state and the TX and RX logs."""

from __future__ import annotations

from ...traffic import TrafficLog
from ..common import MONO, esc
from .controls import LOG_LINES


class TrafficMixin:
    """Counters, TX/RX lamps, which buttons are live, and the two logs (each scrolls in its own box)."""

    # =====================================================================================================
    # counters and logs
    # =====================================================================================================
    @property
    def traffic(self) -> TrafficLog:
        """The log shown: the master's (tx = requests sent) or the slave's (rx = requests received)."""
        if self.is_master:
            return self.master.log if self.master is not None else self._empty_log
        return self.slave.log if self.slave is not None else self._empty_log

    def _render_counters(self) -> None:
        chip = ('<span style="display:inline-block;margin-right:14px"><span style="color:#5c636a">{k}</span> '
                '<b class="mbe-tt-count-{c}">{v}</b></span>')
        if self.is_master:
            n = self.counts
            items = [("polls", "polls", n["polls"]), ("valid responses", "valid", n["valid"]),
                     ("timeouts", "timeouts", n["timeouts"]), ("errors", "errors", n["errors"])]
            extra = esc(self.master.stats.summary()) if self.master is not None else ""
        else:
            c = self.slave.counters if self.slave is not None else None
            d = c.as_dict() if c is not None else {}
            items = [(k.replace("_", " "), k, v) for k, v in d.items()]
            extra = ""
            self.request_count.value = (f'<span style="margin-left:10px">request count: '
                                        f'<b class="mbe-tt-request-count">{d.get("requests", 0)}</b></span>')
        html = self._lamps_html() + "".join(chip.format(k=esc(k), c=c, v=v) for k, c, v in items)
        self.counters.value = (f"<div>{html}</div>" +
                               (f'<div style="font-size:0.85em;color:#5c636a">{extra}</div>'
                                if extra else ""))

    def _update_lamps(self) -> None:
        """The robot test-tool paper's TX and RX indicators: lit when a frame went that way since the last
        redraw."""
        log = self.traffic
        if log is not self._lamp_log or len(log) < self._lamp_seen:  # another log, or it was cleared
            self._lamp_log, self._lamp_seen = log, 0
        directions = {log[i].direction for i in range(self._lamp_seen, len(log))}
        self._lamp_seen = len(log)
        self.lamps = {"tx": "tx" in directions, "rx": "rx" in directions}

    def _lamps_html(self) -> str:
        self._update_lamps()
        colours = {"tx": "#9c4a00", "rx": "#2b6e35"}
        # on or off by shape too (a filled or a hollow disc), not by colour alone, and said in the tooltip
        return "".join(
            f'<span class="mbe-tt-lamp-{d}{" mbe-tt-lamp-on" if on else ""}" style="display:inline-block;'
            f'margin-right:12px" title="{d.upper()} lamp {"on" if on else "off"}">'
            f'<span style="color:{colours[d] if on else "#5c636a"};font-size:1.2em">'
            f'{"&#9679;" if on else "&#9675;"}</span> {d.upper()}</span>' for d, on in self.lamps.items())

    def _render_buttons(self) -> None:
        if self.is_master:
            self.start_button.disabled = self._polling or self.master is None
            self.stop_button.disabled = not self._polling
            self.read_button.disabled = self.master is None or self._polling
            single = "FC05" if self.table.is_bits else "FC06"
            many = "FC15" if self.table.is_bits else "FC16"
            self.write_one_button.description = f"write cell ({single})"
            self.write_many_button.description = f"write cells ({many})"
        else:
            self.start_button.disabled = self.connected and self._answering
            self.stop_button.disabled = not (self.connected and self._answering)
            self.read_button.disabled = True

    def _log_html(self, log: TrafficLog, title: str) -> str:
        entries = list(log)[-LOG_LINES:]
        text = TrafficLog(entries).to_text(newest_first=self.newest_on_top.value) if entries else "(empty)"
        # the widget around this HTML is the scroll box (both ways); the text keeps its own width
        return (f'<div style="font-weight:bold;position:sticky;left:0">{esc(title)} ({len(log)})</div>'
                f'<pre style="{MONO};white-space:pre;font-size:0.8em;width:max-content;min-width:100%;'
                f'box-sizing:border-box;margin:0;padding:2px;line-height:1.35em">'
                f'{esc(text)}</pre>')

    def _render_logs(self) -> None:
        log = self.traffic
        needle = self.search.value.strip() or None
        self.tx_log.value = self._log_html(log.search(text=needle, direction="tx"), "TX log (sent)")
        self.rx_log.value = self._log_html(log.search(text=needle, direction="rx"), "RX log (received)")

    def clear_logs(self) -> None:
        """Forget the traffic shown in the TX and RX logs."""
        self.traffic.clear()
        self._render_logs()
        self.message.show("logs cleared")

