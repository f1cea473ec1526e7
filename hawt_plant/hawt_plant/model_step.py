"""The turbine model's step, compiled: the elements' positions and inflow, the load sums and generalized forces, the
reduced mass matrix, the accelerations and the measured loads.

:class:`hawt_plant.model.TurbineModel` holds the physics' description (its module notes: frames, degrees of freedom,
the mass matrix's reduction); these kernels are its per-step arithmetic, written once as loops over the blades and
their elements, so that a step is a handful of compiled calls instead of a hundred numpy calls on arrays of three
(numpy's per-call cost was most of the step). The model calls them in this order each step (0 only there) and for each
state it evaluates (the initial equilibrium, the linearisation):

0. :func:`advance`: the state over the step, the loads held from its start: the structure and the drivetrain by
   semi-implicit Euler, the pitch actuators;
1. :func:`place_elements`: each blade's unit vectors at its azimuth, the modes' directions at its pitch, the rotor apex
   and the points where the wind is sampled (the elements, the apex, the tower's drag nodes);
2. the wind field at those points (a Python object: steady, turbulent, gusts);
3. :func:`element_inflow`: the tower shadow, the inflow (vx, vy) of every element without induction, the tower drag;
4. :func:`loads_and_measurements`: the skewed wake's geometry (:func:`skew_geometry`), the aerodynamic load sums per
   blade (:func:`hawt_plant.blade_elements.blade_element_loads`), then :func:`generalized_forces`: gravity and
   centrifugal load sums, the generalized forces, the reduced mass matrix;
5. :func:`accelerations` and :func:`measured_loads` with the generator torque acting (:func:`acting_torque`): in the
   step, the same call as 4 (``measure``; a call from Python costs about 0.1 us per array it passes, and the two share
   most of theirs); elsewhere one by one, with the accelerations the caller chooses.

Per-blade quantities that are linear in (cos psi_i, sin psi_i, 1) are rows of a ``feature_matrix`` (R, 3), evaluated
once per step into ``features`` (R, B); :data:`FEATURE_BLOCKS` names their rows. The model's scalar constants travel in
one array indexed by :data:`CONSTANTS` (a named tuple of arguments costs numba microseconds to unbox; an array does
not).
"""
from __future__ import annotations

import math

import numpy as np

from hawt_plant.blade_elements import blade_element_loads
from hawt_plant.compiled import njit
from hawt_plant.pitch_actuator import limited_step
from hawt_plant.tower_drag import node_drag
from hawt_plant.tower_shadow import shadow

__all__ = ["CONSTANTS", "FEATURE_BLOCKS", "FORCES", "LOAD_ROWS", "MEASURED", "accelerations", "acting_torque",
           "advance", "advance_structure", "constant_array", "element_inflow", "generalized_forces",
           "loads_and_measurements", "measured_loads", "place_elements", "skew_geometry"]

LOAD_ROWS = (("n", 0), ("n", 1), ("n", 2), ("n", 3), ("t", 0), ("t", 1), ("t", 2), ("t", 3), ("z", 0), ("z", 2), ("z", 3))
"""The per-blade load sums the model keeps, as (direction, span function): the element loads along e_n, e_t and e_z
summed against 1, s (from the root), phi_flap and phi_edge (0..3); the e_n and e_t rows first, four each, as the
aerodynamic sums come."""
_N0, _N1, _N2, _N3, _T0, _T1, _T2, _T3, _Z0, _Z2, _Z3 = range(len(LOAD_ROWS))
_Z_FUNCTIONS = tuple(f for d, f in LOAD_ROWS if d == "z")  # the span functions of the e_z rows

FEATURE_BLOCKS = (("basis", 9), ("tower_fa", len(LOAD_ROWS)), ("tower_ss", len(LOAD_ROWS)), ("coupling", 8),
                  ("inertia_fa", len(LOAD_ROWS)), ("inertia_ss", len(LOAD_ROWS)), ("fa_mass", 2),
                  ("inflow_motion_fa", 4), ("inflow_motion_ss", 4))
"""The blocks of feature rows, in order, with their number of rows: the blade's unit vectors e_n, e_t, e_z (x, y, z
of each); the generalized tower forces per load row (fore-aft, side-side); the modes' inertial couplings with the
tower (flap along e_n, edge along e_t, flap along e_t, edge along e_n; fore-aft and side-side each); the inertial load
sums of the tower's accelerations per load row; the azimuthal parts of the fore-aft mass; the inflow (vx then vy,
constant then along s_abs) per unit tower-top velocity, fore-aft and side-side."""
_starts = np.cumsum([0] + [rows for _, rows in FEATURE_BLOCKS]).tolist()
BASIS, TOWER_FA, TOWER_SS, COUPLING, INERTIA_FA, INERTIA_SS, FA_MASS, MOTION_FA, MOTION_SS = _starts[:-1]

