"""Specification of the report pages of hawt analyze / hawt compare (hawt_analysis.analysis_report): index.html."""
from html.parser import HTMLParser
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from hawt_analysis.analysis_report import write_analysis_report, write_comparison_report
from hawt_analysis.comparison import compare_summaries
from hawt_analysis.summary import summarize
from hawt_analysis.synthetic_run import synthetic_channels


class Page(HTMLParser):
    """What a test reads of a page: the rows of its tables (cell texts), its captions, its headings, its images and
    links."""

    def __init__(self, text: str):
        super().__init__()
        self.rows, self.captions, self.headings, self.images, self.links = [], [], [], [], []
        self._cell = self._caption = self._heading = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self._cell = ""
        elif tag == "caption":
            self._caption = ""
        elif tag == "h2":
            self._heading = ""
        elif tag == "img":
            self.images.append(attrs["src"])
        elif tag == "a":
            self.links.append(attrs["href"])

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self.rows[-1].append(self._cell)
            self._cell = None
        elif tag == "caption":
            self.captions.append(self._caption)
            self._caption = None
        elif tag == "h2":
            self.headings.append(self._heading)
            self._heading = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data
        if self._caption is not None:
            self._caption += data
        if self._heading is not None:
            self._heading += data


@pytest.fixture(scope="module")
def runs():
    """Run "a" and run "b", whose blade-root out-of-plane moments are half a's: every harmonic −50 %."""
    run = synthetic_channels(duration=40.0, seed=5)
    return {"a": run, "b": {**run, "root_moment_oop": 0.5 * run["root_moment_oop"]}}


def _analysis(label: str, channels: dict) -> SimpleNamespace:
    """What the report writers read of a `hawt_analysis.run_analysis.BagAnalysis`."""
    return SimpleNamespace(path=Path(label), run=SimpleNamespace(channels=channels, events=[], wind_estimates={}),
                           summary=summarize(channels))


def _blade_mean_mn_m(channels: dict) -> np.ndarray:
    """1P-6P amplitudes of M_oop, mean of the three blades [MN·m], from the summary's harmonics."""
    harmonics = summarize(channels)["harmonics"]
    return 1e-6 * np.mean([harmonics[f"root_moment_oop_{blade}"]["amplitude"] for blade in (1, 2, 3)], axis=0)


@pytest.fixture(scope="module")
def written(runs, tmp_path_factory) -> dict:
    """hawt analyze's page of run "a" and hawt compare's page of "a" against "b", each written once into a folder of
    its own: page name -> its index.html."""
    analyses = [_analysis(label, channels) for label, channels in runs.items()]
    comparison = compare_summaries([analysis.summary for analysis in analyses], list(runs))
    return {"analyze": write_analysis_report(_analysis("run.mcap", runs["a"]), tmp_path_factory.mktemp("analyze")),
            "compare": write_comparison_report(comparison, tmp_path_factory.mktemp("compare"), analyses)}


def _page(written: dict, name: str) -> Page:
    return Page(written[name].read_text(encoding="utf-8"))


def test_the_compare_page_has_the_blade_root_harmonics_as_a_table_one_column_per_run(runs, written):
    """One row per harmonic 1P-6P, one column per run: the blades' mean amplitude in MN·m (the unit of the text
    tables), the second run's with its change against the first."""
    page = _page(written, "compare")
    first, second = _blade_mean_mn_m(runs["a"]), _blade_mean_mn_m(runs["b"])
    assert page.rows == [["harmonic", "a", "b"]] + [[f"{n}P", f"{a:.4g}", f"{b:.4g} (-50.0 %)"]
                                                   for n, a, b in zip(range(1, 7), first, second)]
    assert page.captions == ["amplitude of the periodic part, mean of the 3 blades [MN·m]"]
    assert 1.9 < first[0] < 2.1  # the synthetic run's 2 MN·m 1P


def test_the_analyze_page_has_the_harmonic_table_with_one_column(runs, written):
    """hawt analyze's page: the same table, one column named after the bag, no change."""
    assert _page(written, "analyze").rows == [["harmonic", "run.mcap"]] + [
        [f"{n}P", f"{a:.4g}"] for n, a in zip(range(1, 7), _blade_mean_mn_m(runs["a"]))]


@pytest.mark.parametrize("page, expected", [
    ("analyze", (["time_series.png", "spectra.png", "del.png"], ["summary.json"])),
    ("compare", (["del.png", "comparison.png", "compared_time_series.png", "compared_spectra.png"],
                 ["comparison.json"])),
])
def test_every_image_and_link_of_the_page_is_a_file_beside_it(written, page, expected):
    """The figures (the DEL bars first on the compare page, then the changes) and the JSON link name files that
    were written into the report folder."""
    parsed = _page(written, page)
    assert (parsed.images, parsed.links) == expected
    assert all((written[page].parent / name).is_file() for name in parsed.images + parsed.links)


@pytest.mark.parametrize("page, headings", [
    ("analyze", ["rotor speed, power, pitch and loads over time",
                 "power spectral densities of the loads and the pitch, rotor harmonics marked",
                 "damage-equivalent loads (1 Hz)"]),
    ("compare", ["damage-equivalent loads (1 Hz)",
                 "changes against the first run: damage-equivalent loads and pitch activity",
                 "the runs over time: rotor speed, pitch, blade 1 root, hub and tower loads",
                 "the runs' power spectral densities: blade 1 root, hub and tower moments"]),
])
def test_each_figure_is_headed_by_what_it_shows_not_by_its_file_name(written, page, headings):
    """Once "del" and "comparison": the headings say what the figure shows, after the harmonics table's."""
    assert _page(written, page).headings == ["harmonics of the blade-root out-of-plane moment", *headings]
