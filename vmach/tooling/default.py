"""The stand-in tool (``--default-tool`` / ``default_tool`` in vmach.toml) and the library view
that uses it.

vmach never guesses a tool from its name (``"EM10"`` may be a 10 mm end mill in one shop and
tool 10 in another): a tool the library lacks is an ``unknown_tool`` error, and its moves cut
nothing. A user who wants the stock simulated anyway names one stand-in geometry::

    flat:d=10          flat end mill, Ø10 mm, cutting length 3 × d
    ball:d=6,l=20      ball end mill, Ø6 mm, 20 mm cutting length
    drill:d=6.8        twist drill (118° point)

Every tool the stand-in replaces is then a ``default_tool`` warning at its T block (no longer an
error: the user asked for it), and its shank and holder are not checked (a stand-in has none).
"""

from __future__ import annotations

from dataclasses import dataclass

from vmach.errors import InputError
from vmach.tooling.model import Tool

#: the kinds a stand-in may be (the cutting part only; kinds needing more figures are left out)
KINDS = ("flat", "ball", "drill")


def parse_default_tool(spec: str, where: str = "--default-tool") -> Tool:
    """The stand-in Tool of ``spec`` (``flat:d=10[,l=30]``); InputError for anything else."""
    kind, _, rest = spec.strip().partition(":")
    kind = kind.strip().lower()
    if kind not in KINDS:
        raise InputError(f"{where} {spec!r}: expected KIND:d=DIAMETER[,l=LENGTH] with KIND one of "
                         f"{', '.join(KINDS)} (e.g. flat:d=10)", kind="usage")
    values: dict[str, float] = {}
    for item in filter(None, (x.strip() for x in rest.split(","))):
        key, eq, val = item.partition("=")
        key = key.strip().lower()
        if not eq or key not in ("d", "l") or key in values:
            raise InputError(f"{where} {spec!r}: {item!r} is not d=… or l=… (given once)", kind="usage")
        try:
            values[key] = float(val)
        except ValueError:
            raise InputError(f"{where} {spec!r}: {val!r} is not a number", kind="usage") from None
        if not 0 < values[key] <= 1000:
            raise InputError(f"{where} {spec!r}: {key} must be > 0 and at most 1000 mm", kind="usage")
    if "d" not in values:
        raise InputError(f"{where} {spec!r}: give the diameter, e.g. {kind}:d=10", kind="usage")
    d = values["d"]
    return Tool(name=f"default {spec.strip()}", kind=kind, diameter=d,
                cutting_length=values.get("l", 3.0 * d),
                point_angle=118.0 if kind == "drill" else 180.0)


@dataclass(frozen=True)
class WithDefault:
    """A tool library (or none) that answers with the stand-in for every tool it lacks.

    ``lookup``, ``radius`` and ``path`` as :class:`vmach.tooling.library.ToolLibrary`;
    ``stood_in(name)`` says whether a name gets the stand-in.
    """

    library: object | None
    default: Tool

    @property
    def path(self) -> str:
        return getattr(self.library, "path", "(no tool library)")

    def stood_in(self, tool: str | int) -> bool:
        return self.library is None or self.library.lookup(tool) is None

    def lookup(self, tool: str | int) -> Tool | None:
        found = None if self.library is None else self.library.lookup(tool)
        return self.default if found is None else found

    def radius(self, tool: str | int, d: int) -> float | None:
        if not self.stood_in(tool):
            return self.library.radius(tool, d)
        return self.default.radius if d else None

    def data(self, tool: str | int, d: int) -> dict[str, float | str] | None:
        """The control's tool data of offset D``d`` (as :meth:`ToolLibrary.data`); the stand-in's
        for a tool the library lacks (length 0: the stand-in has no offset of its own)."""
        if not self.stood_in(tool):
            return self.library.data(tool, d)
        radius = self.radius(tool, d)
        if radius is None:
            return None
        return {"name": str(tool), "type": self.default.kind, "length": 0.0, "radius": radius,
                "teeth": self.default.teeth}
