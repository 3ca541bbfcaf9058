"""The studio's path view of axis groups and a run that waits forever, on the wire: each
group's path is recorded in its own coordinates (X, Y[, Z]) and scrubbed; a run that can
never end stops with "waits forever", a console line and the state saying so."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.studio.studio_client import StudioServer

HERE = Path(__file__).parent
GROUPS = str(HERE / "groups.hmpl")
MACHINE = str(HERE / "groups.toml")


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    with StudioServer([GROUPS], tmp_path_factory.mktemp("data"), machine=MACHINE) as s:
        yield s


def _points(notes, names):
    out = {n: [] for n in names}
    for note in notes:
        if note["method"] == "scope":
            for n in names:
                out[n] += note["params"]["values"].get(n, [None] * len(note["params"]["t"]))
    return out


def test_each_group_path_is_recorded_in_its_own_coordinates_and_scrubbed(server):
    with server.client() as c:
        c.call("run.speed", {"factor": None})
        c.call("run.reset")
        c.notes.clear()
        c.call("run.to_time", {"seconds": 1.5})
        c.wait_for("stopped")
        assert "groups done" in "\n".join(c.console_text())
        groups = [n["params"]["groups"] for n in c.notes if n["method"] == "scope"][-1]
        assert groups == [
            {
                "name": "group0",
                "dims": 2,
                "channels": ["group0.carte_pose_fb[0]", "group0.carte_pose_fb[1]"],
            },
            {
                "name": "group1",
                "dims": 3,
                "channels": [f"group1.carte_pose_fb[{i}]" for i in range(3)],
            },
        ]
        at = c.call("history.at", {"cycle": 1500, "span": None})
        assert at["path"]["groups"] == groups
        pv = at["path"]["values"]
        xy = [
            (x, y)
            for x, y in zip(
                pv["group0.carte_pose_fb[0]"], pv["group0.carte_pose_fb[1]"], strict=True
            )
            if x is not None
        ]
        assert xy[0] == pytest.approx((0.0, 0.0), abs=1e-6)
        assert xy[-1] == pytest.approx((0.0, 50.0), abs=1e-3)
        assert max(x for x, _ in xy) == pytest.approx(50.0, abs=1e-3)
        xyz = list(zip(*(pv[f"group1.carte_pose_fb[{i}]"] for i in range(3)), strict=True))
        assert xyz[-1] == pytest.approx((40.0, 20.0, 30.0), abs=1e-3)
        # before the groups were enabled, nothing is recorded for them
        assert pv["group0.carte_pose_fb[0]"][0] is None
        # scrubbing back: the path up to that time only, the groups still known
        early = c.call("history.at", {"cycle": 300, "span": None})
        assert early["path"]["groups"] == groups
        assert early["path"]["t"][-1] <= 0.3
        # going back is a replay: the group columns stay recorded and known
        c.call("run.seek", {"cycle": 100})
        c.wait_for("stopped")
        c.notes.clear()
        c.call("run.to_time", {"seconds": 1.2})
        assert c.wait_for("stopped")["reason"] == "exited"
        again = c.call("history.at", {"cycle": 913, "span": None})
        assert again["path"]["groups"] == groups
        assert again["path"]["values"]["group1.carte_pose_fb[2]"][-1] == pytest.approx(
            30.0, abs=1e-3
        )


FOREVER = """void main() {
    Print("waiting");
    Till(GetPosFb(0) > 10);
    Print("never");
}
"""


def test_a_run_that_can_never_end_stops_and_says_it_waits_forever(tmp_path):
    program = tmp_path / "forever.hmpl"
    program.write_text(FOREVER)
    with StudioServer([str(program)], tmp_path / "data") as server, server.client() as c:
        c.call("run.speed", {"factor": None})
        c.call("run.start")
        stopped = c.wait_for("stopped")
        assert stopped["reason"] == "waits forever"
        assert stopped["time"] < 0.1
        assert "task 0 waits forever" in stopped["text"]
        lines = c.console_text()
        assert "waiting" in lines and "never" not in lines
        assert any(line.startswith("the run waits forever at t = 0.0") for line in lines)
        state = c.call("studio.hello")["state"]
        assert state["waits_forever"] and not state["running"]
        # forcing nothing and running again: it stops again at once, still waiting
        c.call("run.start")
        assert c.wait_for("stopped")["reason"] == "waits forever"
        c.call("run.reset")
        assert not c.call("studio.hello")["state"]["waits_forever"]
