"""Specification of hawt_analysis.campaign_report: what `hawt campaign` (and `hawt compare` of campaign folders)
prints of the lifetime loads, and its report page."""
import html
import re

from hawt_analysis.campaign_report import lifetime_text, write_campaign_report

CHANNELS = ("root_moment_oop_1", "root_moment_oop_2", "root_moment_oop_3", "root_moment_ip_1", "hub_tilt_moment",
            "hub_yaw_moment", "tower_base_fa_moment", "tower_base_ss_moment")


def _lifetime(controller: str, dels_mn_m: tuple, aep_gwh: float) -> list:
    """A controller's entries of ``hawt_tools.campaign.lifetime_table``: the DEL of each of CHANNELS, the AEP."""
    return [{"controller": controller, "quantity": f"lifetime DEL {channel}", "m": 10.0, "value": 1e6 * value,
             "cases": "all 4 cases", "missing": ""} for channel, value in zip(CHANNELS, dels_mn_m)] + [
        {"controller": controller, "quantity": "AEP [J]", "m": float("nan"), "value": 3.6e12 * aep_gwh,
         "cases": "all 4 cases", "missing": ""}]


LIFETIME = (_lifetime("baseline", (6.8, 6.7, 6.9, 9.0, 2.91, 3.02, 16.9, 5.59), 24.0)
            + _lifetime("lqg_ipc", (5.4876, 5.5, 6.8793, 8.9, 3.25, 3.19, 17.3, 5.76), 23.64))
"""Blade 1 −19.3 %, blade 3 −0.3 %: the blades do not all gain alike."""


def test_the_lifetime_table_gives_every_blade_under_a_header_that_lines_up():
    """Every blade's root out-of-plane DEL (once blade 1's −19.3 % alone, with blade 3 at −0.3 % only in
    lifetime.csv), the hub and the tower base, then the AEP; each controller's name over its values, each change
    under "change"."""
    assert lifetime_text(LIFETIME).splitlines() == [
        "                                      baseline  lqg_ipc   change",
        "blade 1 root out-of-plane DEL [MN·m]       6.8    5.488  -19.3 %",
        "blade 2 root out-of-plane DEL [MN·m]       6.7      5.5  -17.9 %",
        "blade 3 root out-of-plane DEL [MN·m]       6.9    6.879   -0.3 %",
        "hub tilt DEL [MN·m]                       2.91     3.25  +11.7 %",
        "hub yaw DEL [MN·m]                        3.02     3.19   +5.6 %",
        "tower base fore-aft DEL [MN·m]            16.9     17.3   +2.4 %",
        "tower base side-side DEL [MN·m]           5.59     5.76   +3.0 %",
        "AEP [GWh]                                   24    23.64   -1.5 %"]


def test_the_report_page_heads_each_figure_with_what_it_shows(tmp_path):
    """Not its file name: the DELs against wind speed, the lifetime changes, the pitch activity."""
    rows = [{"controller": entry["controller"], "wind_speed": speed, "seed": 1, "wohler": dict.fromkeys(CHANNELS, 10.0),
             **{f"del.{channel}": 1e6 for channel in CHANNELS}, "pitch.travel": 1.0, "pitch.max_command_rate": 0.1}
            for entry in LIFETIME[::len(CHANNELS) + 1] for speed in (12.0, 16.0)]
    page = write_campaign_report("hawt campaign: test.yaml", rows, LIFETIME, tmp_path, {}).read_text(encoding="utf-8")
    assert [html.unescape(heading) for heading in re.findall(r"<h2>(.*?)</h2>", page)] == [
        "DEL of the main channels against wind speed (mean over the seeds, each seed a dot)",
        "lifetime DEL change against baseline", "pitch activity against wind speed"]


def test_a_campaign_of_one_controller_writes_its_report_without_a_warning(tmp_path, recwarn):
    """One controller has no change to draw against itself: its lifetime figure has no bars, and no empty legend
    (matplotlib's "No artists with labels found" warning)."""
    baseline = LIFETIME[:len(CHANNELS) + 1]
    rows = [{"controller": "baseline", "wind_speed": speed, "seed": 1, "wohler": dict.fromkeys(CHANNELS, 10.0),
             **{f"del.{channel}": 1e6 for channel in CHANNELS}, "pitch.travel": 1.0, "pitch.max_command_rate": 0.1}
            for speed in (12.0, 16.0)]
    write_campaign_report("hawt campaign: one.yaml", rows, baseline, tmp_path, {})
    assert [str(w.message) for w in recwarn] == []