CONSTANTS = (
    "apex_x", "apex_fa_x", "apex_fa_z", "apex_ss_gain", "apex_height", "tower_height", "cos_cone", "sin_cone",
    "cos_tilt", "sin_tilt", "hub_radius", "gravity", "mass_radius", "torsional_stiffness", "torsional_damping",
    "gearbox_ratio", "generator_inertia", "hub_inertia", "rotor_inertia", "slope_fa", "slope_ss", "fa_gravity_force",
    "fa_mass_constant", "fa_mass_linear", "fa_mass_quadratic", "ss_mass", "fa_damping", "ss_damping", "fa_stiffness",
    "ss_stiffness", "base_height", "fa_base_shape", "ss_base_shape", "fa_height_moment", "ss_height_moment",
    "fa_gravity_moment", "ss_gravity_moment", "nacelle_mass", "nacelle_x", "nacelle_z", "hub_mass", "flap_twist",
    "edge_twist",
)
"""The model's scalar constants, in the order of :func:`constant_array`'s array."""
(_APEX_X, _APEX_FA_X, _APEX_FA_Z, _APEX_SS_GAIN, _APEX_HEIGHT, _TOWER_HEIGHT, _COS_CONE, _SIN_CONE, _COS_TILT,
 _SIN_TILT, _HUB_RADIUS, _GRAVITY, _MASS_RADIUS, _TORSIONAL_STIFFNESS, _TORSIONAL_DAMPING, _GEARBOX_RATIO,
 _GENERATOR_INERTIA, _HUB_INERTIA, _ROTOR_INERTIA, _SLOPE_FA, _SLOPE_SS, _FA_GRAVITY_FORCE, _FA_MASS_CONSTANT,
 _FA_MASS_LINEAR, _FA_MASS_QUADRATIC, _SS_MASS, _FA_DAMPING, _SS_DAMPING, _FA_STIFFNESS, _SS_STIFFNESS, _BASE_HEIGHT,
 _FA_BASE_SHAPE, _SS_BASE_SHAPE, _FA_HEIGHT_MOMENT, _SS_HEIGHT_MOMENT, _FA_GRAVITY_MOMENT, _SS_GRAVITY_MOMENT,
 _NACELLE_MASS, _NACELLE_X, _NACELLE_Z, _HUB_MASS, _FLAP_TWIST, _EDGE_TWIST) = range(len(CONSTANTS))

FORCES = ("thrust", "aero_torque", "gravity_torque", "shaft_torque", "residual_fa", "residual_ss")
"""What :func:`generalized_forces` writes besides its arrays, in order: the aerodynamic thrust and torque, the gravity
torque, the shaft torque, and the tower modes' residual forces (without the inertia of the accelerations)."""
_THRUST, _AERO_TORQUE, _GRAVITY_TORQUE, _SHAFT_TORQUE, _RESIDUAL_FA, _RESIDUAL_SS = range(len(FORCES))

MEASURED = ("hub_tilt_moment", "hub_yaw_moment", "yaw_bearing_tilt_moment", "yaw_bearing_yaw_moment",
            "tower_base_fa_moment", "tower_base_ss_moment", "effective_wind_mean", "effective_wind_cos",
            "effective_wind_sin")
"""What :func:`measured_loads` writes besides the blade-root moments, in order (TurbineOutput's fields)."""


def constant_array(**values: float) -> np.ndarray:
    """The constants named by :data:`CONSTANTS` as the kernels' array; every name is needed, no other is taken."""
    missing, unknown = set(CONSTANTS) - set(values), set(values) - set(CONSTANTS)
    if missing or unknown:
        raise ValueError(f"constants: missing {sorted(missing)}, unknown {sorted(unknown)}")
    return np.array([float(values[name]) for name in CONSTANTS])


@njit
def place_elements(azimuth: float, pitch: np.ndarray, displacement: np.ndarray, constants: np.ndarray,
                   feature_matrix: np.ndarray, blade_offsets: np.ndarray, point_basis: np.ndarray,
                   drag_shapes: np.ndarray, trig: np.ndarray, features: np.ndarray, directions: np.ndarray,
                   deflection: np.ndarray, apex: np.ndarray, samples: np.ndarray) -> None:
    """Where the elements are: writes ``trig`` (cos psi_i, sin psi_i, 1), ``features`` (R, B), the modes' directions
    (rows: flap along e_n and e_t, cos theta_f and sin theta_f; edge along e_n and e_t, -sin theta_e and cos theta_e;
    theta the pitch and the mode's angle from the structural twist, ``constants`` flap_twist and edge_twist),
    ``deflection`` (the flap and edgewise tip deflections along those four), ``apex`` (x, y, z) and ``samples``.

    ``displacement``: [tower fa, tower ss, flap 1..B, edge 1..B]; ``point_basis`` (4, N + 1): the span functions
    1, s_abs, phi_flap, phi_edge at the elements and (1, 0, 0, 0) at the apex. Element positions are apex + s_abs e_z +
    w phi_f d_f + v phi_e d_e (model notes); ``samples`` (3, B or B + 1, M) takes them per blade, the apex after each
    blade's elements, and, when ``drag_shapes`` (the fore-aft and side-side mode shapes of the tower's drag nodes,
    (2, K)) has nodes, the nodes' x and y in its last row (padded with the top node; their z is the caller's).
    """
    blades, points = pitch.size, point_basis.shape[1]
    x_top, y_top = displacement[0], displacement[1]
    apex[0] = constants[_APEX_X] + x_top * constants[_APEX_FA_X]
    apex[1] = y_top * constants[_APEX_SS_GAIN]
    apex[2] = constants[_APEX_HEIGHT] + x_top * constants[_APEX_FA_Z]
    for i in range(blades):
        angle = azimuth + blade_offsets[i]
        c, s = math.cos(angle), math.sin(angle)
        trig[0, i], trig[1, i], trig[2, i] = c, s, 1.0
        for r in range(feature_matrix.shape[0]):
            features[r, i] = feature_matrix[r, 0] * c + feature_matrix[r, 1] * s + feature_matrix[r, 2]
        flap_angle, edge_angle = pitch[i] + constants[_FLAP_TWIST], pitch[i] + constants[_EDGE_TWIST]
        directions[0, i], directions[1, i] = math.cos(flap_angle), math.sin(flap_angle)
        directions[2, i], directions[3, i] = -math.sin(edge_angle), math.cos(edge_angle)
        flap, edge = displacement[2 + i], displacement[2 + blades + i]
        for d in range(4):
            deflection[d, i] = directions[d, i] * (flap if d < 2 else edge)
        for axis in range(3):
            along_n, along_t = features[BASIS + axis, i], features[BASIS + 3 + axis, i]
            placement = (apex[axis], features[BASIS + 6 + axis, i],
                         along_n * deflection[0, i] + along_t * deflection[1, i],
                         along_n * deflection[2, i] + along_t * deflection[3, i])
            for j in range(points):
                samples[axis, i, j] = (placement[0] * point_basis[0, j] + placement[1] * point_basis[1, j]
                                       + placement[2] * point_basis[2, j] + placement[3] * point_basis[3, j])
    nodes = drag_shapes.shape[1]
    if nodes > 0:
        for j in range(samples.shape[2]):
            node = min(j, nodes - 1)
            samples[0, blades, j] = drag_shapes[0, node] * x_top
            samples[1, blades, j] = drag_shapes[1, node] * y_top


