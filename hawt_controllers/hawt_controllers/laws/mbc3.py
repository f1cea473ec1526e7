"""Multi-blade coordinate transformation of a periodic linear model, and its azimuth average (Bir 2008).

G. Bir, "Multi-Blade Coordinate Transformation and its Application to Wind Turbine Analysis",
AIAA 2008-1300 (NREL/CP-500-42553). A turbine linearised at azimuth ψ (of blade 1) and constant rotor
speed Ω [rad/s] gives ẋ = A(ψ) x + B(ψ) u, y = C(ψ) x + D(ψ) u, periodic in ψ, with some channels
blade-wise: a *blade group* of B channels, one per blade, of the same quantity. :func:`mbc3` writes
the model at one azimuth in the non-rotating (Coleman) coordinates; :func:`azimuth_average` averages
such models over azimuths evenly spaced in a revolution to one LTI model (Bir's last step before
eigenanalysis).

Conventions (DESIGN.md §3, as :mod:`hawt_core.rotor.mbc`): blade i = 0..B−1 sits at
ψ_i = ψ + 2π i/B. A blade group q_i is expanded as (Bir's MBC, B >= 3 blades)::

    q_i = q_0 + Σ_{n=1..K} (q_nc cos nψ_i + q_ns sin nψ_i) [+ q_d (−1)^i for even B],
    K = (B − 1)/2 for odd B, (B − 2)/2 for even B,

i.e. q = t(ψ) z with row i of t = [1, cos ψ_i, sin ψ_i, cos 2ψ_i, sin 2ψ_i, …, (−1)^i]: B coordinates
for B blades. Its inverse is t⁻¹ = diag(1/B, 2/B, …, 2/B, 1/B) tᵀ, so q_0, q_nc, q_ns are the mean,
cos_n and sin_n of :func:`hawt_core.rotor.mbc.mbc_forward` of harmonic n. Bir numbers the blades from
1 with (−1)^b; here blade 1 has (−1)^0 = +1, so q_d is minus Bir's q_{B/2}.

States (Bir's "derivative terms"): x = T(ψ) z. A blade group q whose time derivative q̇ is also a
blade group of the states (a declared *rate* pair) is transformed so that the Coleman state is (z, ż)
with ż truly the derivative of z; with t' = dt/dψ, t'' = d²t/dψ² and Ω constant::

    [q]   [ t     0 ] [z]            [ t'     0  ]
    [q̇] = [ Ω t'  t ] [ż],   Ṫ = Ω  [ Ω t''  t' ]

A blade group without a rate partner gets t(ψ) and Ṫ = Ω t'; every other state (rotor speed, tower,
drivetrain) passes through (identity). Inputs and outputs: u = T_u(ψ) û, y = T_y(ψ) ŷ with t(ψ) on
their blade groups and the identity elsewhere. Substituting (Bir's transformed state-space form)::

    ż = T⁻¹ (A T − Ṫ) z + T⁻¹ B T_u û
    ŷ = T_y⁻¹ C T z + T_y⁻¹ D T_u û

Names: the channels of a blade group should differ only in the blade number, e.g. ``flap_1``,
``flap_2``, ``flap_3`` or ``b1_flap``, ``b2_flap``, ``b3_flap``. Their *base name* is the prefix and
suffix they share, joined by ``_`` with separators trimmed (``flap``, ``b_flap``); the transformed
channels are ``<base>_collective``, ``<base>_cos``, ``<base>_sin``, then ``<base>_cos2``,
``<base>_sin2``, … for the higher harmonics of B >= 5, and ``<base>_diff`` for even B. They take the
group's positions in ascending order, in that order; every other channel keeps its name and place.

What is supported, and why
--------------------------
* B >= 3. Two values per group cannot carry a mean and a cos/sin pair at every azimuth (the same
  singularity as :func:`hawt_core.rotor.mbc.check_configuration`).
* Constant rotor speed: Ṫ has no Ω̇ term, as in Bir's MBC of a model linearised at a steady
  operating point.
* One level of derivatives: a group is a rate of at most one displacement group and cannot itself
  have a rate (an acceleration is not a state of a first-order model).
* The azimuth average keeps only the mean of the periodic Coleman-frame matrices: exact for an
  isotropic rotor in uniform inflow (the MBC model is then the same at every azimuth), an
  approximation otherwise (wind shear, tower shadow, unequal blades leave periodic terms).
"""
from __future__ import annotations

import math
import operator
import os
import re
from dataclasses import dataclass
from typing import Sequence, Tuple

import numpy as np
from scipy.signal import StateSpace

from hawt_core.arrays import finite_array

from hawt_core.validation import require_finite
from hawt_core.exceptions import ConfigurationError
from hawt_core.rotor.mbc import blade_azimuths

