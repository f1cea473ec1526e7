"""Sampling a wind field's regular (t, z, y) grid at points: the compiled kernel of
:meth:`hawt_plant.turbulence.TurbulentWind.velocity`.

Apart from :mod:`hawt_plant.turbulence` so that the turbulence module, whose IEC constants the plant's parameter table
reads (:mod:`hawt_plant.plant_setup`), does not import numba: ``hawt launch`` checks a graph's parameters without it.
"""
import numpy as np

from hawt_plant.compiled import njit

__all__ = ["trilinear"]


@njit
def trilinear(t, x, y, z, planes, scale, shift, inv_dt, t_cells, upper, strides, corner_offsets, out):
    """:meth:`~hawt_plant.turbulence.TurbulentWind.velocity` at flat points: the 8 nodes around each point's
    fractional grid index (t_f, z, y), weighted by the products of their weights 1 - w_d, w_d along each axis."""
    index = np.empty(3)
    cell = np.empty(3, dtype=np.intp)
    weights = np.empty((3, 2))
    for k in range(x.size):
        index[0] = x[k] * scale[0] + shift[0] + t * inv_dt
        index[0] = index[0] % t_cells
        index[1] = z[k] * scale[1] + shift[1]
        index[2] = y[k] * scale[2] + shift[2]
        first = 0
        for d in range(3):
            value = np.minimum(np.maximum(index[d], 0.0), upper[d])
            cell[d] = int(value)  # value >= 0: truncation is floor
            weight = value - cell[d]
            weights[d, 0], weights[d, 1] = 1.0 - weight, weight
            first += strides[d] * cell[d]
        for c in range(3):
            out[c, k] = 0.0
        corner = 0
        for it in range(2):
            for iz in range(2):
                for iy in range(2):
                    weight = weights[0, it] * weights[1, iz] * weights[2, iy]
                    node = first + corner_offsets[corner]
                    for c in range(3):
                        out[c, k] += planes[c, node] * weight
                    corner += 1
