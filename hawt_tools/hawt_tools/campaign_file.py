"""Campaign files (``hawt campaign CAMPAIGN.yaml``): what a design-load-case sweep runs, read and checked.

A campaign file is YAML::

    turbine: iea15                    # optional: a packaged turbine's name, or a turbine's folder or definition file
    dlc: 1.2                          # IEC 61400-1 DLC of every case: 1.2 (fatigue, the default), 1.1,
                                      # 1.3-1.5, 2.1, 2.3, 6.1-6.3
    fault: pitch_runaway blade=1 to=fine  # DLC 2.x only: the fault of every case (hawt_plant.faults), without at=
    wind:
      speeds: [5, 9, 13, 17, 21, 25]  # bin centres [m/s], increasing
      seeds: 3                        # seeds 1..3 per bin, or a list [4, 7]
      turbulence_class: B             # IEC A, B or C
      shear_exponent: 0.2
    site: {wind_class: I}             # Rayleigh at the IEC class mean; or {mean: 8.5, shape: 2.2} (Weibull)
    duration: 600                     # analysed simulated time per case [s]
    transient: 60                     # simulated time discarded before it [s]
    controllers:
      baseline: {graph: baseline}
      ipc_1p: {graph: ipc, arguments: {ipc_h2: "false", ipc_h3: "false"}}
      lqg: {graph: lqg, parameters: ["lqg_ipc.wind_noise:=0.001"]}

The ``dlc`` says what the cases are and what the campaign reports besides the DELs and the AEP (IEC 61400-1
Ed. 3 Table 2; :mod:`hawt_analysis.ultimate`): 1.2, fatigue in normal turbulence (NTM); 1.1, the same runs for
ultimate loads, each channel's 50-year value extrapolated from every bin's run maxima (at least 3 seeds per bin),
times γ_f 1.25; 1.3, extreme turbulence (ETM, the plant's ``turbulence_model``), the largest extreme of every
channel times γ_f 1.35, with the case that set it; 1.4 and 1.5, the extreme coherent gust with direction change
(ECD) and the extreme wind shear (EWS) of :mod:`hawt_plant.iec_extreme`, deterministic transients starting
``GUST_START`` s into the analysed time, reported as 1.3 is. A transient DLC's seeds are its cases per speed
(1.4: 1 ECD turning towards +y, 2 towards -y; 1.5: 1 and 2 vertical shear faster above or below the hub, 3 and 4
horizontal), all of them unless ``seeds`` picks some. DLC 2.1 and 2.3 add a fault of the plant
(:mod:`hawt_plant.faults`, the ``fault`` key, an entry without ``at=``): 2.1, normal turbulence with a control
system fault (default: blade 1's pitch actuator runs away to feather) ``GUST_START`` s into the analysed time,
γ_f 1.35; 2.3, the extreme operating gust starting then with a loss of the electrical network (default
``grid_loss``) at the gust's start, in its dip and at its peak (cases 1-3, ``EOG_FAULT_DELAYS``; the IEC asks for
the timing that loads most), γ_f 1.1 (abnormal). DLC 6.1-6.3 are the turbine shut down, its rotor idling (the
plant's ``rotor``: blades at feather, generator off) in the steady extreme wind model of the site's class
(:func:`hawt_plant.iec_extreme.steady_extreme_wind`), one case per yaw misalignment (``DesignLoadCase.yaw``): 6.1,
the 50-year wind at -15 and +15 deg (Ed. 3 §7.4.7, the steady model's), γ_f 1.35; 6.2, the 50-year wind with the
grid lost, so that the nacelle cannot yaw, at -135 to 180 deg every 45 deg, γ_f 1.1; 6.3, the 1-year wind at -30
and +30 deg, γ_f 1.35. Their wind speed is the model's (70 and 56 m/s at the hub for class I), so they take no
``speeds``.

A file may run several DLCs, each with its own ``speeds``, ``seeds`` and ``fault`` (what an entry leaves out is the
file's ``wind.speeds``, ``wind.seeds`` and the DLC's own fault), the rest shared (``campaigns/ultimate.yaml``)::

    dlc:
      1.3: {speeds: [11, 17, 25], seeds: 2}
      1.4: {speeds: [9.4, 11.4, 13.4]}
      2.3: {speeds: [9.4, 13.4, 25], fault: grid_loss}

:func:`load_campaigns` reads it as one :class:`Campaign` per DLC; ``hawt campaign`` runs each into a folder of its
own and takes the design load of every channel over all of them (:func:`hawt_analysis.ultimate.governing_loads`).

Every case is a run of a controller's graph (its launch ``arguments`` and ``-p``-style
``parameters``) with the plant's wind set by the campaign. The ``turbine`` is every graph's ``turbine``
argument, as ``turbine:=`` gives it to ``hawt run``: the plant's turbine and, through ``$(turbine-tuning …)``,
every controller's tuning; a folder or file is relative to the working directory (as a graph's), and a
controller's ``arguments`` may not give another. Without it each graph runs its own default turbine.
Everything is checked before a case runs (:func:`hawt_tools.campaign.plan_cases`): an error is a
:class:`CampaignError` whose one line names the file, the line and the key at fault.
"""
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, List, Mapping, Tuple

