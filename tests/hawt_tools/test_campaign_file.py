"""Campaign files are checked before anything runs: a typo or a bad value is one line naming file, line and key,
and `hawt campaign` exits 2 without starting a worker."""
import subprocess
import textwrap
from pathlib import Path

import pytest

from hawt_analysis.lifetime import WindDistribution
from hawt_tools.campaign import case_graph, plan_cases
from hawt_tools.campaign_file import CampaignError, case_overrides, load_campaign, load_campaigns
from hawt_tools.graph_file import ParameterFile
from turbine_folders import copied_turbine

GOOD = """\
wind:
  speeds: [13, 18]
  seeds: 2
  turbulence_class: A
site: {mean: 8.5, shape: 2.2}
duration: 20
transient: 5
controllers:
  baseline: {graph: baseline}
  ipc_1p: {graph: ipc, arguments: {ipc_h2: false, ipc_h3: false}, parameters: ["ipc_h1.integral_gain:=2e-08"]}
"""


def _write(tmp_path, text: str):
    path = tmp_path / "campaign.yaml"
    path.write_text(textwrap.dedent(text))
    return path


def test_a_good_file_gives_every_case_once_with_a_key_of_what_defines_it(tmp_path):
    campaign = load_campaign(_write(tmp_path, GOOD))
    assert campaign.speeds == (13.0, 18.0) and campaign.seeds == (1, 2) and campaign.turbulence_class == "A"
    assert campaign.site == WindDistribution(8.5, 2.2) and (campaign.duration, campaign.transient) == (20.0, 5.0)
    assert campaign.controllers[1].arguments == (("ipc_h2", "false"), ("ipc_h3", "false"))
    cases = plan_cases(campaign)
    assert [(c.controller.name, c.speed, c.seed) for c in cases] == [
        (name, speed, seed) for name in ("baseline", "ipc_1p") for speed in (13.0, 18.0) for seed in (1, 2)]
    assert len({c.key for c in cases}) == 8
    changed = load_campaign(_write(tmp_path, GOOD.replace("integral_gain:=2e-08", "integral_gain:=3e-08")))
    again = plan_cases(changed)
    assert [a.key == b.key for a, b in zip(cases, again)] == [True] * 4 + [False] * 4, \
        "a parameter of one controller changes the keys of its cases only"


@pytest.mark.parametrize("text, message", [
    (GOOD.replace("  speeds:", "  speds:"), "campaign.yaml:2: wind.speds: unknown key (did you mean 'speeds'?)"),
    (GOOD.replace("[13, 18]", "[13, 45]"), "campaign.yaml:2: wind.speeds: expected a number from 3 to 30, found 45"),
    (GOOD.replace("[13, 18]", "[18, 13]"), "campaign.yaml:2: wind.speeds: expected increasing speeds"),
    (GOOD.replace("seeds: 2", "seeds: [1, 1]"), "campaign.yaml:3: wind.seeds: expected a count"),
    (GOOD.replace("class: A", "class: D"), "campaign.yaml:4: wind.turbulence_class: 'D' is not one of A, B, C"),
    (GOOD.replace("duration: 20", "duration: -1"), "campaign.yaml:6: duration: expected a number from 10"),
    (GOOD.replace("duration: 20\n", ""), "campaign.yaml:1: the file: missing key 'duration'"),
    (GOOD.replace("{mean: 8.5, shape: 2.2}", "{wind_class: IV}"), "campaign.yaml:5: site.wind_class: 'IV' is not"),
    (GOOD.replace("{graph: baseline}", "{grahp: baseline}"),
     "campaign.yaml:9: controllers.baseline.grahp: unknown key (did you mean 'graph'?)"),
    (GOOD.replace("{graph: baseline}", "{graph: baselin}"), "campaign.yaml:9: controllers.baseline: baselin: no"),
    (GOOD.replace("ipc_h2: false", "ipc_h7: false"), "campaign.yaml:10: controllers.ipc_1p: "),
    (GOOD.replace("integral_gain:=2e-08", "integral_gian:=2e-08"), "campaign.yaml:10: controllers.ipc_1p: "),
    (GOOD.replace("integral_gain:=2e-08", "integral_gain:=nan"), "campaign.yaml:10: controllers.ipc_1p: "),
    ("wind: {speeds: [5]\n", "campaign.yaml:2:1: YAML error"),
    ("turbine: iea15\n" + GOOD, "campaign.yaml:1: turbine 'iea15': no packaged turbine of that name (packaged: "),
    ("turbine: nrel_5mw\n" + GOOD.replace("ipc_h2: false", "turbine: nrel_5mw, ipc_h2: false"),
     "campaign.yaml:11: controllers.ipc_1p.arguments.turbine: the campaign's turbine is every controller's"),
    ("dlc: 1.6\n" + GOOD, "campaign.yaml:1: dlc: '1.6' is not one of 1.1, 1.2, 1.3, 1.4, 1.5"),
    ("dlc: 1.1\n" + GOOD, "campaign.yaml:4: wind.seeds: DLC 1.1 extrapolates each bin's run maxima, which needs at "
                          "least 3 seeds per bin, found 2"),
], ids=["key typo", "speed range", "speed order", "seeds", "class", "duration", "missing", "site", "controller key",
        "graph", "argument", "parameter name", "parameter value", "yaml", "turbine", "a controller's own turbine",
        "dlc", "dlc 1.1 seeds"])
