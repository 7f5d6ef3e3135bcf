# ruff: noqa: UP031  (printf formats mirror LinuxCNC's C printf calls)
"""LinuxCNC's configuration files as its interpreter reads them: the INI file and the
parameter (``.var``) file.

INI (libnml ``IniFile``): ``[SECTION]`` headers, ``KEY = VALUE`` lines, ``#`` and ``;``
comment lines; the first occurrence of a key wins; section and key names compare as
written in capitals (``#<_ini[vars]x>`` looks up ``[VARS]X``). What the interpreter takes
from ``[RS274NGC]`` is :class:`NgcConfig`.

Parameter file (``Interp::restore_parameters``/``save_parameters``): lines
``NUMBER VALUE`` in increasing order (other lines ignored); numbers 1..5601. Restoring sets
the parameters named and zeroes every other one; saving writes the parameters the file held
and LinuxCNC's required ones (G28/G30 homes, G92, the coordinate systems) as
``NUMBER<TAB>%f``. Lengths are in the machine's units (rs274: inches).
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from interpreters.rs274ngc.diag import NgcError

NUM_PARAMETERS = 5602
_INT_VALUE = re.compile(r"\s*([+-]?\d+)\s+(\S+)")

#: LinuxCNC's _required_parameters: always written to the parameter file
REQUIRED = (*range(5161, 5170), *range(5181, 5190), *range(5210, 5221),
            *(p for base in range(5220, 5400, 20) for p in range(base + 1, base + 11)))

_FEATURE_DEFAULTS = {"INI_VARS": True, "HAL_PIN_VARS": True, "RETAIN_G43": False,
                     "OWORD_NARGS": False, "NO_DOWNCASE_OWORD": False, "OWORD_WARNONLY": False}


@dataclass(frozen=True)
class IniFile:
    """A LinuxCNC INI file: ``sections[SECTION][KEY]`` -> the text after ``=``."""

    path: str
    sections: dict[str, dict[str, str]] = field(default_factory=dict)

    def get(self, section: str, key: str) -> str | None:
        return self.sections.get(section.upper(), {}).get(key.upper())

    def number(self, section: str, key: str) -> float | None:
        """The value as IniFile::Find(double) reads it (a C number), else None."""
        text = self.get(section, key)
        if text is None:
            return None
        try:
            v = float(text)  # the whole value: "25 ; note" is not a number for LinuxCNC
        except ValueError:
            return None
        return v if math.isfinite(v) else None

    def flag(self, section: str, key: str, default: bool) -> bool:
        text = self.get(section, key)
        if text is None:
            return default
        word = text.strip().lower()
        if word in ("1", "true", "yes", "on"):
            return True
        if word in ("0", "false", "no", "off"):
            return False
        return default


def read_ini(path: str | Path) -> IniFile:
    try:
        text = Path(path).read_bytes().decode("utf-8", errors="replace")
    except OSError as exc:
        raise NgcError("ini_unreadable", path=str(path), reason=exc.strerror or str(exc)) from None
    sections: dict[str, dict[str, str]] = {}
    current: dict[str, str] | None = None
    for raw in text.splitlines():
        line = raw.strip()
        if not line or line[0] in "#;":
            continue
        if line.startswith("["):
            end = line.find("]")
            name = line[1:end if end > 0 else None].strip().upper()
            current = sections.setdefault(name, {})
            continue
        if current is None or "=" not in line:
            continue
        key, _, value = line.partition("=")
        current.setdefault(key.strip().upper(), value.strip())
    return IniFile(str(path), sections)


@dataclass(frozen=True)
class NgcConfig:
    """What the interpreter takes from an INI file (rs274ngc_pre.cc ``Interp::init``).

    subroutine_dirs : ``[RS274NGC]SUBROUTINE_PATH`` directories (``:``-separated), relative
        ones against the INI file's directory.
    """

    ini: IniFile
    features: dict[str, bool]
    orient_offset: float = 0.0
    disable_g92_persistence: bool = False
    disable_fanuc_style_sub: bool = False
    subroutine_dirs: tuple[Path, ...] = ()
    remaps: tuple[str, ...] = ()
    arc_tolerance_inch: float | None = None
    arc_tolerance_mm: float | None = None


def ngc_config(ini: IniFile) -> NgcConfig:
    features = {k: ini.flag("RS274NGC", k, d) for k, d in _FEATURE_DEFAULTS.items()}
    base = Path(ini.path).resolve().parent
    dirs = []
    for part in (ini.get("RS274NGC", "SUBROUTINE_PATH") or "").split(":"):
        part = part.strip()
        if part:
            d = (base / part).resolve()
            if d.is_dir():
                dirs.append(d)
    remaps = tuple(v for k, v in ini.sections.get("RS274NGC", {}).items() if k == "REMAP")
    return NgcConfig(
        ini=ini,
        features=features,
        orient_offset=ini.number("RS274NGC", "ORIENT_OFFSET") or 0.0,
        disable_g92_persistence=bool(ini.number("RS274NGC", "DISABLE_G92_PERSISTENCE")),
        disable_fanuc_style_sub=bool(ini.number("RS274NGC", "DISABLE_FANUC_STYLE_SUB")),
        subroutine_dirs=tuple(dirs[:10]),
        remaps=remaps,
        arc_tolerance_inch=ini.number("RS274NGC", "CENTER_ARC_RADIUS_TOLERANCE_INCH"),
        arc_tolerance_mm=ini.number("RS274NGC", "CENTER_ARC_RADIUS_TOLERANCE_MM"),
    )


def read_var_file(path: str | Path) -> dict[int, float]:
    """The parameters a ``.var`` file sets (restore_parameters); a missing file sets none."""
    p = Path(path)
    if not p.exists():
        return {}
    try:
        text = p.read_bytes().decode("utf-8", errors="replace")
    except OSError as exc:
        raise NgcError("var_unreadable", path=str(path), reason=exc.strerror or str(exc)) from None
    values: dict[int, float] = {}
    last = 0
    for number, line in enumerate(text.splitlines(), 1):
        m = _INT_VALUE.match(line)
        if not m:
            continue
        try:
            index, value = int(m.group(1)), float(m.group(2))
        except ValueError:
            continue
        if not 0 < index < NUM_PARAMETERS:
            raise NgcError("var_parameter_range", path=str(path), line=number)
        if index <= last and values:
            raise NgcError("var_out_of_order", path=str(path), line=number)
        values[index] = value
        last = index
    return values


def var_file_text(previous: dict[int, float], params: list[float]) -> str:
    """The file save_parameters writes: the numbers the file held and the required ones."""
    wanted = sorted(set(previous) | set(REQUIRED))
    return "".join("%d\t%f\n" % (k, params[k]) for k in wanted)


def var_copy_path(path: str | Path) -> Path:
    """Where a run writes the parameters it ends with, unless asked to update the file:
    ``NAME.vmach.var`` beside ``NAME.var``."""
    p = Path(path)
    return p.with_name(p.stem + ".vmach" + (p.suffix or ".var"))


def save_var_file(path: str | Path, previous: dict[int, float], params: list[float],
                  update: bool) -> Path:
    """Write the parameters as LinuxCNC saves them at exit: into the copy
    (:func:`var_copy_path`) or, with ``update``, into ``path`` itself, keeping the previous
    file as ``path.bak`` as LinuxCNC does. Written whole, then renamed into place."""
    p = Path(path)
    target = p if update else var_copy_path(p)
    tmp = target.with_name(target.name + ".new")
    tmp.write_text(var_file_text(previous, params), encoding="utf-8")
    if update and p.exists():
        bak = p.with_name(p.name + ".bak")
        bak.unlink(missing_ok=True)
        os.link(p, bak)
    os.replace(tmp, target)
    return target
