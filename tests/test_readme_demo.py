"""The README's demo figures are a block that scripts/readme_demo.py writes from a run of the demo."""
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("readme_demo", ROOT / "scripts" / "readme_demo.py")
readme_demo = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(readme_demo)

DEMO_OUTPUT = """hawt demo: IPC 1P+2P against the baseline, 30 s of IEC class B turbulence at 18 m/s (seed 1)
ipc.mcap against baseline.mcap:
  blade-root out-of-plane DEL           -40.0 % (mean of the blades)
  power (mean)                          5.00 -> 5.00 MW
every number (DELs, harmonics, spectra, pitch activity): bags/demo/report/index.html
"""


def test_the_readme_has_one_demo_block_in_the_form_the_script_writes():
    readme = (ROOT / "README.md").read_text()
    begin, end = readme.index(readme_demo.BEGIN), readme.index(readme_demo.END)
    block = readme[begin:end + len(readme_demo.END)]
    headline = readme_demo.headline_of(block.split("```")[1].strip("\n"))
    assert readme_demo.replace_block(readme, block) == readme
    assert block.startswith(f"{readme_demo.BEGIN}\nMeasured with `./hawt demo --duration ")
    assert f"```\n{headline}\n```\n{readme_demo.END}" in block


def test_the_headline_is_taken_from_the_demos_output_and_replaces_the_block():
    headline = readme_demo.headline_of(DEMO_OUTPUT)
    assert headline.splitlines() == DEMO_OUTPUT.splitlines()[1:4]
    block = readme_demo.demo_block(headline, 30.0, 26.6, 2)
    readme = f"intro\n{readme_demo.BEGIN}\nold figures\n{readme_demo.END}\nrest\n"
    assert readme_demo.replace_block(readme, block) == f"intro\n{block}\nrest\n"
    assert "(27 s wall on 2 cores; written by `scripts/readme_demo.py`)" in block


@pytest.mark.parametrize("readme", ["no markers", f"{readme_demo.END} {readme_demo.BEGIN}",
                                    f"{readme_demo.BEGIN}{readme_demo.END}{readme_demo.BEGIN}{readme_demo.END}"])
def test_a_readme_without_exactly_one_block_is_refused(readme):
    with pytest.raises(ValueError, match="needs one"):
        readme_demo.replace_block(readme, "block")


def test_a_demo_output_without_a_headline_is_refused():
    with pytest.raises(ValueError, match="printed no line"):
        readme_demo.headline_of("hawt demo: failed\n")


def test_a_demo_output_that_cautions_about_a_run_is_refused_and_names_it():
    """A run with a lost contribution is not the demo's comparison: its numbers never reach the README."""
    caution = ("hawt demo: caution: ipc.mcap has 1 warning or error event(s), the first at t=12.30 s, mbc: "
               "contribution_lost (control/ipc/h1: nothing for step 1230 within 1 s)")
    with pytest.raises(ValueError, match="ipc.mcap has 1 warning"):
        readme_demo.headline_of(DEMO_OUTPUT + caution + "\n")
