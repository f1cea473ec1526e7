"""The turbine model: rotor aerodynamics, structure and actuators advanced by a fixed step.

Degrees of freedom
------------------
- rotor azimuth and speed, generator speed, low-speed-shaft torsion (two-inertia drivetrain);
- first flap and first edgewise mode of each blade (tip deflections; ElastoDyn's BldFl1Sh and BldEdgSh), turned by
  the blade's pitch and, as ElastoDyn's twisted shape functions are, by the structural twist: the flap mode along
  cos(theta_f) e_n + sin(theta_f) e_t, the edgewise one along cos(theta_e) e_t - sin(theta_e) e_n, theta = pitch + the
  angle the twist turns the mode's tip deflection (:func:`hawt_plant.modal.twisted_tip_angle`; 7.3 and 9.6 deg for the
  NREL 5 MW). Each mode keeps that direction along its span, and the modes' mass coupling that their different angles
  give (int mu phi_f phi_e sin(theta_e - theta_f), 2.8 % of the geometric mean of their generalized masses for the
  NREL 5 MW, ElastoDyn's from its twisted shapes) is left out; a blade whose definition has no edgewise mode is rigid
  edgewise;
- first fore-aft and side-side tower modes (tower-top displacements);
- a second-order pitch actuator per blade (:mod:`hawt_plant.pitch_actuator`);
- the generator torque follows its command within its rate limit while the generator is on the grid; off it
  (an idling or parked rotor, a grid loss) the torque is 0 at once.

Rotor states (``ModelConfig.rotor``): ``operating``, the default, runs on the commands; ``idling`` and ``parked`` are
a turbine shut down for IEC 61400-1's DLC 6.x: the blades held at feather (the actuator's largest angle), the
generator off the grid, the commands checked but not applied, and for ``parked`` a brake holding the generator (the
high-speed shaft) at rest, so that the rotor moves only by the shaft's torsion. A standing or idling rotor in
storm wind, possibly at a large yaw misalignment, is outside what momentum theory describes: its elements see the
wind without induction (AeroDyn's WakeMod = 0, which Jonkman names with quasi-steady polars for an idling rotor in
high wind with large skew, OpenFAST discussion #2306; the unsteady-airfoil option stays the turbine's). Its blades
are rigid at their deflection of time 0, the tower flexible. Flexible, a feathered rotor in the 50-year wind at
-30 deg of yaw misalignment has a stall-induced blade vibration that grows over 30 s (blade-root flap peak-to-peak in
three 10 s windows: parked 1.0 -> 1.9 -> 3.1 MN m, idling 2.2 -> 5.2 -> 6.1); at 0, 15, 90 and 180 deg the parked
rotor's stays below 0.8 MN m. OpenFAST v5 on the same parked case (70 m/s, -30 deg, no induction, UA_Mod 4) with
ElastoDyn's flexible blades swings blade 1's root 9-11 MN m peak-to-peak, sustained, and without the unsteady airfoil
without bound; with its blades rigid its mean loads are this model's within 3 % (tower-base fore-aft +13 %, README,
extreme wind conditions). A vibration whose size hangs on the dynamic-stall model is not a load this model settles:
the blades of a shut-down rotor stay rigid.

Aerodynamics: blade-element momentum (:mod:`hawt_plant.bem`) on every element of every blade
at its own azimuth, the inflow sampled from the wind field at the element's position (shear,
turbulence and tower shadow are seen by the rotating blade), the element's own motion (flap,
tower) in the relative velocity, its normal turned by the deflected blade's out-of-plane slope as AeroDyn's BEM frame
is (the axial inflow taken and the normal force applied along it: :func:`~hawt_plant.model_step.element_inflow`,
:func:`~hawt_plant.blade_elements.blade_element_loads`), and the induction carried from step to step: a few relaxed
fixed-point iterations per step from the previous step's induction, or Øye's dynamic inflow.

Structure: assumed modes with Kane-style generalized forces. Every blade element's load
(aerodynamic, gravity, and the centrifugal force of the rotor's rotation, which stiffens the modes and, where a
deflection moves the mass off the radius, softens the edgewise one) is projected on the
motion each coordinate gives it; the tower-top rotation of the fore-aft mode nods the rotor (the loads' arms
through the blades' deflections included, as the hub tilt moment has them), the side-side mode translates it, rolls
it (the part about the tilted shaft's vertical axis yaws the rotor; the part about the shaft is the drivetrain's roll
reaction, and twists the shaft through the gearbox that rolls with the nacelle; the rotor and generator speeds stay
inertial, where ElastoDyn's sensors read them relative to the nacelle: they differ by the roll rate). The mass matrix
follows the azimuth and the pitch: the blades' modes couple with the tower and, by their part along e_t, with the
rotor's rotation (the drivetrain's torsion takes the blades' collective edgewise bending with it); each step solves it
by eliminating every blade's modes (their blocks are diagonal) and then the rotor from a 3 x 3 system with the
tower. Blade-root and tower-base moments are force sums over the elements
including the inertial loads of the accelerations of the step.

Frames (DESIGN.md §3): inertial x downwind, z up, y to the left looking downwind, origin at
the tower base; azimuth 0 with blade 1 up, increasing with rotation (clockwise seen from
upwind, i.e. right-handed about the downwind shaft); pitch positive to feather. Blade-root
moments are OpenFAST's RootMyc (out-of-plane, positive bending downwind) and RootMxc
(in-plane, positive in the direction of rotation): about the axes of the coned blade frame,
which does not pitch with the blade.

Time stepping: commands for step k are held over [t_k, t_k+1); loads are evaluated once per
step at the state, the structure and drivetrain advance by semi-implicit (symplectic) Euler
and the pitch actuator by its exact discretization. The step's arithmetic is compiled
(:mod:`hawt_plant.model_step`, :mod:`hawt_plant.blade_elements`); this class holds the constants and the state
and calls the kernels in order.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hawt_plant.bem import (BemBlade, induction_factors, prandtl_loss, rotor_performance, skewed_wake_factor,
                            solve_inflow_angle)
from hawt_plant.blade_elements import MIN_INFLOW, disk_weights
from hawt_plant.compiled import unchecked
from hawt_plant.modal import (BladeMode, blade_edge_mode, blade_modal_properties, hub_centre_moments, polynomial_mode,
                              rotor_inertia, tower_modal_properties)
from hawt_plant.model_step import (FEATURE_BLOCKS, FORCES, LOAD_ROWS, MEASURED, accelerations, acting_torque,
                                   advance, constant_array, element_inflow, loads_and_measurements, measured_loads,
                                   place_elements, skew_geometry, torsion_rate)
from hawt_plant.operating_point import OperatingPoint, baseline_operating_point
from hawt_plant.pitch_actuator import DiscretePitchActuator
from hawt_plant.rotor_state import ROTOR_STATES
from hawt_plant.tower_shadow import TowerShadow
from hawt_plant.tower_drag import TowerDrag
from hawt_plant.turbine import Turbine
from hawt_plant.unsteady_airfoil import UnsteadyAirfoil
from hawt_plant.wind_field import WindChange, WindField

# The step's kernels without the check of their arguments' types (hawt_plant.compiled.unchecked): the model passes them
# only arrays it allocated itself (float64, C-contiguous), the wind's samples made so, and floats.
(accelerations, acting_torque, advance, element_inflow, loads_and_measurements, measured_loads, place_elements,
 skew_geometry, torsion_rate) = map(unchecked, (accelerations, acting_torque, advance, element_inflow,
                                                loads_and_measurements, measured_loads, place_elements, skew_geometry,
                                                torsion_rate))

__all__ = ["STATE_FIELDS", "ModelConfig", "TurbineModel", "TurbineOutput"]

_RESET_ITERATIONS = 4  # fixed-point iterations of the initial equilibrium
_PASSAGE_SAMPLES = 6  # azimuth samples per blade passage for the initial mean loads
_THRUST, _AERO_TORQUE, _SHAFT_TORQUE = (FORCES.index(name) for name in ("thrust", "aero_torque", "shaft_torque"))
_NO_UNSTEADY = (np.zeros((5, 1, 1)), np.zeros((1, 2, 5)), np.zeros((8, 1)))  # blade_element_loads's arrays, unused


@dataclass(frozen=True)
class ModelConfig:
    """Numerical and modelling options of :class:`TurbineModel`.

    Attributes
    ----------
    dt : float
        Time step [s] (default 0.01, the 100 Hz plant rate).
    bem_iterations : int
        Relaxed fixed-point iterations of the induction per step (quasi-steady inflow).
    bem_relaxation : float
        Relaxation factor of each iteration, in (0, 1].
    dynamic_inflow : bool
        Use Øye's dynamic inflow filter instead of the quasi-steady induction.
    tower_shadow : bool
        Apply the tower's potential-flow disturbance to the blade elements.
    torque_disturbance : float
        Amplitude D [N m, high-speed shaft] of a periodic disturbance D sin(psi) added to the generator
        torque acting on the drivetrain, unmeasured (Fratini 2019 R4, a period of one revolution).
    tower_drag : bool
        Aerodynamic drag on the tower in the wind relative to its motion (AeroDyn's TwrAero,
        :class:`hawt_plant.tower_drag.TowerDrag`): tower-base moments and the tower modes' aerodynamic damping.
    skewed_wake : bool
        Correct the axial induction for a skewed wake (Pitt & Peters, as AeroDyn's SkewMod = 2,
        :func:`hawt_plant.bem.skewed_wake_factor`), the skew from the wind at the rotor apex against the
        shaft axis (shaft tilt, turbulence's vertical and lateral components).
    unsteady_airfoil : bool
        Unsteady airfoil aerodynamics: the Hansen-Gaunaa-Madsen dynamic stall model (AeroDyn's UA_Mod = 4,
        :class:`hawt_plant.unsteady_airfoil.UnsteadyAirfoil`) on the elements whose airfoil has unsteady
        parameters, advanced once per step; the other elements, the initial equilibrium and
        :meth:`TurbineModel.continuous_dynamics` use the static polars (the model's states settled there).
    rotor : str
        One of :data:`ROTOR_STATES` (module notes): ``idling`` and ``parked`` hold the blades at feather and rigid
        with the generator off, without induction.
    """

    dt: float = 0.01
    bem_iterations: int = 1
    bem_relaxation: float = 0.5
    dynamic_inflow: bool = False
    tower_shadow: bool = True
    torque_disturbance: float = 0.0
    tower_drag: bool = True
    skewed_wake: bool = False
    unsteady_airfoil: bool = False
    rotor: str = "operating"

    def __post_init__(self) -> None:
        if self.rotor not in ROTOR_STATES:
            raise ValueError(f"rotor: expected one of {', '.join(ROTOR_STATES)}, found {self.rotor!r}")
        if not (math.isfinite(self.dt) and 0.0 < self.dt <= 0.1):
            raise ValueError(f"dt: expected a step in (0, 0.1] s, found {self.dt}")
        if not (isinstance(self.bem_iterations, int) and self.bem_iterations >= 1):
            raise ValueError(f"bem_iterations: expected an integer >= 1, found {self.bem_iterations!r}")
        if not 0.0 < self.bem_relaxation <= 1.0:
            raise ValueError(f"bem_relaxation: expected a value in (0, 1], found {self.bem_relaxation}")
        if not (math.isfinite(self.torque_disturbance) and self.torque_disturbance >= 0.0):
            raise ValueError(f"torque_disturbance: expected a finite amplitude >= 0, found {self.torque_disturbance}")


@dataclass(frozen=True, eq=False)
class TurbineOutput:
    """Measurements of one model step; field names are those of DESIGN.md §5.

    Arrays have one entry per blade, blade 1 first. Units: SI (rad, rad/s, N m, N, m, W).
    ``time`` is the simulation time of the step [s]; ``azimuth`` is wrapped to [0, 2 pi).
    ``root_moment_oop`` / ``root_moment_ip`` are OpenFAST RootMyc / RootMxc: out-of-plane
    (positive bending downwind) and in-plane (positive in the direction of rotation) about
    the axes of the coned blade-root frame, which does not pitch with the blade; aerodynamic,
    gravity and inertial parts included. ``generator_torque`` is the torque applied over the
    step (high-speed shaft), ``rotor_thrust`` and ``aero_torque`` are aerodynamic only,
    ``hub_wind_speed`` is the undisturbed longitudinal wind at the rotor apex. Tower-top
    accelerations and displacements are those of the first modes (positive downwind and to
    the left looking downwind). Hub moments: about the non-rotating shaft axes y_s, z_s at
    the apex (OpenFAST LSSTipMys, LSSTipMzs signs), which are also the main-bearing moments of
    Zalkind & Pao (hub and main bearing at one point); yaw-bearing moments: about the inertial y
    (tilt) and z (yaw) axes at the tower top (OpenFAST YawBrMyp, YawBrMzp, the tower top's small
    rotation neglected); tower-base moments: about y and x at the base (TwrBsMyt, TwrBsMxt).
    ``effective_wind_*``: the blade-effective wind [m/s], the longitudinal wind (shear, tower shadow and
    turbulence included) at 3/4 of the tip radius along each blade, where Selvam et al. (2009, §2.1) let the
    wind act on a blade, in multi-blade coordinates of harmonic 1 (DESIGN.md §3: mean (1/B) Σ u_i, cos
    (2/B) Σ u_i cos ψ_i, sin (2/B) Σ u_i sin ψ_i): the truth beside a wind estimator's (issue 16).
    """

    time: float
    azimuth: float
    rotor_speed: float
    root_moment_oop: np.ndarray
    root_moment_ip: np.ndarray
    pitch: np.ndarray
    generator_speed: float
    generator_torque: float
    electrical_power: float
    aero_torque: float
    rotor_thrust: float
    hub_wind_speed: float
    tower_top_fa_accel: float
    tower_top_ss_accel: float
    tower_top_fa_disp: float
    tower_top_ss_disp: float
    hub_tilt_moment: float
    hub_yaw_moment: float
    yaw_bearing_tilt_moment: float
    yaw_bearing_yaw_moment: float
    tower_base_fa_moment: float
    tower_base_ss_moment: float
    effective_wind_mean: float
    effective_wind_cos: float
    effective_wind_sin: float

    @classmethod
    def _filled(cls, **fields) -> "TurbineOutput":
        """An output of every field, for the model's step: the frozen dataclass's ``__init__`` sets each of its 27
        fields through ``object.__setattr__`` (3 us a step, a tenth of the compiled step); this fills the instance's
        dictionary at once. The fields must be all of them (the model's own construction)."""
        output = object.__new__(cls)
        output.__dict__.update(fields)
        return output


STATE_FIELDS = (
    "generator_speed", "generator_torque", "electrical_power", "aero_torque", "rotor_thrust", "hub_wind_speed",
    "tower_top_fa_accel", "tower_top_ss_accel", "tower_top_fa_disp", "tower_top_ss_disp", "hub_tilt_moment",
    "hub_yaw_moment", "tower_base_fa_moment", "tower_base_ss_moment", "yaw_bearing_tilt_moment",
    "yaw_bearing_yaw_moment", "effective_wind_mean", "effective_wind_cos", "effective_wind_sin",
)
"""The :class:`TurbineOutput` fields that the plant publishes on ``plant/state`` (``TurbineState``)."""


class TurbineModel:
    """A wind turbine in a wind field, advanced one fixed step per call of :meth:`step`.

    Parameters
    ----------
    turbine : Turbine
        The turbine definition (e.g. :func:`hawt_plant.turbine.nrel_5mw`).
    wind : WindField
        Inflow; its ``mean_speed`` sets the initial operating point.
    config : ModelConfig, optional
    azimuth : float
        Initial azimuth of blade 1 [rad].

    Notes
    -----
    The model starts at the steady operating point of the wind's mean speed
    (:meth:`reset_to_operating_point` at ``azimuth``). Same inputs give bit-identical outputs.

    Examples
    --------
    >>> from hawt_plant.shear_wind import PowerLawWind
    >>> from hawt_plant.turbine import nrel_5mw
    >>> model = TurbineModel(nrel_5mw(), PowerLawWind(11.4, shear_exponent=0.2))
    >>> first = model.output
    >>> out = model.step(first.pitch, first.generator_torque)
    >>> out.time
    0.01
    """

    def __init__(self, turbine: Turbine, wind: WindField, config: ModelConfig | None = None,
                 azimuth: float = 0.0) -> None:
        self._turbine = turbine
        self._wind = wind
        self._config = config or ModelConfig()
        self._operating = self._config.rotor == "operating"
        self._parked = self._config.rotor == "parked"
        self._disturbance = float(self._config.torque_disturbance)
        self._grid_connected = self._operating
        self._setup_constants()
        self._pitch_actuator = DiscretePitchActuator(turbine.pitch_actuator, self._config.dt)
        self._unsteady = UnsteadyAirfoil(self._bem.polars, turbine.airfoils, turbine.blade_aerodynamics.airfoil,
                                         turbine.blade_aerodynamics.chord, self._b) \
            if self._config.unsteady_airfoil else None
        shadow = TowerShadow.from_tower(turbine.tower, turbine.rotor.downwind) if self._config.tower_shadow else None
        # model_step.element_inflow's shadow arguments: on, downwind, drag coefficient, the outline.
        self._shadow = (True, bool(shadow.downwind), float(shadow.drag_coefficient), *shadow.outline) if shadow \
            is not None else (False, False, 0.0, np.zeros(1), np.zeros(1))
        drag = TowerDrag.from_turbine(turbine) if self._config.tower_drag else None
        b, n = self._b, self._n
        if drag is None:
            self._drag_constants = np.zeros((4, 0))
            self._samples = np.zeros((3, b, n + 1))  # the elements and the apex, a row per blade
        else:
            self._drag_constants = np.vstack((drag.coefficient, drag.fa_shape, drag.ss_shape, drag.lever))
            # The wind is sampled at once at the blade points, a row per blade, and the tower nodes, a last row
            # (padded by repeating its top node; WindChange's per-blade change leaves that row alone).
            nodes = len(drag.elevation)
            self._samples = np.zeros((3, b + 1, max(n + 1, nodes)))
            self._samples[2, b, :nodes] = drag.elevation
            self._samples[2, b, nodes:] = drag.elevation[-1]
        self._drag_shapes = self._drag_constants[1:3]
        self._output: TurbineOutput
        self.reset_to_operating_point(azimuth)

    # ------------------------------------------------------------------ public interface

    @property
    def turbine(self) -> Turbine:
        """The turbine definition."""
        return self._turbine

    @property
    def config(self) -> ModelConfig:
        """The model options."""
        return self._config

    @property
    def number_of_blades(self) -> int:
        """B."""
        return self._b

    @property
    def output(self) -> TurbineOutput:
        """Measurements at the current time (after the last step or reset)."""
        return self._output

    @property
    def operating_point(self) -> OperatingPoint | None:
        """The schedule's operating point at the wind's mean speed (from the last reset); None for an idling or parked
        rotor."""
        return self._operating_point

    @property
    def grid_connected(self) -> bool:
        """Whether the generator is on the grid (its torque follows the command): an operating rotor's until
        :meth:`disconnect_grid`."""
        return self._grid_connected

    def disconnect_grid(self) -> None:
        """The generator loses the grid (a grid loss): its torque is 0 from the next step on, whatever is commanded."""
        self._grid_connected = False

    def reset_to_operating_point(self, azimuth: float = 0.0, *, rotor_speed: float | None = None,
                                 pitch: float | None = None, flap_offset: np.ndarray | None = None,
                                 edge_offset: np.ndarray | None = None,
                                 tower_offset: tuple[float, float] | None = None) -> TurbineOutput:
        """Restart at time 0 in the steady operating point of the wind's mean speed.

        Rotor speed and pitch come from the baseline schedule
        (:func:`~hawt_plant.operating_point.baseline_operating_point`); above rated the pitch
        is refined so that this model's mean power is rated power (unless ``rotor_speed`` or
        ``pitch`` is given). The generator torque is limited to [0, max_torque]. The induction is the
        converged steady BEM solution in the wind at time 0; the generator torque, shaft
        torsion and tower deflections balance the loads averaged over one blade passage, the
        blade deflections the loads at time 0. All rates start at zero. An idling or parked rotor starts
        at feather with the generator off: parked at rest, the brake holding the shaft's torque; idling at the
        speed where the mean aerodynamic and gravity torque is zero (:meth:`_idling_speed`). The grid is connected
        again for an operating rotor.

        Parameters
        ----------
        azimuth : float
            Initial azimuth of blade 1 [rad].
        rotor_speed : float, optional
            Start at this rotor speed [rad/s] (>= 0) instead of the schedule's.
        pitch : float, optional
            Start at this collective pitch [rad] instead of the schedule's.
        flap_offset, edge_offset : array_like, shape (B,), optional
            Added to the equilibrium blade-tip flap and edgewise deflections [m] (free-decay tests; the edgewise
            one needs a blade with an edgewise mode).
        tower_offset : (float, float), optional
            Added to the equilibrium tower-top fore-aft and side-side displacements [m].

        Returns
        -------
        TurbineOutput
            The measurements at time 0.
        """
        if not math.isfinite(azimuth):
            raise ValueError(f"azimuth: expected a finite angle, found {azimuth}")
        if rotor_speed is not None and not (math.isfinite(rotor_speed) and rotor_speed >= 0.0):
            raise ValueError(f"rotor_speed: expected a finite value >= 0 rad/s, found {rotor_speed}")
        actuator = self._turbine.pitch_actuator
        if pitch is not None and not actuator.min_angle <= pitch <= actuator.max_angle:
            raise ValueError(
                f"pitch: expected a value in [{actuator.min_angle}, {actuator.max_angle}] rad, found {pitch}")
        b, n = self._b, self._n
        flap_offset, edge_offset = (self._checked_blade_offset(name, value) for name, value in
                                    (("flap_offset", flap_offset), ("edge_offset", edge_offset)))
        if np.any(edge_offset) and not self._has_edge:
            raise ValueError(f"edge_offset: the turbine {self._turbine.name!r} has no edgewise mode (rigid blades)")
        tower_offset = np.zeros(2) if tower_offset is None else np.asarray(tower_offset, dtype=float)
        if tower_offset.shape != (2,) or not np.all(np.isfinite(tower_offset)):
            raise ValueError(f"tower_offset: expected 2 finite values, found {tower_offset.tolist()}")
        op = baseline_operating_point(self._turbine, self._wind.mean_speed, self._bem) if self._operating else None
        self._operating_point = op
        self._grid_connected = self._operating
        self._step_index = 0
        self._time = 0.0
        self._azimuth = azimuth % (2.0 * math.pi)
        if op is None:
            self._rotor_speed = 0.0 if rotor_speed is None else float(rotor_speed)
            self._pitch = np.full(b, actuator.max_angle if pitch is None else float(pitch))
        else:
            self._rotor_speed = op.rotor_speed if rotor_speed is None else float(rotor_speed)
            self._pitch = np.full(b, op.pitch if pitch is None else float(pitch))
        self._generator_speed = 0.0 if self._parked else self._rotor_speed
        self._torsion = 0.0
        self._pitch_rate = np.zeros(b)
        # Structural coordinates [tower fa, tower ss, flap 1..B, edge 1..B] and their rates; the tower's is a view into
        # them (a blade rigid edgewise keeps its edge coordinates at 0).
        self._displacement = np.zeros(2 + 2 * b)
        self._velocity = np.zeros(2 + 2 * b)
        self._tower = self._displacement[:2]
        self._generator_torque = 0.0
        self._induction = np.zeros((2, b, n))  # axial and tangential induction factors a, a'
        self._inflow_filter = np.zeros((2, 3, b, n))  # Øye's states, axial and tangential (blade_element_loads)
        generator = self._turbine.generator
        target_power = self._turbine.rated_mechanical_power
        refine_pitch = op is not None and pitch is None and rotor_speed is None and op.pitch > actuator.min_angle
        idling = self._config.rotor == "idling" and rotor_speed is None
        for _ in range(_RESET_ITERATIONS):
            if idling:
                self._rotor_speed = self._generator_speed = self._idling_speed()
            shaft, tower_residual = self._passage_mean_loads()
            self._azimuth = azimuth % (2.0 * math.pi)
            if self._grid_connected:
                self._generator_torque = min(max(shaft / self._gearbox_ratio, 0.0), generator.max_torque)
            elif not self._parked:
                shaft = 0.0  # a free generator carries no torque in equilibrium
            self._torsion = shaft / self._torsional_stiffness
            self._tower += tower_residual / self._tower_stiffness
            if refine_pitch:
                correction = self._rated_pitch_correction(shaft, target_power)
                self._pitch[:] = min(max(float(self._pitch[0]) + correction, actuator.min_angle), actuator.max_angle)
            self._solve_steady_induction()
            self._evaluate_loads(update_induction=False)
            modes = self._modes  # the edge coordinates of a blade rigid edgewise stay 0
            self._displacement[2:][modes] += self._mode_residual[modes] / self._mode_stiffness_now[modes]
        self._displacement[2:] += np.concatenate((flap_offset, edge_offset))
        self._tower += tower_offset
        self._sample_inflow()
        self._evaluate_loads(update_induction=False)
        self._output = self._make_output(self._accelerations(self._generator_torque))
        return self._output

    def _checked_blade_offset(self, name: str, offset: np.ndarray | None) -> np.ndarray:
        """A deflection offset per blade [m], zeros if None; refused by ``name`` unless B finite values."""
        b = self._b
        values = np.zeros(b) if offset is None else np.asarray(offset, dtype=float)
        if values.shape != (b,) or not np.all(np.isfinite(values)):
            raise ValueError(f"{name}: expected {b} finite values, found {values.tolist()}")
        return values

    def _solve_steady_induction(self) -> None:
        """Converged steady BEM induction at the current state (Ning 2014); none for an idling or parked rotor."""
        self._sample_inflow()
        if not self._operating:
            return
        bem = self._rotor_bem
        vx, vy = self._inflow
        pitch = self._pitch[:, None]
        phi = solve_inflow_angle(vx, vy, pitch, bem)
        cl, _ = bem.polars.coefficients(phi - pitch - bem.twist)
        loss = prandtl_loss(np.sin(phi), bem)
        self._induction[0], self._induction[1], _, _ = induction_factors(phi, cl, loss, bem.local_solidity)
        # Øye's filter holds BEM's induced velocities, before the skew's correction
        self._inflow_filter[0] = self._induction[0] * np.maximum(vx, MIN_INFLOW)
        self._inflow_filter[1] = self._induction[1] * np.maximum(vy, MIN_INFLOW)
        if self._config.skewed_wake:
            angle = skew_geometry(self._apex_wind, self._trig, self._constants, self._cos_azimuth)
            if angle != 0.0:
                self._induction[0] *= skewed_wake_factor(self._induction[0], angle, self._tip_ratio,
                                                         self._cos_azimuth[:, None])

    def _passage_mean_loads(self) -> tuple[float, np.ndarray]:
        """Shaft torque and tower residual (without the generator torque) averaged over one
        blade passage (2 pi / B of azimuth) in steady induction."""
        start = self._azimuth
        shaft = 0.0
        tower = np.zeros(2)
        for k in range(_PASSAGE_SAMPLES):
            self._azimuth = start + 2.0 * math.pi * k / (_PASSAGE_SAMPLES * self._b)
            self._solve_steady_induction()
            self._evaluate_loads(update_induction=False)
            forces = dict(zip(FORCES, self._forces.tolist()))
            torque = forces["aero_torque"] + forces["gravity_torque"]
            shaft += torque
            # Side-side: the drivetrain's roll reaction in equilibrium is the whole rotor torque.
            roll = self._slope_ss * self._cos_tilt
            tower += (forces["residual_fa"], forces["residual_ss"] + roll * (
                forces["shaft_torque"] * (1.0 - 1.0 / self._gearbox_ratio) - torque))
        return shaft / _PASSAGE_SAMPLES, tower / _PASSAGE_SAMPLES

    def _idling_speed(self) -> float:
        """The rotor speed [rad/s] at which the mean aerodynamic and gravity torque of the rotor, at its pitch and
        without induction, is zero: an idling rotor's equilibrium with the generator off, searched within plus or
        minus the rated rotor speed (a feathered rotor may idle backwards); the end of that range the torque drives
        it to where there is none."""
        def torque(speed: float) -> float:
            self._rotor_speed = speed
            return self._passage_mean_loads()[0]

        from scipy.optimize import brentq  # here: an idling or parked rotor's start only

        start = self._azimuth
        highest = self._turbine.schedule.rated_rotor_speed
        try:
            low, high = torque(-highest), torque(highest)
            if low > 0.0 > high:
                return brentq(torque, -highest, highest, xtol=1e-6)
            if max(low, high) <= 0.0:
                return -highest
            return highest if min(low, high) >= 0.0 else 0.0  # or a torque rising with speed: at rest
        finally:
            self._azimuth = start

    def _rated_pitch_correction(self, shaft_torque: float, target_power: float) -> float:
        """Newton step of the collective pitch towards rated power, slope from steady BEM."""
        speed, pitch, step = self._rotor_speed, float(self._pitch[0]), 1e-3
        wind = self._wind.mean_speed
        slope = (rotor_performance(self._turbine, wind, speed, pitch + step, self._bem).torque
                 - rotor_performance(self._turbine, wind, speed, pitch, self._bem).torque) / step
        return (shaft_torque - target_power / speed) / -slope

    def step(self, pitch_command: np.ndarray, generator_torque_command: float) -> TurbineOutput:
        """Advance one step with the commands held over it.

        Parameters
        ----------
        pitch_command : array_like, shape (B,)
            Pitch angle command of each blade [rad], within the actuator's angle limits.
        generator_torque_command : float
            Generator torque command on the high-speed shaft [N m], within [0, max_torque].

        Returns
        -------
        TurbineOutput
            The measurements at the end of the step.

        Raises
        ------
        ValueError
            Naming the argument: wrong length, NaN or infinite value, or out of range.
        """
        command = self._checked_pitch(pitch_command)
        torque_command = self._checked_torque(generator_torque_command)
        if not self._operating:
            command = self._standstill_pitch
        dt = self._config.dt
        if self._grid_connected:
            limit = self._turbine.generator.max_torque_rate * dt
            self._generator_torque += min(max(torque_command - self._generator_torque, -limit), limit)
        else:
            self._generator_torque = 0.0
        drive = self._drive
        drive[0], drive[1], drive[2], drive[3] = self._rotor_speed, self._generator_speed, self._torsion, self._azimuth
        advance(dt, self._generator_torque, self._disturbance, self._parked, command,
                *self._pitch_actuator.kernel_arrays, self._schur, self._constants, self._modal_matrix,
                self._scaled_residual, self._mode_scale, self._forces, self._acceleration, self._velocity,
                self._displacement, self._pitch, self._pitch_rate, drive)
        self._rotor_speed, self._generator_speed, self._torsion, self._azimuth = drive.tolist()
        self._step_index += 1
        self._time = self._step_index * dt
        self._sample_inflow()
        loads_and_measurements(*self._loads_arguments(True, measure=True))
        self._output = self._output_of(self._acceleration)
        return self._output

    # ------------------------------------------------------------------ continuous dynamics (linearisation)

    def state_names(self) -> tuple[str, ...]:
        """Names of the entries of :meth:`state` (blade i as ``_<i>``, i from 1): rotor and generator speed
        [rad/s], shaft torsion [rad], tower-top fore-aft and side-side displacement [m], flap and edgewise tip
        deflections [m] (edgewise for a blade with the mode), their rates, pitch angle [rad] and pitch rate [rad/s] of
        every blade. The azimuth is not among them: it is the variable a linear model is periodic in."""
        blades = range(1, self._b + 1)
        bases = ("flap", "edge") if self._has_edge else ("flap",)
        return ("rotor_speed", "generator_speed", "shaft_torsion", "tower_fa", "tower_ss",
                *(f"{base}_{i}" for base in bases for i in blades), "tower_fa_rate", "tower_ss_rate",
                *(f"{base}_rate_{i}" for base in bases for i in blades), *(f"pitch_{i}" for i in blades),
                *(f"pitch_rate_{i}" for i in blades))

    def state(self) -> np.ndarray:
        """The model's continuous state now, in the order of :meth:`state_names`."""
        kept = self._structural_states
        return np.concatenate(((self._rotor_speed, self._generator_speed, self._torsion), self._displacement[kept],
                               self._velocity[kept], self._pitch, self._pitch_rate))

    @property
    def _structural_states(self) -> slice:
        """The structural coordinates that are states: the tower's and the modes' (a blade rigid edgewise has no edge
        ones)."""
        return slice(0, 2 + self._modes.stop)

    def continuous_dynamics(self, state: np.ndarray, azimuth: float, pitch_command: np.ndarray,
                            generator_torque: float, wind_change=0.0) -> tuple[np.ndarray, TurbineOutput]:
        """The state's time derivative and the measurements at ``state`` and ``azimuth`` [rad], in continuous
        time with quasi-steady aerodynamics: what :meth:`step` integrates, for linearisation.

        The induction is the converged steady BEM solution at this state (the stepping model carries it
        from step to step instead, so its loads lag by a few steps); the generator torque acts as commanded
        (no rate limit); the pitch actuators follow ``theta'' = w^2 (theta_c - theta) - 2 zeta w theta'``
        without their limits; ``wind_change`` [m/s] is added to the longitudinal wind, everywhere (a float) or
        along each blade (B values: the blade-effective wind). The model is left at this state.
        """
        b = self._b
        values = np.asarray(state, dtype=float)
        if values.shape != (len(self.state_names()),):
            raise ValueError(f"state: expected {len(self.state_names())} values, found shape {values.shape}")
        kept = self._structural_states
        dof = len(self._displacement[kept])
        self._rotor_speed, self._generator_speed, self._torsion = values[:3].tolist()
        self._displacement[kept] = values[3:3 + dof]
        self._velocity[kept] = values[3 + dof:3 + 2 * dof]
        self._pitch = values[3 + 2 * dof:3 + 2 * dof + b].copy()
        self._pitch_rate = values[3 + 2 * dof + b:].copy()
        self._azimuth = float(azimuth)
        self._generator_torque = float(generator_torque)
        wind = self._wind
        if np.any(wind_change):
            self._wind = WindChange(wind, wind_change)
        try:
            self._solve_steady_induction()
            self._evaluate_loads(update_induction=False)
        finally:
            self._wind = wind
        acting = self._acting_torque()
        acceleration = self._accelerations(acting)
        actuator = self._turbine.pitch_actuator
        w, zeta = actuator.natural_frequency, actuator.damping_ratio
        pitch_acceleration = w * w * (np.asarray(pitch_command, dtype=float) - self._pitch) \
            - 2.0 * zeta * w * self._pitch_rate
        kept = self._structural_states
        derivative = np.concatenate(((acceleration[-1], self._generator_acceleration(acting),
                                      torsion_rate(self._rotor_speed, self._generator_speed, self._velocity[1],
                                                   self._constants)), self._velocity[kept],
                                     acceleration[:-1][kept], self._pitch_rate, pitch_acceleration))
        return derivative, self._make_output(acceleration)

    def _acting_torque(self) -> float:
        """The generator torque acting on the drivetrain now (:func:`~hawt_plant.model_step.acting_torque`)."""
        return acting_torque(self._parked, self._generator_torque, self._disturbance, self._azimuth, self._forces,
                             self._constants)

    # ------------------------------------------------------------------ boundary checks

    def _checked_pitch(self, pitch_command: np.ndarray) -> np.ndarray:
        command = np.array(pitch_command, dtype=float)
        if command.shape != (self._b,):
            raise ValueError(f"pitch_command: expected length B={self._b}, found shape {command.shape}")
        values = command.tolist()
        if not all(map(math.isfinite, values)):
            raise ValueError(f"pitch_command: NaN or infinite value in {values}")
        low, high = min(values), max(values)
        p = self._turbine.pitch_actuator
        if low < p.min_angle - 1e-9 or high > p.max_angle + 1e-9:
            raise ValueError(
                f"pitch_command: {command.tolist()} rad outside the actuator range [{p.min_angle}, {p.max_angle}]"
            )
        return command

    def _checked_torque(self, generator_torque_command: float) -> float:
        try:
            torque = float(generator_torque_command)
        except (TypeError, ValueError) as err:
            raise ValueError(
                f"generator_torque_command: expected a number, found {generator_torque_command!r}") from err
        if not math.isfinite(torque):
            raise ValueError(f"generator_torque_command: NaN or infinite value {torque}")
        max_torque = self._turbine.generator.max_torque
        if torque < 0.0 or torque > max_torque * (1.0 + 1e-9):
            raise ValueError(f"generator_torque_command: {torque} N m outside [0, {max_torque}]")
        return torque

    # ------------------------------------------------------------------ constants

    def _setup_constants(self) -> None:
        t = self._turbine
        rotor, aero = t.rotor, t.blade_aerodynamics
        self._b = b = rotor.number_of_blades
        self._n = n = aero.span.size
        self._bem = BemBlade.from_turbine(t)
        self._standstill_pitch = np.full(b, t.pitch_actuator.max_angle)  # feather: an idling or parked rotor's
        self._rotor_bem = self._bem.tiled(b)  # every element of every blade at once, (B, N) arrays
        self._tip_ratio = self._rotor_bem.radius / self._bem.tip_radius
        self._disk_weights = disk_weights(self._tip_ratio)
        half_rho = 0.5 * t.environment.air_density
        g = t.environment.gravity
        self._blade_offsets = 2.0 * math.pi * np.arange(b) / b
        # A downwind rotor's cone, tilt and overhang point away from the tower (turbine module notes).
        side = -1.0 if rotor.downwind else 1.0
        cone, tilt = side * rotor.cone_angle, side * rotor.shaft_tilt
        cb, sb, ct, st = math.cos(cone), math.sin(cone), math.cos(tilt), math.sin(tilt)
        self._cos_tilt = ct
        span = aero.span
        rh = rotor.hub_radius
        s_abs = rh + span
        radius = s_abs * cb  # distance from the shaft axis (deflection neglected)
        # Blade-effective wind: the elements' wind interpolated to 3/4 of the tip radius along the blade.
        self._effective_weights = np.array([np.interp(0.75 * rotor.tip_radius, s_abs, e) for e in np.eye(n)])
        # Dynamic pressure to element load: 1/2 rho c dr, per blade element.
        self._pressure_to_load = np.tile(half_rho * aero.chord * aero.width, (b, 1))
        xa = -side * rotor.overhang * ct  # rotor apex relative to the tower top
        za = t.nacelle.shaft_above_tower_top + side * rotor.overhang * st
        # Blade: lumped element masses for the loads, continuous integrals for the modes.
        blade = blade_modal_properties(t)
        edge_mode = blade_edge_mode(t)
        self._has_edge = edge_mode is not None
        self._modes = slice(0, (2 if self._has_edge else 1) * b)  # the modal coordinates that are states
        length = t.blade_length
        fine = np.linspace(0.0, 1.0, 4001) * length
        density = np.interp(fine, t.blade_structure.span_fraction * length, t.blade_structure.mass_density)
        cumulative = np.concatenate(([0.0], np.cumsum(0.5 * (density[1:] + density[:-1]) * np.diff(fine))))
        edges = np.concatenate(([0.0], np.cumsum(aero.width)))  # each node's stretch of blade
        mass = np.diff(np.interp(np.clip(edges, 0.0, length), fine, cumulative))
        flap_shape, flap_slope, _ = polynomial_mode(t.blade_structure.flap_mode_shape, span / length)
        edge_shape, edge_slope, _ = polynomial_mode(t.blade_structure.edge_mode_shape, span / length) \
            if self._has_edge else (np.zeros(n), np.zeros(n), None)
        # The shapes' slopes d phi / ds at the elements [1/m]: the deflected blade's out-of-plane slope turns the
        # elements' normal in the inflow (model_step.element_inflow).
        self._mode_slopes = np.vstack((flap_slope, edge_slope)) / length
        # Element loads are summed per blade against the span functions f = 1, s (from the root), phi_flap and
        # phi_edge; the load rows (LOAD_ROWS) are the components along e_n, e_t and e_z against them.
        functions = np.vstack((np.ones(n), span, flap_shape, edge_shape))
        self._span_functions = np.ascontiguousarray(functions.T)
        # Positions and velocities of the elements are per blade combinations of 1, s_abs, phi_flap and phi_edge.
        self._element_basis = np.vstack((np.ones(n), s_abs, flap_shape, edge_shape))
        # Mass sums of each span function f: sum m f, sum m f s_abs, sum m f r and against each mode shape.
        sums, nod, radius_sums = functions @ mass, functions @ (mass * s_abs), functions @ (mass * radius)
        flap_sums, edge_sums = functions @ (mass * flap_shape), functions @ (mass * edge_shape)
        mass_radius = float(radius_sums[0])
        mass_moments = hub_centre_moments(t, blade)
        flap_arms = (blade.modal_first_moment, blade.modal_moment_arm + rh * blade.modal_first_moment)
        edge = edge_mode or BladeMode(1.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # rigid: no coupling, never advanced
        edge_arms = (edge.modal_first_moment, edge.modal_moment_arm + rh * edge.modal_first_moment)
        # The structural twist turns each mode's deflection from the pitch's direction (modal.twisted_tip_angle).
        flap_twist, edge_twist = blade.twist_angle, edge.twist_angle
        # The blades' modes as one array [flap 1..B, edge 1..B]: generalized mass, stiffness, centrifugal stiffening,
        # damping; a mode that does not move (the blades of a shut-down rotor, a blade rigid edgewise) has 0 as its
        # 1/sqrt(mass), which takes it out of the mass matrix and gives it no acceleration.
        def per_mode(flap_value: float, edge_value: float) -> np.ndarray:
            return np.repeat((flap_value, edge_value), b)

        # The rotor's rotation moves the blade's mass along e_t, as a mode does by its part along e_t: their
        # coupling (the last row) is that part of int mu phi r ds (r = s_abs cos cone) in the kinetic energy.
        self._mode_constants = np.vstack((
            per_mode(blade.stiffness, edge.stiffness),
            per_mode(blade.centrifugal_stiffness, edge.centrifugal_stiffness),
            per_mode(*(2.0 * m.damping_ratio * math.sqrt(m.stiffness * m.modal_mass) for m in (blade, edge))),
            per_mode(1.0 / math.sqrt(blade.modal_mass) if self._operating else 0.0,
                     1.0 / math.sqrt(edge.modal_mass) if self._operating and self._has_edge else 0.0),
            per_mode(cb * flap_arms[1], cb * edge_arms[1])))
        self._mode_scale = self._mode_constants[3]
        # Drivetrain.
        drivetrain = t.drivetrain
        self._gearbox_ratio = drivetrain.gearbox_ratio
        self._torsional_stiffness = drivetrain.torsional_stiffness
        torsional_damping = drivetrain.torsional_damping
        rotor_spin_inertia = rotor_inertia(t, blade)
        self._generator_inertia = drivetrain.generator_inertia  # high-speed shaft
        hub_inertia = rotor.hub_inertia
        # Tower: generalized masses include the rigid nacelle and hub moving with the tower
        # top (translation and, fore-aft, rotation phi'(H)); the blades enter through the
        # azimuth-dependent terms below.
        nacelle = t.nacelle
        rna_mass = rotor.hub_mass + nacelle.mass + b * blade.mass
        fa = tower_modal_properties(t, "fa", rna_mass)
        ss = tower_modal_properties(t, "ss", rna_mass)
        sfa, sss = fa.top_slope, ss.top_slope
        self._slope_ss = sss
        xn, zn = nacelle.cm_downwind, nacelle.cm_above_tower_top
        gain = 1.0 + sss * za  # side-side motion of the apex per metre of tower-top motion
        u0x, u0z = 1.0 + sfa * za, -sfa * xa  # fore-aft motion of the apex per metre (x, z)
        fa_mass_constant = (
            fa.modal_mass
            + nacelle.mass * ((1.0 + sfa * zn) ** 2 + (sfa * xn) ** 2) + nacelle.yaw_inertia * sfa**2
            + rotor.hub_mass * (u0x**2 + u0z**2) + 0.5 * rotor.hub_inertia * sfa**2
            + b * (u0x**2 + u0z**2) * mass_moments[0]
            + b * sfa**2 * mass_moments[2]
        )
        fa_mass_azimuthal = (2.0 * sfa * mass_moments[1], -(sfa**2) * mass_moments[2])
        ss_mass = (
            ss.modal_mass + nacelle.mass * (1.0 + sss * zn) ** 2 + nacelle.yaw_inertia * sss**2
            + (rotor.hub_mass + b * blade.mass) * gain**2
        )
        fa_gravity_force = g * sfa * (nacelle.mass * xn + rotor.hub_mass * xa)
        self._tower_stiffness = np.array([fa.stiffness, ss.stiffness])
        tower_damping = np.array([fa.damping, ss.damping])
        # Per-blade features, each a linear function of (cos psi_i, sin psi_i, 1): rows of
        # `features @ [cos; sin; 1]`, starting with e_n, e_t, e_z (x, y, z each). Blade unit
        # vectors: radial e_r = cos psi e_zs - sin psi e_ys,
        # tangential (direction of rotation) e_t = -sin psi e_zs - cos psi e_ys, with the shaft
        # x_s = (ct, 0, -st), e_ys = (0, 1, 0), e_zs = (st, 0, ct); blade axis
        # e_z = cb e_r - sb x_s; out-of-plane e_n = cb x_s + sb e_r.
        unit = np.array([
            [sb * st, 0.0, cb * ct], [0.0, -sb, 0.0], [sb * ct, 0.0, -cb * st],
            [0.0, -st, 0.0], [-1.0, 0.0, 0.0], [0.0, -ct, 0.0],
            [cb * st, 0.0, -sb * ct], [0.0, -cb, 0.0], [cb * ct, 0.0, sb * st],
        ])
        e_n, e_t, e_z = unit[0:3], unit[3:6], unit[6:9]
        # Fore-aft motion of a blade point at apex distance s_abs: U0 + s_abs U1, projected:
        # U0 . e = u0x e_x + u0z e_z; U1 . e_n = sfa cos psi, U1 . e_t = -sfa sb sin psi, U1 . e_z = 0.
        c0 = {"t": u0x * e_t[0] + u0z * e_t[2], "z": u0x * e_z[0] + u0z * e_z[2], "n": u0x * e_n[0] + u0z * e_n[2]}
        c1 = {"t": np.array([0.0, -sfa * sb, 0.0]), "z": np.zeros(3), "n": np.array([sfa, 0.0, 0.0])}
        y_part = {"t": gain * e_t[1], "z": gain * e_z[1], "n": gain * e_n[1]}
        # Side-side: the tower top's roll (-sss per metre about x = ct x_s + st e_zs) turns the rotor about the shaft
        # (the drivetrain's reaction carries that part) and yaws it about e_zs: a blade point at apex distance s_abs
        # moves -sss st s_abs (e_zs x e_z), with (e_zs x e_z) . e_n = sin psi, . e_t = sb cos psi, . e_z = 0. (Its
        # generalized mass, (sss st)^2 times the rotor's inertia about e_zs, is under 1e-3 of the mode's: left out.)
        roll = -sss * st
        y1 = {"t": np.array([roll * sb, 0.0, 0.0]), "z": np.zeros(3), "n": np.array([0.0, roll, 0.0])}
        gravity_part = {"t": -g * e_t[2], "z": -g * e_z[2], "n": -g * e_n[2]}
        by_row = [(d, sums[f], nod[f], radius_sums[f]) for d, f in LOAD_ROWS]
        blocks = {
            "basis": unit,
            # Generalized tower forces per load row: the element's load along the motion U0 + s_abs U1 of its
            # point per metre of tower-top motion (arms from the root shifted to the apex).
            "tower_fa": np.array([c0[d] + rh * c1[d] if f == 0 else c1[d] if f == 1 else 0 * c1[d]
                                  for d, f in LOAD_ROWS]),
            "tower_ss": np.array([y_part[d] + rh * y1[d] if f == 0 else y1[d] if f == 1 else 0 * y1[d]
                                  for d, f in LOAD_ROWS]),
            # Each mode's inertial coupling with the tower coordinates, int mu phi (U . e) ds, for a mode along e_n
            # and along e_t (combined with the mode's direction each step): first the parts along cos theta of the
            # flap (e_n) and edgewise (e_t) modes, then those along sin theta (e_t, e_n).
            "coupling": np.array([row for mode_arms, d in ((flap_arms, "n"), (edge_arms, "t"), (flap_arms, "t"),
                                                           (edge_arms, "n"))
                                  for row in (c0[d] * mode_arms[0] + c1[d] * mode_arms[1],
                                              y_part[d] * mode_arms[0] + y1[d] * mode_arms[1])]),
            "inertia_fa": np.array([c0[d] * w + c1[d] * wn for d, w, wn, _ in by_row]),
            "inertia_ss": np.array([y_part[d] * w + y1[d] * wn for d, w, wn, _ in by_row]),
            "fa_mass": np.array([u0x * e_z[2] - u0z * e_z[0], e_z[1]]),
            # Inflow (vx, vy) of blade points per unit tower-top velocity: constant and s_abs
            # parts of minus the speed along e_n, then of the speed along e_t; fore-aft, then side-side.
            "inflow_motion_fa": np.array([-c0["n"], -c1["n"], c0["t"], c1["t"]]),
            "inflow_motion_ss": np.array([-y_part["n"], -y1["n"], y_part["t"], y1["t"]]),
        }
        self._feature_matrix = np.vstack([blocks[name] for name, _ in FEATURE_BLOCKS])
        self._features = np.empty((len(self._feature_matrix), b))  # the feature rows at the blades' azimuths
        self._trig = np.ones((3, b))  # per blade: cos psi, sin psi, 1
        # Load sums without the inertia of the accelerations: gravity, centrifugal loads (radial, along e_r = cb e_z +
        # sb e_n, and along e_t where a deflection moves the mass off the radius), linear in cos psi, sin psi, 1,
        # omega^2 and omega^2 times each mode's deflection along e_t.
        self._load_operator = np.column_stack((
            [gravity_part[d] * w for d, w, _, _ in by_row],
            [sb * r if d == "n" else cb * r if d == "z" else 0.0 for d, _, _, r in by_row],
            [flap_sums[f] if d == "t" else 0.0 for d, f in LOAD_ROWS],
            [edge_sums[f] if d == "t" else 0.0 for d, f in LOAD_ROWS]))
        self._mode_directions = np.empty((4, b))  # flap along e_n and e_t, edge along e_n and e_t, per blade
        self._deflection_parts = np.empty((4, b))  # the deflections along those
        self._apex = np.empty(3)
        # The wind is sampled at the elements and, after each blade's last element, at the
        # rotor apex (s_abs = 0 without deflection), whose wind is the hub wind.
        self._point_basis = np.column_stack((self._element_basis, (1.0, 0.0, 0.0, 0.0)))
        self._element_wind = np.empty((3, b, n))
        self._inflow = np.empty((2, b, n))
        # Inertial load sums of the rotor's acceleration: on every blade's e_t rows.
        self._rotor_inertia_rows = np.array([radius_sums[f] if d == "t" else 0.0 for d, f in LOAD_ROWS])
        # The modes': a mode's acceleration acts on its own blade's e_n and e_t rows by its direction. Columns flap
        # along e_n, flap along e_t, edge along e_n, edge along e_t, against the modes' accelerations times their
        # directions' parts.
        self._mode_inertia = np.column_stack([[weights[f] if row == d else 0.0 for row, f in LOAD_ROWS]
                                              for weights in (flap_sums, edge_sums) for d in ("n", "t")])
        self._induction_bounds = np.empty((2, 2, b, n))  # lower, upper bounds of a, a'
        self._induction_bounds[0] = -1.0
        self._induction_bounds[1] = np.reshape((0.99, 1.0), (2, 1, 1))
        # A node at the tip or the hub keeps AeroDyn's a = 1, a' = 0 there (bem.induction_factors).
        edge = self._rotor_bem.at_ends
        self._induction_bounds[:, 0][:, edge] = 1.0
        self._induction_bounds[:, 1][:, edge] = 0.0
        if not self._operating:
            self._induction_bounds[:] = 0.0  # an idling or parked rotor's elements see the wind without induction
        # What blade_element_loads takes of the blade, in its order, and the blades' load sums it writes.
        bem = self._rotor_bem
        self._twist = bem.twist
        self._blade_constants = (bem.polars.table, *bem.polars.grid_constants, bem.loss_exponents, bem.local_solidity,
                                 self._induction_bounds, self._pressure_to_load, self._span_functions)
        self._aero_sums = np.empty((3, b, len(self._element_basis)))
        self._apex_wind = np.zeros(3)  # the undisturbed wind at the rotor apex (element_inflow)
        self._cos_azimuth = np.zeros(b)  # each blade's from the skewed wake's most downwind azimuth (skew_geometry)
        self._element_normals = np.zeros((2, b, n))  # tan and cos of the deflected blade's slope at the elements
        # What the other kernels write (model_step).
        self._loads = np.empty((len(LOAD_ROWS), b))
        self._mode_stiffness_now, self._mode_residual, self._scaled_residual = (np.empty(2 * b) for _ in range(3))
        self._modal_matrix = np.empty((3, 2 * b))  # the modes' scaled couplings with the tower and the rotor
        self._schur = np.empty(9)
        self._acceleration = np.empty(3 + 2 * b)  # what advance accelerates the state with
        self._drive = np.empty(4)  # rotor and generator speed, torsion and azimuth, for advance
        self._forces = np.zeros(len(FORCES))
        self._drag_loads = np.zeros(4)
        self._root_moments = np.empty((2, b))
        self._measured = np.empty(len(MEASURED))
        self._constants = constant_array(
            apex_x=xa, apex_fa_x=u0x, apex_fa_z=u0z, apex_ss_gain=gain, apex_height=t.tower.height + za,
            tower_height=t.tower.height, cos_cone=cb, sin_cone=sb, cos_tilt=ct, sin_tilt=st, hub_radius=rh, gravity=g,
            mass_radius=mass_radius, torsional_stiffness=self._torsional_stiffness,
            torsional_damping=torsional_damping, gearbox_ratio=self._gearbox_ratio,
            generator_inertia=self._generator_inertia, hub_inertia=hub_inertia,
            rotor_inertia=rotor_spin_inertia, slope_fa=sfa, slope_ss=sss, fa_gravity_force=fa_gravity_force,
            fa_mass_constant=fa_mass_constant, fa_mass_linear=fa_mass_azimuthal[0],
            fa_mass_quadratic=fa_mass_azimuthal[1], ss_mass=ss_mass, fa_damping=tower_damping[0],
            ss_damping=tower_damping[1], fa_stiffness=fa.stiffness, ss_stiffness=ss.stiffness,
            base_height=t.tower.base_height, fa_base_shape=fa.base_shape, ss_base_shape=ss.base_shape,
            fa_height_moment=fa.modal_height_moment, ss_height_moment=ss.modal_height_moment,
            fa_gravity_moment=fa.modal_first_moment - fa.base_shape * fa.mass_above_base,
            ss_gravity_moment=ss.modal_first_moment - ss.base_shape * ss.mass_above_base,
            nacelle_mass=nacelle.mass, nacelle_x=xn, nacelle_z=zn, hub_mass=rotor.hub_mass,
            flap_twist=flap_twist, edge_twist=edge_twist)

    # ------------------------------------------------------------------ loads (model_step's kernels)

    def _sample_inflow(self) -> None:
        """Geometry of the elements, the wind there and the inflow (vx, vy) without induction
        (:func:`~hawt_plant.model_step.place_elements`, the wind field, :func:`~hawt_plant.model_step.element_inflow`).
        """
        constants, features, directions = self._constants, self._features, self._mode_directions
        samples, displacement = self._samples, self._displacement
        place_elements(self._azimuth, self._pitch, displacement, constants, self._feature_matrix, self._blade_offsets,
                       self._point_basis, self._drag_shapes, self._trig, features, directions, self._deflection_parts,
                       self._apex, samples)
        velocity = np.ascontiguousarray(self._wind.velocity(self._time, samples[0], samples[1], samples[2]),
                                        dtype=float)
        element_inflow(velocity, samples, displacement, self._velocity, self._rotor_speed, constants, features,
                       directions, self._point_basis, self._deflection_parts, self._mode_slopes, *self._shadow,
                       self._drag_constants, self._element_wind, self._inflow, self._element_normals,
                       self._drag_loads, self._apex_wind)

    def _evaluate_loads(self, update_induction: bool) -> None:
        """Aerodynamic and element loads, generalized forces and the reduced mass matrix
        (:func:`~hawt_plant.model_step.loads_and_measurements` without the measurements: the skewed wake's geometry,
        :func:`~hawt_plant.blade_elements.blade_element_loads`, :func:`~hawt_plant.model_step.generalized_forces`)."""
        loads_and_measurements(*self._loads_arguments(update_induction, measure=False))

    def _loads_arguments(self, update_induction: bool, measure: bool) -> tuple:
        """:func:`~hawt_plant.model_step.loads_and_measurements`' arguments, in its order."""
        config, unsteady = self._config, self._unsteady
        return (update_induction, config.skewed_wake, self._apex_wind, self._cos_azimuth, self._inflow,
                self._induction, self._inflow_filter, self._pitch, self._twist, *self._blade_constants,
                config.bem_iterations, config.bem_relaxation, config.dynamic_inflow, config.dt, self._bem.tip_radius,
                self._tip_ratio, self._disk_weights, unsteady is not None, self._pitch_rate,
                *(_NO_UNSTEADY if unsteady is None else unsteady.kernel_arrays), self._element_normals,
                self._aero_sums, self._trig, self._features, self._mode_directions, self._deflection_parts,
                self._displacement, self._velocity, self._rotor_speed, self._generator_speed, self._torsion,
                self._drag_loads, self._constants, self._load_operator, self._mode_constants, self._loads,
                self._mode_stiffness_now, self._mode_residual, self._modal_matrix, self._scaled_residual, self._schur,
                self._forces, measure, self._parked, self._generator_torque, self._disturbance, self._azimuth,
                self._mode_scale, self._acceleration, self._apex, self._element_wind, self._rotor_inertia_rows,
                self._mode_inertia, self._effective_weights, self._root_moments, self._measured)

    @property
    def _shaft_torque(self) -> float:
        return float(self._forces[_SHAFT_TORQUE])

    def _generator_acceleration(self, generator_torque: float) -> float:
        ratio = self._gearbox_ratio
        return (self._shaft_torque - ratio * generator_torque) / (self._generator_inertia * ratio * ratio)

    def _accelerations(self, generator_torque: float) -> np.ndarray:
        """The accelerations [tower fa, tower ss, flap 1..B, edge 1..B, rotor] with this generator torque
        (:func:`~hawt_plant.model_step.accelerations`)."""
        out = np.empty(3 + 2 * self._b)
        accelerations(self._schur, float(generator_torque), self._constants, self._modal_matrix, self._scaled_residual,
                      self._mode_scale, out)
        return out

    # ------------------------------------------------------------------ outputs

    def _make_output(self, acc: np.ndarray) -> TurbineOutput:
        """The measurements with the accelerations ``acc`` (:func:`~hawt_plant.model_step.measured_loads`)."""
        measured_loads(acc, float(self._acting_torque()), self._trig, self._features, self._mode_directions,
                       self._deflection_parts, self._loads, *self._measurement_arguments())
        return self._output_of(acc)

    def _measurement_arguments(self) -> tuple:
        """:func:`~hawt_plant.model_step.measured_loads`' arguments from ``apex`` on, in its order."""
        return (self._apex, self._displacement, self._element_wind, self._constants, self._rotor_inertia_rows,
                self._mode_inertia, self._effective_weights, self._forces, self._drag_loads, self._root_moments,
                self._measured)

    def _output_of(self, acc: np.ndarray) -> TurbineOutput:
        """The step's output from the model's state, the accelerations ``acc`` and the measured loads
        (:func:`~hawt_plant.model_step.measured_loads`' arrays, written)."""
        root, measured = self._root_moments, self._measured
        (tilt, yaw, bearing_tilt, bearing_yaw, base_fa, base_ss, wind_mean, wind_cos, wind_sin) = measured.tolist()
        x_acc, y_acc = acc[:2].tolist()
        x_top, y_top = self._tower.tolist()
        ratio = self._gearbox_ratio
        generator_speed = ratio * self._generator_speed
        forces = self._forces
        return TurbineOutput._filled(
            time=self._time,
            azimuth=self._azimuth,
            rotor_speed=self._rotor_speed,
            root_moment_oop=root[0].copy(),
            root_moment_ip=root[1].copy(),
            pitch=self._pitch.copy(),
            generator_speed=generator_speed,
            generator_torque=self._generator_torque,
            electrical_power=self._turbine.generator.efficiency * self._generator_torque * generator_speed,
            aero_torque=float(forces[_AERO_TORQUE]),
            rotor_thrust=float(forces[_THRUST]),
            hub_wind_speed=float(self._apex_wind[0]),
            tower_top_fa_accel=x_acc,
            tower_top_ss_accel=y_acc,
            tower_top_fa_disp=x_top,
            tower_top_ss_disp=y_top,
            hub_tilt_moment=tilt,
            hub_yaw_moment=yaw,
            yaw_bearing_tilt_moment=bearing_tilt,
            yaw_bearing_yaw_moment=bearing_yaw,
            tower_base_fa_moment=base_fa,
            tower_base_ss_moment=base_ss,
            effective_wind_mean=wind_mean,
            effective_wind_cos=wind_cos,
            effective_wind_sin=wind_sin,
        )