@njit
def element_inflow(velocity: np.ndarray, samples: np.ndarray, displacement: np.ndarray, rates: np.ndarray,
                   rotor_speed: float, constants: np.ndarray, features: np.ndarray, directions: np.ndarray,
                   point_basis: np.ndarray, deflection: np.ndarray, mode_slopes: np.ndarray, shadow_on: bool,
                   downwind: bool, shadow_drag: float, shadow_elevation: np.ndarray, shadow_outline: np.ndarray,
                   drag_constants: np.ndarray, wind: np.ndarray, inflow: np.ndarray, normals: np.ndarray,
                   drag_loads: np.ndarray, apex_wind: np.ndarray) -> None:
    """The wind at every element with the tower shadow (:func:`hawt_plant.tower_shadow.shadow`, at the element
    relative to the tower top's position) into ``wind`` (3, B, N), and the inflow without induction into ``inflow``
    (2, B, N): vx = (V - the element's velocity) . e_n' (its velocity along e_z taken as 0), vy = -V . e_t + (its
    velocity along e_t), the element moving with the tower, its blade's modes and the rotation (omega r, r = s_abs cos
    cone). e_n' = cos gamma e_n - sin gamma e_z is the normal the deflected blade's out-of-plane slope turns towards
    the span, as AeroDyn's BEM frame keeps the node's out-of-plane rotation (its "cant"; ``AeroDyn.f90``,
    Calculate_MeshOrientation_NoSweepPitchTwist); tan gamma = d(deflection along e_n)/ds from ``deflection``
    (:func:`place_elements`) and ``mode_slopes`` (2, N), the flap and edgewise shapes' slopes d phi/ds [1/m] at the
    elements; tan gamma and cos gamma go to ``normals`` (2, B, N), for the element forces' directions
    (:func:`hawt_plant.blade_elements.blade_element_loads`).

    ``velocity`` is the wind at ``samples`` (:func:`place_elements`); ``rates`` the structural rates (as
    ``displacement``). With tower drag nodes (``drag_constants`` (4, K): :class:`~hawt_plant.tower_drag.TowerDrag`'s
    coefficient, fore-aft and side-side shapes, lever) their loads go to ``drag_loads`` (fa force, ss force, base fa
    and ss moments, :func:`hawt_plant.tower_drag.node_drag`); without, it is left alone. The undisturbed wind at the
    rotor apex (``velocity`` after blade 1's elements) goes to ``apex_wind`` (3,).
    """
    blades, elements = wind.shape[1], wind.shape[2]
    for axis in range(3):
        apex_wind[axis] = velocity[axis, 0, elements]
    x_top, y_top, rate_fa, rate_ss = displacement[0], displacement[1], rates[0], rates[1]
    spin = rotor_speed * constants[_COS_CONE]
    motion = np.empty((2, 4))  # vx, vy per unit of 1, s_abs, phi_flap, phi_edge
    for i in range(blades):
        flap_n, edge_n = deflection[0, i], deflection[2, i]
        for row in range(2):
            for part in range(2):
                k = 2 * row + part
                motion[row, part] = rate_fa * features[MOTION_FA + k, i] + rate_ss * features[MOTION_SS + k, i]
        motion[1, 1] += spin
        flap_rate, edge_rate = rates[2 + i], rates[2 + blades + i]
        motion[0, 2], motion[0, 3] = -(directions[0, i] * flap_rate), -(directions[2, i] * edge_rate)
        motion[1, 2], motion[1, 3] = directions[1, i] * flap_rate, directions[3, i] * edge_rate
        for j in range(elements):
            u, v, w = velocity[0, i, j], velocity[1, i, j], velocity[2, i, j]
            if shadow_on:
                du, dv = shadow(samples[0, i, j] - x_top, samples[1, i, j] - y_top, samples[2, i, j],
                                shadow_elevation, shadow_outline, downwind, shadow_drag)
                v += u * dv
                u *= 1.0 + du
            wind[0, i, j], wind[1, i, j], wind[2, i, j] = u, v, w
            for row in range(2):
                sign = 1.0 if row == 0 else -1.0  # vx along e_n, vy along -e_t
                axis = BASIS + 3 * row
                inflow[row, i, j] = (sign * (features[axis, i] * u + features[axis + 1, i] * v
                                             + features[axis + 2, i] * w)
                                     + motion[row, 0] * point_basis[0, j] + motion[row, 1] * point_basis[1, j]
                                     + motion[row, 2] * point_basis[2, j] + motion[row, 3] * point_basis[3, j])
            slope = flap_n * mode_slopes[0, j] + edge_n * mode_slopes[1, j]  # tan gamma
            cos_gamma = 1.0 / math.sqrt(1.0 + slope * slope)
            normals[0, i, j], normals[1, i, j] = slope, cos_gamma
            inflow[0, i, j] = cos_gamma * (inflow[0, i, j] - slope * (features[BASIS + 6, i] * u
                                                                      + features[BASIS + 7, i] * v
                                                                      + features[BASIS + 8, i] * w))
    nodes = drag_constants.shape[1]
    if nodes > 0:
        drag_loads[0], drag_loads[1], drag_loads[2], drag_loads[3] = node_drag(
            velocity[0, blades, :nodes], velocity[1, blades, :nodes], rate_fa, rate_ss, drag_constants[0],
            drag_constants[1], drag_constants[2], drag_constants[3])


