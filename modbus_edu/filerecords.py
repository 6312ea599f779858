"""The files of a data bank (FC 20 read file record, FC 21 write file record): :class:`FileRecords`.

A file is a numbered list of registers (file 1..65535, record 0..9999, see :mod:`modbus_edu.pdu.files`);
:class:`~modbus_edu.datamodel.DataBank` keeps its files in :attr:`~modbus_edu.datamodel.DataBank.files`.
"""

from __future__ import annotations

from collections.abc import Iterable

from .errors import DataModelError, IllegalAddressError

__all__ = ["FileMemoryError", "FileRecords", "MAX_FILE_REGISTERS"]

#: The most registers all the files of one bank hold together (2 MiB): a write past it is refused.
MAX_FILE_REGISTERS = 1 << 20


class FileMemoryError(DataModelError):
    """The bank's files are full: the slave answers exception 04 (server device failure)."""


class FileRecords(dict):
    """The files of a bank (FC 20 and 21): file number 1..65535 -> its registers, record 0 first.

    It is a dict, so a device can be set up directly: ``bank.files[4] = [0] * 20``.  Reads and writes
    from the wire go through :meth:`read` and :meth:`write`:

    * in a **dense** bank every file 1..65535 and record 0..9999 exists, as every table address does:
      a record nobody wrote reads 0, and a write creates the file (or lengthens it) on first use;
    * in a **sparse** bank only the records of files put here exist; any other is an
      :class:`~modbus_edu.errors.IllegalAddressError` (the slave answers exception 02);
    * all files together hold at most ``limit`` registers (:data:`MAX_FILE_REGISTERS`); a write that
      would need more raises :class:`FileMemoryError`, which the slave answers with exception 04
      (server device failure), as a real device whose memory is full would.
    """

    def __init__(self, sparse: bool = False, limit: int = MAX_FILE_REGISTERS) -> None:
        super().__init__()
        self.sparse = sparse
        self.limit = limit

    def _where(self, file: int, record: int, count: int) -> str:
        return f"file {file} records {record}..{record + count - 1}"

    def read(self, file: int, record: int, count: int) -> list[int]:
        """``count`` registers of ``file`` from ``record`` on."""
        stored = self.get(file)
        if stored is None or record + count > len(stored):
            if self.sparse:
                raise IllegalAddressError(f"{self._where(file, record, count)} do not exist in this device")
            stored = stored or []
            return [*stored[record:record + count], *[0] * (record + count - max(len(stored), record))]
        return list(stored[record:record + count])

    def check_write(self, file: int, record: int, count: int) -> int:
        """How many registers the write would add; raises when it may not happen."""
        stored = self.get(file)
        have = len(stored) if stored is not None else 0
        if stored is not None and record + count <= have:
            return 0
        if self.sparse:
            raise IllegalAddressError(f"{self._where(file, record, count)} do not exist in this device")
        return record + count - have

    def write(self, records: Iterable[tuple[int, int, Iterable[int]]]) -> None:
        """Write every ``(file, record, values)``; all are checked (existence, memory) before any is."""
        records = [(file, record, list(values)) for file, record, values in records]
        growth: dict[int, int] = {}
        for file, record, values in records:
            end = record + len(values)
            growth[file] = max(growth.get(file, 0), end)
            self.check_write(file, record, len(values))
        added = sum(max(0, end - len(self.get(file, ()))) for file, end in growth.items())
        if added:
            used = sum(len(registers) for registers in self.values())
            if used + added > self.limit:
                raise FileMemoryError(
                    f"the files would need {used + added} registers; this device keeps at most {self.limit}"
                )
        for file, record, values in records:
            stored = self.setdefault(file, [])
            if len(stored) < record + len(values):
                stored.extend([0] * (record + len(values) - len(stored)))
            stored[record:record + len(values)] = values
