"""Input checks shared by the analysis cores: one-line errors naming the argument."""
import numpy as np

from hawt_core.arrays import finite_array

__all__ = ["finite_array", "same_length"]


def same_length(name: str, array: np.ndarray, n_samples: int, reference: str) -> None:
    """Raise ``ValueError`` unless ``array`` has ``n_samples`` rows like ``reference``."""
    if array.shape[0] != n_samples:
        raise ValueError(
            f"{name}: expected {n_samples} samples like {reference}, found {array.shape[0]}"
        )