def test_a_bad_file_is_one_line_naming_file_line_and_key(tmp_path, text, message):
    with pytest.raises(CampaignError) as raised:
        plan_cases(load_campaign(_write(tmp_path, text)))
    assert message in str(raised.value) and "\n" not in str(raised.value)


def test_the_dlc_sets_every_cases_turbulence_model_and_is_in_its_key(tmp_path):
    """DLC 1.2 by default (normal turbulence); `dlc: 1.3` runs every case in the extreme turbulence model with the
    site's wind class (the class whose annual mean the site has, else I), and no case keeps its 1.2 key."""
    fatigue, extreme = (load_campaign(_write(tmp_path, text)) for text in (GOOD, "dlc: 1.3\n" + GOOD))
    assert (fatigue.dlc, extreme.dlc) == ("1.2", "1.3")
    assert "plant.turbulence_model:=NTM" in case_overrides(fatigue, 13.0, 1)
    assert {"plant.turbulence_model:=ETM", "plant.wind_class:=II"} <= set(case_overrides(extreme, 13.0, 1))  # 8.5
    for site, wind_class in (("{wind_class: III}", "III"), ("{mean: 9.0}", "I")):
        other = load_campaign(_write(tmp_path, "dlc: 1.3\n" + GOOD.replace("{mean: 8.5, shape: 2.2}", site)))
        assert f"plant.wind_class:={wind_class}" in case_overrides(other, 13.0, 1)
    assert not {c.key for c in plan_cases(fatigue)} & {c.key for c in plan_cases(extreme)}


@pytest.mark.parametrize("dlc, cases", [
    ("1.4", [("ecd", 1), ("ecd", -1)]),
    ("1.5", [("ews_vertical", 1), ("ews_vertical", -1), ("ews_horizontal", 1), ("ews_horizontal", -1)]),
])
def test_a_transient_dlc_runs_each_of_its_gusts_at_every_speed_starting_in_the_analysed_time(tmp_path, dlc, cases):
    """DLC 1.4 (ECD) and 1.5 (EWS): without `seeds`, every case of the DLC per speed, each its wind type and sign,
    starting GUST_START s after the transient; no turbulence seed."""
    campaign = load_campaign(_write(tmp_path, f"dlc: {dlc}\n" + GOOD.replace("  seeds: 2\n", "").replace(
        "duration: 20", "duration: 40")))
    assert campaign.seeds == tuple(range(1, len(cases) + 1))
    for seed, (kind, sign) in enumerate(cases, start=1):
        overrides = case_overrides(campaign, 13.0, seed)
        assert {f"plant.wind_type:={kind}", f"plant.gust_sign:={sign}", "plant.step_time:=15.0",
                "plant.wind_speed:=13.0"} <= set(overrides)
        assert not [o for o in overrides if o.startswith("plant.seed:=")]


