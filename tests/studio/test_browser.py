"""The studio in a real browser: Debian's chromium, headless, driven by Playwright.

The page loads with its controls, a scope with a grid and the default channels; a run
shows the program's lines in the console and draws the scope; Pause, Step cycle, a
breakpoint set in the gutter, an input forced in the I/O panel, the time slider scrubbed
back; the token and Origin rules as a browser meets them. Screenshots go to the test's
temporary folder (MOTIONVM_UPDATE_SCREENSHOTS=1: docs/images/studio.png too)."""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import pytest

from tests.studio.studio_client import CHROMIUM, EXAMPLES, StudioServer, inked, launch_chromium

if not Path(CHROMIUM).exists():
    pytest.skip(f"no {CHROMIUM} (apt-get install chromium)", allow_module_level=True)
playwright = pytest.importorskip("playwright.sync_api")
expect = playwright.expect
expect.set_options(timeout=15_000)  # a loaded machine (CI) answers slowly

PROGRAM = str(EXAMPLES / "05_pick_and_place.hmpl")
MACHINE = str(EXAMPLES / "05_pick_and_place.toml")
WAIT_MS = 15_000
DOCS_SHOT = Path(__file__).resolve().parents[2] / "docs" / "images" / "studio.png"


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    with StudioServer([PROGRAM], tmp_path_factory.mktemp("data"), machine=MACHINE) as s:
        yield s


@pytest.fixture(scope="module")
def browser():
    with playwright.sync_playwright() as p:
        b = launch_chromium(p)
        yield b
        b.close()


@pytest.fixture
def page(server, browser):
    """The studio's page, freshly reset (no breakpoints, t = 0)."""
    page = browser.new_page(viewport={"width": 1500, "height": 900})
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.set_default_timeout(WAIT_MS)
    page.goto(server.url)
    page.wait_for_selector("body[data-ready=true]")
    # no breakpoint is left from an earlier test (one that failed before clearing it)
    page.evaluate(
        "async (path) => await studio.rpc.call('breakpoints.set', {path, lines: []})", PROGRAM
    )
    page.get_by_role("button", name="Reset").click()
    expect(page.get_by_role("log")).to_be_empty()
    # the reset is done (a new engine at t = 0) before the test presses anything
    expect(page.get_by_role("status", name="Run status")).to_have_text("ready (paused at t = 0)")
    yield page
    page.close()
    assert errors == []


def _shot(page, tmp_path: Path, name: str) -> Path:
    path = tmp_path / f"{name}.png"
    page.screenshot(path=str(path))
    return path


def _run_to(page, seconds: float) -> None:
    page.get_by_label("Run to time [s]").fill(str(seconds))
    page.get_by_role("button", name="Go").click()
    expect(page.get_by_role("status", name="Run status")).to_contain_text(
        f"paused (t = {seconds:.3f} s)"
    )


def test_the_page_shows_its_controls_and_a_scope_with_a_grid_from_the_start(page, tmp_path):
    for name in ("Run", "Pause", "Step cycle", "Reset"):
        expect(page.get_by_role("button", name=name, exact=True)).to_be_visible()
    expect(page.get_by_role("button", name="Pause", exact=True)).to_be_disabled()
    expect(page.get_by_label("Simulated time")).to_have_text("t = 0.000 s")
    scope = page.get_by_role("region", name="Scope")
    expect(scope.locator("canvas")).to_be_visible()
    expect(scope).to_contain_text("axis0.pos_fb [mm]")
    assert (
        inked(page, "#scope-plot canvas") > 2000
    )  # the axes and the grid are drawn before any run
    expect(page.get_by_role("region", name="Axes").locator("tbody tr")).to_have_count(3)
    expect(page.get_by_role("group", name="Inputs (click to force)")).to_contain_text("gpi3")
    expect(page.locator(".cm-content")).to_contain_text("#define PART_SENSOR 2")
    _shot(page, tmp_path, "start")


