"""What a compiled step sees of the running interpreter.

The steps ``compile``, ``commands`` and ``sandbox`` make are closures over the interpreter that
runs them; they name it by this protocol instead of importing ``interpreter`` (which imports
them), so the dialect's modules import one way only. :class:`interpreter.Interpreter` is the one
implementation.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from interpreters.sinumerik import blocks as b
from interpreters.sinumerik.execute import Machine
from interpreters.sinumerik.expr import Env
from vmach.canon import ControlSpec


class Running(Protocol):
    """The running interpreter: its control, variables, machine state and output, and the
    call stack (``interpreter.Level`` each) with the pending call a step may set."""

    control: ControlSpec
    env: Env
    machine: Machine
    out: list                 # canonical commands (vmach.canon), in order
    stack: list               # interpreter.Level, innermost last
    pending: tuple | None     # the call a block asks for (compile.CALL)
    modal_call: tuple | None  # MCALL of a subprogram: (name, args, source, stack depth)
    ret_to: tuple | None      # RET(target, after, levels, to start): (values, source)
    recorder: Any             # commands.Recorder: commands without geometric effect
    findings: list            # vmach.findings.Finding of the run, in order
    nck: Any                  # nck.Nck: the system variables
    sandbox: Any              # sandbox.Sandbox: the run's in-memory files

    def setter(self, target: b.Target) -> Callable[[Any], None]:
        """A function that writes ``target`` (an R parameter, a variable or an element)."""
        ...

    def jump_target(self, program: b.Program, blk: b.Block, jump: b.Jump) -> Callable[[], int]:
        """A function giving the block index a jump in ``blk`` lands on."""
        ...


class Reading(Protocol):
    """The block parser (``parser.BlockParser``) as the readers of commands and array fills
    (``commands``, ``arrays``) see it: the block's tokens with a cursor, and the parser's own
    readers of the parts they share."""

    g: Any                    # parser.Grammar: the language and the machine's names
    variables: dict           # the names the program has defined so far
    toks: list                # lexer.Token of the block
    pos: int                  # the cursor into toks

    @property
    def tok(self) -> Any:
        """The token at the cursor (lexer.Token)."""
        ...

    def is_op(self, text: str, k: int = 0) -> bool: ...

    def fail(self, kind: str, message: str, col: int | None = None) -> Any:
        """Raise a ProgramError of ``kind`` at ``col`` (the cursor's token by default)."""
        ...

    def expect_op(self, text: str) -> Any: ...

    def describe(self, t: Any) -> str: ...

    def expr(self) -> Any:
        """The expression at the cursor (expr.Node), the cursor moved past it."""
        ...

    def moded_value(self) -> tuple[str | None, Any]: ...

    def arguments(self, loose: bool = False) -> tuple[Any, ...]: ...