from hawt_analysis.lifetime import IEC_CLASS_MEAN_SPEED, WindDistribution
from hawt_core.parameter_table import ParameterError
from hawt_plant.faults import parse_faults
from hawt_plant.gusts import EOG_DURATION, extreme_wind_speed
from hawt_tools.graph_file import GraphError, did_you_mean, load_marked_yaml, resolve_turbine

__all__ = ["Campaign", "CampaignError", "ControllerConfig", "load_campaign", "case_overrides", "graph_arguments",
           "load_campaigns", "TURBULENCE_CLASSES", "DLCS", "DesignLoadCase", "EOG_FAULT_DELAYS", "GUST_START", "site_wind_class"]

TURBULENCE_CLASSES = ("A", "B", "C")


@dataclass(frozen=True)
class DesignLoadCase:
    """What every case of an IEC 61400-1 Ed. 3 DLC runs: turbulence (``turbulence_model`` NTM or ETM, a seed per
    case), or a deterministic transient, one (plant ``wind_type``, ``gust_sign``) per case of a speed; and, for a
    DLC 2.x, the default ``fault`` (a :mod:`hawt_plant.faults` entry without ``at=``), ``GUST_START`` s into the
    analysed time plus the case's ``fault_delays`` entry (one per transient; 0 without transients)."""

    turbulence_model: str = ""
    transients: Tuple[Tuple[str, int], ...] = ()
    fault: str = ""
    fault_delays: Tuple[float, ...] = ()
    yaw: Tuple[float, ...] = ()
    """An extreme wind DLC's (6.x) yaw misalignment of each case [deg], one per transient; its rotor is idling."""

    @property
    def extreme_wind(self) -> str:
        """The steady extreme wind model a shut-down turbine's DLC runs in (ewm50 or ewm1), '' for the others."""
        return self.transients[0][0] if self.yaw else ""

    def label(self, seed: int) -> str:
        """How a case of this DLC is named beside its speed."""
        if not self.transients:
            return f"seed {seed}"
        kind, sign = self.transients[seed - 1]
        if self.yaw:
            return f"{kind.upper()}, yaw {self.yaw[seed - 1]:+g} deg"
        if self.fault_delays:
            return f"{kind.replace('_', ' ').upper()}, fault at +{self.fault_delays[seed - 1]:.2f} s"
        return f"{kind.replace('_', ' ').upper()} {'+' if sign > 0 else '-'}"

    def fault_time(self, transient: float, seed: int) -> float:
        """When the fault of case ``seed`` acts [s simulated]: ``GUST_START`` into the analysed time that starts at
        ``transient``, plus the case's delay."""
        return transient + GUST_START + (self.fault_delays[seed - 1] if self.fault_delays else 0.0)


