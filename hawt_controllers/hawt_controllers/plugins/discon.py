"""The ``discon`` controller: a Bladed-style DISCON library (NREL's ROSCO by default) hosted as a plug-in.

Claims ``collective_pitch`` and ``generator_torque``, and ``blade_pitch`` when ``individual_pitch`` is
set (the library's per-blade demands, records 42-44, less their mean: the collective). Steps on
``plant/blade_loads`` and ``plant/state``; each step is one call of the library
(hawt_controllers.discon.library) with the plant's measurements of that step.

- ``library`` and ``infile`` default to the ``rosco`` wheel's ``libdiscon.so`` and NREL 5 MW
  ``DISCON.IN`` (hawt_controllers.discon.rosco_input). A ROSCO input file is copied into a private folder with
  its relative paths made absolute, ``LoggingLevel`` 0 (hawt records the run) and the IPC settings of
  this controller's parameters (``IPC_ControlMode``, ``IPC_KI``, ``IPC_aziOffset``). Another library's
  file is passed as it is, and the IPC parameters must keep their defaults.
- Each activation starts a fresh instance of the library (its own loaded copy, first call status 0):
  ROSCO initialises its pitch state from the measured blade pitches of that call (records 4, 33, 34)
  and its torque from its own law (rated torque above 98 % of rated speed, else ``VS_Rgn2K`` omega^2).
  When it replaces another collective controller, it is given that controller's last collective pitch as
  the measured pitch of every blade, so the pitch starts where the outgoing one left it. A deactivation
  makes the last call (status -1); so does the end of the process.
- The library file is checked before anything starts (``check_values``, which every engine's parameter
  check runs: hawt_controllers.discon.library.check_library): an ELF shared object of this machine that
  exports ``DISCON``, else one line naming ``library``, the file and what is wrong. So is the input file:
  readable, and for a ROSCO input the settings hawt sets and the rotor performance file (``PerfFileName``)
  there, else one line naming ``infile``.
- While inactive the library is not called; the (unpublished) output is the measured pitch and torque.
- A library that fails (``aviFAIL`` < 0) raises :class:`~hawt_controllers.plugins.controller.ControllerFailure`
  with its message: the ROS node reports it and stops answering (the plant's safety system takes over);
  ``hawt run`` stops with the message.
"""
from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any, Mapping, Optional, Sequence, Tuple

from hawt_core.command_interfaces import BLADE_PITCH, COLLECTIVE_PITCH, GENERATOR_TORQUE
from hawt_core.parameter_table import ParameterError, ParameterSpec
from hawt_core.plant_description import PlantDescription

from hawt_controllers.plugins.controller import (BladeContribution, CollectiveContribution, Contribution, Controller, ControllerFailure,
                         mean_pitch)
from hawt_controllers.discon.library import DisconFailure, DisconInputs, DisconLibrary, DisconLoadError, check_library
from hawt_controllers.discon.rosco_input import is_rosco_input, rosco_files, write_private_input

__all__ = ["DisconController"]

_IPC_DEFAULTS = {"ipc_mode": 0, "ipc_integral_gain": [0.0, 0.0], "ipc_azimuth_offset": [0.0, 0.0]}


