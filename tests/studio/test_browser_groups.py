"""The studio's path view of axis groups in a real browser (chromium, headless): a 2-D
group drawn in its XY plane, a 3-D group in an isometric XYZ view and its planes, and the
time slider scrubbing the group's path. Screenshots go to the test's temporary folder."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.studio.studio_client import CHROMIUM, StudioServer, inked, launch_chromium

if not Path(CHROMIUM).exists():
    pytest.skip(f"no {CHROMIUM} (apt-get install chromium)", allow_module_level=True)
playwright = pytest.importorskip("playwright.sync_api")
expect = playwright.expect
expect.set_options(timeout=15_000)  # a loaded machine (CI) answers slowly

HERE = Path(__file__).parent
WAIT_MS = 15_000


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    data = tmp_path_factory.mktemp("data")
    with StudioServer([str(HERE / "groups.hmpl")], data, machine=str(HERE / "groups.toml")) as server, \
            playwright.sync_playwright() as p:  # fmt: skip
        browser = launch_chromium(p)
        page = browser.new_page(viewport={"width": 1500, "height": 900})
        errors: list[str] = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.set_default_timeout(WAIT_MS)
        page.goto(server.url)
        page.wait_for_selector("body[data-ready=true]")
        yield page
        browser.close()
        assert errors == []


def test_each_group_is_drawn_in_its_own_coordinates_and_scrubbed(page, tmp_path):
    view, plane = page.get_by_label("View"), page.get_by_label("Plane")
    path = page.get_by_role("img", name="Path")
    expect(view).to_have_value("axes")
    page.get_by_role("button", name="Run", exact=True).click()
    expect(page.get_by_role("log")).to_contain_text("groups done")
    expect(page.get_by_role("status", name="Run status")).to_contain_text("the run ended")
    # the first group enabled takes over the view: group0, a 2-D group, in XY
    expect(view).to_have_value("group0")
    expect(view.locator("option")).to_have_text(
        ["axes axis0, axis1, axis2", "group0 (XY)", "group1 (XYZ)"]
    )
    expect(plane.locator("option")).to_have_text(["XY"])
    expect(path).to_have_attribute("aria-label", "Path (group0 XY): X 0.00 mm, Y 50.00 mm")
    page.screenshot(path=str(tmp_path / "group0.png"))
    # the 3-D group: an isometric view of X, Y, Z, and its planes
    view.select_option("group1")
    expect(plane.locator("option")).to_have_text(["XYZ", "XY", "XZ", "YZ"])
    expect(path).to_have_attribute(
        "aria-label", "Path (group1 XYZ): X 40.00 mm, Y 20.00 mm, Z 30.00 mm"
    )
    assert inked(page, "#path") > 500
    page.screenshot(path=str(tmp_path / "group1.png"))
    plane.select_option("YZ")
    expect(path).to_have_attribute("aria-label", "Path (group1 YZ): Y 20.00 mm, Z 30.00 mm")
    # scrubbing back to where group0 drew its first side only
    view.select_option("group0")
    slider = page.get_by_label("Time", exact=True)
    slider.evaluate("(s) => { s.value = '300'; s.dispatchEvent(new Event('input')); }")
    expect(path).to_have_attribute(
        "aria-label", re.compile(r"Path \(group0 XY\): X 4\d\.\d\d mm, Y 0\.00 mm")
    )
    page.screenshot(path=str(tmp_path / "scrubbed.png"))
