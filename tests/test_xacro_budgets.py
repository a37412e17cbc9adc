"""Budgets per stage (issue #22, item 3): a stage that spends its budget stops with one finding
naming the budget and how to raise it; valid files are read exactly as before."""

from __future__ import annotations

import gc
import os
import signal
import sys
import time
from pathlib import Path
from types import FrameType

import pytest
from click.testing import CliRunner

import urdftool
from tests.conftest import FIXTURES
from urdftool.budgets import BudgetError, budget, parse_budgets, stage_budgets
from urdftool.cli import main
from urdftool.parse.packages import PackageResolver
from urdftool.parse.xacro import expand
from urdftool.parse.xacro_guard import expansion_code_folders, interrupts_safely
from urdftool.pipeline.check import CheckOptions, check_file

HEAD = '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'


def _bomb(levels: int) -> str:
    """A macro that calls the one below it twice, *levels* deep: 2**levels elements from a
    file of *levels* lines."""
    lines = [HEAD, '<xacro:macro name="m0"><x/></xacro:macro>']
    lines += [f'<xacro:macro name="m{k}"><xacro:m{k - 1}/><xacro:m{k - 1}/></xacro:macro>'
              for k in range(1, levels)]
    lines.append(f'<link name="base"/><xacro:m{levels - 1}/></robot>')
    return "\n".join(lines)


def _expand(tmp_path: Path, text: str) -> list[tuple[str, str]]:
    path = tmp_path / "robot.urdf.xacro"
    path.write_text(text)
    result = expand(str(path), PackageResolver.create(), {})
    return [(d.code, d.message) for d in result.diagnostics]


def test_an_exponential_macro_stops_at_the_element_budget(tmp_path: Path) -> None:
    start = time.process_time()
    with stage_budgets({"xacro-elements": 20_000}):
        found = _expand(tmp_path, _bomb(40))
    assert time.process_time() - start < 20
    assert len(found) == 1
    code, message = found[0]
    assert code == "X001"
    assert "more than 20000 elements evaluated" in message
    assert "--budget xacro-elements=N" in message


def test_an_expansion_stops_at_the_time_budget(tmp_path: Path) -> None:
    start = time.process_time()
    with stage_budgets({"xacro-seconds": 1}):
        found = _expand(tmp_path, _bomb(40))
    assert time.process_time() - start < 10
    assert [code for code, _ in found] == ["X001"]
    assert "more than 1 s of CPU time" in found[0][1] and "--budget xacro-seconds=N" in found[0][1]


@pytest.mark.skipif(not hasattr(signal, "setitimer"), reason="no CPU-time timer on this platform")
def test_the_time_alarm_does_not_ring_inside_another_librarys_callback(tmp_path: Path) -> None:
    """A garbage-collector callback of another library (hypothesis installs one) that takes most
    of the CPU time: raised there, the alarm would be printed as "Exception ignored in
    gc_callback" and lost. It rings again in the expansion's own code, and the expansion stops
    with its one finding, with nothing unraisable on the way."""
    unraisable: list[object] = []
    spent = {"callback": 0.0}

    def busy_callback(phase: str, info: dict[str, int]) -> None:
        if phase == "start":
            begin = time.process_time()
            for _ in range(500_000):  # user CPU time, which the alarm's timer counts
                pass
            spent["callback"] += time.process_time() - begin

    previous_hook = sys.unraisablehook
    sys.unraisablehook = unraisable.append
    gc.callbacks.append(busy_callback)
    thresholds = gc.get_threshold()
    gc.set_threshold(50)  # a collection every 50 new containers: most CPU time in the callback
    try:
        start = time.process_time()
        with stage_budgets({"xacro-seconds": 0.5}):
            found = _expand(tmp_path, _bomb(40))
        total = time.process_time() - start
    finally:
        gc.set_threshold(*thresholds)
        gc.callbacks.remove(busy_callback)
        sys.unraisablehook = previous_hook
    assert spent["callback"] > total / 2  # the alarm was likely to land in the callback
    assert unraisable == []
    assert [code for code, _ in found] == ["X001"]
    assert "more than 0.5 s of CPU time" in found[0][1]
    assert total < 10