GUST_START = 10.0
"""Time [s] into the analysed window at which a transient DLC's gust or shear starts (it lasts 10-12 s)."""
EOG_FAULT_DELAYS = (0.0, 2.46, EOG_DURATION / 2.0)
"""DLC 2.3's fault times after the EOG starts [s]: at its start, in its dip (slowest wind, at 0.234 T) and at its
peak (fastest, T / 2); each a whole number of 0.01 s steps."""
DLCS = {"1.1": DesignLoadCase("NTM"), "1.2": DesignLoadCase("NTM"), "1.3": DesignLoadCase("ETM"),
        "1.4": DesignLoadCase(transients=(("ecd", 1), ("ecd", -1))),
        "1.5": DesignLoadCase(transients=(("ews_vertical", 1), ("ews_vertical", -1), ("ews_horizontal", 1),
                                          ("ews_horizontal", -1))),
        "2.1": DesignLoadCase("NTM", fault="pitch_runaway blade=1 to=feather"),
        "2.3": DesignLoadCase(transients=(("eog", 1),) * 3, fault="grid_loss", fault_delays=EOG_FAULT_DELAYS),
        **{name: DesignLoadCase(transients=((wind, 1),) * len(yaw), yaw=yaw) for name, wind, yaw in (
            ("6.1", "ewm50", (-15.0, 15.0)), ("6.2", "ewm50", tuple(range(-135, 181, 45))),
            ("6.3", "ewm1", (-30.0, 30.0)))}}
"""The design-load cases a campaign runs."""
_EXTRAPOLATION_SEEDS = 3
_KEYS = {"": ("turbine", "dlc", "fault", "wind", "site", "duration", "transient", "controllers"),
         "wind": ("speeds", "seeds", "turbulence_class", "shear_exponent"),
         "site": ("wind_class", "mean", "shape"),
         "controller": ("graph", "arguments", "parameters"),
         "dlc": ("speeds", "seeds", "fault")}
_REQUIRED = {"": ("wind", "duration", "controllers"), "controller": ("graph",)}


class CampaignError(GraphError):
    """A campaign file that cannot run: one line naming the file, the line and the key."""


@dataclass(frozen=True)
class ControllerConfig:
    """One controller configuration: a graph with its launch arguments and parameter overrides."""

    name: str
    graph: str
    arguments: Tuple[Tuple[str, str], ...] = ()
    parameters: Tuple[str, ...] = ()
    line: int = 0


@dataclass(frozen=True)
class Campaign:
    """A checked campaign file (module notes); speeds [m/s], times [s] simulated."""

    path: Path
    speeds: Tuple[float, ...]
    seeds: Tuple[int, ...]
    controllers: Tuple[ControllerConfig, ...]
    duration: float
    transient: float = 60.0
    turbulence_class: str = "B"
    shear_exponent: float = 0.2
    site: WindDistribution = WindDistribution(IEC_CLASS_MEAN_SPEED["I"])
    turbine: str = ""
    """Every graph's ``turbine`` argument: a packaged name or an absolute path ('': each graph's default)."""
    dlc: str = "1.2"
    fault: str = ""
    """A DLC 2.x's fault of every case (a :mod:`hawt_plant.faults` entry without ``at=``; '' for the others)."""


