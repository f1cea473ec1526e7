"""The discon controller's input file checked before anything starts (issue 31 item 3): a turbine folder whose
DISCON.IN names a rotor performance file (PerfFileName) that is not there, or lacks a setting hawt sets in the
controller's private copy, is one line and exit 2 in ``hawt run``, ``hawt launch`` and ``hawt campaign``, never a
traceback or a node failing after the start."""
import shutil
import subprocess

import pytest

from hawt_controllers.design.tunings import tuning_file

CAMPAIGN = """\
wind: {{speeds: [12], seeds: [1]}}
duration: 10
controllers:
  rosco: {{graph: rosco, arguments: {{turbine: "{turbine}"}}}}
"""


@pytest.mark.parametrize("command", [
    ["run", "rosco", "turbine:={turbine}", "--record", "{out}"],
    ["launch", "rosco", "turbine:={turbine}", "--record", "{out}"],
    ["campaign", "{campaign}", "-o", "{out}"],
], ids=["run", "launch", "campaign"])
@pytest.mark.parametrize("discon, reason", [
    ("without its Cp file", "PerfFileName {turbine}/Cp_Ct_Cq.NREL5MW.txt: no such file"),
    ("without LoggingLevel", "no setting LoggingLevel"),
])
def test_a_turbine_whose_discon_input_rosco_cannot_run_is_refused_by_every_engine_before_anything_starts(
        hawt_cli, imported_deck, tmp_path, command, discon, reason):
    """The imported NREL 5 MW with its cpc tuning and, as DISCON.IN, the rosco wheel's copied without the Cp/Ct/Cq
    file it names (relative to it), or with that file and without its LoggingLevel line: exit 2, one line naming
    ``rosco``'s ``infile`` and what is wrong; nothing printed or written before it."""
    turbine = shutil.copytree(imported_deck("NREL-5MW/NREL-5MW.fst"), tmp_path / "turbine")
    shutil.copy(tuning_file("nrel_5mw", "cpc"), turbine / "cpc.yaml")
    deck = tuning_file("nrel_5mw", "discon")
    lines = deck.read_text().splitlines(True)
    if discon == "without LoggingLevel":
        shutil.copy(deck.with_name("Cp_Ct_Cq.NREL5MW.txt"), turbine)
        lines = [line for line in lines if "! LoggingLevel" not in line]
    (turbine / "DISCON.IN").write_text("".join(lines))
    campaign = tmp_path / "campaign.yaml"
    campaign.write_text(CAMPAIGN.format(turbine=turbine))
    places = {"turbine": turbine, "out": tmp_path / "out", "campaign": campaign}
    result = subprocess.run([*hawt_cli, *(word.format(**places) for word in command)], capture_output=True,
                            text=True, timeout=120)
    assert result.returncode == 2, result.stdout[-2000:] + result.stderr[-2000:]
    assert result.stderr.startswith(f"hawt {command[0]}: ") and len(result.stderr.strip().splitlines()) == 1
    assert f"node rosco: infile: {turbine}/DISCON.IN: {reason.format(turbine=turbine)}" in result.stderr, \
        result.stderr
    assert result.stdout == "" and not (tmp_path / "out").exists()