def test_the_alarm_raises_only_in_the_expansions_code() -> None:
    import xacro

    folders = expansion_code_folders(xacro)

    def frame_in(filename: str) -> FrameType:
        frame: FrameType = eval(compile("__import__('sys')._getframe(0)", filename, "eval"))
        return frame

    assert interrupts_safely(frame_in("<expression>"), folders)
    assert interrupts_safely(frame_in(os.path.join(os.path.dirname(xacro.__file__), "x.py")), folders)
    assert interrupts_safely(frame_in(os.path.join(os.path.dirname(urdftool.__file__), "x.py")),
                             folders)
    # this test module, a gc callback's module: another library's code, as far as xacro knows
    assert not interrupts_safely(sys._getframe(0), folders)
    assert not interrupts_safely(None, folders)


@pytest.mark.skipif(not hasattr(signal, "setitimer"), reason="no CPU-time timer on this platform")
def test_one_slow_expression_stops_at_the_time_budget(tmp_path: Path) -> None:
    """Steps that build nothing large: no size check refuses them, and the time check between
    elements comes too late; the CPU-time alarm stops the expression itself. 10^8 steps take
    2–3 s here, so without the alarm the expression ends (with no finding) and the test fails
    rather than hangs; 10^12 steps would take a day."""
    slow = "python.sum(1 for a in python.range(10**4) for b in python.range(10**4))"
    start = time.process_time()
    with stage_budgets({"xacro-seconds": 0.5}):
        found = _expand(tmp_path, f'{HEAD}<xacro:property name="p" value="${{{slow}}}"/>'
                                  '<link name="b${p}"/></robot>')
    assert time.process_time() - start < 10
    assert [code for code, _ in found] == ["X001"]
    assert "more than 0.5 s of CPU time" in found[0][1] and "--budget xacro-seconds=N" in found[0][1]
    # the alarm is gone with the expansion: the previous handler is back, no timer runs
    assert signal.getsignal(signal.SIGVTALRM) in (signal.SIG_DFL, None)
    assert signal.getitimer(signal.ITIMER_VIRTUAL) == (0.0, 0.0)


@pytest.mark.parametrize("expression, what", [
    ("9**9**9", "bits"),
    ("1 &lt;&lt; 10**9", "bits"),
    ("'x' * 10**10", "items"),
    ("[0] * 10**10", "items"),
    ("python.list(python.range(10**10))", "items"),
    ("'a'.ljust(10**10)", "characters"),
    ("'%10000000000d' % 1", "format width"),
])
def test_an_amplifying_expression_is_refused_before_it_runs(tmp_path: Path, expression: str,
                                                            what: str) -> None:
    start = time.process_time()
    found = _expand(tmp_path, f'{HEAD}<xacro:property name="p" value="${{{expression}}}"/>'
                              '<link name="b${p}"/></robot>')
    assert time.process_time() - start < 5
    assert [code for code, _ in found] == ["X001"]
    assert "expansion stopped" in found[0][1]
    assert what in found[0][1] or "more than" in found[0][1]


def test_valid_expressions_read_as_before(tmp_path: Path) -> None:
    # every amplifier, at sizes real descriptions use, inside and outside comprehensions
    text = (f'{HEAD}<xacro:property name="n" value="3"/>'
            '<link name="a${2**10}_${n*2}_${1 &lt;&lt; 4}_${\'ab\' * 2}_${len([0] * n)}"/>'
            '<link name="b${python.sum([i * 2 for i in python.range(n)])}_'
            '${\'7\'.zfill(3)}_${\'%5.2f\' % 1.5}"/>'
            '<link name="c${2.0**0.5}_${(-2)**3}_${python.range(3)[-1]}"/>'
            '<joint name="j" type="fixed"><parent link="a1024_6_16_abab_3"/>'
            '<child link="b6_007_ 1.50"/></joint></robot>')
    path = tmp_path / "robot.urdf.xacro"
    path.write_text(text)
    result = expand(str(path), PackageResolver.create(), {})
    assert [d.code for d in result.diagnostics if d.severity.value == "error"] == []
    assert result.document is not None
    names = [link.get("name") for link in result.document.root.iter("link")]
    assert names == ["a1024_6_16_abab_3", "b6_007_ 1.50", "c1.4142135623730951_-8_2"]


