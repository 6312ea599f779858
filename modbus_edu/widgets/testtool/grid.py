"""The TestTool's data grid: the chosen function's table, cell edits, writes from a master, dummy data."""

from __future__ import annotations

import ipywidgets as W

from ...datamodel import Table
from ...devices.generators import AutoFill, Uniform, increment_fill, random_fill
from ...errors import ConfigError, ModbusError, shown
from ...values import FORMATS, format_registers, parse_formatted
from ..common import MONO, guarded, parse_bit_list
from .controls import COLUMNS, MAX_CELLS


class GridMixin:
    """The grid of the chosen function's table: show it, edit it, write it to a device, fill it."""

    # =====================================================================================================
    # the data grid
    # =====================================================================================================
    def refresh(self) -> None:
        """Redraw the grid, counters and logs from the tables and logs (called after every exchange)."""
        with self._lock():
            self._render_grid()
            self._render_counters()
            self._render_logs()
        self._render_buttons()
        self._render_status()

    def _grid_texts(self, values: list) -> list[str]:
        if self.table.is_bits:
            return ["1" if v else "0" for v in values]
        return format_registers(values, self.display.value)

    def _render_grid(self) -> None:
        try:
            values = self.values
        except ModbusError as exc:
            self.message.error(exc)
            self.grid.children = []
            self._cells = []
            self._grid_shape = None
            return
        address, n = self.address.value, min(len(values), MAX_CELLS)
        shape = (address, n, self.table.kind)
        if shape != self._grid_shape:
            self._build_grid(address, n)
            self._grid_shape = shape
        texts = self._grid_texts(values)[:n]
        wide = not self.table.is_bits and self.display.value not in FORMATS[:6]
        previous, self._updating = self._updating, True
        try:
            for cell, text in zip(self._cells, texts):
                cell.value = text
                cell.disabled = wide and text in ("", "—")
        finally:
            self._updating = previous
        if not self._write_value_typed and self._cells:
            self._selected_changed()

    def _build_grid(self, address: int, n: int) -> None:
        cells = []
        # the rows never scroll (nor clip) on their own: the grid scrolls them all together, both ways, so
        # that the head stays above its column and a head with no control in it is no scroll box
        row_layout = {"overflow": "visible", "flex": "0 0 auto"}
        rows = [W.HBox([W.HTML(f'<div style="width:70px;{MONO};color:#5c636a">address</div>')] +
                       [W.HTML(f'<div style="width:84px;text-align:center;{MONO};color:#5c636a">+{c}</div>')
                        for c in range(min(COLUMNS, n))], layout=W.Layout(**row_layout))]
        rows[0].add_class("mbe-tt-grid-head")
        for start in range(0, n, COLUMNS):
            row = [W.HTML(f'<div style="width:70px;{MONO}">{address + start}</div>')]
            for i in range(start, min(start + COLUMNS, n)):
                # no room for a label in the grid: the cell's label (read by a screen reader) takes no
                # width on screen, and its tooltip says the same
                name = f"{self.table.kind.replace('_', ' ')[:-1]} at address {address + i}"
                cell = W.Text(continuous_update=False, layout=W.Layout(width="84px"), description=name,
                              style={"description_width": "0px"}, tooltip=name)
                cell.add_class("mbe-tt-cell")
                cell.observe(guarded(self.message, lambda change, i=i: self._cell_edited(i, change)),
                             names="value")
                cells.append(cell)
                row.append(cell)
            rows.append(W.HBox(row, layout=W.Layout(**row_layout)))
        more = len(self.table.read(address, self.length.value)) - n if self.length.value > n else 0
        if more:
            rows.append(W.HTML(f"<i>... and {more} more (the grid shows the first {MAX_CELLS})</i>"))
        self._cells = cells
        self.grid.children = rows

    def _cell_edited(self, index: int, change: dict) -> None:
        if self._updating:
            return
        address = self.address.value + index
        self.set_cell(address, change["new"])

    def set_cell(self, address: int, text: str | int) -> bool:
        """Put a value into the grid's table at ``address``, as typed in the current display format.

        A wide format (say ``float32_ABCD``) writes all the registers of the value.  A slave serves the
        new value at once; a master keeps it for *write cell* / *write cells*.  Returns False (and
        says why under the grid, beside the cells and the write fields) when the text does not fit.
        """
        table = self.table
        try:
            if table.is_bits:
                bits = parse_bit_list(str(text), f"cell {address}")
                if len(bits) != 1:
                    raise ConfigError(f"cell {address}: one bit (1 or 0), got {shown(text)}")
                new: list = bits
            else:
                new = parse_formatted(str(text), self.display.value) if not isinstance(text, int) \
                    else parse_formatted(str(text), "unsigned")
            with self._lock():
                table.write(address, new)
        except ModbusError as exc:
            self.grid_message.error(exc)  # under the grid, once (not also on the header's line)
            self._render_grid()
            return False
        previous, self._updating = self._updating, True
        try:
            self.selected.value = address
        finally:
            self._updating = previous
        self._selected_changed()
        self._render_grid()
        self.grid_message.clear()
        self.message.show(f"cell {address} = {text}", "info")
        return True

    def _write_value_edited(self) -> None:
        if not self._updating:
            self._write_value_typed = True

    def _selected_changed(self) -> None:
        """Show the selected cell's value in the write box (the robot test-tool paper: row and column in a
        text box)."""
        self._write_value_typed = False
        address = self.selected.value
        try:
            values = self.table.read(address, 4)
        except ModbusError:
            try:
                values = self.table.read(address, 1)
            except ModbusError as exc:
                self.message.error(exc)
                return
        previous, self._updating = self._updating, True
        try:
            self.write_value.value = self._grid_texts(values)[0] or ""
        finally:
            self._updating = previous

    # -- writes (master) -----------------------------------------------------------------------------------
    def _writable_table(self) -> Table:
        table = self.table
        if not table.writable:
            raise ConfigError(f"a master cannot write the {table.kind.replace('_', ' ')}: choose a function "
                              f"that reaches the coils (1, 5, 15) or the holding registers (3, 6, 16)")
        return table

    def write_cell(self, address: int | None = None, value: str | int | None = None) -> bool:
        """Write one cell to the device: FC06 for a register (FC16 for a 32/64-bit display format, whose
        value spans several registers), FC05 for a coil.  Defaults: the selected cell and its value."""
        if not self._check_master():
            return False
        try:
            table = self._writable_table()
            address = self.selected.value if address is None else address
            text = self.write_value.value if value is None else value
            if not self.set_cell(address, text):
                return False
            unit = self.unit.value
            assert self.master is not None
            if table.is_bits:
                self.master.write_single_coil(unit, address, table[address])
                what = f"FC05: coil {address} = {'ON' if table[address] else 'OFF'}"
            else:
                regs = parse_formatted(str(text), self.display.value) if not isinstance(text, int) else [text]
                if len(regs) == 1:
                    self.master.write_single_register(unit, address, regs[0])
                    what = f"FC06: register {address} = {regs[0]}"
                else:
                    self.master.write_multiple_registers(unit, address, regs)
                    what = (f"FC16 (a {self.display.value} value takes {len(regs)} registers): "
                            f"address {address}")
        except ModbusError as exc:
            self._note_outcome(exc)
            self._after_exchange()
            return False
        self._note_outcome(None)
        self.message.show(f"written, {what}", "ok")
        self._after_exchange()
        return True

    def write_cells(self, address: int | None = None, count: int | None = None) -> bool:
        """Write ``count`` cells from ``address`` (default: the selected cell, *cells*) with FC16 (FC15)."""
        if not self._check_master():
            return False
        try:
            table = self._writable_table()
            address = self.selected.value if address is None else address
            count = self.write_count.value if count is None else count
            values = table.read(address, count)
            assert self.master is not None
            if table.is_bits:
                self.master.write_multiple_coils(self.unit.value, address, values)
                what = f"FC15: {count} coils from {address}"
            else:
                self.master.write_multiple_registers(self.unit.value, address, values)
                what = f"FC16: {count} registers from {address}"
        except ModbusError as exc:
            self._note_outcome(exc)
            self._after_exchange()
            return False
        self._note_outcome(None)
        self.message.show(f"written, {what}", "ok")
        self._after_exchange()
        return True

    def _check_master(self) -> bool:
        if not self.is_master:
            self.message.show("only a master (or client) writes to a device; a slave's grid is its data",
                              "warn")
            return False
        if self.master is None:
            self.message.show("not connected: press connect first", "error")
            return False
        return True

    # =====================================================================================================
    # dummy data
    # =====================================================================================================
    def random_fill(self) -> list:
        """Fill the grid (start address, length) with random values (seeded: the same every run)."""
        with self._lock():
            values = random_fill(self.table, self.address.value, self.length.value, self._rng)
        self.refresh()
        self.message.show(f"random fill: {len(values)} values")
        return values

    def fill_increment(self, start: int | None = None, step: int | None = None) -> list:
        """Fill the grid with ``start, start+step, ...`` (without *increment*: ``start`` everywhere)."""
        if start is not None:
            self.fill_start.value = start
        if step is not None:
            self.fill_step.value = step
            self.increment.value = True
        step_value = self.fill_step.value if self.increment.value else 0
        with self._lock():
            values = increment_fill(self.table, self.address.value, self.length.value, self.fill_start.value,
                                    step_value)
        self.refresh()
        self.message.show(f"fill: {len(values)} values from {self.fill_start.value}, step {step_value}")
        return values

    def auto_fill_start(self) -> None:
        """Refresh the grid with random values every *every (s)* seconds of the wire's clock."""
        interval = float(self.auto_interval.value)
        generator = Uniform(seed=self._rng.randrange(2**31), period=interval)
        self._autofill = AutoFill(self.table, self.address.value, self.length.value, generator,
                                  interval=interval, first=self.clock.now)
        with self._lock():
            self._autofill.update(self.clock.now)
        if self.link is None:
            self._start_ticker()
        self.refresh()
        self._render_auto_state()
        self.message.show(f"auto fill: new random values every {interval:g} s", "ok")

    def auto_fill_stop(self) -> None:
        if self._autofill is not None:
            self._autofill.stop()
        self._autofill = None
        self._render_auto_state()
        self.message.show("auto fill stopped")

    def _render_auto_state(self) -> None:
        """Beside the auto fill buttons: whether auto fill runs now."""
        running = self._autofill is not None and self._autofill.running
        state = f"every {float(self.auto_interval.value):g} s" if running else "off"
        css = "mbe-tt-auto-on" if running else "mbe-tt-auto-off"
        self.auto_state.value = f'<span class="{css}">auto fill: {state}</span>'
        self.auto_start_button.disabled = running
        self.auto_stop_button.disabled = not running

    def _length_changed(self) -> None:
        """*cells* (how many a range write sends) follows *length*: the grid shows that many."""
        self.write_count.value = max(self.write_count.min, min(self.length.value, self.write_count.max))

