"""The data a program's selection loads (Programming Guide, "Workpiece directory"): beside
``PART.MPF`` its initialisation programs of the same name, ``PART.TOA`` (tool offsets),
``PART.UFR`` (frames), ``PART.RPA`` (R parameters), ``PART.SEA`` (setting data), ``PART.INI``
(any data) — or, as the control names them, ``_N_PART_TOA`` … — which the control runs when the
program is selected. Read from the program's directory only (archive.data_file makes each a
:class:`archive.DataSection`, run before the program like an archive's ``_INI`` sections).
"""

from __future__ import annotations

import os
from pathlib import Path

from interpreters.sinumerik import archive
from vmach.files import contained, decode_text, read_program_bytes


def selection_data(path: Path, display: str) -> list[tuple[str, archive.DataSection]]:
    """(display, data) of the data files of the program at ``path`` beside it (``PART.TOA``,
    ``_N_PART_RPA`` … for ``PART.MPF``, archive.selection_names): the control loads them when
    the program is selected. Read from the program's directory only."""
    directory = path.resolve().parent
    stem = archive.header(f"%{path.name.replace('.', '_')}")
    name = stem[0] if stem and stem[1] in ("MPF", "SPF") else path.stem.upper()
    try:
        entries = {e.upper(): e for e in os.listdir(directory)}
    except OSError:
        return []
    out = []
    for _kind, names in archive.selection_names(name):
        entry = next((entries[n] for n in names if n in entries), None)
        if entry is None or not contained(directory / entry, directory) or not (directory / entry).is_file():
            continue
        shown = os.path.join(os.path.dirname(display), entry)
        text = decode_text(read_program_bytes(directory / entry, shown))
        out.append((shown, archive.data_file(entry, text)))
    return out