@pytest.mark.parametrize("text, message", [
    ("dlc: 1.4\n" + GOOD.replace("seeds: 2", "seeds: [3]").replace("duration: 20", "duration: 40"),
     "campaign.yaml:4: wind.seeds: DLC 1.4 has 2 cases per speed (1 ECD +, 2 ECD -), found [3]"),
    ("dlc: 1.5\n" + GOOD, "campaign.yaml:7: duration: DLC 1.5's transient starts 10 s into the analysed time and "
                          "its loads follow for up to 12 s: expected at least 30 s, found 20"),
    ("dlc: 2.1\n" + GOOD, "campaign.yaml:7: duration: DLC 2.1's fault acts 10 s into the analysed time and its loads "
                          "follow for up to 12 s: expected at least 30 s, found 20"),
])
def test_a_transient_dlc_refuses_cases_it_does_not_have_and_a_window_too_short(tmp_path, text, message):
    with pytest.raises(CampaignError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")
                       .replace("]", r"\]").replace("+", r"\+")):
        load_campaign(_write(tmp_path, text))


def test_dlc_2_1_runs_normal_turbulence_with_a_control_system_fault_in_the_analysed_time(tmp_path):
    """DLC 2.1: every seed in normal turbulence, blade 1's pitch running away to feather by default, GUST_START s
    into the analysed time (transient 5 s: at 15 s); `fault:` names another; the cases are not 1.2's."""
    long = GOOD.replace("duration: 20", "duration: 40")
    default, grid = (load_campaign(_write(tmp_path, "dlc: 2.1\n" + extra + long)) for extra in ("", "fault: grid_loss\n"))
    overrides = case_overrides(default, 13.0, 2)
    assert {"plant.wind_type:=turbulent", "plant.seed:=2", "plant.turbulence_model:=NTM",
            "plant.faults:=['pitch_runaway blade=1 to=feather at=15.0']"} <= set(overrides)
    assert "plant.faults:=['grid_loss at=15.0']" in case_overrides(grid, 13.0, 1)
    fatigue = load_campaign(_write(tmp_path, long))
    assert not {c.key for c in plan_cases(default)} & {c.key for c in plan_cases(fatigue)}


def test_dlc_2_3_loses_the_grid_at_the_start_the_dip_and_the_peak_of_an_extreme_operating_gust(tmp_path):
    campaign = load_campaign(_write(tmp_path, "dlc: 2.3\n" + GOOD.replace("  seeds: 2\n", "").replace(
        "duration: 20", "duration: 40")))
    assert campaign.seeds == (1, 2, 3)
    for seed, at in ((1, 15.0), (2, 17.46), (3, 20.25)):
        assert {"plant.wind_type:=eog", "plant.step_time:=15.0", f"plant.faults:=['grid_loss at={at!r}']"} <= set(
            case_overrides(campaign, 13.0, seed))


def test_dlc_6_runs_an_idling_rotor_in_the_extreme_wind_of_the_sites_class_one_case_per_yaw_misalignment(tmp_path):
    """DLC 6.1: the 50-year wind (70 m/s at the hub for class I; 59.5 m/s for a site of class II's mean, 8.5 m/s) at
    -15 and +15 deg;
    6.2: with the grid lost, from -135 to 180 deg every 45 deg; 6.3: the 1-year wind at -30 and +30 deg. The rotor
    idles (blades at feather, generator off), the speed is the model's and is not a plant parameter; the file's
    speeds do not apply, and a DLC 6.x entry of its own giving speeds is refused."""
    several = GOOD.replace("  seeds: 2\n", "").replace("site: {mean: 8.5, shape: 2.2}", "site: {wind_class: I}")
    dlc61, dlc62, dlc63 = load_campaigns(_write(tmp_path, "dlc: {6.1: , 6.2: , 6.3: }\n" + several))
    assert (dlc61.speeds, dlc61.seeds, dlc62.seeds) == ((70.0,), (1, 2), tuple(range(1, 9)))
    assert dlc63.speeds == (pytest.approx(56.0),)
    overrides = case_overrides(dlc61, 70.0, 2)
    assert {"plant.wind_type:=ewm50", "plant.rotor:=idling", "plant.yaw_misalignment:=0.2617993877991494",
            "plant.wind_class:=I"} <= set(overrides)
    assert not any(text.startswith("plant.wind_speed") for text in overrides)
    assert "plant.yaw_misalignment:=3.141592653589793" in case_overrides(dlc62, 70.0, 8)
    assert "plant.wind_type:=ewm1" in case_overrides(dlc63, 56.0, 1)
    class_ii = load_campaign(_write(tmp_path, "dlc: 6.1\n" + GOOD))
    assert class_ii.speeds == (pytest.approx(59.5),) and "plant.wind_class:=II" in case_overrides(class_ii, 59.5, 1)
    with pytest.raises(CampaignError, match=r"campaign.yaml:1: dlc.6.1.speeds: DLC 6.1 runs in the EWM50 of the "
                                            "site's class: it takes no speeds"):
        load_campaigns(_write(tmp_path, "dlc: {6.1: {speeds: [50]}}\n" + several))
    assert {c.key for c in plan_cases(dlc61)}.isdisjoint({c.key for c in plan_cases(dlc63)})