@njit
def deflection_moments(rows: np.ndarray, deflection: np.ndarray, i: int) -> tuple[float, float, float]:
    """The moments about the apex of blade ``i``'s load sums ``rows`` (:data:`LOAD_ROWS`) through its deflections'
    arms: (along e_n, against the axial force about -e_t; along e_t, against it about e_n; about -e_z, the in-plane
    force on the arm along e_n less the out-of-plane force on the arm along e_t), as :func:`measured_loads` adds them
    to the blade's moments and :func:`generalized_forces` to the tower's."""
    flap_n, flap_t, edge_n, edge_t = deflection[0, i], deflection[1, i], deflection[2, i], deflection[3, i]
    along_n = flap_n * rows[_Z2] + edge_n * rows[_Z3]
    along_t = flap_t * rows[_Z2] + edge_t * rows[_Z3]
    about_z = flap_n * rows[_T2] + edge_n * rows[_T3] - flap_t * rows[_N2] - edge_t * rows[_N3]
    return along_n, along_t, about_z


@njit
def torsion_rate(rotor_speed: float, generator_speed: float, side_side_rate: float, constants: np.ndarray) -> float:
    """The shaft's rate of twist [rad/s]: the rotor's spin less the generator's (both inertial, the generator's
    referred to the low-speed shaft), less the gearbox's share of the nacelle's roll about the shaft, (1 - 1/N) times
    the roll rate -slope_ss cos(tilt) y' of the side-side mode. The gearbox turns with the nacelle, so a roll with the
    rotor and generator still twists the shaft, as in ElastoDyn, whose drivetrain coordinates (DOF_GeAz, DOF_DrTr) are
    relative to the nacelle; the shaft torque's roll reaction on the side-side mode (:func:`generalized_forces`:
    -slope_ss cos(tilt) (1 - 1/N) times the shaft torque) is the force of this kinematics."""
    roll_twist = constants[_SLOPE_SS] * constants[_COS_TILT] * (1.0 - 1.0 / constants[_GEARBOX_RATIO])
    return rotor_speed - generator_speed + roll_twist * side_side_rate