class _Reader:
    """Checks of one campaign file's values, each error naming the file and line of the key."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def fail(self, line: int, message: str) -> None:
        raise CampaignError(f"{self.path}:{line}: {message}")

    def mapping(self, value: Any, line: int, where: str, keys: str) -> Mapping:
        if not isinstance(value, dict):
            self.fail(line, f"{where or 'the file'}: expected a mapping of keys, found {value!r}")
        for key in value:
            if key not in _KEYS[keys]:
                self.fail(_line(value, key), f"{_join(where, key)}: unknown key" + did_you_mean(key, _KEYS[keys]))
        for key in _REQUIRED.get(keys, ()):
            if key not in value:
                self.fail(getattr(value, "line", line), f"{where or 'the file'}: missing key {key!r}")
        return value

    def number(self, value: Any, line: int, what: str, minimum: float, maximum: float = float("inf")) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not minimum <= value <= maximum:
            bound = f"from {minimum:g} to {maximum:g}" if maximum < float("inf") else f"at least {minimum:g}"
            self.fail(line, f"{what}: expected a number {bound}, found {value!r}")
        return float(value)

    def choice(self, value: Any, line: int, what: str, choices: Tuple[str, ...]) -> str:
        if str(value) not in choices:
            self.fail(line, f"{what}: {value!r} is not one of {', '.join(choices)}" + did_you_mean(str(value), choices))
        return str(value)


def _line(mapping: Any, key: str) -> int:
    return getattr(mapping, "key_lines", {}).get(key, getattr(mapping, "line", 0))


def _join(where: str, key: str) -> str:
    return f"{where}.{key}" if where else key


def load_campaign(path: Path) -> Campaign:
    """Read and check a campaign file of one DLC (module notes); :func:`load_campaigns` reads one of several.

    Raises
    ------
    CampaignError
        Naming file, line and key: unknown or missing keys, values of the wrong type or out of range, or a file
        of several DLCs.
    """
    campaigns = load_campaigns(path)
    if len(campaigns) > 1:
        raise CampaignError(f"{path}: {len(campaigns)} DLCs ({', '.join(c.dlc for c in campaigns)}): expected one here")
    return campaigns[0]


def load_campaigns(path: Path) -> Tuple[Campaign, ...]:
    """Read and check a campaign file (module notes): one campaign, or one per DLC where ``dlc`` maps DLCs to their
    ``speeds``, ``seeds`` and ``fault`` (each defaulting to the file's ``wind.speeds``, ``wind.seeds`` and the DLC's
    own fault); everything else is shared. The graphs are checked by :func:`hawt_tools.campaign.plan_cases`.

    Raises
    ------
    CampaignError
        Naming file, line and key: unknown or missing keys, values of the wrong type or out of range.
    """
    path = Path(path)
    try:
        data = load_marked_yaml(path)
    except GraphError as error:
        raise CampaignError(str(error)) from None
    read = _Reader(path)
    top = read.mapping(data, 1, "", "")
    wind = read.mapping(top["wind"], _line(top, "wind"), "wind", "wind")
    dlcs = top.get("dlc", "1.2")
    if not isinstance(dlcs, dict):
        return (_campaign(read, top, wind, _dlc_text(dlcs), _line(top, "dlc"),
                          {key: _setting(mapping, key, where) for key, mapping, where in
                           (("speeds", wind, "wind"), ("seeds", wind, "wind"), ("fault", top, ""))}),)
    if not dlcs:
        read.fail(_line(top, "dlc"), "dlc: expected a DLC or a mapping DLC: {speeds, seeds, fault}, found {}")
    if "fault" in top:
        read.fail(_line(top, "fault"), "fault: with several DLCs, each DLC 2.x takes its fault in its entry")
    campaigns = []
    for key, entry in dlcs.items():
        where = f"dlc.{_dlc_text(key)}"
        entry = read.mapping(entry if entry is not None else {}, _line(dlcs, key), where, "dlc")
        settings = {name: _setting(wind, name, "wind") if name in wind and name not in entry
                    else _setting(entry, name, where) for name in ("speeds", "seeds", "fault")}
        campaigns.append(_campaign(read, top, wind, _dlc_text(key), _line(dlcs, key), settings))
    if len({c.dlc for c in campaigns}) < len(campaigns):
        read.fail(_line(top, "dlc"), "dlc: a DLC named twice")
    return tuple(campaigns)


def _setting(mapping: Mapping, key: str, where: str) -> Tuple[Any, int, str]:
    """A key's value (None where it is not given), its line and its name in errors."""
    return mapping.get(key), _line(mapping, key), _join(where, key)