@pytest.mark.parametrize("text, message", [
    ("dlc: 1.3\nfault: grid_loss\n", "campaign.yaml:2: fault: DLC 1.3 has no fault; faults belong to DLC 2.1 and 2.3"),
    ("dlc: 2.1\nfault: grid_loss at=30\n", "campaign.yaml:2: fault: expected one fault entry 'KIND key=value ...' "
                                           "without at= (the DLC times it), found 'grid_loss at=30'"),
    ("dlc: 2.1\nfault: pitch_runaway blade=1 to=fien\n", "campaign.yaml:2: fault: entry 'pitch_runaway blade=1 "
                                                        "to=fien at=0': to: expected feather or fine, found 'fien'"),
])
def test_a_fault_is_checked_in_the_file_with_its_line(tmp_path, text, message):
    with pytest.raises(CampaignError) as raised:
        load_campaign(_write(tmp_path, text + GOOD.replace("duration: 20", "duration: 40")))
    assert str(raised.value) == str(tmp_path / message)


def test_a_fault_on_a_blade_the_turbine_lacks_is_refused_before_any_wind(tmp_path):
    campaign = load_campaign(_write(tmp_path, "dlc: 2.1\nfault: pitch_stuck blade=4\n" + GOOD.replace(
        "duration: 20", "duration: 40")))
    with pytest.raises(CampaignError, match="blade"):
        plan_cases(campaign)


def test_the_command_refuses_a_bad_file_in_one_line_with_exit_2(tmp_path, hawt_cli):
    path = _write(tmp_path, GOOD.replace("integral_gain:=2e-08", "integral_gian:=2e-08"))
    result = subprocess.run([*hawt_cli, "campaign", str(path), "-o", str(tmp_path / "out")], capture_output=True,
                            text=True, timeout=120)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "integral_gian" in result.stderr and not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["dlc12.yaml", "two_bladed_ac17.yaml", "ultimate.yaml"])
def test_the_shipped_campaign_files_are_valid(name):
    for campaign in load_campaigns(Path(__file__).resolve().parents[2] / "campaigns" / name):
        assert len(plan_cases(campaign)) == len(campaign.controllers) * len(campaign.speeds) * len(campaign.seeds)


SEVERAL = """\
dlc:
  1.4: {speeds: [9.4, 11.4]}
  2.1: {seeds: [4], fault: grid_loss}
  2.3:
wind: {speeds: [13, 18], seeds: 2}
duration: 40
transient: 5
controllers:
  baseline: {graph: baseline}
"""


