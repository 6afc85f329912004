"""The exceptions crestline raises for errors of the library (bad arguments are
``ValueError`` or ``TypeError`` raised by the package before the library runs)."""

from typing import Optional


class Error(Exception):
    """An error of crestline; the message names the file or the problem."""


class FileError(Error):
    """A file that cannot be read or written, or whose content is malformed.
    ``path`` is the file when the library knows it."""

    path: Optional[str] = None


class MeshError(Error, ValueError):
    """A mesh that cannot be used: no faces, a non-orientable component, ..."""


class ArgumentError(Error, ValueError):
    """A parameter outside its meaningful range, as the library checks it."""


class StageError(Error):
    """A stage of a computation that failed on this input (e.g. a linear system
    that is not positive definite); ``stage`` names it as progress reports do."""

    stage: Optional[str] = None