class DisconController(Controller):
    """A DISCON library as a controller (see the module notes)."""

    TYPE = "discon"
    PARAMETERS = (
        ParameterSpec("library", "", "DISCON shared library (empty: the rosco wheel's libdiscon.so)", read_only=True),
        ParameterSpec("infile", "", "the library's input file, accINFILE (empty: the rosco wheel's NREL 5 MW "
                      "DISCON.IN)", read_only=True),
        ParameterSpec("individual_pitch", False, "tell the library the blades pitch individually (record 28) and "
                      "claim blade_pitch for its per-blade demands", read_only=True),
        ParameterSpec("ipc_mode", _IPC_DEFAULTS["ipc_mode"], "ROSCO IPC_ControlMode: 0 off, 1 1P, 2 1P+2P",
                      minimum=0, maximum=2, read_only=True),
        ParameterSpec("ipc_integral_gain", _IPC_DEFAULTS["ipc_integral_gain"], "ROSCO IPC_KI of 1P and 2P",
                      "rad/(N*m*s)", minimum=0.0, read_only=True),
        ParameterSpec("ipc_azimuth_offset", _IPC_DEFAULTS["ipc_azimuth_offset"], "ROSCO IPC_aziOffset of 1P and 2P "
                      "(phi_n = n * offset)", "rad", minimum=-6.3, maximum=6.3, read_only=True),
    )
    INPUTS = ("blade_loads", "turbine_state")
    SWITCHABLE = False

    def __init__(self, values: Mapping[str, Any], plant: PlantDescription) -> None:
        super().__init__(values, plant)
        self.check_values(self.values)
        self.library_path, infile = self.files(self.values)
        self._folder = tempfile.TemporaryDirectory(prefix="hawt-discon-input-")
        if is_rosco_input(infile):
            infile = self._private_input(self.values, infile, Path(self._folder.name))
        elif any(self.values[name] != default for name, default in _IPC_DEFAULTS.items()):
            raise ParameterError(f"ipc_mode, ipc_integral_gain, ipc_azimuth_offset: {infile} is not a ROSCO input "
                                 "file (no PerfFileName setting); set the library's IPC in its own file")
        self.infile = infile
        self.library: Optional[DisconLibrary] = self._instance()  # loaded now: a bad library fails configure
        self.start: Optional[CollectiveContribution] = None
        self.active = False

    @classmethod
    def files(cls, values: Mapping[str, Any]) -> Tuple[Path, Path]:
        """The library and input file the parameters name (the rosco wheel's for empty ones)."""
        if values["library"] and values["infile"]:
            return Path(values["library"]), Path(values["infile"])
        try:
            library, infile = rosco_files()
        except FileNotFoundError as error:
            raise ParameterError(f"library: {error}") from None
        return Path(values["library"] or library), Path(values["infile"] or infile)

    @classmethod
    def check_values(cls, values: Mapping[str, Any]) -> None:
        """The library passes check_library (an ELF shared object of this machine exporting ``DISCON``), the input
        file is readable, and a ROSCO input gives the private copy (:meth:`_private_input`: the settings hawt sets are
        in it and the rotor performance file its estimator reads is there, else ROSCO would end the process); ROSCO's
        IPC needs ``individual_pitch``; two gains and offsets."""
        library, infile = cls.files(values)
        try:
            check_library(library)
        except DisconLoadError as error:
            raise ParameterError(f"library: {error}") from None
        try:
            infile.open("rb").close()
        except OSError as error:
            raise ParameterError(f"infile: {infile}: {error.strerror}") from None
        if is_rosco_input(infile):  # the private copy the controller writes, here before anything starts
            with tempfile.TemporaryDirectory(prefix="hawt-discon-check-") as folder:
                cls._private_input(values, infile, Path(folder))
        for name in ("ipc_integral_gain", "ipc_azimuth_offset"):
            if len(values[name]) != 2:
                raise ParameterError(f"{name}: expected 2 values (1P, 2P), found {len(values[name])}")
        if values["ipc_mode"] > 0 and not values["individual_pitch"]:
            raise ParameterError("ipc_mode: ROSCO's IPC commands each blade; set individual_pitch true")

    @staticmethod
    def _private_input(values: Mapping[str, Any], infile: Path, folder: Path) -> Path:
        """The ROSCO input ``infile`` written into ``folder`` with its paths absolute, ``LoggingLevel`` 0 and the IPC
        parameters (rosco_input.write_private_input); a setting it lacks or a missing performance file is a
        ParameterError naming ``infile``."""
        settings = {"LoggingLevel": "0", "IPC_ControlMode": str(values["ipc_mode"]),
                    "IPC_KI": " ".join(f"{k:.9g}" for k in values["ipc_integral_gain"]),
                    "IPC_aziOffset": " ".join(f"{a:.9g}" for a in values["ipc_azimuth_offset"])}
        try:
            return write_private_input(infile, folder / infile.name, settings)
        except (KeyError, OSError) as error:
            raise ParameterError(f"infile: {error.args[0]}") from None

    @classmethod
    def claimed(cls, values: Mapping[str, Any]) -> Tuple[str, ...]:
        return (COLLECTIVE_PITCH, GENERATOR_TORQUE) + ((BLADE_PITCH,) if values["individual_pitch"] else ())

    def _instance(self) -> DisconLibrary:
        plant = self.plant
        try:
            return DisconLibrary(self.library_path, self.infile, plant.blades, plant.dt,
                                 (plant.min_pitch, plant.max_pitch, plant.max_pitch_rate),
                                 self.values["individual_pitch"])
        except DisconLoadError as error:
            raise ParameterError(f"library: {error}") from None

    def update(self, step: int, loads: Any, state: Any = None) -> Tuple[Contribution, ...]:
        if not self.active:  # the library is not running
            return self._contributions(mean_pitch(loads.pitch), [0.0] * self.plant.blades, state.generator_torque)
        pitch = loads.pitch if self.start is None else [self.start.pitch] * self.plant.blades
        self.start = None
        try:
            demands = self.library.step(DisconInputs(
                step * self.plant.dt, pitch, state.generator_speed, loads.rotor_speed, state.generator_torque,
                state.electrical_power, state.aero_torque * loads.rotor_speed, state.hub_wind_speed,
                loads.root_moment_oop, loads.root_moment_ip, loads.azimuth, state.tower_top_fa_accel,
                state.tower_top_ss_accel, state.hub_tilt_moment, state.hub_yaw_moment))
        except DisconFailure as error:
            raise ControllerFailure(str(error)) from None
        if demands.pitch_override != 0:  # the library leaves the pitch alone: hold the measured one
            return self._contributions(mean_pitch(loads.pitch), [0.0] * self.plant.blades, demands.generator_torque)
        if self.values["individual_pitch"]:
            collective = sum(demands.pitch) / len(demands.pitch)
            return self._contributions(collective, [p - collective for p in demands.pitch], demands.generator_torque)
        return self._contributions(demands.collective, [0.0] * self.plant.blades, demands.generator_torque)

    def _contributions(self, collective: float, increments: Sequence[float], torque: float) -> Tuple[Contribution, ...]:
        out: Tuple[Contribution, ...] = (CollectiveContribution(collective, torque),)
        return out + (BladeContribution(tuple(increments)),) if self.values["individual_pitch"] else out

    def on_activate(self, ramp_time: Optional[float], initial: Sequence[Contribution], loads: Any) -> None:
        """A fresh instance of the library at the next step, from the outgoing collective pitch if it replaces one."""
        if self.library is None or self.library.calls > 0:
            self.close()
            self.library = self._instance()
        self.start = next((c for c in initial if isinstance(c, CollectiveContribution)), None)
        self.active = True

    def on_deactivate(self, ramp_time: Optional[float]) -> None:
        """The library's last call (status -1); it is not called again until an activation."""
        self.close()
        self.active = False

    def close(self) -> None:
        """End the running library instance, if any (status -1 if it was called)."""
        if self.library is not None:
            self.library.close()
            self.library = None