def test_budgets_are_checked_by_name_and_value() -> None:
    assert parse_budgets(["xacro-seconds=5", "collision-faces=20000"]) == {
        "xacro-seconds": 5.0, "collision-faces": 20000.0}
    with pytest.raises(BudgetError, match="did you mean 'collision-faces'"):
        parse_budgets(["collision-triangles=20000"])
    for wrong in ("xacro-seconds=-1", "xacro-elements=inf", "xacro-seconds=nan", "dynamics-dof=x"):
        with pytest.raises(BudgetError, match="positive finite number"):
            parse_budgets([wrong])
    with stage_budgets({"dynamics-dof": 5}):
        assert budget("dynamics-dof") == 5
    assert budget("dynamics-dof") == 120


def test_cli_budget_flag_and_its_errors(tmp_path: Path) -> None:
    path = tmp_path / "robot.urdf.xacro"
    path.write_text(_bomb(40))
    result = CliRunner().invoke(main, ["check", str(path), "--budget", "xacro-elements=5000",
                                       "--no-dynamics"])
    assert result.exit_code == 1
    assert "xacro-elements budget" in result.output
    wrong = CliRunner().invoke(main, ["check", str(path), "--budget", "xacro-element=5000"])
    assert wrong.exit_code == 2
    assert "did you mean 'xacro-elements'" in wrong.output
    # the flag lasts for its invocation only
    assert budget("xacro-elements") == 1_000_000


def test_the_collision_faces_budget_comes_from_the_settings(tmp_path: Path) -> None:
    # provenance: fixtures/rules/M006 (a collision mesh over the default budget of 10000 triangles)
    source = FIXTURES / "rules" / "M006" / "bad.urdf"
    assert source.exists()
    default = check_file(str(source), CheckOptions(select=("M006",)))
    assert [d.code for r in default for d in r.diagnostics] == ["M006"]
    raised = check_file(str(source), CheckOptions(select=("M006",), budgets={"collision-faces": 10**7}))
    assert [d.code for r in raised for d in r.diagnostics] == []
    (tmp_path / "pyproject.toml").write_text('[tool.urdftool]\nbudgets = { collision-triangles = 20000 }\n')
    copied = tmp_path / "robot.urdf"
    copied.write_text(source.read_text())
    result = CliRunner().invoke(main, ["check", str(copied), "--select", "M006"])
    assert result.exit_code == 2
    assert "unknown budget 'collision-triangles'; did you mean 'collision-faces'" in result.output


def test_the_dynamics_dof_budget_names_itself() -> None:
    # a 130-joint chain is over the dense pass's default of 120 moving joints
    links = "".join(f'<link name="l{i}"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" '
                    f'izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>' for i in range(131))
    joints = "".join(f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
                     f'<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>'
                     f'<limit lower="-1" upper="1" effort="1000" velocity="1"/></joint>' for i in range(130))
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "chain.urdf"
        path.write_text(f'<robot name="chain">{links}{joints}</robot>')
        found = [d for r in check_file(str(path), CheckOptions(select=("D004",))) for d in r.diagnostics]
        assert [d.code for d in found] == ["D004"]
        assert "--budget dynamics-dof=N" in (found[0].help or "")
        dense = check_file(str(path), CheckOptions(select=("D004",), budgets={"dynamics-dof": 200}))
        assert [d.code for r in dense for d in r.diagnostics] == []
