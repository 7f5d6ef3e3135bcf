"""The control's file commands on an in-memory sandbox that starts empty at every run; vmach
never reads or writes the disk for them (Job planning, "Writing/reading/deleting a file").

    WRITE(err, file, text)                   append one line to ``file`` (created if new)
    READ(err, file, line, count, lines[])    ``count`` lines from line ``line`` (1-based)
    DELETE(err, file)                        remove ``file``
    ISFILE(file)                             TRUE when ``file`` exists (a function)
    FILEDATE / FILETIME / FILESIZE / FILESTAT / FILEINFO(err, file, result)

``err`` gets the control's result code: 0 done, 3 no such file, 4 line outside the file,
10 the sandbox is full (vmach's limit, ``MAX_BYTES``). Every operation is reported once per
file as an ``info`` finding ``file_sandbox``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.expr import EvalError, compile_expr, element

if TYPE_CHECKING:
    from interpreters.sinumerik.running import Running

from vmach.errors import ProgramError
from vmach.source import SourceRef

#: vmach's limit on what a program writes into the sandbox (all files together)
MAX_BYTES = 1_000_000
#: what FILEDATE and FILETIME report (the sandbox has no clock: the same in every run)
DATE, TIME = "01.01.00", "00:00.00"
OK, NO_FILE, BAD_LINE, FULL = 0, 3, 4, 10
#: command -> number of arguments
OPERATIONS = {"WRITE": 3, "READ": 5, "DELETE": 2, "FILEDATE": 3, "FILETIME": 3, "FILESIZE": 3,
              "FILESTAT": 3, "FILEINFO": 3}


class Sandbox:
    """Files by name (upper case, as the control's names): a list of lines each."""

    def __init__(self) -> None:
        self.files: dict[str, list[str]] = {}
        self.size = 0

    def exists(self, name: str) -> bool:
        return _key(name) in self.files

    def write(self, name: str, text: str) -> int:
        if self.size + len(text) + 1 > MAX_BYTES:
            return FULL
        self.files.setdefault(_key(name), []).append(text)
        self.size += len(text) + 1
        return OK

    def read(self, name: str, first: int, count: int) -> tuple[int, list[str]]:
        lines = self.files.get(_key(name))
        if lines is None:
            return NO_FILE, []
        if first < 1 or count < 1 or first + count - 1 > len(lines):
            return BAD_LINE, []
        return OK, lines[first - 1:first - 1 + count]

    def delete(self, name: str) -> int:
        lines = self.files.pop(_key(name), None)
        if lines is None:
            return NO_FILE
        self.size -= sum(len(x) + 1 for x in lines)
        return OK

    def info(self, what: str, name: str) -> tuple[int, object]:
        lines = self.files.get(_key(name))
        if lines is None:
            return NO_FILE, ""
        size = sum(len(x) + 1 for x in lines)
        return OK, {"FILEDATE": DATE, "FILETIME": TIME, "FILESIZE": size, "FILESTAT": "rwx",
                    "FILEINFO": f"rwx {DATE} {TIME} {size}"}[what]


def _key(name: str) -> str:
    return str(name).strip().upper()


def step(it: Running, item: b.Command, src: SourceRef) -> Callable:
    """The step of a file command: acts on the run's sandbox, sets its result variables."""
    want = OPERATIONS[item.name]
    where = src.at(item.col)
    if len(item.args) != want or any(a is None for a in item.args):
        raise ProgramError("syntax", f"{item.name} takes {want} arguments", where)
    err = _setter(it, item.args[0], item.name, where)
    fs = [compile_expr(a, it.env) for a in item.args[1:]]
    box = it.sandbox
    note = it.recorder.note
    name = item.name

    def run(v):
        file = _text(fs[0](), name)
        if name == "WRITE":
            code = box.write(file, _text(fs[1](), name))
        elif name == "DELETE":
            code = box.delete(file)
        elif name == "READ":
            code, lines = box.read(file, int(fs[1]()), int(fs[2]()))
            target = item.args[4]
            array = it.env.vars.get(target.value) if target.op == "var" else None
            if not isinstance(array, list) or len(array) < len(lines):
                raise EvalError("type_error", "READ: the result is a STRING array with room for the lines")
            for i, line in enumerate(lines):
                lst, k = element(array, [i], target.value)
                lst[k] = line
        else:
            code, value = box.info(name, file)
            if code == OK:
                _setter(it, item.args[2], name, where)(value)
        err(code)
        note(f'{name} "{_key(file)}"', "on vmach's in-memory file sandbox, which starts empty (never "
             "the disk)", where, kind="file_sandbox")

    return run


def _setter(it: Running, node, name: str, where: SourceRef) -> Callable:
    if node.op == "var":
        return it.setter(b.Target(name=node.value, index=node.args))
    if node.op == "r" and isinstance(node.value, int):
        return it.setter(b.Target(r=node.value))
    raise ProgramError("syntax", f"{name}: a variable takes its result", where.at(node.col))


def _text(v, name: str) -> str:
    if not isinstance(v, str):
        raise EvalError("type_error", f"{name}: file names and lines are strings, not {v!r}")
    return v