def _campaign(read: _Reader, top: Mapping, wind: Mapping, dlc_value: str, dlc_line: int,
              settings: Mapping[str, Tuple[Any, int, str]]) -> Campaign:
    """One DLC's campaign: its ``speeds``, ``seeds`` and ``fault`` from ``settings`` (:func:`_setting`), the rest
    from the file's ``top`` and ``wind``."""
    dlc = read.choice(dlc_value, dlc_line, "dlc", tuple(DLCS))
    site = _site(read, top.get("site", {}), _line(top, "site"))
    speeds = _speeds(read, top, dlc, dlc_line, settings["speeds"], site)
    transients = DLCS[dlc].transients
    value, line, name = settings["seeds"]
    seeds = _seeds(read, len(transients) or 1 if value is None else value, line, name)
    if transients and not set(seeds) <= set(range(1, len(transients) + 1)):
        read.fail(line, f"{name}: DLC {dlc} has {len(transients)} cases per speed (" + ", ".join(
            f"{i} {DLCS[dlc].label(i)}" for i in range(1, len(transients) + 1)) + f"), found {list(seeds)}")
    if dlc == "1.1" and len(seeds) < _EXTRAPOLATION_SEEDS:
        read.fail(line, f"{name}: DLC 1.1 extrapolates each bin's run maxima, which needs at least "
                  f"{_EXTRAPOLATION_SEEDS} seeds per bin, found {len(seeds)}")
    duration = read.number(top["duration"], _line(top, "duration"), "duration", 10.0, 36000.0)
    transient = read.number(top.get("transient", 60.0), _line(top, "transient"), "transient", 0.0, 3600.0)
    controllers = top["controllers"]
    if not isinstance(controllers, dict) or not controllers:
        read.fail(_line(top, "controllers"), "controllers: expected a mapping NAME: {graph: GRAPH, ...}, found "
                  f"{controllers!r}")
    turbine = _turbine(read, top.get("turbine", ""), _line(top, "turbine"))
    if (transients and not DLCS[dlc].extreme_wind or DLCS[dlc].fault) and duration < GUST_START + 20.0:
        what = "transient starts" if transients else "fault acts"
        read.fail(_line(top, "duration"), f"duration: DLC {dlc}'s {what} {GUST_START:g} s into the analysed time "
                  f"and its loads follow for up to 12 s: expected at least {GUST_START + 20.0:g} s, found {duration:g}")
    value, line, name = settings["fault"]
    fault = _fault(read, DLCS[dlc].fault if value is None else value, line, dlc, name)
    return Campaign(
        path=read.path, speeds=speeds, seeds=seeds, duration=duration, transient=transient, turbine=turbine, dlc=dlc,
        fault=fault,
        controllers=tuple(_controller(read, name, entry, _line(controllers, name), turbine)
                          for name, entry in controllers.items()),
        turbulence_class=read.choice(wind.get("turbulence_class", "B"), _line(wind, "turbulence_class"),
                                     "wind.turbulence_class", TURBULENCE_CLASSES),
        shear_exponent=read.number(wind.get("shear_exponent", 0.2), _line(wind, "shear_exponent"),
                                   "wind.shear_exponent", -0.5, 0.99),
        site=site)