def test_a_run_prints_to_the_log_draws_the_scope_then_pauses_and_steps(page, tmp_path):
    page.get_by_role("button", name="Run", exact=True).click()
    log = page.get_by_role("log")
    expect(log).to_contain_text("homed at t=1835 ms")
    expect(log).to_contain_text("waiting for start")
    # nothing sets the start input: the run can never end, and says so
    expect(page.get_by_role("status", name="Run status")).to_contain_text("waits forever")
    expect(log).to_contain_text("the run waits forever at t = ")
    expect(page.locator("body")).to_have_attribute("data-run-state", "waits forever")
    expect(page.get_by_role("button", name="Pause", exact=True)).to_be_disabled()
    drawn = page.evaluate("() => [studio.scope.t.length, studio.scope.frames]")
    assert drawn[0] > 20 and drawn[1] > 0
    homed_x = page.evaluate("() => studio.scope.values['axis0.pos_fb'].slice(-1)[0]")
    assert homed_x == pytest.approx(0.0, abs=1e-6)
    before = float(re.search(r"[\d.]+", page.get_by_label("Simulated time").inner_text())[0])
    page.get_by_role("button", name="Step cycle").click()
    expect(page.get_by_label("Simulated time")).to_have_text(f"t = {before + 0.001:.3f} s")
    expect(page.get_by_role("list", name="Call stack")).to_contain_text("main")
    _shot(page, tmp_path, "paused")


def test_a_breakpoint_set_in_the_gutter_stops_the_run(page, tmp_path):
    page.locator(".cm-content").click()
    page.keyboard.press("Control+Home")
    for _ in range(65):  # to line 66: Print("waiting for start");
        page.keyboard.press("ArrowDown")
    page.keyboard.press("F9")
    expect(page.locator(".cm-bp")).to_have_count(1)
    page.get_by_role("button", name="Run", exact=True).click()
    expect(page.get_by_role("status", name="Run status")).to_contain_text(
        "breakpoint at 05_pick_and_place.hmpl:66"
    )
    expect(page.locator(".cm-stopped")).to_contain_text('Print("waiting for start");')
    expect(page.locator("#variables")).to_contain_text("parts")
    expect(page.get_by_role("log")).not_to_contain_text("waiting for start")
    _shot(page, tmp_path, "breakpoint")
    page.locator(".cm-stopped").click()
    page.keyboard.press("F9")  # on the breakpoint's line: off again
    expect(page.locator(".cm-bp")).to_have_count(0)


def test_an_input_forced_in_the_io_panel_makes_the_program_go_on(page, tmp_path):
    _run_to(page, 1.95)
    start = page.get_by_role("group", name="Inputs (click to force)").get_by_role(
        "button", name="gpi3"
    )
    start.click()
    expect(start).to_have_attribute("aria-pressed", "true")
    page.get_by_role("button", name="Run", exact=True).click()
    log = page.get_by_role("log")
    expect(log).to_contain_text("start at t=1950 ms")
    expect(log).to_contain_text("camera armed: 1")  # a part picked: the machine moved
    pause = page.get_by_role("button", name="Pause", exact=True)
    if pause.is_enabled():  # (else the run stopped already: it waits for the next part)
        try:
            pause.click(timeout=2_000)
        except playwright.TimeoutError:  # it stopped between the test and the click
            assert not pause.is_enabled()
    expect(page.get_by_role("status", name="Run status")).to_contain_text(
        re.compile("paused|waits forever"))  # fmt: skip
    path = _shot(page, tmp_path, "moving")
    if os.environ.get("MOTIONVM_UPDATE_SCREENSHOTS") == "1":
        DOCS_SHOT.parent.mkdir(exist_ok=True)
        shutil.copy(path, DOCS_SHOT)


