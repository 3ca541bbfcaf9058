"""The four status-flag commands (IsEnabled, IsMoving, IsInPos, IsErrorStop): one rule
for every flag, answered by one plain call with the axes bound in."""

from __future__ import annotations

import inspect

import pytest
from axis_util import cycle, enabled

from motionvm.motion import axis_status as st
from motionvm.motion.commands import MotionCommands

FLAGS = {"IsEnabled": "enabled", "IsMoving": "moving", "IsInPos": "in_pos",
         "IsErrorStop": "error_stop"}  # fmt: skip


@pytest.mark.parametrize("name", sorted(FLAGS))
def test_a_status_query_is_one_plain_function_of_the_axis_id(name):
    c = enabled(2)
    query = getattr(c, name)
    assert inspect.isfunction(query)  # no bound method: the program calls it directly
    assert getattr(c, name) is query  # made once per commands object
    assert list(inspect.signature(query).parameters) == ["axis_id"]
    method = getattr(MotionCommands, name)  # on the class: a method that calls it
    assert list(inspect.signature(method).parameters) == ["commands", "axis_id"]
    assert method(c, 1) == query(1)


@pytest.mark.parametrize("name", sorted(FLAGS))
def test_every_flag_answers_by_the_same_rule(name):
    c = enabled(2)
    assert c.MoveRel(1, 50.0) == 0
    cycle(c, 5)
    attr = FLAGS[name]
    for i in (0, 1):
        assert getattr(c, name)(i) == (1 if getattr(c.motion.axes[i], attr) else 0)
    c.motion.reads = reads = []  # a task runs with a recorder: the answers are recorded
    answers = [getattr(c, name)(i) for i in (0, 1)]
    axes = c.motion.axes
    assert reads == [(axes[i], attr, getattr(axes[i], attr)) for i in (0, 1)]
    assert answers == [int(bool(r[2])) for r in reads]
    c.motion.system_last_error = 0
    assert getattr(c, name)(2) == 0 and getattr(c, name)(-1) == 0  # bad ids
    assert reads[2:] == [None, None]  # not replayable
    assert c.motion.system_last_error == st.SYS_HMPL_ARG_OUT_OF_RANGE