__all__ = ["LinearModel", "BladeGroups", "coleman_coordinates", "mbc3", "azimuth_average"]

Groups = Tuple[Tuple[int, ...], ...]


@dataclass(frozen=True, eq=False)
class LinearModel:
    """A continuous-time state-space model with named channels: ẋ = A x + B u, y = C x + D u.

    Attributes
    ----------
    a : numpy.ndarray, shape (n_states, n_states)
    b : numpy.ndarray, shape (n_states, n_inputs)
    c : numpy.ndarray, shape (n_outputs, n_states)
    d : numpy.ndarray, shape (n_outputs, n_inputs)
        Stored as read-only float copies.
    states, inputs, outputs : tuple of str
        Unique, non-empty channel names, one per row/column.

    Models compare by identity (``==`` on arrays has no single truth value).

    Raises
    ------
    ConfigurationError
        A ``ValueError`` naming the field at fault: a shape that does not match the names, NaN or
        infinity, an empty or duplicate name.
    """

    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    d: np.ndarray
    states: Tuple[str, ...]
    inputs: Tuple[str, ...]
    outputs: Tuple[str, ...]

    def __post_init__(self) -> None:
        for field in ("states", "inputs", "outputs"):
            object.__setattr__(self, field, _names(field, getattr(self, field)))
        n, m, p = len(self.states), len(self.inputs), len(self.outputs)
        for field, shape in (("a", (n, n)), ("b", (n, m)), ("c", (p, n)), ("d", (p, m))):
            array = np.array(finite_array(field, getattr(self, field), error=ConfigurationError))
            if array.shape != shape:
                raise ConfigurationError(field, f"expected shape {shape} for {n} states, {m} inputs and {p} "
                                                f"outputs, found {array.shape}")
            array.setflags(write=False)
            object.__setattr__(self, field, array)

    def state_space(self) -> StateSpace:
        """The model as a :class:`scipy.signal.StateSpace` (continuous time)."""
        return StateSpace(self.a, self.b, self.c, self.d)

    def modes(self) -> np.ndarray:
        """Natural frequency [Hz] and damping ratio of each mode, sorted by frequency (then damping).

        Returns
        -------
        numpy.ndarray, shape (n_modes, 2)
            One row per complex-conjugate eigenvalue pair and per real eigenvalue λ of A:
            ``(|λ| / 2π, −Re λ / |λ|)``, the convention of MATLAB's ``damp``. A real eigenvalue
            (a first-order lag) reports its corner frequency and damping +1 (stable) or −1 (unstable);
            a zero eigenvalue (a free rotation, an integrator) reports (0, 0).
        """
        eigenvalues = np.linalg.eigvals(self.a)
        poles = eigenvalues[eigenvalues.imag >= 0.0]  # LAPACK returns exact conjugates, real ones with imag 0
        magnitude = np.abs(poles)
        damping = np.divide(-poles.real, magnitude, out=np.zeros_like(magnitude), where=magnitude > 0.0)
        frequency = magnitude / (2.0 * math.pi)
        return np.column_stack((frequency, damping))[np.lexsort((damping, frequency))]


@dataclass(frozen=True)
class BladeGroups:
    """Which channels of a :class:`LinearModel` are blade-wise.

    Attributes
    ----------
    states, inputs, outputs : tuple of tuple of int
        Each group holds B indices into the state (input, output) vector, blade 1 first; all groups
        have the same length B >= 3 and no index is in two groups.
    rates : tuple of (int, int)
        ``(rate group, displacement group)``, indices into ``states``: the rate group is the time
        derivative of the displacement group (module notes). Each group takes part in at most one pair.

    Raises
    ------
    ConfigurationError
        A ``ValueError`` naming the group at fault: no group at all, a group whose length differs from
        the first, B < 3, a repeated or negative index, a rate pair that does not name two distinct
        state groups or reuses one.
    """

    states: Groups = ()
    rates: Tuple[Tuple[int, int], ...] = ()
    inputs: Groups = ()
    outputs: Groups = ()

    def __post_init__(self) -> None:
        for field in ("states", "inputs", "outputs"):
            object.__setattr__(self, field, tuple(_indices(f"{field}[{k}]", group)
                                                  for k, group in enumerate(getattr(self, field))))
        labelled = [(f"{field}[{k}]", group) for field in ("states", "inputs", "outputs")
                    for k, group in enumerate(getattr(self, field))]
        if not labelled:
            raise ConfigurationError("groups", "no blade group: name at least one group of states, inputs or "
                                               "outputs")
        first, n_blades = labelled[0][0], len(labelled[0][1])
        for label, group in labelled:
            if len(group) != n_blades:
                raise ConfigurationError(label, f"expected B={n_blades} indices (the length of {first}), found "
                                                f"{len(group)}: {group}")
        if n_blades < 3:
            raise ConfigurationError("groups", f"MBC needs B >= 3 blades, found groups of {n_blades}: two values "
                                               "cannot carry a mean and a cos/sin pair at every azimuth")
        for field in ("states", "inputs", "outputs"):
            _disjoint(field, getattr(self, field))
        object.__setattr__(self, "rates", tuple(_indices(f"rates[{k}]", pair)
                                                for k, pair in enumerate(self.rates)))
        _check_rates(self.rates, len(self.states))

    @property
    def n_blades(self) -> int:
        """B, the length of every group."""
        return len((self.states + self.inputs + self.outputs)[0])