def _speeds(read: _Reader, top: Mapping, dlc: str, dlc_line: int, setting: Tuple[Any, int, str],
            site: WindDistribution) -> Tuple[float, ...]:
    """A DLC's bin speeds [m/s]: its ``speeds`` (or the file's ``wind.speeds``), increasing, in the plant's range; an
    extreme wind DLC's the one of its model for the site's class (an entry of its own giving speeds is refused)."""
    speeds, line, name = setting
    wind = DLCS[dlc].extreme_wind
    if wind:
        if speeds is not None and name.startswith("dlc"):
            read.fail(line, f"{name}: DLC {dlc} runs in the {wind.upper()} of the site's class: it takes no speeds")
        return (extreme_wind_speed(site_wind_class(site), int(wind.removeprefix("ewm"))),)
    if speeds is None:
        read.fail(dlc_line if name.startswith("dlc") else _line(top, "wind"),
                  f"{name.rpartition('.')[0]}: missing key 'speeds'")
    if not isinstance(speeds, list) or not speeds:
        read.fail(line, f"{name}: expected a list of wind speeds [m/s], found {speeds!r}")
    speeds = tuple(read.number(v, line, name, 3.0, 30.0) for v in speeds)
    if any(b <= a for a, b in zip(speeds, speeds[1:])):
        read.fail(line, f"{name}: expected increasing speeds, found {list(speeds)}")
    return speeds


def site_wind_class(site: WindDistribution) -> str:
    """The IEC wind class whose annual mean speed the site has (the ETM's V_ave); class I for any other site."""
    return next((name for name, mean in IEC_CLASS_MEAN_SPEED.items() if mean == site.mean), "I")


def _fault(read: _Reader, value: Any, line: int, dlc: str, name: str = "fault") -> str:
    """The campaign's fault entry, checked as the plant checks its ``faults`` entries (a blade number against the
    turbine's blades when the graphs are checked, before any case runs)."""
    if not DLCS[dlc].fault:
        if value:
            read.fail(line, f"{name}: DLC {dlc} has no fault; faults belong to DLC " +
                      " and ".join(name for name, case in DLCS.items() if case.fault))
        return ""
    if not isinstance(value, str) or "at=" in value:
        read.fail(line, f"{name}: expected one fault entry 'KIND key=value ...' without at= (the DLC times it), "
                  f"found {value!r}")
    try:
        parse_faults([f"{value} at=0"], 0.01)
    except ParameterError as error:
        read.fail(line, f"{name}: {str(error).removeprefix('faults: ')}")
    return value.strip()


def _dlc_text(value: Any) -> str:
    """A DLC as IEC numbers it: YAML reads ``dlc: 1.3`` as the number 1.3."""
    return f"{value:g}" if isinstance(value, float) else str(value)


def _turbine(read: _Reader, value: Any, line: int) -> str:
    """The campaign's turbine as every engine takes it (:func:`hawt_tools.graph_file.resolve_turbine`)."""
    if not isinstance(value, str):
        read.fail(line, f"turbine: expected a packaged turbine's name or a turbine's folder or file, found {value!r}")
    try:
        return resolve_turbine(value, f"{read.path}:{line}") if value else ""
    except GraphError as error:
        raise CampaignError(str(error)) from None


def _seeds(read: _Reader, value: Any, line: int, name: str = "wind.seeds") -> Tuple[int, ...]:
    if isinstance(value, int) and not isinstance(value, bool) and value >= 1:
        return tuple(range(1, value + 1))
    if isinstance(value, list) and value and all(isinstance(v, int) and not isinstance(v, bool) and v >= 0
                                                 for v in value) and len(set(value)) == len(value):
        return tuple(value)
    read.fail(line, f"{name}: expected a count (1 or more) or a list of distinct seeds >= 0, found {value!r}")


def _site(read: _Reader, value: Any, line: int) -> WindDistribution:
    site = read.mapping(value, line, "site", "site")
    if "wind_class" in site:
        if "mean" in site:
            read.fail(_line(site, "mean"), "site: give wind_class or mean, not both")
        mean = IEC_CLASS_MEAN_SPEED[read.choice(site["wind_class"], _line(site, "wind_class"), "site.wind_class",
                                                tuple(IEC_CLASS_MEAN_SPEED))]
    else:
        mean = read.number(site.get("mean", IEC_CLASS_MEAN_SPEED["I"]), _line(site, "mean"), "site.mean", 1.0, 30.0)
    return WindDistribution(mean, read.number(site.get("shape", 2.0), _line(site, "shape"), "site.shape", 0.5, 10.0))


