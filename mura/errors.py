"""The one error type of the spec languages.

Every failure to read a spec — malformed XML, a schema violation, an unknown symbol, a
dangling time-tag reference — is a :class:`SpecError` that names the file, line and column
and says what was expected, so that a user can go straight to the place in their file.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SourceLocation:
    """A place in a spec file: 1-based line and column, ``0`` when unknown."""

    file: str
    line: int = 0
    column: int = 0

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


class SpecError(ValueError):
    """A spec that cannot be read or does not make sense, with where and what.

    ``str(error)`` reads ``FILE:LINE:COL: message``, the form ``mura check`` prints.
    """

    def __init__(self, message: str, where: SourceLocation | None = None) -> None:
        self.message = message
        self.where = where if where is not None else SourceLocation("<input>")
        super().__init__(f"{self.where}: {message}")

    @property
    def file(self) -> str:
        return self.where.file

    @property
    def line(self) -> int:
        return self.where.line

    @property
    def column(self) -> int:
        return self.where.column


class SpecErrors(SpecError):
    """Several independent problems found in one spec, reported together."""

    def __init__(self, errors: list[SpecError]) -> None:
        if not errors:
            raise ValueError("SpecErrors needs at least one error")
        self.errors = tuple(errors)
        first = errors[0]
        super().__init__(first.message, first.where)
        self.args = ("\n".join(str(e) for e in errors),)

    def __str__(self) -> str:
        return "\n".join(str(e) for e in self.errors)
