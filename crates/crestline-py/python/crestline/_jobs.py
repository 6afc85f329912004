"""The library's jobs as the package calls them: every default and every name
list is read from the library (``DEFAULTS``, ``NAMES``), never restated here. A
keyword argument left at ``None`` takes the library's default."""

import json
from typing import Any, Callable, Dict, Tuple, TypeVar

from . import _crestline

DEFAULTS: Dict[str, Dict[str, Any]] = json.loads(_crestline.defaults())
"""Every job's options with their defaults, by job (``"iso"``, ``"crest_lines"``,
``"crease"``, ``"ridges"``, ``"landmarks"``) and option, as the library has them.
A length relative to the input is ``{"units": x}``: x voxels of an image, or x
mean edge lengths of a mesh; ``{"scales": x}`` is x feature scales (a length the
library takes from the size of the object, not from its sampling)."""

NAMES: Dict[str, Tuple[str, ...]] = {key: tuple(names) for key, names in _crestline.names().items()}
"""The names of every choice (``"estimator"``, ``"kind"``, ``"solver"``,
``"curvature"``, ``"family"``, ...), as the library reads them."""

F = TypeVar("F", bound=Callable[..., Any])


def options(**given: Any) -> str:
    """The options given (those not None) as the JSON the library reads."""
    return json.dumps({name: value for name, value in given.items() if value is not None})


def describe(value: Any, unit: str) -> str:
    """A default as the documentation says it: ``{"units": 3}`` is "3 voxels" (for
    ``unit`` "voxel")."""
    if isinstance(value, dict) and set(value) == {"units"}:
        units = value["units"]
        return f"{units:g} {unit}" + ("" if units == 1 else "s")
    if isinstance(value, dict) and set(value) == {"scales"}:
        scales = value["scales"]
        return f"{scales:g} feature scale" + ("" if scales == 1 else "s")
    if value is None:
        return "none"
    return repr(value)


def documented(job: str, unit: str = "voxel") -> Callable[[F], F]:
    """Fill the ``{option}`` fields of a function's docstring with the defaults of
    ``job``'s options, lengths relative to the input in ``unit``\\ s."""

    def fill(function: F) -> F:
        values = {name: describe(value, unit) for name, value in DEFAULTS[job].items()}
        function.__doc__ = (function.__doc__ or "").format(**values)
        return function

    return fill


def choice(value: Any, name: str, names_key: str) -> Any:
    """``value`` if it is None or one of the library's names for ``names_key``."""
    known = NAMES[names_key]
    if value is not None and value not in known:
        raise ValueError(f"{name}: expected one of {known}, got {value!r}")
    return value