def _controller(read: _Reader, name: Any, entry: Any, line: int, turbine: str) -> ControllerConfig:
    where = f"controllers.{name}"
    if not isinstance(name, str) or not name.replace("_", "").replace("-", "").isalnum():
        read.fail(line, f"{where}: a controller name is letters, digits, _ and -")
    entry = read.mapping(entry, line, where, "controller")
    if not isinstance(entry["graph"], str) or not entry["graph"]:
        read.fail(_line(entry, "graph"), f"{where}.graph: expected a graph name or file, found {entry['graph']!r}")
    arguments = entry.get("arguments", {})
    if not isinstance(arguments, dict) or any(isinstance(v, (dict, list)) for v in arguments.values()):
        read.fail(_line(entry, "arguments"), f"{where}.arguments: expected a mapping NAME: VALUE, found {arguments!r}")
    if turbine and "turbine" in arguments:
        read.fail(_line(arguments, "turbine"), f"{where}.arguments.turbine: the campaign's turbine is every "
                  "controller's; a campaign compares controllers on one turbine")
    parameters = entry.get("parameters", [])
    if not isinstance(parameters, list) or not all(isinstance(p, str) and ":=" in p for p in parameters):
        read.fail(_line(entry, "parameters"), f"{where}.parameters: expected a list of 'NODE.PARAM:=VALUE', found "
                  f"{parameters!r}")
    return ControllerConfig(name, entry["graph"], tuple((str(k), _text(v)) for k, v in arguments.items()),
                            tuple(parameters), line)


def _text(value: Any) -> str:
    """A launch argument as the command line gives it (true/false for YAML booleans)."""
    return str(value).lower() if isinstance(value, bool) else str(value)


def graph_arguments(campaign: Campaign, config: ControllerConfig) -> Dict[str, str]:
    """The launch arguments of a controller's graph in every case: its own and the campaign's ``turbine``."""
    return {**dict(config.arguments), **({"turbine": campaign.turbine} if campaign.turbine else {})}


def case_overrides(campaign: Campaign, speed: float, seed: int) -> List[str]:
    """The ``-p`` texts that set the plant's wind and duration for the case (speed, seed)."""
    total = campaign.transient + campaign.duration  # the plant makes its turbulent field at least this long
    dlc = DLCS[campaign.dlc]
    if dlc.extreme_wind:  # the speed is the model's, beyond the operating range of wind_speed
        return [f"plant.wind_type:={dlc.extreme_wind}", "plant.rotor:=idling",
                f"plant.yaw_misalignment:={math.radians(dlc.yaw[seed - 1])!r}",
                f"plant.wind_class:={site_wind_class(campaign.site)}", f"plant.duration:={total!r}"]
    if dlc.transients:
        kind, sign = dlc.transients[seed - 1]
        wind = [f"plant.wind_type:={kind}", f"plant.gust_sign:={sign}",
                f"plant.step_time:={campaign.transient + GUST_START!r}"]
    else:
        wind = ["plant.wind_type:=turbulent", f"plant.seed:={seed}", f"plant.turbulence_model:={dlc.turbulence_model}"]
    if campaign.fault:
        wind.append(f"plant.faults:=['{campaign.fault} at={dlc.fault_time(campaign.transient, seed)!r}']")
    return [*wind, f"plant.wind_speed:={speed!r}", f"plant.turbulence_class:={campaign.turbulence_class}",
            f"plant.wind_class:={site_wind_class(campaign.site)}",
            f"plant.shear_exponent:={campaign.shear_exponent!r}", f"plant.duration:={total!r}"]
