"""Numeric input checked at the door: one function for every core, with errors that name the argument."""
import math
from typing import Callable, List, Optional, Sequence, Tuple

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["ArrayError", "finite_array", "finite_floats"]


class ArrayError(ValueError):
    """An array argument a core refuses; the message is ``"<name>: <reason>"``."""

    def __init__(self, name: str, reason: str) -> None:
        self.name, self.reason = name, reason
        super().__init__(f"{name}: {reason}")


def finite_array(name: str, values: ArrayLike, *, shape: Optional[Tuple[int, ...]] = None,
                 ndim: Optional[int] = None, columns: str = "blades",
                 error: Callable[[str, str], Exception] = ArrayError) -> np.ndarray:
    """``values`` as a float array, checked for its ``shape`` or ``ndim`` and for NaN and infinities.

    ``columns`` names the second axis in the message of a 2-D check; ``error(name, reason)``
    builds the exception (a core passes its own ValueError subclass).

    Raises
    ------
    ArrayError (or what ``error`` builds)
        ``"pitch: expected shape (3,), found (2,)"``, ``"root_moment_oop: expected 2-D array
        (samples, blades), found shape (5,)"``, ``"pitch: NaN at sample 4"``,
        ``"azimuth: infinite value"`` (a scalar).

    Examples
    --------
    >>> finite_array("x", [1, 2]).tolist()
    [1.0, 2.0]
    >>> finite_array("x", [[0.0, 1.0], [2.0, float("nan")]], ndim=2)
    Traceback (most recent call last):
    ...
    hawt_core.arrays.ArrayError: x: NaN at sample 1
    """
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as cause:
        raise error(name, f"not a numeric array ({cause})") from None
    if shape is not None and array.shape != tuple(shape):
        raise error(name, f"expected shape {tuple(shape)}, found {array.shape}")
    if ndim is not None and array.ndim != ndim:
        expected = "1-D array (samples,)" if ndim == 1 else f"2-D array (samples, {columns})"
        raise error(name, f"expected {expected}, found shape {array.shape}")
    if not np.isfinite(array).all():
        bad = ~np.isfinite(array)
        kind = "NaN" if np.isnan(array.flat[np.flatnonzero(bad)[0]]) else "infinite value"
        raise error(name, kind if array.ndim == 0 else f"{kind} at sample {int(np.argwhere(bad)[0][0])}")
    return array


def finite_floats(name: str, values: Sequence[float], *,
                  error: Callable[[str, str], Exception] = ArrayError) -> List[float]:
    """One sample's few values as plain floats, checked for NaN and infinities like :func:`finite_array`.

    The per-step path of the controllers works on plain floats: on three blades numpy's
    per-call cost is many times the arithmetic.

    Examples
    --------
    >>> finite_floats("moments", (1, 2.5))
    [1.0, 2.5]
    >>> finite_floats("moments", (1.0, float("inf")))
    Traceback (most recent call last):
    ...
    hawt_core.arrays.ArrayError: moments: infinite value at sample 1
    """
    try:
        floats = list(map(float, values.tolist() if isinstance(values, np.ndarray) else values))
    except (TypeError, ValueError) as cause:
        raise error(name, f"not numeric values ({cause})") from None
    if not all(map(math.isfinite, floats)):
        index, value = next((i, v) for i, v in enumerate(floats) if not math.isfinite(v))
        raise error(name, f"{'NaN' if math.isnan(value) else 'infinite value'} at sample {index}")
    return floats
