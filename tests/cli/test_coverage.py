"""Coverage of machine programs: line hits and `if` arms counted by hand in all three
languages, the LCOV and Cobertura reports of `motionvm run`, and `motionvm test` merging
the runs of its cases."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from motionvm.lang.coverage import merge
from motionvm.session import RunSpec, Session, Source

HMPL = """int total = 0;

void main(void)
{
    int k;
    for (k = 0; k < 3; k++) {
        if (k == 1)
            total = total + 10;
        else
            total = total + 1;
    }
    while (total > 20)
        total = total - 1;
    Print("total=%d", total);
}
"""
# line 6 (the for) starts once; 7 runs per iteration (3); 8 once (k == 1), 10 twice;
# the while starts once, its body never runs (total is 12); 14 once
HMPL_LINES = {6: 1, 7: 3, 8: 1, 10: 2, 12: 1, 13: 0, 14: 1}
HMPL_BRANCHES = {7: [[1, 2]]}

PDL = """#long n, m;
n = 0;
loop(4) do
  n++;
  if (n > 2) do
    m++;
  end;
end;
if (m > 5) do
  m = 0;
end;
printl("n=%ld m=%ld", n, m);
"""
PDL_LINES = {2: 1, 3: 1, 4: 4, 5: 4, 6: 2, 9: 1, 10: 0, 12: 1}
PDL_BRANCHES = {5: [[2, 2]], 9: [[0, 1]]}

GDL = """MODULE cell;

  IO$BOARD board [ SLOT = 1, INPUT$MODULE = PRESENT, DESCRIPTION = 'I/O' ];
  DIGITAL$INPUT start_button [ BOARD$NAME = board, CHANNEL = 1, DESCRIPTION = 'Start' ];
  DC$MOTOR$AXIS conveyor [ AXIS$NUMBER = 1, DESCRIPTION = 'Conveyor' ];

  PROCEDURE run_conveyor;
  DECLARE { STATUS OF start_button };
  BEGIN
    IF STATUS OF start_button = ON THEN
      CONSTANT$STATUS OF conveyor = ENABLED;
      RUN$AT$SPEED OF conveyor (100);
    ELSE
      STOP OF conveyor;
    END$IF;
  END$PROCEDURE;

END$MODULE;
"""
GDL_SCENARIO = """[[event]]
at = 0.050
set = "STATUS OF start_button"
value = "ON"

[[event]]
at = 0.150
set = "STATUS OF start_button"
value = "OFF"
"""
# the procedure runs once per change of its input: on, then off
GDL_LINES = {10: 2, 11: 1, 12: 1, 14: 1}
GDL_BRANCHES = {10: [[1, 1]]}


def _coverage(tmp_path, name: str, text: str, **spec) -> dict:
    path = tmp_path / name
    path.write_text(text)
    session = Session(
        RunSpec([Source(str(path))], coverage=True, **spec), emit=lambda s: None, report=print
    )
    session.run(timeout=10)
    data = session.coverage.data()
    session.close()
    return data[str(path)]


def test_hmpl_hits_and_arms(tmp_path):
    d = _coverage(tmp_path, "cov.hmpl", HMPL)
    assert d == {"lines": HMPL_LINES, "branches": HMPL_BRANCHES}


def test_pdl_hits_and_arms(tmp_path):
    d = _coverage(tmp_path, "cov.pdl", PDL, options={"starts": ("top",)})
    assert d == {"lines": PDL_LINES, "branches": PDL_BRANCHES}


def test_gdl_hits_and_arms(tmp_path):
    (tmp_path / "cell.toml").write_text(GDL_SCENARIO)
    d = _coverage(tmp_path, "cell.gdl", GDL, scenario=str(tmp_path / "cell.toml"))
    assert d == {"lines": GDL_LINES, "branches": GDL_BRANCHES}


def test_a_run_without_coverage_has_no_probe(tmp_path):
    path = tmp_path / "cov.hmpl"
    path.write_text(HMPL)
    session = Session(RunSpec([Source(str(path))]), emit=lambda s: None, report=print)
    assert session.coverage is None
    (side,) = session.sides
    assert "_mv_cov" not in side.runtime.ns
    session.close()


def test_merge_sums_hits_and_arms():
    a = {"f": {"lines": {1: 1, 2: 0}, "branches": {2: [[1, 0]]}}}
    b = {
        "f": {"lines": {1: 2, 2: 3}, "branches": {2: [[0, 4]]}},
        "g": {"lines": {5: 1}, "branches": {}},
    }
    merged = merge(merge({}, a), b)
    assert merged["f"] == {"lines": {1: 3, 2: 3}, "branches": {2: [[1, 4]]}}
    assert merged["g"]["lines"] == {5: 1}


def test_run_writes_lcov_and_cobertura(tmp_path, motionvm):
    (tmp_path / "cov.hmpl").write_text(HMPL)
    done = motionvm(
        "run", "cov.hmpl", "--cov-report", "lcov:cov.info", "--cov-report", "xml:cov.xml",
        cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0 and done.stdout == "total=12\n"
    info = (tmp_path / "cov.info").read_text().splitlines()
    assert info[:2] == ["TN:", "SF:cov.hmpl"]
    assert "BRDA:7,0,0,1" in info and "BRDA:7,0,1,2" in info
    assert [x for x in info if x.startswith("DA:")] == [
        f"DA:{k},{v}" for k, v in HMPL_LINES.items()
    ]
    assert info[-3:] == ["LF:7", "LH:6", "end_of_record"]
    root = ET.parse(tmp_path / "cov.xml").getroot()
    assert root.get("lines-valid") == "7" and root.get("lines-covered") == "6"
    lines = {ln.get("number"): ln.get("hits") for ln in root.iter("line")}
    assert lines == {str(k): str(v) for k, v in HMPL_LINES.items()}
    assert not list(tmp_path.glob(".cov*"))  # no temporary left


def test_a_bad_cov_report_is_a_usage_error(tmp_path, motionvm):
    (tmp_path / "cov.hmpl").write_text(HMPL)
    done = motionvm("run", "cov.hmpl", "--cov-report", "html:x", cwd=tmp_path)
    assert done.returncode == 3 and "--cov-report wants FORMAT:PATH" in done.stderr


def test_test_merges_the_runs_of_its_cases(tmp_path, motionvm):
    # a restart runs the same program again: its hits count twice
    (tmp_path / "a.hmpl").write_text(
        "// expect: total=12\n// expect: total=12\n// restart: a.hmpl\n" + HMPL
    )
    (tmp_path / "b.pdl").write_text("// args: --start top\n// expect: n=4 m=2\n" + PDL)
    done = motionvm("test", "-j", "2", "--cov-report", "lcov:cov.info", ".", cwd=tmp_path)
    assert done.returncode == 0, done.stdout
    info = (tmp_path / "cov.info").read_text()
    a, b = info.split("end_of_record\n")[:2]
    assert "SF:a.hmpl" in a and "SF:b.pdl" in b
    shift = 3  # the three directive lines above the program
    assert f"DA:{7 + shift},6" in a and f"BRDA:{7 + shift},0,1,4" in a
    assert f"DA:{4 + 2},4" in b