def test_a_file_of_several_dlcs_is_a_campaign_each_with_its_own_speeds_seeds_and_fault(tmp_path):
    """Each DLC's entry gives its speeds, seeds and fault; what it leaves out is the file's wind.speeds and
    wind.seeds (a transient DLC: all its cases) and the DLC's own fault; the rest is shared."""
    gusts, faulted, grid = load_campaigns(_write(tmp_path, SEVERAL))
    assert (gusts.dlc, gusts.speeds, gusts.seeds, gusts.fault) == ("1.4", (9.4, 11.4), (1, 2), "")
    assert (faulted.dlc, faulted.speeds, faulted.seeds, faulted.fault) == ("2.1", (13.0, 18.0), (4,), "grid_loss")
    assert (grid.dlc, grid.speeds, grid.seeds, grid.fault) == ("2.3", (13.0, 18.0), (1, 2), "grid_loss")
    assert {gusts.duration, faulted.transient, grid.controllers[0].graph} == {40.0, 5.0, "baseline"}
    with pytest.raises(CampaignError, match="3 DLCs"):
        load_campaign(_write(tmp_path, SEVERAL))


@pytest.mark.parametrize("text, message", [
    (SEVERAL.replace("{seeds: [4], fault: grid_loss}", "{seeds: [4], fualt: grid_loss}"),
     "campaign.yaml:3: dlc.2.1.fualt: unknown key (did you mean 'fault'?)"),
    (SEVERAL.replace("  2.3:\n", "  1.3: {fault: grid_loss}\n"),
     "campaign.yaml:4: dlc.1.3.fault: DLC 1.3 has no fault; faults belong to DLC 2.1 and 2.3"),
    ("fault: grid_loss\n" + SEVERAL, "campaign.yaml:1: fault: with several DLCs, each DLC 2.x takes its fault in its "
                                     "entry"),
    (SEVERAL.replace("wind: {speeds: [13, 18], seeds: 2}", "wind: {seeds: 2}"),
     "campaign.yaml:3: dlc.2.1: missing key 'speeds'"),
    (SEVERAL.replace("  2.3:\n", "  1.40: {}\n"), "campaign.yaml:4: duplicate key 1.4"),
    (SEVERAL.replace("  2.3:\n", "  '1.4': {}\n"), "campaign.yaml:1: dlc: a DLC named twice"),
])
def test_a_bad_dlc_entry_is_one_line_naming_its_line_and_key(tmp_path, text, message):
    with pytest.raises(CampaignError) as raised:
        load_campaigns(_write(tmp_path, text))
    assert str(raised.value) == str(tmp_path / message)


def _parameter_files(graph):
    """Node name -> the files its parameters read or name: parameter files and inline values that are files."""
    files = {}
    for node in graph.nodes:
        for source in node.parameters:
            found = [source.path] if isinstance(source, ParameterFile) else [
                Path(value) for _, value in source.values if isinstance(value, str) and Path(value).is_file()]
            files.setdefault(node.name, []).extend(found)
    return files


def test_a_campaign_turbine_folder_reaches_the_controllers(tmp_path, monkeypatch):
    """``turbine: FOLDER`` (relative to the working directory, as a graph's turbine:=) is every case's graph argument:
    the plant gets the folder and each controller the folder's tuning; a case's key changes with the folder's
    definition and with its tunings."""
    folder = copied_turbine(tmp_path / "my_turbine")
    monkeypatch.chdir(tmp_path)
    campaign = load_campaign(_write(tmp_path, "turbine: my_turbine\n" + GOOD))
    assert campaign.turbine == str(folder)
    cases = plan_cases(campaign)
    for config in campaign.controllers:
        graph = case_graph(config, campaign)
        assert graph.arguments["turbine"] == str(folder)
        files = _parameter_files(graph)
        assert dict(graph.node("plant").parameters[0].values)["turbine_file"] == str(folder)
        assert files["cpc"] == [folder / "cpc.yaml"]
        assert all(folder / "ipc.yaml" in files[name] for name in files if name.startswith("ipc_h"))
    (folder / "turbine.yaml").write_text((folder / "turbine.yaml").read_text() + "\n# edited\n")
    definition_edited = plan_cases(campaign)
    (folder / "cpc.yaml").write_text((folder / "cpc.yaml").read_text() + "\n# edited\n")
    tuning_edited = plan_cases(campaign)
    for before, after in ((cases, definition_edited), (definition_edited, tuning_edited)):
        assert not {case.key for case in before} & {case.key for case in after}