@njit
def generalized_forces(aero: np.ndarray, trig: np.ndarray, features: np.ndarray, directions: np.ndarray,
                       deflection: np.ndarray, displacement: np.ndarray, rates: np.ndarray, rotor_speed: float,
                       generator_speed: float, torsion: float, drag_loads: np.ndarray, constants: np.ndarray,
                       load_operator: np.ndarray,
                       mode_constants: np.ndarray, loads: np.ndarray, mode_stiffness: np.ndarray,
                       mode_residual: np.ndarray, scaled: np.ndarray, scaled_residual: np.ndarray, schur: np.ndarray,
                       forces: np.ndarray) -> None:
    """The loads without the inertia of the accelerations (unknown yet), the generalized forces and the mass matrix
    reduced to the tower and the rotor (model notes).

    ``aero`` (3, B, 4): each blade's aerodynamic load sums along e_n, e_t and e_z
    (:func:`~hawt_plant.blade_elements.blade_element_loads`);
    ``load_operator`` (11, 6): the gravity and centrifugal load rows, linear in cos psi, sin psi, 1, omega^2 and
    omega^2 times each mode's deflection along e_t; ``mode_constants`` (5, 2B): the modes' stiffness, centrifugal
    stiffening, damping, 1/sqrt(generalized mass) (0 for a mode that does not move) and arm in the rotor's rotation.
    Writes ``loads`` (11, B), the modes' stiffness now, their residual forces and their couplings with [tower fa,
    tower ss, rotor] scaled by 1/sqrt(mass) (``scaled`` (3, 2B), ``scaled_residual``), ``schur``: the reduced system
    (m11, m12, m22, r1, r2, m13, m23, m33, r3), and ``forces`` (:data:`FORCES`).
    """
    blades = aero.shape[1]
    modes = 2 * blades
    normal = tangential_0 = tangential_1 = gravity = spanwise = 0.0
    for i in range(blades):
        normal += aero[0, i, 0]
        spanwise += aero[2, i, 0]
        tangential_0 += aero[1, i, 0]
        tangential_1 += aero[1, i, 1]
        gravity += features[BASIS + 5, i]  # e_t's z
    cone, cone_s = constants[_COS_CONE], constants[_SIN_CONE]
    forces[_THRUST] = cone * normal - cone_s * spanwise
    aero_torque = cone * (tangential_1 + constants[_HUB_RADIUS] * tangential_0)
    gravity_torque = -constants[_GRAVITY] * constants[_MASS_RADIUS] * gravity
    shaft = constants[_TORSIONAL_STIFFNESS] * torsion + constants[_TORSIONAL_DAMPING] * torsion_rate(
        rotor_speed, generator_speed, rates[1], constants)
    forces[_AERO_TORQUE], forces[_GRAVITY_TORQUE], forces[_SHAFT_TORQUE] = aero_torque, gravity_torque, shaft
    omega2 = rotor_speed * rotor_speed
    tower_fa = tower_ss = deflected_tilt = deflected_yaw = 0.0
    for i in range(blades):
        flap_t, edge_t = omega2 * deflection[1, i], omega2 * deflection[3, i]
        for r in range(loads.shape[0]):
            load = (load_operator[r, 0] * trig[0, i] + load_operator[r, 1] * trig[1, i] + load_operator[r, 2]
                    + load_operator[r, 3] * omega2 + load_operator[r, 4] * flap_t + load_operator[r, 5] * edge_t)
            load += aero[r // 4, i, r % 4] if r < 8 else aero[2, i, _Z_FUNCTIONS[r - 8]]
            loads[r, i] = load
            tower_fa += features[TOWER_FA + r, i] * load
            tower_ss += features[TOWER_SS + r, i] * load
        along_n, along_t, about_z = deflection_moments(loads[:, i], deflection, i)
        turned = cone_s * along_t + cone * about_z  # the part the azimuth turns into tilt (sin psi), yaw (-cos psi)
        deflected_tilt += trig[1, i] * turned - trig[0, i] * along_n
        deflected_yaw -= trig[1, i] * along_n + trig[0, i] * turned
    # The tower top's rotations (slope_fa per metre fore-aft; -slope_ss about x side-side, whose part about e_zs yaws
    # the rotor) turn the loads' arms through the blades' deflections too: their tilt and yaw moments (as
    # measured_loads' hub moments have them) do work on them, as ElastoDyn's partial velocities of the deflected blade
    # points carry it (tests/hawt_plant/test_model.py: the tower top's 3P against OpenFAST's).
    q_fa = tower_fa + constants[_SLOPE_FA] * deflected_tilt + constants[_FA_GRAVITY_FORCE] + drag_loads[0]
    q_ss = tower_ss + drag_loads[1] - constants[_SLOPE_SS] * (constants[_SIN_TILT] * deflected_yaw + constants[
        _COS_TILT] * shaft * (1.0 - 1.0 / constants[_GEARBOX_RATIO]))
    residual_fa = q_fa - constants[_FA_DAMPING] * rates[0] - constants[_FA_STIFFNESS] * displacement[0]
    residual_ss = q_ss - constants[_SS_DAMPING] * rates[1] - constants[_SS_STIFFNESS] * displacement[1]
    forces[_RESIDUAL_FA], forces[_RESIDUAL_SS] = residual_fa, residual_ss
    stiffness, centrifugal, damping, scale, rotor_arms = (mode_constants[0], mode_constants[1], mode_constants[2],
                                                          mode_constants[3], mode_constants[4])
    for i in range(blades):
        for mode in range(2):  # flap, edge
            m = mode * blades + i
            mode_n, mode_t = directions[2 * mode, i], directions[2 * mode + 1, i]  # the mode's direction
            force = mode_n * loads[_N2 + mode, i] + mode_t * loads[_T2 + mode, i]
            mode_stiffness[m] = stiffness[m] + centrifugal[m] * omega2
            mode_residual[m] = force - damping[m] * rates[2 + m] - mode_stiffness[m] * displacement[2 + m]
            scaled_residual[m] = mode_residual[m] * scale[m]
            # couplings with the tower: int mu phi (U . d) ds of the mode's direction d
            for tower in range(2):
                principal = features[COUPLING + 2 * mode + tower, i]  # flap along e_n, edge along e_t
                across = features[COUPLING + 4 + 2 * mode + tower, i]  # flap along e_t, edge along e_n
                if mode == 0:
                    scaled[tower, m] = (mode_n * principal + mode_t * across) * scale[m]
                else:
                    scaled[tower, m] = (mode_t * principal + mode_n * across) * scale[m]
            scaled[2, m] = rotor_arms[m] * mode_t * scale[m]
    modal_mass = np.zeros((3, 3))  # what eliminating the modes takes off the tower's and rotor's mass: M M^T
    projected = np.zeros(3)
    for a in range(3):
        for m in range(modes):
            projected[a] += scaled[a, m] * scaled_residual[m]
            for c in range(3):
                modal_mass[a, c] += scaled[a, m] * scaled[c, m]
    linear = quadratic = 0.0
    for i in range(blades):
        linear += features[FA_MASS, i]
        quadratic += features[FA_MASS + 1, i] * features[FA_MASS + 1, i]
    mass_fa = (constants[_FA_MASS_CONSTANT] + constants[_FA_MASS_LINEAR] * linear
               + constants[_FA_MASS_QUADRATIC] * quadratic)
    schur[0], schur[1], schur[2] = mass_fa - modal_mass[0, 0], -modal_mass[0, 1], constants[_SS_MASS] - modal_mass[1, 1]
    schur[3], schur[4] = residual_fa - projected[0], residual_ss - projected[1]
    schur[5], schur[6], schur[7] = -modal_mass[0, 2], -modal_mass[1, 2], constants[_ROTOR_INERTIA] - modal_mass[2, 2]
    schur[8] = aero_torque + gravity_torque - shaft - projected[2]


@njit
def accelerations(schur: np.ndarray, generator_torque: float, constants: np.ndarray, scaled: np.ndarray,
                  scaled_residual: np.ndarray, scale: np.ndarray, out: np.ndarray) -> None:
    """The accelerations [tower fa, tower ss, flap 1..B, edge 1..B, rotor] into ``out`` with this generator torque
    acting on the drivetrain (its roll reaction on the side-side mode): the reduced 3 x 3 system of the tower and the
    rotor (:func:`generalized_forces`) solved by eliminating the rotor, then each blade's modes."""
    m11, m12, m22, r1, r2, m13, m23, m33, r3 = (schur[0], schur[1], schur[2], schur[3], schur[4], schur[5], schur[6],
                                                 schur[7], schur[8])
    r2 -= constants[_SLOPE_SS] * constants[_COS_TILT] * generator_torque
    a11, a12, a22 = m11 - m13 * m13 / m33, m12 - m13 * m23 / m33, m22 - m23 * m23 / m33
    b1, b2 = r1 - m13 * r3 / m33, r2 - m23 * r3 / m33
    det = a11 * a22 - a12 * a12
    x_acc = (a22 * b1 - a12 * b2) / det
    y_acc = (a11 * b2 - a12 * b1) / det
    rotor_acc = (r3 - m13 * x_acc - m23 * y_acc) / m33
    out[0], out[1], out[out.size - 1] = x_acc, y_acc, rotor_acc
    for m in range(scale.size):
        out[2 + m] = (scaled_residual[m] - (x_acc * scaled[0, m] + y_acc * scaled[1, m] + rotor_acc * scaled[2, m])) \
            * scale[m]


@njit
def measured_loads(acc: np.ndarray, generator_torque: float, trig: np.ndarray, features: np.ndarray,
                   directions: np.ndarray, deflection: np.ndarray, loads: np.ndarray, apex: np.ndarray,
                   displacement: np.ndarray, wind: np.ndarray, constants: np.ndarray, rotor_inertia_rows: np.ndarray,
                   mode_inertia: np.ndarray, effective_weights: np.ndarray, forces: np.ndarray,
                   drag_loads: np.ndarray, root: np.ndarray, measured: np.ndarray) -> None:
    """The blade-root moments (out-of-plane, in-plane) into ``root`` (2, B) and the rotor, yaw-bearing and tower-base
    moments and the blade-effective wind into ``measured`` (:data:`MEASURED`), with the inertial loads of the
    accelerations ``acc`` (:func:`accelerations`) and ``generator_torque`` acting (the spin reaction).

    Per blade, the moments about the apex: A about -e_t (from the loads along e_n), B about e_n (along e_t), C about
    -e_z, with the deflections' arms: along e_n against the axial force about -e_t and the in-plane force about -e_z;
    along e_t against the axial force about e_n and the out-of-plane force. The rotor force at the apex is the sum of
    F_n e_n + F_t e_t + F_z e_z; the nacelle and hub move with the tower top as point masses.
    """
    blades = trig.shape[1]
    x_acc, y_acc, rotor_acc = acc[0], acc[1], acc[acc.size - 1]
    rh = constants[_HUB_RADIUS]
    ca = cb = cc = sa = sb = sc = ob = oc = fx = fy = fz = 0.0
    wind_cos = wind_sin = wind_total = 0.0
    row_loads = np.empty(loads.shape[0])
    mode_acc = np.empty(4)
    for i in range(blades):
        flap_acc, edge_acc = acc[2 + i], acc[2 + blades + i]
        for d in range(4):
            mode_acc[d] = directions[d, i] * (flap_acc if d < 2 else edge_acc)
        for r in range(loads.shape[0]):
            row_loads[r] = loads[r, i] - (x_acc * features[INERTIA_FA + r, i] + y_acc * features[INERTIA_SS + r, i]
                                          + rotor_acc * rotor_inertia_rows[r]) \
                - (mode_inertia[r, 0] * mode_acc[0] + mode_inertia[r, 1] * mode_acc[1]
                   + mode_inertia[r, 2] * mode_acc[2] + mode_inertia[r, 3] * mode_acc[3])
        along_n, along_t, moment_c = deflection_moments(row_loads, deflection, i)
        moment_a = rh * row_loads[_N0] + row_loads[_N1] - along_n
        moment_b = rh * row_loads[_T0] + row_loads[_T1] - along_t
        root[0, i] = row_loads[_N1] - along_n
        root[1, i] = row_loads[_T1] - along_t
        c, s = trig[0, i], trig[1, i]
        ca += c * moment_a
        cb += c * moment_b
        cc += c * moment_c
        sa += s * moment_a
        sb += s * moment_b
        sc += s * moment_c
        ob += moment_b
        oc += moment_c
        force_n, force_t, force_z = row_loads[_N0], row_loads[_T0], row_loads[_Z0]
        fx += features[BASIS, i] * force_n + features[BASIS + 3, i] * force_t + features[BASIS + 6, i] * force_z
        fy += features[BASIS + 1, i] * force_n + features[BASIS + 4, i] * force_t + features[BASIS + 7, i] * force_z
        fz += features[BASIS + 2, i] * force_n + features[BASIS + 5, i] * force_t + features[BASIS + 8, i] * force_z
        effective = 0.0
        for j in range(effective_weights.size):
            effective += wind[0, i, j] * effective_weights[j]
        wind_cos += c * effective
        wind_sin += s * effective
        wind_total += effective
    cone_c, cone_s = constants[_COS_CONE], constants[_SIN_CONE]
    cos_tilt, sin_tilt = constants[_COS_TILT], constants[_SIN_TILT]
    tilt = ca - cone_s * sb + cone_c * sc
    yaw = sa + cone_s * cb - cone_c * cc
    spin = cone_c * ob + cone_s * oc
    ax, ay, az = apex[0], apex[1], apex[2]
    g = constants[_GRAVITY]
    x_top, y_top = displacement[0], displacement[1]
    # Tower-base moments about the tower's base (OpenFAST's TwrBsMyt/Mxt point): at base_height, moved by a flexible
    # base with the mode (0 on the ground or a rigid base); loads of what stands above it.
    zb = constants[_BASE_HEIGHT]
    xb, yb = constants[_FA_BASE_SHAPE] * x_top, constants[_SS_BASE_SHAPE] * y_top
    base_fa = tilt + (az - zb) * fx - (ax - xb) * fz
    base_ss = spin * cos_tilt + yaw * sin_tilt + (ay - yb) * fz - (az - zb) * fy
    # Yaw bearing: the same rotor loads about the tower top; its yaw axis is inertial z.
    height = constants[_TOWER_HEIGHT]
    rx, ry, rz = ax - x_top, ay - y_top, az - height
    bearing_tilt = tilt + rz * fx - rx * fz
    bearing_yaw = yaw * cos_tilt - spin * sin_tilt + rx * fy - ry * fx
    # Nacelle and hub (point masses moving with the tower top).
    sfa, sss = constants[_SLOPE_FA], constants[_SLOPE_SS]
    zn = constants[_NACELLE_Z]
    for body in range(2):
        if body == 0:
            mass, bx, bz, hy = constants[_NACELLE_MASS], constants[_NACELLE_X] + x_top, height + zn, 1.0 + sss * zn
        else:
            mass, bx, bz, hy = constants[_HUB_MASS], ax, az, constants[_APEX_SS_GAIN]
        body_fx = -mass * x_acc * (1.0 + sfa * (bz - height))
        body_fy = -mass * y_acc * hy
        body_fz = -mass * (g - x_acc * sfa * (bx - x_top))
        base_fa += (bz - zb) * body_fx - (bx - xb) * body_fz
        base_ss += (y_top * hy - yb) * body_fz - (bz - zb) * body_fy
        bearing_tilt += (bz - height) * body_fx - (bx - x_top) * body_fz
        bearing_yaw += (bx - x_top) * body_fy - y_top * (hy - 1.0) * body_fx
    # The tower's own inertia and weight, its drag, and the reaction of the drivetrain's spin-up.
    base_fa += -x_acc * constants[_FA_HEIGHT_MOMENT] + g * x_top * constants[_FA_GRAVITY_MOMENT]
    base_ss += y_acc * constants[_SS_HEIGHT_MOMENT] - g * y_top * constants[_SS_GRAVITY_MOMENT]
    base_fa += drag_loads[2]
    base_ss += drag_loads[3]
    ratio, generator_inertia = constants[_GEARBOX_RATIO], constants[_GENERATOR_INERTIA]
    generator_acc = (forces[_SHAFT_TORQUE] - ratio * generator_torque) / (generator_inertia * ratio * ratio)
    spin_reaction = constants[_HUB_INERTIA] * rotor_acc + generator_inertia * ratio * generator_acc
    base_ss -= spin_reaction * cos_tilt
    bearing_yaw += spin_reaction * sin_tilt
    measured[0], measured[1], measured[2], measured[3], measured[4], measured[5] = \
        tilt, yaw, bearing_tilt, bearing_yaw, base_fa, base_ss
    measured[6], measured[7], measured[8] = wind_total / blades, 2.0 / blades * wind_cos, 2.0 / blades * wind_sin


@njit
def advance_structure(acc: np.ndarray, dt: float, velocity: np.ndarray, displacement: np.ndarray) -> None:
    """The structural coordinates over one step by semi-implicit (symplectic) Euler: each rate by its acceleration
    ``acc`` (:func:`accelerations`; its last entry, the rotor's, is the caller's), then each coordinate by its new
    rate."""
    for k in range(velocity.size):
        velocity[k] += dt * acc[k]
        displacement[k] += dt * velocity[k]


@njit
def acting_torque(parked: bool, generator_torque: float, disturbance: float, azimuth: float, forces: np.ndarray,
                  constants: np.ndarray) -> float:
    """The generator torque acting on the drivetrain [N m, high-speed shaft]: the actuator's ``generator_torque`` plus
    the periodic disturbance ``disturbance`` sin(azimuth); parked, the brake's, whatever holds the generator at rest
    against the shaft (the shaft torque of ``forces`` over the gearbox ratio)."""
    if parked:
        return forces[_SHAFT_TORQUE] / constants[_GEARBOX_RATIO]
    return generator_torque + disturbance * math.sin(azimuth) if disturbance != 0.0 else generator_torque


@njit
def advance(dt: float, generator_torque: float, disturbance: float, parked: bool, command: np.ndarray,
            transition: np.ndarray, limits: np.ndarray, schur: np.ndarray, constants: np.ndarray, scaled: np.ndarray,
            scaled_residual: np.ndarray, mode_scale: np.ndarray, forces: np.ndarray, acc: np.ndarray,
            velocity: np.ndarray, displacement: np.ndarray, pitch: np.ndarray, pitch_rate: np.ndarray,
            drive: np.ndarray) -> None:
    """The state over one step by semi-implicit (symplectic) Euler, the loads held from its start (model notes): the
    accelerations with the generator torque acting at its start (:func:`acting_torque`) on the drivetrain
    (:func:`accelerations`, into ``acc``), the structure
    (:func:`advance_structure`), the rotor's and the generator's speed by their accelerations (a parked generator's
    stays at rest), the shaft's torsion by the new speeds (:func:`torsion_rate`), the azimuth by the new rotor speed,
    wrapped to [0, 2 pi); then each blade's pitch actuator towards ``command``
    (:func:`hawt_plant.pitch_actuator.limited_step` with the actuator's ``transition`` and ``limits``, in place).
    ``drive`` (4,): rotor speed, generator speed (low-speed shaft), torsion and azimuth, updated."""
    acting = acting_torque(parked, generator_torque, disturbance, drive[3], forces, constants)
    accelerations(schur, acting, constants, scaled, scaled_residual, mode_scale, acc)
    advance_structure(acc, dt, velocity, displacement)
    rotor_speed, generator_speed = drive[0] + dt * acc[acc.size - 1], drive[1]
    if not parked:
        ratio = constants[_GEARBOX_RATIO]
        generator_speed += dt * ((forces[_SHAFT_TORQUE] - ratio * acting)
                                 / (constants[_GENERATOR_INERTIA] * ratio * ratio))
    drive[0], drive[1] = rotor_speed, generator_speed
    drive[2] += dt * torsion_rate(rotor_speed, generator_speed, velocity[1], constants)
    drive[3] = (drive[3] + dt * rotor_speed) % (2.0 * math.pi)
    limited_step(transition, limits, pitch, pitch_rate, command, pitch, pitch_rate)


@njit
def skew_geometry(apex_wind: np.ndarray, trig: np.ndarray, constants: np.ndarray, cos_azimuth: np.ndarray) -> float:
    """Pitt & Peters's skewed wake for the wind ``apex_wind`` at the rotor apex: returns its angle chi_0 to the shaft
    axis x_s = (ct, 0, -st), 0 when the wind has no part in the rotor plane (no skew), and writes each blade's cos of
    its azimuth from the most downwind one into ``cos_azimuth`` (B,), where the wind's in-plane part (along
    e_zs = (st, 0, ct) and e_ys) points; a blade's radial unit vector is cos psi e_zs - sin psi e_ys."""
    u, v, w = apex_wind[0], apex_wind[1], apex_wind[2]
    ct, st = constants[_COS_TILT], constants[_SIN_TILT]
    along_z, along_y = u * st + w * ct, v
    in_plane = math.hypot(along_z, along_y)
    for i in range(cos_azimuth.size):
        cos_azimuth[i] = trig[0, i] if in_plane == 0.0 else (trig[0, i] * along_z - trig[1, i] * along_y) / in_plane
    return 0.0 if in_plane == 0.0 else math.atan2(in_plane, u * ct - w * st)


@njit
def loads_and_measurements(update: bool, skewed_wake: bool, apex_wind: np.ndarray, cos_azimuth: np.ndarray,
                           inflow: np.ndarray, induction_factors: np.ndarray, inflow_filter: np.ndarray,
                           pitch: np.ndarray, twist: np.ndarray, polar_table: np.ndarray, scale: float,
                           intervals: float, offsets: np.ndarray, loss_exponents: np.ndarray,
                           local_solidity: np.ndarray, bounds: np.ndarray, pressure_to_load: np.ndarray,
                           span_functions: np.ndarray, iterations: int, relaxation: float, dynamic_inflow: bool,
                           dt: float, tip_radius: float, tip_ratio: np.ndarray, disk_weights: np.ndarray,
                           unsteady: bool, pitch_rate: np.ndarray, unsteady_states: np.ndarray,
                           unsteady_table: np.ndarray, unsteady_constants: np.ndarray, normals: np.ndarray,
                           aero: np.ndarray, trig: np.ndarray, features: np.ndarray, directions: np.ndarray,
                           deflection: np.ndarray, displacement: np.ndarray, rates: np.ndarray, rotor_speed: float,
                           generator_speed: float, torsion: float, drag_loads: np.ndarray, constants: np.ndarray,
                           load_operator: np.ndarray, mode_constants: np.ndarray, loads: np.ndarray,
                           mode_stiffness: np.ndarray, mode_residual: np.ndarray, scaled: np.ndarray,
                           scaled_residual: np.ndarray, schur: np.ndarray, forces: np.ndarray, measure: bool,
                           parked: bool, generator_torque: float, disturbance: float, azimuth: float,
                           mode_scale: np.ndarray,
                           acc: np.ndarray, apex: np.ndarray, wind: np.ndarray, rotor_inertia_rows: np.ndarray,
                           mode_inertia: np.ndarray, effective_weights: np.ndarray, root: np.ndarray,
                           measured: np.ndarray) -> None:
    """Steps 4 and, with ``measure``, 5 of the module notes. Step 4: with ``skewed_wake``, the skewed wake's angle and
    azimuths (:func:`skew_geometry`, into ``cos_azimuth``), the blades' aerodynamic load sums into ``aero``
    (:func:`hawt_plant.blade_elements.blade_element_loads`, its arguments in its order; ``pitch`` (B,) and ``twist``
    (B, N) make its ``pitch_twist``), then :func:`generalized_forces` (its arguments in its order after ``aero``).
    Step 5: with the generator torque acting (:func:`acting_torque` of ``parked``, ``generator_torque``,
    ``disturbance`` and ``azimuth``), the accelerations into ``acc`` (:func:`accelerations`) and :func:`measured_loads`
    into ``root`` and ``measured`` (the other arrays theirs); without ``measure`` those arguments are not read."""
    skew_angle = skew_geometry(apex_wind, trig, constants, cos_azimuth) if skewed_wake else 0.0
    pitch_twist = np.empty_like(twist)
    for i in range(twist.shape[0]):
        for j in range(twist.shape[1]):
            pitch_twist[i, j] = pitch[i] + twist[i, j]
    blade_element_loads(inflow, induction_factors, inflow_filter, pitch_twist, polar_table, scale, intervals, offsets,
                        loss_exponents, local_solidity, bounds, pressure_to_load, span_functions, update, iterations,
                        relaxation, dynamic_inflow, dt, tip_radius, tip_ratio, disk_weights, skew_angle != 0.0,
                        skew_angle, cos_azimuth, unsteady, pitch_rate, unsteady_states, unsteady_table,
                        unsteady_constants, normals, aero)
    generalized_forces(aero, trig, features, directions, deflection, displacement, rates, rotor_speed, generator_speed,
                       torsion, drag_loads, constants, load_operator, mode_constants, loads, mode_stiffness,
                       mode_residual, scaled, scaled_residual, schur, forces)
    if measure:
        acting = acting_torque(parked, generator_torque, disturbance, azimuth, forces, constants)
        accelerations(schur, acting, constants, scaled, scaled_residual, mode_scale, acc)
        measured_loads(acc, acting, trig, features, directions, deflection, loads, apex, displacement, wind, constants,
                       rotor_inertia_rows, mode_inertia, effective_weights, forces, drag_loads, root, measured)