def test_the_time_slider_scrubs_back_and_moves_the_debugger_there(page, tmp_path):
    _run_to(page, 2.0)
    log = page.get_by_role("log")
    expect(log.get_by_text("homed at t=1835 ms")).to_be_visible()
    feedback = (
        page.get_by_role("region", name="Axes").locator("tbody tr").first.locator("td").nth(2)
    )
    # the axes table is drawn at most 10 times a second: the stop's values come within
    # 100 ms of the status (the last update is delayed, never dropped)
    page.wait_for_timeout(300)
    late = float(feedback.inner_text())
    slider = page.get_by_label("Time", exact=True)
    slider.fill("200")  # a drag: input events, then the release's change
    expect(page.get_by_role("status", name="Run status")).to_contain_text("paused (t = 0.200 s)")
    early = float(feedback.inner_text())
    assert early == pytest.approx(137.0, abs=0.5) and late < early - 5  # X homes downward
    expect(page.get_by_label("Simulated time")).to_have_text("t = 0.200 s")
    # the console shows what was printed up to there; a later line comes back once
    # the run passes it again, once
    expect(log.get_by_text("homed at t=1835 ms")).to_be_hidden()
    expect(log.get_by_text("stack light")).to_be_visible()
    _shot(page, tmp_path, "scrubbed")
    _run_to(page, 2.0)
    expect(log.get_by_text("homed at t=1835 ms")).to_be_visible()
    expect(log.get_by_text("homed at t=")).to_have_count(1)


def test_the_page_needs_the_token_and_a_foreign_origin_gets_no_websocket(server, browser):
    page = browser.new_page()
    try:
        answer = page.goto(f"http://127.0.0.1:{server.port}/")
        assert answer.status == 403
        page.goto("about:blank")  # another origin than the studio's page
        ws_url = server.ws_url()
        opened = page.evaluate(
            """url => new Promise(done => {
                const ws = new WebSocket(url);
                ws.onopen = () => done("open"); ws.onerror = () => done("refused");
            })""",
            ws_url,
        )
        assert opened == "refused"
    finally:
        page.close()


def test_two_scope_cursors_show_their_times_values_and_the_difference(page, tmp_path):
    _run_to(page, 1.0)
    table = page.get_by_role("table", name="Values at the cursors")
    expect(table).to_be_hidden()
    # click on the plot: cursor A; shift-click: cursor B (the hover cursor stays)
    over = page.locator("#scope-plot .u-over")
    x_at = "(t) => studio.scope.plot.valToPos(t, 'x')"
    over.click(position={"x": page.evaluate(x_at, 0.2), "y": 10})
    over.click(position={"x": page.evaluate(x_at, 0.8), "y": 10}, modifiers=["Shift"])
    a = float(page.get_by_label("Cursor A [s]").input_value())
    b = float(page.get_by_label("B [s]").input_value())
    assert a == pytest.approx(0.2, abs=0.02) and b == pytest.approx(0.8, abs=0.02)
    expect(page.get_by_label("Cursor time difference")).to_have_text(f"Δt {b - a:.3f} s")
    expect(table).to_be_visible()
    rows = table.locator("tr")
    expect(rows).to_have_count(5)  # the channels, the hover cursor, A, B, B − A
    expect(rows.nth(0)).to_contain_text("axis0.pos_fb [mm]")
    expect(rows.nth(1)).to_contain_text("hover")
    expect(rows.nth(4)).to_contain_text("B − A")
    # from the keyboard: type a time, arrow keys step it by a cycle
    field = page.get_by_label("Cursor A [s]")
    field.fill("0.5")
    expect(rows.nth(2).locator("td").first).to_have_text("0.500")
    field.press("ArrowUp")
    expect(rows.nth(2).locator("td").first).to_have_text("0.501")
    x = page.evaluate(
        "() => { const s = studio.scope; return s.values['axis0.pos_fb'][s.sampleAt(0.501)]; }"
    )
    assert rows.nth(2).locator("td").nth(1).inner_text() == f"{float(f'{x:.6g}')}".removesuffix(
        ".0"
    )
    expect(page.get_by_label("Cursor time difference")).to_have_text(f"Δt {b - 0.501:.3f} s")
    _shot(page, tmp_path, "cursors")
    page.get_by_role("button", name="Clear cursors").click()
    expect(table).to_be_hidden()
    expect(page.get_by_label("Cursor time difference")).to_have_text("Δt –")
