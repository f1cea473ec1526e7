"""Input checks shared by the analysis cores: one-line errors naming the argument."""
import numpy as np
from numpy.typing import ArrayLike

__all__ = ["finite_array", "same_length"]


def finite_array(name: str, values: ArrayLike, ndim: int, columns: str = "blades") -> np.ndarray:
    """Return ``values`` as a float array of ``ndim`` (1 or 2) dimensions with only finite entries.

    ``columns`` names the second axis in the message of a 2-D check.

    Raises
    ------
    ValueError
        ``"<name>: expected 2-D array (samples, blades), found shape (5,)"`` or
        ``"<name>: NaN at sample 12"`` (likewise for infinities).
    """
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name}: not a numeric array ({error})") from None
    if array.ndim != ndim:
        expected = "1-D array (samples,)" if ndim == 1 else f"2-D array (samples, {columns})"
        raise ValueError(f"{name}: expected {expected}, found shape {array.shape}")
    bad = ~np.isfinite(array)
    if bad.any():
        sample = int(np.argwhere(bad)[0][0])
        kind = "NaN" if np.isnan(array.flat[np.flatnonzero(bad)[0]]) else "infinite value"
        raise ValueError(f"{name}: {kind} at sample {sample}")
    return array


def same_length(name: str, array: np.ndarray, n_samples: int, reference: str) -> None:
    """Raise ``ValueError`` unless ``array`` has ``n_samples`` rows like ``reference``."""
    if array.shape[0] != n_samples:
        raise ValueError(
            f"{name}: expected {n_samples} samples like {reference}, found {array.shape[0]}"
        )
