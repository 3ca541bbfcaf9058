"""Benchmark: the studio's scope while a run goes faster than real time.

Serves the studio on 127.0.0.1 for a program of four axes moving back and forth, each
move awaited with `Till(IsInPos(a))` (time skipping lets the run go far faster than
real time; 12,000 moves, about 72 minutes of simulated time, so the run outlasts the
measurement), opens the page in Debian's chromium (headless, Playwright), presses Run
and counts for WINDOW seconds of wall time the scope's redraws (8 channels) and the
simulated time gone by. Prints `RESULT` lines: the scope's frames per second and the
run's speed as a multiple of real time. Needs /usr/bin/chromium.
Run: python bench/studio.py
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # the test's server helper

from playwright.sync_api import sync_playwright  # noqa: E402

from tests.studio.studio_client import StudioServer, launch_chromium  # noqa: E402

WINDOW = 3.0
"""Wall time measured [s]."""

PROGRAM = """\
void main()
{
    int k, a;
    for (a = 0; a < 4; a++) Enable(a);
    for (a = 0; a < 4; a++) Till(IsEnabled(a));
    Print("moving");
    for (k = 0; k < 3000; k++) {
        for (a = 0; a < 4; a++) {
            MoveAbs(a, k % 2 ? -100.0 - 20 * a : 100.0 + 20 * a);
            Till(IsInPos(a));
        }
    }
    Print("done");
}
"""


def main() -> None:
    folder = Path(tempfile.mkdtemp(prefix="motionvm-bench-studio-"))
    program = folder / "movers.hmpl"
    program.write_text(PROGRAM, encoding="utf-8")
    with (
        StudioServer([str(program)], folder) as server,
        sync_playwright() as p,
    ):
        browser = launch_chromium(p)
        page = browser.new_page(viewport={"width": 1500, "height": 900})
        page.goto(server.url)
        page.wait_for_selector("body[data-ready=true]")
        page.get_by_role("button", name="Run", exact=True).click()
        page.get_by_role("log").get_by_text("moving").wait_for()
        read = "() => [studio.scope.frames, studio.state.time, studio.scope.channels.length]"
        frames0, sim0, channels = page.evaluate(read)
        sent0 = server.studio.run.frames
        wall0 = time.perf_counter()
        time.sleep(WINDOW)
        frames1, sim1, _ = page.evaluate(read)
        sent = server.studio.run.frames - sent0
        wall = time.perf_counter() - wall0
        page.get_by_role("button", name="Pause", exact=True).click()
        browser.close()
    fps = (frames1 - frames0) / wall
    speed = (sim1 - sim0) / wall
    print(
        f"scope: {channels} channels, {fps:.1f} frames/s while the run went {speed:.0f}x real time"
    )
    print(f"(the server sent {sent / wall:.1f} updates/s)")
    print(f"RESULT studio_scope_fps={fps:.1f}")
    print(f"RESULT studio_run_speed_x_real_time={speed:.0f}")


if __name__ == "__main__":
    main()