def coleman_coordinates(n_blades: int) -> Tuple[str, ...]:
    """Suffixes of the B Coleman coordinates of a blade group, in order (module notes).

    Examples
    --------
    >>> coleman_coordinates(3)
    ('collective', 'cos', 'sin')
    >>> coleman_coordinates(6)
    ('collective', 'cos', 'sin', 'cos2', 'sin2', 'diff')
    """
    harmonics = [f"{kind}{'' if n == 1 else n}" for n in range(1, (n_blades - 1) // 2 + 1)
                 for kind in ("cos", "sin")]
    return ("collective", *harmonics) + (("diff",) if n_blades % 2 == 0 else ())


def mbc3(model: LinearModel, azimuth: float, rotor_speed: float, groups: BladeGroups) -> LinearModel:
    """The model linearised at ``azimuth`` in the Coleman frame (Bir 2008; module notes).

    Parameters
    ----------
    model : LinearModel
        A(ψ), B(ψ), C(ψ), D(ψ) in the rotating frame at this azimuth.
    azimuth : float
        ψ, the azimuth of blade 1 [rad].
    rotor_speed : float
        Ω [rad/s], constant.
    groups : BladeGroups
        The blade-wise channels of ``model``.

    Returns
    -------
    LinearModel
        ``T⁻¹ (A T − Ṫ)``, ``T⁻¹ B T_u``, ``T_y⁻¹ C T``, ``T_y⁻¹ D T_u``, with each blade group's
        channels renamed to its Coleman coordinates (``flap_collective``, ``flap_cos``, …).

    Raises
    ------
    ConfigurationError
        A ``ValueError``: a non-finite azimuth or rotor speed, a group index outside the model, blade
        channel names with nothing in common, or transformed names that collide with another channel.

    Examples
    --------
    Pitch of three blades to their root moments, a static gain of 2: collective and cyclic gains are 2.

    >>> model = LinearModel(np.zeros((0, 0)), np.zeros((0, 3)), np.zeros((3, 0)), 2 * np.eye(3), (),
    ...                     ("pitch_1", "pitch_2", "pitch_3"), ("moment_1", "moment_2", "moment_3"))
    >>> coleman = mbc3(model, 0.4, 1.2, BladeGroups(inputs=((0, 1, 2),), outputs=((0, 1, 2),)))
    >>> coleman.outputs
    ('moment_collective', 'moment_cos', 'moment_sin')
    >>> bool(np.allclose(coleman.d, 2 * np.eye(3)))
    True
    """
    psi = require_finite("azimuth", azimuth)
    omega = require_finite("rotor_speed", rotor_speed)
    sizes = {"states": len(model.states), "inputs": len(model.inputs), "outputs": len(model.outputs)}
    for field, size in sizes.items():
        for k, group in enumerate(getattr(groups, field)):
            if max(group) >= size:
                raise ConfigurationError(f"groups.{field}[{k}]", f"index {max(group)} out of range for a model "
                                                                 f"of {size} {field}")
    t, t_prime, t_second = _basis(psi, groups.n_blades)
    transform = _signal_transform(sizes["states"], groups.states, t)
    rate = np.zeros_like(transform)
    for group in groups.states:
        rate[np.ix_(group, sorted(group))] = omega * t_prime
    for rate_group, displacement_group in groups.rates:
        rows, columns = groups.states[rate_group], sorted(groups.states[displacement_group])
        transform[np.ix_(rows, columns)] = omega * t_prime
        rate[np.ix_(rows, columns)] = omega * omega * t_second
    t_u = _signal_transform(sizes["inputs"], groups.inputs, t)
    t_y = _signal_transform(sizes["outputs"], groups.outputs, t)
    suffixes = coleman_coordinates(groups.n_blades)
    return LinearModel(
        a=np.linalg.solve(transform, model.a @ transform - rate),
        b=np.linalg.solve(transform, model.b @ t_u),
        c=np.linalg.solve(t_y, model.c @ transform),
        d=np.linalg.solve(t_y, model.d @ t_u),
        states=_coleman_names("states", model.states, groups.states, suffixes),
        inputs=_coleman_names("inputs", model.inputs, groups.inputs, suffixes),
        outputs=_coleman_names("outputs", model.outputs, groups.outputs, suffixes),
    )


def azimuth_average(models: Sequence[LinearModel]) -> LinearModel:
    """The element-wise mean of A, B, C, D over ``models``: the LTI model of Bir's azimuth average.

    Pass the :func:`mbc3` models at azimuths evenly spaced over one revolution; the mean over them is the
    average over azimuth (module notes).

    Raises
    ------
    ConfigurationError
        A ``ValueError``: no model, or a model whose state, input or output names differ from the first's.
    """
    models = list(models)
    if not models:
        raise ConfigurationError("models", "need at least one model to average")
    first = models[0]
    for k, model in enumerate(models[1:], start=1):
        for field in ("states", "inputs", "outputs"):
            mine, theirs = getattr(model, field), getattr(first, field)
            if mine != theirs:
                raise ConfigurationError(f"models[{k}].{field}", f"expected the names of models[0], {theirs}, "
                                                                 f"found {mine}")
    return LinearModel(*(np.mean([getattr(model, field) for model in models], axis=0) for field in "abcd"),
                       states=first.states, inputs=first.inputs, outputs=first.outputs)


def _names(field: str, names: Sequence[str]) -> Tuple[str, ...]:
    if isinstance(names, str):
        raise ConfigurationError(field, f"expected a sequence of names, found the string {names!r}")
    names = tuple(names)
    for name in names:
        if not isinstance(name, str) or not name:
            raise ConfigurationError(field, f"expected non-empty strings, found {name!r}")
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise ConfigurationError(field, f"duplicate names {duplicates}")
    return names


def _indices(field: str, values: Sequence[int]) -> Tuple[int, ...]:
    try:
        indices = tuple(operator.index(value) for value in values)
    except TypeError:
        raise ConfigurationError(field, f"expected a tuple of integer indices, found {values!r}") from None
    if any(index < 0 for index in indices):
        raise ConfigurationError(field, f"expected indices >= 0, found {indices}")
    return indices


def _disjoint(field: str, groups: Groups) -> None:
    seen = {}
    for k, group in enumerate(groups):
        for index in group:
            if index in seen:
                raise ConfigurationError(f"{field}[{k}]", f"index {index} is already in {field}[{seen[index]}]")
            seen[index] = k


def _check_rates(rates: Tuple[Tuple[int, ...], ...], n_groups: int) -> None:
    used = {}
    for k, pair in enumerate(rates):
        if len(pair) != 2 or pair[0] == pair[1] or max(pair) >= n_groups:
            raise ConfigurationError(f"rates[{k}]", f"expected (rate group, displacement group), two distinct "
                                                    f"indices below {n_groups} (the state groups), found {pair}")
        for group in pair:
            if group in used:
                raise ConfigurationError(f"rates[{k}]", f"state group {group} is already in rates[{used[group]}]")
            used[group] = k


def _basis(azimuth: float, n_blades: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """t(ψ), t'(ψ), t''(ψ), each (B, B): rows blades, columns the Coleman coordinates (module notes)."""
    psi = blade_azimuths(azimuth, n_blades)
    one, zero = np.ones(n_blades), np.zeros(n_blades)
    columns = [(one, zero, zero)]
    for n in range(1, (n_blades - 1) // 2 + 1):
        cos, sin = np.cos(n * psi), np.sin(n * psi)
        columns += [(cos, -n * sin, -n * n * cos), (sin, n * cos, -n * n * sin)]
    if n_blades % 2 == 0:
        columns.append(((-1.0) ** np.arange(n_blades), zero, zero))
    return tuple(np.column_stack(derivative) for derivative in zip(*columns))


def _signal_transform(size: int, groups: Groups, t: np.ndarray) -> np.ndarray:
    """The identity with t on each group: blade rows in group order, coordinate columns in ascending positions."""
    transform = np.eye(size)
    for group in groups:
        transform[np.ix_(group, sorted(group))] = t
    return transform


def _coleman_names(field: str, names: Tuple[str, ...], groups: Groups, suffixes: Tuple[str, ...]) -> Tuple[str, ...]:
    renamed = list(names)
    for k, group in enumerate(groups):
        blade_names = [names[i] for i in group]
        prefix = os.path.commonprefix(blade_names)
        suffix = os.path.commonprefix([name[len(prefix):][::-1] for name in blade_names])[::-1]
        base = "_".join(part for part in (re.sub(r"[\W_]+$", "", prefix), re.sub(r"^[\W_]+", "", suffix)) if part)
        if not base:
            raise ConfigurationError(f"groups.{field}[{k}]", f"the names {blade_names} have nothing in common to name "
                                                             "their Coleman coordinates (use e.g. flap_1, flap_2, …)")
        for position, coordinate in zip(sorted(group), suffixes):
            renamed[position] = f"{base}_{coordinate}"
    return tuple(renamed)