def test_a_case_on_a_campaign_turbine_folder_runs_with_the_folders_tunings(tmp_path, monkeypatch):
    """One case, 10 s of the ipc graph on a turbine folder given relative to the working directory, run in process as
    a worker runs it: it holds the rotor near the turbine's rated speed (a campaign once refused a folder)."""
    from hawt_tools.campaign import run_case

    copied_turbine(tmp_path / "my_turbine")
    monkeypatch.chdir(tmp_path)
    campaign = load_campaign(_write(tmp_path, "turbine: my_turbine\nwind: {speeds: [13]}\nduration: 10\n"
                                              "transient: 0\ncontrollers:\n  ipc: {graph: ipc}\n"))
    case, = plan_cases(campaign)
    row = run_case(case, campaign)
    assert row["controller"] == "ipc" and abs(row["rotor_speed.mean"] / 1.26711 - 1.0) < 0.05


def test_a_turbine_given_as_a_plant_parameter_is_in_the_case_key_too(tmp_path):
    """A controller whose ``parameters`` set ``plant.turbine_file`` to a definition: editing that definition changes
    its cases' keys (the key hashes the plant's turbine, however it is given)."""
    folder = copied_turbine(tmp_path / "my_turbine")
    text = GOOD.replace('"ipc_h1.integral_gain:=2e-08"', f'"plant.turbine_file:={folder}"')
    cases = plan_cases(load_campaign(_write(tmp_path, text)))
    (folder / "turbine.yaml").write_text((folder / "turbine.yaml").read_text() + "\n# edited\n")
    again = plan_cases(load_campaign(_write(tmp_path, text)))
    assert [a.key == b.key for a, b in zip(cases, again)] == [True] * 4 + [False] * 4


def test_a_campaign_turbine_may_be_a_packaged_name_or_a_definition_file(tmp_path, monkeypatch):
    copied_turbine(tmp_path / "my_turbine")
    monkeypatch.chdir(tmp_path)
    for turbine, expected in (("nrel_5mw", "nrel_5mw"), ("my_turbine/turbine.yaml",
                                                         str(tmp_path / "my_turbine" / "turbine.yaml"))):
        campaign = load_campaign(_write(tmp_path, f"turbine: {turbine}\n" + GOOD))
        assert case_graph(campaign.controllers[0], campaign).arguments["turbine"] == expected


def test_a_tuning_for_another_turbine_is_one_line_with_exit_2_before_any_wind(tmp_path, hawt_cli):
    """The issue 31 campaign: a turbine whose rated speed is not its tuning's. Every case would fail at its first
    step; the command refuses it in one line, before it prints its plan, generates a field or writes anything."""
    folder = copied_turbine(tmp_path / "other")
    definition = folder / "turbine.yaml"
    definition.write_text(definition.read_text().replace("rated_rotor_speed: 1.26711", "rated_rotor_speed: 0.79168"))
    path = _write(tmp_path, f"turbine: {folder}\n" + GOOD)
    result = subprocess.run([*hawt_cli, "campaign", str(path), "-o", str(tmp_path / "out")], capture_output=True,
                            text=True, timeout=120)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert result.stderr.startswith("hawt campaign: ") and "campaign.yaml:10: controllers.baseline: " in result.stderr
    assert "rated generator speed 122.91 rad/s conflicts with plant/description" in result.stderr
    assert result.stdout == "" and not (tmp_path / "out").exists()


def test_an_output_folder_that_cannot_be_made_is_one_line_before_any_worker(tmp_path, monkeypatch):
    """The output's ``cases`` (and with --bags its ``bags``) folder is made before the cluster starts: one that cannot
    be is a CampaignError naming it, and no worker starts."""
    from hawt_tools import campaign as campaign_module

    def refuse(*_args):
        raise AssertionError("a Dask cluster was started")

    monkeypatch.setattr(campaign_module, "_client", refuse)
    output = tmp_path / "out"
    output.mkdir()
    (output / "bags").write_text("a file where the bags would go\n")
    with pytest.raises(CampaignError, match=rf"^-o {output}: cannot create {output}/bags \(File exists\)$"):
        campaign_module.run_campaign(load_campaign(_write(tmp_path, GOOD)), output, bags=True, report=lambda _: None)
