"""The error an expression raises while it runs (the executor adds the source position)."""

from __future__ import annotations


class EvalError(Exception):
    """A runtime error inside an expression: ``kind`` is the finding's kind."""

    def __init__(self, kind: str, message: str):
        super().__init__(message)
        self.kind = kind
        self.message = message
